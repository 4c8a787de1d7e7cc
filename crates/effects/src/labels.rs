//! Text burned into pictures, so a picture says what it shows wherever it is opened: the
//! label strip above each panel of a side-by-side picture and the legends of the signed
//! error maps. Glyphs are the public-domain 8 × 8 bitmap font (the IBM PC's, as collected
//! by D. Hepper's `font8x8.h`) from the `font8x8` crate's byte tables: ASCII, Latin-1 and
//! Greek; row r of a glyph is byte r, bit i (least significant first) the pixel at x = i.
//!
//! Layout of a side-by-side picture ([`side_by_side`]): panels left to right, [`GAP`] pixels
//! of grey between them, each under a strip of the panels' common height holding its label
//! word-wrapped to the panel's width in white on black, [`MARGIN`] pixels from the strip's
//! left and top edges, one line every [`LINE`] pixels.

use crate::trace::TracedFrame;
use font8x8::legacy::{BASIC_LEGACY, GREEK_LEGACY, LATIN_LEGACY};

/// A glyph's width and height in pixels.
pub const GLYPH: u32 = 8;
/// The distance between two lines' tops (the glyph and 2 pixels of leading).
pub const LINE: u32 = 10;
/// The space around the text in a strip.
pub const MARGIN: u32 = 2;
/// The grey columns between two panels.
pub const GAP: u32 = 4;
/// The gap's linear radiance (mid grey).
pub const GAP_RADIANCE: [f64; 3] = [0.2; 3];
/// The label's ink and the strip's background (linear radiance: white and black).
pub const INK: [f64; 3] = [1.0; 3];
pub const PAPER: [f64; 3] = [0.0; 3];

/// The eight rows of `c`'s glyph: ASCII, Latin-1 (U+00A0–U+00FF) and Greek (U+0390–U+03C9)
/// from the font; dashes (en, em, minus) as the hyphen; anything else as `?`.
pub fn glyph(c: char) -> [u8; 8] {
    let code = c as usize;
    match c {
        '\u{2013}' | '\u{2014}' | '\u{2212}' => BASIC_LEGACY[b'-' as usize],
        _ if code < 0x80 => BASIC_LEGACY[code],
        _ if (0xA0..0x100).contains(&code) => LATIN_LEGACY[code - 0xA0],
        _ if (0x390..0x3CA).contains(&code) => GREEK_LEGACY[code - 0x390],
        _ => BASIC_LEGACY[b'?' as usize],
    }
}

/// The characters that fit across `width` pixels with the margins.
pub fn columns(width: u32) -> usize {
    (width.saturating_sub(2 * MARGIN) / GLYPH) as usize
}

/// `text` in lines of at most `columns` characters: a new line at each `\n`, and between
/// words where a line is full (a word longer than a line cut at the line's end); no line
/// for no column or no text.
pub fn wrap(text: &str, columns: usize) -> Vec<String> {
    text.split('\n').flat_map(|paragraph| wrap_words(paragraph, columns)).collect()
}

fn wrap_words(text: &str, columns: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    if columns == 0 {
        return lines;
    }
    let mut line: Vec<char> = Vec::new();
    for word in text.split_whitespace() {
        let mut word: Vec<char> = word.chars().collect();
        if !line.is_empty() && line.len() + 1 + word.len() > columns {
            lines.push(line.drain(..).collect());
        }
        if !line.is_empty() {
            line.push(' ');
        }
        while line.len() + word.len() > columns {
            let room = columns - line.len();
            line.extend(word.drain(..room));
            lines.push(line.drain(..).collect());
        }
        line.extend(word);
    }
    if !line.is_empty() {
        lines.push(line.into_iter().collect());
    }
    lines
}

/// Whether the pixel (x, y) of a strip holding `lines` (from [`wrap`]) is ink: line k's
/// characters start at (MARGIN, MARGIN + k·LINE), [`GLYPH`] pixels apart.
pub fn inked(lines: &[String], x: u32, y: u32) -> bool {
    let (Some(x), Some(y)) = (x.checked_sub(MARGIN), y.checked_sub(MARGIN)) else { return false };
    let (line, row) = ((y / LINE) as usize, y % LINE);
    if row >= GLYPH {
        return false;
    }
    let Some(c) = lines.get(line).and_then(|l| l.chars().nth((x / GLYPH) as usize)) else { return false };
    glyph(c)[row as usize] >> (x % GLYPH) & 1 == 1
}

/// The height of a strip holding `lines` lines (0 for none).
pub fn strip_height(lines: usize) -> u32 {
    if lines == 0 {
        0
    } else {
        2 * MARGIN + (lines as u32 - 1) * LINE + GLYPH
    }
}

/// The width in pixels of `text` in one line.
pub fn text_width(text: &str) -> u32 {
    text.chars().count() as u32 * GLYPH
}

/// `text` in one line with its top-left corner at (x, y) of a `width`-pixel-wide picture
/// of `pixels`, its ink set to `ink` (what falls outside the picture is left out).
pub fn draw_text(pixels: &mut [[f64; 3]], width: u32, (x, y): (u32, u32), text: &str, ink: [f64; 3]) {
    let height = pixels.len() as u32 / width.max(1);
    for (k, c) in text.chars().enumerate() {
        for (row, bits) in glyph(c).into_iter().enumerate() {
            for bit in 0..GLYPH {
                let (px, py) = (x + k as u32 * GLYPH + bit, y + row as u32);
                if bits >> bit & 1 == 1 && px < width && py < height {
                    pixels[(py * width + px) as usize] = ink;
                }
            }
        }
    }
}

/// One panel of a side-by-side picture: what it shows (technique and error figure) and the
/// frame.
#[derive(Clone, Debug)]
pub struct Panel {
    pub label: String,
    pub frame: TracedFrame,
}

/// Where a panel sits in a side-by-side picture: its frame's top-left pixel and size, and
/// its label strip's lines.
#[derive(Clone, Debug, PartialEq)]
pub struct PanelPlace {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
    pub lines: Vec<String>,
}

/// The places of `panels`: left to right, [`GAP`] apart, every frame below a strip as high
/// as the most lines any label needs.
pub fn places(panels: &[Panel]) -> Vec<PanelPlace> {
    let wrapped: Vec<Vec<String>> = panels.iter().map(|p| wrap(&p.label, columns(p.frame.width))).collect();
    let strip = strip_height(wrapped.iter().map(Vec::len).max().unwrap_or(0));
    let mut x = 0;
    panels
        .iter()
        .zip(wrapped)
        .map(|(panel, lines)| {
            let place = PanelPlace { x, y: strip, width: panel.frame.width, height: panel.frame.height, lines };
            x += panel.frame.width + GAP;
            place
        })
        .collect()
}

/// The panels side by side, each under its label (module doc); below a shorter frame, the
/// picture is black.
pub fn side_by_side(panels: &[Panel]) -> TracedFrame {
    let places = places(panels);
    let strip = places.first().map_or(0, |p| p.y);
    let width = places.last().map_or(0, |p| p.x + p.width);
    let height = strip + places.iter().map(|p| p.height).max().unwrap_or(0);
    let mut radiance = vec![GAP_RADIANCE; (width * height) as usize];
    for (panel, place) in panels.iter().zip(&places) {
        for y in 0..height {
            for x in 0..place.width {
                let pixel = if y < strip {
                    if inked(&place.lines, x, y) {
                        INK
                    } else {
                        PAPER
                    }
                } else if y - strip < place.height {
                    panel.frame.radiance[((y - strip) * place.width + x) as usize]
                } else {
                    PAPER
                };
                radiance[(y * width + place.x + x) as usize] = pixel;
            }
        }
    }
    TracedFrame { width, height, seen: vec![None; radiance.len()], radiance, rays: panels.iter().map(|p| p.frame.rays).sum() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_wrap_at_the_column_count() {
        assert_eq!(wrap("surfel AO, 2 passes, tree: mean |Δ| 0.021/px", 26), ["surfel AO, 2 passes, tree:", "mean |Δ| 0.021/px"]);
        assert_eq!(wrap("abcdefgh ij", 3), ["abc", "def", "gh", "ij"]);
        assert_eq!(wrap("no AO\nmean 0.3\n\n", 20), ["no AO", "mean 0.3"]);
        assert_eq!(wrap("  a   b ", 3), ["a b"]);
        assert!(wrap("anything", 0).is_empty() && wrap("   ", 5).is_empty());
        assert_eq!((columns(256), columns(12), columns(11), columns(0)), (31, 1, 0, 0));
        assert_eq!((strip_height(0), strip_height(1), strip_height(2)), (0, 12, 22));
    }

    /// Glyphs come from the font's own tables; characters outside them read `?`.
    #[test]
    fn glyphs_are_the_fonts() {
        assert_eq!(glyph('A'), [0x0C, 0x1E, 0x33, 0x33, 0x3F, 0x33, 0x33, 0x00]);
        assert_eq!(glyph('Δ'), font8x8::legacy::GREEK_LEGACY[4]);
        assert_eq!(glyph('é'), font8x8::legacy::LATIN_LEGACY[0xE9 - 0xA0]);
        assert_eq!(glyph('—'), glyph('-'));
        assert_eq!(glyph('→'), glyph('?'));
    }
}
