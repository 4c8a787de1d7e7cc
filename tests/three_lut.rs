//! The Fresnel LUTs in a real client: clients/three/nklut-lut.js loads each encoding's atlas
//! of a fresh bake (copper, gold, a green soda-lime glass and water: conductors, a tinted
//! and a clear dielectric; PNG and EXR) in three.js (npm `three`, pinned) in headless
//! Chromium (WebGL2 through SwiftShader), and tests/clients/render_lut.mjs reads back the
//! Fresnel term of every sphere pixel from a float target, with that pixel's cos θ. Held here:
//!
//! - per pixel and channel, |F_LUT − F_exact(cos θ)| ≤ the manifest's `max_absolute` (which
//!   includes θ = 90°, where the silhouette's pixels sit) + [`TOLERANCE`];
//! - the silhouette is reached (pixels with cos θ = 0), so the grazing figure is exercised;
//! - a wrong loader setting — TextureLoader's default flipY for the PNG, the EXR's file
//!   order where EXRLoader reverses it — breaks that bound by far for every material, so the
//!   check above cannot pass with the rows swapped;
//! - the table beside it: Schlick (the manifest's F0) and three's own F (its
//!   MeshPhysicalMaterial set up as the paste-in parameters say), per pixel on the same
//!   spheres, are printed and each is worse than the LUT for gold, copper and water.
//!
//! Like tests/clients.rs it needs `scripts/test-deps` (three, puppeteer-core, Chromium) and
//! fails without them unless NKLUT_SKIP_VALIDATOR_TESTS=1. results.json stays in
//! target/tmp/three-lut-artefacts/.

mod common;

use std::ffi::OsStr;
use std::process::Command;
use std::sync::OnceLock;

use common::{artefacts_dir, client_deps_installed, database_dir, read_json, run_client_script, scratch};
use serde_json::Value;

const PAGES: [&str; 4] = ["3d/metals/copper", "3d/metals/gold", "3d/glass/soda-lime-green", "3d/liquids/water"];
const ENCODINGS: [&str; 5] = ["unorm8", "unorm8-srgb", "unorm16", "f16", "f32"];

/// What the GPU may add to the LUT model: the filter weight's fixed-point rounding (up to
/// |t[i+1] − t[i]|/512 per docs/engine-integration.md; the steepest step of these 256-texel
/// rows is ≈ 0.03 → 6·10⁻⁵) and f32 arithmetic (≈ 10⁻⁷), with a margin.
const TOLERANCE: f64 = 1e-4;

struct Rendered {
    results: Value,
    manifest: Value,
}

fn rendered() -> &'static Result<Option<Rendered>, String> {
    static RENDERED: OnceLock<Result<Option<Rendered>, String>> = OnceLock::new();
    RENDERED.get_or_init(render)
}

fn render() -> Result<Option<Rendered>, String> {
    if !client_deps_installed("three.js LUT test")? {
        return Ok(None);
    }
    let out = scratch("three-lut");
    let mut bake = Command::new(env!("CARGO_BIN_EXE_nklut"));
    bake.arg("--db").arg(database_dir()).arg("--out").arg(&*out).args(["bake", "--size", "256", "--layout", "atlas"]);
    for page in PAGES {
        bake.args(["--page", page]);
    }
    let output = bake.output().map_err(|e| format!("nklut bake: {e}"))?;
    if !output.status.success() {
        return Err(format!("nklut bake failed: {}", String::from_utf8_lossy(&output.stderr)));
    }
    let artefacts = artefacts_dir("three-lut-artefacts")?;
    let (luts, pages) = (out.join("luts"), PAGES.join(","));
    run_client_script("render_lut.mjs", [luts.as_os_str(), artefacts.as_os_str(), OsStr::new("--pages"), OsStr::new(&pages)], &out)?;
    Ok(Some(Rendered { results: read_json(&artefacts.join("results.json"))?, manifest: read_json(&luts.join("manifest.json"))? }))
}

fn results() -> Option<&'static Rendered> {
    match rendered() {
        Ok(rendered) => rendered.as_ref(),
        Err(message) => panic!("{message}"),
    }
}

fn run<'a>(rendered: &'a Rendered, name: &str) -> &'a Value {
    rendered.results["runs"].as_array().unwrap().iter().find(|r| r["name"] == name).unwrap_or_else(|| panic!("no run {name}"))
}

/// The manifest's row of `page` in the three-channel set of `encoding`.
fn manifest_row<'a>(rendered: &'a Rendered, encoding: &str, page: &str) -> &'a Value {
    let set = rendered.manifest["textures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["source"] == "three-channel" && t["encoding"] == encoding)
        .unwrap_or_else(|| panic!("no set {encoding}"));
    set["rows"].as_array().unwrap().iter().find(|r| r["page"] == page).unwrap_or_else(|| panic!("no row {page}"))
}

fn f(value: &Value) -> f64 {
    value.as_f64().unwrap_or_else(|| panic!("{value} is not a number"))
}

/// How far a run's pixels exceed the manifest's bound: max over pages and channels of
/// (pixel max − manifest max_absolute), and the table lines.
fn excess(rendered: &Rendered, name: &str, encoding: &str) -> (f64, Vec<String>) {
    let run = run(rendered, name);
    let mut worst = f64::NEG_INFINITY;
    let mut lines = Vec::new();
    for page in PAGES {
        let result = &run["results"][page];
        let row = manifest_row(rendered, encoding, page);
        for c in 0..3 {
            let channel = &result["channels"][c];
            let (pixel, promised) = (f(&channel["lut_max"]), f(&row["error_vs_exact"]["max_absolute"][c]));
            worst = worst.max(pixel - promised);
            lines.push(format!(
                "{name:<16} {page:<26} {} {:>9.3e} {:>9.3e} {:>9.3e} | {:>9.3e} {:>9.3e} | {:>9.3e} {:>9.3e} | {:>6}",
                ["R", "G", "B"][c],
                pixel,
                promised,
                f(&channel["lut_mean"]),
                f(&channel["schlick_max"]),
                f(&channel["schlick_mean"]),
                f(&channel["three_max"]),
                f(&channel["three_mean"]),
                result["pixels"],
            ));
        }
    }
    (worst, lines)
}

#[test]
fn every_encoding_holds_the_manifests_maximum_per_pixel() {
    let Some(rendered) = results() else { return };
    assert!(rendered.results["webgl"].as_str().unwrap().to_lowercase().contains("swiftshader"), "{}", rendered.results["webgl"]);
    let mut table = vec![format!(
        "{:<16} {:<26} c {:>9} {:>9} {:>9} | {:>9} {:>9} | {:>9} {:>9} | pixels",
        "run", "page", "LUT max", "manifest", "LUT mean", "Schl max", "Schl mean", "three max", "three mean"
    )];
    let mut failures = Vec::new();
    for encoding in ENCODINGS {
        let (worst, lines) = excess(rendered, encoding, encoding);
        table.extend(lines);
        if worst > TOLERANCE {
            failures.push(format!("{encoding}: a pixel exceeds the manifest's max_absolute by {worst:.3e} (> {TOLERANCE:e})"));
        }
        for page in PAGES {
            let result = &run(rendered, encoding)["results"][page];
            // The silhouette is in the picture, and both passes saw the same cos θ.
            assert_eq!(f(&result["min_cos"]), 0.0, "{encoding} {page}: no pixel at cos θ = 0");
            assert!(f(&result["grazing_pixels"]) > 0.0);
            assert!(f(&result["max_cos_difference"]) < 1e-6, "{encoding} {page}");
            assert!(f(&result["pixels"]) > 20_000.0, "{encoding} {page}: {} sphere pixels", result["pixels"]);
        }
    }
    eprintln!("{}", table.join("\n"));
    assert!(failures.is_empty(), "{}\n{}", failures.join("\n"), table.join("\n"));
}

#[test]
fn a_wrong_row_order_breaks_the_bound_for_every_material() {
    let Some(rendered) = results() else { return };
    for (name, encoding) in [("unorm8 flipY", "unorm8"), ("f16 file-order", "f16")] {
        let run = run(rendered, name);
        for page in PAGES {
            let result = &run["results"][page];
            let row = manifest_row(rendered, encoding, page);
            let over = (0..3)
                .map(|c| f(&result["channels"][c]["lut_max"]) - f(&row["error_vs_exact"]["max_absolute"][c]))
                .fold(f64::NEG_INFINITY, f64::max);
            assert!(over > 100.0 * TOLERANCE, "{name} {page}: exceeds the bound by only {over:.3e}");
        }
    }
}

/// The LUT against the two constant-parameter forms on the same pixels: Schlick from the
/// exact F0 and three's own Fresnel are worse, by the maximum over the sphere, for the
/// metals and water (at 256 texels even unorm8's maximum, the silhouette included).
#[test]
fn schlick_and_threes_own_fresnel_are_worse_than_the_lut() {
    let Some(rendered) = results() else { return };
    for encoding in ["unorm8", "f16"] {
        for page in ["3d/metals/copper", "3d/metals/gold", "3d/liquids/water"] {
            let result = &run(rendered, encoding)["results"][page];
            let worst = |key: &str| (0..3).map(|c| f(&result["channels"][c][key])).fold(0.0, f64::max);
            let lut = worst("lut_max");
            assert!(worst("schlick_max") > 2.0 * lut, "{encoding} {page}: Schlick {} vs LUT {lut}", worst("schlick_max"));
            assert!(worst("three_max") > 2.0 * lut, "{encoding} {page}: three {} vs LUT {lut}", worst("three_max"));
        }
    }
}

/// clients/three/demo.html opens as a user would (its three.js from the pinned version) and
/// shows every requested sphere without an error.
#[test]
fn the_demo_page_runs() {
    let Some(rendered) = results() else { return };
    let demo = &rendered.results["demo"];
    assert_eq!(demo["error"], Value::Null, "{demo}");
    assert_eq!(demo["spheres"], PAGES.len(), "{demo}");
    assert_eq!(demo["problems"], serde_json::json!([]), "{demo}");
}

/// clients/godot/nklut_lut.gdshaderinc, made GLSL ES 3.00 by removing Godot's uniform hints
/// and initialisers (render_lut.html, godot()), compiles in the browser's WebGL2 and samples
/// each row, cos θ from 0 to 1, within the manifest's maximum (grazing included).
#[test]
fn the_godot_include_samples_each_row_within_the_manifests_maximum() {
    let Some(rendered) = results() else { return };
    let runs = rendered.results["godot"].as_array().unwrap();
    assert_eq!(runs.len(), 2);
    for run in runs {
        let encoding = run["encoding"].as_str().unwrap();
        for page in PAGES {
            let result = &run["results"][page];
            assert_eq!(f(&result["min_cos"]), 0.0);
            let row = manifest_row(rendered, encoding, page);
            for c in 0..3 {
                let (got, promised) = (f(&result["channels"][c]["lut_max"]), f(&row["error_vs_exact"]["max_absolute"][c]));
                assert!(got <= promised + TOLERANCE, "{encoding} {page} channel {c}: {got:e} > {promised:e}");
            }
        }
    }
}
