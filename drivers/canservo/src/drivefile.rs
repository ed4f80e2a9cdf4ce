//! The per-drive SDO file: the drive-specific objects an integrator sets
//! at start-up (homing method, gear ratio, limits, option codes), one
//! SDO write per line:
//!
//! ```text
//! # canservo drive file: INDEX:SUB TYPE VALUE
//! 6098:00 i8  19        # homing method: home switch, positive
//! 0x6099:01 u32 20000   # homing speed while searching the switch
//! 607C:00 i32 -500      # home offset
//! 6065:00 u32 0x4E20    # following error window
//! ```
//!
//! Index and sub-index are hexadecimal, as in EDS files and `cansend`
//! (a `0x` prefix is allowed); the type is one of `u8`, `u16`, `u32`,
//! `i8`, `i16`, `i32` (`s8`, `s16`, `s32` also); the value is decimal
//! or `0x` hexadecimal, negative for signed types, and must fit the
//! type. `#` starts a comment. The writes are made in file order after
//! the driver's own configuration and before NMT start, so a file can
//! override a default the driver chose. Every error names the file and
//! the line.

use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::regs::describe_object;
use crate::sdo::SdoClient;

/// The longest drive file read (a real one is a few dozen lines).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// The type of an SDO value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SdoType {
    /// UNSIGNED8.
    U8,
    /// UNSIGNED16.
    U16,
    /// UNSIGNED32.
    U32,
    /// INTEGER8.
    I8,
    /// INTEGER16.
    I16,
    /// INTEGER32.
    I32,
}

impl SdoType {
    /// The type named `s` (`u8` ... `i32`, `s8` ... `s32`).
    pub fn parse(s: &str) -> Option<SdoType> {
        Some(match s.to_ascii_lowercase().as_str() {
            "u8" => SdoType::U8,
            "u16" => SdoType::U16,
            "u32" => SdoType::U32,
            "i8" | "s8" => SdoType::I8,
            "i16" | "s16" => SdoType::I16,
            "i32" | "s32" => SdoType::I32,
            _ => return None,
        })
    }

    /// Size in bytes.
    pub fn size(self) -> usize {
        match self {
            SdoType::U8 | SdoType::I8 => 1,
            SdoType::U16 | SdoType::I16 => 2,
            SdoType::U32 | SdoType::I32 => 4,
        }
    }

    /// The values the type holds.
    pub fn range(self) -> (i64, i64) {
        match self {
            SdoType::U8 => (0, 0xFF),
            SdoType::U16 => (0, 0xFFFF),
            SdoType::U32 => (0, 0xFFFF_FFFF),
            SdoType::I8 => (-128, 127),
            SdoType::I16 => (-32768, 32767),
            SdoType::I32 => (i64::from(i32::MIN), i64::from(i32::MAX)),
        }
    }

    /// Parses `text` as a value of this type (decimal or `0x` hex).
    pub fn parse_value(self, text: &str) -> Result<i64> {
        let (neg, digits) = match text.strip_prefix('-') {
            Some(d) => (true, d),
            None => (false, text),
        };
        let not_a_number = || Error::NotANumber {
            text: text.to_string(),
        };
        let (radix, digits) = match digits
            .strip_prefix("0x")
            .or_else(|| digits.strip_prefix("0X"))
        {
            Some(h) => (16, h),
            None => (10, digits),
        };
        // Only digits after the one sign: the standard parsers would
        // also take "+5" and "--5".
        if !digits.chars().all(|c| c.is_digit(radix)) {
            return Err(not_a_number());
        }
        let magnitude = i64::from_str_radix(digits, radix).map_err(|_| not_a_number())?;
        let v = if neg { -magnitude } else { magnitude };
        let (lo, hi) = self.range();
        if !(lo..=hi).contains(&v) {
            return Err(Error::OutOfRange {
                value: v,
                ty: self,
                lo,
                hi,
            });
        }
        Ok(v)
    }

    /// The little-endian bytes of `value`.
    pub fn bytes(self, value: i64) -> Vec<u8> {
        value.to_le_bytes()[..self.size()].to_vec()
    }

    /// Reads `bytes` (little-endian, at least `size()` long) as this type.
    pub fn decode(self, bytes: &[u8]) -> Option<i64> {
        let b = bytes.get(..self.size())?;
        let mut a = [0u8; 8];
        a[..b.len()].copy_from_slice(b);
        let u = u64::from_le_bytes(a);
        Some(match self {
            SdoType::U8 | SdoType::U16 | SdoType::U32 => u as i64,
            SdoType::I8 => i64::from(u as u8 as i8),
            SdoType::I16 => i64::from(u as u16 as i16),
            SdoType::I32 => i64::from(u as u32 as i32),
        })
    }
}

impl fmt::Display for SdoType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SdoType::U8 => "u8",
            SdoType::U16 => "u16",
            SdoType::U32 => "u32",
            SdoType::I8 => "i8",
            SdoType::I16 => "i16",
            SdoType::I32 => "i32",
        })
    }
}

/// Parses `INDEX:SUB` (hexadecimal, `0x` optional).
pub fn parse_object(text: &str) -> Result<(u16, u8)> {
    let (i, s) = text.split_once(':').ok_or_else(|| Error::NotAnObject {
        text: text.to_string(),
    })?;
    // Hex digits only: `from_str_radix` alone would also take a sign.
    fn hex(t: &str) -> &str {
        let digits = t
            .strip_prefix("0x")
            .or_else(|| t.strip_prefix("0X"))
            .unwrap_or(t);
        if digits.chars().all(|c| c.is_ascii_hexdigit()) {
            digits
        } else {
            ""
        }
    }
    let index = u16::from_str_radix(hex(i), 16).map_err(|_| Error::BadIndex {
        text: i.to_string(),
    })?;
    let sub = u8::from_str_radix(hex(s), 16).map_err(|_| Error::BadSubIndex {
        text: s.to_string(),
    })?;
    Ok((index, sub))
}

/// The type names a drive file and `canservo-tool write` take.
pub const TYPES: &str = "u8, u16, u32, i8, i16, i32";

/// The [`SdoType`] named `name`, or why there is none (`types`: the
/// names the caller takes, for the message).
pub fn parse_type(name: &str, types: &'static str) -> Result<SdoType> {
    SdoType::parse(name).ok_or_else(|| Error::NotAType {
        name: name.to_string(),
        types,
    })
}

/// One write of a drive file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SdoWrite {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// Type.
    pub ty: SdoType,
    /// Value.
    pub value: i64,
    /// 1-based line in the file.
    pub line: usize,
}

/// A parsed drive file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DriveFile {
    /// Where it came from.
    pub path: PathBuf,
    /// Its writes, in order.
    pub writes: Vec<SdoWrite>,
}

impl DriveFile {
    /// Reads and parses the file at `path`: a regular file of UTF-8
    /// text up to [`MAX_FILE_BYTES`], so a parameter naming a device or
    /// a fifo (`/dev/zero`) is an error instead of a read that never ends.
    pub fn load(path: &Path) -> Result<DriveFile> {
        let io_error = |source| Error::DriveFileIo {
            path: path.to_path_buf(),
            source,
        };
        let file = std::fs::File::open(path).map_err(io_error)?;
        if !file.metadata().map_err(io_error)?.is_file() {
            return Err(io_error(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a regular file",
            )));
        }
        let mut text = String::new();
        file.take(MAX_FILE_BYTES + 1)
            .read_to_string(&mut text)
            .map_err(io_error)?;
        if text.len() as u64 > MAX_FILE_BYTES {
            return Err(io_error(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("longer than {MAX_FILE_BYTES} bytes"),
            )));
        }
        DriveFile::parse(path, &text)
    }

    /// Parses `text`, naming `path` in errors.
    pub fn parse(path: &Path, text: &str) -> Result<DriveFile> {
        let bad = |line: usize, source: Error| Error::DriveFile {
            path: path.to_path_buf(),
            line,
            source: Box::new(source),
        };
        let mut writes = Vec::new();
        for (n, raw) in text.lines().enumerate() {
            let line = n + 1;
            let content = raw.split('#').next().unwrap_or("").trim();
            if content.is_empty() {
                continue;
            }
            let words: Vec<&str> = content.split_whitespace().collect();
            let [object, ty, value] = words[..] else {
                return Err(bad(
                    line,
                    Error::NotAWrite {
                        content: content.to_string(),
                    },
                ));
            };
            let (index, sub) = parse_object(object).map_err(|e| bad(line, e))?;
            let ty = parse_type(ty, TYPES).map_err(|e| bad(line, e))?;
            let value = ty.parse_value(value).map_err(|e| bad(line, e))?;
            writes.push(SdoWrite {
                index,
                sub,
                ty,
                value,
                line,
            });
        }
        Ok(DriveFile {
            path: path.to_path_buf(),
            writes,
        })
    }

    /// Makes the writes through `sdo`; a refusal names the file, the
    /// line and the object.
    pub fn apply(&self, sdo: &SdoClient<'_>) -> Result<()> {
        for w in &self.writes {
            sdo.download(w.index, w.sub, &w.ty.bytes(w.value))
                .map_err(|e| Error::DriveFileWrite {
                    path: self.path.clone(),
                    line: w.line,
                    source: Box::new(e),
                })?;
        }
        Ok(())
    }

    /// The writes as text, one per line, for logs.
    pub fn describe(&self) -> Vec<String> {
        self.writes
            .iter()
            .map(|w| format!("{} {} = {}", describe_object(w.index, w.sub), w.ty, w.value))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<DriveFile> {
        DriveFile::parse(Path::new("x.sdo"), text)
    }

    #[test]
    fn lines_comments_and_values() {
        let f =
            parse("# homing\n6098:00 i8 -3 # method\n\n0x6099:0x01 u32 0x4E20\n607c:0 s32 -500\n")
                .unwrap();
        assert_eq!(
            f.writes,
            vec![
                SdoWrite {
                    index: 0x6098,
                    sub: 0,
                    ty: SdoType::I8,
                    value: -3,
                    line: 2
                },
                SdoWrite {
                    index: 0x6099,
                    sub: 1,
                    ty: SdoType::U32,
                    value: 20000,
                    line: 4
                },
                SdoWrite {
                    index: 0x607C,
                    sub: 0,
                    ty: SdoType::I32,
                    value: -500,
                    line: 5
                },
            ]
        );
        assert_eq!(SdoType::I16.bytes(-2), vec![0xFE, 0xFF]);
        assert_eq!(SdoType::I16.decode(&[0xFE, 0xFF]), Some(-2));
        assert_eq!(SdoType::U32.decode(&[1]), None);
    }

    #[test]
    fn errors_name_file_and_line() {
        let cases = [
            (
                "6098:00 i8\n",
                "line 1: '6098:00 i8' is not INDEX:SUB TYPE VALUE",
            ),
            ("\n6098 i8 3\n", "line 2: '6098' is not INDEX:SUB"),
            ("6098:00 u33 3\n", "line 1: 'u33' is not a type"),
            ("6098:00 u8 300\n", "line 1: 300 does not fit u8 (0..=255)"),
            ("6098:00 u8 -1\n", "line 1: -1 does not fit u8"),
            ("6098:00 u8 x\n", "line 1: 'x' is not a number"),
            ("6098:00 i8 --5\n", "line 1: '--5' is not a number"),
            ("6098:00 u8 +5\n", "line 1: '+5' is not a number"),
            ("6098:00 i8 -0x-5\n", "line 1: '-0x-5' is not a number"),
            (
                "+6098:00 u8 1\n",
                "line 1: index '+6098' is not a hexadecimal number",
            ),
            (
                "g098:00 u8 1\n",
                "line 1: index 'g098' is not a hexadecimal number",
            ),
            (
                "6098:100 u8 1\n",
                "line 1: sub-index '100' is not a hexadecimal number up to FF",
            ),
        ];
        for (text, want) in cases {
            let e = parse(text).unwrap_err().to_string();
            assert!(e.starts_with("drive file x.sdo, "), "{e}");
            assert!(e.contains(want), "{text:?}: {e}");
        }
        let e = DriveFile::load(Path::new("/dev/zero")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "drive file /dev/zero: not a regular file",
            "a device is refused before it is read"
        );
        let e = DriveFile::load(Path::new("/nonexistent/drive.sdo")).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("drive file /nonexistent/drive.sdo: "),
            "{e}"
        );
    }
}
