//! A fuzz harness over the two texts an outside user hands the pipeline: a database
//! (catalog plus data files) and a scene file. Inputs come from grammars of the real
//! layouts with the defects an attacker tries (ids that are not single values, tables in
//! comments, formulas to infinity, CRLF, tabs, deep nesting, cut and flipped bytes),
//! run in-process through the same stages the binary runs, under a bounded case count
//! (`NKLUT_FUZZ_CASES` scales it), and every case must hold:
//!
//! - no panic: the stage returns a result or a named error (exit status 0 or 1);
//! - every catalog entry is in exactly one of `materials.*` and `excluded.csv`, counted by
//!   an independent walk of the catalog's YAML;
//! - no table cell is NaN or infinite;
//! - a scene that parses has finite, bounded placements, its sizes pass or fail the memory
//!   check by name, and its meshes build a BVH or fail with a named error.
//!
//! Failing cases are kept by proptest in `proptest-regressions/fuzz.txt`, and the hand-made
//! corpus of the attacks found so far (`tests/corpus/`) is replayed first.

use std::fs;
use std::path::Path;

use proptest::prelude::*;
use proptest::test_runner::{Config as ProptestConfig, FileFailurePersistence, TestRunner};

use nklut::db::Database;
use nklut::ingest::{self, Config, Selection};
use nklut::output::Values;
use nklut::scene::Scene;

/// Cases per run, scaled by `NKLUT_FUZZ_CASES` (a factor: 0.1 for a quick look, 10 for a
/// long hunt).
fn cases(base: u32) -> u32 {
    let factor: f64 = std::env::var("NKLUT_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(1.0);
    ((base as f64 * factor).round() as u32).max(1)
}

fn config(base: u32) -> ProptestConfig {
    ProptestConfig {
        cases: cases(base),
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct("proptest-regressions/fuzz.txt"))),
        // Shrinking a database case is slow and the failure is kept either way.
        max_shrink_iters: 200,
        ..ProptestConfig::default()
    }
}

// ------------------------------------------------------------------ database grammar

/// Ids: good ones, and every kind of bad one a catalog can hold.
fn id() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => "[A-Za-z][A-Za-z0-9_-]{0,6}".prop_map(|s| s),
        1 => Just("\"\"".to_string()),
        1 => Just("\"a/b\"".to_string()),
        1 => Just("\"..\"".to_string()),
        1 => Just("\".\"".to_string()),
        1 => Just("~".to_string()),
        1 => Just("[1, 2]".to_string()),
        1 => Just("{x: 1}".to_string()),
        1 => Just("12".to_string()),
        1 => Just("\"J\"".to_string()),
        1 => Just("\"j\"".to_string()),
        1 => Just("\"<img src=x>\"".to_string()),
    ]
}

/// Data paths: files of the case, and paths that leave the database or name nothing.
fn data_path(files: usize) -> impl Strategy<Value = String> {
    prop_oneof![
        8 => (0..files).prop_map(|i| format!("f/p{i}.yml")),
        1 => Just("../../etc/hostname".to_string()),
        1 => Just("/etc/hostname".to_string()),
        1 => Just("f/missing.yml".to_string()),
        1 => Just("\"\"".to_string()),
        1 => Just("[x.yml]".to_string()),
        1 => Just("f".to_string()),
    ]
}

/// One entry of a book's content: a page, a divider, or a mapping that is neither.
#[derive(Clone, Debug)]
enum Entry {
    Page(String, Option<String>),
    Divider,
    Neither,
}

fn entry(files: usize) -> impl Strategy<Value = Entry> {
    prop_oneof![
        8 => (id(), proptest::option::weighted(0.9, data_path(files))).prop_map(|(id, data)| Entry::Page(id, data)),
        1 => Just(Entry::Divider),
        1 => Just(Entry::Neither),
    ]
}

/// Shelves of books of entries, each with its id as written.
type Shelves = Vec<(String, Vec<(String, Vec<Entry>)>)>;

/// A catalog: shelves of books of entries (every shelf and book has content).
fn catalog(files: usize) -> impl Strategy<Value = Shelves> {
    let book = (id(), proptest::collection::vec(entry(files), 1..5));
    let shelf = (id(), proptest::collection::vec(book, 1..3));
    proptest::collection::vec(shelf, 1..3)
}

fn catalog_text(shelves: &Shelves) -> String {
    let mut text = String::from("- DIVIDER: \"top\"\n");
    for (shelf, books) in shelves {
        text.push_str(&format!("- SHELF: {shelf}\n  name: \"S\"\n  content:\n"));
        for (book, entries) in books {
            text.push_str(&format!("    - BOOK: {book}\n      content:\n"));
            for entry in entries {
                match entry {
                    Entry::Page(id, data) => {
                        text.push_str(&format!("        - PAGE: {id}\n          name: \"n\"\n"));
                        if let Some(data) = data {
                            text.push_str(&format!("          data: {data}\n"));
                        }
                    }
                    Entry::Divider => text.push_str("        - DIVIDER: \"d\"\n"),
                    Entry::Neither => text.push_str("        - name: \"no page\"\n          data: f/p0.yml\n"),
                }
            }
        }
    }
    text
}

/// A number as the data files print them, with the odd ones an attacker adds.
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        12 => (0.2f64..2.5).prop_map(|x| format!("{x:.4}")),
        4 => (0.0f64..5.0).prop_map(|x| format!("{x:.3}")),
        1 => Just("-1.5".to_string()),
        1 => Just("0".to_string()),
        1 => Just("1e300".to_string()),
        1 => Just("inf".to_string()),
        1 => Just("nan".to_string()),
        1 => Just("1e-320".to_string()),
        1 => Just("x".to_string()),
    ]
}

/// A DATA block: tables (with the rows sorted most of the time) or formulas.
fn block() -> impl Strategy<Value = String> {
    let rows = |columns: usize| proptest::collection::vec(proptest::collection::vec(number(), columns), 0..8);
    let table =
        (prop_oneof![Just(("nk", 3usize)), Just(("n", 2)), Just(("k", 2))], any::<bool>(), prop_oneof![Just("|"), Just("|-"), Just("|+")])
            .prop_flat_map(move |((kind, columns), sorted, chomp)| {
                (Just(kind), Just(sorted), Just(chomp), rows(columns), proptest::collection::vec(0.3f64..0.9, 0..8))
            })
            .prop_map(|(kind, sorted, chomp, rows, mut wavelengths)| {
                if sorted {
                    wavelengths.sort_by(f64::total_cmp);
                }
                let mut text = format!("  - type: tabulated {kind}\n    data: {chomp}\n");
                for (row, w) in rows.iter().zip(wavelengths.iter().chain(std::iter::repeat(&0.5))) {
                    text.push_str(&format!("        {w:.4} {}\n", row[1..].join(" ")));
                }
                text
            });
    let formula = (1u8..=10, proptest::collection::vec(number(), 0..9), number(), number()).prop_map(|(n, coefficients, lo, hi)| {
        format!("  - type: formula {n}\n    wavelength_range: {lo} {hi}\n    coefficients: {}\n", coefficients.join(" "))
    });
    prop_oneof![3 => table, 2 => formula, 1 => Just("  - type: tabulated xyz\n".to_string())]
}

/// A data file: metadata (with the tricks: a table in a comment, PROPERTIES), blocks,
/// then raw damage (CRLF, a BOM, tabs, deep nesting, a cut, a flipped byte).
fn page() -> impl Strategy<Value = Vec<u8>> {
    let comment = prop_oneof![
        Just(String::new()),
        Just("COMMENTS: \"c\"\n".to_string()),
        Just("COMMENTS: |\n    data: |\n        0.30 9.9\n        0.80 9.9\n".to_string()),
        Just("REFERENCES: |\n    data: |\n      0.5 9.9\n".to_string()),
    ];
    let properties = prop_oneof![
        Just(String::new()),
        Just("PROPERTIES:\n    nd: 1.5230\n    Vd: 58.5\n".to_string()),
        Just("PROPERTIES:\n    nd: x\n".to_string())
    ];
    let damage = prop_oneof![
        6 => Just(Damage::None),
        1 => Just(Damage::Crlf),
        1 => Just(Damage::Bom),
        1 => Just(Damage::Tabs),
        1 => Just(Damage::Deep),
        1 => any::<prop::sample::Index>().prop_map(Damage::Cut),
        1 => (any::<prop::sample::Index>(), any::<u8>()).prop_map(|(at, byte)| Damage::Flip(at, byte)),
    ];
    (comment, proptest::collection::vec(block(), 0..3), properties, damage, any::<bool>()).prop_map(
        |(comment, blocks, properties, damage, comment_first)| {
            let data = format!("DATA:\n{}", blocks.concat());
            let text = if comment_first { format!("{comment}{data}{properties}") } else { format!("{data}{comment}{properties}") };
            damage.apply(text.into_bytes())
        },
    )
}

#[derive(Clone, Debug)]
enum Damage {
    None,
    Crlf,
    Bom,
    Tabs,
    Deep,
    Cut(prop::sample::Index),
    Flip(prop::sample::Index, u8),
}

impl Damage {
    fn apply(&self, mut bytes: Vec<u8>) -> Vec<u8> {
        match self {
            Damage::None => bytes,
            Damage::Crlf => String::from_utf8_lossy(&bytes).replace('\n', "\r\n").into_bytes(),
            Damage::Bom => [b"\xEF\xBB\xBF".as_slice(), &bytes].concat(),
            Damage::Tabs => String::from_utf8_lossy(&bytes).replacen("    ", "\t", 2).into_bytes(),
            Damage::Deep => {
                bytes.extend_from_slice(format!("X: {}1{}\n", "[".repeat(5000), "]".repeat(5000)).as_bytes());
                bytes
            }
            Damage::Cut(at) => {
                if !bytes.is_empty() {
                    bytes.truncate(at.index(bytes.len()));
                }
                bytes
            }
            Damage::Flip(at, byte) => {
                if !bytes.is_empty() {
                    let i = at.index(bytes.len());
                    bytes[i] = *byte;
                }
                bytes
            }
        }
    }
}

/// The catalog entries an independent walk of the YAML finds, by the catalog's documented
/// rules (README, "What ingest does"): every item of a book's content that is not a
/// DIVIDER is an entry (under every shelf and book that is not a divider); an entry whose
/// SHELF, BOOK and PAGE are usable ids (single values; not empty, `.` or `..`; no '/' or
/// control character) and whose data is a single value or absent is a page, and a page
/// listed again under its id with the same data file is the same page, counted once.
fn entries_in(text: &str) -> Option<usize> {
    use serde_norway::Value;
    let root: Value = serde_norway::from_str(text).ok()?;
    let content = |v: &Value| v.get("content").and_then(Value::as_sequence).cloned().unwrap_or_default();
    let text_of = |v: Option<&Value>| -> Option<String> {
        match v? {
            Value::String(s) => Some(s.clone()),
            Value::Number(n) => Some(n.to_string()),
            Value::Bool(b) => Some(b.to_string()),
            _ => None,
        }
    };
    let usable = |id: &str| !id.trim().is_empty() && !id.contains('/') && id != "." && id != ".." && !id.chars().any(char::is_control);
    let mut first_data: std::collections::HashMap<String, String> = std::collections::HashMap::new();
    let mut count = 0;
    // A level without its key is a divider when it has a DIVIDER, else an unusable level
    // whose pages are entries all the same.
    let divider = |v: &Value, key: &str| v.get(key).is_none() && v.get("DIVIDER").is_some();
    for shelf in root.as_sequence()? {
        if divider(shelf, "SHELF") {
            continue;
        }
        for book in content(shelf) {
            if divider(&book, "BOOK") {
                continue;
            }
            for item in content(&book) {
                if divider(&item, "PAGE") {
                    continue;
                }
                let ids = (text_of(shelf.get("SHELF")), text_of(book.get("BOOK")), text_of(item.get("PAGE")));
                let data = match item.get("data") {
                    None => Some(String::new()),
                    value => text_of(value),
                };
                match (ids, data) {
                    ((Some(s), Some(b), Some(p)), Some(data)) if usable(&s) && usable(&b) && usable(&p) => {
                        let id = format!("{s}/{b}/{p}");
                        match first_data.get(&id) {
                            None => {
                                first_data.insert(id, data);
                                count += 1;
                            }
                            Some(first) if *first != data => count += 1,
                            Some(_) => {}
                        }
                    }
                    _ => count += 1,
                }
            }
        }
    }
    Some(count)
}

/// Non-finite float cells of a table, by column.
fn non_finite(table: &nklut::output::Table) -> Vec<String> {
    let mut bad = Vec::new();
    for column in &table.columns {
        if let Values::Float(values) = &column.values {
            if values.iter().flatten().any(|x| !x.is_finite()) {
                bad.push(column.name.clone());
            }
        }
    }
    bad
}

/// One database case: write it, ingest it, check the properties.
fn database_case(catalog: &str, pages: &[Vec<u8>], publish: bool) -> Result<(), TestCaseError> {
    let root = tempfile::tempdir().unwrap();
    fs::write(root.path().join("catalog-nk.yml"), catalog).unwrap();
    fs::create_dir_all(root.path().join("data/f")).unwrap();
    for (i, page) in pages.iter().enumerate() {
        fs::write(root.path().join(format!("data/f/p{i}.yml")), page).unwrap();
    }
    let db = Database::open(root.path()).unwrap();
    let result = std::panic::catch_unwind(|| ingest::ingest(&db, &Selection::All, &Config::default()));
    let Ok(result) = result else { return Err(TestCaseError::fail(format!("ingest panicked on\n{catalog}"))) };
    let Ok(result) = result else { return Ok(()) }; // a named error: status 1
    if let Some(entries) = entries_in(catalog) {
        prop_assert_eq!(result.kept.len() + result.excluded.len(), entries, "entries in the tables vs the catalog:\n{}", catalog);
    }
    prop_assert_eq!(result.kept.len() + result.excluded.len(), result.selected);
    let materials = ingest::materials_table(&result);
    prop_assert!(non_finite(&materials).is_empty(), "non-finite {:?}", non_finite(&materials));
    if publish {
        let out = root.path().join("out");
        let written = std::panic::catch_unwind(|| ingest::write_tables(&result, &out));
        prop_assert!(matches!(written, Ok(Ok(_))), "publishing failed");
    }
    Ok(())
}

#[test]
fn fuzz_databases() {
    let mut runner = TestRunner::new(config(10_000));
    let strategy = (1usize..4).prop_flat_map(|files| (catalog(files), proptest::collection::vec(page(), files), 0u32..100));
    runner.run(&strategy, |(shelves, pages, roll)| database_case(&catalog_text(&shelves), &pages, roll == 0)).unwrap();
}

/// Raw damage to a whole catalog text: a cut or a flipped byte anywhere.
#[test]
fn fuzz_damaged_catalogs() {
    let mut runner = TestRunner::new(config(1_000));
    let strategy = (1usize..3).prop_flat_map(|files| {
        (catalog(files), proptest::collection::vec(page(), files), any::<prop::sample::Index>(), any::<u8>(), any::<bool>())
    });
    runner
        .run(&strategy, |(shelves, pages, at, byte, cut)| {
            let mut text = catalog_text(&shelves).into_bytes();
            let i = at.index(text.len());
            if cut {
                text.truncate(i);
            } else {
                text[i] = byte;
            }
            database_case(&String::from_utf8_lossy(&text), &pages, false)
        })
        .unwrap();
}

// ------------------------------------------------------------------ scene grammar

fn coordinate() -> impl Strategy<Value = String> {
    prop_oneof![
        8 => (-3.0f64..3.0).prop_map(|x| format!("{x:.3}")),
        1 => Just("1e300".to_string()),
        1 => Just("3.5e38".to_string()),
        1 => Just("-1e39".to_string()),
        1 => Just(".nan".to_string()),
        1 => Just(".inf".to_string()),
        1 => Just("1e-300".to_string()),
        1 => Just("0".to_string()),
    ]
}

fn object() -> impl Strategy<Value = String> {
    let mesh = prop_oneof![Just("cube"), Just("sphere"), Just("room"), Just("plane"), Just("missing.obj")];
    let role = prop_oneof![
        Just("material: 3d/metals/gold, methods: [exact, schlick]".to_string()),
        Just("diffuse: [0.5, 0.5, 0.5]".to_string()),
        Just("diffuse: [2, 0, 0]".to_string()),
        Just("material: gold".to_string()),
    ];
    let scale = prop_oneof![
        Just(String::new()),
        coordinate().prop_map(|s| format!(", scale: {s}")),
        (coordinate(), coordinate(), coordinate()).prop_map(|(a, b, c)| format!(", scale: [{a}, {b}, {c}]"))
    ];
    let position = prop_oneof![
        Just(String::new()),
        (coordinate(), coordinate(), coordinate()).prop_map(|(a, b, c)| format!(", position: [{a}, {b}, {c}]"))
    ];
    let subdivide = prop_oneof![4 => Just(String::new()), 1 => (0u32..12).prop_map(|s| format!(", subdivide: {s}"))];
    (mesh, role, scale, position, subdivide)
        .prop_map(|(mesh, role, scale, position, subdivide)| format!("  - {{ mesh: {mesh}, {role}{scale}{position}{subdivide} }}\n"))
}

fn scene_text() -> impl Strategy<Value = String> {
    let size = prop_oneof![Just("16"), Just("0"), Just("8192"), Just("100000"), Just("4294967295"), Just("-1")];
    let effects = prop_oneof![
        Just(String::new()),
        Just("effects: { reflection: { max_depth: [1, 2] }, distance_maps: { size: 16, layers: 2 } }\n".to_string()),
        Just("effects: { reflection: { max_depth: 1 }, distance_maps: { size: 4096, layers: 8 } }\n".to_string()),
        Just("effects: { refraction: { max_depth: 9 } }\n".to_string()),
        Just("effects: { ambient_occlusion: { passes: 2 }, indirect: {} }\n".to_string()),
        Just("effects: {}\n".to_string()),
    ];
    let light = prop_oneof![
        Just(String::new()),
        Just("light: { colour: [1e308, 1, 1] }\n".to_string()),
        Just("light: { direction: [0, 0, 0] }\n".to_string()),
        Just("light: { ambient: [0.2, 0.2, 0.2] }\n".to_string())
    ];
    let frames = prop_oneof![Just("1"), Just("0"), Just("3600"), Just("1000000000"), Just("1e9")];
    let damage = prop_oneof![6 => Just(Damage::None), 1 => Just(Damage::Deep), 1 => any::<prop::sample::Index>().prop_map(Damage::Cut), 1 => (any::<prop::sample::Index>(), any::<u8>()).prop_map(|(a, b)| Damage::Flip(a, b))];
    (size.clone(), size, frames, effects, light, proptest::collection::vec(object(), 0..4), damage).prop_map(
        |(w, h, frames, effects, light, objects, damage)| {
            let text = format!(
                "resolution: [{w}, {h}]\ncamera: {{ frames: {frames} }}\nmeasurements: [image_error]\n{effects}{light}objects:\n{}",
                objects.concat()
            );
            String::from_utf8_lossy(&damage.apply(text.into_bytes())).into_owned()
        },
    )
}

/// One scene case: parse; if it parses, every placed coordinate is bounded, the memory
/// check answers by name, and the built-in meshes build a BVH or a named error.
fn scene_case(text: &str) -> Result<(), TestCaseError> {
    let parsed = std::panic::catch_unwind(|| Scene::parse(text, Path::new("fuzz.yaml")));
    let Ok(parsed) = parsed else { return Err(TestCaseError::fail(format!("Scene::parse panicked on\n{text}"))) };
    let Ok(scene) = parsed else { return Ok(()) };
    for object in &scene.objects {
        let p = object.placement;
        prop_assert!(p.position.iter().all(|x| x.abs() <= nklut::scene::MAX_COORDINATE), "{:?}", p);
        prop_assert!(p.scale.iter().all(|s| *s >= nklut::scene::SCALE_RANGE.0 && *s <= nklut::scene::SCALE_RANGE.1), "{:?}", p);
    }
    let budget = nklut::budget::MemoryBudget::given(1 << 30);
    let checked = std::panic::catch_unwind(|| nklut::effects::command::check_memory(&scene, 64, Some([512, 512]), &budget));
    prop_assert!(checked.is_ok(), "the memory check panicked");
    if checked.unwrap().is_ok() && scene.effects.is_some() {
        let built = std::panic::catch_unwind(|| {
            let meshes: Result<Vec<_>, _> = scene
                .objects
                .iter()
                .map(|o| nklut::scene::mesh::load(&o.mesh, |p| scene.mesh_path(p)).map(|m| m.placed(&o.placement)))
                .collect();
            meshes.map(|meshes| nklut::effects::geometry::Geometry::new(&meshes).map(|g| g.triangles()))
        });
        prop_assert!(built.is_ok(), "building the scene's BVH panicked:\n{}", text);
    }
    Ok(())
}

#[test]
fn fuzz_scenes() {
    let mut runner = TestRunner::new(config(2_000));
    runner.run(&scene_text(), |text| scene_case(&text)).unwrap();
}

// ------------------------------------------------------------------ the corpus

/// The attacks found so far, kept as files: each database under `tests/corpus/databases/`
/// and each scene under `tests/corpus/scenes/` goes through the same checks.
#[test]
fn the_corpus_of_past_attacks_holds() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus");
    let mut databases = 0;
    for entry in fs::read_dir(corpus.join("databases")).unwrap() {
        let dir = entry.unwrap().path();
        let catalog = fs::read_to_string(dir.join("catalog-nk.yml")).unwrap();
        let mut pages = Vec::new();
        while let Ok(page) = fs::read(dir.join(format!("data/f/p{}.yml", pages.len()))) {
            pages.push(page);
        }
        database_case(&catalog, &pages, true).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        databases += 1;
    }
    let mut scenes = 0;
    for entry in fs::read_dir(corpus.join("scenes")).unwrap() {
        let path = entry.unwrap().path();
        scene_case(&fs::read_to_string(&path).unwrap()).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        scenes += 1;
    }
    assert!(databases >= 5 && scenes >= 5, "{databases} databases, {scenes} scenes");
}

// ------------------------------------------------------------------ output folders

/// What is planted under `.sets/` before a publish: at the set's link, at a generation's
/// name, at the lock, or `.sets` itself; as a link to the outside folder (absolute, or
/// climbing with `..`), a dangling link, a file, a folder or a FIFO.
#[derive(Clone, Debug)]
enum Planted {
    OutsideAbsolute,
    OutsideClimbing(usize),
    Dangling,
    File,
    Folder,
    Fifo,
}

fn planted() -> impl Strategy<Value = Planted> {
    prop_oneof![
        Just(Planted::OutsideAbsolute),
        (1usize..8).prop_map(Planted::OutsideClimbing),
        Just(Planted::Dangling),
        Just(Planted::File),
        Just(Planted::Folder),
        Just(Planted::Fifo),
    ]
}

/// Where under the output folder it is planted.
fn planted_at() -> impl Strategy<Value = &'static str> {
    prop_oneof![
        Just(".sets/t"),
        Just(".sets/t-1-x"),
        Just(".sets/t-99"),
        Just(".sets/.lock"),
        Just(".sets"),
        Just("a.csv"),
        Just(".sets/.t.link-1")
    ]
}

/// Plant `what` at `at` under `out` (`outside` is the folder an attacker aims at), where
/// it can be planted: nothing is planted through a link or a file planted before.
fn plant(out: &Path, at: &str, what: &Planted, outside: &Path) {
    let path = out.join(at);
    let parent = path.parent().unwrap();
    let _ = fs::create_dir_all(out);
    if parent != out && fs::symlink_metadata(parent).is_ok() && !fs::symlink_metadata(parent).unwrap().is_dir() {
        return;
    }
    let _ = fs::create_dir(parent);
    let _ = fs::remove_file(&path).or_else(|_| fs::remove_dir_all(&path));
    let _ = match what {
        Planted::OutsideAbsolute => std::os::unix::fs::symlink(outside, &path),
        Planted::OutsideClimbing(ups) => {
            std::os::unix::fs::symlink(Path::new(&"../".repeat(*ups)).join(outside.strip_prefix("/").unwrap()), &path)
        }
        Planted::Dangling => std::os::unix::fs::symlink("no/such/place", &path),
        Planted::File => fs::write(&path, b"planted"),
        Planted::Folder => fs::create_dir_all(path.join("inner")),
        Planted::Fifo => {
            let name = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()).unwrap();
            // SAFETY: mkfifo reads a NUL-terminated path.
            unsafe { libc::mkfifo(name.as_ptr(), 0o600) };
            Ok(())
        }
    };
}

/// Every file under `dir` with its bytes (links not followed).
fn snapshot(dir: &Path) -> std::collections::BTreeMap<std::path::PathBuf, Vec<u8>> {
    let mut files = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(folder) = stack.pop() {
        for entry in fs::read_dir(&folder).unwrap().flatten() {
            let kind = entry.file_type().unwrap();
            if kind.is_dir() {
                stack.push(entry.path());
            } else if kind.is_file() {
                files.insert(entry.path(), fs::read(entry.path()).unwrap());
            }
        }
    }
    files
}

/// A publish into an output folder holding up to three planted entries (after none, one
/// or two earlier publishes): it ends (no hang on a FIFO), the folder an attacker aimed at
/// keeps every file it held, and a publish that succeeds is read back whole.
#[test]
fn fuzz_output_folder_links() {
    let mut runner = TestRunner::new(config(300));
    let strategy = (0usize..3, proptest::collection::vec((planted_at(), planted()), 0..4));
    runner
        .run(&strategy, |(earlier, plants)| {
            let root = tempfile::tempdir().unwrap();
            let (out, outside) = (root.path().join("out"), root.path().join("precious"));
            fs::create_dir_all(outside.join("deep")).unwrap();
            fs::write(outside.join("keep.txt"), b"keep").unwrap();
            fs::write(outside.join("deep/keep.txt"), b"deep").unwrap();
            let before = snapshot(&outside);
            for round in 0..earlier {
                nklut::output::publish_set(&out, "t", &[nklut::output::SetFile::new("a.csv", vec![b'0' + round as u8])]).unwrap();
            }
            for (at, what) in &plants {
                plant(&out, at, what, &outside);
            }
            let published = nklut::output::publish_set(&out, "t", &[nklut::output::SetFile::new("a.csv", b"new".to_vec())]);
            prop_assert_eq!(snapshot(&outside), before.clone(), "the outside folder changed: {:?}", plants);
            if published.is_ok() {
                prop_assert_eq!(fs::read(out.join("a.csv")).ok(), Some(b"new".to_vec()), "{:?}", plants);
            }
            // A second publish, whatever the first did, leaves it too.
            let _ = nklut::output::publish_set(&out, "t", &[nklut::output::SetFile::new("a.csv", b"again".to_vec())]);
            prop_assert_eq!(snapshot(&outside), before, "the outside folder changed: {:?}", plants);
            Ok(())
        })
        .unwrap();
}

// ------------------------------------------------------------------ device results

/// A time cell as a device result may state it: plain, or what an attacker writes.
fn time_cell() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (0.0f64..1e4).prop_map(|x| x.to_string()),
        1 => Just("NaN".to_string()),
        1 => Just("inf".to_string()),
        1 => Just("-inf".to_string()),
        1 => (-1e6f64..0.0).prop_map(|x| x.to_string()),
        1 => Just("1e308".to_string()),
        1 => Just("1.7976931348623157e308".to_string()),
        1 => Just(String::new()),
        1 => "[ -~]{0,6}".prop_map(|s| s.replace([',', '"', '\n'], "")),
    ]
}

/// `--devices` folders with generated `gpu_timing.csv` tables and `*.json` entries of every
/// kind: reading them ends, and what is read holds only times the report can print
/// (finite, 0 to a day).
#[test]
fn fuzz_device_results() {
    let mut runner = TestRunner::new(config(300));
    let strategy = (proptest::collection::vec(time_cell(), 1..6), proptest::option::of(planted()));
    runner
        .run(&strategy, |(times, json)| {
            let root = tempfile::tempdir().unwrap();
            let adapter = root.path().join("adapter");
            fs::create_dir_all(&adapter).unwrap();
            let mut table = String::from("material,method,median_ms\n");
            for (i, time) in times.iter().enumerate() {
                table.push_str(&format!("p{i},exact,{time}\n"));
            }
            fs::write(adapter.join("gpu_timing.csv"), table).unwrap();
            if let Some(what) = &json {
                plant(root.path(), "web.json", what, Path::new("/dev/zero"));
            }
            let read = std::panic::catch_unwind(|| nklut::report::inputs::read_devices(root.path()));
            let Ok(read) = read else { return Err(TestCaseError::fail("read_devices panicked")) };
            let valid =
                |t: &String| t.trim().is_empty() && t.is_empty() || t.parse::<f64>().is_ok_and(|x| (0.0..=86_400_000.0).contains(&x));
            if json.is_none() && times.iter().all(valid) {
                prop_assert!(read.is_ok(), "good times refused: {times:?}: {:?}", read.err());
            }
            if let Ok(devices) = read {
                for tables in devices.values() {
                    for row in &tables.timing.rows {
                        let text = tables.timing.text(row, "median_ms");
                        if !text.is_empty() {
                            let x: f64 = text.parse().unwrap();
                            prop_assert!(x.is_finite() && (0.0..=nklut::report::inputs::MAX_DEVICE_MS).contains(&x), "{text}");
                        }
                    }
                }
                // No planted `*.json` entry (a file that is no result, a link, a folder, a
                // FIFO) is read as a result: each is an error.
                prop_assert!(json.is_none(), "{json:?} was read as a result");
            }
            Ok(())
        })
        .unwrap();
}

// ------------------------------------------------------------------ ids at the length limit

/// Ids around and past a file name's length, of any characters: every file name made
/// from one is at most 160 bytes (the suffix's room left), the same on every call, and two
/// different ids give two different names.
#[test]
fn fuzz_ids_at_the_length_limit() {
    let mut runner = TestRunner::new(config(2_000));
    let part = prop_oneof!["[a-z]{150,170}", "[a-z]{250,300}", "\\PC{40,120}", "[a-z]{155}[é😀]{1,8}"].prop_map(|s| s.replace('/', "_"));
    runner
        .run(&(part.clone(), part), |(a, b)| {
            for id in [&a, &b] {
                let stem = nklut::bake::strip_stem(id);
                prop_assert!(stem.len() <= nklut::output::MAX_STEM_BYTES, "{} bytes", stem.len());
                prop_assert_eq!(&stem, &nklut::bake::strip_stem(id));
                let name = nklut::params::mtlx::valid_name(id);
                prop_assert!(name.len() <= nklut::output::MAX_STEM_BYTES, "{} bytes", name.len());
                let page = nklut::report::context::material_path(&format!("s/b/{id}")).unwrap();
                prop_assert!(page.split('/').all(|part| part.len() <= nklut::output::MAX_STEM_BYTES + ".html".len()), "{page}");
            }
            if a != b {
                prop_assert_ne!(nklut::bake::strip_stem(&a), nklut::bake::strip_stem(&b));
                prop_assert_ne!(nklut::output::bounded_stem(&a, '~'), nklut::output::bounded_stem(&b, '~'));
            }
            Ok(())
        })
        .unwrap();
}
