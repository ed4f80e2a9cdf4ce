//! Turning a raw program line into the form the reader scans: spaces,
//! tabs and carriage returns removed and letters lower-cased everywhere
//! except inside comments, as LinuxCNC does.

use crate::error::{InterpError, Result};

/// A line ready for reading.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CleanLine {
    /// The cleaned bytes.
    pub bytes: Vec<u8>,
    /// For each cleaned byte, its 1-based column in the raw line.
    pub columns: Vec<usize>,
}

impl CleanLine {
    /// The raw column of cleaned position `index` (the column after the
    /// line's end for an index past it).
    pub fn column(&self, index: usize) -> usize {
        match self.columns.get(index) {
            Some(&c) => c,
            None => self.columns.last().map_or(1, |&c| c + 1),
        }
    }
}

/// Clean a raw line: drop blanks outside comments, lower-case letters
/// outside comments, keep comments and `;` remainders as written.
pub fn close_and_downcase(raw: &[u8]) -> Result<CleanLine> {
    let mut out = CleanLine {
        bytes: Vec::with_capacity(raw.len()),
        columns: Vec::with_capacity(raw.len()),
    };
    let mut comment = false;
    let mut semicomment = false;
    for (m, &item) in raw.iter().enumerate() {
        if item == 0 {
            break;
        }
        if item == b';' && !comment {
            semicomment = true;
        }
        if semicomment {
            out.push(item, m);
            continue;
        }
        if comment {
            out.push(item, m);
            if item == b')' {
                comment = false;
            } else if item == b'(' {
                return Err(InterpError::NestedComment);
            }
        } else if item == b' ' || item == b'\t' || item == b'\r' {
            // blanks vanish
        } else if item == b'\n' {
            // only a final newline can be here; it vanishes too
        } else if item.is_ascii_uppercase() {
            out.push(item.to_ascii_lowercase(), m);
        } else if item == b'(' {
            comment = true;
            out.push(item, m);
        } else {
            out.push(item, m);
        }
    }
    if comment {
        return Err(InterpError::UnclosedComment);
    }
    Ok(out)
}

impl CleanLine {
    fn push(&mut self, byte: u8, raw_index: usize) {
        self.bytes.push(byte);
        self.columns.push(raw_index + 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blanks_go_and_case_folds_outside_comments() {
        let line = close_and_downcase(b"G0 X 1.5 (Keep Me) Y2 ; Rest AS is").unwrap();
        assert_eq!(line.bytes, b"g0x1.5(Keep Me)y2; Rest AS is");
        assert_eq!(line.column(0), 1);
        assert_eq!(line.column(2), 4);
    }

    #[test]
    fn comment_errors() {
        assert!(matches!(
            close_and_downcase(b"G0 (a (b) c)"),
            Err(InterpError::NestedComment)
        ));
        assert!(matches!(
            close_and_downcase(b"G0 (open"),
            Err(InterpError::UnclosedComment)
        ));
        assert!(close_and_downcase(b"G0 ; (not a comment").is_ok());
    }
}
