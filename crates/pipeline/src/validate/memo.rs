//! The error integrals of `validate` remembered between its runs into one output folder,
//! in `<out>/.cache/error-integrals.bin` (the layout of [`nklut_optics::memo`]). A family's
//! integrals are a function of the channel index, the family's members and the strategy
//! alone (the tolerances belong to the executable, which the memo names), so they are
//! looked up by those bits: a re-run measures only the indices it has not met, and its
//! figures have the bits of a measurement. With them is remembered the time their
//! measurement took, which the `seconds` column of a remembered row reports.

use super::quadrature::{Figures, Integral};
use super::{Strategy, Variant};
use nklut_optics::fresnel::{Encoding, Method, PerPrecision};
use nklut_optics::memo::{Fingerprint, Key, Kind, Memo};
use nklut_optics::spectrum::Index;

/// Where the memo lives under an output folder.
pub const MEMO_PATH: &str = ".cache/error-integrals.bin";

/// Per precision: whether there is a mean relative error, its bits, the maximum's and
/// the RMS's; then the excluded samples and the evaluations.
const MEMBER_WORDS: usize = 10;

/// A family's measurement: each member's integral, and the wall time of the family's
/// integration divided by its members.
#[derive(Clone, Debug, PartialEq)]
pub struct FamilyMeasurement {
    pub integrals: Vec<Integral>,
    pub seconds: f64,
}

/// The error integrals: a value is one word of seconds, then [`MEMBER_WORDS`] per member.
#[derive(Debug)]
pub struct ErrorIntegrals;

impl Kind for ErrorIntegrals {
    const MAGIC: &'static [u8] = b"nklut error integrals 1\n";
    const UNIT: usize = 1;
    const PATH: &'static str = MEMO_PATH;
    const RECORDS: &'static str = "error integrals";
    type Value = FamilyMeasurement;

    fn encode(measured: &FamilyMeasurement) -> Vec<u64> {
        let mut words = vec![measured.seconds.to_bits()];
        for integral in &measured.integrals {
            for figures in [integral.figures.f64, integral.figures.f32] {
                words.extend([
                    u64::from(figures.mean_rel_error.is_some()),
                    figures.mean_rel_error.unwrap_or(0.0).to_bits(),
                    figures.max_abs_error.to_bits(),
                    figures.rms_abs_error.to_bits(),
                ]);
            }
            words.extend([integral.excluded_samples, integral.evaluations]);
        }
        words
    }

    fn decode(words: &[u64]) -> FamilyMeasurement {
        let figures = |w: &[u64]| Figures {
            mean_rel_error: (w[0] != 0).then(|| f64::from_bits(w[1])),
            max_abs_error: f64::from_bits(w[2]),
            rms_abs_error: f64::from_bits(w[3]),
        };
        let integrals = words[1..]
            .chunks_exact(MEMBER_WORDS)
            .map(|w| Integral {
                figures: PerPrecision { f64: figures(&w[0..4]), f32: figures(&w[4..8]) },
                excluded_samples: w[8],
                evaluations: w[9],
            })
            .collect();
        FamilyMeasurement { integrals, seconds: f64::from_bits(words[0]) }
    }
}

/// The remembered integrals of one executable; when recording, the ones measured since
/// they were read.
pub type IntegralMemo = Memo<ErrorIntegrals>;

/// What validate asks of its memo: families by their index, members and strategy.
pub trait Families {
    /// The family `members` on `index` with `strategy`, from the memo when it holds it,
    /// else from `measure` (and kept, when recording).
    fn family(
        &self,
        index: Index,
        members: &[Variant],
        strategy: Strategy,
        measure: impl FnOnce() -> FamilyMeasurement,
    ) -> FamilyMeasurement;

    /// Families measured and recorded since the memo was read (0 when it does not
    /// record).
    fn measured(&self) -> usize;
}

impl Families for Memo<ErrorIntegrals> {
    fn family(
        &self,
        index: Index,
        members: &[Variant],
        strategy: Strategy,
        measure: impl FnOnce() -> FamilyMeasurement,
    ) -> FamilyMeasurement {
        self.remembered(key(index, members, strategy), 1 + MEMBER_WORDS * members.len(), measure)
    }

    fn measured(&self) -> usize {
        self.recorded()
    }
}

/// The index's bits, and a fingerprint of the strategy and the members in order.
fn key(index: Index, members: &[Variant], strategy: Strategy) -> Key {
    let strategy = match strategy {
        Strategy::Fast => 0,
        Strategy::Brute(samples) => 1 + samples as u64,
    };
    let position = |found: Option<usize>| found.map_or(0, |p| 1 + p as u64);
    let words = members.iter().flat_map(|variant| {
        [
            position(Method::ALL.iter().position(|m| *m == variant.method)),
            variant.lut.map_or(0, |spec| spec.texels as u64),
            position(variant.lut.and_then(|spec| Encoding::ALL.iter().position(|e| *e == spec.encoding))),
        ]
    });
    let Fingerprint([a, b]) = Fingerprint::of_words(std::iter::once(strategy).chain(words));
    [index.n.to_bits(), index.k.to_bits(), a, b]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validate::Family;
    use nklut_optics::fresnel::{LutSpec, Prepared};

    fn lut(texels: usize) -> Vec<Variant> {
        Encoding::ALL.iter().map(|&e| Variant { method: Method::Lut, lut: Some(LutSpec::new(texels, e)) }).collect()
    }

    fn measure(index: Index, members: &[Variant]) -> FamilyMeasurement {
        FamilyMeasurement { integrals: Family::new(Prepared::new(index), members).measure(Strategy::Fast), seconds: 0.25 }
    }

    #[test]
    fn remembered_integrals_have_the_bits_of_the_measured_ones() {
        let analytic = Variant::expand(&[Method::Schlick, Method::Nvidia, Method::SchlickCompensated]);
        // A metal, glass, and vacuum (no mean relative error: F_exact = 0 throughout).
        let cases = [(Index::new(0.18, 3.4), lut(16)), (Index::new(1.5, 0.0), analytic.clone()), (Index::new(1.0, 0.0), analytic)];
        let first = IntegralMemo::new("nklut 1").recording();
        let measured: Vec<FamilyMeasurement> =
            cases.iter().map(|(index, members)| first.family(*index, members, Strategy::Fast, || measure(*index, members))).collect();
        assert_eq!(first.measured(), cases.len());
        assert_eq!(measured[2].integrals[0].figures.f64.mean_rel_error, None);
        let second = IntegralMemo::decode(&first.encode(), "nklut 1").recording();
        for ((index, members), measured) in cases.iter().zip(&measured) {
            let remembered = second.family(*index, members, Strategy::Fast, || panic!("measured again: {index:?}"));
            assert_eq!(format!("{remembered:?}"), format!("{measured:?}"));
            assert_eq!(ErrorIntegrals::encode(&remembered), ErrorIntegrals::encode(measured), "the same bits");
        }
        assert_eq!((second.measured(), second.asked()), (0, cases.len()));
        // Another executable remembers nothing.
        let other = IntegralMemo::decode(&first.encode(), "nklut 2");
        let (index, members) = &cases[0];
        assert_eq!(other.family(*index, members, Strategy::Fast, || measure(*index, members)).seconds, 0.25);
    }

    #[test]
    fn a_family_is_remembered_for_its_index_members_and_strategy_only() {
        let glass = Index::new(1.5, 0.0);
        let base = key(glass, &lut(64), Strategy::Fast);
        let mut reordered = lut(64);
        reordered.swap(0, 1);
        let mut one_bit = glass;
        one_bit.n = f64::from_bits(glass.n.to_bits() + 1);
        let others = [
            key(Index::new(1.5, -0.0), &lut(64), Strategy::Fast),
            key(one_bit, &lut(64), Strategy::Fast),
            key(glass, &lut(128), Strategy::Fast),
            key(glass, &lut(64)[..4], Strategy::Fast),
            key(glass, &reordered, Strategy::Fast),
            key(glass, &lut(64), Strategy::Brute(1000)),
            key(glass, &Variant::expand(&[Method::Schlick]), Strategy::Fast),
            key(glass, &Variant::expand(&[Method::SchlickNk]), Strategy::Fast),
        ];
        for other in others {
            assert_ne!(other, base);
        }
        assert_eq!(key(glass, &lut(64), Strategy::Fast), base);
    }
}
