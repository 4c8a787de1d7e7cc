//! One material's page, `report/materials/<id>.html`: previews (spheres under a studio
//! environment), the colour over angle, ΔE2000 over angle, F(θ) per channel, the
//! indices, colours and errors of the tables, each unusual value explained where it
//! appears, and the engine parameters when `engine_params.csv` exists.

use std::fmt::Write;

use anyhow::Result;

use super::charts::{self, DeltaE, Drawn};
use super::context::{
    channel_flags, channel_triple, display_name, fitted_index, preview_path, three_channel_index, up_from_material, Context,
};
use super::curves::{delta_e_over_angle, material_curves, PlotCurve};
use super::html::{delta_e, escape, href, index, percent, reflectance, TableText};
use super::preview;
use nklut_optics::color::fit::{K_MAX, N_BOUNDS};
use nklut_optics::spectrum::{Index, CHANNEL_NAMES};

/// A finished material page and its preview image.
pub struct MaterialPage {
    pub page: String,
    pub html: String,
    /// PNG of the preview spheres side by side (also embedded in `html`).
    pub preview_png: Option<Vec<u8>>,
}

/// A note on an unusual value, shown under the table where the value appears.
fn notes_html(notes: &[String]) -> String {
    if notes.is_empty() {
        return String::new();
    }
    let items: String = notes.iter().map(|n| format!("<li>{}</li>", escape(n))).collect();
    format!("<ul class=\"notes\">{items}</ul>\n")
}

/// Whether a fitted index sits on the fit's search box.
pub fn at_bound(index: Index) -> bool {
    let near = |value: f64, bound: f64| (value - bound).abs() <= 1e-6 * bound;
    near(index.n, N_BOUNDS.0) || near(index.n, N_BOUNDS.1) || near(index.k, K_MAX)
}

/// Build the page of `page`; `spectrum` is its index on the 1 nm grid (None when the
/// data file could not be read, said on the page).
pub fn material_page(ctx: &Context, page: &str, spectrum: Result<&[Index], &str>) -> Result<MaterialPage> {
    let m = ctx.materials.table;
    let row = ctx.materials.first(page).expect("selected pages are rows of materials.csv");
    let up = up_from_material(page);
    let mut html = String::new();
    let title = format!("{page} — {}", display_name(m, row));
    let _ = write!(
        html,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>{}</title><style>{}</style></head><body>\n<p class=\"nav\"><a href=\"{}index.html\">← all materials</a></p>\n<h1>{}</h1>\n<p>{} · data file <code>{}</code> · {}</p>\n",
        escape(&title),
        super::STYLE,
        href(&up),
        escape(&title),
        escape(m.text(row, "kind")),
        escape(m.text(row, "data_file")),
        escape(m.text(row, "reference"))
    );
    let three = three_channel_index(m, row);
    let color_row = ctx.colors.as_ref().and_then(|c| c.first(page).map(|r| (c.table, r)));
    let fitted = color_row.map(|(c, r)| fitted_index(c, r));
    let mut preview_png = None;
    match spectrum {
        Ok(spectrum) => {
            let curves = material_curves(spectrum, &three, fitted.as_ref(), &ctx.theta, &ctx.inputs.fits);
            // A dielectric is seen through: the light through the sphere added to the reflection.
            let through =
                (m.text(row, "kind") == "dielectric").then(|| preview::transmitted(&ctx.layout, &three, ctx.inputs.channels.nanometres()));
            let spheres: Vec<&[[f64; 3]]> = curves.iter().map(|c| c.rgb.as_slice()).collect();
            let png = preview::png(&preview::sheet_through(&ctx.layout, &spheres, through.as_deref()))?;
            figures(&mut html, ctx, page, &curves, &png)?;
            preview_png = Some(png);
        }
        Err(problem) => {
            let _ = writeln!(html, "<p class=\"note\">No previews or curves: the page's data could not be read ({}).</p>", escape(problem));
        }
    }
    indices_section(&mut html, ctx, page, row);
    if let Some((c, r)) = color_row {
        colours_section(&mut html, c, r, m.number(row, "lambda_min_nm"), m.number(row, "lambda_max_nm"));
    } else {
        html.push_str("<p class=\"note\">colors.csv has no row for this page: run <code>nklut colors</code> for spectral colours and fitted indices.</p>\n");
    }
    errors_section(&mut html, ctx, page);
    params_section(&mut html, ctx, page);
    warnings_section(&mut html, ctx, page);
    html.push_str("</body></html>\n");
    Ok(MaterialPage { page: page.to_string(), html, preview_png })
}

/// Previews, colour strips, ΔE over angle and F(θ) with an HTML legend beside.
fn figures(html: &mut String, ctx: &Context, page: &str, curves: &[PlotCurve], png: &[u8]) -> Result<()> {
    let reference = &curves[0];
    let size = ctx.layout.size();
    // One sheet of spheres (the file written beside the page, embedded once as a data URI),
    // each sphere shown from it at its natural size in a box of its own, so the boxes wrap
    // on a narrow page.
    let _ = write!(
        html,
        "<h2 id=\"previews\">Previews</h2>\n<p class=\"note\">Spheres under a studio light (a soft box behind the camera, a bright strip, a rim light), shaded with each curve (schlick_nk draws the same curve as schlick and is not repeated); a dielectric seen through, the light refracted through a sphere 2 cm across (Snell at each channel's n, absorption exp(−4πk/λ·path), internal reflections left out); colours clamped to sRGB. Also written as <code>{}</code>, the spheres side by side.</p>\n<figure class=\"previews\"><div class=\"spheres\" data-sheet-width=\"{}\" style=\"--sheet:url({})\">",
        escape(&preview_path(page)),
        size as usize * curves.len(),
        preview::data_uri(png),
    );
    // Every curve after the reference, against it.
    let series: Vec<DeltaE> =
        curves[1..].iter().zip(delta_e_over_angle(reference, &curves[1..])).map(|(curve, values)| DeltaE { curve, values }).collect();
    let mean_de = std::iter::once(None).chain(series.iter().map(|s| Some(mean(&s.values))));
    for (i, (c, de)) in curves.iter().zip(mean_de).enumerate() {
        let detail = de.map_or_else(|| "reference".to_string(), |de| format!("mean ΔE {}", delta_e(de)));
        let _ = write!(
            html,
            "<div class=\"sphere-cell\" style=\"width:{size}px\"><div class=\"sphere\" role=\"img\" aria-label=\"{} shaded with {}\" style=\"width:{size}px;height:{size}px;background-position:-{}px 0\"></div><span class=\"method\">{}<br>{}</span></div>",
            escape(page),
            escape(&c.name),
            i as u32 * size,
            escape(&c.name),
            detail
        );
    }
    html.push_str("</div></figure>\n<h2 id=\"angle\">Colour over angle</h2>\n<div class=\"strips\">");
    for c in curves {
        let _ = write!(
            html,
            "<div class=\"strip-row\"><span class=\"strip-name\">{}</span><span class=\"strip\" style=\"background:{}\"></span></div>",
            escape(&c.name),
            preview::angle_gradient(&c.rgb)
        );
    }
    html.push_str("<div class=\"strip-row\"><span class=\"strip-name\"></span><span class=\"strip-axis\"><span>0°</span><span>30°</span><span>60°</span><span>90°</span></span></div></div>\n");
    html.push_str("<p class=\"note\">Reflected colour under white light from normal incidence (left) to grazing (right).</p>\n");
    let (chart, cut) = charts::delta_e_chart(&ctx.theta, &series, (760, 320))?;
    let cut = cut.map_or(String::new(), |c| format!("<figcaption>{}.</figcaption>", escape(&c)));
    let _ = write!(
        html,
        "<h2 id=\"delta-e\">Colour difference from the spectral reference</h2>\n<figure class=\"plot\">{chart}{}{cut}</figure>\n",
        charts::merged_legend_html(
            &series
                .iter()
                .map(|s| Drawn { name: &s.curve.name, color: s.curve.color, dashed: s.curve.dashed, values: s.values.clone() })
                .collect::<Vec<_>>()
        )
    );
    let _ = write!(
        html,
        "<h2 id=\"fresnel\">Reflectance per channel</h2>\n<figure class=\"plot\">{}{}</figure>\n",
        charts::fresnel_curves(&ctx.theta, curves, &ctx.inputs.channels, (900, 300))?,
        legend(curves)
    );
    Ok(())
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

/// An HTML legend (outside the plot): a line sample and the curve's name each, curves
/// hidden under another sharing its entry (`charts::merged_legend`).
fn legend(curves: &[PlotCurve]) -> String {
    let drawn: Vec<Drawn> = curves
        .iter()
        .map(|c| Drawn { name: &c.name, color: c.color, dashed: c.dashed, values: c.rgb.iter().flatten().copied().collect() })
        .collect();
    charts::merged_legend_html(&drawn)
}

fn indices_section(html: &mut String, ctx: &Context, page: &str, row: &[String]) {
    let nm = ctx.inputs.channels.nanometres();
    let three = three_channel_index(ctx.materials.table, row);
    let headers: Vec<String> = std::iter::once("index".to_string())
        .chain((0..3).flat_map(|c| [format!("n {} ({} nm)", CHANNEL_NAMES[c], nm[c]), format!("k {}", CHANNEL_NAMES[c])]))
        .collect();
    let mut table = TableText::new(&headers.iter().map(String::as_str).collect::<Vec<_>>());
    table.row(
        std::iter::once("three-channel (materials.csv)".to_string()).chain(three.iter().flat_map(|i| [index(i.n), index(i.k)])).collect(),
    );
    let mut notes = Vec::new();
    if let Some((c, r)) = ctx.colors.as_ref().and_then(|c| c.first(page).map(|r| (c.table, r))) {
        let fitted = fitted_index(c, r);
        let in_range = channel_flags(c, r, "reference_in_unit_range");
        let f0 = channel_triple(c, r, "f0_spectral");
        let mut cells = vec!["fitted to the spectral curve (colors.csv)".to_string()];
        for (ch, i) in fitted.iter().enumerate() {
            let mark = if at_bound(*i) { " †" } else { "" };
            cells.push(format!("{}{mark}", index(i.n)));
            cells.push(format!("{}{mark}", index(i.k)));
            if at_bound(*i) {
                let why = if in_range[ch] {
                    String::new()
                } else {
                    format!(" The spectral reference leaves [0, 1] (F0 {} = {}), and exact Fresnel never does, so the fit can only approach it.", CHANNEL_NAMES[ch], reflectance(f0[ch]))
                };
                notes.push(format!(
                    "† The fitted {} index reached the edge of the search box (n in [{}, {}], k ≤ {}): no index inside it matches better.{why}",
                    CHANNEL_NAMES[ch],
                    index(N_BOUNDS.0),
                    index(N_BOUNDS.1),
                    index(K_MAX)
                ));
            }
        }
        table.row(cells);
    }
    let _ = write!(html, "<h2 id=\"indices\">Indices</h2>\n{}{}", table.html("nk"), notes_html(&notes));
}

fn colours_section(html: &mut String, c: &super::csvdata::CsvTable, r: &[String], lambda_min: Option<f64>, lambda_max: Option<f64>) {
    let spectral = channel_triple(c, r, "f0_spectral");
    let three = channel_triple(c, r, "f0_three_channel");
    let gamut = channel_flags(c, r, "out_of_gamut");
    let gamut_angle = channel_flags(c, r, "out_of_gamut_angle");
    let mut table = TableText::new(&["F0 colour (linear sRGB)", "swatch", "red", "green", "blue"]);
    let mark = |v: f64, flagged: bool| if flagged { format!("{} ‡", reflectance(v)) } else { reflectance(v) };
    table.row(vec![
        "spectral reference".into(),
        super::html::raw(super::swatch(spectral)),
        mark(spectral[0], gamut[0]),
        mark(spectral[1], gamut[1]),
        mark(spectral[2], gamut[2]),
    ]);
    table.row(vec![
        "three-channel index".into(),
        super::html::raw(super::swatch(three)),
        reflectance(three[0]),
        reflectance(three[1]),
        reflectance(three[2]),
    ]);
    for (label, prefix) in [
        ("three-channel error at normal incidence", "index_error_f0"),
        ("three-channel error over angle", "index_error_angle"),
        ("fitted-index error over angle", "effective_error"),
    ] {
        let v = channel_triple(c, r, prefix);
        table.row(vec![label.into(), String::new(), percent(v[0]), percent(v[1]), percent(v[2])]);
    }
    let mut notes = Vec::new();
    for ch in 0..3 {
        if gamut[ch] {
            notes.push(format!(
                "‡ The spectral F0 {} = {} lies outside [0, 1] of linear sRGB (the colour is outside the sRGB gamut): the tables keep the value, the swatch and previews clamp it.",
                CHANNEL_NAMES[ch],
                reflectance(spectral[ch])
            ));
        } else if gamut_angle[ch] {
            notes.push(format!(
                "The spectral reference's {} channel leaves [0, 1] at some angle (not at normal incidence); the previews clamp it.",
                CHANNEL_NAMES[ch]
            ));
        }
    }
    let share = c.number(r, "extrapolated_share").unwrap_or(0.0);
    if share > 0.0 {
        notes.push(format!(
            "{} of the luminance weight lies outside the data's wavelength range ({}–{} nm), where n and k are held at the nearest measured value.",
            percent(share),
            lambda_min.map_or("?".into(), super::html::number),
            lambda_max.map_or("?".into(), super::html::number)
        ));
    }
    let _ = write!(
        html,
        "<h2 id=\"colours\">Colours</h2>\n{}<p>CIEDE2000 between the spectral and three-channel F0: {}</p>\n{}",
        table.html("colors"),
        delta_e(c.number(r, "delta_e2000_f0").unwrap_or(f64::NAN)),
        notes_html(&notes)
    );
}

/// The per-material error table: f64 methods, `exact` in f32 (the GPU-precision floor)
/// and LUTs at the default 256 texels; the full sweep is in errors.csv.
pub fn per_material_row(method: &str, variant: &str) -> bool {
    match method {
        "exact" => true,
        "lut" => variant.starts_with("N=256,") && variant.ends_with("f64"),
        _ => !variant.ends_with("f32"),
    }
}

fn errors_section(html: &mut String, ctx: &Context, page: &str) {
    let Some(errors) = &ctx.errors else {
        html.push_str("<p class=\"note\">errors.csv is absent: run <code>nklut validate</code> for each method's error.</p>\n");
        return;
    };
    let e = errors.table;
    let rows = errors.rows(page);
    if rows.is_empty() {
        html.push_str("<p class=\"note\">errors.csv has no row for this page: run <code>nklut validate</code> on it.</p>\n");
        return;
    }
    let mut table = TableText::new(&["method", "variant", "mean relative error red", "green", "blue", "max |F − F_exact|"]);
    let mut notes = Vec::new();
    let mut order: Vec<(&str, &str)> = Vec::new();
    let mut groups: std::collections::HashMap<(&str, &str), Vec<&[String]>> = std::collections::HashMap::new();
    for r in rows {
        let key = (e.text(r, "method"), e.text(r, "variant"));
        let group = groups.entry(key).or_default();
        if group.is_empty() {
            order.push(key);
        }
        group.push(r);
    }
    for (method, variant) in order {
        let group = &groups[&(method, variant)];
        if !per_material_row(method, variant) {
            continue;
        }
        let mut cells = vec![method.to_string(), variant.to_string()];
        for ch in CHANNEL_NAMES {
            let r = group.iter().find(|r| e.text(r, "channel") == ch);
            let fallback = r.map(|r| e.text(r, "fallback")).unwrap_or("");
            let value = r.and_then(|r| e.number(r, "mean_rel_error")).map_or("–".into(), percent);
            cells.push(if fallback.is_empty() { value } else { format!("{value} §") });
            if !fallback.is_empty() && e.text(r.unwrap(), "precision") == "f64" {
                notes.push(format!(
                    "§ Compensated Schlick has no real exponent for the {ch} channel ({fallback}) and falls back to schlick_nk there."
                ));
            }
            if let Some(skipped) = r.and_then(|r| e.number(r, "excluded_samples")).filter(|s| *s > 0.0) {
                notes.push(format!("{method} {variant} {ch}: {skipped} angles where F_exact = 0 are left out of the mean."));
            }
        }
        let max = group.iter().filter_map(|r| e.number(r, "max_abs_error")).fold(f64::NAN, f64::max);
        cells.push(super::html::number(max));
        table.row(cells);
    }
    notes.dedup();
    let _ = write!(html, "<h2 id=\"errors\">Method errors (errors.csv)</h2>\n{}{}", table.html("errors"), notes_html(&notes));
}

fn params_section(html: &mut String, ctx: &Context, page: &str) {
    let Some(params) = &ctx.params else { return };
    let Some(row) = params.first(page) else {
        html.push_str("<p class=\"note\">engine_params.csv has no row for this page.</p>\n");
        return;
    };
    let t = params.table;
    let mut table = TableText::new(&["parameter", "value"]);
    let mut paste = String::new();
    for (i, column) in t.headers.iter().enumerate() {
        if ["page", "data_file", "shelf", "book", "page_name"].contains(&column.as_str()) {
            continue;
        }
        let value = super::extras::cell(column, &row[i]);
        let _ = writeln!(paste, "{column} = {value}");
        table.row(vec![column.clone(), value]);
    }
    html.push_str("<h2 id=\"paste\">Paste it in (engine_params.csv)</h2>\n");
    // Where the data mislead: the `caveats` column, one line each, above the values.
    if let Some(cell) = t.headers.iter().position(|h| h == "caveats").map(|i| &row[i]).filter(|c| !c.is_empty()) {
        for caveat in cell.split("; ") {
            let _ = writeln!(html, "<p class=\"note caveat\">Caveat: {}</p>", escape(caveat));
        }
    }
    let _ = writeln!(html, "{}<textarea class=\"paste\" readonly rows=\"8\">{}</textarea>", table.html("params"), escape(&paste));
    // One block per tool, from the page's paste-in file (params/<name>.json).
    if let Some(engines) = ctx.inputs.paste.get(page).and_then(|p| p["engines"].as_object()) {
        html.push_str("<h3 id=\"paste-per-tool\">Per tool (params/ paste-in file)</h3>\n");
        for (tool, title) in crate::params::paste::TOOLS {
            if let Some(text) = engines.get(tool).and_then(|t| t.as_str()) {
                let rows = text.lines().count().clamp(2, 16);
                let _ = writeln!(
                    html,
                    "<figure class=\"tool\"><figcaption>{}</figcaption><textarea class=\"paste\" readonly rows=\"{rows}\" data-tool=\"{tool}\">{}</textarea></figure>",
                    escape(title),
                    escape(text)
                );
            }
        }
    }
}

fn warnings_section(html: &mut String, ctx: &Context, page: &str) {
    let Some(warnings) = &ctx.warnings else { return };
    let rows = warnings.rows(page);
    if rows.is_empty() {
        return;
    }
    let t = warnings.table;
    let mut table = TableText::new(&t.headers.iter().map(String::as_str).collect::<Vec<_>>());
    for r in rows {
        table.row(r.to_vec());
    }
    let _ = write!(html, "<h2 id=\"warnings\">Data warnings (warnings.csv)</h2>\n{}", table.html("warnings"));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_on_the_search_box_are_flagged() {
        assert!(at_bound(Index::new(0.001, 100.0)));
        assert!(at_bound(Index::new(0.5, 100.0)));
        assert!(!at_bound(Index::new(0.18, 3.4)));
    }
}
