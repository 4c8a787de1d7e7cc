//! The `ao_histogram` table: the distribution of the signed accessibility error
//! e = a − reference (positive: the surfels under-occlude) per object, technique and pass
//! count, three ways as in `ao_errors` — per vertex, weighted by the vertices' areas, and
//! per pixel of the picture the object covers — binned once here
//! (`nklut_tables::stats::Histogram`: equal bins over [`AO_HISTOGRAM_BINS`], values
//! beyond the range counted in the end bins) for the report to draw. One line per bin.

use nklut_tables::effects_tables::ao_histogram;
use nklut_tables::output::Table;
use nklut_tables::stats::{Histogram, HistogramBins};

/// The bins of every AO histogram: 40 bins of 0.025 over −0.5 … 0.5 (the tails beyond in
/// the end bins), so histograms of every object, technique and pass compare bin by bin.
pub const AO_HISTOGRAM_BINS: HistogramBins = HistogramBins { low: -0.5, high: 0.5, bins: 40 };

/// What an entry of a histogram is: a vertex (weight 1), a vertex weighted by its area, or
/// a covered pixel (weight 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Weighting {
    Vertex,
    Area,
    Pixel,
}

impl Weighting {
    /// The name in the table's `weighting` column.
    pub fn name(self) -> &'static str {
        match self {
            Weighting::Vertex => "vertex",
            Weighting::Area => "area",
            Weighting::Pixel => "pixel",
        }
    }
}

/// One histogram: whose errors (object, technique, passes) and how they are weighted.
#[derive(Clone, Debug, PartialEq)]
pub struct HistogramRow {
    pub mesh: String,
    /// "brute force" or "tree" (surfel AO's two ways of gathering emitters).
    pub technique: String,
    pub passes: u32,
    pub weighting: Weighting,
    pub histogram: Histogram,
}

/// The histograms of one object's per-vertex signed `errors` with its vertices' `areas`
/// (none for no vertex error: a technique measured per pixel only), and of its per-pixel
/// errors where a picture was measured.
pub fn histogram_rows(
    mesh: &str,
    technique: &str,
    passes: u32,
    errors: &[f64],
    areas: &[f64],
    pixels: Option<&[f64]>,
) -> Vec<HistogramRow> {
    let ones = vec![1.0; errors.len()];
    let mut measured = Vec::new();
    if !errors.is_empty() {
        measured.extend([(Weighting::Vertex, errors, ones.as_slice()), (Weighting::Area, errors, areas)]);
    }
    let pixel_ones = pixels.map(|p| vec![1.0; p.len()]);
    if let (Some(pixels), Some(ones)) = (pixels, &pixel_ones) {
        measured.push((Weighting::Pixel, pixels, ones.as_slice()));
    }
    measured
        .into_iter()
        .filter_map(|(weighting, values, weights)| {
            let histogram = Histogram::weighted(values, weights, AO_HISTOGRAM_BINS)?;
            Some(HistogramRow { mesh: mesh.to_string(), technique: technique.to_string(), passes, weighting, histogram })
        })
        .collect()
}

/// The `ao_histogram` table: one line per histogram and bin.
pub fn ao_histogram_table(rows: &[HistogramRow]) -> Table {
    let lines: Vec<(&HistogramRow, usize)> = rows.iter().flat_map(|r| (0..r.histogram.counts.len()).map(move |k| (r, k))).collect();
    let share = |r: &HistogramRow, k: usize| {
        let total = r.histogram.total_weight();
        if total > 0.0 {
            r.histogram.weights[k] / total
        } else {
            0.0
        }
    };
    let mut table = Table::new();
    table
        .put(ao_histogram::MESH, lines.iter().map(|(r, _)| r.mesh.clone()).collect())
        .put(ao_histogram::TECHNIQUE, lines.iter().map(|(r, _)| r.technique.clone()).collect())
        .put(ao_histogram::PASSES, lines.iter().map(|(r, _)| r.passes as i64).collect())
        .put(ao_histogram::WEIGHTING, lines.iter().map(|(r, _)| r.weighting.name().to_string()).collect())
        .put(ao_histogram::BIN, lines.iter().map(|&(_, k)| k as i64).collect())
        .put(ao_histogram::LOWER, lines.iter().map(|(r, k)| r.histogram.edges[*k]).collect())
        .put(ao_histogram::UPPER, lines.iter().map(|(r, k)| r.histogram.edges[k + 1]).collect())
        .put(ao_histogram::COUNT, lines.iter().map(|(r, k)| r.histogram.counts[*k] as i64).collect())
        .put(ao_histogram::WEIGHT, lines.iter().map(|(r, k)| r.histogram.weights[*k]).collect())
        .put(ao_histogram::SHARE, lines.iter().map(|(r, k)| share(r, *k)).collect());
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An object of three vertices (errors −0.6, 0.01, 0.3; areas 1, 2, 5) and two pixels
    /// (0.01, 0.02): the vertex histogram counts one each in bins 0 (below −0.5), 20
    /// ([0, 0.025)) and 32 ([0.3, 0.325)); the area one weighs them 1, 2, 5 (shares 1/8,
    /// 2/8, 5/8); the pixel one has both pixels in bin 20. The table has 40 lines per
    /// histogram with the edges, counts, weights and shares.
    #[test]
    fn histograms_of_an_object_as_a_table() {
        let rows = histogram_rows("cube", "tree", 2, &[-0.6, 0.01, 0.3], &[1.0, 2.0, 5.0], Some(&[0.01, 0.02]));
        assert_eq!(rows.iter().map(|r| r.weighting).collect::<Vec<_>>(), [Weighting::Vertex, Weighting::Area, Weighting::Pixel]);
        let nonzero = |h: &Histogram| h.counts.iter().enumerate().filter(|(_, &c)| c > 0).map(|(k, &c)| (k, c)).collect::<Vec<_>>();
        assert_eq!(nonzero(&rows[0].histogram), [(0, 1), (20, 1), (32, 1)]);
        assert_eq!(nonzero(&rows[1].histogram), [(0, 1), (20, 1), (32, 1)]);
        assert_eq!((rows[1].histogram.weights[0], rows[1].histogram.weights[20], rows[1].histogram.weights[32]), (1.0, 2.0, 5.0));
        assert_eq!(nonzero(&rows[2].histogram), [(20, 2)]);
        assert_eq!(histogram_rows("cube", "tree", 2, &[0.0], &[1.0], None).len(), 2, "no picture: no pixel histogram");
        let per_pixel_only = histogram_rows("cube", "screen space", 0, &[], &[], Some(&[0.01]));
        assert_eq!(per_pixel_only.iter().map(|r| r.weighting).collect::<Vec<_>>(), [Weighting::Pixel]);

        let table = ao_histogram_table(&rows);
        assert_eq!(table.rows(), 3 * 40);
        let csv = String::from_utf8(table.to_csv().unwrap()).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines[0], "mesh,technique,passes,weighting,bin,lower,upper,count,weight,share");
        assert_eq!(lines[1], "cube,tree,2,vertex,0,-0.5,-0.475,1,1,0.3333333333333333");
        assert_eq!(lines[1 + 40 + 32], "cube,tree,2,area,32,0.3,0.325,1,5,0.625");
        assert_eq!(lines[1 + 80 + 20], "cube,tree,2,pixel,20,0,0.025,2,2,1");
        assert_eq!(lines[1 + 80 + 39], "cube,tree,2,pixel,39,0.475,0.5,0,0,0");
    }
}
