//! Small HTML and Markdown writers: escaping, tables, number formatting shared by both.

use std::fmt::Write;

/// Escape text for HTML element content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(ch),
        }
    }
    out
}

/// A number as the report prints it: 4 significant digits, scientific below 1e-3 or at
/// 1e5 and above. The same text goes to HTML and Markdown, so tests can find it.
pub fn number(x: f64) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let magnitude = x.abs();
    if !(1e-3..1e5).contains(&magnitude) {
        return format!("{x:.3e}");
    }
    let decimals = (3 - magnitude.log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

/// A fraction as a percentage with 3 significant digits ("12.3 %", "0.0421 %").
pub fn percent(fraction: f64) -> String {
    if !fraction.is_finite() {
        return "–".into();
    }
    format!("{} %", number(fraction * 100.0))
}

/// A table with a header row, as HTML and as Markdown.
#[derive(Clone, Debug, Default)]
pub struct TableText {
    pub headers: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl TableText {
    pub fn new(headers: &[&str]) -> Self {
        Self { headers: headers.iter().map(|h| h.to_string()).collect(), rows: Vec::new() }
    }

    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }

    /// HTML; cells are escaped except those already wrapped as raw HTML by `raw`.
    pub fn html(&self, class: &str) -> String {
        let mut out = format!("<table class=\"{class}\"><thead><tr>");
        for h in &self.headers {
            let _ = write!(out, "<th>{}</th>", escape(h));
        }
        out.push_str("</tr></thead><tbody>\n");
        for row in &self.rows {
            out.push_str("<tr>");
            for cell in row {
                match cell.strip_prefix(RAW) {
                    Some(raw) => {
                        let _ = write!(out, "<td>{raw}</td>");
                    }
                    None => {
                        let _ = write!(out, "<td>{}</td>", escape(cell));
                    }
                }
            }
            out.push_str("</tr>\n");
        }
        out.push_str("</tbody></table>\n");
        out
    }

    pub fn markdown(&self) -> String {
        let clean = |c: &str| c.strip_prefix(RAW).map(strip_tags).unwrap_or_else(|| c.to_string()).replace('|', "\\|");
        let mut out = format!("| {} |\n", self.headers.iter().map(|h| clean(h)).collect::<Vec<_>>().join(" | "));
        out.push_str(&format!("|{}\n", " --- |".repeat(self.headers.len())));
        for row in &self.rows {
            out.push_str(&format!("| {} |\n", row.iter().map(|c| clean(c)).collect::<Vec<_>>().join(" | ")));
        }
        out
    }
}

/// Marks a cell whose text is HTML already (a swatch); Markdown gets its text only.
pub const RAW: &str = "\u{1}raw:";

pub fn raw(html: String) -> String {
    format!("{RAW}{html}")
}

fn strip_tags(html: &str) -> String {
    crate::db::page::strip_html(html)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_four_significant_digits() {
        assert_eq!(number(0.123456), "0.1235");
        assert_eq!(number(12.3456), "12.35");
        assert_eq!(number(1234.5), "1234");
        assert_eq!(number(0.00012345), "1.234e-4");
        assert_eq!(percent(0.0123), "1.230 %");
    }

    #[test]
    fn tables_escape_and_render_markdown() {
        let mut t = TableText::new(&["a", "b"]);
        t.row(vec!["<x>".into(), raw("<span>ok</span>".into())]);
        assert!(t.html("t").contains("<td>&lt;x&gt;</td><td><span>ok</span></td>"));
        assert_eq!(t.markdown(), "| a | b |\n| --- | --- |\n| <x> | ok |\n");
    }
}
