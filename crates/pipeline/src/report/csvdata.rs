//! The report reads the tables the other stages wrote (CSV), so every number it shows
//! is the number in a file a user can open. A text cell's formula quote (the single quote
//! before text a spreadsheet would take for a formula, `crate::escape::csv`) is taken away
//! as the cell is read.

use std::collections::HashMap;
use std::path::Path;

use anyhow::{Context, Result};
use nklut_tables::columns::{Column, Kind, Numeric};
use rayon::prelude::*;

/// The most bytes read from a table of the whole database (`errors.csv` of `validate
/// --all` is ~0.2 GB): a larger file is refused by name before it is read.
pub const MAX_TABLE_BYTES: u64 = 1 << 30;

/// The bytes a table held whole ([`CsvTable::parse`]: a `String` per cell) takes per byte
/// of its file: 1.47 GB for a 100 MB `gpu_timing.csv` of short cells, counted as 16.
pub const PARSED_BYTES_PER_BYTE: usize = 16;

/// One record of a file being read, by column name (for `CsvTable::parse_selected`).
pub struct Record<'a> {
    record: &'a csv::StringRecord,
    index: &'a HashMap<String, usize>,
}

impl<'a> Record<'a> {
    /// The text of `column` ("" when the file has no such column), its formula quote taken
    /// away ([`crate::escape::csv_text`]).
    pub fn text(&self, column: &str) -> &'a str {
        self.index.get(column).and_then(|&i| self.record.get(i)).map_or("", crate::escape::csv_text)
    }
}

/// A CSV table held as text, with typed accessors.
#[derive(Clone, Debug, Default)]
pub struct CsvTable {
    pub headers: Vec<String>,
    pub rows: Vec<Vec<String>>,
    index: HashMap<String, usize>,
}

impl CsvTable {
    /// A table of `headers` and text `rows` (each as long as `headers`) read from
    /// elsewhere than a CSV file (the browser bench's JSON).
    pub fn from_rows(headers: Vec<String>, rows: Vec<Vec<String>>) -> Self {
        let index = headers.iter().enumerate().map(|(i, h)| (h.clone(), i)).collect();
        Self { headers, rows, index }
    }

    pub fn parse(bytes: &[u8]) -> Result<Self> {
        let mut reader = csv::Reader::from_reader(bytes);
        let headers: Vec<String> = reader.headers()?.iter().map(str::to_string).collect();
        let rows = reader
            .records()
            .map(|r| r.map(|r| r.iter().map(|cell| crate::escape::csv_text(cell).to_string()).collect()))
            .collect::<Result<Vec<Vec<String>>, _>>()?;
        let index = headers.iter().enumerate().map(|(i, h)| (h.clone(), i)).collect();
        Ok(Self { headers, rows, index })
    }

    /// Only `columns` (those the file has) of the rows `keep` accepts, judged on the full
    /// record before anything is copied: a large table (errors.csv of the whole database)
    /// held in a fraction of the memory and time. The records are read in pieces on every
    /// core (see [`record_pieces`]) and kept in file order; a piece that does not read
    /// cleanly sends the whole file through one reader, whose error names the line.
    pub fn parse_selected(bytes: &[u8], columns: &[&str], keep: &(dyn Fn(&Record) -> bool + Sync)) -> Result<Self> {
        let mut reader = csv::Reader::from_reader(bytes);
        let all: Vec<String> = reader.headers()?.iter().map(str::to_string).collect();
        let all_index: HashMap<String, usize> = all.iter().enumerate().map(|(i, h)| (h.clone(), i)).collect();
        let picked: Vec<usize> = columns.iter().filter_map(|c| all_index.get(*c).copied()).collect();
        let headers: Vec<String> = picked.iter().map(|&i| all[i].clone()).collect();
        let index = headers.iter().enumerate().map(|(i, h)| (h.clone(), i)).collect();
        let body = usize::try_from(reader.position().byte()).unwrap_or(bytes.len()).min(bytes.len());
        let read = |piece: &[u8], has_headers: bool| -> csv::Result<Vec<Vec<String>>> {
            let mut reader = csv::ReaderBuilder::new().has_headers(has_headers).from_reader(piece);
            let mut rows = Vec::new();
            let mut record = csv::StringRecord::new();
            while reader.read_record(&mut record)? {
                if !has_headers && record.len() != all.len() {
                    // Not a clean piece: the whole file is read again by one reader.
                    return Err(csv::Error::from(std::io::Error::other("a record of another length")));
                }
                if keep(&Record { record: &record, index: &all_index }) {
                    rows.push(picked.iter().map(|&i| record.get(i).map_or("", crate::escape::csv_text).to_string()).collect());
                }
            }
            Ok(rows)
        };
        let pieces = record_pieces(bytes, body, rayon::current_num_threads() * 4);
        let in_pieces: csv::Result<Vec<Vec<Vec<String>>>> = pieces.par_windows(2).map(|w| read(&bytes[w[0]..w[1]], false)).collect();
        let rows = match in_pieces {
            Ok(pieces) => pieces.concat(),
            Err(_) => read(bytes, true)?,
        };
        Ok(Self { headers, rows, index })
    }

    /// Read `path` (a regular file of at most [`MAX_TABLE_BYTES`]: a FIFO, a device or a
    /// folder there is an error naming it, never a read that waits or grows without end);
    /// `Ok(None)` when the file does not exist (that stage has not run).
    pub fn load(path: &Path) -> Result<Option<Self>> {
        Self::load_bounded(path, MAX_TABLE_BYTES)
    }

    /// [`load`](Self::load) of a file of at most `limit` bytes. A table held whole takes
    /// about [`PARSED_BYTES_PER_BYTE`] times its file (a 100 MB device table measured 1.47 GB),
    /// which is checked against the memory budget before it is parsed.
    pub fn load_bounded(path: &Path, limit: u64) -> Result<Option<Self>> {
        Self::load_with(path, limit, &|bytes| {
            crate::budget::MemoryBudget::of_machine().check(
                &path.display().to_string(),
                format!("the {}-byte table parsed", bytes.len()),
                crate::budget::times(bytes.len() as u128, PARSED_BYTES_PER_BYTE),
            )?;
            Self::parse(bytes)
        })
    }

    /// `load` through `parse_selected`.
    pub fn load_selected(path: &Path, limit: u64, columns: &[&str], keep: &(dyn Fn(&Record) -> bool + Sync)) -> Result<Option<Self>> {
        Self::load_with(path, limit, &|bytes| Self::parse_selected(bytes, columns, keep))
    }

    fn load_with(path: &Path, limit: u64, parse: &dyn Fn(&[u8]) -> Result<Self>) -> Result<Option<Self>> {
        use nklut_optics::db::file::{read_regular, FileProblem};
        // A table is read whole: its stated size must fit the memory budget too (a 1 GiB
        // `errors.csv` under a 100 MB budget is refused before a byte is read).
        if let Ok(meta) = std::fs::metadata(path) {
            if meta.is_file() && meta.len() <= limit {
                crate::budget::MemoryBudget::of_machine().check(
                    &path.display().to_string(),
                    format!("the {}-byte table read", meta.len()),
                    u128::from(meta.len()),
                )?;
            }
        }
        match read_regular(path, limit) {
            Ok(bytes) => Ok(Some(parse(&bytes).with_context(|| format!("reading {}", path.display()))?)),
            Err(FileProblem::Io(e)) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(e).with_context(|| format!("reading {}", path.display())),
        }
    }

    pub fn has(&self, column: &str) -> bool {
        self.index.contains_key(column)
    }

    /// The text of `column` in `row` ("" when the column is absent).
    pub fn text<'a>(&'a self, row: &'a [String], column: &str) -> &'a str {
        self.index.get(column).and_then(|&i| row.get(i)).map(String::as_str).unwrap_or("")
    }

    /// The number in `column` of `row`, `None` when empty or not a number.
    pub fn number(&self, row: &[String], column: &str) -> Option<f64> {
        self.text(row, column).parse().ok()
    }

    /// Whether the file has `column` (a table written before the column existed has not).
    pub fn holds<K>(&self, column: Column<K>) -> bool {
        self.has(column.name)
    }

    /// The cell of `column` in `row`, read as its kind (absent or empty: `None`, or `""`
    /// for text).
    pub fn get<'a, K: Kind>(&'a self, row: &'a [String], column: Column<K>) -> K::Read<'a> {
        column.read(self.text(row, column.name))
    }

    /// The text of `column` in `row` as the file holds it ("" when the column is absent):
    /// a key to match rows on, or a cell shown as written.
    pub fn raw<'a, K>(&'a self, row: &'a [String], column: Column<K>) -> &'a str {
        self.text(row, column.name)
    }

    /// The number in `column` of `row`, `None` when empty or not a number.
    pub fn value<K: Numeric>(&self, row: &[String], column: Column<K>) -> Option<f64> {
        self.number(row, column.name)
    }

    /// The values of `column` in the order they first appear.
    pub fn distinct(&self, column: &str) -> Vec<&str> {
        let mut values: Vec<&str> = Vec::new();
        for row in &self.rows {
            let value = self.text(row, column);
            if !values.contains(&value) {
                values.push(value);
            }
        }
        values
    }

    /// Rows whose `column` equals `value`.
    pub fn rows_where<'a>(&'a self, column: &'a str, value: &'a str) -> impl Iterator<Item = &'a Vec<String>> + 'a {
        self.rows.iter().filter(move |r| self.text(r, column) == value)
    }
}

/// Where the records after `start` are cut into about `pieces` pieces: `start`, then
/// after a line feed outside quotes near each equal share of the rest, then the end. A
/// quote inside a quoted field is doubled, so the count of quotes before a byte tells
/// whether it lies inside one.
fn record_pieces(bytes: &[u8], start: usize, pieces: usize) -> Vec<usize> {
    let mut cuts = vec![start];
    let (mut at, mut quoted) = (start, false);
    for piece in 1..pieces.max(1) {
        let target = start + (bytes.len() - start) * piece / pieces;
        if target <= at {
            continue;
        }
        quoted ^= bytes[at..target].iter().filter(|&&b| b == b'"').count() % 2 == 1;
        at = target;
        while let Some(&b) = bytes.get(at) {
            at += 1;
            match b {
                b'"' => quoted = !quoted,
                b'\n' if !quoted => break,
                _ => {}
            }
        }
        if at < bytes.len() {
            cuts.push(at);
        }
    }
    cuts.push(bytes.len());
    cuts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formula_quotes_come_off_as_cells_are_read() {
        let text = "page,x\n'=1+2,-0.5\n''@a,'-1\n";
        let table = CsvTable::parse(text.as_bytes()).unwrap();
        assert_eq!(table.rows, [["=1+2", "-0.5"], ["'@a", "'-1"]]);
        let some = CsvTable::parse_selected(text.as_bytes(), &["page"], &|r| r.text("page") == "=1+2").unwrap();
        assert_eq!(some.rows, [["=1+2"]]);
    }

    #[test]
    fn typed_columns_read_their_cells_as_their_kind() {
        use nklut_tables::columns::{Integer, OptionalFloat, Text};
        let table = CsvTable::parse(b"name,depth,error\n\"a,b\",3,\nc,x,0.25\n").unwrap();
        let (name, depth, error) =
            (Column::<Text>::new("name", ""), Column::<Integer>::new("depth", ""), Column::<OptionalFloat>::new("error", ""));
        let absent = Column::<Integer>::new("absent", "");
        let (first, second) = (&table.rows[0], &table.rows[1]);
        assert_eq!((table.get(first, name), table.get(first, depth), table.get(first, error)), ("a,b", Some(3), None));
        assert_eq!((table.get(second, depth), table.get(second, error)), (None, Some(0.25)));
        assert_eq!((table.value(first, depth), table.value(second, error)), (Some(3.0), Some(0.25)));
        assert_eq!((table.raw(second, depth), table.get(first, absent), table.holds(absent)), ("x", None, false));
    }

    #[test]
    fn reads_quoted_fields_and_numbers() {
        let table = CsvTable::parse(b"page,x\n\"a,b\",1.5\nc,\n").unwrap();
        assert_eq!(table.text(&table.rows[0], "page"), "a,b");
        assert_eq!(table.number(&table.rows[0], "x"), Some(1.5));
        assert_eq!(table.number(&table.rows[1], "x"), None);
        assert_eq!(table.rows_where("page", "c").count(), 1);
        let some = CsvTable::parse_selected(b"page,x,y\na,1,2\nb,3,4\n", &["y", "page", "absent"], &|r| r.text("x") == "3").unwrap();
        assert_eq!(some.headers, vec!["y", "page"]);
        assert_eq!(some.rows, vec![vec!["4".to_string(), "b".to_string()]]);
    }

    /// The rows of `parse_selected` as one reader gives them, record by record.
    fn selected_by_one_reader(bytes: &[u8], columns: &[&str], keep: &dyn Fn(&csv::StringRecord) -> bool) -> Vec<Vec<String>> {
        let mut reader = csv::Reader::from_reader(bytes);
        let headers = reader.headers().unwrap().clone();
        let picked: Vec<usize> = columns.iter().filter_map(|c| headers.iter().position(|h| h == *c)).collect();
        reader.records().map(Result::unwrap).filter(|r| keep(r)).map(|r| picked.iter().map(|&i| r[i].to_string()).collect()).collect()
    }

    #[test]
    fn records_read_in_pieces_are_the_records_of_one_reader_in_order() {
        // Quoted fields with commas, quotes and line feeds, so that a cut inside a quote
        // would be seen; empty fields; CRLF endings on some lines.
        let mut text = String::from("page,variant,x\n");
        for i in 0..2000 {
            let variant = match i % 4 {
                0 => "\"N=256,unorm8,f64\"".to_string(),
                1 => format!("\"two\nlines {i}\""),
                2 => "\"a \"\"quoted\"\" word\"".to_string(),
                _ => String::new(),
            };
            let end = if i % 7 == 0 { "\r\n" } else { "\n" };
            text.push_str(&format!("p{i},{variant},{}{end}", i as f64 / 3.0));
        }
        let keep = |r: &Record| !r.text("page").ends_with('3');
        let table = CsvTable::parse_selected(text.as_bytes(), &["x", "variant", "page"], &keep).unwrap();
        let expected = selected_by_one_reader(text.as_bytes(), &["x", "variant", "page"], &|r| !r[0].ends_with('3'));
        assert_eq!(table.rows.len(), 1800);
        assert_eq!(table.rows, expected);
        // Every number of pieces, including more pieces than records.
        for pieces in [1, 2, 3, 8, 5000] {
            let cuts = record_pieces(text.as_bytes(), 15, pieces);
            assert!(cuts.windows(2).all(|w| w[0] < w[1]), "{pieces}: {cuts:?}");
            let records: usize = cuts
                .windows(2)
                .map(|w| csv::ReaderBuilder::new().has_headers(false).from_reader(&text.as_bytes()[w[0]..w[1]]).records().count())
                .sum();
            assert_eq!(records, 2000, "{pieces} pieces");
        }
    }

    #[test]
    fn a_broken_record_is_named_as_one_reader_names_it() {
        let mut text = String::from("page,x\n");
        for i in 0..3000 {
            text.push_str(&format!("p{i},{i}\n"));
        }
        text.push_str("broken\n");
        let error = CsvTable::parse_selected(text.as_bytes(), &["page"], &|_| true).unwrap_err().to_string();
        let one_reader = csv::Reader::from_reader(text.as_bytes()).records().find_map(Result::err).unwrap().to_string();
        assert_eq!(error, one_reader);
        assert!(error.contains("line: 3002"), "{error}");
    }
}
