//! The number format of tables whose columns the report does not know in advance (the
//! engine-parameter panel of material pages, the effects page's tables).

use super::html::{delta_e, number, percent};

/// A cell of a table whose columns the report does not know in advance, in the report's
/// number format by the column's name: relative errors as percent, ΔE with 2 decimals,
/// other numbers with 3 significant digits, text as is.
pub fn cell(column: &str, text: &str) -> String {
    let Ok(value) = text.parse::<f64>() else { return text.to_string() };
    let column = column.to_ascii_lowercase();
    if column.contains("delta_e") || column.contains("de2000") {
        delta_e(value)
    } else if column.contains("rel_error") || column.ends_with("_rel") {
        percent(value)
    } else if text.contains('.') || text.contains('e') {
        number(value)
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_tables_follow_the_number_format() {
        assert_eq!(cell("mean_rel_error", "0.0123456"), "1.23 %");
        assert_eq!(cell("mean_delta_e2000", "1.23456"), "1.23");
        assert_eq!(cell("median_ms", "0.123456"), "0.123");
        assert_eq!(cell("passes", "3"), "3");
        assert_eq!(cell("mesh", "bunny"), "bunny");
    }
}
