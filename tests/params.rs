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
    let selection = Selection::pages(PAGES);
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
    // Silicon's F0 (0.35–0.43) is far above the 0.08 of Unreal's Specular: metallic 1 with F0.
    let silicon: serde_json::Value = serde_json::from_slice(&fs::read(out.join("params/nk_3d_crystals_silicon.json")).unwrap()).unwrap();
    let unreal = silicon["engines"]["unreal"].as_str().unwrap();
    assert!(unreal.contains("Metallic: 1") && unreal.contains(&rows[2]["f0_srgb_hex"]), "{unreal}");

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
        // BK7, green glass and water also carry a MaterialX OpenPBR network on
        // outputs:mtlx:surface; the green glass's tint reaches MaterialX's GLSL.
        assert_eq!(report["mtlxShaders"], 3, "{report}");
        assert_eq!(report["mtlxSurfaceOutputs"], 3, "{report}");
        assert_eq!(report["tintInGlsl"], serde_json::json!(["/Materials/nk_3d_glass_soda_lime_green/OpenPBR"]), "{report}");
        let usda = fs::read_to_string(out.join("materials.usda")).unwrap();
        let green = usda.split("def Material \"nk_3d_glass_soda_lime_green\"").nth(1).unwrap().split("def Material").next().unwrap();
        let colour =
            format!("({}, {}, {})", rows[4]["attenuation_colour_r"], rows[4]["attenuation_colour_g"], rows[4]["attenuation_colour_b"]);
        assert!(green.contains(&format!("color3f inputs:transmission_color = {colour}")), "{colour}\n{green}");
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
    let selection = Selection::pages(["3d/metals/mercury", "3d/liquids/mercury"]);
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
    let selection = Selection::pages(published.iter().map(|r| r[1].to_string()));
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

// ---------------------------------------------------------------------------------------
// The whole database: every exported number in its tool's documented range, the tinted
// volume the same in every tool, opaque F0 kept, caveats, names.
// ---------------------------------------------------------------------------------------

/// `nklut params` over the whole database, once per test binary run.
fn whole() -> &'static Path {
    static OUT: std::sync::OnceLock<Scratch> = std::sync::OnceLock::new();
    OUT.get_or_init(|| {
        let out = scratch("params-all");
        nklut::params::command(&database(), &Selection::All, &nklut::ingest::Config::default(), &Default::default(), &out).unwrap();
        out
    })
}

/// Every page of the whole run: its table row and its paste-in file, by page id.
struct Whole {
    rows: Vec<HashMap<String, String>>,
    paste: HashMap<String, serde_json::Value>,
    gltf: serde_json::Value,
}

fn whole_run() -> &'static Whole {
    static WHOLE: std::sync::OnceLock<Whole> = std::sync::OnceLock::new();
    WHOLE.get_or_init(|| {
        let out = whole();
        let rows = read_table(out);
        let mut paste = HashMap::new();
        for entry in fs::read_dir(out.join("params")).unwrap() {
            let value: serde_json::Value = serde_json::from_slice(&fs::read(entry.unwrap().path()).unwrap()).unwrap();
            paste.insert(value["page"].as_str().unwrap().to_string(), value);
        }
        let gltf = serde_json::from_slice(&fs::read(out.join("materials.gltf")).unwrap()).unwrap();
        Whole { rows, paste, gltf }
    })
}

/// Every number written in `text` (plain decimals and exponent notation), in order.
fn numbers_in(text: &str) -> Vec<f64> {
    let mut found = Vec::new();
    let chars: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let starts = chars[i].is_ascii_digit() || (chars[i] == '-' && chars.get(i + 1).is_some_and(|c| c.is_ascii_digit()));
        let after_word = i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_' || chars[i - 1] == '#');
        if starts && !after_word {
            let mut j = i + 1;
            while j < chars.len() && (chars[j].is_ascii_digit() || chars[j] == '.') {
                j += 1;
            }
            if j + 1 < chars.len() && chars[j] == 'e' && (chars[j + 1].is_ascii_digit() || chars[j + 1] == '-') {
                j += 2;
                while j < chars.len() && chars[j].is_ascii_digit() {
                    j += 1;
                }
            }
            let word: String = chars[i..j].iter().collect();
            if let Ok(v) = word.trim_end_matches('.').parse() {
                found.push(v);
            }
            i = j;
        } else {
            i += 1;
        }
    }
    found
}

/// The value part of the line `key: value` of a block (three.js' `  key: value,` too),
/// up to a comment (`//`) or an explanation in parentheses after the value; `None`
/// without such a line.
fn field<'a>(block: &'a str, key: &str) -> Option<&'a str> {
    block.lines().find_map(|line| {
        let rest = line.trim_start().strip_prefix(key)?.strip_prefix(':')?;
        let rest = rest.split(" //").next().unwrap();
        Some(rest.trim())
    })
}

/// The numbers of `field` before its explanation: "(a, b, c)", "X (note)" or "new
/// THREE.Color().setRGB(a, b, c, …)".
fn field_numbers(block: &str, key: &str) -> Option<Vec<f64>> {
    let value = field(block, key)?;
    let value = value.strip_prefix("new THREE.Color().setRGB").unwrap_or(value);
    let value = value.strip_prefix("linear ").unwrap_or(value);
    let head =
        if value.starts_with('(') { value.split(')').next().unwrap().to_string() } else { value.split(" (").next().unwrap().to_string() };
    Some(numbers_in(&head))
}

/// The block of `tool` of a page's paste-in file.
fn block<'a>(paste: &'a serde_json::Value, tool: &str) -> &'a str {
    paste["engines"][tool].as_str().unwrap_or_else(|| panic!("{} has no {tool} block", paste["page"]))
}

fn in_range(values: &[f64], lo: f64, hi: f64) -> bool {
    !values.is_empty() && values.iter().all(|v| v.is_finite() && *v >= lo && *v <= hi)
}

/// Each tool's block against the tool's documented schema, over every page: enum values,
/// ranges and units, no NaN, no zero where a positive number is needed.
///
/// Sources of the schemas:
/// - three.js r187 `src/materials/MeshPhysicalMaterial.js` (the package `scripts/test-deps`
///   installs): `ior` "from 1.0 to 2.333"; `attenuationDistance` "in world space units,
///   and must be greater than zero"; `thickness` ≥ 0 (0 = thin-walled); colours linear.
/// - Filament Materials guide (google/filament docs/Materials.md.html): `refractionMode`
///   "Any of none, cubemap, screenspace"; `refractionType` "Any of solid, thin"; the
///   standard model's table: baseColor, metallic, roughness, reflectance, transmission in
///   [0..1], ior [1..n], absorption [0..n] (e^(−absorption·distance)), thickness [0..n].
/// - Unreal Engine: Material inputs (Metallic, Specular, Roughness, Opacity in [0, 1]);
///   `UMaterialExpressionThinTranslucentMaterialOutput` TransmittanceColor "Valid range is
///   [0,1]", surface coverage from the Opacity input.
/// - Godot 4 `BaseMaterial3D`: metallic, metallic_specular, roughness in [0, 1].
/// - Unity HDRP Lit: Smoothness and Metallic in [0, 1], Absorption Distance > 0 (m).
/// - Blender manual: Principled BSDF Metallic, Roughness, Transmission Weight in [0, 1],
///   IOR ≥ 1 (Blender 4's socket minimum 1); Volume Absorption Color in [0, 1], Density ≥ 0.
#[test]
fn every_block_over_the_whole_database_keeps_its_tools_schema() {
    let whole = whole_run();
    assert!(whole.rows.len() > 2000, "{} pages", whole.rows.len());
    let mut checked = HashMap::<&str, usize>::new();
    for row in &whole.rows {
        let page = &row["page"];
        let paste = &whole.paste[page.as_str()];
        let appearance = row["appearance"].as_str();
        let transmits = appearance == "transparent" || appearance == "tinted";
        let tinted = appearance == "tinted";
        let fail = |tool: &str, what: &str| -> String { format!("{page} ({appearance}) {tool}: {what}\n{}", block(paste, tool)) };

        // three.js: the block as MeshPhysicalMaterial takes it.
        let three = block(paste, "threejs");
        for key in ["roughness", "metalness"] {
            assert!(in_range(&field_numbers(three, key).unwrap(), 0.0, 1.0), "{}", fail("threejs", key));
        }
        if transmits {
            assert!(in_range(&field_numbers(three, "ior").unwrap_or(vec![1.5]), 1.0, 2.333), "{}", fail("threejs", "ior"));
            let thickness = field_numbers(three, "thickness").unwrap();
            assert!(thickness[0] > 0.0, "{}", fail("threejs", "thickness"));
        } else {
            assert_eq!(field_numbers(three, "metalness").unwrap(), [1.0], "{}", fail("threejs", "metalness"));
            assert!(in_range(&field_numbers(three, "color").unwrap(), 0.0, 1.0), "{}", fail("threejs", "color"));
        }
        if tinted {
            let distance = field_numbers(three, "attenuationDistance").unwrap()[0];
            let table = number(row, "attenuation_distance_m");
            assert!(
                distance > 0.0 && ((distance - table) / table).abs() <= 5e-6,
                "{} (table {table})",
                fail("threejs", "attenuationDistance")
            );
            assert!(in_range(&field_numbers(three, "attenuationColor").unwrap(), 1e-6, 1.0), "{}", fail("threejs", "attenuationColor"));
        }

        // Filament.
        let filament = block(paste, "filament");
        for key in ["metallic", "roughness"] {
            assert!(in_range(&field_numbers(filament, key).unwrap(), 0.0, 1.0), "{}", fail("filament", key));
        }
        assert!(in_range(&field_numbers(filament, "baseColor").unwrap(), 0.0, 1.0), "{}", fail("filament", "baseColor"));
        if let Some(reflectance) = field_numbers(filament, "reflectance") {
            assert!(in_range(&reflectance, 0.0, 1.0), "{}", fail("filament", "reflectance"));
        }
        if transmits {
            let material = filament
                .lines()
                .find(|l| l.starts_with("material {"))
                .unwrap_or_else(|| panic!("{}", fail("filament", "no material line")));
            let mode = material.split("refractionMode: ").nth(1).unwrap().split(';').next().unwrap().trim();
            let kind = material.split("refractionType: ").nth(1).unwrap().split(['}', ';']).next().unwrap().trim();
            assert!(["none", "cubemap", "screenspace"].contains(&mode), "{}", fail("filament", mode));
            assert!(["solid", "thin"].contains(&kind), "{}", fail("filament", kind));
            assert!(in_range(&field_numbers(filament, "transmission").unwrap(), 0.0, 1.0));
            assert!(field_numbers(filament, "thickness").unwrap()[0] > 0.0, "{}", fail("filament", "thickness"));
            if let Some(ior) = field_numbers(filament, "ior") {
                assert!(ior[0] >= 1.0 && ior[0].is_finite(), "{}", fail("filament", "ior"));
            }
        }
        if tinted {
            let absorption = field_numbers(filament, "absorption").unwrap();
            assert!(in_range(&absorption, 0.0, f64::MAX) && absorption.iter().any(|a| *a > 0.0), "{}", fail("filament", "absorption"));
        }

        // Unreal.
        let unreal = block(paste, "unreal");
        for key in ["Metallic", "Roughness"] {
            assert!(in_range(&field_numbers(unreal, key).unwrap(), 0.0, 1.0), "{}", fail("unreal", key));
        }
        assert!(in_range(&field_numbers(unreal, "Base Color").unwrap(), 0.0, 1.0), "{}", fail("unreal", "Base Color"));
        if let Some(specular) = field_numbers(unreal, "Specular") {
            assert!(in_range(&specular[..1], 0.0, 1.0), "{}", fail("unreal", "Specular"));
        }
        assert!(!unreal.contains("enter 1"), "{}", fail("unreal", "enter 1"));
        if transmits {
            assert!(unreal.contains("Blend Mode: Translucent"), "{}", fail("unreal", "blend mode"));
            assert!(in_range(&field_numbers(unreal, "Opacity").unwrap()[..1], 0.0, 1.0), "{}", fail("unreal", "Opacity"));
            let transmittance = field_numbers(unreal, "Thin Translucent Material output, Transmittance Color").unwrap();
            assert!(in_range(&transmittance[..3], 0.0, 1.0), "{}", fail("unreal", "Transmittance Color"));
        }

        // Godot.
        let godot = block(paste, "godot");
        for key in ["metallic", "roughness"] {
            assert!(in_range(&field_numbers(godot, key).unwrap(), 0.0, 1.0), "{}", fail("godot", key));
        }
        if let Some(specular) = field_numbers(godot, "metallic_specular") {
            assert!(in_range(&specular[..1], 0.0, 1.0), "{}", fail("godot", "metallic_specular"));
        }

        // Unity HDRP.
        let unity = block(paste, "unity_hdrp");
        assert!(in_range(&field_numbers(unity, "Smoothness").unwrap(), 0.0, 1.0), "{}", fail("unity_hdrp", "Smoothness"));
        if tinted {
            let distance = field_numbers(unity, "Absorption Distance").unwrap()[0];
            assert!(
                distance > 0.0 && ((distance / number(row, "attenuation_distance_m")) - 1.0).abs() <= 5e-6,
                "{}",
                fail("unity_hdrp", "Absorption Distance")
            );
        }

        // Blender.
        let blender = block(paste, "blender");
        for key in ["Metallic", "Roughness"] {
            assert!(in_range(&field_numbers(blender, key).unwrap(), 0.0, 1.0), "{}", fail("blender", key));
        }
        if let Some(ior) = field_numbers(blender, "IOR") {
            assert!(ior[0] >= 1.0 && ior[0].is_finite(), "{}", fail("blender", "IOR"));
        }
        if tinted {
            let volume = field(blender, "Volume").unwrap();
            let linear = volume.split("(linear ").nth(1).unwrap();
            assert!(in_range(&numbers_in(linear.split(')').next().unwrap()), 0.0, 1.0), "{}", fail("blender", "Volume colour"));
            let density = numbers_in(volume.split("Density ").nth(1).unwrap())[0];
            assert!(density > 0.0 && density.is_finite(), "{}", fail("blender", "Density"));
        }
        *checked.entry(appearance).or_default() += 1;
    }
    for appearance in ["metal", "transparent", "tinted", "opaque"] {
        assert!(checked.get(appearance).copied().unwrap_or(0) > 10, "{checked:?}");
    }
}

/// glTF, MaterialX and the table over the whole database: every number finite, glTF's
/// volume and colours in the extensions' ranges (KHR_materials_volume: attenuationDistance
/// positive, attenuationColor in [0, 1]; KHR_materials_ior ior ≥ 1; baseColorFactor in [0, 1]),
/// MaterialX colours in [0, 1] where the node takes a colour (`generalized_schlick_bsdf`
/// color0 clamped as docs/engine-parameters.md says the exports clamp).
#[test]
fn exported_numbers_over_the_whole_database_are_finite_and_in_range() {
    let whole = whole_run();
    for material in whole.gltf["materials"].as_array().unwrap() {
        let name = &material["name"];
        let base: Vec<f64> =
            material["pbrMetallicRoughness"]["baseColorFactor"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        assert!(in_range(&base, 0.0, 1.0), "{name}: {base:?}");
        if let Some(volume) = material["extensions"]["KHR_materials_volume"].as_object() {
            if let Some(distance) = volume.get("attenuationDistance") {
                assert!(distance.as_f64().unwrap() > 0.0, "{name}: {distance}");
                let colour: Vec<f64> = volume["attenuationColor"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
                assert!(in_range(&colour, 1e-6, 1.0), "{name}: {colour:?}");
            }
        }
        if let Some(ior) = material["extensions"]["KHR_materials_ior"]["ior"].as_f64() {
            assert!(ior >= 1.0, "{name}: {ior}");
        }
    }
    let mtlx = fs::read_to_string(self::whole().join("materials.mtlx")).unwrap();
    let mut node = String::new();
    let mut clamped = 0;
    for line in mtlx.lines() {
        let line = line.trim();
        if line.starts_with('<') && !line.starts_with("<input") && !line.starts_with("</") {
            node = line[1..].split(' ').next().unwrap().to_string();
        }
        let Some(value) = line.split("value=\"").nth(1).map(|v| v.split('"').next().unwrap()) else { continue };
        let input = line.split("name=\"").nth(1).unwrap().split('"').next().unwrap();
        let values = numbers_in(value);
        assert!(values.iter().all(|v| v.is_finite()), "{node} {input} = {value}");
        let colour = line.contains("type=\"color3\"");
        let unit = match node.as_str() {
            "open_pbr_surface" => colour,
            "standard_surface" => colour && input != "base_color" && input != "specular_color",
            "generalized_schlick_bsdf" => input == "color0",
            _ => false,
        };
        if unit {
            assert!(in_range(&values, 0.0, 1.0), "{node} {input} = {value}");
            clamped += usize::from(node == "generalized_schlick_bsdf");
        }
        if input == "transmission_depth" {
            assert!(values[0] > 0.0, "{node} {input} = {value}");
        }
    }
    assert_eq!(clamped, whole.rows.len(), "one generalized_schlick_bsdf color0 per page");
}

/// Blender's Volume Absorption absorbs (1 − Color)·Density per metre (Cycles'
/// `svm_node_closure_volume`); the block's Color and Density, as printed, must make a
/// 5 cm slab pass what the glTF's pair gives, attenuationColor^(0.05/attenuationDistance)
/// (KHR_materials_volume's Beer–Lambert law), for every tinted page. Tolerance: the
/// printed numbers' 6 significant digits (relative 5·10⁻⁶ on Density and on each Color
/// channel, so on ln T at most 1.1·10⁻⁵ of the exponent).
#[test]
fn blender_volume_absorption_passes_the_gltf_transmittance_through_5_cm() {
    let whole = whole_run();
    let nodes = whole.gltf["nodes"].as_array().unwrap();
    let mut compared = 0;
    for (i, node) in nodes.iter().enumerate() {
        let page = node["name"].as_str().unwrap();
        let Some(volume) = whole.gltf["materials"][i]["extensions"]["KHR_materials_volume"].as_object() else { continue };
        let Some(distance) = volume.get("attenuationDistance").and_then(|d| d.as_f64()) else { continue };
        let colour: Vec<f64> = volume["attenuationColor"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let blender = field(block(&whole.paste[page], "blender"), "Volume").unwrap();
        let linear = numbers_in(blender.split("(linear ").nth(1).unwrap().split(')').next().unwrap());
        let density = numbers_in(blender.split("Density ").nth(1).unwrap())[0];
        for c in 0..3 {
            let expected_exponent = colour[c].ln() * 0.05 / distance;
            let exponent = -(1.0 - linear[c]) * density * 0.05;
            let bound = 1.1e-5 * density * 0.05 + 1e-12;
            assert!(
                (exponent - expected_exponent).abs() <= bound,
                "{page} channel {c}: Blender passes e^{exponent:.6} through 5 cm, glTF e^{expected_exponent:.6} (bound {bound:.2e}): {blender}"
            );
        }
        compared += 1;
    }
    assert!(compared > 50, "{compared} tinted pages");
    // Soda-lime green by hand: the issue's figures, glTF (0.035, 0.277, 0.259) at 5 cm.
    let green = &whole.paste["3d/glass/soda-lime-green"];
    let d = green["attenuation"]["distance_m"].as_f64().unwrap();
    let c: Vec<f64> = green["attenuation"]["colour"]["linear"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let through: Vec<f64> = c.iter().map(|c| c.powf(0.05 / d)).collect();
    for (got, expected) in through.iter().zip([0.035, 0.277, 0.259]) {
        assert!((got - expected).abs() < 1.5e-3, "{through:?}");
    }
}

/// An opaque dielectric keeps its F0 in every block: metallic 1 with F0 as the colour
/// (three.js, Unreal, Godot, Filament, Blender, OpenPBR) or a specular colour (Unity HDRP),
/// equal to the table's `f0_linear` to the 4 printed decimals (hex: `f0_srgb_hex`); the
/// table's F0 of silicon is the spectral 0.36–0.43, far above the 0.08 a dielectric's
/// Specular field reaches.
#[test]
fn opaque_dielectrics_keep_their_f0_in_every_block() {
    let whole = whole_run();
    let mut opaque = 0;
    for row in whole.rows.iter().filter(|r| r["appearance"] == "opaque") {
        let paste = &whole.paste[row["page"].as_str()];
        let f0: Vec<f64> = ["r", "g", "b"].iter().map(|c| number(row, &format!("f0_linear_{c}")).clamp(0.0, 1.0)).collect();
        let close = |got: Vec<f64>, tool: &str| {
            assert_eq!(got.len(), 3, "{}: {tool}", row["page"]);
            for c in 0..3 {
                assert!((got[c] - f0[c]).abs() <= 5.1e-5, "{} {tool}: {got:?} vs F0 {f0:?}\n{}", row["page"], block(paste, tool));
            }
        };
        close(field_numbers(block(paste, "threejs"), "color").unwrap(), "threejs");
        assert_eq!(field_numbers(block(paste, "threejs"), "metalness").unwrap(), [1.0]);
        close(field_numbers(block(paste, "unreal"), "Base Color").unwrap()[..3].to_vec(), "unreal");
        assert_eq!(field_numbers(block(paste, "unreal"), "Metallic").unwrap(), [1.0]);
        close(field_numbers(block(paste, "filament"), "baseColor").unwrap(), "filament");
        let blender = field(block(paste, "blender"), "Base Color").unwrap();
        close(numbers_in(blender.split("(linear ").nth(1).unwrap()), "blender");
        close(numbers_in(field(block(paste, "unity_hdrp"), "Specular Color").unwrap().split("(linear ").nth(1).unwrap()), "unity_hdrp");
        assert!(field(block(paste, "godot"), "albedo_color").unwrap().contains(&row["f0_srgb_hex"]), "{}", block(paste, "godot"));
        let openpbr = block(paste, "openpbr");
        assert_eq!(field_numbers(openpbr, "base_metalness").unwrap(), [1.0], "{openpbr}");
        let base: Vec<f64> = field(openpbr, "base_color").unwrap().split(", ").map(|v| v.parse().unwrap()).collect();
        for c in 0..3 {
            assert!((base[c] - f0[c]).abs() < 1e-12, "{openpbr}");
        }
        opaque += 1;
    }
    assert!(opaque > 30, "{opaque} opaque pages");
    let silicon = whole.rows.iter().find(|r| r["page"] == "3d/crystals/silicon").unwrap();
    assert!(number(silicon, "f0_linear_b") > 0.4 && number(silicon, "f0_linear_r") > 0.33, "silicon's F0: {}", silicon["f0_srgb_hex"]);
}

/// The caveats name the pages whose class rests on a misleading pattern, each with the
/// numbers that triggered it.
#[test]
fn caveats_flag_misleading_pages_with_their_numbers() {
    let whole = whole_run();
    let row = |page: &str| whole.rows.iter().find(|r| r["page"] == page).unwrap_or_else(|| panic!("{page} not kept"));
    let has = |page: &str, code: &str| {
        let cell = &row(page)["caveats"];
        assert!(cell.contains(&format!("{code}: ")), "{page}: {cell:?}");
        cell.clone()
    };
    // PbI2: k ≥ 1 in the violet makes it a conductor by the k rule, but k = 0 in the red:
    // classed by its depths (a yellow crystal), no longer a bluish metal.
    let pbi2 = has("main/PbI2/Frisenda", "conductor_passes_light");
    assert!(pbi2.contains("red depth infinite"), "{pbi2}");
    assert_ne!(row("main/PbI2/Frisenda")["appearance"], "metal");
    assert_eq!(row("main/PbI2/Frisenda")["kind"], "conductor");
    // PVP on the 3d shelf: opaque by a thin-film model's k, k < 0.01 everywhere.
    let pvp = has("3d/plastics/pvp", "opaque_low_k");
    let largest: f64 = pvp.split("(largest ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert!(largest < 0.01 && largest > 0.0, "{pvp}");
    // MgO and ZrO2 by Synowicki list As2S3's data file; As2S3's own page is not flagged.
    for page in ["main/MgO/Synowicki", "main/ZrO2/Synowicki"] {
        let text = has(page, "shared_data_file");
        assert!(text.contains("main/As2S3/nk/Synowicki.yml") && text.contains("As2S3"), "{text}");
    }
    assert!(!row("main/As2S3/Synowicki")["caveats"].contains("shared_data_file"));
    // Water: transparent, but its red depth is about 2 m: a 1 m pool passes e^(−1/2.03)
    // ≈ 0.61 of red (water's k at 685 nm is 2.68·10⁻⁸ by Hale & Querry).
    let water = has("3d/liquids/water", "transparent_absorbs");
    assert_eq!(row("3d/liquids/water")["appearance"], "transparent");
    let red: f64 = water.split("passes red ").nth(1).unwrap().split(',').next().unwrap().parse().unwrap();
    let depth = number(row("3d/liquids/water"), "absorption_depth_m_r");
    assert!((red - (-1.0 / depth).exp()).abs() < 1e-3 && (0.55..0.66).contains(&red), "{water}");
    // The paste-in file carries the same caveats.
    assert_eq!(whole.paste["3d/liquids/water"]["caveats"][0]["code"], "transparent_absorbs");
    // Most pages carry none.
    let flagged = whole.rows.iter().filter(|r| !r["caveats"].is_empty()).count();
    assert!(flagged * 3 < whole.rows.len(), "{flagged} of {} pages flagged", whole.rows.len());
    // No caveat sentence holds the cell's separator.
    for row in &whole.rows {
        let n = whole.paste[row["page"].as_str()]["caveats"].as_array().unwrap().len();
        assert_eq!(row["caveats"].split("; ").filter(|c| !c.is_empty()).count(), n, "{}", row["caveats"]);
    }
}

/// Display names over the whole database: at most 48 characters, no HTML tag, distinct.
#[test]
fn display_names_are_short_plain_and_unique() {
    let whole = whole_run();
    let mut seen = std::collections::HashSet::new();
    for row in &whole.rows {
        let name = &row["display_name"];
        assert!(name.chars().count() <= 48, "{name:?} has {} characters", name.chars().count());
        assert!(!name.contains('<') && !name.contains('>') && !name.contains("&amp;"), "{name:?}");
        assert!(seen.insert(name.clone()), "{name:?} twice");
    }
    let alumina = whole.rows.iter().find(|r| r["page"].starts_with("main/Al2O3/")).unwrap();
    assert!(alumina["display_name"].starts_with("Al₂O₃"), "{}", alumina["display_name"]);
    // The glTF carries the same names.
    let names: Vec<&str> = whole.gltf["materials"].as_array().unwrap().iter().map(|m| m["name"].as_str().unwrap()).collect();
    assert_eq!(names, whole.rows.iter().map(|r| r["display_name"].as_str()).collect::<Vec<_>>());
}
