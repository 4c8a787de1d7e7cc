//! `nklut colors`: the per-page colour table `colors.{csv,parquet}`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;

use crate::ingest::{self, Config, KeptPage, Selection};
use crate::output::{Table, TableFiles};
use nklut_optics::color::angle_average::{angle_quadrature, NODES, PANELS};
use nklut_optics::color::memo::{CurveMemo, EffectiveMemo};
use nklut_optics::color::page::{page_colors, spectral_reference, PageColors};
use nklut_optics::color::srgb::hex_swatch;
use nklut_optics::db::Database;
use nklut_optics::encoding::texel_cosines;
use nklut_optics::spectrum::Channels;
use nklut_tables::memo_file::MemoFile;

/// Column suffixes of the per-channel columns.
const SUFFIXES: [&str; 3] = ["r", "g", "b"];

/// Wall-clock seconds of the stages of one run.
#[derive(Clone, Copy, Debug, Default)]
pub struct Timings {
    pub ingest_s: f64,
    /// Spectra, normal-incidence colours, quadrature-node and texel curves.
    pub spectral_s: f64,
    /// Index errors and the effective-index fits.
    pub fit_s: f64,
}

/// The colours of every material of `kept`, each distinct data file computed once (in
/// parallel); `texels` is the LUT size whose texel centres are checked for out-of-gamut
/// values; the spectral curves come from `memo` and the effective fits from `fits` where
/// they hold them. Returns one `PageColors` per kept page, in order.
pub fn compute(kept: &[KeptPage], texels: usize, timings: &mut Timings, memo: &CurveMemo, fits: &EffectiveMemo) -> Vec<PageColors> {
    let (unique, positions) = ingest::distinct_materials(kept);
    let quadrature = angle_quadrature();
    let cosines = texel_cosines(texels);

    let start = Instant::now();
    let references =
        crate::progress::par_map(unique.len(), "spectra", |i| spectral_reference(&unique[i], quadrature, &cosines, Some(memo)));
    timings.spectral_s = start.elapsed().as_secs_f64();

    let start = Instant::now();
    let colors: Vec<PageColors> =
        crate::progress::par_map(unique.len(), "fits", |i| page_colors(&unique[i], &references[i], quadrature, fits));
    timings.fit_s = start.elapsed().as_secs_f64();
    positions.into_iter().map(|i| colors[i].clone()).collect()
}

/// `colors.*`: one row per kept page.
pub fn colors_table(kept: &[KeptPage], colors: &[PageColors], channels: &Channels, texels: usize) -> Table {
    let mut table = Table::new();
    table
        .text("page", "page id shelf/book/page", kept.iter().map(|p| p.id()).collect())
        .text("data_file", "data file relative to database/data/", kept.iter().map(|p| p.page.data.clone()).collect())
        .text("kind", "conductor or dielectric (as in materials.csv)", kept.iter().map(|p| p.material.kind.as_str().into()).collect());
    let wavelengths = channels.nanometres();
    let per_channel = |table: &mut Table, stem: &str, meaning: &str, value: &dyn Fn(&PageColors, usize) -> f64| {
        for (c, suffix) in SUFFIXES.iter().enumerate() {
            table.float(&format!("{stem}_{suffix}"), meaning, colors.iter().map(|p| value(p, c)).collect());
        }
    };
    let flags = |table: &mut Table, stem: &str, meaning: &str, value: &dyn Fn(&PageColors, usize) -> bool| {
        for (c, suffix) in SUFFIXES.iter().enumerate() {
            table.boolean(&format!("{stem}_{suffix}"), meaning, colors.iter().map(|p| value(p, c)).collect());
        }
    };
    per_channel(
        &mut table,
        "f0_spectral",
        "spectral reference reflectance at normal incidence, linear sRGB (SPEC 4; may lie outside [0,1])",
        &|p, c| p.f0_spectral[c],
    );
    table.text(
        "f0_spectral_hex",
        "f0_spectral clamped to [0,1], sRGB-encoded, 8-bit #rrggbb swatch (clamping flagged by out_of_gamut_*)",
        colors.iter().map(|p| hex_swatch(p.f0_spectral)).collect(),
    );
    per_channel(
        &mut table,
        "f0_three_channel",
        &format!("exact Fresnel at normal incidence of the channel index at {wavelengths:?} nm (red, green, blue)"),
        &|p, c| p.f0_three_channel[c],
    );
    per_channel(&mut table, "index_error_f0", "|f0_three_channel - f0_spectral| / |f0_spectral| (fraction)", &|p, c| p.index_error_f0[c]);
    per_channel(
        &mut table,
        "index_error_angle",
        &format!("mean over theta uniform in [0,90] deg of |F_three_channel - F_spectral| / |F_spectral| (fraction; {PANELS}x{NODES}-node composite Gauss-Legendre in theta)"),
        &|p, c| p.index_error_angle[c],
    );
    table.float(
        "delta_e2000_f0",
        "CIEDE2000 between f0_three_channel and f0_spectral (CIELAB, D65 white)",
        colors.iter().map(|p| p.delta_e2000_f0).collect(),
    );
    per_channel(
        &mut table,
        "effective_n",
        "effective refractive index n: exact Fresnel closest to the spectral reference over theta (relative least squares)",
        &|p, c| p.effective[c].index.n,
    );
    per_channel(&mut table, "effective_k", "effective extinction coefficient k (same fit)", &|p, c| p.effective[c].index.k);
    per_channel(
        &mut table,
        "effective_error",
        "mean over theta of |F_effective - F_spectral| / |F_spectral| after the fit (fraction)",
        &|p, c| p.effective[c].error,
    );
    flags(
        &mut table,
        "reference_in_unit_range",
        "spectral reference inside [0,1] at normal incidence and every quadrature node (otherwise no exact Fresnel curve, which is <= 1 and >= 0, can match it)",
        &|p, c| p.reference_in_unit_range[c],
    );
    table.float(
        "extrapolated_share",
        "share of the integral of S(lambda) ybar(lambda) over wavelengths outside the data range, where n and k are held (fraction)",
        colors.iter().map(|p| p.extrapolated_share).collect(),
    );
    flags(&mut table, "out_of_gamut", "f0_spectral outside [0,1] in linear sRGB (value kept)", &|p, c| p.out_of_gamut_f0[c]);
    flags(
        &mut table,
        "out_of_gamut_angle",
        &format!("spectral reference outside [0,1] at normal incidence, a quadrature node or a texel centre (i+0.5)/{texels}"),
        &|p, c| p.out_of_gamut_angle[c],
    );
    table
}

/// `nklut colors`: ingest the selection, compute the colours, write `colors.{csv,parquet}`.
pub fn command(db: &Database, selection: &Selection, config: &Config, out: &Path, texels: usize) -> Result<Vec<PathBuf>> {
    let start = Instant::now();
    let ingested = ingest::ingest(db, selection, config)?;
    ingested.check_strict()?;
    let channels = &config.channels;
    let mut timings = Timings { ingest_s: start.elapsed().as_secs_f64(), ..Default::default() };
    let memo = CurveMemo::load(out).recording();
    let fits = EffectiveMemo::load(out).recording();
    let colors = compute(&ingested.kept, texels, &mut timings, &memo, &fits);
    let written = colors_table(&ingested.kept, &colors, channels, texels).write(out, "colors", false)?;
    memo.save_or_warn(out);
    fits.save_or_warn(out);
    eprintln!(
        "colors: {} pages ({} excluded); ingest {:.2} s, spectra + {texels}-texel curves {:.2} s, errors + fits {:.2} s",
        ingested.kept.len(),
        ingested.excluded.len(),
        timings.ingest_s,
        timings.spectral_s,
        timings.fit_s
    );
    Ok(written)
}
