//! Points of the ZX plane as complex numbers (Z real, X imaginary), with
//! the arithmetic done the way C++'s `std::complex<double>` does it under
//! GCC: products by the schoolbook formula, quotients by Smith's method,
//! magnitudes through `hypot`. The profile geometry must round exactly as
//! LinuxCNC's does, or a pass lands one digit off.

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// A point or vector: `re` is Z, `im` is X.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct C {
    pub re: f64,
    pub im: f64,
}

/// The imaginary unit.
pub(crate) const I: C = C { re: 0.0, im: 1.0 };

impl C {
    pub(crate) const fn new(re: f64, im: f64) -> C {
        C { re, im }
    }

    /// Magnitude (`std::abs`).
    pub(crate) fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }

    /// Squared magnitude (`std::norm`: the sum of the squares).
    pub(crate) fn norm(self) -> f64 {
        self.re * self.re + self.im * self.im
    }

    /// Complex conjugate.
    pub(crate) fn conj(self) -> C {
        C::new(self.re, -self.im)
    }

    /// Times a real number.
    pub(crate) fn scale(self, k: f64) -> C {
        C::new(self.re * k, self.im * k)
    }

    /// Divided by a real number.
    pub(crate) fn div_real(self, k: f64) -> C {
        C::new(self.re / k, self.im / k)
    }

    /// Plus a real number.
    pub(crate) fn add_real(self, k: f64) -> C {
        C::new(self.re + k, self.im)
    }
}

/// `a < b ? b : a`, as `std::max` picks.
pub(crate) fn max(a: f64, b: f64) -> f64 {
    if a < b {
        b
    } else {
        a
    }
}

/// `b < a ? b : a`, as `std::min` picks.
pub(crate) fn min(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

impl Add for C {
    type Output = C;
    fn add(self, o: C) -> C {
        C::new(self.re + o.re, self.im + o.im)
    }
}

impl AddAssign for C {
    fn add_assign(&mut self, o: C) {
        *self = *self + o;
    }
}

impl Sub for C {
    type Output = C;
    fn sub(self, o: C) -> C {
        C::new(self.re - o.re, self.im - o.im)
    }
}

impl Neg for C {
    type Output = C;
    fn neg(self) -> C {
        C::new(-self.re, -self.im)
    }
}

impl Mul for C {
    type Output = C;
    fn mul(self, o: C) -> C {
        C::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}

impl Div for C {
    type Output = C;
    /// Smith's division, with the alternate order libgcc uses when the
    /// ratio underflows (the other scalings libgcc does are by powers of
    /// two and change no result in the range a profile uses).
    fn div(self, o: C) -> C {
        let (a, b, c, d) = (self.re, self.im, o.re, o.im);
        if c.abs() < d.abs() {
            let ratio = c / d;
            let denom = c * ratio + d;
            if ratio.abs() > f64::MIN_POSITIVE {
                C::new((a * ratio + b) / denom, (b * ratio - a) / denom)
            } else {
                C::new((c * (a / d) + b) / denom, (c * (b / d) - a) / denom)
            }
        } else {
            let ratio = d / c;
            let denom = d * ratio + c;
            if ratio.abs() > f64::MIN_POSITIVE {
                C::new((b * ratio + a) / denom, (b - a * ratio) / denom)
            } else {
                C::new((a + d * (b / c)) / denom, (b - d * (a / c)) / denom)
            }
        }
    }
}

/// `(re,im)` as C++ streams a complex number (six significant digits).
pub(crate) fn display(z: C) -> String {
    format!("({},{})", crate::cfmt::g(z.re, 6), crate::cfmt::g(z.im, 6))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn division_undoes_multiplication() {
        let a = C::new(3.0, -4.0);
        let b = C::new(0.5, 2.0);
        let q = (a * b) / b;
        assert!((q - a).abs() < 1e-12, "{q:?}");
    }

    #[test]
    fn rotation_by_i_swaps_axes() {
        assert_eq!(C::new(2.0, 3.0) * I, C::new(-3.0, 2.0));
        assert_eq!(display(C::new(1.5, -0.25)), "(1.5,-0.25)");
    }
}
