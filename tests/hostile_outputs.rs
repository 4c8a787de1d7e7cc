//! The `nklut` binary against an output folder and inputs an attacker prepared: links
//! planted under `.sets/` (a generation's link, the lock) that would make a publish remove
//! or truncate what they point at; report inputs that are FIFOs or endless devices; device
//! results with impossible times; wavelengths past what a table can write; page ids past a
//! file name's length; two commands writing one table name into one folder; a memory
//! budget that is not a size; control bytes, newlines and XML-forbidden code points in
//! ids and names. Each is refused by name or written safely; nothing is deleted,
//! truncated, hung or mixed.

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

/// `nklut --db db --out out args…`, given two minutes.
fn nklut(db: &Path, out: &Path, args: &[&str]) -> Output {
    nklut_with(db, out, args, &[])
}

fn nklut_with(db: &Path, out: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = Command::new(common::binary());
    command.arg("--db").arg(db).arg("--out").arg(out).args(args);
    for (key, value) in env {
        command.env(key, value);
    }
    common::bounded(&mut command, Duration::from_secs(120))
}

fn ok(output: &Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "{stderr}");
    stderr
}

/// The run failed with status 1 (not a panic or a signal); its message.
fn failed(output: &Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(1), "{:?}: {stderr}", output.status);
    stderr
}

const GOOD: &[u8] = b"DATA:\n  - type: tabulated nk\n    data: |\n        0.30 1.0 2.0\n        0.50 2.0 3.0\n        0.80 3.0 4.0\n";

/// A database of one shelf `h`, one book `X` and the pages `(id, data file)`, book and
/// pages named `book_name`, with the data files given.
fn database(book_name: &str, pages: &[(&str, &str)], files: &[(&str, &[u8])]) -> tempfile::TempDir {
    let root = tempfile::tempdir().unwrap();
    let mut catalog = format!("- SHELF: h\n  content:\n    - BOOK: X\n      name: {}\n      content:\n", yaml_string(book_name));
    for (id, data) in pages {
        catalog.push_str(&format!(
            "        - PAGE: {}\n          name: {}\n          data: {data}\n",
            yaml_string(id),
            yaml_string(book_name)
        ));
    }
    fs::write(root.path().join("catalog-nk.yml"), catalog).unwrap();
    fs::create_dir_all(root.path().join("data")).unwrap();
    for (path, bytes) in files {
        let path = root.path().join("data").join(path);
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, bytes).unwrap();
    }
    root
}

/// `text` as a YAML double-quoted scalar (controls as `\xNN`, `\uNNNN`).
fn yaml_string(text: &str) -> String {
    let mut out = String::from("\"");
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04x}", c as u32)),
            '\u{FFFE}' | '\u{FFFF}' => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Makes a special entry at a path.
type Plant = dyn Fn(&Path);

fn mkfifo(path: &Path) {
    let name = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: mkfifo reads a NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0, "mkfifo {}", path.display());
}

/// A folder outside the output folder, holding a file, and what it holds.
fn precious() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("keep.txt"), b"precious").unwrap();
    let path = dir.path().to_path_buf();
    (dir, path)
}

fn survives(folder: &Path) {
    assert_eq!(fs::read(folder.join("keep.txt")).unwrap(), b"precious", "{} was touched", folder.display());
}

/// A link planted where a set's current-generation link lives (absolute or climbing out
/// with `..`), where a generation lives, or in place of `.sets` itself: the next publish
/// stops with an error naming the link, and the folder it points at keeps its files.
#[test]
fn planted_set_link_is_refused_and_its_target_survives() {
    let db = database("X", &[("good", "h/X/good.yml")], &[("h/X/good.yml", GOOD)]);
    let (_keep, target) = precious();
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest"]));
    let link = out.join(".sets/ingest");
    let relative = Path::new("../..").join(target.strip_prefix("/").unwrap());
    let climbing = Path::new("../".repeat(target.components().count() + 4).as_str()).join(target.strip_prefix("/").unwrap());
    for planted in [target.clone(), relative, climbing] {
        fs::remove_file(&link).unwrap();
        std::os::unix::fs::symlink(&planted, &link).unwrap();
        let stderr = failed(&nklut(db.path(), &out, &["ingest"]));
        assert!(stderr.contains(&link.display().to_string()), "the error does not name the link: {stderr}");
        survives(&target);
        assert_eq!(fs::read_link(&link).unwrap(), planted, "the planted link was replaced");
    }
    // A link with a generation's name: not followed, not removed.
    fs::remove_file(&link).unwrap();
    let generation = out.join(".sets/ingest-1-planted");
    std::os::unix::fs::symlink(&target, &generation).unwrap();
    let stderr = failed(&nklut(db.path(), &out, &["ingest"]));
    assert!(stderr.contains("ingest-1-planted"), "{stderr}");
    survives(&target);
    fs::remove_file(&generation).unwrap();
    ok(&nklut(db.path(), &out, &["ingest"]));
    // `.sets` itself a link to the folder.
    let other = db.path().join("out2");
    fs::create_dir_all(&other).unwrap();
    std::os::unix::fs::symlink(&target, other.join(".sets")).unwrap();
    let stderr = failed(&nklut(db.path(), &other, &["ingest"]));
    assert!(stderr.contains(".sets is a symbolic link"), "{stderr}");
    survives(&target);
    assert_eq!(fs::read_dir(&target).unwrap().count(), 1, "something was written into the link's target");
}

/// A link planted at `.sets/.lock`: its target is neither truncated nor written, and the
/// run names the link.
#[test]
fn planted_lock_link_is_refused_and_its_target_is_untouched() {
    let db = database("X", &[("good", "h/X/good.yml")], &[("h/X/good.yml", GOOD)]);
    let (_keep, target) = precious();
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest"]));
    let lock = out.join(".sets/.lock");
    fs::remove_file(&lock).unwrap();
    std::os::unix::fs::symlink(target.join("keep.txt"), &lock).unwrap();
    let stderr = failed(&nklut(db.path(), &out, &["ingest"]));
    assert!(stderr.contains(&lock.display().to_string()) && stderr.contains("symbolic link"), "{stderr}");
    survives(&target);
    // A FIFO there does not block the run either.
    fs::remove_file(&lock).unwrap();
    mkfifo(&lock);
    let stderr = failed(&nklut(db.path(), &out, &["ingest"]));
    assert!(stderr.contains(&lock.display().to_string()) && stderr.contains("not a regular file"), "{stderr}");
}

/// An ingested output folder with a scene folder, beside a devices folder with one
/// adapter: every place the report reads a table from.
struct ReportInputs {
    db: tempfile::TempDir,
    out: PathBuf,
    devices: PathBuf,
    adapter: PathBuf,
}

impl ReportInputs {
    fn new() -> ReportInputs {
        let db = database("X", &[("good", "h/X/good.yml")], &[("h/X/good.yml", GOOD)]);
        let out = db.path().join("out");
        ok(&nklut(db.path(), &out, &["ingest"]));
        let devices = db.path().join("devices");
        let adapter = devices.join("adapter");
        fs::create_dir_all(&adapter).unwrap();
        fs::create_dir_all(out.join("scene")).unwrap();
        ReportInputs { db, out, devices, adapter }
    }

    /// The tables: a device's `gpu_timing.csv` and `image_errors.csv` (read only beside a
    /// good `gpu_timing.csv`, the second's flag), a scene's `effects_errors.csv`,
    /// `colors.csv` and `materials.csv`.
    fn tables(&self) -> [(PathBuf, bool); 5] {
        [
            (self.adapter.join("gpu_timing.csv"), false),
            (self.adapter.join("image_errors.csv"), true),
            (self.out.join("scene").join("effects_errors.csv"), false),
            (self.out.join("colors.csv"), false),
            (self.out.join("materials.csv"), false),
        ]
    }

    /// `nklut report --devices …`.
    fn report(&self) -> Output {
        nklut(self.db.path(), &self.out, &["report", "--devices", self.devices.to_str().unwrap()])
    }

    /// The report run with `plant` made at table `input` (what was there put back after).
    fn report_with(&self, (input, with_timing): &(PathBuf, bool), plant: &Plant) -> Output {
        if *with_timing {
            fs::write(self.adapter.join("gpu_timing.csv"), b"material,method,median_ms\nh/X/good,exact,0.5\n").unwrap();
        }
        // `materials.csv` is a link into the published set: the plant takes its place.
        let kept = fs::read(input).ok();
        let _ = fs::remove_file(input);
        plant(input);
        let output = self.report();
        fs::remove_file(input).unwrap();
        if let Some(bytes) = kept {
            fs::write(input, bytes).unwrap();
        }
        let _ = fs::remove_file(self.adapter.join("gpu_timing.csv"));
        output
    }
}

/// A report input as an attacker leaves it: a FIFO with no writer, or a link to /dev/zero
/// (endless); each named file kind of the report is refused by name at once, never read.
#[test]
fn report_inputs_that_are_fifos_or_endless_are_refused_by_name() {
    let inputs = ReportInputs::new();
    for table in &inputs.tables() {
        let kinds: [(&str, &Plant); 2] =
            [("a FIFO", &|p| mkfifo(p)), ("a character device", &|p| std::os::unix::fs::symlink("/dev/zero", p).unwrap())];
        for (kind, plant) in kinds {
            let stderr = failed(&inputs.report_with(table, plant));
            assert!(stderr.contains(&table.0.display().to_string()), "the error does not name {}: {stderr}", table.0.display());
            assert!(stderr.contains(kind), "{stderr}");
        }
    }
    ok(&inputs.report());
}

/// A 100 MB table wherever the report reads one: refused naming the file and its 64 MiB
/// bound, from the size the file states, before a byte of it is read (each file is sparse:
/// 100 MB stated, nothing stored). Whole, such a table took 1.47 GB and 46 s. The minute's
/// bound only guards against a hang.
#[test]
fn report_tables_of_100_mb_are_refused_by_name_before_they_are_read() {
    let inputs = ReportInputs::new();
    for table in &inputs.tables() {
        let start = std::time::Instant::now();
        let stderr = failed(&inputs.report_with(table, &|p| fs::File::create(p).unwrap().set_len(100_000_000).unwrap()));
        assert!(start.elapsed() < Duration::from_secs(60), "{}: {:?}", table.0.display(), start.elapsed());
        assert!(
            stderr.contains(&table.0.display().to_string()) && stderr.contains("more than 67108864 bytes"),
            "{}: {stderr}",
            table.0.display()
        );
    }
    ok(&inputs.report());
}

/// Device results that state NaN, negative or 309-digit times, and `*.json` entries that
/// are not regular files (a FIFO, a link to a device, a link to itself, a folder) or are
/// larger than a result can be: each an error naming the file.
#[test]
fn device_results_with_impossible_times_or_odd_json_entries_are_refused_by_name() {
    let inputs = ReportInputs::new();
    let (devices, adapter) = (&inputs.devices, &inputs.adapter);
    for (time, why) in [
        ("NaN", "not a finite number"),
        ("-500", "below 0"),
        ("1e308", "above the largest"),
        ("inf", "not a finite number"),
        ("abc", "not a number"),
    ] {
        fs::write(adapter.join("gpu_timing.csv"), format!("material,method,median_ms\nh/X/good,exact,{time}\n")).unwrap();
        let stderr = failed(&inputs.report());
        assert!(
            stderr.contains(&adapter.display().to_string()) && stderr.contains("median_ms") && stderr.contains(why),
            "{time}: {stderr}"
        );
        assert!(!stderr.contains(&"0".repeat(300)), "a 309-digit number printed: {stderr}");
    }
    // The runner's list of every sample (`samples_ms`, space-separated): each value checked.
    let samples = |list: &str| format!("material,method,median_ms,samples_ms\nh/X/good,exact,2.5,{list}\n");
    fs::write(adapter.join("gpu_timing.csv"), samples("1.5 2.5 NaN")).unwrap();
    let stderr = failed(&inputs.report());
    assert!(stderr.contains("samples_ms") && stderr.contains("not a finite number"), "{stderr}");
    fs::write(adapter.join("gpu_timing.csv"), samples("1.5 2.5 3.5")).unwrap();
    ok(&inputs.report());
    fs::remove_dir_all(adapter).unwrap();
    let json = devices.join("browser.json");
    let kinds: [(&str, &Plant); 4] = [
        ("a FIFO", &|p| mkfifo(p)),
        ("a character device", &|p| std::os::unix::fs::symlink("/dev/zero", p).unwrap()),
        ("symbolic links", &|p| std::os::unix::fs::symlink(p, p).unwrap()),
        ("a folder", &|p| fs::create_dir(p).unwrap()),
    ];
    for (kind, make) in kinds {
        make(&json);
        let stderr = failed(&inputs.report());
        assert!(stderr.contains(&json.display().to_string()) && stderr.contains(kind), "{kind}: {stderr}");
        let _ = fs::remove_file(&json).or_else(|_| fs::remove_dir(&json));
    }
    fs::write(&json, vec![b' '; (16 << 20) + 1]).unwrap();
    let stderr = failed(&inputs.report());
    assert!(stderr.contains(&json.display().to_string()) && stderr.contains("16777216 bytes"), "{stderr}");
}

/// A row at 1.7976931348623157e308 µm (infinite in nm) or 1e300 µm, or a formula range
/// reaching there: the page is excluded as `wavelength-out-of-range` with its line, the run
/// goes on, and no table holds a number longer than the range's.
#[test]
fn a_wavelength_that_overflows_excludes_its_page_with_a_reason() {
    let row = |um: &str| {
        format!("DATA:\n  - type: tabulated nk\n    data: |\n        0.30 1.0 2.0\n        0.50 2.0 3.0\n        {um} 3.0 4.0\n")
    };
    let (max, huge) = (row("1.7976931348623157e308"), row("1e300"));
    let formula = b"DATA:\n  - type: formula 1\n    wavelength_range: 0.3 1e300\n    coefficients: 0 1.0 0.1\n".as_slice();
    let db = database(
        "X",
        &[("good", "h/X/good.yml"), ("max", "h/X/max.yml"), ("huge", "h/X/huge.yml"), ("formula", "h/X/formula.yml")],
        &[("h/X/good.yml", GOOD), ("h/X/max.yml", max.as_bytes()), ("h/X/huge.yml", huge.as_bytes()), ("h/X/formula.yml", formula)],
    );
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest"]));
    let excluded = common::csv_rows(&out.join("excluded.csv"));
    for page in ["h/X/max", "h/X/huge", "h/X/formula"] {
        let row = excluded.iter().find(|r| r["page"] == page).unwrap_or_else(|| panic!("{page} not excluded: {excluded:?}"));
        assert_eq!(row["reason"], "wavelength-out-of-range", "{row:?}");
    }
    let line = excluded.iter().find(|r| r["page"] == "h/X/max").unwrap()["line"].clone();
    assert_eq!(line, "6", "the row's line");
    let materials = common::csv_rows(&out.join("materials.csv"));
    assert_eq!(materials.iter().map(|r| r["page"].as_str()).collect::<Vec<_>>(), ["h/X/good"]);
    assert_eq!(materials[0]["lambda_max_nm"], "800");
}

/// Page ids of 250 and 300 bytes (two sharing their first 200): params, bake and report
/// succeed for every page, every file name stays within 255 bytes, and the two long ids
/// get two files.
#[test]
fn long_page_ids_name_bounded_files_for_params_bake_and_report() {
    let long_a = format!("{}a", "p".repeat(249));
    let long_b = format!("{}b", "p".repeat(299));
    let db = database(
        "X",
        &[("good", "h/X/good.yml"), (&long_a, "h/X/good2.yml"), (&long_b, "h/X/good3.yml")],
        &[("h/X/good.yml", GOOD), ("h/X/good2.yml", GOOD), ("h/X/good3.yml", GOOD)],
    );
    let out = db.path().join("out");
    for command in [&["ingest"][..], &["params"], &["bake", "--size", "16"], &["report"]] {
        ok(&nklut(db.path(), &out, command));
    }
    let mut names = Vec::new();
    let mut stack = vec![out.clone()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).unwrap() {
            let entry = entry.unwrap();
            let name = entry.file_name().to_string_lossy().into_owned();
            assert!(name.len() <= 255, "{name}");
            if entry.file_type().unwrap().is_dir() {
                stack.push(entry.path());
            }
            names.push(entry.path());
        }
    }
    let paste: Vec<_> =
        names.iter().filter(|p| p.parent().unwrap().ends_with("params") && p.to_string_lossy().contains("nk_h_X_ppp")).collect();
    assert_eq!(paste.len(), 2, "{paste:?}");
    let pages: Vec<_> =
        names.iter().filter(|p| p.extension().is_some_and(|e| e == "html") && p.to_string_lossy().contains("/materials/h/X/ppp")).collect();
    assert_eq!(pages.len(), 2, "{pages:?}");
}

/// `effects_errors.csv` of one command and then of another into the same folder: the
/// second publish is refused, naming the file and both sets, and the first's file stays.
#[test]
fn two_commands_writing_one_table_name_into_one_folder_are_refused() {
    let out = tempfile::tempdir().unwrap();
    let file = |bytes: &[u8]| nklut::output::SetFile::new("effects_errors.csv", bytes.to_vec());
    nklut::output::publish_set(out.path(), "effects", &[file(b"cpu")]).unwrap();
    let error = nklut::output::publish_set(out.path(), "gpu", &[file(b"gpu")]).unwrap_err().to_string();
    assert!(error.contains("effects_errors.csv") && error.contains("\"effects\"") && error.contains("\"gpu\""), "{error}");
    assert_eq!(fs::read(out.path().join("effects_errors.csv")).unwrap(), b"cpu");
    // The same command again replaces its own file.
    nklut::output::publish_set(out.path(), "effects", &[file(b"cpu 2")]).unwrap();
    assert_eq!(fs::read(out.path().join("effects_errors.csv")).unwrap(), b"cpu 2");
}

/// `NKLUT_MEMORY_BUDGET` that is not a size (garbage, a sign, NaN, an exabyte unit, a
/// command after the size, 2⁶⁴) stops the run with an error naming the variable; a size
/// runs.
#[test]
fn memory_budget_that_is_not_a_size_is_an_error_naming_the_variable() {
    let db = database("X", &[("good", "h/X/good.yml")], &[("h/X/good.yml", GOOD)]);
    let out = db.path().join("out");
    for value in ["abc", "-1", "NaN", "16E", "4G;rm -rf /", "18446744073709551616", "0", ""] {
        let stderr = failed(&nklut_with(db.path(), &out, &["ingest"], &[("NKLUT_MEMORY_BUDGET", value)]));
        assert!(stderr.contains("NKLUT_MEMORY_BUDGET") && stderr.contains("is not a memory budget"), "{value:?}: {stderr}");
        assert!(!out.join("materials.csv").exists(), "{value:?} ran");
    }
    ok(&nklut_with(db.path(), &out, &["ingest"], &[("NKLUT_MEMORY_BUDGET", "2G")]));
}

/// A page id holding ESC and BEL (a terminal title sequence) under `--strict`: the error
/// shows them as text, and `excluded.csv` holds no control byte.
#[test]
fn control_bytes_in_ids_reach_no_terminal_or_table_raw() {
    let id = "evil\u{1b}]0;owned\u{7}\u{9b}31m";
    let db = database("X", &[("good", "h/X/good.yml"), (id, "h/X/good.yml")], &[("h/X/good.yml", GOOD)]);
    let out = db.path().join("out");
    let stderr = failed(&nklut(db.path(), &out, &["ingest", "--strict"]));
    assert!(!stderr.contains(['\u{1b}', '\u{7}', '\u{9b}']), "a control byte reached the terminal: {stderr:?}");
    assert!(stderr.contains("\\u{1b}]0;owned\\u{7}"), "{stderr}");
    ok(&nklut(db.path(), &out, &["ingest"]));
    let excluded = fs::read_to_string(out.join("excluded.csv")).unwrap();
    assert!(!excluded.contains(|c: char| c.is_control() && c != '\n'), "{excluded:?}");
    assert!(excluded.contains("evil\\u{1b}]0;owned\\u{7}"), "{excluded}");
}

/// A book name holding a newline and a Markdown heading, and page names holding
/// U+FFFE/U+FFFF and control bytes: `report.md` keeps every table row on its line (no
/// injected heading), and `materials.mtlx` holds only XML 1.0 characters.
#[test]
fn names_with_newlines_and_xml_forbidden_code_points_stay_text() {
    let db = database(
        "Book\u{FFFE}\u{FFFF}\u{1}\n# injected heading\n<script>x</script>",
        &[("good", "h/X/good.yml")],
        &[("h/X/good.yml", GOOD)],
    );
    let out = db.path().join("out");
    for command in ["ingest", "params", "report"] {
        ok(&nklut(db.path(), &out, &[command]));
    }
    let markdown = fs::read_to_string(out.join("report/report.md")).unwrap();
    assert!(!markdown.lines().any(|l| l.starts_with("# injected")), "a heading was injected:\n{markdown}");
    assert!(!markdown.contains("<script>"), "raw HTML in report.md");
    assert!(!markdown.contains(|c: char| c.is_control() && c != '\n'), "a control byte in report.md");
    let mtlx = fs::read_to_string(out.join("materials.mtlx")).unwrap();
    let forbidden: Vec<char> = mtlx.chars().filter(|&c| !nklut::escape::is_xml_char(c)).collect();
    assert!(forbidden.is_empty(), "XML 1.0 forbids {forbidden:?} in materials.mtlx");
}

/// A catalog that is a FIFO: named as such (and not blocked on), not taken for a missing
/// database.
#[test]
fn a_catalog_that_is_a_fifo_is_named_not_taken_for_no_database() {
    let root = tempfile::tempdir().unwrap();
    mkfifo(&root.path().join("catalog-nk.yml"));
    let stderr = failed(&nklut(root.path(), &root.path().join("out"), &["ingest"]));
    assert!(stderr.contains("catalog-nk.yml") && stderr.contains("FIFO"), "{stderr}");
    assert!(!stderr.contains("no refractiveindex.info database"), "{stderr}");
}

/// A report input that fits its size bound but not the memory its rows would take parsed
/// (16 bytes a byte): refused naming the file and the budget, before it is parsed.
#[test]
fn a_table_larger_than_the_budget_holds_is_refused_before_it_is_parsed() {
    let db = database("X", &[("good", "h/X/good.yml")], &[("h/X/good.yml", GOOD)]);
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest"]));
    let colors = out.join("colors.csv");
    let mut table = String::from("page,x\n");
    while table.len() < 2 << 20 {
        table.push_str("h/X/good,1\n");
    }
    fs::write(&colors, &table).unwrap();
    // 2 MiB × 16 = 32 MiB parsed, over a 16 MiB budget.
    let stderr = failed(&nklut_with(db.path(), &out, &["report"], &[("NKLUT_MEMORY_BUDGET", "16M")]));
    assert!(stderr.contains(&colors.display().to_string()) && stderr.contains("more than the memory budget"), "{stderr}");
}

/// `errors.csv`, read whole up to 1 GiB and filtered to the rows shown: a 200 MB one under a
/// 100 MB budget is refused naming the file and the budget before a byte is read.
#[test]
fn an_errors_table_larger_than_the_budget_is_refused_before_it_is_read() {
    let db = database("X", &[("good", "h/X/good.yml")], &[("h/X/good.yml", GOOD)]);
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest"]));
    let errors = out.join("errors.csv");
    let _ = fs::remove_file(&errors);
    fs::File::create(&errors).unwrap().set_len(200_000_000).unwrap();
    let start = std::time::Instant::now();
    let stderr = failed(&nklut_with(db.path(), &out, &["report"], &[("NKLUT_MEMORY_BUDGET", "100M")]));
    assert!(start.elapsed() < Duration::from_secs(60), "{:?}", start.elapsed());
    assert!(stderr.contains(&errors.display().to_string()) && stderr.contains("more than the memory budget"), "{stderr}");
}

/// A wavelength of −1e308 µm and an n of −1e308: excluded with details that write the
/// number in exponent form, never 309 digits.
#[test]
fn huge_numbers_in_details_are_written_in_exponent_form() {
    let negative_wavelength = b"DATA:\n  - type: tabulated nk\n    data: |\n        -1e308 1.0 2.0\n        0.50 2.0 3.0\n".as_slice();
    let negative_n =
        b"DATA:\n  - type: tabulated nk\n    data: |\n        0.30 -1e308 2.0\n        0.50 -1e308 3.0\n        0.80 -1e308 4.0\n"
            .as_slice();
    let db = database(
        "X",
        &[("good", "h/X/good.yml"), ("wavelength", "h/X/w.yml"), ("n", "h/X/n.yml")],
        &[("h/X/good.yml", GOOD), ("h/X/w.yml", negative_wavelength), ("h/X/n.yml", negative_n)],
    );
    let out = db.path().join("out");
    ok(&nklut(db.path(), &out, &["ingest"]));
    let excluded = common::csv_rows(&out.join("excluded.csv"));
    let detail =
        |page: &str| excluded.iter().find(|r| r["page"] == page).unwrap_or_else(|| panic!("{page}: {excluded:?}"))["detail"].clone();
    assert_eq!(detail("h/X/wavelength"), "wavelength -1e308 µm is not positive");
    assert!(detail("h/X/n").contains("-1e308") && !detail("h/X/n").contains(&"0".repeat(100)), "{}", detail("h/X/n"));
}

/// Text a spreadsheet would take for a formula — a book and page name `=HYPERLINK(…)`, a
/// shelf `@h` that starts every page id, a page `-2+3`, a page name `+1+2` — is written to
/// `materials.csv` and `excluded.csv` behind a single quote, and every other cell that
/// starts with `=`, `+`, `-` or `@` is a finite number; the report reads the ids and names
/// back without the quote (its page is found, its Markdown shows the name as written).
#[test]
fn formula_text_in_tables_is_quoted_and_read_back_without_the_quote() {
    let name = "=HYPERLINK(\"http://example.invalid\",\"x\")";
    let root = tempfile::tempdir().unwrap();
    let catalog = format!(
        "- SHELF: '@h'\n  content:\n    - BOOK: X\n      name: {name}\n      content:\n        - PAGE: good\n          name: {name}\n          data: h/X/good.yml\n        - PAGE: '-2+3'\n          name: '+1+2'\n          data: h/X/missing.yml\n",
        name = yaml_string(name)
    );
    fs::write(root.path().join("catalog-nk.yml"), catalog).unwrap();
    fs::create_dir_all(root.path().join("data/h/X")).unwrap();
    fs::write(root.path().join("data/h/X/good.yml"), GOOD).unwrap();
    let out = root.path().join("out");
    ok(&nklut(root.path(), &out, &["ingest"]));
    for table in ["materials.csv", "excluded.csv"] {
        for row in common::csv_rows(&out.join(table)) {
            for (column, cell) in &row {
                if cell.starts_with(['=', '+', '-', '@', '\t', '\r']) {
                    assert!(cell.parse::<f64>().is_ok_and(f64::is_finite), "{table} {column}: {cell:?}");
                }
            }
        }
    }
    let materials = common::csv_rows(&out.join("materials.csv"));
    assert_eq!(materials.len(), 1);
    assert_eq!(materials[0]["page"], "'@h/X/good");
    assert_eq!(materials[0]["catalog_name"], format!("'{name}"));
    let excluded = common::csv_rows(&out.join("excluded.csv"));
    assert_eq!(excluded.iter().map(|r| r["page"].as_str()).collect::<Vec<_>>(), ["'@h/X/-2+3"]);
    ok(&nklut(root.path(), &out, &["report", "--page", "@h/X/good"]));
    let markdown = fs::read_to_string(out.join("report/report.md")).unwrap();
    assert!(markdown.contains("@h/X/good") && !markdown.contains("'@h/X/good"), "{markdown}");
    assert!(markdown.contains(&format!("| {name} |")), "{markdown}");
}
