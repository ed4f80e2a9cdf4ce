//! The jerk-limited (S-curve) planner along the path, on the `rsruckig`
//! crate (a Rust port of Ruckig: time-optimal jerk-limited profiles from
//! any state to any target state, computed in microseconds, allocation
//! free once built), which does this job far better than hand-written
//! heuristics.
//!
//! Each segment gets one profile from the state it is entered with to
//! (its end, its end speed, zero acceleration), so every corner is
//! crossed with zero path acceleration and the next profile starts from
//! a known state; the look-ahead uses the closed forms of
//! [`change_distance`]. PAUSE, ABORT and a zero feed scale switch to a
//! braking profile (velocity target 0) as soon as it comes to rest within
//! the executing segment; until then the segment's own profile runs on to
//! its end (and the check repeats in the next one), so no corner is ever
//! entered other than as the look-ahead planned it. A feed override
//! change re-plans from the current state; a re-plan that would not keep
//! the end speed is skipped (the override applies from the next segment).

use rsruckig::prelude::*;

/// Ruckig's errors without allocating (the caller checks the result).
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct Quiet;

impl RuckigErrorHandler for Quiet {
    fn handle_validation_error(_message: &str) -> Result<(), RuckigError> {
        Err(RuckigError::ValidationError(String::new()))
    }

    fn handle_calculator_error(_message: &str) -> Result<(), RuckigError> {
        Err(RuckigError::CalculatorError(String::new()))
    }
}

/// The time to change speed by `dv` starting and ending with zero
/// acceleration, at acceleration `a` and jerk `j`.
fn change_time(dv: f64, a: f64, j: f64) -> f64 {
    let dv = dv.abs();
    if dv <= a * a / j {
        2.0 * (dv / j).sqrt()
    } else {
        a / j + dv / a
    }
}

/// The distance covered while changing speed from `v0` to `v1` as fast as
/// possible, starting and ending with zero acceleration.
pub(super) fn change_distance(v0: f64, v1: f64, a: f64, j: f64) -> f64 {
    0.5 * (v0 + v1) * change_time(v1 - v0, a, j)
}

/// The fastest entry speed (at most `vmax`) from which a segment `len`
/// long can still end at `ve`.
pub(super) fn entry_speed_max(len: f64, ve: f64, vmax: f64, a: f64, j: f64) -> f64 {
    if ve >= vmax {
        return vmax;
    }
    if change_distance(vmax, ve, a, j) <= len {
        return vmax;
    }
    let (mut lo, mut hi) = (ve, vmax);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if change_distance(mid, ve, a, j) <= len {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The end speed nearest to `want` that can be reached from `v0` (zero
/// acceleration) within distance `d`.
pub(super) fn reachable_end_speed(v0: f64, want: f64, d: f64, a: f64, j: f64) -> f64 {
    if change_distance(v0, want, a, j) <= d {
        return want;
    }
    // Between v0 and want, the distance grows towards want.
    let (mut ok, mut bad) = (v0, want);
    for _ in 0..60 {
        let mid = 0.5 * (ok + bad);
        if change_distance(v0, mid, a, j) <= d {
            ok = mid;
        } else {
            bad = mid;
        }
    }
    ok
}

/// What the profile in use does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Mode {
    /// At rest (or between profiles).
    Idle,
    /// To the end of the executing segment at its end speed.
    Position,
    /// Braking to rest along the path.
    Brake,
}

/// The S-curve planner's state: the profile in use and when it started.
pub(super) struct SCurve {
    otg: Ruckig<1, Quiet>,
    input: InputParameter<1>,
    traj: Trajectory<1>,
    /// A profile being tried before it replaces `traj`.
    trial: Trajectory<1>,
    pub mode: Mode,
    /// Time since the profile started.
    pub t: f64,
    /// The speed limit the profile was made with.
    pub vt: f64,
    /// The end speed of a position profile.
    pub vf: f64,
    /// The end position of a position profile.
    pub target: f64,
}

/// A sample of a profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Sample {
    pub pos: f64,
    pub vel: f64,
    pub acc: f64,
}

impl SCurve {
    /// A planner for period `period`; all memory is allocated here.
    pub fn new(period: f64) -> SCurve {
        let mut input = InputParameter::new(None);
        input.min_velocity = Some(DataArrayOrVec::new(None, 0.0));
        SCurve {
            otg: Ruckig::new(None, period),
            input,
            traj: Trajectory::new(None),
            trial: Trajectory::new(None),
            mode: Mode::Idle,
            t: 0.0,
            vt: 0.0,
            vf: 0.0,
            target: 0.0,
        }
    }

    /// Forgets the profile.
    pub fn reset(&mut self) {
        self.mode = Mode::Idle;
        self.t = 0.0;
    }

    /// Plans from (`s`, `v`, `a`) to (`len`, `vf`, 0) with speed limit
    /// `vt`, acceleration `acc` and jerk `jerk`. False (the old profile
    /// kept) if Ruckig finds none within the limits.
    #[allow(clippy::too_many_arguments)]
    pub fn plan_position(
        &mut self,
        s: f64,
        v: f64,
        a: f64,
        len: f64,
        vf: f64,
        vt: f64,
        acc: f64,
        jerk: f64,
    ) -> bool {
        let inp = &mut self.input;
        inp.control_interface = ControlInterface::Position;
        inp.current_position[0] = s;
        inp.current_velocity[0] = v;
        inp.current_acceleration[0] = a;
        inp.target_position[0] = len;
        inp.target_velocity[0] = vf.min(vt);
        inp.target_acceleration[0] = 0.0;
        inp.max_velocity[0] = vt;
        inp.max_acceleration[0] = acc;
        inp.max_jerk[0] = jerk;
        if !self.valid() {
            return false;
        }
        match self.otg.calculate(&self.input, &mut self.traj) {
            Ok(RuckigResult::Working) => {
                self.mode = Mode::Position;
                self.t = 0.0;
                self.vt = vt;
                self.vf = vf.min(vt);
                self.target = len;
                true
            }
            _ => false,
        }
    }

    /// Plans a stop from (`s`, `v`, `a`) with acceleration `acc` and jerk
    /// `jerk`, if it comes to rest no further than `limit` (the end of the
    /// executing segment: a stop never runs into the next segment, whose
    /// corner speeds assume it is entered without acceleration). True if
    /// it replaced the profile in use.
    pub fn plan_brake_within(
        &mut self,
        s: f64,
        v: f64,
        a: f64,
        acc: f64,
        jerk: f64,
        limit: f64,
    ) -> bool {
        let inp = &mut self.input;
        inp.control_interface = ControlInterface::Velocity;
        inp.current_position[0] = s;
        inp.current_velocity[0] = v;
        inp.current_acceleration[0] = a;
        inp.target_position[0] = s;
        inp.target_velocity[0] = 0.0;
        inp.target_acceleration[0] = 0.0;
        inp.max_velocity[0] = 2.0 * v.max(1e-6);
        inp.max_acceleration[0] = acc;
        inp.max_jerk[0] = jerk;
        if !self.valid() {
            return false;
        }
        match self.otg.calculate(&self.input, &mut self.trial) {
            Ok(RuckigResult::Working) => {}
            _ => return false,
        }
        let mut p = DataArrayOrVec::<f64, 1>::new(None, 0.0);
        let mut section = None;
        self.trial.at_time(
            self.trial.get_duration(),
            &mut Some(&mut p),
            &mut None,
            &mut None,
            &mut None,
            &mut section,
        );
        if p[0] > limit + 1e-12 {
            return false;
        }
        std::mem::swap(&mut self.traj, &mut self.trial);
        self.mode = Mode::Brake;
        self.t = 0.0;
        true
    }

    /// Whether every input is a finite number and every limit positive
    /// (Ruckig's own validation would allocate its message).
    fn valid(&self) -> bool {
        let i = &self.input;
        let f = [
            i.current_position[0],
            i.current_velocity[0],
            i.current_acceleration[0],
            i.target_position[0],
            i.target_velocity[0],
        ];
        f.iter().all(|v| v.is_finite())
            && i.max_velocity[0] > 0.0
            && i.max_acceleration[0] > 0.0
            && i.max_jerk[0] > 0.0
            && i.max_acceleration[0].is_finite()
            && i.max_jerk[0].is_finite()
            && i.current_acceleration[0].abs() <= i.max_acceleration[0] * (1.0 + 1e-9)
    }

    /// The profile's duration.
    pub fn duration(&self) -> f64 {
        self.traj.get_duration()
    }

    /// The profile at time `t`.
    pub fn sample(&self, t: f64) -> Sample {
        let mut p = DataArrayOrVec::<f64, 1>::new(None, 0.0);
        let mut v = DataArrayOrVec::<f64, 1>::new(None, 0.0);
        let mut a = DataArrayOrVec::<f64, 1>::new(None, 0.0);
        let mut section = None;
        self.traj.at_time(
            t.min(self.duration()),
            &mut Some(&mut p),
            &mut Some(&mut v),
            &mut Some(&mut a),
            &mut None,
            &mut section,
        );
        Sample {
            pos: p[0],
            vel: v[0],
            acc: a[0],
        }
    }

    /// Whether the profile in use still honours an end speed of `ve` at
    /// `len` (a corner change is only accepted if it does).
    pub fn keeps(&self, ve: f64, len: f64) -> bool {
        match self.mode {
            Mode::Idle => true,
            Mode::Position => self.vf <= ve + 1e-12 && self.target == len,
            Mode::Brake => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn change_distance_matches_a_ruckig_profile() {
        let (a, j) = (100.0, 2000.0);
        for (v0, v1) in [(0.0, 10.0), (10.0, 0.0), (3.0, 4.0), (20.0, 1.0)] {
            let d = change_distance(v0, v1, a, j);
            let mut sc = SCurve::new(0.001);
            let ok = sc.plan_position(0.0, v0, 0.0, d, v1, 1e3, a, j);
            if !ok {
                let r = sc.otg.calculate(&sc.input, &mut sc.traj);
                panic!("{v0} -> {v1} over {d}: {r:?}");
            }
            // Exactly the distance: no room to cruise, so the profile is the
            // pure speed change.
            let end = sc.sample(sc.duration());
            assert!((end.pos - d).abs() < 1e-9 && (end.vel - v1).abs() < 1e-9);
            assert!((sc.duration() - change_time(v1 - v0, a, j)).abs() < 1e-6);
        }
    }

    #[test]
    fn entry_and_reachable_speeds_bracket_the_distance() {
        let (a, j) = (50.0, 1000.0);
        let v = entry_speed_max(2.0, 1.0, 100.0, a, j);
        assert!((change_distance(v, 1.0, a, j) - 2.0).abs() < 1e-9);
        assert_eq!(entry_speed_max(1e6, 1.0, 30.0, a, j), 30.0);
        let r = reachable_end_speed(0.0, 100.0, 0.5, a, j);
        assert!((change_distance(0.0, r, a, j) - 0.5).abs() < 1e-9);
        assert_eq!(reachable_end_speed(0.0, 1.0, 10.0, a, j), 1.0);
        // Braking: the lowest end speed reachable.
        let low = reachable_end_speed(20.0, 0.0, 1.0, a, j);
        assert!(low > 0.0 && (change_distance(20.0, low, a, j) - 1.0).abs() < 1e-9);
    }

    #[test]
    fn a_brake_profile_stops_within_the_limits() {
        let mut sc = SCurve::new(0.001);
        assert!(
            !sc.plan_brake_within(0.0, 10.0, 50.0, 100.0, 2000.0, 0.5),
            "too far"
        );
        assert!(sc.plan_brake_within(0.0, 10.0, 50.0, 100.0, 2000.0, 100.0));
        assert!(sc.sample(sc.duration()).pos <= 100.0);
        let end = sc.sample(sc.duration());
        assert!(end.vel.abs() < 1e-9 && end.acc.abs() < 1e-9);
        let mut t = 0.0;
        while t < sc.duration() {
            let s = sc.sample(t);
            assert!(s.vel >= -1e-9 && s.acc.abs() <= 100.0 + 1e-9);
            t += 0.001;
        }
    }
}
