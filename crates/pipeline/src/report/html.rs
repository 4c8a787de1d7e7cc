//! Small HTML and Markdown writers: escaping, tables, and the report's one number format
//! (errors as percentages with 3 significant digits, indices and reflectances with 4
//! decimals, colour differences with 2), shared by HTML and Markdown so tests find the
//! same text in both.

use std::fmt::Write;

/// `text` with each character for which `replacement` gives text replaced by it.
fn substituted(text: &str, replacement: impl Fn(char) -> Option<&'static str>) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match replacement(ch) {
            Some(text) => out.push_str(text),
            None => out.push(ch),
        }
    }
    out
}

/// Escape text for HTML element content and attribute values.
pub fn escape(text: &str) -> String {
    substituted(text, |ch| match ch {
        '&' => Some("&amp;"),
        '<' => Some("&lt;"),
        '>' => Some("&gt;"),
        '"' => Some("&quot;"),
        '\'' => Some("&#39;"),
        _ => None,
    })
}

/// Text with `code` spans written as `<code>` (escaped).
pub fn code_spans(text: &str) -> String {
    escape(text)
        .split('`')
        .enumerate()
        .map(|(i, part)| if i % 2 == 1 { format!("<code>{part}</code>") } else { part.to_string() })
        .collect()
}

/// A path for an `href`/`src` attribute: bytes outside `A-Z a-z 0-9 - _ . ~ /` are
/// percent-encoded, so a page id with spaces or `#` still links to its file.
pub fn href(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    for byte in path.bytes() {
        if byte.is_ascii_alphanumeric() || b"-_.~/".contains(&byte) {
            out.push(byte as char);
        } else {
            let _ = write!(out, "%{byte:02X}");
        }
    }
    out
}

/// `x` rounded to `digits` significant digits, written in plain decimals
/// (`significant(0.000123456, 3)` = "0.000123", `significant(1234.5, 3)` = "1230").
pub fn significant(x: f64, digits: i32) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let round = |v: f64| {
        let scale = 10f64.powi(digits - 1 - v.abs().log10().floor() as i32);
        (v * scale).round() / scale
    };
    let rounded = round(x);
    let decimals = (digits - 1 - rounded.abs().log10().floor() as i32).max(0) as usize;
    format!("{rounded:.decimals$}")
}

/// The smallest error the report writes as a number (a fraction; 1e-9 % below it).
pub const SMALLEST_PERCENT: f64 = 1e-9;

/// An error (a fraction) as a percentage with 3 significant digits: "12.3 %",
/// "0.0421 %", "0 %"; below 1e-9 % "< 0.000000001 %".
pub fn percent(fraction: f64) -> String {
    if !fraction.is_finite() {
        return "–".into();
    }
    let pct = fraction * 100.0;
    if pct != 0.0 && pct.abs() < SMALLEST_PERCENT {
        return "< 0.000000001 %".into();
    }
    format!("{} %", significant(pct, 3))
}

/// A refractive index n or extinction coefficient k: 4 decimals.
pub fn index(x: f64) -> String {
    fixed(x, 4)
}

/// A reflectance F (linear): 4 decimals.
pub fn reflectance(x: f64) -> String {
    fixed(x, 4)
}

/// A CIEDE2000 colour difference: 2 decimals.
pub fn delta_e(x: f64) -> String {
    fixed(x, 2)
}

/// Any other measured quantity (ns, ms, nm): 3 significant digits.
pub fn number(x: f64) -> String {
    significant(x, 3)
}

fn fixed(x: f64, decimals: usize) -> String {
    if x.is_finite() {
        format!("{x:.decimals$}")
    } else {
        "–".into()
    }
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

    /// HTML, in a box that scrolls sideways when the table is wider than the window
    /// (`.wide`); cells are escaped except those already wrapped as raw HTML by `raw`.
    pub fn html(&self, class: &str) -> String {
        let mut out = format!("<div class=\"wide\"><table class=\"{class}\"><thead><tr>");
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
        out.push_str("</tbody></table></div>\n");
        out
    }

    pub fn markdown(&self) -> String {
        let clean = |c: &str| match c.strip_prefix(MARKDOWN) {
            // Made with `markdown_text` and `href` already: no `|` or line break is left raw.
            Some(markdown) => markdown.to_string(),
            None => markdown_text(&c.strip_prefix(RAW).map(strip_tags).unwrap_or_else(|| c.to_string())),
        };
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

/// Marks a cell whose text is Markdown already (a link made with [`markdown_text`]).
pub const MARKDOWN: &str = "\u{2}md:";

/// Text as Markdown shows it and nothing more ([`crate::escape::markdown`]: markup
/// characters escaped, controls and line breaks as `\u{…}`).
pub fn markdown_text(text: &str) -> String {
    crate::escape::markdown(text)
}

pub fn raw(html: String) -> String {
    format!("{RAW}{html}")
}

fn strip_tags(html: &str) -> String {
    nklut_optics::db::page::strip_html(html)
}

/// A moment as `YYYY-MM-DD HH:MM UTC` (the civil date from days since 1970-01-01 by
/// H. Hinnant's `civil_from_days`).
pub fn utc(time: std::time::SystemTime) -> String {
    let seconds = time.duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs() as i64).unwrap_or(0);
    let (days, of_day) = (seconds.div_euclid(86_400), seconds.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z - era * 146_097;
    let year_of_era = (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let mp = (5 * day_of_year + 2) / 153;
    let day = day_of_year - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02} {:02}:{:02} UTC", of_day / 3600, of_day % 3600 / 60)
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moments_read_as_utc_dates() {
        let at = |s: u64| utc(std::time::UNIX_EPOCH + std::time::Duration::from_secs(s));
        assert_eq!(at(0), "1970-01-01 00:00 UTC");
        // 2000-02-29 12:34:56: 10 957 days to 2000-01-01, then 59 days.
        assert_eq!(at((10_957 + 59) * 86_400 + 12 * 3600 + 34 * 60 + 56), "2000-02-29 12:34 UTC");
        // `date -u -d @1796300000`: Thu Dec 3 12:13:20 UTC 2026
        assert_eq!(at(1_796_300_000), "2026-12-03 12:13 UTC");
    }

    #[test]
    fn markdown_text_shows_tags_and_brackets_as_text() {
        assert_eq!(markdown_text("<img src=x onerror=alert(1)> & [a](b)"), "&lt;img src=x onerror=alert(1)&gt; &amp; \\[a\\](b)");
        let mut t = TableText::new(&["page"]);
        t.row(vec!["<b>x</b>|y".into()]);
        t.row(vec![format!("{MARKDOWN}[{}](p.html)", markdown_text("<i>"))]);
        assert_eq!(t.markdown(), "| page |\n| --- |\n| &lt;b&gt;x&lt;/b&gt;\\|y |\n| [&lt;i&gt;](p.html) |\n");
    }

    #[test]
    fn errors_are_percent_with_three_significant_digits() {
        assert_eq!(percent(0.123456), "12.3 %");
        assert_eq!(percent(0.1029), "10.3 %");
        assert_eq!(percent(0.0006062), "0.0606 %");
        assert_eq!(percent(3.755e-6), "0.000376 %");
        assert_eq!(percent(12.345), "1230 %");
        assert_eq!(percent(0.099996), "10.0 %");
        assert_eq!(percent(0.0), "0 %");
        assert_eq!(percent(1e-13), "< 0.000000001 %");
        assert_eq!(percent(f64::NAN), "–");
    }

    #[test]
    fn indices_have_four_decimals() {
        assert_eq!(index(0.001), "0.0010");
        assert_eq!(index(100.0), "100.0000");
        assert_eq!(index(0.18344), "0.1834");
        assert_eq!(reflectance(1.02504), "1.0250");
        assert_eq!(delta_e(6.4149), "6.41");
        assert_eq!(number(25.6), "25.6");
        assert_eq!(number(0.000123456), "0.000123");
    }

    #[test]
    fn hrefs_percent_encode_what_a_url_cannot_hold() {
        assert_eq!(href("main/Au/Johnson"), "main/Au/Johnson");
        assert_eq!(href("a b#c"), "a%20b%23c");
    }

    #[test]
    fn tables_escape_and_render_markdown() {
        let mut t = TableText::new(&["a", "b"]);
        t.row(vec!["<x>".into(), raw("<span>ok</span>".into())]);
        assert!(t.html("t").contains("<td>&lt;x&gt;</td><td><span>ok</span></td>"));
        assert_eq!(t.markdown(), "| a | b |\n| --- | --- |\n| &lt;x&gt; | ok |\n");
    }
}
