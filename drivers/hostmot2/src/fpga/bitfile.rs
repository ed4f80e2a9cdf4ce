//! Xilinx `.bit` files: the header bitgen writes before the bitstream,
//! and the bitstream itself (hardware.md 5.1: sections `a` to `e`).
//!
//! Layout, every length big-endian:
//!
//! | field | bytes |
//! |---|---|
//! | preamble length, then the preamble | 2, then that many (9 in every file bitgen writes) |
//! | key count | 2 (always 1) |
//! | `a` design name, `b` part name, `c` date, `d` time | key byte, 2-byte length, that many bytes (a NUL-terminated string) |
//! | `e` bitstream | key byte, 4-byte length, that many bytes |
//!
//! Keys `a` to `d` may come in any order but each at most once; `a`, `b`
//! and `e` are required; `e` ends the file. Every read is bounded by the
//! bytes there are, and a file is read whole only up to [`MAX_FILE_BYTES`].

use std::io::Read;
use std::path::Path;

use super::FpgaError;

/// The largest bitfile accepted: the largest part a PLX-bridged card has
/// (Spartan-3 2000) needs about 1 MiB; 16 MiB leaves room for any.
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// Longest preamble accepted (bitgen's is 9 bytes).
const MAX_PREAMBLE: usize = 64;

/// A parsed bitfile.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BitFile {
    /// Design name (`a`), e.g. `svst8_4.ncd;UserID=0xFFFFFFFF`.
    pub design: String,
    /// FPGA part (`b`), e.g. `2s200pq208`.
    pub part: String,
    /// Build date (`c`), empty when absent.
    pub date: String,
    /// Build time (`d`), empty when absent.
    pub time: String,
    /// The bitstream (`e`), bytes as stored in the file.
    pub bitstream: Vec<u8>,
}

/// A cursor over the file's bytes that never reads past the end.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, what: &'static str) -> Result<&'a [u8], FpgaError> {
        let left = self.bytes.len() - self.at;
        if n > left {
            return Err(FpgaError::BitfileTruncated {
                what,
                offset: self.at,
                needed: n,
                left,
            });
        }
        let s = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(s)
    }

    fn u8(&mut self, what: &'static str) -> Result<u8, FpgaError> {
        Ok(self.take(1, what)?[0])
    }

    fn u16(&mut self, what: &'static str) -> Result<u16, FpgaError> {
        let b = self.take(2, what)?;
        Ok(u16::from_be_bytes([b[0], b[1]]))
    }

    fn u32(&mut self, what: &'static str) -> Result<u32, FpgaError> {
        let b = self.take(4, what)?;
        Ok(u32::from_be_bytes([b[0], b[1], b[2], b[3]]))
    }
}

/// The text of a string field: its bytes up to the first NUL, which must
/// be printable ASCII.
fn text(key: u8, bytes: &[u8]) -> Result<String, FpgaError> {
    let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    let s = &bytes[..end];
    if let Some(&bad) = s.iter().find(|b| !(b.is_ascii_graphic() || **b == b' ')) {
        return Err(FpgaError::BitfileField {
            key: key as char,
            reason: format!("holds the byte 0x{bad:02X}, not printable ASCII"),
        });
    }
    Ok(String::from_utf8_lossy(s).into_owned())
}

/// Parses a whole bitfile.
pub fn parse(bytes: &[u8]) -> Result<BitFile, FpgaError> {
    let mut c = Cursor { bytes, at: 0 };
    let pre = c.u16("the preamble length")? as usize;
    if pre > MAX_PREAMBLE {
        return Err(FpgaError::BitfileHeader {
            reason: format!("preamble length {pre} (bitgen writes 9; at most {MAX_PREAMBLE})"),
        });
    }
    c.take(pre, "the preamble")?;
    let keys = c.u16("the key count")?;
    if keys != 1 {
        return Err(FpgaError::BitfileHeader {
            reason: format!("key count {keys} after the preamble, expected 1"),
        });
    }
    let mut fields: [Option<String>; 4] = Default::default();
    loop {
        let offset = c.at;
        let key = c.u8("a section key")?;
        match key {
            b'a'..=b'd' => {
                let len = c.u16("a section length")? as usize;
                let value = text(key, c.take(len, "a section's text")?)?;
                let slot = &mut fields[(key - b'a') as usize];
                if slot.is_some() {
                    return Err(FpgaError::BitfileField {
                        key: key as char,
                        reason: format!("appears twice (again at byte {offset})"),
                    });
                }
                *slot = Some(value);
            }
            b'e' => {
                let len = c.u32("the bitstream length")? as usize;
                let stream = c.take(len, "the bitstream")?.to_vec();
                let trailing = bytes.len() - c.at;
                if trailing != 0 {
                    return Err(FpgaError::BitfileHeader {
                        reason: format!("{trailing} bytes after the bitstream"),
                    });
                }
                return finish(fields, stream);
            }
            k => {
                return Err(FpgaError::BitfileHeader {
                    reason: format!(
                        "unknown section key 0x{k:02X} at byte {offset} (expected 'a' to 'e')"
                    ),
                })
            }
        }
    }
}

fn finish(fields: [Option<String>; 4], bitstream: Vec<u8>) -> Result<BitFile, FpgaError> {
    let [a, b, c, d] = fields;
    let missing = |key: char| FpgaError::BitfileField {
        key,
        reason: "is missing".into(),
    };
    if bitstream.is_empty() {
        return Err(FpgaError::BitfileField {
            key: 'e',
            reason: "is empty (no bitstream)".into(),
        });
    }
    let part = b.ok_or_else(|| missing('b'))?;
    if part.is_empty() {
        return Err(FpgaError::BitfileField {
            key: 'b',
            reason: "names no part".into(),
        });
    }
    Ok(BitFile {
        design: a.ok_or_else(|| missing('a'))?,
        part,
        date: c.unwrap_or_default(),
        time: d.unwrap_or_default(),
        bitstream,
    })
}

/// Reads and parses the bitfile at `path`: a regular file of at most
/// [`MAX_FILE_BYTES`]. It is opened without blocking (a FIFO put there
/// cannot stall the load) and checked to be a regular file before any read.
pub fn read(path: &Path) -> Result<BitFile, FpgaError> {
    use std::os::unix::fs::OpenOptionsExt;
    let io = |e: std::io::Error| FpgaError::BitfileRead {
        path: path.to_path_buf(),
        reason: e.to_string(),
    };
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(nix::fcntl::OFlag::O_NONBLOCK.bits())
        .open(path)
        .map_err(io)?;
    if !file.metadata().map_err(io)?.is_file() {
        return Err(FpgaError::BitfileRead {
            path: path.to_path_buf(),
            reason: "not a regular file".into(),
        });
    }
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(FpgaError::BitfileRead {
            path: path.to_path_buf(),
            reason: format!("larger than {MAX_FILE_BYTES} bytes"),
        });
    }
    parse(&bytes)
}

/// Writes a bitfile with these fields (the inverse of [`parse`]): how
/// the simulator makes its firmware files and tests make broken ones.
/// Fields longer than a section holds are cut.
pub fn build(design: &str, part: &str, date: &str, time: &str, bitstream: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(bitstream.len() + 128);
    out.extend_from_slice(&9u16.to_be_bytes());
    out.extend_from_slice(&[0x0F, 0xF0, 0x0F, 0xF0, 0x0F, 0xF0, 0x0F, 0xF0, 0x00]);
    out.extend_from_slice(&1u16.to_be_bytes());
    for (key, value) in [(b'a', design), (b'b', part), (b'c', date), (b'd', time)] {
        let v = &value.as_bytes()[..value.len().min(u16::MAX as usize - 1)];
        out.push(key);
        out.extend_from_slice(&(v.len() as u16 + 1).to_be_bytes());
        out.extend_from_slice(v);
        out.push(0);
    }
    out.push(b'e');
    out.extend_from_slice(&(bitstream.len() as u32).to_be_bytes());
    out.extend_from_slice(bitstream);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Vec<u8> {
        build(
            "svst8_4.ncd;UserID=0xFFFFFFFF",
            "2s200pq208",
            "2008/06/10",
            "11:51:54",
            &[0xFF, 0xFF, 0xAA, 0x99, 0x55, 0x66, 1, 2, 3],
        )
    }

    #[test]
    fn a_bitgen_header_is_read_field_by_field() {
        let b = parse(&sample()).unwrap();
        assert_eq!(b.design, "svst8_4.ncd;UserID=0xFFFFFFFF");
        assert_eq!(b.part, "2s200pq208");
        assert_eq!(
            (b.date.as_str(), b.time.as_str()),
            ("2008/06/10", "11:51:54")
        );
        assert_eq!(b.bitstream, [0xFF, 0xFF, 0xAA, 0x99, 0x55, 0x66, 1, 2, 3]);
    }

    #[test]
    fn every_cut_short_file_is_refused_with_what_was_missing() {
        let full = sample();
        for n in 0..full.len() {
            let e = parse(&full[..n]).unwrap_err();
            assert!(matches!(e, FpgaError::BitfileTruncated { .. }), "{n}: {e}");
        }
        let e = parse(&full[..full.len() - 2]).unwrap_err().to_string();
        assert!(e.contains("the bitstream") && e.contains("needs 9"), "{e}");
    }

    #[test]
    fn broken_headers_say_what_is_wrong() {
        let mut two_keys = sample();
        two_keys[12] = 2;
        assert!(parse(&two_keys)
            .unwrap_err()
            .to_string()
            .contains("key count 2"));
        let mut unknown = sample();
        unknown[13] = b'z';
        assert!(parse(&unknown).unwrap_err().to_string().contains("0x7A"));
        let mut trailing = sample();
        trailing.push(0);
        assert!(parse(&trailing)
            .unwrap_err()
            .to_string()
            .contains("1 bytes after"));
        let no_part = build("x.ncd", "", "", "", &[1]);
        assert!(parse(&no_part)
            .unwrap_err()
            .to_string()
            .contains("names no part"));
        let empty = build("x.ncd", "3s400pq208", "", "", &[]);
        assert!(parse(&empty)
            .unwrap_err()
            .to_string()
            .contains("no bitstream"));
        let mut big_pre = sample();
        big_pre[1] = 200;
        assert!(parse(&big_pre)
            .unwrap_err()
            .to_string()
            .contains("preamble length 200"));
    }

    #[test]
    fn a_field_given_twice_or_missing_is_refused() {
        let mut f = vec![0, 0, 0, 1];
        for _ in 0..2 {
            f.extend_from_slice(&[b'a', 0, 2, b'x', 0]);
        }
        let e = parse(&f).unwrap_err().to_string();
        assert!(e.contains("'a'") && e.contains("twice"), "{e}");
        let mut f = vec![0, 0, 0, 1, b'b', 0, 2, b'p', 0, b'e'];
        f.extend_from_slice(&[0, 0, 0, 1, 7]);
        let e = parse(&f).unwrap_err().to_string();
        assert!(e.contains("'a'") && e.contains("missing"), "{e}");
    }

    #[test]
    fn unprintable_names_are_refused() {
        let f = build("de\u{7}sign", "2s200pq208", "", "", &[1]);
        let e = parse(&f).unwrap_err().to_string();
        assert!(e.contains("0x07"), "{e}");
    }

    #[test]
    fn files_are_read_only_when_regular_and_bounded() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("ok.bit");
        std::fs::write(&p, sample()).unwrap();
        assert_eq!(read(&p).unwrap().part, "2s200pq208");
        let e = read(dir.path()).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
        let e = read(&dir.path().join("none.bit")).unwrap_err().to_string();
        assert!(e.contains("none.bit"), "{e}");
        let fifo = dir.path().join("fifo.bit");
        nix::unistd::mkfifo(&fifo, nix::sys::stat::Mode::S_IRWXU).unwrap();
        let e = read(&fifo).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
    }
}
