//! `nklut recommend`: what to ship, per kept page × device — the cheapest Fresnel method
//! whose error against the page's spectral reference curve stays within a stated bound,
//! the runner-up and why every other method loses ([`pick`]), with the parameters a
//! shader author pastes in (the values, or the LUT file, its size and encoding).
//!
//! Inputs, each named in the row it feeds:
//! - the error against the spectral reference: `engine_params.csv` for the engine models
//!   (Schlick on the spectral F0, F82 tint, Gulbrandsen, generalized Schlick, fitted (n, k),
//!   glTF ior); for the closed forms of SPEC §5 on the three-channel index and the LUTs of
//!   the spectral curve, computed here ([`spectral`]) and published as `method_errors.csv`;
//! - the error growth with depth, where an effects scene measured the page and method
//!   (`<out>/<scene>/effects_errors.csv`, [`depth`]): the Fresnel method's own error at the
//!   shallowest and deepest depth and the growth per bounce, carried in the row;
//! - the cost: `cost.csv` (CPU ns per evaluation, f64) as the device `CPU`, and each device
//!   of the devices folder (`read_devices`: a native folder's `gpu_timing.csv`, a browser
//!   bench's JSON) as the median pass time over the materials it timed, × exact and ms per
//!   10⁶ pixels.
//!
//! `command` is the edge: ingest, spectral references, the tables above, then
//! `recommendations.{csv,parquet,json}` and `method_errors.{csv,parquet}` published as one set.

pub mod depth;
pub mod pick;
pub mod spectral;

use nklut_tables::gpu_tables::gpu_timing;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Result};

use crate::ingest::{self, Selection};
use crate::output::{Table, TableFiles};
use crate::report::csvdata::CsvTable;
use nklut_optics::color::{self, CurveMemo, PreparedSpectrum};
use nklut_optics::db::Database;
use nklut_optics::fresnel::{FitMemo, LutSpec, Method};
use nklut_optics::spectrum::Kind;
use nklut_tables::memo_file::MemoFile;

pub use depth::{depth_growth, effects_tables, DepthGrowth};
pub use pick::{recommend, Bound, Candidate, LutSize, Pick, Recommendation, TimeUnit, Timing};
pub use spectral::{method_errors, three_channel_methods, MethodError};

/// The device name of `cost.csv`'s CPU figures.
pub const CPU: &str = "CPU";

/// The engine models of `engine_params.csv`: (column prefix, shader method a device times,
/// where the parameters come from).
pub use crate::report::findings::ENGINE_MODELS;

/// The method errors of one page against its spectral reference.
#[derive(Clone, Debug)]
pub struct PageErrors {
    pub page: String,
    pub kind: Kind,
    pub errors: Vec<MethodError>,
    /// The three-channel (n, k), red green blue, for the parameters column.
    pub index: nklut_optics::spectrum::ChannelIndex,
}

fn kind_name(kind: Kind) -> &'static str {
    match kind {
        Kind::Conductor => "conductor",
        Kind::Dielectric => "dielectric",
    }
}

fn rel_summary(relative: [f64; 3]) -> (f64, f64) {
    (relative.iter().sum::<f64>() / 3.0, relative.iter().copied().fold(0.0, f64::max))
}

/// The variant text of a LUT spec: "N=64,unorm8-srgb".
fn variant(lut: Option<LutSpec>) -> String {
    lut.map(|s| s.name()).unwrap_or_default()
}

/// `method_errors.*`: one row per page × method (× LUT spec).
pub fn method_errors_table(pages: &[PageErrors]) -> Table {
    let rows: Vec<(&PageErrors, &MethodError)> = pages.iter().flat_map(|p| p.errors.iter().map(move |e| (p, e))).collect();
    let mut t = Table::new();
    t.text("page", "page id", rows.iter().map(|(p, _)| p.page.clone()).collect());
    t.text("kind", "conductor or dielectric", rows.iter().map(|(p, _)| kind_name(p.kind).into()).collect());
    t.text("method", "Fresnel method (SPEC 5)", rows.iter().map(|(_, e)| e.method.name().into()).collect());
    t.text(
        "source",
        "three-channel: the closed form on the (n, k) at the channel wavelengths; spectral: a LUT of the spectral reference curve",
        rows.iter().map(|(_, e)| e.source.into()).collect(),
    );
    t.text("variant", "a LUT's N=texels,encoding (empty for closed forms)", rows.iter().map(|(_, e)| variant(e.lut)).collect());
    t.integer(
        "texture_bytes",
        "bytes of the RGB texture of one page (N x 3 x bytes per channel)",
        rows.iter().map(|(_, e)| e.lut.map_or(0, |s| s.texture_bytes()) as i64).collect(),
    );
    t.float(
        "de2000_mean",
        "mean over theta of CIEDE2000 against the spectral reference colour (angle quadrature, D65 CIELAB)",
        rows.iter().map(|(_, e)| e.error.delta_e_mean).collect(),
    );
    t.float("de2000_max", "largest CIEDE2000 at the quadrature nodes", rows.iter().map(|(_, e)| e.error.delta_e_max).collect());
    for (c, name) in ["r", "g", "b"].iter().enumerate() {
        t.float(
            &format!("rel_error_{name}"),
            "mean over theta of |F - F_ref| / F_ref in this channel",
            rows.iter().map(|(_, e)| e.error.relative[c]).collect(),
        );
    }
    t.float("rel_error_mean", "mean of rel_error_r, _g, _b", rows.iter().map(|(_, e)| rel_summary(e.error.relative).0).collect());
    t.float("rel_error_max", "largest of rel_error_r, _g, _b", rows.iter().map(|(_, e)| rel_summary(e.error.relative).1).collect());
    t
}

fn triple(values: [f64; 3]) -> String {
    format!("({}, {}, {})", values[0], values[1], values[2])
}

/// The candidates of one page: the computed errors (three-channel closed forms, spectral
/// LUTs) and the engine models of `engine_params` (its row for the page, when there is one).
pub fn candidates(page: &PageErrors, engine_params: Option<(&CsvTable, &[String])>) -> Vec<Candidate> {
    let kind = kind_name(page.kind).to_string();
    let index = &page.index;
    let nk = format!("n = {}, k = {} (red, green, blue)", triple(index.map(|i| i.n)), triple(index.map(|i| i.k)));
    let mut out = Vec::new();
    let computed = |e: &MethodError| {
        let (rel_mean, rel_max) = rel_summary(e.error.relative);
        let (name, parameters_from, parameters, lut) = match e.lut {
            Some(spec) => {
                let enc = spec.encoding.name();
                let file = format!("luts/spectral/{enc}/strips/{}.{}", crate::bake::strip_stem(&page.page), spec.encoding.extension());
                (
                    format!("lut {} × {enc} (spectral)", spec.texels),
                    "spectral curve".to_string(),
                    format!("{file} ({} × 1, or this page's row of luts/spectral/{enc}/atlas.{}); baked by `nklut bake --source spectral --encoding {enc} --size {}`", spec.texels, spec.encoding.extension(), spec.texels),
                    Some(LutSize::new(spec.texels, enc)),
                )
            }
            None => (format!("{} (three-channel)", e.method.name()), "three-channel (n, k)".to_string(), nk.clone(), None),
        };
        Candidate {
            page: page.page.clone(),
            kind: kind.clone(),
            method: e.method.name().into(),
            parameters_from,
            name,
            lut,
            texture_bytes: e.lut.map_or(0, |s| s.texture_bytes()),
            de2000_mean: e.error.delta_e_mean,
            de2000_max: e.error.delta_e_max,
            rel_error_mean: rel_mean,
            rel_error_max: rel_max,
            parameters,
            error_table: "method_errors.csv".into(),
        }
    };
    out.extend(page.errors.iter().filter(|e| e.lut.is_none()).map(computed));
    if let Some((table, row)) = engine_params {
        for (model, method, from) in ENGINE_MODELS {
            let num = |c: &str| table.number(row, c);
            let (Some(mean), Some(max)) = (num(&format!("{model}_de2000_mean")), num(&format!("{model}_de2000_max"))) else { continue };
            let rel: Option<Vec<f64>> = ["r", "g", "b"].iter().map(|c| num(&format!("{model}_rel_error_{c}"))).collect();
            let Some(rel) = rel else { continue };
            let (rel_mean, rel_max) = rel_summary([rel[0], rel[1], rel[2]]);
            let three = |stem: &str| -> String {
                let v: Vec<&str> = ["r", "g", "b"].iter().map(|c| table.text(row, &format!("{stem}_{c}"))).collect();
                format!("({}, {}, {})", v[0], v[1], v[2])
            };
            let parameters = match model {
                "schlick" => format!("F0 = {} linear Rec.709", three("f0_linear")),
                "f82_tint" => format!("F0 = {}, F82 tint = {}", three("f0_linear"), three("f82_tint")),
                "gulbrandsen" => {
                    format!("reflectivity = {}, edge tint = {}", three("gulbrandsen_reflectivity"), three("gulbrandsen_edge_tint"))
                }
                "generalized_schlick" => format!(
                    "color0 = {}, color82 = {}, exponent = {}",
                    three("f0_linear"),
                    three("generalized_schlick_color82"),
                    table.text(row, "generalized_schlick_exponent")
                ),
                "fitted_nk" => format!("n = {}, k = {}", three("fitted_n"), three("fitted_k")),
                _ => format!("ior = {} (F0 = {})", table.text(row, "n_d"), table.text(row, "gltf_ior_f0")),
            };
            out.push(Candidate {
                page: page.page.clone(),
                kind: kind.clone(),
                method: method.into(),
                parameters_from: from.into(),
                name: format!("{model} (engine_params)"),
                lut: None,
                texture_bytes: 0,
                de2000_mean: mean,
                de2000_max: max,
                rel_error_mean: rel_mean,
                rel_error_max: rel_max,
                parameters,
                error_table: "engine_params.csv".into(),
            });
        }
    }
    out.extend(page.errors.iter().filter(|e| e.lut.is_some()).map(computed));
    out
}

/// The CPU timings of `cost.csv` (its f64 rows; a LUT row per size × encoding).
pub fn cpu_timings(cost: &CsvTable) -> Vec<Timing> {
    let mut out = Vec::new();
    for row in &cost.rows {
        let (method, variant) = (cost.text(row, "method"), cost.text(row, "variant"));
        let Some(ns) = cost.number(row, "ns_per_eval") else { continue };
        let lut = if method == Method::Lut.name() {
            let parts: Vec<&str> = variant.split(',').collect();
            match parts.as_slice() {
                [n, enc, "f64"] => n.strip_prefix("N=").and_then(|n| n.parse().ok()).map(|n: usize| LutSize::new(n, *enc)),
                _ => continue,
            }
        } else if variant == "f64" {
            None
        } else {
            continue;
        };
        out.push(Timing {
            device: CPU.into(),
            method: method.into(),
            lut,
            value: ns,
            unit: TimeUnit::NsPerEvaluation,
            ms_per_mpixel: None,
            source: format!("cost.csv ({method}, {variant})"),
        });
    }
    out
}

/// Pixels of a `WxH` resolution.
fn pixels(resolution: &str) -> Option<f64> {
    let (w, h) = resolution.split_once('x')?;
    Some(w.trim().parse::<f64>().ok()? * h.trim().parse::<f64>().ok()?)
}

/// One timing per method a device timed: the median pass time over its materials
/// ([`crate::report::inputs::DeviceTables::median_ms`]), per 10⁶ pixels where every row of
/// the method has one resolution.
pub fn device_timings(device: &str, tables: &crate::report::inputs::DeviceTables) -> Vec<Timing> {
    let timing = &tables.timing;
    let mut out = Vec::new();
    for method in timing.distinct(gpu_timing::METHOD.name) {
        let Some(median) = tables.median_ms(method) else { continue };
        let rows: Vec<&Vec<String>> = timing.rows_where(gpu_timing::METHOD.name, method).collect();
        let resolutions: Vec<&str> = rows.iter().map(|r| timing.get(r, gpu_timing::RESOLUTION)).collect();
        let per_mpixel =
            resolutions.first().filter(|r| resolutions.iter().all(|x| x == *r)).and_then(|r| pixels(r)).map(|px| median / (px / 1e6));
        out.push(Timing {
            device: device.into(),
            method: method.into(),
            lut: None,
            value: median,
            unit: TimeUnit::MsPerPass,
            ms_per_mpixel: per_mpixel,
            source: format!("devices/{device} ({}; gpu_timing median_ms, median over {} materials)", tables.source, rows.len()),
        });
    }
    out
}

/// `recommendations.*`: one row per page × device; `growth` the pick's depth growth per
/// row ([`depth_growth`]; `None` where no scene measured it).
pub fn recommendations_table(rows: &[Recommendation], growth: &[Option<DepthGrowth>]) -> Table {
    let pick = |r: &Recommendation| r.pick.clone();
    let picks: Vec<Option<Pick>> = rows.iter().map(pick).collect();
    let c = |f: &dyn Fn(&Pick) -> String| picks.iter().map(|p| p.as_ref().map(f).unwrap_or_default()).collect::<Vec<String>>();
    let of = |f: &dyn Fn(&Pick) -> Option<f64>| picks.iter().map(|p| p.as_ref().and_then(f)).collect::<Vec<Option<f64>>>();
    let mut t = Table::new();
    t.text("page", "page id", rows.iter().map(|r| r.page.clone()).collect());
    t.text("kind", "conductor or dielectric", rows.iter().map(|r| r.kind.clone()).collect());
    t.text("device", "CPU (cost.csv) or a device of the devices folder", rows.iter().map(|r| r.device.clone()).collect());
    t.text("method", "the shader method to use (SPEC 5; empty when none passes)", c(&|p| p.candidate.method.clone()));
    t.text("candidate", "the method with the origin of its parameters (and a LUT's size and encoding)", c(&|p| p.candidate.name.clone()));
    t.text("parameters_from", "where the parameters come from", c(&|p| p.candidate.parameters_from.clone()));
    t.text(
        "parameters",
        "what to put in the shader: the values, or the LUT file and how to bake it",
        c(&|p| p.candidate.parameters.clone()),
    );
    t.text(
        "lut_texels",
        "a LUT's texels per row N (empty for closed forms)",
        c(&|p| p.candidate.lut.as_ref().map(|l| l.texels.to_string()).unwrap_or_default()),
    );
    t.text("lut_encoding", "a LUT's texel encoding", c(&|p| p.candidate.lut.as_ref().map(|l| l.encoding.clone()).unwrap_or_default()));
    t.integer(
        "texture_bytes",
        "bytes of the texture one page needs (0: no texture)",
        picks.iter().map(|p| p.as_ref().map_or(0, |p| p.candidate.texture_bytes as i64)).collect(),
    );
    t.boolean(
        "needs_texture",
        "whether the shader path samples a texture",
        picks.iter().map(|p| p.as_ref().is_some_and(|p| p.candidate.lut.is_some())).collect(),
    );
    t.optional_float(
        "de2000_mean",
        "expected error: mean over theta of CIEDE2000 against the spectral reference",
        of(&|p| Some(p.candidate.de2000_mean)),
    );
    t.optional_float("de2000_max", "expected error: largest CIEDE2000 over theta", of(&|p| Some(p.candidate.de2000_max)));
    t.optional_float(
        "rel_error_mean",
        "mean over channels of the mean relative error over theta",
        of(&|p| Some(p.candidate.rel_error_mean)),
    );
    t.optional_float("rel_error_max", "the worst channel's mean relative error over theta", of(&|p| Some(p.candidate.rel_error_max)));
    t.text("error_table", "the table whose row holds the error figures", c(&|p| p.candidate.error_table.clone()));
    t.optional_float("cost", "the method's time on the device (cost_unit)", of(&|p| Some(p.timing.value)));
    t.text("cost_unit", "ns/eval (CPU) or ms/pass (GPU median over materials)", c(&|p| pick::fmt_unit(p.timing.unit).into()));
    t.optional_float("cost_x_exact", "the time relative to exact on the same device", of(&|p| p.x_exact));
    t.optional_float("ms_per_mpixel", "GPU pass ms per 10^6 pixels (where the resolution is known)", of(&|p| p.timing.ms_per_mpixel));
    t.text("cost_source", "the table and rows the time comes from", c(&|p| p.timing.source.clone()));
    t.float("bound_de2000", "the bound on de2000_max", rows.iter().map(|r| r.bound.de2000).collect());
    t.optional_float("bound_rel", "the bound on rel_error_max (empty: none)", rows.iter().map(|r| r.bound.rel).collect());
    t.integer("passing", "candidates within the bound with a time on this device", rows.iter().map(|r| r.passing as i64).collect());
    t.text(
        "runner_up",
        "the cheapest passing candidate of another shader method",
        rows.iter().map(|r| r.runner_up.as_ref().map(|p| p.candidate.name.clone()).unwrap_or_default()).collect(),
    );
    t.optional_float(
        "runner_up_cost_x_exact",
        "its time relative to exact",
        rows.iter().map(|r| r.runner_up.as_ref().and_then(|p| p.x_exact)).collect(),
    );
    t.optional_float(
        "runner_up_de2000_max",
        "its largest CIEDE2000",
        rows.iter().map(|r| r.runner_up.as_ref().map(|p| p.candidate.de2000_max)).collect(),
    );
    let grown = |f: &dyn Fn(&DepthGrowth) -> Option<f64>| -> Vec<Option<f64>> {
        (0..rows.len()).map(|i| growth.get(i).and_then(Option::as_ref).and_then(f)).collect()
    };
    t.text(
        "depth_bounces",
        "the shallowest and deepest depth (reflections + refractions) an effects scene measured the pick's method on this page at, `1-4` (empty: not measured)",
        (0..rows.len())
            .map(|i| growth.get(i).and_then(Option::as_ref).map(|g| format!("{}-{}", g.bounces.0, g.bounces.1)).unwrap_or_default())
            .collect(),
    );
    t.optional_float(
        "depth_de2000_shallow",
        "the pick's method against exact Fresnel on the same paths at the shallowest depth: pixel-weighted mean ΔE2000 (effects_errors.csv)",
        grown(&|g| Some(g.de2000.0)),
    );
    t.optional_float("depth_de2000_deep", "the same at the deepest depth", grown(&|g| Some(g.de2000.1)));
    t.optional_float(
        "depth_growth_per_bounce",
        "(deep - shallow) / bounces apart: how the method's own error grows per bounce (empty: one depth or none)",
        grown(&|g| g.per_bounce),
    );
    t.text(
        "depth_source",
        "the effects tables and rows the depth figures come from",
        (0..rows.len()).map(|i| growth.get(i).and_then(Option::as_ref).map(|g| g.source.clone()).unwrap_or_default()).collect(),
    );
    t.text("reason", "why the pick wins", rows.iter().map(|r| r.reason.clone()).collect());
    t.text("others", "why each other method loses (its best candidate)", rows.iter().map(|r| r.others.clone()).collect());
    t
}

/// Everything `nklut recommend` takes besides the database and the output folder.
#[derive(Clone, Debug)]
pub struct RecommendRequest {
    pub selection: Selection,
    pub reading: ingest::Config,
    /// The devices folder (default: `<out>/devices`).
    pub devices: Option<PathBuf>,
    pub bound: Bound,
}

/// `nklut recommend`: ingest, compute the method errors, read the tables, pick, publish.
pub fn command(db: &Database, out: &Path, request: &RecommendRequest) -> Result<Vec<PathBuf>> {
    let bound = request.bound;
    if !(bound.de2000.is_finite() && bound.de2000 > 0.0) || bound.rel.is_some_and(|r| !(r.is_finite() && r > 0.0)) {
        bail!("the bounds must be positive numbers (--bound-de {}, --bound-rel {:?})", bound.de2000, bound.rel);
    }
    let start = Instant::now();
    let load = |name: &str, by: &str| -> Result<CsvTable> {
        match CsvTable::load(&out.join(name))? {
            Some(t) => Ok(t),
            None => bail!("{} is missing: run `{by}` first", out.join(name).display()),
        }
    };
    let cost = load("cost.csv", "nklut validate")?;
    let engine_params = load("engine_params.csv", "nklut params")?;
    let devices_dir = request.devices.clone().unwrap_or_else(|| out.join(crate::report::inputs::DEVICES_DIR));
    let devices = crate::report::inputs::read_devices(&devices_dir)?;
    let ingested = ingest::ingest(db, &request.selection, &request.reading)?;
    ingested.check_strict()?;
    anyhow::ensure!(!ingested.kept.is_empty(), "no page of the selection passed the coverage filter; nothing to recommend");
    let (unique, positions) = ingest::distinct_materials(&ingested.kept);
    let memo = CurveMemo::load(out);
    let fits = FitMemo::load(out);
    let rule = color::angle_quadrature();
    let per_material: Vec<Vec<MethodError>> = crate::progress::par_map(unique.len(), "method errors against the spectral curve", |i| {
        let material = &unique[i];
        let reference = crate::params::reference(material, &memo);
        let (spectrum, _) = color::sample_spectrum(&material.data);
        let prepared = PreparedSpectrum::new(&spectrum);
        method_errors(&material.channels, &|index| fits.prepared(index), &prepared, &reference, rule)
    });
    let pages: Vec<PageErrors> = ingested
        .kept
        .iter()
        .zip(&positions)
        .map(|(page, &m)| PageErrors { page: page.id(), kind: unique[m].kind, errors: per_material[m].clone(), index: unique[m].channels })
        .collect();
    let mut candidate_rows = Vec::new();
    for page in &pages {
        let row = engine_params.rows_where("page", &page.page).next();
        candidate_rows.extend(candidates(page, row.map(|r| (&engine_params, r.as_slice()))));
    }
    let mut timings = cpu_timings(&cost);
    let mut timed_devices = 0;
    for (name, tables) in &devices {
        let t = device_timings(name, tables);
        if !t.is_empty() {
            timed_devices += 1;
        }
        timings.extend(t);
    }
    let rows = recommend(&candidate_rows, &timings, bound);
    let effects = effects_tables(out)?;
    let growth: Vec<Option<DepthGrowth>> =
        rows.iter().map(|r| r.pick.as_ref().and_then(|p| depth_growth(&effects, &r.page, &p.candidate.method))).collect();
    let mut files = recommendations_table(&rows, &growth).files("recommendations", true)?;
    files.extend(method_errors_table(&pages).files("method_errors", false)?);
    let written = crate::output::publish_set(out, "recommend", &files)?;
    eprintln!(
        "recommend: {} pages × {} devices (CPU + {timed_devices} timed), bound {}; {:.2} s",
        pages.len(),
        1 + timed_devices,
        bound.describe(),
        start.elapsed().as_secs_f64()
    );
    Ok(written)
}
