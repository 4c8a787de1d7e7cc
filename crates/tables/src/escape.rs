//! One escaping function per place text from the database (page ids, book and page names,
//! reasons) is written to: a terminal ([`terminal`]), a CSV cell ([`csv()`]), Markdown
//! ([`markdown`]) and XML 1.0 ([`xml`]). Each writes every character its sink shows as
//! itself unchanged and replaces the rest, so that no id can change a terminal's title or
//! colours (ESC, BEL, C1 controls), end a CSV record or a Markdown table row (a newline),
//! start Markdown or HTML syntax, or make an XML file that a conforming parser rejects
//! (XML 1.0 §2.2 `Char` excludes C0 controls other than tab, LF and CR, and U+FFFE/U+FFFF).
//!
//! A CSV cell of text that a spreadsheet would read as a formula — one that starts with
//! `=`, `+`, `-`, `@`, a tab or a carriage return (OWASP, "CSV Injection") — is written with
//! a single quote before it, which spreadsheets show as text; a cell that reads as a finite
//! number (`-0.5`, `+3`, `-1e308`) is a number, not a formula, and is written as it is.
//! A cell of text that starts with quotes followed by such a character gets one quote
//! more, so the rule reverses exactly: [`csv_text`] takes the quote away again (the
//! report reads nklut's own tables through it).
//!
//! A character that must not reach a terminal or a table is written as `\u{…}` (its
//! code point in hex, as Rust writes it): a reader sees that something was there and what.
//! The characters escaped that way are the Unicode controls (C0, DEL, C1) and the
//! invisible ones that reorder or split what a terminal shows (the bidirectional
//! embeddings, overrides and isolates of UAX #9, the line and paragraph separators, the
//! byte-order mark).

/// Whether `c` is written as `\u{…}` on a terminal and in a CSV cell.
fn hidden(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{200E}' | '\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}' | '\u{2028}' | '\u{2029}' | '\u{FEFF}')
}

/// Append `\u{<hex>}` for `c`.
fn push_code_point(out: &mut String, c: char) {
    use std::fmt::Write as _;
    let _ = write!(out, "\\u{{{:x}}}", c as u32);
}

/// Text for a terminal (an error message, a warning, a progress line): controls and
/// invisible reordering characters as `\u{…}`, everything else as itself.
pub fn terminal(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if hidden(c) {
            push_code_point(&mut out, c);
        } else {
            out.push(c);
        }
    }
    out
}

/// The first characters that make a spreadsheet read a cell as a formula (OWASP, "CSV
/// Injection"). Tab and carriage return never start a cell [`csv()`] writes (they are
/// written as `\u{…}`); they are listed for the rule's sake.
pub const FORMULA_STARTS: [char; 6] = ['=', '+', '-', '@', '\t', '\r'];

/// Whether a spreadsheet would read `cell` as a formula, or `cell` is such a cell behind
/// quotes: after its leading single quotes it starts with one of [`FORMULA_STARTS`], and it
/// is not a finite number.
fn formula_like(cell: &str) -> bool {
    cell.trim_start_matches('\'').starts_with(FORMULA_STARTS) && !cell.parse::<f64>().is_ok_and(f64::is_finite)
}

/// Text for a CSV cell: the same characters replaced as for a terminal (so a record is one
/// line and a table opened in a terminal is safe to show), then a single quote before text
/// a spreadsheet would read as a formula (see the module's notes); the CSV writer then
/// quotes the cell where commas or quotes need it. Borrowed when nothing is replaced (most
/// cells).
pub fn csv(text: &str) -> std::borrow::Cow<'_, str> {
    let shown = if text.chars().any(hidden) { std::borrow::Cow::Owned(terminal(text)) } else { std::borrow::Cow::Borrowed(text) };
    if formula_like(&shown) {
        std::borrow::Cow::Owned(format!("'{shown}"))
    } else {
        shown
    }
}

/// The text of a CSV cell [`csv()`] wrote, its formula quote taken away: the inverse of
/// [`csv()`] on every text without control or reordering characters. Borrowed always.
pub fn csv_text(cell: &str) -> &str {
    match cell.strip_prefix('\'') {
        Some(rest) if formula_like(rest) => rest,
        _ => cell,
    }
}

/// Text as Markdown shows it and nothing more: `&`, `<` and `>` as HTML entities (a
/// Markdown renderer passes raw HTML through, so an id holding a tag would run); `\`, `[`,
/// `]` and `|` escaped with a backslash (no link can start in it and no table cell end);
/// controls and invisible reordering characters (a newline would end a table row and start
/// a heading) as `\u{…}` with its backslash escaped. Backticks stay: a code span only
/// turns markup off, and the report's own notes use them.
pub fn markdown(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '\\' | '[' | ']' | '|' => {
                out.push('\\');
                out.push(c);
            }
            c if hidden(c) => {
                out.push('\\');
                push_code_point(&mut out, c);
            }
            c => out.push(c),
        }
    }
    out
}

/// Text for XML 1.0 element content or a double- or single-quoted attribute value: the
/// five markup characters as entities; controls (C0, DEL, C1) as a space (the C0 ones
/// cannot be written in XML 1.0 at all, not even as references); U+FFFE and U+FFFF, which
/// XML 1.0 excludes, as U+FFFD (the replacement character).
pub fn xml(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\u{FFFE}' | '\u{FFFF}' => out.push('\u{FFFD}'),
            c if c.is_control() => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Whether `c` is a `Char` of XML 1.0 (fifth edition, §2.2).
pub fn is_xml_char(c: char) -> bool {
    matches!(c, '\t' | '\n' | '\r' | '\u{20}'..='\u{D7FF}' | '\u{E000}'..='\u{FFFD}' | '\u{10000}'..='\u{10FFFF}')
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn each_sink_replaces_what_it_cannot_show() {
        // ESC ] 0 ; title BEL: a terminal's title sequence, shown as text.
        assert_eq!(terminal("a\u{1b}]0;x\u{7}b"), "a\\u{1b}]0;x\\u{7}b");
        assert_eq!(terminal("r\u{202E}l\u{9b}"), "r\\u{202e}l\\u{9b}");
        assert_eq!(terminal("main/Au/Johnson é"), "main/Au/Johnson é");
        assert_eq!(csv("a\nb,c"), "a\\u{a}b,c");
        // Formulas behind a quote, numbers as they are; `'=` gets one quote more.
        assert_eq!(csv("=HYPERLINK(\"http://x\")"), "'=HYPERLINK(\"http://x\")");
        assert_eq!(csv("+1+2"), "'+1+2");
        assert_eq!(csv("@SUM(A1)"), "'@SUM(A1)");
        assert_eq!(csv("-cmd|' /C calc'!A0"), "'-cmd|' /C calc'!A0");
        assert_eq!(csv("\tx"), "\\u{9}x");
        assert_eq!(csv("'=x"), "''=x");
        assert_eq!(csv("''x"), "''x");
        for number in ["-0.5", "+3", "-1e308", "-0", "1e-9"] {
            assert_eq!(csv(number), number);
        }
        assert_eq!(csv("-inf"), "'-inf");
        assert_eq!(csv("-"), "'-");
        assert_eq!(csv_text("'=x"), "=x");
        assert_eq!(csv_text("''=x"), "'=x");
        assert_eq!(csv_text("'x"), "'x");
        assert_eq!(csv_text("'-1"), "'-1");
        assert_eq!(markdown("x\n# h"), "x\\\\u{a}# h");
        assert_eq!(markdown("<b>|[a](b)`\\"), "&lt;b&gt;\\|\\[a\\](b)`\\\\");
        assert_eq!(xml("a<\"'&>\u{FFFE}\u{FFFF}\u{1}\u{85}z"), "a&lt;&quot;&apos;&amp;&gt;\u{FFFD}\u{FFFD}  z");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// No control or reordering character reaches a terminal, and every other
        /// character is kept in order.
        #[test]
        fn terminal_text_holds_no_control(text in any::<String>()) {
            let out = terminal(&text);
            prop_assert!(!out.chars().any(hidden));
            // Text with nothing to hide is shown as itself; each hidden character becomes
            // its code point.
            let hidden_count = text.chars().filter(|c| hidden(*c)).count();
            if hidden_count == 0 {
                prop_assert_eq!(&out, &text);
            }
            let written: usize = text.chars().filter(|c| hidden(*c)).map(|c| format!("\\u{{{:x}}}", c as u32).len()).sum();
            prop_assert_eq!(out.len(), text.len() - text.chars().filter(|c| hidden(*c)).map(char::len_utf8).sum::<usize>() + written);
        }

        /// A CSV cell holds no line break, and the cell reads back through the CSV reader
        /// as the escaped text.
        #[test]
        fn csv_cells_stay_on_one_line(text in any::<String>()) {
            let cell = csv(&text);
            prop_assert!(!cell.contains(['\n', '\r']));
            let mut writer = ::csv::Writer::from_writer(Vec::new());
            writer.write_record([&*cell, "end"]).unwrap();
            let bytes = writer.into_inner().unwrap();
            prop_assert_eq!(bytes.iter().filter(|&&b| b == b'\n').count(), 1);
            let mut reader = ::csv::ReaderBuilder::new().has_headers(false).from_reader(bytes.as_slice());
            let record = reader.records().next().unwrap().unwrap();
            prop_assert_eq!(&record[0], &*cell);
            prop_assert_eq!(&record[1], "end");
        }

        /// No CSV cell starts with a formula character unless it is a finite number; the
        /// quote comes off again exactly ([`csv_text`]) for every text without hidden
        /// characters; a number written as text stays the same text and still parses.
        #[test]
        fn csv_cells_start_no_formula_and_read_back(text in any::<String>(), start in proptest::sample::select(&FORMULA_STARTS[..]), quotes in 0usize..3, x in any::<f64>()) {
            for text in [text.clone(), format!("{start}{text}"), format!("{}{start}{text}", "'".repeat(quotes))] {
                let cell = csv(&text);
                let starts_formula = cell.starts_with(FORMULA_STARTS);
                prop_assert!(!starts_formula || cell.parse::<f64>().is_ok_and(f64::is_finite), "{cell:?}");
                if !text.chars().any(hidden) {
                    prop_assert_eq!(csv_text(&cell), text.as_str());
                }
            }
            if x.is_finite() {
                let number = x.to_string();
                prop_assert_eq!(&*csv(&number), number.as_str());
                prop_assert_eq!(csv(&number).parse::<f64>().unwrap(), x);
            }
        }

        /// Markdown text holds no line break, no raw `<`, `>` and no unescaped `|`, `[` or
        /// `]` (each is preceded by an odd number of backslashes).
        #[test]
        fn markdown_text_starts_no_syntax(text in any::<String>()) {
            let out = markdown(&text);
            prop_assert!(!out.chars().any(hidden));
            prop_assert!(!out.contains(['<', '>']));
            let chars: Vec<char> = out.chars().collect();
            for (i, c) in chars.iter().enumerate() {
                if matches!(c, '|' | '[' | ']') {
                    let backslashes = chars[..i].iter().rev().take_while(|&&b| b == '\\').count();
                    prop_assert!(backslashes % 2 == 1, "unescaped {c} at {i} in {out:?}");
                }
            }
        }

        /// XML text is made of XML 1.0 characters only, holds no markup character, and its
        /// five entities read back give the text with only the replaced characters changed.
        #[test]
        fn xml_text_is_xml_1_0(text in any::<String>()) {
            let out = xml(&text);
            prop_assert!(out.chars().all(is_xml_char), "{out:?}");
            prop_assert!(!out.contains(['<', '>', '"', '\'']));
            let expected: String = text
                .chars()
                .map(|c| match c {
                    '\u{FFFE}' | '\u{FFFF}' => '\u{FFFD}',
                    c if c.is_control() => ' ',
                    c => c,
                })
                .collect();
            let unescaped = out.replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"").replace("&apos;", "'").replace("&amp;", "&");
            prop_assert_eq!(unescaped, expected);
        }
    }
}
