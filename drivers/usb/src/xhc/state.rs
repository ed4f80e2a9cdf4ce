//! What the pendant reported, kept between reports, and the experimental
//! velocity jogging outputs computed from the wheel.

use std::time::{Duration, Instant};

use super::report::{InputReport, Switch};

/// The pendant's state as its reports left it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Pendant {
    /// Wheel counts since start-up (wrapping, as an s32 pin).
    pub counts: i32,
    /// The rotary switch.
    pub switch: Switch,
    /// The button held, 0 for none.
    pub button: u8,
    /// The pendant said it is asleep.
    pub sleeping: bool,
}

impl Pendant {
    /// Takes one report in.
    pub fn apply(&mut self, r: &InputReport) {
        self.counts = self.counts.wrapping_add(i32::from(r.wheel));
        self.switch = r.switch;
        self.button = r.button;
        self.sleeping = r.sleeping;
    }

    /// The switch position that enables jogging an axis, by index
    /// x, y, z, a.
    pub fn axis_enabled(&self, axis: usize) -> bool {
        const AXES: [Switch; 4] = [Switch::X, Switch::Y, Switch::Z, Switch::A];
        AXES.get(axis) == Some(&self.switch)
    }

    /// The switch is off (or on a position this driver does not know).
    pub fn off(&self) -> bool {
        matches!(self.switch, Switch::Off | Switch::Unknown(_))
    }
}

/// How long without wheel movement before the velocity outputs drop.
pub const VELOCITY_HOLD: Duration = Duration::from_millis(250);
/// The velocity filter's weight for a new value.
const VELOCITY_K: f64 = 0.05;

/// The `jog.velocity`, `jog.increment` and `jog.plus-*`/`jog.minus-*`
/// outputs, for halui's plus/minus jogging.
#[derive(Debug, Clone, Default)]
pub struct Velocity {
    last_counts: i32,
    last_move: Option<Instant>,
    /// `jog.velocity`.
    pub velocity: f64,
    /// `jog.increment`: |distance| of the last movement.
    pub increment: f64,
    /// The direction of the last movement (+1, -1), 0 once stopped.
    pub direction: i8,
}

impl Velocity {
    /// One update at `now` with the wheel counts, the jog scale and the
    /// `jog.max-velocity` input (units per second).
    pub fn update(&mut self, counts: i32, scale: f64, max_velocity: f64, now: Instant) {
        let since = *self.last_move.get_or_insert(now);
        let delta = f64::from(counts.wrapping_sub(self.last_counts)) * scale;
        if delta != 0.0 {
            let target = max_velocity * 60.0 * scale;
            self.velocity = (1.0 - VELOCITY_K) * self.velocity + VELOCITY_K * target;
            self.increment = delta.abs();
            self.direction = if delta > 0.0 { 1 } else { -1 };
            self.last_counts = counts;
            self.last_move = Some(now);
        } else {
            self.velocity *= 1.0 - VELOCITY_K;
            if now.saturating_duration_since(since) > VELOCITY_HOLD {
                self.velocity = 0.0;
                self.direction = 0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xhc::report::parse_input;

    #[test]
    fn counts_accumulate_and_wrap() {
        let mut p = Pendant {
            counts: i32::MAX,
            ..Default::default()
        };
        p.apply(&parse_input(&[4, 0x0D, 0, 0x11, 1, 0]).unwrap());
        assert_eq!(p.counts, i32::MIN);
        assert_eq!(p.button, 0x0D);
        assert!(p.axis_enabled(0) && !p.axis_enabled(3) && !p.off());
        p.apply(&parse_input(&[4, 0, 0, 0, 0, 0]).unwrap());
        assert!(p.sleeping && p.off());
    }

    #[test]
    fn velocity_follows_the_wheel_and_drops_when_still() {
        let t0 = Instant::now();
        let mut v = Velocity::default();
        v.update(0, 0.01, 1.0, t0);
        assert_eq!((v.velocity, v.direction), (0.0, 0));
        v.update(-3, 0.01, 1.0, t0 + Duration::from_millis(10));
        assert_eq!(v.direction, -1);
        assert!((v.increment - 0.03).abs() < 1e-12);
        assert!((v.velocity - 0.05 * 0.6).abs() < 1e-12);
        v.update(-3, 0.01, 1.0, t0 + Duration::from_millis(100));
        assert_eq!(v.direction, -1, "held within 250 ms");
        v.update(-3, 0.01, 1.0, t0 + Duration::from_millis(400));
        assert_eq!((v.velocity, v.direction), (0.0, 0));
    }
}
