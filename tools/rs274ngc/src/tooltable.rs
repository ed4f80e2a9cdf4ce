//! LinuxCNC tool table files: lines of `T<n> P<n> X.. Y.. Z.. A.. B..
//! C.. U.. V.. W.. D<dia> I<front> J<back> Q<orientation> ;comment`, or
//! the old column format (`tool pocket zoffset diameter`, or with X
//! offset, angles and orientation).
//!
//! On a non-random tool changer the entries take indexes 1, 2, ... in
//! file order (index 0 is the spindle); the P number is kept as the
//! tool's pocket.

use std::path::Path;

use crate::canon::{Pose, ToolEntry};
use crate::cfmt::{scan_double, scan_int_len};
use crate::error::Result;
use crate::source::read_bounded;

/// Largest tool table read: the suite's limit, as iocontrol reads it.
pub const MAX_FILE_BYTES: u64 = hal_core::files::limits::TOOL_TABLE;

/// Entries a table may hold (LinuxCNC's pocket limit).
pub const MAX_TOOLS: usize = 999;

/// A parsed tool table and the lines that were skipped.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ToolTable {
    /// Entries in file order.
    pub entries: Vec<ToolEntry>,
    /// Messages for lines skipped (LinuxCNC prints them and goes on).
    pub warnings: Vec<String>,
}

/// Read a tool table file.
pub fn load(path: &Path) -> Result<ToolTable> {
    let bytes = read_bounded(path, MAX_FILE_BYTES, "tool table")?;
    Ok(parse(&String::from_utf8_lossy(&bytes)))
}

/// Parse tool table text.
pub fn parse(text: &str) -> ToolTable {
    let mut table = ToolTable::default();
    for line in text.split_inclusive('\n') {
        if table.entries.len() >= MAX_TOOLS {
            table
                .warnings
                .push("too many tools. skipping the rest".to_string());
            break;
        }
        if let Some(entry) = scan_old_style(line) {
            table.entries.push(entry);
            continue;
        }
        match parse_line(line) {
            Some(Some(entry)) => table.entries.push(entry),
            Some(None) => {}
            None => table
                .warnings
                .push(format!("Unrecognized line skipped: {line}")),
        }
    }
    table
}

/// The old column formats: `%d %d %lf %lf %lf %lf %lf %d` (lathe) or
/// `%d %d %lf %lf` (mill).
fn scan_old_style(line: &str) -> Option<ToolEntry> {
    let mut rest = line;
    let mut ints = [0i64; 2];
    for slot in &mut ints {
        let t = rest.trim_start();
        let len = scan_int_len(t)?;
        *slot = t[..len].parse().ok()?;
        rest = &t[len..];
    }
    let mut reals = Vec::with_capacity(5);
    let mut orientation = None;
    for _ in 0..5 {
        let t = rest.trim_start();
        match scan_double(t) {
            Some((v, len)) => {
                reals.push(v);
                rest = &t[len..];
            }
            None => break,
        }
    }
    if reals.len() == 5 {
        let t = rest.trim_start();
        if let Some(len) = scan_int_len(t) {
            orientation = t[..len].parse::<i32>().ok();
        }
    }
    let toolno = i32::try_from(ints[0]).ok()?;
    let pocketno = i32::try_from(ints[1]).ok()?;
    if let (true, Some(orientation)) = (reals.len() == 5, orientation) {
        return Some(ToolEntry {
            toolno,
            pocketno,
            offset: Pose {
                z: reals[0],
                x: reals[1],
                ..Pose::ZERO
            },
            diameter: reals[2],
            frontangle: reals[3],
            backangle: reals[4],
            orientation,
        });
    }
    if reals.len() >= 2 {
        return Some(ToolEntry {
            toolno,
            pocketno,
            offset: Pose {
                z: reals[0],
                ..Pose::ZERO
            },
            diameter: reals[1],
            ..ToolEntry::EMPTY
        });
    }
    None
}

/// One line of the lettered format: `Some(Some(entry))`, `Some(None)`
/// for a line with no tool (blank or comment), `None` if invalid.
fn parse_line(line: &str) -> Option<Option<ToolEntry>> {
    let body = line.split(';').next().unwrap_or("");
    let mut entry = ToolEntry::EMPTY;
    let mut has_pocket = false;
    let mut any = false;
    for token in body.split(' ') {
        let token = token.trim_end_matches(['\n', '\r']);
        if token.is_empty() {
            continue;
        }
        any = true;
        let mut chars = token.chars();
        let letter = chars.next().map(|c| c.to_ascii_uppercase()).unwrap_or(' ');
        let value = chars.as_str();
        let real = || scan_double(value).map(|(v, _)| v);
        let int = || scan_int_len(value).and_then(|n| value[..n].parse::<i32>().ok());
        match letter {
            'T' => entry.toolno = int()?,
            'P' => {
                entry.pocketno = int()?;
                has_pocket = true;
            }
            'D' => entry.diameter = real()?,
            'X' => entry.offset.x = real()?,
            'Y' => entry.offset.y = real()?,
            'Z' => entry.offset.z = real()?,
            'A' => entry.offset.a = real()?,
            'B' => entry.offset.b = real()?,
            'C' => entry.offset.c = real()?,
            'U' => entry.offset.u = real()?,
            'V' => entry.offset.v = real()?,
            'W' => entry.offset.w = real()?,
            'I' => entry.frontangle = real()?,
            'J' => entry.backangle = real()?,
            'Q' => entry.orientation = int()?,
            _ => return None,
        }
    }
    if !any {
        return Some(None);
    }
    if !has_pocket {
        return None;
    }
    Some(Some(entry))
}

/// Fuzz body: any bytes as a tool table; every accepted entry must be
/// finite-numbered or come from a number the text spelled.
pub fn fuzz_parse(data: &[u8]) {
    let table = parse(&String::from_utf8_lossy(data));
    assert!(table.entries.len() <= MAX_TOOLS);
    let lines = data.split(|&b| b == b'\n').count();
    assert!(table.entries.len() + table.warnings.len() <= lines + 1);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lettered_lines_in_file_order() {
        let t = parse("T5 P1 Z1 D0.5 ;first\nT3 P7 Z2 D0.25\n\n; only a comment\nT10 P3 Z3 X0.5 D1 I10 J20 Q3\n");
        assert_eq!(t.entries.len(), 3);
        assert_eq!((t.entries[0].toolno, t.entries[0].pocketno), (5, 1));
        assert_eq!(t.entries[2].orientation, 3);
        assert_eq!(t.entries[2].offset.x, 0.5);
        assert!(t.warnings.is_empty());
    }

    #[test]
    fn old_format_and_bad_lines() {
        let t = parse("1 1 0.5 0.25 mill\n2 2 0.1 0.2 0.3 10 20 3\nT1 P1 Zjunk\n");
        assert_eq!(t.entries.len(), 2);
        assert_eq!(t.entries[0].offset.z, 0.5);
        assert_eq!(t.entries[1].orientation, 3);
        assert_eq!(
            t.warnings,
            vec!["Unrecognized line skipped: T1 P1 Zjunk\n".to_string()]
        );
    }
}
