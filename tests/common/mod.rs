//! Helpers shared by the integration tests: the database they read, scratch folders that
//! remove themselves, the scan for non-finite numbers in written tables, and the GPU tests'
//! device (`gpu`).

#![allow(dead_code)] // each test binary uses a part

use std::fs;
use std::ops::Deref;
use std::path::{Path, PathBuf};

use nklut::db::Database;

#[cfg(feature = "gpu")]
pub mod gpu;

/// The database every test reads, by the rule of the binary and the unit tests
/// (`Database::open(None)`): `$NKLUT_DB`, else `refractiveindex/database` (`make db`).
pub fn database() -> Database {
    Database::open(None).expect("no database: run `make db` (or set NKLUT_DB)")
}

/// The database folder, for `nklut --db` in subprocess tests.
pub fn database_dir() -> PathBuf {
    database().root
}

/// An empty folder under the target's temporary directory, removed when dropped.
pub struct Scratch(tempfile::TempDir);

impl Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

/// A fresh scratch folder whose name starts with `name`.
pub fn scratch(name: &str) -> Scratch {
    let dir = tempfile::Builder::new()
        .prefix(&format!("{name}-"))
        .tempdir_in(env!("CARGO_TARGET_TMPDIR"))
        .expect("a scratch folder in the target directory");
    Scratch(dir)
}

/// Every file below `dir` as a reader of the output folder sees it: the links of the
/// published sets followed (files and folders such as `luts/`), the generations under
/// `.sets/` themselves not listed again.
pub fn files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in fs::read_dir(dir).unwrap() {
        let entry = entry.unwrap();
        let path = entry.path();
        if entry.file_name() == ".sets" {
            continue;
        }
        if path.is_dir() {
            found.extend(files(&path));
        } else if path.exists() {
            found.push(path);
        }
    }
    found
}

/// Cells of a CSV or JSON text that read as a non-finite number.
pub fn non_finite_cells(text: &str) -> Vec<String> {
    text.split([',', '\n', ' ', ':', '"', '[', ']'])
        .map(|t| t.trim().to_ascii_lowercase())
        .filter(|t| matches!(t.as_str(), "nan" | "-nan" | "inf" | "-inf" | "+inf" | "infinity" | "-infinity"))
        .collect()
}

/// Every CSV and JSON table below `dir`, with its non-finite cells (empty when clean).
pub fn non_finite_tables(dir: &Path) -> Vec<(String, Vec<String>)> {
    files(dir)
        .into_iter()
        .map(|path| path.to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".csv") || name.ends_with(".json"))
        .map(|name| {
            let bad = non_finite_cells(&fs::read_to_string(&name).unwrap());
            (name, bad)
        })
        .collect()
}
