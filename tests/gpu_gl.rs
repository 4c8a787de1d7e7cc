//! The runner on two backends of this machine: Vulkan (lavapipe) and OpenGL through EGL
//! (Mesa's llvmpipe), the same scenes on each. Every method's cosθ ramp (the F image the
//! shaders compute, all 1024 columns), the image error of each object and method over the
//! camera orbit, and the frames of a scene of multiple reflections and refractions (distance
//! maps rendered, searched and shaded on the GPU) must agree between the two.
//!
//! Mesa's desktop GL 4.5 core context renders to RGBA32F (float colour buffers are core
//! since GL 3.0) but lists neither GL_ARB_color_buffer_float nor GL_EXT_color_buffer_float,
//! the strings wgpu 30 looks for before it allows the runner's float targets; the runner
//! lists the first through Mesa's MESA_EXTENSION_OVERRIDE in its own process before EGL
//! starts (`gpu::context`), so neither these tests nor a user set anything: `nklut gpu run
//! --backend gl SCENE` runs as it is, with the variable removed from its environment.
//!
//! No adapter on either backend is a failure unless NKLUT_SKIP_GPU_TESTS=1.
#![cfg(all(feature = "gpu", target_os = "linux"))]

mod common;

use std::path::Path;

use nklut::gpu::params::{self, MaterialUniform};
use nklut::gpu::render::{self, Renderer};
use nklut::gpu::{self, lut, Gpu, RunStats};
use nklut::scene::{Experiment, Scene, SceneMaterial, Shading};
use nklut::spectrum::{ChannelIndex, Index, Kind};

const GOLDISH: ChannelIndex = [Index::new(0.16, 3.8), Index::new(0.5, 2.3), Index::new(1.2, 1.8)];
const DIAMOND: ChannelIndex = [Index::new(2.409, 0.0), Index::new(2.424, 0.0), Index::new(2.432, 0.0)];

const SCENE: &str = "resolution: [128, 128]
camera: {axis: [1, 1, 1], distance: 2.0, frames: 6, degrees_per_frame: 15, fov_y_degrees: 60}
objects:
  - {mesh: cube, material: x/metals/goldish, methods: [exact, schlick, schlick_nk, schlick_compensated, lazanyi, nvidia, lut, f82_tint, constant, texture]}
  - {mesh: sphere, material: x/crystals/diamond, methods: [exact, schlick, lazanyi, nvidia, lut]}
measurements: [image_error]
lut: {size: 64}
";

/// A glass sphere and a gold cube in a checkered room, reflections and refractions to depth
/// 3, every kind of light (the scene of tests/gpu.rs's effects tests).
const EFFECTS_SCENE: &str = "resolution: [48, 48]
camera: {axis: [0, 1, 0.2], distance: 1.8, frames: 1}
effects:
  reflection: {max_depth: 3}
  refraction: {max_depth: 3}
  distance_maps: {size: 16, layers: 3}
lights:
  - {kind: directional, direction: [-0.3, -1, -0.5], colour: [0.5, 0.5, 0.5]}
  - {kind: point, position: [0.5, 0.8, -0.5], intensity: [0.6, 0.5, 0.4]}
  - {kind: ambient, colour: [0.2, 0.2, 0.2]}
objects:
  - {mesh: sphere, scale: 0.5, position: [0.2, 0, 0], material: x/crystals/diamond, methods: [exact, schlick, lut]}
  - {mesh: cube, scale: 0.25, position: [-0.6, -0.2, 0.3], material: x/metals/goldish, methods: [exact]}
  - {mesh: room, scale: [3, 2, 3], diffuse: [0.8, 0.8, 0.75], pattern: {kind: checker, size: 0.5, albedo: [0.1, 0.3, 0.6]}}
measurements: [image_error]
";

/// Every method's ramp for `channels` (1024 × 1, its LUT of 64 texels) on `gpu`.
fn ramps(gpu: &Gpu, channels: &ChannelIndex) -> Vec<(Shading, Vec<f32>)> {
    let mut renderer = Renderer::new(gpu);
    let prepared = params::prepare(channels);
    let texture = lut::upload(gpu, &lut::texels(&prepared, 64), "lut");
    let view = texture.create_view(&Default::default());
    let binding = renderer.bind(gpu, &MaterialUniform::from_prepared(&prepared), Some(&view)).unwrap();
    Shading::ALL.iter().map(|&m| (m, render::ramp(gpu, &mut renderer, m, &binding, 1024, 1).unwrap())).collect()
}

#[test]
fn vulkan_and_gl_render_the_same_images() {
    let Some(vulkan) = common::gpu::open(Some("vulkan")) else { return };
    let Some(gl) = common::gpu::open(Some("gl")) else { return };
    assert_eq!((vulkan.line.backend.as_str(), gl.line.backend.as_str()), ("Vulkan", "Gl"));
    eprintln!("vulkan: {}\ngl: {}", vulkan.line, gl.line);

    // The F images: every method, both materials, column by column. The same WGSL through
    // two compilers (naga → SPIR-V → llvmpipe; naga → GLSL → Mesa's GLSL → llvmpipe): each
    // is f32 throughout, so they may differ by the rounding of a reordered operation; the
    // bound is 4 f32 steps at F ≤ 1 (4 · 2⁻²⁴ ≈ 2.4e-7), the half-float texture's linear
    // filter included (the same llvmpipe sampler behind both; measured: equal to the bit).
    let mut worst = 0.0f32;
    for channels in [GOLDISH, DIAMOND] {
        for ((method, a), (_, b)) in ramps(&vulkan, &channels).iter().zip(ramps(&gl, &channels)) {
            let difference = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
            assert!(difference <= 2.4e-7, "{method}: {difference}");
            worst = worst.max(difference);
        }
    }
    eprintln!("ramps: largest |vulkan − gl| = {worst:.3e}");

    // The scene's image error over the orbit: the same covered pixels (the rasterisers
    // follow the same rules on the same f32 vertices) and each method's error against
    // exact to 1e-4 of itself (measured: 4e-6 at most, the `lut` rows; the others equal to
    // the digits printed).
    let scene = Scene::parse(SCENE, Path::new("tests/gpu_gl.rs scene")).unwrap();
    assert_eq!(scene.experiments, vec![Experiment::ImageError]);
    let materials = [
        SceneMaterial::new("x/metals/goldish", GOLDISH, Kind::Conductor),
        SceneMaterial::new("x/crystals/diamond", DIAMOND, Kind::Dielectric),
    ];
    let on_vulkan = gpu::run_with_materials(&scene, &materials, &vulkan, RunStats::default(), &mut |_| {}).unwrap();
    let on_gl = gpu::run_with_materials(&scene, &materials, &gl, RunStats::default(), &mut |_| {}).unwrap();
    assert_eq!(on_vulkan.image_errors.len(), 15);
    for (v, g) in on_vulkan.image_errors.iter().zip(&on_gl.image_errors) {
        assert_eq!((&v.object, v.method), (&g.object, g.method));
        assert_eq!(v.pixels, g.pixels, "{} {}: covered pixels", v.object, v.method);
        let (a, b) = (v.mean_rel_error.unwrap(), g.mean_rel_error.unwrap());
        eprintln!("{} {}: vulkan {a:.6e} gl {b:.6e}", v.object, v.method);
        assert!((a - b).abs() <= 1e-4 * a + 1e-9, "{} {}: vulkan {a} gl {b}", v.object, v.method);
    }

    // Multiple reflections and refractions: the GPU frames of every method, pixel for pixel.
    // Each pixel's path crosses up to three searches of the maps; an f32 difference of
    // rounding can move a search across a texel edge and change that pixel, so the bound is
    // on the share of pixels that differ (≤ 1 %) and on the rest (≤ 1e-5 per channel).
    let scene = Scene::parse(EFFECTS_SCENE, Path::new("tests/gpu_gl.rs effects scene")).unwrap();
    let on_vulkan = gpu::run_with_materials(&scene, &materials, &vulkan, RunStats::default(), &mut |_| {}).unwrap();
    let on_gl = gpu::run_with_materials(&scene, &materials, &gl, RunStats::default(), &mut |_| {}).unwrap();
    let (v, g) = (&on_vulkan.effects.pictures, &on_gl.effects.pictures);
    assert!(!v.is_empty() && v.len() == g.len(), "{} and {} pictures", v.len(), g.len());
    for (a, b) in v.iter().zip(g) {
        assert_eq!(a.stem, b.stem);
        let pixels = a.frame.radiance.len();
        let differing = a.frame.radiance.iter().zip(&b.frame.radiance).filter(|(x, y)| (0..3).any(|c| (x[c] - y[c]).abs() > 1e-5)).count();
        let covered = a.frame.seen.iter().filter(|s| s.is_some()).count();
        eprintln!("{}: {differing} of {pixels} pixels differ by more than 1e-5 ({covered} on specular objects)", a.stem);
        assert_eq!(a.frame.seen, b.frame.seen, "{}: the same object seen at every pixel", a.stem);
        assert!(differing * 100 <= pixels, "{}: {differing} of {pixels} pixels differ", a.stem);
    }
}

/// `nklut gpu run --backend gl` with no MESA_EXTENSION_OVERRIDE in its environment: timing
/// and image error of a small scene, both tables written.
#[test]
fn gl_runs_from_the_command_line_with_no_environment_variable() {
    if common::gpu::open(Some("gl")).is_none() {
        return;
    }
    let dir = common::scratch("gpu-gl-cli");
    let scene = dir.join("gl.yaml");
    std::fs::write(
        &scene,
        "resolution: [32, 32]\ncamera: {frames: 1}\nobjects: [{mesh: cube, material: 3d/liquids/water, methods: [exact, schlick]}]\nmeasurements: [timing, image_error]\ntiming: {resolution: [64, 16], warmup: 1, repeats: 3}\n",
    )
    .unwrap();
    let out = dir.join("out");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_nklut"))
        .env_remove("MESA_EXTENSION_OVERRIDE")
        .arg("--db")
        .arg(common::database_dir())
        .arg("--out")
        .arg(&out)
        .args(["gpu", "run", "--backend", "gl"])
        .arg(&scene)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("(Gl,"), "{stderr}");
    for table in ["gpu_timing.csv", "image_errors.csv"] {
        let text = std::fs::read_to_string(out.join(table)).unwrap_or_else(|e| panic!("{table}: {e}\n{stderr}"));
        assert_eq!(text.lines().count(), 3, "{table}: a header and two rows\n{text}");
    }
}
