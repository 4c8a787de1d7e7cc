//! The effects page, `report/effects.html`, and its summary on the index. One section per
//! scene (`make effects` writes `<out>/<scene>/`, `make gpu` `<out>/gpu-<scene>/`; both
//! folders feed one section), led by charts drawn from the effects' tables:
//!
//! - reflections and refractions (`effects_errors.csv`): the Fresnel error (ΔE2000 and
//!   relative) against the depths, one line per method, per material; the total error
//!   against the time of each configuration (GPU `shading_ms` of `effects_timing.csv`
//!   when `make gpu` ran, the CPU twin's `frame_ms` of `effects_cpu_timing.csv`
//!   otherwise) with its Pareto front labelled; the geometry error against the search's
//!   step counts;
//! - ambient occlusion (`ao_errors.csv`): the error against passes per technique and
//!   against CPU time, with the rows' statistics; both techniques and every GTAO preset
//!   against the GPU time of each device that timed them (`super::ao_cost`); the signed
//!   error's histograms
//!   (`ao_histogram.csv`, `super::ao_histogram`);
//!
//! then the hero frame (`effects_hero.csv`): the reference, each method and its error
//! image side by side, every panel labelled with its figures, a colour bar in the error
//! images' units, and the crops where the error is largest; the tables last, collapsed.
//! Every chart point carries the table, column and rows it is the (pixel- or
//! surfel-weighted) mean of, as data attributes of its hover mark. Pictures are linked
//! as files, never inlined: copies under `report/pictures/<scene>/…` (the same path as
//! under the output folder; [`pictures`] lists them), so `report/` alone shows everything.
//!
//! Scenes come in the order of the reader's question ([`scenes`]): reflections and
//! refractions, then spectral, then ambient occlusion; each opens with its findings
//! (`findings::search_finding`, `spectral_finding`, `ao_finding`). The error-against-time
//! charts take the GPU time of each device that timed the scene's configurations (one chart
//! per device) and the CPU twin's only as a labelled fallback; their points are coloured by
//! method and shaped by depth, the Pareto front joined, labelled and named in the caption.
//!
//! Every column is read through its constant in `nklut_tables::effects_tables` (the devices'
//! Fresnel timings and image errors: `gpu_tables`), the list the writers put them from: its
//! name, its kind (`CsvTable::get` reads a cell as that kind, `value` as a number) and, in a
//! chart point's trace, the column it is the mean of. A table written before a column
//! existed reads it as absent.

use std::collections::BTreeMap;
use std::fmt::Write;

use anyhow::Result;

use nklut_tables::columns::{Column, Float, Integer, Numeric, OptionalFloat, Text};
use nklut_tables::effects_tables::{
    ao_errors, ao_histogram, ao_timing, configuration, effects_cpu_timing, effects_errors, effects_hero, effects_timing, spectral_errors,
};
use nklut_tables::gpu_tables::{gpu_timing, image_errors};

use super::charts::{self, CostPoint, ErrorAxis, LineChart, LinePoint, Series, Trace, PALETTE};
use super::csvdata::CsvTable;
use super::extras::cell;
use super::findings::{self, Finding};
use super::html::{code_spans, delta_e, escape, href, number, percent, utc, TableText};
use super::inputs::{DeviceTables, Inputs, DEVICES_DIR};
use crate::stats::median;

/// The effects page, next to `index.html`.
pub const EFFECTS_PAGE: &str = "effects.html";

/// The tables the effects page reads and the command that writes each.
const TABLES: [(&str, &str); 8] = [
    (
        effects_errors::CSV,
        "image error of multiple reflections and refractions per depth and step counts (`make effects`; `make gpu` for the GPU's)",
    ),
    (effects_cpu_timing::CSV, "the CPU twin's frame time per configuration (`make effects`)"),
    (effects_hero::CSV, "the hero frame's panels and their figures (`make effects`)"),
    (effects_timing::CSV, "GPU time of the map update and the shading pass per configuration (`make gpu`)"),
    (ao_errors::CSV, "ambient-occlusion error per passes and technique (`make effects`)"),
    (
        spectral_errors::CSV,
        "three-channel against spectral reference per object, index source and depth (`nklut effects` on a scene with `effects.spectral`)",
    ),
    (ao_timing::CSV, "ambient-occlusion GPU time per surfel configuration and GTAO preset (`make gpu`)"),
    (ao_histogram::CSV, "ambient-occlusion signed error per bin, object, technique and passes (`make effects`)"),
];

/// The tables of one scene: its `make effects` folder and its `make gpu` folder together.
pub struct SceneTables<'a> {
    /// The scene's name: the folder's, without `gpu-` (empty: tables at the top of the
    /// output folder).
    pub name: String,
    /// (path under the output folder, table), in path order.
    pub tables: Vec<(&'a str, &'a CsvTable)>,
}

impl<'a> SceneTables<'a> {
    /// The table `name` of the folder `make effects` writes (`gpu`: of `make gpu`'s).
    fn table(&self, name: &str, gpu: bool) -> Option<(&'a str, &'a CsvTable)> {
        self.tables.iter().copied().find(|(path, _)| path.ends_with(name) && folder_of(path).starts_with("gpu-") == gpu)
    }

    fn id(&self) -> String {
        format!("scene-{}", if self.name.is_empty() { "top" } else { &self.name })
    }

    fn title(&self) -> String {
        if self.name.is_empty() {
            "tables at the top of the output folder".to_string()
        } else {
            format!("scene {}", self.name)
        }
    }
}

/// The folder part of a table's path (`glass-sphere` of `glass-sphere/effects_errors.csv`).
fn folder_of(path: &str) -> &str {
    path.rsplit_once('/').map_or("", |(folder, _)| folder)
}

/// `../<folder>/<file>`: a file an effects table names, seen from the report folder.
fn from_report(folder: &str, file: &str) -> String {
    if folder.is_empty() {
        format!("{PICTURES_DIR}/{}", href(file))
    } else {
        format!("{PICTURES_DIR}/{}/{}", href(folder), href(file))
    }
}

/// The folder under `report/` that holds a copy of every picture the effects page shows,
/// at its path under the output folder, so that `report/` alone shows everything.
pub const PICTURES_DIR: &str = "pictures";

/// The pictures `html` shows or links under [`PICTURES_DIR`]: their paths under the output
/// folder (percent-decoded), each once, in order. A path that would leave the output
/// folder (`..`, an absolute path, an empty part) is left out.
pub fn pictures(html: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for attribute in ["src=\"", "href=\""] {
        let prefix = format!("{attribute}{PICTURES_DIR}/");
        for (at, _) in html.match_indices(&prefix) {
            let rest = &html[at + prefix.len()..];
            let Some(end) = rest.find('"') else { continue };
            let Some(path) = percent_decoded(&rest[..end]) else { continue };
            let inside = path.split('/').all(|part| !part.is_empty() && part != "." && part != "..");
            if inside && !out.contains(&path) {
                out.push(path);
            }
        }
    }
    out
}

/// `%XX` sequences of an `href` decoded (`None` when malformed or not UTF-8).
fn percent_decoded(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The kinds of scene in the order the page answers the reader's question: what the
/// Fresnel method costs in reflections and refractions, then what three channels cost
/// against the spectrum, then ambient occlusion.
pub const SCENE_GROUPS: [&str; 4] = ["reflections and refractions", "spectral", "ambient occlusion", "other tables"];

impl SceneTables<'_> {
    /// The scene's group (an index into [`SCENE_GROUPS`]): spectral when it has
    /// `spectral_errors.csv`, else specular with `effects_errors.csv`, else ambient
    /// occlusion with `ao_errors.csv` or `ao_histogram.csv`.
    pub fn group(&self) -> usize {
        let has = |name: &str| self.table(name, false).or_else(|| self.table(name, true)).is_some();
        if has(spectral_errors::CSV) {
            1
        } else if has(effects_errors::CSV) {
            0
        } else if has(ao_errors::CSV) || has(ao_histogram::CSV) {
            2
        } else {
            3
        }
    }

    /// Whether any path of its `effects_errors.csv` refracts (reflection-only scenes come
    /// first in their group).
    fn refracts(&self) -> bool {
        self.table(effects_errors::CSV, false)
            .or_else(|| self.table(effects_errors::CSV, true))
            .is_some_and(|(_, t)| t.rows.iter().any(|r| t.value(r, effects_errors::REFRACTION_DEPTH).is_some_and(|d| d > 0.0)))
    }
}

/// The effects tables of `inputs`, grouped by scene, in the reader's order: by
/// [`SceneTables::group`], reflection-only before refracting scenes, then by name.
pub fn scenes(inputs: &Inputs) -> Vec<SceneTables<'_>> {
    let mut by_scene: BTreeMap<String, Vec<(&str, &CsvTable)>> = BTreeMap::new();
    for (path, table) in &inputs.extra {
        if TABLES.iter().any(|(name, _)| path.ends_with(name)) {
            let folder = folder_of(path);
            let name = folder.strip_prefix("gpu-").unwrap_or(folder).to_string();
            by_scene.entry(name).or_default().push((path.as_str(), table));
        }
    }
    let mut scenes: Vec<SceneTables> = by_scene.into_iter().map(|(name, tables)| SceneTables { name, tables }).collect();
    scenes.sort_by_cached_key(|s| (s.group(), s.refracts(), s.name.clone()));
    scenes
}

/// The findings a scene opens with, its own kind's first: the Fresnel method against the
/// distance-map search (`effects_errors.csv`), three channels against the spectrum
/// (`spectral_errors.csv`), surfels against GTAO (`ao_errors.csv`).
pub fn scene_findings(scene: &SceneTables, bound: f64) -> Vec<Finding> {
    let name = if scene.name.is_empty() { "the top folder" } else { scene.name.as_str() };
    let mut found: Vec<(usize, Finding)> = Vec::new();
    if let Some((path, t)) = scene.table(effects_errors::CSV, false).or_else(|| scene.table(effects_errors::CSV, true)) {
        found.extend(findings::search_finding(name, path, t).map(|f| (0, f)));
    }
    if let Some((path, t)) = scene.table(spectral_errors::CSV, false) {
        found.extend(findings::spectral_finding(name, path, t, bound).map(|f| (1, f)));
    }
    if let Some((path, t)) = scene.table(ao_errors::CSV, false) {
        found.extend(findings::ao_finding(name, path, t).map(|f| (2, f)));
    }
    let own = scene.group();
    found.sort_by_key(|(kind, _)| (*kind != own, *kind));
    found.into_iter().map(|(_, f)| f).collect()
}

/// The index's effects section: where the effects page is and what it holds, or each
/// absent table with the command that writes it.
pub fn summary(inputs: &Inputs) -> (String, String) {
    let scenes = scenes(inputs);
    let mut html = String::from("<h2 id=\"effects\">Effects</h2>\n");
    let mut markdown = String::from("\n## Effects\n\n");
    if !scenes.is_empty() {
        let links: Vec<String> =
            scenes.iter().map(|s| format!("<a href=\"{EFFECTS_PAGE}#{}\">{}</a>", escape(&s.id()), escape(&s.title()))).collect();
        let _ = writeln!(
            html,
            "<p>Charts of what each method and setting costs in accuracy and time, hero frames with their error images, and the tables, per scene on <a href=\"{EFFECTS_PAGE}\">the effects page</a>: {}.</p>",
            links.join(", ")
        );
        let names: Vec<String> = scenes.iter().map(SceneTables::title).collect();
        let _ = writeln!(markdown, "Per scene on {EFFECTS_PAGE}: {}.\n", names.join(", "));
    }
    for (name, what) in TABLES {
        if !inputs.extra.keys().any(|path| path == name || path.ends_with(&format!("/{name}"))) {
            let _ = writeln!(html, "<p class=\"absent\"><code>{}</code> is absent: {}.</p>", escape(name), code_spans(what));
            let _ = writeln!(markdown, "`{name}` is absent: {what}.\n");
        }
    }
    (html, markdown)
}

/// Style of the effects page beyond the report's own.
const EFFECTS_STYLE: &str = ".wide{overflow-x:auto;max-width:100%}details{margin:0.5em 0}summary{cursor:pointer;font-size:14px}\
.charts{display:flex;flex-wrap:wrap;gap:8px 24px;align-items:flex-start}.charts figure{margin:0}\
.panels{display:grid;grid-template-columns:repeat(auto-fill,minmax(min(360px,100%),1fr));gap:12px}.panels figure{margin:0}\
.panels img{width:100%;height:auto;display:block;image-rendering:pixelated}.panels figcaption{font-size:14px;color:#222}\
.crops{display:flex;flex-wrap:wrap;gap:10px}.crops figure{margin:0;width:200px}.crops img{width:196px;height:196px;image-rendering:pixelated;display:block}\
.crops figcaption{font-size:13px;color:#222}.scale img{width:512px;height:16px;display:block}\
.hero-panels{display:block}.hero-panels figure.panel{margin:0 0 20px}\
.hero-grid{display:grid;grid-template-columns:repeat(auto-fill,minmax(min(512px,100%),512px));gap:6px 12px;margin-top:6px}\
.hero-grid img{width:auto;max-width:100%;height:auto;display:block}.hero-grid .hero-cell:first-child{grid-column:1/-1}.cell-note{font-size:13px;margin:2px 0}\
.legends{display:flex;flex-wrap:wrap;gap:8px 24px}.colour-legend{margin:0;max-width:512px}.colour-legend img{max-width:100%;height:auto;display:block}.colour-legend figcaption{font-size:13px}\
.spectral-panels{display:flex;flex-wrap:wrap;gap:12px}.spectral-panels figure{margin:0;max-width:100%}.spectral-panels img{display:block;max-width:100%;height:auto;image-rendering:pixelated}\
.charts figure{max-width:100%}p.finding{font-size:16px;border-left:4px solid #d55e00;padding-left:8px}.no-chart{font-size:14px;color:#333}";

/// The effects page, or `None` when the output folder holds no effects table.
pub fn page(inputs: &Inputs) -> Result<Option<String>> {
    let scenes = scenes(inputs);
    if scenes.is_empty() && inputs.devices.is_empty() {
        return Ok(None);
    }
    let mut html = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>nklut report: effects</title><style>{}{EFFECTS_STYLE}</style></head><body>\n",
        super::STYLE
    );
    html.push_str("<h1 id=\"top\">nklut report: effects</h1>\n<p><a href=\"index.html\">Back to the index</a>. ");
    html.push_str("Each section is drawn from the tables named under it (the command that wrote each and when). Every chart point names, on hover and in its data attributes, the rows of the table it is the mean of; errors are against the ray-traced f64 reference.</p>\n");
    let mut contents = Vec::new();
    for (group, name) in SCENE_GROUPS.iter().enumerate() {
        let links: Vec<String> = scenes
            .iter()
            .filter(|s| s.group() == group)
            .map(|s| format!("<a href=\"#{}\">{}</a>", escape(&s.id()), escape(&s.title())))
            .collect();
        if !links.is_empty() {
            contents.push(format!("{name}: {}", links.join(", ")));
        }
    }
    if !inputs.devices.is_empty() {
        contents.push("<a href=\"#devices\">across devices</a>".to_string());
    }
    if !contents.is_empty() {
        let _ = writeln!(html, "<p class=\"contents\">Scenes, in the order of the question (what the Fresnel method costs in reflections and refractions, what three channels cost against the spectrum, then ambient occlusion) — {}.</p>", contents.join("; "));
    }
    let bound = findings::bound(inputs.extra.get("recommendations.csv"));
    for scene in &scenes {
        scene_section(&mut html, inputs, scene, bound)?;
    }
    devices_section(&mut html, inputs);
    html.push_str("</body></html>\n");
    Ok(Some(html))
}

/// What wrote a table and when.
fn provenance(inputs: &Inputs, path: &str) -> String {
    let name = path.rsplit('/').next().unwrap_or(path);
    let what = TABLES.iter().find(|(n, _)| *n == name).map_or("", |(_, w)| *w);
    let when = inputs.written.get(path).map(|t| format!(", written {}", utc(*t))).unwrap_or_default();
    format!("<code>{}</code>: {}{when}", escape(path), code_spans(what))
}

fn scene_section(html: &mut String, inputs: &Inputs, scene: &SceneTables, bound: f64) -> Result<()> {
    let _ = writeln!(html, "<section><h2 id=\"{}\">{}</h2>", escape(&scene.id()), escape(&scene.title()));
    for finding in scene_findings(scene, bound) {
        let _ = writeln!(html, "<p class=\"finding\" id=\"finding-{}\">{}</p>", escape(&finding.id), finding.sentence_html());
    }
    let command = if scene.name.is_empty() {
        "<code>nklut effects SCENE</code> into the output folder".to_string()
    } else {
        let name = escape(&scene.name);
        format!("<code>nklut effects scenes/{name}.yaml</code> (make effects) and <code>nklut gpu run scenes/{name}.yaml</code> (make gpu)")
    };
    let provenance: Vec<String> = scene.tables.iter().map(|(path, _)| provenance(inputs, path)).collect();
    let _ = writeln!(html, "<p class=\"note\">From {command}. Tables: {}.</p>", provenance.join("; "));
    let spectral = scene.table(spectral_errors::CSV, false);
    if let Some(spectral) = spectral.filter(|_| scene.group() == 1) {
        spectral_section(html, spectral)?;
    }
    if let Some(errors) = scene.table(effects_errors::CSV, false).or_else(|| scene.table(effects_errors::CSV, true)) {
        specular_section(html, scene, errors, &inputs.devices)?;
    }
    if let Some(ao) = scene.table(ao_errors::CSV, false) {
        ao_section(html, ao)?;
        super::ao_cost::section(html, &scene.name, ao, scene.table(ao_timing::CSV, true), &inputs.devices)?;
    }
    if let Some(histogram) = scene.table(ao_histogram::CSV, false) {
        super::ao_histogram::section(html, histogram)?;
    }
    if let Some(spectral) = spectral.filter(|_| scene.group() != 1) {
        spectral_section(html, spectral)?;
    }
    if let Some(hero) = scene.table(effects_hero::CSV, false) {
        hero_section(html, hero);
    }
    html.push_str("<h3>Tables</h3>\n");
    for (path, table) in &scene.tables {
        let mut text = TableText::new(&table.headers.iter().map(String::as_str).collect::<Vec<_>>());
        for row in &table.rows {
            text.row(table.headers.iter().zip(row).map(|(h, v)| cell(h, v)).collect());
        }
        let _ = writeln!(
            html,
            "<details><summary><code>{}</code>: {} rows × {} columns (<a href=\"../{}\">CSV</a>)</summary><div class=\"wide\">{}</div></details>",
            escape(path),
            table.rows.len(),
            table.headers.len(),
            href(path),
            text.html("effects")
        );
    }
    html.push_str("</section>\n");
    Ok(())
}

/// Those of `rows` searched with `linear` + `secant` steps.
fn rows_at_steps(errors: &CsvTable, rows: &[usize], linear: u64, secant: u64) -> Vec<usize> {
    let (linear, secant) = (linear.to_string(), secant.to_string());
    rows.iter()
        .copied()
        .filter(|&r| {
            let row = &errors.rows[r];
            errors.raw(row, effects_errors::LINEAR_STEPS) == linear && errors.raw(row, effects_errors::SECANT_STEPS) == secant
        })
        .collect()
}

/// The columns that name a configuration of the distance maps, in the tables' order.
const CONFIGURATION: [&str; 5] = [
    effects_errors::METHOD.name,
    configuration::REFLECTION_DEPTH.name,
    configuration::REFRACTION_DEPTH.name,
    configuration::LINEAR_STEPS.name,
    configuration::SECANT_STEPS.name,
];

fn key(table: &CsvTable, row: &[String], columns: &[&str]) -> Vec<String> {
    columns.iter().map(|c| table.text(row, c).to_string()).collect()
}

/// The distinct values of an integer column over `rows`, ascending (a cell that is not an
/// integer left out).
fn integers(table: &CsvTable, rows: &[usize], column: Column<Integer>) -> Vec<u64> {
    let mut values: Vec<u64> = rows.iter().filter_map(|&r| u64::try_from(table.get(&table.rows[r], column)?).ok()).collect();
    values.sort_unstable();
    values.dedup();
    values
}

/// Distinct values of `f` over `rows`, in first-seen order.
fn distinct<T: PartialEq + Clone>(rows: &[usize], f: impl Fn(usize) -> T) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for &r in rows {
        let v = f(r);
        if !out.contains(&v) {
            out.push(v);
        }
    }
    out
}

/// A depth configuration: reflections then refractions, e.g. `3+1`.
fn depth_label(table: &CsvTable, row: &[String]) -> String {
    format!("{}+{}", table.raw(row, configuration::REFLECTION_DEPTH), table.raw(row, configuration::REFRACTION_DEPTH))
}

/// The depth configurations of `rows`, shallowest first (by total bounces, then reflections).
fn depth_categories(table: &CsvTable, rows: &[usize]) -> Vec<String> {
    let mut depths: Vec<(u64, u64)> = distinct(rows, |r| {
        let row = &table.rows[r];
        let n = |c| table.raw(row, c).parse::<u64>().unwrap_or(0);
        (n(configuration::REFLECTION_DEPTH), n(configuration::REFRACTION_DEPTH))
    });
    depths.sort_by_key(|&(r, t)| (r + t, r));
    depths.into_iter().map(|(r, t)| format!("{r}+{t}")).collect()
}

/// A series over the categories `0..categories`: at x, `at(x)` gives the rows and the label
/// of its point (none when no row), the point being the mean of `column` over the rows,
/// weighted by `weight`.
fn series(
    name: String,
    color: plotters::style::RGBColor,
    categories: usize,
    (path, table): (&str, &CsvTable),
    (column, weight): (Column<impl Numeric>, Column<Integer>),
    at: impl Fn(usize) -> (Vec<usize>, String),
) -> Series {
    let points = (0..categories)
        .filter_map(|x| {
            let (rows, label) = at(x);
            (!rows.is_empty()).then(|| LinePoint { x, label, y: Trace::mean_of(path, table, column, rows, Some(weight)) })
        })
        .collect();
    Series { name, color, points }
}

/// A table of objects' errors per depth (`effects_errors`, `spectral_errors`): its path,
/// the table, and its columns of the material and of the pixels each row is the mean over.
struct ObjectTable<'a> {
    path: &'a str,
    table: &'a CsvTable,
    material: Column<Text>,
    pixels: Column<Integer>,
}

/// One line against depth: at each depth category, the pixel-weighted mean of `column` over
/// the `rows` of `material` whose `key` column reads `value`; named `value`.
fn depth_series(
    source: &ObjectTable,
    rows: &[usize],
    categories: &[String],
    material: &str,
    (key, value): (Column<Text>, &str),
    column: Column<impl Numeric>,
    color: plotters::style::RGBColor,
) -> Series {
    let ObjectTable { path, table, .. } = *source;
    series(value.to_string(), color, categories.len(), (path, table), (column, source.pixels), |x| {
        let depth = &categories[x];
        let picked = rows
            .iter()
            .copied()
            .filter(|&r| {
                let row = &table.rows[r];
                table.get(row, source.material) == material && table.get(row, key) == value && depth_label(table, row) == *depth
            })
            .collect();
        (picked, format!("{material}, {value}, depth {depth}"))
    })
}

/// Whether depth categories (`r+t`, shallowest first) are ordered: each has at least the
/// reflections and the refractions of the one before (1+0, 2+0, 3+0; not 1+3 beside 3+1).
pub fn depths_ordered(categories: &[String]) -> bool {
    let parsed: Vec<Option<(u64, u64)>> =
        categories.iter().map(|c| c.split_once('+').and_then(|(r, t)| Some((r.parse().ok()?, t.parse().ok()?)))).collect();
    parsed.windows(2).all(|w| matches!((w[0], w[1]), (Some(a), Some(b)) if a.0 <= b.0 && a.1 <= b.1))
}

/// The sentence that stands for a chart of `series` that would show too little: every value
/// 0, or one point.
fn too_little_sentence(caption: &str, series: &[Series], y_axis: ErrorAxis) -> Option<String> {
    let values: Vec<(f64, &str)> = series.iter().flat_map(|s| s.points.iter().map(|p| (p.y.value, p.label.as_str()))).collect();
    let shown = |v: f64| match y_axis {
        ErrorAxis::Relative => percent(v),
        ErrorAxis::DeltaE => delta_e(v),
        ErrorAxis::Absolute => number(v),
    };
    match charts::too_little(values.iter().map(|v| v.0))? {
        charts::TooLittle::Nothing => Some(format!("{caption}: no value to draw.")),
        charts::TooLittle::AllZero => Some(format!("{caption}: 0 at every point ({} points), so no chart is drawn.", values.len())),
        charts::TooLittle::OnePoint(v) => {
            let label = values.iter().find(|x| x.0.is_finite()).map_or("", |x| x.1);
            Some(format!("{caption}: one point only ({label}): {}.", shown(v)))
        }
    }
}

/// A line chart as a figure of `html`, or the sentence that stands for it when it would
/// show too little ([`charts::too_little`]).
fn chart_or_sentence(html: &mut String, spec: &LineChart, size: (u32, u32), legend: &str, caption: &str) -> Result<()> {
    match too_little_sentence(spec.caption.unwrap_or(caption), spec.series, spec.y_axis) {
        Some(sentence) => {
            let _ = write!(html, "<p class=\"no-chart\">{}</p>", escape(&sentence));
        }
        None => figure(html, &charts::line_chart(spec, size)?, legend, caption),
    }
    Ok(())
}

/// A chart of `series` against depth (reflections+refractions), as a figure of `html`:
/// lines join the depths only where they are ordered ([`depths_ordered`]).
fn depth_chart(html: &mut String, categories: &[String], y_axis: ErrorAxis, series: &[Series], caption: &str) -> Result<()> {
    let joined = depths_ordered(categories);
    let chart = LineChart { categories, x_name: "depth (reflections+refractions)", y_axis, series, caption: Some(caption), joined };
    chart_or_sentence(html, &chart, (440, 300), "", "")
}

/// Cost points traced to their rows, the Pareto front over (cost, error) marked.
fn cost_points(traced: Vec<(String, Trace, Trace)>) -> Vec<CostPoint> {
    let front = charts::pareto_front(&traced.iter().map(|(_, x, y)| (x.value, y.value)).collect::<Vec<_>>());
    traced
        .into_iter()
        .zip(front)
        .map(|((label, x, y), pareto)| CostPoint { label, cost: x.value, error: y.value, pareto, trace: Some([x, y]), style: None })
        .collect()
}

/// The legend of a line chart's series, series hidden under another sharing its entry
/// (values compared category by category, NaN where a series has no point).
fn series_legend(series: &[Series]) -> String {
    let categories = series.iter().flat_map(|s| s.points.iter().map(|p| p.x + 1)).max().unwrap_or(0);
    let values = |s: &Series| {
        let mut values = vec![f64::NAN; categories];
        for p in &s.points {
            values[p.x] = p.y.value;
        }
        values
    };
    let drawn: Vec<charts::Drawn> =
        series.iter().map(|s| charts::Drawn { name: &s.name, color: s.color, dashed: false, values: values(s) }).collect();
    charts::merged_legend_html(&drawn)
}

/// A chart in a figure, its legend beside it and its caption (none where the chart
/// carries its title).
fn figure(html: &mut String, svg: &str, legend: &str, caption: &str) {
    if !svg.is_empty() {
        let caption = if caption.is_empty() { String::new() } else { format!("<figcaption>{}</figcaption>", escape(caption)) };
        let _ = write!(html, "<figure class=\"plot\">{svg}{legend}{caption}</figure>");
    }
}

/// Where the times of an error-against-time chart come from.
struct TimeSource<'a> {
    /// The chart's subject ("GPU time on lavapipe…", "the CPU twin's frame time").
    title: String,
    /// The table's path as a trace names it.
    path: String,
    table: &'a CsvTable,
    /// `shading_ms` (a GPU's) or `frame_ms` (the CPU twin's).
    column: Column<Float>,
    /// The x axis's name with its unit.
    axis: String,
    /// What the caption says of the source.
    note: String,
}

impl TimeSource<'_> {
    /// The columns a timing row and an error row must agree on: the configuration, and the
    /// distance maps' size and layers where both tables have them (a device's timings of
    /// another scene's maps do not count).
    fn match_columns(&self, errors: &CsvTable) -> Vec<&'static str> {
        let mut columns = CONFIGURATION.to_vec();
        for extra in [configuration::MAP_SIZE, configuration::LAYERS] {
            if errors.holds(extra) && self.table.holds(extra) {
                columns.push(extra.name);
            }
        }
        columns
    }
}

/// The resolutions of `table`'s rows, distinct, joined.
fn resolutions(table: &CsvTable) -> String {
    let mut seen: Vec<&str> = Vec::new();
    for row in &table.rows {
        let r = table.get(row, effects_timing::RESOLUTION);
        if !r.is_empty() && !seen.contains(&r) {
            seen.push(r);
        }
    }
    seen.join(", ")
}

/// The time sources of a scene's error-against-time charts: this machine's GPU
/// (`gpu-<scene>/effects_timing.csv`, `make gpu`) and each device result whose
/// `effects_timing` has a row of one of the scene's configurations (same method, depths,
/// steps, map size and layers); the CPU twin (`effects_cpu_timing.csv`) only where no GPU
/// timed the scene.
fn time_sources<'a>(scene: &SceneTables<'a>, errors: &CsvTable, devices: &'a BTreeMap<String, DeviceTables>) -> Vec<TimeSource<'a>> {
    let mut out = Vec::new();
    if let Some((path, table)) = scene.table(effects_timing::CSV, true) {
        out.push(TimeSource {
            title: "GPU time on this machine (make gpu)".into(),
            path: path.to_string(),
            table,
            column: effects_timing::SHADING_MS,
            axis: "GPU time of the shading pass (ms)".into(),
            note: format!("Times: median shading pass of effects_timing.csv at {}.", resolutions(table)),
        });
    }
    for (device, tables) in devices {
        let Some(table) = tables.effects_timing.as_ref() else { continue };
        let path = tables.table_path(device, effects_timing::CSV);
        let source = TimeSource {
            title: format!("GPU time on {}", findings::short_device(device)),
            path,
            table,
            column: effects_timing::SHADING_MS,
            axis: format!("GPU time of the shading pass on {} (ms)", findings::short_device(device)),
            note: format!(
                "Times: the median shading pass of {device} ({}, effects_timing at {}), matched to this scene's rows by method, depths, search steps, map size and layers.",
                tables.source,
                resolutions(table)
            ),
        };
        let columns = source.match_columns(errors);
        let wanted: Vec<Vec<String>> = errors.rows.iter().map(|r| key(errors, r, &columns)).collect();
        if table.rows.iter().any(|r| wanted.contains(&key(table, r, &columns))) {
            out.push(source);
        }
    }
    if out.is_empty() {
        if let Some((path, table)) = scene.table(effects_cpu_timing::CSV, false) {
            out.push(TimeSource {
                title: "the CPU twin's frame time (fallback: no GPU timed this scene)".into(),
                path: path.to_string(),
                table,
                column: effects_cpu_timing::FRAME_MS,
                axis: "CPU twin's frame time (ms, effects_cpu_timing.csv; fallback, not GPU time)".into(),
                note: "Times: the CPU twin's frame (the fallback where no device result times this scene's configurations); CPU-twin times are ratios between configurations on this machine, not GPU cost.".into(),
            });
        }
    }
    out
}

/// The sentence that stands for a cost chart whose points would show too little.
fn too_little_points(caption: &str, points: &[CostPoint]) -> Option<String> {
    let drawn: Vec<&CostPoint> = points.iter().filter(|p| p.cost > 0.0 && p.cost.is_finite() && p.error.is_finite()).collect();
    match charts::too_little(drawn.iter().map(|p| p.error))? {
        charts::TooLittle::Nothing => Some(format!("{caption}: no point has both a time and an error.")),
        charts::TooLittle::AllZero => Some(format!("{caption}: every error is 0 ({} points), so no chart is drawn.", drawn.len())),
        charts::TooLittle::OnePoint(v) => {
            let p = drawn.iter().find(|p| p.error.is_finite()).map_or(String::new(), |p| format!("{}: {} ms", p.label, number(p.cost)));
            Some(format!("{caption}: one configuration only ({p}), mean ΔE2000 {}.", delta_e(v)))
        }
    }
}

fn specular_section(
    html: &mut String,
    scene: &SceneTables,
    (path, errors): (&str, &CsvTable),
    devices: &BTreeMap<String, DeviceTables>,
) -> Result<()> {
    html.push_str("<h3>Multiple reflections and refractions</h3>\n");
    let all: Vec<usize> = (0..errors.rows.len()).collect();
    let (Some(&linear), Some(&secant)) =
        (integers(errors, &all, effects_errors::LINEAR_STEPS).last(), integers(errors, &all, effects_errors::SECANT_STEPS).last())
    else {
        html.push_str("<p class=\"absent\">The table has no step counts.</p>");
        return Ok(());
    };
    let at_steps = rows_at_steps(errors, &all, linear, secant);
    let methods: Vec<String> = distinct(&all, |r| errors.get(&errors.rows[r], effects_errors::METHOD).to_string());
    let color = |method: &str| PALETTE[methods.iter().position(|m| m == method).unwrap_or(0) % PALETTE.len()];
    let legend = charts::legend(methods.iter().map(|m| (m.as_str(), color(m), false)));

    // Fresnel error against depth, per material.
    let _ = writeln!(
        html,
        "<p>How each method's Fresnel error compounds with depth: the error of the image through the distance maps with the method against the same maps with exact Fresnel, at the finest search ({linear} linear + {secant} secant steps), mean over the material's pixels; lines join the depths, shallowest first (reflections+refractions).</p>"
    );
    html.push_str(&legend);
    html.push_str("<div class=\"charts\">");
    let materials: Vec<String> = distinct(&at_steps, |r| errors.get(&errors.rows[r], effects_errors::MATERIAL).to_string());
    let objects = ObjectTable { path, table: errors, material: effects_errors::MATERIAL, pixels: effects_errors::PIXELS };
    let categories = depth_categories(errors, &at_steps);
    for material in &materials {
        for (column, axis, what) in [
            (effects_errors::FRESNEL_MEAN_DELTA_E2000.numbers(), ErrorAxis::DeltaE, "colour difference"),
            (effects_errors::FRESNEL_MEAN_REL_ERROR.numbers(), ErrorAxis::Relative, "relative error"),
        ] {
            let series: Vec<Series> = methods
                .iter()
                .map(|method| {
                    depth_series(&objects, &at_steps, &categories, material, (effects_errors::METHOD, method), column, color(method))
                })
                .collect();
            depth_chart(html, &categories, axis, &series, &format!("{material}: Fresnel {what}"))?;
        }
    }
    html.push_str("</div>");

    // Total error against time: per device that timed this scene's configurations, else
    // the CPU twin (labelled as the fallback it is).
    let configurations: Vec<Vec<String>> = distinct(&all, |r| key(errors, &errors.rows[r], &CONFIGURATION));
    let all_depths = depth_categories(errors, &all);
    let marker = |depth: &str| charts::Marker::nth(all_depths.iter().position(|d| d == depth).unwrap_or(0));
    let sources = time_sources(scene, errors, devices);
    let mut drawn_any = false;
    let legends = format!(
        "{}{}",
        charts::point_legend("method", methods.iter().map(|m| (m.as_str(), color(m), charts::Marker::Circle))),
        charts::point_legend("depth", all_depths.iter().map(|d| (d.as_str(), PALETTE[7], marker(d))))
    );
    for source in &sources {
        let match_columns = source.match_columns(errors);
        let mut traced = Vec::new();
        let mut styles = Vec::new();
        for configuration in &configurations {
            let rows: Vec<usize> =
                all.iter().copied().filter(|&r| key(errors, &errors.rows[r], &CONFIGURATION) == *configuration).collect();
            let Some(&first) = rows.first() else { continue };
            let wanted = key(errors, &errors.rows[first], &match_columns);
            let timed: Vec<usize> =
                (0..source.table.rows.len()).filter(|&r| key(source.table, &source.table.rows[r], &match_columns) == wanted).collect();
            if timed.is_empty() {
                continue;
            }
            let label = format!("{} {}+{} {}/{}", configuration[0], configuration[1], configuration[2], configuration[3], configuration[4]);
            let depth = format!("{}+{}", configuration[1], configuration[2]);
            styles.push(charts::PointStyle { color: color(&configuration[0]), marker: marker(&depth) });
            traced.push((
                label,
                Trace::mean_of(&source.path, source.table, source.column, timed, None),
                Trace::mean_of(path, errors, effects_errors::TOTAL_MEAN_DELTA_E2000, rows, Some(effects_errors::PIXELS)),
            ));
        }
        if traced.is_empty() {
            continue;
        }
        let mut points = cost_points(traced);
        for (point, style) in points.iter_mut().zip(styles) {
            point.style = Some(style);
        }
        let caption_head = format!("Total error against {}", source.title);
        if let Some(sentence) = too_little_points(&caption_head, &points) {
            let _ = write!(html, "<p class=\"no-chart\">{}</p>", escape(&sentence));
            continue;
        }
        let chart = charts::cost_chart(&points, &source.axis, ErrorAxis::DeltaE, (900, 440))?;
        let front: Vec<&str> = points.iter().filter(|p| p.pareto).map(|p| p.label.as_str()).collect();
        figure(
            html,
            &chart.svg,
            if drawn_any { "" } else { &legends },
            &format!(
                "{caption_head}: total error (geometry and Fresnel against the ray-traced reference, mean ΔE2000 over the specular objects' pixels) of each configuration (method depth reflections+refractions linear/secant steps), coloured by method and shaped by depth. {} Pareto front (joined and labelled): {}. Every point shows its values on hover.",
                source.note,
                front.join(", ")
            ),
        );
        drawn_any = true;
    }
    if sources.is_empty() {
        html.push_str("<p class=\"absent\">No timing table: <code>effects_cpu_timing.csv</code> (make effects), <code>effects_timing.csv</code> (make gpu) or a device result timing this scene's configurations.</p>");
    }

    geometry_section(html, (path, errors), &all, methods.first().map_or("", String::as_str))
}

/// Geometry error against the search's step counts, at the deepest depth: the twin with
/// `reference_method` Fresnel against the reference with it, one line per secant count.
fn geometry_section(html: &mut String, (path, errors): (&str, &CsvTable), all: &[usize], reference_method: &str) -> Result<()> {
    let Some(depth) = depth_categories(errors, all).pop() else { return Ok(()) };
    let rows: Vec<usize> = all
        .iter()
        .copied()
        .filter(|&r| {
            let row = &errors.rows[r];
            depth_label(errors, row) == depth && errors.get(row, effects_errors::METHOD) == reference_method
        })
        .collect();
    let (linear_steps, secant_steps) =
        (integers(errors, &rows, effects_errors::LINEAR_STEPS), integers(errors, &rows, effects_errors::SECANT_STEPS));
    let categories: Vec<String> = linear_steps.iter().map(u64::to_string).collect();
    let series: Vec<Series> = secant_steps
        .iter()
        .enumerate()
        .map(|(i, secant)| {
            let color = PALETTE[(i + 1) % PALETTE.len()];
            series(
                format!("{secant} secant steps"),
                color,
                linear_steps.len(),
                (path, errors),
                (effects_errors::GEOMETRY_MEAN_DELTA_E2000, effects_errors::PIXELS),
                |x| {
                    let linear = linear_steps[x];
                    (rows_at_steps(errors, &rows, linear, *secant), format!("{linear} linear + {secant} secant steps, depth {depth}"))
                },
            )
        })
        .collect();
    let legend = series_legend(&series);
    chart_or_sentence(
        html,
        &LineChart {
            categories: &categories,
            x_name: "linear search steps",
            y_axis: ErrorAxis::DeltaE,
            series: &series,
            caption: Some("Geometry error against the search's steps"),
            joined: true,
        },
        (640, 320),
        &legend,
        &format!(
            "What the distance maps' search costs in accuracy: the error of where rays land (the twin with {reference_method} Fresnel against the reference with it), mean ΔE2000 over the specular objects' pixels at depth {depth}."
        ),
    )?;
    Ok(())
}

/// What three colour channels cost: per material a chart of the mean ΔE2000 of the
/// three-channel reference against the spectral one over depth, one line per index source,
/// and the deepest depth's frames (spectral, each source, its ΔE map) side by side.
fn spectral_section(html: &mut String, (path, spectral): (&str, &CsvTable)) -> Result<()> {
    html.push_str("<h3>Three channels against the spectrum</h3>\n");
    let all: Vec<usize> = (0..spectral.rows.len()).collect();
    let first = spectral.rows.first();
    let _ = writeln!(
        html,
        "<p>The three-channel f64 reference against the spectral one ({} wavelengths): mean ΔE2000 over each object's pixels, per depth (reflections+refractions) and source of the channel indices (<code>{}</code>).</p>",
        escape(first.map_or("", |row| spectral.raw(row, spectral_errors::WAVELENGTHS))),
        escape(path)
    );
    let sources: Vec<String> = distinct(&all, |r| spectral.get(&spectral.rows[r], spectral_errors::INDEX_SOURCE).to_string());
    let color = |source: &str| PALETTE[sources.iter().position(|s| s == source).unwrap_or(0) % PALETTE.len()];
    html.push_str(&charts::legend(sources.iter().map(|s| (s.as_str(), color(s), false))));
    html.push_str("<div class=\"charts\">");
    let categories = depth_categories(spectral, &all);
    let field = |r: usize, column: Column<Text>| spectral.get(&spectral.rows[r], column).to_string();
    let source_table = ObjectTable { path, table: spectral, material: spectral_errors::MATERIAL, pixels: spectral_errors::PIXELS };
    for material in distinct(&all, |r| field(r, spectral_errors::MATERIAL)) {
        let of_material: Vec<usize> = all.iter().copied().filter(|&r| field(r, spectral_errors::MATERIAL) == material).collect();
        // One chart per object: a material on several objects (two thicknesses of a glass)
        // is charted for each, named by its place in the scene.
        let objects = distinct(&of_material, |r| spectral.raw(&spectral.rows[r], spectral_errors::OBJECT_INDEX).to_string());
        for object in &objects {
            let rows: Vec<usize> =
                of_material.iter().copied().filter(|&r| spectral.raw(&spectral.rows[r], spectral_errors::OBJECT_INDEX) == object).collect();
            let series: Vec<Series> = sources
                .iter()
                .map(|source| {
                    depth_series(
                        &source_table,
                        &rows,
                        &categories,
                        &material,
                        (spectral_errors::INDEX_SOURCE, source),
                        spectral_errors::MEAN_DELTA_E2000,
                        color(source),
                    )
                })
                .collect();
            let subject = match objects.len() {
                1 => material.clone(),
                _ => {
                    format!("{material} (object {object}, {})", rows.first().map_or(String::new(), |&r| field(r, spectral_errors::OBJECT)))
                }
            };
            depth_chart(html, &categories, ErrorAxis::DeltaE, &series, &format!("{subject}: ΔE2000, three channels vs spectrum"))?;
        }
    }
    html.push_str("</div>");
    if let Some(depth) = categories.last() {
        let folder = folder_of(path);
        let stem = format!("spectral_frames/depth{}", depth.replace('+', "-"));
        let mut files = vec![(format!("{stem}_spectral.png"), "spectral".to_string())];
        for source in &sources {
            files.push((format!("{stem}_{source}.png"), source.clone()));
            files.push((format!("{stem}_{source}_delta_e.png"), format!("ΔE2000 of {source} against the spectral frame")));
        }
        let resolution = first.map_or("", |row| spectral.get(row, spectral_errors::RESOLUTION));
        let (width, height) =
            resolution.split_once('x').and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?))).unwrap_or((0, 0));
        let factor = spectral_zoom(width.max(height));
        let _ = writeln!(
            html,
            "<p class=\"note\">Depth {}: the spectral frame, each source's three-channel frame and its ΔE2000 map (EXR beside each PNG), traced at {} px and shown {factor}× (each pixel a square).</p>",
            escape(depth),
            escape(resolution),
        );
        let legend = from_report(folder, &format!("spectral_frames/{SPECTRAL_LEGEND_FILE}"));
        let _ = writeln!(
            html,
            "<div class=\"legends\"><figure class=\"colour-legend\"><img src=\"{legend}\" width=\"384\" alt=\"colour bar of the ΔE2000 maps, 0 to 5\"><figcaption>ΔE2000 maps: black at 0 through blue, red and yellow to white at 5 and beyond (fixed, so depths and scenes compare; 1 is about the smallest difference a person sees).</figcaption></figure></div><div class=\"spectral-panels\">"
        );
        for (file, label) in files {
            let src = from_report(folder, &file);
            let size = if factor > 0 { format!(" width=\"{}\" height=\"{}\"", width * factor, height * factor) } else { String::new() };
            let _ = write!(
                html,
                "<figure><a href=\"{src}\"><img class=\"spectral\" loading=\"lazy\" src=\"{src}\"{size} alt=\"{}\"></a><figcaption>{}</figcaption></figure>",
                escape(&label),
                escape(&label)
            );
        }
        html.push_str("</div>");
    }
    Ok(())
}

/// The legend of the spectral comparison's ΔE2000 maps in its folder (the effects crate's
/// `spectral_errors::DELTA_E_LEGEND_FILE`).
const SPECTRAL_LEGEND_FILE: &str = "delta_e_scale.png";
/// The least size a spectral frame is shown at, in CSS pixels on its long side.
pub const SPECTRAL_SHOWN: u32 = 384;

/// The whole factor a spectral frame of long side `long` pixels is enlarged by so that it
/// shows at least [`SPECTRAL_SHOWN`] px (1 for a frame that large already; 0 for no size).
pub fn spectral_zoom(long: u32) -> u32 {
    if long == 0 {
        0
    } else {
        SPECTRAL_SHOWN.div_ceil(long).max(1)
    }
}

fn ao_section(html: &mut String, (path, ao): (&str, &CsvTable)) -> Result<()> {
    html.push_str("<h3>Ambient occlusion</h3>\n");
    // The surfel rows (GTAO's, per pixel only, have a table of their own below).
    let all: Vec<usize> = (0..ao.rows.len()).filter(|&r| !is_gtao(ao, &ao.rows[r])).collect();
    let technique = |r: usize| technique_label(ao, &ao.rows[r]);
    let techniques: Vec<String> = distinct(&all, technique);
    let passes = integers(ao, &all, ao_errors::PASSES);
    let categories: Vec<String> = passes.iter().map(u64::to_string).collect();
    let rows_of = |t: &str, p: u64| -> Vec<usize> {
        all.iter().copied().filter(|&r| technique(r) == t && ao.raw(&ao.rows[r], ao_errors::PASSES) == p.to_string()).collect()
    };
    let mut charts_html = String::from("<div class=\"charts\">");
    let mut columns = vec![(ao_errors::MEAN_ERROR, "accessibility")];
    if all.iter().any(|&r| ao.value(&ao.rows[r], ao_errors::INDIRECT_MEAN_ERROR).is_some()) {
        columns.push((ao_errors::INDIRECT_MEAN_ERROR, "indirect light"));
    }
    let colors: Vec<_> = techniques.iter().enumerate().map(|(i, _)| PALETTE[(i + 1) % PALETTE.len()]).collect();
    let legend = charts::legend(techniques.iter().zip(&colors).map(|(t, c)| (t.as_str(), *c, false)));
    for (i, (column, what)) in columns.iter().enumerate() {
        let series: Vec<Series> = techniques
            .iter()
            .zip(&colors)
            .map(|(t, color)| {
                series(t.to_string(), *color, passes.len(), (path, ao), (*column, ao_errors::SURFELS), |x| {
                    let p = passes[x];
                    (rows_of(t, p), format!("{t}, {p} pass(es)"))
                })
            })
            .collect();
        let caption = format!("{what}: error against passes");
        chart_or_sentence(
            &mut charts_html,
            &LineChart {
                categories: &categories,
                x_name: "passes",
                y_axis: ErrorAxis::Absolute,
                series: &series,
                caption: Some(&caption),
                joined: true,
            },
            (440, 300),
            if i == 0 { &legend } else { "" },
            "",
        )?;
    }
    if ao.holds(ao_errors::CPU_MS) {
        let mut traced = Vec::new();
        let mut styles = Vec::new();
        for (t, color) in techniques.iter().zip(&colors) {
            for (i, &p) in passes.iter().enumerate() {
                let rows = rows_of(t, p);
                if !rows.is_empty() {
                    let x = Trace::mean_of(path, ao, ao_errors::CPU_MS, rows.clone(), None);
                    let y = Trace::mean_of(path, ao, ao_errors::MEAN_ERROR, rows, Some(ao_errors::SURFELS));
                    traced.push((format!("{t}, {p} pass(es)"), x, y));
                    styles.push(charts::PointStyle { color: *color, marker: charts::Marker::nth(i) });
                }
            }
        }
        let mut points = cost_points(traced);
        for (point, style) in points.iter_mut().zip(styles) {
            point.style = Some(style);
        }
        let caption = "Accessibility error against CPU time";
        if let Some(sentence) = too_little_points(caption, &points) {
            let _ = write!(charts_html, "<p class=\"no-chart\">{}</p>", escape(&sentence));
        } else {
            let chart = charts::cost_chart(&points, "CPU time of the passes (ms, whole scene)", ErrorAxis::Absolute, (600, 320))?;
            let legends = format!(
                "{}{}",
                charts::point_legend("technique", techniques.iter().zip(&colors).map(|(t, c)| (t.as_str(), *c, charts::Marker::Circle))),
                charts::point_legend(
                    "passes",
                    categories.iter().enumerate().map(|(i, p)| (p.as_str(), PALETTE[7], charts::Marker::nth(i)))
                )
            );
            figure(
                &mut charts_html,
                &chart.svg,
                &legends,
                &format!("{caption}, coloured by technique and shaped by passes; the Pareto front is joined and labelled (CPU times are ratios on this machine)."),
            );
        }
    }
    charts_html.push_str("</div>");
    html.push_str(&charts_html);
    // The statistics per technique and passes, over the scene's surfels.
    let mut table = TableText::new(&[
        "technique",
        "passes",
        "mean error (surfel-weighted)",
        "largest error",
        "reference σ (mean)",
        "emitter evaluations",
        "CPU ms",
    ]);
    for t in &techniques {
        for &p in &passes {
            let rows = rows_of(t, p);
            if rows.is_empty() {
                continue;
            }
            let mean = Trace::mean_of(path, ao, ao_errors::MEAN_ERROR, rows.clone(), Some(ao_errors::SURFELS)).value;
            let sigma = Trace::mean_of(path, ao, ao_errors::REFERENCE_STANDARD_ERROR, rows.clone(), Some(ao_errors::SURFELS)).value;
            let max = rows.iter().filter_map(|&r| ao.value(&ao.rows[r], ao_errors::MAX_ERROR)).fold(f64::NEG_INFINITY, f64::max);
            let first = &ao.rows[rows[0]];
            table.row(vec![
                t.to_string(),
                p.to_string(),
                number(mean),
                number(max),
                number(sigma),
                ao.raw(first, ao_errors::INTERACTIONS).to_string(),
                ao.value(first, ao_errors::CPU_MS).map(number).unwrap_or_else(|| "–".into()),
            ]);
        }
    }
    html.push_str(&table.html("ao-summary"));
    if let Some(screen) = ao_per_pixel_table(ao) {
        html.push_str(
            "<p>Surfel AO beside screen-space GTAO (Jimenez et al. 2016) on the same frame: e = accessibility − reference per covered pixel (surfel values and the reference interpolated from the vertices; GTAO per pixel from the G-buffer), with each row's cost (emitter evaluations or G-buffer reads, and CPU time over the scene or the frame).</p>",
        );
        html.push_str(&screen);
    }
    if let Some(statistics) = ao_statistics_table(ao) {
        html.push_str(
            "<p>Per object, e = accessibility − reference (positive: too light, the surfels under-occlude): |e| per vertex (mean, median, p90, p99, max), its signed mean, the area-weighted and the per-pixel mean (what the surface holds and what the camera sees), and the vertices of flipped or degenerate triangles with the mean without them.</p>",
        );
        html.push_str(&statistics);
    }
    Ok(())
}

/// Whether a row of `ao_errors.csv` is GTAO's (a table written before GTAO has none).
fn is_gtao(ao: &CsvTable, row: &[String]) -> bool {
    ao.holds(ao_errors::TECHNIQUE) && ao.get(row, ao_errors::TECHNIQUE) == "gtao"
}

/// How a row of `ao_errors.csv` was computed, in words: `tree`, `brute force`, or GTAO
/// with its preset (where the table names it), radius, slices and steps, and the frames it
/// accumulates where more than one.
fn technique_label(ao: &CsvTable, row: &[String]) -> String {
    if is_gtao(ao, row) {
        let preset = ao.holds(ao_errors::GTAO_PRESET).then(|| ao.get(row, ao_errors::GTAO_PRESET));
        let frames = ao.value(row, ao_errors::GTAO_FRAMES).map_or(1, |frames| frames as u64);
        super::ao_cost::gtao_label(
            preset,
            ao.raw(row, ao_errors::GTAO_RADIUS),
            ao.raw(row, ao_errors::GTAO_SLICES),
            ao.raw(row, ao_errors::GTAO_STEPS),
            frames,
        )
    } else if ao.raw(row, ao_errors::HIERARCHY) == "true" {
        "tree".into()
    } else {
        "brute force".into()
    }
}

/// A column of an AO table as the page shows it.
#[derive(Clone, Copy)]
enum AoCell {
    /// A count, as written.
    Count(Column<Integer>),
    /// A number in the report's format ("–" where empty).
    Number(Column<OptionalFloat>),
}

/// A row of an AO table: the object, the technique in words, the passes ("–" for GTAO),
/// then `columns`.
fn ao_row_cells(ao: &CsvTable, row: &[String], columns: &[AoCell]) -> Vec<String> {
    let passes = if is_gtao(ao, row) { "–".to_string() } else { ao.raw(row, ao_errors::PASSES).to_string() };
    let mut cells = vec![ao.get(row, ao_errors::MESH).to_string(), technique_label(ao, row), passes];
    cells.extend(columns.iter().map(|&c| match c {
        AoCell::Count(column) => ao.raw(row, column).to_string(),
        AoCell::Number(column) => ao.value(row, column).map(number).unwrap_or_else(|| "–".into()),
    }));
    cells
}

/// Every row's per-pixel figures side by side (surfels and GTAO), `None` where the table
/// has no GTAO row.
fn ao_per_pixel_table(ao: &CsvTable) -> Option<String> {
    if !ao.rows.iter().any(|r| is_gtao(ao, r)) {
        return None;
    }
    let columns = [
        AoCell::Count(ao_errors::PIXELS),
        AoCell::Number(ao_errors::PIXEL_MEAN_ERROR),
        AoCell::Number(ao_errors::PIXEL_SIGNED_ERROR),
        AoCell::Number(ao_errors::PIXEL_MEDIAN_ERROR),
        AoCell::Number(ao_errors::PIXEL_P90_ERROR),
        AoCell::Number(ao_errors::PIXEL_P99_ERROR),
        AoCell::Number(ao_errors::PIXEL_MAX_ERROR),
        AoCell::Count(ao_errors::INTERACTIONS),
        AoCell::Number(ao_errors::CPU_MS.numbers()),
    ];
    let mut table = TableText::new(&[
        "object",
        "technique",
        "passes",
        "pixels",
        "mean |e|",
        "signed e",
        "median |e|",
        "p90",
        "p99",
        "max",
        "evaluations or reads",
        "CPU ms",
    ]);
    for row in &ao.rows {
        table.row(ao_row_cells(ao, row, &columns));
    }
    Some(table.html("ao-per-pixel"))
}

/// The per-object error statistics of `ao_errors.csv` (one row per object, technique and
/// passes), `None` for a table written before it had them.
fn ao_statistics_table(ao: &CsvTable) -> Option<String> {
    if !ao.holds(ao_errors::P90_ERROR) {
        return None;
    }
    let columns = [
        AoCell::Number(ao_errors::MEAN_ERROR),
        AoCell::Number(ao_errors::SIGNED_ERROR),
        AoCell::Number(ao_errors::MEDIAN_ERROR),
        AoCell::Number(ao_errors::P90_ERROR),
        AoCell::Number(ao_errors::P99_ERROR),
        AoCell::Number(ao_errors::MAX_ERROR),
        AoCell::Number(ao_errors::AREA_MEAN_ERROR),
        AoCell::Number(ao_errors::PIXEL_MEAN_ERROR),
        AoCell::Count(ao_errors::DEFECT_VERTICES),
        AoCell::Number(ao_errors::MEAN_ERROR_WITHOUT_DEFECTS),
    ];
    let mut table = TableText::new(&[
        "object",
        "technique",
        "passes",
        "mean |e|",
        "signed e",
        "median |e|",
        "p90",
        "p99",
        "max",
        "area-weighted",
        "per pixel",
        "defect vertices",
        "mean without them",
    ]);
    for row in ao.rows.iter().filter(|r| !is_gtao(ao, r)) {
        table.row(ao_row_cells(ao, row, &columns));
    }
    Some(table.html("ao-statistics"))
}

/// The hero frame: one figure per panel, its label and the figures of `effects_hero.csv`
/// over a grid of pictures at their natural size (two 512-px columns where the page is wide
/// enough, one where not): the frame, then its error against the exact method's panel
/// beside its error against the reference; each kind of error image under its legend (the
/// colour bar with its values, the scale and the rule that chose it); then the crops where
/// the error is largest, labelled in words.
fn hero_section(html: &mut String, (path, hero): (&str, &CsvTable)) {
    let folder = folder_of(path);
    let effects: Vec<String> =
        distinct(&(0..hero.rows.len()).collect::<Vec<_>>(), |r| hero.get(&hero.rows[r], effects_hero::EFFECT).to_string());
    for effect in effects {
        let rows: Vec<(usize, &Vec<String>)> =
            hero.rows.iter().enumerate().filter(|(_, r)| hero.get(r, effects_hero::EFFECT) == effect).collect();
        let Some((_, first)) = rows.first() else { continue };
        let has_exact = rows.iter().any(|(_, r)| !hero.get(r, effects_hero::EXACT_ERROR_FILE).is_empty());
        let _ = writeln!(
            html,
            "<h3>Hero frame: {} ({})</h3>\n<p class=\"note\">Frame 0 at {} with every variant{} (<code>{}</code>). Pictures at their natural size; click one for the file.</p>",
            escape(&effect),
            escape(hero.get(first, effects_hero::RESOLUTION)),
            escape(hero.get(first, effects_hero::RESOLUTION)),
            if has_exact {
                ", each beside its error against the exact method's panel (what the Fresnel method itself costs, through the same distance maps) and against the ray-traced reference (the total, the maps' search included)"
            } else {
                ", each beside its error against the reference"
            },
            escape(path)
        );
        hero_legends(html, (path, hero), &rows);
        html.push_str("<div class=\"panels hero-panels\">");
        for (index, row) in &rows {
            let image = |column: Column<Text>, what: &str| -> String {
                let file = hero.get(row, column);
                if file.is_empty() {
                    return String::new();
                }
                let src = from_report(folder, file);
                let (w, h) = hero.get(row, effects_hero::RESOLUTION).split_once('x').unwrap_or(("", ""));
                format!(
                    "<div class=\"hero-cell\"><a href=\"{src}\"><img class=\"hero\" loading=\"lazy\" src=\"{src}\" width=\"{}\" height=\"{}\" alt=\"{}\"></a><p class=\"cell-note\">{}</p></div>",
                    escape(w),
                    escape(h),
                    escape(&format!("{}: {what}", hero.get(row, effects_hero::LABEL))),
                    escape(what)
                )
            };
            let span = |column: &str, text: String| {
                format!(
                    "<span class=\"figure\" data-table=\"{}\" data-row=\"{index}\" data-column=\"{column}\">{text}</span>",
                    escape(path)
                )
            };
            let figure = |column: Column<OptionalFloat>, shown: fn(f64) -> String| {
                span(column.name, shown(hero.value(row, column).unwrap_or(f64::NAN)))
            };
            let mut figures = if hero.get(row, effects_hero::ERROR_FILE).is_empty() {
                "the reference the others are measured against".to_string()
            } else {
                format!(
                    "against the reference: mean ΔE2000 {}, mean relative error {}, mean |Δ| {}, largest |Δ| {} over {} pixels",
                    figure(effects_hero::MEAN_DELTA_E2000.numbers(), delta_e),
                    figure(effects_hero::MEAN_REL_ERROR.numbers(), percent),
                    figure(effects_hero::MEAN_ABS_ERROR.numbers(), number),
                    figure(effects_hero::MAX_ABS_ERROR.numbers(), number),
                    span(effects_hero::PIXELS.name, hero.raw(row, effects_hero::PIXELS).to_string()),
                )
            };
            if !hero.get(row, effects_hero::EXACT_ERROR_FILE).is_empty() {
                let _ = write!(
                    figures,
                    "; against the exact method: mean ΔE2000 {}, mean |Δ| {}, largest |Δ| {}",
                    figure(effects_hero::EXACT_MEAN_DELTA_E2000.numbers(), delta_e),
                    figure(effects_hero::EXACT_MEAN_ABS_ERROR.numbers(), number),
                    figure(effects_hero::EXACT_MAX_ABS_ERROR.numbers(), number),
                );
            }
            let _ = write!(
                html,
                "<figure class=\"panel\" data-panel=\"{}\"><figcaption><b>{}</b><br>{figures}</figcaption><div class=\"hero-grid\">{}{}{}</div></figure>",
                escape(hero.get(row, effects_hero::PANEL)),
                escape(hero.get(row, effects_hero::LABEL)),
                image(effects_hero::FILE, "the frame"),
                image(effects_hero::EXACT_ERROR_FILE, "error against the exact method"),
                image(effects_hero::ERROR_FILE, "error against the reference"),
            );
        }
        html.push_str("</div>\n");
        let (x, y, size) =
            (hero.raw(first, effects_hero::CROP_X), hero.raw(first, effects_hero::CROP_Y), hero.raw(first, effects_hero::CROP_SIZE));
        let _ = write!(
            html,
            "<p class=\"note\">Where the error is largest: the {size} × {size} px window at ({x}, {y}) with the largest summed error over the variants, enlarged.</p><div class=\"crops\">",
            size = escape(size),
            x = escape(x),
            y = escape(y)
        );
        for (_, row) in &rows {
            for (column, what) in [
                (effects_hero::CROP_FILE, ""),
                (effects_hero::CROP_EXACT_ERROR_FILE, ", error against exact"),
                (effects_hero::CROP_ERROR_FILE, ", error against the reference"),
            ] {
                let file = hero.get(row, column);
                if file.is_empty() {
                    continue;
                }
                let src = from_report(folder, file);
                let _ = write!(
                    html,
                    "<figure><img loading=\"lazy\" src=\"{src}\" alt=\"{0}{what} (crop)\"><figcaption>{0}{what}</figcaption></figure>",
                    escape(&crop_words(hero, row))
                );
            }
        }
        html.push_str("</div>\n");
    }
}

/// What a crop shows, in words: the panel's label up to its first comma (`schlick`, `no AO`,
/// `surfel AO`, `reference: ray-traced`), with the passes and gather of an AO panel.
fn crop_words(hero: &CsvTable, row: &[String]) -> String {
    let label = hero.get(row, effects_hero::LABEL);
    let mut parts = label.split(", ");
    let head = parts.next().unwrap_or(label);
    match hero.raw(row, effects_hero::PASSES) {
        "" | "0" => head.to_string(),
        _ => std::iter::once(head).chain(parts.take(2)).collect::<Vec<_>>().join(", "),
    }
}

/// A 1-2-5 step as the legends print it: the shortest decimal that reads back as it
/// (`0.05`, `2`), as burned into the legend picture.
pub fn step_text(step: f64) -> String {
    if step.is_finite() {
        format!("{step}")
    } else {
        "–".into()
    }
}

/// The legends of a hero frame's error images: per kind (against exact, against the
/// reference) its colour bar with the values burned in and what chose the scale.
fn hero_legends(html: &mut String, (path, hero): (&str, &CsvTable), rows: &[(usize, &Vec<String>)]) {
    let folder = folder_of(path);
    let Some((_, first)) = rows.iter().find(|(_, r)| !hero.get(r, effects_hero::ERROR_FILE).is_empty()) else { return };
    let rule = "the smallest 1-2-5 step at or above the 99th percentile of the values over every panel's counted pixels, so at most about one pixel in a hundred is white";
    html.push_str("<div class=\"legends\">");
    let exact = rows.iter().find(|(_, r)| !hero.get(r, effects_hero::EXACT_ERROR_SCALE_FILE).is_empty());
    if let Some((_, row)) = exact {
        let _ = write!(
            html,
            "<figure class=\"colour-legend\" data-scale=\"{0}\"><img src=\"{1}\" width=\"512\" alt=\"colour bar of the errors against exact, 0 to {0}\"><figcaption>Error against the exact method: |Δ| summed over R, G and B of linear radiance, black at 0 through blue, red and yellow to white at {0} ({rule}).</figcaption></figure>",
            step_text(hero.value(row, effects_hero::EXACT_ERROR_SCALE).unwrap_or(f64::NAN)),
            from_report(folder, hero.get(row, effects_hero::EXACT_ERROR_SCALE_FILE)),
        );
    }
    let scale = hero.value(first, effects_hero::ERROR_SCALE).unwrap_or(f64::NAN);
    let file = hero.get(first, effects_hero::ERROR_SCALE_FILE);
    if !file.is_empty() {
        let _ = write!(
            html,
            "<figure class=\"colour-legend\" data-scale=\"{0}\"><img src=\"{1}\" width=\"512\" alt=\"colour bar of the errors against the reference, 0 to {0}\"><figcaption>Error against the reference: |Δ| summed over R, G and B of linear radiance, black at 0 through blue, red and yellow to white at {0} ({rule}).</figcaption></figure>",
            step_text(scale),
            from_report(folder, file),
        );
    }
    html.push_str("</div>\n");
}

/// The cross-device table: per method, the median over materials of its pass time
/// relative to `exact` on each device of `<out>/devices/` (the study's Tables 6–7).
fn devices_section(html: &mut String, inputs: &Inputs) {
    html.push_str("<section><h2 id=\"devices\">Across devices</h2>\n");
    if inputs.devices.is_empty() {
        let _ = writeln!(
            html,
            "<p class=\"absent\">No device results: <code>{DEVICES_DIR}/&lt;adapter&gt;/gpu_timing.csv</code> is absent (`make report` copies those committed under <code>benchmarks/{DEVICES_DIR}/</code>; `make gpu` measures this machine's).</p></section>"
        );
        return;
    }
    let mut methods: Vec<String> = Vec::new();
    let mut ratios: BTreeMap<(String, String), f64> = BTreeMap::new();
    let mut adapters = Vec::new();
    for (device, tables) in &inputs.devices {
        let table = &tables.timing;
        let Some(exact) = tables.median_ms("exact") else { continue };
        for method in table.distinct(gpu_timing::METHOD.name) {
            if !methods.iter().any(|m| m == method) {
                methods.push(method.to_string());
            }
        }
        for method in &methods {
            if let Some(ms) = tables.median_ms(method) {
                ratios.insert((method.clone(), device.clone()), ms / exact);
            }
        }
        let adapter = table
            .rows
            .first()
            .map(|r| format!("{} ({} timer)", table.get(r, gpu_timing::ADAPTER), table.get(r, gpu_timing::TIMER)))
            .unwrap_or_default();
        adapters.push(format!("{device}: {adapter}"));
    }
    let devices: Vec<&String> = inputs.devices.keys().collect();
    let headers: Vec<String> = std::iter::once("method".to_string()).chain(devices.iter().map(|d| format!("{d} (× exact)"))).collect();
    let mut table = TableText::new(&headers.iter().map(String::as_str).collect::<Vec<_>>());
    for method in &methods {
        table.row(
            std::iter::once(method.clone())
                .chain(
                    devices.iter().map(|d| ratios.get(&(method.clone(), (*d).clone())).map(|r| number(*r)).unwrap_or_else(|| "–".into())),
                )
                .collect(),
        );
    }
    let software = |a: &String| ["llvmpipe", "lavapipe", "swiftshader"].iter().any(|s| a.to_lowercase().contains(s));
    let caveat = if adapters.iter().all(software) {
        " Every device here is a CPU rasteriser: these are ratios between methods, not what a method costs on a GPU; no GPU has been measured yet."
    } else {
        ""
    };
    let _ = writeln!(
        html,
        "<p>Median pass time over materials relative to exact Fresnel on the same device ({}).{caveat}</p>{}",
        escape(&adapters.join("; ")),
        table.html("devices")
    );
    device_methods(html, inputs);
    image_errors_across(html, inputs);
    effects_across(html, &inputs.devices);
    study_form(html, inputs);
    html.push_str("</section>\n");
}

/// Per device and method: the median pass time over its materials, its ratio to exact's and
/// to the bare texture fetch's (the `texture` baseline: what a pass costs that only reads a
/// texel) on the same device, and the mean image error against exact; with where the result
/// came from (native tables or a browser's result file). One row per device and method.
fn device_methods(html: &mut String, inputs: &Inputs) {
    let headers = ["device", "source", "timer", "method", "median ms", "× exact", "× texture fetch", "image error"];
    let mut table = TableText::new(&headers);
    for (device, tables) in &inputs.devices {
        let timing = &tables.timing;
        let (exact, fetch) = (tables.median_ms("exact"), tables.median_ms("texture"));
        let timer = timing.rows.first().map(|r| timing.get(r, gpu_timing::TIMER).to_string()).unwrap_or_default();
        for method in timing.distinct(gpu_timing::METHOD.name) {
            let Some(ms) = tables.median_ms(method) else { continue };
            let ratio = |anchor: Option<f64>| anchor.filter(|a| *a > 0.0).map_or("–".to_string(), |a| number(ms / a));
            let error = tables.mean_image_error(method);
            table.row(vec![
                device.clone(),
                tables.source.clone(),
                timer.clone(),
                method.to_string(),
                format!("{ms:.4}"),
                ratio(exact),
                ratio(fetch),
                error.map_or("–".to_string(), percent),
            ]);
        }
    }
    let _ = writeln!(
        html,
        "<h3>Per device and method</h3><p>Median pass time over the materials each device timed, relative to exact and to the bare texture fetch (<code>texture</code>) on the same device, and the mean image error against exact; – where the device measured no anchor. Browser results come from <code>nklut gpu web</code>'s page.</p>{}",
        table.html("device-methods")
    );
}

/// Each method's image error against exact per device (`image_errors.csv`: the mean over its
/// rows of `mean_rel_error`), one column per device that has the table.
fn image_errors_across(html: &mut String, inputs: &Inputs) {
    let with_errors: Vec<(&String, &DeviceTables)> = inputs.devices.iter().filter(|(_, tables)| tables.image_errors.is_some()).collect();
    if with_errors.is_empty() {
        return;
    }
    let mut methods: Vec<&str> = Vec::new();
    for errors in with_errors.iter().filter_map(|(_, tables)| tables.image_errors.as_ref()) {
        for method in errors.distinct(image_errors::METHOD.name) {
            if !methods.contains(&method) {
                methods.push(method);
            }
        }
    }
    let headers: Vec<String> =
        std::iter::once("method".to_string()).chain(with_errors.iter().map(|(d, _)| format!("{d}: mean relative error"))).collect();
    let mut table = TableText::new(&headers.iter().map(String::as_str).collect::<Vec<_>>());
    for method in methods {
        let cells = with_errors.iter().map(|(_, tables)| tables.mean_image_error(method).map_or("–".to_string(), percent));
        table.row(std::iter::once(method.to_string()).chain(cells).collect());
    }
    let _ = writeln!(
        html,
        "<p>Image error of each method against exact on the same device, the mean over its materials and objects (<code>image_errors.csv</code>).</p>{}",
        table.html("device-errors")
    );
}

/// The reflection/refraction timing of each device that measured it (`effects_timing`,
/// native or from the browser bench's page): one row per device and configuration, its map
/// update and shading pass times and the shading pass relative to `exact`'s in the same
/// configuration (effect, depths, search steps, resolution) on the same device.
fn effects_across(html: &mut String, devices: &BTreeMap<String, DeviceTables>) {
    let with_effects: Vec<(&String, &DeviceTables, &CsvTable)> =
        devices.iter().filter_map(|(device, tables)| Some((device, tables, tables.effects_timing.as_ref()?))).collect();
    if with_effects.is_empty() {
        return;
    }
    // Seven columns that fit a 1000-px window: source and timer in one cell, the
    // configuration (effect, depths, search steps, resolution) in one.
    let headers = [
        "device",
        "source, timer",
        "method",
        "effect · depths refl./refr. · steps lin./sec. · size",
        "map update ms",
        "shading ms",
        "shading × exact",
    ];
    let mut table = TableText::new(&headers);
    for (device, tables, rows) in with_effects {
        let configuration = |r: &[String]| -> Vec<String> {
            [
                effects_timing::EFFECT.name,
                effects_timing::REFLECTION_DEPTH.name,
                effects_timing::REFRACTION_DEPTH.name,
                effects_timing::LINEAR_STEPS.name,
                effects_timing::SECANT_STEPS.name,
                effects_timing::RESOLUTION.name,
            ]
            .iter()
            .map(|c| rows.text(r, c).to_string())
            .collect()
        };
        for row in &rows.rows {
            let shading = rows.value(row, effects_timing::SHADING_MS);
            let exact = rows
                .rows
                .iter()
                .find(|r| rows.get(r, effects_timing::METHOD) == "exact" && configuration(r) == configuration(row))
                .and_then(|r| rows.value(r, effects_timing::SHADING_MS));
            let ratio = match (shading, exact) {
                (Some(ms), Some(anchor)) if anchor > 0.0 => number(ms / anchor),
                _ => "–".to_string(),
            };
            let ms = |column: Column<Float>| rows.value(row, column).map_or("–".to_string(), |x| format!("{x:.4}"));
            table.row(vec![
                device.clone(),
                format!("{}, {}", tables.source, rows.get(row, effects_timing::TIMER)),
                rows.get(row, effects_timing::METHOD).to_string(),
                effects_configuration(
                    rows.get(row, effects_timing::EFFECT),
                    [rows.raw(row, effects_timing::REFLECTION_DEPTH), rows.raw(row, effects_timing::REFRACTION_DEPTH)],
                    [rows.raw(row, effects_timing::LINEAR_STEPS), rows.raw(row, effects_timing::SECANT_STEPS)],
                    rows.get(row, effects_timing::RESOLUTION),
                ),
                ms(effects_timing::MAP_UPDATE_MS),
                ms(effects_timing::SHADING_MS),
                ratio,
            ]);
        }
    }
    let _ = writeln!(
        html,
        "<h3>Reflections and refractions</h3><p>Per device and configuration (<code>effects_timing</code>, native or from the browser bench's page): the median time of one update of every distance map and of the shading pass, and the shading pass relative to <code>exact</code>'s in the same configuration on the same device. One row per device and configuration, never averaged.</p>{}",
        table.html("device-effects")
    );
}

/// One effects configuration in a cell: `reflection · 1/0 · 15/1 · 320x180`.
pub fn effects_configuration(effect: &str, [reflection, refraction]: [&str; 2], [linear, secant]: [&str; 2], resolution: &str) -> String {
    format!("{effect} · {reflection}/{refraction} · {linear}/{secant} · {resolution}")
}

/// The study's Table 6: render time of each method relative to the exact dielectric formula
/// on the same device (Unity, a full-screen quad of Fresnel reflection, 2014 devices), in
/// the order of [`STUDY_COLUMNS`].
const STUDY_TABLE_6: [(&str, &str, [f64; 7]); 5] = [
    ("Lenovo W530", "Intel HD4000", [1.00, 0.54, 1.43, 0.59, 0.70, 0.50, 0.56]),
    ("Samsung Galaxy S3", "Mali 400", [1.00, 0.42, 2.89, 0.62, 0.62, 0.36, 0.47]),
    ("Apple iPhone 5s", "PowerVR G6430", [1.00, 0.60, 1.57, 0.75, 0.84, 0.43, 0.60]),
    ("Google Nexus 4", "Adreno 320", [1.00, 0.32, 1.41, 0.61, 0.80, 0.27, 0.37]),
    ("Samsung Galaxy S5", "Adreno 330", [1.00, 0.33, 1.31, 0.61, 0.75, 0.27, 0.38]),
];

/// The study's columns: a heading, our method and the kind of material it was timed on
/// (`None`: every material).
const STUDY_COLUMNS: [(&str, &str, Option<&str>); 7] = [
    ("exact, dielectric", "exact", Some("dielectric")),
    ("Schlick, dielectric", "schlick", Some("dielectric")),
    ("exact, conductor", "exact", Some("conductor")),
    ("Schlick, conductor", "schlick", Some("conductor")),
    ("compensated Schlick", "schlick_compensated", None),
    ("LUT", "lut", None),
    ("NVIDIA fit", "nvidia", None),
];

/// One device's timing rows as the study-form table reads them.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyRow {
    pub material: String,
    /// `dielectric` or `conductor` (`materials.csv`'s `kind`).
    pub kind: String,
    pub method: String,
    pub median_ms: f64,
    pub spread_ms: f64,
    /// Samples behind the median.
    pub n: u64,
}

/// One cell of the study-form table: the ratio, the samples behind its numerator and the
/// numerator's median interquartile range in the ratio's units.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyCell {
    pub ratio: f64,
    pub n: u64,
    pub iqr: f64,
    /// Materials on each side.
    pub materials: usize,
}

/// A study-form cell for `method` on materials of `kind` (`None`: any), against the
/// study's anchor, exact on dielectric materials (timed by the dielectric formula):
/// - a dielectric or any-kind column: the method and the anchor over the same materials —
///   the dielectric ones the method was timed on (the anchor exists only on those);
/// - a conductor column: the method over the conductors, the anchor over every dielectric
///   material timed (the study's definition; the two sides cannot share materials).
///
/// Medians over materials of each row's median; `n` the samples summed, `iqr` the median of
/// the rows' interquartile ranges over the anchor.
pub fn study_cell(rows: &[StudyRow], method: &str, kind: Option<&str>) -> Option<StudyCell> {
    let anchor_of = |material: &str| rows.iter().find(|r| r.method == "exact" && r.kind == "dielectric" && r.material == material);
    let measured: Vec<&StudyRow> = rows.iter().filter(|r| r.method == method && kind.is_none_or(|k| r.kind == k)).collect();
    let (numerator, anchors): (Vec<&StudyRow>, Vec<&StudyRow>) = if kind == Some("conductor") {
        (measured, rows.iter().filter(|r| r.method == "exact" && r.kind == "dielectric").collect())
    } else {
        measured.into_iter().filter_map(|r| Some((r, anchor_of(&r.material)?))).unzip()
    };
    let medians = |rows: &[&StudyRow], f: &dyn Fn(&StudyRow) -> f64| median(&rows.iter().map(|r| f(r)).collect::<Vec<_>>());
    let anchor = medians(&anchors, &|r| r.median_ms).filter(|a| *a > 0.0)?;
    let top = medians(&numerator, &|r| r.median_ms)?;
    Some(StudyCell {
        ratio: top / anchor,
        n: numerator.iter().map(|r| r.n).sum(),
        iqr: medians(&numerator, &|r| r.spread_ms).unwrap_or(0.0) / anchor,
        materials: numerator.len(),
    })
}

/// The study's form: one row per device, the study's own five first, then each of ours
/// ([`study_cell`] per column), each cell with its samples and spread, each device row with
/// the formula its anchors were timed by. Never averaged across devices.
fn study_form(html: &mut String, inputs: &Inputs) {
    let headers: Vec<&str> =
        ["device", "GPU", "source", "anchors: dielectric / conductor"].into_iter().chain(STUDY_COLUMNS.iter().map(|c| c.0)).collect();
    let mut table = TableText::new(&headers);
    for (device, gpu, ratios) in STUDY_TABLE_6 {
        let cells = ratios.iter().map(|r| format!("{r:.2}"));
        table.row(
            [device, gpu, "the study, Table 6", "dielectric formula / complex formula"]
                .into_iter()
                .map(String::from)
                .chain(cells)
                .collect(),
        );
    }
    let materials = super::context::ByPage::new(&inputs.materials);
    for (device, tables) in &inputs.devices {
        let timing = &tables.timing;
        let rows: Vec<StudyRow> = timing
            .rows
            .iter()
            .filter_map(|r| {
                let material = timing.get(r, gpu_timing::MATERIAL);
                Some(StudyRow {
                    material: material.to_string(),
                    kind: inputs.materials.text(materials.first(material)?, "kind").to_string(),
                    method: timing.get(r, gpu_timing::METHOD).to_string(),
                    median_ms: timing.value(r, gpu_timing::MEDIAN_MS)?,
                    spread_ms: timing.value(r, gpu_timing::SPREAD_MS).unwrap_or(0.0),
                    n: timing.value(r, gpu_timing::REPEATS).unwrap_or(0.0) as u64,
                })
            })
            .collect();
        // Results written before the anchors were split timed exact by the complex formula
        // on every material.
        let formula = |kind: &str| {
            timing
                .rows
                .iter()
                .find(|r| {
                    timing.get(r, gpu_timing::METHOD) == "exact"
                        && rows.iter().any(|x| x.material == timing.get(r, gpu_timing::MATERIAL) && x.kind == kind)
                })
                .map(|r| {
                    if timing.holds(gpu_timing::FORMULA) {
                        timing.get(r, gpu_timing::FORMULA).to_string()
                    } else {
                        "complex (older result)".to_string()
                    }
                })
                .unwrap_or_else(|| "–".to_string())
        };
        let cells = STUDY_COLUMNS.iter().map(|(_, method, kind)| match study_cell(&rows, method, *kind) {
            Some(c) => format!("{:.2} (IQR {:.2}, n {})", c.ratio, c.iqr, c.n),
            None => "–".to_string(),
        });
        let adapter = timing.rows.first().map(|r| timing.get(r, gpu_timing::ADAPTER).to_string()).unwrap_or_default();
        let anchors = format!("{} / {}", formula("dielectric"), formula("conductor"));
        table.row([device.clone(), adapter, "measured here".to_string(), anchors].into_iter().chain(cells).collect());
    }
    let _ = writeln!(
        html,
        "<h3>In the study's form</h3><p>Time relative to exact Fresnel on a dielectric material, on the same device: the study's five devices (its Table 6: Unity, a full-screen quad, 2014 devices) and each device measured here. The anchors, as the study's: exact on a dielectric by the dielectric formula (k = 0: F = ½((g−c)/(g+c))²(1 + ((c(g+c)−1)/(c(g−c)+1))²), g² = n² − 1 + c²) and on a conductor by the complex formula (SPEC §5.1); a result whose anchors say “older result” timed the complex formula on both, which makes the dielectric anchor costlier and every ratio smaller. A dielectric or any-kind column divides the method by the anchor over the same materials (the dielectric ones the method was timed on); a conductor column divides the conductors' median by the dielectric anchor (the study's definition). Each cell: the ratio of medians over materials, the median interquartile range over the anchor, and n, the samples behind it. Caveats: a CPU rasteriser's ratios are not a GPU's; a row whose timing reports medians within 10 × the timer's resolution is not resolved; the study measured frame times in Unity on 2014 devices. – where the device timed none. One row per device, never averaged.</p>{}",
        table.html("study-form")
    );
}

#[cfg(test)]
mod study_form_tests {
    use super::*;

    fn row(material: &str, kind: &str, method: &str, median_ms: f64, spread_ms: f64) -> StudyRow {
        StudyRow { material: material.into(), kind: kind.into(), method: method.into(), median_ms, spread_ms, n: 10 }
    }

    /// Water and glass (dielectric), gold (conductor); compensated Schlick timed on water
    /// and gold only. Hand-computed: dielectric anchor over water and glass = median(2, 4) = 3.
    /// 96 px frames shown at 4 × 96 = 384, 100 px at 4 × 100 = 400 (3 × 100 falls short),
    /// 128 at 3 × 128 = 384; a frame of 384 or more at its size.
    #[test]
    fn spectral_frames_show_at_384_px_or_more_in_whole_steps() {
        assert_eq!([96, 100, 128, 384, 500, 1, 0].map(spectral_zoom), [4, 4, 3, 1, 1, 384, 0]);
    }

    #[test]
    fn crops_are_named_in_words() {
        let hero = CsvTable::parse(
            b"label,passes\n\"schlick, 3 reflection(s), 1 refraction(s), 30+4 search steps\",\nno AO,0\n\"surfel AO, 2 pass(es), tree, mean 0.03\",2\n",
        )
        .unwrap();
        let words: Vec<String> = hero.rows.iter().map(|r| crop_words(&hero, r)).collect();
        assert_eq!(words, ["schlick", "no AO", "surfel AO, 2 pass(es), tree"]);
    }

    #[test]
    fn every_ratio_divides_by_the_anchor_over_the_same_materials() {
        let rows = [
            row("w", "dielectric", "exact", 2.0, 0.2),
            row("g", "dielectric", "exact", 4.0, 0.4),
            row("au", "conductor", "exact", 9.0, 0.9),
            row("w", "dielectric", "schlick", 1.0, 0.1),
            row("g", "dielectric", "schlick", 1.0, 0.3),
            row("au", "conductor", "schlick", 1.5, 0.3),
            row("w", "dielectric", "schlick_compensated", 1.2, 0.1),
            row("au", "conductor", "schlick_compensated", 3.0, 0.1),
        ];
        let cell = |method, kind| study_cell(&rows, method, kind).unwrap();
        let anchor = cell("exact", Some("dielectric"));
        assert_eq!((anchor.ratio, anchor.n, anchor.materials), (1.0, 20, 2));
        assert!((anchor.iqr - 0.1).abs() < 1e-12, "median IQR 0.3 over 3: {}", anchor.iqr);
        assert_eq!(cell("schlick", Some("dielectric")).ratio, 1.0 / 3.0);
        // Conductors against the dielectric anchor (3): 9 / 3 and 1.5 / 3.
        assert_eq!(cell("exact", Some("conductor")), StudyCell { ratio: 3.0, n: 10, iqr: 0.3, materials: 1 });
        assert_eq!(cell("schlick", Some("conductor")).ratio, 0.5);
        // Timed on water (and gold): over water on both sides, 1.2 / 2, not 1.2 / 3.
        assert_eq!(cell("schlick_compensated", None), StudyCell { ratio: 0.6, n: 10, iqr: 0.05, materials: 1 });
        assert_eq!(study_cell(&rows, "lut", None), None);
        assert_eq!(study_cell(&rows[2..3], "exact", Some("conductor")), None, "no dielectric anchor");
    }
}

#[cfg(test)]
mod device_effects_tests {
    use super::*;

    /// One row per device and configuration with its times; the shading ratio against
    /// exact's in the same configuration on the same device (hand-computed: 3.0 / 2.0 = 1.50,
    /// 0.5 / 0.25 = 2.00), – where that configuration has no exact row; a device without
    /// the table adds no row, and without any such device there is no table.
    #[test]
    fn effects_rows_per_device_and_configuration_with_the_ratio_to_exact() {
        let columns = "adapter,backend,timer,method,effect,reflection_depth,refraction_depth,linear_steps,secant_steps,map_size,layers,cube_maps,resolution,repeats,map_update_ms,shading_ms,shading_spread_ms,frame_ms";
        let native = format!(
            "{columns}\nllvmpipe,Vulkan,timestamp,exact,reflection,1,0,15,1,128,3,3,64x64,3,4.0,2.0,0.1,6.0\n\
             llvmpipe,Vulkan,timestamp,lut,reflection,1,0,15,1,128,3,3,64x64,3,4.0,3.0,0.1,7.0\n\
             llvmpipe,Vulkan,timestamp,lut,reflection,2,0,15,1,128,3,3,64x64,3,4.0,5.0,0.1,9.0\n"
        );
        let browser = format!(
            "{columns}\nswiftshader,WebGPU,timestamp,exact,refraction,1,1,8,1,16,3,2,48x48,3,1.5,0.25,0.01,1.75\n\
             swiftshader,WebGPU,timestamp,schlick,refraction,1,1,8,1,16,3,2,48x48,3,1.5,0.5,0.01,2.0\n"
        );
        let device = |csv: &str, source: &str| DeviceTables {
            timing: CsvTable::parse(b"method,median_ms\n").unwrap(),
            image_errors: None,
            effects_timing: Some(CsvTable::parse(csv.as_bytes()).unwrap()),
            ao_timing: None,
            source: source.into(),
        };
        let mut devices = BTreeMap::new();
        devices.insert("lavapipe".to_string(), device(&native, "native"));
        devices.insert("swiftshader".to_string(), device(&browser, "browser: HeadlessChrome/156"));
        devices.insert("other".to_string(), DeviceTables { effects_timing: None, ..device(&native, "native") });
        let mut html = String::new();
        effects_across(&mut html, &devices);
        let rows: Vec<Vec<String>> = html
            .split("<tr>")
            .skip(2)
            .map(|row| row.split("<td>").skip(1).map(|cell| cell.split("</td>").next().unwrap().to_string()).collect())
            .collect();
        assert_eq!(rows.len(), 5, "{html}");
        // Seven columns: device, source and timer, method, the configuration in one cell,
        // map update, shading, shading × exact.
        assert!(rows.iter().all(|r| r.len() == 7), "{rows:?}");
        let pick = |row: &Vec<String>| (row[0].clone(), row[2].clone(), row[3].clone(), row[4].clone(), row[5].clone(), row[6].clone());
        let s = |x: &str| x.to_string();
        assert_eq!(
            pick(&rows[0]),
            (s("lavapipe"), s("exact"), s("reflection · 1/0 · 15/1 · 64x64"), s("4.0000"), s("2.0000"), number(1.0))
        );
        assert_eq!(pick(&rows[1]), (s("lavapipe"), s("lut"), s("reflection · 1/0 · 15/1 · 64x64"), s("4.0000"), s("3.0000"), number(1.5)));
        assert_eq!(pick(&rows[2]), (s("lavapipe"), s("lut"), s("reflection · 2/0 · 15/1 · 64x64"), s("4.0000"), s("5.0000"), s("–")));
        assert_eq!(
            pick(&rows[4]),
            (s("swiftshader"), s("schlick"), s("refraction · 1/1 · 8/1 · 48x48"), s("1.5000"), s("0.5000"), number(2.0))
        );
        assert_eq!(rows[4][1].as_str(), "browser: HeadlessChrome/156, timestamp");
        let mut none = String::new();
        devices.retain(|name, _| name == "other");
        effects_across(&mut none, &devices);
        assert!(none.is_empty());
    }
}

#[cfg(test)]
mod ao_statistics_tests {
    use super::*;

    /// One row per object and configuration with its figures (3 significant digits), – for an
    /// empty cell; nothing for a table without the statistics.
    #[test]
    fn statistics_table_lists_each_object_and_configuration() {
        let csv = "mesh,hierarchy,passes,mean_error,signed_error,median_error,p90_error,p99_error,max_error,area_mean_error,pixel_mean_error,defect_vertices,mean_error_without_defects\n\
                   bunny,true,2,0.0653,0.0378,0.0157,0.21,0.602,0.7146,0.0705,,3,0.0650\n";
        let html = ao_statistics_table(&CsvTable::parse(csv.as_bytes()).unwrap()).unwrap();
        for cell in ["<td>bunny</td>", "<td>tree</td>", "<td>0.0378</td>", "<td>0.210</td>", "<td>0.715</td>", "<td>–</td>", "<td>3</td>"]
        {
            assert!(html.contains(cell), "{cell} in {html}");
        }
        assert_eq!(html.matches("<tr>").count(), 2, "header and one row");
        assert!(ao_statistics_table(&CsvTable::parse(b"mesh,mean_error\nbunny,0.1\n").unwrap()).is_none());
    }
}
