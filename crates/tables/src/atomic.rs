//! Files replaced whole: the bytes go to a temporary name in the same folder, then one
//! rename puts them in place, so a reader (or a run killed at any moment) sees the old file
//! or the new one, never a part. The memo files (`memo_file`) and the single files of the
//! pipeline's outputs are written this way.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// Write `bytes` to `path` atomically: the bytes go to `path.tmp-<pid>` in the same
/// folder, are flushed, then renamed over `path`. A crash leaves either the old file or
/// the new one, plus at worst a stray `.tmp-` file, never a truncated `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    replace_file(path, bytes, true)
}

/// [`write_atomic`] without the flush: a crash of the process still leaves the old file or
/// the new one, but a power cut right after may leave `path` truncated. For caches whose
/// reader checks what it reads.
pub fn write_atomic_unflushed(path: &Path, bytes: &[u8]) -> Result<()> {
    replace_file(path, bytes, false)
}

fn replace_file(path: &Path, bytes: &[u8], flush: bool) -> Result<()> {
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    fs::create_dir_all(dir).with_context(|| format!("creating folder {}", dir.display()))?;
    let tmp = temp_path(path);
    let result = (|| -> Result<()> {
        let mut file = fs::File::create(&tmp).with_context(|| format!("creating {}", tmp.display()))?;
        file.write_all(bytes).with_context(|| format!("writing {}", tmp.display()))?;
        if flush {
            file.sync_all().ok();
        }
        fs::rename(&tmp, path).with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// The temporary name `write_atomic` uses for `path`.
pub fn temp_path(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}
