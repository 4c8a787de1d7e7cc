//! Whole-database checks: the database checks the formula evaluator through its
//! own `PROPERTIES.nd` values, and every catalog page is accounted for.

mod common;

use std::collections::BTreeSet;

use nklut::db::Curve;

use common::database;
use nklut::ingest::{ingest, Selection};
use nklut::spectrum::Channels;

/// |n(587.5618 nm) − nd| ≤ 1e-4, or half a unit of the last printed digit when nd has
/// fewer than four decimals.
#[test]
fn formula_pages_reproduce_their_printed_nd() {
    const D_LINE_UM: f64 = 0.5875618;
    let db = database();
    let catalog = db.catalog().unwrap();
    let files: BTreeSet<&str> = catalog.pages.iter().map(|p| p.data.as_str()).collect();
    let (mut checked, mut outside_range) = (0, 0);
    let mut worst = (0.0f64, String::new());
    let mut failures = Vec::new();
    for file in files {
        let Ok(page) = db.read_page(file) else { continue };
        let (Curve::Formula(formula), Some(nd)) = (&page.n, page.nd) else { continue };
        if !formula.contains(D_LINE_UM) {
            outside_range += 1;
            continue;
        }
        let n = formula.refractive_index(D_LINE_UM);
        let tolerance = if nd.decimals < 4 { 0.5 * 10f64.powi(-(nd.decimals as i32)) } else { 1e-4 };
        let error = (n - nd.value).abs();
        if error.is_nan() || error > tolerance {
            failures.push(format!("{file}: n = {n}, nd = {} (tolerance {tolerance})", nd.value));
        }
        if error > worst.0 {
            worst = (error, file.to_string());
        }
        checked += 1;
    }
    println!(
        "nd check: {checked} formula pages checked, {outside_range} with 587.6 nm outside the formula range; worst |n − nd| = {:.2e} ({})",
        worst.0, worst.1
    );
    assert!(checked >= 1500, "only {checked} pages with a formula and nd: the database looks incomplete");
    assert!(failures.is_empty(), "{} pages disagree with their nd:\n{}", failures.len(), failures.join("\n"));
}

/// The Abbe number Vd = (nd − 1)/(nF − nC) checks the dispersion itself, not just one point.
#[test]
fn formula_pages_reproduce_their_printed_abbe_number() {
    let db = database();
    let catalog = db.catalog().unwrap();
    let files: BTreeSet<&str> = catalog.pages.iter().filter(|p| p.shelf == "specs").map(|p| p.data.as_str()).collect();
    let (mut checked, mut failures) = (0, Vec::new());
    for file in files {
        let Ok(page) = db.read_page(file) else { continue };
        let (Curve::Formula(f), Some(vd)) = (&page.n, page.vd) else { continue };
        let (d, fl, cl) = (0.5875618, 0.4861327, 0.6562725);
        if !(f.contains(fl) && f.contains(cl)) {
            continue;
        }
        let abbe = (f.refractive_index(d) - 1.0) / (f.refractive_index(fl) - f.refractive_index(cl));
        // Catalogues print Vd to 2 decimals from nd, nF, nC rounded to 5-6 decimals: allow 0.5 %.
        if (abbe - vd.value).abs() > 0.005 * vd.value {
            failures.push(format!("{file}: Vd = {abbe:.3}, printed {}", vd.value));
        }
        checked += 1;
    }
    println!("Vd check: {checked} spec-sheet pages checked, {} outside 0.5 %", failures.len());
    assert!(checked >= 1000, "only {checked} pages checked");
    // A handful of catalogue entries carry inconsistent Vd; more than 1 % would be our bug.
    assert!(failures.len() * 100 <= checked, "{} pages disagree:\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn every_catalog_page_is_kept_or_excluded() {
    let db = database();
    let catalog = db.catalog().unwrap();
    let result = ingest(&db, &Selection::All, &nklut::ingest::Config::default()).unwrap();
    println!(
        "{} catalog pages: {} kept, {} excluded {:?}",
        catalog.pages.len(),
        result.kept.len(),
        result.excluded.len(),
        result.excluded_by_reason()
    );
    // Entries listed twice with the same file are one page; none in this snapshot reuse an
    // id for another file.
    let entries =
        std::fs::read_to_string(db.root.join("catalog-nk.yml")).unwrap().lines().filter(|l| l.trim_start().starts_with("- PAGE:")).count();
    assert_eq!(catalog.pages.len() + catalog.duplicates.len(), entries, "every PAGE entry of catalog-nk.yml is read");
    assert_eq!(result.listed_twice.len(), catalog.duplicates.len());
    assert_eq!(result.selected, catalog.pages.len());
    assert_eq!(result.kept.len() + result.excluded.len(), catalog.pages.len());
    let mut ids: Vec<String> = result.kept.iter().map(|p| p.id()).chain(result.excluded.iter().map(|e| e.page.clone())).collect();
    ids.sort();
    let before = ids.len();
    ids.dedup();
    assert_eq!(ids.len(), before, "a page is listed twice");
    // Spot checks against values read off the data files by hand.
    let gold = result.find("3d/metals/gold").expect("gold is kept");
    assert_eq!(gold.page.data, "main/Au/nk/Rakic-BB.yml");
    assert!(gold.shared_with().any(|id| id == "main/Au/Rakic-BB"), "{:?}", gold.sharing);
    assert_eq!(gold.material.kind.as_str(), "conductor");
    assert!(gold.names.iter().any(|n| n == "Gold"), "{:?}", gold.names);
    let excluded: Vec<&str> = result.excluded.iter().map(|e| e.error.reason.code()).collect();
    assert!(excluded.contains(&"no-visible-coverage"));
}

#[test]
fn johnson_gold_channels_match_the_table_rows() {
    // main/Au/nk/Johnson.yml rows around 685 nm: 0.6888 µm → n 0.13, k 3.97? Read them from
    // the file itself and interpolate by hand, independently of Curve::at.
    let db = database();
    let text = std::fs::read_to_string(db.data_path("main/Au/nk/Johnson.yml")).unwrap();
    let rows: Vec<[f64; 3]> = text
        .lines()
        .filter_map(|l| {
            let v: Vec<f64> = l.split_whitespace().filter_map(|x| x.parse().ok()).collect();
            (v.len() == 3).then(|| [v[0], v[1], v[2]])
        })
        .collect();
    let result = ingest(&db, &Selection::pages(["main/Au/Johnson"]), &nklut::ingest::Config::default()).unwrap();
    let material = &result.kept[0].material;
    for (channel, nm) in Channels::default().nanometres().into_iter().enumerate() {
        let um = nm / 1000.0;
        let i = rows.iter().position(|r| r[0] > um).unwrap();
        let (a, b) = (rows[i - 1], rows[i]);
        let t = (um - a[0]) / (b[0] - a[0]);
        let (n, k) = (a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2]));
        assert!((material.channels[channel].n - n).abs() < 1e-12, "n at {nm}");
        assert!((material.channels[channel].k - k).abs() < 1e-12, "k at {nm}");
    }
}

/// Both catalogs keep to the block layout, so they are read without the YAML parser, and
/// to the parser's own value.
#[test]
fn the_catalogs_are_read_without_the_yaml_parser_to_its_value() {
    let db = database();
    for name in ["catalog-nk.yml", "catalog-n2.yml"] {
        let text = std::fs::read_to_string(db.root.join(name)).unwrap();
        let value = nklut::db::block_yaml::block_value(&text).unwrap_or_else(|| panic!("{name} left the layout"));
        assert_eq!(value, serde_norway::from_str::<serde_norway::Value>(&text).unwrap(), "{name}");
    }
}

/// The data pages are read without the YAML parser where they keep to the block layout
/// (most of them), each to the parser's own value.
#[test]
fn data_pages_in_the_block_layout_read_to_the_parser_s_value() {
    let db = database();
    let (mut read, mut total) = (0, 0);
    let mut folders = vec![db.root.join("data")];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
                continue;
            }
            let Ok(text) = std::fs::read_to_string(&path) else { continue };
            total += 1;
            if let Some(value) = nklut::db::block_yaml::block_value(&text) {
                read += 1;
                assert_eq!(Some(value), serde_norway::from_str::<serde_norway::Value>(&text).ok(), "{}", path.display());
            }
        }
    }
    println!("{read} of {total} data files read in the block layout");
    assert!(total > 4000 && read * 10 >= total * 9, "{read} of {total}");
}
