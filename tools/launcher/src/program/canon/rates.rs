//! The path speed and acceleration the axes' INI limits allow along one
//! move, as LinuxCNC's canon works them out for SET_LINE's `ini_maxvel`
//! and `acc`: each axis needs at least `distance / limit` for its part,
//! the slowest axis sets the time, and the path length over that time is
//! the path's limit. The path length is the XYZ length, else the UVW
//! length, else (a rotary move) the ABC length. A rapid asks for that
//! speed; a feed for the smaller of it and its feed rate. A move of no
//! length has no rate: task does not queue it, as LinuxCNC's does not.

/// Motions smaller than this, machine units or degrees, count as none.
const TINY: f64 = 1e-7;

/// Each world axis's `[AXIS_L]MAX_VELOCITY` and `MAX_ACCELERATION`,
/// machine units (degrees for A B C).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisRates {
    /// Velocity limits, X Y Z A B C U V W.
    pub vel: [f64; 9],
    /// Acceleration limits.
    pub acc: [f64; 9],
}

impl Default for AxisRates {
    /// No limits (LinuxCNC's 1e99), for axes the INI does not limit.
    fn default() -> Self {
        AxisRates {
            vel: [1e99; 9],
            acc: [1e99; 9],
        }
    }
}

/// What a move may do along its path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveRates {
    /// The largest path speed.
    pub vel: f64,
    /// The largest path acceleration.
    pub acc: f64,
}

impl MoveRates {
    /// No caps of the move's own (motion's 0): the axes' limits apply.
    pub const UNCAPPED: MoveRates = MoveRates { vel: 0.0, acc: 0.0 };

    /// A speed asked for, held to the move's own cap if it has one.
    pub fn cap(&self, vel: f64) -> f64 {
        if self.vel > 0.0 {
            vel.min(self.vel)
        } else {
            vel
        }
    }
}

fn length(d: &[f64]) -> f64 {
    d.iter().map(|v| v * v).sum::<f64>().sqrt()
}

impl AxisRates {
    /// The rates of a straight move from `from` to `to` (machine
    /// coordinates); `None` if it does not move.
    pub fn straight(&self, from: &[f64; 9], to: &[f64; 9]) -> Option<MoveRates> {
        let mut d = [0.0; 9];
        for (i, v) in d.iter_mut().enumerate() {
            let m = (to[i] - from[i]).abs();
            *v = if m < TINY { 0.0 } else { m };
        }
        let len = [length(&d[0..3]), length(&d[6..9]), length(&d[3..6])]
            .into_iter()
            .find(|&l| l > 0.0)?;
        self.over(&d, len)
    }

    /// The rates of an arc from `from` to `to` about the axis through
    /// `center` (XYZ) along the unit vector `normal`, `turns` as motion's
    /// SET_CIRCLE has it, with the length motion's planner gives it. The
    /// two axes of its plane are counted with the whole path length
    /// (either may move that fast on the way round); the others with
    /// their travel. `None` for an arc motion refuses or of no length.
    pub fn arc(
        &self,
        from: &[f64; 9],
        to: &[f64; 9],
        center: [f64; 3],
        normal: [f64; 3],
        turns: i32,
    ) -> Option<MoveRates> {
        let len = motion::tp::arc_length(
            &motion::Pose(*from),
            &motion::Pose(*to),
            center,
            normal,
            turns,
        )?;
        if len.is_nan() || len < TINY {
            return None;
        }
        let mut d = [0.0; 9];
        for (i, v) in d.iter_mut().enumerate() {
            let along = if i < 3 { normal[i].abs() } else { 0.0 };
            // The plane's axes (those the normal does not point along).
            *v = if i < 3 && along < 1.0 - 1e-9 {
                len
            } else {
                (to[i] - from[i]).abs()
            };
        }
        self.over(&d, len)
    }

    /// The path limits of a move `len` long whose axes travel `d`.
    fn over(&self, d: &[f64; 9], len: f64) -> Option<MoveRates> {
        let mut t_vel = 0.0f64;
        let mut t_acc = 0.0f64;
        for (i, &m) in d.iter().enumerate() {
            if m > 0.0 {
                t_vel = t_vel.max(m / self.vel[i]);
                t_acc = t_acc.max(m / self.acc[i]);
            }
        }
        let rates = MoveRates {
            vel: len / t_vel,
            acc: len / t_acc,
        };
        (rates.vel.is_finite() && rates.acc.is_finite() && rates.vel > 0.0 && rates.acc > 0.0)
            .then_some(rates)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rates() -> AxisRates {
        AxisRates {
            vel: [4.0; 9],
            acc: [1000.0; 9],
        }
    }

    /// LinuxCNC's own numbers for its motion-logger test's moves.
    #[test]
    fn the_slowest_axis_sets_the_path_rates() {
        let r = rates();
        let home = [0.0; 9];
        let to = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
        let m = r.straight(&home, &to).unwrap();
        assert_eq!(hal_core::cfmt::fmt_g(m.vel, 6), "1.66296");
        assert_eq!(hal_core::cfmt::fmt_g(m.acc, 6), "415.74");
        let next = [0.1, 2.0, 0.3, 0.4, 5.0, 0.6, 0.7, 8.0, 0.9];
        let m = r.straight(&to, &next).unwrap();
        assert_eq!(hal_core::cfmt::fmt_g(m.vel, 6), "1.40546");
        assert_eq!(hal_core::cfmt::fmt_g(m.acc, 6), "351.364");
        // Along X alone: the axis's own limits.
        let mut x = home;
        x[0] = 1.0;
        assert_eq!(
            r.straight(&home, &x),
            Some(MoveRates {
                vel: 4.0,
                acc: 1000.0
            })
        );
    }

    #[test]
    fn rotary_and_uvw_moves_use_their_own_length_and_no_move_has_none() {
        let mut r = rates();
        r.vel[3] = 90.0;
        let home = [0.0; 9];
        let mut a = home;
        a[3] = 45.0;
        assert_eq!(r.straight(&home, &a).unwrap().vel, 90.0);
        let mut u = home;
        u[6] = 3.0;
        u[3] = 90.0;
        // U's 3 units take 0.75 s, A's 90 degrees 1 s: 3 units a second.
        assert!((r.straight(&home, &u).unwrap().vel - 3.0).abs() < 1e-12);
        let mut tiny = home;
        tiny[1] = 1e-9;
        assert_eq!(r.straight(&home, &tiny), None);
    }

    #[test]
    fn an_arc_is_held_to_its_plane_axes_limits() {
        let mut r = rates();
        r.vel[1] = 2.0;
        r.acc[0] = 50.0;
        let from = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let to = [-1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let half = r.arc(&from, &to, [0.0; 3], [0.0, 0.0, 1.0], 0).unwrap();
        assert!((half.vel - 2.0).abs() < 1e-12 && (half.acc - 50.0).abs() < 1e-9);
        // A full turn more, clockwise: the same limits, and the same
        // start and end make no arc at all only when they have no length.
        assert!(r.arc(&from, &to, [0.0; 3], [0.0, 0.0, 1.0], -2).is_some());
        assert_eq!(
            r.arc(
                &from,
                &from,
                from[..3].try_into().unwrap(),
                [0.0, 0.0, 1.0],
                0
            ),
            None
        );
    }
}
