//! The memory a run may take, and the check that every size a scene file or a flag asks
//! for passes *before* anything of that size is allocated: the caller estimates the bytes
//! its structures will hold (from their element sizes and counts) and asks the budget,
//! which answers with an error naming the field, what it asked for and both sizes — at
//! once, instead of an allocation that aborts the process or a machine that starts to
//! swap. The budget is half of the machine's physical memory (the other half is left to
//! the system and to what the estimates leave out), or `NKLUT_MEMORY_BUDGET` (bytes, or
//! with a K, M, G or T suffix in powers of 1024). The variable is read strictly: a
//! number (decimals allowed), optionally one unit (`K`, `M`, `G`, `T`, each optionally
//! followed by `B` or `iB`), nothing else; a value that is not such a size, is 0, or does
//! not fit 64 bits is an error naming the variable ([`MemoryBudget::from_environment`]),
//! never a silent fallback.

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
    /// `NKLUT_MEMORY_BUDGET` is set but is not a size: nothing fits (the binary refuses
    /// such a value before any work, [`MemoryBudget::from_environment`]).
    Invalid,
    /// A figure given by the caller (tests).
    Given,
}

impl fmt::Display for BudgetSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BudgetSource::HalfOfMemory => "half of this machine's memory; NKLUT_MEMORY_BUDGET sets another",
            BudgetSource::Environment => "NKLUT_MEMORY_BUDGET",
            BudgetSource::Invalid => "NKLUT_MEMORY_BUDGET is set but is not a size",
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

/// The environment variable that sets the budget.
pub const BUDGET_VARIABLE: &str = "NKLUT_MEMORY_BUDGET";

/// `NKLUT_MEMORY_BUDGET` holds something other than a size.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{BUDGET_VARIABLE}={value:?} is not a memory budget: {why} (write bytes, or a number with K, M, G or T in powers of 1024: 512M, 2G, 1.5T)")]
pub struct BadBudget {
    pub value: String,
    pub why: String,
}

/// The physical memory assumed where the machine's cannot be read.
const ASSUMED_MEMORY: u64 = 8 << 30;

impl MemoryBudget {
    /// A budget of `bytes`.
    pub fn given(bytes: u64) -> MemoryBudget {
        MemoryBudget { bytes, source: BudgetSource::Given }
    }

    /// `NKLUT_MEMORY_BUDGET` when it is set, else half of the physical memory; a value that
    /// is not a size is an error naming the variable and the value.
    pub fn from_environment() -> Result<MemoryBudget, BadBudget> {
        match std::env::var_os(BUDGET_VARIABLE) {
            None => Ok(MemoryBudget { bytes: physical_memory().unwrap_or(ASSUMED_MEMORY) / 2, source: BudgetSource::HalfOfMemory }),
            Some(value) => {
                let text = value
                    .to_str()
                    .ok_or_else(|| BadBudget { value: value.to_string_lossy().into_owned(), why: "not UTF-8 text".into() })?;
                let bytes = parse_size(text).map_err(|why| BadBudget { value: text.to_string(), why })?;
                Ok(MemoryBudget { bytes, source: BudgetSource::Environment })
            }
        }
    }

    /// [`from_environment`](Self::from_environment) where an error cannot be returned: a
    /// value that is not a size gives a budget of 0 bytes (every check fails, naming the
    /// variable), never a silent fallback to another figure.
    pub fn of_machine() -> MemoryBudget {
        Self::from_environment().unwrap_or(MemoryBudget { bytes: 0, source: BudgetSource::Invalid })
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

/// `1234`, `512M`, `2G`, `1.5T`, `2GiB` (powers of 1024) as bytes, exactly (decimals
/// are read as a fraction of the unit, rounded down to a byte); why not, for anything
/// else: an empty value, a sign, `NaN`, `inf`, an exponent, a unit other than K, M, G or
/// T, text after the unit, 0, or a size past 2⁶⁴ − 1 bytes.
pub fn parse_size(text: &str) -> Result<u64, String> {
    let text = text.trim();
    let digits_end = text.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(text.len());
    let (number, unit) = text.split_at(digits_end);
    let (whole, fraction) = number.split_once('.').unwrap_or((number, ""));
    if whole.is_empty() || !whole.bytes().all(|b| b.is_ascii_digit()) || !fraction.bytes().all(|b| b.is_ascii_digit()) {
        return Err("not a number of bytes".into());
    }
    if fraction.len() > 18 {
        return Err("more than 18 decimals".into());
    }
    let shift = match unit.trim_start() {
        "" | "B" | "b" => 0,
        "K" | "k" | "KB" | "kB" | "KiB" | "kiB" => 10,
        "M" | "MB" | "MiB" => 20,
        "G" | "GB" | "GiB" => 30,
        "T" | "TB" | "TiB" => 40,
        other => return Err(format!("the unit {other:?} is not one of K, M, G, T")),
    };
    let too_large = || "more than 2⁶⁴ − 1 bytes".to_string();
    // whole · 2^shift + fraction · 2^shift / 10^decimals, in u128 (no float rounding).
    let whole: u128 = whole.parse().map_err(|_| too_large())?;
    let fraction_value: u128 = if fraction.is_empty() { 0 } else { fraction.parse().map_err(|_| too_large())? };
    let bytes = whole
        .checked_shl(shift)
        .filter(|b| b >> shift == whole)
        .ok_or_else(too_large)?
        .checked_add((fraction_value << shift) / 10u128.pow(fraction.len() as u32))
        .ok_or_else(too_large)?;
    let bytes = u64::try_from(bytes).map_err(|_| too_large())?;
    if bytes == 0 {
        return Err("0 bytes leaves nothing to run with".into());
    }
    Ok(bytes)
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
        assert_eq!(parse_size("1234"), Ok(1234));
        assert_eq!(parse_size("512M"), Ok(512 << 20));
        assert_eq!(parse_size("2G"), Ok(2 << 30));
        assert_eq!(parse_size("2GiB"), Ok(2 << 30));
        assert_eq!(parse_size("1.5k"), Ok(1536));
        assert_eq!(parse_size(" 16T "), Ok(16 << 40));
        // 0.1 G = 107 374 182.4 bytes, rounded down.
        assert_eq!(parse_size("0.1G"), Ok(107_374_182));
        assert_eq!(parse_size("18446744073709551615"), Ok(u64::MAX));
        // 16 777 215 T = 2⁶⁴ − 2⁴⁰ bytes fits; one more T does not.
        assert_eq!(parse_size("16777215T"), Ok(u64::MAX - (1 << 40) + 1));
        for bad in ["", "-1", "x", "abc", "1Q", "NaN", "inf", "16E", "1e3", "4G;rm -rf /", "0", "0.0G", "1..2", ".5G", "G", "2 G x"] {
            assert!(parse_size(bad).is_err(), "{bad:?} read as {:?}", parse_size(bad));
        }
        assert_eq!(parse_size("18446744073709551616"), Err("more than 2⁶⁴ − 1 bytes".into()));
        assert_eq!(parse_size("16777216T"), Err("more than 2⁶⁴ − 1 bytes".into()));
        assert_eq!(parse_size("99999999999999999999999999999999999999999"), Err("more than 2⁶⁴ − 1 bytes".into()));
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
