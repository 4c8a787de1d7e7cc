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
    write(
        "data/h/X/huge.yml",
        b"DATA:\n  - type: tabulated nk\n    data: |\n        0.30 1.0 2.0\n        0.50 1e300 3.0\n        0.80 3.0 4.0\n",
    );
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
    Command::new(common::binary()).arg("--db").arg(db).arg("--out").arg(out).args(args).output().unwrap()
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

#[test]
fn every_bad_page_is_excluded_with_its_reason_and_line() {
    let db = hostile();
    let out = db.path().join("out");
    let stderr = ok(&nklut(db.path(), &out, &["ingest"]));
    let excluded = common::csv_rows(&out.join("excluded.csv"));
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
    let kept: Vec<String> = common::csv_rows(&out.join("materials.csv")).into_iter().map(|r| r["page"].clone()).collect();
    assert_eq!(kept, ["h/X/good", "h/X/bom", "h/X/from450", "h/X/restart"]);
    assert_eq!(kept.len() + excluded.len(), 12, "{kept:?} {excluded:?}");
    let warnings = common::csv_rows(&out.join("warnings.csv"));
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(
        (warnings[0]["page"].as_str(), warnings[0]["reason"].as_str(), warnings[0]["line"].as_str()),
        ("h/X/restart", "non-monotonic-wavelengths", "8")
    );
    assert!(stderr.contains("1 data warning"), "{stderr}");
    // Nothing was read from outside the database.
    assert!(!fs::read_to_string(out.join("materials.csv")).unwrap().contains("etc/hostname,"));
    // The study's stricter rule drops the page that starts at 450 nm.
    ok(&nklut(db.path(), &out, &["ingest", "--visible", "full"]));
    let full = common::csv_rows(&out.join("excluded.csv"));
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
    let material = &common::csv_rows(&out.join("materials.csv"))[0];
    assert_eq!((material["n_red"].as_str(), material["k_red"].as_str()), ("2.5", "3.5"));
    assert_eq!((material["n_blue"].as_str(), material["k_blue"].as_str()), ("1.75", "2.75"));
    let wavelengths: std::collections::BTreeSet<String> =
        common::csv_rows(&out.join("errors.csv")).into_iter().map(|r| r["wavelength_nm"].clone()).collect();
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
    assert_eq!(common::csv_rows(&out.join("errors.csv")).len(), 6);
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
    let mut child = Command::new(common::binary())
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
        let killed = Command::new(common::binary())
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
        let mut child = Command::new(common::binary())
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
        text.lines()
            .skip(1)
            .map(|l| {
                let cells: Vec<f64> = l.split(',').map(|c| c.trim().parse().unwrap()).collect();
                (cells[0], cells[column])
            })
            .collect()
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
    let colors: f64 = common::csv_rows(&out.join("colors.csv"))[0]["extrapolated_share"].parse().unwrap();
    assert!((colors - expected).abs() < 1e-9, "colors.csv {colors} vs {expected}");
    assert!(expected > 1e-3, "{expected}");
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(out.join("luts/manifest.json")).unwrap()).unwrap();
    let shares: Vec<f64> = manifest["textures"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|set| set["rows"].as_array().unwrap().iter().map(|r| r["extrapolated_share"].as_f64().unwrap()))
        .collect();
    assert!(!shares.is_empty() && shares.iter().all(|&s| s == colors), "{shares:?} vs {colors}");
}

// ---------------------------------------------------------------------------------------
// The faults an outside attack found, one test each (the item numbers of the attack's list).

/// A database of `catalog` text and `files` under `data/`.
fn fixture(catalog: &str, files: &[(&str, &[u8])]) -> tempfile::TempDir {
    let root = tempfile::tempdir().unwrap();
    fs::write(root.path().join("catalog-nk.yml"), catalog).unwrap();
    for (path, bytes) in files {
        let path = root.path().join("data").join(path);
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, bytes).unwrap();
    }
    fs::create_dir_all(root.path().join("data")).unwrap();
    root
}

/// A catalog of one shelf `h`, one book `X` and the pages `(id, data file)`.
fn catalog_of(pages: &[(&str, &str)]) -> String {
    let mut text = String::from("- SHELF: h\n  content:\n    - BOOK: X\n      content:\n");
    for (id, data) in pages {
        text.push_str(&format!("        - PAGE: \"{id}\"\n          data: {data}\n"));
    }
    text
}

const GOOD: &[u8] = b"DATA:\n  - type: tabulated nk\n    data: |\n        0.30 1.0 2.0\n        0.50 2.0 3.0\n        0.80 3.0 4.0\n";

fn nklut_bounded(db: &Path, out: &Path, args: &[&str]) -> Output {
    common::bounded(Command::new(common::binary()).arg("--db").arg(db).arg("--out").arg(out).args(args), std::time::Duration::from_secs(60))
}

/// Exit status 0 or 1: never a panic (101) or a signal.
fn exit_0_or_1(output: &Output) -> i32 {
    let code = output.status.code();
    assert!(matches!(code, Some(0 | 1)), "status {:?}: {}", output.status, String::from_utf8_lossy(&output.stderr));
    code.unwrap()
}

fn excluded_reason(out: &Path, page: &str) -> String {
    let excluded = common::csv_rows(&out.join("excluded.csv"));
    excluded.iter().find(|r| r["page"] == page).unwrap_or_else(|| panic!("{page} not in excluded.csv: {excluded:?}"))["reason"].clone()
}

/// A `data: |` line inside a comment's block is not the page's table; the parser
/// decides where the DATA block's table is.
#[test]
fn a_table_inside_a_comment_is_not_the_page_s_data() {
    let page = b"COMMENTS: |\n    an example of the layout:\n    data: |\n        0.30 9.9\n        0.80 9.9\nREFERENCES: \"r\"\nDATA:\n  - type: tabulated n\n    data: |\n        0.30 1.5\n        0.80 1.5\n";
    let quoted =
        b"COMMENTS: |\n    data: |\n        0.30 9.9\n        0.80 9.9\nDATA:\n  - type: tabulated n\n    data: \"0.30 1.5\\n0.80 1.5\"\n";
    let db = fixture(
        &catalog_of(&[("comment", "h/X/comment.yml"), ("quoted", "h/X/quoted.yml")]),
        &[("h/X/comment.yml", page), ("h/X/quoted.yml", quoted)],
    );
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest"]));
    for row in common::csv_rows(&out.join("materials.csv")) {
        assert_eq!(row["n_green"], "1.5", "{}: the comment's 9.9 was read", row["page"]);
    }
    let printed = nklut(db.path(), &out, &["nk", "h/X/comment", "--nm", "500"]);
    assert_eq!(String::from_utf8_lossy(&printed.stdout).trim(), "500 1.5 0");
}

/// FIFOs, devices and links that leave the database are refused without reading
/// (nothing blocks), each with its reason; the rest of the run goes on.
#[cfg(unix)]
#[test]
fn special_files_and_links_out_of_the_database_are_refused_without_blocking() {
    let db = fixture(
        &catalog_of(&[
            ("good", "h/X/good.yml"),
            ("fifo", "h/X/fifo.yml"),
            ("zero", "h/X/zero.yml"),
            ("random", "h/X/random.yml"),
            ("outside", "h/X/outside.yml"),
            ("kmsg", "h/X/kmsg.yml"),
        ]),
        &[("h/X/good.yml", GOOD)],
    );
    let data = db.path().join("data/h/X");
    let fifo = std::ffi::CString::new(data.join("fifo.yml").as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: mkfifo reads a NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) }, 0);
    std::os::unix::fs::symlink("/dev/zero", data.join("zero.yml")).unwrap();
    std::os::unix::fs::symlink("/dev/urandom", data.join("random.yml")).unwrap();
    std::os::unix::fs::symlink("/proc/kmsg", data.join("kmsg.yml")).unwrap();
    let elsewhere = tempfile::tempdir().unwrap();
    fs::write(elsewhere.path().join("page.yml"), GOOD).unwrap();
    std::os::unix::fs::symlink(elsewhere.path().join("page.yml"), data.join("outside.yml")).unwrap();
    let out = db.path().join("out");
    ok(&nklut_bounded(db.path(), &out, &["ingest"]));
    assert_eq!(excluded_reason(&out, "h/X/fifo"), "not-a-regular-file");
    assert_eq!(excluded_reason(&out, "h/X/zero"), "not-a-regular-file");
    assert_eq!(excluded_reason(&out, "h/X/random"), "not-a-regular-file");
    assert_eq!(excluded_reason(&out, "h/X/outside"), "path-outside-database");
    assert_eq!(excluded_reason(&out, "h/X/kmsg"), "path-outside-database");
    let kept: Vec<String> = common::csv_rows(&out.join("materials.csv")).into_iter().map(|r| r["page"].clone()).collect();
    assert_eq!(kept, ["h/X/good"]);
}

/// Catalog entries whose levels are not single values are in excluded.csv, not
/// dropped: every PAGE of the catalog is in exactly one of the two tables.
#[test]
fn catalog_entries_that_are_not_pages_are_excluded_not_dropped() {
    let catalog = "- SHELF: h\n  content:\n    - BOOK: ~\n      content:\n        - PAGE: a\n          data: h/X/good.yml\n    - BOOK: X\n      content:\n        - PAGE: [1, 2]\n          data: h/X/good.yml\n        - PAGE: {x: 1}\n          data: h/X/good.yml\n        - PAGE: good\n          data: h/X/good.yml\n- SHELF: [1, 2]\n  content:\n    - BOOK: Y\n      content:\n        - PAGE: b\n          data: h/X/good.yml\n";
    let db = fixture(catalog, &[("h/X/good.yml", GOOD)]);
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest"]));
    let kept = common::csv_rows(&out.join("materials.csv"));
    let excluded = common::csv_rows(&out.join("excluded.csv"));
    assert_eq!(kept.len(), 1);
    assert_eq!(kept.len() + excluded.len(), catalog.matches("PAGE:").count(), "{excluded:?}");
    assert!(excluded.iter().all(|r| r["reason"] == "bad-catalog-entry"), "{excluded:?}");
}

/// Pages sharing one data file cost memory and table bytes linear in the pages.
#[test]
fn pages_sharing_one_data_file_cost_linear_memory() {
    let pages: Vec<(String, &str)> = (0..5000).map(|i| (format!("p{i}"), "h/X/good.yml")).collect();
    let listed: Vec<(&str, &str)> = pages.iter().map(|(id, data)| (id.as_str(), *data)).collect();
    let db = fixture(&catalog_of(&listed), &[("h/X/good.yml", GOOD)]);
    let out = db.path().join("out");
    let (output, peak_kb) =
        with_peak_memory(Command::new(common::binary()).arg("--db").arg(db.path()).arg("--out").arg(&out).arg("ingest"));
    ok(&output);
    let materials = fs::metadata(out.join("materials.csv")).unwrap().len();
    // One row of a few hundred bytes per page (296 MB when each listed every other page).
    assert!(materials < 5000 * 1024, "materials.csv holds {materials} bytes");
    assert!(peak_kb < 400 * 1024, "peak resident memory {peak_kb} kB");
    let first = &common::csv_rows(&out.join("materials.csv"))[0];
    assert_eq!(first["shared_with"], "h/X/p1; h/X/p2; h/X/p3; h/X/p4; h/X/p5; h/X/p6; h/X/p7; h/X/p8; … and 4991 more");
}

/// The output of a command and its peak resident memory in kB (the kernel's count).
// The child is reaped by wait4 (for its resource use), not by `Child::wait`.
#[allow(clippy::zombie_processes)]
fn with_peak_memory(command: &mut Command) -> (Output, i64) {
    let child = command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let pid = child.id() as libc::pid_t;
    let mut stderr = child.stderr.unwrap();
    let mut stdout = child.stdout.unwrap();
    let reader = std::thread::spawn(move || {
        let mut text = Vec::new();
        stderr.read_to_end(&mut text).unwrap();
        text
    });
    let mut out_text = Vec::new();
    stdout.read_to_end(&mut out_text).unwrap();
    let err_text = reader.join().unwrap();
    let mut status = 0;
    // SAFETY: wait4 on our own child, with valid pointers.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    assert_eq!(unsafe { libc::wait4(pid, &mut status, 0, &mut usage) }, pid);
    use std::os::unix::process::ExitStatusExt;
    (Output { status: std::process::ExitStatus::from_raw(status), stdout: out_text, stderr: err_text }, usage.ru_maxrss)
}

/// YAML nested past the readers' bound is refused at once, with its reason: the
/// catalog (the run cannot go on, and says why) and a data file (the page is excluded).
#[test]
fn deep_nesting_is_refused_with_its_reason() {
    let deep = |levels: usize| format!("{}1{}", "[".repeat(levels), "]".repeat(levels));
    let page = format!("DATA:\n  - type: tabulated n\n    data: |\n        0.3 1.5\n        0.8 1.5\nCOMMENTS: {}\n", deep(1_000_000));
    let db = fixture(
        &catalog_of(&[("good", "h/X/good.yml"), ("deep", "h/X/deep.yml")]),
        &[("h/X/good.yml", GOOD), ("h/X/deep.yml", page.as_bytes())],
    );
    let out = db.path().join("out");
    ok(&nklut_bounded(db.path(), &out, &["ingest"]));
    assert_eq!(excluded_reason(&out, "h/X/deep"), "nesting-too-deep");
    let catalog = format!("{}\n{}", catalog_of(&[("good", "h/X/good.yml")]), format_args!("- SHELF: d\n  content: {}\n", deep(100_000)));
    fs::write(db.path().join("catalog-nk.yml"), catalog).unwrap();
    let stderr = failed(&nklut_bounded(db.path(), &out, &["ingest"]));
    assert!(stderr.contains("nesting-too-deep") && stderr.contains("catalog-nk.yml"), "{stderr}");
}

/// A formula's range must be finite numbers (no `inf` reaches a table).
#[test]
fn a_formula_range_to_infinity_is_refused() {
    let page = b"DATA:\n  - type: formula 2\n    wavelength_range: 0.3 inf\n    coefficients: 0 1.0 0.01\n";
    let words = b"DATA:\n  - type: formula 2\n    wavelength_range: 0.3 x 2.0\n    coefficients: 0 1.0 0.01\n";
    let db = fixture(
        &catalog_of(&[("inf", "h/X/inf.yml"), ("words", "h/X/words.yml"), ("good", "h/X/good.yml")]),
        &[("h/X/inf.yml", page), ("h/X/words.yml", words), ("h/X/good.yml", GOOD)],
    );
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest"]));
    assert_eq!(excluded_reason(&out, "h/X/inf"), "too-few-coefficients");
    assert_eq!(excluded_reason(&out, "h/X/words"), "too-few-coefficients");
    let materials = fs::read_to_string(out.join("materials.csv")).unwrap();
    assert_eq!(common::csv_rows(&out.join("materials.csv")).len(), 1);
    assert!(common::non_finite_cells(&materials).is_empty(), "{materials}");
}

/// No single catalog entry disables a command: `..` is a bad id, and ids that
/// differ in case or in `__` against `/` bake to strips of their own.
#[test]
fn odd_page_ids_disable_no_command() {
    let pages = [("good", "h/X/good.yml"), ("..", "h/X/good.yml"), ("J", "h/X/j1.yml"), ("j", "h/X/j2.yml")];
    let mut catalog = catalog_of(&pages);
    catalog.push_str("    - BOOK: X__Y\n      content:\n        - PAGE: z\n          data: h/X/z1.yml\n    - BOOK: X\n      content:\n        - PAGE: Y__z\n          data: h/X/z2.yml\n");
    let files: Vec<(&str, &[u8])> =
        ["h/X/good.yml", "h/X/j1.yml", "h/X/j2.yml", "h/X/z1.yml", "h/X/z2.yml"].into_iter().map(|f| (f, GOOD)).collect();
    let db = fixture(&catalog, &files);
    let out = db.path().join("out");
    for command in ["ingest", "colors", "validate", "bake", "report"] {
        ok(&nklut(db.path(), &out, &[command]));
    }
    assert_eq!(excluded_reason(&out, "h/X/.."), "bad-page-id");
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(out.join("luts/manifest.json")).unwrap()).unwrap();
    let strips: Vec<String> =
        manifest["textures"][0]["rows"].as_array().unwrap().iter().map(|r| r["strip_file"].as_str().unwrap().to_string()).collect();
    assert_eq!(strips.len(), 5);
    let distinct: std::collections::BTreeSet<String> = strips.iter().map(|s| s.to_lowercase()).collect();
    assert_eq!(distinct.len(), 5, "{strips:?}");
    for strip in &strips {
        assert!(out.join("luts").join(strip).is_file(), "{strip} was not written");
    }
}

/// `report.md` shows a page id holding HTML as text.
#[test]
fn report_markdown_shows_html_in_ids_as_text() {
    let id = "<img src=x onerror=alert(1)>";
    let db = fixture(&catalog_of(&[(id, "h/X/good.yml")]), &[("h/X/good.yml", GOOD)]);
    let out = db.path().join("out");
    for command in ["ingest", "report"] {
        ok(&nklut(db.path(), &out, &[command]));
    }
    let markdown = fs::read_to_string(out.join("report/report.md")).unwrap();
    assert!(!markdown.contains("<img"), "raw HTML in report.md");
    assert!(markdown.contains("&lt;img src=x onerror=alert(1)&gt;"));
}

/// Runs into one output folder take turns; each leaves one whole set, and the
/// tables are never lost.
#[test]
fn concurrent_ingests_into_one_folder_leave_one_whole_set() {
    let pages: Vec<(String, String)> = (0..400).map(|i| (format!("p{i}"), format!("h/X/p{i}.yml"))).collect();
    let listed: Vec<(&str, &str)> = pages.iter().map(|(id, data)| (id.as_str(), data.as_str())).collect();
    let files: Vec<(&str, &[u8])> = pages.iter().map(|(_, data)| (data.as_str(), GOOD)).collect();
    let db = fixture(&catalog_of(&listed), &files);
    let out = db.path().join("out");
    let whole = db.path().join("whole");
    ok(&nklut(db.path(), &whole, &["ingest"]));
    let expected = ingest_set(&whole);
    for round in 0..10 {
        let spawn = || {
            Command::new(common::binary())
                .arg("--db")
                .arg(db.path())
                .arg("--out")
                .arg(&out)
                .arg("ingest")
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (a, b) = (spawn(), spawn());
        for child in [a, b] {
            let output = child.wait_with_output().unwrap();
            let stderr = String::from_utf8_lossy(&output.stderr);
            assert!(output.status.success(), "round {round}: {stderr}");
        }
        assert!(ingest_set(&out) == expected, "round {round}: the folder does not hold one whole set");
        let generations = fs::read_dir(out.join(".sets")).unwrap().filter(|e| e.as_ref().unwrap().file_type().unwrap().is_dir()).count();
        assert_eq!(generations, 1, "round {round}");
    }
}

/// A write that fails (here: past a file-size limit, as on a full disk) removes
/// its generation and leaves the previous set.
#[cfg(target_os = "linux")]
#[test]
fn a_failed_write_leaves_no_generation_behind() {
    use std::os::unix::process::CommandExt;
    let db = hostile();
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest", "--page", "h/X/good"]));
    let before = ingest_set(&out);
    let mut command = Command::new(common::binary());
    command.arg("--db").arg(db.path()).arg("--out").arg(&out).arg("ingest");
    // SAFETY: between fork and exec only async-signal-safe calls: setrlimit and signal.
    unsafe {
        command.pre_exec(|| {
            // Files stop at 512 bytes; the write past it fails (EFBIG) instead of killing.
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            let limit = libc::rlimit { rlim_cur: 512, rlim_max: libc::RLIM_INFINITY };
            libc::setrlimit(libc::RLIMIT_FSIZE, &limit);
            Ok(())
        });
    }
    let output = command.output().unwrap();
    assert_eq!(exit_0_or_1(&output), 1, "{}", String::from_utf8_lossy(&output.stderr));
    assert!(ingest_set(&out) == before, "the previous set changed");
    let generations: Vec<String> = fs::read_dir(out.join(".sets"))
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(generations.len(), 1, "{generations:?}");
}

/// Bake and report are published as sets: a kill at any step leaves the previous
/// folder or the new one whole, never none.
#[test]
fn killed_bakes_and_reports_leave_a_whole_folder() {
    let db = hostile();
    let out = db.path().join("out");
    for command in ["ingest", "colors", "validate"] {
        ok(&nklut(db.path(), &out, &[command]));
    }
    for (command, folder, small, large) in [
        ("bake", "luts", ["bake", "--size", "8"], ["bake", "--size", "16"]),
        ("report", "report", ["report", "--page", "h/X/good"], ["report", "--page", "h/X/bom"]),
    ] {
        ok(&nklut(db.path(), &out, &small));
        let a = folder_hashes(&out.join(folder));
        ok(&nklut(db.path(), &out, &large));
        let b = folder_hashes(&out.join(folder));
        assert!(a != b && !a.is_empty(), "{command}: the two runs must differ");
        for step in ["staged", "switched", "linked"] {
            ok(&nklut(db.path(), &out, &small));
            let killed = Command::new(common::binary())
                .env("NKLUT_CRASH_AT", step)
                .arg("--db")
                .arg(db.path())
                .arg("--out")
                .arg(&out)
                .args(large)
                .output()
                .unwrap();
            assert!(!killed.status.success(), "{command} {step}: the run should have been killed");
            let now = folder_hashes(&out.join(folder));
            assert!(
                now == if step == "staged" { a.clone() } else { b.clone() },
                "{command}: after a kill at {step} the folder is not one whole run"
            );
        }
    }
}

/// Every file below `dir` (following the set's link) and its bytes.
fn folder_hashes(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut found = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(folder) = stack.pop() {
        let Ok(entries) = fs::read_dir(&folder) else { continue };
        for entry in entries {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                found.insert(path.strip_prefix(dir).unwrap().to_string_lossy().into_owned(), fs::read(&path).unwrap());
            }
        }
    }
    found
}
