//! `nklut recommend`: the pick rules on hand-made tables whose answers are derived by hand,
//! and on the 3d shelf: the same bytes on a rerun, and every pick's figures the rows of the
//! tables they come from (re-read here from the CSVs), none cheaper left within the bound.

mod common;

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;
use std::process::{Command, Output};

use common::{database_dir, scratch, SPECULAR_SCENE};
use nklut::recommend::{recommend, Bound, Candidate, LutSize, TimeUnit, Timing, ENGINE_MODELS};
use nklut::report::csvdata::CsvTable;

fn candidate(page: &str, kind: &str, method: &str, from: &str, lut: Option<(usize, &str)>, de_max: f64, rel_max: f64) -> Candidate {
    let bytes = lut.map_or(0, |(n, enc)| n * 3 * if enc.starts_with("unorm8") { 1 } else { 2 });
    Candidate {
        page: page.into(),
        kind: kind.into(),
        method: method.into(),
        parameters_from: from.into(),
        name: match lut {
            Some((n, enc)) => format!("lut {n} × {enc}"),
            None => format!("{method} ({from})"),
        },
        lut: lut.map(|(n, e)| LutSize::new(n, e)),
        texture_bytes: bytes,
        de2000_mean: de_max / 3.0,
        de2000_max: de_max,
        rel_error_mean: rel_max / 2.0,
        rel_error_max: rel_max,
        parameters: String::new(),
        error_table: "hand-made".into(),
    }
}

fn timing(device: &str, method: &str, lut: Option<(usize, &str)>, value: f64) -> Timing {
    Timing {
        device: device.into(),
        method: method.into(),
        lut: lut.map(|(n, e)| LutSize::new(n, e)),
        value,
        unit: if device == "CPU" { TimeUnit::NsPerEvaluation } else { TimeUnit::MsPerPass },
        ms_per_mpixel: None,
        source: "hand-made".into(),
    }
}

/// CPU figures in the proportions of cost.csv: exact 25.6 ns, Schlick 2.36 ns, a LUT 11.9 ns
/// at every size.
fn cpu() -> Vec<Timing> {
    vec![timing("CPU", "exact", None, 25.6), timing("CPU", "schlick", None, 2.36), timing("CPU", "lut", None, 11.9)]
}

#[test]
fn schlick_within_the_bound_and_cheapest_is_the_pick() {
    let page = "glass/a";
    let candidates = vec![
        candidate(page, "dielectric", "exact", "three-channel", None, 0.2, 0.003),
        candidate(page, "dielectric", "schlick", "spectral F0", None, 0.8, 0.05),
        candidate(page, "dielectric", "lut", "spectral curve", Some((64, "unorm8")), 0.1, 0.01),
    ];
    let rows = recommend(&candidates, &cpu(), Bound::default());
    assert_eq!(rows.len(), 1);
    let r = &rows[0];
    let pick = r.pick.as_ref().unwrap();
    assert_eq!(pick.candidate.method, "schlick");
    // 2.36 / 25.6 = 0.0921875 exactly in binary-friendly terms: 236/2560.
    assert!((pick.x_exact.unwrap() - 0.0921875).abs() < 1e-15, "{:?}", pick.x_exact);
    assert_eq!(r.passing, 3);
    // The runner-up is the cheapest passing candidate of another method: the LUT (11.9 ns).
    let runner = r.runner_up.as_ref().unwrap();
    assert_eq!(runner.candidate.method, "lut");
    assert!((runner.x_exact.unwrap() - 11.9 / 25.6).abs() < 1e-15);
    assert!(r.others.contains("exact (three-channel): slower, 1× exact vs 0.0922× exact"), "{}", r.others);
    assert!(r.others.contains("lut (spectral curve): slower, 0.465× exact"), "{}", r.others);
    // A relative bound of 0.02 rules Schlick out (0.05): the LUT (0.01) is then cheapest.
    let strict = recommend(&candidates, &cpu(), Bound { de2000: 1.0, rel: Some(0.02) });
    assert_eq!(strict[0].pick.as_ref().unwrap().candidate.method, "lut");
    assert!(strict[0].others.contains("schlick (spectral F0): relative error 0.05 > 0.02"), "{}", strict[0].others);
}

/// A gold-like conductor: every closed form above ΔE 1 at its worst angle, the LUT of
/// the spectral curve within it from 64 texels on.
fn conductor() -> Vec<Candidate> {
    let page = "metals/au";
    vec![
        candidate(page, "conductor", "exact", "three-channel", None, 3.51, 0.05),
        candidate(page, "conductor", "schlick", "spectral F0", None, 2.18, 0.04),
        candidate(page, "conductor", "f82_tint", "spectral F0 + F82 tint", None, 1.07, 0.02),
        candidate(page, "conductor", "lut", "spectral curve", Some((16, "unorm8")), 1.9, 0.03),
        candidate(page, "conductor", "lut", "spectral curve", Some((64, "unorm8-srgb")), 0.876, 0.005),
    ]
}

#[test]
fn a_conductor_where_only_the_lut_passes_gets_the_lut() {
    let rows = recommend(&conductor(), &cpu(), Bound::default());
    let r = &rows[0];
    let pick = r.pick.as_ref().unwrap();
    assert_eq!((pick.candidate.method.as_str(), pick.candidate.lut.clone()), ("lut", Some(LutSize::new(64, "unorm8-srgb"))));
    assert_eq!(pick.candidate.texture_bytes, 192, "64 texels × 3 channels × 1 byte");
    assert_eq!(r.passing, 1);
    assert!(r.runner_up.is_none(), "no other method passes");
    assert!(r.others.contains("schlick (spectral F0): ΔE2000 max 2.18 > 1"), "{}", r.others);
    assert!(r.others.contains("exact (three-channel): ΔE2000 max 3.51 > 1"), "{}", r.others);
    // With ΔE ≤ 0.5 nothing passes: no pick, and the reason names the smallest error.
    let none = recommend(&conductor(), &cpu(), Bound { de2000: 0.5, rel: None });
    assert!(none[0].pick.is_none());
    assert!(none[0].reason.contains("the smallest ΔE2000 max is 0.876 (lut 64 × unorm8-srgb)"), "{}", none[0].reason);
}

#[test]
fn where_the_lut_is_slower_than_exact_exact_wins() {
    let mut candidates = conductor();
    // Exact Fresnel of a fitted (n, k): ΔE 0.85, no texture.
    candidates.push(candidate("metals/au", "conductor", "exact", "fitted (n, k)", None, 0.85, 0.01));
    let mut timings = cpu();
    // A device whose texture fetch costs more than the arithmetic: 12 ms vs exact's 10 ms.
    timings.extend([timing("gpu", "exact", None, 10.0), timing("gpu", "lut", None, 12.0), timing("gpu", "schlick", None, 5.0)]);
    let rows = recommend(&candidates, &timings, Bound::default());
    assert_eq!(rows.iter().map(|r| r.device.as_str()).collect::<Vec<_>>(), ["CPU", "gpu"]);
    // On the CPU the LUT (11.9 ns) beats exact (25.6 ns) …
    assert_eq!(rows[0].pick.as_ref().unwrap().candidate.method, "lut");
    assert_eq!(rows[0].runner_up.as_ref().unwrap().candidate.parameters_from, "fitted (n, k)");
    // … on the device exact (10 ms, 1×) beats the LUT (12 ms, 1.2×).
    let gpu = &rows[1];
    let pick = gpu.pick.as_ref().unwrap();
    assert_eq!((pick.candidate.method.as_str(), pick.candidate.parameters_from.as_str()), ("exact", "fitted (n, k)"));
    assert_eq!(pick.x_exact, Some(1.0));
    let runner = gpu.runner_up.as_ref().unwrap();
    assert_eq!(runner.candidate.method, "lut");
    assert!((runner.x_exact.unwrap() - 1.2).abs() < 1e-15);
    assert!(gpu.others.contains("lut (spectral curve): slower, 1.2× exact vs 1× exact"), "{}", gpu.others);
    // A method the device never timed cannot be ranked there.
    let mut untimed = candidates.clone();
    untimed.push(candidate("metals/au", "conductor", "generalized_schlick", "spectral F0 + F82 colour", None, 0.34, 0.01));
    let rows = recommend(&untimed, &timings, Bound::default());
    assert!(rows[1].others.contains("generalized_schlick (spectral F0 + F82 colour): no time on gpu"), "{}", rows[1].others);
}

#[test]
fn ties_are_broken_by_texture_bytes_then_error_then_candidate_order() {
    let page = "x/tie";
    // Two LUT sizes at one CPU cost (cost.csv times every size alike): the smaller texture wins.
    let luts = vec![
        candidate(page, "dielectric", "lut", "spectral curve", Some((64, "unorm8")), 0.5, 0.01),
        candidate(page, "dielectric", "lut", "spectral curve", Some((32, "unorm8")), 0.9, 0.02),
    ];
    let r = &recommend(&luts, &cpu(), Bound::default())[0];
    assert_eq!(r.pick.as_ref().unwrap().candidate.texture_bytes, 96);
    assert!(r.reason.contains("tied on cost with lut 64 × unorm8, won on fewer texture bytes"), "{}", r.reason);
    // Equal cost and bytes (same shader method, two parameter origins): the lower ΔE max wins.
    let models = vec![
        candidate(page, "dielectric", "schlick", "three-channel", None, 0.7, 0.01),
        candidate(page, "dielectric", "schlick", "spectral F0", None, 0.6, 0.01),
    ];
    let r = &recommend(&models, &cpu(), Bound::default())[0];
    assert_eq!(r.pick.as_ref().unwrap().candidate.parameters_from, "spectral F0");
    assert!(r.reason.ends_with("won on the lower ΔE2000 max"), "{}", r.reason);
    // Identical in every figure: the earlier candidate.
    let twins = vec![
        candidate(page, "dielectric", "schlick", "first", None, 0.6, 0.01),
        candidate(page, "dielectric", "schlick", "second", None, 0.6, 0.01),
    ];
    let r = &recommend(&twins, &cpu(), Bound::default())[0];
    assert_eq!(r.pick.as_ref().unwrap().candidate.parameters_from, "first");
    assert!(r.reason.ends_with("won on the candidate order"), "{}", r.reason);
    // A per-size CPU time, where the table has one, overrides the method's: the 64-texel
    // LUT at 5 ns beats the 32-texel one at the method's 11.9 ns.
    let mut timings = cpu();
    timings.push(timing("CPU", "lut", Some((64, "unorm8")), 5.0));
    let r = &recommend(&luts, &timings, Bound::default())[0];
    assert_eq!(r.pick.as_ref().unwrap().candidate.texture_bytes, 192);
}

fn nklut(out: &Path, args: &[&str]) -> Output {
    let output = Command::new(env!("CARGO_BIN_EXE_nklut"))
        .args(["--db", &database_dir().display().to_string(), "--out", &out.display().to_string()])
        .args(args)
        .output()
        .unwrap();
    assert!(output.status.success(), "nklut {args:?}: {}", String::from_utf8_lossy(&output.stderr));
    output
}

fn load(out: &Path, name: &str) -> CsvTable {
    CsvTable::load(&out.join(name)).unwrap().unwrap_or_else(|| panic!("{name} missing"))
}

fn num(t: &CsvTable, row: &[String], column: &str) -> f64 {
    t.number(row, column).unwrap_or_else(|| panic!("{column} empty in {row:?}"))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// Each device's time per method, recomputed from its files: cost.csv's f64 rows for the
/// CPU (LUTs per "N=..,encoding"), the median of gpu_timing's `median_ms` over materials.
fn costs(out: &Path, devices: &Path) -> BTreeMap<(String, String), f64> {
    let mut costs = BTreeMap::new();
    let cost = load(out, "cost.csv");
    for row in &cost.rows {
        let (method, variant) = (cost.text(row, "method"), cost.text(row, "variant"));
        if variant == "f64" {
            costs.insert(("CPU".to_string(), method.to_string()), num(&cost, row, "ns_per_eval"));
        } else if let Some(spec) = variant.strip_suffix(",f64") {
            costs.insert(("CPU".to_string(), format!("{method} {spec}")), num(&cost, row, "ns_per_eval"));
        }
    }
    let devices = nklut::report::inputs::read_devices(devices).unwrap();
    for (name, tables) in &devices {
        let t = &tables.timing;
        for method in t.distinct("method") {
            let times: Vec<f64> = t.rows_where("method", method).filter_map(|r| t.number(r, "median_ms")).collect();
            if !times.is_empty() {
                costs.insert((name.clone(), method.to_string()), median(times));
            }
        }
    }
    costs
}

#[test]
fn the_3d_shelf_picks_are_stable_and_their_figures_are_the_tables_rows() {
    let out = scratch("recommend-3d");
    for stage in ["ingest", "colors", "params", "validate"] {
        nklut(&out, &[stage, "--shelf", "3d"]);
    }
    let devices = Path::new(env!("CARGO_MANIFEST_DIR")).join("benchmarks/devices");
    let args = ["recommend", "--shelf", "3d", "--devices", devices.to_str().unwrap()];
    nklut(&out, &args);
    let first: Vec<Vec<u8>> =
        ["recommendations.csv", "recommendations.json", "method_errors.csv"].iter().map(|f| fs::read(out.join(f)).unwrap()).collect();
    nklut(&out, &args);
    for (i, f) in ["recommendations.csv", "recommendations.json", "method_errors.csv"].iter().enumerate() {
        assert!(fs::read(out.join(f)).unwrap() == first[i], "{f} differs on a rerun");
    }

    let bad: Vec<_> = common::non_finite_tables(&out).into_iter().filter(|(_, cells)| !cells.is_empty()).collect();
    assert!(bad.is_empty(), "non-finite cells: {bad:?}");
    let recs = load(&out, "recommendations.csv");
    let method_errors = load(&out, "method_errors.csv");
    let engine = load(&out, "engine_params.csv");
    let colors = load(&out, "colors.csv");
    let materials = load(&out, "materials.csv");
    let costs = costs(&out, &devices);
    let device_names: Vec<&str> = recs.distinct("device");
    let pages = materials.rows.len();
    assert!(device_names.contains(&"CPU") && device_names.len() >= 2, "CPU and the timed devices: {device_names:?}");
    assert_eq!(recs.rows.len(), pages * device_names.len(), "one row per page × device");

    // The exact Fresnel of the three-channel index against the spectral curve is colors.csv's
    // index error over θ, computed by another stage: equal to the last bit.
    for row in method_errors.rows.iter().filter(|r| method_errors.text(r, "method") == "exact") {
        let page = method_errors.text(row, "page");
        let c = colors.rows_where("page", page).next().unwrap();
        for ch in ["r", "g", "b"] {
            assert_eq!(
                num(&method_errors, row, &format!("rel_error_{ch}")),
                num(&colors, c, &format!("index_error_angle_{ch}")),
                "{page} {ch}"
            );
        }
    }

    // Every candidate of a page with its figures and its cost key, from the tables alone.
    struct Row {
        name: String,
        method: String,
        cost_key: (String, Option<String>),
        de_mean: f64,
        de_max: f64,
        rel: [f64; 3],
        bytes: i64,
    }
    let mut by_page: BTreeMap<String, Vec<Row>> = BTreeMap::new();
    for r in &method_errors.rows {
        let method = method_errors.text(r, "method").to_string();
        let variant = method_errors.text(r, "variant");
        let name = if variant.is_empty() {
            format!("{method} (three-channel)")
        } else {
            let (n, enc) = variant.trim_start_matches("N=").split_once(',').unwrap();
            format!("lut {n} × {enc} (spectral)")
        };
        by_page.entry(method_errors.text(r, "page").into()).or_default().push(Row {
            name,
            cost_key: (method.clone(), (!variant.is_empty()).then(|| variant.to_string())),
            method,
            de_mean: num(&method_errors, r, "de2000_mean"),
            de_max: num(&method_errors, r, "de2000_max"),
            rel: ["r", "g", "b"].map(|c| num(&method_errors, r, &format!("rel_error_{c}"))),
            bytes: num(&method_errors, r, "texture_bytes") as i64,
        });
    }
    for r in &engine.rows {
        for (model, shader, _) in ENGINE_MODELS {
            let Some(de_max) = engine.number(r, &format!("{model}_de2000_max")) else { continue };
            by_page.entry(engine.text(r, "page").into()).or_default().push(Row {
                name: format!("{model} (engine_params)"),
                method: shader.into(),
                cost_key: (shader.into(), None),
                de_mean: num(&engine, r, &format!("{model}_de2000_mean")),
                de_max,
                rel: ["r", "g", "b"].map(|c| num(&engine, r, &format!("{model}_rel_error_{c}"))),
                bytes: 0,
            });
        }
    }
    let cost_of = |device: &str, row: &Row| -> Option<f64> {
        let (method, variant) = &row.cost_key;
        variant
            .as_ref()
            .and_then(|v| costs.get(&(device.to_string(), format!("{method} {v}"))))
            .or_else(|| costs.get(&(device.to_string(), method.clone())))
            .copied()
    };

    let mut checked = 0;
    let mut lut_picks = 0;
    for rec in &recs.rows {
        let (page, device) = (recs.text(rec, "page"), recs.text(rec, "device"));
        assert_eq!(num(&recs, rec, "bound_de2000"), 1.0);
        let rows = &by_page[page];
        let name = recs.text(rec, "candidate");
        let pick = rows.iter().find(|r| r.name == name).unwrap_or_else(|| panic!("{page}: {name} is no table row"));
        // The error figures are the row's.
        assert_eq!(num(&recs, rec, "de2000_mean"), pick.de_mean, "{page} {device} {name}");
        assert_eq!(num(&recs, rec, "de2000_max"), pick.de_max);
        assert_eq!(num(&recs, rec, "rel_error_mean"), pick.rel.iter().sum::<f64>() / 3.0);
        assert_eq!(num(&recs, rec, "rel_error_max"), pick.rel.iter().copied().fold(0.0, f64::max));
        assert_eq!(num(&recs, rec, "texture_bytes") as i64, pick.bytes);
        assert_eq!(recs.text(rec, "method"), pick.method);
        assert!(pick.de_max <= 1.0);
        // The cost is the device's, and × exact its ratio to exact's.
        let cost = cost_of(device, pick).unwrap();
        assert_eq!(num(&recs, rec, "cost"), cost, "{page} {device}");
        let exact = costs[&(device.to_string(), "exact".to_string())];
        assert_eq!(num(&recs, rec, "cost_x_exact"), cost / exact);
        // Nothing within the bound is cheaper on this device, and on equal cost nothing
        // has fewer texture bytes.
        for other in rows.iter().filter(|r| r.de_max <= 1.0) {
            let Some(c) = cost_of(device, other) else { continue };
            assert!(c > cost || (c == cost && other.bytes >= pick.bytes), "{page} {device}: {} ({c}) beats {name} ({cost})", other.name);
        }
        if recs.text(rec, "method") == "lut" {
            lut_picks += 1;
            let file = recs.text(rec, "parameters");
            assert!(file.starts_with("luts/spectral/") && file.contains(&recs.text(rec, "lut_encoding").to_string()), "{file}");
        }
        checked += 1;
    }
    assert_eq!(checked, recs.rows.len(), "every page has a pick on every device");
    // Gold: no closed form stays within ΔE 1 at every angle (engine_params: Schlick 2.18, F82 1.07).
    let gold_cpu = recs.rows.iter().find(|r| recs.text(r, "page") == "3d/metals/gold" && recs.text(r, "device") == "CPU").unwrap();
    assert_eq!(recs.text(gold_cpu, "method"), "lut");
    assert!(lut_picks > 0);
}

/// The quantile of sorted `v` at `q`, linear between order statistics.
fn quantile(v: &[f64], q: f64) -> f64 {
    let position = q * (v.len() - 1) as f64;
    let (lo, hi) = (position.floor() as usize, position.ceil() as usize);
    v[lo] + (v[hi] - v[lo]) * (position - lo as f64)
}

/// What a figure of the index's first screen must be, recomputed from the CSVs by its key.
fn recompute(key: &str, out: &Path, devices: &Path) -> f64 {
    let recs = load(out, "recommendations.csv");
    let me = load(out, "method_errors.csv");
    let engine = load(out, "engine_params.csv");
    let colors = load(out, "colors.csv");
    let costs = costs(out, devices);
    let bound = num(&recs, &recs.rows[0], "bound_de2000");
    let group = |r: &[String]| format!("{} ({})", recs.text(r, "method"), recs.text(r, "parameters_from"));
    let parts: Vec<&str> = key.split(':').collect();
    let sorted = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v
    };
    match parts.as_slice() {
        ["bound"] => bound,
        ["pages", kind] => {
            let mut p: Vec<&str> = recs.rows.iter().filter(|r| recs.text(r, "kind") == *kind).map(|r| recs.text(r, "page")).collect();
            p.sort();
            p.dedup();
            p.len() as f64
        }
        ["pick-count", kind, device, g] => {
            let rows: Vec<&Vec<String>> =
                recs.rows.iter().filter(|r| recs.text(r, "kind") == *kind && recs.text(r, "device") == *device).collect();
            let n = rows.iter().filter(|r| group(r) == *g).count();
            // It is the most frequent pick there.
            assert!(rows.iter().all(|r| rows.iter().filter(|s| group(s) == group(r)).count() <= n), "{key} is not the most frequent pick");
            n as f64
        }
        ["picks-worst-de", kind, device] => recs
            .rows
            .iter()
            .filter(|r| recs.text(r, "kind") == *kind && recs.text(r, "device") == *device)
            .map(|r| num(&recs, r, "de2000_max"))
            .fold(f64::NAN, f64::max),
        ["picks-median-x", kind, device] => median(
            recs.rows
                .iter()
                .filter(|r| recs.text(r, "kind") == *kind && recs.text(r, "device") == *device)
                .map(|r| num(&recs, r, "cost_x_exact"))
                .collect(),
        ),
        ["schlick-within"] => engine.rows.iter().filter(|r| num(&engine, r, "schlick_de2000_max") <= bound).count() as f64,
        ["schlick-pages"] => engine.rows.len() as f64,
        ["schlick-median", kind] => {
            median(engine.rows.iter().filter(|r| engine.text(r, "kind") == *kind).map(|r| num(&engine, r, "schlick_de2000_max")).collect())
        }
        ["schlick-worst"] => engine.rows.iter().map(|r| num(&engine, r, "schlick_de2000_max")).fold(0.0, f64::max),
        ["index-f0-median", kind] => {
            median(colors.rows.iter().filter(|r| colors.text(r, "kind") == *kind).map(|r| num(&colors, r, "delta_e2000_f0")).collect())
        }
        ["index-f0-worst"] => colors.rows.iter().map(|r| num(&colors, r, "delta_e2000_f0")).fold(0.0, f64::max),
        ["exact-within"] => me.rows.iter().filter(|r| me.text(r, "method") == "exact" && num(&me, r, "de2000_max") <= bound).count() as f64,
        ["exact-pages"] => me.rows.iter().filter(|r| me.text(r, "method") == "exact").count() as f64,
        ["lut-within" | "lut-pages" | "lut-bytes-median" | "lut-bytes-max"] => {
            let mut smallest: BTreeMap<&str, f64> = BTreeMap::new();
            let mut pages: Vec<&str> = Vec::new();
            for r in me.rows.iter().filter(|r| me.text(r, "method") == "lut") {
                let page = me.text(r, "page");
                pages.push(page);
                if num(&me, r, "de2000_max") <= bound {
                    let b = num(&me, r, "texture_bytes");
                    let e = smallest.entry(page).or_insert(b);
                    *e = e.min(b);
                }
            }
            pages.sort();
            pages.dedup();
            match parts[0] {
                "lut-within" => smallest.len() as f64,
                "lut-pages" => pages.len() as f64,
                "lut-bytes-median" => median(smallest.values().copied().collect()),
                _ => smallest.values().copied().fold(0.0, f64::max),
            }
        }
        ["x-exact", device, "lut"] | ["x-exact", device, "schlick"] => {
            let method = parts[2];
            let method_key = if *device == "CPU" && method == "lut" { "lut N=256,unorm8".to_string() } else { method.to_string() };
            costs[&(device.to_string(), method_key)] / costs[&(device.to_string(), "exact".to_string())]
        }
        [what, rest @ ..] if rest.last().is_some_and(|id| id.contains('|')) => {
            // A decision-table cell: id = method|parameters from|variant.
            let id: Vec<&str> = rest.last().unwrap().split('|').collect();
            let (method, from, variant) = (id[0], id[1], id[2]);
            let values: Vec<(String, f64)> = if from == "three-channel (n, k)" || from == "spectral curve" {
                me.rows
                    .iter()
                    .filter(|r| me.text(r, "method") == method && me.text(r, "variant") == variant)
                    .map(|r| (me.text(r, "kind").to_string(), num(&me, r, "de2000_max")))
                    .collect()
            } else {
                let (model, _, _) = ENGINE_MODELS.iter().find(|(_, s, f)| *s == method && *f == from).unwrap();
                engine
                    .rows
                    .iter()
                    .filter_map(|r| Some((engine.text(r, "kind").to_string(), engine.number(r, &format!("{model}_de2000_max"))?)))
                    .collect()
            };
            let of = |kind: &str| sorted(values.iter().filter(|v| v.0 == kind).map(|v| v.1).collect());
            match (*what, rest.len()) {
                ("cpu-ns", 1) => {
                    let k = if variant.is_empty() { method.to_string() } else { format!("{method} {variant}") };
                    costs[&("CPU".to_string(), k)]
                }
                ("x-exact", 2) => costs[&(rest[0].to_string(), method.to_string())] / costs[&(rest[0].to_string(), "exact".to_string())],
                ("de-median", 2) => median(of(rest[0])),
                ("de-p95", 2) => quantile(&of(rest[0]), 0.95),
                ("within", 1) => values.iter().filter(|v| v.1 <= bound).count() as f64,
                _ => panic!("unknown figure {key}"),
            }
        }
        _ => panic!("unknown figure {key}"),
    }
}

/// Read off the index's DOM at 1400 × 900 in headless Chromium: every figure of the answer
/// section with its box, the sections' boxes, the links and the page's scroll width.
const FIRST_SCREEN_SCRIPT: &str = r#"<script>window.addEventListener('load',()=>{const out={figures:[],boxes:{},links:[],scroll:document.documentElement.scrollWidth,width:window.innerWidth,findings:[]};
for(const s of document.querySelectorAll('#answer span.figure')){const r=s.getBoundingClientRect();out.figures.push({key:s.dataset.key,value:parseFloat(s.dataset.value),raw:s.dataset.value,text:s.textContent,top:r.top,bottom:r.bottom,finding:!!s.closest('li.finding')});}
for(const id of ['findings','answer-picks','answer-methods']){const r=document.getElementById(id).getBoundingClientRect();out.boxes[id]=[r.top,r.bottom];}
for(const a of document.querySelectorAll('#answer a'))out.links.push(a.getAttribute('href'));
for(const li of document.querySelectorAll('li.finding'))out.findings.push(li.textContent);
const p=document.createElement('pre');p.id='nk-audit';p.textContent=JSON.stringify(out);document.body.appendChild(p);});</script>"#;

#[derive(serde::Deserialize, Debug)]
struct ScreenFigure {
    key: String,
    value: f64,
    raw: String,
    text: String,
    top: f64,
    bottom: f64,
    finding: bool,
}

#[derive(serde::Deserialize, Debug)]
struct FirstScreen {
    figures: Vec<ScreenFigure>,
    boxes: BTreeMap<String, [f64; 2]>,
    links: Vec<String>,
    scroll: f64,
    width: f64,
    findings: Vec<String>,
}

#[test]
fn the_index_first_screen_shows_the_answer_and_every_figure_is_its_tables() {
    let out = scratch("recommend-index");
    for stage in ["ingest", "colors", "params", "validate"] {
        nklut(&out, &[stage, "--shelf", "3d"]);
    }
    let devices = Path::new(env!("CARGO_MANIFEST_DIR")).join("benchmarks/devices");
    let dev = devices.to_str().unwrap();
    nklut(&out, &["recommend", "--shelf", "3d", "--devices", dev]);
    nklut(&out, &["report", "--shelf", "3d", "--devices", dev]);
    let index = out.join("report/index.html");
    let audited = out.join("report/audit-index.html");
    fs::write(&audited, fs::read_to_string(&index).unwrap().replace("</body>", &format!("{FIRST_SCREEN_SCRIPT}</body>"))).unwrap();
    let dom = Command::new("chromium")
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--hide-scrollbars", "--virtual-time-budget=5000"])
        .arg(format!("--user-data-dir={}", out.join("profile").display()))
        .args(["--window-size=1400,900", "--dump-dom"])
        .arg(format!("file://{}", audited.display()))
        .output()
        .expect("chromium is not installed: scripts/test-deps installs it");
    assert!(dom.status.success(), "{}", String::from_utf8_lossy(&dom.stderr));
    let dom = String::from_utf8_lossy(&dom.stdout);
    let start = dom.find("<pre id=\"nk-audit\">").expect("the audit ran") + "<pre id=\"nk-audit\">".len();
    let json = dom[start..start + dom[start..].find("</pre>").unwrap()]
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    let screen: FirstScreen = serde_json::from_str(&json).unwrap_or_else(|e| panic!("{e}: {json}"));

    // The findings and the recommendation per class and device are on the first screen,
    // the decision table starts on it; nothing wider than the window.
    assert!(screen.boxes["findings"][0] < 900.0 && screen.boxes["answer-picks"][1] <= 900.0, "{:?}", screen.boxes);
    assert!(screen.boxes["answer-methods"][0] < 900.0, "{:?}", screen.boxes);
    assert!(screen.scroll <= screen.width, "scroll width {} > {}", screen.scroll, screen.width);
    for f in screen.figures.iter().filter(|f| f.finding) {
        assert!(f.bottom <= 900.0, "finding figure {} at {}–{} px is below the first screen", f.key, f.top, f.bottom);
    }
    for link in ["#materials", "effects.html", "effects.html#devices"] {
        assert!(screen.links.iter().any(|l| l == link), "no link to {link}: {:?}", screen.links);
    }
    assert!(screen.links.iter().any(|l| l.starts_with("materials/")), "findings link material pages: {:?}", screen.links);
    assert!(screen.findings.len() >= 5, "{:?}", screen.findings);

    // Every figure recomputed from the CSVs, and shown as the value it carries.
    let findings_figures = screen.figures.iter().filter(|f| f.finding).count();
    assert!(findings_figures >= 20 && screen.figures.len() > 100, "{findings_figures} / {}", screen.figures.len());
    for f in &screen.figures {
        let expected = recompute(&f.key, &out, &devices);
        // The attribute's text, parsed by Rust (serde_json's float parsing may miss the last bit).
        let value = f.raw.parse::<f64>().unwrap();
        assert!((value - f.value).abs() <= 1e-15 * value.abs());
        assert!((value - expected).abs() <= 1e-12 * expected.abs().max(1e-300), "{}: page {value} vs CSV {expected}", f.key);
        let shown = if value.fract() == 0.0 { format!("{}", value as i64) } else { nklut::report::findings::sig3(value) };
        assert_eq!(f.text, shown, "{}", f.key);
    }
    // report.md carries the same sentences.
    let markdown = fs::read_to_string(out.join("report/report.md")).unwrap();
    for sentence in &screen.findings {
        let text = sentence.rsplit_once(" (").map_or(sentence.as_str(), |(t, _)| t);
        assert!(markdown.contains(text.split(": ").next().unwrap()), "report.md lacks {text}");
    }
    let first = screen.figures.iter().find(|f| f.key.starts_with("pick-count:dielectric")).unwrap();
    println!("first screen: {} figures, {} in findings; {} = {}", screen.figures.len(), findings_figures, first.key, first.value);
}

#[test]
fn the_search_finding_states_the_effects_tables_figures() {
    let out = scratch("recommend-effects");
    let pages = ["--page", "3d/glass/BK7", "--page", "3d/crystals/diamond"];
    for stage in ["ingest", "colors", "params", "validate", "recommend"] {
        nklut(&out, &[&[stage][..], &pages].concat());
    }
    let scene = out.join("specular.yaml");
    // The scene measures what the picks are (on the CPU a 64-texel LUT of the spectral curve
    // for both pages) beside exact and Schlick.
    fs::write(&scene, SPECULAR_SCENE.replace("methods: [exact, schlick]", "methods: [exact, schlick, lut]")).unwrap();
    nklut(&out.join("specular"), &["effects", "--hero-size", "0", scene.to_str().unwrap()]);
    // With the scene measured, recommend carries each pick's error growth with depth:
    // recomputed here from effects_errors.csv (pixel-weighted fresnel ΔE2000 per total
    // depth, the shallowest and the deepest, and their slope).
    nklut(&out, &[&["recommend"][..], &pages].concat());
    let recs = load(&out, "recommendations.csv");
    let errors = load(&out.join("specular"), "effects_errors.csv");
    let mut measured = 0;
    for row in &recs.rows {
        let (page, method) = (recs.text(row, "page"), recs.text(row, "method"));
        let mut depths: BTreeMap<u64, (f64, f64)> = BTreeMap::new();
        for r in errors.rows.iter().filter(|r| errors.text(r, "material") == page && errors.text(r, "method") == method) {
            let bounces: u64 =
                errors.text(r, "reflection_depth").parse::<u64>().unwrap() + errors.text(r, "refraction_depth").parse::<u64>().unwrap();
            let pixels = num(&errors, r, "pixels");
            let entry = depths.entry(bounces).or_default();
            entry.0 += pixels * num(&errors, r, "fresnel_mean_delta_e2000");
            entry.1 += pixels;
        }
        let depths: Vec<(u64, f64)> = depths.into_iter().filter(|(_, (_, w))| *w > 0.0).map(|(d, (s, w))| (d, s / w)).collect();
        let Some((&(d0, e0), &(d1, e1))) = depths.first().zip(depths.last()) else {
            assert_eq!(recs.text(row, "depth_bounces"), "", "{page} {method}: no scene measured it");
            continue;
        };
        measured += 1;
        assert_eq!(recs.text(row, "depth_bounces"), format!("{d0}-{d1}"), "{page} {method}");
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-12);
        assert!(close(num(&recs, row, "depth_de2000_shallow"), e0) && close(num(&recs, row, "depth_de2000_deep"), e1), "{page} {method}");
        if d1 > d0 {
            assert!(close(num(&recs, row, "depth_growth_per_bounce"), (e1 - e0) / (d1 - d0) as f64), "{page} {method}");
        }
        assert!(recs.text(row, "depth_source").starts_with("specular/effects_errors.csv ("), "{}", recs.text(row, "depth_source"));
    }
    assert!(measured >= 1, "the scene measured a pick's method: {measured}");
    nklut(&out, &[&["report"][..], &pages].concat());
    let html = fs::read_to_string(out.join("report/index.html")).unwrap();
    let start = html.find("<li class=\"finding\" id=\"finding-search-specular\">").expect("the search finding for the scene");
    let item = &html[start..start + html[start..].find("</li>").unwrap()];
    assert!(item.contains("href=\"effects.html#scene-specular\""), "{item}");
    // Its figures, from the attributes, against effects_errors.csv re-read here.
    let errors = load(&out.join("specular"), "effects_errors.csv");
    let column = |name: &str, skip_exact: bool| -> Vec<f64> {
        errors.rows.iter().filter(|r| !skip_exact || errors.text(r, "method") != "exact").map(|r| num(&errors, r, name)).collect()
    };
    let max = |v: Vec<f64>| v.into_iter().fold(f64::NAN, f64::max);
    let min = |v: Vec<f64>| v.into_iter().fold(f64::NAN, f64::min);
    let expected = [
        ("search:specular:fresnel-max", max(column("fresnel_mean_delta_e2000", true))),
        ("search:specular:total-min", min(column("total_mean_delta_e2000", false))),
        ("search:specular:total-max", max(column("total_mean_delta_e2000", false))),
        ("search:specular:geometry-max", max(column("geometry_mean_delta_e2000", false))),
    ];
    let mut rest = item;
    for (key, value) in expected {
        let needle = format!("data-key=\"{key}\" data-value=\"");
        let at = rest.find(&needle).unwrap_or_else(|| panic!("{key} missing in {item}"));
        let tail = &rest[at + needle.len()..];
        let shown: f64 = tail[..tail.find('"').unwrap()].parse().unwrap();
        assert_eq!(shown, value, "{key}");
        rest = tail;
    }
    // The clause that names the dominant error follows the figures.
    let dominates = expected[3].1 > expected[0].1;
    assert_eq!(item.contains("the search, not the Fresnel formula, dominates"), dominates, "{item}");
    println!("{}", item);
}

/// The `data-key` → `data-value` figures of the index's finding `id`, in order, and its text.
fn index_finding(html: &str, id: &str) -> (Vec<(String, f64)>, String) {
    let start = html.find(&format!("<li class=\"finding\" id=\"finding-{id}\">")).unwrap_or_else(|| panic!("no finding {id} on the index"));
    let item = &html[start..start + html[start..].find("</li>").unwrap()];
    let figures = item
        .split("data-key=\"")
        .skip(1)
        .map(|rest| {
            let key = &rest[..rest.find('"').unwrap()];
            let value = rest.split("data-value=\"").nth(1).unwrap();
            (key.to_string(), value[..value.find('"').unwrap()].parse().unwrap())
        })
        .collect();
    (figures, item.to_string())
}

/// The index's first screen says at which depth three wavelengths stop being enough
/// against the spectral truth, and what GTAO and surfels trade, from hand-made tables
/// whose answers are derived here by hand.
///
/// Spectral (gold in gold, bound ΔE2000 1 of `nklut recommend`): per depth the worst
/// object's mean ΔE2000 — three-wavelength: max(0.4, 0.5) = 0.5 at 1+0, 0.8 at 2+0,
/// max(1.3, 1.1) = 1.3 at 3+0 (the first above 1), 6 at 8+0; effective 0.2 at 1+0 and 0.95
/// at 8+0, within 1 at every depth.
///
/// AO: brute force, 1 pass: (100 × 0.10 + 300 × 0.06) / 400 = 0.07; 2 passes:
/// (100 × 0.05 + 300 × 0.03) / 400 = 0.035, the best; tree, 1 pass: 0.2. The best's CPU
/// time (20 + 22) / 2 = 21 ms; per pixel (1000 × 0.04 + 3000 × 0.02) / 4000 = 0.025;
/// GTAO (1000 × 0.09 + 3000 × 0.03) / 4000 = 0.045.
#[test]
fn the_index_states_where_three_wavelengths_stop_and_what_gtao_and_surfels_trade() {
    let out = scratch("index-effects-findings");
    let pages = ["--page", "3d/metals/gold"];
    for stage in ["ingest", "colors", "params", "validate", "recommend"] {
        nklut(&out, &[&[stage][..], &pages].concat());
    }
    fs::create_dir_all(out.join("gold-in-gold")).unwrap();
    let mut spectral =
        String::from("object,object_index,material,index_source,reflection_depth,refraction_depth,wavelengths,pixels,mean_delta_e2000\n");
    for (source, object, index, values) in [
        ("three-wavelength", "sphere", 0, [0.4, 0.8, 1.3, 5.0]),
        ("three-wavelength", "plane", 2, [0.5, 0.7, 1.1, 6.0]),
        ("effective", "sphere", 0, [0.1, 0.2, 0.4, 0.9]),
        ("effective", "plane", 2, [0.2, 0.3, 0.5, 0.95]),
    ] {
        for (depth, value) in [1, 2, 3, 8].iter().zip(values) {
            spectral.push_str(&format!("{object},{index},3d/metals/gold,{source},{depth},0,96,100,{value}\n"));
        }
    }
    fs::write(out.join("gold-in-gold/spectral_errors.csv"), spectral).unwrap();
    fs::create_dir_all(out.join("bunny")).unwrap();
    fs::write(
        out.join("bunny/ao_errors.csv"),
        "object,technique,hierarchy,passes,surfels,mean_error,cpu_ms,pixels,pixel_mean_error
a,surfels,false,1,100,0.10,10,1000,0.08
b,surfels,false,1,300,0.06,10,3000,0.05
a,surfels,false,2,100,0.05,20,1000,0.04
b,surfels,false,2,300,0.03,22,3000,0.02
a,surfels,true,1,100,0.2,5,1000,0.2
b,surfels,true,1,300,0.2,5,3000,0.2
a,gtao,,,,,,1000,0.09
b,gtao,,,,,,3000,0.03
",
    )
    .unwrap();
    nklut(&out, &[&["report"][..], &pages].concat());
    let html = fs::read_to_string(out.join("report/index.html")).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);

    let (figures, item) = index_finding(&html, "spectral-gold-in-gold");
    let expected = [
        ("spectral:gold-in-gold:three-wavelength:1+0", 0.5),
        ("spectral:gold-in-gold:three-wavelength:8+0", 6.0),
        ("bound", 1.0),
        ("spectral:gold-in-gold:three-wavelength:3+0", 1.3),
        ("spectral:gold-in-gold:effective:1+0", 0.2),
        ("spectral:gold-in-gold:effective:8+0", 0.95),
        ("bound", 1.0),
    ];
    assert_eq!(figures.len(), expected.len(), "{item}");
    for ((key, value), (want_key, want)) in figures.iter().zip(expected) {
        assert!(key == want_key && close(*value, want), "{key} {value} vs {want_key} {want}: {item}");
    }
    assert!(item.contains(" at depth 3+0 ("), "the first depth above the bound is named: {item}");
    assert!(item.contains("href=\"effects.html#scene-gold-in-gold\""), "{item}");

    let (figures, item) = index_finding(&html, "ao-bunny");
    let expected = [
        ("ao:bunny:best", 0.035),
        ("ao:bunny:best-cpu-ms", 21.0),
        ("ao:bunny:one-pass", 0.07),
        ("ao:bunny:gtao-pixel", 0.045),
        ("ao:bunny:surfel-pixel", 0.025),
    ];
    assert_eq!(figures.len(), expected.len(), "{item}");
    for ((key, value), (want_key, want)) in figures.iter().zip(expected) {
        assert!(key == want_key && close(*value, want), "{key} {value} vs {want_key} {want}: {item}");
    }
    assert!(item.contains("with the brute force and 2 pass(es)"), "{item}");
}
