//! The page parser never panics, whatever it is fed ("no input makes the program
//! panic"), and tabulated data it accepts evaluate to finite values inside their range.

use nklut::db::parse_page;
use nklut::spectrum::{evaluate, Channels};
use proptest::prelude::*;

const BLOCK_TYPES: [&str; 6] = ["tabulated nk", "tabulated n", "tabulated k", "formula 1", "formula 4", "formula 9"];

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<f64>().prop_map(|x| x.to_string()),
        (-10.0f64..10.0).prop_map(|x| format!("{x:.4}")),
        Just("nan".to_string()),
        Just("1e400".to_string()),
        "[a-z.-]{1,4}",
    ]
}

fn row() -> impl Strategy<Value = String> {
    prop::collection::vec(number(), 0..5).prop_map(|v| v.join(" "))
}

fn page_text() -> impl Strategy<Value = String> {
    (prop::sample::select(BLOCK_TYPES.to_vec()), prop::collection::vec(row(), 0..8), row(), row()).prop_map(
        |(kind, rows, coefficients, range)| {
            let body: String = rows.iter().map(|r| format!("        {r}\n")).collect();
            format!(
                "REFERENCES: x\nDATA:\n  - type: {kind}\n    wavelength_range: {range}\n    coefficients: {coefficients}\n    data: |\n{body}"
            )
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
        let _ = parse_page("fuzz.yml", &text);
    }

    #[test]
    fn structured_pages_never_panic_and_stay_finite(text in page_text()) {
        if let Ok(page) = parse_page("fuzz.yml", &text) {
            if let Ok(material) = evaluate(page, &Channels::default(), nklut::spectrum::Coverage::default()) {
                for index in material.channels {
                    prop_assert!(index.n.is_finite() && index.n > 0.0);
                    prop_assert!(index.k.is_finite() && index.k >= 0.0);
                }
            }
        }
    }
}
