//! Reading programs and other files from outside, with bounds: only
//! regular files are opened (a device such as /dev/zero is refused),
//! whole-file reads have a size limit, and program lines are read one at
//! a time, each at most [`LINE_MAX`] bytes as in LinuxCNC.

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};

use hal_core::files;
use std::path::{Path, PathBuf};

use crate::error::{InterpError, Result};

/// LinuxCNC's line buffer size: a line with its newline must be shorter
/// than `LINELEN - 1` bytes (an MDI line shorter than `LINELEN`), or it
/// is "Command too long".
pub const LINELEN: usize = 255;

/// Longest program file opened.
pub const MAX_PROGRAM_BYTES: u64 = 1 << 30;

/// Open `path` for reading if it is a regular file no larger than
/// `limit` bytes, through the suite's reader of users' files (a device,
/// FIFO or directory is refused in its words). `what` names the kind of
/// file in errors ("program").
pub fn open_regular(path: &Path, limit: u64, what: &'static str) -> Result<File> {
    let file = files::open_regular(path, what).map_err(InterpError::from_file)?;
    let size = file.metadata().map_err(|e| InterpError::io(path, e))?.len();
    if size > limit {
        return Err(InterpError::FileTooLarge {
            path: path.to_path_buf(),
            size,
            limit,
        });
    }
    Ok(file)
}

/// Read a whole regular file of at most `limit` bytes, through the
/// suite's reader of users' files; `what` names the kind of file in
/// errors ("tool table").
pub fn read_bounded(path: &Path, limit: u64, what: &'static str) -> Result<Vec<u8>> {
    files::read_user_file(path, limit, what).map_err(InterpError::from_file)
}

/// One line as read: its text (trailing white space removed) or the
/// fact that it was too long.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Line {
    /// The line's bytes, up to any NUL, trailing white space removed.
    Text(Vec<u8>),
    /// The line, with its newline, was `LINELEN - 1` bytes or longer: the
    /// bytes read (as LinuxCNC shows them, a newline included); the rest
    /// of it was skipped.
    TooLong(Vec<u8>),
}

/// What a program is read from: a file, or bytes in memory.
trait ReadSeek: Read + Seek + Send {}
impl<T: Read + Seek + Send> ReadSeek for T {}

/// A program file read line by line, with seeking for loops and calls.
pub struct Source {
    path: PathBuf,
    reader: BufReader<Box<dyn ReadSeek>>,
    offset: u64,
}

impl std::fmt::Debug for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Source")
            .field("path", &self.path)
            .field("offset", &self.offset)
            .finish()
    }
}

impl Source {
    /// Open a program file.
    pub fn open(path: &Path) -> Result<Source> {
        let file = open_regular(path, MAX_PROGRAM_BYTES, "program")?;
        Ok(Source {
            path: path.to_path_buf(),
            reader: BufReader::new(Box::new(file)),
            offset: 0,
        })
    }

    /// A program held in memory, named `path` in messages.
    pub fn from_bytes(path: &Path, bytes: Vec<u8>) -> Source {
        Source {
            path: path.to_path_buf(),
            reader: BufReader::new(Box::new(std::io::Cursor::new(bytes))),
            offset: 0,
        }
    }

    /// The file's path as it was opened.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Byte offset of the next line.
    pub fn tell(&self) -> u64 {
        self.offset
    }

    /// Continue reading at byte `offset`.
    pub fn seek(&mut self, offset: u64) -> Result<()> {
        self.reader
            .seek(SeekFrom::Start(offset))
            .map_err(|e| InterpError::io(&self.path, e))?;
        self.offset = offset;
        Ok(())
    }

    /// The next line, or `None` at the end of the file. Reads at most
    /// [`LINELEN`] - 1 bytes of a line into memory.
    pub fn read_line(&mut self) -> Result<Option<Line>> {
        let mut buf = Vec::with_capacity(80);
        let limit = (LINELEN - 1) as u64;
        let n = (&mut self.reader)
            .take(limit)
            .read_until(b'\n', &mut buf)
            .map_err(|e| InterpError::io(&self.path, e))?;
        if n == 0 {
            return Ok(None);
        }
        self.offset += n as u64;
        let text_len = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
        if text_len == LINELEN - 1 {
            if buf.last() != Some(&b'\n') {
                self.skip_rest_of_line()?;
            }
            return Ok(Some(Line::TooLong(buf)));
        }
        buf.truncate(text_len);
        while buf.last().is_some_and(|&b| is_c_space(b)) {
            buf.pop();
        }
        Ok(Some(Line::Text(buf)))
    }

    fn skip_rest_of_line(&mut self) -> Result<()> {
        loop {
            let chunk = self
                .reader
                .fill_buf()
                .map_err(|e| InterpError::io(&self.path, e))?;
            if chunk.is_empty() {
                return Ok(());
            }
            match chunk.iter().position(|&b| b == b'\n') {
                Some(i) => {
                    self.reader.consume(i + 1);
                    self.offset += i as u64 + 1;
                    return Ok(());
                }
                None => {
                    let len = chunk.len();
                    self.reader.consume(len);
                    self.offset += len as u64;
                }
            }
        }
    }
}

/// C's `isspace` in the C locale.
pub fn is_c_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn temp_file(bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.ngc");
        std::fs::File::create(&path)
            .unwrap()
            .write_all(bytes)
            .unwrap();
        (dir, path)
    }

    #[test]
    fn lines_are_trimmed_and_offsets_kept() {
        let (_d, path) = temp_file(b"G0 X1  \r\nG1\n\nlast");
        let mut s = Source::open(&path).unwrap();
        assert_eq!(s.read_line().unwrap(), Some(Line::Text(b"G0 X1".to_vec())));
        let second = s.tell();
        assert_eq!(s.read_line().unwrap(), Some(Line::Text(b"G1".to_vec())));
        assert_eq!(s.read_line().unwrap(), Some(Line::Text(Vec::new())));
        assert_eq!(s.read_line().unwrap(), Some(Line::Text(b"last".to_vec())));
        assert_eq!(s.read_line().unwrap(), None);
        s.seek(second).unwrap();
        assert_eq!(s.read_line().unwrap(), Some(Line::Text(b"G1".to_vec())));
    }

    #[test]
    fn long_lines_are_refused_and_skipped() {
        let mut text = vec![b'X'; 253];
        text.extend_from_slice(b"\nG0\n");
        let (_d, path) = temp_file(&text);
        let mut s = Source::open(&path).unwrap();
        assert_eq!(
            s.read_line().unwrap(),
            Some(Line::TooLong([vec![b'X'; 253], b"\n".to_vec()].concat()))
        );
        assert_eq!(s.read_line().unwrap(), Some(Line::Text(b"G0".to_vec())));

        let mut text = vec![b'X'; 252];
        text.push(b'\n');
        let (_d, path) = temp_file(&text);
        let mut s = Source::open(&path).unwrap();
        assert!(matches!(s.read_line().unwrap(), Some(Line::Text(t)) if t.len() == 252));

        let mut text = vec![b'Y'; 5000];
        text.extend_from_slice(b"\nG1\n");
        let (_d, path) = temp_file(&text);
        let mut s = Source::open(&path).unwrap();
        assert_eq!(s.read_line().unwrap(), Some(Line::TooLong(vec![b'Y'; 254])));
        assert_eq!(s.read_line().unwrap(), Some(Line::Text(b"G1".to_vec())));
    }

    #[test]
    fn devices_are_refused_as_not_regular_files() {
        let err = Source::open(Path::new("/dev/zero")).unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("program /dev/zero: is a character device, not a regular file"),
            "{text}"
        );
    }
}
