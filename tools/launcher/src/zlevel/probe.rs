//! The probe map: `probe_points.txt` in the configuration directory, one
//! probed point a line as `X Y Z` (more columns are ignored, `#` starts a
//! comment, blank lines are skipped), read with a bound on its size.

use std::path::Path;

use crate::error::LaunchError;

/// The file name LinuxCNC's component reads, in its working directory
/// (the configuration directory).
pub const FILE_NAME: &str = "probe_points.txt";
/// The largest probe file read (bytes).
pub const MAX_BYTES: u64 = 1 << 20;
/// The most points a map may hold.
pub const MAX_POINTS: usize = 4096;
/// The fewest points a map needs.
pub const MIN_POINTS: usize = 3;

/// One probed point: X and Y rounded to 0.1 as LinuxCNC's component
/// rounds them, Z as measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbePoint {
    /// X (machine units, rounded to 0.1).
    pub x: f64,
    /// Y (machine units, rounded to 0.1).
    pub y: f64,
    /// The measured Z offset.
    pub z: f64,
}

fn round_tenth(v: f64) -> f64 {
    (v * 10.0).round_ties_even() / 10.0
}

/// Parses a probe file's text; `path` names it in the errors.
pub fn parse(path: &Path, bytes: &[u8]) -> Result<Vec<ProbePoint>, LaunchError> {
    let bad = |line: usize, why: String| LaunchError::ProbeFile {
        path: path.to_path_buf(),
        line,
        why,
    };
    let mut points = Vec::new();
    for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line = i + 1;
        let text = std::str::from_utf8(raw).map_err(|_| bad(line, "is not UTF-8 text".into()))?;
        let text = text.split('#').next().unwrap_or("").trim();
        if text.is_empty() {
            continue;
        }
        let mut xyz = [0.0; 3];
        let mut words = text.split_whitespace();
        for (slot, axis) in xyz.iter_mut().zip(["X", "Y", "Z"]) {
            let word = words
                .next()
                .ok_or_else(|| bad(line, format!("has no {axis} value (a line is 'X Y Z')")))?;
            *slot = word
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && v.abs() < 1e9)
                .ok_or_else(|| bad(line, format!("{axis} value '{word}' is not a number")))?;
        }
        if points.len() == MAX_POINTS {
            return Err(bad(line, format!("more than {MAX_POINTS} points")));
        }
        points.push(ProbePoint {
            x: round_tenth(xyz[0]),
            y: round_tenth(xyz[1]),
            z: xyz[2],
        });
    }
    if points.len() < MIN_POINTS {
        return Err(LaunchError::ProbeFile {
            path: path.to_path_buf(),
            line: 0,
            why: format!(
                "has {} point(s); the map needs at least {MIN_POINTS}",
                points.len()
            ),
        });
    }
    Ok(points)
}

/// Reads and parses the probe file at `path`, at most [`MAX_BYTES`] of it.
/// Through the suite's reader of users' files: only a regular file is
/// read (a FIFO named like the map is refused, never waited on).
pub fn load(path: &Path) -> Result<Vec<ProbePoint>, LaunchError> {
    let bytes = hal_core::files::read_user_file(path, MAX_BYTES, "probe file")?;
    parse(path, &bytes)
}

/// The probe-file fuzz target's body: a parse never panics, and a map it
/// accepts has finite values and a bounded number of points.
pub fn fuzz_parse(data: &[u8]) {
    if let Ok(points) = parse(Path::new("fuzz"), data) {
        assert!((MIN_POINTS..=MAX_POINTS).contains(&points.len()));
        assert!(points
            .iter()
            .all(|p| p.x.is_finite() && p.y.is_finite() && p.z.is_finite()));
        let _ = super::interp::Surface::new(&points);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(text: &str) -> Result<Vec<ProbePoint>, LaunchError> {
        parse(Path::new("/cfg/probe_points.txt"), text.as_bytes())
    }

    #[test]
    fn reads_points_comments_and_extra_columns() {
        let pts = p("# map\n0 0 0.1\n\n10.04 0 0.2 7\n0 10.06 -0.3 # edge\n").unwrap();
        assert_eq!(pts.len(), 3);
        assert_eq!(
            pts[1],
            ProbePoint {
                x: 10.0,
                y: 0.0,
                z: 0.2
            }
        );
        assert_eq!(
            pts[2],
            ProbePoint {
                x: 0.0,
                y: 10.1,
                z: -0.3
            }
        );
    }

    #[test]
    fn malformed_line_names_file_and_line() {
        let e = p("0 0 0\n1 x 0\n2 2 2\n").unwrap_err().to_string();
        assert!(
            e.contains("/cfg/probe_points.txt") && e.contains("line 2"),
            "{e}"
        );
        assert!(e.contains("'x'"), "{e}");
        let e = p("0 0 0\n1 1\n").unwrap_err().to_string();
        assert!(e.contains("line 2") && e.contains("no Z"), "{e}");
        let e = p("0 0 nan\n").unwrap_err().to_string();
        assert!(e.contains("line 1"), "{e}");
    }

    #[test]
    fn too_few_points_and_binary_refused() {
        let e = p("0 0 0\n1 1 1\n").unwrap_err().to_string();
        assert!(e.contains("at least 3"), "{e}");
        let e = parse(Path::new("z"), &[0u8; 64]).unwrap_err().to_string();
        assert!(e.contains("line 1"), "{e}");
    }

    #[test]
    fn dev_zero_and_huge_files_are_bounded() {
        let e = load(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(
            e.contains("/dev/zero") && e.contains("not a regular file"),
            "{e}"
        );
        let big = std::env::temp_dir().join(format!("zlevel-big-{}.txt", std::process::id()));
        std::fs::write(&big, vec![b'\n'; MAX_BYTES as usize + 1]).unwrap();
        let e = load(&big).unwrap_err().to_string();
        std::fs::remove_file(&big).unwrap();
        assert!(e.contains("zlevel-big") && e.contains("larger than"), "{e}");
        let e = load(Path::new("/nonexistent/probe_points.txt"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/probe_points.txt"), "{e}");
        let many: String = (0..=MAX_POINTS).map(|i| format!("{i} 0 0\n")).collect();
        let e = p(&many).unwrap_err().to_string();
        assert!(e.contains("more than"), "{e}");
    }
}
