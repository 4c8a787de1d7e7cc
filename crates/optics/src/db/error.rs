//! Named errors for bad data (SPEC §2 reason codes). Every excluded page carries one.

use std::fmt;

/// Why a page was excluded. `code()` is the stable string written to `excluded.csv`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Reason {
    /// The catalog names a data file that does not exist or cannot be read.
    MissingFile,
    /// The file is not valid YAML or its DATA section has the wrong shape.
    ParseError,
    /// A DATA block type other than tabulated nk/n/k or formula 1-9.
    UnknownBlockType,
    /// A tabulated row is short, long or not numeric.
    BadRow,
    /// Tabulated wavelengths do not strictly increase.
    NonMonotonicWavelengths,
    /// A formula has no coefficients or no valid wavelength_range.
    TooFewCoefficients,
    /// A formula has more coefficients than its definition uses.
    TooManyCoefficients,
    /// A wavelength outside the data's range was asked for.
    FormulaOutOfRange,
    /// N <= 0 (or n² < 0 from a formula) where it is evaluated.
    NegativeN,
    /// K < 0 where it is evaluated.
    NegativeK,
    /// The page has no n data.
    NoData,
    /// The n (or k) data do not cover the channel wavelengths (or 390-700 nm with --visible full).
    NoVisibleCoverage,
    /// The catalog lists this page id again with a different data file.
    DuplicatePageId,
    /// The catalog entry names no data file (no data key, or an empty one).
    NoDataFile,
    /// The data path is absolute or leaves the database's data folder.
    PathOutsideDatabase,
    /// The data file is not UTF-8 text (e.g. Latin-1).
    NotUtf8,
    /// A formula's coefficients end in half of a term (a weight without its pole or exponent).
    IncompleteTerm,
    /// A wavelength outside the tabulated data's range was asked for.
    OutsideTableRange,
    /// N or k outside the domain the Fresnel methods are tested on (n in [1e-3, 1e3], k in [0, 1e3]).
    IndexOutOfDomain,
    /// A shelf, book or page id in the catalog is empty, '.' or '..', or contains '/' or a control character.
    BadPageId,
    /// The data path names a FIFO, a device, a socket or a folder, not a regular file.
    NotAFile,
    /// The data file is larger than the most read from one (64 MiB).
    FileTooLarge,
    /// The file's YAML nests deeper than 64 levels.
    NestingTooDeep,
    /// A catalog entry whose SHELF, BOOK or PAGE is not a single value, or a book's entry that is neither PAGE nor DIVIDER.
    BadCatalogEntry,
    /// A tabulated wavelength or a formula's wavelength_range outside 1e-9 to 1e8 µm (1 fm to 100 m).
    WavelengthOutOfRange,
}

impl Reason {
    /// Every reason, in the order of SPEC §2.
    pub const ALL: [Reason; 25] = [
        Reason::MissingFile,
        Reason::ParseError,
        Reason::UnknownBlockType,
        Reason::BadRow,
        Reason::NonMonotonicWavelengths,
        Reason::TooFewCoefficients,
        Reason::TooManyCoefficients,
        Reason::FormulaOutOfRange,
        Reason::NegativeN,
        Reason::NegativeK,
        Reason::NoData,
        Reason::NoVisibleCoverage,
        Reason::DuplicatePageId,
        Reason::NoDataFile,
        Reason::PathOutsideDatabase,
        Reason::NotUtf8,
        Reason::IncompleteTerm,
        Reason::OutsideTableRange,
        Reason::IndexOutOfDomain,
        Reason::BadPageId,
        Reason::NotAFile,
        Reason::FileTooLarge,
        Reason::NestingTooDeep,
        Reason::BadCatalogEntry,
        Reason::WavelengthOutOfRange,
    ];

    /// The stable code written to `excluded.csv` (`missing-file`, …).
    pub fn code(self) -> &'static str {
        match self {
            Reason::MissingFile => "missing-file",
            Reason::ParseError => "parse-error",
            Reason::UnknownBlockType => "unknown-block-type",
            Reason::BadRow => "bad-row",
            Reason::NonMonotonicWavelengths => "non-monotonic-wavelengths",
            Reason::TooFewCoefficients => "too-few-coefficients",
            Reason::TooManyCoefficients => "too-many-coefficients",
            Reason::FormulaOutOfRange => "formula-out-of-range",
            Reason::NegativeN => "negative-n",
            Reason::NegativeK => "negative-k",
            Reason::NoData => "no-data",
            Reason::NoVisibleCoverage => "no-visible-coverage",
            Reason::DuplicatePageId => "duplicate-page-id",
            Reason::NoDataFile => "no-data-file",
            Reason::PathOutsideDatabase => "path-outside-database",
            Reason::NotUtf8 => "not-utf8",
            Reason::IncompleteTerm => "incomplete-formula-term",
            Reason::OutsideTableRange => "outside-table-range",
            Reason::IndexOutOfDomain => "index-out-of-domain",
            Reason::BadPageId => "bad-page-id",
            Reason::NotAFile => "not-a-regular-file",
            Reason::FileTooLarge => "file-too-large",
            Reason::NestingTooDeep => "nesting-too-deep",
            Reason::BadCatalogEntry => "bad-catalog-entry",
            Reason::WavelengthOutOfRange => "wavelength-out-of-range",
        }
    }

    /// What each code means, for the README and the report.
    pub fn meaning(self) -> &'static str {
        match self {
            Reason::MissingFile => "the catalog names a data file that does not exist or cannot be read",
            Reason::ParseError => "the file is not valid YAML or its DATA section has the wrong shape",
            Reason::UnknownBlockType => "a DATA block type other than tabulated nk/n/k or formula 1-9",
            Reason::BadRow => "a tabulated row is short, long or not numeric",
            Reason::NonMonotonicWavelengths => "tabulated wavelengths do not strictly increase",
            Reason::TooFewCoefficients => "a formula has no coefficients or no valid wavelength_range",
            Reason::TooManyCoefficients => "a formula has more coefficients than its definition uses",
            Reason::FormulaOutOfRange => "a wavelength outside the data's range was asked for",
            Reason::NegativeN => "n <= 0 (or n^2 < 0 from a formula) where it is evaluated",
            Reason::NegativeK => "k < 0 where it is evaluated",
            Reason::NoData => "the page has no n data",
            Reason::NoVisibleCoverage => "the n (or k) data do not cover the channel wavelengths (or 390-700 nm with --visible full)",
            Reason::DuplicatePageId => "the catalog lists this page id again with a different data file",
            Reason::NoDataFile => "the catalog entry names no data file (no data key, or an empty one)",
            Reason::PathOutsideDatabase => "the data path is absolute or leaves the database's data folder",
            Reason::NotUtf8 => "the data file is not UTF-8 text (e.g. Latin-1)",
            Reason::IncompleteTerm => "a formula's coefficients end in half of a term (a weight without its pole or exponent)",
            Reason::OutsideTableRange => "a wavelength outside the tabulated data's range was asked for",
            Reason::IndexOutOfDomain => "n or k outside the domain the Fresnel methods are tested on (n in [1e-3, 1e3], k in [0, 1e3])",
            Reason::BadPageId => "a shelf, book or page id in the catalog is empty, '.' or '..', or contains '/' or a control character",
            Reason::NotAFile => "the data path names a FIFO, a device, a socket or a folder, not a regular file",
            Reason::FileTooLarge => "the data file is larger than the most read from one (64 MiB)",
            Reason::NestingTooDeep => "the file's YAML nests deeper than 64 levels",
            Reason::BadCatalogEntry => {
                "a catalog entry whose SHELF, BOOK or PAGE is not a single value, or a book's entry that is neither PAGE nor DIVIDER"
            }
            Reason::WavelengthOutOfRange => "a tabulated wavelength or a formula's wavelength_range outside 1e-9 to 1e8 µm (1 fm to 100 m)",
        }
    }
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.code())
    }
}

/// A number as a detail shows it: plainly within 1e-6..1e16 in magnitude (and 0), in
/// exponent form beyond (−1e308 as `-1e308`, not 309 digits).
pub fn number_text(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-6..1e16).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A data error: the reason, the data file (relative to `database/data/`), the line in
/// that file where there is one, and a human-readable detail.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{reason} in {file}{}: {detail}", line.map(|l| format!(" line {l}")).unwrap_or_default())]
pub struct DataError {
    /// What is wrong.
    pub reason: Reason,
    /// The data file, relative to `database/data/`.
    pub file: String,
    /// The line of the file, where there is one.
    pub line: Option<usize>,
    /// What is wrong, in words.
    pub detail: String,
}

impl DataError {
    /// An error of `reason` in `file` (at `line`), with `detail`.
    pub fn new(reason: Reason, file: &str, line: Option<usize>, detail: impl Into<String>) -> Self {
        Self { reason, file: file.to_string(), line, detail: detail.into() }
    }
}
