//! The report's index, `report/index.html` (and `report.md`): where the pages come from
//! and where they went, what accuracy costs, where each approximation is worst, and a
//! sortable, filterable list of the materials linking to their pages. Light: no curves.

use nklut_tables::gpu_tables::gpu_timing;
use std::collections::BTreeMap;
use std::fmt::Write;

use anyhow::Result;

use super::charts::{self, CostPoint};
use super::context::{channel_flags, channel_triple, display_name, fitted_index, material_path, Context};
use super::csvdata::CsvTable;
use super::findings;
use super::html::{code_spans, delta_e, escape, href, markdown_text, number, percent, raw, TableText, MARKDOWN};
use super::inputs::{self, Count};
use super::page::at_bound;

/// HTML and Markdown written side by side.
pub struct Builder {
    pub html: String,
    pub markdown: String,
}

impl Builder {
    fn heading(&mut self, level: usize, id: &str, text: &str) {
        let _ = writeln!(self.html, "<h{level} id=\"{}\">{}</h{level}>", escape(id), escape(text));
        let _ = writeln!(self.markdown, "\n{} {}\n", "#".repeat(level), markdown_text(text));
    }

    /// A small note (where a section's figures come from); nothing when empty.
    fn note(&mut self, text: &str) {
        if !text.is_empty() {
            let _ = writeln!(self.html, "<p class=\"note\">{}</p>", code_spans(text));
            let _ = writeln!(self.markdown, "{}\n", markdown_text(text));
        }
    }

    fn paragraph(&mut self, text: &str) {
        let _ = writeln!(self.html, "<p>{}</p>", escape(text));
        let _ = writeln!(self.markdown, "{}\n", markdown_text(text));
    }

    /// A paragraph with counts: `parts` alternate text and counts.
    fn counted(&mut self, parts: &[Part]) {
        let mut html = String::from("<p>");
        let mut markdown = String::new();
        for part in parts {
            match part {
                Part::Text(t) => {
                    html.push_str(&escape(t));
                    markdown.push_str(&markdown_text(t));
                }
                Part::Count(c) => {
                    html.push_str(&c.html());
                    markdown.push_str(&c.value.to_string());
                }
            }
        }
        let _ = writeln!(self.html, "{html}</p>");
        let _ = writeln!(self.markdown, "{markdown}\n");
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
        let _ = writeln!(self.html, "<figure class=\"plot\">{svg}<figcaption>{}</figcaption></figure>", escape(caption));
        let _ = writeln!(self.markdown, "*(figure in index.html: {})*\n", markdown_text(caption));
    }
}

/// Text or a count in a sentence.
pub enum Part {
    Text(String),
    Count(Count),
}

fn t(text: &str) -> Part {
    Part::Text(text.to_string())
}

const SORT_SCRIPT: &str = "function nkFilter(q){q=q.toLowerCase();for(const r of document.querySelectorAll('#materials-table tbody tr')){r.style.display=r.dataset.key.includes(q)?'':'none'}}\
function nkSort(th){const table=th.closest('table'),i=[...th.parentNode.children].indexOf(th),body=table.tBodies[0],up=th.dataset.dir!=='up';th.dataset.dir=up?'up':'down';\
const key=r=>{const c=r.children[i];const v=c.dataset.sort;return v===undefined?c.textContent:parseFloat(v)};\
[...body.rows].sort((a,b)=>{const x=key(a),y=key(b);const o=typeof x==='number'&&typeof y==='number'?x-y:String(x).localeCompare(String(y));return up?o:-o}).forEach(r=>body.appendChild(r))}";

/// The index page and its Markdown twin.
pub fn index_page(ctx: &Context, pages: &[String], gallery: (String, String)) -> Result<Builder> {
    let mut b = Builder { html: String::new(), markdown: String::new() };
    let _ = write!(
        b.html,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>nklut report</title><style>{}{ANSWER_STYLE}</style><script>{SORT_SCRIPT}</script></head><body>\n",
        super::STYLE
    );
    b.heading(1, "top", "nklut report: Fresnel methods per material");
    answer(&mut b, ctx);
    let nm = ctx.inputs.channels.nanometres();
    b.paragraph(&format!("Channel wavelengths (materials.csv): red {} nm, green {} nm, blue {} nm. Errors are relative, in percent; indices have 4 decimals.", nm[0], nm[1], nm[2]));
    overview(&mut b, ctx.inputs);
    cost_section(&mut b, ctx.inputs)?;
    summaries(&mut b, ctx);
    materials_list(&mut b, ctx, pages)?;
    b.html.push_str(&gallery.0);
    b.markdown.push_str(&gallery.1);
    b.html.push_str("</body></html>\n");
    Ok(b)
}

/// The first screen's layout: findings beside the recommendation per class and device,
/// the decision table under them; one column below 1000 px.
const ANSWER_STYLE: &str = "#answer h2{margin:0.3em 0}.answer-links{margin:0.2em 0 0.5em;font-size:14px}\
.answer-grid{display:grid;grid-template-columns:minmax(0,1.1fr) minmax(0,1fr);gap:0 20px}@media (max-width:1000px){.answer-grid{grid-template-columns:minmax(0,1fr)}}\
ul.findings{margin:0;padding-left:1.1em;font-size:14px;line-height:1.3}ul.findings li{margin:0 0 4px}\
#answer table{font-size:13px;margin:0.2em 0 0.6em}#answer td,#answer th{padding:1px 5px}#answer h3{font-size:15px;margin:0.2em 0}\
.answer-scroll{overflow-x:auto;max-width:100%}";

/// The decision, first: findings, what to ship per class and device (recommendations.csv),
/// and the table per method. Every figure a `span.figure` with its full value.
fn answer(b: &mut Builder, ctx: &Context) {
    let inputs = ctx.inputs;
    let Some(recs) = inputs.extra.get("recommendations.csv") else {
        b.paragraph("recommendations.csv is absent: run `nklut recommend` for the decision (the cheapest method within a stated error bound, per material and device).");
        return;
    };
    let bound = findings::bound(Some(recs));
    let _ = writeln!(b.html, "<section id=\"answer\">");
    b.heading(
        2,
        "answer-heading",
        &format!("The answer: what to ship (ΔE2000 ≤ {} against the spectral curve at every angle)", findings::sig3(bound)),
    );
    let effects_link = if inputs.devices.is_empty() && !inputs.extra.keys().any(|k| k.contains('/')) {
        String::new()
    } else {
        " · <a href=\"effects.html\">the effects page</a> · <a href=\"effects.html#devices\">across devices (#devices)</a>".into()
    };
    let _ = writeln!(
        b.html,
        "<p class=\"answer-links\">From recommendations.csv, method_errors.csv, engine_params.csv, cost.csv and the devices folder{effects_link} · <a href=\"#materials\">the material pages</a> · <a href=\"#cost\">what accuracy costs</a></p>"
    );
    let _ = writeln!(b.markdown, "From recommendations.csv, method_errors.csv, engine_params.csv, cost.csv and the devices folder.\n");
    let _ = writeln!(b.html, "<div class=\"answer-grid\"><div>");
    let found = findings::findings(inputs, &|page| material_path(page).map(|p| href(&p)).unwrap_or_default());
    let _ = writeln!(b.html, "<h3 id=\"findings\">Findings</h3><ul class=\"findings\">");
    for f in &found {
        let _ = writeln!(b.html, "{}", f.html());
        let _ = writeln!(b.markdown, "- {}", markdown_text(&f.text()));
    }
    let _ = writeln!(b.html, "</ul></div><div>");
    b.markdown.push('\n');
    // Per class and device: the most frequent pick, how many pages, the worst error and median cost of the picks.
    let devices = findings::devices(recs);
    let _ = writeln!(b.html, "<h3 id=\"answer-picks\">Per material class and device</h3>");
    let mut table = TableText::new(&["class", "device", "pick (most pages)", "pages", "ΔE2000 max (worst pick)", "× exact (median)"]);
    for kind in ["conductor", "dielectric"] {
        for device in &devices {
            let rows: Vec<&Vec<String>> =
                recs.rows.iter().filter(|r| recs.text(r, "kind") == kind && recs.text(r, "device") == device).collect();
            let Some((group, n)) = findings::most_frequent(recs, &rows) else { continue };
            let worst = rows.iter().filter_map(|r| recs.number(r, "de2000_max")).fold(f64::NAN, f64::max);
            let x: Vec<f64> = rows.iter().filter_map(|r| recs.number(r, "cost_x_exact")).collect();
            let fig = |key: String, v: f64| raw(findings::figure_span(&key, v));
            table.row(vec![
                kind.to_string(),
                findings::short_device(device),
                group.clone(),
                raw(format!(
                    "<span class=\"figure\" data-key=\"pick-count:{kind}:{}:{}\" data-value=\"{n}\">{n}</span> of {}",
                    escape(device),
                    escape(&group),
                    rows.len()
                )),
                fig(format!("picks-worst-de:{kind}:{device}"), worst),
                crate::stats::median(&x).map(|m| fig(format!("picks-median-x:{kind}:{device}"), m)).unwrap_or_else(|| "–".into()),
            ]);
        }
    }
    b.table(&table, "answer-picks");
    let _ = writeln!(b.html, "</div></div>");
    // The decision table per method.
    let rows = findings::method_rows(inputs, &devices.iter().filter(|d| *d != "CPU").cloned().collect::<Vec<_>>());
    let gpu_devices: Vec<&String> = devices.iter().filter(|d| *d != "CPU").collect();
    let _ = writeln!(
        b.html,
        "<h3 id=\"answer-methods\">Per method: cost and error against the spectral curve (ΔE2000 max over angle, over pages)</h3>"
    );
    let mut headers: Vec<String> = vec!["method".into(), "parameters from".into(), "CPU ns/eval".into()];
    headers.extend(gpu_devices.iter().map(|d| format!("× exact on {}", findings::short_device(d))));
    headers.extend([
        "conductors: median / p95".to_string(),
        "dielectrics: median / p95".to_string(),
        format!("pages within {}", findings::sig3(bound)),
    ]);
    let header_refs: Vec<&str> = headers.iter().map(String::as_str).collect();
    let mut table = TableText::new(&header_refs);
    for r in &rows {
        let id = format!("{}|{}|{}", r.method, r.parameters_from, r.variant);
        let fig = |key: &str, v: f64| findings::figure_span(&format!("{key}:{id}"), v);
        let mut cells = vec![
            if r.variant.is_empty() { r.method.clone() } else { format!("{} {}", r.method, r.variant) },
            r.parameters_from.clone(),
            r.cpu_ns.map(|v| raw(fig("cpu-ns", v))).unwrap_or_else(|| "–".into()),
        ];
        for (d, x) in gpu_devices.iter().zip(&r.gpu_x_exact) {
            cells.push(x.map(|v| raw(fig(&format!("x-exact:{d}"), v))).unwrap_or_else(|| "–".into()));
        }
        for (k, spread) in ["conductor", "dielectric"].iter().zip(&r.de_max) {
            cells.push(match spread {
                Some((m, p)) => raw(format!("{} / {}", fig(&format!("de-median:{k}"), *m), fig(&format!("de-p95:{k}"), *p))),
                None => "–".into(),
            });
        }
        cells.push(raw(format!("{} of {}", fig("within", r.within.0 as f64), r.within.1)));
        table.row(cells);
    }
    let _ = writeln!(b.html, "<div class=\"answer-scroll\">");
    b.table(&table, "answer-methods");
    let _ = writeln!(b.html, "</div></section>");
}

fn overview(b: &mut Builder, inputs: &inputs::Inputs) {
    b.heading(2, "overview", "Overview");
    b.note(&inputs.provenance(&["materials.csv", "excluded.csv"]));
    let kept = inputs::rows("materials.csv", &inputs.materials);
    let excluded = inputs::rows("excluded.csv", &inputs.excluded);
    b.counted(&[
        t("Pages kept: "),
        Part::Count(kept),
        t("; excluded: "),
        Part::Count(excluded),
        t(" (each with its reason, file and line in excluded.csv)."),
    ]);
    let mut reasons = TableText::new(&["exclusion reason", "pages"]);
    for count in inputs::exclusions_by_reason(&inputs.excluded) {
        let reason = count.key.trim_start_matches("reason=").to_string();
        reasons.rows.push(vec![reason, raw(count.html())]);
    }
    b.table(&reasons, "reasons");
    if let Some(warnings) = &inputs.warnings {
        b.counted(&[t("Data warnings kept with their page (warnings.csv): "), Part::Count(inputs::rows("warnings.csv", warnings)), t(".")]);
    }
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

fn floor_note(at_floor: &[String]) -> String {
    if at_floor.is_empty() {
        String::new()
    } else {
        format!(" {} has error 0 (it is the reference) and is drawn at the axis floor as an open triangle.", at_floor.join(", "))
    }
}

/// "What accuracy costs": analytic methods against CPU ns (and GPU ms when measured);
/// LUTs against texture bytes. Errors are means over materials from cost.csv; medians
/// beside them because a few near-zero-F materials (gases) dominate means.
fn cost_section(b: &mut Builder, inputs: &inputs::Inputs) -> Result<()> {
    b.heading(2, "cost", "What accuracy costs");
    b.note(&inputs.provenance(&["cost.csv", "gpu_timing.csv"]));
    let Some(cost) = &inputs.cost else {
        b.paragraph("cost.csv is absent: run `nklut validate` to measure each method's error and cost.");
        return Ok(());
    };
    let rows = cost_rows(cost);
    let gpu = gpu_medians(inputs);
    let methods: Vec<&CostRow> = rows.iter().filter(|r| r.method != "lut" || r.variant.starts_with("N=256,")).collect();
    let flags = charts::pareto_front(&methods.iter().map(|r| (r.ns_per_eval, r.mean)).collect::<Vec<_>>());
    let mut table = TableText::new(&[
        "method",
        "variant",
        "mean relative error",
        "median relative error",
        "CPU ns/eval",
        "GPU ms (median)",
        "Pareto (CPU)",
    ]);
    for (r, &on) in methods.iter().zip(&flags) {
        table.row(vec![
            r.method.clone(),
            r.variant.clone(),
            percent(r.mean),
            percent(r.median),
            number(r.ns_per_eval),
            gpu.get(&r.method).map(|&ms| number(ms)).unwrap_or_else(|| "–".into()),
            if on { "yes".into() } else { String::new() },
        ]);
    }
    let points: Vec<CostPoint> = methods
        .iter()
        .zip(&flags)
        .map(|(r, &pareto)| CostPoint {
            label: short_label(&r.method, &r.variant),
            cost: r.ns_per_eval,
            error: r.mean,
            pareto,
            trace: None,
            style: None,
        })
        .collect();
    if points.iter().any(|p| p.cost.is_finite()) {
        let chart = charts::cost_chart(&points, "CPU time per evaluation (ns)", charts::ErrorAxis::Relative, (900, 460))?;
        b.figure(&chart.svg, &format!("Mean relative error over materials against CPU time per evaluation; the Pareto front is joined and labelled, every point is in the table below and named on hover.{}", floor_note(&chart.at_floor)));
    } else {
        b.paragraph("CPU cost per evaluation is not recorded yet (run `make bench` and record the figures in benchmarks/fresnel_cpu.csv).");
    }
    b.table(&table, "cost");
    match &inputs.gpu_timing {
        Some(t) if !gpu.is_empty() => {
            let mut adapters: Vec<String> = t
                .rows
                .iter()
                .map(|r| format!("{} ({}, {} timer)", t.text(r, "adapter"), t.text(r, "driver"), t.text(r, "timer")))
                .collect();
            adapters.dedup();
            let software = adapters.iter().any(|a| a.contains("llvmpipe") || a.contains("lavapipe") || a.contains("SwiftShader"));
            b.paragraph(&format!(
                "GPU ms: median over materials of gpu_timing.csv, measured on {}{}",
                adapters.join("; "),
                if software { ". This adapter is a CPU rasteriser: its times show ratios between methods, not GPU cost." } else { "." }
            ));
        }
        _ => b.paragraph("GPU time: gpu_timing.csv is absent (run `make gpu`, which needs the gpu feature and a GPU)."),
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
    let flags = charts::pareto_front(&luts.iter().map(|r| (r.texture_bytes, r.mean)).collect::<Vec<_>>());
    let points: Vec<CostPoint> = luts
        .iter()
        .zip(&flags)
        .map(|(r, &pareto)| CostPoint {
            label: r.variant.trim_end_matches(",f64").to_string(),
            cost: r.texture_bytes,
            error: r.mean,
            pareto,
            trace: None,
            style: None,
        })
        .collect();
    let chart = charts::cost_chart(&points, "texture size (bytes: N texels × 3 channels)", charts::ErrorAxis::Relative, (900, 460))?;
    b.figure(&chart.svg, &format!("LUT mean relative error over materials against texture size; the Pareto front is joined and labelled, the rest are in the table and named on hover.{}", floor_note(&chart.at_floor)));
    let mut table =
        TableText::new(&["LUT (texels, encoding)", "texture bytes", "mean relative error", "median relative error", "Pareto (bytes)"]);
    for (r, &on) in luts.iter().zip(&flags) {
        table.row(vec![
            r.variant.trim_end_matches(",f64").to_string(),
            format!("{}", r.texture_bytes),
            percent(r.mean),
            percent(r.median),
            if on { "yes".into() } else { String::new() },
        ]);
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
fn gpu_medians(inputs: &inputs::Inputs) -> BTreeMap<String, f64> {
    let mut by_method: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    if let Some(t) = &inputs.gpu_timing {
        for r in &t.rows {
            if let Some(ms) = t.value(r, gpu_timing::MEDIAN_MS) {
                by_method.entry(t.get(r, gpu_timing::METHOD).to_string()).or_default().push(ms);
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

fn summaries(b: &mut Builder, ctx: &Context) {
    let inputs = ctx.inputs;
    b.heading(2, "summaries", "Where each approximation is worst");
    b.note(&ctx.inputs.provenance(&["errors.csv", "colors.csv"]));
    match &inputs.errors {
        Some(errors) => {
            let mut by_method: BTreeMap<(String, String), Vec<(String, f64)>> = BTreeMap::new();
            for ((page, method, variant), e) in material_errors(errors, "mean_rel_error") {
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
            b.heading(3, "fallback", "Where compensated Schlick falls back");
            let fallbacks = inputs::compensation_fallbacks(errors);
            let counts = inputs::fallback_counts(&fallbacks);
            let mut parts = vec![t("Page-channels of errors.csv where compensated Schlick has no real exponent that makes it exact at 84.26° (it uses schlick_nk there): "), Part::Count(counts[0].clone())];
            for c in &counts[1..] {
                parts.push(t(&format!("; {} ", c.key.trim_start_matches("fallback="))));
                parts.push(Part::Count(c.clone()));
            }
            parts.push(t(if fallbacks.is_empty() { "." } else { ". Pages: " }));
            if !fallbacks.is_empty() {
                parts.push(t(&fallbacks.iter().map(|(p, c, _)| format!("{p} ({c})")).collect::<Vec<_>>().join(", ")));
            }
            b.counted(&parts);
        }
        None => {
            b.paragraph("errors.csv is absent: run `nklut validate`.");
            b.heading(3, "fallback", "Where compensated Schlick falls back");
            b.paragraph("Not measured: errors.csv is absent (run `nklut validate`).");
        }
    }
    b.heading(3, "unusual", "Unusual values");
    let sparse = inputs.materials.rows_where("sparse", "true").count();
    b.counted(&[
        t("Kept pages with tabulated rows more than 50 nm apart in 390–700 nm (materials.csv, sparse): "),
        Part::Count(Count { table: "materials.csv", key: "sparse".into(), value: sparse }),
        t("."),
    ]);
    if let Some(colors) = &inputs.colors {
        let gamut = inputs::flagged_pages(colors, "out_of_gamut").len();
        let extrapolated = inputs::extrapolated_pages(colors).len();
        b.counted(&[
            t("Pages whose spectral F0 lies outside [0, 1] of linear sRGB in some channel (colors.csv, out_of_gamut): "),
            Part::Count(Count { table: "colors.csv", key: "out-of-gamut".into(), value: gamut }),
            t("; pages whose spectral colour holds n and k beyond the data's range (colors.csv, extrapolated_share > 0): "),
            Part::Count(Count { table: "colors.csv", key: "extrapolated".into(), value: extrapolated }),
            t("."),
        ]);
    }
    if let Some(c) = &inputs.colors {
        let bound = c.rows.iter().filter(|r| fitted_index(c, r).iter().any(|i| at_bound(*i))).count();
        b.counted(&[
            t("Pages with a fitted index on the edge of the fit's search box (colors.csv, effective_n/effective_k; explained on their pages): "),
            Part::Count(Count { table: "colors.csv", key: "fit-at-bound".into(), value: bound }),
            t("."),
        ]);
    }
}

/// The materials: one row each, sortable by any column, filterable by text.
fn materials_list(b: &mut Builder, ctx: &Context, pages: &[String]) -> Result<()> {
    b.heading(2, "materials", &format!("Materials ({})", pages.len()));
    let _ = writeln!(b.html, "<p><input id=\"search\" placeholder=\"filter by page, name or kind\" oninput=\"nkFilter(this.value)\"> Click a column heading to sort.</p>");
    let m = ctx.materials.table;
    let _ = writeln!(
        b.html,
        "<div class=\"wide\"><table id=\"materials-table\" class=\"materials\"><thead><tr>{}</tr></thead><tbody>",
        [
            "page",
            "names",
            "kind",
            "F0",
            "ΔE2000 F0",
            "three-channel error over angle (worst channel)",
            "fitted error (worst channel)",
            "notes"
        ]
        .iter()
        .map(|h| format!("<th onclick=\"nkSort(this)\">{}</th>", escape(h)))
        .collect::<String>()
    );
    let mut markdown = TableText::new(&["page", "names", "kind", "ΔE2000 F0"]);
    for page in pages {
        let row = ctx.materials.first(page).expect("selected from materials.csv");
        let link = href(&material_path(page)?);
        let names = display_name(m, row);
        let names = names.as_str();
        let kind = m.text(row, "kind");
        let key = escape(&format!("{page} {names} {kind}").to_lowercase());
        let color = ctx.colors.as_ref().and_then(|c| c.first(page).map(|r| (c.table, r)));
        let (swatch, de, index_error, fitted_error, notes) = match color {
            Some((c, r)) => {
                let worst = |prefix| channel_triple(c, r, prefix).into_iter().fold(f64::NAN, f64::max);
                let mut notes = Vec::new();
                if channel_flags(c, r, "out_of_gamut").contains(&true) {
                    notes.push("out of gamut");
                }
                if fitted_index(c, r).iter().any(|i| at_bound(*i)) {
                    notes.push("fit at bound");
                }
                if c.number(r, "extrapolated_share").is_some_and(|s| s > 0.0) {
                    notes.push("extrapolated");
                }
                (
                    super::swatch(channel_triple(c, r, "f0_spectral")),
                    c.number(r, "delta_e2000_f0").unwrap_or(f64::NAN),
                    worst("index_error_angle"),
                    worst("effective_error"),
                    notes,
                )
            }
            None => (String::new(), f64::NAN, f64::NAN, f64::NAN, vec!["no colours"]),
        };
        let mut notes = notes;
        if m.text(row, "sparse") == "true" {
            notes.push("sparse");
        }
        let sort = |v: f64| if v.is_finite() { format!(" data-sort=\"{v}\"") } else { " data-sort=\"-1\"".into() };
        let _ = writeln!(
            b.html,
            "<tr data-key=\"{key}\"><td><a href=\"{link}\">{}</a></td><td>{}</td><td>{}</td><td>{swatch}</td><td{}>{}</td><td{}>{}</td><td{}>{}</td><td>{}</td></tr>",
            escape(page),
            escape(names),
            escape(kind),
            sort(de),
            delta_e(de),
            sort(index_error),
            percent(index_error),
            sort(fitted_error),
            percent(fitted_error),
            escape(&notes.join(", "))
        );
        markdown.row(vec![format!("{MARKDOWN}[{}]({link})", markdown_text(page)), names.to_string(), kind.to_string(), delta_e(de)]);
    }
    b.html.push_str("</tbody></table></div>\n");
    b.markdown.push_str(&markdown.markdown());
    b.markdown.push('\n');
    Ok(())
}
