//! The refractiveindex.info database on disk: the catalog, the data files, the book
//! `about.yml` names (SPEC §1).

pub mod block_yaml;
pub mod catalog;
pub mod error;
pub mod file;
pub mod formula;
pub mod page;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde::Deserialize;

pub use catalog::{Catalog, CatalogPage, RejectedEntry};
pub use error::{DataError, Reason};
pub use formula::Formula;
pub use page::{parse_page, Curve, PageData, Printed};

/// The database's folder in a checkout of nklut (`make db` links it there): where a program
/// may look when told nowhere else. The library reads no environment variable; the
/// program chooses the folder.
pub const DEFAULT_DB: &str = "refractiveindex/database";

/// The most bytes read from one data file or `about.yml` (the database's largest data
/// file holds about 1.2 MB).
pub const MAX_DATA_FILE_BYTES: u64 = 64 << 20;
/// The most bytes read from `catalog-nk.yml` (about 0.5 MB today).
pub const MAX_CATALOG_BYTES: u64 = 256 << 20;

/// A database folder: the one holding `catalog-nk.yml` and `data/`.
#[derive(Clone, Debug)]
pub struct Database {
    /// The `database` folder.
    pub root: PathBuf,
    /// `data/` with every symbolic link resolved: a data file whose resolved path leaves it
    /// is `path-outside-database`. `None` when `data/` cannot be resolved.
    resolved_data: Option<PathBuf>,
}

/// Why [`Database::open`] found no database.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// Neither the folder nor its `database/` holds `catalog-nk.yml`.
    #[error("no refractiveindex.info database at {} (expected catalog-nk.yml there or in database/)", dir.display())]
    NotFound {
        /// The folder looked in.
        dir: PathBuf,
    },
}

impl Database {
    /// The database at `dir`: the `database` folder itself or the repository folder above
    /// it, whichever holds `catalog-nk.yml`.
    pub fn open(dir: impl AsRef<Path>) -> Result<Self, OpenError> {
        let dir = dir.as_ref();
        for candidate in [dir.to_path_buf(), dir.join("database")] {
            // Anything named catalog-nk.yml marks the database (a FIFO or a folder there is
            // then refused by name when the catalog is read, not taken for no database).
            if candidate.join("catalog-nk.yml").exists() {
                let resolved_data = std::fs::canonicalize(candidate.join("data")).ok();
                return Ok(Self { root: candidate, resolved_data });
            }
        }
        Err(OpenError::NotFound { dir: dir.to_path_buf() })
    }

    /// Read and parse `catalog-nk.yml`.
    pub fn catalog(&self) -> Result<Catalog> {
        self.parse_catalog(&self.catalog_text()?)
    }

    fn catalog_path(&self) -> PathBuf {
        self.root.join("catalog-nk.yml")
    }

    /// The text of `catalog-nk.yml` (a regular file of at most [`MAX_CATALOG_BYTES`]).
    pub fn catalog_text(&self) -> Result<String> {
        let path = self.catalog_path();
        file::read_regular_text(&path, MAX_CATALOG_BYTES).with_context(|| format!("reading {}", path.display()))
    }

    /// [`Catalog::parse`] of the catalog's text, errors naming the file.
    pub fn parse_catalog(&self, text: &str) -> Result<Catalog> {
        Catalog::parse(text).with_context(|| format!("parsing {}", self.catalog_path().display()))
    }

    /// The path of data file `data` (relative to `data/`); not checked.
    pub fn data_path(&self, data: &str) -> PathBuf {
        self.root.join("data").join(data)
    }

    /// Read and parse one data file. The path must stay inside `data/`, as written and
    /// with its links resolved (`path-outside-database`), and name a regular file
    /// (`no-data-file`, `missing-file`, `not-a-regular-file`) of at most
    /// [`MAX_DATA_FILE_BYTES`] (`file-too-large`) holding UTF-8 text (`not-utf8`).
    pub fn read_page(&self, data: &str) -> Result<PageData, DataError> {
        // Each worker thread reads its files into one buffer it keeps: no allocation and no
        // fresh pages per file.
        thread_local! {
            static BUFFER: std::cell::RefCell<Vec<u8>> = const { std::cell::RefCell::new(Vec::new()) };
        }
        BUFFER.with_borrow_mut(|buffer| {
            let length = self.read_data_file(data, MAX_DATA_FILE_BYTES, buffer)?;
            parse_page(data, utf8_str(data, &buffer[..length])?)
        })
    }

    /// The bytes of the data file `data` (a path under `data/`) into `buffer`, with the
    /// checks of [`Database::read_page`]. Returns the number of bytes read.
    pub fn read_data_file(&self, data: &str, limit: u64, buffer: &mut Vec<u8>) -> Result<usize, DataError> {
        check_data_path(data)?;
        let path = self.data_path(data);
        let problem = |e: file::FileProblem| match e {
            file::FileProblem::NotRegular(kind) => {
                DataError::new(Reason::NotAFile, data, None, format!("the data path names {kind}, not a regular file"))
            }
            file::FileProblem::TooLarge { limit } => {
                DataError::new(Reason::FileTooLarge, data, None, format!("the data file holds more than {limit} bytes"))
            }
            file::FileProblem::Io(e) => DataError::new(Reason::MissingFile, data, None, e.to_string()),
        };
        let opened = file::open_regular(&path).map_err(problem)?;
        let inside = match (&self.resolved_data, file::resolved(&opened, &path)) {
            (Some(root), Ok(resolved)) => resolved.starts_with(root),
            _ => false,
        };
        if !inside {
            return Err(DataError::new(
                Reason::PathOutsideDatabase,
                data,
                None,
                "the data path leads out of the database's data folder through a symbolic link",
            ));
        }
        file::read_opened(opened, limit, buffer).map_err(problem)
    }

    /// `NAMES` of `data/<book>/about.yml`, HTML removed; `None` when the file is missing,
    /// unreadable or names nothing. Pages of one book share it: read it once per book.
    pub fn about_names(&self, book: &Path) -> Option<Vec<String>> {
        #[derive(Deserialize)]
        struct About {
            #[serde(rename = "NAMES", default)]
            names: Vec<serde_norway::Value>,
        }
        let mut buffer = Vec::new();
        let length = self.read_data_file(&book.join("about.yml").to_string_lossy(), MAX_DATA_FILE_BYTES, &mut buffer).ok()?;
        let text = std::str::from_utf8(&buffer[..length]).ok()?;
        let about: About = block_yaml::from_str(text).ok()?;
        let names: Vec<String> = about.names.iter().filter_map(|v| v.as_str().map(page::strip_html)).filter(|n| !n.is_empty()).collect();
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
            format!(
                "byte 0x{:02X} at offset {valid} is not UTF-8 (the database's files are UTF-8; re-encode it, e.g. from Latin-1)",
                bytes[valid]
            ),
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
