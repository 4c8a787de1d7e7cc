//! Fresnel lookup textures for engines (SPEC §5.7, §7).
//!
//! A row is one page's F(cosθ) per colour channel at the texel centres
//! c_i = (i + ½)/N, i = 0..N−1, so that a GPU's linear filter with clamp-to-edge at
//! u = cosθ reproduces the LUT model of SPEC §5.7 exactly. `bake` is the pure core:
//! rows (plain data) → encoded PNG/EXR bytes and the manifest, per source × encoding ×
//! layout; `run` is the edge: arguments → ingest → curves → `bake` → `publish`.
//!
//! Each page's spectrum (1 nm, SPEC §4) is sampled once, and its spectral reference
//! evaluated once at the colour module's angle-quadrature nodes ([`PageReference`]); that
//! serves the `effective` fit and every row's `error_vs_spectral`. The `spectral` source
//! adds one evaluation per texel.
//!
//! Layouts: one N×1 strip per page (`<source>/<encoding>/strips/<page id, '/' → '__'>.<ext>`)
//! and one N×rows atlas per source × encoding (`<source>/<encoding>/atlas.<ext>`), row r =
//! the r-th kept page in catalog order.

pub mod accuracy;
pub use nklut_tables::image_files as files;
pub mod manifest;
pub mod publish;
pub use nklut_tables::texel;

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use anyhow::{bail, ensure, Result};
use rayon::prelude::*;

use crate::ingest::{self, Ingest, KeptPage, Selection};
use crate::output::fnv1a;
use nklut_optics::color;
use nklut_optics::db::Database;
use nklut_optics::spectrum::{ChannelIndex, Channels, Kind};
use nklut_tables::memo_file::MemoFile;

use accuracy::LutError;
use manifest::{Manifest, RowEntry, TextureSet};
pub use publish::{BeforeWrite, OutFile};
pub use texel::{Encoding, Texels};

/// F per channel (red, green, blue) at the texel cosines c_i = (i + ½)/N.
pub type ChannelCurve = [Vec<f64>; 3];

/// The largest texture width a bake accepts (the WebGPU/Vulkan guaranteed 2D limit is
/// 8192; 65536 is what 16-bit texel addressing and PNG tooling handle comfortably).
pub const MAX_SIZE: usize = 65536;

/// Where a row's curve comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Source {
    /// `exact` Fresnel (SPEC §5.1) of the three-channel (n, k) (SPEC §3).
    ThreeChannel,
    /// `exact` Fresnel of the fitted effective indices (color module).
    Effective,
    /// The spectral reference colour RGB(θ) (SPEC §4), may exceed 1.
    Spectral,
}

impl Source {
    pub const ALL: [Source; 3] = [Source::ThreeChannel, Source::Effective, Source::Spectral];

    pub fn name(self) -> &'static str {
        match self {
            Source::ThreeChannel => "three-channel",
            Source::Effective => "effective",
            Source::Spectral => "spectral",
        }
    }

    pub fn description(self) -> &'static str {
        match self {
            Source::ThreeChannel => "exact Fresnel (SPEC 5.1) of the page's (n, k) at the channel wavelengths (SPEC 3)",
            Source::Effective => "exact Fresnel of the page's effective (n, k), fitted per channel to the spectral reference",
            Source::Spectral => "the spectral reference colour RGB(theta) in linear sRGB (SPEC 4); may exceed 1",
        }
    }
}

/// How rows are laid out in files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Layout {
    /// One N×1 image per page.
    Strip,
    /// One N×rows image, row r = page r.
    Atlas,
}

impl Layout {
    pub const ALL: [Layout; 2] = [Layout::Strip, Layout::Atlas];

    pub fn name(self) -> &'static str {
        match self {
            Layout::Strip => "strip",
            Layout::Atlas => "atlas",
        }
    }

    pub fn description(self) -> &'static str {
        match self {
            Layout::Strip => "one N x 1 image per page, <source>/<encoding>/strips/<page id with '/' replaced by '__'>.<ext>",
            Layout::Atlas => {
                "one N x rows image per source and encoding, <source>/<encoding>/atlas.<ext>; row r is rows[r] of the texture set"
            }
        }
    }
}

/// The spectral side of one page, computed once and shared by its curves and its
/// `error_vs_spectral`: the index on the 1 nm grid (SPEC §4) and the spectral reference
/// RGB(θ) at the nodes of `color::angle_quadrature()`.
#[derive(Clone, Debug)]
pub struct PageReference {
    /// The page's spectrum prepared once for every reference colour the bake needs.
    pub spectrum: color::PreparedSpectrum,
    /// The bits of the sampled spectrum, the memo's key.
    pub fingerprint: color::Fingerprint,
    /// Per channel, the spectral reference at `color::angle_quadrature().cosines`.
    pub at_nodes: [Vec<f64>; 3],
    /// Share of the luminance weight ∫ S ȳ outside the page's data, where n and k are
    /// held at the nearest measured value (a fraction).
    pub extrapolated_share: f64,
}

impl PageReference {
    /// The page's reference, its curves from `memo` where it holds them.
    pub fn new(page: &KeptPage, memo: &color::CurveMemo) -> Self {
        let (sampled, extrapolated_share) = color::sample_spectrum(&page.material.data);
        let spectrum = color::PreparedSpectrum::new(&sampled);
        let fingerprint = color::Fingerprint::of_spectrum(&sampled);
        let at_nodes = by_channel(&memo.curve(fingerprint, &spectrum, &color::angle_quadrature().cosines));
        Self { spectrum, fingerprint, at_nodes, extrapolated_share }
    }

    /// Per channel, the (n, k) whose exact Fresnel curve best fits the spectral reference
    /// over θ (`color::fit_effective_index`, started from the three-channel index), from
    /// `fits` where it holds them.
    pub fn effective_index(&self, channels: &ChannelIndex, fits: &color::EffectiveMemo) -> ChannelIndex {
        let rule = color::angle_quadrature();
        std::array::from_fn(|c| fits.effective(&self.at_nodes[c], channels[c], rule).index)
    }

    /// F of `source` for `page` (the page this reference was made from) at the texel
    /// cosines of an N-texel LUT.
    pub fn curve(&self, source: Source, page: &KeptPage, size: usize, memo: &color::CurveMemo) -> ChannelCurve {
        match source {
            Source::ThreeChannel => exact_curve(&page.material.channels, size),
            Source::Effective => exact_curve(&self.effective_index(&page.material.channels, &color::EffectiveMemo::default()), size),
            Source::Spectral => by_channel(&memo.curve(self.fingerprint, &self.spectrum, &nklut_optics::encoding::texel_cosines(size))),
        }
    }
}

/// RGB triples → one vector per channel.
fn by_channel(rgb: &[[f64; 3]]) -> [Vec<f64>; 3] {
    std::array::from_fn(|c| rgb.iter().map(|v| v[c]).collect())
}

/// F of `source` for one kept page at the texel cosines of an N-texel LUT (samples the
/// page's spectrum; to bake several sources of a page, share one [`PageReference`]).
pub fn curve(source: Source, page: &KeptPage, size: usize) -> ChannelCurve {
    match source {
        Source::ThreeChannel => exact_curve(&page.material.channels, size),
        _ => {
            let memo = color::CurveMemo::default();
            PageReference::new(page, &memo).curve(source, page, size, &memo)
        }
    }
}

/// `exact` (SPEC §5.1) per channel at c_i = (i + ½)/N.
pub fn exact_curve(index: &ChannelIndex, size: usize) -> ChannelCurve {
    accuracy::exact_reference(index, &nklut_optics::encoding::texel_cosines(size))
}

/// One page to bake.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub page: String,
    pub names: Vec<String>,
    pub kind: Kind,
    /// The page's data file, relative to database/data/.
    pub data_file: String,
    /// The three-channel (n, k): `exact` of it is the reference of `error_vs_exact`.
    pub index: ChannelIndex,
    /// The effective (n, k) fitted per channel to the spectral reference (None: not
    /// computed, e.g. rows made through the library API).
    pub fitted: Option<ChannelIndex>,
    /// One curve per source of the plan, in `Plan::sources` order.
    pub curves: Vec<ChannelCurve>,
    /// Per channel, the spectral reference (SPEC §4) at `color::angle_quadrature().cosines`:
    /// the reference of `error_vs_spectral` (None: that error is not computed).
    pub spectral: Option<[Vec<f64>; 3]>,
    /// Share of the spectral reference's luminance weight held outside the data (None
    /// without a spectral reference).
    pub extrapolated_share: Option<f64>,
    /// The spectral reference at θ = 90° and θ = 0° (its F0): the ends of
    /// `error_vs_spectral`'s rule and the spectral source's `f0_source` (None: not computed;
    /// `error_vs_spectral` then stays on the quadrature's nodes alone).
    pub spectral_ends: Option<accuracy::Ends>,
}

/// What to bake. Lists are kept in the given order; `normalise` sorts and dedups them.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub size: usize,
    pub channels: Channels,
    pub sources: Vec<Source>,
    pub encodings: Vec<Encoding>,
    pub layouts: Vec<Layout>,
}

impl Plan {
    /// Defaults for empty lists (every encoding, both layouts, three-channel), sorted, deduplicated.
    pub fn normalise(mut self) -> Self {
        fn tidy<T: Ord + Copy>(list: &mut Vec<T>, default: &[T]) {
            if list.is_empty() {
                list.extend_from_slice(default);
            }
            list.sort();
            list.dedup();
        }
        tidy(&mut self.sources, &[Source::ThreeChannel]);
        tidy(&mut self.encodings, &Encoding::ALL);
        tidy(&mut self.layouts, &[Layout::Strip, Layout::Atlas]);
        self
    }

    /// Everything that can be checked without data: size range, non-empty lists.
    pub fn validate(&self) -> Result<()> {
        ensure!((1..=MAX_SIZE).contains(&self.size), "--size must be between 1 and {MAX_SIZE} texels, got {}", self.size);
        ensure!(
            !self.sources.is_empty() && !self.encodings.is_empty() && !self.layouts.is_empty(),
            "nothing to bake: no source, encoding or layout"
        );
        Ok(())
    }

    /// The texture sets, source-major: (index into `sources`, encoding).
    fn sets(&self) -> Vec<(usize, Encoding)> {
        (0..self.sources.len()).flat_map(|s| self.encodings.iter().map(move |&e| (s, e))).collect()
    }
}

/// A file-name stem from a page id: '/' → '__'; characters that are not allowed in
/// Windows or POSIX file names (\ : * ? " < > | and controls) and '%' are written %XX (UTF-8 bytes);
/// a stem longer than [`crate::output::MAX_STEM_BYTES`] is cut and ends in `~` and a hash
/// of the whole ([`crate::output::bounded_stem`]).
pub fn strip_stem(page: &str) -> String {
    let stem = escaped_stem(page);
    crate::output::bounded_stem(&stem, '~').into_owned()
}

/// [`strip_stem`] before its length is bounded.
fn escaped_stem(page: &str) -> String {
    let mut stem = String::with_capacity(page.len() + 8);
    for ch in page.chars() {
        match ch {
            '/' => stem.push_str("__"),
            '\\' | ':' | '*' | '?' | '"' | '<' | '>' | '|' | '%' => stem.push_str(&format!("%{:02X}", ch as u32)),
            c if c.is_control() => c.encode_utf8(&mut [0; 4]).bytes().for_each(|b| stem.push_str(&format!("%{b:02X}"))),
            c => stem.push(c),
        }
    }
    stem
}

fn set_folder(plan: &Plan, (source, encoding): (usize, Encoding)) -> String {
    format!("{}/{}", plan.sources[source].name(), encoding.name())
}

/// The pure result of a bake: image files (relative paths) and the manifest (without tables).
#[derive(Clone, Debug)]
pub struct Baked {
    pub files: Vec<OutFile>,
    pub manifest: Manifest,
}

/// One row in one texture set: its stored texels and figures.
struct Cell {
    quantised: texel::Quantised,
    error: LutError,
    error_vs_spectral: Option<LutError>,
}

/// One row's figures that do not depend on the encoding, per source in plan order: F0 of
/// the source and the recommended encodings (None where the source has no exact curve).
struct RowFigures {
    f0_source: Vec<Option<[f64; 3]>>,
    recommended: Vec<Option<Vec<accuracy::Choice>>>,
}

/// The exact (n, k) behind a source's curve, where it has one: the three-channel index,
/// or the fitted one of the effective source; the spectral source is a 471-wavelength sum.
fn exact_index(source: Source, row: &Row) -> Option<ChannelIndex> {
    match source {
        Source::ThreeChannel => Some(row.index),
        Source::Effective => row.fitted,
        Source::Spectral => None,
    }
}

/// F0 of every source and the recommendations of those with an exact curve, for one row;
/// `reference` is `exact` of the row's three-channel index on `candidates.rule()`.
fn row_figures(row: &Row, plan: &Plan, candidates: &accuracy::Candidates, reference: &[Vec<f64>; 3]) -> RowFigures {
    let bound = accuracy::RECOMMENDATION_BOUND;
    RowFigures {
        f0_source: plan
            .sources
            .iter()
            .map(|&source| match source {
                Source::Spectral => row.spectral_ends.map(|e| e.normal),
                _ => exact_index(source, row).map(|index| accuracy::exact_ends(&index).normal),
            })
            .collect(),
        recommended: plan
            .sources
            .iter()
            .map(|&source| {
                let index = exact_index(source, row)?;
                let own;
                let reference = if source == Source::ThreeChannel {
                    reference
                } else {
                    own = accuracy::exact_reference(&index, &candidates.rule().cosines);
                    &own
                };
                Some(accuracy::recommend(&candidates.errors(&index, reference, Some(&bound)), &bound))
            })
            .collect(),
    }
}

fn check_rows(rows: &[Row], plan: &Plan) -> Result<()> {
    ensure!(!rows.is_empty(), "nothing to bake: no rows");
    let mut stems = BTreeMap::new();
    for row in rows {
        ensure!(row.curves.len() == plan.sources.len(), "{}: {} curves for {} sources", row.page, row.curves.len(), plan.sources.len());
        for curve in row.curves.iter().flatten() {
            ensure!(curve.len() == plan.size, "{}: curve of {} values for size {}", row.page, curve.len(), plan.size);
            ensure!(curve.iter().all(|v| v.is_finite()), "{}: curve has a non-finite value", row.page);
        }
        let nodes = color::angle_quadrature().cosines.len();
        for reference in row.spectral.iter().flatten() {
            ensure!(reference.len() == nodes, "{}: spectral reference of {} values for {nodes} nodes", row.page, reference.len());
            ensure!(reference.iter().all(|v| v.is_finite()), "{}: spectral reference has a non-finite value", row.page);
        }
        if let Some(ends) = &row.spectral_ends {
            ensure!(
                ends.grazing.iter().chain(&ends.normal).all(|v| v.is_finite()),
                "{}: spectral reference has a non-finite value at an end",
                row.page
            );
        }
    }
    // Unique ignoring case, so that the strips also survive case-insensitive file systems.
    for (row, stem) in rows.iter().zip(strip_stems(rows)) {
        if let Some(other) = stems.insert(stem.to_lowercase(), &row.page) {
            bail!("pages {other:?} and {:?} map to the same strip file name (ignoring case)", row.page);
        }
    }
    Ok(())
}

/// The strip file stem of each row: [`strip_stem`] of its page id, and where two ids give
/// stems equal ignoring case (`J` and `j`, or `a/b__c` and `a__b/c`), each of them followed
/// by `~` and eight hex digits of a hash of its id, so that no page of a catalog disables
/// the bake. Only identical ids still collide.
pub fn strip_stems(rows: &[Row]) -> Vec<String> {
    let stems: Vec<String> = rows.iter().map(|r| strip_stem(&r.page)).collect();
    let mut count: HashMap<String, usize> = HashMap::new();
    for stem in &stems {
        *count.entry(stem.to_lowercase()).or_default() += 1;
    }
    stems
        .into_iter()
        .zip(rows)
        .map(|(stem, row)| if count[&stem.to_lowercase()] > 1 { format!("{stem}~{:08x}", fnv1a(&row.page) >> 32) } else { stem })
        .collect()
}

/// Quantise every row in every set and measure its error against `exact` of its
/// three-channel index (reference computed once per row) and, where the row has it,
/// against its spectral reference; with each row's [`RowFigures`].
fn cells(rows: &[Row], plan: &Plan, sets: &[(usize, Encoding)]) -> Vec<(Vec<Cell>, RowFigures)> {
    let candidates = accuracy::Candidates::new(plan.size);
    let midpoint = candidates.rule();
    let nodes = color::angle_quadrature();
    let nodes_with_ends = accuracy::with_ends(nodes);
    let midpoint_taps = accuracy::Taps::new(plan.size, &midpoint.cosines);
    let midpoint = &midpoint;
    let (node_taps, node_taps_with_ends) =
        (accuracy::Taps::new(plan.size, &nodes.cosines), accuracy::Taps::new(plan.size, &nodes_with_ends.cosines));
    rows.par_iter()
        .map(|row| {
            let reference = accuracy::exact_reference(&row.index, &midpoint.cosines);
            let spectral = row.spectral.as_ref().map(|s| match &row.spectral_ends {
                Some(ends) => (accuracy::append_ends(s, ends), &node_taps_with_ends, &nodes_with_ends),
                None => (s.clone(), &node_taps, nodes),
            });
            let row_cells = sets
                .iter()
                .map(|&(source, encoding)| {
                    let quantised = texel::quantise(encoding, &row.curves[source]);
                    let decoded = accuracy::deinterleave(&quantised.texels.decode(encoding));
                    Cell {
                        error: accuracy::lut_error_with_taps(&decoded, &midpoint_taps, midpoint, &reference),
                        error_vs_spectral: spectral.as_ref().map(|(s, taps, rule)| accuracy::lut_error_with_taps(&decoded, taps, rule, s)),
                        quantised,
                    }
                })
                .collect();
            (row_cells, row_figures(row, plan, &candidates, &reference))
        })
        .collect()
}

/// Bake `rows` by `plan` (normalised or not, validated here): the pure core. Files are
/// listed set by set (sources, then encodings, in plan order), atlas first, then strips
/// in row order.
pub fn bake(rows: &[Row], plan: &Plan) -> Result<Baked> {
    let (files, manifest) = bake_then(rows, plan, |manifest| manifest)?;
    Ok(Baked { files, manifest })
}

/// [`bake`], with `finish` applied to the manifest while the image files are encoded (on
/// the whole database, writing the manifest out as JSON takes a core for a third of a
/// second).
fn bake_then<R: Send>(rows: &[Row], plan: &Plan, finish: impl FnOnce(Manifest) -> R + Send) -> Result<(Vec<OutFile>, R)> {
    plan.validate()?;
    check_rows(rows, plan)?;
    let sets = plan.sets();
    let (cells, figures): (Vec<Vec<Cell>>, Vec<RowFigures>) = cells(rows, plan, &sets).into_iter().unzip();
    let strips = plan.layouts.contains(&Layout::Strip);
    let atlas = plan.layouts.contains(&Layout::Atlas);
    let stems = strip_stems(rows);
    // (set, None) = the set's atlas, (set, Some(row)) = a strip.
    let jobs: Vec<(usize, Option<usize>)> = (0..sets.len())
        .flat_map(|s| atlas.then_some((s, None)).into_iter().chain((0..rows.len()).filter(|_| strips).map(move |r| (s, Some(r)))))
        .collect();
    let encode = || -> Result<Vec<OutFile>> {
        jobs.par_iter()
            .map(|&(s, row)| {
                let (_, encoding) = sets[s];
                let folder = set_folder(plan, sets[s]);
                match row {
                    None => {
                        let texels = Texels::concat(encoding, cells.iter().map(|c| &c[s].quantised.texels));
                        let bytes = files::encode(encoding, plan.size, rows.len(), &texels)?;
                        Ok(OutFile { path: format!("{folder}/atlas.{}", encoding.extension()), bytes })
                    }
                    Some(r) => {
                        let bytes = files::encode(encoding, plan.size, 1, &cells[r][s].quantised.texels)?;
                        Ok(OutFile { path: strip_path(&folder, &stems[r], encoding), bytes })
                    }
                }
            })
            .collect()
    };
    let (files, finished) = rayon::join(encode, || finish(build_manifest(rows, &stems, plan, &sets, (&cells, &figures), strips, atlas)));
    Ok((files?, finished))
}

fn strip_path(folder: &str, stem: &str, encoding: Encoding) -> String {
    format!("{folder}/strips/{stem}.{}", encoding.extension())
}

fn build_manifest(
    rows: &[Row],
    stems: &[String],
    plan: &Plan,
    sets: &[(usize, Encoding)],
    (cells, figures): (&[Vec<Cell>], &[RowFigures]),
    strips: bool,
    atlas: bool,
) -> Manifest {
    let textures = sets
        .iter()
        .enumerate()
        .map(|(s, &(source, encoding))| {
            let folder = set_folder(plan, (source, encoding));
            let clamped: usize = cells.iter().map(|c| c[s].quantised.clamped).sum();
            TextureSet {
                source: plan.sources[source].name().into(),
                encoding: encoding.name().into(),
                color_space: encoding.color_space().into(),
                color_meaning: manifest::color_meaning(plan.sources[source], &plan.channels),
                png_color_chunks: (!encoding.is_float()).then(|| files::png_color_chunks(encoding).into()),
                clamped_texels: clamped,
                atlas: atlas.then(|| manifest::ImageFile {
                    file: format!("{folder}/atlas.{}", encoding.extension()),
                    width: plan.size,
                    height: rows.len(),
                    clamped_texels: clamped,
                }),
                strips: strips.then(|| manifest::StripFolder {
                    folder: format!("{folder}/strips"),
                    width: plan.size,
                    height: 1,
                    file_name_rule: "page id with '/' replaced by '__' (and \\ : * ? \" < > | % and control characters as %XX); where two ids give names equal ignoring case, each followed by '~' and the top 8 hex digits of the FNV-1a (64-bit) hash of its id; then the extension".into(),
                }),
                rows: rows
                    .iter()
                    .zip(cells.iter().zip(figures))
                    .enumerate()
                    .map(|(r, (row, (cell, figures)))| RowEntry {
                        row: r,
                        page: row.page.clone(),
                        names: row.names.clone(),
                        kind: row.kind.as_str().into(),
                        data_file: row.data_file.clone(),
                        index_three_channel: manifest::index_entries(&row.index, Some(&plan.channels)),
                        index_fitted: row.fitted.as_ref().map(|f| manifest::index_entries(f, None)),
                        f0: accuracy::exact_ends(&row.index).normal,
                        f0_source: figures.f0_source[source],
                        recommended: figures.recommended[source].clone(),
                        strip_file: strips.then(|| strip_path(&folder, &stems[r], encoding)),
                        clamped_texels: cell[s].quantised.clamped,
                        error_vs_exact: cell[s].error.clone(),
                        error_vs_spectral: cell[s].error_vs_spectral.clone(),
                        extrapolated_share: row.extrapolated_share,
                    })
                    .collect(),
            }
        })
        .collect();
    Manifest {
        format_version: manifest::FORMAT_VERSION,
        generator: format!("nklut {} bake", env!("CARGO_PKG_VERSION")),
        size: plan.size,
        sampling: manifest::sampling(),
        channel_wavelengths: manifest::channels(&plan.channels),
        color: manifest::color_info(),
        sixteen_bit_png: manifest::SIXTEEN_BIT_PNG_NOTE.into(),
        row_order: "catalog order (catalog-nk.yml order of shelves, books and pages) of the kept pages; the atlas row of a \
                    page is its rows[].row"
            .into(),
        error: manifest::error_definition(accuracy::error_samples(plan.size), color::angle_quadrature().cosines.len()),
        recommendation: manifest::recommendation_definition(plan.size),
        sources: plan.sources.iter().map(|&s| manifest::source_info(s)).collect(),
        encodings: plan.encodings.iter().map(|&e| manifest::encoding_info(e)).collect(),
        layouts: plan.layouts.iter().map(|&l| manifest::layout_info(l)).collect(),
        textures,
        duplicate_catalog_pages: Vec::new(),
        tables: Vec::new(),
    }
}

/// What `nklut bake` does, as plain values.
#[derive(Clone, Debug)]
pub struct BakeRequest {
    /// The pages to bake; every page named explicitly must be kept by the filter.
    pub selection: Selection,
    /// How pages are read (channel wavelengths, coverage rule, strictness).
    pub reading: ingest::Config,
    /// Texels per row N (1..=[`MAX_SIZE`]).
    pub size: usize,
    /// Where F comes from; empty means three-channel.
    pub sources: Vec<Source>,
    /// Texel encodings; empty means all.
    pub encodings: Vec<Encoding>,
    /// File layouts; empty means both.
    pub layouts: Vec<Layout>,
}

impl BakeRequest {
    /// The plan of this request, lists defaulted, sorted and deduplicated.
    pub fn plan(&self) -> Plan {
        Plan {
            size: self.size,
            channels: self.reading.channels,
            sources: self.sources.clone(),
            encodings: self.encodings.clone(),
            layouts: self.layouts.clone(),
        }
        .normalise()
    }
}

/// What `run` did.
#[derive(Clone, Debug)]
pub struct Summary {
    pub luts: PathBuf,
    pub rows: usize,
    pub files: usize,
    pub clamped_texels: usize,
}

/// Every explicitly named page must have been kept.
fn check_named_pages_kept(ingest: &Ingest, named: &[String]) -> Result<()> {
    for id in named {
        if ingest.find(id).is_none() {
            let why = ingest.excluded.iter().find(|e| e.page == *id).map(|e| e.error.to_string()).unwrap_or_default();
            bail!("page {id:?} was excluded by the visible-range filter and cannot be baked: {why}");
        }
    }
    ensure!(!ingest.kept.is_empty(), "no page of the selection passed the visible-range filter; nothing to bake");
    Ok(())
}

/// The rows of `pages`: curves computed per source, and the spectral reference of
/// `error_vs_spectral`, all from one [`PageReference`] per page (its curves from `memo`,
/// its effective indices from `fits`, where they hold them).
pub fn rows(pages: &[&KeptPage], plan: &Plan, memo: &color::CurveMemo, fits: &color::EffectiveMemo) -> Vec<Row> {
    pages
        .par_iter()
        .map(|page| {
            let reference = PageReference::new(page, memo);
            let fitted = reference.effective_index(&page.material.channels, fits);
            let curve = |source: Source| match source {
                Source::Effective => exact_curve(&fitted, plan.size),
                _ => reference.curve(source, page, plan.size, memo),
            };
            let ends = reference.spectrum.curve(&[0.0, 1.0]);
            Row {
                page: page.id(),
                names: page.names.clone(),
                kind: page.material.kind,
                data_file: page.page.data.clone(),
                index: page.material.channels,
                fitted: Some(fitted),
                curves: plan.sources.iter().map(|&s| curve(s)).collect(),
                extrapolated_share: Some(reference.extrapolated_share),
                spectral: Some(reference.at_nodes),
                spectral_ends: Some(accuracy::Ends { grazing: ends[0], normal: ends[1] }),
            }
        })
        .collect()
}

/// The manifest and README as files, tables documented from ingest's own column
/// descriptions — only the table files `exists` finds next to `luts/` (a bake into a fresh
/// folder has none; the manifest's rows carry each page's (n, k) themselves).
fn documents(mut manifest: Manifest, ingest: &Ingest, exists: &dyn Fn(&str) -> bool) -> Result<Vec<OutFile>> {
    let present = |files: &[&'static str]| -> Vec<&'static str> { files.iter().copied().filter(|f| exists(f)).collect() };
    let materials = present(&["../materials.csv", "../materials.parquet", "../materials.json"]);
    let excluded = present(&["../excluded.csv"]);
    if !materials.is_empty() {
        manifest.tables.push(manifest::table_doc(
            &ingest::materials_table(ingest),
            &materials,
            "page kept by the visible-range filter (SPEC 2), in catalog order (written by `nklut ingest`, possibly for another selection than this bake)",
            Vec::new(),
        ));
    }
    if !excluded.is_empty() {
        manifest.tables.push(manifest::table_doc(
            &ingest::problems_table(&ingest.excluded),
            &excluded,
            "page dropped by the filter (written by `nklut ingest`)",
            manifest::reason_codes(),
        ));
    }
    let mut json = serde_json::to_vec_pretty(&manifest)?;
    json.push(b'\n');
    Ok(vec![
        OutFile { path: "manifest.json".into(), bytes: json },
        OutFile { path: "README.md".into(), bytes: manifest::readme(&manifest).into_bytes() },
    ])
}

/// `nklut bake`: validate everything, ingest, bake, publish `<out>/luts` all or nothing.
pub fn run(db: &Database, out: &Path, request: &BakeRequest) -> Result<Summary> {
    run_with_hook(db, out, request, &|_, _| Ok(()))
}

/// `run` with a callback before each file is written (tests use it to inject failures).
pub fn run_with_hook(db: &Database, out: &Path, request: &BakeRequest, before_write: BeforeWrite) -> Result<Summary> {
    let plan = request.plan();
    plan.validate()?;
    publish::check_writable(out)?;
    let ingest = ingest::ingest(db, &request.selection, &request.reading)?;
    ingest.check_strict()?;
    check_named_pages_kept(&ingest, request.selection.named_pages())?;
    // The catalog keeps a page id listed twice (same data file) once; ingest names them.
    let pages: Vec<&KeptPage> = ingest.kept.iter().collect();
    let mut duplicates = ingest.listed_twice.clone();
    duplicates.sort();
    let memo = color::CurveMemo::load(out);
    let fits = color::EffectiveMemo::load(out);
    let rows = rows(&pages, &plan, &memo, &fits);
    let (mut files, documented) = bake_then(&rows, &plan, |mut manifest| {
        manifest.duplicate_catalog_pages = duplicates;
        let clamped_texels: usize = manifest.textures.iter().map(|t| t.clamped_texels).sum();
        // Table paths are relative to luts/: "../x" is out/x.
        documents(manifest, &ingest, &|relative| out.join(relative.trim_start_matches("../")).is_file())
            .map(|documents| (documents, clamped_texels))
    })?;
    let (documents, clamped_texels) = documented?;
    files.extend(documents);
    let luts = publish::publish(out, &files, before_write)?;
    Ok(Summary { luts, rows: rows.len(), files: files.len(), clamped_texels })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nklut_optics::spectrum::Index;

    fn plan(size: usize) -> Plan {
        Plan { size, channels: Channels::default(), sources: vec![], encodings: vec![], layouts: vec![] }.normalise()
    }

    /// A glass row and a row above 1 (as the spectral source gives for gold's red).
    fn rows(size: usize) -> Vec<Row> {
        let glass = [Index::new(1.5, 0.0); 3];
        let mut bright = exact_curve(&glass, size);
        bright[0].iter_mut().take(3).for_each(|v| *v = 1.2);
        vec![
            Row {
                page: "3d/glass/x".into(),
                names: vec!["X".into()],
                kind: Kind::Dielectric,
                data_file: "x.yml".into(),
                index: glass,
                fitted: Some(glass),
                curves: vec![exact_curve(&glass, size)],
                spectral: None,
                extrapolated_share: None,
                spectral_ends: None,
            },
            Row {
                page: "main/Y/a:b".into(),
                names: vec![],
                kind: Kind::Dielectric,
                data_file: "y.yml".into(),
                index: glass,
                fitted: None,
                curves: vec![bright],
                spectral: None,
                extrapolated_share: None,
                spectral_ends: None,
            },
        ]
    }

    #[test]
    fn every_file_decodes_to_the_curve_within_half_a_step() {
        let (size, rows) = (16, rows(16));
        let baked = bake(&rows, &plan(size)).unwrap();
        assert_eq!(baked.files.len(), 5 * 3);
        for file in &baked.files {
            let encoding = Encoding::ALL.into_iter().find(|e| file.path.contains(&format!("/{}/", e.name()))).unwrap();
            let decoded = files::decode(encoding, &file.bytes).unwrap();
            let which: Vec<&Row> = if file.path.contains("atlas") {
                rows.iter().collect()
            } else {
                rows.iter().filter(|r| file.path.contains(&strip_stem(&r.page))).collect()
            };
            assert_eq!((decoded.width, decoded.height), (size, which.len()), "{}", file.path);
            let values = decoded.texels.decode(encoding);
            for (r, row) in which.iter().enumerate() {
                for i in 0..size {
                    for c in 0..3 {
                        let want = row.curves[0][c][i];
                        let want = if encoding.is_float() { want } else { want.clamp(0.0, 1.0) };
                        let got = values[3 * (r * size + i) + c];
                        let (got_s, want_s) = if encoding == Encoding::Unorm8Srgb {
                            (nklut_optics::encoding::srgb_encode(got), nklut_optics::encoding::srgb_encode(want))
                        } else {
                            (got, want)
                        };
                        assert!(
                            (got_s - want_s).abs() <= encoding.half_step(want_s) * (1.0 + 1e-9),
                            "{} {r} {i} {c}: {got} vs {want}",
                            file.path
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn clamps_are_counted_for_integers_only() {
        let baked = bake(&rows(16), &plan(16)).unwrap();
        for t in &baked.manifest.textures {
            let want = if t.encoding.starts_with('f') { 0 } else { 3 };
            assert_eq!((t.clamped_texels, t.rows[1].clamped_texels, t.rows[0].clamped_texels), (want, want, 0), "{}", t.encoding);
        }
    }

    #[test]
    fn error_vs_spectral_is_measured_on_the_angle_quadrature_where_a_row_has_a_reference() {
        let mut rows = rows(64);
        let glass = rows[0].index;
        rows[0].spectral = Some(accuracy::exact_reference(&glass, &color::angle_quadrature().cosines));
        let baked = bake(&rows, &plan(64)).unwrap();
        assert_eq!(baked.manifest.error.spectral_samples, color::angle_quadrature().cosines.len());
        for t in &baked.manifest.textures {
            assert!(t.rows[1].error_vs_spectral.is_none());
            // The reference is the row's own exact curve: what is left is sampling and quantisation.
            let e = t.rows[0].error_vs_spectral.as_ref().unwrap();
            let exact = &t.rows[0].error_vs_exact;
            assert!(e.max_absolute_rgb <= exact.max_absolute_rgb + 1e-12, "{}: {e:?} vs {exact:?}", t.encoding);
            assert!(e.mean_relative_rgb.unwrap() < 2.0 * exact.mean_relative_rgb.unwrap() + 1e-6, "{}: {e:?} vs {exact:?}", t.encoding);
        }
    }

    #[test]
    fn strip_names_replace_slashes_and_escape_unsafe_characters() {
        assert_eq!(strip_stem("3d/metals/gold"), "3d__metals__gold");
        assert_eq!(strip_stem("main/Y/a:b%"), "main__Y__a%3Ab%25");
        assert_eq!(strip_stem("other/C2ClF3_n - x/FDS90(P)"), "other__C2ClF3_n - x__FDS90(P)");
    }

    /// Ids whose stems meet ignoring case each get a hash of their own id; the others keep
    /// the plain stem, and every stem is distinct.
    #[test]
    fn colliding_strip_names_are_told_apart_by_a_hash_of_the_id() {
        let mut rows = rows(4);
        let template = rows[0].clone();
        rows.clear();
        for page in ["h/X/J", "h/X/j", "h/X__Y/z", "h/X/Y__z", "h/X/alone"] {
            rows.push(Row { page: page.into(), ..template.clone() });
        }
        let stems = strip_stems(&rows);
        assert_eq!(stems[4], "h__X__alone");
        // FNV-1a of "h/X/J", computed by hand from its definition, top 32 bits.
        let fnv = |text: &str| text.bytes().fold(0xcbf29ce484222325u64, |h, b| (h ^ b as u64).wrapping_mul(0x100000001b3));
        assert_eq!(stems[0], format!("h__X__J~{:08x}", fnv("h/X/J") >> 32));
        assert!(stems[2].starts_with("h__X__Y__z~") && stems[3].starts_with("h__X__Y__z~") && stems[2] != stems[3]);
        let lower: std::collections::BTreeSet<String> = stems.iter().map(|s| s.to_lowercase()).collect();
        assert_eq!(lower.len(), 5);
        assert!(bake(&rows, &plan(4)).is_ok());
    }

    #[test]
    fn bad_plans_and_rows_are_errors() {
        for size in [0, MAX_SIZE + 1] {
            let e = bake(&rows(4), &plan(size)).unwrap_err().to_string();
            assert!(e.contains("--size"), "{e}");
        }
        let mut two = plan(4);
        two.sources = vec![Source::ThreeChannel, Source::Spectral];
        assert!(bake(&rows(4), &two).unwrap_err().to_string().contains("2 sources"));
        let mut short = rows(4);
        short[0].spectral = Some([vec![0.04; 3], vec![0.04; 3], vec![0.04; 3]]);
        assert!(bake(&short, &plan(4)).unwrap_err().to_string().contains("spectral reference of 3 values"));
        let mut bad = rows(4);
        bad[0].curves[0][1][2] = f64::NAN;
        assert!(bake(&bad, &plan(4)).unwrap_err().to_string().contains("non-finite"));
        let mut twins = rows(4);
        twins[1].page = twins[0].page.clone();
        assert!(bake(&twins, &plan(4)).unwrap_err().to_string().contains("same strip file name"));
        assert!(bake(&[], &plan(4)).is_err());
    }
}
