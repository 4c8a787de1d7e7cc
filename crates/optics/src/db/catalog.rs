//! `catalog-nk.yml`: shelves → books → pages, with dividers (SPEC §1). Entries that
//! cannot become pages are kept as rejected entries with a reason, never dropped: an id
//! that is empty, `.` or `..`, or holds '/' or a control character (`bad-page-id`); a
//! SHELF, BOOK or PAGE that is not a single value (a list, a mapping, null), a `data` that
//! is not a path, or an entry of a book that is neither a page nor a divider
//! (`bad-catalog-entry`; every page below a bad shelf or book is rejected). The entries
//! are the items of the books' content: a shelf or book without content holds none.

use serde_norway::Value;

use super::error::{DataError, Reason};

/// One page of the catalog, identified as `shelf/book/page`.
#[derive(Clone, Debug, PartialEq)]
pub struct CatalogPage {
    /// The shelf id (`3d`, `main`, …).
    pub shelf: String,
    /// The book id.
    pub book: String,
    /// The page id.
    pub page: String,
    /// The catalog's display names.
    pub shelf_name: String,
    /// The book's display name.
    pub book_name: String,
    /// The page's display name.
    pub page_name: String,
    /// The data file, relative to `database/data/`.
    pub data: String,
    /// The nearest DIVIDER above the page inside its book (e.g. "Experimental data: bulk").
    pub divider: Option<String>,
}

impl CatalogPage {
    /// `shelf/book/page`.
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
    /// Every usable page, in file order, each id once.
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
    /// The shelf the entry sits on.
    pub shelf: String,
    /// The entry's id as written.
    pub id: String,
    /// Why it cannot be a page.
    pub error: DataError,
}

/// Why an id cannot be part of `shelf/book/page` (nor a file name made of it), if it cannot.
fn id_problem(what: &str, id: &str) -> Option<String> {
    if id.trim().is_empty() {
        Some(format!("the {what} id is empty"))
    } else if id.contains('/') {
        Some(format!("the {what} id {id:?} contains '/'"))
    } else if id == "." || id == ".." {
        Some(format!("the {what} id {id:?} names a folder, not an entry"))
    } else if id.chars().any(char::is_control) {
        Some(format!("the {what} id {id:?} contains a control character"))
    } else {
        None
    }
}

/// A scalar's text (strings, numbers and booleans alike).
fn scalar(value: &Value) -> Option<String> {
    match value {
        Value::String(s) => Some(s.clone()),
        Value::Number(n) => Some(n.to_string()),
        Value::Bool(b) => Some(b.to_string()),
        _ => None,
    }
}

fn field(map: &Value, key: &str) -> Option<String> {
    scalar(map.get(key)?)
}

/// A value as one short line (JSON), for the id of an entry that has none.
fn shown(value: &Value) -> String {
    let line = serde_json::to_string(value).unwrap_or_else(|_| "(a value with keys that are not text)".into());
    match line.char_indices().nth(60) {
        Some((cut, _)) => format!("{}…", &line[..cut]),
        None => line,
    }
}

/// What the `key` of a catalog level holds: an id, a value that is not one, or nothing.
enum Id {
    Scalar(String),
    NotScalar(String),
    Missing,
}

fn id_of(map: &Value, key: &str) -> Id {
    match map.get(key) {
        None => Id::Missing,
        Some(value) => scalar(value).map_or_else(|| Id::NotScalar(shown(value)), Id::Scalar),
    }
}

fn items(map: &Value) -> &[Value] {
    map.get("content").and_then(Value::as_sequence).map(Vec::as_slice).unwrap_or(&[])
}

/// Why a catalog could not be read at all.
#[derive(Debug, thiserror::Error)]
pub enum CatalogError {
    /// The text is not YAML.
    #[error(transparent)]
    Yaml(#[from] serde_norway::Error),
    /// The YAML nests too deep.
    #[error("{0} (nesting-too-deep)")]
    TooDeep(#[from] super::block_yaml::TooDeep),
    /// The top level is not a list of shelves.
    #[error("the catalog's top level is not a list of shelves")]
    NotAList,
}

/// A level of the catalog whose id is unusable: every page below it is rejected with the
/// reason, under the id `shelf/book/page` made of what each level holds.
struct Unusable {
    reason: Reason,
    detail: String,
}

/// The id an entry holds under `key` (SHELF, BOOK or PAGE; inside a `holder`) and why it
/// cannot be used, if it cannot; `None` for a divider (no `key`, a DIVIDER).
fn level(entry: &Value, key: &str, holder: &str) -> Option<(String, Option<Unusable>)> {
    let what = key.to_lowercase();
    match id_of(entry, key) {
        Id::Scalar(id) => {
            let problem = id_problem(&what, &id).map(|detail| Unusable { reason: Reason::BadPageId, detail });
            Some((id, problem))
        }
        Id::NotScalar(shown) => {
            let detail = format!("the {key} is {shown}, not a single value");
            Some((shown, Some(Unusable { reason: Reason::BadCatalogEntry, detail })))
        }
        Id::Missing if entry.get("DIVIDER").is_some() => None,
        Id::Missing => {
            let detail = format!("an entry of the {holder} that is neither a {key} nor a DIVIDER");
            Some((shown(entry), Some(Unusable { reason: Reason::BadCatalogEntry, detail })))
        }
    }
}

impl Catalog {
    /// Parse the catalog text. A page without a data path keeps an empty `data` (reading
    /// it is a `no-data-file` error); entries that cannot become pages go to `rejected`.
    /// Never panics; text nesting deeper than the YAML readers take is an error.
    pub fn parse(yaml: &str) -> Result<Catalog, CatalogError> {
        let root: Value = match super::block_yaml::block_value(yaml) {
            Some(root) => root,
            None => {
                if let Some(deep) = super::block_yaml::too_deep(yaml) {
                    return Err(deep.into());
                }
                serde_norway::from_str(yaml)?
            }
        };
        let shelves = root.as_sequence().ok_or(CatalogError::NotAList)?;
        let mut seen = std::collections::HashSet::new();
        let mut rejected = Vec::new();
        let mut add_rejected = |shelf: &str, id: String, reason: Reason, data: &str, detail: String| {
            rejected.push(RejectedEntry { shelf: shelf.to_string(), id, error: DataError::new(reason, data, None, detail) });
        };
        let mut pages = Vec::new();
        let mut duplicates = Vec::new();
        for shelf in shelves {
            let Some((shelf_id, shelf_problem)) = level(shelf, "SHELF", "top level") else { continue };
            let shelf_name = field(shelf, "name").unwrap_or_else(|| shelf_id.clone());
            for book in items(shelf) {
                let Some((book_id, book_problem)) = level(book, "BOOK", "shelf") else { continue };
                let problem_above = shelf_problem.as_ref().or(book_problem.as_ref());
                let book_name = field(book, "name").unwrap_or_else(|| book_id.clone());
                let mut divider = None;
                for page in items(book) {
                    let Some((page_id, page_problem)) = level(page, "PAGE", "book") else {
                        divider = field(page, "DIVIDER");
                        continue;
                    };
                    let (data, data_problem) = match page.get("data") {
                        None => (String::new(), None),
                        Some(value) => match scalar(value) {
                            Some(path) => (path, None),
                            None => {
                                let detail = format!("the data path is {}, not a single value", shown(value));
                                (String::new(), Some(Unusable { reason: Reason::BadCatalogEntry, detail }))
                            }
                        },
                    };
                    let id = format!("{shelf_id}/{book_id}/{page_id}");
                    if let Some(problem) = problem_above.or(page_problem.as_ref()).or(data_problem.as_ref()) {
                        add_rejected(&shelf_id, id, problem.reason, &data, problem.detail.clone());
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
                    if seen.insert(id) {
                        pages.push(entry);
                    } else {
                        duplicates.push(entry);
                    }
                }
            }
        }
        Ok(Catalog { pages, duplicates, rejected })
    }

    /// The page of id `shelf/book/page`.
    pub fn find(&self, id: &str) -> Option<&CatalogPage> {
        self.pages.iter().find(|p| p.has_id(id))
    }

    /// The shelf ids, in file order, each once.
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

    /// Entries whose levels are not single values, or that are neither pages nor dividers,
    /// are rejected with what they hold; every PAGE of the text is in exactly one list.
    #[test]
    fn entries_that_cannot_be_pages_are_rejected_never_dropped() {
        let text = r#"
- SHELF: s
  content:
    - BOOK: ~
      content:
        - PAGE: a
          data: s/a.yml
    - BOOK: b
      content:
        - PAGE: [1, 2]
          data: s/b.yml
        - PAGE: {x: 1}
          data: s/c.yml
        - PAGE: ".."
          data: s/d.yml
        - PAGE: "."
          data: s/e.yml
        - PAGE: "tab\there"
          data: s/f.yml
        - PAGE: listed-data
          data: [x.yml]
        - name: "no PAGE key"
          data: s/g.yml
        - PAGE: good
          data: s/h.yml
- SHELF: [1, 2]
  content:
    - BOOK: c
      content:
        - PAGE: p
          data: s/i.yml
- name: "neither shelf nor divider"
"#;
        let catalog = Catalog::parse(text).unwrap();
        assert_eq!(catalog.pages.iter().map(CatalogPage::id).collect::<Vec<_>>(), ["s/b/good"]);
        let rejected: Vec<(&str, &str)> = catalog.rejected.iter().map(|r| (r.id.as_str(), r.error.reason.code())).collect();
        assert_eq!(
            rejected,
            [
                ("s/null/a", "bad-catalog-entry"),
                ("s/b/[1,2]", "bad-catalog-entry"),
                ("s/b/{\"x\":1}", "bad-catalog-entry"),
                ("s/b/..", "bad-page-id"),
                ("s/b/.", "bad-page-id"),
                ("s/b/tab\there", "bad-page-id"),
                ("s/b/listed-data", "bad-catalog-entry"),
                ("s/b/{\"name\":\"no PAGE key\",\"data\":\"s/g.yml\"}", "bad-catalog-entry"),
                ("[1,2]/c/p", "bad-catalog-entry"),
            ]
        );
        // Every item of a book's content is one entry: the PAGE keys and the one without.
        let pages_in_text = text.matches("PAGE:").count();
        assert_eq!(catalog.pages.len() + catalog.rejected.len(), pages_in_text + 1);
        assert!(matches!(Catalog::parse("SHELF: x\n"), Err(CatalogError::NotAList)));
        let deep = format!("{}{}", "[".repeat(MAX + 1), "]".repeat(MAX + 1));
        assert!(matches!(Catalog::parse(&deep), Err(CatalogError::TooDeep(_))));
    }

    const MAX: usize = crate::db::block_yaml::MAX_NESTING;
}
