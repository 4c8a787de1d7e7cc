//! The index's first screen: findings (sentences generated from the tables, each figure
//! carried with its full value and the table it comes from), the recommendation per
//! material class and device (`recommendations.csv`, written by `nklut recommend`), and the
//! decision table per method (CPU ns from `cost.csv`, GPU time × exact per device from the
//! devices folder, ΔE2000 against the spectral curve over pages by class from
//! `method_errors.csv` and `engine_params.csv`).
//!
//! Nothing here is a hand-written figure: every number is computed from a table row, and
//! each appears in the HTML as `<span class="figure" data-key data-value>` so that a
//! reader (and the tests) can recompute it. Medians are `stats::median`; p95 is
//! `stats::quantile` (linear between order statistics).

use nklut_tables::columns::{Column, Float, Integer, OptionalFloat};
use nklut_tables::effects_tables::{ao_errors, configuration, effects_errors, spectral_errors};
use std::collections::BTreeMap;

use super::csvdata::CsvTable;
use super::html::escape;
use super::inputs::Inputs;
use crate::stats;

/// Three significant digits, trailing zeros dropped (the figures of findings and of
/// `recommendations.csv`'s reasons).
pub fn sig3(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (2 - x.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{x:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A device folder's or result file's name without its date and driver detail
/// (`device-google-swiftshader-2026-12-03` → `google swiftshader`).
pub fn short_device(name: &str) -> String {
    name.trim_start_matches("device-").split('-').take(2).collect::<Vec<_>>().join(" ")
}

/// A figure as the report writes it: `<span class="figure" data-key data-value>shown</span>`.
pub fn figure_span(key: &str, value: f64) -> String {
    let f = Figure::new(key, value);
    format!("<span class=\"figure\" data-key=\"{}\" data-value=\"{}\">{}</span>", escape(key), value, escape(&f.shown()))
}

/// A number in a sentence: what it is (`key`), its value, and how it is shown.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    pub key: String,
    pub value: f64,
}

impl Figure {
    fn new(key: impl Into<String>, value: f64) -> Self {
        Self { key: key.into(), value }
    }

    /// Counts as integers, the rest with three significant digits.
    pub fn shown(&self) -> String {
        if self.value.fract() == 0.0 && self.value.abs() < 1e15 {
            format!("{}", self.value as i64)
        } else {
            sig3(self.value)
        }
    }
}

/// A piece of a finding's sentence.
#[derive(Clone, Debug, PartialEq)]
pub enum Piece {
    Text(String),
    Figure(Figure),
}

/// One finding: its sentence and the chart or table it comes from.
#[derive(Clone, Debug, PartialEq)]
pub struct Finding {
    pub id: String,
    pub pieces: Vec<Piece>,
    /// Link target (relative to `report/index.html`) and its words.
    pub link: (String, String),
}

impl Finding {
    pub fn figures(&self) -> Vec<&Figure> {
        self.pieces
            .iter()
            .filter_map(|p| match p {
                Piece::Figure(f) => Some(f),
                Piece::Text(_) => None,
            })
            .collect()
    }

    /// The sentence as HTML, each figure a [`figure_span`].
    pub fn sentence_html(&self) -> String {
        let mut html = String::new();
        for piece in &self.pieces {
            match piece {
                Piece::Text(t) => html.push_str(&escape(t)),
                Piece::Figure(f) => html.push_str(&figure_span(&f.key, f.value)),
            }
        }
        html
    }

    pub fn html(&self) -> String {
        let mut html = format!("<li class=\"finding\" id=\"finding-{}\">", self.id);
        html.push_str(&self.sentence_html());
        html.push_str(&format!(" <a href=\"{}\">({})</a></li>", escape(&self.link.0), escape(&self.link.1)));
        html
    }

    pub fn text(&self) -> String {
        self.pieces
            .iter()
            .map(|p| match p {
                Piece::Text(t) => t.clone(),
                Piece::Figure(f) => f.shown(),
            })
            .collect()
    }
}

/// A sentence under construction.
struct Sentence(Vec<Piece>);

impl Sentence {
    fn new() -> Self {
        Self(Vec::new())
    }
    fn t(mut self, text: impl Into<String>) -> Self {
        self.0.push(Piece::Text(text.into()));
        self
    }
    fn f(mut self, key: impl Into<String>, value: f64) -> Self {
        self.0.push(Piece::Figure(Figure::new(key, value)));
        self
    }
}

/// The candidate group of a recommendation row: its method and where its parameters come from.
pub fn group(t: &CsvTable, row: &[String]) -> String {
    format!("{} ({})", t.text(row, "method"), t.text(row, "parameters_from"))
}

/// The devices of `recommendations.csv` in the order of its rows.
pub fn devices(recs: &CsvTable) -> Vec<String> {
    let mut seen: Vec<String> = Vec::new();
    for r in &recs.rows {
        let d = recs.text(r, "device");
        if !seen.iter().any(|s| s == d) {
            seen.push(d.to_string());
        }
    }
    seen
}

/// The bound the recommendations were made with (ΔE2000 max), else 1.
pub fn bound(recs: Option<&CsvTable>) -> f64 {
    recs.and_then(|t| t.rows.first().and_then(|r| t.number(r, "bound_de2000"))).unwrap_or(1.0)
}

/// The most frequent pick group of `rows` with its count (ties: the first in name order).
pub fn most_frequent(recs: &CsvTable, rows: &[&Vec<String>]) -> Option<(String, usize)> {
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    for r in rows.iter().filter(|r| !recs.text(r, "method").is_empty()) {
        *counts.entry(group(recs, r)).or_default() += 1;
    }
    counts.into_iter().fold(None, |best: Option<(String, usize)>, (g, n)| match best {
        Some((_, m)) if m >= n => best,
        _ => Some((g, n)),
    })
}

fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars.next().map(|c| c.to_uppercase().chain(chars).collect()).unwrap_or_default()
}

fn class_name(kind: &str) -> &str {
    match kind {
        "conductor" => "conductors",
        "dielectric" => "dielectrics",
        other => other,
    }
}

/// The findings the tables support (a finding whose table is absent is left out).
pub fn findings(inputs: &Inputs, material_href: &dyn Fn(&str) -> String) -> Vec<Finding> {
    let recs = inputs.extra.get("recommendations.csv");
    let method_errors = inputs.extra.get("method_errors.csv");
    let bound = bound(recs);
    let mut out = Vec::new();
    if let Some(recs) = recs {
        out.extend(ship_findings(recs, bound));
    }
    out.extend(inputs.extra.get("engine_params.csv").and_then(|engine| schlick_finding(engine, bound, material_href)));
    if let (Some(colors), Some(me)) = (&inputs.colors, method_errors) {
        out.extend(three_wavelengths_finding(colors, me, bound, material_href));
    }
    out.extend(method_errors.and_then(|me| lut_size_finding(me, bound)));
    for (path, table) in inputs.extra.iter().filter(|(k, _)| k.ends_with("/effects_errors.csv")) {
        out.extend(search_finding(path.trim_end_matches("/effects_errors.csv"), path, table));
    }
    // Where three wavelengths stop being enough against the spectral truth, and what GTAO
    // and surfels trade: the effects page's scene findings, on the first screen too.
    for (path, table) in inputs.extra.iter().filter(|(k, _)| k.ends_with("/spectral_errors.csv")) {
        out.extend(spectral_finding(path.trim_end_matches("/spectral_errors.csv"), path, table, bound));
    }
    for (path, table) in inputs.extra.iter().filter(|(k, _)| k.ends_with("/ao_errors.csv")) {
        out.extend(ao_finding(path.trim_end_matches("/ao_errors.csv"), path, table));
    }
    out.extend(inputs.cost.as_ref().and_then(|cost| cost_finding(cost, inputs)));
    out
}

/// Per material class, the pick each device makes most often within the bound.
fn ship_findings(recs: &CsvTable, bound: f64) -> Vec<Finding> {
    let mut out = Vec::new();
    for kind in ["conductor", "dielectric"] {
        let pages: Vec<&str> = {
            let mut p: Vec<&str> = recs.rows.iter().filter(|r| recs.text(r, "kind") == kind).map(|r| recs.text(r, "page")).collect();
            p.dedup();
            p
        };
        if pages.is_empty() {
            continue;
        }
        let mut s = Sentence::new()
            .t(format!("{} (", capitalised(class_name(kind))))
            .f(format!("pages:{kind}"), pages.len() as f64)
            .t(" pages), cheapest within ΔE2000 ≤ ")
            .f("bound", bound)
            .t(" at every angle: ");
        // Devices grouped by their most frequent pick, in device order.
        let mut by_group: Vec<(String, Vec<(String, usize)>)> = Vec::new();
        for device in devices(recs) {
            let rows: Vec<&Vec<String>> =
                recs.rows.iter().filter(|r| recs.text(r, "kind") == kind && recs.text(r, "device") == device).collect();
            let Some((g, n)) = most_frequent(recs, &rows) else { continue };
            match by_group.iter_mut().find(|(k, _)| *k == g) {
                Some((_, v)) => v.push((device, n)),
                None => by_group.push((g, vec![(device, n)])),
            }
        }
        for (i, (g, on)) in by_group.iter().enumerate() {
            s = s.t(format!("{}{g} for ", if i == 0 { "" } else { "; " }));
            for (j, (device, n)) in on.iter().enumerate() {
                s = s
                    .t(if j == 0 { "" } else { ", " })
                    .f(format!("pick-count:{kind}:{device}:{g}"), *n as f64)
                    .t(format!(" on {}", short_device(device)));
            }
        }
        out.push(Finding {
            id: format!("ship-{kind}s"),
            pieces: s.t(".").0,
            link: ("#answer-picks".into(), "recommendation table; recommendations.csv".into()),
        });
    }
    out
}

/// How far Schlick on the spectral F0 (the engines' model) strays, over the pages.
fn schlick_finding(engine: &CsvTable, bound: f64, material_href: &dyn Fn(&str) -> String) -> Option<Finding> {
    let rows: Vec<(&str, &str, f64)> = engine
        .rows
        .iter()
        .filter_map(|r| Some((engine.text(r, "page"), engine.text(r, "kind"), engine.number(r, "schlick_de2000_max")?)))
        .collect();
    let &(worst_page, _, worst) = rows.iter().max_by(|a, b| a.2.total_cmp(&b.2))?;
    let within = rows.iter().filter(|r| r.2 <= bound).count();
    let mut s = Sentence::new()
        .t("Schlick on the spectral F0 (glTF, Unreal, Unity) stays within ΔE2000 ")
        .f("bound", bound)
        .t(" at every angle on ")
        .f("schlick-within", within as f64)
        .t(" of ")
        .f("schlick-pages", rows.len() as f64)
        .t(" pages");
    let mut lead = "; median worst-angle ΔE2000 ";
    for kind in ["conductor", "dielectric"] {
        let of: Vec<f64> = rows.iter().filter(|r| r.1 == kind).map(|r| r.2).collect();
        if let Some(m) = stats::median(&of) {
            s = s.t(lead).f(format!("schlick-median:{kind}"), m).t(format!(" ({})", class_name(kind)));
            lead = ", ";
        }
    }
    s = s.t(format!(", largest {worst_page}: ")).f("schlick-worst", worst).t(".");
    Some(Finding { id: "schlick".into(), pieces: s.0, link: (material_href(worst_page), format!("{worst_page}; engine_params.csv")) })
}

/// What three wavelengths cost against the spectral truth, at normal incidence and over
/// all angles.
fn three_wavelengths_finding(colors: &CsvTable, me: &CsvTable, bound: f64, material_href: &dyn Fn(&str) -> String) -> Option<Finding> {
    let conductors: Vec<f64> =
        colors.rows.iter().filter(|r| colors.text(r, "kind") == "conductor").filter_map(|r| colors.number(r, "delta_e2000_f0")).collect();
    let worst = colors
        .rows
        .iter()
        .filter_map(|r| Some((colors.text(r, "page"), colors.number(r, "delta_e2000_f0")?)))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let exact: Vec<f64> = me.rows.iter().filter(|r| me.text(r, "method") == "exact").filter_map(|r| me.number(r, "de2000_max")).collect();
    let (Some(median), Some((page, value))) = (stats::median(&conductors), worst) else { return None };
    let within = exact.iter().filter(|v| **v <= bound).count();
    let s = Sentence::new()
        .t("Three wavelengths against the spectral truth: exact Fresnel of the three-channel (n, k) is off by ΔE2000 ")
        .f("index-f0-median:conductor", median)
        .t(" at normal incidence (median over conductors), up to ")
        .f("index-f0-worst", value)
        .t(format!(" ({page}); over all angles it stays within ΔE2000 "))
        .f("bound", bound)
        .t(" on ")
        .f("exact-within", within as f64)
        .t(" of ")
        .f("exact-pages", exact.len() as f64)
        .t(" pages.");
    Some(Finding {
        id: "three-wavelengths".into(),
        pieces: s.0,
        link: (material_href(page), format!("{page}; colors.csv, method_errors.csv")),
    })
}

/// Per page, the smallest texture of a spectral LUT within the bound.
fn lut_size_finding(me: &CsvTable, bound: f64) -> Option<Finding> {
    let mut smallest: BTreeMap<&str, (f64, &str)> = BTreeMap::new();
    let mut pages: Vec<&str> = Vec::new();
    for r in me.rows.iter().filter(|r| me.text(r, "method") == "lut") {
        let page = me.text(r, "page");
        if !pages.contains(&page) {
            pages.push(page);
        }
        let (Some(bytes), Some(de)) = (me.number(r, "texture_bytes"), me.number(r, "de2000_max")) else { continue };
        if de <= bound && smallest.get(page).is_none_or(|(b, _)| bytes < *b) {
            smallest.insert(page, (bytes, me.text(r, "variant")));
        }
    }
    let bytes: Vec<f64> = smallest.values().map(|v| v.0).collect();
    let (Some(median), Some((page, (max, variant)))) = (stats::median(&bytes), smallest.iter().max_by(|a, b| a.1 .0.total_cmp(&b.1 .0)))
    else {
        return None;
    };
    let s = Sentence::new()
        .t("A LUT of the spectral curve stays within ΔE2000 ")
        .f("bound", bound)
        .t(" on ")
        .f("lut-within", smallest.len() as f64)
        .t(" of ")
        .f("lut-pages", pages.len() as f64)
        .t(" pages; the smallest such texture is ")
        .f("lut-bytes-median", median)
        .t(" bytes per page at the median, ")
        .f("lut-bytes-max", *max)
        .t(format!(" bytes at most ({variant}, {page})."));
    Some(Finding { id: "lut-size".into(), pieces: s.0, link: ("#answer-methods".into(), "decision table; method_errors.csv".into()) })
}

/// What a LUT lookup and Schlick cost against exact Fresnel, on the CPU and each device.
fn cost_finding(cost: &CsvTable, inputs: &Inputs) -> Option<Finding> {
    let ns = |method: &str, variant: &str| {
        cost.rows
            .iter()
            .find(|r| cost.text(r, "method") == method && cost.text(r, "variant") == variant)
            .and_then(|r| cost.number(r, "ns_per_eval"))
    };
    let (Some(exact), Some(lut), Some(schlick)) = (ns("exact", "f64"), ns("lut", "N=256,unorm8,f64"), ns("schlick", "f64")) else {
        return None;
    };
    let mut s = Sentence::new()
        .t("Cost against exact Fresnel: on the CPU a LUT lookup is ")
        .f("x-exact:CPU:lut", lut / exact)
        .t("× and Schlick ")
        .f("x-exact:CPU:schlick", schlick / exact)
        .t("×");
    for (name, device) in &inputs.devices {
        if let (Some(e), Some(l), Some(sc)) = (device.median_ms("exact"), device.median_ms("lut"), device.median_ms("schlick")) {
            s = s
                .t(format!("; on {} ", short_device(name)))
                .f(format!("x-exact:{name}:lut"), l / e)
                .t("× and ")
                .f(format!("x-exact:{name}:schlick"), sc / e)
                .t("×");
        }
    }
    let link = if inputs.devices.is_empty() {
        ("#cost".to_string(), "cost.csv".to_string())
    } else {
        ("effects.html#devices".to_string(), "across devices; cost.csv".to_string())
    };
    Some(Finding { id: "cost".into(), pieces: s.t(" (median pass time over materials).").0, link })
}

/// How much of an effects scene's total error the Fresnel method makes and how much the
/// distance-map search (`effects_errors.csv` of the scene's folder `scene`, at `path`).
pub fn search_finding(scene: &str, path: &str, table: &CsvTable) -> Option<Finding> {
    let column = |column: Column<Float>, keep: &dyn Fn(&[String]) -> bool| -> Vec<f64> {
        table.rows.iter().filter(|r| keep(r)).filter_map(|r| table.value(r, column)).collect()
    };
    let fresnel = column(effects_errors::FRESNEL_MEAN_DELTA_E2000, &|r| table.get(r, effects_errors::METHOD) != "exact");
    let total = column(effects_errors::TOTAL_MEAN_DELTA_E2000, &|_| true);
    let geometry = column(effects_errors::GEOMETRY_MEAN_DELTA_E2000, &|_| true);
    let max = |v: &[f64]| v.iter().copied().fold(f64::NAN, f64::max);
    let min = |v: &[f64]| v.iter().copied().fold(f64::NAN, f64::min);
    if fresnel.is_empty() || total.is_empty() || geometry.is_empty() {
        return None;
    }
    let (f, g) = (max(&fresnel), max(&geometry));
    let s = Sentence::new()
        .t(format!("In {scene}, the Fresnel method's own error (against exact Fresnel on the same paths) stays at ΔE2000 ≤ "))
        .f(format!("search:{scene}:fresnel-max"), f)
        .t(" while the total against the ray-traced reference is ")
        .f(format!("search:{scene}:total-min"), min(&total))
        .t("–")
        .f(format!("search:{scene}:total-max"), max(&total))
        .t("; the distance-map search alone (exact Fresnel) gives up to ")
        .f(format!("search:{scene}:geometry-max"), g)
        .t(if g > f { ": the search, not the Fresnel formula, dominates." } else { "." });
    Some(Finding { id: format!("search-{scene}"), pieces: s.0, link: (format!("effects.html#scene-{scene}"), format!("{scene}; {path}")) })
}

/// A depth (reflections, refractions) of an effects row, when both cells are counts.
fn depth_of(t: &CsvTable, row: &[String]) -> Option<(u64, u64)> {
    Some((t.raw(row, configuration::REFLECTION_DEPTH).parse().ok()?, t.raw(row, configuration::REFRACTION_DEPTH).parse().ok()?))
}

/// Where three channels stop being enough against the spectral truth in a scene
/// (`spectral_errors.csv`): per index source, the worst object's mean ΔE2000 at the
/// shallowest and the deepest depth (depths ordered by total bounces, then reflections)
/// and the first depth where it exceeds `bound`.
pub fn spectral_finding(scene: &str, path: &str, t: &CsvTable, bound: f64) -> Option<Finding> {
    let mut depths: Vec<(u64, u64)> = Vec::new();
    let mut sources: Vec<&str> = Vec::new();
    for row in &t.rows {
        if let Some(d) = depth_of(t, row) {
            if !depths.contains(&d) {
                depths.push(d);
            }
        }
        let source = t.get(row, spectral_errors::INDEX_SOURCE);
        if !sources.contains(&source) {
            sources.push(source);
        }
    }
    depths.sort_by_key(|&(r, x)| (r + x, r));
    let (&first, &last) = (depths.first()?, depths.last()?);
    let mut s = Sentence::new()
        .t(format!("In {scene}, three channels against the spectral reference (mean ΔE2000 over an object's pixels, the worst object): "));
    for (i, source) in sources.iter().enumerate() {
        let worst = |d: (u64, u64)| {
            t.rows
                .iter()
                .filter(|r| t.get(r, spectral_errors::INDEX_SOURCE) == *source && depth_of(t, r) == Some(d))
                .filter_map(|r| t.value(r, spectral_errors::MEAN_DELTA_E2000))
                .fold(f64::NAN, f64::max)
        };
        let key = |d: (u64, u64)| format!("spectral:{scene}:{source}:{}+{}", d.0, d.1);
        s = s
            .t(format!("{}{source} ", if i == 0 { "" } else { "; " }))
            .f(key(first), worst(first))
            .t(format!(" at depth {}+{}", first.0, first.1));
        if last != first {
            s = s.t(" to ").f(key(last), worst(last)).t(format!(" at depth {}+{}", last.0, last.1));
        }
        s = match depths.iter().find(|&&d| worst(d) > bound) {
            Some(&d) => s.t(", first above ΔE2000 ").f("bound", bound).t(format!(" at depth {}+{} (", d.0, d.1)).f(key(d), worst(d)).t(")"),
            None => s.t(", within ΔE2000 ").f("bound", bound).t(" at every depth"),
        };
    }
    Some(Finding {
        id: format!("spectral-{scene}"),
        pieces: s.t(".").0,
        link: (format!("effects.html#scene-{scene}"), format!("{scene}; {path}")),
    })
}

/// What surfel ambient occlusion and GTAO trade in a scene (`ao_errors.csv`): the surfel
/// technique and pass count with the smallest accessibility error (the surfel-weighted mean
/// of `mean_error` over the objects) with its CPU time (the mean of `cpu_ms` over its rows),
/// one pass of the same technique, and GTAO's per-pixel mean error (pixel-weighted) beside
/// those surfels' per-pixel mean.
pub fn ao_finding(scene: &str, path: &str, t: &CsvTable) -> Option<Finding> {
    let gtao = |r: &[String]| t.holds(ao_errors::TECHNIQUE) && t.get(r, ao_errors::TECHNIQUE) == "gtao";
    let technique = |r: &[String]| if t.raw(r, ao_errors::HIERARCHY) == "true" { "tree" } else { "brute force" };
    let weighted = |rows: &[&Vec<String>], column: Column<OptionalFloat>, weight: Column<Integer>| {
        let (mut sum, mut total) = (0.0, 0.0);
        for r in rows {
            if let (Some(v), Some(w)) = (t.value(r, column), t.value(r, weight)) {
                sum += v * w;
                total += w;
            }
        }
        if total > 0.0 {
            Some(sum / total)
        } else {
            None
        }
    };
    let mut configurations: Vec<(&str, &str)> = Vec::new();
    for r in t.rows.iter().filter(|r| !gtao(r)) {
        let c = (technique(r), t.raw(r, ao_errors::PASSES));
        if !configurations.contains(&c) {
            configurations.push(c);
        }
    }
    let rows_of = |(tech, passes): (&str, &str)| -> Vec<&Vec<String>> {
        t.rows.iter().filter(|r| !gtao(r) && technique(r) == tech && t.raw(r, ao_errors::PASSES) == passes).collect()
    };
    let (best, error) = configurations
        .iter()
        .filter_map(|&c| Some((c, weighted(&rows_of(c), ao_errors::MEAN_ERROR, ao_errors::SURFELS)?)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let best_rows = rows_of(best);
    let cpu: Vec<f64> = best_rows.iter().filter_map(|r| t.value(r, ao_errors::CPU_MS)).collect();
    let mut s = Sentence::new()
        .t(format!("In {scene}, surfel ambient occlusion is closest to the ray-traced reference with the {} and {} pass(es): mean accessibility error ", best.0, best.1))
        .f(format!("ao:{scene}:best"), error);
    if !cpu.is_empty() {
        s = s.t(" over surfels in ").f(format!("ao:{scene}:best-cpu-ms"), cpu.iter().sum::<f64>() / cpu.len() as f64).t(" ms of CPU");
    }
    if best.1 != "1" {
        if let Some(one) = weighted(&rows_of((best.0, "1")), ao_errors::MEAN_ERROR, ao_errors::SURFELS) {
            s = s.t(" (one pass: ").f(format!("ao:{scene}:one-pass"), one).t(")");
        }
    }
    let gtao_rows: Vec<&Vec<String>> = t.rows.iter().filter(|r| gtao(r)).collect();
    if let (Some(g), Some(surfels)) = (
        weighted(&gtao_rows, ao_errors::PIXEL_MEAN_ERROR, ao_errors::PIXELS),
        weighted(&best_rows, ao_errors::PIXEL_MEAN_ERROR, ao_errors::PIXELS),
    ) {
        s = s
            .t("; per covered pixel, GTAO's mean error is ")
            .f(format!("ao:{scene}:gtao-pixel"), g)
            .t(" against those surfels' ")
            .f(format!("ao:{scene}:surfel-pixel"), surfels);
    }
    Some(Finding {
        id: format!("ao-{scene}"),
        pieces: s.t(".").0,
        link: (format!("effects.html#scene-{scene}"), format!("{scene}; {path}")),
    })
}

/// One row of the decision table: a candidate group over the pages.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodRow {
    /// The shader method a device times.
    pub method: String,
    pub parameters_from: String,
    /// The LUT variant where the row is one size × encoding.
    pub variant: String,
    pub cpu_ns: Option<f64>,
    /// × exact per device (in `devices` order).
    pub gpu_x_exact: Vec<Option<f64>>,
    /// Per class (conductor, dielectric): (median, p95) of ΔE2000 max over its pages.
    pub de_max: [Option<(f64, f64)>; 2],
    /// Pages within the bound, and pages measured.
    pub within: (usize, usize),
}

/// The engine models of `engine_params.csv` and the shader method that evaluates each
/// (Gulbrandsen and fitted (n, k) are exact Fresnel of an (n, k); glTF ior is Schlick).
pub const ENGINE_MODELS: [(&str, &str, &str); 6] = [
    ("schlick", "schlick", "spectral F0"),
    ("f82_tint", "f82_tint", "spectral F0 + F82 tint"),
    ("gulbrandsen", "exact", "Gulbrandsen reflectivity + edge tint"),
    ("generalized_schlick", "generalized_schlick", "spectral F0 + F82 colour + exponent"),
    ("fitted_nk", "exact", "fitted (n, k)"),
    ("gltf_ior", "schlick", "glTF ior (n_d)"),
];

/// The LUT rows the decision table shows: the size `make luts` bakes, in two encodings.
pub const TABLE_LUTS: [&str; 2] = ["N=256,unorm8-srgb", "N=256,f16"];

fn spread(values: &mut [f64]) -> Option<(f64, f64)> {
    values.sort_by(f64::total_cmp);
    Some((stats::median(values)?, stats::quantile(values, 0.95)))
}

/// The decision table: the closed forms on the three-channel index, the engine models, and
/// the [`TABLE_LUTS`] of the spectral curve.
pub fn method_rows(inputs: &Inputs, devices: &[String]) -> Vec<MethodRow> {
    let bound = bound(inputs.extra.get("recommendations.csv"));
    let cpu = |method: &str, variant: &str| {
        inputs.cost.as_ref().and_then(|c| {
            let v = if variant.is_empty() { "f64".to_string() } else { format!("{variant},f64") };
            c.rows.iter().find(|r| c.text(r, "method") == method && c.text(r, "variant") == v).and_then(|r| c.number(r, "ns_per_eval"))
        })
    };
    let gpu = |method: &str| -> Vec<Option<f64>> {
        devices
            .iter()
            .map(|d| {
                let t = inputs.devices.get(d)?;
                Some(t.median_ms(method)? / t.median_ms("exact")?)
            })
            .collect()
    };
    let row = |method: &str, from: &str, variant: &str, values: Vec<(String, f64)>| {
        let of = |kind: &str| spread(&mut values.iter().filter(|v| v.0 == kind).map(|v| v.1).collect::<Vec<f64>>());
        MethodRow {
            method: method.into(),
            parameters_from: from.into(),
            variant: variant.into(),
            cpu_ns: cpu(method, variant),
            gpu_x_exact: gpu(method),
            de_max: [of("conductor"), of("dielectric")],
            within: (values.iter().filter(|v| v.1 <= bound).count(), values.len()),
        }
    };
    let mut rows = Vec::new();
    if let Some(me) = inputs.extra.get("method_errors.csv") {
        let mut methods: Vec<&str> = Vec::new();
        for r in me.rows.iter().filter(|r| me.text(r, "source") == "three-channel") {
            let m = me.text(r, "method");
            if !methods.contains(&m) {
                methods.push(m);
            }
        }
        let values = |method: &str, variant: &str| -> Vec<(String, f64)> {
            me.rows
                .iter()
                .filter(|r| me.text(r, "method") == method && me.text(r, "variant") == variant)
                .filter_map(|r| Some((me.text(r, "kind").to_string(), me.number(r, "de2000_max")?)))
                .collect()
        };
        for m in methods {
            rows.push(row(m, "three-channel (n, k)", "", values(m, "")));
        }
        if let Some(engine) = inputs.extra.get("engine_params.csv") {
            for (model, shader, from) in ENGINE_MODELS {
                let v: Vec<(String, f64)> = engine
                    .rows
                    .iter()
                    .filter_map(|r| Some((engine.text(r, "kind").to_string(), engine.number(r, &format!("{model}_de2000_max"))?)))
                    .collect();
                if !v.is_empty() {
                    rows.push(row(shader, from, "", v));
                }
            }
        }
        for variant in TABLE_LUTS {
            let v = values("lut", variant);
            if !v.is_empty() {
                rows.push(row("lut", "spectral curve", variant, v));
            }
        }
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sig3_keeps_three_significant_digits() {
        assert_eq!(sig3(0.123456), "0.123");
        assert_eq!(sig3(12.345), "12.3");
        assert_eq!(sig3(1.0), "1");
        assert_eq!(sig3(2500.0), "2500");
        assert_eq!(sig3(0.000_512_3), "0.000512");
    }

    /// Hand-derived: three-wavelength's worst object is 0.4 at 1+0, max(1.5, 0.9) = 1.5 at
    /// 2+0 (above 1: the first such depth), 2.5 at 3+0; effective stays at or under 0.8.
    #[test]
    fn spectral_finding_names_the_first_depth_above_the_bound() {
        let csv = "object,object_index,material,index_source,reflection_depth,refraction_depth,mean_delta_e2000\n\
                   sphere,0,au,three-wavelength,3,0,2.5\nsphere,0,au,three-wavelength,1,0,0.4\nsphere,0,au,three-wavelength,2,0,1.5\n\
                   cube,1,au,three-wavelength,2,0,0.9\nsphere,0,au,effective,1,0,0.2\nsphere,0,au,effective,2,0,0.5\nsphere,0,au,effective,3,0,0.8\n";
        let t = CsvTable::parse(csv.as_bytes()).unwrap();
        let f = spectral_finding("gig", "gig/spectral_errors.csv", &t, 1.0).unwrap();
        assert_eq!(
            f.text(),
            "In gig, three channels against the spectral reference (mean ΔE2000 over an object's pixels, the worst object): three-wavelength 0.4 at depth 1+0 to 2.5 at depth 3+0, first above ΔE2000 1 at depth 2+0 (1.5); effective 0.2 at depth 1+0 to 0.8 at depth 3+0, within ΔE2000 1 at every depth."
        );
        assert!(f.figures().iter().any(|x| x.key == "spectral:gig:three-wavelength:2+0" && x.value == 1.5));
        assert_eq!(f.link.0, "effects.html#scene-gig");
    }

    /// Hand-derived, surfel-weighted: tree 1 pass (0.2·100 + 0.1·300)/400 = 0.125, tree 2
    /// passes (0.1·100 + 0.02·300)/400 = 0.04 (the smallest), brute force 0.3; its CPU
    /// mean(20, 20) = 20 ms; per pixel, GTAO (0.1·50 + 0.02·150)/200 = 0.04 against the
    /// tree's (0.2·50 + 0.04·150)/200 = 0.08.
    #[test]
    fn ao_finding_states_the_best_surfels_and_gtao_beside_them() {
        let csv = "mesh,hierarchy,passes,technique,surfels,mean_error,cpu_ms,pixels,pixel_mean_error\n\
                   bunny,true,1,surfels,100,0.2,10,50,0.25\nslab,true,1,surfels,300,0.1,10,150,0.05\n\
                   bunny,true,2,surfels,100,0.1,20,50,0.2\nslab,true,2,surfels,300,0.02,20,150,0.04\n\
                   bunny,false,2,surfels,100,0.3,40,50,0.3\nslab,false,2,surfels,300,0.3,40,150,0.3\n\
                   bunny,,,gtao,,,,50,0.1\nslab,,,gtao,,,,150,0.02\n";
        let t = CsvTable::parse(csv.as_bytes()).unwrap();
        let f = ao_finding("ao", "ao/ao_errors.csv", &t).unwrap();
        assert_eq!(
            f.text(),
            "In ao, surfel ambient occlusion is closest to the ray-traced reference with the tree and 2 pass(es): mean accessibility error 0.04 over surfels in 20 ms of CPU (one pass: 0.125); per covered pixel, GTAO's mean error is 0.04 against those surfels' 0.08."
        );
        let value = |key: &str| f.figures().iter().find(|x| x.key == key).unwrap().value;
        for (key, expected) in [("ao:ao:best", 0.04), ("ao:ao:one-pass", 0.125), ("ao:ao:gtao-pixel", 0.04), ("ao:ao:surfel-pixel", 0.08)] {
            assert!((value(key) - expected).abs() < 1e-15, "{key}: {}", value(key));
        }
    }

    #[test]
    fn most_frequent_counts_picks_and_breaks_ties_by_name() {
        let t = CsvTable::from_rows(
            vec!["method".into(), "parameters_from".into()],
            vec![
                vec!["lut".into(), "spectral curve".into()],
                vec!["exact".into(), "fitted (n, k)".into()],
                vec!["lut".into(), "spectral curve".into()],
                vec!["".into(), "".into()],
            ],
        );
        let rows: Vec<&Vec<String>> = t.rows.iter().collect();
        assert_eq!(most_frequent(&t, &rows), Some(("lut (spectral curve)".into(), 2)));
        assert_eq!(most_frequent(&t, &rows[1..2]), Some(("exact (fitted (n, k))".into(), 1)));
        // One each: "exact …" comes before "lut …".
        assert_eq!(most_frequent(&t, &rows[..2]), Some(("exact (fitted (n, k))".into(), 1)));
    }
}
