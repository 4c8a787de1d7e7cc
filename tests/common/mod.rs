//! Helpers shared by the integration tests: the scan for non-finite numbers in written
//! tables.

use std::fs;
use std::path::{Path, PathBuf};

/// Every file below `dir`, following the links of the output folder's published sets.
pub fn files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in fs::read_dir(dir).unwrap() {
        let entry = entry.unwrap();
        let path = entry.path();
        if entry.file_type().unwrap().is_dir() {
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
