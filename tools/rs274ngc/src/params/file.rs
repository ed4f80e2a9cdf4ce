//! The parameter file (`.var`): numbered parameters kept between runs.
//!
//! Each line holding two numbers, a parameter number and a value, sets
//! that parameter; other lines are ignored. Numbers must ascend. On exit
//! the file is rewritten: every parameter it held, plus the persistent
//! set (G28/G30 positions, G92 offsets, the work coordinate systems),
//! with the old file kept as `<name>.bak`.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use super::{Parameters, MAX_PARAMETERS};
use crate::cfmt;
use crate::error::{InterpError, Result};
use crate::source::read_bounded;

/// Largest parameter file read (a full one is under 100 kB).
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// The parameters written to the file whether it held them or not.
pub fn is_persistent(index: usize) -> bool {
    match index {
        5161..=5169 | 5181..=5189 | 5210..=5220 => true,
        5221..=5390 => {
            let in_system = (index - 5221) % 20;
            in_system < 10
        }
        _ => false,
    }
}

/// Scan `"%d %lf"` from the start of a line as C's `sscanf` does:
/// leading white space, an integer, white space, a floating-point
/// number; anything after is ignored.
pub fn scan_pair(line: &str) -> Option<(i64, f64)> {
    let rest = line.trim_start();
    let int_len = cfmt::scan_int_len(rest)?;
    let number: i64 = rest[..int_len].parse().ok().or_else(|| {
        // Out of i64 range: sscanf saturates; any such number is out of
        // the parameter range either way.
        Some(if rest.starts_with('-') {
            i64::MIN
        } else {
            i64::MAX
        })
    })?;
    let rest = rest[int_len..].trim_start();
    let (value, _) = cfmt::scan_double(rest)?;
    Some((number, value))
}

/// The (number, value) pairs of a parameter file's text, checked for
/// range and order.
pub fn parse(text: &str, path: &Path) -> Result<Vec<(usize, f64)>> {
    let mut pairs = Vec::new();
    let mut next = 0usize;
    for (n, line) in text.lines().enumerate() {
        let Some((number, value)) = scan_pair(line) else {
            continue;
        };
        if number <= 0 || number >= MAX_PARAMETERS as i64 {
            return Err(InterpError::BadFileLine {
                path: path.to_path_buf(),
                line: n + 1,
                what: InterpError::ParameterOutOfRange.to_string(),
            });
        }
        let number = number as usize;
        if number < next {
            return Err(InterpError::ParameterFileOrder);
        }
        next = number + 1;
        pairs.push((number, value));
    }
    Ok(pairs)
}

/// Read a parameter file into `params`. A file that does not exist is
/// not an error (it is created on exit). Returns the numbers it held.
pub fn restore(path: &Path, params: &mut Parameters) -> Result<Vec<usize>> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let bytes = read_bounded(path, MAX_FILE_BYTES, "parameter file")?;
    let text = String::from_utf8_lossy(&bytes);
    let pairs = parse(&text, path)?;
    let mut held = Vec::with_capacity(pairs.len());
    for (number, value) in pairs {
        params.set(number, value);
        held.push(number);
    }
    Ok(held)
}

/// The text of a parameter file holding `held` and the persistent set.
pub fn render(params: &Parameters, held: &[usize]) -> String {
    let mut out = String::new();
    for k in 1..MAX_PARAMETERS {
        if is_persistent(k) || held.binary_search(&k).is_ok() {
            out.push_str(&format!("{}\t{}\n", k, cfmt::f(params.get(k), 6)));
        }
    }
    out
}

/// Save the parameters to `path`, keeping the old file as `path.bak`.
/// The numbers written are those the old file held plus the persistent
/// set.
pub fn save(path: &Path, params: &Parameters) -> Result<()> {
    let mut held = Vec::new();
    if path.exists() {
        let bytes = read_bounded(path, MAX_FILE_BYTES, "parameter file")?;
        let text = String::from_utf8_lossy(&bytes);
        held = parse(&text, path)?.into_iter().map(|(n, _)| n).collect();
        let backup = backup_path(path);
        fs::rename(path, &backup).map_err(|e| InterpError::io(&backup, e))?;
    }
    let text = render(params, &held);
    let mut file = fs::File::create(path).map_err(|e| InterpError::io(path, e))?;
    file.write_all(text.as_bytes())
        .map_err(|e| InterpError::io(path, e))
}

fn backup_path(path: &Path) -> PathBuf {
    let mut name = path.as_os_str().to_owned();
    name.push(".bak");
    PathBuf::from(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn persistent_set_is_the_documented_ranges() {
        assert!(is_persistent(5161) && is_persistent(5169) && !is_persistent(5170));
        assert!(is_persistent(5210) && is_persistent(5220));
        assert!(is_persistent(5221) && is_persistent(5230) && !is_persistent(5231));
        assert!(is_persistent(5381) && is_persistent(5390) && !is_persistent(5391));
        assert!(!is_persistent(31) && !is_persistent(5400));
    }

    #[test]
    fn lines_need_two_numbers_and_ascend() {
        let p = Path::new("t.var");
        let pairs = parse("33 7\nhello\n5161 1.5 trailing\n", p).unwrap();
        assert_eq!(pairs, vec![(33, 7.0), (5161, 1.5)]);
        assert!(matches!(
            parse("5161 1\n33 2\n", p),
            Err(InterpError::ParameterFileOrder)
        ));
        assert!(parse("9999 1\n", p).is_err());
    }

    #[test]
    fn render_writes_held_and_persistent_with_six_decimals() {
        let mut params = Parameters::default();
        params.set(33, 8.0);
        params.set(5161, 1.5);
        let text = render(&params, &[33]);
        assert!(text.starts_with("33\t8.000000\n5161\t1.500000\n5162\t0.000000\n"));
        assert!(text.ends_with("5390\t0.000000\n"));
        assert!(!text.contains("\n34\t"));
    }
}
