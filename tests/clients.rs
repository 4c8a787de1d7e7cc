//! `nklut params`' glTF export in a real client: three.js (npm `three`, pinned) loads
//! `materials.gltf` of the 3d shelf in headless Chromium (WebGL2 through SwiftShader) and
//! renders each material's sphere in front of a black-and-white checkerboard under a neutral
//! environment; tests/clients/render_gltf.mjs measures the pixels (its header defines every
//! number) and these tests check that the spheres look like the materials: clear glass shows
//! the board, green glass is green, opaque dielectrics hide the board, gold reflects its F0.
//! Each page's three.js paste-in block (params/<name>.json) is evaluated literally in the
//! same page and rendered the same way: it must show what the glTF shows, and a tinted
//! glass the colour its volume gives 5 cm of it.
//!
//! three.js, puppeteer-core (which drives the system Chromium) and Chromium itself are
//! installed by `scripts/test-deps` (`make test` runs it); without them these tests fail,
//! unless NKLUT_SKIP_VALIDATOR_TESTS=1, which skips them with a message. The screenshots
//! and results.json stay in target/tmp/clients-artefacts/ for a look after a failure; the
//! run itself needs no network (a server on 127.0.0.1 feeds the page).

mod common;

use std::ffi::OsStr;
use std::path::PathBuf;
use std::process::Command;
use std::sync::OnceLock;

use common::{artefacts_dir, client_deps_installed, database_dir, read_json, run_client_script, scratch};
use serde_json::Value;

/// Clear dielectrics of the shelf.
const CLEAR: [&str; 3] = ["3d/glass/BK7", "3d/glass/soda-lime-clear", "3d/liquids/water"];
/// A tinted glass whose colour is green.
const GREEN: &str = "3d/glass/soda-lime-green";
/// Dielectrics that absorb within far less than the sphere: opaque.
const OPAQUE: [&str; 2] = ["3d/crystals/silicon", "3d/misc/diesel_soot"];
const GOLD: &str = "3d/metals/gold";

/// What the client run produced: results.json and the exported glTF document.
struct Rendered {
    results: Value,
    gltf: Value,
    /// engine_params.csv of the same run, one map column → cell per page.
    table: Vec<std::collections::HashMap<String, String>>,
    artefacts: PathBuf,
}

/// The client run, once per test binary: `Ok(None)` when skipped, `Err` with the reason when
/// the export or the client failed (every test then fails with it, without running it again).
fn rendered() -> &'static Result<Option<Rendered>, String> {
    static RENDERED: OnceLock<Result<Option<Rendered>, String>> = OnceLock::new();
    RENDERED.get_or_init(render)
}

fn render() -> Result<Option<Rendered>, String> {
    if !client_deps_installed("glTF client test")? {
        return Ok(None);
    }

    let out = scratch("clients");
    for stage in ["ingest", "params"] {
        let output = Command::new(env!("CARGO_BIN_EXE_nklut"))
            .arg("--db")
            .arg(database_dir())
            .arg("--out")
            .arg(&*out)
            .args([stage, "--shelf", "3d"])
            .output()
            .map_err(|e| format!("nklut {stage}: {e}"))?;
        if !output.status.success() {
            return Err(format!("nklut {stage} --shelf 3d failed: {}", String::from_utf8_lossy(&output.stderr)));
        }
    }

    let artefacts = artefacts_dir("clients-artefacts")?;
    let (gltf, params) = (out.join("materials.gltf"), out.join("params"));
    run_client_script("render_gltf.mjs", [gltf.as_os_str(), artefacts.as_os_str(), OsStr::new("--blocks"), params.as_os_str()], &out)?;
    let table = csv::Reader::from_path(out.join("engine_params.csv"))
        .and_then(|mut reader| {
            let header: Vec<String> = reader.headers()?.iter().map(String::from).collect();
            reader.records().map(|r| Ok(header.iter().cloned().zip(r?.iter().map(String::from)).collect())).collect()
        })
        .map_err(|e| format!("engine_params.csv: {e}"))?;
    Ok(Some(Rendered { results: read_json(&artefacts.join("results.json"))?, gltf: read_json(&gltf)?, table, artefacts }))
}

/// The run's results, or `None` when skipped; panics with the run's failure.
fn results() -> Option<&'static Rendered> {
    match rendered() {
        Ok(rendered) => rendered.as_ref(),
        Err(message) => panic!("{message}"),
    }
}

/// One material's measurements (panics, naming the artefacts, when the page was not rendered).
fn material<'a>(rendered: &'a Rendered, page: &str) -> &'a Value {
    let found = &rendered.results["materials"][page];
    assert!(found.is_object(), "{page} was not rendered (see {})", rendered.artefacts.display());
    found
}

/// The glTF material of a node's (single-primitive) mesh.
fn gltf_material<'a>(gltf: &'a Value, node: &Value) -> &'a Value {
    let mesh = &gltf["meshes"][node["mesh"].as_u64().expect("a node with a mesh") as usize];
    &gltf["materials"][mesh["primitives"][0]["material"].as_u64().expect("a primitive with a material") as usize]
}

fn number(value: &Value, key: &str) -> f64 {
    value[key].as_f64().unwrap_or_else(|| panic!("{key} = {} is not a number", value[key]))
}

fn triple(value: &Value, key: &str) -> [f64; 3] {
    let array = value[key].as_array().unwrap_or_else(|| panic!("{key} = {} is not an array", value[key]));
    [0, 1, 2].map(|c| array[c].as_f64().unwrap_or_else(|| panic!("{key}[{c}] = {} is not a number", array[c])))
}

/// The measurements and what three.js loaded, for failure messages, with the screenshot.
fn describe(rendered: &Rendered, page: &str, value: &Value) -> String {
    let mut shown = value.clone();
    if let Some(map) = shown.as_object_mut() {
        map.retain(|k, _| !k.starts_with("lab") && !k.starts_with("transmitted_lab"));
    }
    format!("{page}: {shown}\n(screenshot: {})", rendered.artefacts.join(format!("{}.png", page.replace('/', "__"))).display())
}

#[test]
fn every_node_renders_with_the_material_the_file_gives_it() {
    let Some(rendered) = results() else { return };
    let nodes = rendered.gltf["nodes"].as_array().unwrap();
    let materials = rendered.results["materials"].as_object().unwrap();
    assert_eq!(materials.len(), nodes.len(), "one result per node");
    assert!(nodes.len() >= 30, "the 3d shelf has {} renderable pages", nodes.len());
    assert!(rendered.results["webgl"].as_str().unwrap().to_lowercase().contains("swiftshader"), "{}", rendered.results["webgl"]);
    for node in nodes {
        let page = node["name"].as_str().unwrap();
        let result = material(rendered, page);
        let def = gltf_material(&rendered.gltf, node);
        // three.js read the factors the file gives (exactly: JSON numbers to JS numbers).
        let pbr = &def["pbrMetallicRoughness"];
        let transmission = def["extensions"]["KHR_materials_transmission"]["transmissionFactor"].as_f64().unwrap_or(0.0);
        for (key, expected) in [
            ("metalness", pbr["metallicFactor"].as_f64().unwrap_or(1.0)),
            ("roughness", pbr["roughnessFactor"].as_f64().unwrap_or(1.0)),
            ("transmission", transmission),
        ] {
            assert!((number(result, key) - expected).abs() < 1e-6, "{key} {expected} in the file; {}", describe(rendered, page, result));
        }
        // Every measurement is a number (no NaN from an empty disc or a failed read-back).
        for key in ["contrast", "hue_degrees", "chroma"] {
            assert!(number(result, key).is_finite(), "{key}: {}", describe(rendered, page, result));
        }
        for key in ["mean_linear_rgb", "centre_linear", "transmitted_linear_rgb"] {
            assert!(triple(result, key).iter().all(|v| v.is_finite() && *v >= 0.0), "{key}: {}", describe(rendered, page, result));
        }
    }
}

/// Clear glass and water show the checkerboard through the sphere. `contrast` is the share
/// of the board's black-to-white swing that reaches the eye through the central disc (the
/// render with the board inverted subtracted: reflections cancel, and refraction, which
/// inverts and magnifies the checks, changes which check a pixel sees but not how much of it
/// comes through). A clear sphere loses about 4 % at each surface at normal incidence (n ≈
/// 1.5) and a little more off-axis, and bicubic sampling blurs the check edges: three.js shows
/// 0.95 for smooth solid glass, 0.75–0.86 even for rough (0.2) thin-walled glass; an opaque
/// sphere gives 0 exactly. 0.5 keeps a wide margin on both sides.
#[test]
fn clear_glass_shows_the_checkerboard() {
    let Some(rendered) = results() else { return };
    for page in CLEAR {
        let result = material(rendered, page);
        assert!(number(result, "contrast") >= 0.5, "the board is hardly seen through {}", describe(rendered, page, result));
    }
}

/// Green glass looks green: the mean colour of the central disc (reflections, and the board
/// seen through the glass) has green as its strongest channel and is not yellow-green —
/// an HSV hue of 90–180° (yellow is 60°, green 120°, cyan 180°: HSV puts a colour whose
/// largest channel is green between 60° and 180°; iron-tinted soda-lime glass is a
/// blue-green, close to the upper end) — and a chroma (HSV saturation of the colour
/// normalised to its brightest channel, 0 for any grey) of at least 0.05; a colourless glass
/// scores 0 exactly.
#[test]
fn green_glass_looks_green() {
    let Some(rendered) = results() else { return };
    let result = material(rendered, GREEN);
    let (hue, chroma) = (number(result, "hue_degrees"), number(result, "chroma"));
    assert!(chroma >= 0.05, "no colour (chroma {chroma:.3}): {}", describe(rendered, GREEN, result));
    assert!((90.0..=180.0).contains(&hue), "hue {hue:.0}° is not green: {}", describe(rendered, GREEN, result));
}

/// Silicon (k ≈ 0.02–0.1 across the visible: light is absorbed within a few microns) and
/// diesel soot are opaque: no checkerboard through them. 0.1 allows for nothing but a faint
/// glimpse through a very thin absorber; an opaque material scores 0 exactly (the two board
/// phases render alike).
#[test]
fn opaque_dielectrics_hide_the_checkerboard() {
    let Some(rendered) = results() else { return };
    for page in OPAQUE {
        let result = material(rendered, page);
        assert!(number(result, "contrast") <= 0.1, "the board shows through {}", describe(rendered, page, result));
    }
}

/// Gold reflects gold. The centre pixel sees the environment straight behind the camera,
/// reflected: its colour is F0 times that radiance (three.js: F0·A + B with B ≈ 0 at normal
/// incidence), not F0 itself, and the environment there can be a light far above 1 — so the
/// pixel's hue is checked (gold's F0 ≈ (1.0, 0.72, 0.34) linear is an HSV hue of about 39°;
/// 30–70° is gold to yellow) and its blue/red ratio (0.34 for gold; below 0.8 rules out
/// silver-like greys), and the pixel divided by the same pixel of a white mirror (F0 = 1, same
/// roughness, same environment) must give the F0 the file writes as base colour, per
/// channel, within 0.05 (the split-sum's B and the DFG table's interpolation stay below 0.01).
#[test]
fn gold_reflects_its_f0() {
    let Some(rendered) = results() else { return };
    let result = material(rendered, GOLD);
    let hue = number(result, "centre_hue_degrees");
    assert!((30.0..=70.0).contains(&hue), "centre hue {hue:.0}° is not gold: {}", describe(rendered, GOLD, result));
    let centre = triple(result, "centre_linear");
    assert!(centre[0] > 0.0 && centre[2] / centre[0] < 0.8, "centre blue/red: {}", describe(rendered, GOLD, result));

    let node = rendered.gltf["nodes"].as_array().unwrap().iter().find(|n| n["name"] == GOLD).expect("a gold node");
    let base = gltf_material(&rendered.gltf, node)["pbrMetallicRoughness"]["baseColorFactor"].as_array().unwrap();
    let shown = triple(result, "centre_over_white_mirror");
    for c in 0..3 {
        let f0 = base[c].as_f64().unwrap();
        let seen = shown[c];
        assert!(
            (seen - f0).abs() <= 0.05,
            "channel {c}: F0 {f0:.3} in the file, {seen:.3} on screen: {}",
            describe(rendered, GOLD, result)
        );
    }
}

/// The three.js paste-in block of every page of the shelf, evaluated literally in Chromium
/// (`new Function` over the text a user pastes) on a 5 cm sphere modelled in metres at scale
/// 1, renders like the glTF path's sphere: every measurement finite (no NaN from an
/// attenuationDistance printed as 0), the same contrast, and for a transmissive page the
/// same seen-through colour (`transmitted_linear_rgb`, the share of a white background that
/// reaches the eye through the central disc), within 0.002 + 1 % per channel — the same
/// shaders on two tessellations of one sphere (16 × 32 both; the glTF's scaled unit mesh
/// against three.js' SphereGeometry), measured 0.0000 apart on SwiftShader.
#[test]
fn threejs_blocks_render_what_the_gltf_renders() {
    let Some(rendered) = results() else { return };
    let blocks = rendered.results["blocks"].as_object().expect("results.json has the blocks' renders");
    assert_eq!(blocks.len(), rendered.results["materials"].as_object().unwrap().len(), "one block per node");
    for (page, block) in blocks {
        let gltf = material(rendered, page);
        for key in ["contrast", "hue_degrees", "chroma", "metalness", "roughness", "transmission"] {
            assert!(number(block, key).is_finite(), "{key}: {}", describe(rendered, page, block));
        }
        for key in ["mean_linear_rgb", "transmitted_linear_rgb", "centre_linear"] {
            assert!(triple(block, key).iter().all(|v| v.is_finite() && *v >= 0.0), "{key}: {}", describe(rendered, page, block));
        }
        assert!(
            (number(block, "contrast") - number(gltf, "contrast")).abs() <= 0.02,
            "contrast: block {}; glTF {}",
            describe(rendered, page, block),
            describe(rendered, page, gltf)
        );
        if number(gltf, "transmission") > 0.0 {
            let (ours, theirs) = (triple(block, "transmitted_linear_rgb"), triple(gltf, "transmitted_linear_rgb"));
            for c in 0..3 {
                assert!(
                    (ours[c] - theirs[c]).abs() <= 0.002 + 0.01 * theirs[c],
                    "channel {c}: block {ours:?}, glTF {theirs:?}: {}",
                    describe(rendered, page, block)
                );
            }
        }
    }
}

/// A tinted page of the shelf seen through 5 cm: the glTF render and the pasted three.js
/// block show the colour the page's volume gives, c^(0.05/D) per channel of the table's
/// attenuation colour c at its distance D (Beer–Lambert over the sphere's diameter, the
/// closed form both files carry). The render loses a grey share at the two surfaces (about
/// (1 − F0)² ≈ 0.92 for n ≈ 1.5) and the rays off the centre travel less than 5 cm, so the
/// render over the closed form is one factor for the three channels, in [0.85, 1]: the
/// channels' factors within 3 % of each other (the colour agrees) — measured 0.937 for
/// BAF10 and 0.957 for soda-lime green, equal to the third decimal.
#[test]
fn tinted_glass_passes_its_volumes_colour_through_5_cm() {
    let Some(rendered) = results() else { return };
    let tinted: Vec<_> = rendered.table.iter().filter(|r| r["appearance"] == "tinted").collect();
    assert!(tinted.len() >= 4, "{} tinted pages on the shelf", tinted.len());
    for row in tinted {
        let page = row["page"].as_str();
        let distance: f64 = row["attenuation_distance_m"].parse().unwrap();
        let closed =
            ["r", "g", "b"].map(|c| row[&format!("attenuation_colour_{c}")].parse::<f64>().unwrap().clamp(1e-6, 1.0).powf(0.05 / distance));
        for (what, value) in [("glTF", material(rendered, page)), ("three.js block", &rendered.results["blocks"][page])] {
            let seen = triple(value, "transmitted_linear_rgb");
            let factors: Vec<f64> = (0..3).map(|c| seen[c] / closed[c]).collect();
            let (lo, hi) = factors.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), f| (lo.min(*f), hi.max(*f)));
            assert!(
                lo >= 0.85 && hi <= 1.0 && hi / lo <= 1.03,
                "{what}: seen {seen:?}, closed form {closed:?}, factors {factors:?}: {}",
                describe(rendered, page, value)
            );
        }
    }
}
