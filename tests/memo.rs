//! The spectral curves remembered between commands (`<out>/.cache/spectral-curves.bin`):
//! `colors` writes them, `params` and `bake` read them and write the same bytes as they do
//! without them, and a damaged memo is not read (one of another executable neither: see
//! the unit tests of `color::memo`).

mod common;

use std::fs;
use std::path::Path;

use common::{database, files, scratch};
use nklut::bake::{BakeRequest, Source};
use nklut::color::memo::MEMO_PATH;
use nklut::ingest::{Config, Selection};

const PAGES: [&str; 4] = ["3d/metals/gold", "3d/metals/copper", "3d/glass/BK7", "3d/liquids/water"];

fn selection() -> Selection {
    Selection { pages: PAGES.iter().map(|p| p.to_string()).collect(), ..Default::default() }
}

fn colors(out: &Path) {
    nklut::color::command(&database(), &selection(), &Config::default(), out, 64).unwrap();
}

fn params(out: &Path) {
    nklut::params::command(&database(), &selection(), &Config::default(), out).unwrap();
}

fn bake(out: &Path) {
    let request = BakeRequest { selection: selection(), reading: Config::default(), size: 64, sources: vec![Source::ThreeChannel, Source::Spectral], encodings: vec![], layouts: vec![] };
    nklut::bake::run(&database(), out, &request).unwrap();
}

/// Every output file under `out` (the memo aside) and its bytes, by relative path.
fn outputs(out: &Path) -> Vec<(String, Vec<u8>)> {
    let mut all: Vec<(String, Vec<u8>)> = files(out)
        .into_iter()
        .filter(|p| p.is_file())
        .map(|p| p.strip_prefix(out).unwrap().to_string_lossy().into_owned())
        .filter(|name| !name.starts_with(".cache") && !name.starts_with(".sets"))
        .map(|name| (name.clone(), fs::read(out.join(&name)).unwrap()))
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
    // params and bake find every curve they need (the nodes; the 64 texel centres): the
    // memo does not grow, so it is not written again.
    params(&remembered);
    bake(&remembered);
    assert_eq!(fs::read(&memo).unwrap(), written, "the memo grew: a curve was computed again");

    let fresh = scratch("memo-fresh");
    colors(&fresh);
    fs::remove_file(fresh.join(MEMO_PATH)).unwrap();
    params(&fresh);
    bake(&fresh);
    assert_eq!(outputs(&remembered), outputs(&fresh));
    assert!(!outputs(&fresh).is_empty());
}

#[test]
fn a_damaged_memo_is_not_read() {
    let reference = scratch("memo-reference");
    params(&reference);
    let memo = fs::read(reference.join(MEMO_PATH)).expect("params remembers the curves it computed");
    let mut flipped = memo.clone();
    flipped[memo.len() / 2] ^= 1;
    for (name, bytes) in [("torn", memo[..memo.len() / 2].to_vec()), ("one byte changed", flipped), ("garbage", vec![0x5a; 1000])] {
        let out = scratch(&format!("memo-{name}"));
        fs::create_dir_all(out.join(MEMO_PATH).parent().unwrap()).unwrap();
        fs::write(out.join(MEMO_PATH), &bytes).unwrap();
        params(&out);
        assert_eq!(outputs(&out), outputs(&reference), "{name}");
        // Not read, so every curve was computed and the memo written anew.
        assert_eq!(fs::read(out.join(MEMO_PATH)).unwrap(), memo, "{name}");
    }
}
