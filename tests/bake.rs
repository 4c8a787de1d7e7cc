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
        selection: Selection::pages(pages.iter().copied()),
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
    let kept = ingest::ingest(&database(), &Selection::pages(PAGES), &nklut::ingest::Config::default()).unwrap().kept;
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
    let gold = &ingest::ingest(&database(), &Selection::pages(["3d/metals/gold"]), &ingest::Config::default()).unwrap().kept[0];
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
    ingest::write_tables(&ingest::ingest(&database(), &Selection::pages(["3d/metals/gold"]), &ingest::Config::default()).unwrap(), &out)
        .unwrap();
    bake::run(&database(), &out, &spectral).unwrap();
    let manifest: serde_json::Value = serde_json::from_slice(&fs::read(luts.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["tables"][0]["files"][0], "../materials.csv");
}

/// The manifest's per-row F0, maximum with θ = 90° and recommendation, recomputed from the
/// written files alone: each texture read back without nklut's decoder (the `png` crate's
/// reader, sRGB decoded by the IEC 61966-2-1 formula here; EXR as flat channels by name),
/// exact Fresnel written out below from the amplitude coefficients, the LUT model and the
/// midpoint rule with both ends as `manifest.json → error` defines them. The recommendation
/// is recomputed from bakes at every width it tries, each measured on the 64-texel bake's
/// rule as `recommendation.definition` says.
mod from_the_files {
    use super::*;

    /// Exact unpolarised reflectance of n + ik from vacuum at cos θ (Born & Wolf §1.5,
    /// §14.2): w = √(ñ² − sin²θ), rs = (c − w)/(c + w), rp = (ñ²c − w)/(ñ²c + w).
    fn fresnel(n: f64, k: f64, c: f64) -> f64 {
        let (er, ei) = (n * n - k * k, 2.0 * n * k);
        let (ar, ai) = (er - (1.0 - c * c), ei);
        let modulus = ar.hypot(ai);
        let wr = ((modulus + ar) / 2.0).max(0.0).sqrt();
        let wi = ((modulus - ar) / 2.0).max(0.0).sqrt().copysign(ai);
        let ratio = |pr: f64, pi: f64, qr: f64, qi: f64| (pr * pr + pi * pi) / (qr * qr + qi * qi);
        if wr == 0.0 && wi == 0.0 && c == 0.0 {
            return 1.0;
        }
        0.5 * (ratio(c - wr, -wi, c + wr, wi) + ratio(er * c - wr, ei * c - wi, er * c + wr, ei * c + wi))
    }

    fn srgb_to_linear(v: f64) -> f64 {
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    }

    /// Width, height and linear F per texel (R, G, B), rows in file order.
    fn read_texture(path: &Path, encoding: &str) -> (usize, usize, Vec<[f64; 3]>) {
        if encoding.starts_with('f') {
            let image = exr::prelude::read_first_flat_layer_from_file(path).unwrap();
            let size = image.layer_data.size;
            let channel = |name: &str| -> Vec<f64> {
                let found = image.layer_data.channel_data.list.iter().find(|c| c.name.to_string() == name).unwrap();
                match &found.sample_data {
                    exr::prelude::FlatSamples::F16(v) => v.iter().map(|x| x.to_f64()).collect(),
                    exr::prelude::FlatSamples::F32(v) => v.iter().map(|&x| x as f64).collect(),
                    exr::prelude::FlatSamples::U32(_) => panic!("{}: integer samples", path.display()),
                }
            };
            let (r, g, b) = (channel("R"), channel("G"), channel("B"));
            (size.width(), size.height(), (0..r.len()).map(|i| [r[i], g[i], b[i]]).collect())
        } else {
            let decoder = png::Decoder::new(std::io::BufReader::new(fs::File::open(path).unwrap()));
            let mut reader = decoder.read_info().unwrap();
            let mut bytes = vec![0; reader.output_buffer_size().unwrap()];
            let info = reader.next_frame(&mut bytes).unwrap();
            assert_eq!(info.color_type, png::ColorType::Rgb);
            let samples: Vec<f64> = match info.bit_depth {
                png::BitDepth::Eight => bytes[..info.buffer_size()].iter().map(|&b| b as f64 / 255.0).collect(),
                png::BitDepth::Sixteen => {
                    bytes[..info.buffer_size()].chunks(2).map(|p| u16::from_be_bytes([p[0], p[1]]) as f64 / 65535.0).collect()
                }
                other => panic!("{}: bit depth {other:?}", path.display()),
            };
            let linear = |v: f64| if encoding == "unorm8-srgb" { srgb_to_linear(v) } else { v };
            (info.width as usize, info.height as usize, samples.chunks(3).map(|p| [linear(p[0]), linear(p[1]), linear(p[2])]).collect())
        }
    }

    /// Linear filtering with clamp-to-edge at u = c over texels at (i + 0.5)/N.
    fn lut(texels: &[f64], c: f64) -> f64 {
        let n = texels.len();
        let x = c * n as f64 - 0.5;
        let i = x.floor();
        let t = x - i;
        let at = |j: f64| texels[j.clamp(0.0, (n - 1) as f64) as usize];
        at(i) * (1.0 - t) + at(i + 1.0) * t
    }

    /// (max |F_lut − F| over the midpoint rule of `m` samples and both ends, the value at
    /// θ = 90°, mean relative error).
    fn figures(texels: &[f64], n: f64, k: f64, m: usize) -> (f64, f64, f64) {
        let (mut max, mut sum, mut counted) = (0.0f64, 0.0, 0usize);
        for j in 0..m {
            let c = ((j as f64 + 0.5) * std::f64::consts::FRAC_PI_2 / m as f64).cos();
            let exact = fresnel(n, k, c);
            let diff = (lut(texels, c) - exact).abs();
            max = max.max(diff);
            if exact > 0.0 {
                sum += diff / exact;
                counted += 1;
            }
        }
        let grazing = (lut(texels, 0.0) - fresnel(n, k, 0.0)).abs();
        let normal = (lut(texels, 1.0) - fresnel(n, k, 1.0)).abs();
        (max.max(grazing).max(normal), grazing, sum / counted as f64)
    }

    fn bytes_per_channel(encoding: &str) -> usize {
        match encoding {
            "unorm8" | "unorm8-srgb" => 1,
            "unorm16" | "f16" => 2,
            _ => 4,
        }
    }

    fn close(a: f64, b: f64, what: &str) {
        assert!((a - b).abs() <= 1e-9 * b.abs().max(1e-3), "{what}: {a} from the files, {b} in the manifest");
    }

    #[test]
    fn f0_grazing_maximum_and_recommendation_match_the_files() {
        let pages = ["3d/metals/gold", "3d/glass/soda-lime-green", "3d/liquids/water"];
        // The scratch folder (removed when dropped) and the manifest of a bake at `size`.
        let bake_at = |size: usize| -> (common::Scratch, serde_json::Value) {
            let out = scratch(&format!("files-{size}"));
            let mut request = args(&pages, size);
            request.layouts = vec![bake::Layout::Atlas];
            bake::run(&database(), &out, &request).unwrap();
            let manifest = serde_json::from_slice(&fs::read(out.join("luts/manifest.json")).unwrap()).unwrap();
            (out, manifest)
        };
        let (own_dir, manifest) = bake_at(64);
        let sizes: Vec<usize> =
            manifest["recommendation"]["sizes"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect();
        assert_eq!(sizes, [16, 32, 64, 128, 256, 512, 1024]);
        let bound = &manifest["recommendation"]["bound"];
        // Every width is measured on the bake's own rule: M = clamp(32 · 64, 4096, 262144).
        let samples = manifest["error"]["samples"].as_u64().unwrap() as usize;
        assert_eq!(samples, 4096);
        let (bound_max, bound_mean) = (bound["max_absolute"].as_f64().unwrap(), bound["mean_relative"].as_f64().unwrap());
        // Figures of every (size, encoding, row) from the files of a bake at that size.
        let mut found: BTreeMap<(usize, String, usize), (f64, f64, f64)> = BTreeMap::new();
        for &size in &sizes {
            let other = (size != 64).then(|| bake_at(size));
            let dir = other.as_ref().map_or(own_dir.join("luts/three-channel"), |(out, _)| out.join("luts/three-channel"));
            for set in manifest["textures"].as_array().unwrap() {
                let encoding = set["encoding"].as_str().unwrap();
                let ext = if encoding.starts_with('f') { "exr" } else { "png" };
                let (width, height, texels) = read_texture(&dir.join(encoding).join(format!("atlas.{ext}")), encoding);
                assert_eq!((width, height), (size, pages.len()));
                for row in set["rows"].as_array().unwrap() {
                    let r = row["row"].as_u64().unwrap() as usize;
                    let index = &row["index_three_channel"];
                    let mut worst = (0.0f64, 0.0f64, 0.0f64);
                    for c in 0..3 {
                        let (n, k) = (index[c]["n"].as_f64().unwrap(), index[c]["k"].as_f64().unwrap());
                        let channel: Vec<f64> = texels[r * width..(r + 1) * width].iter().map(|t| t[c]).collect();
                        let (max, grazing, mean) = figures(&channel, n, k, samples);
                        if size == 64 {
                            let page = row["page"].as_str().unwrap();
                            // F0 is exact F at cos θ = 1, not the last texel.
                            close(row["f0"][c].as_f64().unwrap(), fresnel(n, k, 1.0), &format!("{page} f0[{c}]"));
                            assert_ne!(row["f0"][c].as_f64().unwrap(), channel[width - 1]);
                            let e = &row["error_vs_exact"];
                            close(e["max_absolute"][c].as_f64().unwrap(), max, &format!("{page} {encoding} max[{c}]"));
                            close(e["grazing_absolute"][c].as_f64().unwrap(), grazing, &format!("{page} {encoding} grazing[{c}]"));
                        }
                        worst = (worst.0.max(max), worst.1.max(grazing), worst.2 + mean / 3.0);
                    }
                    found.insert((size, encoding.to_string(), r), worst);
                }
            }
        }
        // The dielectrics' maximum sits at the silhouette.
        for r in [1, 2] {
            let (max, grazing, _) = found[&(64, "f32".to_string(), r)];
            assert_eq!(max, grazing, "row {r}");
        }
        // The recommendation, chosen from the files' figures as the manifest defines it.
        for set in manifest["textures"].as_array().unwrap() {
            for row in set["rows"].as_array().unwrap() {
                let r = row["row"].as_u64().unwrap() as usize;
                let mut want: Vec<(usize, usize, f64, String)> = Vec::new();
                for encoding in ["unorm8", "unorm8-srgb", "unorm16", "f16", "f32"] {
                    let meets = sizes.iter().find(|&&n| {
                        let (max, _, mean) = found[&(n, encoding.to_string(), r)];
                        max <= bound_max && mean <= bound_mean
                    });
                    if let Some(&n) = meets {
                        want.push((4 * bytes_per_channel(encoding) * n, n, found[&(n, encoding.to_string(), r)].0, encoding.into()));
                    }
                }
                want.sort_by(|a, b| a.0.cmp(&b.0).then(a.2.total_cmp(&b.2)));
                let got: Vec<(usize, usize, f64, String)> = row["recommended"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|c| {
                        (
                            c["gpu_bytes"].as_u64().unwrap() as usize,
                            c["size"].as_u64().unwrap() as usize,
                            c["max_absolute_rgb"].as_f64().unwrap(),
                            c["encoding"].as_str().unwrap().to_string(),
                        )
                    })
                    .collect();
                assert_eq!(got.len(), want.len(), "{}: {got:?} vs {want:?}", row["page"]);
                for (g, w) in got.iter().zip(&want) {
                    assert_eq!((g.0, g.1, &g.3), (w.0, w.1, &w.3), "{}: {got:?} vs {want:?}", row["page"]);
                    close(g.2, w.2, &format!("{} recommended {}", row["page"], g.3));
                }
            }
        }
        // Water needs more than the bake's 64 texels in any encoding; sRGB is its cheapest.
        let water = &manifest["textures"][0]["rows"][2];
        assert_eq!(water["page"], "3d/liquids/water");
        assert_eq!(water["recommended"][0]["encoding"], "unorm8-srgb", "{}", water["recommended"]);
        assert!(water["recommended"][0]["size"].as_u64().unwrap() > 64);
    }
}
