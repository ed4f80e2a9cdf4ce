//! C printf conversions reproduced exactly: halcmd's values (`%.7g`),
//! motion-logger's numbers (`%.6g`) and `%f`.

/// C's `%.{prec}g`.
pub fn fmt_g(v: f64, prec: usize) -> String {
    let prec = prec.max(1);
    if v.is_nan() {
        return if v.is_sign_negative() { "-nan" } else { "nan" }.to_string();
    }
    if v.is_infinite() {
        return if v < 0.0 { "-inf" } else { "inf" }.to_string();
    }
    if v == 0.0 {
        return if v.is_sign_negative() { "-0" } else { "0" }.to_string();
    }
    // Round to `prec` significant digits first; the exponent of the rounded
    // value decides between fixed and scientific notation.
    let sci = format!("{:.*e}", prec - 1, v);
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if exp < -4 || exp >= prec as i32 {
        let m = strip_zeros(mantissa);
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{m}e{sign}{:02}", exp.unsigned_abs())
    } else {
        fixed(mantissa, exp)
    }
}

/// `%g`'s fixed notation: `mantissa` (`[-]d.ddd`, the value rounded to
/// its significant digits) times ten to `exp` (-4 up to one less than the
/// digits), without trailing zeros. C rounds to `prec - 1 - exp`
/// decimals, which keeps exactly those digits (and when rounding carried
/// into a new digit, the coarser rounding gives the same power of ten):
/// moving the point is the same as formatting again, at a fraction of
/// the cost (halcmd and hal-web print thousands of values a second).
fn fixed(mantissa: &str, exp: i32) -> String {
    let (sign, m) = match mantissa.strip_prefix('-') {
        Some(m) => ("-", m),
        None => ("", mantissa),
    };
    let (lead, rest) = m.split_once('.').unwrap_or((m, ""));
    let mut out = String::with_capacity(sign.len() + m.len() + 6);
    out.push_str(sign);
    if let Ok(shift) = usize::try_from(exp) {
        // `shift` digits of `rest` move before the point.
        let at = shift.min(rest.len());
        out.push_str(lead);
        out.push_str(&rest[..at]);
        out.push('.');
        out.push_str(&rest[at..]);
    } else {
        out.push_str("0.");
        for _ in 1..exp.unsigned_abs() {
            out.push('0');
        }
        out.push_str(lead);
        out.push_str(rest);
    }
    let kept = strip_zeros(&out).len();
    out.truncate(kept);
    out
}

/// C's `%f` (six decimals).
pub fn fmt_f(v: f64) -> String {
    if v.is_nan() {
        return if v.is_sign_negative() { "-nan" } else { "nan" }.to_string();
    }
    if v.is_infinite() {
        return if v < 0.0 { "-inf" } else { "inf" }.to_string();
    }
    format!("{v:.6}")
}

fn strip_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_c_percent_g_7() {
        for (v, want) in [
            (0.0, "0"),
            (-0.0, "-0"),
            (1.0, "1"),
            (-2.5, "-2.5"),
            (1e-7, "1e-07"),
            (123456789.0, "1.234568e+08"),
            (12345678901234567890.0, "1.234568e+19"),
            (-1.5e10, "-1.5e+10"),
            (0.333333333333333, "0.3333333"),
            (1e300, "1e+300"),
            (-1e-300, "-1e-300"),
            (1.23456789, "1.234568"),
            (1000000.0, "1000000"),
            (9999999.5, "1e+07"),
            (0.000123456789, "0.0001234568"),
            (0.0001, "0.0001"),
            (0.00001, "1e-05"),
            (0.1, "0.1"),
            (f64::INFINITY, "inf"),
        ] {
            assert_eq!(fmt_g(v, 7), want, "{v:e}");
        }
    }

    /// `%g` as C words it: rounded once to significant digits, then
    /// again to decimals for the fixed form.
    fn g_formatted_twice(v: f64, prec: usize) -> String {
        let sci = format!("{:.*e}", prec - 1, v);
        let exp: i32 = sci.split_once('e').unwrap().1.parse().unwrap();
        if exp < -4 || exp >= prec as i32 {
            fmt_g(v, prec)
        } else {
            let decimals = (prec as i32 - 1 - exp).max(0) as usize;
            strip_zeros(&format!("{v:.decimals$}")).to_string()
        }
    }

    #[test]
    fn the_fixed_form_moves_the_point_as_formatting_again_would() {
        let mut values = Vec::new();
        // Every exponent the fixed form takes, each side of every
        // rounding step of a few digits, and the carries (9.9999995...).
        for e in -6..=18 {
            let p = 10f64.powi(e);
            for m in [
                1.0, 1.5, 2.5, 9.9999995, 9.99999949, 9.9999999, 0.5, 0.99999995,
            ] {
                // The value and its neighbours (all positive here).
                let v = m * p;
                let (up, down) = (v.to_bits() + 1, v.to_bits() - 1);
                values.extend([v, f64::from_bits(up), f64::from_bits(down), -v]);
            }
        }
        // And a spread of arbitrary values (a fixed xorshift sequence).
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let mantissa = (x >> 11) as f64 / (1u64 << 53) as f64;
            let e = (x % 26) as i32 - 7;
            values.push((mantissa - 0.5) * 2.0 * 10f64.powi(e));
        }
        for v in values {
            if v == 0.0 || !v.is_finite() {
                continue;
            }
            for prec in [1, 2, 6, 7, 15, 17] {
                assert_eq!(
                    fmt_g(v, prec),
                    g_formatted_twice(v, prec),
                    "{v:e} %.{prec}g"
                );
            }
        }
    }

    #[test]
    fn matches_c_percent_f() {
        assert_eq!(fmt_f(1.5), "1.500000");
        assert_eq!(fmt_f(-0.0), "-0.000000");
        assert_eq!(fmt_f(1e20), "100000000000000000000.000000");
        assert_eq!(fmt_f(f64::NEG_INFINITY), "-inf");
    }
}
