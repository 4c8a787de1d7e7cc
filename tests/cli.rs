//! The `nklut` binary on a small fixture database written by the test: bad data is
//! recorded with file and line and the run continues; `--strict` makes it fatal.

mod common;

use common::{scratch, Scratch};
use std::fs;
use std::path::Path;
use std::process::{Command, Output};

fn fixture(name: &str) -> Scratch {
    let root = scratch(&format!("cli-{name}"));
    let write = |path: &str, text: &str| {
        let path = root.join(path);
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, text).unwrap();
    };
    write(
        "catalog-nk.yml",
        r#"
- SHELF: test
  name: "Test shelf"
  content:
    - BOOK: X
      name: "X"
      content:
        - PAGE: good
          data: test/X/nk/good.yml
        - PAGE: badrow
          data: test/X/nk/badrow.yml
        - PAGE: missing
          data: test/X/nk/missing.yml
        - PAGE: infrared
          data: test/X/nk/infrared.yml
"#,
    );
    write("data/test/X/about.yml", "NAMES:\n  - Testium\n  - Ts<sub>2</sub>\n");
    write("data/test/X/nk/good.yml", "REFERENCES: |\n    Hand 2026\nDATA:\n  - type: tabulated nk\n    data: |\n        0.30 1.0 2.0\n        0.50 2.0 3.0\n        0.80 3.0 4.0\n");
    write("data/test/X/nk/badrow.yml", "DATA:\n  - type: tabulated nk\n    data: |\n        0.30 1.0 2.0\n        0.50 x 3.0\n");
    write("data/test/X/nk/infrared.yml", "DATA:\n  - type: formula 5\n    wavelength_range: 1.0 5.0\n    coefficients: 1.5\n");
    root
}

fn nklut(db: &Path, out: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nklut")).arg("--db").arg(db).arg("--out").arg(out).args(args).output().unwrap()
}

#[test]
fn ingest_records_bad_pages_and_continues() {
    let db = fixture("ingest");
    let out = db.join("out");
    let result = nklut(&db, &out, &["ingest"]);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    let materials = fs::read_to_string(out.join("materials.csv")).unwrap();
    assert_eq!(materials.lines().count(), 2, "{materials}");
    // good.yml at 535 nm: between 0.50 and 0.80 µm, t = 35/300: n = 2 + t, k = 3 + t.
    let row: Vec<&str> = materials.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(row[0], "test/X/good");
    assert_eq!(row[4], "Testium; Ts2");
    let t = 35.0 / 300.0;
    let n_green: f64 = row[11].parse().unwrap();
    assert!((n_green - (2.0 + t)).abs() < 1e-12, "{row:?}");
    let excluded = fs::read_to_string(out.join("excluded.csv")).unwrap();
    assert!(excluded.contains("test/X/badrow,test/X/nk/badrow.yml,bad-row,5,"), "{excluded}");
    assert!(excluded.contains("test/X/missing,test/X/nk/missing.yml,missing-file,"), "{excluded}");
    assert!(excluded.contains("test/X/infrared,test/X/nk/infrared.yml,no-visible-coverage,"), "{excluded}");
    let json: serde_json::Value = serde_json::from_slice(&fs::read(out.join("materials.json")).unwrap()).unwrap();
    assert_eq!(json[0]["kind"], "conductor");
    assert_eq!(&fs::read(out.join("materials.parquet")).unwrap()[..4], b"PAR1");
}

#[test]
fn strict_makes_data_errors_fatal_but_not_coverage() {
    let db = fixture("strict");
    let out = db.join("out");
    let result = nklut(&db, &out, &["ingest", "--strict"]);
    assert!(!result.status.success());
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(stderr.contains("bad-row in test/X/nk/badrow.yml line 5"), "{stderr}");
    assert!(!stderr.contains("infrared.yml line"), "{stderr}");
    let only_coverage = nklut(&db, &out, &["ingest", "--strict", "--page", "test/X/good", "--page", "test/X/infrared"]);
    assert!(only_coverage.status.success(), "{}", String::from_utf8_lossy(&only_coverage.stderr));
}

#[test]
fn nk_prints_one_line_per_wavelength_and_names_the_range() {
    let db = fixture("nk");
    let out = db.join("out");
    let result = nklut(&db, &out, &["nk", "test/X/good", "--nm", "400", "--nm", "650"]);
    assert!(result.status.success());
    // 400 nm: t = 0.5 between 0.30 and 0.50 µm → n 1.5, k 2.5; 650 nm: t = 0.5 → n 2.5, k 3.5.
    assert_eq!(String::from_utf8(result.stdout).unwrap(), "400 1.5 2.5\n650 2.5 3.5\n");
    let result = nklut(&db, &out, &["nk", "test/X/good", "--nm", "900"]);
    assert!(!result.status.success());
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(stderr.contains("300.0–800.0 nm"), "{stderr}");
    let result = nklut(&db, &out, &["nk", "test/X/nope", "--nm", "500"]);
    assert!(String::from_utf8_lossy(&result.stderr).contains("unknown page"));
}

/// A scene of diffuse objects alone (ambient occlusion) reads no material: `effects` runs
/// without a database at all.
#[test]
fn an_ao_only_scene_needs_no_database() {
    let dir = scratch("ao-no-db");
    let scene = dir.join("ao.yaml");
    fs::write(
        &scene,
        "resolution: [12, 12]\ncamera: { frames: 1 }\nmeasurements: [image_error]\neffects: { ambient_occlusion: { passes: 1 } }\nobjects:\n  - { mesh: cube, diffuse: [0.5, 0.5, 0.5] }\n  - { mesh: plane, scale: 2, position: [0, -0.6, 0], diffuse: [0.5, 0.5, 0.5] }\n",
    )
    .unwrap();
    let output = nklut(&dir.join("no-database-here"), &dir.join("out"), &["effects", scene.to_str().unwrap(), "--ao-rays", "8"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(dir.join("out/ao_errors.csv").exists());
    // A scene that names a material still says where the database was looked for.
    fs::write(&scene, "measurements: [image_error]\neffects: { reflection: { max_depth: 1 } }\nobjects:\n  - { mesh: sphere, material: 3d/metals/gold, method: exact }\n").unwrap();
    let output = nklut(&dir.join("no-database-here"), &dir.join("out"), &["effects", scene.to_str().unwrap()]);
    assert!(!output.status.success() && String::from_utf8_lossy(&output.stderr).contains("no refractiveindex.info database"));
}
