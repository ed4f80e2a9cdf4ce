//! Number formatting and scanning the way C's printf and scanf do it,
//! so printed values match LinuxCNC's byte for byte.

/// `printf("%.{prec}f", x)`.
pub fn f(x: f64, prec: usize) -> String {
    if x.is_nan() {
        return if x.is_sign_negative() { "-nan" } else { "nan" }.to_string();
    }
    if x.is_infinite() {
        return if x < 0.0 { "-inf" } else { "inf" }.to_string();
    }
    format!("{x:.prec$}")
}

/// `printf("%.{prec}e", x)`: mantissa, `e`, sign, at least two exponent
/// digits.
pub fn e(x: f64, prec: usize) -> String {
    if !x.is_finite() {
        return f(x, prec);
    }
    let s = format!("{x:.prec$e}");
    let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
    let exp: i32 = exponent.parse().unwrap_or(0);
    let sign = if exp < 0 { '-' } else { '+' };
    format!("{mantissa}e{sign}{:02}", exp.abs())
}

/// `printf("%.{prec}g", x)`.
pub fn g(x: f64, prec: usize) -> String {
    if !x.is_finite() {
        return f(x, prec);
    }
    let p = prec.max(1);
    if x == 0.0 {
        return if x.is_sign_negative() { "-0" } else { "0" }.to_string();
    }
    // The exponent of x once rounded to p significant digits.
    let rounded = format!("{x:.prec$e}", prec = p - 1);
    let exp: i32 = rounded
        .split_once('e')
        .and_then(|(_, e)| e.parse().ok())
        .unwrap_or(0);
    let body = if exp < -4 || exp >= p as i32 {
        e(x, p - 1)
    } else {
        f(x, (p as i32 - 1 - exp).max(0) as usize)
    };
    strip_zeros(&body)
}

fn strip_zeros(s: &str) -> String {
    let (number, exponent) = match s.find('e') {
        Some(i) => (&s[..i], &s[i..]),
        None => (s, ""),
    };
    let number = if number.contains('.') {
        number.trim_end_matches('0').trim_end_matches('.')
    } else {
        number
    };
    format!("{number}{exponent}")
}

/// Length of an integer as `%d` scans it at the start of `s` (optional
/// sign, then digits); `None` when there are no digits.
pub fn scan_int_len(s: &str) -> Option<usize> {
    let bytes = s.as_bytes();
    let mut i = 0;
    if matches!(bytes.first(), Some(b'+') | Some(b'-')) {
        i = 1;
    }
    let digits = bytes[i..].iter().take_while(|b| b.is_ascii_digit()).count();
    (digits > 0).then_some(i + digits)
}

/// A floating-point number as `%lf` (strtod) scans it at the start of
/// `s`: sign, digits with an optional point, optional exponent, or
/// `inf`/`nan`. Returns the value and the length used.
pub fn scan_double(s: &str) -> Option<(f64, usize)> {
    let bytes = s.as_bytes();
    let mut i = 0;
    if matches!(bytes.first(), Some(b'+') | Some(b'-')) {
        i = 1;
    }
    let lower = s[i..].to_ascii_lowercase();
    for word in ["infinity", "inf", "nan"] {
        if lower.starts_with(word) {
            let value: f64 = if word == "nan" {
                f64::NAN
            } else {
                f64::INFINITY
            };
            let value = if bytes.first() == Some(&b'-') {
                -value
            } else {
                value
            };
            return Some((value, i + word.len()));
        }
    }
    let int_digits = bytes[i..].iter().take_while(|b| b.is_ascii_digit()).count();
    let mut j = i + int_digits;
    let mut frac_digits = 0;
    if bytes.get(j) == Some(&b'.') {
        frac_digits = bytes[j + 1..]
            .iter()
            .take_while(|b| b.is_ascii_digit())
            .count();
        j += 1 + frac_digits;
    }
    if int_digits + frac_digits == 0 {
        return None;
    }
    if matches!(bytes.get(j), Some(b'e') | Some(b'E')) {
        let mut k = j + 1;
        if matches!(bytes.get(k), Some(b'+') | Some(b'-')) {
            k += 1;
        }
        let exp_digits = bytes[k..].iter().take_while(|b| b.is_ascii_digit()).count();
        if exp_digits > 0 {
            j = k + exp_digits;
        }
    }
    let text = &s[..j];
    let text = text.strip_suffix('.').unwrap_or(text);
    let value = text.parse::<f64>().ok().or_else(|| {
        // "1.e5" and the like: Rust wants digits after the point.
        text.replace(".e", "e").replace(".E", "E").parse().ok()
    })?;
    Some((value, j))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_matches_printf() {
        assert_eq!(f(-0.0, 4), "-0.0000");
        assert_eq!(f(2.54, 4), "2.5400");
        assert_eq!(f(0.03125, 4), "0.0312");
        assert_eq!(f(1e21, 2), "1000000000000000000000.00");
        assert_eq!(f(f64::NAN, 4), "nan");
        assert_eq!(f(f64::NEG_INFINITY, 4), "-inf");
    }

    #[test]
    fn general_matches_printf() {
        assert_eq!(g(0.00123456, 4), "0.001235");
        assert_eq!(g(1234567.0, 4), "1.235e+06");
        assert_eq!(g(0.5, 4), "0.5");
        assert_eq!(g(0.00001234, 4), "1.234e-05");
        assert_eq!(g(100.0, 4), "100");
        assert_eq!(g(9999.9, 4), "1e+04");
    }

    #[test]
    fn scanning_matches_scanf() {
        assert_eq!(scan_int_len("-12abc"), Some(3));
        assert_eq!(scan_int_len("x"), None);
        assert_eq!(scan_double("1.5 x"), Some((1.5, 3)));
        assert_eq!(scan_double("3e8;"), Some((3e8, 3)));
        assert_eq!(scan_double("-.5"), Some((-0.5, 3)));
        assert_eq!(scan_double("2."), Some((2.0, 2)));
        assert_eq!(scan_double("."), None);
        assert_eq!(scan_double("1e"), Some((1.0, 1)));
    }
}
