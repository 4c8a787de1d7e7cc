//! `nklut report`: one self-contained HTML file (inline SVG and CSS, a few lines of inline
//! script for search; no network) and a Markdown file with the same tables. Every number
//! comes from a table another stage wrote (`materials.csv`, `excluded.csv`, `colors.csv`,
//! `errors.csv`, `cost.csv`, `gpu_timing.csv`), so a reader can trace it to its CSV.

pub mod charts;
pub mod csvdata;
pub mod curves;
pub mod html;

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Result};

use crate::cli::PageSelection;
use crate::db::Database;
use crate::ingest::{ingest, Ingest, Selection};
use crate::output::write_atomic;
use crate::spectrum::Index;
use charts::CostPoint;
use csvdata::CsvTable;
use html::{escape, number, percent, raw, TableText};

/// The tables the report is built from.
pub struct Inputs {
    pub materials: CsvTable,
    pub excluded: CsvTable,
    pub colors: Option<CsvTable>,
    pub errors: Option<CsvTable>,
    pub cost: Option<CsvTable>,
    pub gpu_timing: Option<CsvTable>,
}

impl Inputs {
    /// Load from an output folder. `materials.csv` and `excluded.csv` are required.
    pub fn load(out: &Path) -> Result<Self> {
        let required = |name: &str| -> Result<CsvTable> {
            match CsvTable::load(&out.join(name))? {
                Some(t) => Ok(t),
                None => bail!("{} is missing: run `nklut ingest` first", out.join(name).display()),
            }
        };
        Ok(Self {
            materials: required("materials.csv")?,
            excluded: required("excluded.csv")?,
            colors: CsvTable::load(&out.join("colors.csv"))?,
            errors: CsvTable::load(&out.join("errors.csv"))?,
            cost: CsvTable::load(&out.join("cost.csv"))?,
            gpu_timing: CsvTable::load(&out.join("gpu_timing.csv"))?,
        })
    }
}

/// A finished report: the HTML page and the Markdown twin.
pub struct Report {
    pub html: String,
    pub markdown: String,
}

/// Which materials get a detailed section, and how much is drawn for each.
pub struct Options {
    /// Page ids to detail (in order).
    pub pages: Vec<String>,
    /// Draw the Fresnel plots of the first `max_plots` pages only (HTML size).
    pub max_plots: usize,
}

struct Builder {
    html: String,
    markdown: String,
}

impl Builder {
    fn heading(&mut self, level: usize, id: &str, text: &str) {
        let _ = writeln!(self.html, "<h{level} id=\"{}\">{}</h{level}>", escape(id), escape(text));
        let _ = writeln!(self.markdown, "\n{} {text}\n", "#".repeat(level));
    }

    fn paragraph(&mut self, text: &str) {
        let _ = writeln!(self.html, "<p>{}</p>", escape(text));
        let _ = writeln!(self.markdown, "{text}\n");
    }

    fn table(&mut self, table: &TableText, class: &str) {
        self.html.push_str(&table.html(class));
        self.markdown.push_str(&table.markdown());
        self.markdown.push('\n');
    }

    fn figure(&mut self, svg: &str, caption: &str) {
        if svg.is_empty() {
            return;
        }
        let _ = writeln!(self.html, "<figure>{svg}<figcaption>{}</figcaption></figure>", escape(caption));
        let _ = writeln!(self.markdown, "*(figure in index.html: {caption})*\n");
    }
}

const STYLE: &str = "body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:0.5em 0 1.5em;font-size:0.85em}th,td{border:1px solid #ccc;padding:2px 6px;text-align:right}\
th{background:#f2f2f2}td:first-child,th:first-child{text-align:left}.swatch{display:inline-block;width:2.2em;height:1.2em;border:1px solid #888;vertical-align:middle}\
section.material{border-top:2px solid #ddd;margin-top:1.5em}figure{margin:0}figcaption{font-size:0.8em;color:#555}\
#toc{columns:4;font-size:0.8em}#search{width:20em;padding:4px}.note{color:#555;font-size:0.9em}";

const SEARCH_SCRIPT: &str = "function nkFilter(q){q=q.toLowerCase();for(const s of document.querySelectorAll('section.material')){s.style.display=s.dataset.key.includes(q)?'':'none'}for(const a of document.querySelectorAll('#toc li')){a.style.display=a.dataset.key.includes(q)?'':'none'}}";

/// Build the report from loaded tables. `curves` draws the per-material Fresnel curves.
pub fn build(inputs: &Inputs, options: &Options, curves: &dyn Fn(&str) -> Option<Vec<charts::Series>>) -> Result<Report> {
    let mut b = Builder { html: String::new(), markdown: String::new() };
    let _ = write!(
        b.html,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>nklut report</title><style>{STYLE}</style><script>{SEARCH_SCRIPT}</script></head><body>\n"
    );
    b.heading(1, "top", "nklut report: Fresnel methods per material");
    overview(&mut b, inputs);
    cost_section(&mut b, inputs)?;
    summaries(&mut b, inputs);
    materials_section(&mut b, inputs, options, curves)?;
    b.html.push_str("</body></html>\n");
    Ok(Report { html: b.html, markdown: b.markdown })
}

fn overview(b: &mut Builder, inputs: &Inputs) {
    b.heading(2, "overview", "Overview");
    let kept = inputs.materials.rows.len();
    let excluded = inputs.excluded.rows.len();
    let mut counts = TableText::new(&["pages", "count"]);
    counts.row(vec!["ingested".into(), (kept + excluded).to_string()]);
    counts.row(vec!["kept".into(), kept.to_string()]);
    counts.row(vec!["excluded".into(), excluded.to_string()]);
    b.table(&counts, "counts");
    let mut by_reason: BTreeMap<&str, usize> = BTreeMap::new();
    for row in &inputs.excluded.rows {
        *by_reason.entry(inputs.excluded.text(row, "reason")).or_default() += 1;
    }
    let mut reasons = TableText::new(&["exclusion reason", "pages"]);
    for (reason, count) in by_reason {
        reasons.row(vec![reason.to_string(), count.to_string()]);
    }
    b.table(&reasons, "reasons");
    let _ = writeln!(b.html, "<p>The full exclusion list, with file and line: <a href=\"../excluded.csv\">excluded.csv</a>.</p>");
    b.markdown.push_str("The full exclusion list, with file and line: [excluded.csv](../excluded.csv).\n\n");
}

/// One row of `cost.csv`.
struct CostRow {
    method: String,
    variant: String,
    ns_per_eval: f64,
    texture_bytes: f64,
    mean: f64,
    median: f64,
}

fn cost_rows(cost: &CsvTable) -> Vec<CostRow> {
    cost.rows
        .iter()
        .map(|r| CostRow {
            method: cost.text(r, "method").to_string(),
            variant: cost.text(r, "variant").to_string(),
            ns_per_eval: cost.number(r, "ns_per_eval").unwrap_or(f64::NAN),
            texture_bytes: cost.number(r, "texture_bytes").unwrap_or(0.0),
            mean: cost.number(r, "mean_rel_error").unwrap_or(f64::NAN),
            median: cost.number(r, "median_rel_error").unwrap_or(f64::NAN),
        })
        .collect()
}

/// Pareto flags over (cost, error); points without a finite cost are never on the front.
fn front(points: &[(f64, f64)]) -> Vec<bool> {
    let finite: Vec<(f64, f64)> = points.iter().map(|&(c, e)| if c.is_finite() && e.is_finite() { (c, e) } else { (f64::INFINITY, f64::INFINITY) }).collect();
    charts::pareto_front(&finite).into_iter().zip(points).map(|(on, p)| on && p.0.is_finite() && p.1.is_finite()).collect()
}

/// "What accuracy costs" (issue 6): analytic methods against CPU ns (and GPU ms when
/// measured); LUTs against texture bytes. Errors are means over materials from cost.csv;
/// medians beside them because a few near-zero-F materials (gases) dominate means.
fn cost_section(b: &mut Builder, inputs: &Inputs) -> Result<()> {
    b.heading(2, "cost", "What accuracy costs");
    let Some(cost) = &inputs.cost else {
        b.paragraph("cost.csv is missing: run `nklut validate` to measure each method's error and cost.");
        return Ok(());
    };
    let rows = cost_rows(cost);
    let gpu = gpu_medians(inputs);
    let methods: Vec<&CostRow> = rows.iter().filter(|r| r.method != "lut" || r.variant.starts_with("N=256,")).collect();
    let flags = front(&methods.iter().map(|r| (r.ns_per_eval, r.mean)).collect::<Vec<_>>());
    let mut table = TableText::new(&["method", "variant", "mean relative error", "median relative error", "CPU ns/eval", "GPU ms (median)", "Pareto (CPU)"]);
    for (r, &on) in methods.iter().zip(&flags) {
        table.row(vec![
            r.method.clone(),
            r.variant.clone(),
            number(r.mean),
            number(r.median),
            number(r.ns_per_eval),
            gpu.get(&r.method).map(|&ms| number(ms)).unwrap_or_else(|| "–".into()),
            if on { "yes".into() } else { String::new() },
        ]);
    }
    let points: Vec<CostPoint> = methods
        .iter()
        .zip(&flags)
        .map(|(r, &pareto)| CostPoint { label: short_label(&r.method, &r.variant), cost: r.ns_per_eval, error: r.mean, pareto })
        .collect();
    if points.iter().any(|p| p.cost.is_finite()) {
        b.figure(&charts::cost_chart(&points, "CPU ns per evaluation", (900, 460))?, "Mean relative error over materials against CPU cost per evaluation; the Pareto front is joined.");
    } else {
        b.paragraph("CPU cost per evaluation is not recorded yet (run `make bench` and record the figures in validate::CPU_COST_NS).");
    }
    b.table(&table, "cost");
    match &inputs.gpu_timing {
        Some(t) if !gpu.is_empty() => {
            let mut adapters: Vec<String> = t.rows.iter().map(|r| format!("{} ({}, {} timer)", t.text(r, "adapter"), t.text(r, "driver"), t.text(r, "timer"))).collect();
            adapters.dedup();
            let software = adapters.iter().any(|a| a.contains("llvmpipe") || a.contains("lavapipe") || a.contains("SwiftShader"));
            b.paragraph(&format!(
                "GPU ms: median over materials of gpu_timing.csv, measured on {}{}",
                adapters.join("; "),
                if software { ". This adapter is a CPU rasteriser: its times show ratios between methods, not GPU cost." } else { "." }
            ));
        }
        _ => b.paragraph("GPU time: output/gpu_timing.csv is absent (run `make gpu`, which needs the gpu feature and a GPU)."),
    }
    lut_cost(b, &rows)
}

/// LUT size × encoding: error against texture bytes, Pareto front over bytes.
fn lut_cost(b: &mut Builder, rows: &[CostRow]) -> Result<()> {
    let luts: Vec<&CostRow> = rows.iter().filter(|r| r.method == "lut" && r.variant.ends_with(",f64")).collect();
    if luts.is_empty() {
        return Ok(());
    }
    b.heading(3, "lut-cost", "Lookup textures: error against texture size");
    let flags = front(&luts.iter().map(|r| (r.texture_bytes, r.mean)).collect::<Vec<_>>());
    let points: Vec<CostPoint> = luts
        .iter()
        .zip(&flags)
        .map(|(r, &pareto)| CostPoint { label: r.variant.trim_end_matches(",f64").to_string(), cost: r.texture_bytes, error: r.mean, pareto })
        .collect();
    b.figure(&charts::cost_chart(&points, "texture bytes (N texels × 3 channels)", (900, 460))?, "LUT mean relative error over materials against texture bytes; the Pareto front is joined.");
    let mut table = TableText::new(&["LUT (texels, encoding)", "texture bytes", "mean relative error", "median relative error", "Pareto (bytes)"]);
    for (r, &on) in luts.iter().zip(&flags) {
        table.row(vec![r.variant.trim_end_matches(",f64").to_string(), number(r.texture_bytes), number(r.mean), number(r.median), if on { "yes".into() } else { String::new() }]);
    }
    b.table(&table, "lut-cost");
    Ok(())
}

fn short_label(method: &str, variant: &str) -> String {
    if variant.is_empty() || variant == "f64" {
        method.to_string()
    } else {
        format!("{method} {variant}")
    }
}

/// Median GPU ms per method over materials, from gpu_timing.csv when present.
fn gpu_medians(inputs: &Inputs) -> BTreeMap<String, f64> {
    let mut by_method: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    if let Some(t) = &inputs.gpu_timing {
        for r in &t.rows {
            if let Some(ms) = t.number(r, "median_ms") {
                by_method.entry(t.text(r, "method").to_string()).or_default().push(ms);
            }
        }
    }
    by_method
        .into_iter()
        .map(|(m, mut v)| {
            v.sort_by(f64::total_cmp);
            (m, v[v.len() / 2])
        })
        .collect()
}

/// Per (page, method, variant): the mean over channels of `column` from errors.csv.
fn material_errors(errors: &CsvTable, column: &str) -> BTreeMap<(String, String, String), f64> {
    let mut sums: BTreeMap<(String, String, String), (f64, usize)> = BTreeMap::new();
    for r in &errors.rows {
        if let Some(v) = errors.number(r, column) {
            let key = (errors.text(r, "page").to_string(), errors.text(r, "method").to_string(), errors.text(r, "variant").to_string());
            let e = sums.entry(key).or_default();
            e.0 += v;
            e.1 += 1;
        }
    }
    sums.into_iter().map(|(k, (s, n))| (k, s / n as f64)).collect()
}

fn summaries(b: &mut Builder, inputs: &Inputs) {
    b.heading(2, "summaries", "Where each approximation is worst");
    if let Some(errors) = &inputs.errors {
        let per_material = material_errors(errors, "mean_rel_error");
        let mut by_method: BTreeMap<(String, String), Vec<(String, f64)>> = BTreeMap::new();
        for ((page, method, variant), e) in per_material {
            by_method.entry((method, variant)).or_default().push((page, e));
        }
        let mut table = TableText::new(&["method", "variant", "worst page", "mean relative error", "2nd", "3rd"]);
        for ((method, variant), mut pages) in by_method {
            // One line per method: f64 precision, LUTs at the default 256 texels.
            if method == "exact" || variant.ends_with("f32") || (method == "lut" && !variant.starts_with("N=256,")) {
                continue;
            }
            pages.sort_by(|a, b| b.1.total_cmp(&a.1));
            let cell = |i: usize| pages.get(i).map(|(p, e)| format!("{p} ({})", percent(*e))).unwrap_or_default();
            table.row(vec![method, variant, pages[0].0.clone(), percent(pages[0].1), cell(1), cell(2)]);
        }
        b.table(&table, "worst");
        b.heading(3, "fallback", "Pages where compensated Schlick falls back");
        if errors.has("fallback") {
            let mut fallback: Vec<String> = errors
                .rows
                .iter()
                .filter(|r| errors.text(r, "method") == "schlick_compensated" && errors.text(r, "fallback") == "true")
                .map(|r| format!("{} ({})", errors.text(r, "page"), errors.text(r, "channel")))
                .collect();
            fallback.dedup();
            b.paragraph(&format!(
                "{} page-channels have no real exponent that makes compensated Schlick exact at 84.26°: {}",
                fallback.len(),
                if fallback.is_empty() { "none".to_string() } else { fallback.join(", ") }
            ));
        }
    } else {
        b.paragraph("errors.csv is missing: run `nklut validate`.");
        b.heading(3, "fallback", "Pages where compensated Schlick falls back");
        b.paragraph("Not measured yet: run `nklut validate`.");
    }
    let sparse: Vec<&Vec<String>> = inputs.materials.rows_where("sparse", "true").collect();
    b.heading(3, "sparse", "Sparse data");
    let mut table = TableText::new(&["page", "largest gap in 390–700 nm (nm)"]);
    for r in &sparse {
        table.row(vec![inputs.materials.text(r, "page").into(), number(inputs.materials.number(r, "max_visible_gap_nm").unwrap_or(f64::NAN))]);
    }
    b.paragraph(&format!("{} kept pages have tabulated rows more than 50 nm apart in the visible range.", sparse.len()));
    b.table(&table, "sparse");
}

/// A CSS swatch of a linear-sRGB colour (sRGB-encoded, clamped for display).
fn swatch(rgb: [f64; 3]) -> String {
    format!("<span class=\"swatch\" style=\"background:{}\"></span>", crate::color::hex_swatch(rgb))
}

fn channel_triple(table: &CsvTable, row: &[String], prefix: &str) -> [f64; 3] {
    ["r", "g", "b"].map(|c| table.number(row, &format!("{prefix}_{c}")).unwrap_or(f64::NAN))
}

fn materials_section(b: &mut Builder, inputs: &Inputs, options: &Options, curves: &dyn Fn(&str) -> Option<Vec<charts::Series>>) -> Result<()> {
    b.heading(2, "materials", &format!("Materials ({})", options.pages.len()));
    let m = &inputs.materials;
    let _ = writeln!(b.html, "<p><input id=\"search\" placeholder=\"search pages and names\" oninput=\"nkFilter(this.value)\"></p><ul id=\"toc\">");
    for page in &options.pages {
        let Some(row) = m.rows_where("page", page).next() else { continue };
        let key = escape(&format!("{} {}", page, m.text(row, "names")).to_lowercase());
        let _ = writeln!(b.html, "<li data-key=\"{key}\"><a href=\"#{}\">{}</a></li>", escape(page), escape(page));
    }
    b.html.push_str("</ul>\n");
    let errors_mean = inputs.errors.as_ref().map(|e| material_errors(e, "mean_rel_error"));
    let errors_max = inputs.errors.as_ref().map(|e| material_errors(e, "max_abs_error"));
    if options.pages.len() > options.max_plots {
        b.paragraph(&format!(
            "Fresnel plots are drawn for the first {} of {} materials (pass --max-plots to draw more; each adds about 100 kB).",
            options.max_plots,
            options.pages.len()
        ));
    }
    for (position, page) in options.pages.iter().enumerate() {
        let Some(row) = m.rows_where("page", page).next() else { continue };
        let key = escape(&format!("{} {}", page, m.text(row, "names")).to_lowercase());
        let _ = writeln!(b.html, "<section class=\"material\" data-key=\"{key}\">");
        b.heading(3, page, &format!("{page} — {} ({})", m.text(row, "names"), m.text(row, "kind")));
        let mut nk = TableText::new(&["index", "n red", "k red", "n green", "k green", "n blue", "k blue"]);
        let three: Vec<String> = ["red", "green", "blue"]
            .iter()
            .flat_map(|c| [number(m.number(row, &format!("n_{c}")).unwrap_or(f64::NAN)), number(m.number(row, &format!("k_{c}")).unwrap_or(f64::NAN))])
            .collect();
        nk.row([vec!["three-wavelength (685/535/475 nm)".to_string()], three].concat());
        let color_row = inputs.colors.as_ref().and_then(|c| c.rows_where("page", page).next().map(|r| (c, r)));
        if let Some((c, r)) = color_row {
            let n = channel_triple(c, r, "effective_n");
            let k = channel_triple(c, r, "effective_k");
            nk.row(vec!["effective (fitted to the spectral curve)".into(), number(n[0]), number(k[0]), number(n[1]), number(k[1]), number(n[2]), number(k[2])]);
        }
        b.table(&nk, "nk");
        if let Some((c, r)) = color_row {
            let spectral = channel_triple(c, r, "f0_spectral");
            let three = channel_triple(c, r, "f0_three_channel");
            let index_f0 = channel_triple(c, r, "index_error_f0");
            let index_angle = channel_triple(c, r, "index_error_angle");
            let effective = channel_triple(c, r, "effective_error");
            let mut colors = TableText::new(&["F0 colour (linear sRGB)", "swatch", "red", "green", "blue"]);
            colors.row(vec!["spectral reference".into(), raw(swatch(spectral)), number(spectral[0]), number(spectral[1]), number(spectral[2])]);
            colors.row(vec!["three-wavelength".into(), raw(swatch(three)), number(three[0]), number(three[1]), number(three[2])]);
            colors.row(vec!["index error at normal incidence".into(), String::new(), percent(index_f0[0]), percent(index_f0[1]), percent(index_f0[2])]);
            colors.row(vec!["index error over angle".into(), String::new(), percent(index_angle[0]), percent(index_angle[1]), percent(index_angle[2])]);
            colors.row(vec!["effective-index error over angle".into(), String::new(), percent(effective[0]), percent(effective[1]), percent(effective[2])]);
            b.table(&colors, "colors");
            b.paragraph(&format!("CIEDE2000 between the spectral and three-wavelength F0: {}", number(c.number(r, "delta_e2000_f0").unwrap_or(f64::NAN))));
        }
        if position < options.max_plots {
            if let Some(series) = curves(page) {
                let theta: Vec<f64> = (0..series[0].values[0].len()).map(|i| 90.0 * i as f64 / (series[0].values[0].len() - 1) as f64).collect();
                let exact = series.iter().find(|s| s.name == "exact").unwrap_or(&series[0]);
                if m.text(row, "kind") == "conductor" {
                    let minima: Vec<String> = (0..3)
                        .map(|ch| {
                            let (i, f) = exact.values[ch].iter().enumerate().fold((0, f64::INFINITY), |a, (i, &f)| if f < a.1 { (i, f) } else { a });
                            format!("{} {}° (F = {})", crate::spectrum::CHANNEL_NAMES[ch], number(theta[i]), number(f))
                        })
                        .collect();
                    b.paragraph(&format!("Reflectance minimum of the exact three-channel curve: {}", minima.join(", ")));
                }
                let svg = charts::fresnel_curves(&theta, &series, (960, 260))?;
                b.figure(&svg, &format!("{page}: F against θ per channel, exact and each approximation"));
            }
        }
        if let (Some(mean), Some(max)) = (&errors_mean, &errors_max) {
            let mut table = TableText::new(&["method", "variant", "mean relative error", "max absolute error"]);
            for ((p, method, variant), e) in mean.range((page.clone(), String::new(), String::new())..) {
                if p != page {
                    break;
                }
                if !per_material_row(method, variant) {
                    continue;
                }
                let key = (p.clone(), method.clone(), variant.clone());
                table.row(vec![method.clone(), variant.clone(), percent(*e), number(max.get(&key).copied().unwrap_or(f64::NAN))]);
            }
            b.table(&table, "errors");
        }
        b.html.push_str("</section>\n");
    }
    Ok(())
}

/// The per-material error table lists f64 methods, `exact` in f32 (the GPU-precision
/// floor) and LUTs at the default 256 texels; the full sweep is in errors.csv.
fn per_material_row(method: &str, variant: &str) -> bool {
    match method {
        "exact" => true,
        "lut" => variant.starts_with("N=256,") && variant.ends_with("f64"),
        _ => !variant.ends_with("f32"),
    }
}

/// Write `report/index.html` and `report/report.md` under `out`.
pub fn write(report: &Report, out: &Path) -> Result<Vec<PathBuf>> {
    let dir = out.join("report");
    let html = dir.join("index.html");
    let markdown = dir.join("report.md");
    write_atomic(&html, report.html.as_bytes())?;
    write_atomic(&markdown, report.markdown.as_bytes())?;
    Ok(vec![html, markdown])
}

/// The stages whose tables the report reads, in the order they run.
pub const STAGES: [&str; 3] = ["ingest", "colors", "validate"];

/// Per-page columns the report shows, by file: tests check each value is on the page.
pub const TRACED_COLUMNS: &[(&str, &[&str])] = &[
    ("materials.csv", &["n_red", "k_red", "n_green", "k_green", "n_blue", "k_blue"]),
    (
        "colors.csv",
        &[
            "f0_spectral_r",
            "f0_spectral_g",
            "f0_spectral_b",
            "f0_three_channel_r",
            "f0_three_channel_b",
            "index_error_f0_r",
            "index_error_angle_b",
            "effective_n_g",
            "effective_k_b",
            "effective_error_r",
            "delta_e2000_f0",
        ],
    ),
];

/// How the report writes the value of `column`: error columns (fractions) as percentages,
/// everything else with `html::number`.
pub fn shown(column: &str, value: f64) -> String {
    if column.contains("error") && !column.contains("abs") && !column.starts_with("delta_e") {
        percent(value)
    } else {
        number(value)
    }
}

/// `nklut report`: the selected pages (default: the 3d shelf) that `materials.csv` lists,
/// with Fresnel curves computed from the three-channel index, the effective index of
/// `colors.csv` and the spectral reference of the page's data.
pub fn command(db: &Database, out: &Path, pages: &PageSelection, max_plots: usize) -> Result<Vec<PathBuf>> {
    let inputs = Inputs::load(out)?;
    let m = &inputs.materials;
    let explicit = pages.all || !pages.pages.is_empty() || !pages.shelves.is_empty();
    let selection = if explicit { pages.selection() } else { Selection::shelf("3d") };
    let everything = selection.shelves.is_empty() && selection.pages.is_empty();
    let chosen: Vec<String> = m
        .rows
        .iter()
        .filter(|r| everything || selection.shelves.iter().any(|s| s == m.text(r, "shelf")) || selection.pages.iter().any(|p| p == m.text(r, "page")))
        .map(|r| m.text(r, "page").to_string())
        .collect();
    let plotted = Selection { shelves: vec![], pages: chosen.iter().take(max_plots).cloned().collect() };
    let kept = if plotted.pages.is_empty() { Ingest::default() } else { ingest(db, &plotted, &crate::ingest::Config::default())? };
    let curves = |page: &str| {
        let kept_page = kept.find(page)?;
        let effective = inputs.colors.as_ref().and_then(|c| {
            let row = c.rows_where("page", page).next()?;
            let n = channel_triple(c, row, "effective_n");
            let k = channel_triple(c, row, "effective_k");
            Some([0, 1, 2].map(|i| Index::new(n[i], k[i])))
        });
        Some(curves::material_curves(&kept_page.material, effective.as_ref(), 91))
    };
    let built = build(&inputs, &Options { pages: chosen, max_plots }, &curves)?;
    write(&built, out)
}
