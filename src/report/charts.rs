//! The report's plots, drawn with plotters into SVG strings that are inlined in the HTML.

use anyhow::{anyhow, Result};
use plotters::prelude::*;

/// One curve family of the Fresnel plot: a method's F per channel over the θ grid.
pub struct Series {
    pub name: String,
    pub color: RGBColor,
    pub dashed: bool,
    /// F for red, green, blue at each θ of the grid.
    pub values: [Vec<f64>; 3],
}

/// Colours of the methods, fixed so every plot reads the same.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 0, 0),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(213, 94, 0),
    RGBColor(0, 114, 178),
    RGBColor(120, 120, 120),
];

fn plot_error<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("drawing a plot: {e:?}")
}

/// F against θ (degrees), one panel per colour channel, like the study's figures.
pub fn fresnel_curves(theta_deg: &[f64], series: &[Series], size: (u32, u32)) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let panels = root.split_evenly((1, 3));
        for (channel, (panel, channel_name)) in panels.iter().zip(crate::spectrum::CHANNEL_NAMES).enumerate() {
            let mut chart = ChartBuilder::on(panel)
                .caption(channel_name, ("sans-serif", 13))
                .margin(4)
                .x_label_area_size(26)
                .y_label_area_size(34)
                .build_cartesian_2d(0f64..90f64, 0f64..1.05f64)
                .map_err(plot_error)?;
            chart
                .configure_mesh()
                .x_labels(4)
                .y_labels(6)
                .disable_mesh()
                .x_desc("θ (°)")
                .label_style(("sans-serif", 10))
                .draw()
                .map_err(plot_error)?;
            for s in series {
                let points = theta_deg.iter().copied().zip(s.values[channel].iter().copied());
                let style = ShapeStyle::from(&s.color).stroke_width(1);
                let drawn = if s.dashed {
                    chart.draw_series(DashedLineSeries::new(points, 4, 3, style)).map_err(plot_error)?
                } else {
                    chart.draw_series(LineSeries::new(points, style)).map_err(plot_error)?
                };
                if channel == 0 {
                    let color = s.color;
                    drawn.label(s.name.clone()).legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 14, y)], color));
                }
            }
            if channel == 0 {
                chart
                    .configure_series_labels()
                    .position(SeriesLabelPosition::UpperLeft)
                    .label_font(("sans-serif", 9))
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK.mix(0.3))
                    .draw()
                    .map_err(plot_error)?;
            }
        }
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// A point of the cost chart.
pub struct CostPoint {
    pub label: String,
    pub cost: f64,
    pub error: f64,
    pub pareto: bool,
}

/// Mean relative error against cost, both log scales; the Pareto front joined by a line.
pub fn cost_chart(points: &[CostPoint], cost_label: &str, size: (u32, u32)) -> Result<String> {
    let finite: Vec<&CostPoint> = points.iter().filter(|p| p.cost > 0.0 && p.error > 0.0 && p.cost.is_finite() && p.error.is_finite()).collect();
    if finite.is_empty() {
        return Ok(String::new());
    }
    let (x_lo, x_hi) = bounds(finite.iter().map(|p| p.cost));
    let (y_lo, y_hi) = bounds(finite.iter().map(|p| p.error));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let mut chart = ChartBuilder::on(&root)
            .margin(10)
            .x_label_area_size(36)
            .y_label_area_size(56)
            .build_cartesian_2d((x_lo..x_hi).log_scale(), (y_lo..y_hi).log_scale())
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc(cost_label)
            .y_desc("mean relative error")
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 11))
            .draw()
            .map_err(plot_error)?;
        let mut front: Vec<(f64, f64)> = finite.iter().filter(|p| p.pareto).map(|p| (p.cost, p.error)).collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart.draw_series(LineSeries::new(front, ShapeStyle::from(&PALETTE[5]).stroke_width(2))).map_err(plot_error)?;
        chart
            .draw_series(finite.iter().map(|p| {
                let color = if p.pareto { PALETTE[5] } else { PALETTE[6] };
                EmptyElement::at((p.cost, p.error))
                    + Circle::new((0, 0), 3, ShapeStyle::from(&color).filled())
                    + Text::new(p.label.clone(), (5, -5), ("sans-serif", 9))
            }))
            .map_err(plot_error)?;
        root.present().map_err(plot_error)?;
    }
    Ok(svg)
}

/// Log-scale bounds with half a decade of margin.
fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    (lo / 3.0, hi * 3.0)
}

/// Indices of the points on the Pareto front: no other point is both cheaper (or equal)
/// and more accurate (or equal), with one strict.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(cost, error)| {
            !points.iter().any(|&(c, e)| c <= cost && e <= error && (c < cost || e < error))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_front_keeps_undominated_points() {
        let points = [(1.0, 0.1), (2.0, 0.01), (3.0, 0.05), (0.5, 0.5), (2.0, 0.02)];
        assert_eq!(pareto_front(&points), vec![true, true, false, true, false]);
    }

    #[test]
    fn plots_are_svg_with_one_path_per_series_and_channel() {
        let theta: Vec<f64> = (0..=90).map(f64::from).collect();
        let flat = vec![0.5; theta.len()];
        let series = vec![Series { name: "exact".into(), color: PALETTE[0], dashed: false, values: [flat.clone(), flat.clone(), flat] }];
        let svg = fresnel_curves(&theta, &series, (600, 200)).unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        assert!(svg.matches("<polyline").count() >= 3);
        let chart = cost_chart(&[CostPoint { label: "lut".into(), cost: 1.0, error: 0.01, pareto: true }], "ns", (400, 300)).unwrap();
        assert!(chart.contains("lut"));
    }
}
