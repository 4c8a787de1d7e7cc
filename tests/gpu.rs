//! The wgpu runner on whatever adapter there is (lavapipe in CI): every method's shader
//! against its CPU f32 reference on a cosθ ramp, image error sanity, and the runner's
//! promise to compute only what the scene names.
//!
//! No adapter at all is a FAILURE (install `mesa-vulkan-drivers`), unless
//! NKLUT_SKIP_GPU_TESTS=1, which skips these tests with a message.
#![cfg(feature = "gpu")]

mod common;

use std::path::Path;

use common::gpu::shared as device;
use common::{database, scratch};
use nklut::fresnel;
use nklut::gpu::params::{self, MaterialUniform};
use nklut::gpu::render::{self, Renderer};
use nklut::gpu::{self, lut, RunStats};
use nklut::scene::{Scene, SceneMaterial, Shading};
use nklut::spectrum::{ChannelIndex, Index, Kind};

const GOLDISH: ChannelIndex = [Index::new(0.16, 3.8), Index::new(0.5, 2.3), Index::new(1.2, 1.8)];
const WATER: ChannelIndex = [Index::new(1.331, 0.0), Index::new(1.336, 0.0), Index::new(1.338, 0.0)];
const DIAMOND: ChannelIndex = [Index::new(2.409, 0.0), Index::new(2.424, 0.0), Index::new(2.432, 0.0)];
/// A channel with no real compensated λ (schlick_nk below exact at 84.26°): the fallback.
const MIXED: ChannelIndex = [Index::new(1.0, 0.0), Index::new(0.05, 0.5), Index::new(3.0, 4.0)];

const RAMP_WIDTH: u32 = 1024;

fn ramp_c(x: u32) -> f32 {
    (x as f32 + 0.5) / RAMP_WIDTH as f32
}

/// The CPU LUT model of one channel (`fresnel::sample_lut`: texel i at u = (i + ½)/N,
/// linear between neighbouring centres, clamp-to-edge) and the two texels it blends.
fn lut_model(texels: &[[f32; 4]], channel: usize, u: f32) -> (f32, f32, f32) {
    let column: Vec<f32> = texels.iter().map(|t| t[channel]).collect();
    let last = column.len() as i64 - 1;
    let i0 = (u * column.len() as f32 - 0.5).floor() as i64;
    let at = |i: i64| column[i.clamp(0, last) as usize];
    (fresnel::sample_lut(&column, u), at(i0), at(i0 + 1))
}

/// One step of half-float quantisation at `v` (the spacing of f16 values around it).
fn half_step(v: f32) -> f32 {
    let v = v.abs().max(6.1e-5); // smallest normal half
    2f32.powi(v.log2().floor() as i32 - 10)
}

#[test]
fn every_method_matches_its_cpu_reference_on_a_cos_ramp() {
    let Some(gpu) = device() else { return };
    let mut renderer = Renderer::new(&gpu);
    const LUT_SIZE: usize = 32;
    let mut worst = Vec::new();
    // The same pure functions evaluate a ray from inside: the parameters of conj(1/η).
    let inside = |channels: ChannelIndex| channels.map(nklut::effects::optics::inside_index);
    let materials = [
        ("goldish", GOLDISH),
        ("water", WATER),
        ("diamond", DIAMOND),
        ("mixed", MIXED),
        ("water inside", inside(WATER)),
        ("diamond inside", inside(DIAMOND)),
    ];
    for (name, channels) in materials {
        let prepared = params::prepare(&channels);
        let uniform = MaterialUniform::from_prepared(&prepared);
        // Already half floats: what the texture stores.
        let stored = lut::texels(&prepared, LUT_SIZE);
        let view = lut::upload(&gpu, &stored, name).create_view(&Default::default());
        let binding = renderer.bind(&gpu, &uniform, Some(&view)).unwrap();
        for method in Shading::ALL {
            let pixels = render::ramp(&gpu, &mut renderer, method, &binding, RAMP_WIDTH, 1).unwrap();
            let mut max_error = 0.0f32;
            for x in 0..RAMP_WIDTH {
                let c = ramp_c(x);
                for channel in 0..3 {
                    let shader = pixels[x as usize * 4 + channel];
                    assert!(shader.is_finite(), "{name} {method} c {c}: {shader}");
                    let (expected, tolerance) = match method {
                        Shading::Fresnel(fresnel::Method::Lut) => {
                            let (model, a, b) = lut_model(&stored, channel, c);
                            // One half-float step, plus the sub-texel weight precision a GPU may
                            // use (8 bits on current hardware; a CPU rasteriser uses floats).
                            (model, half_step(a.max(b)) + (b - a).abs() / 256.0)
                        }
                        Shading::Texture => (lut_model(&stored, channel, 0.5).0, half_step(1.0)),
                        _ => (uniform.evaluate_f32(method, channel, c).unwrap(), 1e-5),
                    };
                    let error = (shader - expected).abs();
                    assert!(
                        error <= tolerance,
                        "{name} {method} channel {channel} c {c}: shader {shader} cpu {expected} (tolerance {tolerance})"
                    );
                    // Past the critical angle inside a dielectric (sin²θ > n², n = 1/η < 1, k = 0),
                    // exact F is 1 (to an f32 rounding).
                    let Index { n, k } = channels[channel];
                    if method == Shading::Fresnel(fresnel::Method::Exact) && k == 0.0 && n < 1.0 && 1.0 - c * c > (n * n) as f32 * 1.0001 {
                        assert!(
                            shader >= 1.0 - 2.0 * f32::EPSILON,
                            "{name} channel {channel} c {c}: total internal reflection, F = {shader}"
                        );
                    }
                    max_error = max_error.max(error);
                }
            }
            worst.push(format!("{name} {method} {max_error:.2e}"));
        }
    }
    eprintln!("largest |shader − cpu| per material and method:\n  {}", worst.join("\n  "));
    assert_eq!(renderer.created.shader_modules, Shading::ALL.len(), "one module per method, shared by all materials");
}

#[test]
fn mixed_material_really_falls_back() {
    let prepared = params::prepare(&MIXED);
    assert!(
        prepared.iter().any(|p| p.params::<fresnel::methods::schlick_compensated::SchlickCompensated>().fallback.is_some()),
        "{prepared:?}"
    );
    let uniform = MaterialUniform::from_prepared(&prepared);
    for i in 0..=100 {
        for channel in 0..3 {
            assert!(uniform
                .evaluate_f32(Shading::Fresnel(fresnel::Method::SchlickCompensated), channel, i as f32 / 100.0)
                .unwrap()
                .is_finite());
        }
    }
}

/// A wgpu call that fails validation outside any error scope (a mappable buffer that is
/// also a storage buffer) comes back as an error from `wait`, not a panic.
#[test]
fn an_uncaptured_wgpu_error_is_an_error() {
    let Some(gpu) = device() else { return };
    gpu.wait().unwrap();
    let _buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("invalid on purpose"),
        size: 16,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let error = gpu.wait().expect_err("the invalid buffer is reported").to_string();
    assert!(error.contains("wgpu reported 1 error"), "{error}");
    gpu.wait().expect("errors are reported once");
}

fn scene(text: &str) -> Scene {
    Scene::parse(text, Path::new("tests/gpu.rs inline scene")).unwrap()
}

/// Mean over θ ∈ [0°, 90°] (uniform) of |schlick − exact| / exact for one index, in f64.
fn schlick_function_error(index: Index) -> f64 {
    let f0 = fresnel::schlick_f0(index.n, index.k);
    let samples = 90_000;
    (0..samples)
        .map(|i| {
            let c = ((i as f64 + 0.5) / samples as f64 * 90.0).to_radians().cos();
            let exact = fresnel::exact(index.n, index.k, c);
            (fresnel::schlick(f0, c) - exact).abs() / exact
        })
        .sum::<f64>()
        / samples as f64
}

#[test]
fn image_error_is_zero_for_exact_and_of_the_function_errors_order_for_schlick() {
    let Some(gpu) = device() else { return };
    let scene = scene(
        "resolution: [128, 128]\ncamera: {frames: 4, degrees_per_frame: 7}\n\
         objects:\n  - {mesh: sphere, material: 3d/liquids/water, methods: [exact, schlick]}\n  - {mesh: cube, material: 3d/liquids/water, methods: [exact, schlick]}\n\
         measurements: [image_error]\n",
    );
    let materials = [SceneMaterial::new("3d/liquids/water", WATER, Kind::Dielectric)];
    let report = gpu::run_with_materials(&scene, &materials, &gpu, RunStats::default(), &mut |line| eprintln!("{line}")).unwrap();
    let row = |object: &str, method: Shading| report.image_errors.iter().find(|r| r.object == object && r.method == method).unwrap();
    for object in ["sphere", "cube"] {
        let exact = row(object, Shading::Fresnel(fresnel::Method::Exact));
        assert_eq!(exact.frames, 4);
        assert!(exact.pixels > 4 * 1000, "{object} covers {} pixels in 4 frames", exact.pixels);
        assert_eq!((exact.mean_rel_error, exact.max_rel_error), (Some(0.0), 0.0), "{object}: exact against itself");
        assert_eq!(exact.skipped_zero_reference, 0, "water reflects at every angle");
    }
    // The function error weighs every angle θ alike; an image weighs c = |N·V| by the screen
    // area at that angle — on a sphere the projected area per dc is ∝ c, so near-normal
    // incidence (where Schlick is nearly exact) dominates and grazing pixels (where it is
    // worst) are few; a cube shows a handful of mid-range angles. Both are averages of the
    // same |a − r|/r curve with different positive weights, so they must agree in order of
    // magnitude (a factor 10 either way), and must not be zero.
    let function_error = (0..3).map(|ch| schlick_function_error(WATER[ch])).sum::<f64>() / 3.0;
    for object in ["sphere", "cube"] {
        let image_error = row(object, Shading::Fresnel(fresnel::Method::Schlick)).mean_rel_error.expect("water is lit at every pixel");
        eprintln!("water schlick: function error {function_error:.4e}, {object} image error {image_error:.4e}");
        assert!(image_error > 0.0);
        assert!(
            image_error > function_error / 10.0 && image_error < function_error * 10.0,
            "{object}: image {image_error} vs function {function_error}"
        );
    }
}

/// A valid scene whose readback would exceed the device's buffer limit is an error naming
/// the scene and the limit, found before anything is allocated.
#[test]
fn an_oversized_scene_is_an_error_not_a_panic() {
    let Some(gpu) = device() else { return };
    let limit = gpu.device.limits().max_buffer_size;
    // Five RGBA32Float images (exact + four methods) of side s: 5·16·s² bytes over the limit.
    let side = ((limit as f64 / 80.0).sqrt().ceil() as u32 + 64).min(gpu.device.limits().max_texture_dimension_2d);
    if 80 * (side as u64) * (side as u64) <= limit {
        eprintln!("max_buffer_size {limit} is beyond any target this device can make; nothing to check");
        return;
    }
    let text = format!("resolution: [{side}, {side}]\ncamera: {{frames: 1}}\nobjects: [{{mesh: cube, material: 3d/liquids/water, methods: [schlick, lazanyi, nvidia, schlick_nk]}}]\nmeasurements: [image_error]\n");
    let error = gpu::run(&scene(&text), &database(), &Default::default(), &gpu, &mut |_| {}).err().expect("over the limit").to_string();
    assert!(error.contains("max_buffer_size") && error.contains("inline scene"), "{error}");
    // An oversized target is an error too.
    let too_wide = gpu.device.limits().max_texture_dimension_2d + 1;
    let error = render::Target::new(&gpu, too_wide, 4, render::FLOAT_TARGET, false).err().expect("over the limit").to_string();
    assert!(error.contains("max_texture_dimension_2d"), "{error}");
}

/// The rule: `image_error` compiles one mesh pipeline per named method plus the `exact`
/// reference; `timing` one fullscreen pipeline per named method; pages = named materials.
#[test]
fn runner_compiles_and_touches_only_what_the_scene_names() {
    let Some(gpu) = device() else { return };
    let db = database();
    let log = &mut |line: &str| eprintln!("{line}");

    let image = scene("resolution: [32, 32]\ncamera: {frames: 1}\nobjects: [{mesh: sphere, material: 3d/liquids/water, method: schlick}]\nmeasurements: [image_error]\n");
    let report = gpu::run(&image, &db, &Default::default(), &gpu, log).unwrap();
    eprintln!("{}", report.stats);
    assert_eq!(report.stats.pipelines_compiled, 2, "schlick + the exact reference");
    assert_eq!(report.stats.pages_touched, 1);
    assert_eq!(report.stats.textures_baked, 0);
    assert_eq!(report.stats.timed_passes, 0);
    assert!(report.stats.skipped.iter().any(|s| s.starts_with("timing")));
    assert_eq!(report.image_errors.len(), 1);
    // No effects named: no cube map, no effect pipeline, no reference frame.
    assert_eq!(
        (report.stats.effects.cube_maps, report.stats.effects.layers, report.stats.effect_pipelines, report.stats.effects.reference_frames),
        (0, 0, 0, 0)
    );
    assert!(report.effects.timing.is_empty() && report.effects.errors.is_empty());

    let exact_only = scene("resolution: [32, 32]\ncamera: {frames: 1}\nobjects: [{mesh: cube, material: 3d/liquids/water, method: exact}]\nmeasurements: [image_error]\n");
    assert_eq!(
        gpu::run(&exact_only, &db, &Default::default(), &gpu, log).unwrap().stats.pipelines_compiled,
        1,
        "exact is its own reference"
    );

    let timing = scene(
        "objects: [{mesh: cube, material: 3d/metals/gold, method: lut}]\nmeasurements: [timing]\ntiming: {resolution: [64, 64], warmup: 1, repeats: 3, amplify: false}\n",
    );
    let report = gpu::run(&timing, &db, &Default::default(), &gpu, log).unwrap();
    eprintln!("{}", report.stats);
    assert_eq!(report.stats.pipelines_compiled, 1);
    assert_eq!(report.stats.pages_touched, 1);
    assert_eq!(report.stats.textures_baked, 1);
    assert_eq!(report.stats.frames_rendered, 0);
    assert_eq!(report.stats.timed_passes, 4);
    let row = &report.timing[0];
    assert_eq!((row.method, row.stats.n, row.evaluations), (Shading::Fresnel(fresnel::Method::Lut), 3, 1));
    assert!(row.stats.median_ms >= 0.0 && row.stats.spread_ms >= 0.0);
    assert_eq!(row.relative_to_exact_dielectric, None, "no exact on a dielectric timed");
}

#[test]
fn timing_normalises_by_exact_on_a_dielectric_and_subtracts() {
    let Some(gpu) = device() else { return };
    let scene = scene(
        "objects:\n  - {mesh: cube, material: 3d/liquids/water, methods: [exact, constant]}\n  - {mesh: cube, material: 3d/metals/gold, methods: [exact]}\n\
         measurements: [timing]\ntiming: {resolution: [128, 128], warmup: 1, repeats: 7, subtract: true}\n",
    );
    // 128² and 7 rounds: a difference of two passes stays positive in its median when the
    // machine runs other tests beside it (64² and 3 rounds once gave a median ≤ 0).
    let materials =
        [SceneMaterial::new("3d/liquids/water", WATER, Kind::Dielectric), SceneMaterial::new("3d/metals/gold", GOLDISH, Kind::Conductor)];
    let report = gpu::run_with_materials(&scene, &materials, &gpu, RunStats::default(), &mut |line| eprintln!("{line}")).unwrap();
    assert_eq!(report.timing.len(), 3);
    assert_eq!(report.stats.pipelines_compiled, 4, "exact by the dielectric formula (water) and the complex one (gold), constant, burner");
    // Burner alone + burner with the method, per pair and round (1 warm-up and 7 timed): the
    // study's method, one evaluation per pixel.
    assert_eq!(report.stats.timed_passes, 3 * 8 * 2);
    assert!(report.timing.iter().all(|r| r.evaluations == 1));
    let water_exact =
        report.timing.iter().find(|r| r.material == "3d/liquids/water" && r.method == Shading::Fresnel(fresnel::Method::Exact)).unwrap();
    assert_eq!(water_exact.relative_to_exact_dielectric, Some(1.0));
    assert_eq!(water_exact.relative_to_exact, Some(1.0));
    assert!(report.timing.iter().all(|r| r.relative_to_exact_dielectric.is_some()));
    // The study's anchors: exact on water by the dielectric formula, on gold by the complex one.
    let formula = |material: &str| {
        report.timing.iter().find(|r| r.material == material && r.method == Shading::Fresnel(fresnel::Method::Exact)).unwrap().formula
    };
    assert_eq!((formula("3d/liquids/water"), formula("3d/metals/gold")), ("dielectric (k = 0)", "complex"));
    for row in &report.timing {
        // Every sample kept; one amplification for all; the cost per evaluation per pixel is
        // the median over evaluations × pixels.
        assert_eq!(row.samples.len(), 7);
        assert_eq!(row.evaluations, report.timing[0].evaluations);
        let per = row.stats.median_ms * 1e6 / (row.evaluations as f64 * 128.0 * 128.0);
        assert!((row.stats.ns_per_evaluation - per).abs() <= 1e-12 * per.abs().max(1.0), "{row:?}");
        assert!(row.timer_resolution_ns >= 1.0);
    }
    let table = gpu::runner::timing_table(&report);
    let names: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "adapter",
            "backend",
            "driver",
            "timer",
            "method",
            "formula",
            "material",
            "resolution",
            "evaluations",
            "timer_resolution_ns",
            "seed",
            "repeats",
            "mean_ms",
            "median_ms",
            "spread_ms",
            "ns_per_evaluation",
            "relative_to_exact",
            "relative_to_fetch",
            "relative_to_exact_dielectric",
            "near_resolution",
            "samples_ms"
        ]
    );
}

/// A pass far shorter than the sample target (64 × 16 pixels on lavapipe): the runner
/// amplifies until the cheapest Fresnel method's pass spans the target, every row resolved.
#[test]
fn a_short_pass_is_amplified_until_it_spans_the_target() {
    let Some(gpu) = device() else { return };
    let scene = scene(
        "objects:\n  - {mesh: cube, material: 3d/liquids/water, methods: [exact, schlick, constant]}\n\
         measurements: [timing]\ntiming: {resolution: [64, 16], warmup: 1, repeats: 5}\n",
    );
    let materials = [SceneMaterial::new("3d/liquids/water", WATER, Kind::Dielectric)];
    let report = gpu::run_with_materials(&scene, &materials, &gpu, RunStats::default(), &mut |line| eprintln!("{line}")).unwrap();
    let schlick = report.timing.iter().find(|r| r.method == Shading::Fresnel(fresnel::Method::Schlick)).unwrap();
    assert!(schlick.evaluations > 1, "{schlick:?}");
    assert!(schlick.stats.median_ms >= 0.5 * nklut::gpu::sampling::MIN_SAMPLE_MS, "{schlick:?}");
    assert!(report.timing.iter().all(|r| !r.stats.near_resolution && r.samples.len() == 5), "{:?}", report.timing);
    // Exact costs more per evaluation than Schlick on any rasteriser.
    let exact = report.timing.iter().find(|r| r.method == Shading::Fresnel(fresnel::Method::Exact)).unwrap();
    assert!(exact.stats.ns_per_evaluation > schlick.stats.ns_per_evaluation, "{exact:?} {schlick:?}");
}

/// The dielectric anchor (`fresnel_exact_dielectric`) is exact F for k = 0: against the f64
/// reference on water, diamond and their inside indices (TIR past the critical angle), to
/// f32 precision; and the amplified pass writes the mean of F at c + iφ mod 1 (computed
/// here in f64), so every repeat is evaluated.
#[test]
fn the_dielectric_anchor_is_exact_f_and_the_amplified_pass_averages_its_repeats() {
    let Some(gpu) = device() else { return };
    let mut renderer = Renderer::new(&gpu);
    let inside = |channels: ChannelIndex| channels.map(nklut::effects::optics::inside_index);
    let mut worst = 0.0f64;
    for channels in [WATER, DIAMOND, inside(WATER), inside(DIAMOND)] {
        let uniform = MaterialUniform::from_prepared(&params::prepare(&channels));
        let binding = renderer.bind(&gpu, &uniform, None).unwrap();
        let pixels = render::ramp_of(&gpu, &mut renderer, render::Shade::ExactDielectric, &binding, [RAMP_WIDTH, 1], 1).unwrap();
        for x in 0..RAMP_WIDTH {
            for (channel, index) in channels.iter().enumerate() {
                let c = ramp_c(x) as f64;
                let reference = fresnel::exact(index.n, index.k, c);
                worst = worst.max((pixels[x as usize * 4 + channel] as f64 - reference).abs());
            }
        }
    }
    eprintln!("dielectric anchor: largest |shader − f64 exact| = {worst:.2e}");
    assert!(worst <= 2e-5, "{worst}");

    let uniform = MaterialUniform::from_prepared(&params::prepare(&GOLDISH));
    let binding = renderer.bind(&gpu, &uniform, None).unwrap();
    let repeats = 7u32;
    let exact = Shading::Fresnel(fresnel::Method::Exact);
    let pixels = render::ramp_of(&gpu, &mut renderer, render::Shade::Method(exact), &binding, [RAMP_WIDTH, 1], repeats).unwrap();
    let mut worst = 0.0f64;
    for x in 0..RAMP_WIDTH {
        let c = ramp_c(x);
        for (channel, index) in GOLDISH.iter().enumerate() {
            let mean = (0..repeats)
                .map(|i| {
                    let ci = if i == 0 { c } else { (c + i as f32 * 0.618034).fract() };
                    fresnel::exact(index.n, index.k, ci as f64)
                })
                .sum::<f64>()
                / repeats as f64;
            worst = worst.max((pixels[x as usize * 4 + channel] as f64 - mean).abs());
        }
    }
    assert!(worst <= 2e-5, "amplified mean: {worst}");
    // Once is the plain ramp, bit for bit.
    let once = render::ramp_of(&gpu, &mut renderer, render::Shade::Method(exact), &binding, [RAMP_WIDTH, 1], 1).unwrap();
    assert_eq!(once, render::ramp(&gpu, &mut renderer, exact, &binding, RAMP_WIDTH, 1).unwrap());
}

#[test]
fn default_scene_parses_and_its_sculpture_loads() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::load(&root.join("scenes/default.yaml")).unwrap();
    assert!(scene.materials().len() >= 3);
    for object in &scene.objects {
        if let nklut::scene::MeshSource::File(path) = &object.mesh {
            let resolved = root.join(path);
            if resolved.exists() {
                let mesh = gpu::mesh::load_obj(&resolved).unwrap();
                assert!(mesh.triangles() > 50_000);
                assert_eq!(mesh.normals.len(), mesh.positions.len());
            } else {
                eprintln!("{} not present; mesh load not checked", resolved.display());
            }
        }
    }
}

#[test]
fn bad_scenes_are_named_errors_not_panics() {
    let dir = scratch("gpu-scene");
    let file = dir.join("bad.yaml");
    std::fs::write(&file, "objects: [{mesh: cube, material: 3d/metals/gold, method: fastest}]\nmeasurements: [timing]\n").unwrap();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_nklut")).args(["gpu", "run"]).arg(&file).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("bad.yaml") && stderr.contains("unknown method \"fastest\""), "{stderr}");

    // An unknown page is found before any GPU work, with the scene named.
    let scene =
        Scene::parse("objects: [{mesh: cube, material: 3d/metals/unobtainium, method: exact}]\nmeasurements: [timing]\n", &file).unwrap();
    let error = nklut::scene::read_materials(&scene, &database(), &Default::default()).err().unwrap().to_string();
    assert!(error.contains("bad.yaml") && error.contains("unobtainium"), "{error}");
}

/// An OBJ whose vertices lie near the end of f32's range (NaN once fitted in f32 before) runs
/// through `gpu run` like any mesh: fitted to the unit sphere in f64, finite everywhere.
#[test]
fn a_mesh_at_the_end_of_f32_s_range_runs_on_the_gpu() {
    let Some(gpu) = device() else { return };
    let dir = scratch("gpu-far");
    std::fs::write(dir.join("far.obj"), "v 3.4e38 3.4e38 3.4e38\nv -3.4e38 3.3e38 3.4e38\nv 3.4e38 -3.4e38 -3.3e38\nv -3.4e38 -3.4e38 3.4e38\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n").unwrap();
    let file = dir.join("far.yaml");
    std::fs::write(&file, "resolution: [16, 16]\ncamera: {frames: 1}\nobjects: [{mesh: far.obj, material: 3d/metals/gold, methods: [schlick]}]\nmeasurements: [image_error]\n").unwrap();
    let report = gpu::run(&Scene::load(&file).unwrap(), &database(), &Default::default(), &gpu, &mut |_| {}).unwrap();
    assert!(report.image_errors.iter().all(|r| r.mean_rel_error.is_some_and(f64::is_finite) && r.pixels > 0), "{:?}", report.image_errors);
}

/// The WGSL distance-map search against its f64 CPU twin, every ray: the same layer and
/// texel and the same point to [`SEARCH_BOUND`] of the scene's size. A ray whose f32 probe
/// lands on the other side of a texel edge or of g = 0 than the f64 one would fail; none of
/// these 384 does (the probes' roundings, ~10⁻⁷ of the map's size, would have to fall on a
/// edge that a ray meets at random). Measured on lavapipe: every ray, point worst printed.
#[test]
fn the_wgsl_distance_map_search_matches_its_cpu_twin() {
    use nklut::effects::distance_map::DistanceMap;
    use nklut::effects::trace::{stage_from_table, SpecularMaterial};
    use nklut::gpu::distance_search::{search, SearchRay};
    use nklut::scene::SearchSteps;
    let Some(gpu) = device() else { return };
    let text = "camera: {frames: 1}\neffects: {reflection: {max_depth: 2}, refraction: {max_depth: 2}}\nobjects:\n  - {mesh: sphere, scale: 0.5, material: x/y/glass, method: exact}\n  - {mesh: room, scale: [3, 2, 3], diffuse: [0.5, 0.5, 0.5]}\nmeasurements: [image_error]\n";
    let scene = Scene::parse(text, Path::new("tests/gpu.rs inline scene")).unwrap();
    let glass = SpecularMaterial { channels: [Index::new(1.5, 0.0); 3], kind: Kind::Dielectric };
    let stage = stage_from_table(&scene, &[SceneMaterial { page: "x/y/glass".to_string(), optics: glass, spectrum: None }]).unwrap();
    let map = DistanceMap::render(&stage, 0, 16, 3);
    // Rays from the sphere's surface outwards and inwards, and from inside it, over a
    // Fibonacci spiral of directions.
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut rays = Vec::new();
    for i in 0..128 {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / 128.0;
        let (radius, phi) = ((1.0 - z * z).sqrt(), golden * i as f64);
        let d = [radius * phi.cos(), z, radius * phi.sin()];
        let turn = [d[2], d[0], d[1]]; // another direction, not along d
        let mix = |a: f64, b: f64| -> [f64; 3] {
            let v: [f64; 3] = std::array::from_fn(|k| a * d[k] + b * turn[k]);
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            v.map(|x| x / n)
        };
        for (scale, direction) in [(0.5, mix(1.0, 0.6)), (0.5, mix(-1.0, 0.4)), (0.2, mix(0.3, 1.0))] {
            let f = |v: [f64; 3], s: f64| [(v[0] * s) as f32, (v[1] * s) as f32, (v[2] * s) as f32, 0.0];
            rays.push(SearchRay { origin: f(d, scale), direction: f(direction, 1.0) });
        }
    }
    for steps in [SearchSteps { linear: 15, secant: 1 }, SearchSteps { linear: 40, secant: 6 }] {
        let hits = search(&gpu, &map, &rays, steps).unwrap();
        let mut agree = 0;
        let mut found = 0;
        let mut worst = 0.0f64;
        for (ray, gpu_hit) in rays.iter().zip(&hits) {
            let widen = |v: [f32; 4]| glam::DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
            let cpu = map.search(widen(ray.origin), widen(ray.direction), steps);
            let same = match cpu {
                None => gpu_hit.point[3] < 0.0,
                Some(hit) => {
                    found += 1;
                    let point = widen(gpu_hit.point);
                    let off = (point - hit.point).length() / (1.0 + hit.point.length());
                    worst = worst.max(off);
                    gpu_hit.point[3] >= 0.0
                        && (gpu_hit.at[0] as usize, gpu_hit.at[1] as usize) == (hit.layer, hit.index)
                        && off <= SEARCH_BOUND
                }
            };
            agree += same as usize;
        }
        eprintln!(
            "distance-map search {}/{}: GPU = CPU twin on {agree} of {} rays ({found} hits), point off by {worst:.2e} at worst",
            steps.linear,
            steps.secant,
            rays.len()
        );
        assert!(found > rays.len() / 2, "most rays hit something: {found}");
        assert_eq!(agree, rays.len(), "every ray: the same texel and point");
    }
}

/// How far (relative to the scene's size) the GPU's search may put a hit point from the
/// twin's: the f32 probe and its secant steps round at ~2⁻²⁴ times the few units the ray
/// spans, some ten roundings deep: ≲ 10⁻⁶; 10⁻⁵ bounds it.
const SEARCH_BOUND: f64 = 1e-5;

/// How far (in texels) from a map texel's centre the GPU's rasteriser may in effect sample:
/// it snaps the vertices' screen positions to its sub-pixel grid, 1/16 of a pixel at the
/// coarsest Vulkan allows (`subPixelPrecisionBits` ≥ 4; lavapipe has 8), which moves the
/// interpolated position as a sample moved by as much would.
const TEXEL_STRAY: f64 = 1.0 / 16.0;

/// A glass sphere and a gold cube in a checkered room, small enough for lavapipe.
fn effects_stage(refraction: bool) -> (Scene, nklut::effects::trace::Stage) {
    use nklut::effects::trace::{stage_from_table, SpecularMaterial};
    // With refraction, every kind of light (`lights`); without, the shorthand `light`.
    let (refraction, lights) = if refraction {
        (
            "  refraction: {max_depth: 3}\n",
            "lights:\n  - {kind: directional, direction: [-0.3, -1, -0.5], colour: [0.5, 0.5, 0.5]}\n  - {kind: point, position: [0.5, 0.8, -0.5], intensity: [0.6, 0.5, 0.4]}\n  - {kind: ambient, colour: [0.2, 0.2, 0.2]}\n",
        )
    } else {
        ("", "")
    };
    let text = format!(
        "resolution: [48, 48]\ncamera: {{axis: [0, 1, 0.2], distance: 1.8, frames: 1}}\neffects:\n  reflection: {{max_depth: 3}}\n{refraction}  distance_maps: {{size: 16, layers: 3}}\n{lights}\
         objects:\n  - {{mesh: sphere, scale: 0.5, position: [0.2, 0, 0], material: x/y/glass, methods: [exact, schlick, lut]}}\n  - {{mesh: cube, scale: 0.25, position: [-0.6, -0.2, 0.3], material: x/y/gold, methods: [exact]}}\n\
         \x20 - {{mesh: room, scale: [3, 2, 3], diffuse: [0.8, 0.8, 0.75], pattern: {{kind: checker, size: 0.5, albedo: [0.1, 0.3, 0.6]}}}}\nmeasurements: [image_error]\n"
    );
    let scene = Scene::parse(&text, Path::new("tests/gpu.rs effects scene")).unwrap();
    let table = [
        SceneMaterial { page: "x/y/glass".into(), optics: SpecularMaterial { channels: DIAMOND, kind: Kind::Dielectric }, spectrum: None },
        SceneMaterial { page: "x/y/gold".into(), optics: SpecularMaterial { channels: GOLDISH, kind: Kind::Conductor }, spectrum: None },
    ];
    let stage = stage_from_table(&scene, &table).unwrap();
    (scene, stage)
}

/// Distance maps rasterised on the GPU against the CPU's ray-cast twin, every texel: the
/// same surface (or none), the same distance (10⁻⁴ relative), normal (10⁻³) and colour
/// (10⁻⁴) as the CPU's ray through the texel's centre — or, on a wall texel whose ray passes
/// an edge (between two of the checker's cells, or between two walls at the room's corner),
/// the same distance as that ray and the normal and cell of a CPU ray [`TEXEL_STRAY`] of a
/// texel from the centre, the cell's albedo lit at the texel's own point. The sphere's
/// centre lies on the checker's cell grid, so some texel rays meet the walls exactly on a
/// cell's edge. Measured on lavapipe: 56 of the 9216 texels take the neighbouring cell or
/// wall, every one found 1/16 of a texel away.
#[test]
fn gpu_distance_maps_match_the_ray_cast_twin() {
    use nklut::effects::distance_map::{face_direction, DistanceMap, Texel};
    use nklut::effects::scene::lights::unshadowed;
    use nklut::effects::trace::{ObjectOptics, Surface};
    use nklut::gpu::passes::distance_maps::{MapRenderer, SceneMeshes};
    let Some(gpu) = device() else { return };
    let (_, stage) = effects_stage(true);
    let renderer = MapRenderer::new(&gpu, &stage).unwrap();
    let meshes = SceneMeshes::upload(&gpu, &stage).unwrap();
    let maps = renderer.allocate(&gpu, &stage, 16, 3).unwrap();
    renderer.render(&gpu, &meshes, &maps).unwrap();
    let texels = maps.read(&gpu).unwrap();
    assert_eq!(texels.views.len(), 2, "one map per specular object");
    let same_colour = |a: [f64; 3], b: [f64; 3]| (0..3).all(|i| (a[i] - b[i]).abs() <= 1e-4);
    let same_surface = |g: Surface, c: Surface| match (g, c) {
        (Surface::Specular(a), Surface::Specular(b)) => a == b,
        (Surface::Diffuse(a), Surface::Diffuse(b)) => same_colour(a, b),
        _ => false,
    };
    let mut strayed = 0;
    for (m, object) in [(0, 0), (1, 1)] {
        let gpu_map = texels.unpack(m);
        let cpu_map = DistanceMap::render(&stage, object, 16, 3);
        assert!((gpu_map.centre - cpu_map.centre).length() < 1e-6);
        // The CPU's ray from the map's centre through texel `index` (face-major, then row,
        // then column), moved (`ds`, `dt`) texels from the texel's centre.
        let texel_ray = |index: usize, ds: f64, dt: f64| {
            let (face, row, column) = (index / 256, (index % 256) / 16, index % 16);
            face_direction(face, (column as f64 + 0.5 + ds) / 16.0, (row as f64 + 0.5 + dt) / 16.0)
        };
        // Whether a CPU ray [`TEXEL_STRAY`] of a texel from the centre of texel `index` meets a
        // wall whose normal is the GPU texel's and whose albedo there, lit at the texel's own
        // point `at` (the light varies over a texel), is the GPU texel's colour.
        let found_near = |g: &Texel, at: glam::DVec3, index: usize| {
            let d = TEXEL_STRAY;
            [(d, 0.0), (-d, 0.0), (0.0, d), (0.0, -d), (d, d), (d, -d), (-d, d), (-d, -d)].iter().any(|&(ds, dt)| {
                stage.geometry.nearest(cpu_map.centre, texel_ray(index, ds, dt), None, |o| !stage.is_specular(o)).is_some_and(|hit| {
                    let ObjectOptics::Diffuse(wall) = &stage.objects[hit.object] else { return false };
                    let albedo = wall.albedo_at(hit.point.to_array(), hit.normal.to_array());
                    let lit = unshadowed(&stage.lights, albedo, at.to_array(), hit.normal.to_array());
                    (hit.normal - g.normal).length() <= 1e-3 && same_surface(g.surface, Surface::Diffuse(lit))
                })
            })
        };
        for layer in 0..3 {
            let (mut same, mut filled) = (0, 0);
            let mut differing = Vec::new();
            for (index, (g, c)) in gpu_map.layers[layer].iter().zip(&cpu_map.layers[layer]).enumerate() {
                filled += c.is_some() as usize;
                let agrees = match (g, c) {
                    (None, None) => true,
                    (Some(g), Some(c)) => {
                        let distance = (g.distance - c.distance).abs() <= 1e-4 * c.distance;
                        if distance && (g.normal - c.normal).length() <= 1e-3 && same_surface(g.surface, c.surface) {
                            true
                        } else {
                            let at = cpu_map.centre + texel_ray(index, 0.0, 0.0) * c.distance;
                            let diffuse = matches!(g.surface, Surface::Diffuse(_));
                            let found = distance && diffuse && found_near(g, at, index);
                            strayed += found as usize;
                            found
                        }
                    }
                    _ => false,
                };
                same += agrees as usize;
                if !agrees && differing.len() < 8 {
                    let hit = stage.geometry.nearest(cpu_map.centre, texel_ray(index, 0.0, 0.0), None, |o| !stage.is_specular(o));
                    let wall = hit.map(|h| (h.point, h.object));
                    differing.push(format!("texel {index}: gpu {g:?}, cpu {c:?}; the CPU ray's wall hit (point, object) {wall:?}"));
                }
            }
            let total = gpu_map.layers[layer].len();
            eprintln!("map {m} layer {layer}: {same} of {total} texels agree ({filled} filled on the CPU)");
            assert!(filled > 0, "layer {layer} of map {m} holds something");
            assert_eq!(same, total, "map {m} layer {layer}: every texel; first differing:\n{}", differing.join("\n"));
        }
    }
    eprintln!("{strayed} texels show the surface a ray {TEXEL_STRAY} of a texel from their centre finds");
}

/// How far a GPU pixel is from the twin's: per channel |gpu − twin| / (1 + twin), the
/// largest channel; infinite where the twin shows another object.
fn pixel_distance(gpu: [f32; 3], gpu_seen: Option<usize>, twin: &nklut::effects::trace::TracedFrame, pixel: usize) -> f64 {
    if twin.seen[pixel] != gpu_seen {
        return f64::INFINITY;
    }
    let c = twin.radiance[pixel];
    (0..3).map(|i| (gpu[i] as f64 - c[i]).abs() / (1.0 + c[i].abs())).fold(0.0, f64::max)
}

/// The largest [`pixel_distance`] over a frame and the pixel (column, row) where it is.
fn worst_pixel(image: &nklut::gpu::passes::specular::EffectImage, twin: &nklut::effects::trace::TracedFrame) -> (f64, (u32, u32)) {
    (0..image.radiance.len()).map(|p| (pixel_distance(image.radiance[p], image.seen[p], twin, p), p)).fold(
        (0.0, (0, 0)),
        |(worst, at), (d, p)| if d > worst { (d, (p as u32 % image.width, p as u32 / image.width)) } else { (worst, at) },
    )
}

/// How far any pixel of the WGSL bounce loop may be from its f64 twin on the same maps
/// ([`pixel_distance`]). The GPU follows the twin's path in f32: the primary hit from the
/// rasteriser's interpolation and every later one from the f32 search, so each hit point,
/// normal and direction carries a few roundings of 2⁻²⁴ (≈ 6·10⁻⁸) times the condition of
/// what computes it — about 10 for a normalised interpolated normal, Snell's refraction and
/// the search's secant steps — i.e. ≲ 10⁻⁶ per bounce; F and its 1 − F multiply that by at
/// most |d ln F/d cos θ| ≲ 10 at the angles of these scenes (none within 1° of grazing),
/// and a path weights at most 6 such factors (depth 3 with refraction): ≲ 6·10⁻⁵ of the
/// radiance. 10⁻⁴ bounds it. A pixel whose ray passed within that rounding of a map
/// texel's edge or of the rasteriser's edge could take the other side; none does in these
/// scenes (each would be a test failure to look at, not noise to average away).
const TWIN_BOUND: f64 = 1e-4;

/// The WGSL bounce loop against its f64 twin on the same (CPU-rendered) maps, every pixel:
/// the same object and radiance within [`TWIN_BOUND`]. Measured on lavapipe (Mesa 22.3.6):
/// every pixel, worst 9.0·10⁻⁶ (exact 3/3), 6.2·10⁻⁶ (schlick 2/0), 8.7·10⁻⁶ (lut 2/2).
#[test]
fn gpu_specular_pass_matches_the_distance_map_twin() {
    use nklut::effects::experiment::{distance_maps, twin_frame};
    use nklut::effects::image_error::compare;
    use nklut::effects::trace::Camera;
    use nklut::fresnel::{LutSpec, Method};
    use nklut::gpu::passes::distance_maps::{GpuMaps, SceneMeshes};
    use nklut::gpu::passes::specular::{Shot, SpecularPass};
    use nklut::scene::{Depths, SearchSteps};
    let Some(gpu) = device() else { return };
    let (scene, stage) = effects_stage(true);
    let cpu_maps = distance_maps(&stage, 16, 3);
    let maps = GpuMaps::upload(&gpu, &stage, &cpu_maps).unwrap();
    let meshes = SceneMeshes::upload(&gpu, &stage).unwrap();
    let mut pass = SpecularPass::new(&gpu, &stage, 64).unwrap();
    let steps = SearchSteps { linear: 15, secant: 4 };
    let camera = Camera::new(&scene.camera, 0, 48, 48);
    for (method, depths) in [
        (Method::Exact, Depths { reflection: 3, refraction: 3 }),
        (Method::Schlick, Depths { reflection: 2, refraction: 0 }),
        (Method::Lut, Depths { reflection: 2, refraction: 2 }),
    ] {
        let shot = Shot { camera: &scene.camera, frame: 0, depths, steps };
        let image = pass.render(&gpu, &meshes, &maps, shot, method, [48, 48]).unwrap();
        let twin = twin_frame(&stage, &camera, &cpu_maps, method, depths, steps, LutSpec::new(64, lut::ENCODING));
        assert!(image.radiance.iter().flatten().all(|x| x.is_finite()));
        let error = compare(&image.traced(), &twin);
        let (worst, at) = worst_pixel(&image, &twin);
        eprintln!("{method:?} {depths:?}: {} specular pixels; worst pixel {worst:.3e} at {at:?}", error.pixels);
        assert!(error.pixels > 200, "the frame shows the specular objects");
        assert!(worst <= TWIN_BOUND, "{method:?}: pixel {at:?} differs by {worst}");
    }
    assert_eq!(pass.pipelines_compiled, 3, "one pipeline per (effect, method) used");
    assert_eq!(pass.lut_curves, 4, "two curves per specular object, baked once for lut");
}

/// A coarse mesh whose smooth normals stray far from its faces: an octahedron with vertex
/// normals along its corners (54.7° from each face's plane at a corner), half its faces
/// wound clockwise seen from outside. Near its outline the interpolated normal faces away
/// from camera rays that meet a face from outside; the GPU decides the side by the face
/// (`front_facing` on the mesh rewound outwards) as the CPU twin does by the triangle's
/// plane, so every pixel agrees with the twin to [`TWIN_BOUND`] as in the smooth scene.
/// Measured on lavapipe: 70 pixels where the two disagree; every pixel, worst 2.5·10⁻⁶.
#[test]
fn on_a_coarse_mesh_the_gpu_and_the_twin_take_one_side_at_the_primary_hit() {
    use nklut::effects::experiment::{distance_maps, twin_frame};
    use nklut::effects::trace::{stage_from_table, Camera, SpecularMaterial, Surface};
    use nklut::fresnel::{LutSpec, Method};
    use nklut::gpu::passes::distance_maps::{GpuMaps, SceneMeshes};
    use nklut::gpu::passes::specular::{Shot, SpecularPass};
    use nklut::scene::{Depths, SearchSteps};
    let Some(gpu) = device() else { return };
    let dir = scratch("gpu-octahedron");
    let mut obj = String::from("v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n");
    obj += "vn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\nvn 0 0 1\nvn 0 0 -1\n";
    // Every octant's face as (x, y, z) corners: counter-clockwise from outside where the
    // octant's signs multiply to +1, clockwise where they multiply to −1.
    for x in [1, 2] {
        for y in [3, 4] {
            for z in [5, 6] {
                obj += &format!("f {x}//{x} {y}//{y} {z}//{z}\n");
            }
        }
    }
    std::fs::write(dir.join("octahedron.obj"), obj).unwrap();
    let file = dir.join("octahedron.yaml");
    let text = "resolution: [48, 48]\ncamera: {axis: [0.3, 1, 0.2], distance: 1.6, frames: 1}\neffects:\n  reflection: {max_depth: 2}\n  refraction: {max_depth: 2}\n  distance_maps: {size: 16, layers: 3}\n\
         objects:\n  - {mesh: octahedron.obj, scale: 0.6, material: x/y/glass, methods: [exact]}\n\
         \x20 - {mesh: room, scale: [3, 2, 3], diffuse: [0.8, 0.8, 0.75], pattern: {kind: checker, size: 0.5, albedo: [0.1, 0.3, 0.6]}}\nmeasurements: [image_error]\n";
    std::fs::write(&file, text).unwrap();
    let scene = Scene::load(&file).unwrap();
    let glass = SpecularMaterial { channels: DIAMOND, kind: Kind::Dielectric };
    let stage = stage_from_table(&scene, &[SceneMaterial { page: "x/y/glass".into(), optics: glass, spectrum: None }]).unwrap();
    let camera = Camera::new(&scene.camera, 0, 48, 48);
    // The scene does what it is for: pixels where the interpolated normal and the face
    // disagree about the side the camera ray meets the glass from.
    let mut disagree = 0;
    for y in 0..48 {
        for x in 0..48 {
            let ray = camera.ray(x, y);
            if let Some(hit) = stage.nearest(camera.eye, ray, None).filter(|h| matches!(h.surface, Surface::Specular(_))) {
                disagree += ((ray.dot(hit.normal) > 0.0) != (ray.dot(hit.geometric) > 0.0)) as usize;
            }
        }
    }
    eprintln!("octahedron: {disagree} pixels where the interpolated normal and the face disagree on the side");
    assert!(disagree >= 10, "{disagree}");
    let cpu_maps = distance_maps(&stage, 16, 3);
    let maps = GpuMaps::upload(&gpu, &stage, &cpu_maps).unwrap();
    let meshes = SceneMeshes::upload(&gpu, &stage).unwrap();
    let mut pass = SpecularPass::new(&gpu, &stage, 64).unwrap();
    let steps = SearchSteps { linear: 15, secant: 4 };
    let depths = Depths { reflection: 2, refraction: 2 };
    let shot = Shot { camera: &scene.camera, frame: 0, depths, steps };
    let image = pass.render(&gpu, &meshes, &maps, shot, Method::Exact, [48, 48]).unwrap();
    let twin = twin_frame(&stage, &camera, &cpu_maps, Method::Exact, depths, steps, LutSpec::new(64, lut::ENCODING));
    let (worst, at) = worst_pixel(&image, &twin);
    eprintln!("octahedron: worst pixel {worst:.3e} at {at:?}");
    assert!(worst <= TWIN_BOUND, "pixel {at:?} differs by {worst}");
}

/// The runner builds only the effect the scene names: a reflection-only scene renders one
/// cube map per specular object and compiles reflection pipelines only (one per method);
/// naming refraction compiles the refraction variant instead. Its image error goes to
/// `effects_errors` rows from the GPU (exact against itself: zero Fresnel error), its timing
/// to `effects_timing` with the map update apart from the shading pass.
#[test]
fn runner_builds_only_the_effects_the_scene_names() {
    use nklut::fresnel::Method;
    use nklut::gpu::passes::specular::Effect;
    let Some(gpu) = device() else { return };
    let log = &mut |line: &str| eprintln!("{line}");
    for refraction in [false, true] {
        let (mut scene, stage) = effects_stage(refraction);
        scene.resolution = [32, 32];
        scene.experiments = vec![nklut::scene::Experiment::ImageError, nklut::scene::Experiment::Timing];
        scene.timing.resolution = [32, 32];
        scene.timing.warmup = 0;
        scene.timing.repeats = 2;
        let materials = [
            SceneMaterial {
                page: "x/y/glass".into(),
                optics: nklut::effects::trace::SpecularMaterial { channels: DIAMOND, kind: Kind::Dielectric },
                spectrum: None,
            },
            SceneMaterial {
                page: "x/y/gold".into(),
                optics: nklut::effects::trace::SpecularMaterial { channels: GOLDISH, kind: Kind::Conductor },
                spectrum: None,
            },
        ];
        let report = gpu::run_with_materials(&scene, &materials, &gpu, RunStats::default(), log).unwrap();
        let stats = &report.stats;
        eprintln!("{stats}");
        assert_eq!(stats.effects.cube_maps, stage.objects.iter().enumerate().filter(|(o, _)| stage.is_specular(*o)).count());
        assert_eq!(stats.effects.layers, 3);
        assert_eq!(stats.effect_pipelines, 3, "exact, schlick, lut: one pipeline each");
        assert_eq!(stats.refraction_pipelines, if refraction { 3 } else { 0 });
        assert_eq!(stats.pipelines_compiled, 0, "no F-only pipeline in a scene with effects");
        assert_eq!(stats.effects.reference_frames, 1, "one camera frame, one depth configuration");
        let rows = &report.effects.errors;
        assert!(!rows.is_empty() && rows.iter().all(|r| r.renderer == "gpu"));
        for row in rows.iter().filter(|r| r.method == Method::Exact) {
            assert_eq!(row.fresnel.mean_relative(), Some(0.0), "exact against itself on the same path");
            assert!(row.total.pixels > 0 && row.geometry.mean_relative() == row.total.mean_relative());
        }
        let timing = &report.effects.timing;
        assert_eq!(timing.len(), 3, "one row per method (one depth, one search configuration)");
        for row in timing {
            assert_eq!(row.effect, if refraction { Effect::Refraction } else { Effect::Reflection });
            assert!(row.map_update_ms > 0.0 && row.shading_ms > 0.0, "{row:?}");
        }
        assert_eq!(stats.timed_passes, 2 * (1 + 3), "each round: one map update, one shading pass per method");
    }
}

/// `--backend` picks among the backends this build has, and names them when asked for one
/// it lacks.
#[test]
fn a_backend_is_picked_by_name_and_an_unknown_one_is_named() {
    let Some(_shared) = device() else { return };
    for (name, line) in [("Vulkan", "Vulkan"), ("gl", "Gl")] {
        if gpu::context::backends().iter().any(|(built, _)| built.eq_ignore_ascii_case(name)) {
            assert_eq!(gpu::open(None, Some(name)).unwrap().line.backend, line, "llvmpipe is on both");
        }
    }
    let message = format!("{:#}", gpu::open(None, Some("glide")).err().expect("no such backend"));
    let built: Vec<&str> = gpu::context::backends().into_iter().map(|(name, _)| name).collect();
    assert!(message.contains(&format!("backend \"glide\" is not built here; built: {}", built.join(", "))), "{message}");
}
