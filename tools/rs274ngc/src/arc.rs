//! Arc geometry: the centre and turn count of an arc given by its
//! centre offsets (I J K) or its radius (R), with LinuxCNC's tolerances
//! and refusals.

use crate::canon::Plane;
use crate::cfmt;
use crate::codes::G_2;
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::setup::SpindleMode;

/// Radius slack for R-format arcs, inches.
const RADIUS_TOLERANCE_INCH: f64 = 0.00005;
/// Radius slack for R-format arcs, millimetres.
const RADIUS_TOLERANCE_MM: f64 = RADIUS_TOLERANCE_INCH * 25.4;
/// Start and end radii may differ by this fraction.
const SPIRAL_RELATIVE_TOLERANCE: f64 = 0.001;
/// Below this, an arc's half chord equals its radius.
const TINY: f64 = 1e-12;

/// The letters of the plane's two axes (for messages).
fn axis_letters(plane: Plane) -> (char, char) {
    match plane {
        Plane::Xy => ('X', 'Y'),
        Plane::Xz => ('Z', 'X'),
        Plane::Yz => ('Y', 'Z'),
        _ => ('!', '!'),
    }
}

/// `a - π/2` and `a + π/2` rounded as C's long double arithmetic does.
fn minus_half_pi(a: f64) -> f64 {
    const HI: f64 = std::f64::consts::FRAC_PI_2;
    const LO: f64 = 6.123233995736766e-17;
    let s = a - HI;
    let bb = s - a;
    let err = (a - (s - bb)) + (-HI - bb);
    s + (err - LO)
}

fn plus_half_pi(a: f64) -> f64 {
    -minus_half_pi(-a)
}

/// Centre and turns of an arc given by centre offsets (or an absolute
/// centre with G90.1).
#[allow(clippy::too_many_arguments)]
pub fn arc_data_ijk(
    mv: i32,
    plane: Plane,
    current: (f64, f64),
    end: (f64, f64),
    ij_absolute: bool,
    offset: (f64, f64),
    turns: i32,
    radius_tolerance: f64,
    spiral_tolerance: f64,
) -> Result<((f64, f64), i32)> {
    let (a, b) = axis_letters(plane);
    let center = if ij_absolute {
        offset
    } else {
        (current.0 + offset.0, current.1 + offset.1)
    };
    let r1 = (center.0 - current.0).hypot(center.1 - current.1);
    let r2 = (center.0 - end.0).hypot(center.1 - end.1);
    if r1 < radius_tolerance || r2 < radius_tolerance {
        return Err(InterpError::ArcZeroRadius {
            a,
            b,
            sx: current.0,
            sy: current.1,
            cx: center.0,
            cy: center.1,
            ex: end.0,
            ey: end.1,
            r1,
            r2,
        });
    }
    let abs_err = (r1 - r2).abs();
    let rel_err = abs_err / r1.max(r2);
    // LinuxCNC 2.9 refuses only an end that is off in both measures.
    if abs_err > spiral_tolerance && rel_err > SPIRAL_RELATIVE_TOLERANCE {
        let f4 = |v: f64| cfmt::f(v, 4);
        return Err(InterpError::ArcRadiusMismatch(format!(
            "Radius to end of arc differs from radius to start: start=({a}{},{b}{}) center=({a}{},{b}{}) end=({a}{},{b}{}) r1={} r2={} abs_err={} rel_err={}%",
            f4(current.0),
            f4(current.1),
            f4(center.0),
            f4(center.1),
            f4(end.0),
            f4(end.1),
            f4(r1),
            f4(r2),
            cfmt::g(abs_err, 4),
            f4(rel_err * 100.0)
        )));
    }
    let turn = if mv == G_2 { -turns } else { turns };
    Ok((center, turn))
}

/// Centre and turns of an arc given by its radius (negative for more
/// than half a circle).
pub fn arc_data_r(
    mv: i32,
    _plane: Plane,
    current: (f64, f64),
    end: (f64, f64),
    radius: f64,
    turns: i32,
    tolerance: f64,
) -> Result<((f64, f64), i32)> {
    if end.0 == current.0 && end.1 == current.1 {
        return Err(InterpError::ArcSameEnds);
    }
    let abs_radius = radius.abs();
    let mid_x = (end.0 + current.0) / 2.0;
    let mid_y = (end.1 + current.1) / 2.0;
    let mut half_length = (mid_x - end.0).hypot(mid_y - end.1);
    if half_length - abs_radius > tolerance {
        return Err(InterpError::ArcRadiusTooSmall);
    }
    if half_length / abs_radius > 1.0 - TINY {
        half_length = abs_radius;
    }
    let direction = (end.1 - current.1).atan2(end.0 - current.0);
    let theta = if (mv == G_2 && radius > 0.0) || (mv != G_2 && radius < 0.0) {
        minus_half_pi(direction)
    } else {
        plus_half_pi(direction)
    };
    let turn2 = (half_length / abs_radius).asin();
    let offset = abs_radius * turn2.cos();
    let center = (mid_x + offset * theta.cos(), mid_y + offset * theta.sin());
    let turn = if mv == G_2 { -turns } else { turns };
    Ok((center, turn))
}

impl Interp {
    /// (radius tolerance for R arcs, end radius tolerance for IJK arcs)
    /// in program units.
    pub(crate) fn arc_tolerances(&self) -> (f64, f64) {
        if self.s.length_units == crate::canon::Units::Inches {
            (
                RADIUS_TOLERANCE_INCH,
                self.config.center_arc_radius_tolerance_inch,
            )
        } else {
            (
                RADIUS_TOLERANCE_MM,
                self.config.center_arc_radius_tolerance_mm,
            )
        }
    }

    /// Feed checks shared by arcs: a feed rate, a spindle speed in feed
    /// per revolution, an F word in inverse time.
    pub(crate) fn check_arc_feed(&self, f_flag: bool) -> Result<()> {
        use crate::setup::FeedMode;
        match self.s.feed_mode {
            FeedMode::UnitsPerMinute => {
                if self.s.feed_rate == 0.0 {
                    return Err(InterpError::ArcZeroFeed);
                }
            }
            FeedMode::UnitsPerRevolution => {
                if self.s.feed_rate == 0.0 {
                    return Err(InterpError::ArcZeroFeed);
                }
                let spindle = &self.s.spindles[self.s.feed_spindle];
                if spindle.speed == 0.0 && spindle.mode == SpindleMode::ConstantRpm {
                    return Err(InterpError::ZeroSpeedFeedPerRev);
                }
            }
            FeedMode::InverseTime => {
                if !f_flag {
                    return Err(InterpError::FMissingInverseArc);
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::codes::G_3;

    #[test]
    fn quarter_circle_by_radius_and_offsets_agree() {
        let (c, t) = arc_data_r(G_3, Plane::Xy, (1.0, 0.0), (0.0, 1.0), 1.0, 1, 0.001).unwrap();
        assert!((c.0).abs() < 1e-12 && (c.1).abs() < 1e-12 && t == 1);
        let (c2, t2) = arc_data_ijk(
            G_2,
            Plane::Xy,
            (1.0, 0.0),
            (0.0, 1.0),
            false,
            (-1.0, 0.0),
            2,
            0.001,
            0.01,
        )
        .unwrap();
        assert_eq!((c2, t2), ((0.0, 0.0), -2));
    }

    #[test]
    fn refusals_have_linuxcnc_texts() {
        let e = arc_data_r(G_2, Plane::Xy, (0.0, 0.0), (0.0, 0.0), 1.0, 1, 0.001).unwrap_err();
        assert_eq!(e.to_string(), "Current point same as end point of arc");
        let e = arc_data_r(G_2, Plane::Xy, (0.0, 0.0), (5.0, 0.0), 1.0, 1, 0.001).unwrap_err();
        assert_eq!(e.to_string(), "Arc radius too small to reach end point");
        let e = arc_data_ijk(
            G_2,
            Plane::Xy,
            (0.0, 0.0),
            (3.0, 0.0),
            false,
            (1.0, 0.0),
            1,
            0.001,
            0.01,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with(
                "Radius to end of arc differs from radius to start: start=(X0.0000,Y0.0000)"
            ),
            "{e}"
        );
        assert!(e.ends_with("abs_err=1 rel_err=50.0000%"), "{e}");
    }

    #[test]
    fn half_pi_steps_round_once() {
        // π/2 in double is a little short of π/2; long double sees it.
        assert_eq!(
            minus_half_pi(std::f64::consts::FRAC_PI_2),
            -6.123233995736766e-17
        );
        assert_eq!(plus_half_pi(0.0), std::f64::consts::FRAC_PI_2);
    }
}
