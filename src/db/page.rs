//! One data file of the database (a "page"): its DATA blocks turned into an n curve and
//! an optional k curve, plus the metadata the outputs carry (SPEC §1).

use serde::Deserialize;

use super::error::{DataError, Reason};
use super::formula::{max_coefficients, Formula};

/// n(λ) or k(λ) over a wavelength range, λ in µm.
#[derive(Clone, Debug, PartialEq)]
pub enum Curve {
    /// Rows of (λ, value), λ strictly increasing; linear interpolation between rows.
    Tabulated { wavelengths_um: Vec<f64>, values: Vec<f64> },
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
        let (lo, hi) = self.range_um();
        if !(um >= lo && um <= hi) {
            return None;
        }
        Some(match self {
            Curve::Formula(f) => f.refractive_index(um),
            Curve::Tabulated { wavelengths_um: x, values: y } => {
                let i = x.partition_point(|&w| w <= um);
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

/// A printed property value and its number of decimals (e.g. `nd: 1.523` → 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Printed {
    pub value: f64,
    pub decimals: usize,
}

/// A parsed data file.
#[derive(Clone, Debug, PartialEq)]
pub struct PageData {
    /// Path relative to `database/data/`.
    pub file: String,
    pub n: Curve,
    pub k: Option<Curve>,
    /// First line of REFERENCES, HTML tags removed.
    pub reference: String,
    /// `PROPERTIES.nd`, the index at the d line (587.5618 nm), as printed.
    pub nd: Option<Printed>,
    /// `PROPERTIES.Vd`, the Abbe number, as printed.
    pub vd: Option<Printed>,
}

#[derive(Deserialize)]
struct RawPage {
    #[serde(rename = "REFERENCES", default)]
    references: Option<serde_yaml::Value>,
    #[serde(rename = "DATA", default)]
    data: Option<Vec<RawBlock>>,
}

#[derive(Deserialize)]
struct RawBlock {
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    data: Option<serde_yaml::Value>,
    #[serde(default)]
    coefficients: Option<serde_yaml::Value>,
    #[serde(default)]
    wavelength_range: Option<serde_yaml::Value>,
}

/// A YAML scalar as text (numbers and strings alike).
fn scalar_text(value: &serde_yaml::Value) -> Option<String> {
    match value {
        serde_yaml::Value::String(s) => Some(s.clone()),
        serde_yaml::Value::Number(n) => Some(n.to_string()),
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

/// 1-based line numbers of the `data:` keys of the DATA blocks, in file order, so that
/// row i of the j-th tabulated block is at line `data_lines[j] + 1 + i`.
fn data_key_lines(text: &str) -> Vec<usize> {
    text.lines()
        .enumerate()
        .filter(|(_, line)| {
            let t = line.trim_start();
            t.starts_with("data:") && line.len() - t.len() >= 2
        })
        .map(|(i, _)| i + 1)
        .collect()
}

/// `PROPERTIES.<key>` as printed in the text (decimals matter for the nd check).
fn printed_property(text: &str, key: &str) -> Option<Printed> {
    let mut in_properties = false;
    for line in text.lines() {
        if !line.starts_with(' ') && !line.is_empty() {
            in_properties = line.starts_with("PROPERTIES:");
            continue;
        }
        let trimmed = line.trim_start();
        // Direct children of PROPERTIES only (4 spaces in the database's layout, any > 0 here).
        if in_properties && trimmed.starts_with(key) && trimmed[key.len()..].starts_with(':') {
            let raw = trimmed[key.len() + 1..].trim();
            let value: f64 = raw.parse().ok()?;
            let decimals = raw.split_once('.').map(|(_, d)| d.chars().take_while(|c| c.is_ascii_digit()).count()).unwrap_or(0);
            return Some(Printed { value, decimals });
        }
    }
    None
}

/// Parse rows of `columns` numbers each. λ must strictly increase.
fn parse_rows(file: &str, block: &str, columns: usize, first_line: Option<usize>) -> Result<Vec<Vec<f64>>, DataError> {
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for (i, line) in block.lines().enumerate() {
        let line_no = first_line.map(|l| l + i);
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        if fields.len() != columns {
            return Err(DataError::new(
                Reason::BadRow,
                file,
                line_no,
                format!("expected {columns} numbers, found {}: {:?}", fields.len(), line.trim()),
            ));
        }
        let mut row = Vec::with_capacity(columns);
        for field in fields {
            match field.parse::<f64>() {
                Ok(x) if x.is_finite() => row.push(x),
                _ => return Err(DataError::new(Reason::BadRow, file, line_no, format!("not a finite number: {field:?}"))),
            }
        }
        if let Some(previous) = rows.last() {
            if row[0] <= previous[0] {
                return Err(DataError::new(
                    Reason::NonMonotonicWavelengths,
                    file,
                    line_no,
                    format!("wavelength {} µm follows {} µm", row[0], previous[0]),
                ));
            }
        }
        if row[0] <= 0.0 {
            return Err(DataError::new(Reason::BadRow, file, line_no, format!("wavelength {} µm is not positive", row[0])));
        }
        rows.push(row);
    }
    if rows.is_empty() {
        return Err(DataError::new(Reason::NoData, file, first_line, "tabulated block has no rows"));
    }
    Ok(rows)
}

fn column(rows: &[Vec<f64>], i: usize) -> Vec<f64> {
    rows.iter().map(|r| r[i]).collect()
}

fn parse_formula(file: &str, number: u8, block: &RawBlock) -> Result<Formula, DataError> {
    let text = block.coefficients.as_ref().and_then(scalar_text).unwrap_or_default();
    let mut coefficients = Vec::new();
    for field in text.split_whitespace() {
        match field.parse::<f64>() {
            Ok(x) if x.is_finite() => coefficients.push(x),
            _ => return Err(DataError::new(Reason::ParseError, file, None, format!("formula {number}: coefficient {field:?} is not a number"))),
        }
    }
    if coefficients.is_empty() {
        return Err(DataError::new(Reason::TooFewCoefficients, file, None, format!("formula {number} has no coefficients")));
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
    let range: Vec<f64> = range_text.split_whitespace().filter_map(|f| f.parse().ok()).collect();
    if range.len() != 2 || !(range[0] > 0.0 && range[1] > range[0]) {
        return Err(DataError::new(
            Reason::TooFewCoefficients,
            file,
            None,
            format!("formula {number}: wavelength_range {range_text:?} is not two increasing positive numbers"),
        ));
    }
    Ok(Formula { number, coefficients, range_um: (range[0], range[1]) })
}

/// Parse one data file's text. `file` is its path relative to `database/data/`, used in
/// errors. Never panics on any input (a property test feeds it arbitrary text).
pub fn parse_page(file: &str, text: &str) -> Result<PageData, DataError> {
    let raw: RawPage = serde_yaml::from_str(text).map_err(|e| {
        DataError::new(Reason::ParseError, file, e.location().map(|l| l.line()), e.to_string())
    })?;
    let blocks = raw.data.ok_or_else(|| DataError::new(Reason::NoData, file, None, "no DATA section"))?;
    let data_lines = data_key_lines(text);
    let mut data_block_index = 0;
    let mut n: Option<Curve> = None;
    let mut k: Option<Curve> = None;
    let set = |slot: &mut Option<Curve>, curve: Curve, what: &str| -> Result<(), DataError> {
        if slot.is_some() {
            return Err(DataError::new(Reason::ParseError, file, None, format!("more than one {what} block")));
        }
        *slot = Some(curve);
        Ok(())
    };
    for block in &blocks {
        let kind = block.kind.trim();
        if let Some(columns) = match kind {
            "tabulated nk" => Some(3),
            "tabulated n" | "tabulated k" => Some(2),
            _ => None,
        } {
            let first_line = data_lines.get(data_block_index).map(|l| l + 1);
            data_block_index += 1;
            let body = block.data.as_ref().and_then(scalar_text).ok_or_else(|| {
                DataError::new(Reason::ParseError, file, first_line.map(|l| l - 1), format!("{kind} block has no data text"))
            })?;
            let rows = parse_rows(file, &body, columns, first_line)?;
            let wavelengths_um = column(&rows, 0);
            let tabulated = |i| Curve::Tabulated { wavelengths_um: wavelengths_um.clone(), values: column(&rows, i) };
            match kind {
                // A formula n followed by tabulated nk (e.g. organic/PVP/Konig): the
                // formula stays the n source and the table supplies k, as on the site.
                "tabulated nk" if matches!(n, Some(Curve::Formula(_))) => set(&mut k, tabulated(2), "k")?,
                "tabulated nk" => {
                    set(&mut n, tabulated(1), "n")?;
                    set(&mut k, tabulated(2), "k")?;
                }
                "tabulated n" => set(&mut n, tabulated(1), "n")?,
                _ => set(&mut k, tabulated(1), "k")?,
            }
        } else if let Some(number) = kind.strip_prefix("formula ").and_then(|d| d.trim().parse::<u8>().ok()).filter(|d| (1..=9).contains(d)) {
            if block.data.is_some() {
                data_block_index += 1;
            }
            set(&mut n, Curve::Formula(parse_formula(file, number, block)?), "n")?;
        } else {
            return Err(DataError::new(Reason::UnknownBlockType, file, None, format!("block type {kind:?}")));
        }
    }
    let n = n.ok_or_else(|| DataError::new(Reason::NoData, file, None, "no n data (only k)"))?;
    let reference = raw
        .references
        .as_ref()
        .and_then(scalar_text)
        .and_then(|r| r.lines().map(strip_html).find(|l| !l.is_empty()))
        .unwrap_or_default();
    Ok(PageData {
        file: file.to_string(),
        n,
        k,
        reference,
        nd: printed_property(text, "nd"),
        vd: printed_property(text, "Vd"),
    })
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
        assert_eq!(reason("DATA:\n  - type: formula 8\n    wavelength_range: 0.3 2\n    coefficients: 1 2 3 4 5\n").0, Reason::TooManyCoefficients);
        assert_eq!(reason("DATA:\n  - type: tabulated k\n    data: |\n        0.4 1.5\n").0, Reason::NoData);
        assert_eq!(reason("REFERENCES: x\n").0, Reason::NoData);
    }
}
