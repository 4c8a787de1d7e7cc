//! The surfel ambient-occlusion kernel (`shaders/surfel_ao.wgsl`) on whatever adapter there
//! is (lavapipe in CI) against its f64 CPU twin (`effects::ao`): the shadow term over a
//! ramp of configurations, and accessibility and bent normals after 1, 2 and 3 passes,
//! by brute force and through the surfel tree, on a small self-occluding mesh; and the
//! GTAO kernel (`shaders/gtao.wgsl`) against its f32 CPU twin (`effects::ao::gtao`) on a frame.
//!
//! No adapter at all is a FAILURE (install `mesa-vulkan-drivers`), unless
//! NKLUT_SKIP_GPU_TESTS=1, which skips these tests with a message.
#![cfg(feature = "gpu")]

mod common;

use common::gpu::shared as device;
use glam::DVec3;
use nklut::effects::ao::accessibility::{accessibility_by_pass, BruteForce};
use nklut::effects::ao::hierarchy::{Closeness, SurfelTree};
use nklut::effects::ao::shadow::{disc_term_real, transfer, ShadowForm};
use nklut::effects::ao::shapes::torus;
use nklut::effects::ao::surfel::{surfels, Surfel};
use nklut::gpu::passes::ao::{shadow_terms, Gather, SurfelAoPass};

/// The shadow term over a ramp, against its f32 twin (`disc_term_real::<f32>`) and the f64
/// form: a disc of area 0.05 at distances 0.05 … 5 along a direction
/// that turns from the receiver's normal to below its horizon, its own normal turning from
/// facing away (casting) to facing the receiver (casting nothing), for g = 1 and 4. The
/// WGSL evaluates the same formula in f32: a handful of roundings of values of order 1,
/// relative error ≲ 10 ulp ≈ 1e-6; bound 1e-5 relative plus 1e-7 absolute (for the
/// near-zero values at the horizon, where cos θ is the difference of order-1 numbers).
#[test]
fn the_wgsl_shadow_term_matches_its_cpu_twin_on_a_ramp() {
    let Some(gpu) = device() else { return };
    let mut pairs = Vec::new();
    for i in 0..40 {
        let h = 0.05 * 100f64.powf(i as f64 / 39.0);
        for j in 0..12 {
            let polar = 1.7 * j as f64 / 11.0; // up to past the horizon
            for k in 0..6 {
                let turn = std::f64::consts::PI * k as f64 / 5.0;
                let direction = DVec3::new(polar.sin(), 0.0, polar.cos());
                let normal = DVec3::new((polar + turn).sin(), 0.0, (polar + turn).cos());
                let emitter = Surfel { centre: direction * h, normal, area: 0.05 };
                let receiver = Surfel { centre: DVec3::ZERO, normal: DVec3::Z, area: 1.0 };
                pairs.push((emitter, receiver));
            }
        }
    }
    for form in [ShadowForm::FORM_FACTOR, ShadowForm::RECEIVER_GAIN_FOUR] {
        let gpu_terms = shadow_terms(&gpu, &pairs, form).unwrap();
        let mut worst: f64 = 0.0;
        let mut worst_twin: f64 = 0.0;
        let mut casting = 0;
        for ((emitter, receiver), got) in pairs.iter().zip(&gpu_terms) {
            // The f32 twin: the same operations in the same order; the GPU may fuse a
            // multiply-add in the dot products, so a few ulp apart (bound 1e-6 relative,
            // 1e-9 absolute at the horizon, where cos θ is a difference of order-1 terms).
            let narrow = |v: DVec3| v.as_vec3().to_array();
            let twin = disc_term_real::<f32>(
                narrow(emitter.centre),
                narrow(emitter.normal),
                emitter.area as f32,
                narrow(receiver.centre),
                narrow(receiver.normal),
                form.receiver_gain as f32,
                1.0,
            );
            let twin_error = (got[0] - twin[0]).abs() as f64;
            worst_twin = worst_twin.max(twin_error / (twin[0] as f64).max(1e-3));
            assert!(twin_error <= 1e-6 * twin[0] as f64 + 1e-9, "g {}: {emitter:?}: GPU {got:?}, f32 twin {twin:?}", form.receiver_gain);
            let (s, v) = transfer(form, emitter, receiver.centre, receiver.normal);
            casting += (s > 0.0) as usize;
            let error = (got[0] as f64 - s).abs();
            worst = worst.max(error / (s + 1e-2));
            assert!(error <= 1e-5 * s + 1e-7, "g {}: {emitter:?}: GPU {got:?}, CPU {s} {v:?}", form.receiver_gain);
            if s > 0.0 {
                assert!((DVec3::new(got[1] as f64, got[2] as f64, got[3] as f64) - v).length() < 1e-6);
            }
        }
        eprintln!(
            "shadow term g = {}: {} of {} configurations cast shadow; worst relative error against the f64 twin {worst:.2e}, against the f32 twin {worst_twin:.2e}",
            form.receiver_gain,
            casting,
            pairs.len()
        );
        assert!(casting > pairs.len() / 4 && casting < pairs.len(), "the ramp covers both casting and non-casting configurations");
    }
}

/// The largest |Δ| between GPU and CPU accessibility, and the largest angle between bent normals.
fn differences(gpu: &nklut::gpu::passes::ao::AoOutput, values: &[f64], bent: &[DVec3]) -> (f64, f64, usize) {
    let mut worst = 0.0f64;
    let mut over = 0;
    for (g, c) in gpu.accessibility.iter().zip(values) {
        let d = (*g as f64 - c).abs();
        worst = worst.max(d);
        over += (d > 1e-4) as usize;
    }
    let angle = gpu
        .bent_normals
        .iter()
        .zip(bent)
        .map(|(g, c)| DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64).angle_between(*c))
        .fold(0.0, f64::max);
    (worst, angle, over)
}

/// Accessibility and bent normals of the kernel against the f64 CPU twin on a torus of
/// 1 225 surfels (self-occluding: the inner ring hides itself), for 1, 2 and 3 passes, by
/// brute force and through the tree at κ = 16 (which merges: the CPU twin does at most
/// half of brute force's evaluations).
///
/// Bound, brute force: each accessibility is 1 − a sum of 1 224 terms in [0, 1), each the
/// f32 shadow term (relative 1e-6, the ramp above) times an f32 weight, summed in f32: the
/// error of the sum is ≲ 1 224 × 2⁻²⁴ × Σ|terms| ≲ 7e-5 × the total shadow (< 1); passes
/// carry the previous pass's error through weights that multiply terms summing to < 1, so
/// errors do not grow. Bound 1e-4 per vertex. Bent normals: the same sums, direction within
/// 1e-3 rad.
/// Through the tree the same, except where a node's test r² ≥ κA falls within f32 rounding
/// of equality: GPU and CPU then take different cuts, and the vertex differs by the
/// hierarchy's own approximation of that node (≤ 0.02, the bound of the hierarchy against
/// brute force in `effects::ao`). At most 2 % of vertices may do so.
#[test]
fn the_wgsl_surfel_kernel_matches_its_cpu_twin_for_each_pass_count_with_and_without_the_tree() {
    let Some(gpu) = device() else { return };
    let s = surfels(&torus(1.0, 0.6, 48, 24));
    assert_eq!(s.len(), 1225);
    let form = ShadowForm::FORM_FACTOR;
    let closeness = Closeness::default();
    let tree = SurfelTree::new(&s, form, closeness);
    let brute = BruteForce { surfels: &s, form };
    let cpu_brute = accessibility_by_pass(&brute, 3);
    let cpu_tree = accessibility_by_pass(&tree, 3);
    assert!(
        cpu_tree[1].interactions * 2 <= cpu_brute[1].interactions,
        "the tree merges: {} vs {}",
        cpu_tree[1].interactions,
        cpu_brute[1].interactions
    );
    let brute_pass = SurfelAoPass::new(&gpu, &s, None, Gather::BruteForce, form, closeness).unwrap();
    let tree_pass = SurfelAoPass::new(&gpu, &s, Some(&tree), Gather::Hierarchy, form, closeness).unwrap();
    for passes in 1..=3u32 {
        let cpu = &cpu_brute[passes as usize];
        let out = brute_pass.run(&gpu, passes).unwrap();
        assert_eq!(out.dispatches, passes as u64);
        let (worst, angle, _) = differences(&out, &cpu.values, &cpu.bent_normals);
        eprintln!("brute force, {passes} passes: max |Δa| {worst:.2e}, max bent-normal angle {angle:.2e} rad");
        assert!(worst <= 1e-4 && angle <= 1e-3, "brute force {passes} passes: {worst} {angle}");
        let cpu = &cpu_tree[passes as usize];
        let out = tree_pass.run(&gpu, passes).unwrap();
        assert_eq!(out.dispatches, 2 * passes as u64);
        let (worst, angle, over) = differences(&out, &cpu.values, &cpu.bent_normals);
        eprintln!("tree, {passes} passes: max |Δa| {worst:.2e} ({over} vertices over 1e-4), max bent-normal angle {angle:.2e} rad");
        assert!(worst <= 0.02 && over * 50 <= s.len(), "tree {passes} passes: max {worst}, {over} vertices over 1e-4");
        // The tree's result differs from brute force's (it is an approximation), so the
        // comparison above really tells the two kernels apart.
        assert_ne!(cpu_tree[passes as usize].values, cpu_brute[passes as usize].values);
    }
    // Zero passes: everything accessible.
    assert!(brute_pass.run(&gpu, 0).unwrap().accessibility.iter().all(|&a| a == 1.0));
}

/// Bad input is an error, not a panic.
#[test]
fn the_surfel_pass_rejects_what_it_cannot_run() {
    let Some(gpu) = device() else { return };
    let form = ShadowForm::FORM_FACTOR;
    assert!(SurfelAoPass::new(&gpu, &[], None, Gather::BruteForce, form, Closeness::default()).is_err());
    let s = surfels(&torus(1.0, 0.6, 6, 4));
    let error =
        SurfelAoPass::new(&gpu, &s, None, Gather::Hierarchy, form, Closeness::default()).err().expect("the hierarchy without a tree");
    assert!(error.to_string().contains("tree"), "{error}");
}

/// Colour bleeding on the GPU against the f64 twin: a white floor beside a red wall (two
/// subdivided squares), lit from (1, 1, 0); one and two bounces, emitters weighted by 1 and
/// by weights that vary from emitter to emitter (here the open squares hide nothing from
/// each other, so their accessibility would be 1 everywhere). Bound: each gathered value is a sum of ~160 products
/// of f32 form factors (relative 1e-6, the ramp above), f32 radiosity and f32 weights, summed
/// in f32: ≲ 160 × 2⁻²⁴ ≈ 1e-5 of the sum; the second bounce carries the first's error
/// through albedos < 1. Bound 1e-4 relative to the largest value, per channel.
#[test]
fn the_wgsl_indirect_gather_matches_its_cpu_twin() {
    use nklut::effects::ao::indirect::{surfel_indirect, Rgb};
    use nklut::gpu::passes::indirect::IndirectPass;
    use nklut::scene::mesh::Mesh;
    let Some(gpu) = device() else { return };
    let quad = |centre: DVec3, u: DVec3, v: DVec3| {
        let n = u.cross(v);
        let corner = |a: f64, b: f64| (centre + u * a + v * b).as_vec3().to_array();
        let mesh = Mesh {
            positions: vec![corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)],
            normals: vec![n.as_vec3().to_array(); 4],
            indices: vec![0, 1, 2, 0, 2, 3],
        };
        nklut::effects::ao::surfel::subdivided_times(&mesh, 3)
    };
    let floor = surfels(&quad(DVec3::ZERO, DVec3::Z, DVec3::X));
    let wall = surfels(&quad(DVec3::new(-1.0, 1.0, 0.0), DVec3::Y, DVec3::Z));
    let all: Vec<Surfel> = floor.iter().chain(&wall).copied().collect();
    let albedo: Vec<Rgb> = (0..all.len()).map(|i| if i < floor.len() { [0.8; 3] } else { [0.8, 0.1, 0.1] }).collect();
    // Direct light without shadows (the walls do not shade each other from (1, 1, 0)).
    let towards = DVec3::new(1.0, 1.0, 0.0).normalize();
    let direct: Vec<Rgb> = all.iter().map(|s| [s.normal.dot(towards).max(0.0); 3]).collect();
    let form = ShadowForm::FORM_FACTOR;
    let varying: Vec<f64> = (0..all.len()).map(|j| 0.3 + 0.7 * (j % 7) as f64 / 6.0).collect();
    let pass = IndirectPass::new(&gpu, &all, form).unwrap();
    for weights in [vec![1.0; all.len()], varying] {
        for bounces in [1, 2] {
            let cpu = surfel_indirect(&all, &albedo, &direct, &weights, form, bounces);
            let out = pass.run(&gpu, &albedo, &direct, &weights, bounces).unwrap();
            assert_eq!(out.dispatches, bounces as u64);
            let largest = cpu.iter().flatten().copied().fold(0.0, f64::max);
            let worst =
                cpu.iter().zip(&out.irradiance).flat_map(|(c, g)| (0..3).map(move |k| (c[k] - g[k] as f64).abs())).fold(0.0, f64::max);
            eprintln!("indirect, {bounces} bounces: largest {largest:.4}, max |GPU − CPU| {worst:.2e}");
            assert!(largest > 0.01, "the wall bleeds onto the floor");
            assert!(worst <= 1e-4 * largest, "{bounces} bounces: {worst} of {largest}");
        }
    }
}

/// The scene-driven runner computes the surfel effects a scene names, and nothing for a
/// scene that names none: the counters stay zero without `ambient_occlusion` / `indirect`;
/// with them they count one surfel per vertex, the tree's 2n − 1 nodes, the passes and the
/// bounces, and the GPU's accessibility equals the CPU twin's to f32 precision.
#[test]
fn the_runner_runs_surfel_effects_only_when_the_scene_names_them() {
    use nklut::effects::experiment::EffectsStats;
    use nklut::gpu::passes::ao::run_scene;
    use nklut::gpu::{run_with_materials, RunStats};
    use nklut::scene::Scene;
    use std::path::Path;
    let Some(gpu) = device() else { return };
    let reflections = "measurements: [image_error]\neffects: { reflection: { max_depth: 1 } }\nobjects:\n  - { mesh: sphere, material: a/b/c, method: exact }\n  - { mesh: plane, diffuse: [0.5, 0.5, 0.5] }\n";
    let mut stats = EffectsStats::default();
    let none = run_scene(&Scene::parse(reflections, Path::new("reflections.yaml")).unwrap(), &gpu, &mut stats, &mut |_| {}).unwrap();
    assert!(none.is_none());
    assert_eq!(stats, EffectsStats::default());

    let ao = "resolution: [8, 8]\ncamera: { frames: 1 }\nmeasurements: [image_error]\neffects: { ambient_occlusion: { passes: 2, hierarchy: true, gtao: { radius: 0.5 } }, indirect: { bounces: 2 } }\nobjects:\n  - { mesh: cube, diffuse: [0.8, 0.2, 0.2], subdivide: 2 }\n  - { mesh: cube, scale: [2, 0.05, 2], position: [0, -0.62, 0], diffuse: [0.7, 0.7, 0.7], subdivide: 2 }\n";
    let scene = Scene::parse(ao, Path::new("ao.yaml")).unwrap();
    let report = run_with_materials(&scene, &[], &gpu, RunStats::default(), &mut |line| eprintln!("{line}")).unwrap();
    let counted = &report.stats.effects;
    // Each cube: 6 faces × 25 vertices after two subdivisions.
    assert_eq!(counted.surfels, 2 * 6 * 25);
    assert_eq!((counted.tree_nodes, counted.ao_passes, counted.indirect_bounces), (2 * counted.surfels - 1, 2, 2));
    assert_eq!((counted.cube_maps, report.stats.frames_rendered), (0, 0), "no specular object, no cube map, no F-only frame");
    let mut again = EffectsStats::default();
    let result = run_scene(&scene, &gpu, &mut again, &mut |_| {}).unwrap().unwrap();
    assert_eq!(&again, counted);
    assert!(result.twin_difference <= 1e-4, "{}", result.twin_difference);
    assert!(result.accessibility.accessibility.iter().any(|&a| a < 0.99), "the cubes shade each other");
    let indirect = result.indirect.unwrap();
    assert!(indirect.irradiance.iter().all(|e| e.iter().all(|x| x.is_finite() && *x >= 0.0)));
    assert!(indirect.irradiance.iter().any(|e| e[0] > e[2]), "the red cube bleeds red");
    // GTAO, named by the scene, over its 8×8 frame.
    let gtao = result.gtao.unwrap();
    assert_eq!(gtao.accessibility.len(), 64);
    assert!(gtao.accessibility.iter().any(|a| a.is_some()));
    assert!(gtao.twin_difference <= 2e-4, "{}", gtao.twin_difference);
}

/// An AO scene timed (`gpu bench` asks for timing) names no (material, method) pair: no
/// F-only pass runs, the run says why, and no empty `gpu_timing` table is published.
#[test]
fn an_ao_scene_asked_for_timing_publishes_no_empty_fresnel_timing() {
    use nklut::gpu::{run_with_materials, RunStats};
    use nklut::scene::Scene;
    use std::path::Path;
    let Some(gpu) = device() else { return };
    let ao = "resolution: [8, 8]\ncamera: { frames: 1 }\nmeasurements: [timing]\neffects: { ambient_occlusion: { passes: 1 } }\nobjects:\n  - { mesh: cube, diffuse: [0.8, 0.2, 0.2], subdivide: 1 }\n";
    let scene = Scene::parse(ao, Path::new("ao.yaml")).unwrap();
    let report = run_with_materials(&scene, &[], &gpu, RunStats::default(), &mut |_| {}).unwrap();
    assert!(report.timing.is_empty());
    assert!(report.stats.skipped.iter().any(|s| s.contains("no (material, method) pair")), "{:?}", report.stats.skipped);
    let out = tempfile::tempdir().unwrap();
    let written = nklut::gpu::runner::write_tables(&report, out.path()).unwrap();
    assert!(written.iter().all(|p| !p.to_string_lossy().contains("gpu_timing")), "{written:?}");
}

/// GTAO on the GPU against its f32 CPU twin (the body of the f64 figures) over a frame of a
/// cube on a slab, 96×64: every covered pixel covered on both, and equal within f32
/// rounding. Where they can part: the GPU's acos/cos/sin (a few ulp; acos near ±1
/// magnifies them) and a sample that rounding moves across a pixel edge.
#[test]
fn the_wgsl_gtao_matches_its_cpu_twin_on_a_frame() {
    use nklut::budget::MemoryBudget;
    use nklut::effects::ao::experiment::SurfelScene;
    use nklut::effects::ao::gtao::{gtao, GBuffer, Parameters};
    use nklut::effects::trace::Camera;
    use nklut::gpu::passes::gtao::GtaoPass;
    use nklut::scene::Scene;
    use std::path::Path;
    let Some(gpu) = device() else { return };
    let text = "camera: { axis: [0.3, 1, 0.2], distance: 3, frames: 1 }\nmeasurements: [image_error]\neffects: { ambient_occlusion: { passes: 1 } }\nobjects:\n  - { mesh: cube, diffuse: [0.8, 0.8, 0.8], subdivide: 1 }\n  - { mesh: cube, scale: [2, 0.05, 2], position: [0, -0.55, 0], diffuse: [0.7, 0.7, 0.7], subdivide: 2 }\n";
    let scene = Scene::parse(text, Path::new("gtao.yaml")).unwrap();
    let stage = SurfelScene::new(&scene, &MemoryBudget::of_machine()).unwrap();
    let camera = Camera::new(&scene.camera, 0, 96, 64);
    let wide = GBuffer::from_coverage(&camera, &stage.coverage(&camera), &stage.surfels);
    let g = wide.narrowed();
    for p in [Parameters::bare(0.5, 4, 8), Parameters::bare(2.0, 2, 24)] {
        let got = GtaoPass::new(&gpu, &g, p.narrowed()).unwrap().run(&gpu).unwrap();
        let twin = gtao(&g, p.narrowed());
        let f64_values = gtao(&wide, p);
        let (mut largest, mut covered, mut occluded) = (0.0f64, 0, 0);
        let mut largest_f64 = 0.0f64;
        for ((a, b), c) in got.iter().zip(&twin).zip(&f64_values) {
            assert_eq!(a.is_some(), b.is_some());
            if let (Some(a), Some(b), Some(c)) = (a, b, c) {
                largest = largest.max((a - b).abs() as f64);
                largest_f64 = largest_f64.max((*a as f64 - c).abs());
                covered += 1;
                occluded += (*b < 0.9) as usize;
            }
        }
        eprintln!("{p:?}: {covered} pixels, {occluded} below 0.9; largest |GPU − f32 twin| {largest:.2e}, |GPU − f64| {largest_f64:.2e}");
        // Measured (lavapipe): 955 covered, 69 and 417 below 0.9; largest 2.0e-5, 3.3e-5.
        assert!(covered > 800 && occluded > 20, "{covered} {occluded}");
        assert!(largest < 2e-4, "{largest}");
    }
}

/// `ao_timing`'s scene rows: an AO scene's surfel pass (1–2 passes, brute force and tree)
/// and GTAO of each configuration at each resolution (square and not), timed in one run;
/// GTAO's rows count the pixels that see a surface (as many as the coverage has), carry the
/// configuration, time one frame's dispatch, and state the frames to convergence (1 for
/// Algorithm 1, the frames the scene names for XeGTAO High) and that time × the frames.
#[test]
fn ao_timing_times_the_scene_surfels_beside_gtao_at_each_resolution() {
    use nklut::effects::ao::experiment::{AoSettings, SurfelScene};
    use nklut::effects::trace::Camera;
    use nklut::gpu::ao_timing::{ao_timing_table, scene_rows, SweepSettings, Timed};
    use nklut::scene::Scene;
    use std::path::Path;
    let Some(gpu) = device() else { return };
    let text = "camera: { axis: [0.3, 1, 0.2], distance: 3, frames: 1 }\nmeasurements: [image_error]\neffects: { ambient_occlusion: { passes: 1, gtao: [{ radius: 0.5, slices: 2, steps: 4 }, { preset: xe-high, radius: 0.5, frames: 8 }] } }\nobjects:\n  - { mesh: cube, diffuse: [0.8, 0.8, 0.8], subdivide: 1 }\n";
    let scene = Scene::parse(text, Path::new("t.yaml")).unwrap();
    let settings = SweepSettings { passes: 2, repeats: 2, ..SweepSettings::default() };
    let sizes = [[16u32, 16], [32, 24]];
    let rows = scene_rows(&gpu, "t", &scene, &sizes, &settings, &mut |_| {}).unwrap();
    let names: Vec<(&str, u32)> = rows.iter().map(|r| (r.gather.name(), r.passes)).collect();
    assert_eq!(
        names,
        [("brute_force", 1), ("brute_force", 2), ("hierarchy", 1), ("hierarchy", 2), ("gtao", 1), ("gtao", 1), ("gtao", 1), ("gtao", 1)]
    );
    let stage = SurfelScene::new(&scene, &AoSettings::default().budget).unwrap();
    let configurations = &scene.effects.as_ref().unwrap().ambient_occlusion.as_ref().unwrap().gtao;
    for (pair, [width, height]) in rows[4..].chunks(2).zip(sizes) {
        let covered = stage.coverage(&Camera::new(&scene.camera, 0, width, height)).iter().flatten().count();
        assert!(covered > 0);
        for (row, (g, frames)) in pair.iter().zip(configurations.iter().zip([1, 8])) {
            assert_eq!(row.gather, Timed::Gtao { gtao: *g, resolution: [width, height], covered });
            assert_eq!((row.dispatches, row.surfels, row.frames()), (1, 6 * 9, frames));
            assert_eq!(row.convergence_ms(), Some(row.median_ms * frames as f64));
        }
    }
    assert!(rows[..4].iter().all(|r| r.frames() == 0 && r.convergence_ms().is_none()));
    assert!(rows.iter().all(|r| r.median_ms.is_finite() && r.median_ms > 0.0 && r.spread_ms >= 0.0));
    let table = ao_timing_table(&rows, &gpu.line);
    for column in
        ["emitters", "width", "height", "covered_pixels", "slices", "steps", "preset", "radius", "frames", "median_ms", "convergence_ms"]
    {
        assert!(table.column(column).is_some(), "{column}");
    }
}

/// Every GTAO configuration the scenes name runs on the GPU as its f32 CPU twin runs it
/// (`effects::ao::gtao::pixel_visibility`, one body for f64 and f32): each preset (bare,
/// XeGTAO Low, Medium, High, Ultra) in one frame and accumulated over frames of per-pixel
/// Hilbert-R2 noise, and XeGTAO High with the heuristics the presets leave at their
/// defaults set (thin-occluder compensation 0.7, the screen radius clamped to [6, 14] px),
/// with the hard cut instead of the falloff, with the denoiser off or at 2 and 3 passes,
/// over the frame of a cube on a slab, 96×64; and XeGTAO High with samples beyond the
/// image's edge read clamped or skipped, over a slab that fills the frame.
///
/// Bound, per covered pixel. Both run the same f32 operations in the same order; they part
/// by the GPU's acos, cos, sin, exp2 and log2 (a few ulp; acos near ±1 magnifies them) and
/// any multiply-add the GPU fuses: |Δ| ≤ 2e-4, as the bare pass (measured there 2e-5).
/// Except where such a difference moves a sample across a texel edge: that sample then
/// reads another texel, and at most one slice of one frame changes, by at most its share
/// of the mean (eq. 10 of one slice is at most 1, so 1/slices), raised through the final
/// power (|x^p − y^p| ≤ p |x − y| on [0, 1] for p ≥ 1): |Δ| ≤ p/slices. At most 1 % of the
/// pixels may do so (measured below).
#[test]
fn the_wgsl_gtao_matches_its_cpu_twin_for_every_preset_one_frame_and_accumulated() {
    use nklut::budget::MemoryBudget;
    use nklut::effects::ao::experiment::SurfelScene;
    use nklut::effects::ao::gtao::{gtao, GBuffer, Parameters, Preset};
    use nklut::effects::trace::Camera;
    use nklut::gpu::passes::gtao::GtaoPass;
    use nklut::scene::Scene;
    use std::path::Path;
    let Some(gpu) = device() else { return };
    let text = "camera: { axis: [0.3, 1, 0.2], distance: 3, frames: 1 }\nmeasurements: [image_error]\neffects: { ambient_occlusion: { passes: 1 } }\nobjects:\n  - { mesh: cube, diffuse: [0.8, 0.8, 0.8], subdivide: 1 }\n  - { mesh: cube, scale: [2, 0.05, 2], position: [0, -0.55, 0], diffuse: [0.7, 0.7, 0.7], subdivide: 2 }\n";
    let frame = |text: &str| {
        let scene = Scene::parse(text, Path::new("gtao.yaml")).unwrap();
        let stage = SurfelScene::new(&scene, &MemoryBudget::of_machine()).unwrap();
        let camera = Camera::new(&scene.camera, 0, 96, 64);
        GBuffer::from_coverage(&camera, &stage.coverage(&camera), &stage.surfels).narrowed()
    };
    let g = frame(text);
    // The slab widened to fill the frame: its edge texels are surface, for the clamped reads.
    let filled = frame(&text.replace("scale: [2, 0.05, 2]", "scale: [8, 0.05, 8]"));
    let mut configurations = Vec::new();
    for preset in Preset::ALL {
        let [slices, steps] = preset.slices_steps();
        let p = Parameters { radius: 0.5, slices, steps, heuristics: preset.heuristics() };
        let mut one = p;
        one.heuristics.frames = 1;
        configurations.push((format!("{}, 1 frame", preset.name()), one));
        if p.heuristics.noise {
            configurations.push((format!("{}, {} frames", preset.name(), p.heuristics.frames), p));
        }
    }
    let [slices, steps] = Preset::XeHigh.slices_steps();
    let mut clamped = Parameters { radius: 0.5, slices, steps, heuristics: Preset::XeHigh.heuristics() };
    clamped.heuristics.thin_occluder = 0.7;
    clamped.heuristics.min_radius_pixels = 6.0;
    clamped.heuristics.max_radius_pixels = 14.0;
    clamped.heuristics.frames = 16;
    configurations.push(("xe-high, thin occluder 0.7, radius clamped to [6, 14] px, 16 frames".into(), clamped));
    let mut hard = clamped;
    hard.heuristics.falloff_range = 0.0;
    configurations.push(("xe-high, hard cut, thin occluder 0.7, clamped, 16 frames".into(), hard));
    // The denoiser off, and at 2 and 3 passes (its two kernels taking turns, the result in
    // either buffer), over one noisy frame.
    for passes in [0, 2, 3] {
        let mut p = Parameters { radius: 0.5, slices, steps, heuristics: Preset::XeHigh.heuristics() };
        p.heuristics.frames = 1;
        p.heuristics.denoise_passes = passes;
        configurations.push((format!("xe-high, 1 frame, {passes} denoiser passes"), p));
    }
    // XeGTAO High at a radius that reaches past the frame's edge from its outer pixels, with
    // those samples skipped instead of reading the edge texel: the two differ there (on the
    // twin, measured: 692 of 4464 pixels by more than 1e-3).
    let mut reaching = Parameters { radius: 1.0, slices, steps, heuristics: Preset::XeHigh.heuristics() };
    reaching.heuristics.frames = 16;
    let mut skipped = reaching;
    skipped.heuristics.clamp_to_edge = false;
    let edge_pixels = gtao(&filled, reaching.narrowed())
        .iter()
        .zip(gtao(&filled, skipped.narrowed()))
        .filter(|(a, b)| matches!((a, b), (Some(a), Some(b)) if (a - b).abs() > 1e-3))
        .count();
    assert!(edge_pixels > 50, "clamping to the edge changes only {edge_pixels} pixels");
    let mut configurations: Vec<(String, Parameters<f64>, &GBuffer<f32>)> =
        configurations.into_iter().map(|(name, p)| (name, p, &g)).collect();
    configurations.push(("xe-high, radius 1, 16 frames, slab filling the frame".into(), reaching, &filled));
    configurations.push(("xe-high, radius 1, samples beyond the edge skipped, 16 frames, slab filling the frame".into(), skipped, &filled));
    let mut previous: Option<Vec<Option<f32>>> = None;
    for (name, p, g) in configurations {
        let pass = GtaoPass::new(&gpu, g, p.narrowed()).unwrap();
        let expected_frames = if p.heuristics.noise { p.heuristics.frames } else { 1 };
        assert_eq!(pass.frames(), expected_frames, "{name}");
        let got = pass.run(&gpu).unwrap();
        let twin = gtao(g, p.narrowed());
        let (mut covered, mut over, mut largest, mut sum) = (0usize, 0usize, 0.0f64, 0.0f64);
        for (a, b) in got.iter().zip(&twin) {
            assert_eq!(a.is_some(), b.is_some(), "{name}");
            if let (Some(a), Some(b)) = (a, b) {
                let d = (a - b).abs() as f64;
                assert!((0.0..=1.0).contains(a), "{name}: {a}");
                covered += 1;
                over += (d > 2e-4) as usize;
                largest = largest.max(d);
                sum += d;
            }
        }
        let crossing = p.heuristics.final_power / p.slices as f64;
        eprintln!(
            "{name}: {covered} pixels, |GPU − f32 twin| mean {:.2e}, largest {largest:.2e}, {over} over 2e-4 (bound for those {crossing:.2})",
            sum / covered as f64
        );
        assert!(covered > 800, "{covered}");
        assert!(over * 100 <= covered, "{name}: {over} of {covered} pixels over 2e-4");
        assert!(largest <= crossing, "{name}: {largest}");
        // Each configuration gives another image (the comparison tells them apart).
        if let Some(previous) = &previous {
            let differing = previous.iter().zip(&got).filter(|(a, b)| matches!((a, b), (Some(a), Some(b)) if (a - b).abs() > 1e-3)).count();
            assert!(differing * 10 > covered, "{name}: only {differing} pixels differ from the configuration before");
        }
        previous = Some(got);
    }
}

/// Parameters the pass cannot run are named errors, not panics or garbage.
#[test]
fn the_gtao_pass_names_the_parameters_it_refuses() {
    use nklut::effects::ao::gtao::{GBuffer, Parameters, ViewSample};
    use nklut::gpu::passes::gtao::GtaoPass;
    let Some(gpu) = device() else { return };
    let sample = Some(ViewSample { position: [0.0f32, 0.0, -2.0], normal: [0.0, 0.0, 1.0] });
    let g = GBuffer { width: 2, height: 2, focal: 2.0f32, samples: vec![sample; 4] };
    let bare = Parameters::bare(1.0, 2, 2).narrowed();
    let mut nan = bare;
    nan.heuristics.final_power = f32::NAN;
    let error = GtaoPass::new(&gpu, &g, nan).err().expect("NaN final power");
    assert!(error.to_string().contains("final_power"), "{error}");
    let mut many = Parameters::bare(1.0, 2, 2).narrowed();
    many.heuristics.noise = true;
    many.heuristics.frames = 100_000;
    let error = GtaoPass::new(&gpu, &g, many).err().expect("too many frames");
    assert!(error.to_string().contains("100000 frames"), "{error}");
    let short = GBuffer { samples: vec![sample; 3], ..g.clone() };
    assert!(GtaoPass::new(&gpu, &short, bare).is_err());
    // An open plane facing the eye: every pixel 1 (eq. 10 with γ = 0, h± = ±π/2), with and
    // without noise.
    let mut noisy = bare;
    noisy.heuristics.noise = true;
    noisy.heuristics.frames = 3;
    for p in [bare, noisy] {
        let got = GtaoPass::new(&gpu, &g, p).unwrap().run(&gpu).unwrap();
        assert!(got.iter().all(|a| a.is_some_and(|a| (a - 1.0).abs() < 1e-6)), "{got:?}");
    }
}
