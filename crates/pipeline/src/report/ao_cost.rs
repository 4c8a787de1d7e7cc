//! What ambient occlusion costs on a GPU against what it gets right (effects page, AO
//! section): every surfel configuration and every GTAO configuration of a scene's
//! `ao_errors.csv` that a device timed (`ao_timing`: this machine's `make gpu`, each device
//! result under `devices/`), one chart per device: the error per covered pixel against the
//! full ray-traced reference (pixel-weighted over the scene's objects) against the median
//! GPU time of one frame, both techniques and every preset on the same axes, the Pareto
//! front joined; and a table with the time to convergence and the error against the
//! range-limited reference beside it. A configuration is matched by what both tables name:
//! the surfels' emitters and passes, GTAO's preset (as labelled, "(modified)" included),
//! radius, slices, steps and frames; a timing row counts only for the scene it was measured on (its
//! `mesh` cell is the scene's name).

use nklut_tables::columns::{Column, Integer, OptionalFloat};
use nklut_tables::effects_tables::{ao_errors, ao_timing};
use std::collections::BTreeMap;
use std::fmt::{Display, Write};

use anyhow::Result;

use super::charts::{self, CostPoint, ErrorAxis, Marker, PointStyle, Trace, PALETTE};
use super::csvdata::CsvTable;
use super::findings::short_device;
use super::html::{escape, number, TableText};
use super::inputs::DeviceTables;

/// A configuration as both tables name it.
#[derive(Clone, Debug, PartialEq)]
enum Configuration {
    /// Surfel AO: `hierarchy` or `brute_force`, and its passes.
    Surfels { emitters: String, passes: u64 },
    /// GTAO: the preset as labelled (with "(modified)" where the scene overrode a
    /// heuristic), the radius, slices × steps and the frames accumulated.
    Gtao { preset: String, radius: f64, slices: u64, steps: u64, frames: u64 },
}

impl Configuration {
    /// The configuration of row `row` of `ao_errors.csv` (`None`: a GTAO row of a table
    /// written before GTAO had presets).
    fn of_error(ao: &CsvTable, row: &[String]) -> Option<Configuration> {
        if ao.holds(ao_errors::TECHNIQUE) && ao.get(row, ao_errors::TECHNIQUE) == "gtao" {
            let preset = ao.get(row, ao_errors::GTAO_PRESET);
            let frames = ao.value(row, ao_errors::GTAO_FRAMES).unwrap_or(1.0);
            (!preset.is_empty()).then(|| Configuration::Gtao {
                preset: preset.to_string(),
                radius: ao.value(row, ao_errors::GTAO_RADIUS).unwrap_or(f64::NAN),
                slices: ao.value(row, ao_errors::GTAO_SLICES).unwrap_or(0.0) as u64,
                steps: ao.value(row, ao_errors::GTAO_STEPS).unwrap_or(0.0) as u64,
                frames: frames as u64,
            })
        } else {
            let emitters = if ao.raw(row, ao_errors::HIERARCHY) == "true" { "hierarchy" } else { "brute_force" };
            Some(Configuration::Surfels { emitters: emitters.into(), passes: ao.value(row, ao_errors::PASSES)? as u64 })
        }
    }

    /// The configuration of row `row` of an `ao_timing` table.
    fn of_timing(timing: &CsvTable, row: &[String]) -> Option<Configuration> {
        let emitters = timing.get(row, ao_timing::EMITTERS);
        if emitters == "gtao" {
            let preset = timing.get(row, ao_timing::PRESET);
            (!preset.is_empty()).then(|| Configuration::Gtao {
                preset: preset.to_string(),
                radius: timing.value(row, ao_timing::RADIUS).unwrap_or(f64::NAN),
                slices: timing.value(row, ao_timing::SLICES).unwrap_or(0.0) as u64,
                steps: timing.value(row, ao_timing::STEPS).unwrap_or(0.0) as u64,
                frames: timing.value(row, ao_timing::FRAMES).unwrap_or(1.0) as u64,
            })
        } else {
            Some(Configuration::Surfels { emitters: emitters.to_string(), passes: timing.value(row, ao_timing::PASSES)? as u64 })
        }
    }

    /// Whether two rows name the same configuration (radii equal to 1e-9 relative).
    fn same(&self, other: &Configuration) -> bool {
        match (self, other) {
            (
                Configuration::Gtao { preset: p, radius: r, slices: a, steps: b, frames: f },
                Configuration::Gtao { preset: q, radius: s, slices: c, steps: d, frames: g },
            ) => p == q && (a, b, f) == (c, d, g) && (r - s).abs() <= 1e-9 * r.abs().max(s.abs()),
            _ => self == other,
        }
    }

    /// The configuration in words: "surfels, tree, 2 passes", "GTAO xe-high r 2, 3×3, 64
    /// frames".
    fn label(&self) -> String {
        match self {
            Configuration::Surfels { emitters, passes } => {
                let tree = if emitters == "hierarchy" { "tree" } else { "brute force" };
                format!("surfels, {tree}, {passes} pass{}", if *passes == 1 { "" } else { "es" })
            }
            Configuration::Gtao { preset, radius, slices, steps, frames } => gtao_label(Some(preset), radius, slices, steps, *frames),
        }
    }

    /// Its family on the chart: a colour each.
    fn family(&self) -> Family {
        match self {
            Configuration::Surfels { .. } => Family::Surfels,
            Configuration::Gtao { preset, .. } if preset.starts_with("xe-") => Family::XeGtao,
            Configuration::Gtao { preset, .. } if preset.starts_with("unreal") => Family::Unreal,
            Configuration::Gtao { .. } => Family::Bare,
        }
    }
}

/// A GTAO configuration in words, as the report names it in every AO chart and table: "GTAO
/// xe-high r 2, 3×3, 64 frames" (no preset where a table written before presets names
/// none; the frames only where more than one).
pub(super) fn gtao_label(preset: Option<&str>, radius: impl Display, slices: impl Display, steps: impl Display, frames: u64) -> String {
    let preset = preset.map_or(String::new(), |p| format!(" {p}"));
    let frames = if frames > 1 { format!(", {frames} frames") } else { String::new() };
    format!("GTAO{preset} r {radius}, {slices}×{steps}{frames}")
}

/// The chart's colours: the surfels, and GTAO as the paper gives it, as XeGTAO ships it and
/// as Unreal does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Family {
    Surfels,
    Bare,
    XeGtao,
    Unreal,
}

impl Family {
    const ALL: [Family; 4] = [Family::Surfels, Family::Bare, Family::XeGtao, Family::Unreal];

    fn name(self) -> &'static str {
        match self {
            Family::Surfels => "surfels",
            Family::Bare => "GTAO, Algorithm 1",
            Family::XeGtao => "XeGTAO presets",
            Family::Unreal => "Unreal's GTAO",
        }
    }

    fn color(self) -> plotters::style::RGBColor {
        match self {
            Family::Surfels => PALETTE[1],
            Family::Bare => PALETTE[2],
            Family::XeGtao => PALETTE[3],
            Family::Unreal => PALETTE[5],
        }
    }
}

/// One configuration's point: its error rows and its timing rows.
struct Measured {
    configuration: Configuration,
    errors: Vec<usize>,
    timings: Vec<usize>,
    /// The frame size its GTAO times are of ("256×256"; empty for the surfels, whose time
    /// does not depend on it).
    frame: String,
}

/// The configurations of `ao` that `timing` timed on scene `scene`: for GTAO, the rows of
/// the smallest frame measured.
fn measured(ao: &CsvTable, timing: &CsvTable, scene: &str) -> Vec<Measured> {
    let mut out: Vec<Measured> = Vec::new();
    for (r, row) in ao.rows.iter().enumerate() {
        let Some(configuration) = Configuration::of_error(ao, row) else { continue };
        match out.iter_mut().find(|m| m.configuration.same(&configuration)) {
            Some(m) => m.errors.push(r),
            None => out.push(Measured { configuration, errors: vec![r], timings: Vec::new(), frame: String::new() }),
        }
    }
    let of_scene = |row: &[String]| !timing.holds(ao_timing::MESH) || timing.get(row, ao_timing::MESH) == scene;
    let pixels = |row: &[String]| timing.value(row, ao_timing::WIDTH).unwrap_or(0.0) * timing.value(row, ao_timing::HEIGHT).unwrap_or(0.0);
    for m in &mut out {
        let timed: Vec<usize> = (0..timing.rows.len())
            .filter(|&r| {
                let row = &timing.rows[r];
                of_scene(row) && Configuration::of_timing(timing, row).is_some_and(|c| c.same(&m.configuration))
            })
            .collect();
        let smallest = timed.iter().map(|&r| pixels(&timing.rows[r])).fold(f64::INFINITY, f64::min);
        m.timings = timed.into_iter().filter(|&r| pixels(&timing.rows[r]) == smallest).collect();
        if let (Some(&first), Configuration::Gtao { .. }) = (m.timings.first(), &m.configuration) {
            let row = &timing.rows[first];
            m.frame = format!("{}×{}", timing.raw(row, ao_timing::WIDTH), timing.raw(row, ao_timing::HEIGHT));
        }
    }
    out.retain(|m| !m.timings.is_empty());
    out
}

/// Where a chart's times come from: its title and the path a trace names.
struct Source<'a> {
    device: String,
    path: String,
    table: &'a CsvTable,
}

/// The `ao_timing` tables of this machine (`gpu`, `make gpu`) and of every device.
fn sources<'a>(gpu: Option<(&'a str, &'a CsvTable)>, devices: &'a BTreeMap<String, DeviceTables>) -> Vec<Source<'a>> {
    let mut out: Vec<Source> =
        gpu.into_iter().map(|(path, table)| Source { device: "this machine (make gpu)".into(), path: path.to_string(), table }).collect();
    for (device, tables) in devices {
        let Some(table) = tables.ao_timing.as_ref() else { continue };
        out.push(Source { device: short_device(device), path: tables.table_path(device, "ao_timing.csv"), table });
    }
    out
}

/// The section: per device that timed the scene's configurations, the chart and its table;
/// nothing where none did.
pub fn section(
    html: &mut String,
    scene: &str,
    (path, ao): (&str, &CsvTable),
    gpu: Option<(&str, &CsvTable)>,
    devices: &BTreeMap<String, DeviceTables>,
) -> Result<()> {
    for source in sources(gpu, devices) {
        let measured = measured(ao, source.table, scene);
        if measured.is_empty() {
            continue;
        }
        let _ = write!(html, "<h4>Error against GPU time on {}</h4>", escape(&source.device));
        let points: Vec<CostPoint> = cost_points(&measured, (path, ao), &source);
        let families: Vec<Family> = Family::ALL.into_iter().filter(|f| measured.iter().any(|m| m.configuration.family() == *f)).collect();
        if points.len() < 2 {
            let _ = write!(html, "<p class=\"no-chart\">{}</p>", escape(&format!("One configuration timed only: {}.", points[0].label)));
        } else {
            let chart =
                charts::cost_chart(&points, &format!("GPU time of one frame on {} (ms)", source.device), ErrorAxis::Absolute, (640, 360))?;
            let legend = charts::point_legend("technique", families.iter().map(|f| (f.name(), f.color(), Marker::Circle)));
            let frames: Vec<&str> = measured.iter().map(|m| m.frame.as_str()).filter(|f| !f.is_empty()).collect();
            let gtao = match frames.first() {
                Some(frame) => format!(
                    "GTAO's frame at {frame} with its denoiser passes (a preset that accumulates frames reaches its error after that many: the table's time to convergence), "
                ),
                None => "no GTAO configuration of the scene timed there; ".to_string(),
            };
            let caption = format!(
                "Accessibility error per covered pixel against the full ray-traced reference (pixel-weighted over the objects) against the median GPU time of one frame on {} ({}): {gtao}the surfels' passes over the scene (object space: the same at any frame size). Coloured by technique; the Pareto front is joined and labelled.",
                source.device, source.path
            );
            let _ = write!(html, "<figure class=\"plot\">{}{legend}<figcaption>{}</figcaption></figure>", chart.svg, escape(&caption));
        }
        html.push_str(&cost_table(&measured, (path, ao), source.table).html("ao-cost"));
    }
    Ok(())
}

/// The chart's points: per configuration, the mean time of its timing rows and its error
/// rows' pixel-weighted mean error, styled by family (the marker counts the family's
/// configurations).
fn cost_points(measured: &[Measured], (path, ao): (&str, &CsvTable), source: &Source) -> Vec<CostPoint> {
    let traced: Vec<(String, Trace, Trace)> = measured
        .iter()
        .map(|m| {
            let time = Trace::mean_of(&source.path, source.table, ao_timing::MEDIAN_MS, m.timings.clone(), None);
            let error = Trace::mean_of(path, ao, ao_errors::PIXEL_MEAN_ERROR, m.errors.clone(), Some(ao_errors::PIXELS));
            (m.configuration.label(), time, error)
        })
        .collect();
    let front = charts::pareto_front(&traced.iter().map(|(_, x, y)| (x.value, y.value)).collect::<Vec<_>>());
    let mut seen: BTreeMap<&str, usize> = BTreeMap::new();
    traced
        .into_iter()
        .zip(front)
        .zip(measured)
        .map(|(((label, x, y), pareto), m)| {
            let family = m.configuration.family();
            let nth = seen.entry(family.name()).or_default();
            let style = PointStyle { color: family.color(), marker: Marker::nth(*nth) };
            *nth += 1;
            CostPoint { label, cost: x.value, error: y.value, pareto, trace: Some([x, y]), style: Some(style) }
        })
        .collect()
}

/// The table beside the chart: per configuration, its time per frame and to convergence,
/// and its mean and signed error against both references (pixel-weighted over the objects;
/// percentiles, which do not combine so, are in the AO section's per-object tables).
fn cost_table(measured: &[Measured], (path, ao): (&str, &CsvTable), timing: &CsvTable) -> TableText {
    let mut table = TableText::new(&[
        "configuration",
        "frame",
        "GPU ms per frame",
        "GPU ms to convergence",
        "mean |e| per covered pixel, full reference",
        "signed mean e, full reference",
        "mean |e|, range-limited reference",
        "signed mean e, range-limited reference",
    ]);
    let mean = |column: Column<OptionalFloat>, rows: &[usize], weight: Option<Column<Integer>>, t: &CsvTable| {
        let value = Trace::mean_of(path, t, column, rows.to_vec(), weight).value;
        if value.is_finite() {
            number(value)
        } else {
            "–".to_string()
        }
    };
    for m in measured {
        table.row(vec![
            m.configuration.label(),
            if m.frame.is_empty() { "any".into() } else { m.frame.clone() },
            mean(ao_timing::MEDIAN_MS.numbers(), &m.timings, None, timing),
            mean(ao_timing::CONVERGENCE_MS, &m.timings, None, timing),
            mean(ao_errors::PIXEL_MEAN_ERROR, &m.errors, Some(ao_errors::PIXELS), ao),
            mean(ao_errors::PIXEL_SIGNED_ERROR, &m.errors, Some(ao_errors::PIXELS), ao),
            mean(ao_errors::PIXEL_MEAN_ERROR_WITHIN_RADIUS, &m.errors, Some(ao_errors::PIXELS), ao),
            mean(ao_errors::PIXEL_SIGNED_ERROR_WITHIN_RADIUS, &m.errors, Some(ao_errors::PIXELS), ao),
        ]);
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> CsvTable {
        CsvTable::parse(text.as_bytes()).unwrap()
    }

    /// Hand-made tables: the surfel tree at 1 and 2 passes and GTAO presets, one timed at two
    /// frame sizes, one on another scene, one (3 × 4 steps) not timed. Each configuration
    /// takes its own rows; the GTAO preset its smallest frame's; the other scene's row, the
    /// untimed steps and the untimed surfel pass count nowhere; the error is the pixel-weighted mean over the objects
    /// ((0.1·100 + 0.3·300)/400 = 0.25).
    #[test]
    fn configurations_meet_their_timings_on_their_own_scene() {
        let ao = table(
            "mesh,technique,hierarchy,passes,gtao_preset,gtao_radius,gtao_slices,gtao_steps,gtao_frames,pixels,pixel_mean_error,pixel_signed_error,pixel_mean_error_within_radius,pixel_signed_error_within_radius\n\
             bunny,surfels,true,1,,,,,,100,0.1,-0.1,,\n\
             ground,surfels,true,1,,,,,,300,0.3,0.1,,\n\
             bunny,surfels,true,2,,,,,,100,0.05,0.05,,\n\
             bunny,surfels,true,3,,,,,,100,0.04,0.04,,\n\
             bunny,gtao,,,xe-high,2,3,3,64,100,0.06,-0.02,0.01,0.005\n\
             bunny,gtao,,,xe-high,2,3,4,64,100,0.07,0.07,0.01,0.01\n\
             bunny,gtao,,,unreal,2,2,8,64,100,0.08,0.08,0.02,0.02\n",
        );
        let timing = table(
            "mesh,emitters,passes,width,height,slices,steps,preset,radius,frames,median_ms,convergence_ms\n\
             scene,hierarchy,1,0,0,0,0,,,0,700,\n\
             scene,hierarchy,2,0,0,0,0,,,0,1400,\n\
             scene,gtao,1,1024,1024,3,3,xe-high,2,64,1800,115200\n\
             scene,gtao,1,256,256,3,3,xe-high,2,64,100,6400\n\
             other,gtao,1,256,256,2,8,unreal,2,64,90,5760\n",
        );
        let measured = measured(&ao, &timing, "scene");
        let found: Vec<(String, Vec<usize>, Vec<usize>, &str)> =
            measured.iter().map(|m| (m.configuration.label(), m.errors.clone(), m.timings.clone(), m.frame.as_str())).collect();
        assert_eq!(
            found,
            [
                ("surfels, tree, 1 pass".to_string(), vec![0, 1], vec![0], ""),
                ("surfels, tree, 2 passes".to_string(), vec![2], vec![1], ""),
                ("GTAO xe-high r 2, 3×3, 64 frames".to_string(), vec![4], vec![3], "256×256"),
            ]
        );
        let source = Source { device: "d".into(), path: "t.csv".into(), table: &timing };
        let points = cost_points(&measured, ("a.csv", &ao), &source);
        assert_eq!(points.iter().map(|p| (p.cost, p.error)).collect::<Vec<_>>(), [(700.0, 0.25), (1400.0, 0.05), (100.0, 0.06)]);
        let text = cost_table(&measured, ("a.csv", &ao), &timing);
        assert_eq!(text.rows[2], ["GTAO xe-high r 2, 3×3, 64 frames", "256×256", "100", "6400", "0.0600", "-0.0200", "0.0100", "0.00500"]);
        assert_eq!(text.rows[0][3], "–");
        // The surfels' signed error, pixel-weighted by hand: (−0.1·100 + 0.1·300)/400 = 0.05.
        assert_eq!(text.rows[0][5], "0.0500");
    }
}
