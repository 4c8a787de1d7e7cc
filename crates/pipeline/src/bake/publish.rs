//! Writing a bake (or the report): `<out>/luts` is published as one set
//! ([`crate::output::publish_folder_with`]): every file goes to a fresh generation under
//! `<out>/.sets/`, which one rename of a link switches in only once every file is written.
//! Readers see the previous bake or the new one, never a mix (a kill at any moment
//! included), and a failure removes the new generation.
//!
//! Files inside the private staging folder are written without a per-file fsync: at
//! ~3 ms per fsync on this machine's ext4, the tens of thousands of strips of `--all`
//! would cost more than the whole bake (see BENCHMARKS.md, LUT bake). A power cut right after
//! a bake can therefore leave truncated files, which a re-run replaces; a crash of the
//! process cannot.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use rayon::prelude::*;

/// A file of the bake: its path relative to `<out>/luts` ('/'-separated) and bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct OutFile {
    pub path: String,
    pub bytes: Vec<u8>,
}

/// The folder under `out` that holds a bake.
pub const LUTS_DIR: &str = "luts";

/// The staging and set-aside names of `folder` (`.luts.staging-`, `.luts.old-`).
fn prefixes(folder: &str) -> (String, String) {
    (format!(".{folder}.staging-"), format!(".{folder}.old-"))
}

/// Called with each file's index in the list and its relative path before it is written;
/// an error aborts the bake (tests inject failures with it).
pub type BeforeWrite<'a> = &'a (dyn Fn(usize, &str) -> Result<()> + Sync);

/// Check up front that `out` can be created and written: make the folder, create and
/// remove a probe file.
pub fn check_writable(out: &Path) -> Result<()> {
    let fail = |what: &str| format!("output folder {} is not writable ({what})", out.display());
    fs::create_dir_all(out).with_context(|| fail("cannot create it"))?;
    let probe = out.join(format!(".nklut-probe-{}", std::process::id()));
    fs::write(&probe, b"probe").with_context(|| fail("cannot create a file in it"))?;
    fs::remove_file(&probe).with_context(|| fail("cannot remove a file from it"))?;
    let luts = out.join(LUTS_DIR);
    if luts.exists() && !luts.is_dir() {
        bail!("{} exists and is not a folder", luts.display());
    }
    Ok(())
}

/// Leftovers of a bake killed while earlier versions staged it beside `<out>/luts`.
fn remove_leftovers(out: &Path, folder: &str) -> Result<()> {
    let (staging_prefix, old_prefix) = prefixes(folder);
    for entry in fs::read_dir(out).with_context(|| format!("listing {}", out.display()))? {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with(&staging_prefix) || name.starts_with(&old_prefix) {
            fs::remove_dir_all(entry.path()).with_context(|| format!("removing the leftover {}", entry.path().display()))?;
        }
    }
    Ok(())
}

fn relative_path(root: &Path, path: &str) -> Result<PathBuf> {
    let relative = Path::new(path);
    if path.is_empty() || relative.is_absolute() || relative.components().any(|c| !matches!(c, std::path::Component::Normal(_))) {
        bail!("bad output path {path:?}");
    }
    Ok(root.join(relative))
}

fn write_all(staging: &Path, files: &[OutFile], before_write: BeforeWrite) -> Result<()> {
    let folders: BTreeSet<PathBuf> = files
        .iter()
        .map(|f| relative_path(staging, &f.path).map(|p| p.parent().unwrap_or(staging).to_path_buf()))
        .collect::<Result<_>>()?;
    for folder in folders {
        fs::create_dir_all(&folder).with_context(|| format!("creating {}", folder.display()))?;
    }
    files.par_iter().enumerate().try_for_each(|(i, file)| {
        before_write(i, &file.path)?;
        let path = relative_path(staging, &file.path)?;
        fs::write(&path, &file.bytes).with_context(|| format!("writing {}", path.display()))
    })
}

/// Write `files` as the new `<out>/luts`, all or nothing. Returns the folder.
pub fn publish(out: &Path, files: &[OutFile], before_write: BeforeWrite) -> Result<PathBuf> {
    publish_folder(out, LUTS_DIR, files, before_write)
}

/// Write `files` as the new `<out>/<folder>` (e.g. `luts`, `report`), all or nothing.
pub fn publish_folder(out: &Path, folder: &str, files: &[OutFile], before_write: BeforeWrite) -> Result<PathBuf> {
    publish_with(out, folder, &|staging| write_all(staging, files, before_write))
}

/// Fill a fresh folder with `fill` (which writes its files into the folder it is given,
/// e.g. as they are computed), then make it the new `<out>/<folder>`, all or nothing.
/// Returns the folder.
pub fn publish_with(out: &Path, folder: &str, fill: &dyn Fn(&Path) -> Result<()>) -> Result<PathBuf> {
    remove_leftovers(out, folder)?;
    crate::output::publish_folder_with(out, folder, fill)
}
