//! How a method's error grows with depth, where an effects scene measured it: from the
//! `effects_errors.csv` of the scene folders under the output folder (`make effects`
//! writes `<out>/<scene>/`), the Fresnel method's own error (`fresnel_mean_delta_e2000`:
//! the method against exact Fresnel on the same distance-map paths) of a page and method at
//! the shallowest and the deepest depth measured, and the growth per bounce between them.
//!
//! The figures: at a depth (bounces = reflections + refractions) the pixel-weighted mean of
//! `fresnel_mean_delta_e2000` over the rows of the page and method at that depth (every
//! object, search configuration and scene; `pixels` the weight); the growth is
//! (deep − shallow) / (deepest bounces − shallowest bounces). It is carried in the
//! recommendation's row beside the pick (an input named with its table, not a criterion of
//! the pick: the bound is on the F(θ) curve).

use std::path::Path;

use anyhow::Result;

use crate::report::csvdata::CsvTable;
use nklut_tables::columns::{Column, Integer};
use nklut_tables::effects_tables::effects_errors;

/// The table an effects scene writes its image errors to.
pub const EFFECTS_ERRORS: &str = effects_errors::CSV;

/// A page and method's error at the shallowest and deepest depth a scene measured.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthGrowth {
    /// Bounces (reflections + refractions) at the shallowest and deepest depth.
    pub bounces: (u64, u64),
    /// Pixel-weighted mean ΔE2000 of the method against exact Fresnel at each.
    pub de2000: (f64, f64),
    /// (deep − shallow) / (bounces apart); `None` when one depth was measured.
    pub per_bounce: Option<f64>,
    /// The tables and rows the figures come from.
    pub source: String,
}

/// The effects tables under `out`: `<out>/effects_errors.csv` and
/// `<out>/<folder>/effects_errors.csv` (one level), as (path under `out`, table), in path
/// order. A folder without the table is skipped; one that cannot be read is an error.
pub fn effects_tables(out: &Path) -> Result<Vec<(String, CsvTable)>> {
    let mut found = Vec::new();
    if let Some(table) = CsvTable::load(&out.join(EFFECTS_ERRORS))? {
        found.push((EFFECTS_ERRORS.to_string(), table));
    }
    let Ok(entries) = std::fs::read_dir(out) else { return Ok(found) };
    // Folders, links to folders followed (a published set's entries are links, to files
    // as well as folders).
    let mut folders: Vec<String> = entries
        .flatten()
        .filter(|e| std::fs::metadata(e.path()).is_ok_and(|m| m.is_dir()))
        .filter_map(|e| e.file_name().to_str().map(str::to_string))
        .filter(|name| !name.starts_with('.'))
        .collect();
    folders.sort();
    for folder in folders {
        if let Some(table) = CsvTable::load(&out.join(&folder).join(EFFECTS_ERRORS))? {
            found.push((format!("{folder}/{EFFECTS_ERRORS}"), table));
        }
    }
    Ok(found)
}

/// The depth growth of `method` on `page` over `tables` (module doc); `None` where no
/// row of the page and method has a depth, a weight and a figure.
pub fn depth_growth(tables: &[(String, CsvTable)], page: &str, method: &str) -> Option<DepthGrowth> {
    // (bounces, Σ pixels × ΔE, Σ pixels) per depth, and the tables that contributed.
    let mut sums: Vec<(u64, f64, f64)> = Vec::new();
    let mut sources: Vec<(String, usize)> = Vec::new();
    for (path, t) in tables {
        let mut used = 0;
        for row in t.rows.iter().filter(|r| t.get(r, effects_errors::MATERIAL) == page && t.get(r, effects_errors::METHOD) == method) {
            let bounces = |c: Column<Integer>| t.get(row, c).and_then(|b| u64::try_from(b).ok());
            let (Some(reflection), Some(refraction)) =
                (bounces(effects_errors::REFLECTION_DEPTH), bounces(effects_errors::REFRACTION_DEPTH))
            else {
                continue;
            };
            let (Some(pixels), Some(de)) = (t.value(row, effects_errors::PIXELS), t.value(row, effects_errors::FRESNEL_MEAN_DELTA_E2000))
            else {
                continue;
            };
            if !(pixels > 0.0) || !de.is_finite() {
                continue;
            }
            let depth = reflection + refraction;
            match sums.iter_mut().find(|s| s.0 == depth) {
                Some(s) => {
                    s.1 += pixels * de;
                    s.2 += pixels;
                }
                None => sums.push((depth, pixels * de, pixels)),
            }
            used += 1;
        }
        if used > 0 {
            sources.push((path.clone(), used));
        }
    }
    sums.sort_by_key(|s| s.0);
    let (first, last) = (sums.first()?, sums.last()?);
    let (shallow, deep) = (first.1 / first.2, last.1 / last.2);
    let per_bounce = (last.0 > first.0).then(|| (deep - shallow) / (last.0 - first.0) as f64);
    let source = sources.iter().map(|(path, rows)| format!("{path} ({rows} rows)")).collect::<Vec<_>>().join("; ");
    Some(DepthGrowth {
        bounces: (first.0, last.0),
        de2000: (shallow, deep),
        per_bounce,
        source: format!("{source}: fresnel_mean_delta_e2000, pixel-weighted"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// BK7 with schlick at 1+0 over two objects (100 px at 0.2, 300 px at 0.4: mean
    /// (20 + 120) / 400 = 0.35), at 2+0 (0.5, 100 px) and at 3+1 in a second scene (200 px
    /// at 0.95): from 1 to 4 bounces, 0.35 → 0.95, growth 0.6 / 3 = 0.2 per bounce. Rows
    /// of other pages, methods, without pixels or a depth are left out.
    #[test]
    fn growth_is_the_pixel_weighted_error_from_the_shallowest_to_the_deepest_depth() {
        let header = "object,material,method,reflection_depth,refraction_depth,pixels,fresnel_mean_delta_e2000\n";
        let a = CsvTable::parse(
            format!(
                "{header}sphere,3d/glass/BK7,schlick,1,0,100,0.2\nslab,3d/glass/BK7,schlick,1,0,300,0.4\nsphere,3d/glass/BK7,schlick,2,0,100,0.5\n\
sphere,3d/glass/BK7,exact,3,1,100,0\nsphere,3d/metals/gold,schlick,3,1,100,9\nsphere,3d/glass/BK7,schlick,4,0,0,9\nsphere,3d/glass/BK7,schlick,,,100,9\n"
            )
            .as_bytes(),
        )
        .unwrap();
        let b = CsvTable::parse(format!("{header}prism,3d/glass/BK7,schlick,3,1,200,0.95\n").as_bytes()).unwrap();
        let tables = vec![("a/effects_errors.csv".to_string(), a), ("b/effects_errors.csv".to_string(), b)];
        let growth = depth_growth(&tables, "3d/glass/BK7", "schlick").unwrap();
        assert_eq!(growth.bounces, (1, 4));
        assert!((growth.de2000.0 - 0.35).abs() < 1e-12 && (growth.de2000.1 - 0.95).abs() < 1e-12, "{growth:?}");
        assert!((growth.per_bounce.unwrap() - 0.2).abs() < 1e-12, "{growth:?}");
        assert_eq!(growth.source, "a/effects_errors.csv (3 rows); b/effects_errors.csv (1 rows): fresnel_mean_delta_e2000, pixel-weighted");
        assert!(depth_growth(&tables, "3d/glass/BK7", "lut").is_none());
        // One depth: no growth.
        let gold = depth_growth(&tables, "3d/metals/gold", "schlick").unwrap();
        assert_eq!((gold.bounces, gold.per_bounce), ((4, 4), None));
    }
}
