//! `catalog-nk.yml`: shelves → books → pages, with dividers (SPEC §1). Entries that
//! cannot become pages (an id that is empty or contains '/') are kept as rejected
//! entries with a reason, never dropped.

use serde_yaml::Value;

use super::error::{DataError, Reason};

/// One page of the catalog, identified as `shelf/book/page`.
#[derive(Clone, Debug, PartialEq)]
pub struct CatalogPage {
    pub shelf: String,
    pub book: String,
    pub page: String,
    /// The catalog's display names.
    pub shelf_name: String,
    pub book_name: String,
    pub page_name: String,
    /// The data file, relative to `database/data/`.
    pub data: String,
    /// The nearest DIVIDER above the page inside its book (e.g. "Experimental data: bulk").
    pub divider: Option<String>,
}

impl CatalogPage {
    pub fn id(&self) -> String {
        format!("{}/{}/{}", self.shelf, self.book, self.page)
    }

    /// `self.id() == id`, without building the id.
    pub fn has_id(&self, id: &str) -> bool {
        let page = id
            .strip_prefix(self.shelf.as_str())
            .and_then(|rest| rest.strip_prefix('/'))
            .and_then(|rest| rest.strip_prefix(self.book.as_str()))
            .and_then(|rest| rest.strip_prefix('/'));
        page == Some(self.page.as_str())
    }
}

/// The data paths a line scan of the catalog's text finds (`data: <path>` with a plain
/// value), sorted, each once: a guess made before the catalog is parsed, so that reading
/// the files can start meanwhile. The parsed catalog decides which files are used.
pub fn guess_data_paths(text: &str) -> Vec<&str> {
    let mut paths: Vec<&str> = text
        .lines()
        .filter_map(|line| line.trim_start().strip_prefix("data:"))
        .map(str::trim)
        .filter(|path| path.ends_with(".yml") && !path.starts_with(['"', '\'', '[', '{', '&', '*', '!', '|', '>']))
        .collect();
    paths.sort_unstable();
    paths.dedup();
    paths
}

/// The whole catalog, pages in file order, each id once.
#[derive(Clone, Debug, Default)]
pub struct Catalog {
    pub pages: Vec<CatalogPage>,
    /// Later entries whose id was already listed (the real catalog lists some glass pages
    /// under two dividers). Same data file: the same page, listed once in `pages`.
    /// Another data file: excluded as `duplicate-page-id` by the ingest.
    pub duplicates: Vec<CatalogPage>,
    /// Entries whose shelf, book or page id is unusable (empty, or containing '/', which
    /// would make `shelf/book/page` ambiguous). The ingest lists them as excluded.
    pub rejected: Vec<RejectedEntry>,
}

/// A catalog entry that cannot become a page: the id as written and the error.
#[derive(Clone, Debug, PartialEq)]
pub struct RejectedEntry {
    pub shelf: String,
    pub id: String,
    pub error: DataError,
}

/// Why an id cannot be part of `shelf/book/page`, if it cannot.
fn id_problem(what: &str, id: &str) -> Option<String> {
    if id.trim().is_empty() {
        Some(format!("the {what} id is empty"))
    } else if id.contains('/') {
        Some(format!("the {what} id {id:?} contains '/'"))
    } else {
        None
    }
}

fn field(map: &Value, key: &str) -> Option<String> {
    match map.get(key)? {
        Value::String(s) => Some(s.clone()),
        Value::Number(n) => Some(n.to_string()),
        Value::Bool(b) => Some(b.to_string()),
        _ => None,
    }
}

fn items(map: &Value) -> &[Value] {
    map.get("content").and_then(Value::as_sequence).map(Vec::as_slice).unwrap_or(&[])
}

impl Catalog {
    /// Parse the catalog text. A page without a data path keeps an empty `data` (reading
    /// it is a `no-data-file` error); entries with unusable ids go to `rejected`. Never
    /// panics.
    pub fn parse(yaml: &str) -> Result<Catalog, serde_yaml::Error> {
        let root: Value = match super::block_yaml::block_value(yaml) {
            Some(root) => root,
            None => serde_yaml::from_str(yaml)?,
        };
        let mut catalog = Catalog::default();
        let mut seen = std::collections::HashSet::new();
        for shelf in root.as_sequence().map(Vec::as_slice).unwrap_or(&[]) {
            let Some(shelf_id) = field(shelf, "SHELF") else { continue };
            let shelf_name = field(shelf, "name").unwrap_or_else(|| shelf_id.clone());
            for book in items(shelf) {
                let Some(book_id) = field(book, "BOOK") else { continue };
                let book_name = field(book, "name").unwrap_or_else(|| book_id.clone());
                let mut divider = None;
                for page in items(book) {
                    if let Some(d) = field(page, "DIVIDER") {
                        divider = Some(d);
                        continue;
                    }
                    let Some(page_id) = field(page, "PAGE") else { continue };
                    let data = field(page, "data").unwrap_or_default();
                    let problem = id_problem("shelf", &shelf_id)
                        .or_else(|| id_problem("book", &book_id))
                        .or_else(|| id_problem("page", &page_id));
                    if let Some(detail) = problem {
                        catalog.rejected.push(RejectedEntry {
                            shelf: shelf_id.clone(),
                            id: format!("{shelf_id}/{book_id}/{page_id}"),
                            error: DataError::new(Reason::BadPageId, &data, None, detail),
                        });
                        continue;
                    }
                    let entry = CatalogPage {
                        shelf: shelf_id.clone(),
                        book: book_id.clone(),
                        page: page_id.clone(),
                        shelf_name: shelf_name.clone(),
                        book_name: book_name.clone(),
                        page_name: field(page, "name").unwrap_or_else(|| page_id.clone()),
                        data,
                        divider: divider.clone(),
                    };
                    if seen.insert(entry.id()) {
                        catalog.pages.push(entry);
                    } else {
                        catalog.duplicates.push(entry);
                    }
                }
            }
        }
        Ok(catalog)
    }

    pub fn find(&self, id: &str) -> Option<&CatalogPage> {
        self.pages.iter().find(|p| p.has_id(id))
    }

    pub fn shelves(&self) -> Vec<String> {
        let mut shelves: Vec<String> = Vec::new();
        for page in &self.pages {
            if !shelves.contains(&page.shelf) {
                shelves.push(page.shelf.clone());
            }
        }
        shelves
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_shelves_books_pages_and_dividers() {
        let text = r#"
- DIVIDER: "Research data"
- SHELF: main
  name: "MAIN"
  content:
    - DIVIDER: "Au - Gold"
    - BOOK: Au
      name: "Au (Gold)"
      content:
        - DIVIDER: "Experimental"
        - PAGE: Johnson
          name: "Johnson and Christy"
          data: main/Au/nk/Johnson.yml
        - PAGE: Broken
          name: "no data"
        - PAGE: "a/b"
          data: main/Au/nk/Johnson.yml
        - PAGE: ""
          data: main/Au/nk/Johnson.yml
        - DIVIDER: "Again"
        - PAGE: Johnson
          data: main/Au/nk/Johnson.yml
- SHELF: 3d
  name: "3D"
  content:
    - BOOK: metals
      content:
        - PAGE: gold
          data: main/Au/nk/Johnson.yml
"#;
        let catalog = Catalog::parse(text).unwrap();
        assert_eq!(catalog.pages.len(), 3);
        assert_eq!(catalog.pages[0].id(), "main/Au/Johnson");
        // A page without a data key stays a page; reading its empty path is the error.
        assert_eq!(catalog.pages[1].id(), "main/Au/Broken");
        assert_eq!(catalog.pages[1].data, "");
        let rejected: Vec<(&str, Reason)> = catalog.rejected.iter().map(|r| (r.id.as_str(), r.error.reason)).collect();
        assert_eq!(rejected, vec![("main/Au/a/b", Reason::BadPageId), ("main/Au/", Reason::BadPageId)]);
        assert!(catalog.rejected[0].error.detail.contains("contains '/'"));
        assert!(catalog.rejected[1].error.detail.contains("empty"));
        assert_eq!(catalog.pages[0].divider.as_deref(), Some("Experimental"));
        assert_eq!(catalog.pages[2].id(), "3d/metals/gold");
        assert_eq!(catalog.pages[2].book_name, "metals");
        assert_eq!(catalog.pages[0].data, catalog.pages[2].data);
        assert_eq!(catalog.duplicates.len(), 1);
        assert_eq!(catalog.duplicates[0].divider.as_deref(), Some("Again"));
        assert_eq!(catalog.shelves(), vec!["main", "3d"]);
        assert!(catalog.pages[0].has_id("main/Au/Johnson"));
        for other in ["main/Au/Johnso", "main/Au/Johnson/", "main/AuJohnson", "main//Au/Johnson", "3d/metals/gold", ""] {
            assert!(!catalog.pages[0].has_id(other), "{other}");
        }
        assert_eq!(guess_data_paths(text), vec!["main/Au/nk/Johnson.yml"]);
    }
}
