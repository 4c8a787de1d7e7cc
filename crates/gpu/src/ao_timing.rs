//! `ao_timing`: the surfel ambient-occlusion pass's GPU time against surfel count, by brute
//! force and through the surfel tree, over a sweep of meshes (the scanned meshes decimated
//! by vertex clustering and subdivided), with the fitted exponent p of time ∝ nᵖ
//! (least squares on log t over log n) per way of gathering; and, for the AO scenes that
//! name GTAO, on the same run, the scene's surfel pass (1–3 passes, tree and brute force)
//! beside the screen-space GTAO pass of each configuration the scene names (every preset,
//! bare and XeGTAO's, with its heuristics) over the scene's frame at each resolution asked
//! for (the G-buffer from the same coverage as `ao_errors`' per-pixel figures): the time of
//! one frame and, for the presets that accumulate frames of noise, the time to convergence
//! (frames × one frame), so that error (`ao_errors`) and time sit side by side. Time is GPU timestamps around the compute
//! pass where the adapter has them, else wall time from submit until the device is idle;
//! the table says which. On a CPU rasteriser (lavapipe) the figures are only meaningful
//! as ratios.

use anyhow::Result;
use nklut_tables::effects_tables::ao_timing;

use super::context::Gpu;
use super::passes::ao::{Gather, SurfelAoPass};
use super::passes::gtao::GtaoPass;
use super::timing::{median_and_iqr, Stopwatch, Timer};
use nklut_effects::ao::hierarchy::{Closeness, SurfelTree};
use nklut_effects::ao::shadow::ShadowForm;
use nklut_effects::ao::surfel::{decimated, subdivided, surfels, Surfel};
use nklut_effects::scene::mesh::Mesh;
use nklut_pipeline::output::Table;

/// One mesh of the sweep: its name (e.g. `bunny-decimated-0.02`) and surfels.
pub struct SweepMesh {
    pub name: String,
    pub surfels: Vec<Surfel>,
}

/// Vertex-clustering cell edges of the decimated meshes (unit-sphere meshes: about 1 k,
/// 3 k and 10 k vertices from the bunny).
pub const DECIMATION_CELLS: [f32; 3] = [0.1, 0.05, 0.025];

/// The sweep of one mesh: decimated at each of [`DECIMATION_CELLS`], as it is, and
/// subdivided once (about 4× the vertices).
pub fn sweep_meshes(name: &str, mesh: &Mesh) -> Vec<SweepMesh> {
    let mut out: Vec<SweepMesh> = DECIMATION_CELLS
        .iter()
        .map(|&cell| SweepMesh { name: format!("{name}-decimated-{cell}"), surfels: surfels(&decimated(mesh, cell)) })
        .collect();
    out.push(SweepMesh { name: name.into(), surfels: surfels(mesh) });
    out.push(SweepMesh { name: format!("{name}-subdivided-1"), surfels: surfels(&subdivided(mesh)) });
    out
}

/// How the sweep runs: brute force only up to `max_brute` surfels (n² per pass), `passes`
/// accessibility passes per sample, `warmup` untimed samples, then `repeats` timed ones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepSettings {
    pub max_brute: usize,
    pub passes: u32,
    pub warmup: u32,
    pub repeats: u32,
    pub form: ShadowForm,
    pub closeness: Closeness,
}

impl Default for SweepSettings {
    fn default() -> SweepSettings {
        SweepSettings {
            max_brute: 40_000,
            passes: 1,
            warmup: 1,
            repeats: 3,
            form: ShadowForm::FORM_FACTOR,
            closeness: Closeness::default(),
        }
    }
}

/// What a row times: the surfel pass gathering one way, or GTAO over a frame of
/// `resolution` of which `covered` pixels see a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Timed {
    Surfels(Gather),
    Gtao { gtao: nklut_effects::scene::surfels::Gtao, resolution: [u32; 2], covered: usize },
}

impl Timed {
    /// The `emitters` column: brute_force, hierarchy or gtao.
    pub fn name(self) -> &'static str {
        match self {
            Timed::Surfels(gather) => gather_name(gather),
            Timed::Gtao { .. } => "gtao",
        }
    }
}

/// One (mesh, way of gathering) timed.
#[derive(Clone, Debug, PartialEq)]
pub struct AoTimingRow {
    pub mesh: String,
    pub surfels: usize,
    pub gather: Timed,
    pub tree_nodes: usize,
    pub passes: u32,
    pub dispatches: u64,
    pub timer: Timer,
    pub repeats: u32,
    pub median_ms: f64,
    pub spread_ms: f64,
    /// p of time ∝ nᵖ fitted over every row of the same way of gathering.
    pub fitted_exponent: f64,
}

/// The name of a way of gathering in tables.
pub fn gather_name(gather: Gather) -> &'static str {
    match gather {
        Gather::BruteForce => "brute_force",
        Gather::Hierarchy => "hierarchy",
    }
}

/// Least-squares slope of ln t over ln n (NaN for fewer than two distinct n).
pub fn fitted_exponent(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().filter(|(n, t)| *n > 0.0 && *t > 0.0).map(|(n, t)| (n.ln(), t.ln())).collect();
    let k = logs.len() as f64;
    let (mx, my) = (logs.iter().map(|p| p.0).sum::<f64>() / k, logs.iter().map(|p| p.1).sum::<f64>() / k);
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Time `passes` passes of `pass`: one sample in milliseconds and the dispatches recorded.
fn sample(gpu: &Gpu, pass: &SurfelAoPass, passes: u32, stopwatch: &mut Stopwatch) -> Result<(f64, u64)> {
    let mut dispatches = 0;
    let ms = stopwatch.time_pass(gpu, |encoder, timestamps| {
        let writes = timestamps.map(|set| wgpu::ComputePassTimestampWrites {
            query_set: set,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        });
        dispatches = pass.encode(gpu, encoder, passes, writes);
    })?;
    Ok((ms, dispatches))
}

/// Time every mesh by brute force (up to `settings.max_brute` surfels) and through the tree.
pub fn sweep(gpu: &Gpu, meshes: &[SweepMesh], settings: &SweepSettings, log: &mut dyn FnMut(&str)) -> Result<Vec<AoTimingRow>> {
    let mut stopwatch = Stopwatch::new(gpu)?;
    let mut rows = Vec::new();
    for mesh in meshes {
        rows.extend(surfel_rows(gpu, &mesh.name, &mesh.surfels, settings.passes..=settings.passes, settings, &mut stopwatch, log)?);
    }
    for gather in [Gather::BruteForce, Gather::Hierarchy] {
        let timed = Timed::Surfels(gather);
        let points: Vec<(f64, f64)> = rows.iter().filter(|r| r.gather == timed).map(|r| (r.surfels as f64, r.median_ms)).collect();
        let p = fitted_exponent(&points);
        // One point fits no slope: the column stays empty.
        rows.iter_mut().filter(|r| r.gather == timed).for_each(|r| r.fitted_exponent = p);
    }
    Ok(rows)
}

/// The surfel pass over `surfels` (named `name`), through the tree and, up to
/// `settings.max_brute` surfels, by brute force, timed at each pass count of `pass_counts`.
fn surfel_rows(
    gpu: &Gpu,
    name: &str,
    surfels: &[Surfel],
    pass_counts: std::ops::RangeInclusive<u32>,
    settings: &SweepSettings,
    stopwatch: &mut Stopwatch,
    log: &mut dyn FnMut(&str),
) -> Result<Vec<AoTimingRow>> {
    let n = surfels.len();
    let tree = SurfelTree::new(surfels, settings.form, settings.closeness);
    let mut rows = Vec::new();
    for gather in [Gather::BruteForce, Gather::Hierarchy] {
        if gather == Gather::BruteForce && n > settings.max_brute {
            log(&format!("  {name} ({n} surfels): brute force skipped (> {})", settings.max_brute));
            continue;
        }
        let pass = SurfelAoPass::new(gpu, surfels, Some(&tree), gather, settings.form, settings.closeness)?;
        for passes in pass_counts.clone() {
            let mut dispatches = 0;
            let (median_ms, spread_ms) = timed(settings, || {
                let (ms, d) = sample(gpu, &pass, passes, stopwatch)?;
                dispatches = d;
                Ok(ms)
            })?;
            log(&format!(
                "  {name} ({n} surfels) {}, {passes} passes: median {median_ms:.3} ms, IQR {spread_ms:.3} ms",
                gather_name(gather)
            ));
            rows.push(AoTimingRow {
                mesh: name.into(),
                surfels: n,
                gather: Timed::Surfels(gather),
                tree_nodes: if gather == Gather::Hierarchy { tree.nodes.len() } else { 0 },
                passes,
                dispatches,
                timer: stopwatch.timer(),
                repeats: settings.repeats,
                median_ms,
                spread_ms,
                fitted_exponent: f64::NAN,
            });
        }
    }
    Ok(rows)
}

/// Median and IQR of `settings.repeats` timed samples after `settings.warmup` untimed ones.
fn timed(settings: &SweepSettings, mut sample: impl FnMut() -> Result<f64>) -> Result<(f64, f64)> {
    let mut samples = Vec::new();
    for round in 0..settings.warmup + settings.repeats {
        let ms = sample()?;
        if round >= settings.warmup {
            samples.push(ms);
        }
    }
    Ok(median_and_iqr(&samples))
}

/// An AO scene's surfel pass (passes 1..=`settings.passes`, through the tree and, up to
/// `settings.max_brute` surfels, by brute force) and, where the scene names GTAO, the GTAO
/// pass of each configuration (every preset and heuristic) over its frame at each of
/// `resolutions` ([width, height]), all timed in this run. A GTAO row times one frame's
/// dispatch (of an accumulating configuration: a frame after the first, which reads the
/// running sum and adds to it) and the denoiser's passes after it; its time to convergence is that × the frames accumulated
/// ([`AoTimingRow::convergence_ms`]). A scene naming no surfel effect gives no rows.
pub fn scene_rows(
    gpu: &Gpu,
    name: &str,
    scene: &nklut_effects::scene::Scene,
    resolutions: &[[u32; 2]],
    settings: &SweepSettings,
    log: &mut dyn FnMut(&str),
) -> Result<Vec<AoTimingRow>> {
    use nklut_effects::ao::experiment::{AoSettings, SurfelScene};
    use nklut_effects::ao::gtao::{GBuffer, Parameters};
    use nklut_effects::trace::Camera;
    let Some(effects) = &scene.effects else { return Ok(Vec::new()) };
    if !effects.names(nklut_effects::scene::EffectFamily::Surfels) {
        return Ok(Vec::new());
    }
    let stage = SurfelScene::new(scene, &AoSettings::default().budget)?;
    let n = stage.surfels.len();
    let mut stopwatch = Stopwatch::new(gpu)?;
    let timer = stopwatch.timer();
    let mut rows = surfel_rows(gpu, name, &stage.surfels, 1..=settings.passes, settings, &mut stopwatch, log)?;
    let configurations = effects.ambient_occlusion.as_ref().map(|a| a.gtao.clone()).unwrap_or_default();
    if configurations.is_empty() {
        return Ok(rows);
    }
    for &[width, height] in resolutions {
        let camera = Camera::new(&scene.camera, 0, width, height);
        let coverage = stage.coverage(&camera);
        let covered = coverage.iter().flatten().count();
        let gbuffer = GBuffer::from_coverage(&camera, &coverage, &stage.surfels).narrowed();
        for &g in &configurations {
            let pass = GtaoPass::new(gpu, &gbuffer, Parameters::of(g).narrowed())?;
            let frames = pass.frames();
            let frame = super::passes::gtao::timed_frame(frames);
            let (median_ms, spread_ms) = timed(settings, || {
                stopwatch.time_pass(gpu, |encoder, timestamps| {
                    let writes = timestamps.map(|set| wgpu::ComputePassTimestampWrites {
                        query_set: set,
                        beginning_of_pass_write_index: Some(0),
                        end_of_pass_write_index: Some(1),
                    });
                    pass.encode_frames(encoder, frame..frame + 1, writes);
                })
            })?;
            log(&format!(
                "  {name} gtao {width}×{height} ({covered} covered pixels, {}): one frame median {median_ms:.3} ms, IQR {spread_ms:.3} ms; {frames} frames {:.1} ms",
                g.label(),
                median_ms * frames as f64
            ));
            rows.push(AoTimingRow {
                mesh: name.into(),
                surfels: n,
                gather: Timed::Gtao { gtao: g, resolution: [width, height], covered },
                tree_nodes: 0,
                passes: 1,
                dispatches: 1,
                timer,
                repeats: settings.repeats,
                median_ms,
                spread_ms,
                fitted_exponent: f64::NAN,
            });
        }
    }
    Ok(rows)
}

impl AoTimingRow {
    /// GTAO's frames to convergence (the frames accumulated; 1 without noise); 0 for the
    /// surfel pass.
    pub fn frames(&self) -> u32 {
        match self.gather {
            Timed::Gtao { gtao, .. } => super::passes::gtao::accumulated_frames(nklut_effects::ao::gtao::Parameters::of(gtao).narrowed()),
            Timed::Surfels(_) => 0,
        }
    }

    /// GTAO's time to convergence: one frame's median × [`AoTimingRow::frames`] (`None` for
    /// the surfel pass, whose row is already its whole cost).
    pub fn convergence_ms(&self) -> Option<f64> {
        matches!(self.gather, Timed::Gtao { .. }).then(|| self.median_ms * self.frames() as f64)
    }
}

/// The largest frame edge GTAO is timed at (the G-buffer of 16384² is 8 GiB).
pub const MAX_GTAO_EDGE: u32 = 16_384;

/// A frame size as the command line gives it: `N` (N × N) or `WxH` (e.g. `1920x1080`), each
/// edge 1 to [`MAX_GTAO_EDGE`]; anything else is an error naming the text.
pub fn frame_size(text: &str) -> Result<[u32; 2], String> {
    let edge = |part: &str| -> Result<u32, String> {
        match part.trim().parse::<u32>() {
            Ok(n) if (1..=MAX_GTAO_EDGE).contains(&n) => Ok(n),
            _ => Err(format!("frame size {text:?}: each edge must be a whole number of pixels from 1 to {MAX_GTAO_EDGE} (N or WxH)")),
        }
    };
    match text.split_once(['x', '×']) {
        Some((w, h)) => Ok([edge(w)?, edge(h)?]),
        None => edge(text).map(|n| [n, n]),
    }
}

/// `ao_timing.*`: one row per (mesh, way of gathering), and per scene's GTAO resolution.
pub fn ao_timing_table(rows: &[AoTimingRow], adapter: &super::AdapterLine) -> Table {
    let a = adapter;
    let text = |f: &dyn Fn(&AoTimingRow) -> String| rows.iter().map(f).collect::<Vec<_>>();
    let gtao = |f: &dyn Fn(nklut_effects::scene::surfels::Gtao, [u32; 2], usize) -> i64| {
        rows.iter()
            .map(|r| match r.gather {
                Timed::Gtao { gtao, resolution, covered } => f(gtao, resolution, covered),
                Timed::Surfels(_) => 0,
            })
            .collect::<Vec<_>>()
    };
    let mut table = Table::new();
    table
        .put(ao_timing::ADAPTER, text(&|_| a.name.clone()))
        .put(ao_timing::DRIVER, text(&|_| a.driver.clone()))
        .put(ao_timing::MESH, text(&|r| r.mesh.clone()))
        .put(ao_timing::SURFELS, rows.iter().map(|r| r.surfels as i64).collect())
        .put(ao_timing::EMITTERS, text(&|r| r.gather.name().into()))
        .put(ao_timing::TREE_NODES, rows.iter().map(|r| r.tree_nodes as i64).collect())
        .put(ao_timing::PASSES, rows.iter().map(|r| r.passes as i64).collect())
        .put(ao_timing::DISPATCHES, rows.iter().map(|r| r.dispatches as i64).collect())
        .put(ao_timing::WIDTH, gtao(&|_, [w, _], _| w as i64))
        .put(ao_timing::HEIGHT, gtao(&|_, [_, h], _| h as i64))
        .put(ao_timing::COVERED_PIXELS, gtao(&|_, _, c| c as i64))
        .put(ao_timing::SLICES, gtao(&|g, _, _| g.slices as i64))
        .put(ao_timing::STEPS, gtao(&|g, _, _| g.steps as i64))
        .put(
            ao_timing::PRESET,
            text(&|r| match r.gather {
                Timed::Gtao { gtao, .. } => gtao.preset_label(),
                Timed::Surfels(_) => String::new(),
            }),
        )
        .put(
            ao_timing::RADIUS,
            rows.iter()
                .map(|r| match r.gather {
                    Timed::Gtao { gtao, .. } => Some(gtao.radius),
                    Timed::Surfels(_) => None,
                })
                .collect(),
        )
        .put(ao_timing::FRAMES, rows.iter().map(|r| r.frames() as i64).collect())
        .put(ao_timing::TIMER, text(&|r| r.timer.name().into()))
        .put(ao_timing::REPEATS, rows.iter().map(|r| r.repeats as i64).collect())
        .put(ao_timing::MEDIAN_MS, rows.iter().map(|r| r.median_ms).collect())
        .put(ao_timing::SPREAD_MS, rows.iter().map(|r| r.spread_ms).collect())
        .put(ao_timing::CONVERGENCE_MS, rows.iter().map(AoTimingRow::convergence_ms).collect())
        .put(ao_timing::FITTED_EXPONENT, rows.iter().map(|r| Some(r.fitted_exponent).filter(|p| p.is_finite())).collect());
    table
}

#[cfg(test)]
mod tests {
    use super::fitted_exponent;

    /// The tables of the GPU runner put the columns `nklut_tables::effects_tables` and
    /// `gpu_tables` list for them, in that order (the report reads them through the same
    /// constants).
    #[test]
    fn the_runners_tables_are_written_with_the_columns_their_reader_names() {
        use nklut_tables::effects_tables::{ao_timing, effects_timing};
        let names = |table: nklut_pipeline::output::Table| table.columns.into_iter().map(|c| c.name).collect::<Vec<_>>();
        let adapter = crate::AdapterLine::default();
        assert_eq!(names(super::ao_timing_table(&[], &adapter)), ao_timing::NAMES);
        assert_eq!(names(crate::effects::timing_table(&[], &adapter)), effects_timing::NAMES);
        assert_eq!(names(crate::runner::timing_rows_table(&[], &adapter)), nklut_tables::gpu_tables::gpu_timing::NAMES);
        assert_eq!(names(crate::runner::image_error_rows_table(&[])), nklut_tables::gpu_tables::image_errors::NAMES);
    }

    #[test]
    fn frame_sizes_read_as_squares_or_width_by_height() {
        use super::frame_size;
        assert_eq!(frame_size("256"), Ok([256, 256]));
        assert_eq!(frame_size("1920x1080"), Ok([1920, 1080]));
        assert_eq!(frame_size("1920×1080"), Ok([1920, 1080]));
        for bad in ["0", "x", "1920x", "-4", "20000", "1.5", "12x0"] {
            let error = frame_size(bad).unwrap_err();
            assert!(error.contains(&format!("{bad:?}")), "{error}");
        }
    }

    #[test]
    fn the_fitted_exponent_recovers_a_power_law() {
        let points: Vec<(f64, f64)> = [1e3, 4e3, 1.6e4, 6.4e4].iter().map(|&n: &f64| (n, 3e-7 * n.powf(1.9))).collect();
        assert!((fitted_exponent(&points) - 1.9).abs() < 1e-12);
        assert!(fitted_exponent(&points[..1]).is_nan());
    }
}
