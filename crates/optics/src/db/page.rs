//! One data file of the database (a "page"): its DATA blocks turned into an n curve and
//! an optional k curve, plus the metadata the outputs carry (SPEC §1).
//!
//! A defect of a table that lies outside every wavelength a stage evaluates
//! ([`EVALUATED_NM`]: wavelengths that do not increase, far in the infrared, say) is a
//! warning with its line, not an exclusion: the curve keeps the one run of increasing
//! rows that reaches into that window. Tabulated values used there must lie in the index
//! domain the Fresnel methods are tested on ([`N_DOMAIN`], [`K_MAX`]).

use serde::Deserialize;

use super::error::{DataError, Reason};
use super::formula::{max_coefficients, Formula};

/// The widest wavelength window (nm) any stage evaluates: the spectral grid of the
/// reference colours, which holds every channel wavelength and the visible window.
pub const EVALUATED_NM: (f64, f64) = (360.0, 830.0);

/// The refractive indices n the Fresnel methods are tested on (their property tests'
/// domain); data outside it are excluded as `index-out-of-domain`.
pub const N_DOMAIN: (f64, f64) = (1e-3, 1e3);
/// The largest extinction coefficient k of that domain (k ≥ 0).
pub const K_MAX: f64 = 1e3;

/// The wavelengths (µm) a table row or a formula's range may hold: 1 fm to 100 m, far
/// past the database's X-ray and radio pages, and a range every table writes in a few
/// digits (`lambda_min_nm` 0.000001 to `lambda_max_nm` 100000000000; the database's shortest
/// is 8.3e-8 µm). A wavelength outside
/// it (1e300 µm, or 1.8e308, which is infinite in nm) excludes its page as
/// `wavelength-out-of-range` with its line.
pub const WAVELENGTH_DOMAIN_UM: (f64, f64) = (1e-9, 1e8);

/// Whether `um` lies in [`WAVELENGTH_DOMAIN_UM`].
pub fn wavelength_in_domain(um: f64) -> bool {
    (WAVELENGTH_DOMAIN_UM.0..=WAVELENGTH_DOMAIN_UM.1).contains(&um)
}

/// n(λ) or k(λ) over a wavelength range, λ in µm.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve {
    /// Rows of (λ, value), λ strictly increasing; linear interpolation between rows.
    Tabulated {
        /// λ of each row (µm).
        wavelengths_um: Vec<f64>,
        /// n or k of each row.
        values: Vec<f64>,
    },
    /// A dispersion formula (n only).
    Formula(Formula),
}

impl Curve {
    /// The wavelength range (µm) the curve is defined on.
    pub fn range_um(&self) -> (f64, f64) {
        match self {
            Curve::Tabulated { wavelengths_um, .. } => (wavelengths_um[0], *wavelengths_um.last().unwrap()),
            Curve::Formula(f) => f.range_um,
        }
    }

    /// Value at λ (µm), or `None` outside the range. Tabulated: linear in λ between the
    /// neighbouring rows (what the database's site does).
    pub fn at(&self, um: f64) -> Option<f64> {
        self.value_at(um, |x| x.partition_point(|&w| w <= um))
    }

    /// [`at`](Self::at) for wavelengths read in increasing order: `row` holds the row the
    /// previous call found (start with 0) and is moved forward a few rows at a time instead
    /// of searching the whole table again. Any `row` gives the same value as `at`.
    pub fn at_near(&self, um: f64, row: &mut usize) -> Option<f64> {
        self.value_at(um, |x| {
            *row = rows_not_above(x, um, *row);
            *row
        })
    }

    /// The value at λ, `rows(x)` giving how many tabulated wavelengths are ≤ λ.
    #[inline(always)]
    fn value_at(&self, um: f64, rows: impl FnOnce(&[f64]) -> usize) -> Option<f64> {
        let (lo, hi) = self.range_um();
        if !(um >= lo && um <= hi) {
            return None;
        }
        Some(match self {
            Curve::Formula(f) => f.refractive_index(um),
            Curve::Tabulated { wavelengths_um: x, values: y } => {
                let i = rows(x);
                if i == 0 {
                    y[0]
                } else if i >= x.len() {
                    y[x.len() - 1]
                } else {
                    let t = (um - x[i - 1]) / (x[i] - x[i - 1]);
                    y[i - 1] + t * (y[i] - y[i - 1])
                }
            }
        })
    }

    /// Value at λ with the nearest end held constant outside the range (SPEC §4).
    pub fn at_held(&self, um: f64) -> f64 {
        let (lo, hi) = self.range_um();
        self.at(um.clamp(lo, hi)).unwrap_or(f64::NAN)
    }

    /// The tabulated wavelengths, if any.
    pub fn samples_um(&self) -> Option<&[f64]> {
        match self {
            Curve::Tabulated { wavelengths_um, .. } => Some(wavelengths_um),
            Curve::Formula(_) => None,
        }
    }
}

/// How many of the increasing wavelengths `x` are ≤ `um` (`x.partition_point(|&w| w <= um)`),
/// found by stepping forward from `from` when the answer lies a few rows on, else by a binary
/// search. The count is the same whatever `from` is.
fn rows_not_above(x: &[f64], um: f64, from: usize) -> usize {
    /// Rows stepped over before a binary search of the rest takes over.
    const STEPS: usize = 8;
    if from > x.len() || (from > 0 && !(x[from - 1] <= um)) {
        return x.partition_point(|&w| w <= um);
    }
    // Every row before `from` is ≤ um.
    let mut i = from;
    for _ in 0..STEPS {
        if i == x.len() || !(x[i] <= um) {
            return i;
        }
        i += 1;
    }
    i + x[i..].partition_point(|&w| w <= um)
}

/// A printed property value and its number of decimals (e.g. `nd: 1.523` → 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Printed {
    /// The number.
    pub value: f64,
    /// Decimals as printed.
    pub decimals: usize,
}

/// A parsed data file.
#[derive(Clone, Debug, PartialEq)]
pub struct PageData {
    /// Path relative to `database/data/`.
    pub file: String,
    /// The refractive index n over wavelength.
    pub n: Curve,
    /// The extinction coefficient k over wavelength, where the page has it.
    pub k: Option<Curve>,
    /// First line of REFERENCES, HTML tags removed.
    pub reference: String,
    /// `PROPERTIES.nd`, the index at the d line (587.5618 nm), as printed.
    pub nd: Option<Printed>,
    /// `PROPERTIES.Vd`, the Abbe number, as printed.
    pub vd: Option<Printed>,
    /// Defects that do not touch the evaluated window, each with its line.
    pub warnings: Vec<DataError>,
}

#[derive(Deserialize)]
struct RawPage {
    #[serde(rename = "REFERENCES", default)]
    references: Option<serde_norway::Value>,
    #[serde(rename = "DATA", default)]
    data: Option<Vec<RawBlock>>,
    #[serde(rename = "PROPERTIES", default)]
    properties: Option<serde_norway::Value>,
}

#[derive(Deserialize)]
struct RawBlock {
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    data: Option<serde_norway::Value>,
    #[serde(default)]
    coefficients: Option<serde_norway::Value>,
    #[serde(default)]
    wavelength_range: Option<serde_norway::Value>,
}

/// A YAML scalar as text (numbers and strings alike).
fn scalar_text(value: &serde_norway::Value) -> Option<String> {
    match value {
        serde_norway::Value::String(s) => Some(s.clone()),
        serde_norway::Value::Number(n) => Some(n.to_string()),
        _ => None,
    }
}

/// Remove HTML tags and collapse whitespace.
pub fn strip_html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut in_tag = false;
    for ch in text.chars() {
        match ch {
            '<' => in_tag = true,
            '>' if in_tag => in_tag = false,
            _ if !in_tag => out.push(ch),
            _ => {}
        }
    }
    out.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// What the line scans of a data file's text find, in one pass over its lines.
struct TextKeys {
    /// 1-based line numbers of the `data:` keys of the DATA blocks, in file order, so that
    /// row i of the j-th tabulated block is at line `data_lines[j] + 1 + i`.
    data_lines: Vec<usize>,
    /// `PROPERTIES.nd` and `PROPERTIES.Vd` as printed.
    nd: Option<Printed>,
    vd: Option<Printed>,
}

impl TextKeys {
    fn scan(text: &str) -> Self {
        let mut data_lines = Vec::new();
        // The first `nd:` / `Vd:` line under PROPERTIES decides (a value that is not a
        // number gives none).
        let mut nd: Option<Option<Printed>> = None;
        let mut vd: Option<Option<Printed>> = None;
        let mut in_properties = false;
        let bytes = text.as_bytes();
        // Lines as `str::lines` cuts them, numbered from 1.
        let mut at = 0;
        let mut number = 0;
        while at < bytes.len() {
            number += 1;
            // An empty line (a blanked table row, mostly) changes nothing but the count.
            if bytes[at] == b'\n' {
                at += 1;
                continue;
            }
            let (line, end) = str_lines_line(text, at);
            at = end + 1;
            let trimmed = line.trim_start();
            if trimmed.starts_with("data:") && line.len() - trimmed.len() >= 2 {
                data_lines.push(number);
            }
            if !line.starts_with(' ') && !line.is_empty() {
                in_properties = line.starts_with("PROPERTIES:");
                continue;
            }
            // Direct children of PROPERTIES only (4 spaces in the database's layout, any > 0 here).
            if in_properties {
                for (key, slot) in [("nd", &mut nd), ("Vd", &mut vd)] {
                    if slot.is_none() && trimmed.starts_with(key) && trimmed[key.len()..].starts_with(':') {
                        *slot = Some(printed_value(&trimmed[key.len() + 1..]));
                    }
                }
            }
        }
        Self { data_lines, nd: nd.flatten(), vd: vd.flatten() }
    }
}

/// The literal block scalars (`data: |`) of a data file, cut out of its text: the numeric
/// tables are most of the database's 47 MB, and a YAML parser spends nearly all its time
/// scanning them character by character. The YAML parser gets the compact text, in which
/// each table's lines are replaced by one line naming the table ([`TABLE_MARKER`] and its
/// number), so the parser — not the line scan — says which key holds which table: a block
/// whose value is a marker takes that table's text from here, and a `data: |` the scan
/// found anywhere else (inside a comment's block, say) names no DATA block, which sends
/// the page to the parser whole ([`parse_page`]). Lines found in the compact text are
/// numbered as in the file by [`CutTables::file_line`]; a YAML error is reported from the
/// text with the tables blanked instead ([`CutTables::blanked`]: every line kept, so the
/// parser's own line and column are the file's).
struct CutTables<'a> {
    text: &'a str,
    /// The text for the YAML parser.
    compact: String,
    /// Per table, the compact text's line of its `data:` key and how many lines the cut
    /// removed after it, in file order.
    removed: Vec<(usize, usize)>,
    /// The tables' bytes in the text.
    blank: Vec<Blanked>,
    /// (line of the `data:` key, the raw lines of its block) in file order.
    tables: Vec<(usize, &'a str)>,
}

impl<'a> CutTables<'a> {
    /// `None` when the file has no literal block, one whose layout a plain line scan cannot
    /// follow exactly (a content line indented less than the block's first line, a tab in
    /// the indentation), or holds [`TABLE_MARKER`] itself: the YAML parser then reads the
    /// whole text.
    fn cut(text: &'a str) -> Option<Self> {
        if memchr::memmem::find(text.as_bytes(), TABLE_MARKER.as_bytes()).is_some() {
            return None;
        }
        let mut tables = Vec::new();
        let mut blank: Vec<Blanked> = Vec::new();
        let mut lines = LineOffsets::new(text);
        while let Some((number, start, line)) = lines.next() {
            let Some(indent) = literal_data_key(line) else { continue };
            let body_start = start + line.len() + newline_len(text, start + line.len());
            let mut body_end = body_start;
            let mut block_indent: Option<usize> = None;
            let mut body_lines = 0;
            // The body's lines, as `LineOffsets` cuts them, read in place.
            let mut line_start = lines.at;
            while line_start < text.len() {
                let (next, end) = line_at(text, line_start);
                let bytes = next.as_bytes();
                let spaces = leading_spaces(bytes, 0);
                let content = &next[spaces..];
                let (content_line, tab) = match bytes.get(spaces) {
                    // A table row: printable ASCII after the spaces.
                    Some(&b) if b > b' ' && b.is_ascii() => (true, false),
                    None => (false, false),
                    // Anything else (a tab, other whitespace, a non-ASCII character): the
                    // general rule, by the `str` methods.
                    Some(_) => (!content.trim().is_empty(), content.starts_with('\t')),
                };
                if !content_line {
                    if tab {
                        return None;
                    }
                } else if spaces <= indent {
                    break;
                } else {
                    if tab {
                        return None;
                    }
                    match block_indent {
                        None => block_indent = Some(spaces),
                        Some(b) if spaces < b => return None,
                        Some(_) => {}
                    }
                }
                body_end = line_start + next.len();
                body_lines += 1;
                line_start = end + 1;
            }
            lines.skip_to(line_start, body_lines);
            tables.push((number, &text[body_start.min(body_end)..body_end]));
            // Every body line but the last ends inside the body.
            blank.push(Blanked {
                start: body_start,
                end: body_end,
                newlines: body_lines.max(1) - 1,
                indent: block_indent.unwrap_or(indent + 2),
            });
        }
        if tables.is_empty() {
            return None;
        }
        // Each table's key line in the compact text and the lines removed after it.
        let removed = tables
            .iter()
            .zip(&blank)
            .filter(|(_, table)| table.start < table.end)
            .scan(0, |lines_removed, (&(key_line, _), table)| {
                let entry = (key_line - *lines_removed, table.newlines);
                *lines_removed += table.newlines;
                Some(entry)
            })
            .collect();
        let compact = replace_tables(text, &blank, Replacement::Marker);
        Some(Self { text, compact, removed, blank, tables })
    }

    /// The text with each table's lines blanked: every line of the file, so a YAML error
    /// in it is at the file's line and column.
    fn blanked(&self) -> String {
        replace_tables(self.text, &self.blank, Replacement::LineEnds)
    }

    /// The table a DATA block's parsed `data` value names, if it is a marker: its number.
    fn marked(value: &serde_norway::Value) -> Option<usize> {
        value.as_str()?.trim().strip_prefix(TABLE_MARKER)?.parse().ok()
    }

    /// The file's number of line `line` of the compact text (the tables' keys and every
    /// line outside the tables are in both).
    fn file_line(&self, line: usize) -> usize {
        line + self.removed.iter().take_while(|(key, _)| *key < line).map(|(_, n)| n).sum::<usize>()
    }
}

/// What stands in a table's place: its line ends (every line keeps its number), or one
/// line naming it ([`TABLE_MARKER`] and the table's number among the non-empty ones).
#[derive(Clone, Copy, PartialEq)]
enum Replacement {
    LineEnds,
    Marker,
}

/// The start of the line that replaces a table in the compact text; a file holding it is
/// read by the YAML parser whole.
const TABLE_MARKER: &str = "@nklut-table-";

/// `text` with each table's bytes replaced as `replacement` says.
fn replace_tables(text: &str, tables: &[Blanked], replacement: Replacement) -> String {
    let kept = |table: &Blanked| match replacement {
        Replacement::LineEnds => table.newlines,
        Replacement::Marker => table.indent + TABLE_MARKER.len() + 20,
    };
    let length = tables.iter().filter(|t| t.start < t.end).fold(text.len(), |length, t| length - (t.end - t.start) + kept(t));
    let mut out = String::with_capacity(length);
    let mut at = 0;
    for (number, table) in tables.iter().enumerate() {
        if table.start >= table.end {
            continue;
        }
        out.push_str(&text[at..table.start]);
        match replacement {
            Replacement::LineEnds => out.extend(std::iter::repeat_n('\n', table.newlines)),
            Replacement::Marker => {
                use std::fmt::Write as _;
                let _ = write!(out, "{:width$}{TABLE_MARKER}{number}", "", width = table.indent);
            }
        }
        at = table.end;
    }
    out.push_str(&text[at..]);
    out
}

/// A table's bytes `start..end` in the text, its `newlines` line ends, and the indentation
/// of its block's lines.
struct Blanked {
    start: usize,
    end: usize,
    newlines: usize,
    indent: usize,
}

/// The indentation of a `data: |` key (a literal block, clip/strip/keep chomping, no
/// comment) inside a DATA block; `None` for any other line.
fn literal_data_key(line: &str) -> Option<usize> {
    let trimmed = line.trim_start_matches(' ');
    let indent = line.len() - trimmed.len();
    let value = trimmed.strip_prefix("data:")?.trim();
    (indent >= 2 && matches!(value, "|" | "|-" | "|+")).then_some(indent)
}

/// 1 for "\n", 2 for "\r\n", 0 at the end of the text.
fn newline_len(text: &str, at: usize) -> usize {
    match &text.as_bytes()[at..] {
        [b'\r', b'\n', ..] => 2,
        [b'\n', ..] => 1,
        _ => 0,
    }
}

/// Lines with their 1-based number and byte offset (line ends as `str::lines` sees them).
struct LineOffsets<'a> {
    text: &'a str,
    at: usize,
    number: usize,
}

impl<'a> LineOffsets<'a> {
    fn new(text: &'a str) -> Self {
        Self { text, at: 0, number: 0 }
    }

    /// Continue at byte `at`, the start of a line, after `lines` lines read elsewhere.
    fn skip_to(&mut self, at: usize, lines: usize) {
        self.at = at;
        self.number += lines;
    }
}

impl<'a> Iterator for LineOffsets<'a> {
    type Item = (usize, usize, &'a str);

    fn next(&mut self) -> Option<Self::Item> {
        if self.at >= self.text.len() {
            return None;
        }
        let (line, end) = line_at(self.text, self.at);
        let start = self.at;
        self.at = end + 1;
        self.number += 1;
        Some((self.number, start, line))
    }
}

/// The line of `text` that starts at byte `at`, as [`LineOffsets`] cuts it (a `\r` before
/// its end dropped), and the byte where it ends (its `\n`, or the end of the text).
fn line_at(text: &str, at: usize) -> (&str, usize) {
    let end = memchr::memchr(b'\n', &text.as_bytes()[at..]).map_or(text.len(), |e| at + e);
    let line = &text[at..end];
    (line.strip_suffix('\r').unwrap_or(line), end)
}

/// [`line_at`] as `str::lines` cuts the line: a `\r` is dropped only before a `\n`, so the
/// text's last line keeps a bare one.
fn str_lines_line(text: &str, at: usize) -> (&str, usize) {
    let (line, end) = line_at(text, at);
    (if end < text.len() { line } else { &text[at..end] }, end)
}

/// A property value as printed after its key (decimals matter for the nd check).
fn printed_value(after_key: &str) -> Option<Printed> {
    let raw = after_key.trim();
    let value: f64 = raw.parse().ok()?;
    let decimals = raw.split_once('.').map(|(_, d)| d.chars().take_while(|c| c.is_ascii_digit()).count()).unwrap_or(0);
    Some(Printed { value, decimals })
}

/// One tabulated row (λ and one or two values; unused slots are 0) and its line.
struct Row {
    values: [f64; 3],
    line: Option<usize>,
}

/// What a byte is to the field splitter of the tables.
#[derive(Clone, Copy, PartialEq)]
enum ByteClass {
    /// Whitespace as [`char::is_whitespace`] sees it among ASCII bytes: tab, line feed,
    /// vertical tab, form feed, carriage return, space.
    Space,
    /// A byte of a plain decimal number: digits, `.`, `+`, `-`, `e`, `E`.
    Numeric,
    /// Any other ASCII byte.
    Other,
    /// A byte of a multi-byte character (≥ 0x80).
    NonAscii,
}

const BYTE_CLASSES: [ByteClass; 256] = {
    let mut classes = [ByteClass::Other; 256];
    let mut b = 0;
    while b < 256 {
        classes[b] = match b as u8 {
            b'\t'..=b'\r' | b' ' => ByteClass::Space,
            b'0'..=b'9' | b'.' | b'+' | b'-' | b'e' | b'E' => ByteClass::Numeric,
            0x80..=0xFF => ByteClass::NonAscii,
            _ => ByteClass::Other,
        };
        b += 1;
    }
    classes
};

/// One field of a table row, and whether all its bytes are [`ByteClass::Numeric`].
#[derive(Clone, Copy, Default)]
struct Field<'a> {
    text: &'a str,
    plain: bool,
}

/// The whitespace-separated fields of `line` as [`str::split_whitespace`] gives them: the
/// first three in `fields`, and their count. A line of ASCII is split byte by byte; any
/// other goes through `split_whitespace` itself (Unicode spaces separate fields too).
fn split_fields<'a>(line: &'a str, fields: &mut [Field<'a>; 3]) -> usize {
    let bytes = line.as_bytes();
    let mut count = 0;
    let mut at = 0;
    while at < bytes.len() {
        match BYTE_CLASSES[bytes[at] as usize] {
            ByteClass::Space => {
                at += 1;
                continue;
            }
            ByteClass::NonAscii => return split_fields_unicode(line, fields),
            _ => {}
        }
        let start = at;
        let mut plain = true;
        while at < bytes.len() {
            match BYTE_CLASSES[bytes[at] as usize] {
                ByteClass::Space => break,
                ByteClass::Numeric => {}
                ByteClass::Other => plain = false,
                ByteClass::NonAscii => return split_fields_unicode(line, fields),
            }
            at += 1;
        }
        if let Some(slot) = fields.get_mut(count) {
            *slot = Field { text: &line[start..at], plain };
        }
        count += 1;
    }
    count
}

/// [`split_fields`] of a line holding a non-ASCII character, by `split_whitespace`.
fn split_fields_unicode<'a>(line: &'a str, fields: &mut [Field<'a>; 3]) -> usize {
    let mut count = 0;
    for text in line.split_whitespace() {
        if let Some(slot) = fields.get_mut(count) {
            *slot = Field { text, plain: false };
        }
        count += 1;
    }
    count
}

/// A field read as `f64`'s [`FromStr`](std::str::FromStr) reads it. Fields of up to 64
/// digits, signs, points and exponent marks (every table number) go to `fast-float2`,
/// whose grammar for them is the same and whose result is the same correctly rounded
/// value; anything else (`inf`, `NaN`, stray text, longer fields) to the standard parser.
pub fn parse_float(field: &str) -> Option<f64> {
    let plain = field.bytes().all(|b| BYTE_CLASSES[b as usize] == ByteClass::Numeric);
    parse_field(Field { text: field, plain })
}

/// [`parse_float`] of a field whose bytes were classified while it was split off.
fn parse_field(field: Field) -> Option<f64> {
    if field.plain && field.text.len() <= 64 {
        fast_float2::parse(field.text).ok()
    } else {
        field.text.parse().ok()
    }
}

/// The numbers of the row that starts at byte `at` of a table, read in one pass when the
/// row is plain: ASCII whitespace around exactly `columns` numbers, each finite, of at most
/// 64 bytes and ending at whitespace, read by fast-float2 (the standard parser's value: a
/// finite result comes from the plain decimal grammar, which the two share). Returns the
/// values and the offset of the row's line end (its `\n`, or the end of the table); `None`
/// for any other row (blank, short, long, not numbers), which [`general_row`] then reads.
fn plain_row(bytes: &[u8], at: usize, columns: usize) -> Option<([f64; 3], usize)> {
    let mut values = [0.0; 3];
    let mut count = 0;
    // The row's indentation (spaces, most of a row's whitespace) eight bytes at a time.
    let mut at = at + leading_spaces(bytes, at);
    loop {
        // Whitespace within the line: every ASCII whitespace byte but the line feed.
        while at < bytes.len() && matches!(bytes[at], b'\t' | b'\x0B' | b'\x0C' | b'\r' | b' ') {
            at += 1;
        }
        if at == bytes.len() || bytes[at] == b'\n' || count == columns {
            break;
        }
        let (value, length) = exact_decimal(&bytes[at..]).or_else(|| fast_float2::parse_partial::<f64, _>(&bytes[at..]).ok())?;
        at += length;
        let ends_at_space = bytes.get(at).is_none_or(|&b| BYTE_CLASSES[b as usize] == ByteClass::Space);
        if length > 64 || !value.is_finite() || !ends_at_space {
            return None;
        }
        values[count] = value;
        count += 1;
    }
    let line_end = at == bytes.len() || bytes[at] == b'\n';
    (count == columns && line_end).then_some((values, at))
}

/// The number at the start of `bytes` when it is a short decimal that one IEEE operation
/// reads exactly (Clinger's fast path, which the standard parser and fast-float2 take first
/// too): `[+-]digits[.digits][(e|E)[+-]digits]`, at most 19 digits whose integer m ≤ 2⁵³,
/// and a power of ten 10^e with |e| ≤ 22. m and 10^|e| are exact doubles, so m·10^e or
/// m/10^|e| is the correctly rounded value, the bits any correct parser gives. Returns the
/// value and the number's length; `None` for anything else (fast-float2 reads it then).
fn exact_decimal(bytes: &[u8]) -> Option<(f64, usize)> {
    const POWERS: [f64; 23] =
        [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22];
    let digit = |at: usize| bytes.get(at).filter(|b| b.is_ascii_digit()).map(|b| u64::from(b - b'0'));
    let mut at = 0;
    let negative = sign(bytes, &mut at);
    let mut exponent: i64 = 0;
    let (whole, mut mantissa) = read_digits(bytes, at, 0);
    at += whole;
    let mut digits = whole;
    if bytes.get(at) == Some(&b'.') {
        at += 1;
        let (fraction, with_fraction) = read_digits(bytes, at, mantissa);
        mantissa = with_fraction;
        digits += fraction;
        exponent -= fraction as i64;
        at += fraction;
    }
    if digits == 0 || digits > 19 || mantissa > 1 << 53 {
        return None;
    }
    if matches!(bytes.get(at), Some(b'e' | b'E')) {
        at += 1;
        let negative_exponent = sign(bytes, &mut at);
        let start = at;
        let mut written: i64 = 0;
        while let Some(d) = digit(at) {
            written = (10 * written + d as i64).min(1 << 20);
            at += 1;
        }
        if at == start {
            return None;
        }
        exponent += if negative_exponent { -written } else { written };
    }
    let power = *POWERS.get(exponent.unsigned_abs() as usize)?;
    let magnitude = if exponent >= 0 { mantissa as f64 * power } else { mantissa as f64 / power };
    Some((if negative { -magnitude } else { magnitude }, at))
}

/// An optional sign at byte `at`, stepped over: whether it is `-`.
#[inline(always)]
fn sign(bytes: &[u8], at: &mut usize) -> bool {
    match bytes.get(*at) {
        Some(&sign @ (b'-' | b'+')) => {
            *at += 1;
            sign == b'-'
        }
        _ => false,
    }
}

/// The run of ASCII digits at byte `at` of `bytes` appended to `mantissa` (×10 plus the
/// digit, wrapping, for each digit): the run's length and the new mantissa. Eight bytes are
/// looked at at once while eight remain (Lemire's SWAR digit test and combination, as in
/// fast_float), so a table number's few digits take one step instead of one per digit.
#[inline(always)]
fn read_digits(bytes: &[u8], at: usize, mut mantissa: u64) -> (usize, u64) {
    const ONES: u64 = 0x0101_0101_0101_0101;
    let mut length = 0;
    while let Some(chunk) = bytes.get(at + length..at + length + 8) {
        let word = u64::from_le_bytes(chunk.try_into().expect("eight bytes"));
        // The high bit of each byte set where the byte is not '0'..='9'. A byte below '0'
        // borrows from, and one above '9' may carry into, only the bytes after it, which
        // follow the first non-digit and are not read.
        let values = word.wrapping_sub(0x30 * ONES);
        let not_digit = (values | word.wrapping_add(0x46 * ONES)) & (0x80 * ONES);
        let run = (not_digit.trailing_zeros() / 8) as usize;
        if run == 0 {
            return (length, mantissa);
        }
        // The run's digit values as the last `run` bytes of eight, zeros before them (the
        // first byte is the most significant digit), combined into their integer.
        let aligned = values << (8 * (8 - run));
        let pairs = aligned.wrapping_mul(10).wrapping_add(aligned >> 8);
        let mask = 0x0000_00FF_0000_00FF;
        let number = ((pairs & mask).wrapping_mul(0x000F_4240_0000_0064))
            .wrapping_add(((pairs >> 16) & mask).wrapping_mul(0x0000_2710_0000_0001))
            >> 32;
        mantissa = mantissa.wrapping_mul(POWERS_OF_TEN[run]).wrapping_add(number);
        length += run;
        if run < 8 {
            return (length, mantissa);
        }
    }
    while let Some(&b) = bytes.get(at + length).filter(|b| b.is_ascii_digit()) {
        mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
        length += 1;
    }
    (length, mantissa)
}

/// How many bytes from `at` on are spaces (b' '), counted eight at a time while eight bytes
/// remain and a byte at a time after.
#[inline(always)]
fn leading_spaces(bytes: &[u8], at: usize) -> usize {
    const ONES: u64 = 0x0101_0101_0101_0101;
    let mut length = 0;
    while let Some(chunk) = bytes.get(at + length..at + length + 8) {
        // Zero bytes where there are spaces; the high bit of each byte set where there is
        // not (per byte, no carries between bytes).
        let other = u64::from_le_bytes(chunk.try_into().expect("eight bytes")) ^ (b' ' as u64 * ONES);
        let not_space = ((other & (0x7F * ONES)).wrapping_add(0x7F * ONES) | other) & (0x80 * ONES);
        let run = (not_space.trailing_zeros() / 8) as usize;
        length += run;
        if run < 8 {
            return length;
        }
    }
    length + bytes[(at + length).min(bytes.len())..].iter().take_while(|&&b| b == b' ').count()
}

/// 10^i for i = 0..=8.
const POWERS_OF_TEN: [u64; 9] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000, 10_000_000, 100_000_000];

/// The numbers of one row by the general rule (fields split as `split_whitespace` splits
/// them, read as `f64`'s `FromStr` reads them): `None` for a blank line, the named error
/// for a row that does not hold `columns` finite numbers.
fn general_row(file: &str, line: &str, columns: usize, line_no: Option<usize>) -> Result<Option<[f64; 3]>, DataError> {
    // At most three fields are kept; the count says whether the row has `columns`.
    let mut fields = [Field::default(); 3];
    let count = split_fields(line, &mut fields);
    if count == 0 {
        return Ok(None);
    }
    if count != columns {
        return Err(DataError::new(Reason::BadRow, file, line_no, format!("expected {columns} numbers, found {count}: {:?}", line.trim())));
    }
    let mut values = [0.0; 3];
    for (slot, field) in values.iter_mut().zip(&fields[..columns]) {
        match parse_field(*field) {
            Some(x) if x.is_finite() => *slot = x,
            _ => return Err(DataError::new(Reason::BadRow, file, line_no, format!("not a finite number: {:?}", field.text))),
        }
    }
    Ok(Some(values))
}

/// Parse rows of `columns` numbers each, wavelength first and positive. Lines as
/// [`str::lines`] cuts them; each row read by [`plain_row`], else by [`general_row`].
fn parse_rows(file: &str, block: &str, columns: usize, first_line: Option<usize>) -> Result<Vec<Row>, DataError> {
    let bytes = block.as_bytes();
    // One row per line at most, and a row takes at least 4 bytes ("1 2" and its line end):
    // counting the line ends is cheaper than growing the list.
    let lines = memchr::memchr_iter(b'\n', bytes).count() + 1;
    let mut rows: Vec<Row> = Vec::with_capacity(lines.min(bytes.len() / 4 + 1));
    let mut at = 0;
    let mut i = 0;
    while at < bytes.len() {
        let line_no = first_line.map(|l| l + i);
        i += 1;
        let (values, end) = match plain_row(bytes, at, columns) {
            Some(row) => row,
            None => {
                let (line, end) = str_lines_line(block, at);
                match general_row(file, line, columns, line_no)? {
                    Some(values) => (values, end),
                    None => {
                        at = end + 1;
                        continue;
                    }
                }
            }
        };
        at = end + 1;
        if values[0] <= 0.0 {
            return Err(DataError::new(
                Reason::BadRow,
                file,
                line_no,
                format!("wavelength {} µm is not positive", super::error::number_text(values[0])),
            ));
        }
        if !wavelength_in_domain(values[0]) {
            return Err(DataError::new(
                Reason::WavelengthOutOfRange,
                file,
                line_no,
                format!("wavelength {:e} µm is outside {:e}–{:e} µm", values[0], WAVELENGTH_DOMAIN_UM.0, WAVELENGTH_DOMAIN_UM.1),
            ));
        }
        rows.push(Row { values, line: line_no });
    }
    if rows.is_empty() {
        return Err(DataError::new(Reason::NoData, file, first_line, "tabulated block has no rows"));
    }
    Ok(rows)
}

/// A break in the wavelength order: row `at` does not come after row `at - 1`.
fn order_defect(file: &str, rows: &[Row], at: usize) -> DataError {
    DataError::new(
        Reason::NonMonotonicWavelengths,
        file,
        rows[at].line,
        format!("wavelength {} µm follows {} µm", rows[at].values[0], rows[at - 1].values[0]),
    )
}

/// Does the run of rows `[start, end)` reach into the evaluated window?
fn run_reaches_window(rows: &[Row], start: usize, end: usize) -> bool {
    let (lo, hi) = (EVALUATED_NM.0 / 1000.0, EVALUATED_NM.1 / 1000.0);
    rows[start].values[0] <= hi && rows[end - 1].values[0] >= lo
}

/// The rows a curve is built from: the one run of strictly increasing wavelengths that
/// reaches into the evaluated window, with each order defect outside it as a warning. Two
/// runs reaching into the window, or none while the table has defects, exclude the page
/// (`non-monotonic-wavelengths` at the first defect).
fn increasing_run(file: &str, rows: Vec<Row>, warnings: &mut Vec<DataError>) -> Result<Vec<Row>, DataError> {
    let breaks: Vec<usize> = (1..rows.len()).filter(|&i| rows[i].values[0] <= rows[i - 1].values[0]).collect();
    if breaks.is_empty() {
        return Ok(rows);
    }
    let bounds: Vec<usize> = std::iter::once(0).chain(breaks.iter().copied()).chain(std::iter::once(rows.len())).collect();
    let reaching: Vec<(usize, usize)> = bounds.windows(2).map(|w| (w[0], w[1])).filter(|&(a, b)| run_reaches_window(&rows, a, b)).collect();
    let &[(start, end)] = reaching.as_slice() else {
        return Err(order_defect(file, &rows, breaks[0]));
    };
    warnings.extend(breaks.iter().map(|&at| {
        let mut warning = order_defect(file, &rows, at);
        warning.detail.push_str(&format!(
            "; outside the evaluated {}-{} nm, the curve uses rows {}-{} of the block",
            EVALUATED_NM.0,
            EVALUATED_NM.1,
            start + 1,
            end
        ));
        warning
    }));
    Ok(rows.into_iter().skip(start).take(end - start).collect())
}

/// Rows the evaluated window reads: those inside it and the neighbour on each side
/// (linear interpolation reaches them).
fn rows_read(rows: &[Row]) -> &[Row] {
    let (lo, hi) = (EVALUATED_NM.0 / 1000.0, EVALUATED_NM.1 / 1000.0);
    let first = rows.partition_point(|r| r.values[0] < lo).saturating_sub(1);
    let last = rows.partition_point(|r| r.values[0] <= hi).min(rows.len() - 1);
    &rows[first..=last]
}

/// What a tabulated column holds.
#[derive(Clone, Copy)]
enum Quantity {
    N,
    K,
}

/// Values of `quantity` in column `i` that the evaluated window reads must lie in the
/// methods' domain (`index-out-of-domain`, at the row's line). n ≤ 0 and k < 0 are left
/// to the `negative-n` / `negative-k` checks where the values are evaluated.
fn check_domain(file: &str, rows: &[Row], i: usize, quantity: Quantity) -> Result<(), DataError> {
    for row in rows_read(rows) {
        let value = row.values[i];
        let (name, outside) = match quantity {
            Quantity::N => ("n", value > N_DOMAIN.1 || (value > 0.0 && value < N_DOMAIN.0)),
            Quantity::K => ("k", value > K_MAX),
        };
        if outside {
            return Err(DataError::new(
                Reason::IndexOutOfDomain,
                file,
                row.line,
                format!(
                    "{name} = {value:e} at {} µm; the methods are tested on n in [{:e}, {:e}], k in [0, {K_MAX:e}]",
                    row.values[0], N_DOMAIN.0, N_DOMAIN.1
                ),
            ));
        }
    }
    Ok(())
}

fn column(rows: &[Row], i: usize) -> Vec<f64> {
    rows.iter().map(|r| r.values[i]).collect()
}

/// How the coefficients of a formula group into terms: `C1` alone, then pairs (a weight
/// and its pole or exponent) from `C(first_pair)` on. `None` for formulas whose every
/// coefficient is a term of its own (7, 8, 9).
fn pair_terms_from(number: u8) -> Option<usize> {
    match number {
        1 | 2 | 3 | 5 | 6 => Some(2),
        // Formula 4: C2..C5 and C6..C9 are two four-coefficient terms, pairs from C10.
        4 => Some(10),
        _ => None,
    }
}

/// Coefficients that end inside a term: formula 1 with `C1 B1 C1' B2` lacks B2's pole.
fn incomplete_term(number: u8, count: usize) -> Option<String> {
    let first_pair = pair_terms_from(number)?;
    if count < first_pair {
        // Formula 4: C1 | C2 C3 C4 C5 | C6 C7 C8 C9, complete after 1, 5 or 9 coefficients.
        return (number == 4 && ![1, 5, 9].contains(&count)).then(|| {
            format!("formula 4 has {count} coefficients; its terms end after C1, C5 or C9 (a weight without its exponent or pole)")
        });
    }
    (count - first_pair).is_multiple_of(2).then(|| {
        format!(
            "formula {number} has {count} coefficients, which ends in half a term: C{count} has no partner C{} (its pole or exponent)",
            count + 1
        )
    })
}

fn parse_formula(file: &str, number: u8, block: &RawBlock) -> Result<Formula, DataError> {
    let text = block.coefficients.as_ref().and_then(scalar_text).unwrap_or_default();
    let mut coefficients = Vec::new();
    for field in text.split_whitespace() {
        match field.parse::<f64>() {
            Ok(x) if x.is_finite() => coefficients.push(x),
            _ => {
                return Err(DataError::new(
                    Reason::ParseError,
                    file,
                    None,
                    format!("formula {number}: coefficient {field:?} is not a number"),
                ))
            }
        }
    }
    if coefficients.is_empty() {
        return Err(DataError::new(Reason::TooFewCoefficients, file, None, format!("formula {number} has no coefficients")));
    }
    if let Some(detail) = incomplete_term(number, coefficients.len()) {
        return Err(DataError::new(Reason::IncompleteTerm, file, None, detail));
    }
    if coefficients.len() > max_coefficients(number) {
        return Err(DataError::new(
            Reason::TooManyCoefficients,
            file,
            None,
            format!("formula {number} takes at most {} coefficients, found {}", max_coefficients(number), coefficients.len()),
        ));
    }
    let range_text = block.wavelength_range.as_ref().and_then(scalar_text).unwrap_or_default();
    let range: Vec<f64> = range_text.split_whitespace().map(|f| f.parse().ok()).collect::<Option<_>>().unwrap_or_default();
    if range.len() != 2 || !(range[0] > 0.0 && range[1] > range[0] && range[1].is_finite()) {
        return Err(DataError::new(
            Reason::TooFewCoefficients,
            file,
            None,
            format!("formula {number}: wavelength_range {range_text:?} is not two increasing positive finite numbers"),
        ));
    }
    if !(wavelength_in_domain(range[0]) && wavelength_in_domain(range[1])) {
        return Err(DataError::new(
            Reason::WavelengthOutOfRange,
            file,
            None,
            format!(
                "formula {number}: wavelength_range {:e}–{:e} µm leaves {:e}–{:e} µm",
                range[0], range[1], WAVELENGTH_DOMAIN_UM.0, WAVELENGTH_DOMAIN_UM.1
            ),
        ));
    }
    Ok(Formula { number, coefficients, range_um: (range[0], range[1]) })
}

/// Parse one data file's text. `file` is its path relative to `database/data/`, used in
/// errors. Never panics on any input (a property test feeds it arbitrary text).
pub fn parse_page(file: &str, text: &str) -> Result<PageData, DataError> {
    match parse_cut(file, text, CutTables::cut(text)) {
        Ok(page) => page,
        // A `data: |` outside every DATA block: the whole text to the parser. Without cut
        // tables none is unclaimed.
        Err(Unclaimed) => parse_cut(file, text, None).unwrap_or_else(|Unclaimed| {
            Err(DataError::new(Reason::ParseError, file, None, "a table of the file could not be matched to its DATA block"))
        }),
    }
}

/// A table the line scan cut out that no DATA block's `data` names.
struct Unclaimed;

/// [`parse_page`] with the tables `cut` took out of the text (`None`: the parser reads it
/// whole). `Err(Unclaimed)` when a cut table belongs to no DATA block.
fn parse_cut(file: &str, original: &str, cut: Option<CutTables>) -> Result<Result<PageData, DataError>, Unclaimed> {
    // The text without its tables has the same keys: the line scans below read it.
    let text = cut.as_ref().map_or(original, |c| c.compact.as_str());
    let yaml_error = |e: serde_norway::Error| DataError::new(Reason::ParseError, file, e.location().map(|l| l.line()), e.to_string());
    let too_deep = |text: &str| {
        super::block_yaml::too_deep(text).map(|deep| {
            let line = cut.as_ref().map_or(deep.line, |c| c.file_line(deep.line));
            DataError::new(Reason::NestingTooDeep, file, Some(line), deep.to_string())
        })
    };
    // An error is taken from the text with the tables blanked: its line is the file's.
    let raw: RawPage = match (super::block_yaml::from_str(text), &cut) {
        (Ok(raw), _) => raw,
        (Err(e), cut) => {
            if let Some(deep) = too_deep(text) {
                return Ok(Err(deep));
            }
            match cut {
                Some(cut) => match serde_norway::from_str(&cut.blanked()) {
                    Ok(raw) => raw,
                    Err(e) => return Ok(Err(yaml_error(e))),
                },
                None => return Ok(Err(yaml_error(e))),
            }
        }
    };
    let Some(blocks) = raw.data else {
        return Ok(Err(DataError::new(Reason::NoData, file, None, "no DATA section")));
    };
    // Every cut table must be the `data` of one DATA block.
    if let Some(cut) = &cut {
        let mut claimed = vec![false; cut.tables.len()];
        for number in blocks.iter().filter_map(|b| b.data.as_ref().and_then(CutTables::marked)) {
            match claimed.get_mut(number) {
                Some(slot) if !*slot => *slot = true,
                _ => return Err(Unclaimed),
            }
        }
        let empty = |i: usize| cut.blank[i].start >= cut.blank[i].end;
        if (0..claimed.len()).any(|i| !claimed[i] && !empty(i)) {
            return Err(Unclaimed);
        }
    }
    Ok(page_of_blocks(file, text, &cut, raw.references, raw.properties, &blocks))
}

/// The curves and metadata of a parsed page: its DATA `blocks` (tables named by markers
/// taken from `cut`), its REFERENCES and PROPERTIES; `text` is what the parser read.
fn page_of_blocks(
    file: &str,
    text: &str,
    cut: &Option<CutTables>,
    references: Option<serde_norway::Value>,
    properties: Option<serde_norway::Value>,
    blocks: &[RawBlock],
) -> Result<PageData, DataError> {
    let keys = TextKeys::scan(text);
    let mut data_lines = keys.data_lines;
    if let Some(cut) = cut {
        data_lines.iter_mut().for_each(|line| *line = cut.file_line(*line));
    }
    let mut data_block_index = 0;
    let mut n: Option<Curve> = None;
    let mut k: Option<Curve> = None;
    let mut warnings = Vec::new();
    let set = |slot: &mut Option<Curve>, curve: Curve, what: &str| -> Result<(), DataError> {
        if slot.is_some() {
            return Err(DataError::new(Reason::ParseError, file, None, format!("more than one {what} block")));
        }
        *slot = Some(curve);
        Ok(())
    };
    for block in blocks {
        let kind = block.kind.trim();
        if let Some(columns) = match kind {
            "tabulated nk" => Some(3),
            "tabulated n" | "tabulated k" => Some(2),
            _ => None,
        } {
            let scanned_line = data_lines.get(data_block_index).map(|l| l + 1);
            data_block_index += 1;
            // A table cut out of the text: the parser says which, by its marker.
            let marked = cut.as_ref().zip(block.data.as_ref().and_then(CutTables::marked)).and_then(|(c, i)| c.tables.get(i));
            let (body, first_line) = match marked {
                Some(&(key_line, body)) => (std::borrow::Cow::Borrowed(body), Some(key_line + 1)),
                None => (
                    std::borrow::Cow::Owned(block.data.as_ref().and_then(scalar_text).ok_or_else(|| {
                        DataError::new(Reason::ParseError, file, scanned_line.map(|l| l - 1), format!("{kind} block has no data text"))
                    })?),
                    scanned_line,
                ),
            };
            let rows = increasing_run(file, parse_rows(file, &body, columns, first_line)?, &mut warnings)?;
            match kind {
                "tabulated nk" => {
                    check_domain(file, &rows, 1, Quantity::N)?;
                    check_domain(file, &rows, 2, Quantity::K)?;
                }
                "tabulated n" => check_domain(file, &rows, 1, Quantity::N)?,
                _ => check_domain(file, &rows, 1, Quantity::K)?,
            }
            let wavelengths_um = column(&rows, 0);
            // The wavelengths are copied only for a table that gives both n and k.
            let tabulated = |wavelengths_um, i| Curve::Tabulated { wavelengths_um, values: column(&rows, i) };
            match kind {
                // A formula n followed by tabulated nk (e.g. organic/PVP/Konig): the
                // formula stays the n source and the table supplies k, as on the site.
                "tabulated nk" if matches!(n, Some(Curve::Formula(_))) => set(&mut k, tabulated(wavelengths_um, 2), "k")?,
                "tabulated nk" => {
                    set(&mut n, tabulated(wavelengths_um.clone(), 1), "n")?;
                    set(&mut k, tabulated(wavelengths_um, 2), "k")?;
                }
                "tabulated n" => set(&mut n, tabulated(wavelengths_um, 1), "n")?,
                _ => set(&mut k, tabulated(wavelengths_um, 1), "k")?,
            }
        } else if let Some(number) = kind.strip_prefix("formula ").and_then(|d| d.trim().parse::<u8>().ok()).filter(|d| (1..=9).contains(d))
        {
            if block.data.is_some() {
                data_block_index += 1;
            }
            set(&mut n, Curve::Formula(parse_formula(file, number, block)?), "n")?;
        } else {
            return Err(DataError::new(Reason::UnknownBlockType, file, None, format!("block type {kind:?}")));
        }
    }
    let n = n.ok_or_else(|| DataError::new(Reason::NoData, file, None, "no n data (only k)"))?;
    let reference =
        references.as_ref().and_then(scalar_text).and_then(|r| r.lines().map(strip_html).find(|l| !l.is_empty())).unwrap_or_default();
    let property = |key: &str| properties.as_ref().and_then(|p| p.get(key));
    Ok(PageData {
        file: file.to_string(),
        n,
        k,
        reference,
        nd: confirmed(keys.nd, property("nd")),
        vd: confirmed(keys.vd, property("Vd")),
        warnings,
    })
}

/// A property as the line scan printed it, where the parser read the same number there;
/// else the parser's number, its decimals those of its shortest form (a scan fooled by
/// the text's layout never decides a value).
fn confirmed(scanned: Option<Printed>, parsed: Option<&serde_norway::Value>) -> Option<Printed> {
    let value = match parsed? {
        serde_norway::Value::Number(number) => number.as_f64(),
        serde_norway::Value::String(text) => text.trim().parse().ok(),
        _ => None,
    }
    .filter(|v: &f64| v.is_finite())?;
    match scanned {
        Some(printed) if printed.value.to_bits() == value.to_bits() => Some(printed),
        _ => printed_value(&value.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NK: &str = "REFERENCES: |\n    <b>Someone</b> 2020.\n    second line\nDATA:\n  - type: tabulated nk\n    data: |\n        0.4 1.0 2.0\n        0.5 2.0 4.0\n        0.7 3.0 1.0\n";

    #[test]
    fn tabulated_nk_interpolates_linearly() {
        let page = parse_page("x.yml", NK).unwrap();
        assert_eq!(page.reference, "Someone 2020.");
        assert_eq!(page.n.at(0.45), Some(1.5));
        let k = page.k.as_ref().unwrap();
        assert!((k.at(0.6).unwrap() - 2.5).abs() < 1e-15);
        assert_eq!(page.n.at(0.39), None);
        assert_eq!(page.n.at_held(0.39), 1.0);
        assert_eq!(page.n.at_held(0.9), 3.0);
    }

    #[test]
    fn formula_with_tabulated_k_and_properties() {
        let text = "DATA:\n  - type: formula 2\n    wavelength_range: 0.3 2.5\n    coefficients: 0 1.0 0.01\n  - type: tabulated k\n    data: |\n        0.3 1e-8\n        2.5 2e-8\nPROPERTIES:\n    nd: 1.523\n    Vd: 58.5\n";
        let page = parse_page("g.yml", text).unwrap();
        let n = page.n.at(0.5).unwrap();
        assert!((n - (1.0f64 + 0.25 / 0.24).sqrt()).abs() < 1e-15);
        assert_eq!(page.nd, Some(Printed { value: 1.523, decimals: 3 }));
        assert_eq!(page.vd, Some(Printed { value: 58.5, decimals: 1 }));
    }

    fn reason(text: &str) -> (Reason, Option<usize>) {
        let e = parse_page("bad.yml", text).unwrap_err();
        (e.reason, e.line)
    }

    #[test]
    fn bad_inputs_get_named_errors_with_lines() {
        assert_eq!(reason("DATA: [unclosed").0, Reason::ParseError);
        assert_eq!(reason("DATA:\n  - type: tabulated xyz\n").0, Reason::UnknownBlockType);
        // Row 2 of the block is on line 4.
        assert_eq!(reason("DATA:\n  - type: tabulated n\n    data: |\n        0.4 1.5\n        0.5 abc\n"), (Reason::BadRow, Some(5)));
        assert_eq!(reason("DATA:\n  - type: tabulated nk\n    data: |\n        0.4 1.5\n"), (Reason::BadRow, Some(4)));
        assert_eq!(
            reason("DATA:\n  - type: tabulated n\n    data: |\n        0.5 1.5\n        0.5 1.6\n"),
            (Reason::NonMonotonicWavelengths, Some(5))
        );
        assert_eq!(reason("DATA:\n  - type: formula 1\n    wavelength_range: 0.3 2\n    coefficients: \n").0, Reason::TooFewCoefficients);
        assert_eq!(
            reason("DATA:\n  - type: formula 8\n    wavelength_range: 0.3 2\n    coefficients: 1 2 3 4 5\n").0,
            Reason::TooManyCoefficients
        );
        assert_eq!(reason("DATA:\n  - type: tabulated k\n    data: |\n        0.4 1.5\n").0, Reason::NoData);
        assert_eq!(reason("REFERENCES: x\n").0, Reason::NoData);
        // Sellmeier C1 B1 C1' B2: B2 has no pole.
        assert_eq!(
            reason("DATA:\n  - type: formula 1\n    wavelength_range: 0.3 2\n    coefficients: 0 1.0 0.1 0.5\n").0,
            Reason::IncompleteTerm
        );
        assert_eq!(reason("DATA:\n  - type: formula 4\n    wavelength_range: 0.3 2\n    coefficients: 1 2 3\n").0, Reason::IncompleteTerm);
        assert_eq!(
            reason("DATA:\n  - type: formula 4\n    wavelength_range: 0.3 2\n    coefficients: 1 2 3 4 5 6 7 8 9 10\n").0,
            Reason::IncompleteTerm
        );
        assert!(parse_page("ok.yml", "DATA:\n  - type: formula 4\n    wavelength_range: 0.3 2\n    coefficients: 1 2 3 4 5\n").is_ok());
        assert!(parse_page("ok.yml", "DATA:\n  - type: formula 7\n    wavelength_range: 0.3 2\n    coefficients: 1 2\n").is_ok());
    }

    /// The cut tables hold the same numbers as the YAML parser's block text, the text left
    /// for the parser keeps every line, and layouts a line scan cannot follow fall back.
    #[test]
    fn tables_cut_out_of_the_text_match_the_yaml_blocks() {
        let text = "REFERENCES: x\r\nDATA:\r\n  - type: tabulated n\r\n    data: |\r\n        0.4 1.0\r\n\r\n        0.5 2.0\r\n  - type: tabulated k\r\n    data: |-\r\n        0.4 0.1\r\n        0.5 0.2\r\nPROPERTIES:\r\n    nd: 1.5\r\n";
        let cut = CutTables::cut(text).unwrap();
        assert_eq!(cut.blanked().lines().count(), text.lines().count());
        // Three table lines removed (two of the first table, one of the second); the keys
        // and the lines after each table are numbered as in the file.
        assert_eq!(cut.compact.lines().count(), text.lines().count() - 3);
        assert_eq!([4, 5, 6, 7, 8, 10].map(|line| cut.file_line(line)), [4, 7, 8, 9, 11, 13]);
        let raw: RawPage = serde_norway::from_str(text).unwrap();
        let words = |t: &str| t.split_whitespace().map(String::from).collect::<Vec<_>>();
        let blocks = raw.data.unwrap();
        assert_eq!((cut.tables[0].0, cut.tables[1].0), (4, 9));
        assert_eq!(words(cut.tables[0].1), words(&scalar_text(blocks[0].data.as_ref().unwrap()).unwrap()));
        assert_eq!(words(cut.tables[1].1), words(&scalar_text(blocks[1].data.as_ref().unwrap()).unwrap()));
        // The parser reads each table's place as its marker.
        let compact: RawPage = serde_norway::from_str(&cut.compact).unwrap();
        let marked: Vec<Option<usize>> = compact.data.unwrap().iter().map(|b| b.data.as_ref().and_then(CutTables::marked)).collect();
        assert_eq!(marked, [Some(0), Some(1)]);
        assert_eq!(parse_page("crlf.yml", text).unwrap().nd, Some(Printed { value: 1.5, decimals: 1 }));
        // A row indented less than the first one, or a tab, leaves the text to the parser.
        assert!(CutTables::cut("DATA:\n  - type: tabulated n\n    data: |\n        0.4 1.0\n      0.5 2.0\n").is_none());
        assert!(CutTables::cut("DATA:\n  - type: tabulated n\n    data: |\n        0.4 1.0\n      \t0.5 2.0\n").is_none());
        assert!(CutTables::cut("DATA:\n  - type: formula 1\n    coefficients: 1\n").is_none());
    }

    /// A `data: |` inside a comment's block, a quoted DATA table, and PROPERTIES the line
    /// scan could misread: the parser decides, the cut tables only stand in for what it
    /// places in a DATA block.
    #[test]
    fn only_the_data_blocks_tables_are_read() {
        let comment = "COMMENTS: |\n    data: |\n        0.30 9.9\n        0.80 9.9\nDATA:\n  - type: tabulated n\n    data: |\n        0.30 1.5\n        0.80 1.5\n";
        assert_eq!(parse_page("c.yml", comment).unwrap().n.at(0.5), Some(1.5));
        // A table in the comment and a quoted one in DATA: the quoted one.
        let quoted = "COMMENTS: |\n    data: |\n        0.30 9.9\n        0.80 9.9\nDATA:\n  - type: tabulated n\n    data: \"0.30 1.5\\n0.80 1.5\"\n";
        assert_eq!(parse_page("q.yml", quoted).unwrap().n.at(0.5), Some(1.5));
        // The reference keeps its own text, not a marker.
        let reference = "REFERENCES: |\n    data: |\n      Someone 2020\nDATA:\n  - type: tabulated n\n    data: |\n        0.30 1.5\n        0.80 1.5\n";
        assert_eq!(parse_page("r.yml", reference).unwrap().reference, "data: |");
        // A file holding the marker text itself goes to the parser whole.
        let marker =
            format!("COMMENTS: \"{TABLE_MARKER}0\"\nDATA:\n  - type: tabulated n\n    data: |\n        0.30 1.5\n        0.80 1.5\n");
        assert!(CutTables::cut(&marker).is_none());
        assert_eq!(parse_page("m.yml", &marker).unwrap().n.at(0.5), Some(1.5));
        // Printed properties are the parser's numbers, with the decimals as printed.
        let properties = "DATA:\n  - type: formula 2\n    wavelength_range: 0.3 2.5\n    coefficients: 0 1.0 0.01\nPROPERTIES:\n    nd: 1.5230\n    Vd: 58.50 # comment\n";
        let page = parse_page("p.yml", properties).unwrap();
        assert_eq!(page.nd, Some(Printed { value: 1.523, decimals: 4 }));
        assert_eq!(page.vd, Some(Printed { value: 58.5, decimals: 1 }));
        // Nesting past the bound is named, at the file's line.
        let deep = format!(
            "DATA:\n  - type: tabulated n\n    data: |\n        0.30 1.5\n        0.80 1.5\nX: {}1{}\n",
            "[".repeat(100),
            "]".repeat(100)
        );
        let e = parse_page("d.yml", &deep).unwrap_err();
        assert_eq!((e.reason, e.line), (Reason::NestingTooDeep, Some(6)));
    }

    #[test]
    fn order_defects_outside_the_evaluated_window_are_warnings() {
        // Rows 0.3-2.5 µm, then the wavelengths restart at 2.0 µm (line 8).
        let text = "DATA:\n  - type: tabulated nk\n    data: |\n        0.3 1.0 2.0\n        0.5 2.0 4.0\n        1.0 3.0 1.0\n        2.5 3.0 1.0\n        2.0 3.1 1.1\n        3.0 3.2 1.2\n";
        let page = parse_page("w.yml", text).unwrap();
        assert_eq!(page.n.range_um(), (0.3, 2.5));
        assert_eq!(page.warnings.len(), 1);
        assert_eq!((page.warnings[0].reason, page.warnings[0].line), (Reason::NonMonotonicWavelengths, Some(8)));
        // The same break inside the window excludes the page at its line.
        let inside = "DATA:\n  - type: tabulated n\n    data: |\n        0.4 1.5\n        0.6 1.6\n        0.5 1.7\n        0.9 1.8\n";
        assert_eq!(reason(inside), (Reason::NonMonotonicWavelengths, Some(6)));
        // A defect in an infrared-only table keeps today's exclusion.
        let infrared = "DATA:\n  - type: tabulated n\n    data: |\n        2.0 1.5\n        3.0 1.6\n        2.5 1.7\n";
        assert_eq!(reason(infrared), (Reason::NonMonotonicWavelengths, Some(6)));
    }

    #[test]
    fn values_outside_the_methods_domain_are_named_with_their_line() {
        let huge = "DATA:\n  - type: tabulated nk\n    data: |\n        0.3 1.0 2.0\n        0.5 1e300 4.0\n        0.9 3.0 1.0\n";
        assert_eq!(reason(huge), (Reason::IndexOutOfDomain, Some(5)));
        let big_k = "DATA:\n  - type: tabulated k\n    data: |\n        0.3 2.0\n        0.5 5e3\n  - type: formula 5\n    wavelength_range: 0.3 1.0\n    coefficients: 1.5\n";
        assert_eq!(reason(big_k).0, Reason::IndexOutOfDomain);
        // Far-infrared rows beyond the window's neighbours are not read, so not judged.
        let far =
            "DATA:\n  - type: tabulated nk\n    data: |\n        0.3 1.0 2.0\n        0.9 3.0 1.0\n        50 20 2e3\n        90 30 4e3\n";
        assert!(parse_page("far.yml", far).is_ok());
    }

    /// The line scans as they were written first, on `str` methods: the reference the
    /// byte-level scans must agree with.
    mod reference {
        use super::super::Printed;

        pub fn data_key_lines(text: &str) -> Vec<usize> {
            text.lines()
                .enumerate()
                .filter(|(_, line)| {
                    let t = line.trim_start();
                    t.starts_with("data:") && line.len() - t.len() >= 2
                })
                .map(|(i, _)| i + 1)
                .collect()
        }

        pub fn printed_property(text: &str, key: &str) -> Option<Printed> {
            let mut in_properties = false;
            for line in text.lines() {
                if !line.starts_with(' ') && !line.is_empty() {
                    in_properties = line.starts_with("PROPERTIES:");
                    continue;
                }
                let trimmed = line.trim_start();
                if in_properties && trimmed.starts_with(key) && trimmed[key.len()..].starts_with(':') {
                    let raw = trimmed[key.len() + 1..].trim();
                    let value: f64 = raw.parse().ok()?;
                    let decimals = raw.split_once('.').map(|(_, d)| d.chars().take_while(|c| c.is_ascii_digit()).count()).unwrap_or(0);
                    return Some(Printed { value, decimals });
                }
            }
            None
        }

        /// A row's values as bits, and its line.
        type RowBits = ([u64; 3], Option<usize>);

        /// Rows read by `lines`, `split_whitespace` and `str::parse`: (values, line) per row,
        /// or the error's reason, line and detail.
        pub fn parse_rows(file: &str, block: &str, columns: usize, first_line: Option<usize>) -> Result<Vec<RowBits>, String> {
            let mut rows = Vec::new();
            for (i, line) in block.lines().enumerate() {
                let line_no = first_line.map(|l| l + i);
                let fields: Vec<&str> = line.split_whitespace().collect();
                if fields.is_empty() {
                    continue;
                }
                if fields.len() != columns {
                    return Err(format!("bad-row {line_no:?} expected {columns} numbers, found {}: {:?}", fields.len(), line.trim()));
                }
                let mut values = [0.0f64; 3];
                for (slot, field) in values.iter_mut().zip(&fields) {
                    match field.parse::<f64>() {
                        Ok(x) if x.is_finite() => *slot = x,
                        _ => return Err(format!("bad-row {line_no:?} not a finite number: {field:?}")),
                    }
                }
                if values[0] <= 0.0 {
                    let x = values[0];
                    let shown = if x == 0.0 || (1e-6..1e16).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") };
                    return Err(format!("bad-row {line_no:?} wavelength {shown} µm is not positive"));
                }
                if !(1e-9..=1e8).contains(&values[0]) {
                    return Err(format!("wavelength-out-of-range {line_no:?} wavelength {:e} µm is outside 1e-9–1e8 µm", values[0]));
                }
                rows.push((values.map(f64::to_bits), line_no));
            }
            if rows.is_empty() {
                return Err(format!("no-data {first_line:?} tabulated block has no rows"));
            }
            let _ = file;
            Ok(rows)
        }

        /// The table cut by `str` methods: the blanked text and (key line, body) pairs.
        pub fn cut(text: &str) -> Option<(String, Vec<(usize, &str)>)> {
            let mut lines: Vec<(usize, usize, &str)> = Vec::new();
            let mut at = 0;
            for (i, piece) in text.split_inclusive('\n').enumerate() {
                let line = piece.strip_suffix('\n').unwrap_or(piece);
                let line = line.strip_suffix('\r').unwrap_or(line);
                lines.push((i + 1, at, line));
                at += piece.len();
            }
            let mut tables = Vec::new();
            let mut blank = Vec::new();
            let mut i = 0;
            while i < lines.len() {
                let (number, start, line) = lines[i];
                i += 1;
                let trimmed = line.trim_start_matches(' ');
                let indent = line.len() - trimmed.len();
                let Some(value) = trimmed.strip_prefix("data:").map(str::trim) else { continue };
                if !(indent >= 2 && matches!(value, "|" | "|-" | "|+")) {
                    continue;
                }
                let after = start + line.len();
                let body_start = after
                    + if text[after..].starts_with("\r\n") {
                        2
                    } else if text[after..].starts_with('\n') {
                        1
                    } else {
                        0
                    };
                let mut body_end = body_start;
                let mut block_indent: Option<usize> = None;
                while i < lines.len() {
                    let (_, line_start, next) = lines[i];
                    let content = next.trim_start_matches(' ');
                    let spaces = next.len() - content.len();
                    if content.trim().is_empty() {
                        if content.starts_with('\t') {
                            return None;
                        }
                    } else if spaces <= indent {
                        break;
                    } else {
                        if content.starts_with('\t') {
                            return None;
                        }
                        match block_indent {
                            None => block_indent = Some(spaces),
                            Some(b) if spaces < b => return None,
                            Some(_) => {}
                        }
                    }
                    body_end = line_start + next.len();
                    i += 1;
                }
                tables.push((number, &text[body_start.min(body_end)..body_end]));
                blank.push((body_start, body_end));
            }
            if tables.is_empty() {
                return None;
            }
            let mut yaml = String::new();
            let mut at = 0;
            for (start, end) in blank {
                if start >= end {
                    continue;
                }
                yaml.push_str(&text[at..start]);
                yaml.extend(text[start..end].bytes().filter(|&b| b == b'\n').map(|_| '\n'));
                at = end;
            }
            yaml.push_str(&text[at..]);
            Some((yaml, tables))
        }
    }

    /// Lines of a data file's layout with the characters that make scanning hard: tabs,
    /// carriage returns, vertical tabs, Unicode spaces, numbers and words.
    fn layout_line() -> impl proptest::strategy::Strategy<Value = String> {
        use proptest::prelude::*;
        let piece = prop_oneof![
            Just(" ".to_string()),
            Just("    ".to_string()),
            Just("\t".to_string()),
            Just("\r".to_string()),
            Just("\u{b}".to_string()),
            Just("\u{a0}".to_string()),
            Just("\u{3000}".to_string()),
            Just("data: |".to_string()),
            Just("data: |-".to_string()),
            Just("data:".to_string()),
            Just("PROPERTIES:".to_string()),
            Just("nd: 1.52".to_string()),
            Just("Vd: x".to_string()),
            Just("- type: tabulated n".to_string()),
            "[0-9.eE+-]{1,8}",
            "[a-zé]{1,3}",
        ];
        proptest::collection::vec(piece, 0..6).prop_map(|pieces| pieces.concat())
    }

    /// Pages of tabulated blocks in the database's layout with the variations a table
    /// may have: chomping, blank and deeper-indented rows, CRLF, a missing last line end,
    /// keys after the tables.
    fn page_text() -> impl proptest::strategy::Strategy<Value = String> {
        use proptest::prelude::*;
        let row = prop_oneof![6 => Just("        0.5 1.5 0.1"), 1 => Just(""), 1 => Just("          0.6 1.6"), 1 => Just("        x")];
        let table = (
            prop_oneof![Just("|"), Just("|-"), Just("|+")],
            proptest::collection::vec(row, 0..6),
            prop_oneof![Just("tabulated nk"), Just("tabulated n"), Just("tabulated k")],
        );
        let after = prop_oneof![Just(""), Just("COMMENTS: \"c\""), Just("PROPERTIES:\n    nd: 1.5\n    Vd: 60"), Just("  - bad: [")];
        (proptest::collection::vec(table, 0..4), after, prop_oneof![Just("\n"), Just("\r\n")], any::<bool>()).prop_map(
            |(tables, after, end, last_end)| {
                let mut lines = vec!["REFERENCES: \"r\"".to_string(), "DATA:".to_string()];
                for (chomp, rows, kind) in tables {
                    lines.push(format!("  - type: {kind}"));
                    lines.push(format!("    data: {chomp}"));
                    lines.extend(rows.into_iter().map(String::from));
                }
                lines.extend(after.lines().map(String::from));
                lines.join(end) + if last_end { end } else { "" }
            },
        )
    }

    /// A parsed YAML value with every string of line ends only, and every table marker,
    /// emptied: a table's block reads as its marker in the compact text and as empty in
    /// the blanked one, where with keep chomping (`|+`) it keeps as many line ends as each
    /// has, which nothing reads.
    fn line_ends_emptied(value: serde_norway::Value) -> serde_norway::Value {
        use serde_norway::Value;
        match value {
            Value::String(s) if s.chars().all(|c| c == '\n') || s.trim().starts_with(TABLE_MARKER) => Value::String(String::new()),
            Value::Sequence(items) => Value::Sequence(items.into_iter().map(line_ends_emptied).collect()),
            Value::Mapping(map) => Value::Mapping(map.into_iter().map(|(k, v)| (k, line_ends_emptied(v))).collect()),
            other => other,
        }
    }

    /// Whether a marker sits inside a longer string of the parsed value: a "table" the line
    /// scan cut out of another block's text (`data: |` inside a block scalar), which no DATA
    /// block can claim, so [`parse_page`] reads the whole text instead (`Unclaimed`).
    fn marker_inside_text(value: &serde_norway::Value) -> bool {
        use serde_norway::Value;
        match value {
            Value::String(s) => s.contains(TABLE_MARKER) && !s.trim().starts_with(TABLE_MARKER),
            Value::Sequence(items) => items.iter().any(marker_inside_text),
            Value::Mapping(map) => map.iter().any(|(k, v)| marker_inside_text(k) || marker_inside_text(v)),
            _ => false,
        }
    }

    /// The compact text parses as the blanked one, or fails where it fails, and the keys
    /// found in it are on the file's lines — wherever each cut table is a string of its own
    /// (elsewhere the reader does not use the cut: [`marker_inside_text`]).
    fn compact_is_blanked(text: &str) -> Result<(), proptest::test_runner::TestCaseError> {
        if let Some(cut) = CutTables::cut(text) {
            if serde_norway::from_str::<serde_norway::Value>(&cut.compact).is_ok_and(|v| marker_inside_text(&v)) {
                return Ok(());
            }
            let blanked = cut.blanked();
            let value = |t: &str| serde_norway::from_str::<serde_norway::Value>(t).ok().map(line_ends_emptied);
            proptest::prop_assert_eq!(value(&cut.compact), value(&blanked), "{:?}", text);
            let lines: Vec<usize> = TextKeys::scan(&cut.compact).data_lines.iter().map(|&line| cut.file_line(line)).collect();
            proptest::prop_assert_eq!(lines, TextKeys::scan(&blanked).data_lines, "{:?}", text);
        }
        Ok(())
    }

    fn layout_text() -> impl proptest::strategy::Strategy<Value = String> {
        use proptest::prelude::*;
        (proptest::collection::vec(layout_line(), 0..14), prop_oneof![Just("\n"), Just("\r\n")], any::<bool>())
            .prop_map(|(lines, end, last_end)| lines.join(end) + if last_end { end } else { "" })
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(3000))]

        /// Same value bits, same rejections as `str::parse::<f64>`.
        #[test]
        fn fast_numbers_are_the_standard_parser_s(text in "[0-9.eE+-]{0,24}|[0-9]{1,3}\\.[0-9]{1,25}([eE][+-]?[0-9]{1,3})?|\\PC{0,8}") {
            let standard = text.parse::<f64>().ok().map(f64::to_bits);
            proptest::prop_assert_eq!(parse_float(&text).map(f64::to_bits), standard);
        }

        /// Where the fast path reads a number, it is the standard parser's value, bit for bit.
        #[test]
        fn exact_decimals_are_the_standard_parser_s(text in "[+-]?[0-9]{0,12}(\\.[0-9]{0,12})?([eE][+-]?[0-9]{1,3})?|[0-9]{14,20}\\.?[0-9]{0,3}") {
            if let Some((value, length)) = exact_decimal(text.as_bytes()) {
                proptest::prop_assert_eq!(Some(value.to_bits()), text[..length].parse::<f64>().ok().map(f64::to_bits), "{}", text);
            }
        }

        /// Eight digits at a time, the run's length and mantissa are those of one at a time.
        #[test]
        fn digit_runs_are_read_as_one_by_one(text in "[0-9]{0,30}[^0-9]?[0-9]{0,12}|[0-9/:.eE +-]{0,24}|\\PC{0,12}", at in 0usize..8, start in proptest::prelude::any::<u64>()) {
            let bytes = text.as_bytes();
            let at = at.min(bytes.len());
            let mut mantissa = start;
            let mut length = 0;
            while let Some(&b) = bytes.get(at + length).filter(|b| b.is_ascii_digit()) {
                mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(b - b'0'));
                length += 1;
            }
            proptest::prop_assert_eq!(read_digits(bytes, at, start), (length, mantissa), "{:?} at {}", text, at);
        }

        /// Spaces counted eight at a time are those counted one at a time.
        #[test]
        fn leading_spaces_are_counted_as_one_by_one(text in "[ ]{0,20}[^ ]?[ 0-9\t]{0,12}|\\PC{0,12}", at in 0usize..8) {
            let bytes = text.as_bytes();
            let at = at.min(bytes.len());
            proptest::prop_assert_eq!(leading_spaces(bytes, at), bytes[at..].iter().take_while(|&&b| b == b' ').count());
        }

        #[test]
        fn compact_pages_parse_as_blanked_pages(text in page_text()) {
            compact_is_blanked(&text)?;
        }

        #[test]
        fn compact_layouts_parse_as_blanked_layouts(text in layout_text()) {
            compact_is_blanked(&text)?;
        }

        /// The fields and their count are those of `split_whitespace`.
        #[test]
        fn fields_are_those_of_split_whitespace(text in layout_text()) {
            for line in text.lines() {
                let mut fields = [Field::default(); 3];
                let count = split_fields(line, &mut fields);
                let expected: Vec<&str> = line.split_whitespace().collect();
                proptest::prop_assert_eq!(count, expected.len());
                let kept: Vec<&str> = fields[..count.min(3)].iter().map(|f| f.text).collect();
                proptest::prop_assert_eq!(&kept[..], &expected[..count.min(3)]);
            }
        }

        /// The one-pass scan finds what the three `str` scans found, and the byte-level cut
        /// gives the text and tables of the `str` cut.
        #[test]
        fn byte_scans_are_the_str_scans(text in layout_text()) {
            let keys = TextKeys::scan(&text);
            proptest::prop_assert_eq!(keys.data_lines, reference::data_key_lines(&text));
            proptest::prop_assert_eq!(keys.nd, reference::printed_property(&text, "nd"));
            proptest::prop_assert_eq!(keys.vd, reference::printed_property(&text, "Vd"));
            let cut = CutTables::cut(&text).map(|c| (c.blanked(), c.tables));
            proptest::prop_assert_eq!(cut, reference::cut(&text));
        }
    }

    /// Table bodies of rows that are mostly plain numbers, with the defects and layouts the
    /// general rule must handle.
    fn table_body() -> impl proptest::strategy::Strategy<Value = String> {
        use proptest::prelude::*;
        let field = prop_oneof![
            8 => (0.01f64..100.0).prop_map(|x| format!("{x}")),
            4 => (0.1f64..10.0, -8i32..3).prop_map(|(m, e)| format!("{m:.5}E{e:+03}")),
            1 => Just("-1.5".to_string()),
            1 => Just("0".to_string()),
            1 => Just("1e400".to_string()),
            1 => Just("inf".to_string()),
            1 => Just("nan".to_string()),
            1 => Just("1.5e".to_string()),
            1 => Just("+.5".to_string()),
            1 => Just("2.".to_string()),
            1 => Just("1,5".to_string()),
            1 => Just("0.1234567890123456789012345678901234567890123456789012345678901234567".to_string()),
            1 => "[0-9.eE+-]{1,6}",
            1 => "[a-zé]{1,3}",
        ];
        let space = prop_oneof![8 => Just(" "), 1 => Just("  "), 1 => Just("\t"), 1 => Just("\r"), 1 => Just("\u{b}"), 1 => Just("\u{a0}"), 1 => Just("\u{3000}")];
        let row = (space.clone(), proptest::collection::vec((field, space.clone()), 0..5)).prop_map(|(lead, fields)| {
            let mut row = String::from(lead);
            for (field, space) in fields {
                row.push_str(&field);
                row.push_str(space);
            }
            row
        });
        (proptest::collection::vec(row, 0..8), prop_oneof![Just("\n"), Just("\r\n")], any::<bool>())
            .prop_map(|(rows, end, last_end)| rows.join(end) + if last_end { end } else { "" })
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4000))]

        /// Rows read the plain way or the general way are the rows (or the error) of the
        /// `str` methods and the standard float parser.
        #[test]
        fn rows_are_those_of_the_str_methods(body in table_body(), columns in 2usize..=3) {
            let ours = parse_rows("t.yml", &body, columns, Some(7)).map(|rows| rows.iter().map(|r| (r.values.map(f64::to_bits), r.line)).collect::<Vec<_>>()).map_err(|e| {
                format!("{} {:?} {}", e.reason.code(), e.line, e.detail)
            });
            proptest::prop_assert_eq!(ours, reference::parse_rows("t.yml", &body, columns, Some(7)));
        }
    }

    #[test]
    fn table_numbers_and_edge_cases_parse_as_the_standard_parser() {
        for text in [
            "1.28246E+00",
            "1.11870E-06",
            "0.39",
            "+.5",
            "5.",
            ".",
            "-",
            "+",
            "1e",
            "1e+",
            "e5",
            "1..2",
            "1e5e5",
            "-0",
            "1e400",
            "1e-400",
            "inf",
            "NaN",
            "0x10",
            "1_0",
        ] {
            assert_eq!(parse_float(text).map(f64::to_bits), text.parse::<f64>().ok().map(f64::to_bits), "{text}");
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]

        /// The forward search counts the rows `partition_point` counts, from any start row.
        #[test]
        fn rows_not_above_is_the_partition_point(steps in proptest::collection::vec(1e-6f64..0.5, 0..40), um in -0.5f64..12.0, from in 0usize..45) {
            let x: Vec<f64> = steps.iter().scan(0.0, |w, s| { *w += s; Some(*w) }).collect();
            proptest::prop_assert_eq!(rows_not_above(&x, um, from), x.partition_point(|&w| w <= um));
            // The table's own wavelengths, where `<=` changes from true to false.
            for &w in &x {
                proptest::prop_assert_eq!(rows_not_above(&x, w, from), x.partition_point(|&v| v <= w));
            }
        }

        /// Read in increasing order (then again from the start), `at_near` gives the bits `at` gives.
        #[test]
        fn at_near_gives_the_values_of_at(steps in proptest::collection::vec(1e-4f64..0.2, 2..60), values in proptest::collection::vec(-5.0f64..5.0, 60), points in proptest::collection::vec(0.0f64..8.0, 0..80)) {
            let x: Vec<f64> = steps.iter().scan(0.1, |w, s| { *w += s; Some(*w) }).collect();
            let curve = Curve::Tabulated { values: values[..x.len()].to_vec(), wavelengths_um: x.clone() };
            let mut sorted = points.clone();
            sorted.sort_by(f64::total_cmp);
            let mut row = 0;
            for um in sorted.iter().chain(&x).chain(&sorted) {
                proptest::prop_assert_eq!(curve.at_near(*um, &mut row).map(f64::to_bits), curve.at(*um).map(f64::to_bits));
            }
        }
    }
}
