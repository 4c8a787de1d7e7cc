//! The memo files under an output folder (`<out>/.cache/`, the layout of
//! [`nklut_optics::memo`]): read for the running executable, written atomically when they
//! grew. The optics crate encodes and decodes a memo; its file is this crate's.

use std::path::Path;

use anyhow::Result;
use nklut_optics::memo::{Kind, Memo};

/// The largest memo read back (a whole database's records are a few megabytes); a larger
/// file is not this program's memo and is ignored.
pub const MAX_MEMO_BYTES: u64 = 1 << 30;

/// A memo's file under an output folder.
pub trait MemoFile: Sized {
    /// The memo of the output folder `out` for the running executable (empty when there
    /// is none, it is another executable's, or the executable cannot be identified).
    fn load(out: &Path) -> Self;

    /// Write the memo under `out` when it grew, atomically but without waiting for the
    /// disk (a file torn by a power cut reads as a miss: see [`nklut_optics::memo`]).
    fn save(&self, out: &Path) -> Result<()>;

    /// [`MemoFile::save`], a failure reported as a warning: the outputs are written
    /// already, and the next command computes what was not remembered.
    fn save_or_warn(&self, out: &Path);
}

impl<K: Kind> MemoFile for Memo<K> {
    fn load(out: &Path) -> Self {
        let identity = executable_identity();
        if identity.is_empty() {
            return Self::new("");
        }
        // A regular file of at most MAX_MEMO_BYTES (a FIFO or a device there is no memo,
        // and reading it neither waits nor grows without end).
        match nklut_optics::db::file::read_regular(&out.join(K::PATH), MAX_MEMO_BYTES) {
            Ok(bytes) => Self::decode(&bytes, &identity),
            Err(_) => Self::new(&identity),
        }
    }

    fn save(&self, out: &Path) -> Result<()> {
        // Without an identity no later run could tell this memo is its own.
        if self.identity().is_empty() || !self.grew() {
            return Ok(());
        }
        crate::atomic::write_atomic_unflushed(&out.join(K::PATH), &self.encode())
    }

    fn save_or_warn(&self, out: &Path) {
        if let Err(error) = self.save(out) {
            eprintln!("warning: the {} were not remembered: {error:#}", K::RECORDS);
        }
    }
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
