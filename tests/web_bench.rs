//! The browser bench (`nklut gpu web`) in a real browser: the page of a small scene runs in
//! the system Chromium's WebGPU on SwiftShader (tests/clients/run_web_bench.mjs drives it
//! through puppeteer-core), and what it measures is held to the native runner on this
//! machine's Vulkan adapter (lavapipe): every module compiles without a message, every timed
//! pair has a positive median, each method's image error against `exact` agrees with the
//! native runner's, and the page's read-back F ramp equals `render::ramp`'s. A reflection
//! and refraction scene's page times every configuration the native runner times
//! (`effects_timing`, by timestamps and by the wall clock) and renders the frame lavapipe
//! renders, within a stated bound; maps over the storage limit are named. The page's
//! twins of `image_error::compare` and `stats::median_and_iqr` are run on a hand-made
//! input beside the Rust functions, and the failure paths show their messages: no
//! adapter, no `navigator.gpu`, a scene over the adapter's `maxBufferSize`.
//!
//! Chromium and puppeteer-core come from `scripts/test-deps` (`make test`); without them
//! these tests fail unless NKLUT_SKIP_VALIDATOR_TESTS=1. No adapter for the native side is
//! a failure unless NKLUT_SKIP_GPU_TESTS=1 (as tests/gpu.rs).
#![cfg(feature = "gpu")]

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use common::scratch;
use nklut::gpu::params::{self, MaterialUniform};
use nklut::gpu::render::{self, Renderer};
use nklut::gpu::{self, lut, web, RunStats};
use nklut::scene::{Scene, SceneMaterial, Shading};
use nklut::spectrum::{ChannelIndex, Index, Kind};
use serde_json::Value;

const GOLDISH: ChannelIndex = [Index::new(0.16, 3.8), Index::new(0.5, 2.3), Index::new(1.2, 1.8)];
const WATER: ChannelIndex = [Index::new(1.331, 0.0), Index::new(1.336, 0.0), Index::new(1.338, 0.0)];

const SCENE: &str = "resolution: [96, 96]
camera: {axis: [1, 1, 1], distance: 2.0, frames: 4, degrees_per_frame: 20, fov_y_degrees: 60}
objects:
  - {mesh: cube, material: test/metals/goldish, methods: [exact, schlick, lut, nvidia, constant, texture]}
  - {mesh: sphere, material: test/liquids/water, methods: [exact, schlick, lazanyi, lut]}
measurements: [timing, image_error]
timing: {resolution: [256, 64], warmup: 2, repeats: 6}
lut: {size: 64}
";

const RAMP: [u32; 2] = [256, 2];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn materials() -> Vec<SceneMaterial> {
    vec![
        SceneMaterial::new("test/metals/goldish", GOLDISH, Kind::Conductor),
        SceneMaterial::new("test/liquids/water", WATER, Kind::Dielectric),
    ]
}

fn scene(text: &str) -> Scene {
    Scene::parse(text, Path::new("web-test.yaml")).unwrap()
}

fn skip_browser(reason: &str) -> bool {
    if std::env::var("NKLUT_SKIP_VALIDATOR_TESTS").as_deref() == Ok("1") {
        eprintln!("browser bench test skipped (NKLUT_SKIP_VALIDATOR_TESTS=1): {reason}");
        return true;
    }
    false
}

/// Write the page of `text` and run it with `args`; the runner's output JSON.
fn run_page(name: &str, text: &str, args: &[String]) -> Result<Option<Value>, String> {
    let deps = std::env::var_os("NKLUT_TEST_DEPS").map(PathBuf::from).unwrap_or_else(|| root().join(".test-deps"));
    let puppeteer = deps.join("npm/node_modules/puppeteer-core/package.json");
    if !puppeteer.exists() {
        let reason = format!("{} is missing: run `bash scripts/test-deps` (make test does)", puppeteer.display());
        return if skip_browser(&reason) { Ok(None) } else { Err(reason) };
    }
    let dir = scratch(name);
    let html = web::page(&web::plan(&scene(text), &materials()).map_err(|e| format!("{e:#}"))?).map_err(|e| format!("{e:#}"))?;
    let page = dir.join("page.html");
    std::fs::write(&page, html).map_err(|e| e.to_string())?;
    let out = dir.join("out.json");
    let output = Command::new("node")
        .arg(root().join("tests/clients/run_web_bench.mjs"))
        .arg(&page)
        .arg(&out)
        .args(args)
        .env("NKLUT_TEST_DEPS", &deps)
        .output()
        .map_err(|e| format!("node (scripts/test-deps installs it): {e}"))?;
    if !output.status.success() {
        return Err(format!("run_web_bench failed: {}", String::from_utf8_lossy(&output.stderr)));
    }
    let text = std::fs::read_to_string(&out).map_err(|e| e.to_string())?;
    serde_json::from_str(&text).map(Some).map_err(|e| e.to_string())
}

/// The twin input: the hand-made frame of `image_error`'s unit test and a sample list.
const TWIN_METHOD: [f32; 8] = [0.55, 0.25, 0.1, 1.0, 0.0, 0.0, 0.0, 0.0];
const TWIN_REFERENCE: [f32; 8] = [0.5, 0.25, 0.0, 1.0, 9.0, 9.0, 9.0, 0.0];
const TWIN_SAMPLES: [f64; 6] = [5.0, 1.0, 3.0, 2.0, 4.0, 9.5];
/// A seed past 2^53 (the page reads it as a decimal string into a BigInt) and readings
/// quantised to 100 µs from an offset.
const TWIN_SEED: u64 = 18_446_744_073_709_551_557;
const TWIN_READINGS: [u64; 4] = [17_000_300_000, 17_000_400_000, 17_000_900_000, 17_001_100_000];

/// The page run of [`SCENE`] on SwiftShader with the ramp of `lut` and the twins, once.
fn main_run() -> &'static Result<Option<Value>, String> {
    static RUN: OnceLock<Result<Option<Value>, String>> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = scratch("web-twin");
        let twin = dir.join("twin.json");
        let input = serde_json::json!({
            "method": TWIN_METHOD, "reference": TWIN_REFERENCE, "samples": TWIN_SAMPLES,
            "seed": TWIN_SEED.to_string(), "n": 23, "readings": TWIN_READINGS.map(|r| r.to_string()),
        });
        std::fs::write(&twin, input.to_string()).map_err(|e| e.to_string())?;
        let ramp = format!("0,lut,{},{},{}", RAMP[0], RAMP[1], web::fullscreen_view(RAMP[0], RAMP[1]));
        run_page(
            "web-bench",
            SCENE,
            &["--ramp".into(), ramp, "--twin".into(), twin.display().to_string(), "--query".into(), "frames=all".into()],
        )
    })
}

fn page_output() -> Option<&'static Value> {
    match main_run() {
        Ok(value) => value.as_ref(),
        Err(error) => panic!("{error}"),
    }
}

fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

#[test]
fn every_module_compiles_and_every_pair_is_timed() {
    let Some(out) = page_output() else { return };
    let result = &out["result"];
    assert_eq!(out["problem"], Value::Null, "{out}");
    assert_eq!(result["complete"], true);
    assert_eq!(result["format"], web::FORMAT);
    // Every module of every pass, compiled unchanged: no error, no warning.
    let plan = web::plan(&scene(SCENE), &materials()).unwrap();
    let compiled = result["compile"].as_array().unwrap();
    assert_eq!(compiled.len(), plan.checks.len());
    for module in compiled {
        assert_eq!(module["errors"].as_array().unwrap().len(), 0, "{module}");
        assert_eq!(module["warnings"].as_array().unwrap().len(), 0, "{module}");
    }
    // SwiftShader grants timestamp queries; one row per (material, method), positive.
    let rows = result["gpu_timing"].as_array().unwrap();
    let pairs = scene(SCENE).material_shadings();
    assert_eq!(rows.len(), pairs.len());
    for (row, (material, method)) in rows.iter().zip(&pairs) {
        assert_eq!((row["material"].as_str(), row["method"].as_str()), (Some(material.as_str()), Some(method.name())));
        assert_eq!(row["timer"], "timestamp");
        assert_eq!(row["repeats"], 6);
        assert!(row["evaluations"].as_u64().is_some_and(|n| n >= 1), "{row}");
        assert_eq!(row["samples_ms"].as_str().unwrap().split(' ').count(), 6, "every sample kept: {row}");
        assert!(number(&row["ns_per_evaluation"]) > 0.0, "{row}");
        assert!(number(&row["median_ms"]) > 0.0, "{row}");
        assert!(number(&row["spread_ms"]) >= 0.0, "{row}");
        // The keys are the native table's columns.
        let keys: Vec<&str> = row.as_object().unwrap().keys().map(String::as_str).collect();
        let mut columns: Vec<&str> = plan.columns.gpu_timing.iter().map(String::as_str).collect();
        let mut sorted_keys = keys.clone();
        sorted_keys.sort();
        columns.sort();
        assert_eq!(sorted_keys, columns);
    }
    // The study's normalisation: exact on water (the dielectric) is 1.
    let water_exact = rows.iter().find(|r| r["material"] == "test/liquids/water" && r["method"] == "exact").unwrap();
    assert!((number(&water_exact["relative_to_exact_dielectric"]) - 1.0).abs() < 1e-12);
    // The page shows a row per pair and a bar per ratio, and names its download.
    assert_eq!(out["tables"]["timing"].as_array().unwrap().len(), rows.len() + 1);
    assert_eq!(out["chart_bars"].as_u64(), Some(rows.len() as u64));
    // A bar per image-error row but exact's (10 rows, 2 of them exact).
    assert_eq!(out["error_bars"].as_u64(), Some(8));
    let download = out["download"].as_str().unwrap();
    assert!(download.starts_with("device-google-swiftshader-web-test-") && download.ends_with(".json"), "{download}");
    // What a result says of itself.
    assert_eq!(result["nklut_version"], env!("CARGO_PKG_VERSION"));
    let html = web::page(&plan).unwrap();
    let hash = result["plan_hash"].as_str().unwrap();
    assert_eq!(hash.len(), 16);
    assert!(html.contains(&format!("data-hash=\"{hash}\"")), "the hash of this plan");
    assert!(result["adapter"]["is_fallback_adapter"].is_boolean());
    assert_eq!(result["adapter"]["adapter_type"], "cpu", "SwiftShader is a CPU rasteriser");
    assert_eq!(result["image_error_frames"], "all");
    assert_eq!(result["timing_sampling"]["seed"], scene(SCENE).timing.seed.to_string());
}

#[test]
fn the_page_s_twins_equal_the_rust_functions() {
    let Some(out) = page_output() else { return };
    let twin = &out["twin"];
    let frame = gpu::image_error::compare(&TWIN_METHOD, &TWIN_REFERENCE);
    assert_eq!(twin["frame"]["pixels"].as_u64(), Some(frame.pixels));
    assert_eq!(twin["frame"]["samples"].as_u64(), Some(frame.samples));
    assert_eq!(twin["frame"]["skipped_zero_reference"].as_u64(), Some(frame.skipped_zero_reference));
    // f32 inputs: JavaScript's doubles of the same f32 values, the same operations.
    assert!((number(&twin["frame"]["sum_relative"]) - frame.sum_relative).abs() < 1e-12);
    assert!((number(&twin["frame"]["max_relative"]) - frame.max_relative).abs() < 1e-12);
    let mut summary = gpu::image_error::ErrorSummary::default();
    summary.add(&frame);
    summary.add(&gpu::image_error::compare(&TWIN_REFERENCE, &TWIN_REFERENCE));
    assert!((number(&twin["summary_mean"]) - summary.mean_relative().unwrap()).abs() < 1e-12);
    // Hand-derived: sorted 1 2 3 4 5 9.5 → median 3.5, q25 = 2.25, q75 = 4.75.
    let (median, iqr) = nklut::gpu::timing::median_and_iqr(&TWIN_SAMPLES);
    assert_eq!((median, iqr), (3.5, 2.5));
    assert_eq!((number(&twin["median"]), number(&twin["iqr"])), (median, iqr));
    // The pairs' order and the timer's resolution: sampling's SplitMix64 and gcd rule.
    let order = nklut::gpu::sampling::SplitMix64::new(TWIN_SEED).permutation(23);
    let page: Vec<usize> = twin["permutation"].as_array().unwrap().iter().map(|x| x.as_u64().unwrap() as usize).collect();
    assert_eq!(page, order);
    assert_eq!(nklut::gpu::sampling::resolution_ns(&TWIN_READINGS, 1.0), Some(100_000.0));
    assert_eq!(number(&twin["resolution"]), 100_000.0);
}

/// The native runner's image errors and ramp on this machine's adapter, for comparison.
#[test]
fn image_errors_and_the_ramp_agree_with_the_native_runner() {
    let Some(out) = page_output() else { return };
    let Some(gpu) = common::gpu::open(None) else { return };
    let mut image_error_scene = scene(SCENE);
    image_error_scene.experiments = vec![nklut::scene::Experiment::ImageError];
    let native = gpu::run_with_materials(&image_error_scene, &materials(), &gpu, RunStats::default(), &mut |_| {}).unwrap();
    let page_rows = out["result"]["image_errors"].as_array().unwrap();
    assert_eq!(page_rows.len(), native.image_errors.len());
    let mut report = Vec::new();
    for (page, native) in page_rows.iter().zip(&native.image_errors) {
        assert_eq!(page["method"].as_str(), Some(native.method.name()));
        assert_eq!(page["object"].as_str(), Some(native.object.as_str()));
        assert_eq!(page["frames"].as_u64(), Some(native.frames as u64));
        // Coverage: the two rasterisers may differ on edge pixels only (top-left rule, f32
        // vertex transforms): within 1 % of the covered pixels.
        let pixels = page["pixels"].as_u64().unwrap() as f64;
        assert!((pixels - native.pixels as f64).abs() <= 0.01 * native.pixels as f64, "{page} vs {native:?}");
        // The mean relative error of each method against exact: within 2 % of the native
        // figure (1e-6 absolute for exact against itself). The two drivers rasterise the
        // same f32 vertices with their own f32 maths (exp2/log2, sqrt), and the edge pixels
        // they cover differ; measured here (SwiftShader against lavapipe): 1 % at most, on
        // the sphere's `lut`, whose error (4.6e-4) is itself f32 and half-float noise; the
        // analytic methods agree to 0.1 %.
        let (p, n) = (page["mean_rel_error"].as_f64().unwrap(), native.mean_rel_error.unwrap());
        report.push(format!("{} {}: page {p:.4e} native {n:.4e}", native.object, native.method));
        assert!((p - n).abs() <= 0.02 * n + 1e-6, "{}", report.join("\n"));
    }
    eprintln!("{}", report.join("\n"));

    // The read-back ramp of `lut` for the first material, texel for texel against the
    // native render::ramp of the same uniform and texture.
    let mut renderer = Renderer::new(&gpu);
    let prepared = params::prepare(&GOLDISH);
    let texture = lut::upload(&gpu, &lut::texels(&prepared, 64), "goldish");
    let view = texture.create_view(&Default::default());
    let binding = renderer.bind(&gpu, &MaterialUniform::from_prepared(&prepared), Some(&view)).unwrap();
    let native_ramp = render::ramp(&gpu, &mut renderer, Shading::Fresnel(nklut::fresnel::Method::Lut), &binding, RAMP[0], RAMP[1]).unwrap();
    let page_ramp: Vec<f64> = out["ramp"].as_array().unwrap().iter().map(number).collect();
    assert_eq!(page_ramp.len(), native_ramp.len());
    let worst = page_ramp.iter().zip(&native_ramp).map(|(p, n)| (p - *n as f64).abs()).fold(0.0, f64::max);
    // The same uniform, texture and sampler through the same WGSL: measured equal to the
    // bit between SwiftShader and lavapipe; held to 1e-6 (a few f32 steps at F ≤ 1), which
    // leaves room for one rounding of the linear filter's weights and nothing more.
    eprintln!("ramp: largest |page − native| = {worst:.3e}");
    assert!(worst <= 1e-6, "largest ramp difference {worst}");
}

#[test]
fn no_adapter_and_no_webgpu_each_say_what_is_missing() {
    let Ok(Some(off)) = run_page("web-off", SCENE, &["--webgpu".into(), "off".into()]).map_err(|e| panic!("{e}")) else { return };
    let text = off["problem"].as_str().unwrap_or_else(|| panic!("no problem shown: {off}"));
    assert!(text.contains("requestAdapter() returned no adapter"), "{text}");
    assert_eq!(off["result"]["complete"], false);
    let Ok(Some(absent)) = run_page("web-absent", SCENE, &["--webgpu".into(), "absent".into()]).map_err(|e| panic!("{e}")) else { return };
    let text = absent["problem"].as_str().unwrap_or_else(|| panic!("no problem shown: {absent}"));
    assert!(text.contains("navigator.gpu is missing"), "{text}");
}

#[test]
fn a_scene_over_the_adapter_s_buffer_limit_names_the_limit() {
    // The cube's readback: exact and its six methods, seven 8192² RGBA32Float images in one
    // buffer (7 GiB), over SwiftShader's 1 GiB; checked before anything is allocated.
    let text = SCENE.replace("resolution: [96, 96]", "resolution: [8192, 8192]");
    let Ok(Some(out)) = run_page("web-limit", &text, &[]).map_err(|e| panic!("{e}")) else { return };
    let problem = out["problem"].as_str().unwrap_or_else(|| panic!("no problem shown: {out}"));
    let asked = 8192u64 * 16 * 8192 * 7;
    assert!(problem.contains("maxBufferSize") && problem.contains(&asked.to_string()), "{problem}");
    assert_eq!(out["result"]["gpu_timing"].as_array().unwrap().len(), 0);
}

#[test]
fn without_timestamps_the_page_times_by_the_wall_clock() {
    // `?timer=wall` takes the path of an adapter without timestamp queries.
    let text = SCENE.replace("measurements: [timing, image_error]", "measurements: [timing]");
    let Ok(Some(out)) = run_page("web-wall", &text, &["--query".into(), "timer=wall".into()]).map_err(|e| panic!("{e}")) else { return };
    let result = &out["result"];
    assert_eq!(result["complete"], true, "{out}");
    assert_eq!(result["adapter"]["timestamp_query"], false);
    let rows = result["gpu_timing"].as_array().unwrap();
    assert_eq!(rows.len(), scene(&text).material_shadings().len());
    assert!(rows.iter().all(|r| r["timer"] == "wall" && number(&r["median_ms"]) > 0.0), "{rows:?}");
    assert_eq!(result["image_errors"].as_array().unwrap().len(), 0, "image error not in the scene's measurements");
}

#[test]
fn the_study_s_subtraction_runs_the_burner_under_each_method() {
    // `subtract`: each sample is the burner with the method blended on top minus the burner
    // alone; the page compiles the burner's module and times every pair that way.
    let text = SCENE
        .replace("measurements: [timing, image_error]", "measurements: [timing]")
        .replace("repeats: 6}", "repeats: 6, subtract: true}");
    let plan = web::plan(&scene(&text), &materials()).unwrap();
    assert!(plan.timing.as_ref().unwrap().subtract);
    let Ok(Some(out)) = run_page("web-subtract", &text, &[]).map_err(|e| panic!("{e}")) else { return };
    let result = &out["result"];
    assert_eq!(result["complete"], true, "{out}");
    let compiled: Vec<&str> = result["compile"].as_array().unwrap().iter().map(|c| c["module"].as_str().unwrap()).collect();
    assert!(compiled.contains(&"fresnel pass: burner"), "{compiled:?}");
    let rows = result["gpu_timing"].as_array().unwrap();
    assert_eq!(rows.len(), scene(&text).material_shadings().len());
    // A difference of two noisy times: finite, not necessarily positive on a CPU rasteriser.
    assert!(rows.iter().all(|r| r["median_ms"].as_f64().is_some_and(f64::is_finite) && r["repeats"] == 6), "{rows:?}");
}

/// A water sphere and a gold cube in a checkered room, reflections one and two bounces deep
/// with refraction, two linear search lengths: 2 depths × 2 search configurations × 3
/// methods, small enough for SwiftShader and lavapipe (16² maps, a 48² target).
const EFFECTS_SCENE: &str = "resolution: [48, 48]
camera: {axis: [0, 1, 0.2], distance: 1.8, frames: 1}
effects:
  reflection: {max_depth: [1, 2]}
  refraction: {max_depth: 2}
  distance_maps: {size: 16, layers: 3, linear_steps: [8, 15], secant_steps: [1]}
lights:
  - {kind: directional, direction: [-0.3, -1, -0.5], colour: [0.5, 0.5, 0.5]}
  - {kind: point, position: [0.5, 0.8, -0.5], intensity: [0.6, 0.5, 0.4]}
  - {kind: ambient, colour: [0.2, 0.2, 0.2]}
objects:
  - {mesh: sphere, scale: 0.5, position: [0.2, 0, 0], material: test/liquids/water, methods: [exact, schlick, lut]}
  - {mesh: cube, scale: 0.25, position: [-0.6, -0.2, 0.3], material: test/metals/goldish, methods: [exact]}
  - {mesh: room, scale: [3, 2, 3], diffuse: [0.8, 0.8, 0.75], pattern: {kind: checker, size: 0.5, albedo: [0.1, 0.3, 0.6]}}
measurements: [timing]
timing: {resolution: [48, 48], warmup: 1, repeats: 3}
lut: {size: 64}
";

/// The effects configuration whose frame the page reads back: `lut` (its atlas, sampler and
/// half floats in play) at reflection depth 2 and refraction 2, 15 linear steps.
const EFFECT_FRAME: usize = 11;

/// The page run of [`EFFECTS_SCENE`] with the frame of [`EFFECT_FRAME`] read back, once.
fn effects_run() -> Option<&'static Value> {
    static RUN: OnceLock<Result<Option<Value>, String>> = OnceLock::new();
    match RUN.get_or_init(|| run_page("web-effects", EFFECTS_SCENE, &["--effect-frame".into(), EFFECT_FRAME.to_string()])) {
        Ok(value) => value.as_ref(),
        Err(error) => panic!("{error}"),
    }
}

/// A configuration's key: (method, effect, reflection depth, refraction depth, linear steps,
/// secant steps).
type ConfigurationKey = (String, String, u64, u64, u64, u64);

fn key_of(row: &Value) -> ConfigurationKey {
    let int = |name: &str| row[name].as_u64().unwrap_or_else(|| panic!("{name} in {row}"));
    let text = |name: &str| row[name].as_str().unwrap_or_else(|| panic!("{name} in {row}")).to_string();
    (text("method"), text("effect"), int("reflection_depth"), int("refraction_depth"), int("linear_steps"), int("secant_steps"))
}

#[test]
fn the_page_times_every_effects_configuration_the_native_runner_times() {
    use nklut::gpu::effects::timed_configurations;
    use nklut::gpu::passes::specular::Effect;
    let scene = scene(EFFECTS_SCENE);
    let plan = web::plan(&scene, &materials()).unwrap();
    // As the native runner: a scene with specular effects measures those, not the F-only passes.
    assert!(plan.timing.is_none() && plan.image_error.is_none());
    let effects = plan.effects.as_ref().expect("an effects plan");
    let planned: Vec<ConfigurationKey> = timed_configurations(&scene)
        .iter()
        .map(|c| {
            let effect = Effect::of(c.depths).name().to_string();
            (
                c.method.name().to_string(),
                effect,
                c.depths.reflection.into(),
                c.depths.refraction.into(),
                c.steps.linear.into(),
                c.steps.secant.into(),
            )
        })
        .collect();
    // Hand count: depths (1, 2) and (2, 2) × linear steps 8 and 15 × exact, schlick, lut.
    assert_eq!(planned.len(), 12);
    assert_eq!(planned[EFFECT_FRAME], ("lut".into(), "refraction".into(), 2, 2, 15, 1));
    assert_eq!(effects.configurations.len(), planned.len());
    // The map update: 2 specular objects × 3 layers, each step six faces.
    assert_eq!((effects.maps.cube_maps, effects.maps.steps.len()), (2, 6));
    assert_eq!(effects.maps.buffer_bytes, 2 * 6 * 16 * 16 * 3 * 16);

    let Some(out) = effects_run() else { return };
    let result = &out["result"];
    assert_eq!(out["problem"], Value::Null, "{out}");
    assert_eq!(result["complete"], true);
    let rows = result["effects_timing"].as_array().unwrap();
    let page: Vec<ConfigurationKey> = rows.iter().map(key_of).collect();
    assert_eq!(page, planned, "one row per configuration, in the native order");
    let mut columns: Vec<&str> = plan.columns.effects_timing.iter().map(String::as_str).collect();
    columns.sort();
    for row in rows {
        // The native table's columns, no more, no fewer.
        let mut keys: Vec<&str> = row.as_object().unwrap().keys().map(String::as_str).collect();
        keys.sort();
        assert_eq!(keys, columns, "{row}");
        // SwiftShader grants timestamp queries.
        assert_eq!(row["timer"], "timestamp");
        assert_eq!((row["repeats"].as_u64(), row["map_size"].as_u64(), row["layers"].as_u64()), (Some(3), Some(16), Some(3)));
        assert_eq!((row["cube_maps"].as_u64(), row["resolution"].as_str()), (Some(2), Some("48x48")));
        for name in ["map_update_ms", "shading_ms"] {
            let ms = number(&row[name]);
            assert!(ms.is_finite() && ms > 0.0, "{name} {row}");
        }
        assert!(number(&row["shading_spread_ms"]) >= 0.0, "{row}");
        let frame = number(&row["frame_ms"]) - number(&row["map_update_ms"]) - number(&row["shading_ms"]);
        assert!(frame.abs() <= 1e-9 * number(&row["frame_ms"]), "frame_ms is the sum {row}");
    }
    // One map update per round, shared by the rows.
    assert!(rows.iter().all(|r| r["map_update_ms"] == rows[0]["map_update_ms"]));
    // The page's table: a header and a row per configuration.
    assert_eq!(out["tables"]["effects"].as_array().unwrap().len(), rows.len() + 1);

    // The native runner on this machine's adapter times the same set.
    let Some(gpu) = common::gpu::open(None) else { return };
    let mut quick = scene.clone();
    quick.timing.warmup = 0;
    quick.timing.repeats = 1;
    let native = gpu::run_with_materials(&quick, &materials(), &gpu, RunStats::default(), &mut |_| {}).unwrap();
    let native: Vec<ConfigurationKey> = native
        .effects
        .timing
        .iter()
        .map(|r| {
            let (d, s) = (r.depths, r.steps);
            (
                r.method.name().to_string(),
                r.effect.name().to_string(),
                d.reflection.into(),
                d.refraction.into(),
                s.linear.into(),
                s.secant.into(),
            )
        })
        .collect();
    assert_eq!(page, native);
}

/// The page's frame of one configuration (its maps rendered by the page, then the shading
/// pass) against the native runner's on lavapipe: the same maps rendered by the same
/// WGSL from the same bytes, then the same shading. Every pixel is bounded:
///
/// - it shows the object the native pixel shows;
/// - it differs from the native pixel by no more than the walls' largest colour jump (the
///   spread, per channel, of the lit colours in the native maps' diffuse layer) plus
///   [`PAGE_ROUNDING`]. SwiftShader and lavapipe rasterise the maps' texels near a checker
///   cell's edge into different cells (as lavapipe does against the CPU's ray-cast maps,
///   `gpu_distance_maps_match_the_ray_cast_twin`), so a branch reading such a texel ends on
///   the other colour of the walls; a path's branch weights sum to at most 1 (F + (1 − F) =
///   1 per bounce, total internal reflection 1), so the whole pixel moves by at most one
///   such jump.
///
/// The bulk is held where only roundings differ: the median pixel within [`PAGE_ROUNDING`].
/// Measured (SwiftShader in Chromium 156 against lavapipe, Mesa 22.3.6): no pixel sees
/// another object, 62 of 2304 differ by over 10⁻³, the largest 0.32 (the jump is 0.55 in
/// red), median 8.8·10⁻⁶.
#[test]
fn the_page_s_effects_frame_agrees_with_the_native_runner() {
    use nklut::effects::trace::{stage_from_table, Surface};
    use nklut::gpu::effects::timed_configurations;
    use nklut::gpu::passes::distance_maps::{MapRenderer, SceneMeshes};
    use nklut::gpu::passes::specular::{Shot, SpecularPass};
    let Some(out) = effects_run() else { return };
    let Some(gpu) = common::gpu::open(None) else { return };
    let scene = scene(EFFECTS_SCENE);
    let configuration = timed_configurations(&scene)[EFFECT_FRAME];
    let stage = stage_from_table(&scene, &materials()).unwrap();
    let meshes = SceneMeshes::upload(&gpu, &stage).unwrap();
    let renderer = MapRenderer::new(&gpu, &stage).unwrap();
    let settings = &scene.effects.as_ref().unwrap().distance_maps;
    let maps = renderer.allocate(&gpu, &stage, settings.size, settings.layers).unwrap();
    renderer.render(&gpu, &meshes, &maps).unwrap();
    let mut pass = SpecularPass::new(&gpu, &stage, scene.lut.size as usize).unwrap();
    let shot = Shot { camera: &scene.camera, frame: 0, depths: configuration.depths, steps: configuration.steps };
    let native = pass.render(&gpu, &meshes, &maps, shot, configuration.method, scene.timing.resolution).unwrap();
    // The walls' colour jump: per channel, the spread of the diffuse layer's lit colours.
    let texels = maps.read(&gpu).unwrap();
    let mut low = [f64::INFINITY; 3];
    let mut high = [f64::NEG_INFINITY; 3];
    for m in 0..texels.views.len() {
        for texel in texels.unpack(m).layers.last().unwrap().iter().flatten() {
            if let Surface::Diffuse(rgb) = texel.surface {
                for c in 0..3 {
                    (low[c], high[c]) = (low[c].min(rgb[c]), high[c].max(rgb[c]));
                }
            }
        }
    }
    let jump: [f64; 3] = std::array::from_fn(|c| high[c] - low[c]);

    let page: Vec<f64> = out["effect_frame"].as_array().unwrap_or_else(|| panic!("no frame: {out}")).iter().map(number).collect();
    let [width, height] = scene.timing.resolution;
    assert_eq!(page.len(), (4 * width * height) as usize);
    let pixels = (width * height) as usize;
    let mut seen_differs = 0;
    let (mut radiance, mut over_jump) = (Vec::with_capacity(pixels), 0.0f64);
    for (p, (rgb, seen)) in page.chunks_exact(4).zip(native.radiance.iter().zip(&native.seen)) {
        seen_differs += ((p[3] >= 1.0).then(|| p[3] as usize - 1) != *seen) as usize;
        let difference: [f64; 3] = std::array::from_fn(|c| (p[c] - rgb[c] as f64).abs());
        over_jump = over_jump.max((0..3).map(|c| difference[c] - jump[c]).fold(f64::NEG_INFINITY, f64::max));
        radiance.push(difference.into_iter().fold(0.0, f64::max));
    }
    let worst_at = radiance.iter().enumerate().fold(0, |a, (i, d)| if *d > radiance[a] { i } else { a });
    let worst = radiance[worst_at];
    radiance.sort_by(f64::total_cmp);
    let median = radiance[radiance.len() / 2];
    let over = radiance.iter().filter(|d| **d > 1e-3).count();
    let specular = native.seen.iter().filter(|s| s.is_some()).count();
    let brightest = native.radiance.iter().flatten().fold(0.0f32, |a, &b| a.max(b));
    eprintln!(
        "effects frame: {specular} specular pixels, brightest {brightest:.3}; {seen_differs} of {pixels} pixels see another object; {over} differ by over 1e-3, median {median:.3e}, largest {worst:.3e} at {:?}; the walls' colour jump {jump:.3?}",
        (worst_at as u32 % width, worst_at as u32 / width)
    );
    // Not an empty frame: the sphere and the cube cover a fifth of it, lit.
    assert!(specular * 5 >= pixels && brightest > 0.1, "{specular} specular pixels, brightest {brightest}");
    assert_eq!(seen_differs, 0, "every pixel sees the native pixel's object");
    assert!(over_jump <= PAGE_ROUNDING, "a pixel differs by {over_jump} more than the walls' colour jump {jump:?}");
    assert!(median <= PAGE_ROUNDING, "median difference {median}");
}

/// How far the page's f32 arithmetic may stray from lavapipe's where both take the same
/// path (largest channel, linear radiance): the same WGSL on the same bytes, differing by
/// how SwiftShader and lavapipe round (exp2, log2, sqrt: a few ulp each, ~10⁻⁶ of the
/// radiance, through at most six Fresnel factors): 10⁻⁴ bounds it.
const PAGE_ROUNDING: f64 = 1e-4;

#[test]
fn without_timestamps_the_effects_are_timed_by_the_wall_clock() {
    // `?timer=wall`: each pass submitted alone and closed by onSubmittedWorkDone.
    let text = EFFECTS_SCENE.replace("linear_steps: [8, 15]", "linear_steps: [8]");
    let Ok(Some(out)) = run_page("web-effects-wall", &text, &["--query".into(), "timer=wall".into()]).map_err(|e| panic!("{e}")) else {
        return;
    };
    let result = &out["result"];
    assert_eq!(result["complete"], true, "{out}");
    assert_eq!(result["adapter"]["timestamp_query"], false);
    let rows = result["effects_timing"].as_array().unwrap();
    // 2 depths × 1 search configuration × 3 methods.
    assert_eq!(rows.len(), 6);
    assert!(rows.iter().all(|r| r["timer"] == "wall" && number(&r["map_update_ms"]) > 0.0 && number(&r["shading_ms"]) > 0.0), "{rows:?}");
}

#[test]
fn distance_maps_over_the_adapter_s_storage_limit_name_the_limit() {
    // Two maps of 6 × 4096² texels × 8 layers, 16 bytes each: 12.9 GB per buffer, over
    // SwiftShader's storage binding limit; checked before anything is allocated.
    let text = EFFECTS_SCENE.replace("size: 16, layers: 3", "size: 4096, layers: 8");
    let Ok(Some(out)) = run_page("web-effects-limit", &text, &[]).map_err(|e| panic!("{e}")) else { return };
    let problem = out["problem"].as_str().unwrap_or_else(|| panic!("no problem shown: {out}"));
    let asked = 2u64 * 6 * 4096 * 4096 * 8 * 16;
    assert!(problem.contains("maxStorageBufferBindingSize") && problem.contains(&asked.to_string()), "{problem}");
    assert!(problem.contains("lower effects.distance_maps.size or layers"), "{problem}");
    assert_eq!(out["result"]["effects_timing"].as_array().unwrap().len(), 0);
}

/// The phone-sized scene: one material, a cheap and an exact method, timing only unless
/// asked.
const SMALL_SCENE: &str = "resolution: [32, 32]
camera: {axis: [1, 1, 1], distance: 2.0, frames: 3, degrees_per_frame: 20}
objects:
  - {mesh: cube, material: test/liquids/water, methods: [exact, schlick]}
measurements: [timing, image_error]
timing: {resolution: [64, 16], warmup: 1, repeats: 4}
";

#[test]
fn at_390_px_the_page_fits_and_a_hidden_tab_is_noted() {
    let args: Vec<String> = ["--viewport", "390", "--hide-at", "200"].iter().map(|s| s.to_string()).collect();
    let Ok(Some(out)) = run_page("web-phone", SMALL_SCENE, &args).map_err(|e| panic!("{e}")) else { return };
    let result = &out["result"];
    assert_eq!(result["complete"], true, "{out}");
    // Nothing wider than the screen: the document does not scroll sideways, every chart
    // and table box ends inside it (a wide table scrolls inside its box).
    let layout = &out["layout"];
    assert_eq!(layout["viewport"], 390, "{layout}");
    assert!(number(&layout["scroll_width"]) <= 390.0, "{layout}");
    for b in layout["boxes"].as_array().unwrap() {
        assert!(number(&b["right"]) <= 390.0 + 0.5, "{b} in {layout}");
    }
    // The hidden tab: noted in the result with its phase, and on the page.
    let hidden = result["hidden"].as_array().unwrap();
    assert_eq!(hidden.len(), 1, "{result}");
    assert!(out["hidden_note"].as_str().unwrap().contains("hidden during"), "{out}");
    // Phases with their times; the status line's last phase; one frame of image error by
    // default, and the file name with the scene and the time.
    let phases: Vec<&str> = result["phases"].as_array().unwrap().iter().map(|p| p["phase"].as_str().unwrap()).collect();
    assert_eq!(phases, ["opening the GPU", "compiling", "timing", "image error", "done"]);
    assert!(out["status"].as_str().unwrap().starts_with("done:") && out["status"].as_str().unwrap().contains("elapsed"), "{out}");
    assert_eq!(result["image_error_frames"], "first");
    assert!(result["image_errors"].as_array().unwrap().iter().all(|r| r["frames"] == 1), "{result}");
    assert!(result["wake_lock"].is_string(), "{result}");
    let download = out["download"].as_str().unwrap();
    let stamp = &result["date"].as_str().unwrap()[..19].replace(['-', ':'], "").replace('T', "-");
    assert_eq!(download, format!("device-google-swiftshader-web-test-{stamp}.json"));
}

#[test]
fn a_lost_device_says_so_and_marks_the_page_incomplete() {
    let args: Vec<String> = ["--query", "lose_after=2"].iter().map(|s| s.to_string()).collect();
    let Ok(Some(out)) = run_page("web-lost", SMALL_SCENE, &args).map_err(|e| panic!("{e}")) else { return };
    let result = &out["result"];
    let problem = out["problem"].as_str().unwrap_or_else(|| panic!("no problem shown: {out}"));
    assert!(problem.starts_with("The device was lost (destroyed"), "{problem}");
    assert!(!problem.contains("Unexpected error"), "{problem}");
    assert_eq!(result["complete"], false);
    assert!(out["incomplete"].as_str().unwrap().starts_with("Incomplete: The device was lost"), "{out}");
    assert!(out["title"].as_str().unwrap().starts_with("[incomplete]"), "{out}");
    assert!(out["download"].as_str().unwrap().ends_with("-incomplete.json"), "{out}");
    // The two rounds timed before are kept, with their true count.
    let rows = result["gpu_timing"].as_array().unwrap();
    assert_eq!(rows.len(), 2, "{result}");
    assert!(rows.iter().all(|r| r["repeats"] == 2 && r["samples_ms"].as_str().unwrap().split(' ').count() == 2), "{rows:?}");
}

#[test]
fn over_http_on_a_lan_name_the_page_names_the_secure_context_first() {
    let Ok(Some(out)) = run_page("web-insecure", SMALL_SCENE, &["--insecure".into()]).map_err(|e| panic!("{e}")) else { return };
    let problem = out["problem"].as_str().unwrap_or_else(|| panic!("no problem shown: {out}"));
    assert!(problem.starts_with("This page is not in a secure context"), "{problem}");
    assert!(problem.contains("open it from https:// or file://, not http on a LAN address"), "{problem}");
    assert!(problem.contains("http://nklut.test"), "{problem}");
    assert_eq!(out["result"]["secure_context"], false);
}

/// Work shrunk so one pass is far below the quantum: a 32 × 8 target (256 pixels).
const QUANTISED_SCENE: &str = "resolution: [16, 16]
camera: {axis: [1, 1, 1], distance: 2.0, frames: 1}
objects:
  - {mesh: cube, material: test/metals/goldish, methods: [exact, schlick, constant]}
  - {mesh: sphere, material: test/liquids/water, methods: [exact, schlick, lazanyi]}
measurements: [timing]
timing: {resolution: [32, 8], warmup: 1, repeats: 11}
";

/// Each row's ratio to exact on its material, by (material, method).
fn exact_ratios(result: &Value) -> Vec<(String, String, f64)> {
    let rows = result["gpu_timing"].as_array().unwrap();
    rows.iter()
        .filter(|r| r["method"] != "exact")
        .map(|r| {
            let ratio = r["relative_to_exact"].as_f64().unwrap_or(f64::NAN);
            (r["material"].as_str().unwrap().to_string(), r["method"].as_str().unwrap().to_string(), ratio)
        })
        .collect()
}

/// The largest |ratio − reference ratio| (infinite where a ratio is missing or not finite).
fn worst_difference(ratios: &[(String, String, f64)], reference: &[(String, String, f64)]) -> f64 {
    ratios
        .iter()
        .zip(reference)
        .map(|((m, k, r), (m2, k2, r2))| {
            assert_eq!((m, k), (m2, k2));
            if r.is_finite() && r2.is_finite() {
                (r - r2).abs()
            } else {
                f64::INFINITY
            }
        })
        .fold(0.0, f64::max)
}

/// The tolerance on a ratio to exact between a quantised and the unquantised run, both
/// amplified (SwiftShader under load; see BENCHMARKS.md for the measured differences).
const QUANTISED_TOLERANCE: f64 = 0.15;

#[test]
fn amplified_samples_survive_a_quantised_timer_and_single_draws_do_not() {
    let run = |name: &str, query: &str| {
        let args = vec!["--query".to_string(), query.to_string(), "--timeout".into(), "600".into()];
        run_page(name, QUANTISED_SCENE, &args).unwrap_or_else(|e| panic!("{e}"))
    };
    // The reference at the span the quantised runs reach (10 ms), so both carry the same
    // share of the pass's fixed cost.
    let Some(reference) = run("web-quantised-reference", "quantum_us=0&min_sample_ms=10") else { return };
    let reference_ratios = exact_ratios(&reference["result"]);
    let sampling = &reference["result"]["timing_sampling"];
    eprintln!("unquantised: {sampling} {reference_ratios:?}");
    let mut report = Vec::new();
    for (name, query) in
        [("web-quantised-timestamps", "quantum_us=100"), ("web-quantised-wall", "timer=wall&quantum_us=100&floor_ms=0.3125")]
    {
        let out = run(name, query).unwrap();
        let result = &out["result"];
        assert_eq!(result["complete"], true, "{out}");
        let sampling = &result["timing_sampling"];
        // The resolution found from the readings alone: the 100 µs quantum.
        assert_eq!(number(&sampling["resolution_ns"]), 100_000.0, "{sampling}");
        assert_eq!(sampling["capped"], false, "{sampling}");
        let ratios = exact_ratios(result);
        let worst = worst_difference(&ratios, &reference_ratios);
        report.push(format!("{query}: evaluations {}, worst |Δ ratio| {worst:.3}, {ratios:?}", sampling["evaluations"]));
        eprintln!("{}", report.last().unwrap());
        // Every Fresnel method resolved (the baselines may fold their repeats: not a target).
        let fresnel = |r: &&Value| !["constant", "texture"].contains(&r["method"].as_str().unwrap());
        assert!(result["gpu_timing"].as_array().unwrap().iter().filter(fresnel).all(|r| r["near_resolution"] == "no"), "{result}");
        assert!(worst <= QUANTISED_TOLERANCE, "{}", report.join("\n"));
        // The single-draw design through the same timer.
        let single = run(&format!("{name}-single"), &format!("{query}&amplify=0")).unwrap();
        let ratios = exact_ratios(&single["result"]);
        let worst = worst_difference(&ratios, &reference_ratios);
        report.push(format!("{query} single draw: worst |Δ ratio| {worst:.3}, {ratios:?}"));
        eprintln!("{}", report.last().unwrap());
        assert!(worst > QUANTISED_TOLERANCE, "{}", report.join("\n"));
        // The flag follows its rule on every row: a median within the span `near_ms` gives
        // the page's own resolution and floor is flagged, one above it is not (how many
        // single draws fall within it depends on the machine's load, so no count is held).
        let sampling = &single["result"]["timing_sampling"];
        let near = nklut::gpu::sampling::near_ms(number(&sampling["resolution_ns"]), number(&sampling["floor_ms"]));
        for row in single["result"]["gpu_timing"].as_array().unwrap() {
            let flagged = number(&row["median_ms"]) <= near;
            assert_eq!(row["near_resolution"], if flagged { "yes" } else { "no" }, "within {near} ms: {row}");
        }
    }
    eprintln!("{}", report.join("\n"));
}

/// An ambient-occlusion scene: a cube on a slab, the surfel pass through the tree (and by
/// brute force: 204 surfels), GTAO in every preset over the 40×32 frame.
const AO_SCENE: &str = "resolution: [40, 32]
camera: {axis: [0.3, 1, 0.2], distance: 3, frames: 1}
effects:
  ambient_occlusion:
    passes: 1
    hierarchy: true
    gtao:
      - {preset: bare, radius: 0.5}
      - {preset: xe-low, radius: 0.5}
      - {preset: xe-medium, radius: 0.5}
      - {preset: xe-high, radius: 0.5, frames: 16}
      - {preset: xe-ultra, radius: 0.5}
      - {preset: unreal, radius: 0.5}
objects:
  - {mesh: cube, material: test/metals/goldish, methods: [schlick], subdivide: 1}
  - {mesh: cube, scale: [2, 0.05, 2], position: [0, -0.55, 0], diffuse: [0.7, 0.7, 0.7], subdivide: 2}
measurements: [timing]
timing: {resolution: [32, 8], warmup: 1, repeats: 2}
";

/// The page of a scene that names ambient occlusion times the surfel pass (brute force and
/// tree, 1–3 passes) and one frame of every GTAO preset as `ao_timing` rows of the native
/// schema: every column, the configuration's cells as the native table writes them (preset,
/// slices × steps of XeGTAO's quality levels, frames to convergence: 1 for Algorithm 1, 64
/// or the 16 the scene names), finite positive times, the time to convergence = one frame ×
/// frames; and the result reads through the reader of `nklut report --devices` with its
/// `ao_timing` rows.
#[test]
fn the_page_times_the_surfel_passes_and_every_gtao_preset_as_ao_timing() {
    use nklut::effects::ao::gtao::Preset;
    use nklut::report::inputs::browser_result;
    let plan = web::plan(&scene(AO_SCENE), &materials()).unwrap();
    let ao = plan.ao.as_ref().expect("an AO plan");
    // Hand count: 2 cubes subdivided once and twice: 6 × 9 + 6 × 25 = 204 surfels, under the
    // brute-force limit: brute force and tree at 1, 2, 3 passes, then the six presets.
    assert_eq!(ao.surfels.count, 204);
    let kinds: Vec<(&str, u32)> = ao.rows.iter().map(|r| (r.kind, r.passes)).collect();
    let mut expected =
        vec![("brute_force", 1), ("brute_force", 2), ("brute_force", 3), ("hierarchy", 1), ("hierarchy", 2), ("hierarchy", 3)];
    expected.extend([("gtao", 1); 6]);
    assert_eq!(kinds, expected);
    let Some(out) = run_page("web-ao", AO_SCENE, &[]).unwrap() else { return };
    let result = &out["result"];
    assert_eq!(out["problem"], Value::Null, "{out}");
    assert_eq!(result["complete"], true);
    let rows = result["ao_timing"].as_array().unwrap();
    assert_eq!(rows.len(), 12);
    for row in rows {
        eprintln!(
            "{} {} passes {}: median {} ms, to convergence {} ms ({})",
            row["emitters"], row["preset"], row["passes"], row["median_ms"], row["convergence_ms"], row["driver"]
        );
        for column in &plan.columns.ao_timing {
            assert!(row.get(column).is_some(), "{column} missing in {row}");
        }
        let median = number(&row["median_ms"]);
        assert!(median.is_finite() && median > 0.0 && median < 60_000.0, "{row}");
        assert!(number(&row["spread_ms"]) >= 0.0, "{row}");
        assert_eq!(row["timer"], "timestamp", "SwiftShader grants timestamp-query");
    }
    for (row, passes) in rows[..6].iter().zip([1, 2, 3, 1, 2, 3]) {
        assert_eq!((row["passes"].as_u64(), row["frames"].as_u64()), (Some(passes), Some(0)));
        assert_eq!(row["convergence_ms"], Value::Null);
        assert_eq!(row["surfels"].as_u64(), Some(204));
    }
    for (row, (preset, frames)) in rows[6..].iter().zip(Preset::ALL.iter().zip([1u64, 64, 64, 16, 64, 64])) {
        let [slices, steps] = preset.slices_steps();
        let name = if *preset == Preset::XeHigh { "xe-high (modified)".to_string() } else { preset.name().to_string() };
        assert_eq!(row["emitters"], "gtao");
        assert_eq!(row["preset"].as_str(), Some(name.as_str()), "{row}");
        assert_eq!(
            (row["slices"].as_u64(), row["steps"].as_u64(), row["frames"].as_u64()),
            (Some(slices as u64), Some(steps as u64), Some(frames))
        );
        assert_eq!((row["width"].as_u64(), row["height"].as_u64()), (Some(40), Some(32)));
        assert!(row["covered_pixels"].as_u64().is_some_and(|c| c > 0 && c <= 40 * 32), "{row}");
        let convergence = number(&row["convergence_ms"]);
        assert!((convergence - number(&row["median_ms"]) * frames as f64).abs() <= 1e-9 * convergence, "{row}");
    }
    // The reader `nklut report --devices` uses.
    let tables = browser_result(result.to_string().as_bytes()).unwrap();
    tables.check_measurements().unwrap();
    let read = tables.ao_timing.expect("ao_timing rows read");
    assert_eq!(read.rows.len(), 12);
    assert_eq!(read.headers, plan.columns.ao_timing);
}
