//! Frames a person can look at: the reference beside the distance-map renders, as linear
//! OpenEXR (float) and sRGB PNG, and a false-colour PNG of each render's error against the
//! reference on its own scale with that scale's legend (`colour_bar`); and signed maps (a per-pixel signed error, such as accessibility − reference)
//! in a diverging colour scale shared by every map of a scene, above a legend strip (the
//! colour bar, its range, which end is over- and which under-occlusion). Encoding through `nklut_tables::image_files` (the textures' encoders); the files join the
//! set of the command that made them (`output::publish_contents`), so frames of a killed
//! or earlier run never mix with this one's.

use anyhow::Result;

use super::colour_bar::{colour, error_png, legend_png, p99_scale};
use super::labels;
use super::trace::TracedFrame;
use nklut_optics::color::srgb;
use nklut_tables::image_files::encode;
use nklut_tables::output::SetFile;
use nklut_tables::texel::{Encoding, Texels};

/// One frame to show: a file stem, the frame and, for an error image, its reference.
#[derive(Clone, Debug)]
pub struct Picture {
    pub stem: String,
    pub frame: TracedFrame,
    pub reference: Option<TracedFrame>,
}

/// The scales a set of signed maps may share (1-2-5 steps, accessibility units): the
/// smallest at or above the 99th percentile of |e| over every map of the set ([`shared_scale`]).
pub const SIGNED_SCALES: [f64; 7] = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0];
/// The colour bar of one technique's signed maps with their shared scale and legend, alone:
/// `<technique>_signed_scale.png`.
pub const SIGNED_SCALE_FILE: &str = "signed_scale.png";
/// Where a signed map has no value (no surface): mid grey.
pub const NO_VALUE: [f64; 3] = [0.5, 0.5, 0.5];
/// What the ends of the colour bar mean: negative e, too little accessibility (the picture
/// too dark), and positive e, too much.
pub const NEGATIVE_MEANING: &str = "over-occludes";
pub const POSITIVE_MEANING: &str = "under-occludes";

/// The diverging colour of a signed error e on a scale s: white at 0, to pure blue at −s
/// and beyond (negative: too little accessibility, the surfels over-occlude), to pure red at
/// +s (positive: they under-occlude); linear in between.
pub fn signed_colour(error: f64, scale: f64) -> [f64; 3] {
    let t = (error / scale).clamp(-1.0, 1.0);
    if t >= 0.0 {
        [1.0, 1.0 - t, 1.0 - t]
    } else {
        [1.0 + t, 1.0 + t, 1.0]
    }
}

/// A per-pixel signed error (`None`: nothing there) of `width` × `height` pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct SignedMap {
    pub stem: String,
    /// The technique the map shows (`surfels`, `gtao`): the maps of one technique share a
    /// scale, so one technique's tail does not wash another's map out.
    pub technique: &'static str,
    pub width: u32,
    pub height: u32,
    pub values: Vec<Option<f64>>,
}

/// The scale every map of `maps` is drawn on, so their colours compare: `colour_bar`'s rule
/// (the 1-2-5 step at or above the 99th percentile of |e| over all their values together)
/// held within [`SIGNED_SCALES`] (its smallest for no value or tiny errors, its largest
/// where the percentile exceeds it), so a few extreme pixels saturate rather than wash the
/// rest out.
pub fn shared_scale<'a>(maps: impl IntoIterator<Item = &'a SignedMap>) -> f64 {
    let step = p99_scale(maps.into_iter().flat_map(|m| m.values.iter().flatten().copied()));
    step.clamp(SIGNED_SCALES[0], SIGNED_SCALES[SIGNED_SCALES.len() - 1])
}

/// The legend strip's layout: the colour bar's top and height, then two lines of text
/// (the bar's end and middle values, what each end means), black on white.
pub const LEGEND_BAR_TOP: u32 = labels::MARGIN;
pub const LEGEND_BAR_HEIGHT: u32 = 10;
pub const LEGEND_TEXT_TOP: u32 = LEGEND_BAR_TOP + LEGEND_BAR_HEIGHT + 2;
pub const LEGEND_HEIGHT: u32 = LEGEND_TEXT_TOP + labels::LINE + labels::GLYPH + labels::MARGIN;
/// The narrowest legend: both meanings on one line, a character apart.
pub const LEGEND_WIDTH: u32 = 2 * labels::MARGIN + (NEGATIVE_MEANING.len() + 1 + POSITIVE_MEANING.len()) as u32 * labels::GLYPH;
const LEGEND_PAPER: [f64; 3] = [1.0; 3];
const LEGEND_INK: [f64; 3] = [0.0; 3];

/// The value the colour bar shows at its pixel `i` of `n`: −`scale` at the first, +`scale`
/// at the last, linear between.
pub fn bar_value(i: u32, n: u32, scale: f64) -> f64 {
    if n < 2 {
        return 0.0;
    }
    scale * (2.0 * f64::from(i) / f64::from(n - 1) - 1.0)
}

/// The legend strip `width` pixels wide ([`LEGEND_HEIGHT`] high): the colour bar from
/// −`scale` to +`scale` between the margins, below it "−scale" at the left, "0" in the
/// middle and "+scale" at the right, and below those what each end means.
pub fn legend(width: u32, scale: f64) -> Vec<[f64; 3]> {
    let mut pixels = vec![LEGEND_PAPER; (width * LEGEND_HEIGHT) as usize];
    let bar = width.saturating_sub(2 * labels::MARGIN);
    for y in LEGEND_BAR_TOP..LEGEND_BAR_TOP + LEGEND_BAR_HEIGHT {
        for i in 0..bar {
            pixels[(y * width + labels::MARGIN + i) as usize] = signed_colour(bar_value(i, bar, scale), scale);
        }
    }
    let right = |text: &str| width.saturating_sub(labels::MARGIN + labels::text_width(text));
    let (low, high) = (format!("-{scale}"), format!("+{scale}"));
    let lines = [
        [(labels::MARGIN, low.as_str()), ((width.saturating_sub(labels::GLYPH)) / 2, "0"), (right(&high), high.as_str())],
        [(labels::MARGIN, NEGATIVE_MEANING), (right(POSITIVE_MEANING), POSITIVE_MEANING), (0, "")],
    ];
    for (k, line) in lines.iter().enumerate() {
        for &(x, text) in line {
            labels::draw_text(&mut pixels, width, (x, LEGEND_TEXT_TOP + k as u32 * labels::LINE), text, LEGEND_INK);
        }
    }
    pixels
}

/// A signed map in [`signed_colour`] on `scale` ([`NO_VALUE`] where it has none) above its
/// legend: max(width, [`LEGEND_WIDTH`]) × (height + [`LEGEND_HEIGHT`]) pixels, the map at
/// the top left, grey beside a narrower map.
pub fn signed_picture(map: &SignedMap, scale: f64) -> (u32, u32, Vec<[f64; 3]>) {
    let width = map.width.max(LEGEND_WIDTH);
    let mut pixels = vec![NO_VALUE; (width * map.height) as usize];
    for y in 0..map.height {
        for x in 0..map.width {
            if let Some(Some(e)) = map.values.get((y * map.width + x) as usize) {
                pixels[(y * width + x) as usize] = signed_colour(*e, scale);
            }
        }
    }
    pixels.extend(legend(width, scale));
    (width, map.height + LEGEND_HEIGHT, pixels)
}

/// `<folder>/<stem>.png` per map ([`signed_picture`]), the maps of each technique on their
/// [`shared_scale`] (passes of one technique compare; two techniques each get the scale of
/// their own errors), and per technique that scale's legend alone,
/// `<folder>/<technique>_signed_scale.png` (256 wide).
pub fn signed_files(folder: &str, maps: &[SignedMap]) -> Result<Vec<SetFile>> {
    let mut techniques: Vec<&str> = Vec::new();
    for map in maps {
        if !techniques.contains(&map.technique) {
            techniques.push(map.technique);
        }
    }
    let scales: Vec<f64> = techniques.iter().map(|t| shared_scale(maps.iter().filter(|m| m.technique == *t))).collect();
    let scale_of = |technique: &str| scales[techniques.iter().position(|t| *t == technique).unwrap_or(0)];
    let mut written = Vec::new();
    for map in maps {
        let (width, height, pixels) = signed_picture(map, scale_of(map.technique));
        written.push(SetFile::new(format!("{folder}/{}.png", map.stem), error_png(width, height, pixels.into_iter())?));
    }
    for (technique, scale) in techniques.iter().zip(&scales) {
        let legend = error_png(256, LEGEND_HEIGHT, legend(256, *scale).into_iter())?;
        written.push(SetFile::new(format!("{folder}/{technique}_{SIGNED_SCALE_FILE}"), legend));
    }
    Ok(written)
}

/// |Δ| summed over the channels, per pixel: what an error image shows in false colour.
pub fn error_map(frame: &TracedFrame, reference: &TracedFrame) -> Vec<f64> {
    frame.radiance.iter().zip(&reference.radiance).map(|(a, r)| (0..3).map(|c| (a[c] - r[c]).abs()).sum()).collect()
}

/// A PNG of linear radiance, sRGB-encoded.
pub fn srgb_png(width: u32, height: u32, linear: impl Iterator<Item = [f64; 3]>) -> Result<Vec<u8>> {
    let bytes = linear.flat_map(srgb::srgb8).collect();
    encode(Encoding::Unorm8Srgb, width as usize, height as usize, &Texels::U8(bytes))
}

/// The files `<folder>/<stem>.exr` (linear) and `<stem>.png` (sRGB) per picture, and for a
/// picture with a reference `<stem>_error.png` (false colour of |Δ| summed over channels, on
/// the 1-2-5 step at or above its 99th percentile: `colour_bar`'s rule) with that scale's
/// legend, `<stem>_error_scale.png` ([`ERROR_LEGEND_WIDTH`] wide).
/// The width of an error picture's legend in pixels.
pub const ERROR_LEGEND_WIDTH: u32 = 256;

pub fn files(folder: &str, pictures: &[Picture]) -> Result<Vec<SetFile>> {
    let mut written = Vec::new();
    for picture in pictures {
        let frame = &picture.frame;
        let (w, h) = (frame.width, frame.height);
        let linear = Texels::F32(frame.radiance.iter().flat_map(|rgb| rgb.map(|v| v as f32)).collect());
        let mut files = vec![(format!("{}.exr", picture.stem), encode(Encoding::F32, w as usize, h as usize, &linear)?)];
        files.push((format!("{}.png", picture.stem), srgb_png(w, h, frame.radiance.iter().copied())?));
        if let Some(reference) = &picture.reference {
            let errors = error_map(frame, reference);
            let scale = p99_scale(errors.iter().copied());
            files.push((format!("{}_error.png", picture.stem), error_png(w, h, errors.iter().map(|&e| colour(e, scale)))?));
            let legend = legend_png(ERROR_LEGEND_WIDTH, scale, "|picture - reference| summed over R, G, B")?;
            files.push((format!("{}_error_scale.png", picture.stem), legend));
        }
        written.extend(files.into_iter().map(|(name, bytes)| SetFile::new(format!("{folder}/{name}"), bytes)));
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// White at 0, pure red at +scale, pure blue at −scale, half-way between: half-tinted.
    #[test]
    fn signed_colour_diverges_from_white() {
        let s = 0.25;
        assert_eq!(signed_colour(0.0, s), [1.0; 3]);
        assert_eq!(signed_colour(s, s), [1.0, 0.0, 0.0]);
        assert_eq!(signed_colour(3.0, s), [1.0, 0.0, 0.0]);
        assert_eq!(signed_colour(-s, s), [0.0, 0.0, 1.0]);
        assert_eq!(signed_colour(s / 2.0, s), [1.0, 0.5, 0.5]);
        assert_eq!(signed_colour(-s / 4.0, s), [0.75, 0.75, 1.0]);
    }

    /// The shared scale is the smallest 1-2-5 step at or above the 99th percentile of |e|
    /// over every map: |e| = 0.01, 0.03, 0.04 put it at 0.03 + 0.98 × 0.01 = 0.0398 → 0.05;
    /// one 0.9 among 99 zeros at 0.01 × 0.9 = 0.009 → 0.01 (the outlier saturates); none →
    /// the smallest step; everything beyond 1 → 1.
    #[test]
    fn maps_share_the_step_above_their_99th_percentile() {
        let map = |values: Vec<Option<f64>>| SignedMap { stem: "m".into(), technique: "t", width: values.len() as u32, height: 1, values };
        assert_eq!(shared_scale(&[map(vec![Some(0.01), Some(-0.03), None]), map(vec![Some(0.04)])]), 0.05);
        let mut outlier = vec![Some(0.0); 99];
        outlier.push(Some(-0.9));
        assert_eq!(shared_scale(&[map(outlier)]), 0.01);
        assert_eq!(shared_scale(&[map(vec![None])]), 0.01);
        assert_eq!(shared_scale(&[]), 0.01);
        assert_eq!(shared_scale(&[map(vec![Some(3.0), Some(f64::NAN), Some(-2.0)])]), 1.0);
    }

    /// Two hand-made maps written as files and decoded: both on the shared scale 0.05 (|e|
    /// sorted 0, 0.0125, 0.02, 0.025, 0.05, 0.05: p99 0.05), each pixel the colour of its
    /// value (the second map's −0.02 at 0.4 of blue, not the full blue its own scale would
    /// give), grey where nothing is and beside the map, and below it the legend: the bar
    /// from pure blue to pure red, its range "-0.05" … "+0.05" and what each end means, in
    /// the font's glyphs.
    #[test]
    fn signed_maps_share_a_scale_and_carry_their_legend() {
        let maps = [
            SignedMap {
                stem: "a".into(),
                technique: "surfels",
                width: 3,
                height: 2,
                values: vec![Some(0.05), None, Some(-0.025), Some(0.0), Some(-0.05), Some(0.0125)],
            },
            SignedMap { stem: "b".into(), technique: "surfels", width: 1, height: 1, values: vec![Some(-0.02)] },
        ];
        let written = signed_files("f", &maps).unwrap();
        assert_eq!(written.iter().map(|f| f.name.as_str()).collect::<Vec<_>>(), ["f/a.png", "f/b.png", "f/surfels_signed_scale.png"]);
        let decoded = |k: usize| {
            let image = nklut_tables::image_files::decode(Encoding::Unorm8, &written[k].bytes).unwrap();
            let Texels::U8(bytes) = image.texels else { panic!("8-bit") };
            (image.width as u32, image.height as u32, bytes)
        };
        let (width, height, a) = decoded(0);
        assert_eq!((width, height), (228, 2 + LEGEND_HEIGHT));
        assert_eq!(LEGEND_WIDTH, 228);
        let pixel = |bytes: &[u8], width: u32, x: u32, y: u32| {
            let i = 3 * (y * width + x) as usize;
            [bytes[i], bytes[i + 1], bytes[i + 2]]
        };
        // 0.0125 of 0.05: a quarter of the way to red, 1 − 0.25 = 0.75 → 191; −0.025: 128.
        let expected = [[255, 0, 0], [128, 128, 128], [128, 128, 255], [255, 255, 255], [0, 0, 255], [255, 191, 191]];
        for (i, colour) in expected.iter().enumerate() {
            assert_eq!(pixel(&a, width, i as u32 % 3, i as u32 / 3), *colour, "map pixel {i}");
        }
        assert_eq!(pixel(&a, width, 3, 0), [128; 3]);
        assert_eq!(pixel(&a, width, 227, 1), [128; 3]);
        let (_, _, b) = decoded(1);
        assert_eq!(pixel(&b, 228, 0, 0), [153, 153, 255], "0.6 × 255 = 153");
        // The legend under the map: the bar's ends, the paper around it, the text.
        let top = 2 + LEGEND_BAR_TOP;
        assert_eq!(pixel(&a, width, 2, top), [0, 0, 255]);
        assert_eq!(pixel(&a, width, 225, top + LEGEND_BAR_HEIGHT - 1), [255, 0, 0]);
        assert_eq!((pixel(&a, width, 1, top), pixel(&a, width, 226, top), pixel(&a, width, 2, top - 1)), ([255; 3], [255; 3], [255; 3]));
        let text_at = |bytes: &[u8], width: u32, (x, y): (u32, u32), text: &str| {
            for (k, c) in text.chars().enumerate() {
                let rows = font8x8::legacy::BASIC_LEGACY[c as usize];
                for (row, bits) in rows.iter().enumerate() {
                    for bit in 0..8 {
                        let ink = bits & (1 << bit) != 0;
                        let found = pixel(bytes, width, x + 8 * k as u32 + bit, y + row as u32);
                        assert_eq!(found, if ink { [0; 3] } else { [255; 3] }, "{text:?}, char {k} row {row} bit {bit}");
                    }
                }
            }
        };
        let text_top = 2 + LEGEND_TEXT_TOP;
        text_at(&a, width, (2, text_top), "-0.05");
        text_at(&a, width, (228 - 2 - 40, text_top), "+0.05");
        text_at(&a, width, (110, text_top), "0");
        text_at(&a, width, (2, text_top + 10), "over-occludes");
        text_at(&a, width, (228 - 2 - 8 * 14, text_top + 10), "under-occludes");
        // The legend alone: 256 wide, the same ends.
        let (width, height, scale) = decoded(2);
        assert_eq!((width, height), (256, LEGEND_HEIGHT));
        assert_eq!((pixel(&scale, 256, 2, LEGEND_BAR_TOP), pixel(&scale, 256, 253, LEGEND_BAR_TOP)), ([0, 0, 255], [255, 0, 0]));
        text_at(&scale, 256, (256 - 2 - 40, LEGEND_TEXT_TOP), "+0.05");
        assert!(signed_files("f", &[]).unwrap().is_empty());
    }

    /// The bar's ends are exactly ∓scale and its middle pixel of an odd count exactly 0.
    #[test]
    fn the_bar_runs_from_minus_to_plus_the_scale() {
        assert_eq!((bar_value(0, 5, 0.2), bar_value(2, 5, 0.2), bar_value(4, 5, 0.2)), (-0.2, 0.0, 0.2));
        assert_eq!((bar_value(0, 1, 0.2), bar_value(0, 0, 0.2)), (0.0, 0.0));
    }

    #[test]
    fn pictures_are_written_as_exr_png_and_error_png() {
        let frame =
            TracedFrame { width: 2, height: 1, radiance: vec![[0.5, 0.25, 1.0], [0.0, 0.0, 0.0]], seen: vec![Some(0), None], rays: 2 };
        let mut other = frame.clone();
        other.radiance[0][0] = 0.6;
        let written = files(
            "f",
            &[
                Picture { stem: "reference".into(), frame: frame.clone(), reference: None },
                Picture { stem: "schlick".into(), frame: other, reference: Some(frame) },
            ],
        )
        .unwrap();
        let names: Vec<&str> = written.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(
            names,
            ["f/reference.exr", "f/reference.png", "f/schlick.exr", "f/schlick.png", "f/schlick_error.png", "f/schlick_error_scale.png"]
        );
        let bytes = |name: &str| written.iter().find(|f| f.name == name).unwrap().bytes.clone();
        let decoded = nklut_tables::image_files::decode(Encoding::F32, &bytes("f/schlick.exr")).unwrap();
        assert_eq!(decoded.texels, Texels::F32(vec![0.6, 0.25, 1.0, 0.0, 0.0, 0.0]));
        let error = nklut_tables::image_files::decode(Encoding::Unorm8, &bytes("f/schlick_error.png")).unwrap();
        // |Δ| = 0.1 at the first pixel, 0 at the second: the 99th percentile 0.099 puts the
        // scale at the step 0.1, so white, then black.
        assert_eq!(error.texels, Texels::U8(vec![255, 255, 255, 0, 0, 0]));
        // The legend: 256 wide, the bar's right end white (the scale).
        let legend = nklut_tables::image_files::decode(Encoding::Unorm8, &bytes("f/schlick_error_scale.png")).unwrap();
        assert_eq!((legend.width, legend.height), (ERROR_LEGEND_WIDTH as usize, crate::colour_bar::LEGEND_HEIGHT as usize));
        let Texels::U8(legend) = legend.texels else { panic!("8-bit") };
        let at = |x: u32, y: u32| &legend[3 * (y * ERROR_LEGEND_WIDTH + x) as usize..][..3];
        let bar_y = labels::MARGIN + crate::colour_bar::BAR_HEIGHT / 2;
        assert_eq!(at(ERROR_LEGEND_WIDTH - labels::MARGIN - 1, bar_y), [255, 255, 255]);
        assert_eq!(at(labels::MARGIN, bar_y), [0, 0, 0]);
    }

    /// The labels module's side-by-side picture with two labelled panels (3 × 2 px of one colour, 20 × 3 of another) written as the PNG a
    /// person opens and decoded: the sizes and places are exact, the frames' pixels are where
    /// they belong, and every pixel of the label strips is the font's bitmap of the labels
    /// (read here straight from the crate's tables), white on black.
    #[test]
    fn labels_decode_to_the_fonts_glyphs() {
        let solid = |width: u32, height: u32, value: f64| TracedFrame {
            width,
            height,
            radiance: vec![[value; 3]; (width * height) as usize],
            seen: vec![None; (width * height) as usize],
            rays: 1,
        };
        // 20 px hold 2 columns: "AΔ 7" wraps to "AΔ", "7"; 3 px hold none.
        let panels = [
            labels::Panel { label: "too narrow".into(), frame: solid(3, 2, 0.5) },
            labels::Panel { label: "AΔ 7".into(), frame: solid(20, 3, 1.0) },
        ];
        let strip = 2 * labels::MARGIN + labels::LINE + labels::GLYPH;
        let placed = labels::places(&panels);
        assert_eq!(placed[0], labels::PanelPlace { x: 0, y: strip, width: 3, height: 2, lines: vec![] });
        assert_eq!(
            placed[1],
            labels::PanelPlace { x: 3 + labels::GAP, y: strip, width: 20, height: 3, lines: vec!["AΔ".into(), "7".into()] }
        );
        let frame = labels::side_by_side(&panels);
        let (width, height) = (3 + labels::GAP + 20, strip + 3);
        assert_eq!((frame.width, frame.height, frame.radiance.len(), frame.rays), (width, height, (width * height) as usize, 2));

        let written = files("f", &[Picture { stem: "s".into(), frame, reference: None }]).unwrap();
        let png =
            nklut_tables::image_files::decode(Encoding::Unorm8Srgb, &written.iter().find(|f| f.name == "f/s.png").unwrap().bytes).unwrap();
        let Texels::U8(bytes) = png.texels else { panic!("8-bit PNG") };
        let pixel = |x: u32, y: u32| {
            let i = 3 * (y * width + x) as usize;
            [bytes[i], bytes[i + 1], bytes[i + 2]]
        };
        let font = |c: char| match c {
            'Δ' => font8x8::legacy::GREEK_LEGACY[0x394 - 0x390],
            _ => font8x8::legacy::BASIC_LEGACY[c as usize],
        };
        let grey = nklut_optics::color::srgb::srgb8(labels::GAP_RADIANCE);
        let half = nklut_optics::color::srgb::srgb8([0.5; 3]);
        for y in 0..height {
            for x in 0..width {
                let expected = if (3..3 + labels::GAP).contains(&x) {
                    grey
                } else if x < 3 {
                    // The narrow panel: an empty strip, its frame, black below it.
                    if (strip..strip + 2).contains(&y) {
                        half
                    } else {
                        [0; 3]
                    }
                } else if y >= strip {
                    [255; 3]
                } else {
                    let (px, py) = (x - 3 - labels::GAP, y);
                    let ink = match (px.checked_sub(labels::MARGIN), py.checked_sub(labels::MARGIN)) {
                        (Some(gx), Some(gy)) if gx < 16 && gy % labels::LINE < labels::GLYPH => {
                            let text = if gy < labels::LINE { ['A', 'Δ'].get((gx / 8) as usize) } else { ['7'].get((gx / 8) as usize) };
                            text.is_some_and(|&c| font(c)[(gy % labels::LINE) as usize] & (1 << (gx % 8)) != 0)
                        }
                        _ => false,
                    };
                    if ink {
                        [255; 3]
                    } else {
                        [0; 3]
                    }
                };
                assert_eq!(pixel(x, y), expected, "pixel ({x}, {y})");
            }
        }
        // Some ink was drawn: 'A' has 28 set bits in the font, 'Δ' and '7' more than none.
        let inked_pixels =
            (0..height).flat_map(|y| (0..width).map(move |x| (x, y))).filter(|&(x, y)| y < strip && pixel(x, y) == [255; 3]).count();
        let set_bits = |c: char| font(c).iter().map(|r| r.count_ones() as usize).sum::<usize>();
        assert_eq!(set_bits('A'), 28);
        assert_eq!(inked_pixels, set_bits('A') + set_bits('Δ') + set_bits('7'));
    }
}
