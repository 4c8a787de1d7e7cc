//! The database's YAML read without the YAML parser, when the text keeps to the block
//! layout the database writes (YAML 1.2, chapter 8): block mappings and sequences, one
//! `key: value` or `- entry` per line; scalars plain, quoted without escapes, or literal
//! blocks (`|`, `|-`); comments on lines of their own. The result is the `Value` serde_norway
//! builds from the same text, plain scalars resolved as it resolves them (null, booleans,
//! integers, floats, else text). Any line outside that layout gives `None`, and serde_norway
//! reads the text, with its own errors. libyaml spends about 330 instructions a byte of
//! metadata; the catalog is read at every command's start, the pages' metadata is a third
//! of the ingest's instructions.

use serde_norway::{Mapping, Value};

/// The value of `text`, when every line keeps to the block layout; `None` otherwise.
pub fn block_value(text: &str) -> Option<Value> {
    if !plain_text(text) {
        return None;
    }
    let mut lines = Lines::new(text);
    if lines.peek()?.indent != 0 {
        return None;
    }
    let value = node(&mut lines, 0)?;
    lines.peek().is_none().then_some(value)
}

/// A `T` from `text` as serde_norway's `from_str` gives it: the block layout read directly,
/// anything else — and a value `T` does not take — by serde_norway, with its errors. Text
/// nesting deeper than [`MAX_NESTING`] is an error before serde_norway sees it.
pub fn from_str<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, serde_norway::Error> {
    match block_value(text).and_then(|value| serde_norway::from_value(value).ok()) {
        Some(read) => Ok(read),
        None => {
            if let Some(deep) = too_deep(text) {
                return Err(serde::de::Error::custom(deep.to_string()));
            }
            serde_norway::from_str(text)
        }
    }
}

/// The deepest nesting of collections read from any YAML file (the database nests four
/// deep, scene files three): libyaml and serde_norway take time that grows with the square
/// of the depth (a catalog of 100 000 levels ran for minutes), so deeper text is refused
/// before they see it.
pub const MAX_NESTING: usize = 64;

/// Text that nests deeper than [`MAX_NESTING`]: the first line that does, and the depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: the YAML nests {depth} levels deep, deeper than the {max} read", max = MAX_NESTING)]
pub struct TooDeep {
    /// The first line that nests too deep (1-based).
    pub line: usize,
    /// How deep it nests.
    pub depth: usize,
}

/// Whether `text` nests deeper than [`MAX_NESTING`], by a bound read in one pass over its
/// lines: the block levels open at a line (the indentations of the lines above it that
/// enclose it, plus each `- ` or `? ` indicator that opens a collection on the line itself)
/// plus the open flow brackets `[` and `{`. Comments, and the lines of block scalars (`|`,
/// `>`), are passed over; brackets inside quoted text are counted too, so the bound is
/// never below the real depth.
pub fn too_deep(text: &str) -> Option<TooDeep> {
    let mut indents: Vec<usize> = Vec::new();
    let mut flow: usize = 0;
    // The indentation of the line that opened a block scalar: deeper lines are its text.
    let mut scalar_parent: Option<usize> = None;
    for (i, line) in text.split('\n').enumerate() {
        let content = line.trim_start_matches([' ', '\t']);
        let indent = line.len() - content.len();
        let content = content.trim_end();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        if let Some(parent) = scalar_parent {
            if indent > parent {
                continue;
            }
            scalar_parent = None;
        }
        if flow == 0 {
            while indents.last().is_some_and(|&top| top > indent) {
                indents.pop();
            }
            if indents.last().is_none_or(|&top| top < indent) {
                indents.push(indent);
            }
        }
        let mut rest = content;
        let mut indicators = 0;
        while let Some(after) = rest.strip_prefix("- ").or_else(|| rest.strip_prefix("? ")) {
            indicators += 1;
            rest = after.trim_start_matches(' ');
        }
        let mut deepest = flow;
        for byte in rest.bytes() {
            match byte {
                b'[' | b'{' => {
                    flow += 1;
                    deepest = deepest.max(flow);
                }
                b']' | b'}' => flow = flow.saturating_sub(1),
                _ => {}
            }
        }
        let depth = indents.len() + indicators + deepest;
        if depth > MAX_NESTING {
            return Some(TooDeep { line: i + 1, depth });
        }
        let header =
            rest.rsplit_once(' ').map_or(rest, |(_, last)| last).trim_end_matches(|c: char| c == '-' || c == '+' || c.is_ascii_digit());
        if flow == 0 && matches!(header, "|" | ">") {
            scalar_parent = Some(indent);
        }
    }
    None
}

/// Whether every character of `text` is a [`plain_text_char`]: ASCII text byte by byte in
/// blocks the compiler vectorises, other text character by character.
fn plain_text(text: &str) -> bool {
    if text.is_ascii() {
        let plain = |b: u8| (b' '..=b'~').contains(&b) || b == b'\n';
        return text.as_bytes().chunks(64).all(|block| block.iter().fold(true, |all, &b| all & plain(b)));
    }
    text.chars().all(plain_text_char)
}

/// The characters that mean themselves everywhere in this layout: the line feed and the
/// printable characters of YAML 1.2 §5.1 except the BOM, and neither tab nor carriage
/// return, nor the line breaks libyaml also knows (NEL, U+2028, U+2029).
fn plain_text_char(c: char) -> bool {
    matches!(c, '\n' | ' '..='~' | '\u{a0}'..='\u{2027}' | '\u{202a}'..='\u{d7ff}' | '\u{e000}'..='\u{fefe}' | '\u{ff00}'..='\u{fffd}' | '\u{10000}'..)
}

/// A line with content: its indentation (spaces), the rest, and where the next line starts.
#[derive(Clone, Copy)]
struct Line<'a> {
    indent: usize,
    content: &'a str,
    next: usize,
}

/// The text's lines: the next one with content (blank lines and comment lines passed
/// over), or the next one as it is (inside a literal block).
struct Lines<'a> {
    text: &'a str,
    at: usize,
    next: Option<Line<'a>>,
    /// The collections open around the line (sequences and mappings).
    depth: usize,
}

/// The deepest nesting read here (the database nests four deep); deeper text is left to
/// serde_norway, whose own limit then reports it, instead of recursing without bound.
const MAX_DEPTH: usize = 32;

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        let mut lines = Lines { text, at: 0, next: None, depth: 0 };
        lines.next = lines.find_content();
        lines
    }

    fn peek(&self) -> Option<Line<'a>> {
        self.next
    }

    /// Past the line [`Lines::peek`] gives.
    fn advance(&mut self) {
        if let Some(line) = self.next {
            self.at = line.next;
            self.next = self.find_content();
        }
    }

    /// The next line as it is, without its line feed, and whether it has one.
    fn peek_raw(&self) -> Option<(&'a str, bool)> {
        let rest = self.text.get(self.at..).filter(|rest| !rest.is_empty())?;
        Some(match memchr::memchr(b'\n', rest.as_bytes()) {
            Some(end) => (&rest[..end], true),
            None => (rest, false),
        })
    }

    /// Past the line [`Lines::peek_raw`] gives.
    fn advance_raw(&mut self) {
        if let Some((line, _)) = self.peek_raw() {
            self.at += line.len() + 1;
            self.next = self.find_content();
        }
    }

    /// One collection deeper; `None` past [`MAX_DEPTH`].
    fn enter(&mut self) -> Option<()> {
        self.depth += 1;
        (self.depth <= MAX_DEPTH).then_some(())
    }

    fn find_content(&self) -> Option<Line<'a>> {
        let mut at = self.at;
        while let Some(rest) = self.text.get(at..).filter(|rest| !rest.is_empty()) {
            let end = memchr::memchr(b'\n', rest.as_bytes()).unwrap_or(rest.len());
            let line = &rest[..end];
            let content = line.trim_start_matches(' ');
            if !content.is_empty() && !content.starts_with('#') {
                return Some(Line { indent: line.len() - content.len(), content, next: at + end + 1 });
            }
            at += end + 1;
        }
        None
    }
}

/// Whether a line's content is a block sequence's entry.
fn is_entry(content: &str) -> bool {
    content == "-" || content.starts_with("- ")
}

/// The block node whose lines start at `indent` (the next line's): a sequence when that
/// line is an entry, a mapping otherwise.
fn node(lines: &mut Lines, indent: usize) -> Option<Value> {
    let first = lines.peek()?;
    if is_entry(first.content) {
        sequence(lines, indent)
    } else {
        lines.advance();
        mapping(lines, indent, first.content)
    }
}

/// A block sequence whose `- ` indicators stand at `indent`; an entry is a mapping when it
/// starts with a key, a scalar otherwise.
fn sequence(lines: &mut Lines, indent: usize) -> Option<Value> {
    lines.enter()?;
    let mut entries = Vec::new();
    while let Some(line) = lines.peek().filter(|line| line.indent >= indent) {
        if line.indent > indent {
            return None;
        }
        let first = line.content.strip_prefix("- ")?;
        lines.advance();
        entries.push(if key_of(first).is_some() { mapping(lines, indent + 2, first)? } else { scalar(first)? });
    }
    lines.depth -= 1;
    Some(Value::Sequence(entries))
}

/// A block mapping whose keys stand at `column`, its first entry `first` (on a line
/// already passed).
fn mapping(lines: &mut Lines, column: usize, first: &str) -> Option<Value> {
    lines.enter()?;
    let mut map = Mapping::new();
    entry(lines, column, first, &mut map)?;
    while let Some(line) = lines.peek().filter(|line| line.indent >= column) {
        if line.indent > column {
            return None;
        }
        lines.advance();
        entry(lines, column, line.content, &mut map)?;
    }
    lines.depth -= 1;
    Some(Value::Mapping(map))
}

/// The key of a `key:` or `key: value` line, and the rest after the colon; keys are
/// identifiers (letters, digits, `_`, `-`, not first) other than null and the booleans.
fn key_of(text: &str) -> Option<(&str, &str)> {
    let (key, rest) = text.split_once(':')?;
    let identifier = key.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        && key.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-');
    (identifier && reserved(key).is_none() && (rest.is_empty() || rest.starts_with(' '))).then_some((key, rest))
}

/// One `key: value` of a mapping at `column`, added to `map` (a repeated key is left to
/// serde_norway). A key without a value on its line owns the block node below it, more
/// indented, or is null; `key: |` and `key: |-` own the literal block below.
fn entry(lines: &mut Lines, column: usize, text: &str, map: &mut Mapping) -> Option<()> {
    let (key, rest) = key_of(text)?;
    let rest = rest.trim_matches(' ');
    let value = match rest {
        "" => match lines.peek() {
            Some(next) if next.indent > column => node(lines, next.indent)?,
            Some(next) if next.indent == column && is_entry(next.content) => return None,
            _ => Value::Null,
        },
        "|" => literal(lines, column, true)?,
        "|-" => literal(lines, column, false)?,
        _ => scalar(rest)?,
    };
    map.insert(Value::String(key.to_string()), value).is_none().then_some(())
}

/// A literal block scalar (YAML 1.2 §8.1.2) whose header closed the previous line, for a
/// key at `column`: its lines are the following ones indented as its first line with
/// content, deeper than the key (blank lines among them are empty lines of the text); the
/// final line feed kept (clip) or not (strip), blank lines after the text dropped either
/// way. Blank lines holding more spaces than the block's indentation, and a first text line
/// indented less than a blank line before it, are left to serde_norway.
fn literal(lines: &mut Lines, column: usize, clip: bool) -> Option<Value> {
    let mut indent: Option<usize> = None;
    let mut widest_blank = 0;
    // The block's lines (blank ones empty), up to its last text line, and whether that
    // line ends in a line feed.
    let mut kept: Vec<&str> = Vec::new();
    let (mut text_lines, mut line_feed) = (0, false);
    while let Some((line, has_feed)) = lines.peek_raw() {
        let spaces = line.len() - line.trim_start_matches(' ').len();
        if spaces == line.len() {
            match indent {
                None => widest_blank = widest_blank.max(spaces),
                Some(n) if spaces > n => return None,
                Some(_) => {}
            }
            kept.push("");
        } else {
            let n = *indent.get_or_insert(spaces);
            if spaces < n || spaces <= column {
                if spaces > column {
                    return None;
                }
                break;
            }
            if widest_blank > n {
                return None;
            }
            kept.push(&line[n..]);
            (text_lines, line_feed) = (kept.len(), has_feed);
        }
        lines.advance_raw();
    }
    let mut text = kept[..text_lines].join("\n");
    if clip && line_feed {
        text.push('\n');
    }
    Some(Value::String(text))
}

/// A scalar alone on the rest of its line: double- or single-quoted without escapes, or
/// plain, resolved as serde_norway resolves it (null, a boolean, an integer, a float, else
/// text); quoted scalars with escapes and plain ones starting with punctuation are left to
/// serde_norway.
fn scalar(text: &str) -> Option<Value> {
    let text = text.trim_end_matches(' ');
    // Double quotes escape with a backslash, single quotes by doubling the quote.
    for (quote, escape) in [('"', '\\'), ('\'', '\'')] {
        if let Some(quoted) = text.strip_prefix(quote) {
            let inner = quoted.strip_suffix(quote)?;
            return (!inner.contains([quote, escape])).then(|| Value::String(inner.to_string()));
        }
    }
    if text.contains(": ") || text.contains(" #") || text.ends_with(':') {
        return None;
    }
    if let Some(value) = reserved(text) {
        return Some(value);
    }
    let mut chars = text.chars();
    let (first, second) = (chars.next()?, chars.next());
    if first.is_ascii_alphabetic() || !first.is_ascii() {
        return Some(Value::String(text.to_string()));
    }
    let number_start = first.is_ascii_digit() || (matches!(first, '-' | '.') && second.is_some_and(|c| c.is_ascii_digit()));
    if !number_start {
        return None;
    }
    number_or_text(text)
        .or_else(|| serde_norway::from_str::<Value>(text).ok().filter(|value| matches!(value, Value::String(_) | Value::Number(_))))
}

/// serde_norway's resolution of a plain scalar that starts as a number does (a digit, or `-`
/// or `.` before one), for the forms it is sure of: text with a space (no integer or
/// float has one), digits with a leading zero (text, YAML 1.2), decimal integers, and
/// decimal floats (Rust's parser, as serde_norway's); `None` for the rest.
fn number_or_text(text: &str) -> Option<Value> {
    if text.contains(' ') {
        return Some(Value::String(text.to_string()));
    }
    let unsigned = text.strip_prefix('-').unwrap_or(text);
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if digits(unsigned) {
        if unsigned.len() > 1 && unsigned.starts_with('0') {
            return Some(Value::String(text.to_string()));
        }
        return if unsigned.len() == text.len() {
            text.parse::<u64>().ok().map(Value::from)
        } else {
            text.parse::<i64>().ok().map(Value::from)
        };
    }
    let (mantissa, exponent) = unsigned.split_once(['e', 'E']).map_or((unsigned, None), |(m, e)| (m, Some(e)));
    let (whole, fraction) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let mantissa_ok =
        (digits(whole) || whole.is_empty()) && (digits(fraction) || fraction.is_empty()) && !(whole.is_empty() && fraction.is_empty());
    let exponent_ok = exponent.is_none_or(|e| digits(e.strip_prefix(['+', '-']).unwrap_or(e)));
    if !(mantissa_ok && exponent_ok) {
        return None;
    }
    text.parse::<f64>().ok().filter(|x| x.is_finite()).map(Value::from)
}

/// The plain scalars serde_norway reads as null or a boolean, as that value.
fn reserved(text: &str) -> Option<Value> {
    match text {
        "null" | "Null" | "NULL" | "~" => Some(Value::Null),
        "true" | "True" | "TRUE" => Some(Value::Bool(true)),
        "false" | "False" | "FALSE" => Some(Value::Bool(false)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parser(text: &str) -> Option<Value> {
        serde_norway::from_str(text).ok()
    }

    #[test]
    fn the_catalog_layout_reads_as_the_parser_reads_it() {
        let text = "# header\n\n- DIVIDER: \"Research data\"\n- SHELF: main\n  name: \"MAIN: simple # inorganic\"\n  content:\n    # a comment line\n    - BOOK: Ag\n      name: \"Ag (Silver) µm–γ\"\n      content:\n        - PAGE: Kato-γ\n          data: organic/(C8H8)n - polystyrene/nk/Sultanova.yml   \n        - PAGE: 1975\n          data: main/Ag/nk/x.yml\n        - PAGE: 0012\n        - PAGE: 1.50\n        - PAGE: -3\n          name: \"\"\n  extra: value\n- SHELF: 3d\n  content:\n      - BOOK: metals\n";
        let value = block_value(text).expect("the layout");
        assert_eq!(Some(&value), parser(text).as_ref());
        // Numbers stay numbers, a leading zero keeps text.
        let pages = &value[1]["content"][0]["content"];
        assert_eq!(pages[1]["PAGE"], Value::Number(1975.into()));
        assert_eq!(pages[2]["PAGE"], Value::String("0012".into()));
        assert_eq!(pages[3]["PAGE"], Value::Number(1.5.into()));
        assert_eq!(pages[0]["data"], Value::String("organic/(C8H8)n - polystyrene/nk/Sultanova.yml".into()));
    }

    #[test]
    fn block_mappings_scalars_and_literal_blocks_read_as_the_parser_reads_them() {
        for text in [
            "KEY: value\n",
            "- a\n- 1.5\n- 'single'\n",
            "- KEY:value\n",
            "- KEY: true\n  B: False\n  C: null\n  D: ~\n  E: NULL\n",
            "- KEY: 'single'\n",
            "- KEY:\n  other: x\n",
            "A:\nB: 1\n",
            "A: 12\nB: -7\nC: 0\nD: -0\nE: 007\nF: 1.5e-3\nG: .5\nH: 5.\nI: 2E+05\nJ: 1 2 3\nK: 3d\nL: 1.2.3\nM: 0x1F\nO: 20 °C\n",
            "A: |\n  x\n\n  y\n\n\nB: 1\n",
            "A: |-\n  x\n  y\n",
            "A: |\n\n  x\n",
            "A: |\n  x\n    deeper\n  z",
            "A: |\n    \nB: 2\n",
            "A: |\nB: 2\n",
            "A: |\n  # not a comment\n  x: y\n",
            "- data: |\n    1 2\n    3 4\n  other: x\n",
            "P:\n    nd: 1.5\n    density:\n      - value: 3610\n      - value: 3.5\n        unit: kg\n    list:\n      - a b\n      - 2\n",
        ] {
            let value = block_value(text);
            assert!(value.is_some(), "{text:?}");
            assert_eq!(value, parser(text), "{text:?}");
        }
    }

    #[test]
    fn deep_nesting_is_left_to_the_parser() {
        let nested = |depth: usize| {
            (0..depth).map(|level| format!("{}k{level}:\n", " ".repeat(level))).collect::<String>() + &" ".repeat(depth) + "leaf: 1\n"
        };
        assert!(block_value(&nested(MAX_DEPTH - 1)).is_some());
        assert_eq!(block_value(&nested(MAX_DEPTH)), None);
        // Deeper than a test thread's stack holds for a recursive reader without the limit
        // (checked: it overflows there): no recursion beyond the limit.
        assert_eq!(block_value(&nested(3_000)), None);
    }

    #[test]
    fn anything_outside_the_layout_is_left_to_the_parser() {
        for text in [
            "",
            "# only a comment\n",
            "- KEY: \"esc\\\"aped\"\n",
            "- KEY: \"two\n  lines\"\n",
            "- KEY: plain\n  continued\n",
            "- KEY: a: b\n",
            "- KEY: value # comment\n",
            "- KEY: &anchor x\n",
            "- KEY: [1, 2]\n",
            "- KEY: -\n",
            "- KEY: +1\n",
            "- KEY: x\n  KEY: y\n",
            "- KEY:\n  - x: 1\n",
            "- KEY: x\r\n",
            "- KEY: x\t\n",
            "- KEY: x\u{85}y\n",
            "\u{feff}- KEY: x\n",
            "---\n- KEY: x\n",
            "- KEY: x\n   other: y\n",
            "- KEY: x\n ...\n",
            " - KEY: x\n",
            "-  KEY: x\n",
            "- true: x\n",
            "- 1: x\n",
            "A: |+\n  x\n",
            "A: |2\n  x\n",
            "A: >\n  x\n",
            "A: | # c\n  x\n",
            "A: |\n     \n  x\n",
            "A: |\n  x\n     \n  y\n",
            "A:\n  B: |\n   x\n  y\n",
        ] {
            assert_eq!(block_value(text), None, "{text:?}");
        }
    }

    /// Where the reader gives a value, it is the parser's.
    fn read_as_the_parser_reads(text: &str) -> Result<(), proptest::test_runner::TestCaseError> {
        if let Some(value) = block_value(text) {
            proptest::prop_assert_eq!(Some(value), parser(text), "{:?}", text);
        }
        Ok(())
    }

    /// A text in the layout is read (the direct path is the one taken), to the parser's value.
    fn read_in_the_layout(text: &str) -> Result<(), proptest::test_runner::TestCaseError> {
        let value = block_value(text);
        proptest::prop_assert!(value.is_some(), "{:?}", text);
        proptest::prop_assert_eq!(value, parser(text), "{:?}", text);
        Ok(())
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(3000))]

        /// Catalogs built from the layout's pieces and the pieces just outside it.
        #[test]
        fn a_catalog_read_is_the_parser_s(text in catalog_text(true)) {
            read_as_the_parser_reads(&text)?;
        }

        #[test]
        fn catalogs_in_the_layout_are_read(text in catalog_text(false)) {
            read_in_the_layout(&text)?;
        }

        /// Data pages, likewise.
        #[test]
        fn a_page_read_is_the_parser_s(text in page_text(true)) {
            read_as_the_parser_reads(&text)?;
        }

        #[test]
        fn pages_in_the_layout_are_read(text in page_text(false)) {
            read_in_the_layout(&text)?;
        }
    }

    /// Data pages: references as a literal block or quoted, DATA blocks of tables and
    /// formulas, conditions and properties with numbers, booleans, nulls and lists; with
    /// `wild`, lines from just outside the layout too.
    fn page_text(wild: bool) -> impl proptest::strategy::Strategy<Value = String> {
        use proptest::prelude::*;
        let tame_scalar = prop_oneof![
            "[A-Za-z][A-Za-z0-9_./()+,<>= -]{0,10}[A-Za-z0-9)]".prop_map(|s| s),
            "\"[ !#-\\[\\]-~µ]{0,10}\"".prop_map(|s| s),
            "'[ -&(-~]{0,8}'".prop_map(|s| s),
            "-?[0-9]{1,4}(\\.[0-9]{0,3})?([eE][+-]?[0-9]{1,2})?".prop_map(|s| s),
            prop_oneof![Just("true"), Just("False"), Just("null"), Just("~"), Just("20 °C"), Just("0.4 0.7"), Just("007"), Just(".5")]
                .prop_map(String::from),
        ];
        let wild_scalar = prop_oneof![
            6 => tame_scalar.clone(),
            1 => "[ -~]{0,8}".prop_map(|s| s),
            1 => prop_oneof![Just("|+"), Just("|2"), Just(">"), Just("a: b"), Just("x #c"), Just("+1"), Just("0x1F"), Just("\"a\\nb\""), Just("-")].prop_map(String::from),
        ];
        let scalar = if wild { wild_scalar.boxed() } else { tame_scalar.boxed() };
        let text_line = if wild { "[ ]{0,3}[ -~]{0,12}".boxed() } else { "[A-Za-z0-9<>/.:#-][ -~]{0,12}[!-~]".boxed() };
        let block = proptest::collection::vec(prop_oneof![6 => text_line, 1 => Just(String::new()), 1 => Just("  more".to_string())], 0..5);
        let row = prop_oneof![6 => Just("        0.5 1.5 0.1".to_string()), 1 => Just(String::new()), 1 => Just("          0.6 1.6".to_string()), 1 => if wild { Just("      0.7 1".to_string()) } else { Just("        0.7 1".to_string()) }];
        let table = (prop_oneof![Just("|"), Just("|-")], proptest::collection::vec(row, 0..5), scalar.clone());
        let property = ("[a-z][a-z_]{0,6}", scalar.clone());
        (
            any::<bool>(),
            block,
            proptest::collection::vec(table, 0..3),
            proptest::collection::vec(property, 0..4),
            proptest::collection::vec(scalar.clone(), 0..3),
            any::<bool>(),
        )
            .prop_map(|(block_references, references, tables, properties, list, blank_comments)| {
                let mut lines = vec!["# this file is part of a database".to_string(), String::new()];
                if block_references {
                    lines.extend(["REFERENCES: |".to_string(), "    <b>Author</b> 2020".to_string()]);
                    lines.extend(references.iter().map(|line| format!("    {line}")));
                } else {
                    lines.push("REFERENCES: \"r\"".to_string());
                }
                if blank_comments {
                    lines.extend(["COMMENTS: |".to_string(), "    ".to_string()]);
                }
                lines.push("DATA:".to_string());
                for (chomp, rows, coefficients) in &tables {
                    lines.push("  - type: tabulated nk".to_string());
                    lines.push(format!("    coefficients: {coefficients}"));
                    lines.extend([format!("    data: {chomp}"), "        0.4 1.4 0.2".to_string()]);
                    lines.extend(rows.iter().cloned());
                }
                lines.push("PROPERTIES:".to_string());
                let mut seen = std::collections::HashSet::new();
                for (key, value) in properties.iter().filter(|(key, _)| seen.insert(key.clone()) && reserved(key).is_none()) {
                    lines.push(format!("    {key}: {value}"));
                }
                lines.push("    density:".to_string());
                lines.push("      - value: 3610".to_string());
                if !list.is_empty() {
                    lines.push("    list:".to_string());
                    lines.extend(list.iter().map(|item| format!("      - {item}")));
                }
                lines.join("\n") + "\n"
            })
    }

    /// Catalog texts: shelves of books of pages with dividers and comments; with `wild`,
    /// values, keys and indentation from outside the layout too.
    fn catalog_text(wild: bool) -> impl proptest::strategy::Strategy<Value = String> {
        use proptest::prelude::*;
        let tame_value = prop_oneof![
            "[A-Za-z][A-Za-z0-9_./()+ -]{0,8}[A-Za-z0-9)]".prop_map(|s| s),
            "\"[ !#-\\[\\]-~µγ–]{0,10}\"".prop_map(|s| s),
            "[0-9]{1,4}(\\.[0-9]{1,2})?".prop_map(|s| s),
            Just("γ-phase".to_string()),
        ];
        let wild_value = prop_oneof![
            4 => tame_value.clone(),
            1 => "[ -~]{0,8}".prop_map(|s| s),
            1 => prop_oneof![Just("true"), Just("~"), Just("-"), Just("null"), Just("-.5"), Just("+1"), Just("0x1F"), Just(".inf"), Just("a: b"), Just("a #b"), Just("'q'"), Just("\"x\\\"y\"")].prop_map(String::from),
        ];
        let value = if wild { wild_value.boxed() } else { tame_value.boxed() };
        let key = if wild {
            prop_oneof![4 => Just("name".to_string()), 1 => "[a-z0-9_]{1,4}".prop_map(|s| s), 1 => Just("true".to_string())].boxed()
        } else {
            Just("name".to_string()).boxed()
        };
        let indent = if wild {
            prop_oneof![6 => Just(2usize), 1 => Just(1usize), 1 => Just(3usize)].boxed()
        } else {
            prop_oneof![Just(2usize), Just(4usize)].boxed()
        };
        let page = (value.clone(), proptest::option::of((key, value.clone())), any::<bool>())
            .prop_map(|(id, extra, comment)| (id, extra, comment));
        let book = (value.clone(), proptest::collection::vec(page, 0..4));
        let shelf = (value.clone(), proptest::collection::vec(book, 0..3), indent);
        proptest::collection::vec(shelf, 1..3).prop_map(|shelves| {
            let mut lines = vec!["# this file is part of a database".to_string(), String::new()];
            for (shelf, books, step) in shelves {
                lines.push(format!("- SHELF: {shelf}"));
                if !books.is_empty() {
                    lines.push("  content:".to_string());
                }
                let book_indent = 2 + step;
                for (book, pages) in books {
                    lines.push(format!("{}- BOOK: {book}", " ".repeat(book_indent)));
                    if pages.is_empty() {
                        continue;
                    }
                    lines.push(format!("{}content:", " ".repeat(book_indent + 2)));
                    let page_indent = book_indent + 2 + step;
                    for (id, extra, comment) in pages {
                        if comment {
                            lines.push(format!("{}# note", " ".repeat(page_indent)));
                        }
                        lines.push(format!("{}- PAGE: {id}", " ".repeat(page_indent)));
                        if let Some((key, value)) = extra {
                            lines.push(format!("{}{key}: {value}", " ".repeat(page_indent + 2)));
                        }
                    }
                }
            }
            lines.join("\n") + "\n"
        })
    }

    /// The nesting bound counts block levels, indicators and flow brackets, passes over
    /// block scalars and comments, and is never below the real depth.
    #[test]
    fn nesting_is_bounded_in_one_pass() {
        assert_eq!(too_deep("a: 1\nb:\n  c: [1, {d: 2}]\n"), None);
        let flow = format!("x: {}1{}", "[".repeat(MAX_NESTING), "]".repeat(MAX_NESTING));
        assert_eq!(too_deep(&flow), Some(TooDeep { line: 1, depth: MAX_NESTING + 1 }));
        // Block mappings, one level per line.
        let block: String = (0..=MAX_NESTING).map(|i| format!("{}k{i}:\n", " ".repeat(i))).collect();
        assert_eq!(too_deep(&block).map(|d| d.line), Some(MAX_NESTING + 1));
        // Compact sequences: every `- ` opens one.
        assert!(too_deep(&format!("{}x\n", "- ".repeat(MAX_NESTING + 1))).is_some());
        // Brackets inside a literal block or a comment are text.
        let literal = format!("a: |\n  {}\n# {}\nb: 1\n", "[".repeat(1000), "[".repeat(1000));
        assert_eq!(too_deep(&literal), None);
        // What serde_norway refuses as too deep is refused here first.
        let deep = format!("{}{}", "[".repeat(200), "]".repeat(200));
        assert!(serde_norway::from_str::<Value>(&deep).is_err() && too_deep(&deep).is_some());
        let message = from_str::<Value>(&deep).unwrap_err().to_string();
        assert!(message.contains("line 1: the YAML nests 201 levels deep, deeper than the 64 read"), "{message}");
    }
}
