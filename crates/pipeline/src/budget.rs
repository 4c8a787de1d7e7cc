//! The memory a run may take, and the check that every size a scene file or a flag asks
//! for passes *before* anything of that size is allocated: the caller estimates the bytes
//! its structures will hold (from their element sizes and counts) and asks the budget,
//! which answers with an error naming the field, what it asked for and both sizes — at
//! once, instead of an allocation that aborts the process or a machine that starts to
//! swap. The budget is half of the machine's physical memory (the other half is left to
//! the system and to what the estimates leave out), or `NKLUT_MEMORY_BUDGET` (bytes, or
//! with a K, M, G or T suffix in powers of 1024).

use std::fmt;

/// How many bytes a run may hold, and where that figure comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryBudget {
    pub bytes: u64,
    pub source: BudgetSource,
}

/// Where a budget's figure comes from, for its error messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BudgetSource {
    /// Half of the machine's physical memory.
    HalfOfMemory,
    /// The environment variable `NKLUT_MEMORY_BUDGET`.
    Environment,
    /// A figure given by the caller (tests).
    Given,
}

impl fmt::Display for BudgetSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BudgetSource::HalfOfMemory => "half of this machine's memory; NKLUT_MEMORY_BUDGET sets another",
            BudgetSource::Environment => "NKLUT_MEMORY_BUDGET",
            BudgetSource::Given => "as given",
        })
    }
}

/// A size over the budget: the field that asked for it, what it asked for, the bytes.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{field}: {what} would take about {}, more than the memory budget of {} ({source})", bytes_text(*needed), bytes_text(u128::from(budget.bytes)), source = budget.source)]
pub struct TooLarge {
    pub field: String,
    pub what: String,
    pub needed: u128,
    pub budget: MemoryBudget,
}

/// The physical memory assumed where the machine's cannot be read.
const ASSUMED_MEMORY: u64 = 8 << 30;

impl MemoryBudget {
    /// A budget of `bytes`.
    pub fn given(bytes: u64) -> MemoryBudget {
        MemoryBudget { bytes, source: BudgetSource::Given }
    }

    /// `NKLUT_MEMORY_BUDGET` when it is set and reads as a size, else half of the physical
    /// memory.
    pub fn of_machine() -> MemoryBudget {
        if let Some(bytes) = std::env::var("NKLUT_MEMORY_BUDGET").ok().and_then(|text| parse_size(&text)) {
            return MemoryBudget { bytes, source: BudgetSource::Environment };
        }
        MemoryBudget { bytes: physical_memory().unwrap_or(ASSUMED_MEMORY) / 2, source: BudgetSource::HalfOfMemory }
    }

    /// Whether `needed` bytes fit; `field` names what asked (`effects.distance_maps`,
    /// `--ao-rays`), `what` says what in words.
    pub fn check(&self, field: &str, what: impl fmt::Display, needed: u128) -> Result<(), TooLarge> {
        if needed <= u128::from(self.bytes) {
            Ok(())
        } else {
            Err(TooLarge { field: field.to_string(), what: what.to_string(), needed, budget: *self })
        }
    }
}

/// `1234`, `512M`, `2G`, `1.5T` (powers of 1024) as bytes.
pub fn parse_size(text: &str) -> Option<u64> {
    let text = text.trim();
    let (number, unit) = match text.char_indices().find(|(_, c)| c.is_ascii_alphabetic()) {
        Some((at, _)) => (&text[..at], text[at..].trim_end_matches(['B', 'b', 'i'])),
        None => (text, ""),
    };
    let scale: u64 = match unit.to_ascii_uppercase().as_str() {
        "" => 1,
        "K" => 1 << 10,
        "M" => 1 << 20,
        "G" => 1 << 30,
        "T" => 1 << 40,
        _ => return None,
    };
    let value: f64 = number.trim().parse().ok()?;
    (value.is_finite() && value >= 0.0 && value * scale as f64 <= u64::MAX as f64).then_some((value * scale as f64) as u64)
}

/// Bytes in words: `3.2 GB`, `640 MB`, `12 kB` (powers of 1000, as people read them).
pub fn bytes_text(bytes: u128) -> String {
    let b = bytes as f64;
    match bytes {
        0..1_000 => format!("{bytes} bytes"),
        1_000..1_000_000 => format!("{:.0} kB", b / 1e3),
        1_000_000..1_000_000_000 => format!("{:.0} MB", b / 1e6),
        1_000_000_000..1_000_000_000_000 => format!("{:.1} GB", b / 1e9),
        _ => format!("{:.1} TB", b / 1e12),
    }
}

/// The machine's physical memory in bytes, where it can be read.
fn physical_memory() -> Option<u64> {
    #[cfg(unix)]
    {
        // SAFETY: sysconf only reads system parameters.
        let (pages, page) = unsafe { (libc::sysconf(libc::_SC_PHYS_PAGES), libc::sysconf(libc::_SC_PAGESIZE)) };
        if pages > 0 && page > 0 {
            return (pages as u64).checked_mul(page as u64);
        }
    }
    None
}

/// `count` elements of `size` bytes each, as the check takes them (saturating, never
/// wrapping: a count that overflows is simply too large).
pub fn times(count: u128, size: usize) -> u128 {
    count.saturating_mul(size as u128)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_with_their_units() {
        assert_eq!(parse_size("1234"), Some(1234));
        assert_eq!(parse_size("512M"), Some(512 << 20));
        assert_eq!(parse_size("2G"), Some(2 << 30));
        assert_eq!(parse_size("2GiB"), Some(2 << 30));
        assert_eq!(parse_size("1.5k"), Some(1536));
        assert_eq!(parse_size("-1"), None);
        assert_eq!(parse_size("x"), None);
        assert_eq!(parse_size("1Q"), None);
    }

    #[test]
    fn the_check_names_the_field_and_both_sizes() {
        let budget = MemoryBudget::given(1_000_000);
        assert!(budget.check("f", "x", 1_000_000).is_ok());
        let error = budget.check("effects.distance_maps", "2 maps of 6 × 4096² × 8 texels", 64_400_000_000).unwrap_err();
        assert_eq!(error.to_string(), "effects.distance_maps: 2 maps of 6 × 4096² × 8 texels would take about 64.4 GB, more than the memory budget of 1 MB (as given)");
        assert_eq!(times(u128::MAX, 8), u128::MAX);
        let machine = MemoryBudget::of_machine();
        assert!(machine.bytes > 0);
    }
}
