//! The ingest stage: catalog → every named data file (each parsed once, in parallel) →
//! coverage filter and channel indices → the tables of `materials.*`, `excluded.csv` and
//! `warnings.csv` (published as one set by the pipeline's `ingest::write_tables`).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::sync::Arc;

use anyhow::{bail, Result};
use rayon::prelude::*;

use crate::output::Table;
use nklut_optics::db::{book_dir, check_data_path, CatalogPage, DataError, Database, Reason};
use nklut_optics::spectrum::{self, Channels, Coverage, Material, CHANNEL_NAMES, SPARSE_GAP_NM};

/// How pages are read: the channel wavelengths and the coverage rule. Every stage that
/// reads pages takes one, so the wavelengths chosen at ingest reach every table.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Config {
    pub channels: Channels,
    pub coverage: Coverage,
    /// Data errors (other than missing coverage) and warnings are fatal.
    pub strict: bool,
}

/// Which pages to ingest: the whole catalog, or the shelves and pages named.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Selection {
    /// Every page of the catalog.
    All,
    /// The pages of these shelves and these pages (ids such as 3d/metals/gold); naming
    /// nothing selects nothing.
    Named {
        /// Catalog shelves, every page of each.
        shelves: Vec<String>,
        /// Page ids.
        pages: Vec<String>,
    },
}

impl Selection {
    /// Every page of one shelf.
    pub fn shelf(name: &str) -> Self {
        Self::Named { shelves: vec![name.to_string()], pages: vec![] }
    }

    /// These pages.
    pub fn pages(pages: impl IntoIterator<Item = impl Into<String>>) -> Self {
        Self::Named { shelves: vec![], pages: pages.into_iter().map(Into::into).collect() }
    }

    /// The page ids named (none for [`Selection::All`]).
    pub fn named_pages(&self) -> &[String] {
        match self {
            Self::All => &[],
            Self::Named { pages, .. } => pages,
        }
    }

    /// The shelves named (none for [`Selection::All`]).
    pub fn named_shelves(&self) -> &[String] {
        match self {
            Self::All => &[],
            Self::Named { shelves, .. } => shelves,
        }
    }

    /// [`Selection::includes_id`] of a catalog page, without formatting its id.
    fn includes(&self, page: &CatalogPage) -> bool {
        self.selects(&page.shelf, |id| page.has_id(id))
    }

    /// Whether the page `id` on `shelf` is selected. Tables are filtered by this rule.
    pub fn includes_id(&self, shelf: &str, id: &str) -> bool {
        self.selects(shelf, |named| named == id)
    }

    /// The rule: every page for [`Selection::All`], else the named shelves and the pages
    /// for which `is_page` holds of a named id.
    fn selects(&self, shelf: &str, is_page: impl Fn(&str) -> bool) -> bool {
        match self {
            Self::All => true,
            Self::Named { shelves, pages } => shelves.iter().any(|s| s == shelf) || pages.iter().any(|id| is_page(id)),
        }
    }
}

/// A page that passed the filter.
#[derive(Clone, Debug)]
pub struct KeptPage {
    pub page: CatalogPage,
    /// Material names from the book's `about.yml`, else the catalog's book name.
    pub names: Vec<String>,
    /// Shared by every page pointing at the same data file (evaluated once).
    pub material: Arc<Material>,
    /// The selected page ids that use the same data file, this one included, in catalog
    /// order: one list per file, shared by its pages (memory linear in the pages however
    /// many share a file).
    pub sharing: Arc<[String]>,
}

/// How many of the other pages sharing a data file `materials.*` lists by id; more are
/// counted ("… and N more"), so the table grows linearly with the pages.
pub const SHARED_WITH_LISTED: usize = 8;

impl KeptPage {
    pub fn id(&self) -> String {
        self.page.id()
    }

    /// The other selected page ids that use the same data file.
    pub fn shared_with(&self) -> impl Iterator<Item = &str> {
        self.sharing.iter().map(String::as_str).filter(move |other| !self.page.has_id(other))
    }

    /// [`KeptPage::shared_with`] as `materials.*` writes it: '; '-separated, the first
    /// [`SHARED_WITH_LISTED`] by id and the rest counted.
    pub fn shared_with_text(&self) -> String {
        let others = self.sharing.len().saturating_sub(1);
        let mut text = self.shared_with().take(SHARED_WITH_LISTED).collect::<Vec<_>>().join("; ");
        if others > SHARED_WITH_LISTED {
            text.push_str(&format!("; … and {} more", others - SHARED_WITH_LISTED));
        }
        text
    }
}

/// The distinct materials of `kept` (pages sharing a data file share one `Material`), in
/// first-seen order, and for each page the index of its material in that list: per-material
/// work is done once and mapped back to the pages.
pub fn distinct_materials(kept: &[KeptPage]) -> (Vec<Arc<Material>>, Vec<usize>) {
    let mut unique: Vec<Arc<Material>> = Vec::new();
    let mut slot: HashMap<*const Material, usize> = HashMap::new();
    let positions = kept
        .iter()
        .map(|page| {
            *slot.entry(Arc::as_ptr(&page.material)).or_insert_with(|| {
                unique.push(page.material.clone());
                unique.len() - 1
            })
        })
        .collect();
    (unique, positions)
}

/// A page that did not pass, with its named error; or, in `Ingest::warnings`, a kept
/// page with a defect outside the wavelengths any stage evaluates.
#[derive(Clone, Debug)]
pub struct Excluded {
    pub page: String,
    pub error: DataError,
}

/// A defect of a kept page that does not touch what is evaluated (same shape as an
/// exclusion: the page and the named error with its line).
pub type Warning = Excluded;

/// The result of an ingest: every selected page is in exactly one of the two lists.
#[derive(Clone, Debug, Default)]
pub struct Ingest {
    pub selected: usize,
    pub kept: Vec<KeptPage>,
    pub excluded: Vec<Excluded>,
    /// Defects of kept pages outside the evaluated wavelengths, one per defect.
    pub warnings: Vec<Warning>,
    /// The channel wavelengths and coverage rule the pages were read with.
    pub config: Config,
    /// Selected page ids the catalog lists more than once with the same data file
    /// (kept once).
    pub listed_twice: Vec<String>,
}

impl Ingest {
    pub fn find(&self, id: &str) -> Option<&KeptPage> {
        self.kept.iter().find(|p| p.page.has_id(id))
    }

    /// Excluded pages counted by reason code.
    pub fn excluded_by_reason(&self) -> BTreeMap<&'static str, usize> {
        let mut counts = BTreeMap::new();
        for e in &self.excluded {
            *counts.entry(e.error.reason.code()).or_insert(0) += 1;
        }
        counts
    }

    /// Under `--strict` (`config.strict`) every exclusion other than
    /// `no-visible-coverage`, and every warning, is fatal.
    pub fn check_strict(&self) -> Result<()> {
        if !self.config.strict {
            return Ok(());
        }
        let fatal: Vec<String> = self
            .excluded
            .iter()
            .filter(|e| e.error.reason != Reason::NoVisibleCoverage)
            .chain(&self.warnings)
            .map(|e| crate::escape::terminal(&format!("{}: {}", e.page, e.error)))
            .collect();
        if !fatal.is_empty() {
            bail!("--strict: {} data error(s) or warning(s):\n  {}", fatal.len(), fatal.join("\n  "));
        }
        Ok(())
    }
}

/// Data files read and evaluated, and the names of their books.
struct Evaluated<'a> {
    materials: HashMap<&'a str, Result<Arc<Material>, DataError>>,
    /// `NAMES` of each book's about.yml, read once per book.
    names: HashMap<&'a Path, Option<Vec<String>>>,
}

impl Evaluated<'_> {
    fn empty() -> Self {
        Self { materials: HashMap::new(), names: HashMap::new() }
    }
}

/// Read and evaluate each of `files` (sorted, each once) and the about.yml of each of their
/// books, in parallel.
fn evaluate_files<'a>(db: &Database, files: &[&'a str], config: &Config) -> Evaluated<'a> {
    if files.is_empty() {
        return Evaluated::empty();
    }
    // Only paths that stay inside the database name a book (the others are never opened).
    let mut books: Vec<&Path> = files.iter().filter(|&&file| check_data_path(file).is_ok()).filter_map(|&file| book_dir(file)).collect();
    books.sort_unstable();
    books.dedup();
    let bar = crate::progress::bar(files.len(), "ingest");
    let (materials, names) = rayon::join(
        || {
            // Jobs of at most four files: otherwise rayon leaves runs of about a quarter of
            // the files unsplit on the thread that started the loop, and the other thread,
            // back from the catalog, finds nothing to take.
            files
                .par_iter()
                .with_max_len(4)
                .map(|&file| {
                    let result =
                        db.read_page(file).and_then(|data| spectrum::evaluate(data, &config.channels, config.coverage)).map(Arc::new);
                    bar.inc(1);
                    (file, result)
                })
                .collect()
        },
        || books.par_iter().map(|&book| (book, db.about_names(book))).collect(),
    );
    bar.finish_and_clear();
    Evaluated { materials, names }
}

/// Read, filter and evaluate the selected pages. Data errors are recorded, never fatal.
pub fn ingest(db: &Database, selection: &Selection, config: &Config) -> Result<Ingest> {
    let text = db.catalog_text()?;
    // The whole catalog: the files a line scan of its text names are read and evaluated
    // while it is parsed (one core parses, the other reads); the parsed catalog then
    // decides which results are used, and any file the scan missed is read after.
    let whole = *selection == Selection::All;
    let (catalog, early) = if whole {
        rayon::join(|| db.parse_catalog(&text), || evaluate_files(db, &nklut_optics::db::catalog::guess_data_paths(&text), config))
    } else {
        (db.parse_catalog(&text), Evaluated::empty())
    };
    let mut catalog = catalog?;
    for wanted in selection.named_pages() {
        if catalog.find(wanted).is_none() {
            bail!("unknown page {wanted:?} (ids look like main/Au/Johnson or 3d/metals/gold)");
        }
    }
    let known_shelves = catalog.shelves();
    for shelf in selection.named_shelves() {
        if !known_shelves.contains(shelf) {
            bail!("unknown shelf {shelf:?}; the catalog has {}", known_shelves.join(", "));
        }
    }
    let mut result = Ingest { config: *config, ..Default::default() };
    for rejected in catalog.rejected.iter().filter(|r| selection.includes_id(&r.shelf, &r.id)) {
        result.selected += 1;
        result.excluded.push(Excluded { page: rejected.id.clone(), error: rejected.error.clone() });
    }
    for duplicate in catalog.duplicates.iter().filter(|p| selection.includes(p)) {
        let id = duplicate.id();
        let first = catalog.find(&id).map(|p| p.data.as_str());
        if first == Some(duplicate.data.as_str()) {
            // A page listed three times is still named once.
            if !result.listed_twice.contains(&id) {
                result.listed_twice.push(id);
            }
        } else {
            result.selected += 1;
            result.excluded.push(Excluded {
                page: id,
                error: DataError::new(
                    Reason::DuplicatePageId,
                    &duplicate.data,
                    None,
                    format!("page id already used for {}", first.unwrap_or("?")),
                ),
            });
        }
    }
    // The selected pages are moved out of the catalog (each is kept or excluded once).
    let pages: Vec<CatalogPage> = std::mem::take(&mut catalog.pages).into_iter().filter(|p| selection.includes(p)).collect();
    // What is left of the catalog is freed on a worker, beside the assembly.
    rayon::spawn(move || drop(catalog));
    result.selected += pages.len();
    let ids: Vec<String> = pages.par_iter().map(|p| p.id()).collect();

    // Each data file once, in parallel.
    let mut files: Vec<&str> = pages.iter().map(|p| p.data.as_str()).collect();
    files.sort_unstable();
    files.dedup();
    let missing: Vec<String> = files.iter().filter(|file| !early.materials.contains_key(*file)).map(|file| file.to_string()).collect();
    let missing: Vec<&str> = missing.iter().map(String::as_str).collect();
    let late = evaluate_files(db, &missing, config);
    let material_of = |file: &str| early.materials.get(file).or_else(|| late.materials.get(file));
    let names_of = |file: &str| book_dir(file).and_then(|book| early.names.get(book).or_else(|| late.names.get(book)).cloned().flatten());

    let mut ids_by_file: HashMap<&str, Vec<String>> = HashMap::new();
    for (page, id) in pages.iter().zip(&ids) {
        ids_by_file.entry(page.data.as_str()).or_default().push(id.clone());
    }
    let groups: HashMap<&str, Arc<[String]>> = ids_by_file.into_iter().map(|(file, ids)| (file, Arc::from(ids))).collect();
    let shared_with: Vec<Arc<[String]>> = pages.iter().map(|page| groups[page.data.as_str()].clone()).collect();
    // Each page's outcome, built in parallel (the page moved into it) and taken in catalog order.
    let outcomes: Vec<Result<KeptPage, Excluded>> = pages
        .into_par_iter()
        .zip(ids)
        .zip(shared_with)
        .map(|((page, id), sharing)| match material_of(&page.data).expect("every selected data file was evaluated") {
            Ok(material) => Ok(KeptPage {
                names: names_of(&page.data).unwrap_or_else(|| vec![page.book_name.clone()]),
                material: material.clone(),
                sharing,
                page,
            }),
            Err(error) => Err(Excluded { page: id, error: error.clone() }),
        })
        .collect();
    for outcome in outcomes {
        match outcome {
            Ok(kept) => {
                result.warnings.extend(kept.material.data.warnings.iter().map(|w| Warning { page: kept.id(), error: w.clone() }));
                result.kept.push(kept);
            }
            Err(excluded) => result.excluded.push(excluded),
        }
    }
    Ok(result)
}

/// `materials.*`: one row per kept page.
pub fn materials_table(ingest: &Ingest) -> Table {
    let channels = &ingest.config.channels;
    let kept = &ingest.kept;
    // Each text column formatted in parallel (rows in order).
    let text = |f: &(dyn Fn(&KeptPage) -> String + Sync)| kept.par_iter().map(f).collect::<Vec<_>>();
    let mut table = Table::new();
    table
        .text("page", "page id shelf/book/page", text(&|p| p.id()))
        .text("shelf", "catalog shelf id", text(&|p| p.page.shelf.clone()))
        .text("book", "catalog book id", text(&|p| p.page.book.clone()))
        .text("page_name", "catalog page id within the book", text(&|p| p.page.page.clone()))
        .text("names", "material names, '; '-separated (about.yml NAMES, else the catalog book name)", text(&|p| p.names.join("; ")))
        .text("catalog_name", "the catalog's display name of the page", text(&|p| p.page.page_name.clone()))
        .text("data_file", "data file relative to database/data/", text(&|p| p.page.data.clone()))
        .text(
            "shared_with",
            &format!("other page ids using the same data file, '; '-separated (the first {SHARED_WITH_LISTED}; more are counted: '… and N more')"),
            text(&|p| p.shared_with_text()),
        )
        .text("kind", "conductor (k >= 1 somewhere in 390-700 nm where the data reach) or dielectric", text(&|p| p.material.kind.as_str().into()));
    for (c, (name, nm)) in CHANNEL_NAMES.iter().zip(channels.nanometres()).enumerate() {
        table.float(
            &format!("n_{name}"),
            &format!("refractive index n at {nm} nm"),
            kept.iter().map(|p| p.material.channels[c].n).collect(),
        );
        table.float(
            &format!("k_{name}"),
            &format!("extinction coefficient k at {nm} nm"),
            kept.iter().map(|p| p.material.channels[c].k).collect(),
        );
    }
    for (name, nm) in CHANNEL_NAMES.iter().zip(channels.nanometres()) {
        table.float(
            &format!("lambda_{name}_nm"),
            &format!("wavelength (nm) of the {name} channel, where n_{name} and k_{name} are evaluated (--channels)"),
            vec![nm; kept.len()],
        );
    }
    table
        .float("lambda_min_nm", "shortest wavelength covered by n and k data (nm)", kept.iter().map(|p| p.material.range_nm.0).collect())
        .float("lambda_max_nm", "longest wavelength covered by n and k data (nm)", kept.iter().map(|p| p.material.range_nm.1).collect())
        .optional_float(
            "max_visible_gap_nm",
            "largest spacing between tabulated rows over 390-700 nm (nm); empty for a formula",
            kept.iter().map(|p| p.material.max_visible_gap_nm).collect(),
        )
        .boolean(
            "sparse",
            &format!("max_visible_gap_nm > {SPARSE_GAP_NM} nm"),
            kept.iter().map(|p| p.material.max_visible_gap_nm.is_some_and(|g| g > SPARSE_GAP_NM)).collect(),
        )
        .text("reference", "first line of the data file's REFERENCES", text(&|p| p.material.data.reference.clone()));
    table
}

/// `excluded.csv` (one row per dropped page) or `warnings.csv` (one row per defect of a
/// kept page): the page, its data file, the reason code, the line and the detail.
pub fn problems_table(rows: &[Excluded]) -> Table {
    let mut table = Table::new();
    table
        .text("page", "page id", rows.iter().map(|e| e.page.clone()).collect())
        .text("data_file", "data file relative to database/data/", rows.iter().map(|e| e.error.file.clone()).collect())
        .text("reason", "reason code", rows.iter().map(|e| e.error.reason.code().to_string()).collect())
        .optional_float(
            "line",
            "line in the data file, where the error has one",
            rows.iter().map(|e| e.error.line.map(|l| l as f64)).collect(),
        )
        .text("detail", "what was wrong", rows.iter().map(|e| e.error.detail.clone()).collect());
    table
}
