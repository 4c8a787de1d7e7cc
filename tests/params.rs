//! `nklut params` on the linked database (`make db`): the table documents every column,
//! a crown glass's n_d and Abbe number match the glass maker's catalogue, the exports carry
//! the table's values, and the ecosystems' own validators accept them — MaterialX's Python
//! package for `materials.mtlx`, the Khronos glTF-Validator for `materials.gltf` (both
//! installed into .test-deps/ by `scripts/test-deps`, which `make test` runs; without them
//! these tests fail, unless NKLUT_SKIP_VALIDATOR_TESTS=1, which skips the validator runs
//! with a message).

mod common;

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::{database, scratch, Scratch};
use nklut::ingest::Selection;

/// In catalog order (the tables' order).
const PAGES: [&str; 7] = [
    "3d/metals/gold",
    "3d/metals/iron",
    "3d/crystals/silicon",
    "3d/glass/BK7",
    "3d/glass/soda-lime-green",
    "3d/liquids/water",
    "3d/misc/diesel_soot",
];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `nklut params` for `PAGES` into a fresh folder (once per test binary run and name).
fn run(name: &str) -> Scratch {
    let out = scratch(&format!("params-{name}"));
    let selection = Selection { pages: PAGES.iter().map(|p| p.to_string()).collect(), ..Default::default() };
    nklut::params::command(&database(), &selection, &nklut::ingest::Config::default(), &Default::default(), &out).unwrap();
    out
}

/// The CSV as one map column → cell per row.
fn read_table(out: &Path) -> Vec<HashMap<String, String>> {
    let mut reader = csv::Reader::from_path(out.join("engine_params.csv")).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    reader.records().map(|r| header.iter().cloned().zip(r.unwrap().iter().map(String::from)).collect()).collect()
}

fn number(row: &HashMap<String, String>, column: &str) -> f64 {
    row[column].parse().unwrap_or_else(|e| panic!("{column} = {:?}: {e}", row[column]))
}

/// Whether the validator installed at `needed` is there; a missing one fails the test
/// unless NKLUT_SKIP_VALIDATOR_TESTS=1 (then `false`, with a message).
fn installed(needed: &Path) -> bool {
    if needed.exists() {
        return true;
    }
    let message = format!("{} is missing: run `bash scripts/test-deps` (make test does)", needed.display());
    if std::env::var("NKLUT_SKIP_VALIDATOR_TESTS").as_deref() == Ok("1") {
        eprintln!("validator skipped (NKLUT_SKIP_VALIDATOR_TESTS=1): {message}");
        return false;
    }
    panic!("{message}");
}

/// Runs `program tests/validators/<script> <file>` and parses the JSON line it prints last.
fn validate(mut command: Command, script: &str, file: &Path) -> serde_json::Value {
    let output = command.arg(root().join("tests/validators").join(script)).arg(file).output().unwrap_or_else(|e| panic!("{script}: {e}"));
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line =
        stdout.lines().last().unwrap_or_else(|| panic!("{script} printed nothing; stderr: {}", String::from_utf8_lossy(&output.stderr)));
    serde_json::from_str(line).unwrap_or_else(|e| panic!("{script}: {e}: {line}"))
}

#[test]
fn the_table_documents_every_column_and_has_one_row_per_page() {
    let out = run("table");
    let rows = read_table(&out);
    assert_eq!(rows.iter().map(|r| r["page"].as_str()).collect::<Vec<_>>(), PAGES);
    let columns: serde_json::Value = serde_json::from_slice(&fs::read(out.join("engine_params.columns.json")).unwrap()).unwrap();
    let documented: Vec<&str> = columns["columns"].as_array().unwrap().iter().map(|c| c["name"].as_str().unwrap()).collect();
    let mut header: Vec<&str> = rows[0].keys().map(String::as_str).collect();
    header.sort_unstable();
    let mut sorted = documented.clone();
    sorted.sort_unstable();
    assert_eq!(header, sorted);
    for c in columns["columns"].as_array().unwrap() {
        assert!(c["description"].as_str().unwrap().len() > 20, "{c}");
    }
    // Every model has its error columns; glTF's ior model only for the dielectrics.
    for row in &rows {
        for model in ["schlick", "f82_tint", "gulbrandsen", "generalized_schlick", "fitted_nk"] {
            assert!(number(row, &format!("{model}_de2000_mean")).is_finite());
        }
        let dielectric = row["kind"] == "dielectric";
        assert_eq!(!row["gltf_ior_de2000_mean"].is_empty(), dielectric, "{}", row["page"]);
        assert_eq!(!row["n_d"].is_empty(), dielectric, "{}", row["page"]);
        let best = &row["best_model"];
        assert!((number(row, "best_de2000_mean") - number(row, &format!("{best}_de2000_mean"))).abs() < 1e-12);
    }
    // The JSON twin holds the same page order.
    let json: serde_json::Value = serde_json::from_slice(&fs::read(out.join("engine_params.json")).unwrap()).unwrap();
    assert_eq!(json[3]["page"], "3d/glass/BK7");
}

#[test]
fn crown_glass_matches_the_schott_catalogue() {
    // Schott N-BK7 datasheet: n_d = 1.51680, ν_d = 64.17 (the page is Schott's Sellmeier formula).
    let rows = read_table(&run("bk7"));
    let bk7 = rows.iter().find(|r| r["page"] == "3d/glass/BK7").unwrap();
    assert!((number(bk7, "n_d") - 1.51680).abs() < 5e-5, "{}", bk7["n_d"]);
    assert!((number(bk7, "abbe_d") - 64.17).abs() < 0.05, "{}", bk7["abbe_d"]);
    let f0 = ((1.51680f64 - 1.0) / (1.51680 + 1.0)).powi(2);
    assert!((number(bk7, "gltf_ior_f0") - f0).abs() < 1e-6);
    // Water at 20 °C: n_d ≈ 1.333 (CRC Handbook 1.3330).
    let water = rows.iter().find(|r| r["page"] == "3d/liquids/water").unwrap();
    assert!((number(water, "n_d") - 1.333).abs() < 1e-3, "{}", water["n_d"]);
}

#[test]
fn exports_carry_the_table_values_and_pass_their_validators() {
    let out = run("exports");
    let rows = read_table(&out);
    let mtlx = fs::read_to_string(out.join("materials.mtlx")).unwrap();
    let gltf: serde_json::Value = serde_json::from_slice(&fs::read(out.join("materials.gltf")).unwrap()).unwrap();
    // Gold: conductor_bsdf gets the fitted (n, k) as written in the table — but in the red
    // channel, whose fit ended on its search box, the channel's own n; glTF the clamped F0.
    let gold = &rows[0];
    assert_eq!(
        (gold["fitted_at_bound_r"].as_str(), gold["fitted_at_bound_g"].as_str()),
        ("true", "false"),
        "gold's red fit is (0.001, 100)"
    );
    let ior = format!("{}, {}, {}", gold["channel_n_r"], gold["fitted_n_g"], gold["fitted_n_b"]);
    assert!(mtlx.contains(&format!("<input name=\"ior\" type=\"color3\" value=\"{ior}\" />")), "{ior}");
    let base = gltf["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"].as_array().unwrap();
    for (c, suffix) in ["r", "g", "b"].iter().enumerate() {
        assert_eq!(base[c].as_f64().unwrap(), number(gold, &format!("f0_linear_{suffix}")).clamp(0.0, 1.0));
    }
    assert_eq!(gltf["materials"][2]["extensions"]["KHR_materials_ior"]["ior"].as_f64().unwrap(), number(&rows[2], "n_d"));
    assert_eq!(gltf["nodes"].as_array().unwrap().len(), PAGES.len());
    // The exports follow the appearance: clear glass is smooth and refracts through its
    // volume with its dispersion (KHR: 20/Abbe); green glass carries its volume's colour;
    // silicon and soot transmit nothing and show their F0; one roughness per class.
    let appearance: Vec<&str> = rows.iter().map(|r| r["appearance"].as_str()).collect();
    assert_eq!(appearance, ["metal", "metal", "opaque", "transparent", "tinted", "transparent", "opaque"]);
    let material = |i: usize| &gltf["materials"][i];
    let bk7 = material(3);
    assert_eq!(bk7["pbrMetallicRoughness"]["roughnessFactor"], 0.0);
    assert_eq!(bk7["extensions"]["KHR_materials_transmission"]["transmissionFactor"], 1.0);
    assert_eq!(bk7["extensions"]["KHR_materials_volume"]["thicknessFactor"], 2.0);
    assert!(
        (bk7["extensions"]["KHR_materials_dispersion"]["dispersion"].as_f64().unwrap() - 20.0 / number(&rows[3], "abbe_d")).abs() < 1e-12
    );
    assert_eq!(material(0)["pbrMetallicRoughness"]["roughnessFactor"], 0.2);
    let green = &material(4)["extensions"]["KHR_materials_volume"];
    assert_eq!(green["attenuationDistance"].as_f64().unwrap(), number(&rows[4], "attenuation_distance_m"));
    let colour: Vec<f64> = green["attenuationColor"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert!(colour[1] > colour[0], "green glass passes more green than red: {colour:?}");
    for opaque in [2, 6] {
        let m = material(opaque);
        assert!(m["extensions"]["KHR_materials_transmission"].is_null(), "{m}");
        assert_eq!(m["pbrMetallicRoughness"]["baseColorFactor"], serde_json::json!([0.0, 0.0, 0.0, 1.0]));
        assert!(rows[opaque]["abbe_d"].is_empty(), "an opaque dielectric has no Abbe number");
        let ior = m["extensions"]["KHR_materials_ior"]["ior"].as_f64().unwrap();
        let from_ior = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let specular = m["extensions"]["KHR_materials_specular"]["specularColorFactor"][1].as_f64().unwrap();
        assert!((specular * from_ior - number(&rows[opaque], "f0_linear_g")).abs() < 1e-12, "F0 = specular colour × the ior's F0");
    }
    // Display names are short; the long lists stay in `synonyms`.
    assert_eq!(rows[4]["display_name"], "Soda-lime glass - Green");
    assert!(rows.iter().all(|r| r["display_name"].chars().count() <= 48));
    assert_eq!(material(0)["name"], "Gold (Au)");
    // Every page has its paste-in file with the table's colours.
    let paste: serde_json::Value = serde_json::from_slice(&fs::read(out.join("params/nk_3d_metals_gold.json")).unwrap()).unwrap();
    assert_eq!(paste["f0"]["hex"], gold["f0_srgb_hex"].as_str());
    assert_eq!(paste["f82_tint"]["hex"], gold["f82_tint_hex"].as_str());
    assert!((paste["f0"]["linear"][0].as_f64().unwrap() - number(gold, "f0_linear_r")).abs() < 1e-15, "JSON and CSV round the same double");
    let blender = paste["engines"]["blender"].as_str().unwrap();
    assert!(blender.contains(&format!("Base Color: {}", gold["f0_srgb_hex"])) && blender.contains("Metallic: 1"), "{blender}");
    let unreal: serde_json::Value = serde_json::from_slice(&fs::read(out.join("params/nk_3d_crystals_silicon.json")).unwrap()).unwrap();
    assert!(unreal["engines"]["unreal"].as_str().unwrap().contains("above the field's 1"), "silicon's F0 > 0.08");

    let deps = std::env::var_os("NKLUT_TEST_DEPS").map(PathBuf::from).unwrap_or_else(|| root().join(".test-deps"));
    let python = deps.join("venv/bin/python");
    if installed(&python) {
        let report = validate(Command::new(&python), "validate_mtlx.py", &out.join("materials.mtlx"));
        assert_eq!(report["valid"], true, "{report}");
        assert_eq!(report["materials"], 5 * PAGES.len(), "{report}");
        // GLSL generated for every material, one shader per model and page.
        assert_eq!(report["glsl_failures"], serde_json::json!([]), "{report}");
        for (model, count) in [("open_pbr_surface", 1), ("standard_surface", 1), ("conductor_bsdf", 2), ("generalized_schlick_bsdf", 1)] {
            assert_eq!(report["glsl"][model], count * PAGES.len(), "{model}: {report}");
        }
        // USD: the preview surfaces pass USD's own validators.
        let report = validate(Command::new(&python), "validate_usd.py", &out.join("materials.usda"));
        assert_eq!(report["valid"], true, "{report}");
        assert_eq!(report["previewSurfaces"], PAGES.len(), "{report}");
    }
    let modules = deps.join("npm/node_modules");
    if installed(&modules.join("gltf-validator/package.json")) {
        let mut node = Command::new("node");
        node.env("NODE_PATH", &modules);
        let report = validate(node, "validate_gltf.js", &out.join("materials.gltf"));
        assert_eq!(report["errors"], 0, "{report}");
        assert_eq!(report["warnings"], 0, "{report}");
    }
}

/// The Physically Based database (physicallybased.info, API v2) derives its metals' F0 and
/// F82 tint from named refractiveindex.info pages (data/published/README.md); on those
/// pages nklut's values must agree to the 3 decimals it prints.
#[test]
fn pages_that_share_a_name_are_told_apart() {
    // The 3d shelf lists mercury under metals and under liquids with one page name.
    let out = scratch("params-mercury");
    let selection = Selection { pages: vec!["3d/metals/mercury".into(), "3d/liquids/mercury".into()], ..Default::default() };
    nklut::params::command(&database(), &selection, &nklut::ingest::Config::default(), &Default::default(), &out).unwrap();
    let rows = read_table(&out);
    let names: Vec<&str> = rows.iter().map(|r| r["display_name"].as_str()).collect();
    assert_eq!(names.len(), 2);
    assert_ne!(names[0], names[1]);
    assert!(names.iter().all(|n| n.starts_with("Mercury (Hg), ")), "{names:?}");
    let gltf: serde_json::Value = serde_json::from_slice(&fs::read(out.join("materials.gltf")).unwrap()).unwrap();
    assert_eq!(gltf["materials"][0]["name"], names[0]);
    assert_eq!(gltf["materials"][1]["name"], names[1]);
}

#[test]
fn metals_agree_with_the_physically_based_database() {
    let mut reader = csv::Reader::from_path(root().join("data/published/physicallybased-metals.csv")).unwrap();
    let published: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    let selection = Selection { pages: published.iter().map(|r| r[1].to_string()).collect(), ..Default::default() };
    let ingested = nklut::ingest::ingest(&database(), &selection, &nklut::ingest::Config::default()).unwrap();
    let params = nklut::params::compute(&ingested.kept, &Default::default(), &mut Default::default(), &Default::default()).unwrap();
    let mut compared = 0;
    for record in &published {
        let Some(position) = ingested.kept.iter().position(|p| p.id() == record[1]) else {
            // Cs, K and Rb (Monin) do not cover 390–700 nm: excluded by the visible-range filter.
            assert!(ingested.excluded.iter().any(|e| e.page == record[1]), "{} neither kept nor excluded", &record[1]);
            continue;
        };
        let ours = &params[position];
        for c in 0..3 {
            let (f0, tint): (f64, f64) = (record[2 + c].parse().unwrap(), record[5 + c].parse().unwrap());
            assert!((ours.f0[c] - f0).abs() <= 1.5e-3, "{} F0[{c}]: {} vs {f0}", &record[0], ours.f0[c]);
            assert!((ours.f82[c].tint - tint).abs() <= 1.5e-3, "{} F82[{c}]: {} vs {tint}", &record[0], ours.f82[c].tint);
        }
        compared += 1;
    }
    assert_eq!(compared, published.len() - 3);
}
