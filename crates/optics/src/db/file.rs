//! Reading the files a run is pointed at — data files, the catalog, `about.yml`, scene
//! files, meshes — without trusting them to be plain files. Only a regular file is read:
//! the path is looked at (`stat`, which neither opens nor blocks) before it is opened, and
//! the opened file again (`fstat`), so a FIFO, a device, a socket or a folder is refused
//! before any read and nothing waits on a writer that never comes. The size is checked
//! against the caller's bound before the buffer grows, and reading stops one byte past the
//! bound, so a file that reports no size (as /proc's do) cannot grow a buffer without limit.
//! [`resolved`] gives the path the kernel opened, symbolic links followed, for checks that
//! a file lies inside a folder.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Why a file was not read.
#[derive(Debug, thiserror::Error)]
pub enum FileProblem {
    /// It does not exist or cannot be opened or read.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// Something other than a regular file (a FIFO, a device, a socket, a folder).
    #[error("{0} is not a regular file; only regular files are read")]
    NotRegular(&'static str),
    /// Larger than the caller's bound.
    #[error("the file holds more than {limit} bytes, the most read from such a file")]
    TooLarge {
        /// The bound (bytes).
        limit: u64,
    },
}

/// What kind of file the metadata describe, in words.
fn kind(metadata: &std::fs::Metadata) -> &'static str {
    let file_type = metadata.file_type();
    if file_type.is_dir() {
        return "a folder";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if file_type.is_char_device() {
            return "a character device";
        }
        if file_type.is_block_device() {
            return "a block device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    "a special file"
}

/// Open `path` for reading if it is a regular file (links followed), without blocking.
pub fn open_regular(path: &Path) -> Result<File, FileProblem> {
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        return Err(FileProblem::NotRegular(kind(&metadata)));
    }
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        // Should the path have become a FIFO since the look, opening does not wait for a
        // writer; the check below then refuses it.
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    let metadata = file.metadata()?;
    if !metadata.is_file() {
        return Err(FileProblem::NotRegular(kind(&metadata)));
    }
    Ok(file)
}

/// Read the whole regular file `file` (opened by [`open_regular`]) into `buffer` (kept and
/// reused: its length only grows), at most `limit` bytes. Returns the number of bytes read.
pub fn read_opened(mut file: File, limit: u64, buffer: &mut Vec<u8>) -> Result<usize, FileProblem> {
    let stated = file.metadata()?.len();
    if stated > limit {
        return Err(FileProblem::TooLarge { limit });
    }
    // One byte past the bound is read, to tell a file of `limit` bytes from a longer one.
    let end = usize::try_from(limit).unwrap_or(usize::MAX).saturating_add(1);
    let mut length = 0;
    loop {
        if length == end {
            return Err(FileProblem::TooLarge { limit });
        }
        if length == buffer.len() {
            let grown = (2 * buffer.len()).max(1 << 16).max(usize::try_from(stated).unwrap_or(usize::MAX).saturating_add(1));
            buffer.resize(grown.min(end), 0);
        }
        let room = buffer.len().min(end);
        match file.read(&mut buffer[length..room]) {
            Ok(0) => return Ok(length),
            Ok(read) => length += read,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e.into()),
        }
    }
}

/// [`open_regular`] then [`read_opened`] into a fresh buffer, cut to what was read.
pub fn read_regular(path: &Path, limit: u64) -> Result<Vec<u8>, FileProblem> {
    let mut buffer = Vec::new();
    let length = read_opened(open_regular(path)?, limit, &mut buffer)?;
    buffer.truncate(length);
    Ok(buffer)
}

/// [`read_regular`] as UTF-8 text (a byte-order mark kept; invalid UTF-8 is an I/O error
/// of kind `InvalidData`).
pub fn read_regular_text(path: &Path, limit: u64) -> Result<String, FileProblem> {
    let bytes = read_regular(path, limit)?;
    String::from_utf8(bytes).map_err(|e| FileProblem::Io(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))
}

/// The path the kernel opened for `file` (`path` when opened), every symbolic link
/// followed: /proc/self/fd on Linux (one call), else the canonical form of `path`.
pub fn resolved(file: &File, path: &Path) -> std::io::Result<PathBuf> {
    #[cfg(target_os = "linux")]
    {
        use std::os::fd::AsRawFd;
        if let Ok(target) = std::fs::read_link(format!("/proc/self/fd/{}", file.as_raw_fd())) {
            return Ok(target);
        }
    }
    let _ = file;
    std::fs::canonicalize(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_are_read_within_their_bound_and_nothing_else_is_opened() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.yml");
        std::fs::write(&file, b"0123456789").unwrap();
        assert_eq!(read_regular(&file, 10).unwrap(), b"0123456789");
        assert!(matches!(read_regular(&file, 9), Err(FileProblem::TooLarge { limit: 9 })));
        assert!(matches!(read_regular(dir.path(), 100), Err(FileProblem::NotRegular("a folder"))));
        assert!(matches!(read_regular(&dir.path().join("missing"), 100), Err(FileProblem::Io(_))));
        #[cfg(unix)]
        {
            // A FIFO with no writer: refused at once instead of waiting for one.
            let fifo = dir.path().join("fifo");
            let name = std::ffi::CString::new(fifo.as_os_str().as_encoded_bytes()).unwrap();
            // SAFETY: mkfifo reads a NUL-terminated path.
            assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
            assert!(matches!(read_regular(&fifo, 100), Err(FileProblem::NotRegular("a FIFO (named pipe)"))));
            assert!(matches!(read_regular(Path::new("/dev/zero"), 100), Err(FileProblem::NotRegular("a character device"))));
            // A link to a device is the device.
            let link = dir.path().join("zero.yml");
            std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
            assert!(matches!(read_regular(&link, 100), Err(FileProblem::NotRegular(_))));
            // The resolved path of a link is its target's.
            let other = dir.path().join("b.yml");
            std::os::unix::fs::symlink(&file, &other).unwrap();
            let opened = open_regular(&other).unwrap();
            assert_eq!(resolved(&opened, &other).unwrap(), std::fs::canonicalize(&file).unwrap());
        }
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_file_that_states_no_size_stops_at_the_bound() {
        // /proc/self/maps reports a size of 0 and holds more than 16 bytes.
        let mut buffer = Vec::new();
        let opened = open_regular(Path::new("/proc/self/maps")).unwrap();
        assert!(matches!(read_opened(opened, 16, &mut buffer), Err(FileProblem::TooLarge { limit: 16 })));
        assert_eq!(buffer.len(), 17);
    }
}
