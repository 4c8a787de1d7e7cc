//! `nklut effects` end to end on a small scene and the real database (`make db`): the
//! effects_errors table with its geometry / Fresnel / total split; the shipped effects
//! scenes parse.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::{database_dir, scratch, Scratch};

use nklut::scene::{Role, Scene};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `nklut effects [flags] SCENE` on `scene` (YAML) written into a fresh folder; the folder
/// (outputs under `out/`) and what the command printed.
fn run_effects(name: &str, scene: &str, flags: &[&str]) -> (Scratch, Output) {
    let dir = scratch(name);
    let file = dir.join("scene.yaml");
    std::fs::write(&file, scene).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_nklut"))
        .arg("--db")
        .arg(database_dir())
        .arg("--out")
        .arg(dir.join("out"))
        .arg("effects")
        .args(flags)
        .arg(&file)
        .output()
        .unwrap();
    (dir, output)
}

/// A CSV table: its header and rows.
fn read_csv(path: &Path) -> (csv::StringRecord, Vec<csv::StringRecord>) {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let headers = reader.headers().unwrap().clone();
    (headers, reader.records().map(|r| r.unwrap()).collect())
}

#[test]
fn shipped_effects_scenes_parse_and_name_their_effects() {
    for (file, reflection, refraction) in
        [("teapot-in-a-box.yaml", vec![1, 2, 3], None), ("glass-sphere.yaml", vec![1, 3], Some(vec![1, 3]))]
    {
        let scene = Scene::load(&root().join("scenes").join(file)).unwrap();
        let effects = scene.effects.as_ref().unwrap();
        assert_eq!(effects.reflection.as_ref().unwrap().max_depth, reflection, "{file}");
        assert_eq!(effects.refraction.as_ref().map(|r| r.max_depth.clone()), refraction, "{file}");
        assert_eq!(effects.distance_maps.steps.len(), 4, "{file}: 15/1, 15/10, 80/1, 80/10");
        assert_eq!(scene.materials().len(), 3, "{file}");
        assert!(scene.objects.iter().any(|o| matches!(o.role, Role::Diffuse(_))), "{file}");
    }
    // The spectral scenes: depths, the spectral reference's wavelengths, the scene unit.
    for (file, unit) in [("gold-in-gold.yaml", 1.0), ("prism.yaml", 1.0), ("coloured-glass.yaml", 0.05)] {
        let scene = Scene::load(&root().join("scenes").join(file)).unwrap();
        let effects = scene.effects.as_ref().unwrap();
        assert_eq!(effects.spectral.map(|s| s.wavelengths), Some(96), "{file}");
        assert_eq!(effects.metres_per_unit, unit, "{file}");
    }
    let gold = Scene::load(&root().join("scenes/gold-in-gold.yaml")).unwrap();
    assert_eq!(gold.effects.unwrap().reflection.unwrap().max_depth, (1..=8).collect::<Vec<u32>>());
    // The default scene has no effects: exactly what it meant before.
    assert!(Scene::load(&root().join("scenes/default.yaml")).unwrap().effects.is_none());
}

#[test]
fn effects_command_splits_geometry_and_fresnel_error() {
    let (dir, output) = run_effects(
        "effects",
        "resolution: [12, 12]\ncamera: {axis: [0, 1, 0.2], distance: 1.6, frames: 1}\neffects:\n  reflection: {max_depth: [1, 3]}\n  refraction: {max_depth: 3}\n  distance_maps: {size: 16, layers: 2, linear_steps: [15, 80], secant_steps: 1}\nobjects:\n  - {mesh: sphere, scale: 0.6, material: 3d/liquids/water, methods: [exact, schlick, constant]}\n  - {mesh: room, scale: 3, diffuse: [0.8, 0.8, 0.8], pattern: {kind: checker, size: 0.75, albedo: [0.1, 0.3, 0.6]}}\nmeasurements: [image_error]\n",
        &[],
    );
    let out = dir.join("out");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let (headers, rows) = read_csv(&out.join("effects_errors.csv"));
    let column = |name: &str| headers.iter().position(|h| h == name).unwrap();
    // 2 Fresnel methods (the `constant` baseline has no bounce rule) × 2 depth
    // configurations × 2 search configurations.
    assert_eq!(rows.len(), 8);
    let number = |row: &csv::StringRecord, name: &str| row[column(name)].parse::<f64>().unwrap();
    for row in &rows {
        assert_eq!(&row[column("refraction_depth")], "3");
        assert!(number(row, "pixels") > 20.0);
        let geometry = number(row, "geometry_mean_delta_e2000");
        assert!(geometry > 0.0, "a 16² map is not exact");
        match &row[column("method")] {
            "exact" => {
                assert_eq!(number(row, "fresnel_mean_delta_e2000"), 0.0);
                assert_eq!(number(row, "total_mean_delta_e2000"), geometry);
            }
            "schlick" => assert!(number(row, "fresnel_mean_rel_error") > 1e-3),
            other => panic!("unexpected method {other}"),
        }
    }
    assert!(out.join("effects_errors.parquet").exists() && out.join("effects_errors.columns.json").exists());
    // Frame 0 of each depth configuration at the last search configuration (80/1): the
    // reference (EXR + PNG) and each method (EXR + PNG + error PNG + its scale's legend).
    let mut frames: Vec<String> =
        std::fs::read_dir(out.join("effects_frames")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    frames.sort();
    assert_eq!(frames.len(), 2 * (2 + 4 + 4), "{frames:?}");
    assert!(frames.contains(&"depth3-3_steps80-1_schlick_error.png".to_string()), "{frames:?}");
    assert!(frames.contains(&"depth3-3_steps80-1_schlick_error_scale.png".to_string()), "{frames:?}");
}

/// The shipped AO scenes parse, name only surfel effects, need no specular object, and
/// their mesh files are where the scenes say (relative to `scenes/`).
#[test]
fn shipped_ao_scenes_parse_and_name_surfel_effects() {
    for file in ["ao-bunny.yaml", "ao-sculpture.yaml", "ao-colour-bleeding.yaml"] {
        let scene = Scene::load(&root().join("scenes").join(file)).unwrap();
        let effects = scene.effects.as_ref().unwrap();
        assert!(effects.ambient_occlusion.is_some() && effects.reflection.is_none() && effects.refraction.is_none(), "{file}");
        assert_eq!(scene.specular_objects().count(), 0, "{file}");
        assert!(scene.objects.iter().all(|o| matches!(o.role, Role::Diffuse(_))), "{file}");
    }
    let bleeding = Scene::load(&root().join("scenes/ao-colour-bleeding.yaml")).unwrap();
    assert_eq!(bleeding.effects.unwrap().indirect.map(|i| i.bounces), Some(2));
}

/// `nklut effects` on a small AO scene with indirect light: ao_errors (CSV, Parquet,
/// columns.json) with a row per object, pass count (1–3) and way of gathering (brute force
/// and tree), finite numbers and the indirect columns filled; the pictures (no AO, 1, 2, 3
/// passes with error images, the reference, side by side, the signed accessibility error of
/// 1, 2, 3 passes above their legend, and the legend alone); the error histograms
/// (`ao_histogram`); no page read and no
/// effects_errors (the scene names no reflection).
#[test]
fn effects_command_measures_ambient_occlusion_against_the_reference() {
    let (dir, output) = run_effects(
        "ao-effects",
        "resolution: [10, 8]\ncamera: {axis: [0, 1, 0.2], distance: 2.5, frames: 1}\neffects:\n  ambient_occlusion: {passes: 2, bent_normals: true}\n  indirect: {bounces: 1}\nlights:\n  - {kind: directional, direction: [-0.3, -1, -0.2], colour: [1, 1, 1]}\n  - {kind: ambient, colour: [0.3, 0.3, 0.3]}\nobjects:\n  - {mesh: cube, scale: 0.5, diffuse: [0.8, 0.2, 0.2], subdivide: 1}\n  - {mesh: cube, scale: [2, 0.05, 2], position: [0, -0.32, 0], diffuse: [0.7, 0.7, 0.7], subdivide: 2}\nmeasurements: [image_error]\n",
        &["--ao-rays", "32"],
    );
    let out = dir.join("out");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("0 cube maps") && stderr.contains(" 6 AO passes"), "{stderr}");
    let (headers, rows) = read_csv(&out.join("ao_errors.csv"));
    let column = |name: &str| headers.iter().position(|h| h == name).unwrap_or_else(|| panic!("{name}"));
    assert_eq!(rows.len(), 2 * 3 * 2, "2 objects × 3 passes × brute force and tree");
    for row in &rows {
        for name in ["mean_error", "max_error", "reference_standard_error", "indirect_mean_error", "indirect_reference_mean"] {
            let value: f64 = row[column(name)].parse().unwrap_or_else(|e| panic!("{name} {:?}: {e}", &row[column(name)]));
            assert!(value.is_finite() && value >= 0.0, "{name} {value}");
        }
        assert!(row[column("mean_error")].parse::<f64>().unwrap() <= row[column("max_error")].parse::<f64>().unwrap());
        // The order statistics are ordered, each weighting's signed mean within its mean |e|,
        // and both objects are seen by the camera.
        for prefix in ["", "area_", "pixel_"] {
            let value = |name: &str| row[column(&format!("{prefix}{name}"))].parse::<f64>().unwrap();
            let ordered = [value("median_error"), value("p90_error"), value("p99_error"), value("max_error")];
            assert!(ordered.windows(2).all(|w| w[0] <= w[1]), "{prefix}: {ordered:?}");
            assert!(value("signed_error").abs() <= value("mean_error") + 1e-15, "{prefix}");
        }
        assert!(row[column("pixels")].parse::<u64>().unwrap() > 0);
        // The scene asks for bent normals: their angle to the ray-traced ones, in degrees.
        let angle: f64 = row[column("bent_normal_mean_angle")].parse().unwrap();
        assert!((0.0..=180.0).contains(&angle), "{angle}");
        assert_eq!(&row[column("defect_vertices")], "0", "cubes are closed and consistently wound");
    }
    assert!(out.join("ao_errors.parquet").exists() && out.join("ao_errors.columns.json").exists());
    // The histograms: per row of ao_errors, 40 bins per vertex, area and pixel weighting;
    // each vertex histogram counts its object's surfels.
    let (histogram_headers, bins) = read_csv(&out.join("ao_histogram.csv"));
    assert_eq!(bins.len(), rows.len() * 3 * 40);
    let at = |name: &str| histogram_headers.iter().position(|h| h == name).unwrap_or_else(|| panic!("{name}"));
    for row in &rows {
        let technique = if &row[column("hierarchy")] == "true" { "tree" } else { "brute force" };
        let counted: u64 = bins
            .iter()
            .filter(|b| {
                b[at("mesh")] == row[column("mesh")]
                    && &b[at("technique")] == technique
                    && b[at("passes")] == row[column("passes")]
                    && &b[at("weighting")] == "vertex"
            })
            .map(|b| b[at("count")].parse::<u64>().unwrap())
            .sum();
        assert_eq!(counted, row[column("surfels")].parse::<u64>().unwrap());
    }
    assert!(out.join("ao_histogram.parquet").exists() && out.join("ao_histogram.columns.json").exists());
    // A signed map above its legend, at least as wide as the legend's text.
    let signed = image::open(out.join("ao_frames/ao_passes2_signed.png")).unwrap();
    let legend = nklut::effects::pictures::LEGEND_HEIGHT;
    assert_eq!((signed.width(), signed.height()), (nklut::effects::pictures::LEGEND_WIDTH, 8 + legend));
    assert!(!out.join("effects_errors.csv").exists());
    let mut pictures: Vec<String> =
        std::fs::read_dir(out.join("ao_frames")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    pictures.sort();
    assert_eq!(pictures.len(), 4 * 4 + 2 + 2 + 3 + 1, "{pictures:?}");
    assert!(pictures.contains(&"ao_passes2_signed.png".to_string()) && pictures.contains(&"surfels_signed_scale.png".to_string()));
    assert!(
        pictures.contains(&"ao_passes2_error.png".to_string())
            && pictures.contains(&"ao_passes2_error_scale.png".to_string())
            && pictures.contains(&"ao_side_by_side.exr".to_string()),
        "{pictures:?}"
    );
}
