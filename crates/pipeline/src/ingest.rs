//! The ingest stage: `nklut_tables::ingest` (catalog → every named data file → coverage
//! filter and channel indices → the tables; re-exported here at its old paths), and its
//! tables `materials.*`, `excluded.csv` and `warnings.csv` published as one set.

use std::path::{Path, PathBuf};

use anyhow::Result;

pub use nklut_tables::ingest::*;

use crate::output::{SetContent, SetFile, TableFiles};

/// Publish `materials.{csv,parquet,json}` (+ columns), `excluded.csv` and `warnings.csv`
/// under `out` as one set; the materials' encodings run as their files are written.
pub fn write_tables(ingest: &Ingest, out: &Path) -> Result<Vec<PathBuf>> {
    let materials = materials_table(ingest);
    let excluded = SetFile::new("excluded.csv", problems_table(&ingest.excluded).to_csv()?);
    let warnings = SetFile::new("warnings.csv", problems_table(&ingest.warnings).to_csv()?);
    let streamed = materials.streamed_files("materials", true);
    let files: Vec<&dyn SetContent> =
        streamed.iter().map(|f| f as &dyn SetContent).chain([&excluded as &dyn SetContent, &warnings]).collect();
    crate::output::publish_contents(out, "ingest", &files)
}
