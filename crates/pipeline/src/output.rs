//! File output at the edge of the pipeline: everything of `nklut_tables::output` (tables as
//! CSV and JSON, atomic writes, files published as one set; re-exported here at its old
//! paths) and the Parquet encoder those tables take, through polars: [`parquet`] of a whole
//! table, [`write_parquet_blocks`] of a table written in row blocks, and [`TableFiles`], the
//! table's files with this encoder.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;

pub use nklut_tables::output::*;

/// A column as a polars column (text as strings, floats with nulls for `None`).
fn series(column: &Column) -> polars::prelude::Column {
    use polars::prelude::*;
    let name = PlSmallStr::from(column.name.as_str());
    let series = match &column.values {
        Values::Text(v) => Series::new(name, v.as_slice()),
        Values::SharedText(v) => Series::new(name, v.iter().map(|s| &**s).collect::<Vec<&str>>().as_slice()),
        Values::Float(v) => Series::new(name, v.as_slice()),
        Values::Integer(v) => Series::new(name, v.as_slice()),
        Values::Boolean(v) => Series::new(name, v.as_slice()),
    };
    series.into()
}

/// The table as a polars DataFrame, each column released once converted.
fn into_frame(table: Table) -> Result<polars::prelude::DataFrame> {
    let rows = table.rows();
    let columns = table.columns.into_iter().map(|c| series(&c)).collect();
    polars::prelude::DataFrame::new(rows, columns).map_err(|e| anyhow::anyhow!("building the polars DataFrame: {e}"))
}

/// The table as a Parquet file (polars' writer): the [`ParquetEncoder`] of every table
/// the pipeline, the effects and the GPU runner write.
pub fn parquet(table: &Table) -> Result<Vec<u8>> {
    use polars::prelude::*;
    let columns = table.columns.iter().map(series).collect();
    let mut frame = DataFrame::new(table.rows(), columns).map_err(|e| anyhow::anyhow!("building the polars DataFrame: {e}"))?;
    let mut bytes = Vec::new();
    ParquetWriter::new(&mut bytes).finish(&mut frame).map_err(|e| anyhow::anyhow!("encoding Parquet: {e}"))?;
    Ok(bytes)
}

/// Parquet of a table written in row blocks, one row group at a time
/// ([`RowBlocks::row_groups`]: the groups polars forms from the whole table), each built,
/// encoded and released before the next: the bytes [`parquet`] gives on the whole table.
pub fn write_parquet_blocks(blocks: &RowBlocks, out: &mut dyn Write) -> Result<()> {
    use polars::prelude::*;
    let groups = blocks.row_groups();
    let mut sink = std::io::BufWriter::with_capacity(1 << 20, out);
    let first = into_frame((blocks.block)(groups[0].clone()))?;
    let mut writer = ParquetWriter::new(&mut sink).batched(first.schema()).map_err(|e| anyhow::anyhow!("encoding Parquet: {e}"))?;
    writer.write_batch(&first).map_err(|e| anyhow::anyhow!("encoding Parquet: {e}"))?;
    drop(first);
    for group in &groups[1..] {
        let frame = into_frame((blocks.block)(group.clone()))?;
        writer.write_batch(&frame).map_err(|e| anyhow::anyhow!("encoding Parquet: {e}"))?;
    }
    writer.finish().map_err(|e| anyhow::anyhow!("encoding Parquet: {e}"))?;
    drop(writer);
    sink.flush()?;
    Ok(())
}

/// A table's files with the pipeline's Parquet encoder ([`parquet`]): what
/// [`Table::files_with`], [`Table::streamed_files_with`] and [`Table::write_with`] give
/// with it.
pub trait TableFiles {
    /// The table as Parquet ([`parquet`]).
    fn to_parquet(&self) -> Result<Vec<u8>>;
    /// `<stem>.columns.json`, `.csv`, `.parquet` (and `.json` when asked) encoded into
    /// memory.
    fn files(&self, stem: &str, json: bool) -> Result<Vec<SetFile>>;
    /// The same files, each encoded while it is written.
    fn streamed_files(&self, stem: &str, json: bool) -> Vec<StreamedFile<'_>>;
    /// Publish the table's files under `dir` as the set `stem`.
    fn write(&self, dir: &Path, stem: &str, json: bool) -> Result<Vec<PathBuf>>;
}

impl TableFiles for Table {
    fn to_parquet(&self) -> Result<Vec<u8>> {
        parquet(self)
    }

    fn files(&self, stem: &str, json: bool) -> Result<Vec<SetFile>> {
        self.files_with(stem, json, parquet)
    }

    fn streamed_files(&self, stem: &str, json: bool) -> Vec<StreamedFile<'_>> {
        self.streamed_files_with(stem, json, parquet)
    }

    fn write(&self, dir: &Path, stem: &str, json: bool) -> Result<Vec<PathBuf>> {
        self.write_with(dir, stem, json, parquet)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ops::Range;
    use std::sync::Arc;

    fn sample() -> Table {
        let mut table = Table::new();
        table
            .text("page", "page id", vec!["main/Au/Johnson".into(), "a,b".into()])
            .optional_float("n", "refractive index", vec![Some(0.25), None])
            .integer("count", "count", vec![3, -1])
            .boolean("flag", "flag", vec![true, false]);
        table
    }

    #[test]
    fn parquet_starts_and_ends_with_magic() {
        let bytes = sample().to_parquet().unwrap();
        assert_eq!(&bytes[..4], b"PAR1");
        assert_eq!(&bytes[bytes.len() - 4..], b"PAR1");
    }

    /// Shared text writes as plain text in every format: the same bytes.
    #[test]
    fn shared_text_gives_the_same_bytes() {
        let plain = sample();
        let mut shared = plain.clone();
        let mut values = SharedText::default();
        for column in &mut shared.columns {
            if let Values::Text(v) = &column.values {
                column.values = Values::SharedText(v.iter().map(|s| values.get(s)).collect());
            }
        }
        assert!(shared.columns.iter().any(|c| matches!(c.values, Values::SharedText(_))));
        let (a, b) = (plain.files("t", true).unwrap(), shared.files("t", true).unwrap());
        assert_eq!(a.iter().map(|f| f.name.as_str()).collect::<Vec<_>>(), ["t.columns.json", "t.csv", "t.parquet", "t.json"]);
        assert_eq!(a, b);
        assert!(Arc::ptr_eq(&values.get("a,b"), &values.get("a,b")));
    }

    /// A table written in row blocks gives the Parquet bytes of the whole table, with the
    /// row groups polars forms (two here: 2·512² + 12 345 rows), quoted text, missing floats
    /// and repeated text included.
    #[test]
    fn row_blocks_give_the_parquet_bytes_of_the_whole_table() {
        let rows = 2 * PARQUET_ROW_GROUP + 12_345;
        let table_of = |range: Range<usize>| {
            let mut shared = SharedText::default();
            let mut table = Table::new();
            table
                .shared_text(
                    "page",
                    "page id",
                    range.clone().map(|i| shared.get(if i % 3 == 0 { "a,b" } else { "main/Au/Johnson" })).collect(),
                )
                .optional_float("x", "a value", range.clone().map(|i| (i % 7 != 0).then_some(i as f64 / 3.0)).collect())
                .integer("i", "row", range.map(|i| i as i64).collect());
            table
        };
        let whole = table_of(0..rows);
        let blocks = RowBlocks { rows, block: &table_of };
        let mut bytes = Vec::new();
        write_parquet_blocks(&blocks, &mut bytes).unwrap();
        assert!(bytes == whole.to_parquet().unwrap(), "Parquet differs");
    }
}
