//! C printf conversions halcmd's output depends on, reproduced exactly.

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
        let decimals = (prec as i32 - 1 - exp).max(0) as usize;
        strip_zeros(&format!("{v:.decimals$}")).to_string()
    }
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

    #[test]
    fn matches_c_percent_f() {
        assert_eq!(fmt_f(1.5), "1.500000");
        assert_eq!(fmt_f(-0.0), "-0.000000");
        assert_eq!(fmt_f(1e20), "100000000000000000000.000000");
        assert_eq!(fmt_f(f64::NEG_INFINITY), "-inf");
    }
}
