//! The spectral reference curves RGB(θ) of SPEC §4 remembered between the commands of
//! one output folder: `colors`, `params` and `bake` each need a page's curve at the same
//! cosines (the angle quadrature's nodes, the texel centres), and in separate processes
//! each would sum the 421 wavelengths again. `colors`, whose product these curves are,
//! writes them; `params` and `bake` read them and compute what is missing, leaving their
//! own outputs as they were. A curve is a function of the sampled spectrum and the
//! cosines alone, so it is looked up by their bits — and only by the executable that
//! computed it (its path, size and modification time), so a rebuilt `nklut` never reads a
//! curve its predecessor computed.
//!
//! The file is `<out>/.cache/spectral-curves.bin` in the layout of [`crate::memo`]: per
//! curve, the spectrum's and the cosines' fingerprints and the RGB triples.
//!
//! Beside it, `<out>/.cache/effective-fits.bin` holds the effective channel indices
//! (`fit_effective_index`) that `colors` fits to those curves and `bake` records in its
//! manifest: a fit is a function of the channel's reference curve, its first guess and
//! the angle quadrature, so it is looked up by their bits.

use super::angle_average::AngleQuadrature;
use super::fit::{fit_effective_index, EffectiveIndex};
use super::spectral::PreparedSpectrum;
use crate::memo::{Key, Kind, Memo};
use crate::spectrum::Index;

pub use crate::memo::Fingerprint;

/// Where the memo lives under an output folder.
pub const MEMO_PATH: &str = ".cache/spectral-curves.bin";

impl Fingerprint {
    /// Of a spectrum sampled on the 1 nm grid (`sample_spectrum`).
    pub fn of_spectrum(spectrum: &[Index]) -> Self {
        Self::of(spectrum.iter().flat_map(|i| [i.n, i.k]))
    }

    /// Of a set of cosines (a quadrature's nodes).
    pub fn of_cosines(cosines: &[f64]) -> Self {
        Self::of(cosines.iter().copied())
    }
}

/// The spectral curves: a value is RGB triples.
#[derive(Debug)]
pub struct SpectralCurves;

impl Kind for SpectralCurves {
    const MAGIC: &'static [u8] = b"nklut spectral curves 1\n";
    const UNIT: usize = 3;
    const PATH: &'static str = MEMO_PATH;
    const RECORDS: &'static str = "spectral curves";
    type Value = Vec<[f64; 3]>;

    fn encode(curve: &Vec<[f64; 3]>) -> Vec<u64> {
        curve.iter().flatten().map(|v| v.to_bits()).collect()
    }

    fn decode(words: &[u64]) -> Vec<[f64; 3]> {
        words.chunks_exact(3).map(|rgb| [0, 1, 2].map(|c| f64::from_bits(rgb[c]))).collect()
    }
}

/// The remembered curves of one executable, looked up by spectrum and cosines; when it
/// records (`colors`), the ones computed since they were read. A memo that only reads
/// (`params`, `bake`) keeps nothing it computes.
pub type CurveMemo = Memo<SpectralCurves>;

impl Memo<SpectralCurves> {
    /// `spectrum.curve(cosines)` (the spectrum sampled as `sampled`), from the memo
    /// when it holds it, else computed (and kept, when recording). No cosines, no curve.
    pub fn curve(&self, sampled: Fingerprint, spectrum: &PreparedSpectrum, cosines: &[f64]) -> Vec<[f64; 3]> {
        if cosines.is_empty() {
            return Vec::new();
        }
        let at = Fingerprint::of_cosines(cosines);
        let key: Key = [sampled.0[0], sampled.0[1], at.0[0], at.0[1]];
        self.remembered(key, cosines.len(), || spectrum.curve(cosines))
    }
}

/// Where the effective fits live under an output folder.
pub const FITS_PATH: &str = ".cache/effective-fits.bin";

/// The effective channel indices: a value is one fit, its n, k and mean relative error.
#[derive(Debug)]
pub struct EffectiveFits;

impl Kind for EffectiveFits {
    const MAGIC: &'static [u8] = b"nklut effective fits 1\n";
    const UNIT: usize = 3;
    const PATH: &'static str = FITS_PATH;
    const RECORDS: &'static str = "effective fits";
    type Value = EffectiveIndex;

    fn encode(fit: &EffectiveIndex) -> Vec<u64> {
        [fit.index.n, fit.index.k, fit.error].map(f64::to_bits).to_vec()
    }

    fn decode(words: &[u64]) -> EffectiveIndex {
        let value = |i: usize| f64::from_bits(words[i]);
        EffectiveIndex { index: Index::new(value(0), value(1)), error: value(2) }
    }
}

/// The remembered effective fits of one executable; when it records (`colors`), the ones
/// fitted since they were read.
pub type EffectiveMemo = Memo<EffectiveFits>;

impl Memo<EffectiveFits> {
    /// [`fit_effective_index`] of one channel's `reference` at the nodes of `quadrature`
    /// from `start`: from the memo when it holds it, else fitted (and kept, when
    /// recording).
    pub fn effective(&self, reference: &[f64], start: Index, quadrature: &AngleQuadrature) -> EffectiveIndex {
        let problem = Fingerprint::of(reference.iter().copied().chain([start.n, start.k]));
        let rule = quadrature.fingerprint();
        let key: Key = [problem.0[0], problem.0[1], rule.0[0], rule.0[1]];
        self.remembered(key, 1, || fit_effective_index(reference, start, quadrature))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::SPECTRAL_SAMPLES;

    fn spectrum(k: f64) -> Vec<Index> {
        (0..SPECTRAL_SAMPLES).map(|i| Index::new(0.2 + i as f64 * 1e-3, k)).collect()
    }

    #[test]
    fn a_remembered_curve_has_the_bits_of_the_computed_one() {
        let cosines = crate::encoding::texel_cosines(19);
        let sampled = spectrum(3.0);
        let prepared = PreparedSpectrum::new(&sampled);
        let key = Fingerprint::of_spectrum(&sampled);
        let first = CurveMemo::new("nklut 1").recording();
        let computed = first.curve(key, &prepared, &cosines);
        assert!(first.grew());
        let second = CurveMemo::decode(&first.encode(), "nklut 1").recording();
        assert!(!second.grew());
        // Looked up with a prepared spectrum of another material: the memo answers.
        let other = PreparedSpectrum::new(&spectrum(0.0));
        let remembered = second.curve(key, &other, &cosines);
        assert!(!second.grew(), "answered from the memo");
        let bits = |c: &[[f64; 3]]| c.iter().flatten().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&remembered), bits(&computed));
        assert_eq!(bits(&computed), bits(&prepared.curve(&cosines)));
        // Other cosines are another key; no cosines, no curve and nothing recorded.
        assert!(second.curve(key, &prepared, &[]).is_empty());
        assert!(!second.grew());
        second.curve(key, &prepared, &cosines[1..]);
        assert!(second.grew());
    }

    /// A fit read back has the bits of the fit made; another first guess or another
    /// reference curve is another fit.
    #[test]
    fn a_remembered_effective_fit_has_the_bits_of_the_fit_made() {
        let quadrature = crate::color::angle_quadrature();
        let gold = Index::new(0.18, 3.0);
        let reference: Vec<f64> = quadrature.cosines.iter().map(|&c| 0.9 * crate::fresnel::exact(0.2, 3.2, c)).collect();
        let recorder = EffectiveMemo::new("nklut 1").recording();
        let fitted = recorder.effective(&reference, gold, quadrature);
        assert!(recorder.grew());
        let made = fit_effective_index(&reference, gold, quadrature);
        let bits = |f: &EffectiveIndex| [f.index.n, f.index.k, f.error].map(f64::to_bits);
        assert_eq!(bits(&fitted), bits(&made));
        let reader = EffectiveMemo::decode(&recorder.encode(), "nklut 1");
        assert_eq!(reader.len(), 1);
        assert_eq!(bits(&reader.effective(&reference, gold, quadrature)), bits(&made));
        // Another start or a curve one bit away is looked up under another key.
        let nudged: Vec<f64> =
            reference.iter().enumerate().map(|(i, &r)| if i == 3 { f64::from_bits(r.to_bits() + 1) } else { r }).collect();
        let recorder = EffectiveMemo::decode(&recorder.encode(), "nklut 1").recording();
        recorder.effective(&reference, Index::new(0.2, 3.0), quadrature);
        recorder.effective(&nudged, gold, quadrature);
        assert_eq!(recorder.recorded(), 2);
        // A memo that only reads keeps nothing it fits.
        let reader = EffectiveMemo::decode(&recorder.encode(), "nklut 1");
        reader.effective(&reference, Index::new(1.5, 0.0), quadrature);
        assert!(!reader.grew());
    }

    #[test]
    fn a_memo_that_only_reads_keeps_nothing_it_computes() {
        let cosines = [1.0, 0.5, 0.0];
        let (a, b) = (spectrum(1.0), spectrum(2.0));
        let recorder = CurveMemo::new("nklut 1").recording();
        recorder.curve(Fingerprint::of_spectrum(&a), &PreparedSpectrum::new(&a), &cosines);
        let bytes = recorder.encode();
        let reader = CurveMemo::decode(&bytes, "nklut 1");
        let computed = reader.curve(Fingerprint::of_spectrum(&b), &PreparedSpectrum::new(&b), &cosines);
        assert_eq!(computed, PreparedSpectrum::new(&b).curve(&cosines));
        assert!(!reader.grew());
        assert_eq!(reader.encode(), bytes);
    }

    #[test]
    fn another_executable_reads_no_curve() {
        let cosines = [1.0, 0.5, 0.0];
        let sampled = spectrum(1.0);
        let memo = CurveMemo::new("nklut 1").recording();
        memo.curve(Fingerprint::of_spectrum(&sampled), &PreparedSpectrum::new(&sampled), &cosines);
        let bytes = memo.encode();
        assert_eq!(CurveMemo::decode(&bytes, "nklut 1").len(), 1);
        assert!(CurveMemo::decode(&bytes, "nklut 2").is_empty());
    }

    #[test]
    fn the_same_curves_give_the_same_bytes() {
        let cosines = crate::encoding::texel_cosines(7);
        let memos = [[0.5, 2.0], [2.0, 0.5]].map(|order| {
            let memo = CurveMemo::new("x").recording();
            for k in order {
                let sampled = spectrum(k);
                memo.curve(Fingerprint::of_spectrum(&sampled), &PreparedSpectrum::new(&sampled), &cosines);
            }
            memo.encode()
        });
        assert_eq!(memos[0], memos[1]);
    }
}
