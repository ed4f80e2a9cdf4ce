//! Reading the files users hand the suite (INI files and their includes,
//! HAL and Tcl files, tool tables, part programs, compensation tables,
//! drive files, sample files): one bounded, regular-file-only reader that
//! every such reader uses.
//!
//! A path that names a FIFO, a device (`/dev/zero`), a socket or a
//! directory is refused before a byte is read, and opening never blocks
//! (a FIFO without a writer would hold the caller forever). A regular file
//! larger than the caller's limit is refused with the limit in the message;
//! a file that grows while it is read stops at the limit too. The error
//! names the kind of file, the path and why, so a careless `#INCLUDE
//! /dev/zero` costs a line of text, not memory. Streams that are not
//! files (standard input, pipes) are read a bounded line at a time
//! ([`read_line_within`]); a file written back is replaced whole
//! ([`replace_file`]).

use std::fs::{File, OpenOptions};
use std::io::Read;
use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
use std::path::{Path, PathBuf};

/// Size limits of the kinds of files the suite reads, in bytes. Each is
/// far above any real file of its kind and far below what would hurt.
pub mod limits {
    /// An INI file, and each file it includes.
    pub const INI: u64 = 4 << 20;
    /// A HAL file (halcmd `-f`, `source`, `[HAL]HALFILE`).
    pub const HAL: u64 = 16 << 20;
    /// A Tcl HAL file.
    pub const TCL: u64 = 16 << 20;
    /// A tool table.
    pub const TOOL_TABLE: u64 = 16 << 20;
    /// A G-code part program.
    pub const PROGRAM: u64 = 128 << 20;
    /// A joint compensation table.
    pub const COMP: u64 = 16 << 20;
    /// A drive file of SDO writes.
    pub const DRIVE: u64 = 1 << 20;
    /// A sample file (halsampler's output) to plot.
    pub const SAMPLES: u64 = 512 << 20;
}

/// Why a user's file could not be read: the kind of file, its path and
/// the [`FileProblem`]. Shown as `tool table /x/t.tbl: is a FIFO, not a
/// regular file (only regular files are read)`.
#[derive(Debug)]
pub struct FileError {
    /// The kind of file ("tool table", "INI file").
    pub what: &'static str,
    /// The path as given.
    pub path: PathBuf,
    /// What was wrong.
    pub problem: FileProblem,
}

/// What was wrong with a user's file.
#[derive(Debug, thiserror::Error)]
pub enum FileProblem {
    /// Opening it failed (missing, no permission, ...).
    #[error(transparent)]
    Open(std::io::Error),
    /// It is not a regular file.
    #[error("is {0}, not a regular file (only regular files are read)")]
    NotRegular(&'static str),
    /// It is larger than the limit for its kind.
    #[error("larger than the limit of {limit} ({0} bytes)", limit = human(*.0))]
    TooLarge(u64),
    /// Reading it failed part way.
    #[error("reading: {0}")]
    Read(std::io::Error),
}

impl std::fmt::Display for FileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}: {}", self.what, self.path.display(), self.problem)
    }
}

impl std::error::Error for FileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        // The problem is part of the message; only an I/O error's own
        // cause goes on.
        match &self.problem {
            FileProblem::Open(e) | FileProblem::Read(e) => e.source(),
            _ => None,
        }
    }
}

impl FileError {
    fn new(what: &'static str, path: &Path, problem: FileProblem) -> FileError {
        FileError {
            what,
            path: path.to_path_buf(),
            problem,
        }
    }

    /// The path the error is about.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether the file does not exist.
    pub fn is_not_found(&self) -> bool {
        matches!(&self.problem, FileProblem::Open(e) if e.kind() == std::io::ErrorKind::NotFound)
    }
}

/// For readers whose callers expect an I/O error (and print the path
/// themselves): the problem alone, with an I/O error's kind kept.
impl From<FileError> for std::io::Error {
    fn from(e: FileError) -> std::io::Error {
        match e.problem {
            FileProblem::Open(io) => io,
            FileProblem::Read(io) => std::io::Error::new(io.kind(), format!("reading: {io}")),
            other => std::io::Error::new(std::io::ErrorKind::InvalidInput, other.to_string()),
        }
    }
}

/// A byte count as people read it: `16 MiB`, `512 KiB`, `100 bytes`.
fn human(n: u64) -> String {
    match n {
        n if n >= 1 << 30 && n % (1 << 30) == 0 => format!("{} GiB", n >> 30),
        n if n >= 1 << 20 && n % (1 << 20) == 0 => format!("{} MiB", n >> 20),
        n if n >= 1 << 10 && n % (1 << 10) == 0 => format!("{} KiB", n >> 10),
        n => format!("{n} bytes"),
    }
}

/// What a file that is not regular is, for messages.
fn kind_of(t: std::fs::FileType) -> &'static str {
    if t.is_dir() {
        "a directory"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

/// Opens `path` for reading if it is a regular file: without blocking
/// (a FIFO is refused, never waited on), following links as any program
/// does, and checking what was opened rather than what the name said a
/// moment earlier.
pub fn open_regular(path: &Path, what: &'static str) -> Result<File, FileError> {
    let file = OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK | libc::O_CLOEXEC | libc::O_NOCTTY)
        .open(path)
        .map_err(|e| FileError::new(what, path, FileProblem::Open(e)))?;
    let meta = file
        .metadata()
        .map_err(|e| FileError::new(what, path, FileProblem::Open(e)))?;
    if !meta.file_type().is_file() {
        return Err(FileError::new(
            what,
            path,
            FileProblem::NotRegular(kind_of(meta.file_type())),
        ));
    }
    Ok(file)
}

/// Reads the whole of `path`, a regular file of at most `limit` bytes, as
/// bytes. `what` names the kind of file in errors ("tool table").
pub fn read_user_file(path: &Path, limit: u64, what: &'static str) -> Result<Vec<u8>, FileError> {
    let file = open_regular(path, what)?;
    let too_large = || FileError::new(what, path, FileProblem::TooLarge(limit));
    let size = file.metadata().map(|m| m.len()).unwrap_or(0);
    if size > limit {
        return Err(too_large());
    }
    // One byte past the limit tells a file that grew while being read.
    let mut bytes = Vec::with_capacity(usize::try_from(size).unwrap_or(0));
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| FileError::new(what, path, FileProblem::Read(e)))?;
    if bytes.len() as u64 > limit {
        return Err(too_large());
    }
    Ok(bytes)
}

/// [`read_user_file`] as text: bytes that are not UTF-8 become U+FFFD
/// (halcmd and the INI reader work that way, as LinuxCNC's do on bytes).
pub fn read_user_text(path: &Path, limit: u64, what: &'static str) -> Result<String, FileError> {
    read_user_file(path, limit, what).map(|b| match String::from_utf8(b) {
        Ok(s) => s,
        Err(e) => String::from_utf8_lossy(e.as_bytes()).into_owned(),
    })
}

/// Reads one line (up to and including its `\n`) of a stream that is
/// not a file (standard input, a pipe) into `line`, appending: at most
/// `max` bytes, so a stream without newlines (`< /dev/zero`) is an error
/// naming the limit instead of memory without end. Returns the bytes read,
/// 0 at the end of the stream.
pub fn read_line_within(
    r: &mut impl std::io::BufRead,
    line: &mut Vec<u8>,
    max: usize,
) -> std::io::Result<usize> {
    use std::io::BufRead as _;
    let n = r.by_ref().take(max as u64 + 1).read_until(b'\n', line)?;
    if n > max {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("a line longer than the limit of {}", human(max as u64)),
        ));
    }
    Ok(n)
}

/// Replaces the file at `path` with `bytes` so that a reader sees the old
/// contents or the new, never a part: the bytes go to a new file beside
/// it (created exclusively, never through a link), are flushed to disk,
/// and the new file is renamed over the old one. A link at `path` is
/// followed first, so the file it points to is the one replaced. The new
/// file keeps the old one's permissions (0644 for a new file).
pub fn replace_file(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    use std::os::unix::fs::PermissionsExt;
    let target = match std::fs::canonicalize(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => path.to_path_buf(),
        Err(e) => return Err(e),
    };
    let mode = std::fs::metadata(&target).map_or(0o644, |m| m.permissions().mode() & 0o7777);
    let name = target
        .file_name()
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "no file name"))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".new-{}", std::process::id()));
    let tmp = target.with_file_name(tmp_name);
    let write = || -> std::io::Result<()> {
        let mut f = OpenOptions::new()
            .write(true)
            .create_new(true)
            .mode(mode)
            .custom_flags(libc::O_NOFOLLOW | libc::O_CLOEXEC)
            .open(&tmp)?;
        // create_new's mode passes through the umask: set it exactly.
        f.set_permissions(std::fs::Permissions::from_mode(mode))?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, &target)
    };
    let r = write();
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    fn scratch(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("hal-userfiles-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn regular_files_within_the_limit_are_read_whole() {
        let d = scratch("ok");
        let p = d.join("a.hal");
        std::fs::write(&p, b"loadrt and2\n\xf8 comment\n").unwrap();
        assert_eq!(
            read_user_file(&p, 100, "HAL file").unwrap(),
            b"loadrt and2\n\xf8 comment\n"
        );
        assert_eq!(
            read_user_text(&p, 100, "HAL file").unwrap(),
            "loadrt and2\n\u{fffd} comment\n"
        );
        // Exactly at the limit is fine, one past is not.
        std::fs::write(&p, [b'x'; 100]).unwrap();
        assert_eq!(read_user_file(&p, 100, "HAL file").unwrap().len(), 100);
        let e = read_user_file(&p, 99, "HAL file").unwrap_err();
        assert!(matches!(e.problem, FileProblem::TooLarge(99)), "{e}");
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn devices_fifos_and_directories_are_refused_at_once() {
        let d = scratch("odd");
        let fifo = d.join("fifo");
        nix::unistd::mkfifo(&fifo, nix::sys::stat::Mode::from_bits_truncate(0o600)).unwrap();
        let began = Instant::now();
        for (p, kind) in [
            (Path::new("/dev/zero"), "a character device"),
            (fifo.as_path(), "a FIFO"),
            (d.as_path(), "a directory"),
        ] {
            let e = read_user_file(p, limits::INI, "INI file").unwrap_err();
            let m = e.to_string();
            assert!(
                m.contains(&p.display().to_string())
                    && m.contains(kind)
                    && m.contains("not a regular file")
                    && m.starts_with("INI file "),
                "{m}"
            );
            assert_eq!(e.path(), p);
        }
        assert!(began.elapsed() < Duration::from_secs(5), "a refusal waited");
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn a_sparse_giant_is_refused_by_its_size_with_the_limit_stated() {
        let d = scratch("big");
        let p = d.join("big.tbl");
        let f = File::create(&p).unwrap();
        f.set_len(limits::TOOL_TABLE + 1).unwrap();
        let m = read_user_file(&p, limits::TOOL_TABLE, "tool table")
            .unwrap_err()
            .to_string();
        assert_eq!(
            m,
            format!(
                "tool table {}: larger than the limit of 16 MiB (16777216 bytes)",
                p.display()
            )
        );
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn missing_files_say_so() {
        let e = read_user_file(Path::new("/nonexistent/x.ini"), 10, "INI file").unwrap_err();
        assert!(e.is_not_found());
        assert!(
            e.to_string().starts_with("INI file /nonexistent/x.ini: "),
            "{e}"
        );
        // As an I/O error: the problem alone, the kind kept.
        let io = std::io::Error::from(e);
        assert_eq!(io.kind(), std::io::ErrorKind::NotFound);
        let io = std::io::Error::from(read_user_file(Path::new("/dev/zero"), 1, "x").unwrap_err());
        assert_eq!(
            io.to_string(),
            "is a character device, not a regular file (only regular files are read)"
        );
    }

    #[test]
    fn replacing_a_file_keeps_its_mode_and_goes_through_a_link() {
        use std::os::unix::fs::PermissionsExt;
        let d = scratch("replace");
        let real = d.join("tools.tbl");
        std::fs::write(&real, "old\n").unwrap();
        std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o640)).unwrap();
        let link = d.join("link.tbl");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        replace_file(&link, b"new\n").unwrap();
        assert_eq!(std::fs::read(&real).unwrap(), b"new\n");
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        let mode = std::fs::metadata(&real).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o640);
        // Nothing left beside it.
        let names: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        std::fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn stream_lines_stop_at_their_limit() {
        let mut r: &[u8] = b"short\nlonger line\nend";
        let mut line = Vec::new();
        assert_eq!(read_line_within(&mut r, &mut line, 8).unwrap(), 6);
        line.clear();
        let e = read_line_within(&mut r, &mut line, 8).unwrap_err();
        assert_eq!(e.to_string(), "a line longer than the limit of 8 bytes");
        let mut zero = std::io::BufReader::new(File::open("/dev/zero").unwrap());
        let mut line = Vec::new();
        assert!(read_line_within(&mut zero, &mut line, 1 << 16).is_err());
        assert!(line.len() <= (1 << 16) + 1);
    }

    #[test]
    fn sizes_read_as_people_write_them() {
        assert_eq!(human(16 << 20), "16 MiB");
        assert_eq!(human(1 << 30), "1 GiB");
        assert_eq!(human(3 << 10), "3 KiB");
        assert_eq!(human(99), "99 bytes");
    }
}
