//! The scale of a false-colour error picture and its legend. The scale rule: the smallest
//! 1-2-5 step (…, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, …) at or above the 99th
//! percentile (linear interpolation, `stats::quantile`) of the values the picture shows,
//! so at most about one pixel in a hundred saturates and the rest spread over the colours
//! instead of washing out at one end; [`SMALLEST_STEP`] for no value or all zeros. The
//! colours are [`false_colour`]'s (black, blue, red, yellow, white), 0 at
//! black and the scale at white. The legend ([`legend_png`]) is the colour bar with its
//! values burned in (0, half the scale and the scale under the bar's left, middle and right
//! ends) and a line saying what the values are, black on white in the 8 × 8 font of
//! [`crate::labels`], so the picture's numbers travel with it.

use anyhow::Result;

use super::labels;
use nklut_tables::image_files::encode;
use nklut_tables::stats::quantile;
use nklut_tables::texel::{Encoding, Texels};

/// |Δ| summed over channels at which the false colour saturates (white).
pub const ERROR_SCALE: f64 = 0.1;

/// The false colour of an error e ≥ 0: black at 0, through blue, red and yellow, to white
/// at [`ERROR_SCALE`] and beyond (piecewise linear between those five stops).
pub fn false_colour(error: f64) -> [f64; 3] {
    const STOPS: [[f64; 3]; 5] = [[0.0, 0.0, 0.0], [0.1, 0.1, 0.8], [0.9, 0.1, 0.1], [1.0, 0.9, 0.1], [1.0, 1.0, 1.0]];
    let x = (error / ERROR_SCALE).clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let w = x - i as f64;
    std::array::from_fn(|c| STOPS[i][c] + w * (STOPS[i + 1][c] - STOPS[i][c]))
}

/// A PNG of false colours ([`false_colour`]), stored as they are: they are display-referred.
pub fn error_png(width: u32, height: u32, colours: impl Iterator<Item = [f64; 3]>) -> Result<Vec<u8>> {
    let bytes = colours.flat_map(|rgb| rgb.map(|v| (v * 255.0).round() as u8)).collect();
    encode(Encoding::Unorm8, width as usize, height as usize, &Texels::U8(bytes))
}

/// The smallest scale the rule gives (no value, or every value 0).
pub const SMALLEST_STEP: f64 = 1e-4;

/// The smallest 1-2-5 step at or above `x` (k · 10^e, k ∈ {1, 2, 5}); [`SMALLEST_STEP`] for
/// x at or below it or not a number, `f64::MAX`'s decade caps an infinity.
pub fn step_125(x: f64) -> f64 {
    if !(x > SMALLEST_STEP) {
        return SMALLEST_STEP;
    }
    let x = x.min(1e300);
    let mut exponent = x.log10().floor() as i32 - 1;
    loop {
        for k in [1.0, 2.0, 5.0] {
            // k / 10^−e for negative e: the quotient of two exact numbers, correctly rounded,
            // so 0.02 prints as "0.02".
            let step = if exponent < 0 { k / 10f64.powi(-exponent) } else { k * 10f64.powi(exponent) };
            if step >= x {
                return step;
            }
        }
        exponent += 1;
    }
}

/// The scale rule (module doc) over `values`: the 1-2-5 step at or above their 99th
/// percentile; values that are not finite are left out.
pub fn p99_scale(values: impl IntoIterator<Item = f64>) -> f64 {
    let mut sorted: Vec<f64> = values.into_iter().filter(|v| v.is_finite()).map(f64::abs).collect();
    if sorted.is_empty() {
        return SMALLEST_STEP;
    }
    sorted.sort_by(f64::total_cmp);
    step_125(quantile(&sorted, 0.99))
}

/// The false colour of `value` on `scale`: black at 0, white at `scale` and beyond (on
/// [`ERROR_SCALE`] exactly [`false_colour`]: the factor is 1).
pub fn colour(value: f64, scale: f64) -> [f64; 3] {
    false_colour(value * (ERROR_SCALE / scale))
}

/// A value as the legend prints it: the shortest decimal that reads back as the number
/// (`0.02`, `0.25`, `5`).
pub fn value_text(value: f64) -> String {
    format!("{value}")
}

/// The legend's layout: the bar [`BAR_HEIGHT`] px high from [`labels::MARGIN`] down, the
/// values one line below it, the meaning on the next.
pub const BAR_HEIGHT: u32 = 12;
const VALUES_TOP: u32 = labels::MARGIN + BAR_HEIGHT + 2;
/// The legend's height in pixels.
pub const LEGEND_HEIGHT: u32 = VALUES_TOP + labels::LINE + labels::GLYPH + labels::MARGIN;
const PAPER: [f64; 3] = [1.0; 3];
const INK: [f64; 3] = [0.0; 3];

/// The legend of a picture on `scale`, `width` px wide: the colour bar from 0 (left, inside
/// the margin) to `scale` (right), "0", half the scale and the scale printed under the
/// bar's ends and middle, `meaning` on the line below (cut to the width).
pub fn legend_pixels(width: u32, scale: f64, meaning: &str) -> Vec<[f64; 3]> {
    let width = width.max(2 * labels::MARGIN + 2);
    let mut pixels = vec![PAPER; (width * LEGEND_HEIGHT) as usize];
    let bar = width - 2 * labels::MARGIN;
    for x in 0..bar {
        let value = scale * f64::from(x) / f64::from((bar - 1).max(1));
        for y in labels::MARGIN..labels::MARGIN + BAR_HEIGHT {
            pixels[(y * width + labels::MARGIN + x) as usize] = colour(value, scale);
        }
    }
    let (low, middle, high) = ("0".to_string(), value_text(scale / 2.0), value_text(scale));
    labels::draw_text(&mut pixels, width, (labels::MARGIN, VALUES_TOP), &low, INK);
    let centre = (width / 2).saturating_sub(labels::text_width(&middle) / 2);
    labels::draw_text(&mut pixels, width, (centre, VALUES_TOP), &middle, INK);
    let right = (width - labels::MARGIN).saturating_sub(labels::text_width(&high));
    labels::draw_text(&mut pixels, width, (right, VALUES_TOP), &high, INK);
    let line = labels::wrap(meaning, labels::columns(width)).into_iter().next().unwrap_or_default();
    labels::draw_text(&mut pixels, width, (labels::MARGIN, VALUES_TOP + labels::LINE), &line, INK);
    pixels
}

/// [`legend_pixels`] as a PNG (display-referred bytes, as the error pictures).
pub fn legend_png(width: u32, scale: f64, meaning: &str) -> Result<Vec<u8>> {
    let pixels = legend_pixels(width, scale, meaning);
    let width = width.max(2 * labels::MARGIN + 2);
    error_png(width, LEGEND_HEIGHT, pixels.into_iter())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn false_colour_runs_from_black_to_white_through_its_stops() {
        assert_eq!(false_colour(0.0), [0.0; 3]);
        assert_eq!(false_colour(-1.0), [0.0; 3]);
        assert_eq!(false_colour(ERROR_SCALE), [1.0; 3]);
        assert_eq!(false_colour(5.0), [1.0; 3]);
        // Halfway: the middle stop (red).
        assert_eq!(false_colour(ERROR_SCALE / 2.0), [0.9, 0.1, 0.1]);
        // An eighth: halfway between black and blue.
        let eighth = false_colour(ERROR_SCALE / 8.0);
        assert!((eighth[2] - 0.4).abs() < 1e-12 && (eighth[0] - 0.05).abs() < 1e-12);
    }

    /// Steps by hand: 0.013 → 0.02, 0.02 → 0.02 (at or above), 0.021 → 0.05, 0.07 → 0.1,
    /// 3 → 5, 7.5 → 10, 120 → 200; nothing, zero and NaN → the smallest step.
    #[test]
    fn steps_are_the_next_1_2_5() {
        let cases = [
            (0.013, 0.02),
            (0.02, 0.02),
            (0.021, 0.05),
            (0.07, 0.1),
            (0.1, 0.1),
            (3.0, 5.0),
            (7.5, 10.0),
            (120.0, 200.0),
            (0.00031, 0.0005),
        ];
        for (x, step) in cases {
            assert_eq!(step_125(x), step, "{x}");
        }
        assert_eq!((step_125(0.0), step_125(f64::NAN), step_125(-4.0)), (SMALLEST_STEP, SMALLEST_STEP, SMALLEST_STEP));
        assert!(step_125(f64::INFINITY).is_finite());
        assert_eq!(value_text(step_125(0.013)), "0.02");
        assert_eq!(value_text(step_125(0.013) / 2.0), "0.01");
    }

    /// The 99th percentile of 0, 0.01, …, 0.99 (100 values) is 0.99 × 0.99 = 0.9801 → 1; one
    /// value of 40 among 999 of 0.03: position 0.99 × 999 = 989.01 lies among the 0.03s →
    /// 0.05 (the outlier saturates, the rest does not wash out); NaN and infinities left out.
    #[test]
    fn the_scale_is_the_step_above_the_99th_percentile() {
        assert_eq!(p99_scale((0..100).map(|i| f64::from(i) / 100.0)), 1.0);
        let mut values = vec![0.03; 999];
        values.push(40.0);
        assert_eq!(p99_scale(values), 0.05);
        assert_eq!(p99_scale([f64::NAN, f64::INFINITY, 0.3]), 0.5);
        assert_eq!(p99_scale(std::iter::empty()), SMALLEST_STEP);
        assert_eq!(p99_scale([0.0; 10]), SMALLEST_STEP);
    }

    /// The legend of scale 0.2 at 140 px: black at the bar's left pixel, white at its right,
    /// the middle stop (red) half-way; "0", "0.1", "0.2" in the font's glyphs under the bar;
    /// paper around.
    #[test]
    fn the_legend_carries_its_values() {
        let width = 140;
        let pixels = legend_pixels(width, 0.2, "|Δ| over R+G+B");
        let at = |x: u32, y: u32| pixels[(y * width + x) as usize];
        let bar_y = labels::MARGIN + 1;
        assert_eq!(at(labels::MARGIN, bar_y), [0.0; 3]);
        assert_eq!(at(width - labels::MARGIN - 1, bar_y), [1.0; 3]);
        assert_eq!(at(0, bar_y), PAPER);
        assert_eq!(colour(0.1, 0.2), [0.9, 0.1, 0.1]);
        let text_at = |(x, y): (u32, u32), text: &str| {
            for (k, c) in text.chars().enumerate() {
                for (row, bits) in labels::glyph(c).into_iter().enumerate() {
                    for bit in 0..8 {
                        let ink = bits >> bit & 1 == 1;
                        assert_eq!(at(x + 8 * k as u32 + bit, y + row as u32), if ink { INK } else { PAPER }, "{text} {k} {row} {bit}");
                    }
                }
            }
        };
        text_at((labels::MARGIN, VALUES_TOP), "0");
        text_at((70 - 12, VALUES_TOP), "0.1");
        text_at((width - labels::MARGIN - 24, VALUES_TOP), "0.2");
        text_at((labels::MARGIN, VALUES_TOP + labels::LINE), "|Δ| over R+G+B");
        let png = legend_png(width, 0.2, "x").unwrap();
        let decoded = nklut_tables::image_files::decode(nklut_tables::texel::Encoding::Unorm8, &png).unwrap();
        assert_eq!((decoded.width, decoded.height), (width as usize, LEGEND_HEIGHT as usize));
    }
}
