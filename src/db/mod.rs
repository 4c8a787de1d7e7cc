//! The refractiveindex.info database on disk: the catalog, the data files, the book
//! `about.yml` names (SPEC §1).

pub mod block_yaml;
pub mod catalog;
pub mod error;
pub mod formula;
pub mod page;

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use serde::Deserialize;

pub use catalog::{Catalog, CatalogPage, RejectedEntry};
pub use error::{DataError, Reason};
pub use formula::Formula;
pub use page::{parse_page, Curve, PageData, Printed};

/// Where the database is looked for when neither `--db` nor `NKLUT_DB` says.
pub const DEFAULT_DB: &str = "refractiveindex/database";

/// A database folder: the one holding `catalog-nk.yml` and `data/`.
#[derive(Clone, Debug)]
pub struct Database {
    pub root: PathBuf,
}

impl Database {
    /// Resolve `--db DIR` (or `NKLUT_DB`, or the default) and check it looks right. DIR
    /// may be the `database` folder itself or the repository folder above it.
    pub fn open(dir: Option<&Path>) -> Result<Self> {
        let dir = match dir {
            Some(d) => d.to_path_buf(),
            None => std::env::var_os("NKLUT_DB").map(PathBuf::from).unwrap_or_else(|| PathBuf::from(DEFAULT_DB)),
        };
        for candidate in [dir.clone(), dir.join("database")] {
            if candidate.join("catalog-nk.yml").is_file() {
                return Ok(Self { root: candidate });
            }
        }
        bail!(
            "no refractiveindex.info database at {} (expected catalog-nk.yml there or in database/); run `make db` or pass --db DIR",
            dir.display()
        )
    }

    pub fn catalog(&self) -> Result<Catalog> {
        self.parse_catalog(&self.catalog_text()?)
    }

    fn catalog_path(&self) -> PathBuf {
        self.root.join("catalog-nk.yml")
    }

    /// The text of `catalog-nk.yml`.
    pub fn catalog_text(&self) -> Result<String> {
        let path = self.catalog_path();
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))
    }

    /// [`Catalog::parse`] of the catalog's text, errors naming the file.
    pub fn parse_catalog(&self, text: &str) -> Result<Catalog> {
        Catalog::parse(text).with_context(|| format!("parsing {}", self.catalog_path().display()))
    }

    pub fn data_path(&self, data: &str) -> PathBuf {
        self.root.join("data").join(data)
    }

    /// Read and parse one data file. The path must stay inside `data/`
    /// (`path-outside-database`), name a readable file (`no-data-file`, `missing-file`)
    /// holding UTF-8 text (`not-utf8`).
    pub fn read_page(&self, data: &str) -> Result<PageData, DataError> {
        check_data_path(data)?;
        let path = self.data_path(data);
        // Each worker thread reads its files into one buffer it keeps: no allocation and no
        // fresh pages per file.
        thread_local! {
            static BUFFER: std::cell::RefCell<Vec<u8>> = const { std::cell::RefCell::new(Vec::new()) };
        }
        BUFFER.with_borrow_mut(|buffer| {
            let length = read_into(&path, buffer).map_err(|e| {
                // A folder opens but does not read: named as such, as before reading.
                let detail = if path.is_dir() { "the data path names a folder, not a file".to_string() } else { e.to_string() };
                DataError::new(Reason::MissingFile, data, None, detail)
            })?;
            parse_page(data, utf8_str(data, &buffer[..length])?)
        })
    }

    /// `NAMES` of `data/<book>/about.yml`, HTML removed; `None` when the file is missing,
    /// unreadable or names nothing. Pages of one book share it: read it once per book.
    pub fn about_names(&self, book: &Path) -> Option<Vec<String>> {
        #[derive(Deserialize)]
        struct About {
            #[serde(rename = "NAMES", default)]
            names: Vec<serde_yaml::Value>,
        }
        let text = std::fs::read_to_string(self.root.join("data").join(book).join("about.yml")).ok()?;
        let about: About = block_yaml::from_str(&text).ok()?;
        let names: Vec<String> = about
            .names
            .iter()
            .filter_map(|v| v.as_str().map(page::strip_html))
            .filter(|n| !n.is_empty())
            .collect();
        (!names.is_empty()).then_some(names)
    }
}

/// The book folder of a data file (`main/Au/nk/Johnson.yml` → `main/Au`): the folder above
/// the one holding the file, where its `about.yml` lives. `None` for a path too short.
pub fn book_dir(data: &str) -> Option<&Path> {
    Path::new(data).parent()?.parent()
}

/// A catalog data path must be a non-empty relative path that stays inside `data/`: no
/// root, no `..`, judged on the text alone (before any file is opened).
pub fn check_data_path(data: &str) -> Result<(), DataError> {
    use std::path::Component;
    if data.trim().is_empty() {
        return Err(DataError::new(Reason::NoDataFile, data, None, "the catalog entry names no data file"));
    }
    let path = Path::new(data);
    if path.is_absolute() || path.components().any(|c| matches!(c, Component::ParentDir | Component::RootDir | Component::Prefix(_))) {
        return Err(DataError::new(
            Reason::PathOutsideDatabase,
            data,
            None,
            "the data path is absolute or climbs out of the database's data folder with '..'",
        ));
    }
    Ok(())
}

/// The whole file at `path` into `buffer` (kept initialised and reused: its length only
/// grows), without asking the file's size first. Returns the number of bytes read.
fn read_into(path: &Path, buffer: &mut Vec<u8>) -> std::io::Result<usize> {
    use std::io::Read;
    let mut file = std::fs::File::open(path)?;
    let mut length = 0;
    loop {
        if length == buffer.len() {
            buffer.resize((2 * buffer.len()).max(1 << 16), 0);
        }
        match file.read(&mut buffer[length..]) {
            Ok(0) => return Ok(length),
            Ok(read) => length += read,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

/// The file's bytes as text. A UTF-8 byte-order mark is dropped (YAML allows one);
/// anything that is not UTF-8 (a Latin-1 file, say) is `not-utf8` at the line of the
/// first bad byte.
pub fn utf8_str<'a>(file: &str, bytes: &'a [u8]) -> Result<&'a str, DataError> {
    const BOM: &[u8] = b"\xEF\xBB\xBF";
    let bytes = bytes.strip_prefix(BOM).unwrap_or(bytes);
    std::str::from_utf8(bytes).map_err(|e| {
        let valid = e.valid_up_to();
        let line = 1 + bytes[..valid].iter().filter(|&&b| b == b'\n').count();
        DataError::new(
            Reason::NotUtf8,
            file,
            Some(line),
            format!("byte 0x{:02X} at offset {valid} is not UTF-8 (the database's files are UTF-8; re-encode it, e.g. from Latin-1)", bytes[valid]),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_paths_must_stay_inside_the_database() {
        assert_eq!(check_data_path("").unwrap_err().reason, Reason::NoDataFile);
        assert_eq!(check_data_path("  ").unwrap_err().reason, Reason::NoDataFile);
        assert_eq!(check_data_path("../../../../etc/hostname").unwrap_err().reason, Reason::PathOutsideDatabase);
        assert_eq!(check_data_path("main/../../x.yml").unwrap_err().reason, Reason::PathOutsideDatabase);
        assert_eq!(check_data_path("/etc/hostname").unwrap_err().reason, Reason::PathOutsideDatabase);
        assert!(check_data_path("main/Au/nk/Johnson.yml").is_ok());
    }

    #[test]
    fn byte_order_mark_is_dropped_and_latin1_is_named_with_its_line() {
        assert_eq!(utf8_str("a.yml", b"\xEF\xBB\xBFDATA: x\n").unwrap(), "DATA: x\n");
        let e = utf8_str("b.yml", b"REFERENCES: ok\nCOMMENTS: caf\xE9\n").unwrap_err();
        assert_eq!((e.reason, e.line), (Reason::NotUtf8, Some(2)));
        assert!(e.detail.contains("0xE9"), "{}", e.detail);
    }
}
