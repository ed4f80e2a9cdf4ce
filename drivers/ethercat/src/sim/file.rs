//! The segment file `ethercat-sim` runs: one slave per line, in the
//! order they sit on the line, a type and then `key=value` options.
//!
//! ```text
//! # a coupler, I/O and two drives
//! EK1100
//! EL1008
//! EL2008 serial=0x1234
//! EL7041
//! servo
//! servo serial=2
//! generic vid=0x539 pid=0x10 out=7000:01:16,7010:01:8 in=6000:01:16,6010:01:8
//! ```
//!
//! Types are those of [`super::DEVICE_NAMES`] (case does not matter)
//! and `generic`. Options: `serial=N` for any slave (default: its
//! position + 1); for `generic`, `vid=` and `pid=` (required) and
//! `out=`/`in=` lists of `INDEX:SUB:BITS` entries (hexadecimal index and
//! sub-index; 1, 8, 16 or 32 bits), each its own PDO; an input takes the
//! value of the output at the same place in the list when their sizes
//! match. `#` starts a comment. Every error names the file, the line
//! and the word at fault.

use std::path::{Path, PathBuf};

use super::{catalog, device_by_name, Device, Segment, DEVICE_NAMES};
use crate::error::{Error, Result};
use crate::master::MAX_SLAVES;

/// Bytes a segment file may have at most (a line per slave is short).
const MAX_FILE_BYTES: u64 = 1 << 20;

/// One slave of the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlaveSpec {
    /// Its type as [`device_by_name`] knows it, or `generic`.
    pub kind: String,
    /// Serial number.
    pub serial: u32,
    /// For `generic`: vendor id, product code, output and input entries.
    pub generic: Option<GenericSpec>,
    /// Its line in the file.
    pub line: u32,
}

/// A generic slave's identity and entries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GenericSpec {
    /// Vendor id.
    pub vid: u32,
    /// Product code.
    pub pid: u32,
    /// Output entries (index, sub-index, bits).
    pub outputs: Vec<catalog::GenericEntry>,
    /// Input entries.
    pub inputs: Vec<catalog::GenericEntry>,
}

/// A whole segment file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SegmentSpec {
    /// The file (for messages).
    pub file: PathBuf,
    /// The slaves in line order.
    pub slaves: Vec<SlaveSpec>,
}

impl SegmentSpec {
    /// The devices of the file, in order.
    pub fn devices(&self) -> Result<Vec<Device>> {
        self.slaves
            .iter()
            .map(|s| match &s.generic {
                Some(g) => Ok(catalog::generic(
                    g.vid, g.pid, s.serial, &g.outputs, &g.inputs,
                )),
                None => device_by_name(&s.kind, s.serial).ok_or_else(|| Error::Config {
                    file: self.file.clone(),
                    line: s.line,
                    element: s.kind.clone(),
                    reason: "unknown slave type".into(),
                }),
            })
            .collect()
    }

    /// The segment of the file's slaves, link up.
    pub fn build(&self) -> Result<Segment> {
        Ok(Segment::new(self.devices()?))
    }
}

/// Reads and parses a segment file.
pub fn read(path: &Path) -> Result<SegmentSpec> {
    use std::io::Read;
    let read_err = |source| Error::ReadFile {
        path: path.to_path_buf(),
        source,
    };
    let f = std::fs::File::open(path).map_err(read_err)?;
    let mut bytes = Vec::new();
    f.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(read_err)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(Error::Config {
            file: path.to_path_buf(),
            line: 1,
            element: "file".into(),
            reason: format!(
                "longer than {MAX_FILE_BYTES} bytes; a segment file has a line per slave"
            ),
        });
    }
    parse(&String::from_utf8_lossy(&bytes), path)
}

/// Parses the text of a segment file named `file`.
pub fn parse(text: &str, file: &Path) -> Result<SegmentSpec> {
    let mut slaves = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = u32::try_from(n + 1).unwrap_or(u32::MAX);
        let content = raw.split('#').next().unwrap_or("");
        let mut words = content.split_whitespace();
        let Some(kind) = words.next() else { continue };
        let err = |element: &str, reason: String| Error::Config {
            file: file.to_path_buf(),
            line,
            element: element.to_string(),
            reason,
        };
        if slaves.len() >= MAX_SLAVES {
            return Err(err(kind, format!("more than {MAX_SLAVES} slaves")));
        }
        let generic = kind.eq_ignore_ascii_case("generic");
        if !generic && device_by_name(kind, 0).is_none() {
            return Err(err(
                kind,
                format!(
                    "unknown slave type; known: {}, generic",
                    DEVICE_NAMES.join(", ")
                ),
            ));
        }
        let mut spec = SlaveSpec {
            kind: if generic {
                "generic".into()
            } else {
                kind.to_string()
            },
            serial: u32::try_from(slaves.len() + 1).unwrap_or(u32::MAX),
            generic: None,
            line,
        };
        let mut g = (None, None, Vec::new(), Vec::new());
        for word in words {
            let Some((key, value)) = word.split_once('=') else {
                return Err(err(word, "expected KEY=VALUE".into()));
            };
            match (key, generic) {
                ("serial", _) => {
                    spec.serial = number(value).ok_or_else(|| err(word, "not a number".into()))?
                }
                ("vid", true) => {
                    g.0 = Some(number(value).ok_or_else(|| err(word, "not a number".into()))?)
                }
                ("pid", true) => {
                    g.1 = Some(number(value).ok_or_else(|| err(word, "not a number".into()))?)
                }
                ("out", true) => g.2 = entries(value).map_err(|r| err(word, r))?,
                ("in", true) => g.3 = entries(value).map_err(|r| err(word, r))?,
                _ => {
                    let allowed = if generic {
                        "serial, vid, pid, out, in"
                    } else {
                        "serial"
                    };
                    return Err(err(
                        word,
                        format!("unknown option '{key}' (allowed: {allowed})"),
                    ));
                }
            }
        }
        if generic {
            let (Some(vid), Some(pid)) = (g.0, g.1) else {
                return Err(err(kind, "a generic slave needs vid= and pid=".into()));
            };
            spec.generic = Some(GenericSpec {
                vid,
                pid,
                outputs: g.2,
                inputs: g.3,
            });
        }
        slaves.push(spec);
    }
    if slaves.is_empty() {
        return Err(Error::Config {
            file: file.to_path_buf(),
            line: 1,
            element: "file".into(),
            reason: "no slaves: write one type per line (EK1100, EL1008, servo, ...)".into(),
        });
    }
    Ok(SegmentSpec {
        file: file.to_path_buf(),
        slaves,
    })
}

/// A decimal or `0x` hexadecimal u32.
fn number(s: &str) -> Option<u32> {
    match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(h) => u32::from_str_radix(h, 16).ok(),
        None => s.parse().ok(),
    }
}

/// `INDEX:SUB:BITS,...`.
fn entries(list: &str) -> std::result::Result<Vec<catalog::GenericEntry>, String> {
    let mut out = Vec::new();
    for item in list.split(',') {
        let parts: Vec<&str> = item.split(':').collect();
        let [index, sub, bits] = parts[..] else {
            return Err(format!("entry '{item}' is not INDEX:SUB:BITS"));
        };
        let index = u16::from_str_radix(index.trim_start_matches("0x"), 16)
            .map_err(|_| format!("entry '{item}': index '{index}' is not hexadecimal"))?;
        let sub = u8::from_str_radix(sub.trim_start_matches("0x"), 16)
            .map_err(|_| format!("entry '{item}': sub-index '{sub}' is not hexadecimal"))?;
        let bits: u8 = match bits.parse() {
            Ok(b @ (1 | 8 | 16 | 32)) => b,
            _ => return Err(format!("entry '{item}': {bits} bits (1, 8, 16 or 32)")),
        };
        if !(0x6000..=0x7FFF).contains(&index) {
            return Err(format!(
                "entry '{item}': index {index:#06x} is not a process object (0x6000..0x7fff)"
            ));
        }
        if out.iter().any(|&(i, s, _)| (i, s) == (index, sub)) {
            return Err(format!("entry '{item}' appears twice"));
        }
        out.push((index, sub, bits));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mixed_file_builds_its_segment() {
        let text = "# test\nEK1100\nel1008 serial=0x10\n\nservo # a drive\ngeneric vid=0x539 pid=2 out=7000:01:16 in=6000:01:16\n";
        let s = parse(text, Path::new("seg")).unwrap();
        assert_eq!(s.slaves.len(), 4);
        assert_eq!(s.slaves[1].serial, 16);
        assert_eq!(s.slaves[2].line, 5);
        let g = s.slaves[3].generic.as_ref().unwrap();
        assert_eq!((g.vid, g.outputs[0]), (0x539, (0x7000, 1, 16)));
        assert_eq!(s.build().unwrap().slaves().len(), 4);
    }

    #[test]
    fn errors_name_file_line_and_word() {
        let e = |t: &str| parse(t, Path::new("seg")).unwrap_err().to_string();
        assert!(e("EK1100\nEL9999\n").starts_with("seg:2: <EL9999>: unknown slave type"));
        assert!(e("servo colour=red").starts_with("seg:1: <colour=red>: unknown option 'colour'"));
        assert!(e("generic vid=1").contains("needs vid= and pid="));
        assert!(e("generic vid=1 pid=2 out=7000:1:12").contains("12 bits"));
        assert!(e("generic vid=1 pid=2 in=1000:1:8").contains("not a process object"));
        assert!(e("EL1008 serial").contains("KEY=VALUE"));
        assert!(e("# nothing\n").contains("no slaves"));
        let many = "EL1008\n".repeat(MAX_SLAVES + 1);
        assert!(e(&many).contains(&format!("seg:{}:", MAX_SLAVES + 1)));
    }
}
