//! `[TRAJ]POSITION_FILE`: the joints' positions kept from one run to the
//! next, for machines without home switches, as LinuxCNC's task keeps
//! them: at exit the feedback position of every joint slot (16, used or
//! not) is written one per line with 17 decimals; at start, before
//! anything moves, each joint's motor offset is set so that the joint
//! reads the saved position where the motors are now. Homing replaces
//! the offset as usual.
//!
//! A missing file is the first run: nothing is restored and nothing is
//! said. A file that does not hold 16 numbers is not used, with a
//! message (LinuxCNC's: it ignores the file). The file is replaced as a
//! whole at exit, never truncated in place, so a crash while writing
//! leaves the old positions.

use std::path::{Path, PathBuf};

use hal_lang::ini::Ini;

use crate::error::LaunchError;

/// Joint slots in the file (LinuxCNC's EMCMOT_MAX_JOINTS).
pub const SLOTS: usize = 16;

/// Largest file read: 16 lines of a few dozen characters, with room to
/// spare for hand-edited files.
const MAX_BYTES: u64 = 64 * 1024;

/// The position file of `ini`, relative to its folder; `None` when
/// `[TRAJ]POSITION_FILE` is absent or empty.
pub fn path_of(ini: &Ini) -> Option<PathBuf> {
    let value = ini.get("TRAJ", "POSITION_FILE")?.trim();
    if value.is_empty() {
        return None;
    }
    let p = Path::new(value);
    Some(if p.is_absolute() {
        p.to_path_buf()
    } else {
        ini.dir().join(p)
    })
}

/// What reading the file gave.
#[derive(Debug, Clone, PartialEq)]
pub enum Loaded {
    /// The positions of the 16 joint slots.
    Positions([f64; SLOTS]),
    /// No file yet: nothing to restore.
    Missing,
}

/// Reads the 16 positions of `path`. A missing file is [`Loaded::Missing`];
/// anything else that keeps 16 finite numbers from being read is an
/// error naming the file and the first slot that failed.
pub fn load(path: &Path) -> Result<Loaded, LaunchError> {
    let bytes = match hal_core::files::read_user_file(path, MAX_BYTES, "position file") {
        Ok(b) => b,
        Err(e) if e.is_not_found() => return Ok(Loaded::Missing),
        Err(e) => return Err(e.into()),
    };
    parse(path, &String::from_utf8_lossy(&bytes)).map(Loaded::Positions)
}

/// The 16 positions of `text` (whitespace-separated numbers).
pub fn parse(path: &Path, text: &str) -> Result<[f64; SLOTS], LaunchError> {
    let mut words = text.split_whitespace();
    let mut out = [0.0; SLOTS];
    for (joint, slot) in out.iter_mut().enumerate() {
        let bad = |why: String| LaunchError::PositionFile {
            path: path.to_path_buf(),
            joint,
            why,
        };
        let word = words
            .next()
            .ok_or_else(|| bad(format!("the file ends before joint {joint}'s position")))?;
        let v: f64 = word
            .parse()
            .map_err(|_| bad(format!("{word:?} is not a number")))?;
        if !v.is_finite() {
            return Err(bad(format!("{word:?} is not a finite position")));
        }
        *slot = v;
    }
    Ok(out)
}

/// The file's text for `positions` (missing slots as 0), LinuxCNC's
/// layout: one `%.17f` value per line.
pub fn format(positions: &[f64]) -> String {
    (0..SLOTS)
        .map(|j| format!("{:.17}\n", positions.get(j).copied().unwrap_or(0.0)))
        .collect()
}

/// Writes `positions` to `path`, replacing the old file as a whole.
pub fn save(path: &Path, positions: &[f64]) -> Result<(), LaunchError> {
    hal_core::files::replace_file(path, format(positions).as_bytes()).map_err(|source| {
        LaunchError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Fuzz entry point: any bytes as a position file's text; a file that
/// is accepted holds 16 finite positions that format back and read the
/// same to the 17 decimals written (as LinuxCNC's `%.17f`, a position
/// below 5e-18 in size comes back as 0).
pub fn fuzz_parse(data: &[u8]) {
    let path = Path::new("fuzz");
    if let Ok(p) = parse(path, &String::from_utf8_lossy(data)) {
        assert!(p.iter().all(|v| v.is_finite()));
        let back = parse(path, &format(&p)).expect("what format writes reads back");
        for (a, b) in p.iter().zip(back.iter()) {
            assert!((a - b).abs() <= 1e-17, "{a} came back as {b}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sixteen_lines_of_seventeen_decimals_read_back_exactly() {
        let positions = [1.5, -0.1, 1e-9, 12345.678901234567];
        let text = format(&positions);
        assert_eq!(text.lines().count(), SLOTS);
        assert_eq!(text.lines().next(), Some("1.50000000000000000"));
        assert_eq!(text.lines().nth(4), Some("0.00000000000000000"));
        let back = parse(Path::new("p.txt"), &text).unwrap();
        assert_eq!(&back[..4], &positions[..]);
        assert!(back[4..].iter().all(|v| *v == 0.0));
    }

    #[test]
    fn a_short_or_bad_file_names_the_joint_that_failed() {
        let p = Path::new("/cfg/position.txt");
        let e = parse(p, "1 2 3").unwrap_err().to_string();
        assert_eq!(
            e,
            "/cfg/position.txt: joint 3: the file ends before joint 3's position \
             (positions not restored)"
        );
        let e = parse(p, &"0\n".repeat(5).replace("0\n0\n0\n0\n0\n", "0 0 x 0 0"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("joint 2: \"x\" is not a number"), "{e}");
        let e = parse(p, &format!("inf {}", "0 ".repeat(15)))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("joint 0: \"inf\" is not a finite position"),
            "{e}"
        );
    }

    #[test]
    fn a_missing_file_is_the_first_run_and_a_directory_is_refused() {
        let d = std::env::temp_dir().join(format!("posfile-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        assert_eq!(load(&d.join("none.txt")).unwrap(), Loaded::Missing);
        assert!(load(&d).is_err());
        let f = d.join("position.txt");
        save(&f, &[2.0, 3.0]).unwrap();
        match load(&f).unwrap() {
            Loaded::Positions(p) => assert_eq!(&p[..3], &[2.0, 3.0, 0.0]),
            other => panic!("{other:?}"),
        }
        std::fs::remove_dir_all(&d).unwrap();
    }
}
