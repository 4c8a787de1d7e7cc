//! `nklut bake` end to end on the linked database (`make db`): round trip of every written
//! file, byte-identical reruns, all-or-nothing publishing, and argument errors up front.

mod common;

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

use sha2::{Digest, Sha256};

use common::{database, scratch};
use nklut::bake::{self, files, texel, BakeRequest, Encoding, Source};
use nklut::ingest::{self, Selection};

const PAGES: [&str; 3] = ["3d/metals/gold", "3d/glass/BK7", "main/Au/Johnson"];

fn args(pages: &[&str], size: usize) -> BakeRequest {
    BakeRequest {
        selection: Selection { pages: pages.iter().map(|p| p.to_string()).collect(), shelves: vec![] },
        reading: ingest::Config::default(),
        size,
        encodings: vec![],
        sources: vec![],
        layouts: vec![],
    }
}

/// Relative path → SHA-256 of every file under `dir` as a reader sees it (the set's links
/// followed, the generations under `.sets/` not listed again), sorted.
fn hashes(dir: &Path) -> BTreeMap<String, String> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, String>) {
        for entry in fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.file_name().is_some_and(|n| n == ".sets") {
                continue;
            }
            if path.is_dir() {
                walk(root, &path, out);
            } else {
                let digest = Sha256::digest(fs::read(&path).unwrap());
                let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
                out.insert(path.strip_prefix(root).unwrap().to_string_lossy().into_owned(), hex);
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

#[test]
fn every_written_file_reads_back_as_the_baked_values() {
    let out = scratch("roundtrip");
    let size = 64;
    bake::run(&database(), &out, &args(&PAGES, size)).unwrap();
    let luts = out.join("luts");
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(luts.join("manifest.json")).unwrap()).unwrap();
    let kept = ingest::ingest(
        &database(),
        &Selection { pages: PAGES.map(String::from).to_vec(), shelves: vec![] },
        &nklut::ingest::Config::default(),
    )
    .unwrap()
    .kept;
    let curves: Vec<_> = kept.iter().map(|p| bake::curve(Source::ThreeChannel, p, size)).collect();
    let mut checked = 0;
    for set in manifest["textures"].as_array().unwrap() {
        let encoding = Encoding::ALL.into_iter().find(|e| e.name() == set["encoding"]).unwrap();
        let expected: Vec<texel::Texels> = curves.iter().map(|c| texel::quantise(encoding, c).texels).collect();
        let atlas = files::decode(encoding, &fs::read(luts.join(set["atlas"]["file"].as_str().unwrap())).unwrap()).unwrap();
        assert_eq!((atlas.width, atlas.height), (size, kept.len()));
        assert_eq!(atlas.texels, texel::Texels::concat(encoding, &expected));
        for (r, row) in set["rows"].as_array().unwrap().iter().enumerate() {
            assert_eq!(row["page"], kept[r].id());
            let strip = files::decode(encoding, &fs::read(luts.join(row["strip_file"].as_str().unwrap())).unwrap()).unwrap();
            assert_eq!((strip.width, strip.height), (size, 1));
            assert_eq!(strip.texels, expected[r]);
            // Within the quantisation step of the in-memory (f64) values.
            let stored = strip.texels.decode(encoding);
            for (i, &got) in stored.iter().enumerate() {
                let want = curves[r][i % 3][i / 3];
                let (got, want) = match encoding {
                    Encoding::Unorm8Srgb => (nklut::encoding::srgb_encode(got), nklut::encoding::srgb_encode(want)),
                    _ => (got, want),
                };
                assert!((got - want).abs() <= encoding.half_step(want) * (1.0 + 1e-9), "{}: {got} vs {want}", row["page"]);
            }
            checked += 1;
        }
        checked += 1;
    }
    assert_eq!(checked, 5 * (PAGES.len() + 1));
}

#[test]
fn two_runs_write_byte_identical_files() {
    let (a, b) = (scratch("det-a"), scratch("det-b"));
    bake::run(&database(), &a, &args(&PAGES, 32)).unwrap();
    bake::run(&database(), &b, &args(&PAGES, 32)).unwrap();
    let (ha, hb) = (hashes(&a), hashes(&b));
    assert_eq!(ha.len(), 5 * (PAGES.len() + 1) + 2);
    assert_eq!(ha, hb);
}

#[test]
fn an_interrupted_bake_leaves_the_previous_one_intact() {
    let out = scratch("atomic");
    bake::run(&database(), &out, &args(&PAGES, 32)).unwrap();
    let before = hashes(&out);
    // A different size changes every file; fail once half the files are written.
    let total = 5 * (PAGES.len() + 1) + 2;
    let hook = |i: usize, _: &str| if i >= total / 2 { anyhow::bail!("injected failure at file {i}") } else { Ok(()) };
    let e = bake::run_with_hook(&database(), &out, &args(&PAGES, 48), &hook).unwrap_err();
    assert!(e.to_string().contains("injected failure"), "{e:#}");
    assert_eq!(hashes(&out), before, "previous bake changed or temp files left");
    let mut names: Vec<String> = fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, [".sets", "luts"]);
    // The failed run's generation is gone: the set holds the previous bake alone.
    let generations: Vec<String> = fs::read_dir(out.join(".sets"))
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(generations.len(), 1, "{generations:?}");
}

#[test]
fn bad_arguments_fail_before_any_work() {
    let out = scratch("bad");
    let err = |args: &BakeRequest, out: &Path| format!("{:#}", bake::run(&database(), out, args).unwrap_err());
    assert!(err(&args(&["main/Au/Nobody"], 32), &out).contains("unknown page"));
    assert!(err(&args(&PAGES, 0), &out).contains("--size"));
    assert!(err(&args(&PAGES, 65537), &out).contains("--size"));
    // A folder below a regular file cannot be created, even by root.
    fs::write(out.join("file"), b"x").unwrap();
    assert!(err(&args(&PAGES, 32), &out.join("file").join("sub")).contains("not writable"));
    // Nothing was written by any of them.
    let names: Vec<String> = fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(names, ["file"]);
}

#[test]
fn engine_notes_include_the_wgsl_snippet_verbatim() {
    let docs = include_str!("../docs/engine-integration.md");
    let wgsl = include_str!("../shaders/lut_sample.wgsl");
    assert!(docs.contains(&format!("```wgsl\n{wgsl}```")), "docs/engine-integration.md must include shaders/lut_sample.wgsl verbatim");
    for convention in ["u = cos_theta", "texel i centre = (i + 0.5)/N", "v = (row + 0.5)/rows"] {
        assert!(docs.contains(convention), "{convention}");
    }
}

#[test]
fn a_page_the_catalog_lists_twice_is_baked_once() {
    let out = scratch("twice");
    let page = "specs/HIKARI-optical/Q-FK01S";
    let mut one = args(&[page], 8);
    one.encodings = vec![Encoding::Unorm8];
    let summary = bake::run(&database(), &out, &one).unwrap();
    assert_eq!(summary.rows, 1);
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(out.join("luts/manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["duplicate_catalog_pages"], serde_json::json!([page]));
}

/// The spectral and effective sources (SPEC 4, colour module): gold's spectral red above 1
/// is kept in EXR and clamped (and counted) in PNG; every row carries `error_vs_spectral`,
/// and the effective fit is closer to the spectral reference than the three channels.
#[test]
fn spectral_and_effective_sources_bake_with_errors_against_the_spectral_reference() {
    let out = scratch("spectral");
    let size = 32;
    let mut both = args(&["3d/metals/gold", "3d/glass/BK7"], size);
    both.sources = vec![Source::Spectral, Source::Effective, Source::ThreeChannel];
    both.encodings = vec![Encoding::Unorm8, Encoding::F32];
    bake::run(&database(), &out, &both).unwrap();
    let luts = out.join("luts");
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(luts.join("manifest.json")).unwrap()).unwrap();
    let sets = manifest["textures"].as_array().unwrap();
    let set = |source: &str, encoding: &str| sets.iter().find(|s| s["source"] == source && s["encoding"] == encoding).unwrap();
    assert_eq!(sets.len(), 6);
    assert!(!manifest["error"]["error_vs_spectral"].as_str().unwrap().contains("null"));
    // Gold is row 0 (catalog order); its spectral red exceeds 1 near normal incidence.
    let f32_atlas =
        files::decode(Encoding::F32, &fs::read(luts.join(set("spectral", "f32")["atlas"]["file"].as_str().unwrap())).unwrap()).unwrap();
    let red_max = f32_atlas.texels.decode(Encoding::F32).iter().take(3 * size).step_by(3).copied().fold(0.0, f64::max);
    assert!(red_max > 1.0, "gold's spectral red {red_max}");
    assert_eq!(set("spectral", "f32")["clamped_texels"], 0);
    let clamped = set("spectral", "unorm8")["rows"][0]["clamped_texels"].as_u64().unwrap();
    assert!(clamped > 0 && clamped < size as u64, "{clamped}");
    for s in sets {
        for row in s["rows"].as_array().unwrap() {
            assert!(row["error_vs_spectral"]["mean_relative_rgb"].as_f64().unwrap() >= 0.0, "{} {}", s["source"], row["page"]);
        }
    }
    let vs_spectral =
        |source: &str, row: usize| set(source, "f32")["rows"][row]["error_vs_spectral"]["mean_relative_rgb"].as_f64().unwrap();
    for row in 0..2 {
        assert!(vs_spectral("effective", row) <= vs_spectral("three-channel", row) * 1.001, "row {row}");
        // 32 texels: what is left is sampling (and float rounding), well under the model errors.
        assert!(vs_spectral("spectral", row) < 5e-3, "row {row}: {}", vs_spectral("spectral", row));
    }
    assert!(vs_spectral("spectral", 0) < 0.1 * vs_spectral("three-channel", 0), "gold");
}

/// A bake into a fresh folder stands on its own: each row names its data file and carries
/// its (n, k) (three-wavelength and fitted), each set says what R, G, B mean, the colour
/// matrix is stated, and no table that is not there is referenced.
#[test]
fn the_manifest_of_a_fresh_bake_stands_on_its_own() {
    let out = scratch("standalone");
    let mut spectral = args(&["3d/metals/gold"], 16);
    spectral.sources = vec![Source::Spectral, Source::ThreeChannel];
    spectral.encodings = vec![Encoding::Unorm16];
    bake::run(&database(), &out, &spectral).unwrap();
    let luts = out.join("luts");
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(luts.join("manifest.json")).unwrap()).unwrap();
    let readme = fs::read_to_string(luts.join("README.md")).unwrap();
    assert_eq!(manifest["tables"], serde_json::json!([]));
    assert!(!readme.contains("materials.csv") && !manifest.to_string().contains("materials.csv"));
    let gold =
        &ingest::ingest(&database(), &Selection { pages: vec!["3d/metals/gold".into()], shelves: vec![] }, &ingest::Config::default())
            .unwrap()
            .kept[0];
    for set in manifest["textures"].as_array().unwrap() {
        let row = &set["rows"][0];
        assert_eq!(row["page"], "3d/metals/gold");
        assert_eq!(row["data_file"], gold.page.data.as_str());
        for c in 0..3 {
            assert_eq!(row["index_three_channel"][c]["n"].as_f64().unwrap(), gold.material.channels[c].n);
            assert_eq!(row["index_three_channel"][c]["k"].as_f64().unwrap(), gold.material.channels[c].k);
            assert!(row["index_fitted"][c]["n"].as_f64().unwrap() > 0.0);
        }
        assert_eq!(row["index_three_channel"][1]["wavelength_nm"], 535.0);
        let meaning = set["color_meaning"].as_str().unwrap();
        match set["source"].as_str().unwrap() {
            "spectral" => assert!(meaning.contains("primaries, not wavelengths"), "{meaning}"),
            _ => assert!(meaning.contains("685 nm"), "{meaning}"),
        }
        assert!(set["png_color_chunks"].as_str().unwrap().contains("gAMA 100000"));
    }
    // XYZ → linear sRGB as IEC 61966-2-1 prints it (4 decimals; ours is derived from the
    // primaries and the integrated D65 white).
    let m = &manifest["color"]["xyz_to_linear_srgb"];
    for (r, row) in [[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]].iter().enumerate() {
        for (c, want) in row.iter().enumerate() {
            assert!((m[r][c].as_f64().unwrap() - want).abs() < 2e-3, "[{r}][{c}]");
        }
    }
    assert!(manifest["sixteen_bit_png"].as_str().unwrap().contains("IMREAD_UNCHANGED"));
    // With ingest's tables next to luts/, the manifest documents them.
    ingest::write_tables(
        &ingest::ingest(&database(), &Selection { pages: vec!["3d/metals/gold".into()], shelves: vec![] }, &ingest::Config::default())
            .unwrap(),
        &out,
    )
    .unwrap();
    bake::run(&database(), &out, &spectral).unwrap();
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(luts.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["tables"][0]["files"][0], "../materials.csv");
}
