//! Engine parameters per kept page (`nklut params`): what engines and artists paste in —
//! F0 (linear Rec.709, ACEScg, 8-bit sRGB), F82 tint, Gulbrandsen's (r, g), Hoffman's
//! generalized Schlick, the fitted per-channel (n, k), a dielectric's n_d and Abbe number
//! — each model with its error against the page's spectral reference curve over θ.
//! Formulas and sources: [`models`] and [`page`]; the engine fields each value goes into:
//! docs/engine-integration.md and the table's column descriptions.
//!
//! `compute` is pure (pages → parameters); `command` is the edge: ingest, compute, then
//! write `engine_params.{csv,parquet,json}` (+ columns.json), `materials.mtlx` and
//! `materials.gltf` + `materials.bin` atomically.

pub mod caveats;
pub mod gltf;
pub use nklut_tables::models;
pub mod mtlx;
pub mod page;
pub mod paste;
pub mod table;
pub mod usd;

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;
use rayon::prelude::*;

use crate::ingest::{self, KeptPage, Selection};
use crate::output::{SetFile, TableFiles};
use nklut_optics::appearance::Appearance;
use nklut_optics::color::{self, CurveMemo, Fingerprint, PreparedSpectrum};
use nklut_optics::db::Database;
use nklut_optics::spectrum::{Channels, Material};
use nklut_tables::memo_file::MemoFile;

pub use models::{F82Tint, GeneralizedSchlick, Gulbrandsen, EDGE_COS};
pub use page::{curve_error, engine_params, CurveError, EngineModel, EngineParams, ModelError, Reference};
pub use table::engine_params_table;

/// The folder of the per-page paste-in files (`params/<name>.json`).
pub const PASTE_DIR: &str = "params";

/// What every export of one run shares: the roughness given to each material, the same in
/// glTF, MaterialX, USD and the paste-in blocks. Unless `--roughness` sets one for all, a
/// metal gets [`ExportSettings::METAL_ROUGHNESS`] and a dielectric
/// [`ExportSettings::DIELECTRIC_ROUGHNESS`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExportSettings {
    pub roughness: Option<f64>,
}

impl ExportSettings {
    /// Metals: the optical constants describe a polished surface, but at roughness 0 a
    /// viewer shows a mirror whose colour is seen only in what it reflects; 0.2 spreads the
    /// highlight enough that F0 and the edge colour read under any environment.
    pub const METAL_ROUGHNESS: f64 = 0.2;
    /// Dielectrics: glass and liquids are optically smooth; any roughness frosts them.
    pub const DIELECTRIC_ROUGHNESS: f64 = 0.0;

    /// The roughness of a material of `appearance`.
    pub fn roughness(&self, appearance: Appearance) -> f64 {
        self.roughness.unwrap_or(match appearance {
            Appearance::Metal => Self::METAL_ROUGHNESS,
            Appearance::Transparent | Appearance::Tinted | Appearance::Opaque => Self::DIELECTRIC_ROUGHNESS,
        })
    }

    /// The rule in words, for the exports' metadata.
    pub fn describe(&self) -> String {
        match self.roughness {
            Some(r) => format!("{r} for every material (--roughness)"),
            None => format!("{} for metals, {} for dielectrics (the defaults)", Self::METAL_ROUGHNESS, Self::DIELECTRIC_ROUGHNESS),
        }
    }
}

/// The spectral reference of a material on the angle quadrature (its curve from `memo`
/// when it holds it).
pub fn reference(material: &Material, memo: &CurveMemo) -> Reference {
    let (spectrum, _) = color::sample_spectrum(&material.data);
    let rule = color::angle_quadrature();
    let prepared = PreparedSpectrum::new(&spectrum);
    Reference::from_curve(&prepared, &memo.curve(Fingerprint::of_spectrum(&spectrum), &prepared, &rule.cosines))
}

/// Wall-clock seconds of the two stages of [`compute`].
#[derive(Clone, Copy, Debug, Default)]
pub struct ParamsTimings {
    /// Spectra and the reference colours at F0, μ̄ and the quadrature nodes.
    pub reference_s: f64,
    /// Every parameter, fit and error from the references.
    pub parameters_s: f64,
}

/// The parameters of every page of `kept`, each distinct data file computed once (in
/// parallel), in the order of `kept`.
pub fn compute(kept: &[KeptPage], channels: &Channels, timings: &mut ParamsTimings, memo: &CurveMemo) -> Result<Vec<EngineParams>> {
    let (unique, positions) = ingest::distinct_materials(kept);
    let start = Instant::now();
    let references: Vec<Reference> = crate::progress::par_map(unique.len(), "spectral references", |i| reference(&unique[i], memo));
    timings.reference_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let rule = color::angle_quadrature();
    let params: Vec<EngineParams> =
        crate::progress::par_map(unique.len(), "engine parameters", |i| engine_params(&unique[i], &references[i], rule, channels));
    timings.parameters_s = start.elapsed().as_secs_f64();
    Ok(positions.into_iter().map(|i| params[i].clone()).collect())
}

/// `nklut params`: ingest the selection, compute, publish the table and the two exports
/// as one set.
pub fn command(
    db: &Database,
    selection: &Selection,
    config: &ingest::Config,
    settings: &ExportSettings,
    out: &Path,
) -> Result<Vec<PathBuf>> {
    if let Some(r) = settings.roughness {
        anyhow::ensure!((0.0..=1.0).contains(&r), "--roughness {r} must lie in [0, 1]");
    }
    let start = Instant::now();
    let ingested = ingest::ingest(db, selection, config)?;
    ingested.check_strict()?;
    anyhow::ensure!(!ingested.kept.is_empty(), "no page of the selection passed the coverage filter; no engine parameters to write");
    let ingest_s = start.elapsed().as_secs_f64();
    let mut timings = ParamsTimings::default();
    let memo = CurveMemo::load(out);
    let params = compute(&ingested.kept, &config.channels, &mut timings, &memo)?;
    let caveats = caveats::caveats(&ingested.kept, &params);
    let mut files = table::engine_params_table(&ingested.kept, &params, &caveats, settings).files("engine_params", true)?;
    let pages: Vec<mtlx::ExportPage> = ingested
        .kept
        .iter()
        .zip(mtlx::display_names(&ingested.kept))
        .zip(&params)
        .zip(caveats)
        .map(|(((page, display), params), caveats)| mtlx::ExportPage::new(page, display, params, caveats, settings))
        .collect();
    files.push(SetFile::new("materials.mtlx", mtlx::document(&pages).into_bytes()));
    let scene = gltf::scene(&pages, "materials.bin", settings)?;
    files.push(SetFile::new("materials.bin", scene.bin));
    files.push(SetFile::new("materials.gltf", scene.json));
    files.push(SetFile::new("materials.usda", usd::document(&pages, &settings.describe()).into_bytes()));
    let names = mtlx::unique_names(pages.iter().map(|p| p.page.as_str()));
    let paste_files: Vec<SetFile> = pages
        .par_iter()
        .zip(&names)
        .map(|(page, name)| {
            let mut json = serde_json::to_vec_pretty(&paste::page_json(page))?;
            json.push(b'\n');
            Ok(SetFile::new(format!("{PASTE_DIR}/{name}.json"), json))
        })
        .collect::<Result<_>>()?;
    files.extend(paste_files);
    let written = crate::output::publish_set(out, "params", &files)?;
    eprintln!(
        "params: {} pages ({} excluded); ingest {ingest_s:.2} s, spectral references {:.2} s, parameters + fits + errors {:.2} s",
        ingested.kept.len(),
        ingested.excluded.len(),
        timings.reference_s,
        timings.parameters_s
    );
    Ok(written)
}
