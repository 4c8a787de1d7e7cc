//! The report's plots, drawn with plotters into SVG strings inlined in the HTML. Rules
//! every plot keeps: text at 13 px or more, both axes named with their unit, legends
//! outside the data (the pages draw them in HTML beside the plot), θ ticks at 0°, 30°,
//! 60° and 90°.

use std::fmt::Write;

use anyhow::{anyhow, Result};
use plotters::prelude::*;

use super::curves::PlotCurve;
use nklut_optics::fresnel::Method;
use nklut_optics::spectrum::{Channels, CHANNEL_NAMES};

/// Font size (px) of tick labels and axis names; captions are one larger.
pub const FONT_PX: u32 = 13;
/// plotters' SVG backend writes font-size = requested size / 1.24 (points to pixels).
const SVG_FONT_SCALE: f64 = 1.24;
const FONT: (&str, f64) = ("sans-serif", FONT_PX as f64 * SVG_FONT_SCALE + 0.01);
const CAPTION: (&str, f64) = ("sans-serif", (FONT_PX + 1) as f64 * SVG_FONT_SCALE + 0.01);
/// Stroke width of curves (distinct from the 1 px axes, so `dash` finds them).
const CURVE_WIDTH: u32 = 2;

/// Colours of the methods, fixed so every plot reads the same (Okabe–Ito, then grey).
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

/// The methods' colours, one per method in the order of [`Method::ALL`] (Okabe–Ito, then
/// Paul Tol's muted scheme): none is the reference's grey or the fitted curve's wine.
const METHOD_PALETTE: [RGBColor; 12] = [
    RGBColor(0, 0, 0),
    RGBColor(230, 159, 0),
    RGBColor(240, 228, 66),
    RGBColor(86, 180, 233),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(213, 94, 0),
    RGBColor(0, 114, 178),
    RGBColor(68, 170, 153),
    RGBColor(153, 153, 51),
    RGBColor(51, 34, 136),
    RGBColor(136, 204, 238),
];

// A method beyond the palette does not build: give the palette another colour.
const _: () = assert!(Method::ALL.len() <= METHOD_PALETTE.len(), "more Fresnel methods than METHOD_PALETTE has colours");

/// The colour of a method's curves: its place in [`Method::ALL`] in [`METHOD_PALETTE`];
/// `curves`' tests hold every method's colour apart from the others' and from
/// [`REFERENCE_COLOR`] and [`FITTED_COLOR`].
pub const fn method_color(method: Method) -> RGBColor {
    METHOD_PALETTE[method.index()]
}

/// The spectral reference's curve (and the F = 1 line of the reflectance plots).
pub const REFERENCE_COLOR: RGBColor = PALETTE[7];
/// Exact Fresnel with the fitted indices (Tol's wine: apart from every method's colour).
pub const FITTED_COLOR: RGBColor = RGBColor(136, 34, 85);

/// CSS `#rrggbb` of a palette colour (for the HTML legends).
pub fn css(color: RGBColor) -> String {
    format!("#{:02x}{:02x}{:02x}", color.0, color.1, color.2)
}

fn plot_error<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("drawing a plot: {e:?}")
}

/// θ axis ticks.
const THETA_TICKS: [f64; 4] = [0.0, 30.0, 60.0, 90.0];
const THETA_NAME: &str = "angle of incidence θ (°)";

fn line<'a, DB: DrawingBackend + 'a>(chart: &mut Chart<'a, DB>, points: Vec<(f64, f64)>, color: RGBColor, dashed: bool) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let _ = dashed; // drawn solid, dashed afterwards by `dash` (one element per curve)
    chart.draw_series(LineSeries::new(points, ShapeStyle::from(&color).stroke_width(CURVE_WIDTH))).map_err(plot_error)?;
    Ok(())
}

/// Give the curves of `color` a dash pattern: plotters draws a dashed series as one
/// element per dash, this keeps one polyline per curve (the SVG stays small).
fn dash(svg: &mut String, color: RGBColor) {
    let solid = format!("stroke=\"#{:02X}{:02X}{:02X}\" stroke-width=\"{CURVE_WIDTH}\"", color.0, color.1, color.2);
    *svg = svg.replace(&solid, &format!("{solid} stroke-dasharray=\"6 4\""));
}

type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>>;

/// Tick marks and their labels under the x axis of `chart` (drawn on `area`, the chart's own
/// drawing area or the root it was built on), at each `(x, label)`.
fn x_ticks<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    chart: &Chart<DB>,
    ticks: impl IntoIterator<Item = (f64, String)>,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let (origin_x, origin_y) = area.get_base_pixel();
    let style = TextStyle::from(FONT)
        .pos(plotters::style::text_anchor::Pos::new(plotters::style::text_anchor::HPos::Center, plotters::style::text_anchor::VPos::Top));
    for (tick, label) in ticks {
        let (x, y) = chart.backend_coord(&(tick, 0.0));
        let (x, y) = (x - origin_x, y - origin_y);
        area.draw(&PathElement::new(vec![(x, y), (x, y + 5)], BLACK)).map_err(plot_error)?;
        area.draw(&Text::new(label, (x, y + 7), style.clone())).map_err(plot_error)?;
    }
    Ok(())
}

/// A chart over θ ∈ [0°, 90°] on `area`: ticks every 30°, both axes named, no grid.
fn theta_chart<'a, DB: DrawingBackend + 'a>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    caption: Option<&str>,
    margin_right: u32,
    top: f64,
    y_name: &str,
    y_label: &dyn Fn(&f64) -> String,
) -> Result<Chart<'a, DB>>
where
    DB::ErrorType: 'static,
{
    let mut builder = ChartBuilder::on(area);
    if let Some(caption) = caption {
        builder.caption(caption, CAPTION);
    }
    let mut chart = builder
        .margin(8)
        .margin_right(margin_right)
        .x_label_area_size(42)
        .y_label_area_size(58)
        .build_cartesian_2d(0f64..90f64, 0f64..top)
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(0)
        .y_labels(6)
        .x_desc(THETA_NAME)
        .y_desc(y_name)
        .label_style(FONT)
        .axis_desc_style(FONT)
        .y_label_formatter(y_label)
        .draw()
        .map_err(plot_error)?;
    x_ticks(area, &chart, THETA_TICKS.map(|tick| (tick, format!("{tick}"))))?;
    Ok(chart)
}

/// F against θ, one panel per colour channel (named with its wavelength).
pub fn fresnel_curves(theta_deg: &[f64], curves: &[PlotCurve], channels: &Channels, size: (u32, u32)) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let wavelengths = channels.nanometres();
        for (c, panel) in root.split_evenly((1, 3)).iter().enumerate() {
            let top = curves.iter().flat_map(|s| s.rgb.iter().map(move |v| v[c])).fold(1.0f64, f64::max);
            let caption = format!("{} channel, {} nm", CHANNEL_NAMES[c], wavelengths[c]);
            let mut chart = theta_chart(panel, Some(&caption), 14, top * 1.02, "reflectance F (linear)", &|v| format!("{v:.1}"))?;
            for s in curves {
                line(&mut chart, theta_deg.iter().copied().zip(s.channel(c)).collect(), s.color, s.dashed)?;
            }
        }
        root.present().map_err(plot_error)?;
    }
    for s in curves.iter().filter(|s| s.dashed) {
        dash(&mut svg, s.color);
    }
    Ok(svg)
}

/// One curve of the colour-difference plot.
pub struct DeltaE<'a> {
    pub curve: &'a PlotCurve,
    pub values: Vec<f64>,
}

/// The angle up to which a curve's values set the ΔE chart's range ([`delta_e_range`]).
pub const CLIP_BELOW_DEG: f64 = 80.0;

/// A curve the ΔE chart cuts at its top: its name, its largest value and where.
#[derive(Clone, Debug, PartialEq)]
pub struct Clipped {
    pub name: String,
    pub peak: f64,
    pub theta_deg: f64,
}

/// The ΔE chart's top and the curves cut by it. The rule: the largest value of any curve at
/// θ ≤ [`CLIP_BELOW_DEG`] (at least 4), unless no curve goes above 1.5 times that over the
/// whole range (then the largest value of all); times 1.05 for room. So one method's
/// spike near grazing (Schlick on a metal reaching ΔE 40 at 89°) does not flatten every
/// other curve; the curves above are drawn along the top edge and named in the chart's
/// caption.
pub fn delta_e_range(theta_deg: &[f64], series: &[DeltaE]) -> (f64, Vec<Clipped>) {
    let finite = |s: &DeltaE| -> Vec<(f64, f64)> {
        theta_deg.iter().copied().zip(s.values.iter().copied()).filter(|(_, v)| v.is_finite()).collect()
    };
    let below =
        series.iter().flat_map(|s| finite(s).into_iter().filter(|(t, _)| *t <= CLIP_BELOW_DEG).map(|(_, v)| v)).fold(4.0f64, f64::max);
    let all = series.iter().flat_map(|s| finite(s).into_iter().map(|(_, v)| v)).fold(4.0f64, f64::max);
    if all <= 1.5 * below {
        return (all * 1.05, Vec::new());
    }
    let top = below * 1.05;
    let clipped = series
        .iter()
        .filter_map(|s| {
            let (theta_deg, peak) = finite(s).into_iter().max_by(|a, b| a.1.total_cmp(&b.1))?;
            (peak > top).then(|| Clipped { name: s.curve.name.clone(), peak, theta_deg })
        })
        .collect();
    (top, clipped)
}

/// The caption that says a ΔE chart is cut: `ΔE axis cut at 6.3 (the largest value below
/// 80°): schlick reaches 41 at 89°`; the two highest peaks named, the others counted.
pub fn clipped_caption(top: f64, clipped: &[Clipped]) -> Option<String> {
    if clipped.is_empty() {
        return None;
    }
    let mut highest: Vec<&Clipped> = clipped.iter().collect();
    highest.sort_by(|a, b| b.peak.total_cmp(&a.peak));
    let mut named: Vec<String> =
        highest.iter().take(2).map(|c| format!("{} reaches {:.0} at {:.0}°", c.name, c.peak, c.theta_deg)).collect();
    if highest.len() > 2 {
        named.push(format!("{} more", highest.len() - 2));
    }
    Some(format!("ΔE axis cut at {top:.1} (the largest value below {CLIP_BELOW_DEG:.0}°): {}", named.join(", ")))
}

/// CIEDE2000 against the reference over θ, with the "just noticeable" level (1) as a
/// line and the "clearly visible" band (2–3) shaded, named in the right margin; the range
/// by [`delta_e_range`], a cut said in the chart's caption. Returns the SVG and, for a cut
/// chart, the figure's caption naming which curves reach how far ([`clipped_caption`]: a
/// chart's one caption line cannot hold it).
pub fn delta_e_chart(theta_deg: &[f64], series: &[DeltaE], size: (u32, u32)) -> Result<(String, Option<String>)> {
    let (top, clipped) = delta_e_range(theta_deg, series);
    let caption = (!clipped.is_empty()).then(|| format!("ΔE axis cut at {top:.1} (the largest value below {CLIP_BELOW_DEG:.0}°)"));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let mut chart = theta_chart(&root, caption.as_deref(), 190, top, "colour difference ΔE2000", &|v| format!("{v:.0}"))?;
        chart
            .draw_series(std::iter::once(Rectangle::new([(0.0, 2.0), (90.0, 3.0)], RGBColor(255, 220, 200).mix(0.6).filled())))
            .map_err(plot_error)?;
        chart
            .draw_series(LineSeries::new(vec![(0.0, 1.0), (90.0, 1.0)], ShapeStyle::from(&PALETTE[7]).stroke_width(CURVE_WIDTH)))
            .map_err(plot_error)?;
        for s in series {
            let points = theta_deg.iter().copied().zip(s.values.iter().map(|v| v.min(top))).collect();
            line(&mut chart, points, s.curve.color, s.curve.dashed)?;
        }
        let (x, y1) = chart.backend_coord(&(90.0, 1.0));
        let (_, y25) = chart.backend_coord(&(90.0, 2.5));
        let y25 = y25.min(y1 - FONT_PX as i32 - 6);
        root.draw(&Text::new("just noticeable (ΔE 1)", (x + 10, y1 - 7), FONT)).map_err(plot_error)?;
        root.draw(&Text::new("clearly visible (ΔE 2–3)", (x + 10, y25 - 7), FONT)).map_err(plot_error)?;
        root.present().map_err(plot_error)?;
    }
    dash(&mut svg, PALETTE[7]);
    for s in series.iter().filter(|s| s.curve.dashed) {
        dash(&mut svg, s.curve.color);
    }
    Ok((svg, clipped_caption(top, &clipped)))
}

/// A point of a cost chart.
pub struct CostPoint {
    pub label: String,
    pub cost: f64,
    pub error: f64,
    pub pareto: bool,
    /// Where its cost and error come from, written on its hover mark (`data-x-…`,
    /// `data-y-…`) so a reader (and a test) can find the rows.
    pub trace: Option<[Trace; 2]>,
    /// Its colour and marker (e.g. by method and by depth); `None`: coloured by whether it
    /// is on the Pareto front, a circle.
    pub style: Option<PointStyle>,
}

/// The marker of a chart point: a shape per value of one variable (a depth, a pass count).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
    TriangleDown,
    Cross,
}

impl Marker {
    /// The markers in the order they are handed out.
    pub const ALL: [Marker; 6] = [Marker::Circle, Marker::Square, Marker::Triangle, Marker::Diamond, Marker::TriangleDown, Marker::Cross];

    /// The `i`-th marker (cycling).
    pub fn nth(i: usize) -> Marker {
        Marker::ALL[i % Marker::ALL.len()]
    }

    /// The marker as an SVG element centred at (`x`, `y`): filled with `color`, or only
    /// outlined when `hollow` (a value drawn at the axis floor).
    pub fn svg(self, x: f64, y: f64, color: RGBColor, hollow: bool) -> String {
        let c = css(color);
        let paint = if hollow {
            format!("fill=\"white\" stroke=\"{c}\" stroke-width=\"2\"")
        } else {
            format!("fill=\"{c}\" stroke=\"{c}\" stroke-width=\"1\"")
        };
        let polygon = |points: &[(f64, f64)]| {
            let p: Vec<String> = points.iter().map(|(dx, dy)| format!("{:.1},{:.1}", x + dx, y + dy)).collect();
            format!("<polygon class=\"marker\" points=\"{}\" {paint}/>", p.join(" "))
        };
        match self {
            Marker::Circle => format!("<circle class=\"marker\" cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"4.5\" {paint}/>"),
            Marker::Square => format!("<rect class=\"marker\" x=\"{:.1}\" y=\"{:.1}\" width=\"8\" height=\"8\" {paint}/>", x - 4.0, y - 4.0),
            Marker::Triangle => polygon(&[(0.0, -6.0), (5.5, 4.0), (-5.5, 4.0)]),
            Marker::Diamond => polygon(&[(0.0, -6.0), (6.0, 0.0), (0.0, 6.0), (-6.0, 0.0)]),
            Marker::TriangleDown => polygon(&[(0.0, 6.0), (5.5, -4.0), (-5.5, -4.0)]),
            Marker::Cross => format!(
                "<path class=\"marker\" d=\"M{:.1},{:.1}L{:.1},{:.1}M{:.1},{:.1}L{:.1},{:.1}\" stroke=\"{c}\" stroke-width=\"2.5\" fill=\"none\"/>",
                x - 5.0,
                y - 5.0,
                x + 5.0,
                y + 5.0,
                x - 5.0,
                y + 5.0,
                x + 5.0,
                y - 5.0
            ),
        }
    }
}

/// A point's colour and marker.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PointStyle {
    pub color: RGBColor,
    pub marker: Marker,
}

/// An HTML legend of point styles: a marker sample and the name of each entry (a colour
/// drawn as a circle, a marker drawn in grey).
pub fn point_legend<'a>(title: &str, entries: impl Iterator<Item = (&'a str, RGBColor, Marker)>) -> String {
    let mut out = format!("<ul class=\"legend\"><li><b>{}</b></li>", super::html::escape(title));
    for (name, color, marker) in entries {
        let _ = write!(
            out,
            "<li><svg width=\"16\" height=\"16\">{}</svg>{}</li>",
            marker.svg(8.0, 8.0, color, false),
            super::html::escape(name)
        );
    }
    out.push_str("</ul>");
    out
}

/// What a cost chart's error axis shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorAxis {
    /// Mean relative error, drawn in percent.
    Relative,
    /// Mean CIEDE2000 colour difference.
    DeltaE,
    /// Mean absolute difference of a quantity in [0, 1] (accessibility, irradiance).
    Absolute,
}

impl ErrorAxis {
    fn name(self) -> &'static str {
        match self {
            ErrorAxis::Relative => "mean relative error (%)",
            ErrorAxis::DeltaE => "mean colour difference ΔE2000",
            ErrorAxis::Absolute => "mean absolute error",
        }
    }

    fn tick(self, v: f64) -> String {
        match self {
            ErrorAxis::Relative => format!("{} %", super::html::significant(v * 100.0, 1)),
            ErrorAxis::DeltaE | ErrorAxis::Absolute => super::html::significant(v, 2),
        }
    }
}

/// Where a drawn value comes from: a table (its path under the output folder), a column
/// and the data rows (0-based, header not counted) whose mean it is — weighted by the
/// column `weight` when one is named.
#[derive(Clone, Debug, PartialEq)]
pub struct Trace {
    pub table: String,
    pub column: String,
    pub rows: Vec<usize>,
    pub weight: Option<String>,
    pub value: f64,
}

impl Trace {
    /// The mean of `column` over `rows` of `table` (weighted by `weight`), traced.
    pub fn mean(path: &str, table: &super::csvdata::CsvTable, column: &str, rows: Vec<usize>, weight: Option<&str>) -> Trace {
        let (mut sum, mut total) = (0.0, 0.0);
        for &r in &rows {
            let w = weight.and_then(|w| table.number(&table.rows[r], w)).unwrap_or(1.0);
            if let Some(v) = table.number(&table.rows[r], column) {
                sum += w * v;
                total += w;
            }
        }
        let value = if total > 0.0 { sum / total } else { f64::NAN };
        Trace { table: path.to_string(), column: column.to_string(), rows, weight: weight.map(str::to_string), value }
    }

    /// [`mean`](Self::mean) of a typed column, weighted by a whole-number column.
    pub fn mean_of<K: nklut_tables::columns::Numeric>(
        path: &str,
        table: &super::csvdata::CsvTable,
        column: nklut_tables::columns::Column<K>,
        rows: Vec<usize>,
        weight: Option<nklut_tables::columns::Column<nklut_tables::columns::Integer>>,
    ) -> Trace {
        Trace::mean(path, table, column.name, rows, weight.map(|w| w.name))
    }

    /// `data-<axis>-table`, `-column`, `-rows` (space-separated), `-weight` and `data-<axis>`
    /// (the value, shortest round-trip form).
    fn attributes(&self, axis: &str) -> String {
        let rows: Vec<String> = self.rows.iter().map(usize::to_string).collect();
        let weight = self.weight.as_deref().map(|w| format!(" data-{axis}-weight=\"{}\"", super::html::escape(w))).unwrap_or_default();
        format!(
            " data-{axis}-table=\"{}\" data-{axis}-column=\"{}\" data-{axis}-rows=\"{}\"{weight} data-{axis}=\"{}\"",
            super::html::escape(&self.table),
            super::html::escape(&self.column),
            rows.join(" "),
            self.value
        )
    }
}

/// The hover mark of a point: a transparent circle with its label as title and its
/// traces as data attributes.
fn hover_mark(x: i32, y: i32, label: &str, traces: &[(&str, &Trace)]) -> String {
    let data: String = traces.iter().map(|(axis, t)| t.attributes(axis)).collect();
    format!(
        "<circle class=\"trace\" cx=\"{x}\" cy=\"{y}\" r=\"7\" fill=\"transparent\"{data}><title>{}</title></circle>",
        super::html::escape(label)
    )
}

/// An HTML legend (outside the plot): a line sample and the name of each entry.
pub fn legend<'a>(entries: impl Iterator<Item = (&'a str, RGBColor, bool)>) -> String {
    let mut out = String::from("<ul class=\"legend\">");
    for (name, color, dashed) in entries {
        let dash = if dashed { " stroke-dasharray=\"6 4\"" } else { "" };
        let _ = write!(
            out,
            "<li><svg width=\"28\" height=\"8\"><line x1=\"0\" y1=\"4\" x2=\"28\" y2=\"4\" stroke=\"{}\" stroke-width=\"2\"{dash}/></svg>{}</li>",
            css(color),
            super::html::escape(name)
        );
    }
    out.push_str("</ul>");
    out
}

/// One curve as a legend sees it: its name, style and the values it draws (any layout, the
/// same for every curve of a chart: points in order, channels flattened).
pub struct Drawn<'a> {
    pub name: &'a str,
    pub color: RGBColor,
    pub dashed: bool,
    pub values: Vec<f64>,
}

/// How close two curves must run to hide one under the other: within this fraction of the
/// chart's range (the largest |value| of any curve) at every point; 0.2 %, under a pixel
/// of a 300-px plot.
pub const HIDDEN_FRACTION: f64 = 0.002;

/// Legend entries of `curves` with the ones hidden under another merged: curves whose
/// values stay within [`HIDDEN_FRACTION`] of the chart's range of an earlier curve's at
/// every point (same count, NaN where the other is NaN) share its entry, named
/// `a = b = …` in drawing order and drawn in the style of the last of them (the one on
/// top).
pub fn merged_legend<'a>(curves: &[Drawn<'a>]) -> Vec<(String, RGBColor, bool)> {
    let range = curves.iter().flat_map(|c| c.values.iter()).filter(|v| v.is_finite()).fold(0.0f64, |m, v| m.max(v.abs()));
    let tolerance = HIDDEN_FRACTION * range;
    let same =
        |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x.is_nan() && y.is_nan()) || (x - y).abs() <= tolerance);
    // Groups: the first member's values and the members' indices.
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, curve) in curves.iter().enumerate() {
        match groups.iter_mut().find(|g| same(&curves[g[0]].values, &curve.values)) {
            Some(group) => group.push(i),
            None => groups.push(vec![i]),
        }
    }
    groups
        .into_iter()
        .map(|group| {
            let top = &curves[*group.last().expect("a group has a member")];
            let name = group.iter().map(|&i| curves[i].name).collect::<Vec<_>>().join(" = ");
            (name, top.color, top.dashed)
        })
        .collect()
}

/// [`legend`] of [`merged_legend`]'s entries.
pub fn merged_legend_html(curves: &[Drawn]) -> String {
    let entries = merged_legend(curves);
    legend(entries.iter().map(|(name, color, dashed)| (name.as_str(), *color, *dashed)))
}

/// A point of a line chart: at category `x` (an index into the chart's categories), its
/// value traced to its rows.
pub struct LinePoint {
    pub x: usize,
    pub y: Trace,
    pub label: String,
}

/// A series of a line chart.
pub struct Series {
    pub name: String,
    pub color: RGBColor,
    pub points: Vec<LinePoint>,
}

/// A line chart over categories (depths, step counts, passes): its x categories and
/// axis names, the y axis's format.
pub struct LineChart<'a> {
    pub categories: &'a [String],
    pub x_name: &'a str,
    pub y_axis: ErrorAxis,
    pub series: &'a [Series],
    pub caption: Option<&'a str>,
    /// Whether the categories are ordered, so lines may join neighbours (depths 1+0, 2+0,
    /// 3+0); unordered ones (1+3 beside 3+1) get markers only.
    pub joined: bool,
}

/// A line chart: the categories evenly spaced on x with a tick each, y from 0, a line and a
/// marker per series, each point's hover mark traced to its rows. Empty when nothing is
/// finite.
pub fn line_chart(spec: &LineChart, size: (u32, u32)) -> Result<String> {
    let values = spec.series.iter().flat_map(|s| s.points.iter().map(|p| p.y.value)).filter(|v| v.is_finite());
    let top = values.fold(f64::NEG_INFINITY, f64::max);
    if !top.is_finite() || spec.categories.is_empty() {
        return Ok(String::new());
    }
    let top = if top > 0.0 { top * 1.12 } else { 1.0 };
    let last = (spec.categories.len() - 1).max(1) as f64;
    let mut svg = String::new();
    let mut marks = String::new();
    let plot;
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let mut builder = ChartBuilder::on(&root);
        if let Some(caption) = spec.caption {
            builder.caption(caption, CAPTION);
        }
        let mut chart = builder
            .margin(8)
            .margin_right(24)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(-0.3f64..last + 0.3, 0f64..top)
            .map_err(plot_error)?;
        let axis = spec.y_axis;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(0)
            .y_labels(5)
            .x_desc(spec.x_name)
            .y_desc(axis.name())
            .label_style(FONT)
            .axis_desc_style(FONT)
            .y_label_formatter(&|v| axis.tick(*v))
            .draw()
            .map_err(plot_error)?;
        x_ticks(&root, &chart, spec.categories.iter().enumerate().map(|(i, name)| (i as f64, name.clone())))?;
        plot = plot_box(&chart.plotting_area().get_pixel_range());
        for s in spec.series {
            let points: Vec<(f64, f64)> = s.points.iter().filter(|p| p.y.value.is_finite()).map(|p| (p.x as f64, p.y.value)).collect();
            if spec.joined {
                line(&mut chart, points.clone(), s.color, false)?;
            }
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, ShapeStyle::from(&s.color).filled()))).map_err(plot_error)?;
            for p in s.points.iter().filter(|p| p.y.value.is_finite()) {
                let (x, y) = chart.backend_coord(&(p.x as f64, p.y.value));
                marks.push_str(&hover_mark(x, y, &p.label, &[("y", &p.y)]));
            }
        }
        root.present().map_err(plot_error)?;
    }
    if let Some(end) = svg.rfind("</svg>") {
        svg.insert_str(end, &marks);
    }
    tag_root(&mut svg, &format!("class=\"chart line\" data-plot=\"{plot}\""));
    Ok(svg)
}

/// `svg` with `attributes` added to its root element: what the chart is (`class="chart"`),
/// its axes' scales and its plotting area (`data-plot="left top right bottom"`, px), so a
/// reader of the page (and a test) can tell tick labels from other text.
fn tag_root(svg: &mut String, attributes: &str) {
    if let Some(at) = svg.find("<svg") {
        svg.insert_str(at + 4, &format!(" {attributes}"));
    }
}

/// The plotting area as `left top right bottom`.
fn plot_box(area: &(std::ops::Range<i32>, std::ops::Range<i32>)) -> String {
    format!("{} {} {} {}", area.0.start, area.1.start, area.0.end, area.1.end)
}

/// A drawn cost chart and the points it drew at the axis floor (error 0).
pub struct CostChart {
    pub svg: String,
    pub at_floor: Vec<String>,
}

/// An estimate of a label's box in px (width from the character count at FONT_PX).
fn label_box(text: &str, x: i32, y: i32) -> (i32, i32, i32, i32) {
    let width = (text.chars().count() as f64 * FONT_PX as f64 * 0.62).ceil() as i32;
    (x, y - FONT_PX as i32, x + width, y + 3)
}

fn overlaps(a: (i32, i32, i32, i32), b: (i32, i32, i32, i32)) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// What a chart of `values` would show when it would show too little to be a chart.
#[derive(Clone, Debug, PartialEq)]
pub enum TooLittle {
    /// No finite value.
    Nothing,
    /// Every value is 0.
    AllZero,
    /// One point (its value).
    OnePoint(f64),
}

/// Whether the finite `values` of a chart's points make a chart: two or more points and
/// not all 0; otherwise what a sentence should say instead.
pub fn too_little(values: impl IntoIterator<Item = f64>) -> Option<TooLittle> {
    let finite: Vec<f64> = values.into_iter().filter(|v| v.is_finite()).collect();
    match finite.as_slice() {
        [] => Some(TooLittle::Nothing),
        _ if finite.iter().all(|v| *v == 0.0) => Some(TooLittle::AllZero),
        [one] => Some(TooLittle::OnePoint(*one)),
        _ => None,
    }
}

/// The ticks of a log axis over [`lo`, `hi`]: 1, 2 and 5 times the powers of ten inside,
/// or only the powers of ten where those are 3 or more and the 1-2-5 ticks would stand
/// closer than `min_gap` of a decade (so labels never crowd).
fn log_ticks(lo: f64, hi: f64, min_gap: f64) -> Vec<f64> {
    let of = |mantissas: &[f64]| -> Vec<f64> {
        let mut out = Vec::new();
        let mut decade = 10f64.powf(lo.log10().floor() - 1.0);
        while decade <= hi {
            for m in mantissas {
                let v = decade * m;
                if v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9) {
                    out.push(v);
                }
            }
            decade *= 10.0;
        }
        out
    };
    let decades = of(&[1.0]);
    // 1 → 2 is the closest pair of the 1-2-5 ticks: log10(2) of a decade.
    if decades.len() >= 3 && 2f64.log10() < min_gap {
        decades
    } else {
        of(&[1.0, 2.0, 5.0])
    }
}

/// Log-scale bounds around `values` with half a decade of margin, widened until they hold
/// three 1-2-5 ticks.
fn log_bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = bounds(values);
    while log_ticks(lo, hi, 0.0).len() < 3 {
        lo /= 1.5;
        hi *= 1.5;
    }
    (lo, hi)
}

/// Error against cost, both log scales (each axis named "log scale", three or more
/// labelled ticks at 1, 2 and 5 times the powers of ten). Only the Pareto front is
/// labelled (each label placed where it overlaps no earlier one); every point has a hover
/// title. Points with error 0 are drawn at the axis floor, hollow. A point's style is its
/// own ([`PointStyle`]) or, without one, its place on or off the front.
pub fn cost_chart(points: &[CostPoint], cost_label: &str, error_axis: ErrorAxis, size: (u32, u32)) -> Result<CostChart> {
    let drawn: Vec<&CostPoint> =
        points.iter().filter(|p| p.cost > 0.0 && p.cost.is_finite() && p.error >= 0.0 && p.error.is_finite()).collect();
    let positive: Vec<f64> = drawn.iter().map(|p| p.error).filter(|e| *e > 0.0).collect();
    if positive.is_empty() {
        return Ok(CostChart { svg: String::new(), at_floor: Vec::new() });
    }
    let (x_lo, x_hi) = log_bounds(drawn.iter().map(|p| p.cost));
    let (y_lo, y_hi) = log_bounds(positive.iter().copied());
    let at_floor: Vec<String> = drawn.iter().filter(|p| p.error == 0.0).map(|p| p.label.clone()).collect();
    let mut svg = String::new();
    let mut titles = String::new();
    let plot;
    let (margin, x_area, y_area) = (12u32, 44u32, 84u32);
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let mut chart = ChartBuilder::on(&root)
            .margin(margin)
            .margin_right(24)
            .x_label_area_size(x_area)
            .y_label_area_size(y_area)
            .build_cartesian_2d((x_lo..x_hi).log_scale(), (y_lo..y_hi).log_scale())
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(0)
            .y_labels(0)
            .x_label_formatter(&|_| String::new())
            .y_label_formatter(&|_| String::new())
            .x_desc(format!("{cost_label}, log scale"))
            .y_desc(format!("{}, log scale", error_axis.name()))
            .label_style(FONT)
            .axis_desc_style(FONT)
            .draw()
            .map_err(plot_error)?;
        let area = chart.plotting_area().get_pixel_range();
        plot = plot_box(&area);
        let (width, height) = (f64::from(area.0.end - area.0.start), f64::from(area.1.end - area.1.start));
        // Ticks at least a label apart: ~6 characters across, a line of text up.
        let x_ticks = log_ticks(x_lo, x_hi, 60.0 / (width / (x_hi / x_lo).log10()));
        let y_ticks = log_ticks(y_lo, y_hi, (FONT_PX as f64 + 6.0) / (height / (y_hi / y_lo).log10()));
        let below = TextStyle::from(FONT).pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Top,
        ));
        for tick in x_ticks {
            let (x, y) = chart.backend_coord(&(tick, y_lo));
            root.draw(&PathElement::new(vec![(x, y), (x, y + 5)], BLACK)).map_err(plot_error)?;
            root.draw(&Text::new(super::html::significant(tick, 2), (x, y + 7), below.clone())).map_err(plot_error)?;
        }
        let left = TextStyle::from(FONT).pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Right,
            plotters::style::text_anchor::VPos::Center,
        ));
        for tick in y_ticks {
            let (x, y) = chart.backend_coord(&(x_lo, tick));
            root.draw(&PathElement::new(vec![(x - 5, y), (x, y)], BLACK)).map_err(plot_error)?;
            root.draw(&Text::new(error_axis.tick(tick), (x - 7, y), left.clone())).map_err(plot_error)?;
        }
        let at = |p: &CostPoint| (p.cost, if p.error > 0.0 { p.error } else { y_lo });
        let mut front: Vec<(f64, f64)> = drawn.iter().filter(|p| p.pareto).map(|p| at(p)).collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
        chart.draw_series(LineSeries::new(front, ShapeStyle::from(&PALETTE[5]).stroke_width(2))).map_err(plot_error)?;
        for p in &drawn {
            let style = p.style.unwrap_or(PointStyle { color: if p.pareto { PALETTE[5] } else { PALETTE[6] }, marker: Marker::Circle });
            let (x, y) = chart.backend_coord(&at(p));
            titles.push_str(&style.marker.svg(f64::from(x), f64::from(y), style.color, p.error == 0.0));
        }
        for p in &drawn {
            let (x, y) = chart.backend_coord(&at(p));
            let traces: Vec<(&str, &Trace)> = p.trace.iter().flat_map(|[x, y]| [("x", x), ("y", y)]).collect();
            let title = format!(
                "{}\n{}: {}\n{}: {}",
                p.label,
                cost_label,
                super::html::significant(p.cost, 3),
                error_axis.name(),
                error_axis.tick(p.error)
            );
            titles.push_str(&hover_mark(x, y, &title, &traces));
        }
        let mut placed: Vec<(i32, i32, i32, i32)> = Vec::new();
        let mut front_points: Vec<&&CostPoint> = drawn.iter().filter(|p| p.pareto).collect();
        front_points.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        for p in front_points {
            let (x, y) = chart.backend_coord(&at(p));
            let width = label_box(&p.label, 0, 0).2;
            let candidates =
                [(x + 8, y - 6), (x + 8, y + 18), (x - width - 8, y - 6), (x - width - 8, y + 18), (x + 8, y - 24), (x + 8, y + 36)];
            let inside = |b: (i32, i32, i32, i32)| b.0 >= area.0.start && b.2 <= area.0.end && b.1 >= area.1.start && b.3 <= area.1.end;
            let choice = candidates
                .iter()
                .map(|&(lx, ly)| (lx, ly, label_box(&p.label, lx, ly)))
                .find(|(_, _, b)| inside(*b) && !placed.iter().any(|q| overlaps(*q, *b)));
            if let Some((lx, ly, b)) = choice {
                placed.push(b);
                root.draw(&Text::new(p.label.clone(), (lx, ly - FONT_PX as i32), FONT)).map_err(plot_error)?;
            }
        }
        root.present().map_err(plot_error)?;
    }
    let mut svg = without_repeated_text(&svg);
    if let Some(end) = svg.rfind("</svg>") {
        svg.insert_str(end, &titles);
    }
    tag_root(&mut svg, &format!("class=\"chart cost\" data-x-scale=\"log\" data-y-scale=\"log\" data-plot=\"{plot}\""));
    Ok(CostChart { svg, at_floor })
}

/// `svg` without a `<text>` element equal to an earlier one: plotters' log axes may give
/// one tick twice (10 as the end of one decade and the start of the next).
fn without_repeated_text(svg: &str) -> String {
    let mut seen: Vec<&str> = Vec::new();
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg;
    while let Some(start) = rest.find("<text") {
        out.push_str(&rest[..start]);
        let Some(end) = rest[start..].find("</text>").map(|e| start + e + "</text>".len()) else { break };
        let element = &rest[start..end];
        if !seen.contains(&element) {
            seen.push(element);
            out.push_str(element);
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// Log-scale bounds with half a decade of margin.
fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    (lo / 3.0, hi * 3.0)
}

/// Indices of the points on the Pareto front: no other point is both cheaper (or equal)
/// and more accurate (or equal), with one strict. A point without a finite cost and error
/// is never on the front and dominates none.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    let finite = |&(c, e): &(f64, f64)| c.is_finite() && e.is_finite();
    points
        .iter()
        .map(|&(cost, error)| {
            finite(&(cost, error)) && !points.iter().filter(|p| finite(p)).any(|&(c, e)| c <= cost && e <= error && (c < cost || e < error))
        })
        .collect()
}

/// One bar of a histogram: its bin's edges, its share of the histogram's weight (drawn),
/// its count and the table row it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Bar {
    pub lower: f64,
    pub upper: f64,
    pub share: f64,
    pub count: u64,
    pub row: usize,
}

/// The bars of one histogram, drawn side by side with the others' in each bin.
pub struct BarSeries {
    pub name: String,
    pub color: RGBColor,
    pub bars: Vec<Bar>,
}

/// A histogram chart: the table its bars are rows of, the x axis's name, the series.
pub struct HistogramChart<'a> {
    pub table: &'a str,
    pub x_name: &'a str,
    pub series: &'a [BarSeries],
    pub caption: Option<&'a str>,
}

/// A histogram chart: x over the bins' span (and a little room) with 5 ticks, y the share in percent from 0;
/// in each bin one bar per series side by side (series k in the k-th part of the bin's
/// width), each a `<rect class="bar">` (heights in unrounded pixels, proportional to the
/// share) carrying its table, row, count and share as data attributes and its figures as
/// title. Empty when there is no bar.
pub fn histogram_chart(spec: &HistogramChart, size: (u32, u32)) -> Result<String> {
    let bars = || spec.series.iter().flat_map(|s| s.bars.iter());
    let (Some(low), Some(high)) = (bars().map(|b| b.lower).reduce(f64::min), bars().map(|b| b.upper).reduce(f64::max)) else {
        return Ok(String::new());
    };
    if !(low < high) {
        return Ok(String::new());
    }
    let top = bars().map(|b| b.share).filter(|v| v.is_finite()).fold(0.0, f64::max);
    let top = if top > 0.0 { top * 1.12 } else { 1.0 };
    let mut svg = String::new();
    let mut marks = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let mut builder = ChartBuilder::on(&root);
        if let Some(caption) = spec.caption {
            builder.caption(caption, CAPTION);
        }
        let mut chart = builder
            .margin(8)
            .margin_right(24)
            .x_label_area_size(44)
            .y_label_area_size(64)
            // 6 % of the span free at each side, so the first x tick's label clears the y
            // axis's 0.
            .build_cartesian_2d(low - 0.06 * (high - low)..high + 0.06 * (high - low), 0f64..top)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(0)
            .y_labels(5)
            .x_desc(spec.x_name)
            .y_desc("share (%)")
            .label_style(FONT)
            .axis_desc_style(FONT)
            .y_label_formatter(&|v| super::html::significant(v * 100.0, 2))
            .draw()
            .map_err(plot_error)?;
        x_ticks(&root, &chart, (0..=4).map(|k| low + (high - low) * f64::from(k) / 4.0).map(|x| (x, super::html::significant(x, 2))))?;
        // Pixel coordinates, unrounded: plotters maps linearly, so two mapped points give it.
        let (x0, y0) = chart.backend_coord(&(low, 0.0));
        let (x1, y1) = chart.backend_coord(&(high, top));
        let px = |x: f64| f64::from(x0) + (f64::from(x1) - f64::from(x0)) * (x - low) / (high - low);
        let py = |y: f64| f64::from(y0) + (f64::from(y1) - f64::from(y0)) * y / top;
        let parts = spec.series.len().max(1) as f64;
        for (k, series) in spec.series.iter().enumerate() {
            for bar in &series.bars {
                let share = if bar.share.is_finite() { bar.share.max(0.0) } else { 0.0 };
                let width = (bar.upper - bar.lower) / parts;
                let (left, right) = (px(bar.lower + width * k as f64), px(bar.lower + width * (k as f64 + 1.0)));
                let (bottom, height) = (py(0.0), py(0.0) - py(share));
                let _ = write!(
                    marks,
                    "<rect class=\"bar\" x=\"{left:.3}\" y=\"{:.3}\" width=\"{:.3}\" height=\"{height:.3}\" fill=\"{}\" data-table=\"{}\" data-row=\"{}\" data-series=\"{}\" data-count=\"{}\" data-share=\"{}\"><title>{}</title></rect>",
                    bottom - height,
                    (right - left).max(0.0),
                    css(series.color),
                    super::html::escape(spec.table),
                    bar.row,
                    super::html::escape(&series.name),
                    bar.count,
                    bar.share,
                    super::html::escape(&format!(
                        "{}: {} … {}: {} ({} %)",
                        series.name,
                        super::html::significant(bar.lower, 3),
                        super::html::significant(bar.upper, 3),
                        bar.count,
                        super::html::significant(share * 100.0, 3)
                    ))
                );
            }
        }
        root.present().map_err(plot_error)?;
    }
    if let Some(end) = svg.rfind("</svg>") {
        svg.insert_str(end, &marks);
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {

    /// θ 0°, 40°, 80°, 85°, 89°: a at 1, 2, 6, 7, 8; b at 0.5, 1, 3, 10, 41 (a spike). The
    /// largest at or below 80° is 6; b's 41 > 1.5 × 6, so the top is 6 × 1.05 = 6.3 and b
    /// (peak 41 at 89°) is cut, a (8 > 6.3) as well. Without b nothing exceeds 1.5 × 6:
    /// the top is 8 × 1.05 = 8.4, nothing cut. All under 4: the top stays 4 × 1.05.
    #[test]
    fn one_spike_near_grazing_does_not_set_the_delta_e_range() {
        let theta = [0.0, 40.0, 80.0, 85.0, 89.0];
        let curve = |name: &str| super::super::curves::PlotCurve { name: name.into(), color: PALETTE[1], dashed: false, rgb: vec![] };
        let (a, b) = (curve("a"), curve("b"));
        let series =
            [DeltaE { curve: &a, values: vec![1.0, 2.0, 6.0, 7.0, 8.0] }, DeltaE { curve: &b, values: vec![0.5, 1.0, 3.0, 10.0, 41.0] }];
        let (top, clipped) = delta_e_range(&theta, &series);
        assert!((top - 6.3).abs() < 1e-12, "{top}");
        assert_eq!(
            clipped,
            [Clipped { name: "a".into(), peak: 8.0, theta_deg: 89.0 }, Clipped { name: "b".into(), peak: 41.0, theta_deg: 89.0 }]
        );
        assert_eq!(
            clipped_caption(top, &clipped).unwrap(),
            "ΔE axis cut at 6.3 (the largest value below 80°): b reaches 41 at 89°, a reaches 8 at 89°"
        );
        let (top, clipped) = delta_e_range(&theta, &series[..1]);
        assert!((top - 8.4).abs() < 1e-12 && clipped.is_empty(), "{top} {clipped:?}");
        let small = [DeltaE { curve: &a, values: vec![0.1, 0.2, 0.3, 0.2, 3.0] }];
        assert_eq!(delta_e_range(&theta, &small), (4.0 * 1.05, vec![]));
        let (svg, caption) = delta_e_chart(&theta, &series, (760, 320)).unwrap();
        assert!(svg.contains("ΔE axis cut at 6.3"), "the cut is said on the chart");
        assert_eq!(
            caption.as_deref(),
            Some("ΔE axis cut at 6.3 (the largest value below 80°): b reaches 41 at 89°, a reaches 8 at 89°"),
            "and named in the figure's caption"
        );
    }

    /// Three curves on a range of 1: b equals a, c differs from a by 0.01 at one point (5 ×
    /// the 0.002 tolerance), d runs 0.001 under c everywhere (half the tolerance): a and b
    /// share one entry named "a = b" in b's style (drawn last, on top), c and d one in d's.
    #[test]
    fn curves_hidden_under_another_share_one_legend_entry() {
        let curve = |name, color, values: Vec<f64>| Drawn { name, color, dashed: name != "a", values };
        let a = vec![0.0, 0.5, 1.0];
        let mut c = a.clone();
        c[1] = 0.51;
        let d: Vec<f64> = c.iter().map(|v| v - 0.001).collect();
        let curves =
            [curve("a", PALETTE[0], a.clone()), curve("b", PALETTE[1], a.clone()), curve("c", PALETTE[2], c), curve("d", PALETTE[3], d)];
        let entries = merged_legend(&curves);
        assert_eq!(entries, vec![("a = b".to_string(), PALETTE[1], true), ("c = d".to_string(), PALETTE[3], true)]);
        let html = merged_legend_html(&curves);
        assert_eq!(html.matches("<li>").count(), 2, "{html}");
        assert!(html.contains("a = b") && html.contains("c = d"), "{html}");
        // Apart by more than the tolerance: their own entries.
        let apart = [curve("a", PALETTE[0], vec![0.0, 1.0]), curve("b", PALETTE[1], vec![0.0, 0.99])];
        assert_eq!(merged_legend(&apart).len(), 2);
    }

    use super::*;

    #[test]
    fn a_text_drawn_twice_is_kept_once() {
        let svg = "<svg><text x=\"1\">\n10\n</text><line/><text x=\"1\">\n10\n</text><text x=\"2\">\n10\n</text></svg>";
        assert_eq!(without_repeated_text(svg), "<svg><text x=\"1\">\n10\n</text><line/><text x=\"2\">\n10\n</text></svg>");
    }

    /// 1-2-5 ticks inside the bounds; decades alone where those are three or more and the
    /// 1-2-5 ticks would crowd; bounds widened until three ticks fit.
    #[test]
    fn log_axes_have_three_ticks_or_more() {
        let close = |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-12 * y);
        assert!(close(&log_ticks(0.15, 30.0, 0.0), &[0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0]), "{:?}", log_ticks(0.15, 30.0, 0.0));
        assert_eq!(log_ticks(0.15, 30.0, 0.5).len(), 7, "two decades are too few: 1-2-5 kept");
        assert!(close(&log_ticks(0.05, 300.0, 0.5), &[0.1, 1.0, 10.0, 100.0]), "{:?}", log_ticks(0.05, 300.0, 0.5));
        // 1.1 … 9.9 holds 2 and 5 only: widened by 1.5 until 1 or 10 joins.
        let (lo, hi) = log_bounds([3.3, 3.3].into_iter());
        assert!(log_ticks(lo, hi, 0.0).len() >= 3 && lo < 3.3 / 3.0 && hi > 3.3 * 3.0, "{lo} {hi}");
        assert_eq!(too_little([0.0, 0.0, f64::NAN]), Some(TooLittle::AllZero));
        assert_eq!(too_little([f64::NAN, 0.5]), Some(TooLittle::OnePoint(0.5)));
        assert_eq!(too_little([0.0, 0.5]), None);
        assert_eq!(too_little(std::iter::empty()), Some(TooLittle::Nothing));
    }

    #[test]
    fn pareto_front_keeps_undominated_points() {
        let points = [(1.0, 0.1), (2.0, 0.01), (3.0, 0.05), (0.5, 0.5), (2.0, 0.02)];
        assert_eq!(pareto_front(&points), vec![true, true, false, true, false]);
        // A point without a finite cost or error is off the front and hides nothing.
        let with_unknown = [(1.0, 0.1), (f64::NAN, 0.0), (0.0, f64::INFINITY), (2.0, 0.01)];
        assert_eq!(pareto_front(&with_unknown), vec![true, false, false, true]);
    }

    #[test]
    fn plots_have_readable_text_and_theta_ticks_every_30_degrees() {
        let theta: Vec<f64> = (0..=90).map(f64::from).collect();
        let curve = PlotCurve { name: "exact".into(), color: PALETTE[0], dashed: false, rgb: vec![[0.5; 3]; theta.len()] };
        let svg = fresnel_curves(&theta, std::slice::from_ref(&curve), &Channels::default(), (900, 300)).unwrap();
        assert!(svg.starts_with("<svg"), "{}", &svg[..40]);
        assert!(svg.matches("<polyline").count() >= 3);
        for tick in ["0", "30", "60", "90"] {
            assert!(svg.contains(&format!(">\n{tick}\n</text>")), "tick {tick}");
        }
        assert!(svg.contains("red channel, 685 nm") && svg.contains("reflectance F"));
        let sizes: Vec<f64> = svg.split("font-size=\"").skip(1).map(|s| s[..s.find('"').unwrap()].parse().unwrap()).collect();
        assert!(!sizes.is_empty() && sizes.iter().all(|s| *s >= 12.0), "{sizes:?}");
    }

    #[test]
    fn cost_charts_label_only_the_front_and_draw_zero_at_the_floor() {
        let points = [
            CostPoint { label: "exact f64".into(), cost: 25.0, error: 0.0, pareto: true, trace: None, style: None },
            CostPoint { label: "schlick".into(), cost: 2.0, error: 0.05, pareto: true, trace: None, style: None },
            CostPoint { label: "lazanyi".into(), cost: 9.0, error: 0.08, pareto: false, trace: None, style: None },
        ];
        let chart = cost_chart(&points, "CPU time per evaluation (ns)", ErrorAxis::Relative, (600, 400)).unwrap();
        assert_eq!(chart.at_floor, vec!["exact f64"]);
        assert!(chart.svg.contains(">\nschlick\n</text>") && chart.svg.contains(">\nexact f64\n</text>"), "{}", chart.svg);
        assert!(!chart.svg.contains(">\nlazanyi\n</text>"), "off-front points are not labelled");
        assert!(chart.svg.contains("<title>lazanyi\n"), "but they have a hover title");
        assert!(chart.svg.contains("CPU time per evaluation (ns), log scale") && chart.svg.contains("mean relative error (%), log scale"));
    }
}
