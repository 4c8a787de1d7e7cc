//! `nklut report`: a light index (`report/index.html`, `report/report.md`) linking one
//! self-contained page per material (`report/materials/<id>.html`: inline SVG plots,
//! PNG previews as data URIs, inline CSS; no network), and the previews as PNG files
//! (`report/previews/<id>.png`), and with the effects' tables `report/effects.html`
//! (charts, hero frames; see `effects`). Every number comes from a table another stage wrote
//! (`materials.csv`, `excluded.csv`, `colors.csv`, `errors.csv`, `cost.csv`, …) and the
//! channel wavelengths are those `materials.csv` records, so a reader can trace each
//! figure to its CSV. Curves are recomputed from those indices and the page's data.

pub mod ao_cost;
pub mod ao_histogram;
pub mod charts;
pub mod context;
pub mod csvdata;
pub mod curves;
pub mod effects;
pub mod extras;
pub mod findings;
pub mod html;
pub mod index;
pub mod inputs;
pub mod page;
pub mod preview;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::{Context as _, Result};
use rayon::prelude::*;

use crate::bake::publish::publish_with;
use crate::ingest::Selection;
use context::{material_path, preview_path, ByPage, Context};
pub use inputs::Inputs;
use nklut_optics::db::Database;
use nklut_optics::spectrum::Index;
use page::MaterialPage;

/// The report's style. Narrow windows (a phone's 390 px): the page never scrolls sideways —
/// tables, charts, preview strips and colour bars wider than the window scroll inside their
/// own box (`.wide`, `figure.plot`, …) and keep their text size; words break in prose.
pub(crate) const STYLE: &str = "body{font-family:system-ui,sans-serif;font-size:15px;max-width:1240px;margin:2em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:0.5em 0 1.5em;font-size:14px}th,td{border:1px solid #ccc;padding:2px 6px;text-align:right}\
th{background:#f2f2f2}td:first-child,th:first-child{text-align:left}.swatch{display:inline-block;width:2.2em;height:1.2em;border:1px solid #888;vertical-align:middle}\
figure{margin:0 0 1em}figcaption,.note{font-size:14px;color:#555}.notes{font-size:14px;color:#533}.absent{color:#666;font-size:14px}\
figure.plot{display:flex;align-items:flex-start;gap:12px;flex-wrap:wrap}.legend{list-style:none;padding:0;margin:8px 0;font-size:14px}.legend li{white-space:nowrap;margin:3px 0}.legend svg{margin-right:6px;vertical-align:middle}\
.spheres{display:flex;flex-wrap:wrap;gap:6px 8px}.sphere-cell{flex:none;max-width:100%;font-size:13px;text-align:center}.sphere{background-image:var(--sheet);background-repeat:no-repeat;max-width:100%}.method{overflow-wrap:anywhere;padding:0 2px}\
.strips{font-size:13px}.strip-row{display:flex;align-items:center;margin:2px 0}.strip-name{width:190px;flex:none}.strip{flex:none;width:540px;height:18px;border:1px solid #999}\
.strip-axis{display:flex;justify-content:space-between;width:542px;font-size:13px}#search{width:22em;padding:4px;font-size:14px}\
table.materials th{cursor:pointer}.paste{width:100%;font-family:monospace;font-size:13px}\
.wide{overflow-x:auto;max-width:100%}figure.plot,.previews,.strips{overflow-x:auto;max-width:100%}figure.plot>svg{flex:none}\
p,li,figcaption,summary,h1,h2,h3{overflow-wrap:break-word}#search{max-width:100%;box-sizing:border-box}";

/// A CSS swatch of a linear-sRGB colour (sRGB-encoded, clamped for display).
pub(crate) fn swatch(rgb: [f64; 3]) -> String {
    format!("<span class=\"swatch\" style=\"background:{}\"></span>", nklut_optics::color::srgb::hex_swatch(rgb))
}

/// The index of each selected page on the 1 nm grid, or why it could not be had.
pub type Spectra = HashMap<String, Result<Vec<Index>, String>>;

/// Build the report for `pages` (rows of `materials.csv`) from loaded tables and write it
/// as one set under `<out>/report`: each material page and preview is written into a
/// staging folder as soon as it is built (the report is never held in memory whole), then
/// the index and `report.md`, and the folder is renamed into place (readers see the
/// previous report or the new one, never a mix). `spectra` holds each page's spectrum by
/// data file. Returns the files written.
pub fn build_and_write(inputs: &Inputs, pages: &[String], spectra: &Spectra, out: &Path) -> Result<Vec<PathBuf>> {
    let ctx = Context::new(inputs);
    let written = Mutex::new(Vec::new());
    let put = |staging: &Path, path: String, bytes: &[u8]| -> Result<()> {
        let file = staging.join(&path);
        if let Some(folder) = file.parent() {
            std::fs::create_dir_all(folder).with_context(|| format!("creating {}", folder.display()))?;
        }
        std::fs::write(&file, bytes).with_context(|| format!("writing {}", file.display()))?;
        written.lock().expect("no writer panicked").push(path);
        Ok(())
    };
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let dir = publish_with(out, REPORT_DIR, &|staging| {
        pages.par_iter().try_for_each(|page| {
            let file = ctx.materials.first(page).map(|r| inputs.materials.text(r, "data_file")).unwrap_or("");
            let spectrum = match spectra.get(file) {
                Some(Ok(s)) => Ok(s.as_slice()),
                Some(Err(e)) => Err(e.as_str()),
                None => Err("not read"),
            };
            let built: MaterialPage = page::material_page(&ctx, page, spectrum)?;
            put(staging, material_path(page)?, built.html.as_bytes())?;
            match &built.preview_png {
                Some(png) => put(staging, preview_path(page), png),
                None => Ok(()),
            }
        })?;
        let index = index::index_page(&ctx, pages, effects::summary(inputs))?;
        if let Some(page) = effects::page(inputs)? {
            // Every picture the page shows, copied in (read through the output folder's
            // links into `.sets/`); one that is absent stays a named gap (its alt text).
            for picture in effects::pictures(&page) {
                match std::fs::read(out.join(&picture)) {
                    Ok(bytes) => put(staging, format!("{}/{picture}", effects::PICTURES_DIR), &bytes)?,
                    Err(e) => eprintln!("report: picture {picture} not copied: {e}"),
                }
            }
            put(staging, effects::EFFECTS_PAGE.into(), page.as_bytes())?;
        }
        put(staging, "index.html".into(), index.html.as_bytes())?;
        put(staging, "report.md".into(), index.markdown.as_bytes())
    })?;
    let mut written = written.into_inner().expect("no writer panicked");
    written.sort();
    Ok(written.into_iter().map(|p| dir.join(p)).collect())
}

/// The folder under the output folder that holds the report.
pub const REPORT_DIR: &str = "report";

/// The stages whose tables the report reads, in the order they run.
pub const STAGES: [&str; 3] = ["ingest", "colors", "validate"];

/// Per-page columns a material page shows, by file: tests check each value is on it.
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

/// How the report writes the value of `column`: relative errors as percentages, n and
/// k with 4 decimals, reflectances with 4 decimals, ΔE with 2.
pub fn shown(column: &str, value: f64) -> String {
    if column.starts_with("delta_e") {
        html::delta_e(value)
    } else if column.contains("error") {
        html::percent(value)
    } else if column.starts_with("f0_") {
        html::reflectance(value)
    } else {
        html::index(value)
    }
}

/// The spectrum of each data file of `pages` (each file read once, in parallel).
fn read_spectra(db: &Database, inputs: &Inputs, pages: &[String]) -> Spectra {
    let m = ByPage::new(&inputs.materials);
    let mut files: Vec<String> = pages.iter().filter_map(|p| m.first(p).map(|r| m.table.text(r, "data_file").to_string())).collect();
    files.sort();
    files.dedup();
    files
        .into_par_iter()
        .map(|file| {
            let spectrum = db.read_page(&file).map(|data| nklut_optics::color::sample_spectrum(&data).0).map_err(|e| e.to_string());
            (file, spectrum)
        })
        .collect()
}

/// `nklut report`: the pages of `materials.csv` that `selection` picks (every page when
/// it names none, as for every command). A named page or shelf the tables lack is an
/// error naming each. `devices`: the folder of device results (default `<out>/devices`).
pub fn command(db: &Database, out: &Path, selection: &Selection, devices: Option<&Path>) -> Result<Vec<PathBuf>> {
    let mut inputs = Inputs::load(out)?;
    if let Some(folder) = devices {
        if !folder.is_dir() {
            anyhow::bail!("--devices {}: not a folder", folder.display());
        }
        inputs.devices = inputs::read_devices(folder)?;
    }
    let pages = inputs::select_pages(&inputs.materials, &inputs.excluded, selection)?;
    let spectra = read_spectra(db, &inputs, &pages);
    build_and_write(&inputs, &pages, &spectra, out)
}
