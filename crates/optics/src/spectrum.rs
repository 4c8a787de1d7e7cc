//! n and k at a wavelength: the complex index of a page, the three colour channels
//! (SPEC §3), the coverage filter (SPEC §2: a kept page's data cover the channel
//! wavelengths, or 390–700 nm under the stricter `full` rule) and the 1 nm spectral grid
//! the reference colours integrate over (SPEC §4).

use serde::{Deserialize, Serialize};

/// Complex refractive index η = n + i k at one wavelength (k is the extinction coefficient).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Index {
    /// Refractive index n (the real part).
    pub n: f64,
    /// Extinction coefficient k (the imaginary part, ≥ 0 in absorbing media).
    pub k: f64,
}

impl Index {
    /// η = n + i k.
    pub const fn new(n: f64, k: f64) -> Self {
        Self { n, k }
    }

    /// Inside the domain every Fresnel method is tested on (n in [1e-3, 1e3], k in
    /// [0, 1e3]); otherwise what is outside, in words.
    pub fn check_domain(&self) -> Result<(), String> {
        let Index { n, k } = *self;
        if !(N_DOMAIN.0..=N_DOMAIN.1).contains(&n) || !(0.0..=K_MAX).contains(&k) {
            return Err(format!(
                "n = {n:e}, k = {k:e} lies outside the methods' domain n in [{:e}, {:e}], k in [0, {K_MAX:e}]",
                N_DOMAIN.0, N_DOMAIN.1
            ));
        }
        Ok(())
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
    /// The red channel's wavelength (nm).
    pub red_nm: f64,
    /// The green channel's wavelength (nm).
    pub green_nm: f64,
    /// The blue channel's wavelength (nm).
    pub blue_nm: f64,
}

impl Default for Channels {
    fn default() -> Self {
        Self { red_nm: 685.0, green_nm: 535.0, blue_nm: 475.0 }
    }
}

impl Channels {
    /// Channels at these wavelengths (nm), each inside the spectral grid 360–830 nm the
    /// reference colours are computed on.
    pub fn new(red_nm: f64, green_nm: f64, blue_nm: f64) -> Result<Self, String> {
        let (lo, hi) = EVALUATED_NM;
        for nm in [red_nm, green_nm, blue_nm] {
            if !(lo..=hi).contains(&nm) {
                return Err(format!("channel wavelength {nm} nm is outside {lo}-{hi} nm, the spectral range of the reference colours"));
            }
        }
        Ok(Self { red_nm, green_nm, blue_nm })
    }

    /// Wavelengths in nm, red, green, blue.
    pub fn nanometres(&self) -> [f64; 3] {
        [self.red_nm, self.green_nm, self.blue_nm]
    }

    /// "685/535/475 nm", as the tables and the report print them.
    pub fn label(&self) -> String {
        let [r, g, b] = self.nanometres();
        format!("{r}/{g}/{b} nm")
    }
}

/// Which wavelengths a kept page's data must cover (SPEC §2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Coverage {
    /// The three channel wavelengths (the default): the spectral colour holds the nearest
    /// measured value outside the data and records the extrapolated share.
    #[default]
    Channels,
    /// The whole visible window 390–700 nm (the study's rule).
    Full,
}

/// The visible window a kept page must cover (SPEC §2), in nm.
pub const VISIBLE_NM: (f64, f64) = (390.0, 700.0);

/// The spectral grid of the reference colours (SPEC §4): 360..=830 nm in 1 nm steps, the
/// widest window any stage evaluates.
pub const SPECTRAL_START_NM: f64 = EVALUATED_NM.0;
/// The last wavelength of the spectral grid (nm).
pub const SPECTRAL_END_NM: f64 = EVALUATED_NM.1;
/// The samples of the spectral grid: one per nanometre from 360 to 830 nm.
pub const SPECTRAL_SAMPLES: usize = 471;

/// The wavelength (nm) of spectral sample `i`.
pub fn spectral_wavelength_nm(i: usize) -> f64 {
    SPECTRAL_START_NM + i as f64
}

use crate::db::page::{EVALUATED_NM, K_MAX, N_DOMAIN};
use crate::db::{Curve, DataError, PageData, Reason};

/// Conductor or dielectric, by the README's rule: a page is a `conductor` when its k
/// reaches 1.0 or more anywhere in 390–700 nm (sampled every 5 nm and at every tabulated
/// row there), otherwise a `dielectric` (pages without k data are dielectrics, k = 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// k reaches [`CONDUCTOR_K`] somewhere in 390–700 nm.
    Conductor,
    /// k stays below [`CONDUCTOR_K`] over 390–700 nm (or the page has no k).
    Dielectric,
}

impl Kind {
    /// The name in tables: `conductor` or `dielectric`.
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
    /// The parsed page.
    pub data: PageData,
    /// (n, k) at the channel wavelengths, red, green, blue.
    pub channels: ChannelIndex,
    /// Conductor or dielectric.
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

/// n and k of a page at λ (nm): an error outside the data's range, where n ≤ 0 / k < 0,
/// or outside the methods' domain.
///
/// ```
/// use nklut_optics::db::parse_page;
/// use nklut_optics::spectrum::index_at;
/// let page = parse_page("x.yml", "DATA:\n  - type: tabulated nk\n    data: |\n        0.4 1.0 2.0\n        0.6 2.0 4.0\n").unwrap();
/// let at = index_at(&page, 500.0).unwrap(); // halfway between the rows, linearly
/// assert_eq!((at.n, at.k), (1.5, 3.0));
/// assert_eq!(index_at(&page, 700.0).unwrap_err().reason.code(), "outside-table-range");
/// ```
pub fn index_at(data: &PageData, nm: f64) -> Result<Index, DataError> {
    let out_of_range = |curve: &Curve, what: &str| {
        let (lo, hi) = range_nm(curve);
        let (reason, source) = match curve {
            Curve::Formula(_) => (Reason::FormulaOutOfRange, "formula"),
            Curve::Tabulated { .. } => (Reason::OutsideTableRange, "table"),
        };
        DataError::new(reason, &data.file, None, format!("the {what} {source} covers {lo:.1}–{hi:.1} nm; {nm} nm is outside it"))
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
        return Err(DataError::new(Reason::NegativeN, &data.file, None, format!("n = {} at {nm} nm", crate::db::error::number_text(n))));
    }
    // Rounding noise such as k = −5.9e−18 (main/CdS/Treharne) counts as k = 0.
    let k = if (-K_NOISE..0.0).contains(&k) { 0.0 } else { k };
    if !(k >= 0.0) {
        return Err(DataError::new(Reason::NegativeK, &data.file, None, format!("k = {} at {nm} nm", crate::db::error::number_text(k))));
    }
    let index = Index::new(n, k);
    index.check_domain().map_err(|detail| DataError::new(Reason::IndexOutOfDomain, &data.file, None, format!("{detail} at {nm} nm")))?;
    Ok(index)
}

/// n and k at λ with the nearest measured values held outside the data (SPEC §4).
pub fn index_held(data: &PageData, nm: f64) -> Index {
    Index::new(data.n.at_held(um(nm)), data.k.as_ref().map_or(0.0, |k| k.at_held(um(nm))))
}

/// The largest spacing between tabulated rows that overlaps `VISIBLE_NM`.
fn visible_gap_nm(samples_um: &[f64]) -> f64 {
    let (lo, hi) = VISIBLE_NM;
    // The spacings that overlap are one stretch of the increasing rows (×1000 keeps their
    // order): from the last row at or below lo to the first at or above hi.
    let first = samples_um.partition_point(|s| s * 1000.0 <= lo).saturating_sub(1);
    let end = (samples_um.partition_point(|s| s * 1000.0 < hi) + 1).min(samples_um.len()).max(first);
    samples_um[first..end]
        .windows(2)
        .map(|w| (w[0] * 1000.0, w[1] * 1000.0))
        .filter(|&(a, b)| b > lo && a < hi)
        .map(|(a, b)| b - a)
        .fold(0.0, f64::max)
}

/// Wavelengths (nm) the filter checks: every 5 nm over the visible window plus every
/// tabulated row inside it (n's, then k's). Each of the three runs increases.
fn visible_check_points(data: &PageData) -> impl Iterator<Item = f64> + '_ {
    let (lo, hi) = VISIBLE_NM;
    let grid = (0..).map(move |i| lo + 5.0 * i as f64).take_while(move |&x| x <= hi);
    let rows = std::iter::once(&data.n).chain(data.k.as_ref()).filter_map(Curve::samples_um).flat_map(move |samples| {
        // The rows whose wavelength in nm lies in [lo, hi]: one stretch of the increasing
        // wavelengths (×1000 keeps their order), found by two binary searches.
        let first = samples.partition_point(|s| s * 1000.0 < lo);
        let end = samples.partition_point(|s| s * 1000.0 <= hi).max(first);
        samples[first..end].iter().map(|s| s * 1000.0)
    });
    grid.chain(rows)
}

/// The rows [`index_near`] last found in n and k.
#[derive(Default)]
struct Rows {
    n: usize,
    k: usize,
}

/// [`index_at`] with each curve's row looked for from the last one found
/// ([`Curve::at_near`]): the same index, or at a point where `index_at` fails its error.
fn index_near(data: &PageData, nm: f64, rows: &mut Rows) -> Result<Index, DataError> {
    let n = data.n.at_near(um(nm), &mut rows.n);
    let k = match &data.k {
        Some(curve) => curve.at_near(um(nm), &mut rows.k),
        None => Some(0.0),
    };
    match (n, k) {
        (Some(n), Some(k)) => check_index(data, nm, n, k),
        _ => index_at(data, nm),
    }
}

/// The largest k at the visible check points, each clamped to `[visible_lo, visible_hi]`
/// (where the data meet the visible window), or the first point's error in the order of
/// [`visible_check_points`].
fn visible_max_k(data: &PageData, visible_lo: f64, visible_hi: f64) -> Result<f64, DataError> {
    let mut max_k: f64 = 0.0;
    let mut rows = Rows::default();
    for nm in visible_check_points(data).map(|nm| nm.clamp(visible_lo, visible_hi)) {
        max_k = max_k.max(index_near(data, nm, &mut rows)?.k);
    }
    Ok(max_k)
}

/// The coverage filter (SPEC §2) and channel evaluation (SPEC §3): n (and k where the
/// page has k) must cover the channel wavelengths (or 390–700 nm under
/// [`Coverage::Full`]), with n > 0 and k ≥ 0 wherever the data meet the visible window.
pub fn evaluate(data: PageData, channels: &Channels, coverage: Coverage) -> Result<Material, DataError> {
    let (n_lo, n_hi) = range_nm(&data.n);
    let (k_lo, k_hi) = data.k.as_ref().map_or((f64::NEG_INFINITY, f64::INFINITY), range_nm);
    let (lo, hi) = (n_lo.max(k_lo), n_hi.min(k_hi));
    // A small tolerance absorbs µm ↔ nm rounding (0.39 µm × 1000 = 390.00000000000006).
    const EPS: f64 = 1e-9;
    let wavelengths = channels.nanometres();
    let (need_lo, need_hi) = match coverage {
        Coverage::Channels => (wavelengths.iter().copied().fold(f64::INFINITY, f64::min), wavelengths.iter().copied().fold(0.0, f64::max)),
        Coverage::Full => VISIBLE_NM,
    };
    if lo > need_lo + EPS || hi < need_hi - EPS {
        let k_text = data.k.as_ref().map(|_| format!(", k {k_lo:.1}–{k_hi:.1} nm")).unwrap_or_default();
        let need = match coverage {
            Coverage::Channels => format!("the channel wavelengths {} need data", channels.label()),
            Coverage::Full => format!("need {}–{} nm (--visible full)", VISIBLE_NM.0, VISIBLE_NM.1),
        };
        return Err(DataError::new(Reason::NoVisibleCoverage, &data.file, None, format!("n {n_lo:.1}–{n_hi:.1} nm{k_text}; {need}")));
    }
    let mut max_k = 0.0;
    let (visible_lo, visible_hi) = (VISIBLE_NM.0.max(lo), VISIBLE_NM.1.min(hi));
    if visible_lo <= visible_hi {
        max_k = visible_max_k(&data, visible_lo, visible_hi)?;
    }
    let [r, g, b] = wavelengths;
    let channel_index = [index_at(&data, r)?, index_at(&data, g)?, index_at(&data, b)?];
    let gaps: Vec<f64> = std::iter::once(&data.n).chain(data.k.as_ref()).filter_map(|c| c.samples_um().map(visible_gap_nm)).collect();
    Ok(Material {
        channels: channel_index,
        kind: if max_k >= CONDUCTOR_K { Kind::Conductor } else { Kind::Dielectric },
        range_nm: (lo, hi),
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

    /// `visible_max_k` as it was first written: the check points collected, each looked up
    /// by [`index_at`] (a binary search per curve).
    fn visible_max_k_by_index_at(data: &PageData, visible_lo: f64, visible_hi: f64) -> Result<f64, DataError> {
        let (lo, hi) = VISIBLE_NM;
        let mut points: Vec<f64> = (0..).map(|i| lo + 5.0 * i as f64).take_while(|&x| x <= hi).collect();
        for curve in std::iter::once(&data.n).chain(data.k.as_ref()) {
            if let Some(samples) = curve.samples_um() {
                points.extend(samples.iter().map(|s| s * 1000.0).filter(|&x| x >= lo && x <= hi));
            }
        }
        let mut max_k: f64 = 0.0;
        for nm in points.into_iter().map(|nm| nm.clamp(visible_lo, visible_hi)) {
            max_k = max_k.max(index_at(data, nm)?.k);
        }
        Ok(max_k)
    }

    /// A table of `rows` rows from `start` µm in steps of `step` µm, n and k from a seed
    /// (k dips below 0, and n too, when `negative` says so).
    fn table_page(start: f64, step: f64, rows: usize, seed: u64, negative: bool) -> PageData {
        let mut state = seed;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut text = String::from("DATA:\n  - type: tabulated nk\n    data: |\n");
        for i in 0..rows {
            let (a, b) = (next(), next());
            let n = if negative && a < 0.02 { -0.5 - a } else { 0.1 + 3.0 * a };
            let k = if negative && b < 0.02 { -0.1 } else { 2.0 * b };
            text.push_str(&format!("        {} {n} {k}\n", start + step * i as f64));
        }
        page(&text)
    }

    #[test]
    fn visible_checks_by_nearby_rows_match_index_at() {
        let mut pages = vec![page("DATA:\n  - type: formula 3\n    wavelength_range: 0.3 1.0\n    coefficients: 1.0 -8.0 2\n")];
        for (seed, (start, step, rows)) in
            [(0.2, 0.001, 900), (0.38, 0.0173, 40), (0.391, 0.005, 62), (0.1, 0.3, 5), (0.45, 0.0001, 3000), (0.25, 0.05, 12)]
                .into_iter()
                .enumerate()
        {
            for negative in [false, true] {
                pages.push(table_page(start, step, rows, seed as u64, negative));
            }
        }
        // A formula n beside a tabulated k.
        pages.push(page("DATA:\n  - type: formula 2\n    wavelength_range: 0.3 2.5\n    coefficients: 0 1.0 0.01\n  - type: tabulated k\n    data: |\n        0.3 1e-8\n        0.41 -2e-13\n        0.52 0.5\n        2.5 2e-8\n"));
        for data in &pages {
            let (lo, hi) = (range_nm(&data.n).0.max(VISIBLE_NM.0), range_nm(&data.n).1.min(VISIBLE_NM.1));
            for (visible_lo, visible_hi) in [(lo, hi), (VISIBLE_NM.0, VISIBLE_NM.1), (450.0, 600.0)] {
                let ours = visible_max_k(data, visible_lo, visible_hi).map(f64::to_bits).map_err(|e| (e.reason, e.detail));
                let reference = visible_max_k_by_index_at(data, visible_lo, visible_hi).map(f64::to_bits).map_err(|e| (e.reason, e.detail));
                assert_eq!(ours, reference, "{visible_lo}-{visible_hi} nm");
            }
        }
        // The largest visible spacing, from the rows near the window, is that of all rows.
        let gap_of_all_rows = |samples: &[f64]| {
            samples
                .windows(2)
                .map(|w| (w[0] * 1000.0, w[1] * 1000.0))
                .filter(|&(a, b)| b > 390.0 && a < 700.0)
                .map(|(a, b)| b - a)
                .fold(0.0, f64::max)
        };
        let tables = pages.iter().flat_map(|d| std::iter::once(&d.n).chain(d.k.as_ref())).filter_map(Curve::samples_um);
        for samples in tables.chain([&[0.3, 0.39, 0.7, 0.8][..], &[0.39, 0.7], &[0.2, 0.3], &[0.8, 0.9], &[0.5], &[]]) {
            assert_eq!(visible_gap_nm(samples).to_bits(), gap_of_all_rows(samples).to_bits(), "{samples:?}");
        }
        // Both outcomes are covered.
        assert!(pages.iter().any(|d| visible_max_k(d, 390.0, 700.0).is_err()));
        assert!(pages.iter().any(|d| visible_max_k(d, 390.0, 700.0).is_ok_and(|k| k > 1.0)));
    }

    #[test]
    fn channels_are_interpolated_and_kind_follows_k() {
        let data = page("DATA:\n  - type: tabulated nk\n    data: |\n        0.38 0.5 2.0\n        0.48 0.6 2.5\n        0.71 1.0 4.0\n");
        let m = evaluate(data, &Channels::default(), Coverage::default()).unwrap();
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
        // k covers 400-800 nm: the channels (475-685 nm) but not 390 nm.
        assert!(evaluate(data.clone(), &Channels::default(), Coverage::Channels).is_ok());
        let e = evaluate(data, &Channels::default(), Coverage::Full).unwrap_err();
        assert_eq!(e.reason, Reason::NoVisibleCoverage);
        assert!(e.detail.contains("k 400.0–800.0 nm"), "{}", e.detail);
    }

    #[test]
    fn formula_with_negative_square_is_negative_n() {
        let data = page("DATA:\n  - type: formula 3\n    wavelength_range: 0.3 1.0\n    coefficients: 1.0 -8.0 2\n");
        assert_eq!(evaluate(data, &Channels::default(), Coverage::default()).unwrap_err().reason, Reason::NegativeN);
    }

    #[test]
    fn out_of_range_wavelength_names_the_range() {
        let data = page("DATA:\n  - type: formula 5\n    wavelength_range: 0.3 1.0\n    coefficients: 1.5\n");
        let e = index_at(&data, 1200.0).unwrap_err();
        assert_eq!(e.reason, Reason::FormulaOutOfRange);
        assert!(e.detail.contains("300.0–1000.0 nm"), "{}", e.detail);
        assert_eq!(index_held(&data, 1200.0), Index::new(1.5, 0.0));
        // A table names itself: 0 nm is outside the table, not a formula's range.
        let table = page("DATA:\n  - type: tabulated n\n    data: |\n        0.4 1.5\n        0.8 1.6\n");
        let e = index_at(&table, 0.0).unwrap_err();
        assert_eq!(e.reason, Reason::OutsideTableRange);
        assert!(e.detail.contains("table covers 400.0–800.0 nm"), "{}", e.detail);
    }

    /// Data from 450 nm cover the channels 475–685 nm but not 390 nm: kept by default,
    /// excluded under the full rule; data from 476.5 nm miss blue (475 nm) either way.
    #[test]
    fn coverage_follows_the_channels_unless_full() {
        let from_450 = "DATA:\n  - type: tabulated n\n    data: |\n        0.45 1.50\n        0.75 1.48\n";
        let m = evaluate(page(from_450), &Channels::default(), Coverage::Channels).unwrap();
        assert_eq!(m.range_nm, (450.0, 750.0));
        assert!((m.channels[2].n - (1.50 - 0.02 * 25.0 / 300.0)).abs() < 1e-12);
        let e = evaluate(page(from_450), &Channels::default(), Coverage::Full).unwrap_err();
        assert_eq!(e.reason, Reason::NoVisibleCoverage);
        let from_476 = "DATA:\n  - type: tabulated n\n    data: |\n        0.4765 1.36\n        0.75 1.35\n";
        let e = evaluate(page(from_476), &Channels::default(), Coverage::Channels).unwrap_err();
        assert_eq!(e.reason, Reason::NoVisibleCoverage);
        assert!(e.detail.contains("685/535/475 nm"), "{}", e.detail);
    }

    #[test]
    fn channel_wavelengths_stay_in_the_spectral_grid() {
        assert!(Channels::new(650.0, 550.0, 450.0).is_ok());
        assert!(Channels::new(900.0, 550.0, 450.0).unwrap_err().contains("900"));
        assert!(Channels::new(650.0, 550.0, 0.0).is_err());
    }

    #[test]
    fn indices_outside_the_methods_domain_are_named() {
        assert!(Index::new(1.5, 0.0).check_domain().is_ok());
        assert!(Index::new(1e3, 1e3).check_domain().is_ok());
        assert!(Index::new(1e20, 0.0).check_domain().is_err());
        assert!(Index::new(1.5, 2e3).check_domain().is_err());
        assert!(Index::new(1e-4, 1.0).check_domain().is_err());
        assert!(Index::new(f64::NAN, 1.0).check_domain().is_err());
    }
}
