//! n and k at a wavelength: the complex index of a page, the three colour channels
//! (SPEC §3), the visible-range filter (SPEC §2) and the 1 nm spectral grid the
//! reference colours integrate over (SPEC §4).

use serde::{Deserialize, Serialize};

/// Complex refractive index η = n + i k at one wavelength (k is the extinction coefficient).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Index {
    pub n: f64,
    pub k: f64,
}

impl Index {
    pub const fn new(n: f64, k: f64) -> Self {
        Self { n, k }
    }
}

/// The three channel indices of a material, in the order red, green, blue.
pub type ChannelIndex = [Index; 3];

/// Channel names in the order every per-channel array uses.
pub const CHANNEL_NAMES: [&str; 3] = ["red", "green", "blue"];

/// The channel wavelengths (SPEC §3). Configuration, not constants: every stage takes
/// a `Channels` value; `Channels::default()` is the study's 685/535/475 nm.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Channels {
    pub red_nm: f64,
    pub green_nm: f64,
    pub blue_nm: f64,
}

impl Default for Channels {
    fn default() -> Self {
        Self { red_nm: 685.0, green_nm: 535.0, blue_nm: 475.0 }
    }
}

impl Channels {
    /// Wavelengths in nm, red, green, blue.
    pub fn nanometres(&self) -> [f64; 3] {
        [self.red_nm, self.green_nm, self.blue_nm]
    }
}

/// The visible window a kept page must cover (SPEC §2), in nm.
pub const VISIBLE_NM: (f64, f64) = (390.0, 700.0);

/// The spectral grid of the reference colours (SPEC §4): 360..=830 nm in 1 nm steps.
pub const SPECTRAL_START_NM: f64 = 360.0;
pub const SPECTRAL_END_NM: f64 = 830.0;
pub const SPECTRAL_SAMPLES: usize = 471;

/// The wavelength (nm) of spectral sample `i`.
pub fn spectral_wavelength_nm(i: usize) -> f64 {
    SPECTRAL_START_NM + i as f64
}

use crate::db::{Curve, DataError, PageData, Reason};

/// Conductor or dielectric, by the README's rule: a page is a `conductor` when its k
/// reaches 1.0 or more anywhere in 390–700 nm (sampled every 5 nm and at every tabulated
/// row there), otherwise a `dielectric` (pages without k data are dielectrics, k = 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    Conductor,
    Dielectric,
}

impl Kind {
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Conductor => "conductor",
            Kind::Dielectric => "dielectric",
        }
    }
}

/// Negative k above −K_NOISE is rounding noise in the data and read as 0.
pub const K_NOISE: f64 = 1e-12;
/// The k threshold of the conductor rule.
pub const CONDUCTOR_K: f64 = 1.0;
/// A visible-range sample spacing above this (nm) flags a page as sparse.
pub const SPARSE_GAP_NM: f64 = 50.0;

/// A page that passed the visible-range filter, with its channel indices.
#[derive(Clone, Debug)]
pub struct Material {
    pub data: PageData,
    pub channels: ChannelIndex,
    pub kind: Kind,
    /// The wavelength range (nm) covered by both n and k.
    pub range_nm: (f64, f64),
    /// The largest spacing (nm) between tabulated rows over 390–700 nm (n or k,
    /// whichever is larger); `None` for formula n without tabulated k.
    pub max_visible_gap_nm: Option<f64>,
}

fn um(nm: f64) -> f64 {
    nm / 1000.0
}

/// The range (nm) a curve covers.
fn range_nm(curve: &Curve) -> (f64, f64) {
    let (lo, hi) = curve.range_um();
    (lo * 1000.0, hi * 1000.0)
}

/// n and k of a page at λ (nm): an error outside the data's range or where n ≤ 0 / k < 0.
pub fn index_at(data: &PageData, nm: f64) -> Result<Index, DataError> {
    let out_of_range = |curve: &Curve, what: &str| {
        let (lo, hi) = range_nm(curve);
        DataError::new(
            Reason::FormulaOutOfRange,
            &data.file,
            None,
            format!("{what} is defined on {lo:.1}–{hi:.1} nm; {nm} nm is outside"),
        )
    };
    let n = data.n.at(um(nm)).ok_or_else(|| out_of_range(&data.n, "n"))?;
    let k = match &data.k {
        Some(curve) => curve.at(um(nm)).ok_or_else(|| out_of_range(curve, "k"))?,
        None => 0.0,
    };
    check_index(data, nm, n, k)
}

fn check_index(data: &PageData, nm: f64, n: f64, k: f64) -> Result<Index, DataError> {
    if !(n > 0.0) {
        return Err(DataError::new(Reason::NegativeN, &data.file, None, format!("n = {n} at {nm} nm")));
    }
    // Rounding noise such as k = −5.9e−18 (main/CdS/Treharne) counts as k = 0.
    let k = if (-K_NOISE..0.0).contains(&k) { 0.0 } else { k };
    if !(k >= 0.0) {
        return Err(DataError::new(Reason::NegativeK, &data.file, None, format!("k = {k} at {nm} nm")));
    }
    Ok(Index::new(n, k))
}

/// n and k at λ with the nearest measured values held outside the data (SPEC §4).
pub fn index_held(data: &PageData, nm: f64) -> Index {
    Index::new(data.n.at_held(um(nm)), data.k.as_ref().map_or(0.0, |k| k.at_held(um(nm))))
}

/// The largest spacing between tabulated rows that overlaps `VISIBLE_NM`.
fn visible_gap_nm(samples_um: &[f64]) -> f64 {
    let (lo, hi) = VISIBLE_NM;
    samples_um
        .windows(2)
        .map(|w| (w[0] * 1000.0, w[1] * 1000.0))
        .filter(|&(a, b)| b > lo && a < hi)
        .map(|(a, b)| b - a)
        .fold(0.0, f64::max)
}

/// Wavelengths (nm) the filter checks: every 5 nm over the visible window plus every
/// tabulated row inside it.
fn visible_check_points(data: &PageData) -> Vec<f64> {
    let (lo, hi) = VISIBLE_NM;
    let mut points: Vec<f64> = (0..).map(|i| lo + 5.0 * i as f64).take_while(|&x| x <= hi).collect();
    for curve in std::iter::once(&data.n).chain(data.k.as_ref()) {
        if let Some(samples) = curve.samples_um() {
            points.extend(samples.iter().map(|s| s * 1000.0).filter(|&x| x >= lo && x <= hi));
        }
    }
    points
}

/// The visible-range filter (SPEC §2) and channel evaluation (SPEC §3): n (and k where
/// the page has k) must cover 390–700 nm, n > 0 and k ≥ 0 over it.
pub fn evaluate(data: PageData, channels: &Channels) -> Result<Material, DataError> {
    let (lo, hi) = VISIBLE_NM;
    let (n_lo, n_hi) = range_nm(&data.n);
    let (k_lo, k_hi) = data.k.as_ref().map_or((f64::NEG_INFINITY, f64::INFINITY), range_nm);
    // A small tolerance absorbs µm ↔ nm rounding (0.39 µm × 1000 = 390.00000000000006).
    const EPS: f64 = 1e-9;
    if n_lo > lo + EPS || n_hi < hi - EPS || k_lo > lo + EPS || k_hi < hi - EPS {
        let k_text = data.k.as_ref().map(|_| format!(", k {k_lo:.1}–{k_hi:.1} nm")).unwrap_or_default();
        return Err(DataError::new(
            Reason::NoVisibleCoverage,
            &data.file,
            None,
            format!("n {n_lo:.1}–{n_hi:.1} nm{k_text}; need {lo}–{hi} nm"),
        ));
    }
    let mut max_k: f64 = 0.0;
    for nm in visible_check_points(&data) {
        let index = index_at(&data, nm.clamp(lo.max(n_lo).max(k_lo), hi.min(n_hi).min(k_hi)))?;
        max_k = max_k.max(index.k);
    }
    let [r, g, b] = channels.nanometres();
    let channel_index = [index_at(&data, r)?, index_at(&data, g)?, index_at(&data, b)?];
    let gaps: Vec<f64> = std::iter::once(&data.n)
        .chain(data.k.as_ref())
        .filter_map(|c| c.samples_um().map(visible_gap_nm))
        .collect();
    Ok(Material {
        channels: channel_index,
        kind: if max_k >= CONDUCTOR_K { Kind::Conductor } else { Kind::Dielectric },
        range_nm: (n_lo.max(k_lo), n_hi.min(k_hi)),
        max_visible_gap_nm: gaps.into_iter().reduce(f64::max),
        data,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::parse_page;

    fn page(text: &str) -> PageData {
        parse_page("t.yml", text).unwrap()
    }

    #[test]
    fn channels_are_interpolated_and_kind_follows_k() {
        let data = page("DATA:\n  - type: tabulated nk\n    data: |\n        0.38 0.5 2.0\n        0.48 0.6 2.5\n        0.71 1.0 4.0\n");
        let m = evaluate(data, &Channels::default()).unwrap();
        // 685 nm: between 480 and 710 nm, t = 205/230.
        let t = 205.0 / 230.0;
        assert!((m.channels[0].n - (0.6 + t * 0.4)).abs() < 1e-12);
        assert!((m.channels[0].k - (2.5 + t * 1.5)).abs() < 1e-12);
        assert_eq!(m.kind, Kind::Conductor);
        assert!((m.max_visible_gap_nm.unwrap() - 230.0).abs() < 1e-9);
    }

    #[test]
    fn narrow_k_range_drops_the_page() {
        let data = page("DATA:\n  - type: formula 5\n    wavelength_range: 0.3 1.0\n    coefficients: 1.5\n  - type: tabulated k\n    data: |\n        0.4 0.0\n        0.8 0.0\n");
        let e = evaluate(data, &Channels::default()).unwrap_err();
        assert_eq!(e.reason, Reason::NoVisibleCoverage);
    }

    #[test]
    fn formula_with_negative_square_is_negative_n() {
        let data = page("DATA:\n  - type: formula 3\n    wavelength_range: 0.3 1.0\n    coefficients: 1.0 -8.0 2\n");
        assert_eq!(evaluate(data, &Channels::default()).unwrap_err().reason, Reason::NegativeN);
    }

    #[test]
    fn out_of_range_wavelength_names_the_range() {
        let data = page("DATA:\n  - type: formula 5\n    wavelength_range: 0.3 1.0\n    coefficients: 1.5\n");
        let e = index_at(&data, 1200.0).unwrap_err();
        assert_eq!(e.reason, Reason::FormulaOutOfRange);
        assert!(e.detail.contains("300.0–1000.0 nm"), "{}", e.detail);
        assert_eq!(index_held(&data, 1200.0), Index::new(1.5, 0.0));
    }
}
