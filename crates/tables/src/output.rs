//! File output at the edge of the pipeline: atomic writes (temp file + rename) so an
//! interrupted run never leaves a half-written file; the files of one command published
//! as one set ([`publish_set`]) so that an interrupted run leaves the previous set or the
//! new one, never a mix; and the tables every stage writes (CSV, JSON, and Parquet through
//! the encoder the caller hands over: [`ParquetEncoder`]) from one column-oriented
//! description. No Parquet writer is built here: the one nklut uses (polars') is most of a
//! build, and the crates below the pipeline (the effects) must not carry it.
//!
//! How a set is published: every file goes to a fresh generation folder
//! `<out>/.sets/<set>-<stamp>`; one symbolic link `<out>/.sets/<set>` names the current
//! generation and is replaced by a single rename; each `<out>/<name>` (a file, or a folder
//! such as `luts/` or `effects_frames/`) is a fixed link to `.sets/<set>/<name>`. Readers
//! open `<out>/<name>` as before and see whichever generation the one link names. A
//! generation whose writing fails is removed at once (a full disk stays full no longer than
//! the failed run). Runs that publish into one output folder take turns: each holds an
//! exclusive lock on `<out>/.sets/.lock` (released by the kernel when the process ends,
//! however it ends) from before it tidies the folder until its set is switched in, so no
//! run removes a generation another is still writing; a run that has to wait says so.
//! Nothing under `.sets/` is followed out of it: the lock is opened without following a
//! link (and must be a regular file), the link `.sets/<set>` must name a generation by a
//! plain name (`<set>-<stamp>…`) that is a real folder inside `.sets/`, and what is removed
//! is a real folder directly under `.sets/` (or a link, never its target); anything else —
//! a link planted at `.sets/<set>`, `.sets/.lock` or a generation's name, or `.sets` itself
//! a link — is an error naming it, and nothing is written or removed. For tests, the environment variable `NKLUT_CRASH_AT` (`staged`, `switched` or `linked`)
//! aborts the process at that step.

use std::fs;
use std::io::Write;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result};
use rayon::prelude::*;

pub use crate::atomic::{temp_path, write_atomic, write_atomic_unflushed};

/// A file of a set: its name in the output folder (no folders) and its bytes.
#[derive(Clone, Debug, PartialEq)]
pub struct SetFile {
    pub name: String,
    pub bytes: Vec<u8>,
}

impl SetFile {
    pub fn new(name: impl Into<String>, bytes: Vec<u8>) -> Self {
        Self { name: name.into(), bytes }
    }
}

/// What a file of a set holds: its name in the output folder and a way to write its bytes.
pub trait SetContent: Sync {
    fn name(&self) -> &str;
    /// Write the whole file to `out`.
    fn write_to(&self, out: &mut dyn Write) -> Result<()>;
}

impl SetContent for SetFile {
    fn name(&self) -> &str {
        &self.name
    }

    fn write_to(&self, out: &mut dyn Write) -> Result<()> {
        out.write_all(&self.bytes)?;
        Ok(())
    }
}

/// A file of a set produced while it is written (a large table, block by block) instead
/// of held in memory whole.
pub struct StreamedFile<'a> {
    pub name: String,
    write: Box<Writer<'a>>,
}

/// What writes a streamed file's bytes.
type Writer<'a> = dyn Fn(&mut dyn Write) -> Result<()> + Sync + 'a;

impl<'a> StreamedFile<'a> {
    pub fn new(name: impl Into<String>, write: impl Fn(&mut dyn Write) -> Result<()> + Sync + 'a) -> Self {
        Self { name: name.into(), write: Box::new(write) }
    }
}

impl SetContent for StreamedFile<'_> {
    fn name(&self) -> &str {
        &self.name
    }

    fn write_to(&self, out: &mut dyn Write) -> Result<()> {
        (self.write)(out)
    }
}

/// The most bytes of a file or folder name made from an id (a page id's part, a strip's
/// stem, a paste-in file's name), before the suffix its writer adds (`.json`,
/// `_f0_srgb8.png`, …): file systems take 255 bytes a name, and a long id must not fail
/// the run for every page.
pub const MAX_STEM_BYTES: usize = 160;

/// FNV-1a (64-bit) of a text: a fixed hash, the same on every machine and run.
pub fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |hash, byte| (hash ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3))
}

/// `stem` itself when it is at most [`MAX_STEM_BYTES`] long; else its longest head (cut
/// at a character boundary) that leaves room for `separator` and the 16 hex digits of the
/// FNV-1a hash of the whole stem: at most `MAX_STEM_BYTES`, the same on every run, and
/// different for stems that differ anywhere (up to a 64-bit hash's collisions).
pub fn bounded_stem(stem: &str, separator: char) -> std::borrow::Cow<'_, str> {
    if stem.len() <= MAX_STEM_BYTES {
        return std::borrow::Cow::Borrowed(stem);
    }
    let mut cut = MAX_STEM_BYTES - 16 - separator.len_utf8();
    while !stem.is_char_boundary(cut) {
        cut -= 1;
    }
    std::borrow::Cow::Owned(format!("{}{separator}{:016x}", &stem[..cut], fnv1a(stem)))
}

/// The folder under the output folder that holds the generations of every set.
pub const SETS_DIR: &str = ".sets";

/// Abort here when `NKLUT_CRASH_AT` names this step (the kill tests' hook).
fn crash_point(step: &str) {
    if std::env::var_os("NKLUT_CRASH_AT").is_some_and(|v| v == step) {
        std::process::abort();
    }
}

/// The exclusive lock on an output folder's sets, held while a run publishes into it.
struct SetsLock {
    _file: fs::File,
}

/// The lock file under `.sets/`.
const LOCK_FILE: &str = ".lock";

impl SetsLock {
    /// Take the lock of `sets`, waiting (and saying so once) while another run holds it.
    fn take(sets: &Path) -> Result<SetsLock> {
        let path = sets.join(LOCK_FILE);
        let mut options = fs::OpenOptions::new();
        options.create(true).truncate(false).read(true).write(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt;
            // A link planted at the lock's name is not followed (its target is neither
            // truncated nor written), and a FIFO there does not block the open.
            options.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
        }
        let file = match options.open(&path) {
            Ok(file) => file,
            Err(error) if fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) => {
                anyhow::bail!(
                    "{} is a symbolic link, not the lock file nklut creates; nothing was written (remove the link): {error}",
                    path.display()
                )
            }
            Err(error) => return Err(error).with_context(|| format!("opening the lock {}", path.display())),
        };
        let metadata = file.metadata().with_context(|| format!("opening the lock {}", path.display()))?;
        if !metadata.is_file() {
            anyhow::bail!("{} is not a regular file, not the lock file nklut creates; nothing was written (remove it)", path.display());
        }
        #[cfg(unix)]
        {
            use std::os::fd::AsRawFd;
            // SAFETY: flock on a descriptor this function owns.
            let try_lock = || unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) };
            if try_lock() != 0 {
                // Who holds it, read from the descriptor already open (a few bytes at most).
                let mut holder = String::new();
                let _ = std::io::Read::read_to_string(&mut std::io::Read::take(&file, 64), &mut holder);
                eprintln!(
                    "waiting: another nklut run ({}) is publishing into {}; its outputs are switched in first",
                    if holder.trim().is_empty() { "pid unknown".to_string() } else { crate::escape::terminal(holder.trim()) },
                    sets.parent().unwrap_or(sets).display()
                );
                loop {
                    // SAFETY: as above, blocking until the holder ends or lets go.
                    if unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX) } == 0 {
                        break;
                    }
                    let error = std::io::Error::last_os_error();
                    if error.kind() != std::io::ErrorKind::Interrupted {
                        return Err(error).with_context(|| format!("locking {}", path.display()));
                    }
                }
            }
        }
        // Who holds it, for a run that has to wait (best effort: the lock is the flock).
        let _ = file.set_len(0);
        let _ = std::io::Seek::seek(&mut (&file), std::io::SeekFrom::Start(0));
        let _ = (&file).write_all(format!("pid {}", std::process::id()).as_bytes());
        Ok(SetsLock { _file: file })
    }
}

/// `.sets` under `out`, created when absent: a real folder, not a link to one elsewhere.
fn sets_folder(out: &Path) -> Result<PathBuf> {
    let sets = out.join(SETS_DIR);
    if fs::symlink_metadata(&sets).is_err() {
        fs::create_dir_all(&sets).with_context(|| format!("creating folder {}", sets.display()))?;
    }
    let metadata = fs::symlink_metadata(&sets).with_context(|| format!("reading {}", sets.display()))?;
    if metadata.file_type().is_symlink() {
        anyhow::bail!(
            "{} is a symbolic link; nklut keeps its generations in a real folder there and follows no link out of it (remove the link)",
            sets.display()
        );
    }
    if !metadata.is_dir() {
        anyhow::bail!("{} is not a folder (remove it)", sets.display());
    }
    Ok(sets)
}

/// Whether `name` (an entry directly under `.sets/`) has the form of a generation of
/// `set`: `<set>-` then a digit (`<set>-<stamp>-<pid>`, `<set>-0-adopted`, …).
fn is_generation_name(set: &str, name: &str) -> bool {
    name.strip_prefix(set).and_then(|rest| rest.strip_prefix('-')).is_some_and(|stamp| stamp.starts_with(|c: char| c.is_ascii_digit()))
        && !name.contains(['/', '\\'])
}

/// `<sets>/<name>` when it is a generation folder of `set`: a plain name of a generation's
/// form, and a real folder (not a link) directly under `.sets/`. Anything else is an
/// error naming it.
fn generation_folder(sets: &Path, set: &str, name: &str) -> Result<PathBuf> {
    let path = sets.join(name);
    if !is_generation_name(set, name) {
        anyhow::bail!(
            "{} names {name:?}, not a generation of the set {set} inside {}; nklut follows no link out of it (remove the link)",
            sets.join(set).display(),
            sets.display()
        );
    }
    let metadata = fs::symlink_metadata(&path).with_context(|| format!("reading the generation {}", path.display()))?;
    if metadata.file_type().is_symlink() {
        anyhow::bail!("{} is a symbolic link, not a generation folder nklut wrote; nothing was removed (remove the link)", path.display());
    }
    if !metadata.is_dir() {
        anyhow::bail!("{} is not a folder, not a generation nklut wrote (remove it)", path.display());
    }
    Ok(path)
}

/// The generation the link `<out>/.sets/<set>` names, if the link exists: checked to be a
/// generation folder inside `.sets/` ([`generation_folder`]); a link to anything else, or
/// a file or folder planted at the link's name, is an error naming it.
fn current_generation(sets: &Path, set: &str) -> Result<Option<String>> {
    let link = sets.join(set);
    let Ok(metadata) = fs::symlink_metadata(&link) else { return Ok(None) };
    if !metadata.file_type().is_symlink() {
        anyhow::bail!("{} is not the link to a generation that nklut writes there (remove it)", link.display());
    }
    let target = fs::read_link(&link).with_context(|| format!("reading the link {}", link.display()))?;
    let name = target.to_str().unwrap_or("").to_string();
    if name.is_empty()
        || Path::new(&name).components().count() != 1
        || !matches!(Path::new(&name).components().next(), Some(std::path::Component::Normal(_)))
    {
        anyhow::bail!(
            "{} is a link to {}, not to a generation of the set inside {}; nklut follows no link out of it, and nothing was removed (remove the link)",
            link.display(),
            target.display(),
            sets.display()
        );
    }
    generation_folder(sets, set, &name)?;
    Ok(Some(name))
}

/// Make `link` a symbolic link to `target`, replacing what is there by one rename.
#[cfg(unix)]
fn replace_with_link(target: &Path, link: &Path) -> Result<()> {
    let name = link.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = link.with_file_name(format!(".{name}.link-{}", std::process::id()));
    let _ = fs::remove_file(&tmp);
    std::os::unix::fs::symlink(target, &tmp).with_context(|| format!("linking {} to {}", tmp.display(), target.display()))?;
    fs::rename(&tmp, link).with_context(|| format!("renaming {} to {}", tmp.display(), link.display()))
}

#[cfg(not(unix))]
fn replace_with_link(_target: &Path, link: &Path) -> Result<()> {
    anyhow::bail!("publishing {} needs symbolic links (Unix)", link.display())
}

/// Is `<out>/<name>` already the fixed link into the set?
fn is_set_link(out: &Path, set: &str, name: &str) -> bool {
    fs::read_link(out.join(name)).is_ok_and(|t| t == Path::new(SETS_DIR).join(set).join(name))
}

/// Each name of a set belongs to that set alone: a `<out>/<name>` that is the link of
/// another set (`effects_errors.csv` of `nklut effects`, then of `nklut gpu run` into the
/// same folder) would mix two commands' outputs under one folder. Refused before anything
/// is written, naming the file and both sets.
fn check_owners(out: &Path, set: &str, names: &[&str]) -> Result<()> {
    for name in names {
        let Ok(target) = fs::read_link(out.join(name)) else { continue };
        let mut parts = target.components();
        let owner = match (parts.next(), parts.next(), parts.next(), parts.next()) {
            (Some(dir), Some(owner), Some(file), None) if dir.as_os_str() == SETS_DIR && file.as_os_str() == *name => {
                owner.as_os_str().to_string_lossy().into_owned()
            }
            _ => continue,
        };
        if owner != set {
            anyhow::bail!(
                "{} is written by another command (the set {owner:?}) and this one ({set:?}) writes a file of the same name: \
                 the two would be mixed in one folder; give each command its own --out",
                out.join(name).display()
            );
        }
    }
    Ok(())
}

/// Make `<out>/<name>` the fixed link into the set. A real folder there (written before
/// sets, or by hand) is moved under `.sets/` first, where the next run removes it.
fn link_entry(out: &Path, sets: &Path, set: &str, name: &str) -> Result<()> {
    let path = out.join(name);
    if fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir()) {
        let aside = sets.join(format!("{set}-0-displaced-{}-{name}", std::process::id()));
        fs::rename(&path, &aside).with_context(|| format!("moving the folder {} aside", path.display()))?;
    }
    replace_with_link(&Path::new(SETS_DIR).join(set).join(name), &path)
}

/// Remove generations of `set` that the link does not name (left by a killed or failed
/// run; called with the lock held, so none is being written).
fn remove_stale_generations(sets: &Path, set: &str) -> Result<()> {
    let current = current_generation(sets, set)?;
    for entry in fs::read_dir(sets).with_context(|| format!("listing {}", sets.display()))? {
        let name = entry?.file_name().to_string_lossy().into_owned();
        let stale_generation = is_generation_name(set, &name);
        let stale_link = name.starts_with(&format!(".{set}.link-"));
        if stale_generation && Some(&name) != current.as_ref() {
            // A real folder directly under `.sets/` (a link there is an error, not removed).
            let path = generation_folder(sets, set, &name)?;
            fs::remove_dir_all(&path).with_context(|| format!("removing the leftover {}", path.display()))?;
        } else if stale_link {
            // One of this module's temporary links: the link itself goes, never its target.
            let path = sets.join(&name);
            fs::remove_file(&path).with_context(|| format!("removing the leftover {}", path.display()))?;
        }
    }
    Ok(())
}

/// A set of at most this many files gets an `fsync` per file; a larger one (the paste-in
/// files of `params --all`, thousands of small files) is written without, as the bake's
/// strips are: at ~3 ms an `fsync` on this machine's ext4 they would cost more than the
/// stage. A crash of the process still leaves the previous set (the switch comes after
/// every write); a power cut right after a run may leave such files truncated.
const FSYNC_FILES: usize = 16;

/// Write the files and their folder to disk before the folder is published. The files are
/// created first (with the folders their names hold); then the folder's `fsync` and each
/// file (written, and when streamed produced, then `fsync`ed) run on threads of their own,
/// all at once: one file waits on the disk while the others are still being encoded. A set
/// of more than [`FSYNC_FILES`] files is written in parallel without the per-file `fsync`.
fn write_generation(dir: &Path, files: &[&dyn SetContent]) -> Result<()> {
    if files.len() > FSYNC_FILES {
        fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        return files.par_iter().try_for_each(|file| {
            let path = dir.join(file.name());
            if let Some(folder) = path.parent().filter(|folder| *folder != dir) {
                fs::create_dir_all(folder).with_context(|| format!("creating {}", folder.display()))?;
            }
            let mut f = std::io::BufWriter::new(fs::File::create(&path).with_context(|| format!("creating {}", path.display()))?);
            file.write_to(&mut f).with_context(|| format!("writing {}", path.display()))?;
            f.flush().with_context(|| format!("writing {}", path.display()))
        });
    }
    fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let created = files
        .iter()
        .map(|file| {
            let path = dir.join(file.name());
            if let Some(folder) = path.parent().filter(|folder| *folder != dir) {
                fs::create_dir_all(folder).with_context(|| format!("creating {}", folder.display()))?;
            }
            fs::File::create(&path).with_context(|| format!("creating {}", path.display()))
        })
        .collect::<Result<Vec<fs::File>>>()?;
    let write = |file: &dyn SetContent, mut f: fs::File| -> Result<()> {
        file.write_to(&mut f).with_context(|| format!("writing {}", dir.join(file.name()).display()))?;
        f.sync_all().ok();
        Ok(())
    };
    std::thread::scope(|scope| {
        // Every file is named in the folder by now: its entries go to disk beside the bytes.
        let folder = scope.spawn(|| {
            if let Ok(d) = fs::File::open(dir) {
                d.sync_all().ok();
            }
        });
        // At most a few writers at a time: a set of many files is written in rounds.
        let mut results: Vec<Result<()>> = Vec::with_capacity(files.len());
        let mut pending = files.iter().zip(created);
        loop {
            let round: Vec<_> = pending.by_ref().take(16).map(|(&file, f)| scope.spawn(move || write(file, f))).collect();
            if round.is_empty() {
                break;
            }
            // Every writer is joined; the first error in set order is returned, a panic goes on.
            results.extend(round.into_iter().map(|w| w.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))));
        }
        folder.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        results.into_iter().collect::<Result<()>>()
    })
}

/// An output folder written before sets existed holds plain files: move them into a
/// generation of their own (hard links, so each name keeps its bytes throughout) and
/// make the names links to it, so that the next switch replaces them all at once. (Plain
/// folders are moved aside when their link is made: [`link_entry`].)
fn adopt_plain_files(out: &Path, sets: &Path, set: &str, names: &[&str]) -> Result<()> {
    if current_generation(sets, set)?.is_some() {
        return Ok(());
    }
    let plain: Vec<&str> = names.iter().copied().filter(|n| fs::symlink_metadata(out.join(n)).is_ok_and(|m| m.is_file())).collect();
    if plain.is_empty() {
        return Ok(());
    }
    let generation = format!("{set}-0-adopted");
    let dir = sets.join(&generation);
    if fs::symlink_metadata(&dir).is_ok() {
        fs::remove_dir_all(generation_folder(sets, set, &generation)?)?;
    }
    fs::create_dir(&dir).with_context(|| format!("creating {}", dir.display()))?;
    for name in &plain {
        fs::hard_link(out.join(name), dir.join(name)).or_else(|_| fs::copy(out.join(name), dir.join(name)).map(|_| ()))?;
    }
    replace_with_link(Path::new(&generation), &sets.join(set))?;
    for name in plain {
        replace_with_link(&Path::new(SETS_DIR).join(set).join(name), &out.join(name))?;
    }
    Ok(())
}

/// The names a set's files take in the output folder: the first component of each file's
/// path, each once, in order.
fn top_level_names<'a>(paths: impl Iterator<Item = &'a str>) -> Vec<&'a str> {
    let mut names: Vec<&str> = Vec::new();
    for path in paths {
        let name = path.split('/').next().unwrap_or(path);
        if !names.contains(&name) {
            names.push(name);
        }
    }
    names
}

/// Publish `files` as the new set `set` under `out`, all at once: a run killed at any
/// point leaves `out` with the previous set or this one. Returns the paths written.
pub fn publish_set(out: &Path, set: &str, files: &[SetFile]) -> Result<Vec<PathBuf>> {
    publish_contents(out, set, &files.iter().map(|f| f as &dyn SetContent).collect::<Vec<_>>())
}

/// [`publish_set`] for files held in memory or streamed ([`SetContent`]). A name may hold
/// folders (`effects_frames/x.png`): its first component is then the set's name for it.
pub fn publish_contents(out: &Path, set: &str, files: &[&dyn SetContent]) -> Result<Vec<PathBuf>> {
    for file in files {
        check_relative(file.name())?;
    }
    let names = top_level_names(files.iter().map(|f| f.name()));
    publish_generation(out, set, &names, &|generation| write_generation(generation, files))?;
    Ok(files.iter().map(|f| out.join(f.name())).collect())
}

/// Publish the folder `<out>/<folder>` (`luts`, `report`) as the set of the same name,
/// all at once: `fill` writes the whole folder into the empty folder it is given (as its
/// files are computed, say); if it fails, nothing of it stays. Returns `<out>/<folder>`.
pub fn publish_folder_with(out: &Path, folder: &str, fill: &dyn Fn(&Path) -> Result<()>) -> Result<PathBuf> {
    check_relative(folder)?;
    publish_generation(out, folder, &[folder], &|generation| {
        let dir = generation.join(folder);
        fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        fill(&dir)
    })?;
    Ok(out.join(folder))
}

/// A file's path in a set: relative, '/'-separated, with no empty, `.` or `..` part.
fn check_relative(path: &str) -> Result<()> {
    if path.is_empty() || path.split('/').any(|part| part.is_empty() || part == "." || part == "..") || path.contains('\\') {
        anyhow::bail!("bad output path {path:?}");
    }
    Ok(())
}

/// The steps every set takes: under the lock, tidy the folder, have `fill` write a fresh
/// generation (removed again if it fails), link names new to the set, switch the set's link
/// to the generation, relink the other names, and remove the previous generation.
fn publish_generation(out: &Path, set: &str, names: &[&str], fill: &dyn Fn(&Path) -> Result<()>) -> Result<()> {
    fs::create_dir_all(out).with_context(|| format!("creating folder {}", out.display()))?;
    let sets = sets_folder(out)?;
    let _lock = SetsLock::take(&sets)?;
    check_owners(out, set, names)?;
    adopt_plain_files(out, &sets, set, names)?;
    remove_stale_generations(&sets, set)?;
    let previous = current_generation(&sets, set)?;
    let stamp = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_nanos()).unwrap_or(0);
    let generation = format!("{set}-{stamp}-{}", std::process::id());
    let dir = sets.join(&generation);
    let written = fs::create_dir(&dir).with_context(|| format!("creating {}", dir.display())).and_then(|_| fill(&dir));
    if let Err(error) = written {
        let _ = fs::remove_dir_all(&dir);
        return Err(error);
    }
    crash_point("staged");
    // Names new to the set get their link first; it dangles (reads as absent) until the
    // switch, as the previous set had no such file.
    for name in names.iter().filter(|name| fs::symlink_metadata(out.join(name)).is_err()) {
        link_entry(out, &sets, set, name)?;
    }
    replace_with_link(Path::new(&generation), &sets.join(set))?;
    crash_point("switched");
    for name in names.iter().filter(|name| !is_set_link(out, set, name)) {
        link_entry(out, &sets, set, name)?;
    }
    crash_point("linked");
    if let Some(previous) = previous.filter(|p| *p != generation) {
        // Checked again: a real generation folder directly under `.sets/`.
        if let Ok(path) = generation_folder(&sets, set, &previous) {
            let _ = fs::remove_dir_all(path);
        }
    }
    Ok(())
}

/// One column of a table: a name, a unit or meaning for the manifest, and the values.
#[derive(Clone, Debug)]
pub struct Column {
    pub name: String,
    pub description: String,
    pub values: Values,
}

/// Column values. `None` in an optional float column is written as an empty CSV cell,
/// a Parquet null and a JSON null.
#[derive(Clone, Debug)]
pub enum Values {
    Text(Vec<String>),
    /// Text whose values repeat down the column (page ids, method names in a table of
    /// every page × method): each distinct value stored once, rows share it. Written
    /// exactly as `Text`.
    SharedText(Vec<Arc<str>>),
    Float(Vec<Option<f64>>),
    Integer(Vec<i64>),
    Boolean(Vec<bool>),
}

impl Values {
    fn len(&self) -> usize {
        match self {
            Values::Text(v) => v.len(),
            Values::SharedText(v) => v.len(),
            Values::Float(v) => v.len(),
            Values::Integer(v) => v.len(),
            Values::Boolean(v) => v.len(),
        }
    }

    /// Whether rows `a` and `b` hold the same value, so that their cells are the same text
    /// (floats compared bit for bit; shared text by its one stored copy).
    fn same(&self, a: usize, b: usize) -> bool {
        match self {
            Values::Text(v) => v[a] == v[b],
            Values::SharedText(v) => Arc::ptr_eq(&v[a], &v[b]),
            Values::Float(v) => v[a].map(f64::to_bits) == v[b].map(f64::to_bits),
            Values::Integer(v) => v[a] == v[b],
            Values::Boolean(v) => v[a] == v[b],
        }
    }

    /// Append the CSV text of a cell (text through [`crate::escape::csv`], floats as
    /// [`format_float`]; empty for `None`).
    fn write_cell(&self, row: usize, out: &mut String) {
        use std::fmt::Write as _;
        let _ = match self {
            // Text as a CSV cell shows it: controls written as `\u{…}` (crate::escape::csv).
            Values::Text(v) => {
                out.push_str(&crate::escape::csv(&v[row]));
                Ok(())
            }
            Values::SharedText(v) => {
                out.push_str(&crate::escape::csv(&v[row]));
                Ok(())
            }
            Values::Float(v) => v[row].map_or(Ok(()), |x| write!(out, "{x}")),
            Values::Integer(v) => write!(out, "{}", v[row]),
            Values::Boolean(v) => write!(out, "{}", v[row]),
        };
    }

    fn json(&self, row: usize) -> serde_json::Value {
        match self {
            Values::Text(v) => serde_json::Value::from(v[row].clone()),
            Values::SharedText(v) => serde_json::Value::from(&*v[row]),
            Values::Float(v) => v[row].filter(|x| x.is_finite()).map(serde_json::Value::from).unwrap_or(serde_json::Value::Null),
            Values::Integer(v) => serde_json::Value::from(v[row]),
            Values::Boolean(v) => serde_json::Value::from(v[row]),
        }
    }
}

/// The rows of a table as JSON objects, keys in `order` (column indices by name).
struct JsonRows<'a> {
    table: &'a Table,
    order: &'a [usize],
}

/// One row of [`JsonRows`].
struct JsonRow<'a> {
    rows: &'a JsonRows<'a>,
    row: usize,
}

/// One cell of a [`JsonRow`], serialized as [`Values::json`] gives it.
struct JsonCell<'a> {
    values: &'a Values,
    row: usize,
}

impl serde::Serialize for JsonRows<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeSeq;
        let mut seq = serializer.serialize_seq(Some(self.table.rows()))?;
        for row in 0..self.table.rows() {
            seq.serialize_element(&JsonRow { rows: self, row })?;
        }
        seq.end()
    }
}

impl serde::Serialize for JsonRow<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = serializer.serialize_map(Some(self.rows.order.len()))?;
        for &c in self.rows.order {
            let column = &self.rows.table.columns[c];
            map.serialize_entry(&column.name, &JsonCell { values: &column.values, row: self.row })?;
        }
        map.end()
    }
}

impl serde::Serialize for JsonCell<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self.values {
            Values::Text(v) => serializer.serialize_str(&v[self.row]),
            Values::SharedText(v) => serializer.serialize_str(&v[self.row]),
            Values::Float(v) => match v[self.row].filter(|x| x.is_finite()) {
                Some(x) => serializer.serialize_f64(x),
                None => serializer.serialize_unit(),
            },
            Values::Integer(v) => serializer.serialize_i64(v[self.row]),
            Values::Boolean(v) => serializer.serialize_bool(v[self.row]),
        }
    }
}

/// Shortest text that reads back to the same f64 (Rust's `Display` is round-trip exact).
pub fn format_float(x: f64) -> String {
    format!("{x}")
}

/// The distinct values of a text column, each stored once: `get` hands out a shared copy.
#[derive(Debug, Default)]
pub struct SharedText {
    values: std::collections::HashMap<String, Arc<str>>,
}

impl SharedText {
    pub fn get(&mut self, value: &str) -> Arc<str> {
        if let Some(shared) = self.values.get(value) {
            return shared.clone();
        }
        let shared: Arc<str> = Arc::from(value);
        self.values.insert(value.to_string(), shared.clone());
        shared
    }
}

/// Rows per CSV block: blocks are formatted in parallel.
const CSV_BLOCK: usize = 16_384;

/// Rows per Parquet row group at most, as polars' writer forms them.
pub const PARQUET_ROW_GROUP: usize = 512 * 512;

/// A table too large to hold whole, written in row blocks: `block(range)` builds the table
/// of the rows in `range` (every block with the same columns). [`RowBlocks::write_csv`]
/// gives the bytes [`Table::to_csv`] gives on the whole table; a Parquet writer encodes
/// one of [`RowBlocks::row_groups`] at a time.
pub struct RowBlocks<'a> {
    pub rows: usize,
    pub block: &'a (dyn Fn(Range<usize>) -> Table + Sync),
}

impl RowBlocks<'_> {
    /// CSV, `CSV_BLOCK` rows per block, one block per thread formatted in parallel at a time
    /// and written in order.
    pub fn write_csv(&self, out: &mut dyn Write) -> Result<()> {
        let rows = self.rows;
        let blocks = rows.div_ceil(CSV_BLOCK).max(1);
        let batch = rayon::current_num_threads().max(1);
        for first in (0..blocks).step_by(batch) {
            let texts: Vec<Result<Vec<u8>>> = (first..(first + batch).min(blocks))
                .into_par_iter()
                .map(|b| {
                    let range = b * CSV_BLOCK..((b + 1) * CSV_BLOCK).min(rows);
                    (self.block)(range.clone()).csv_records(0..range.len(), b == 0)
                })
                .collect();
            for text in texts {
                out.write_all(&text?)?;
            }
        }
        Ok(())
    }

    /// The row ranges of the Parquet row groups polars' writer forms from the whole table
    /// (⌊rows / 512²⌋ parts of equal size, the last with the remainder; one part below
    /// 512² rows): a block writer encodes one group at a time.
    pub fn row_groups(&self) -> Vec<Range<usize>> {
        let rows = self.rows;
        let parts = (rows / PARQUET_ROW_GROUP).max(1);
        let size = rows / parts;
        (0..parts).map(|i| if i + 1 == parts { i * size..rows } else { i * size..(i + 1) * size }).collect()
    }
}

/// A column-oriented table, built column by column, written as CSV, JSON and (through a
/// [`ParquetEncoder`]) Parquet.
#[derive(Clone, Debug, Default)]
pub struct Table {
    pub columns: Vec<Column>,
}

impl Table {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn rows(&self) -> usize {
        self.columns.first().map(|c| c.values.len()).unwrap_or(0)
    }

    pub(crate) fn push(&mut self, name: &str, description: &str, values: Values) -> &mut Self {
        assert!(
            self.columns.is_empty() || values.len() == self.rows(),
            "column {name} has {} rows, table has {}",
            values.len(),
            self.rows()
        );
        self.columns.push(Column { name: name.into(), description: description.into(), values });
        self
    }

    pub fn text(&mut self, name: &str, description: &str, values: Vec<String>) -> &mut Self {
        self.push(name, description, Values::Text(values))
    }

    /// A text column of repeating values (see [`Values::SharedText`] and [`SharedText`]).
    pub fn shared_text(&mut self, name: &str, description: &str, values: Vec<Arc<str>>) -> &mut Self {
        self.push(name, description, Values::SharedText(values))
    }

    pub fn float(&mut self, name: &str, description: &str, values: Vec<f64>) -> &mut Self {
        self.push(name, description, Values::Float(values.into_iter().map(Some).collect()))
    }

    pub fn optional_float(&mut self, name: &str, description: &str, values: Vec<Option<f64>>) -> &mut Self {
        self.push(name, description, Values::Float(values))
    }

    pub fn integer(&mut self, name: &str, description: &str, values: Vec<i64>) -> &mut Self {
        self.push(name, description, Values::Integer(values))
    }

    pub fn boolean(&mut self, name: &str, description: &str, values: Vec<bool>) -> &mut Self {
        self.push(name, description, Values::Boolean(values))
    }

    /// Look a column up by name.
    pub fn column(&self, name: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.name == name)
    }

    /// CSV records of the rows in `rows`, after a header of column names if asked.
    fn csv_records(&self, rows: Range<usize>, header: bool) -> Result<Vec<u8>> {
        let mut writer = csv::Writer::from_writer(Vec::new());
        if header {
            writer.write_record(self.columns.iter().map(|c| c.name.as_str()))?;
        }
        // Each column's cell of the previous row, formatted again only when the value changes
        // (down a column, values repeat: the page, the channel's index, the method).
        let mut cells = vec![String::new(); self.columns.len()];
        for row in rows.clone() {
            for (column, cell) in self.columns.iter().zip(&mut cells) {
                if row == rows.start || !column.values.same(row - 1, row) {
                    // No table holds NaN or an infinity: a stage that computed one has a
                    // defect to name, not a cell to write.
                    if let Values::Float(values) = &column.values {
                        if let Some(x) = values[row].filter(|x| !x.is_finite()) {
                            anyhow::bail!("column {} of row {row} holds {x}, not a finite number", column.name);
                        }
                    }
                    cell.clear();
                    column.values.write_cell(row, cell);
                }
                writer.write_field(&*cell)?;
            }
            writer.write_record(None::<&[u8]>)?;
        }
        writer.into_inner().context("flushing CSV")
    }

    /// The table as CSV: a header of column names, then one record per row. Blocks of rows
    /// are formatted in parallel and joined in order (the bytes do not depend on it).
    pub fn to_csv(&self) -> Result<Vec<u8>> {
        let rows = self.rows();
        let blocks: Vec<Result<Vec<u8>>> = (0..rows.div_ceil(CSV_BLOCK).max(1))
            .into_par_iter()
            .map(|block| self.csv_records(block * CSV_BLOCK..((block + 1) * CSV_BLOCK).min(rows), block == 0))
            .collect();
        let blocks = blocks.into_iter().collect::<Result<Vec<_>>>()?;
        // One allocation of the final size: growing by doubling would hold up to twice the
        // table's bytes while the last block is copied in.
        let mut bytes = Vec::with_capacity(blocks.iter().map(Vec::len).sum());
        for block in blocks {
            bytes.extend_from_slice(&block);
        }
        Ok(bytes)
    }

    /// The table as a pretty-printed JSON array of one object per row, keys in name order
    /// (as a `serde_json::Map` orders them), missing and non-finite floats as null.
    pub fn to_json(&self) -> Result<Vec<u8>> {
        let mut order: Vec<usize> = (0..self.columns.len()).collect();
        order.sort_by(|&a, &b| self.columns[a].name.cmp(&self.columns[b].name));
        let mut bytes = if order.windows(2).any(|w| self.columns[w[0]].name == self.columns[w[1]].name) {
            // Two columns of one name: a map keeps one of them, as it always did.
            let rows: Vec<serde_json::Value> = (0..self.rows())
                .map(|row| {
                    let object = self.columns.iter().map(|c| (c.name.clone(), c.values.json(row))).collect();
                    serde_json::Value::Object(object)
                })
                .collect();
            serde_json::to_vec_pretty(&rows)?
        } else {
            // Streamed from the columns: no value tree per row.
            serde_json::to_vec_pretty(&JsonRows { table: self, order: &order })?
        };
        bytes.push(b'\n');
        Ok(bytes)
    }

    /// The columns' names and descriptions (units and meaning) as JSON, so that an engine
    /// or a script can read what each column is without reading this code (SPEC §7).
    pub fn columns_json(&self, stem: &str) -> Result<Vec<u8>> {
        self.columns_json_of(stem, self.rows())
    }

    /// [`columns_json`](Self::columns_json) of a table of `rows` rows with these columns
    /// (a table written in blocks: this one holds none or some of them).
    pub fn columns_json_of(&self, stem: &str, rows: usize) -> Result<Vec<u8>> {
        let columns: Vec<serde_json::Value> =
            self.columns.iter().map(|c| serde_json::json!({ "name": c.name, "description": c.description })).collect();
        let mut bytes = serde_json::to_vec_pretty(&serde_json::json!({ "table": stem, "rows": rows, "columns": columns }))?;
        bytes.push(b'\n');
        Ok(bytes)
    }

    /// The files of the table ([`streamed_files_with`](Self::streamed_files_with)) encoded into
    /// memory, side by side on the cores (the encodings of a large table take about as long
    /// each).
    pub fn files_with(&self, stem: &str, json: bool, parquet: ParquetEncoder) -> Result<Vec<SetFile>> {
        self.streamed_files_with(stem, json, parquet)
            .par_iter()
            .map(|file| {
                let mut bytes = Vec::new();
                file.write_to(&mut bytes)?;
                Ok(SetFile::new(file.name.clone(), bytes))
            })
            .collect()
    }

    /// The files of the table: `<stem>.columns.json` (the column documentation),
    /// `<stem>.csv`, `<stem>.parquet` (encoded by `parquet`) and, when asked, `<stem>.json`,
    /// each encoded while it is written: handed to [`publish_contents`], the encodings run
    /// side by side and each file goes to disk as soon as its own encoding is done.
    pub fn streamed_files_with(&self, stem: &str, json: bool, parquet: ParquetEncoder) -> Vec<StreamedFile<'_>> {
        let encoded =
            |encode: fn(&Table) -> Result<Vec<u8>>| move |out: &mut dyn Write| -> Result<()> { Ok(out.write_all(&encode(self)?)?) };
        let stem_owned = stem.to_string();
        let mut files = vec![
            StreamedFile::new(format!("{stem}.columns.json"), move |out: &mut dyn Write| -> Result<()> {
                Ok(out.write_all(&self.columns_json(&stem_owned)?)?)
            }),
            StreamedFile::new(format!("{stem}.csv"), encoded(Table::to_csv)),
            StreamedFile::new(format!("{stem}.parquet"), encoded(parquet)),
        ];
        if json {
            files.push(StreamedFile::new(format!("{stem}.json"), encoded(Table::to_json)));
        }
        files
    }

    /// Publish the table's [`files_with`](Self::files_with) under `dir` as the set `stem`.
    pub fn write_with(&self, dir: &Path, stem: &str, json: bool, parquet: ParquetEncoder) -> Result<Vec<PathBuf>> {
        let files = self.streamed_files_with(stem, json, parquet);
        publish_contents(dir, stem, &files.iter().map(|f| f as &dyn SetContent).collect::<Vec<_>>())
    }
}

/// What encodes a whole table as a Parquet file. This crate holds no Parquet writer (the
/// one nklut uses, polars', is most of a build); the layer that has one passes its encoder
/// (`nklut_pipeline::output::parquet`) to [`Table::streamed_files_with`] and the like.
pub type ParquetEncoder = fn(&Table) -> Result<Vec<u8>>;

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Table {
        let mut table = Table::new();
        table
            .text("page", "page id", vec!["main/Au/Johnson".into(), "a,b".into()])
            .optional_float("n", "refractive index", vec![Some(0.25), None])
            .integer("count", "count", vec![3, -1])
            .boolean("flag", "flag", vec![true, false]);
        table
    }

    #[test]
    fn csv_quotes_and_leaves_missing_floats_empty() {
        let text = String::from_utf8(sample().to_csv().unwrap()).unwrap();
        assert_eq!(text, "page,n,count,flag\nmain/Au/Johnson,0.25,3,true\n\"a,b\",,-1,false\n");
    }

    /// A cell that repeats the one above it is the same text, and a value that only looks
    /// like its neighbour (−0 after 0, a missing float after an empty text, equal text in
    /// another copy) is written as itself; a block that starts below a repeat writes it.
    #[test]
    fn csv_writes_every_cell_as_its_own_value() {
        let mut table = Table::new();
        let shared: Arc<str> = Arc::from("x");
        table
            .optional_float("f", "", vec![Some(0.0), Some(0.0), Some(-0.0), Some(-0.0), None, None, Some(0.1), Some(2.5)])
            .shared_text(
                "s",
                "",
                vec![shared.clone(), shared.clone(), Arc::from("x"), Arc::from(""), Arc::from(""), shared.clone(), shared, Arc::from("y")],
            )
            .integer("i", "", vec![1, 1, 1, 2, 2, 2, 1, 1])
            .boolean("b", "", vec![true, true, false, false, true, true, true, false]);
        let text = String::from_utf8(table.to_csv().unwrap()).unwrap();
        assert_eq!(text, "f,s,i,b\n0,x,1,true\n0,x,1,true\n-0,x,1,false\n-0,,2,false\n,,2,true\n,x,2,true\n0.1,x,1,true\n2.5,y,1,false\n");
        // A table holding NaN or an infinity is an error naming the cell, never a cell.
        let mut bad = Table::new();
        bad.optional_float("g", "", vec![Some(1.0), None, Some(f64::INFINITY)]);
        assert_eq!(bad.to_csv().unwrap_err().to_string(), "column g of row 2 holds inf, not a finite number");
        let block = String::from_utf8(table.csv_records(3..5, false).unwrap()).unwrap();
        assert_eq!(block, "-0,,2,false\n,,2,true\n");
    }

    #[test]
    fn json_writes_null_for_missing() {
        let value: serde_json::Value = serde_json::from_slice(&sample().to_json().unwrap()).unwrap();
        assert_eq!(value[0]["n"], 0.25);
        assert!(value[1]["n"].is_null());
        assert_eq!(value[1]["page"], "a,b");
    }

    /// The streamed JSON is the text of a `serde_json::Value` tree of the rows.
    #[test]
    fn json_rows_are_the_value_tree_s_text() {
        let mut table = sample();
        table.float("a_first", "sorted before the others", vec![f64::NAN, 1e300]).shared_text(
            "z \"quoted\"",
            "escaped",
            vec![Arc::from("é\n"), Arc::from("")],
        );
        let rows: Vec<serde_json::Value> = (0..2)
            .map(|row| serde_json::Value::Object(table.columns.iter().map(|c| (c.name.clone(), c.values.json(row))).collect()))
            .collect();
        let mut expected = serde_json::to_vec_pretty(&rows).unwrap();
        expected.push(b'\n');
        assert_eq!(String::from_utf8(table.to_json().unwrap()).unwrap(), String::from_utf8(expected).unwrap());
        assert_eq!(Table::new().to_json().unwrap(), b"[]\n");
        // Two columns of one name: the later one, as a map keeps it.
        let mut twice = Table::new();
        twice.integer("x", "first", vec![1]).integer("x", "second", vec![2]);
        assert_eq!(twice.to_json().unwrap(), b"[\n  {\n    \"x\": 2\n  }\n]\n");
    }

    #[test]
    fn column_documentation_names_every_column() {
        let value: serde_json::Value = serde_json::from_slice(&sample().columns_json("t").unwrap()).unwrap();
        assert_eq!(value["rows"], 2);
        assert_eq!(value["columns"][1]["name"], "n");
        assert_eq!(value["columns"][1]["description"], "refractive index");
    }

    /// Shared text writes as plain text in CSV and JSON: the same bytes (Parquet: the
    /// pipeline's test).
    #[test]
    fn shared_text_gives_the_same_bytes() {
        let plain = sample();
        let mut shared = plain.clone();
        let mut values = SharedText::default();
        for column in &mut shared.columns {
            if let Values::Text(v) = &column.values {
                column.values = Values::SharedText(v.iter().map(|s| values.get(s)).collect());
            }
        }
        assert!(shared.columns.iter().any(|c| matches!(c.values, Values::SharedText(_))));
        assert_eq!(plain.to_csv().unwrap(), shared.to_csv().unwrap());
        assert_eq!(plain.to_json().unwrap(), shared.to_json().unwrap());
        assert!(Arc::ptr_eq(&values.get("a,b"), &values.get("a,b")));
    }

    /// A table written in row blocks gives the CSV bytes of the whole table across block
    /// boundaries, quoted text, missing floats and repeated text included; its Parquet row
    /// groups are ⌊rows / 512²⌋ parts of equal size, the last with the remainder.
    #[test]
    fn row_blocks_give_the_bytes_of_the_whole_table() {
        let rows = 3 * CSV_BLOCK + 345;
        let table_of = |range: Range<usize>| {
            let mut shared = SharedText::default();
            let mut table = Table::new();
            table
                .shared_text(
                    "page",
                    "page id",
                    range.clone().map(|i| shared.get(if i % 3 == 0 { "a,b" } else { "main/Au/Johnson" })).collect(),
                )
                .optional_float("x", "a value", range.clone().map(|i| (i % 7 != 0).then_some(i as f64 / 3.0)).collect())
                .integer("i", "row", range.map(|i| i as i64).collect());
            table
        };
        let whole = table_of(0..rows);
        let blocks = RowBlocks { rows, block: &table_of };
        let mut csv = Vec::new();
        blocks.write_csv(&mut csv).unwrap();
        assert!(csv == whole.to_csv().unwrap(), "CSV differs");
        assert_eq!(table_of(0..0).columns_json_of("t", rows).unwrap(), whole.columns_json("t").unwrap());
        // 2·512² + 12 345 = 536 633 rows: two groups of ⌊536 633 / 2⌋ = 268 316 rows, the
        // second with the remainder; 3·512²: three of 512²; below 512², one.
        let groups = |rows| RowBlocks { rows, block: &table_of }.row_groups();
        assert_eq!(groups(2 * 262_144 + 12_345), vec![0..268_316, 268_316..536_633]);
        assert_eq!(groups(3 * 262_144), vec![0..262_144, 262_144..524_288, 524_288..786_432]);
        assert_eq!(groups(1000), vec![0..1000]);
        assert_eq!(groups(0), vec![0..0]);
    }

    /// The names of a set read the newest generation; a second publish replaces every
    /// file at once, adopts plain files written before sets, and leaves one generation.
    #[test]
    fn sets_replace_every_file_and_keep_one_generation() {
        let dir = std::env::temp_dir().join(format!("nklut-set-test-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        fs::write(dir.join("a.csv"), b"plain").unwrap();
        publish_set(&dir, "t", &[SetFile::new("a.csv", b"one".to_vec()), SetFile::new("b.csv", b"uno".to_vec())]).unwrap();
        assert_eq!(fs::read(dir.join("a.csv")).unwrap(), b"one");
        publish_set(&dir, "t", &[SetFile::new("a.csv", b"two".to_vec()), SetFile::new("b.csv", b"dos".to_vec())]).unwrap();
        assert_eq!(fs::read(dir.join("a.csv")).unwrap(), b"two");
        assert_eq!(fs::read(dir.join("b.csv")).unwrap(), b"dos");
        let generations = fs::read_dir(dir.join(SETS_DIR)).unwrap().filter(|e| e.as_ref().unwrap().file_type().unwrap().is_dir()).count();
        assert_eq!(generations, 1);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn atomic_write_replaces_and_leaves_no_temp() {
        let dir = std::env::temp_dir().join(format!("nklut-output-test-{}", std::process::id()));
        let path = dir.join("x.txt");
        write_atomic(&path, b"one").unwrap();
        write_atomic(&path, b"two").unwrap();
        assert_eq!(fs::read(&path).unwrap(), b"two");
        assert!(!temp_path(&path).exists());
        fs::remove_dir_all(&dir).unwrap();
    }
}
