//! The `nvidia` fits (SPEC §5.6) remembered between the commands run into one output
//! folder, in `<out>/.cache/nvidia-fits.bin` (the layout of [`crate::memo`]). A fit is a
//! function of the sanitised channel index alone, so it is looked up by the index's bits:
//! `validate` fits every channel index it measures and keeps the fits, and `report`, which
//! draws the `nvidia` curve of every page, reads them instead of fitting again. A fit read
//! back has the bits of the one made.

use super::methods::nvidia::Nvidia;
use super::nvidia::{fit_nvidia, NvidiaFit};
use super::{sanitise, Prepared};
use crate::memo::{Key, Kind, Memo};
use crate::spectrum::Index;

/// Where the memo lives under an output folder.
pub const MEMO_PATH: &str = ".cache/nvidia-fits.bin";

/// The `nvidia` fits: a value is one fit, its bias, scale, power and RMS residual.
#[derive(Debug)]
pub struct NvidiaFits;

impl Kind for NvidiaFits {
    const MAGIC: &'static [u8] = b"nklut nvidia fits 1\n";
    const UNIT: usize = 4;
    const PATH: &'static str = MEMO_PATH;
    const RECORDS: &'static str = "nvidia fits";
    type Value = NvidiaFit;

    fn encode(fit: &NvidiaFit) -> Vec<u64> {
        [fit.bias, fit.scale, fit.power, fit.rms_residual].map(f64::to_bits).to_vec()
    }

    fn decode(words: &[u64]) -> NvidiaFit {
        let value = |i: usize| f64::from_bits(words[i]);
        NvidiaFit { bias: value(0), scale: value(1), power: value(2), rms_residual: value(3) }
    }
}

/// The remembered fits of one executable; when recording, the ones made since they were
/// read.
pub type FitMemo = Memo<NvidiaFits>;

impl Memo<NvidiaFits> {
    /// [`Prepared::new`] of `index`, its `nvidia` fit from the memo when it holds it,
    /// else fitted (and kept, when recording).
    pub fn prepared(&self, index: Index) -> Prepared {
        let key = key(sanitise(index));
        let prepared = Prepared::new(index);
        let fit = self.remembered(key, 1, || fit_nvidia(&prepared.exact));
        prepared.with_params::<Nvidia>(fit)
    }
}

/// The sanitised index's bits.
fn key(index: Index) -> Key {
    [index.n.to_bits(), index.k.to_bits(), 0, 0]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bits(prepared: &Prepared) -> Vec<u64> {
        NvidiaFits::encode(prepared.params::<Nvidia>())
    }

    #[test]
    fn a_remembered_fit_has_the_bits_of_a_fit_made() {
        // A metal, a glass, a gas and an index that sanitising changes (negative k).
        let indices = [Index::new(0.17, 3.75), Index::new(1.5168, 0.0), Index::new(1.000293, 0.0), Index::new(1.4, -0.5)];
        let memo = FitMemo::new("this executable").recording();
        for index in indices {
            assert_eq!(memo.prepared(index).params::<Nvidia>(), Prepared::new(index).params::<Nvidia>());
        }
        assert_eq!(memo.recorded(), 4);
        let read = FitMemo::decode(&memo.encode(), "this executable");
        for index in indices {
            let remembered = read.prepared(index);
            assert_eq!(bits(&remembered), bits(&Prepared::new(index)), "{index:?}");
            assert_eq!(remembered.params::<Nvidia>(), Prepared::new(index).params::<Nvidia>());
        }
        // Nothing was fitted again: a memo that only reads records nothing, and a
        // recording one over the same file records nothing new.
        let again = FitMemo::decode(&memo.encode(), "this executable").recording();
        for index in indices {
            again.prepared(index);
        }
        assert_eq!(again.recorded(), 0);
    }

    #[test]
    fn another_executables_fits_are_not_read() {
        let memo = FitMemo::new("one executable").recording();
        memo.prepared(Index::new(0.17, 3.75));
        let other = FitMemo::decode(&memo.encode(), "another executable").recording();
        other.prepared(Index::new(0.17, 3.75));
        assert_eq!(other.recorded(), 1);
    }

    #[test]
    fn a_fit_is_keyed_by_the_sanitised_index() {
        // k = −0.5 sanitises to k = 0: its fit is the one of k = 0. One bit of n apart is
        // another index.
        let memo = FitMemo::new("this executable").recording();
        memo.prepared(Index::new(1.4, -0.5));
        let read = FitMemo::decode(&memo.encode(), "this executable").recording();
        assert_eq!(read.prepared(Index::new(1.4, 0.0)).params::<Nvidia>(), Prepared::new(Index::new(1.4, 0.0)).params::<Nvidia>());
        assert_eq!(read.recorded(), 0);
        read.prepared(Index::new(f64::from_bits(1.4f64.to_bits() + 1), 0.0));
        assert_eq!(read.recorded(), 1);
    }
}
