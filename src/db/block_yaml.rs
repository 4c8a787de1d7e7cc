//! The catalog's YAML read without the YAML parser, when the text keeps to the block layout
//! the database writes it in (YAML 1.2, chapter 8: block sequences of block mappings): one
//! `key: value` per line, each value a plain scalar or a double-quoted one without escapes
//! on its line, or a block sequence on the lines below its key; comments on lines of their
//! own. The result is the `Value` serde_yaml builds from the same text. Any line outside
//! that layout gives `None`, and serde_yaml reads the text, with its own errors. libyaml
//! spends about 330 instructions a byte on the catalog, most of a command's serial start.

use serde_yaml::{Mapping, Value};

/// The value of `text`, when every line keeps to the catalog's layout; `None` otherwise.
pub fn block_value(text: &str) -> Option<Value> {
    if !text.chars().all(plain_text_char) {
        return None;
    }
    let mut lines = Lines::new(text);
    if lines.peek()?.indent != 0 {
        return None;
    }
    let value = sequence(&mut lines, 0)?;
    lines.peek().is_none().then_some(value)
}

/// The characters that mean themselves everywhere in this layout: the line feed and the
/// printable characters of YAML 1.2 §5.1 except the BOM, and neither tab nor carriage
/// return, nor the line breaks libyaml also knows (NEL, U+2028, U+2029).
fn plain_text_char(c: char) -> bool {
    matches!(c, '\n' | ' '..='~' | '\u{a0}'..='\u{2027}' | '\u{202a}'..='\u{d7ff}' | '\u{e000}'..='\u{fefe}' | '\u{ff00}'..='\u{fffd}' | '\u{10000}'..)
}

/// A line with content: its indentation (spaces) and the rest.
#[derive(Clone, Copy)]
struct Line<'a> {
    indent: usize,
    content: &'a str,
}

/// The lines with content, comment lines and blank lines left out.
struct Lines<'a> {
    lines: std::str::Lines<'a>,
    next: Option<Line<'a>>,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        let mut lines = Lines { lines: text.lines(), next: None };
        lines.advance();
        lines
    }

    fn peek(&self) -> Option<Line<'a>> {
        self.next
    }

    fn advance(&mut self) {
        self.next = self.lines.by_ref().find_map(|line| {
            let content = line.trim_start_matches(' ');
            (!content.is_empty() && !content.starts_with('#')).then_some(Line { indent: line.len() - content.len(), content })
        });
    }
}

/// A block sequence whose `- ` indicators stand at `indent`, each entry a block mapping.
fn sequence(lines: &mut Lines, indent: usize) -> Option<Value> {
    let mut entries = Vec::new();
    while let Some(line) = lines.peek().filter(|line| line.indent >= indent) {
        if line.indent > indent {
            return None;
        }
        let first = line.content.strip_prefix("- ")?;
        lines.advance();
        entries.push(mapping(lines, indent + 2, first)?);
    }
    Some(Value::Sequence(entries))
}

/// A block mapping whose keys stand at `column`, its first entry `first` (the rest of a
/// sequence entry's line).
fn mapping(lines: &mut Lines, column: usize, first: &str) -> Option<Value> {
    let mut map = Mapping::new();
    entry(lines, column, first, &mut map)?;
    while let Some(line) = lines.peek().filter(|line| line.indent >= column) {
        if line.indent > column {
            return None;
        }
        lines.advance();
        entry(lines, column, line.content, &mut map)?;
    }
    Some(Value::Mapping(map))
}

/// One `key: value` of a mapping at `column` (a key without a value on its line owns the
/// block sequence below it), added to `map`; a repeated key is left to serde_yaml.
fn entry(lines: &mut Lines, column: usize, text: &str, map: &mut Mapping) -> Option<()> {
    let (key, value) = text.split_once(':')?;
    let key_is_text = key.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') && key.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_');
    if !key_is_text || reserved_word(key) {
        return None;
    }
    let value = if value.is_empty() {
        let nested = lines.peek().filter(|line| line.indent > column && line.content.starts_with("- "))?;
        sequence(lines, nested.indent)?
    } else {
        scalar(value.strip_prefix(' ')?)?
    };
    map.insert(Value::String(key.to_string()), value).is_none().then_some(())
}

/// A scalar alone on the rest of its line: a double-quoted one without escapes, or a plain
/// one resolved as serde_yaml resolves it (text unless it reads as null, a boolean or a
/// number; those, and plain scalars starting with punctuation, are left to serde_yaml).
fn scalar(text: &str) -> Option<Value> {
    let text = text.trim_end_matches(' ');
    if let Some(quoted) = text.strip_prefix('"') {
        let inner = quoted.strip_suffix('"')?;
        return (!inner.contains(['"', '\\'])).then(|| Value::String(inner.to_string()));
    }
    if text.contains(": ") || text.contains(" #") || text.ends_with(':') {
        return None;
    }
    let mut chars = text.chars();
    let (first, second) = (chars.next()?, chars.next());
    if first.is_ascii_alphabetic() || !first.is_ascii() {
        return (!reserved_word(text)).then(|| Value::String(text.to_string()));
    }
    // A number's start: serde_yaml reads the scalar alone (the same resolution).
    let number_start = first.is_ascii_digit() || (matches!(first, '+' | '-' | '.') && second.is_some_and(|c| c.is_ascii_digit()));
    if !number_start || !text.bytes().all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'.' | b'+' | b'-')) {
        return None;
    }
    serde_yaml::from_str::<Value>(text).ok().filter(|value| matches!(value, Value::String(_) | Value::Number(_)))
}

/// The plain scalars serde_yaml reads as null or a boolean.
fn reserved_word(text: &str) -> bool {
    matches!(text, "null" | "Null" | "NULL" | "true" | "True" | "TRUE" | "false" | "False" | "FALSE")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parser(text: &str) -> Option<Value> {
        serde_yaml::from_str(text).ok()
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
    fn anything_outside_the_layout_is_left_to_the_parser() {
        for text in [
            "",
            "# only a comment\n",
            "KEY: value\n",
            "- a\n",
            "- KEY: \"esc\\\"aped\"\n",
            "- KEY: \"two\n  lines\"\n",
            "- KEY: plain\n  continued\n",
            "- KEY: a: b\n",
            "- KEY: value # comment\n",
            "- KEY: true\n",
            "- KEY: null\n",
            "- KEY: ~\n",
            "- KEY: 'single'\n",
            "- KEY: &anchor x\n",
            "- KEY: [1, 2]\n",
            "- KEY: |\n    block\n",
            "- KEY: -\n",
            "- KEY: x\n  KEY: y\n",
            "- KEY:\n  other: x\n",
            "- KEY:\n  - x: 1\n",
            "- KEY:value\n",
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
        ] {
            assert_eq!(block_value(text), None, "{text:?}");
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(3000))]

        /// Where the reader gives a value, it is the parser's, for catalogs built from the
        /// layout's pieces and the pieces just outside it.
        #[test]
        fn a_value_read_is_the_parser_s(text in catalog_text(true)) {
            if let Some(value) = block_value(&text) {
                proptest::prop_assert_eq!(Some(value), parser(&text), "{:?}", text);
            }
        }

        /// Catalogs that keep to the layout are read (the fast path is the one taken).
        #[test]
        fn the_layout_is_read(text in catalog_text(false)) {
            let value = block_value(&text);
            proptest::prop_assert!(value.is_some(), "{:?}", text);
            proptest::prop_assert_eq!(value, parser(&text), "{:?}", text);
        }
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
        let key = if wild { prop_oneof![4 => Just("name".to_string()), 1 => "[a-z0-9_]{1,4}".prop_map(|s| s), 1 => Just("true".to_string())].boxed() } else { Just("name".to_string()).boxed() };
        let indent = if wild { prop_oneof![6 => Just(2usize), 1 => Just(1usize), 1 => Just(3usize)].boxed() } else { prop_oneof![Just(2usize), Just(4usize)].boxed() };
        let page = (value.clone(), proptest::option::of((key, value.clone())), any::<bool>()).prop_map(|(id, extra, comment)| (id, extra, comment));
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
}
