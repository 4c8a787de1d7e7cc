//! Results remembered between the commands of one output folder, each a function of its
//! key alone: records of a 256-bit key and a value of 64-bit words, encoded as the bytes of
//! one file under `<out>/.cache/` ([`Kind::PATH`]; `nklut-tables`' `memo_file` reads and
//! writes it: this crate touches no file of its own). A record is only ever read by the executable that computed it (its path,
//! size and modification time), so a rebuilt `nklut` never reads what its predecessor
//! computed. What is remembered: the spectral curves and the effective fits
//! (`color::memo`), the error integrals (`validate::memo`), the `nvidia` fits
//! (`fresnel::memo`), each a [`Kind`] of [`Memo`] with its value's words; one lookup,
//! [`Memo::remembered`], serves them all.
//!
//! The file (little-endian) holds a magic line naming what is remembered, the
//! executable's identity, the record count, then per record the key's four words, the
//! value's length in units (a unit is a fixed number of words, e.g. an RGB triple) and the
//! words; last, a checksum of everything before it. A missing, foreign or damaged file
//! reads as empty, so a memo is written without waiting for the disk: a file torn by a
//! power cut is a miss, not a wrong value.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::marker::PhantomData;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};

/// 128 bits of a sequence of words or f64 (two SipHash-1-3 sums with different prefixes,
/// over the bit patterns): the key of a spectrum, a set of cosines, a family of methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Fingerprint(pub [u64; 2]);

impl Fingerprint {
    /// Of a sequence of f64, by their bit patterns.
    pub fn of(values: impl Iterator<Item = f64> + Clone) -> Self {
        Self::of_words(values.map(f64::to_bits))
    }

    /// Of a sequence of words.
    pub fn of_words(words: impl Iterator<Item = u64> + Clone) -> Self {
        Self([0u8, 1u8].map(|prefix| {
            let mut hasher = std::hash::DefaultHasher::new();
            prefix.hash(&mut hasher);
            for word in words.clone() {
                word.hash(&mut hasher);
            }
            hasher.finish()
        }))
    }
}

/// A record's key.
pub type Key = [u64; 4];

/// One kind of memo: the magic line of its file, the words per unit of a value (an RGB
/// triple is a unit of three), its place under an output folder, what a warning calls
/// its records, and what a record holds with its words.
pub trait Kind {
    /// The first line of the file, which names the kind and its layout.
    const MAGIC: &'static [u8];
    /// Words per unit of a value.
    const UNIT: usize;
    /// The file, relative to an output folder.
    const PATH: &'static str;
    /// What a warning calls the records.
    const RECORDS: &'static str;
    /// What a record holds.
    type Value;
    /// The value's words: a whole number of units, which [`Kind::decode`] reads back with
    /// every bit.
    fn encode(value: &Self::Value) -> Vec<u64>;
    /// The value of `words` that [`Kind::encode`] wrote.
    fn decode(words: &[u64]) -> Self::Value;
}

/// The records of one kind and one executable and, when it records, the ones computed
/// since they were read. A memo that only reads keeps nothing it computes.
#[derive(Debug)]
pub struct Memo<K: Kind> {
    identity: String,
    remembered: Records,
    /// Where each remembered key is in `remembered`.
    lookup: HashMap<Key, usize>,
    fresh: Option<Mutex<Records>>,
    /// Lookups made, found or not.
    asked: AtomicUsize,
    kind: PhantomData<fn() -> K>,
}

impl<K: Kind> Default for Memo<K> {
    /// A memo that holds nothing and is never written: everything is computed.
    fn default() -> Self {
        Self::new("")
    }
}

/// Records with their words in one buffer: one allocation, which the allocator hands
/// back whole when the memo is let go (tens of thousands of small ones would stay in its
/// free lists and add to the peak of what a command does next).
#[derive(Debug, Default)]
struct Records {
    /// Each record's key and its range in `words`.
    ranges: Vec<(Key, Range<usize>)>,
    words: Vec<u64>,
}

impl Records {
    fn push(&mut self, key: Key, words: impl IntoIterator<Item = u64>) {
        let start = self.words.len();
        self.words.extend(words);
        self.ranges.push((key, start..self.words.len()));
    }

    fn iter(&self) -> impl Iterator<Item = (&Key, &[u64])> {
        self.ranges.iter().map(|(key, range)| (key, &self.words[range.clone()]))
    }
}

impl<K: Kind> Memo<K> {
    /// The identity of the executable whose records these are (empty: none, and such a
    /// memo is neither read nor written).
    pub fn identity(&self) -> &str {
        &self.identity
    }

    /// An empty memo for the executable named by `identity` (empty: one that neither
    /// reads nor writes a file).
    pub fn new(identity: &str) -> Self {
        Self::of(identity, Records::default(), HashMap::new())
    }

    fn of(identity: &str, remembered: Records, lookup: HashMap<Key, usize>) -> Self {
        Self { identity: identity.to_string(), remembered, lookup, fresh: None, asked: AtomicUsize::new(0), kind: PhantomData }
    }

    /// This memo, keeping the records computed for [`Memo::encode`].
    pub fn recording(self) -> Self {
        Self { fresh: Some(Mutex::default()), ..self }
    }

    /// The remembered value of `key`, if it has `units` units.
    pub fn get(&self, key: &Key, units: usize) -> Option<&[u64]> {
        self.asked.fetch_add(1, Ordering::Relaxed);
        let (_, range) = &self.remembered.ranges[*self.lookup.get(key)?];
        Some(&self.remembered.words[range.clone()]).filter(|words| words.len() == units * K::UNIT)
    }

    /// The value of `key`: from the memo when it holds one of `units` units, else
    /// `compute`d (and kept, when recording).
    pub fn remembered(&self, key: Key, units: usize, compute: impl FnOnce() -> K::Value) -> K::Value {
        if let Some(words) = self.get(&key, units) {
            return K::decode(words);
        }
        let value = compute();
        if self.fresh.is_some() {
            self.record(key, K::encode(&value));
        }
        value
    }

    /// Keep a computed value (when recording; otherwise `words` is not even read).
    pub fn record(&self, key: Key, words: impl IntoIterator<Item = u64>) {
        if let Some(fresh) = &self.fresh {
            let mut fresh = lock(fresh);
            let start = fresh.words.len();
            fresh.push(key, words);
            debug_assert_eq!((fresh.words.len() - start) % K::UNIT, 0, "a value of whole units");
        }
    }

    /// Whether values were recorded that the memo did not hold.
    pub fn grew(&self) -> bool {
        self.fresh.as_ref().is_some_and(|fresh| !lock(fresh).ranges.is_empty())
    }

    /// Lookups made ([`Memo::get`]), found or not.
    pub fn asked(&self) -> usize {
        self.asked.load(Ordering::Relaxed)
    }

    /// Records kept since the memo was read (0 when it does not record).
    pub fn recorded(&self) -> usize {
        self.fresh.as_ref().map_or(0, |fresh| lock(fresh).ranges.len())
    }

    /// The remembered records held.
    pub fn len(&self) -> usize {
        self.lookup.len()
    }

    /// Whether no record is held.
    pub fn is_empty(&self) -> bool {
        self.lookup.is_empty()
    }

    /// The memo's bytes: every record it held and every one recorded since, in key order
    /// (the same records give the same bytes).
    pub fn encode(&self) -> Vec<u8> {
        let fresh = self.fresh.as_ref().map(lock);
        let mut all: Vec<(&Key, &[u64])> = self.remembered.iter().collect();
        all.extend(fresh.iter().flat_map(|fresh| fresh.iter()));
        all.sort_by_key(|(k, _)| **k);
        all.dedup_by_key(|(k, _)| **k);
        let words: usize = all.iter().map(|(_, words)| 5 + words.len()).sum();
        let mut bytes = Vec::with_capacity(K::MAGIC.len() + 8 * (3 + words) + self.identity.len());
        bytes.extend_from_slice(K::MAGIC);
        put_u64(&mut bytes, self.identity.len() as u64);
        bytes.extend_from_slice(self.identity.as_bytes());
        put_u64(&mut bytes, all.len() as u64);
        for (key, words) in all {
            for word in key {
                put_u64(&mut bytes, *word);
            }
            put_u64(&mut bytes, (words.len() / K::UNIT) as u64);
            for word in words {
                put_u64(&mut bytes, *word);
            }
        }
        let check = checksum(&bytes);
        bytes.extend_from_slice(&check);
        bytes
    }

    /// The memo in `bytes` if it is of this kind and was written by the executable named
    /// `identity`; an empty one for any other executable, a damaged file or one of
    /// another kind.
    pub fn decode(bytes: &[u8], identity: &str) -> Self {
        Self::read(bytes, identity).unwrap_or_else(|| Self::new(identity))
    }

    fn read(bytes: &[u8], identity: &str) -> Option<Self> {
        let (body, check) = bytes.split_at_checked(bytes.len().checked_sub(8)?)?;
        if check != checksum(body) {
            return None;
        }
        let mut reader = Reader { bytes: body.strip_prefix(K::MAGIC)? };
        let length = usize::try_from(reader.u64()?).ok()?;
        if reader.take(length)? != identity.as_bytes() {
            return None;
        }
        let count = reader.u64()?;
        let mut remembered = Records { ranges: Vec::new(), words: Vec::with_capacity(body.len() / 8) };
        let mut lookup = HashMap::new();
        for _ in 0..count {
            let key: Key = [reader.u64()?, reader.u64()?, reader.u64()?, reader.u64()?];
            let units = usize::try_from(reader.u64()?).ok()?;
            let raw = reader.take(units.checked_mul(8 * K::UNIT)?)?;
            // A key written twice (only by hand): the first stands.
            lookup.entry(key).or_insert(remembered.ranges.len());
            remembered.push(key, raw.chunks_exact(8).map(|word| u64::from_le_bytes(word.try_into().expect("8 bytes"))));
        }
        reader.bytes.is_empty().then(|| Self::of(identity, remembered, lookup))
    }
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
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

    #[derive(Debug)]
    struct Pairs;
    impl Kind for Pairs {
        const MAGIC: &'static [u8] = b"nklut test pairs 1\n";
        const UNIT: usize = 2;
        const PATH: &'static str = ".cache/test-pairs.bin";
        const RECORDS: &'static str = "test pairs";
        type Value = Vec<u64>;
        fn encode(value: &Vec<u64>) -> Vec<u64> {
            value.clone()
        }
        fn decode(words: &[u64]) -> Vec<u64> {
            words.to_vec()
        }
    }

    #[derive(Debug)]
    struct Other;
    impl Kind for Other {
        const MAGIC: &'static [u8] = b"nklut test other 1\n";
        const UNIT: usize = 2;
        const PATH: &'static str = ".cache/test-other.bin";
        const RECORDS: &'static str = "test others";
        type Value = Vec<u64>;
        fn encode(value: &Vec<u64>) -> Vec<u64> {
            value.clone()
        }
        fn decode(words: &[u64]) -> Vec<u64> {
            words.to_vec()
        }
    }

    fn memo_of(identity: &str, records: &[(Key, Vec<u64>)]) -> Memo<Pairs> {
        let memo = Memo::new(identity).recording();
        for (key, words) in records {
            memo.record(*key, words.iter().copied());
        }
        memo
    }

    #[test]
    fn records_come_back_by_key_with_their_length_checked() {
        let memo = memo_of("nklut 1", &[([1, 2, 3, 4], vec![5, 6, 7, 8]), ([0; 4], vec![])]);
        assert!(memo.grew());
        let read = Memo::<Pairs>::decode(&memo.encode(), "nklut 1");
        assert_eq!(read.len(), 2);
        assert_eq!(read.get(&[1, 2, 3, 4], 2), Some(&[5, 6, 7, 8][..]));
        assert_eq!(read.get(&[1, 2, 3, 4], 1), None, "another length is a miss");
        assert_eq!(read.get(&[0; 4], 0), Some(&[][..]));
        assert_eq!(read.get(&[1, 2, 3, 5], 2), None);
        assert_eq!(read.asked(), 4, "every lookup counted, found or not");
        // `remembered` answers a held record without computing; a record of another
        // length is computed.
        assert_eq!(read.remembered([1, 2, 3, 4], 2, || panic!("computed again")), vec![5, 6, 7, 8]);
        assert_eq!(read.remembered([1, 2, 3, 4], 1, || vec![9, 9]), vec![9, 9]);
        // A memo that only reads keeps nothing it computes.
        read.record([9; 4], [1, 2]);
        assert!(!read.grew());
        assert_eq!(read.encode(), memo.encode());
    }

    #[test]
    fn another_executable_another_format_or_damaged_bytes_read_as_empty() {
        let bytes = memo_of("nklut 1", &[([1, 2, 3, 4], vec![5, 6, 7, 8])]).encode();
        assert_eq!(Memo::<Pairs>::decode(&bytes, "nklut 1").len(), 1);
        assert!(Memo::<Pairs>::decode(&bytes, "nklut 2").is_empty());
        assert!(Memo::<Other>::decode(&bytes, "nklut 1").is_empty());
        // Every truncation and a trailing byte: empty, never a panic.
        for cut in 0..bytes.len() {
            assert!(Memo::<Pairs>::decode(&bytes[..cut], "nklut 1").is_empty(), "cut at {cut}");
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(Memo::<Pairs>::decode(&longer, "nklut 1").is_empty());
        // Any one byte changed (a value torn by a power cut, say).
        for at in 0..bytes.len() {
            let mut flipped = bytes.clone();
            flipped[at] ^= 0x10;
            assert!(Memo::<Pairs>::decode(&flipped, "nklut 1").is_empty(), "byte {at} changed");
        }
        // A count that claims more than the file holds.
        let mut huge = bytes[..bytes.len() - 8].to_vec();
        let at = Pairs::MAGIC.len() + 8 + "nklut 1".len();
        huge[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        let check = checksum(&huge);
        huge.extend_from_slice(&check);
        assert!(Memo::<Pairs>::decode(&huge, "nklut 1").is_empty());
    }

    #[test]
    fn the_same_records_give_the_same_bytes() {
        let a = ([1, 0, 0, 0], vec![1, 2]);
        let b = ([0, 1, 0, 0], vec![3, 4]);
        assert_eq!(memo_of("x", &[a.clone(), b.clone()]).encode(), memo_of("x", &[b, a]).encode());
    }

    #[test]
    fn fingerprints_tell_the_sign_of_zero_and_the_order_apart() {
        let a = Fingerprint::of([0.0, 1.0].into_iter());
        assert_ne!(a, Fingerprint::of([-0.0, 1.0].into_iter()));
        assert_ne!(a, Fingerprint::of([1.0, 0.0].into_iter()));
        assert_eq!(a, Fingerprint::of([0.0, 1.0].into_iter()));
        assert_eq!(a, Fingerprint::of_words([0.0f64.to_bits(), 1.0f64.to_bits()].into_iter()));
    }
}
