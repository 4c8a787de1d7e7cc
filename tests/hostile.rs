//! The `nklut` binary on a hostile fixture database written by the test: every bad input
//! gets a named reason with its file (and line), nothing is dropped silently, every flag
//! that reads pages is honoured by every command, and a killed run leaves one complete
//! set of tables.

use std::fs;
use std::io::Read;
use std::path::Path;
use std::process::{Command, Output, Stdio};

mod common;

/// A database whose pages each carry one defect (and two good ones).
fn hostile() -> tempfile::TempDir {
    let root = tempfile::tempdir().unwrap();
    let write = |path: &str, bytes: &[u8]| {
        let path = root.path().join(path);
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, bytes).unwrap();
    };
    write(
        "catalog-nk.yml",
        br#"
- SHELF: h
  name: "Hostile"
  content:
    - BOOK: X
      name: "X"
      content:
        - PAGE: good
          data: h/X/good.yml
        - PAGE: nodata
          name: "no data key"
        - PAGE: emptydata
          data: ""
        - PAGE: escape
          data: ../../../../etc/hostname
        - PAGE: halfterm
          data: h/X/halfterm.yml
        - PAGE: huge
          data: h/X/huge.yml
        - PAGE: bom
          data: h/X/bom.yml
        - PAGE: latin1
          data: h/X/latin1.yml
        - PAGE: "a/b"
          data: h/X/good.yml
        - PAGE: ""
          data: h/X/good.yml
        - PAGE: from450
          data: h/X/from450.yml
        - PAGE: restart
          data: h/X/restart.yml
"#,
    );
    let good = b"DATA:\n  - type: tabulated nk\n    data: |\n        0.30 1.0 2.0\n        0.50 2.0 3.0\n        0.80 3.0 4.0\n";
    write("data/h/X/good.yml", good);
    write("data/h/X/halfterm.yml", b"DATA:\n  - type: formula 1\n    wavelength_range: 0.3 2.0\n    coefficients: 0 1.0 0.1 0.5\n");
    write("data/h/X/huge.yml", b"DATA:\n  - type: tabulated nk\n    data: |\n        0.30 1.0 2.0\n        0.50 1e300 3.0\n        0.80 3.0 4.0\n");
    let mut bom = b"\xEF\xBB\xBF".to_vec();
    bom.extend_from_slice(good);
    write("data/h/X/bom.yml", &bom);
    write("data/h/X/latin1.yml", b"COMMENTS: caf\xE9\nDATA:\n  - type: formula 5\n    wavelength_range: 0.3 2.0\n    coefficients: 1.5\n");
    write("data/h/X/from450.yml", b"DATA:\n  - type: tabulated n\n    data: |\n        0.45 1.50\n        0.75 1.48\n");
    // Wavelengths restart at 2.0 µm after 2.5 µm (line 8): far outside 360-830 nm.
    write(
        "data/h/X/restart.yml",
        b"DATA:\n  - type: tabulated nk\n    data: |\n        0.3 1.0 2.0\n        0.5 2.0 4.0\n        1.0 3.0 1.0\n        2.5 3.0 1.0\n        2.0 3.1 1.1\n        3.0 3.2 1.2\n",
    );
    root
}

fn nklut(db: &Path, out: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nklut")).arg("--db").arg(db).arg("--out").arg(out).args(args).output().unwrap()
}

fn ok(output: &Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "{stderr}");
    stderr
}

fn failed(output: &Output) -> String {
    assert!(!output.status.success(), "expected a failure");
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Rows of a CSV as maps from column name to cell.
fn rows(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    reader.records().map(|r| header.iter().cloned().zip(r.unwrap().iter().map(String::from)).collect()).collect()
}

#[test]
fn every_bad_page_is_excluded_with_its_reason_and_line() {
    let db = hostile();
    let out = db.path().join("out");
    let stderr = ok(&nklut(db.path(), &out, &["ingest"]));
    let excluded = rows(&out.join("excluded.csv"));
    let reason = |page: &str| {
        let row = excluded.iter().find(|r| r["page"] == page).unwrap_or_else(|| panic!("{page} not in excluded.csv: {excluded:?}"));
        (row["reason"].clone(), row["line"].clone(), row["detail"].clone())
    };
    assert_eq!(reason("h/X/nodata").0, "no-data-file");
    assert_eq!(reason("h/X/emptydata").0, "no-data-file");
    assert_eq!(reason("h/X/escape").0, "path-outside-database");
    assert_eq!(reason("h/X/halfterm").0, "incomplete-formula-term");
    assert_eq!(reason("h/X/huge").0, "index-out-of-domain");
    assert_eq!(reason("h/X/huge").1, "5");
    let (code, line, detail) = reason("h/X/latin1");
    assert_eq!((code.as_str(), line.as_str()), ("not-utf8", "1"));
    assert!(detail.contains("0xE9"), "{detail}");
    assert_eq!(reason("h/X/a/b").0, "bad-page-id");
    assert_eq!(reason("h/X/").0, "bad-page-id");
    // Kept: the good page, the one with a byte-order mark, the one from 450 nm and the
    // one whose order defect lies far in the infrared; every page is in one table.
    let kept: Vec<String> = rows(&out.join("materials.csv")).into_iter().map(|r| r["page"].clone()).collect();
    assert_eq!(kept, ["h/X/good", "h/X/bom", "h/X/from450", "h/X/restart"]);
    assert_eq!(kept.len() + excluded.len(), 12, "{kept:?} {excluded:?}");
    let warnings = rows(&out.join("warnings.csv"));
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!((warnings[0]["page"].as_str(), warnings[0]["reason"].as_str(), warnings[0]["line"].as_str()), ("h/X/restart", "non-monotonic-wavelengths", "8"));
    assert!(stderr.contains("1 data warning"), "{stderr}");
    // Nothing was read from outside the database.
    assert!(!fs::read_to_string(out.join("materials.csv")).unwrap().contains("etc/hostname,"));
    // The study's stricter rule drops the page that starts at 450 nm.
    ok(&nklut(db.path(), &out, &["ingest", "--visible", "full"]));
    let full = rows(&out.join("excluded.csv"));
    assert!(full.iter().any(|r| r["page"] == "h/X/from450" && r["reason"] == "no-visible-coverage"), "{full:?}");
}

#[test]
fn strict_is_taken_by_every_command_that_reads_pages() {
    let db = hostile();
    let out = db.path().join("out");
    for command in ["ingest", "colors", "validate", "bake"] {
        let stderr = failed(&nklut(db.path(), &out, &[command, "--strict"]));
        assert!(stderr.contains("--strict") && stderr.contains("path-outside-database"), "{command}: {stderr}");
        // One good page alone passes under --strict.
        ok(&nklut(db.path(), &out, &[command, "--strict", "--page", "h/X/good"]));
    }
}

#[test]
fn channel_wavelengths_reach_every_table() {
    let db = hostile();
    let out = db.path().join("out");
    let channels = ["--channels", "650,550,450", "--page", "h/X/good"];
    for command in ["ingest", "colors", "validate", "bake"] {
        ok(&nklut(db.path(), &out, &[&[command][..], &channels[..]].concat()));
    }
    // good.yml at 650 nm: t = 0.5 between 0.50 and 0.80 µm → n 2.5, k 3.5; 450 nm: t = 0.75
    // between 0.30 and 0.50 µm → n 1.75, k 2.75.
    let material = &rows(&out.join("materials.csv"))[0];
    assert_eq!((material["n_red"].as_str(), material["k_red"].as_str()), ("2.5", "3.5"));
    assert_eq!((material["n_blue"].as_str(), material["k_blue"].as_str()), ("1.75", "2.75"));
    let wavelengths: std::collections::BTreeSet<String> = rows(&out.join("errors.csv")).into_iter().map(|r| r["wavelength_nm"].clone()).collect();
    assert_eq!(wavelengths.into_iter().collect::<Vec<_>>(), ["450", "550", "650"]);
    let columns = fs::read_to_string(out.join("colors.columns.json")).unwrap();
    assert!(columns.contains("[650.0, 550.0, 450.0]"), "{columns}");
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(out.join("luts/manifest.json")).unwrap()).unwrap();
    let nm: Vec<f64> = manifest["channel_wavelengths"].as_array().unwrap().iter().map(|c| c["wavelength_nm"].as_f64().unwrap()).collect();
    assert_eq!(nm, [650.0, 550.0, 450.0]);
    // Outside the spectral grid the colours are computed on, the wavelengths are refused.
    assert!(failed(&nklut(db.path(), &out, &["ingest", "--channels", "900,550,450"])).contains("900"));
}

#[test]
fn flags_are_checked_and_outputs_hold_no_nan() {
    let db = hostile();
    let out = db.path().join("out");
    // A wavelength outside a table names the table's range.
    let stderr = failed(&nklut(db.path(), &out, &["nk", "h/X/good", "--nm", "0"]));
    assert!(stderr.contains("outside-table-range") && stderr.contains("300.0–800.0 nm"), "{stderr}");
    // colors --texels has bake --size's bounds.
    for texels in ["0", "100000000"] {
        assert!(failed(&nklut(db.path(), &out, &["colors", "--texels", texels])).contains("65536"));
    }
    // validate: --nk outside the methods' domain is refused, --nk with a selection too,
    // and a method named twice is measured once (3 channels x 2 precisions).
    let stderr = failed(&nklut(db.path(), &out, &["validate", "--nk", "1e20,0;1.5,0;1.5,0"]));
    assert!(stderr.contains("--nk red") && stderr.contains("domain"), "{stderr}");
    assert!(!out.join("errors.csv").exists());
    failed(&nklut(db.path(), &out, &["validate", "--page", "h/X/good", "--nk", "1.5,0;1.5,0;1.5,0"]));
    ok(&nklut(db.path(), &out, &["validate", "--nk", "0.2,3.5;0.5,2.4;1.3,1.9", "--method", "schlick_nk", "--method", "schlick_nk"]));
    assert_eq!(rows(&out.join("errors.csv")).len(), 6);
    // Every table of every command over the whole fixture is free of NaN and infinity.
    for command in ["ingest", "colors", "validate", "bake"] {
        ok(&nklut(db.path(), &out, &[command]));
    }
    for (name, bad) in common::non_finite_tables(&out) {
        assert!(bad.is_empty(), "{name}: {bad:?}");
    }
}

#[test]
fn a_closed_pipe_ends_the_program_quietly() {
    let db = hostile();
    let out = db.path().join("out");
    let mut child = Command::new(env!("CARGO_BIN_EXE_nklut"))
        .arg("--db")
        .arg(db.path())
        .arg("--out")
        .arg(&out)
        .args(["nk", "h/X/good", "--nm", "400", "--nm", "500", "--nm", "600"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The reader goes away before the first line is written.
    drop(child.stdout.take());
    let mut stderr = String::new();
    child.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}: {stderr}");
    assert_eq!(stderr, "");
}

/// The bytes of every table of the ingest set, by name.
fn ingest_set(out: &Path) -> Vec<(String, Option<Vec<u8>>)> {
    ["materials.csv", "materials.json", "materials.parquet", "materials.columns.json", "excluded.csv", "warnings.csv"]
        .into_iter()
        .map(|name| (name.to_string(), fs::read(out.join(name)).ok()))
        .collect()
}

#[test]
fn a_killed_ingest_leaves_one_complete_set() {
    let db = hostile();
    let out = db.path().join("out");
    // Run A: two pages. Run B: the whole shelf (different bytes in every table).
    let a_args = ["ingest", "--page", "h/X/good", "--page", "h/X/huge"];
    ok(&nklut(db.path(), &out, &a_args));
    let a = ingest_set(&out);
    let b_out = db.path().join("b");
    ok(&nklut(db.path(), &b_out, &["ingest"]));
    let b = ingest_set(&b_out);
    assert!(a.iter().zip(&b).all(|(x, y)| x.1 != y.1), "the two runs must differ in every table");
    for step in ["staged", "switched", "linked"] {
        ok(&nklut(db.path(), &out, &a_args));
        let killed = Command::new(env!("CARGO_BIN_EXE_nklut"))
            .env("NKLUT_CRASH_AT", step)
            .arg("--db")
            .arg(db.path())
            .arg("--out")
            .arg(&out)
            .arg("ingest")
            .output()
            .unwrap();
        assert!(!killed.status.success(), "{step}: the run should have been killed");
        let now = ingest_set(&out);
        let expected = if step == "staged" { &a } else { &b };
        assert!(now == *expected, "after a kill at {step} the folder holds a mix or the wrong run");
        // The next run cleans up what the killed one left and publishes normally.
        ok(&nklut(db.path(), &out, &a_args));
        assert!(ingest_set(&out) == a);
        let generations = fs::read_dir(out.join(".sets")).unwrap().filter(|e| e.as_ref().unwrap().file_type().unwrap().is_dir()).count();
        assert_eq!(generations, 1, "{step}: leftovers remain");
    }
    // Kills at arbitrary moments: the folder always holds run A or run B whole.
    for delay_ms in [0u64, 2, 5, 10, 20, 40] {
        ok(&nklut(db.path(), &out, &a_args));
        let mut child = Command::new(env!("CARGO_BIN_EXE_nklut"))
            .arg("--db")
            .arg(db.path())
            .arg("--out")
            .arg(&out)
            .arg("ingest")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let _ = child.kill();
        let _ = child.wait();
        let now = ingest_set(&out);
        assert!(now == a || now == b, "after a kill at {delay_ms} ms the folder holds a mix");
    }
}

/// Σ S(λ) ȳ(λ) over the 1 nm grid 360–830 nm for λ below `below_nm`, over the whole
/// grid: D65 (5 nm) interpolated linearly to 1 nm, from the CIE tables themselves.
fn luminance_share_below(below_nm: f64) -> f64 {
    let cie = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/cie");
    let table = |name: &str, column: usize| -> Vec<(f64, f64)> {
        let text = fs::read_to_string(cie.join(name)).unwrap();
        text.lines().skip(1).map(|l| {
            let cells: Vec<f64> = l.split(',').map(|c| c.trim().parse().unwrap()).collect();
            (cells[0], cells[column])
        }).collect()
    };
    let d65 = table("cie_d65_spd.csv", 1);
    let ybar = table("cie1931_2deg_xyz_cmf_1nm.csv", 2);
    let s = |nm: f64| -> f64 {
        let i = d65.iter().position(|&(w, _)| w > nm).map_or(d65.len() - 1, |i| i.max(1));
        if nm > d65[d65.len() - 1].0 {
            return 0.0;
        }
        let ((w0, s0), (w1, s1)) = (d65[i - 1], d65[i]);
        s0 + (nm - w0) / (w1 - w0) * (s1 - s0)
    };
    let weight = |&(nm, y): &(f64, f64)| if (360.0..=830.0).contains(&nm) { s(nm) * y } else { 0.0 };
    let total: f64 = ybar.iter().map(weight).sum();
    let below: f64 = ybar.iter().filter(|(nm, _)| *nm < below_nm).map(weight).sum();
    below / total
}

/// Data from 450 nm: the spectral colour holds n below 450 nm, and colors.csv and the
/// LUT manifest both record the share of the luminance weight held.
#[test]
fn the_extrapolated_share_is_recorded_in_colors_and_the_manifest() {
    let db = hostile();
    let out = db.path().join("out");
    for command in ["colors", "bake"] {
        ok(&nklut(db.path(), &out, &[command, "--page", "h/X/from450", "--source", "spectral"][..if command == "bake" { 5 } else { 3 }]));
    }
    // from450.yml covers 450–750 nm: held below 450 nm and above 750 nm (D65's ȳ weight
    // beyond 750 nm is about 1e-4 of the total).
    let expected = luminance_share_below(450.0) + (1.0 - luminance_share_below(751.0));
    let colors: f64 = rows(&out.join("colors.csv"))[0]["extrapolated_share"].parse().unwrap();
    assert!((colors - expected).abs() < 1e-9, "colors.csv {colors} vs {expected}");
    assert!(expected > 1e-3, "{expected}");
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(out.join("luts/manifest.json")).unwrap()).unwrap();
    let shares: Vec<f64> = manifest["textures"].as_array().unwrap().iter().flat_map(|set| set["rows"].as_array().unwrap().iter().map(|r| r["extrapolated_share"].as_f64().unwrap())).collect();
    assert!(!shares.is_empty() && shares.iter().all(|&s| s == colors), "{shares:?} vs {colors}");
}
