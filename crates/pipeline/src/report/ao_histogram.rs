//! The ambient-occlusion error histograms on the effects page, drawn from
//! `ao_histogram.csv` (binned once by `nklut effects` with `stats::Histogram`): per object
//! and technique at the technique's largest pass count, the share of the object's vertices and
//! of the pixels it covers in each bin of the signed error e = accessibility − reference
//! (positive: the surfels under-occlude). Each bar is one row of the table and says which.

use nklut_tables::effects_tables::ao_histogram;
use std::fmt::Write;

use anyhow::Result;

use super::charts::{self, Bar, BarSeries, HistogramChart, PALETTE};
use super::csvdata::CsvTable;
use super::html::escape;

/// The weightings drawn (the table's `weighting` column) with their names and colours;
/// the area-weighted histograms stay in the table.
const DRAWN: [(&str, &str, usize); 2] = [("vertex", "per vertex", 6), ("pixel", "per covered pixel", 1)];

/// The bars of `table`'s histogram of `mesh`, `technique`, `passes` and `weighting`, in
/// row order.
pub fn bars(table: &CsvTable, mesh: &str, technique: &str, passes: &str, weighting: &str) -> Vec<Bar> {
    table
        .rows
        .iter()
        .enumerate()
        .filter(|(_, row)| {
            table.get(row, ao_histogram::MESH) == mesh
                && table.get(row, ao_histogram::TECHNIQUE) == technique
                && table.raw(row, ao_histogram::PASSES) == passes
                && table.get(row, ao_histogram::WEIGHTING) == weighting
        })
        .filter_map(|(r, row)| {
            Some(Bar {
                lower: table.value(row, ao_histogram::LOWER)?,
                upper: table.value(row, ao_histogram::UPPER)?,
                share: table.value(row, ao_histogram::SHARE)?,
                count: table.raw(row, ao_histogram::COUNT).parse().ok()?,
                row: r,
            })
        })
        .collect()
}

/// The largest pass count of `technique`'s rows (`None`: no row with a pass count).
pub fn largest_passes(table: &CsvTable, technique: &str) -> Option<u64> {
    table
        .rows_where(ao_histogram::TECHNIQUE.name, technique)
        .filter_map(|row| table.raw(row, ao_histogram::PASSES).parse::<u64>().ok())
        .max()
}

/// The histograms' part of the AO section: one chart per object and technique, at the
/// technique's largest pass count.
pub fn section(html: &mut String, (path, table): (&str, &CsvTable)) -> Result<()> {
    let _ = writeln!(
        html,
        "<p>Distribution of e = accessibility − reference (positive: too light, the surfels under-occlude) per object and technique at its largest pass count: the share of the object's vertices and of the pixels it covers in each bin (<code>{}</code>; the end bins also hold everything beyond them; the area-weighted histograms are in the table).</p>",
        escape(path)
    );
    let legend = charts::legend(DRAWN.iter().map(|&(_, name, color)| (name, PALETTE[color], false)));
    html.push_str("<div class=\"charts\">");
    let mut first = true;
    for mesh in table.distinct(ao_histogram::MESH.name) {
        for technique in table.distinct(ao_histogram::TECHNIQUE.name) {
            let Some(passes) = largest_passes(table, technique) else { continue };
            let passes = passes.to_string();
            let series: Vec<BarSeries> = DRAWN
                .iter()
                .map(|&(weighting, name, color)| BarSeries {
                    name: name.to_string(),
                    color: PALETTE[color],
                    bars: bars(table, mesh, technique, &passes, weighting),
                })
                .filter(|s| !s.bars.is_empty())
                .collect();
            let caption = format!("{mesh}, {technique}, {passes} passes");
            let svg = charts::histogram_chart(
                &HistogramChart { table: path, x_name: "signed error e (accessibility)", series: &series, caption: Some(&caption) },
                (440, 300),
            )?;
            if !svg.is_empty() {
                let _ = write!(
                    html,
                    "<figure class=\"plot histogram\" data-mesh=\"{}\" data-technique=\"{}\" data-passes=\"{}\">{svg}{}</figure>",
                    escape(mesh),
                    escape(technique),
                    escape(&passes),
                    if first { legend.as_str() } else { "" }
                );
                first = false;
            }
        }
    }
    html.push_str("</div>\n");
    Ok(())
}
