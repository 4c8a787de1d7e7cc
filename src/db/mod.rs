//! The refractiveindex.info database on disk: the catalog, the data files, the book
//! `about.yml` names (SPEC §1).

pub mod catalog;
pub mod error;
pub mod formula;
pub mod page;

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use serde::Deserialize;

pub use catalog::{Catalog, CatalogPage};
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

    pub fn catalog(&self) -> Result<(Catalog, Vec<String>)> {
        let path = self.root.join("catalog-nk.yml");
        let text = std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
        Catalog::parse(&text).with_context(|| format!("parsing {}", path.display()))
    }

    pub fn data_path(&self, data: &str) -> PathBuf {
        self.root.join("data").join(data)
    }

    /// Read and parse one data file; a missing file is a `missing-file` error.
    pub fn read_page(&self, data: &str) -> Result<PageData, DataError> {
        let text = std::fs::read_to_string(self.data_path(data))
            .map_err(|e| DataError::new(Reason::MissingFile, data, None, e.to_string()))?;
        parse_page(data, &text)
    }

    /// The material names of the book a data file belongs to: `NAMES` of the `about.yml`
    /// beside its `nk/` folder, HTML removed. `None` when there is no such file.
    pub fn book_names(&self, data: &str) -> Option<Vec<String>> {
        #[derive(Deserialize)]
        struct About {
            #[serde(rename = "NAMES", default)]
            names: Vec<serde_yaml::Value>,
        }
        let book_dir = Path::new(data).parent()?.parent()?;
        let text = std::fs::read_to_string(self.root.join("data").join(book_dir).join("about.yml")).ok()?;
        let about: About = serde_yaml::from_str(&text).ok()?;
        let names: Vec<String> = about
            .names
            .iter()
            .filter_map(|v| v.as_str().map(page::strip_html))
            .filter(|n| !n.is_empty())
            .collect();
        (!names.is_empty()).then_some(names)
    }
}
