//! Reading a joint's COMP_FILE (`[JOINT_n]COMP_FILE` and COMP_FILE_TYPE):
//! one entry per line, three numbers separated by white space — the
//! nominal position, then two values whose meaning COMP_FILE_TYPE gives:
//! * type 0: the *actual* positions reached when travelling to the
//!   nominal in the positive and in the negative direction (turned into
//!   trims: nominal minus actual);
//! * type 1: the trims themselves, added to the command when moving in
//!   the positive and in the negative direction.
//!
//! Nominals must strictly increase, at most [`MAX_COMP_ENTRIES`] entries.
//! Blank lines and lines starting with `#` are skipped. LinuxCNC stops
//! reading silently at the first line it cannot parse; here such a line
//! is an error naming the file and line, as is anything else wrong, and
//! nothing is loaded.

use std::path::Path;

use crate::comp::{CompEntry, MAX_COMP_ENTRIES};

/// What the two values after the nominal are (COMP_FILE_TYPE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CompFileType {
    /// 0: actual positions reached moving positive, moving negative.
    Actual,
    /// 1: trims added to the command moving positive, moving negative.
    Trim,
}

impl CompFileType {
    /// The type with COMP_FILE_TYPE value `text` ("0" or "1").
    pub fn from_ini(text: &str) -> Result<CompFileType, CompFileError> {
        match text.trim() {
            "0" => Ok(CompFileType::Actual),
            "1" => Ok(CompFileType::Trim),
            other => Err(CompFileError::BadType {
                found: other.to_string(),
            }),
        }
    }
}

/// Why a compensation file was not loaded.
#[derive(Debug, thiserror::Error)]
pub enum CompFileError {
    /// The file could not be read.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: String,
        /// What went wrong.
        source: std::io::Error,
    },
    /// A line is not three numbers.
    #[error("{file}:{line}: expected three numbers (nominal, then two values), found {found:?}")]
    Malformed {
        /// The file.
        file: String,
        /// The line (from 1).
        line: usize,
        /// The line's text (cut to 80 characters).
        found: String,
    },
    /// A number is infinite or not a number.
    #[error("{file}:{line}: {value} is not a finite number")]
    NotFinite {
        /// The file.
        file: String,
        /// The line (from 1).
        line: usize,
        /// The number as written.
        value: String,
    },
    /// A nominal is not above the one before.
    #[error(
        "{file}:{line}: nominal {nominal} does not increase (line {previous_line} has {previous}); \
         nominals must be in increasing order"
    )]
    NotIncreasing {
        /// The file.
        file: String,
        /// The line (from 1).
        line: usize,
        /// Its nominal.
        nominal: f64,
        /// The line of the entry before.
        previous_line: usize,
        /// The nominal before.
        previous: f64,
    },
    /// More entries than a table holds.
    #[error("{file}:{line}: more than {MAX_COMP_ENTRIES} entries")]
    TooMany {
        /// The file.
        file: String,
        /// The line of the first entry too many.
        line: usize,
    },
    /// The file holds no entry.
    #[error("{file}: no compensation entries")]
    Empty {
        /// The file.
        file: String,
    },
    /// COMP_FILE_TYPE is not 0 or 1.
    #[error("COMP_FILE_TYPE must be 0 or 1, not {found:?}")]
    BadType {
        /// What was given.
        found: String,
    },
}

/// The text of a line for a message: at most 80 characters.
fn shown(line: &str) -> String {
    let t: String = line.chars().take(80).collect();
    if line.chars().count() > 80 {
        t + "..."
    } else {
        t
    }
}

/// Parses the text of a compensation file; `file` names it in errors.
pub fn parse_comp(
    file: &str,
    text: &[u8],
    kind: CompFileType,
) -> Result<Vec<CompEntry>, CompFileError> {
    let mut entries: Vec<CompEntry> = Vec::new();
    let mut previous_line = 0;
    for (i, raw) in text.split(|&b| b == b'\n').enumerate() {
        let line_no = i + 1;
        let malformed = |found: &str| CompFileError::Malformed {
            file: file.to_string(),
            line: line_no,
            found: shown(found),
        };
        let Ok(line) = std::str::from_utf8(raw) else {
            return Err(malformed(&String::from_utf8_lossy(raw)));
        };
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        if words.len() != 3 {
            return Err(malformed(line));
        }
        let mut v = [0.0; 3];
        for (slot, w) in v.iter_mut().zip(&words) {
            let x: f64 = w.parse().map_err(|_| malformed(line))?;
            if !x.is_finite() {
                return Err(CompFileError::NotFinite {
                    file: file.to_string(),
                    line: line_no,
                    value: shown(w),
                });
            }
            *slot = x;
        }
        let [nominal, a, b] = v;
        if let Some(last) = entries.last() {
            if nominal <= last.nominal {
                return Err(CompFileError::NotIncreasing {
                    file: file.to_string(),
                    line: line_no,
                    nominal,
                    previous_line,
                    previous: last.nominal,
                });
            }
        }
        if entries.len() == MAX_COMP_ENTRIES {
            return Err(CompFileError::TooMany {
                file: file.to_string(),
                line: line_no,
            });
        }
        let (forward, reverse) = match kind {
            CompFileType::Actual => (nominal - a, nominal - b),
            CompFileType::Trim => (a, b),
        };
        if !(forward.is_finite() && reverse.is_finite()) {
            return Err(CompFileError::NotFinite {
                file: file.to_string(),
                line: line_no,
                value: shown(line),
            });
        }
        entries.push(CompEntry {
            nominal,
            forward,
            reverse,
        });
        previous_line = line_no;
    }
    if entries.is_empty() {
        return Err(CompFileError::Empty {
            file: file.to_string(),
        });
    }
    Ok(entries)
}

/// Reads and parses the compensation file at `path`: a regular file of
/// at most [`limits::COMP`](hal_core::files::limits::COMP) bytes.
pub fn read_comp_file(path: &Path, kind: CompFileType) -> Result<Vec<CompEntry>, CompFileError> {
    use hal_core::files::{limits, read_user_file};
    let name = path.display().to_string();
    let text =
        read_user_file(path, limits::COMP, "compensation file").map_err(|e| CompFileError::Io {
            file: name.clone(),
            source: e.into(),
        })?;
    parse_comp(&name, &text, kind)
}

/// The fuzz target's body: any bytes, either type, never a panic; what is
/// accepted is a table a joint takes whole.
pub fn fuzz_comp_file(data: &[u8]) {
    for kind in [CompFileType::Actual, CompFileType::Trim] {
        if let Ok(entries) = parse_comp("fuzz", data, kind) {
            assert!(!entries.is_empty() && entries.len() <= MAX_COMP_ENTRIES);
            let mut table = crate::comp::CompTable::default();
            for e in entries {
                table.push(e).expect("a parsed table loads");
            }
            let _ = table.trim(0.0, true);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn type_0_is_turned_into_trims_and_type_1_is_taken_as_is() {
        // LinuxCNC's examples.
        let t0 = b"-1.000 -1.005 -0.995\n0.000 0.002 -0.003\n1.000 1.003 0.998\n";
        let e = parse_comp("t0", t0, CompFileType::Actual).unwrap();
        let want = [
            (-1.0, 0.005, -0.005),
            (0.0, -0.002, 0.003),
            (1.0, -0.003, 0.002),
        ];
        for (got, (n, f, r)) in e.iter().zip(want) {
            assert_eq!(got.nominal, n);
            assert!((got.forward - f).abs() < 1e-12 && (got.reverse - r).abs() < 1e-12);
        }
        let t1 = b"# trims\n\n-1.000 0.005 -0.005\n0.000 0.002 -0.003\n  1.000\t0.003 -0.004\n";
        let e = parse_comp("t1", t1, CompFileType::Trim).unwrap();
        assert_eq!(e.len(), 3);
        assert_eq!(
            (e[2].nominal, e[2].forward, e[2].reverse),
            (1.0, 0.003, -0.004)
        );
    }

    #[test]
    fn malformed_files_name_the_file_and_line() {
        let err = |text: &[u8]| {
            parse_comp("screw.tbl", text, CompFileType::Trim)
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            err(b"0 0 0\n1 0.1\n"),
            "screw.tbl:2: expected three numbers (nominal, then two values), found \"1 0.1\""
        );
        assert_eq!(
            err(b"0 0 0\n1 0 0 0\n"),
            "screw.tbl:2: expected three numbers (nominal, then two values), found \"1 0 0 0\""
        );
        assert!(err(b"0 x 0\n").starts_with("screw.tbl:1: expected three numbers"));
        assert_eq!(err(b"0 0 inf\n"), "screw.tbl:1: inf is not a finite number");
        assert_eq!(err(b"0 0 NaN\n"), "screw.tbl:1: NaN is not a finite number");
        assert_eq!(
            err(b"0 0 0\n\n2 0 0\n1 0 0\n"),
            "screw.tbl:4: nominal 1 does not increase (line 3 has 2); nominals must be in \
             increasing order"
        );
        assert_eq!(
            err(b"1 0 0\n1 0 0\n"),
            "screw.tbl:2: nominal 1 does not increase (line 1 has 1); nominals must be in \
             increasing order"
        );
        assert_eq!(err(b"# nothing\n\n"), "screw.tbl: no compensation entries");
        assert!(err(b"0 0 0\n\xff 1 1\n").starts_with("screw.tbl:2:"));
        let many: String = (0..=MAX_COMP_ENTRIES)
            .map(|k| format!("{k} 0 0\n"))
            .collect();
        assert_eq!(err(many.as_bytes()), "screw.tbl:257: more than 256 entries");
        assert!(matches!(
            CompFileType::from_ini("2"),
            Err(CompFileError::BadType { .. })
        ));
        let missing = read_comp_file(Path::new("/nonexistent/comp.tbl"), CompFileType::Trim)
            .unwrap_err()
            .to_string();
        assert!(missing.starts_with("/nonexistent/comp.tbl: "), "{missing}");
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 100_000, ..ProptestConfig::default() })]

        /// The fuzz target (run on stable until the workspace's fuzz crate
        /// exists): random bytes, and random near-valid tables.
        #[test]
        fn fuzz_comp_file_never_panics(data in prop::collection::vec(any::<u8>(), 0..64)) {
            fuzz_comp_file(&data);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2_000, ..ProptestConfig::default() })]

        #[test]
        fn near_valid_tables_load_or_say_where(
            rows in prop::collection::vec((-1e3f64..1e3, -1.0f64..1.0, -1.0f64..1.0), 0..300),
        ) {
            let text: String = rows.iter().map(|(n, a, b)| format!("{n} {a} {b}\n")).collect();
            fuzz_comp_file(text.as_bytes());
            match parse_comp("p", text.as_bytes(), CompFileType::Trim) {
                Ok(e) => prop_assert!(e.windows(2).all(|w| w[0].nominal < w[1].nominal)),
                Err(e) => prop_assert!(e.to_string().starts_with("p")),
            }
        }
    }
}
