//! Offset moves: `plasmac` moves Z (and X/Y for consumable change and cut
//! recovery) through motion's external offsets by stepping a count
//! toward a target, a fixed number of counts per period. Motion applies
//! `counts * offset-scale` and reports the offset it has reached
//! (`axis.N.eoffset`), which says when a move is done.

/// One offset axis: the counts commanded and where they are going.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Mover {
    /// Counts commanded now (`axis.N.eoffset-counts`).
    pub counts: i32,
    /// Counts the move goes to.
    pub target: i32,
    /// Counts per period.
    pub speed: i32,
}

impl Mover {
    /// Starts a move to `target` at `speed` counts per period.
    pub fn go(&mut self, target: i32, speed: i32) {
        self.target = target;
        self.speed = speed.max(1);
    }

    /// Moves by `delta` counts at once (THC corrections, probing steps).
    pub fn nudge(&mut self, delta: i32) {
        self.counts = self.counts.saturating_add(delta);
        self.target = self.counts;
    }

    /// One period of the move.
    pub fn step(&mut self) {
        let d = i64::from(self.target) - i64::from(self.counts);
        let s = i64::from(self.speed.max(1));
        self.counts = (i64::from(self.counts) + d.clamp(-s, s)) as i32;
    }

    /// Whether the commanded counts reached the target and motion's
    /// offset `current` (in units, `scale` units per count) followed.
    pub fn arrived(&self, current: f64, scale: f64) -> bool {
        self.counts == self.target
            && (current - f64::from(self.counts) * scale).abs() <= scale * 2.0
    }
}

/// `units-per-mm` as the component uses it: 0, negative, unset or not a
/// number reads as metric (1).
pub fn usable_units_per_mm(units_per_mm: f64) -> f64 {
    if units_per_mm > 0.0 && units_per_mm.is_finite() {
        units_per_mm
    } else {
        1.0
    }
}

/// Units per offset count: 0.001 mm over `resolution` counts, in machine
/// units per mm `upm` ([`usable_units_per_mm`]).
pub fn offset_scale(resolution: i32, upm: f64) -> f64 {
    0.001 * usable_units_per_mm(upm) / f64::from(resolution.max(1))
}

/// Counts per period of a feed rate in units per minute (at least one).
pub fn counts_per_period(feed_upm: f64, dt: f64, scale: f64) -> i32 {
    let c = feed_upm.abs() / 60.0 * dt / scale;
    if c.is_finite() {
        c.round().clamp(1.0, f64::from(i32::MAX / 4)) as i32
    } else {
        1
    }
}

/// Counts of a distance in units (rounded, saturated).
pub fn to_counts(units: f64, scale: f64) -> i32 {
    let c = (units / scale).round();
    if c.is_finite() {
        c.clamp(f64::from(i32::MIN / 2), f64::from(i32::MAX / 2)) as i32
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moves_step_toward_the_target_and_stop_there() {
        let mut m = Mover::default();
        m.go(-25, 10);
        m.step();
        assert_eq!(m.counts, -10);
        m.step();
        m.step();
        assert_eq!(m.counts, -25);
        assert!(m.arrived(-25.0 * 0.01, 0.01));
        assert!(!m.arrived(0.0, 0.01));
        m.nudge(3);
        assert_eq!((m.counts, m.target), (-22, -22));
    }

    #[test]
    fn scale_and_speeds() {
        assert_eq!(offset_scale(100, 1.0), 1e-5);
        assert_eq!(offset_scale(100, 0.0), 1e-5);
        assert!((offset_scale(100, 1.0 / 25.4) - 1e-5 / 25.4).abs() < 1e-15);
        // 600 mm/min in 1 ms at 1e-5 mm per count: 1000 counts.
        assert_eq!(counts_per_period(600.0, 0.001, 1e-5), 1000);
        assert_eq!(counts_per_period(0.0, 0.001, 1e-5), 1);
        assert_eq!(to_counts(-0.5, 1e-5), -50000);
        assert_eq!(to_counts(f64::NAN, 1e-5), 0);
    }
}
