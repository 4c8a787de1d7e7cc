//! The browser bench's part of ambient occlusion: what the page needs to time the native
//! `ao_timing` scene rows ([`crate::ao_timing::scene_rows`]) of a scene that names
//! `ambient_occlusion` — the surfel pass (brute force up to the native limit and through the
//! surfel tree, 1 to [`PASSES`] passes) and one frame of GTAO per configuration (every preset
//! and heuristic), with its time to convergence — as rows of the same schema.
//!
//! Every byte comes from the functions the native passes upload from: the discs, links and
//! parameter blocks of [`SurfelUpload`], the G-buffer and per-frame uniforms of
//! [`crate::passes::gtao`] (each frame's uniform at a stride of WebGPU's default uniform
//! offset alignment, 256); the bindings come from the passes' [`Interface`] declarations,
//! the modules are the compile check's, and each row's cells but the measured ones are the
//! native `ao_timing` table's own ([`ao_timing_table`]). GTAO runs at the scene's
//! `resolution` only (a 1024² G-buffer would be 32 MiB of page); the native runner times
//! the larger frames.

use anyhow::Result;
use serde::Serialize;

use super::base64;
use super::effects::{module_name, BindingPlan};
use crate::ao_timing::{ao_timing_table, AoTimingRow, SweepSettings, Timed};
use crate::passes::ao::{Gather, SurfelAoPass, SurfelUpload};
use crate::passes::gtao::{accumulated_frames, gbuffer_bytes, timed_frame, uniform_bytes, GtaoPass, UNIFORM_SIZE};
use crate::passes::Pass;
use crate::timing::Timer;
use nklut_effects::ao::experiment::{AoSettings, SurfelScene};
use nklut_effects::ao::gtao::{GBuffer, Parameters};
use nklut_effects::ao::hierarchy::SurfelTree;
use nklut_effects::scene::Scene;
use nklut_effects::trace::Camera;

/// The columns of `ao_timing` the page measures and fills in; every other cell comes with
/// the row.
pub const MEASURED: [&str; 6] = ["adapter", "driver", "timer", "median_ms", "spread_ms", "convergence_ms"];

/// The surfel pass's accessibility passes timed, 1 to this (as `nklut gpu ao-timing`).
pub const PASSES: u32 = 3;

/// WebGPU's default `minUniformBufferOffsetAlignment`: every device accepts offsets of it.
pub const UNIFORM_ALIGNMENT: u32 = 256;

/// Ambient occlusion's timing, as the page runs it.
#[derive(Debug, Serialize)]
pub struct AoPlan {
    pub warmup: u32,
    pub repeats: u32,
    pub surfels: SurfelPlan,
    pub gtao: Option<GtaoPlan>,
    /// One per row of `ao_timing`, in the native order.
    pub rows: Vec<AoRowPlan>,
    pub measured: Vec<&'static str>,
}

/// The surfel pass (`shaders/surfel_ao.wgsl`).
#[derive(Debug, Serialize)]
pub struct SurfelPlan {
    pub module: String,
    pub bindings: Vec<BindingPlan>,
    pub count: u32,
    pub nodes: u32,
    /// The discs (surfels, then tree nodes), the links and the two `Params` blocks, base64.
    pub discs: String,
    pub links: String,
    pub params: [String; 2],
    /// Bytes of the accessibility state and of the bent normals.
    pub state_bytes: u64,
    pub bent_bytes: u64,
}

/// GTAO (`shaders/gtao.wgsl`) over the scene's frame.
#[derive(Debug, Serialize)]
pub struct GtaoPlan {
    pub module: String,
    pub bindings: Vec<BindingPlan>,
    pub width: u32,
    pub height: u32,
    /// `GSample` per pixel, base64.
    pub gbuffer: String,
    /// Bytes between two frames' uniforms, and one uniform's size.
    pub stride: u64,
    pub uniform_size: u64,
    pub configurations: Vec<GtaoConfigurationPlan>,
}

#[derive(Debug, Serialize)]
pub struct GtaoConfigurationPlan {
    /// Every accumulated frame's `GtaoParams`, frame k at k × stride, then each denoiser
    /// pass's, pass j at (frames + j) × stride, base64.
    pub uniforms: String,
    pub frames: u32,
    /// Denoiser passes, dispatched after every timed frame (as an engine denoises each).
    pub denoise_passes: u32,
    /// The frame one timed sample dispatches ([`timed_frame`]).
    pub timed_frame: u32,
}

/// A row: what it times and its cells but the [`MEASURED`] ones.
#[derive(Debug, Serialize)]
pub struct AoRowPlan {
    /// `brute_force`, `hierarchy` or `gtao`.
    pub kind: &'static str,
    /// Accessibility passes (surfel rows).
    pub passes: u32,
    /// The GTAO configuration (gtao rows).
    pub configuration: Option<usize>,
    /// Frames to convergence (gtao rows; 0 for the surfel pass).
    pub frames: u32,
    pub row: serde_json::Map<String, serde_json::Value>,
}

/// The AO plan of `scene` (none when it names no `ambient_occlusion`).
pub fn plan(scene: &Scene) -> Result<Option<AoPlan>> {
    let Some(ao) = scene.effects.as_ref().and_then(|e| e.ambient_occlusion.as_ref()) else { return Ok(None) };
    let settings = AoSettings::default();
    let sweep = SweepSettings::default();
    let stage = SurfelScene::new(scene, &settings.budget)?;
    let n = stage.surfels.len();
    let tree = SurfelTree::new(&stage.surfels, settings.form, settings.closeness);
    let upload = SurfelUpload::of(&stage.surfels, Some(&tree), settings.form, settings.closeness);
    let [discs, links, first, second] = upload.bytes();
    let [state_bytes, bent_bytes] = upload.state_bytes();
    let surfel_interface = <SurfelAoPass as Pass>::INTERFACE;
    let surfels = SurfelPlan {
        module: module_name(&surfel_interface, surfel_interface.name),
        bindings: super::effects::bindings(&surfel_interface),
        count: n as u32,
        nodes: tree.nodes.len() as u32,
        discs: base64(&discs),
        links: base64(&links),
        params: [base64(&first), base64(&second)],
        state_bytes,
        bent_bytes,
    };
    // The native rows: brute force (up to its limit) then the tree, each at 1..=PASSES passes;
    // then GTAO per configuration over the scene's frame.
    let mut rows: Vec<AoTimingRow> = Vec::new();
    let mut kinds = Vec::new();
    let blank = |gather: Timed, tree_nodes: usize, passes: u32, dispatches: u64| AoTimingRow {
        mesh: scene.file.file_stem().map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned()),
        surfels: n,
        gather,
        tree_nodes,
        passes,
        dispatches,
        timer: Timer::Timestamp,
        repeats: scene.timing.repeats,
        median_ms: 0.0,
        spread_ms: 0.0,
        fitted_exponent: f64::NAN,
    };
    for gather in [Gather::BruteForce, Gather::Hierarchy] {
        if gather == Gather::BruteForce && n > sweep.max_brute {
            continue;
        }
        for passes in 1..=PASSES {
            let (nodes, dispatches) = match gather {
                Gather::BruteForce => (0, passes as u64),
                Gather::Hierarchy => (tree.nodes.len(), 2 * passes as u64),
            };
            rows.push(blank(Timed::Surfels(gather), nodes, passes, dispatches));
            kinds.push((crate::ao_timing::gather_name(gather), passes, None, 0));
        }
    }
    let gtao = if ao.gtao.is_empty() {
        None
    } else {
        let [width, height] = scene.resolution;
        let camera = Camera::new(&scene.camera, 0, width, height);
        let coverage = stage.coverage(&camera);
        let covered = coverage.iter().flatten().count();
        let gbuffer: GBuffer<f32> = GBuffer::from_coverage(&camera, &coverage, &stage.surfels).narrowed();
        let stride = crate::passes::gtao::uniform_stride(UNIFORM_ALIGNMENT);
        let mut configurations = Vec::new();
        for (index, &g) in ao.gtao.iter().enumerate() {
            let parameters = Parameters::of(g).narrowed();
            let frames = accumulated_frames(parameters);
            configurations.push(GtaoConfigurationPlan {
                uniforms: base64(&uniform_bytes(&gbuffer, parameters, stride)),
                frames,
                denoise_passes: parameters.heuristics.denoise_passes,
                timed_frame: timed_frame(frames),
            });
            rows.push(blank(Timed::Gtao { gtao: g, resolution: [width, height], covered }, 0, 1, 1));
            kinds.push(("gtao", 1, Some(index), frames));
        }
        let gtao_interface = <GtaoPass as Pass>::INTERFACE;
        Some(GtaoPlan {
            module: module_name(&gtao_interface, gtao_interface.name),
            bindings: super::effects::bindings(&gtao_interface),
            width,
            height,
            gbuffer: base64(&gbuffer_bytes(&gbuffer)),
            stride,
            uniform_size: UNIFORM_SIZE,
            configurations,
        })
    };
    let table = ao_timing_table(&rows, &Default::default());
    let cells = row_cells(&table)?;
    let rows = kinds
        .into_iter()
        .zip(cells)
        .map(|((kind, passes, configuration, frames), row)| AoRowPlan { kind, passes, configuration, frames, row })
        .collect();
    Ok(Some(AoPlan { warmup: scene.timing.warmup, repeats: scene.timing.repeats, surfels, gtao, rows, measured: MEASURED.to_vec() }))
}

/// The rows of `table` as JSON objects without the [`MEASURED`] cells.
fn row_cells(table: &nklut_pipeline::output::Table) -> Result<Vec<serde_json::Map<String, serde_json::Value>>> {
    super::rows_without(table, "ao_timing", &MEASURED)
}

#[cfg(test)]
mod tests {
    use super::*;
    use base64::Engine;

    /// The uniforms the page binds: frame k's `GtaoParams` at k × 256 bytes, its `frame`
    /// (the fifth u32, byte 16) k, `frames` (byte 20) the frames accumulated, `noise` (byte
    /// 24) on for XeGTAO, then its denoiser pass's; Algorithm 1 one frame without noise or
    /// denoiser. The timed frame is the second of an accumulating configuration.
    #[test]
    fn each_frame_s_uniform_sits_at_its_offset_with_its_index() {
        let text = "resolution: [16, 12]\ncamera: {axis: [0.3, 1, 0.2], distance: 3, frames: 1}\neffects: {ambient_occlusion: {passes: 1, gtao: [{radius: 0.5}, {preset: xe-high, radius: 0.5, frames: 16}]}}\nobjects:\n  - {mesh: cube, diffuse: [0.8, 0.8, 0.8]}\nmeasurements: [image_error]\n";
        let scene = Scene::parse(text, std::path::Path::new("ao.yaml")).unwrap();
        let plan = plan(&scene).unwrap().expect("an AO plan");
        let gtao = plan.gtao.as_ref().unwrap();
        assert_eq!((gtao.stride, gtao.uniform_size), (256, 96));
        let word = |bytes: &[u8], at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
        for (configuration, (frames, noise, denoise)) in gtao.configurations.iter().zip([(1u32, 0u32, 0u32), (16, 1, 1)]) {
            let bytes = base64::engine::general_purpose::STANDARD.decode(&configuration.uniforms).unwrap();
            assert_eq!(bytes.len(), 256 * (frames + denoise) as usize);
            for k in 0..frames as usize {
                assert_eq!([word(&bytes, 256 * k), word(&bytes, 256 * k + 4)], [16, 12]);
                assert_eq!([word(&bytes, 256 * k + 16), word(&bytes, 256 * k + 20), word(&bytes, 256 * k + 24)], [k as u32, frames, noise]);
            }
            // XeGTAO's one denoiser pass: the last, its centre weighing beta 1.2 (byte 80),
            // the last-pass flag (byte 84) set.
            for j in 0..denoise as usize {
                let at = 256 * (frames as usize + j);
                assert_eq!((f32::from_bits(word(&bytes, at + 80)), word(&bytes, at + 84)), (1.2, 1));
            }
            assert_eq!((configuration.frames, configuration.denoise_passes), (frames, denoise));
            assert_eq!(configuration.timed_frame, if frames > 1 { 1 } else { 0 });
        }
        // G-buffer: 32 bytes a pixel.
        assert_eq!(base64::engine::general_purpose::STANDARD.decode(&gtao.gbuffer).unwrap().len(), 16 * 12 * 32);
        // Rows: brute force and tree at 1–3 passes (6 × 9 = 54 surfels), then each configuration.
        assert_eq!(plan.rows.len(), 2 * PASSES as usize + 2);
        assert!(plan.rows.iter().all(|r| MEASURED.iter().all(|m| !r.row.contains_key(*m))));
        // Its frames (16 of the preset's 64) make it a modified preset, as ao_errors names it.
        assert_eq!(plan.rows[7].row["preset"], "xe-high (modified)");
        assert_eq!(plan.rows[7].frames, 16);
    }
}
