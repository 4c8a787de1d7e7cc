//! What is remembered between commands of one output folder (the unit tests of `memo`:
//! another executable's or a damaged file is not read):
//! - the spectral curves (`<out>/.cache/spectral-curves.bin`): `colors` writes them,
//!   `params` and `bake` read them and write the same bytes as they do without them, and a
//!   damaged memo is not read;
//! - the error integrals (`<out>/.cache/error-integrals.bin`): a second `validate` into the
//!   folder measures nothing and writes the bytes of the first, seconds included; without
//!   the memo it measures again and writes the same figures;
//! - the `nvidia` fits (`<out>/.cache/nvidia-fits.bin`): `validate` writes them, `report`
//!   reads them and writes the same bytes as it does without them;
//! - the effective channel indices (`<out>/.cache/effective-fits.bin`): `colors` writes
//!   them, `bake` reads them and writes the same bytes as it does without them.

mod common;

use std::fs;
use std::path::Path;

use common::{database, files, scratch};
use nklut::bake::{BakeRequest, Source};
use nklut::color::memo::{EffectiveFits, FITS_PATH, MEMO_PATH};
use nklut::fresnel::Method;
use nklut::ingest::{Config, Selection};
use nklut::memo::Kind;
use nklut::validate::{Strategy, ValidateRequest};

const PAGES: [&str; 4] = ["3d/metals/gold", "3d/metals/copper", "3d/glass/BK7", "3d/liquids/water"];

fn selection() -> Selection {
    Selection::pages(PAGES)
}

fn colors(out: &Path) {
    nklut::colors::command(&database(), &selection(), &Config::default(), out, 64).unwrap();
}

fn params(out: &Path) {
    nklut::params::command(&database(), &selection(), &Config::default(), &Default::default(), out).unwrap();
}

fn bake(out: &Path) {
    let request = BakeRequest {
        selection: selection(),
        reading: Config::default(),
        size: 64,
        sources: vec![Source::ThreeChannel, Source::Spectral],
        encodings: vec![],
        layouts: vec![],
    };
    nklut::bake::run(&database(), out, &request).unwrap();
}

/// Every output file under `out` (the memo aside) and a hash of its bytes, by relative
/// path.
fn outputs(out: &Path) -> Vec<(String, u64)> {
    let mut all: Vec<(String, u64)> = files(out)
        .into_iter()
        .filter(|p| p.is_file())
        .map(|p| p.strip_prefix(out).unwrap().to_string_lossy().into_owned())
        .filter(|name| !name.starts_with(".cache") && !name.starts_with(".sets"))
        .map(|name| {
            let mut hasher = std::hash::DefaultHasher::new();
            std::hash::Hasher::write(&mut hasher, &fs::read(out.join(&name)).unwrap());
            (name, std::hash::Hasher::finish(&hasher))
        })
        .collect();
    all.sort();
    all
}

#[test]
fn params_and_bake_read_the_curves_colors_remembered_and_write_the_same_bytes() {
    let remembered = scratch("memo-remembered");
    colors(&remembered);
    let memo = remembered.join(MEMO_PATH);
    let written = fs::read(&memo).expect("colors remembers its curves");
    params(&remembered);
    bake(&remembered);
    assert_eq!(fs::read(&memo).unwrap(), written, "params and bake leave the memo as it was");

    let fresh = scratch("memo-fresh");
    colors(&fresh);
    fs::remove_file(fresh.join(MEMO_PATH)).unwrap();
    fs::remove_file(fresh.join(FITS_PATH)).unwrap();
    params(&fresh);
    bake(&fresh);
    assert_eq!(outputs(&remembered), outputs(&fresh));
    assert!(!outputs(&fresh).is_empty());

    // The curves are read: halve every value in the memo (its checksum made again) and
    // params writes other parameters.
    let halved = scratch("memo-halved");
    fs::create_dir_all(halved.join(MEMO_PATH).parent().unwrap()).unwrap();
    fs::write(halved.join(MEMO_PATH), halve_every_curve(&written)).unwrap();
    params(&halved);
    params(&fresh);
    let table = |out: &Path| fs::read(out.join("engine_params.csv")).unwrap();
    assert_ne!(table(&halved), table(&fresh));
}

#[test]
fn bake_records_the_effective_fits_colors_remembered_with_the_same_bytes() {
    let remembered = scratch("fits-remembered");
    colors(&remembered);
    let fits = remembered.join(FITS_PATH);
    let written = fs::read(&fits).expect("colors remembers its effective fits");
    bake(&remembered);
    assert_eq!(fs::read(&fits).unwrap(), written, "bake leaves the fits as they were");

    let fresh = scratch("fits-fresh");
    colors(&fresh);
    fs::remove_file(fresh.join(FITS_PATH)).unwrap();
    bake(&fresh);
    assert_eq!(outputs(&remembered), outputs(&fresh));
    assert!(!fresh.join(FITS_PATH).exists(), "bake reads the fits, never writes them");

    // The fits are read: with every fitted n halved (a fit is n, k, error), the manifest's
    // effective indices change.
    fs::write(fresh.join(FITS_PATH), halve_values::<EffectiveFits>(&written, |word| word % 3 == 0)).unwrap();
    bake(&fresh);
    assert_ne!(outputs(&remembered), outputs(&fresh));
}

/// The memo's bytes with every curve value (the RGB triples) halved.
fn halve_every_curve(memo: &[u8]) -> Vec<u8> {
    halve_values::<nklut::color::memo::SpectralCurves>(memo, |_| true)
}

#[test]
fn a_damaged_memo_is_not_read() {
    let remembered = scratch("memo-source");
    colors(&remembered);
    let memo = fs::read(remembered.join(MEMO_PATH)).expect("colors remembers its curves");
    let reference = scratch("memo-reference");
    params(&reference);
    assert!(!reference.join(MEMO_PATH).exists(), "params reads the memo, never writes it");
    let mut flipped = memo.clone();
    flipped[memo.len() / 2] ^= 1;
    for (name, bytes) in [("torn", memo[..memo.len() / 2].to_vec()), ("one byte changed", flipped), ("garbage", vec![0x5a; 1000])] {
        let out = scratch(&format!("memo-{name}"));
        fs::create_dir_all(out.join(MEMO_PATH).parent().unwrap()).unwrap();
        fs::write(out.join(MEMO_PATH), &bytes).unwrap();
        params(&out);
        // A changed curve value that was read would change the parameters.
        assert_eq!(outputs(&out), outputs(&reference), "{name}");
        assert_eq!(fs::read(out.join(MEMO_PATH)).unwrap(), bytes, "{name}: params leaves the memo as it was");
    }
}

fn validate(out: &Path) -> String {
    let request = ValidateRequest {
        selection: selection(),
        reading: Config::default(),
        nk: None,
        methods: vec![Method::Schlick, Method::Nvidia, Method::Lut],
        strategy: Strategy::Fast,
    };
    nklut::validate::run(&request, Some(&database()), out).unwrap().summary
}

/// The records of `errors.csv` without its `seconds` column (the time of a measurement).
fn errors_without_seconds(out: &Path) -> Vec<Vec<String>> {
    let mut reader = csv::Reader::from_path(out.join("errors.csv")).unwrap();
    let column = reader.headers().unwrap().iter().position(|c| c == "seconds").expect("a seconds column");
    reader
        .records()
        .map(|record| record.unwrap().iter().enumerate().filter(|(i, _)| *i != column).map(|(_, v)| v.to_string()).collect())
        .collect()
}

#[test]
fn a_second_validate_remembers_every_integral_and_writes_the_same_bytes() {
    // "…; M families measured, R remembered (.cache/error-integrals.bin)"
    let counts = |summary: &str| -> [usize; 2] {
        let tail = summary.lines().next().unwrap().split("; ").nth(1).unwrap().to_string();
        let numbers: Vec<usize> = tail.split([' ', ',']).filter_map(|w| w.parse().ok()).collect();
        [numbers[0], numbers[1]]
    };
    let out = scratch("memo-validate");
    let [families, remembered] = counts(&validate(&out));
    // Per distinct channel index, the analytic family and one per LUT size: seven.
    assert!(families >= 7 * 3 && remembered == 0, "{families} {remembered}");
    let memo = out.join(nklut::validate::memo::MEMO_PATH);
    let written = fs::read(&memo).expect("validate remembers its integrals");
    let before = outputs(&out);

    assert_eq!(counts(&validate(&out)), [0, families], "every family remembered");
    assert_eq!(outputs(&out), before, "errors.* and cost.* with the same bytes, seconds included");
    assert_eq!(fs::read(&memo).unwrap(), written, "nothing new to remember");

    // Without the memo every family is measured again, to the same figures.
    let fresh = scratch("memo-validate-fresh");
    assert_eq!(counts(&validate(&fresh)), [families, 0]);
    assert_eq!(errors_without_seconds(&fresh), errors_without_seconds(&out));
    // A damaged memo is measured past, not read.
    let mut flipped = written.clone();
    flipped[written.len() / 2] ^= 1;
    fs::write(fresh.join(nklut::validate::memo::MEMO_PATH), &flipped).unwrap();
    assert_eq!(counts(&validate(&fresh)), [families, 0]);
    assert_eq!(errors_without_seconds(&fresh), errors_without_seconds(&out));
}

/// The report of `PAGES` after ingest, colors and validate, its pages' bytes by path.
fn report(out: &Path) -> Vec<(String, u64)> {
    nklut::report::command(&database(), out, &selection(), None).unwrap();
    outputs(&out.join(nklut::report::REPORT_DIR))
}

fn stages_before_the_report(out: &Path) {
    let database = database();
    nklut::ingest::write_tables(&nklut::ingest::ingest(&database, &selection(), &Config::default()).unwrap(), out).unwrap();
    colors(out);
    validate(out);
}

#[test]
fn the_report_draws_the_nvidia_fits_validate_kept_with_the_same_bytes() {
    let fits = nklut::fresnel::memo::MEMO_PATH;
    let kept = scratch("memo-fits-kept");
    stages_before_the_report(&kept);
    let written = fs::read(kept.join(fits)).expect("validate keeps its nvidia fits");
    let with_fits = report(&kept);
    assert_eq!(fs::read(kept.join(fits)).unwrap(), written, "the report reads the fits, never writes them");

    let fresh = scratch("memo-fits-fresh");
    stages_before_the_report(&fresh);
    fs::remove_file(fresh.join(fits)).unwrap();
    assert_eq!(report(&fresh), with_fits);
    assert!(!with_fits.is_empty());

    // The fits are read: with every scale halved the nvidia curves, and so the pages,
    // change.
    fs::write(fresh.join(fits), halve_every_scale(&written)).unwrap();
    assert_ne!(report(&fresh), with_fits);
}

/// The fit memo's bytes with every fit's scale halved (a fit is bias, scale, power, RMS
/// residual).
fn halve_every_scale(memo: &[u8]) -> Vec<u8> {
    halve_values::<nklut::fresnel::memo::NvidiaFits>(memo, |word| word % 4 == 1)
}

/// A memo file of kind `K` with the value words that `chosen` picks (by their place in the
/// record's value) halved as f64, and the checksum made again. The layout of
/// `nklut::memo`: the magic line, the identity's length and bytes, the record count, then
/// per record a 32-byte key, the value's length in units of `K::UNIT` words and the
/// words; last, SipHash-1-3 of the rest.
fn halve_values<K: Kind>(memo: &[u8], chosen: impl Fn(usize) -> bool) -> Vec<u8> {
    let mut bytes = memo[..memo.len() - 8].to_vec();
    assert!(bytes.starts_with(K::MAGIC));
    let mut at = K::MAGIC.len();
    at += 8 + word_at(&bytes, at);
    let count = word_at(&bytes, at);
    at += 8;
    for _ in 0..count {
        at += 32;
        let words = K::UNIT * word_at(&bytes, at);
        at += 8;
        for word in 0..words {
            if chosen(word) {
                let value = f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
                bytes[at..at + 8].copy_from_slice(&(0.5 * value).to_le_bytes());
            }
            at += 8;
        }
    }
    assert_eq!(at, bytes.len());
    with_checksum(bytes)
}

/// A memo file's body followed by its checksum: SipHash-1-3 (the standard library's
/// default hasher, keys 0) of the body.
fn with_checksum(mut bytes: Vec<u8>) -> Vec<u8> {
    let mut hasher = std::hash::DefaultHasher::new();
    std::hash::Hasher::write(&mut hasher, &bytes);
    let check = std::hash::Hasher::finish(&hasher);
    bytes.extend_from_slice(&check.to_le_bytes());
    bytes
}

/// The little-endian word at byte `at`.
fn word_at(bytes: &[u8], at: usize) -> usize {
    u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) as usize
}
