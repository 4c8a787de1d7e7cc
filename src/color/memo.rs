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
//! The file `<out>/.cache/spectral-curves.bin` (little-endian) holds a magic line, the
//! executable's identity, then per curve: the spectrum's and the cosines' fingerprints
//! and the RGB triples; last, a checksum of everything before it. A missing, foreign
//! or damaged file reads as empty, so the memo is written without waiting for the disk:
//! a file torn by a power cut is a miss, not a wrong curve.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use anyhow::Result;

use super::spectral::PreparedSpectrum;
use crate::spectrum::Index;

/// Where the memo lives under an output folder.
pub const MEMO_PATH: &str = ".cache/spectral-curves.bin";

const MAGIC: &[u8] = b"nklut spectral curves 1\n";

/// 128 bits of a sequence of f64 (two SipHash-1-3 sums with different prefixes, over the
/// bit patterns): the key of a spectrum or a set of cosines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Fingerprint([u64; 2]);

impl Fingerprint {
    pub fn of(values: impl Iterator<Item = f64> + Clone) -> Self {
        Self([0u8, 1u8].map(|prefix| {
            let mut hasher = std::hash::DefaultHasher::new();
            prefix.hash(&mut hasher);
            for v in values.clone() {
                v.to_bits().hash(&mut hasher);
            }
            hasher.finish()
        }))
    }

    /// Of a spectrum sampled on the 1 nm grid (`sample_spectrum`).
    pub fn of_spectrum(spectrum: &[Index]) -> Self {
        Self::of(spectrum.iter().flat_map(|i| [i.n, i.k]))
    }

    pub fn of_cosines(cosines: &[f64]) -> Self {
        Self::of(cosines.iter().copied())
    }
}

/// A key: which spectrum, at which cosines.
type Key = (Fingerprint, Fingerprint);

/// The remembered curves of one executable and, when it records (`colors`), the ones
/// computed since they were read. A memo that only reads (`params`, `bake`) keeps nothing
/// it computes.
#[derive(Debug, Default)]
pub struct CurveMemo {
    identity: String,
    curves: HashMap<Key, Vec<[f64; 3]>>,
    fresh: Option<Mutex<Vec<(Key, Vec<[f64; 3]>)>>>,
}

impl CurveMemo {
    /// An empty memo for the executable named by `identity`.
    pub fn new(identity: &str) -> Self {
        Self { identity: identity.to_string(), ..Self::default() }
    }

    /// This memo, keeping the curves it computes for [`CurveMemo::encode`].
    pub fn recording(self) -> Self {
        Self { fresh: Some(Mutex::default()), ..self }
    }

    /// `spectrum.curve(cosines)` (the spectrum sampled as `sampled`), from the memo
    /// when it holds it, else computed (and kept, when recording). No cosines, no curve.
    pub fn curve(&self, sampled: Fingerprint, spectrum: &PreparedSpectrum, cosines: &[f64]) -> Vec<[f64; 3]> {
        if cosines.is_empty() {
            return Vec::new();
        }
        let key = (sampled, Fingerprint::of_cosines(cosines));
        if let Some(curve) = self.curves.get(&key).filter(|c| c.len() == cosines.len()) {
            return curve.clone();
        }
        let curve = spectrum.curve(cosines);
        if let Some(fresh) = &self.fresh {
            fresh.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).push((key, curve.clone()));
        }
        curve
    }

    /// Whether curves were recorded that the memo did not hold.
    pub fn grew(&self) -> bool {
        self.fresh.as_ref().is_some_and(|fresh| !fresh.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).is_empty())
    }

    /// The memo's bytes: every curve it held and every one recorded since, in key order
    /// (the same curves give the same bytes).
    pub fn encode(&self) -> Vec<u8> {
        let fresh = self.fresh.as_ref().map(|fresh| fresh.lock().unwrap_or_else(|poisoned| poisoned.into_inner()));
        let mut all: Vec<(&Key, &Vec<[f64; 3]>)> = self.curves.iter().collect();
        all.extend(fresh.iter().flat_map(|fresh| fresh.iter().map(|(k, c)| (k, c))));
        all.sort_by_key(|(k, _)| **k);
        all.dedup_by_key(|(k, _)| **k);
        let mut bytes = MAGIC.to_vec();
        put_u64(&mut bytes, self.identity.len() as u64);
        bytes.extend_from_slice(self.identity.as_bytes());
        put_u64(&mut bytes, all.len() as u64);
        for ((spectrum, cosines), curve) in all {
            for word in spectrum.0.iter().chain(&cosines.0) {
                put_u64(&mut bytes, *word);
            }
            put_u64(&mut bytes, curve.len() as u64);
            for value in curve.iter().flatten() {
                bytes.extend_from_slice(&value.to_le_bytes());
            }
        }
        let check = checksum(&bytes);
        bytes.extend_from_slice(&check);
        bytes
    }

    /// The memo in `bytes` if it was written by the executable named `identity`; an empty
    /// one for any other executable, a damaged file or one of another format.
    pub fn decode(bytes: &[u8], identity: &str) -> Self {
        Self::read(bytes, identity).unwrap_or_else(|| Self::new(identity))
    }

    fn read(bytes: &[u8], identity: &str) -> Option<Self> {
        let (body, check) = bytes.split_at_checked(bytes.len().checked_sub(8)?)?;
        if check != checksum(body) {
            return None;
        }
        let mut reader = Reader { bytes: body.strip_prefix(MAGIC)? };
        let length = usize::try_from(reader.u64()?).ok()?;
        if reader.take(length)? != identity.as_bytes() {
            return None;
        }
        let count = reader.u64()?;
        let mut curves = HashMap::new();
        for _ in 0..count {
            let words: [u64; 4] = [reader.u64()?, reader.u64()?, reader.u64()?, reader.u64()?];
            let points = usize::try_from(reader.u64()?).ok()?;
            let raw = reader.take(points.checked_mul(24)?)?;
            let curve = raw.chunks_exact(24).map(|rgb| [0, 1, 2].map(|c| f64::from_le_bytes(rgb[8 * c..8 * c + 8].try_into().expect("8 bytes")))).collect();
            curves.insert((Fingerprint([words[0], words[1]]), Fingerprint([words[2], words[3]])), curve);
        }
        reader.bytes.is_empty().then(|| Self { identity: identity.to_string(), curves, fresh: None })
    }

    /// The memo of the output folder `out` for the running executable (empty when there
    /// is none, it is another executable's, or the executable cannot be identified).
    pub fn load(out: &Path) -> Self {
        let identity = executable_identity();
        if identity.is_empty() {
            return Self::default();
        }
        match std::fs::read(memo_path(out)) {
            Ok(bytes) => Self::decode(&bytes, &identity),
            Err(_) => Self::new(&identity),
        }
    }

    /// Write the memo under `out` when it grew, atomically but without waiting for the
    /// disk (see the module doc).
    pub fn save(&self, out: &Path) -> Result<()> {
        // Without an identity no later run could tell this memo is its own.
        if self.identity.is_empty() || !self.grew() {
            return Ok(());
        }
        crate::output::write_atomic_unflushed(&memo_path(out), &self.encode())
    }

    /// [`CurveMemo::save`], a failure reported as a warning: the outputs are written
    /// already, and the next command computes its curves itself.
    pub fn save_or_warn(&self, out: &Path) {
        if let Err(error) = self.save(out) {
            eprintln!("warning: the spectral curves were not remembered: {error:#}");
        }
    }
}

fn memo_path(out: &Path) -> PathBuf {
    out.join(MEMO_PATH)
}

/// The running executable as a memo sees it: its path, size and modification time (a
/// rebuild changes them). Empty when they cannot be read; such a run neither reads nor
/// writes a memo.
fn executable_identity() -> String {
    let Ok(path) = std::env::current_exe() else { return String::new() };
    let Ok(metadata) = std::fs::metadata(&path) else { return String::new() };
    let modified = metadata.modified().ok().and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok()).map_or(0, |d| d.as_nanos());
    format!("{} {} {modified}", path.display(), metadata.len())
}

/// A SipHash-1-3 sum of the memo's bytes (one pass; it guards against a torn or damaged
/// file, not against a forger).
fn checksum(bytes: &[u8]) -> [u8; 8] {
    let mut hasher = std::hash::DefaultHasher::new();
    hasher.write(bytes);
    hasher.finish().to_le_bytes()
}

fn put_u64(bytes: &mut Vec<u8>, value: u64) {
    bytes.extend_from_slice(&value.to_le_bytes());
}

/// Bounds-checked reads from the memo's bytes.
struct Reader<'a> {
    bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take(&mut self, count: usize) -> Option<&'a [u8]> {
        if count > self.bytes.len() {
            return None;
        }
        let (head, tail) = self.bytes.split_at(count);
        self.bytes = tail;
        Some(head)
    }

    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
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
    fn another_executable_or_damaged_bytes_read_as_empty() {
        let cosines = [1.0, 0.5, 0.0];
        let sampled = spectrum(1.0);
        let memo = CurveMemo::new("nklut 1").recording();
        memo.curve(Fingerprint::of_spectrum(&sampled), &PreparedSpectrum::new(&sampled), &cosines);
        let bytes = memo.encode();
        assert_eq!(CurveMemo::decode(&bytes, "nklut 1").curves.len(), 1);
        assert!(CurveMemo::decode(&bytes, "nklut 2").curves.is_empty());
        // Every truncation and a trailing byte: empty, never a panic.
        for cut in 0..bytes.len() {
            assert!(CurveMemo::decode(&bytes[..cut], "nklut 1").curves.is_empty(), "cut at {cut}");
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(CurveMemo::decode(&longer, "nklut 1").curves.is_empty());
        // Any one byte changed (a curve value torn by a power cut, say).
        for at in (0..bytes.len()).step_by(7) {
            let mut flipped = bytes.clone();
            flipped[at] ^= 0x10;
            assert!(CurveMemo::decode(&flipped, "nklut 1").curves.is_empty(), "byte {at} changed");
        }
        // A count that claims more than the file holds.
        let mut huge = bytes[..bytes.len() - 8].to_vec();
        let at = MAGIC.len() + 8 + "nklut 1".len();
        huge[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        let check = checksum(&huge);
        huge.extend_from_slice(&check);
        assert!(CurveMemo::decode(&huge, "nklut 1").curves.is_empty());
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

    #[test]
    fn fingerprints_tell_the_sign_of_zero_and_the_order_apart() {
        let a = Fingerprint::of([0.0, 1.0].into_iter());
        assert_ne!(a, Fingerprint::of([-0.0, 1.0].into_iter()));
        assert_ne!(a, Fingerprint::of([1.0, 0.0].into_iter()));
        assert_eq!(a, Fingerprint::of([0.0, 1.0].into_iter()));
    }
}
