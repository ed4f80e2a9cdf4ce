//! The spindles: SPINDLE_ON, SPINDLE_OFF, SPINDLE_SCALE, the brake
//! commands and SPINDLE_ORIENT (M19) with its handshake, the at-speed
//! barrier they set for the next feed move, SET_SPINDLESYNC (G95 feed per
//! revolution, G33 position sync; the planner's `spindle_sync` does the
//! following) with the `index-enable` it sets, and what the `spindle.N.*`
//! outputs show each cycle (reference "Spindle commands", §4.3 and
//! `output_to_hal`).
//!
//! Differences from LinuxCNC, for safety: a spindle starts only while
//! motion is enabled, and every spindle stops (brake on) when motion
//! disables, whatever disabled it (a command, a fault, `motion.enable`).

use super::*;
use crate::command::{CommandResult, Quantity, Reject};

/// One spindle as commanded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spindle {
    /// Commanded on (M3/M4).
    pub on: bool,
    /// Commanded speed in rpm; the sign is the direction (positive:
    /// forward, M3).
    pub speed: f64,
    /// The brake is applied.
    pub brake: bool,
    /// The spindle override (SPINDLE_SCALE, at least 0).
    pub scale: f64,
    /// Where an M19 orientation is.
    pub orient: OrientState,
    /// The M19 angle, degrees (`spindle.N.orient-angle`).
    pub orient_angle: f64,
    /// The M19 direction mode (`spindle.N.orient-mode`).
    pub orient_mode: i32,
    /// `spindle.N.orient-fault` when the last orientation failed.
    pub orient_fault: i32,
    /// Constant surface speed (G96): rpm times radius, machine units
    /// (0: off; `speed` is then the speed, else its limit).
    pub css_factor: f64,
    /// The machine X of the spindle axis, for the radius.
    pub css_x_offset: f64,
    /// The speed range (SET_SPINDLE_PARAMS).
    pub limits: SpindleLimits,
}

/// A spindle's speed range, rpm (SET_SPINDLE_PARAMS): forward speeds lie
/// within `min_pos..=max_pos`, reverse speeds within `max_neg..=min_neg`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpindleLimits {
    /// The fastest forward speed.
    pub max_pos: f64,
    /// The slowest forward speed.
    pub min_pos: f64,
    /// The fastest reverse speed (≤ 0).
    pub max_neg: f64,
    /// The slowest reverse speed (≤ 0).
    pub min_neg: f64,
}

impl Default for SpindleLimits {
    /// No limit (LinuxCNC's defaults: ±1e99, 0).
    fn default() -> Self {
        SpindleLimits {
            max_pos: 1e99,
            min_pos: 0.0,
            max_neg: -1e99,
            min_neg: 0.0,
        }
    }
}

impl SpindleLimits {
    /// `speed` held within the range of its direction (0 stays 0).
    pub fn clamp(&self, speed: f64) -> f64 {
        if speed > 0.0 {
            speed.clamp(self.min_pos, self.max_pos)
        } else if speed < 0.0 {
            speed.clamp(self.max_neg, self.min_neg)
        } else {
            speed
        }
    }
}

/// Where a spindle orientation (M19) is, as LinuxCNC's motion reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OrientState {
    /// None asked for (or cancelled by M3, M4, M5).
    #[default]
    None,
    /// `spindle.N.orient` is on; waiting for `is-oriented`.
    InProgress,
    /// `is-oriented` came: the spindle is `locked`, brake on.
    Complete,
    /// `orient-fault` was non-zero while orienting.
    Faulted,
}

impl Default for Spindle {
    fn default() -> Self {
        Spindle {
            on: false,
            speed: 0.0,
            brake: false,
            scale: 1.0,
            orient: OrientState::None,
            orient_angle: 0.0,
            orient_mode: 0,
            orient_fault: 0,
            css_factor: 0.0,
            css_x_offset: 0.0,
            limits: SpindleLimits::default(),
        }
    }
}

/// What a spindle's output pins show this cycle.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpindleOutput {
    /// `spindle.N.on`.
    pub on: bool,
    /// `spindle.N.forward`.
    pub forward: bool,
    /// `spindle.N.reverse`.
    pub reverse: bool,
    /// `spindle.N.brake`.
    pub brake: bool,
    /// `spindle.N.speed-out`: rpm with the override, signed.
    pub speed: f64,
    /// `spindle.N.speed-cmd-rps`: the commanded speed without override,
    /// revolutions per second.
    pub cmd_rps: f64,
    /// `spindle.N.orient`: an orientation is asked for.
    pub orient: bool,
    /// `spindle.N.locked`: the orientation is complete.
    pub locked: bool,
    /// `spindle.N.orient-angle`.
    pub orient_angle: f64,
    /// `spindle.N.orient-mode`.
    pub orient_mode: i32,
}

impl MotionCore {
    /// The spindles a command names: `spindle` or, for −1, every one.
    fn spindle_range(&self, spindle: i32) -> Result<std::ops::Range<usize>, Reject> {
        let n = self.spindles_in_use;
        match spindle {
            -1 => Ok(0..n),
            s if s >= 0 && (s as usize) < n => Ok(s as usize..s as usize + 1),
            _ => Err(Reject::NoSuchSpindle {
                spindle,
                num_spindles: n,
            }),
        }
    }

    /// SPINDLE_ON: turn at `speed` rpm (sign: direction), brake released;
    /// with `wait`, the next feed move waits for the spindle at speed.
    pub(super) fn spindle_on(&mut self, spindle: i32, speed: f64, wait: bool) -> CommandResult {
        let range = self.spindle_range(spindle)?;
        let speed = Self::finite(Quantity::SpindleSpeed, speed)?;
        if !self.enabled {
            return Err(Reject::NotEnabled);
        }
        for s in &mut self.spindles[range] {
            s.on = true;
            s.speed = s.limits.clamp(speed);
            s.brake = false;
            s.orient = OrientState::None;
        }
        self.atspeed_next_feed = wait;
        Ok(())
    }

    /// SET_SPINDLE_PARAMS: the speed range of `spindle` (−1: every
    /// one); a spindle turning now keeps its speed until its next
    /// SPINDLE_ON.
    pub(super) fn set_spindle_params(
        &mut self,
        spindle: i32,
        limits: SpindleLimits,
    ) -> CommandResult {
        let range = self.spindle_range(spindle)?;
        let SpindleLimits {
            max_pos,
            min_pos,
            max_neg,
            min_neg,
        } = limits;
        for v in [max_pos, min_pos, max_neg, min_neg] {
            Self::finite(Quantity::SpindleSpeedLimit, v)?;
        }
        if !(0.0 <= min_pos && min_pos <= max_pos) {
            return Err(Reject::SpindleRangeReversed {
                low: min_pos,
                high: max_pos,
            });
        }
        if !(max_neg <= min_neg && min_neg <= 0.0) {
            return Err(Reject::SpindleRangeReversed {
                low: max_neg,
                high: min_neg,
            });
        }
        for s in &mut self.spindles[range] {
            s.limits = limits;
        }
        Ok(())
    }

    /// Constant surface speed on (`factor` > 0) or off (0) for `spindle`
    /// (−1: every one).
    pub(super) fn spindle_css(
        &mut self,
        spindle: i32,
        factor: f64,
        x_offset: f64,
    ) -> CommandResult {
        let range = self.spindle_range(spindle)?;
        let factor = Self::non_negative(Quantity::SurfaceSpeed, factor)?;
        let x_offset = Self::finite(Quantity::SurfaceSpeed, x_offset)?;
        for s in &mut self.spindles[range] {
            s.css_factor = factor;
            s.css_x_offset = x_offset;
        }
        Ok(())
    }

    /// Feed per revolution of the moves queued next: `per_rev` machine
    /// units per revolution of `spindle` (0: off).
    pub(super) fn set_feed_per_rev(&mut self, spindle: i32, per_rev: f64) -> CommandResult {
        let per_rev = Self::non_negative(Quantity::FeedPerRev, per_rev)?;
        let range = self.spindle_range(spindle)?;
        // One spindle: −1 (every spindle) means nothing here.
        if spindle < 0 {
            return Err(Reject::NoSuchSpindle {
                spindle,
                num_spindles: self.spindles_in_use,
            });
        }
        let follow = (per_rev > 0.0).then_some(crate::tp::FeedPerRev {
            spindle: range.start,
            per_rev,
        });
        self.tp.set_feed_per_rev(follow);
        Ok(())
    }

    /// SET_SPINDLESYNC: the feed moves queued next follow `spindle`'s
    /// position (`velocity_mode` false) or speed at `per_rev` machine
    /// units per revolution; 0 ends both.
    pub(super) fn spindle_sync(
        &mut self,
        spindle: i32,
        per_rev: f64,
        velocity_mode: bool,
    ) -> CommandResult {
        if velocity_mode {
            return self.set_feed_per_rev(spindle, per_rev);
        }
        let per_rev = Self::non_negative(Quantity::FeedPerRev, per_rev)?;
        let range = self.spindle_range(spindle)?;
        if spindle < 0 {
            return Err(Reject::NoSuchSpindle {
                spindle,
                num_spindles: self.cfg.num_spindles,
            });
        }
        let follow = (per_rev > 0.0).then_some(crate::tp::FeedPerRev {
            spindle: range.start,
            per_rev,
        });
        self.tp.set_position_sync(follow);
        if follow.is_none() {
            self.tp.set_feed_per_rev(None);
        }
        Ok(())
    }

    /// The spindles commanded in reverse (bit n: spindle n).
    pub(super) fn spindles_reversed(&self) -> u32 {
        (0..self.cfg.num_spindles)
            .filter(|&n| self.spindles[n].speed < 0.0)
            .fold(0, |m, n| m | 1 << n)
    }

    /// Whether spindle `n`'s `index-enable` is set this cycle: a
    /// position-synchronised move waits for its index.
    pub fn spindle_index_arm(&self, n: usize) -> bool {
        self.state == MotionState::Coord && self.tp.index_arm() == Some(n)
    }

    /// The speed spindle `n` is commanded now, rpm, signed: its SPINDLE_ON
    /// speed or, with constant surface speed, the speed for the commanded
    /// X radius, at most the SPINDLE_ON speed.
    pub fn spindle_speed_now(&self, n: usize) -> f64 {
        let s = &self.spindles[n];
        if s.css_factor <= 0.0 {
            return s.speed;
        }
        let limit = s.speed.abs();
        let radius = (self.carte_pos_cmd.0[0] - s.css_x_offset).abs();
        let rpm = if radius > 0.0 {
            (s.css_factor / radius).min(limit)
        } else {
            limit
        };
        rpm.copysign(s.speed)
    }

    /// SPINDLE_OFF: stop, brake applied.
    pub(super) fn spindle_off(&mut self, spindle: i32) -> CommandResult {
        let range = self.spindle_range(spindle)?;
        for s in &mut self.spindles[range] {
            s.on = false;
            s.speed = 0.0;
            s.brake = true;
            s.orient = OrientState::None;
        }
        self.atspeed_next_feed = false;
        Ok(())
    }

    /// SPINDLE_ORIENT (M19): stop turning, brake released, and ask the
    /// drive for `angle` degrees in `mode` until `is-oriented` or
    /// `orient-fault` answers ([`Self::process_spindle_orient`]).
    pub(super) fn spindle_orient(&mut self, spindle: i32, angle: f64, mode: i32) -> CommandResult {
        if spindle < 0 {
            return Err(Reject::NoSuchSpindle {
                spindle,
                num_spindles: self.spindles_in_use,
            });
        }
        let range = self.spindle_range(spindle)?;
        let angle = Self::finite(Quantity::OrientAngle, angle)?;
        if !self.enabled {
            return Err(Reject::NotEnabled);
        }
        for s in &mut self.spindles[range] {
            s.on = false;
            s.speed = 0.0;
            s.brake = false;
            s.orient = OrientState::InProgress;
            s.orient_angle = angle;
            s.orient_mode = mode;
            s.orient_fault = 0;
        }
        Ok(())
    }

    /// The orient handshake, once per cycle: a non-zero `orient-fault`
    /// fails the orientation (an error; the queue aborts), `is-oriented`
    /// completes it (`locked`, brake on).
    pub(super) fn process_spindle_orient(&mut self) {
        for n in 0..self.cfg.num_spindles {
            if self.spindles[n].orient != OrientState::InProgress {
                continue;
            }
            let fault = self.inputs.spindle_orient_fault[n];
            if fault != 0 {
                let s = &mut self.spindles[n];
                s.orient = OrientState::Faulted;
                s.orient_fault = fault;
                self.events
                    .push(crate::Event::SpindleOrientFault { spindle: n, fault });
                self.error = true;
                self.tp.abort();
            } else if self.inputs.spindle_is_oriented[n] {
                let s = &mut self.spindles[n];
                s.orient = OrientState::Complete;
                s.brake = true;
            }
        }
    }

    /// SPINDLE_SCALE: the spindle override.
    pub(super) fn spindle_scale(&mut self, spindle: i32, scale: f64) -> CommandResult {
        let range = self.spindle_range(spindle)?;
        let scale = Self::non_negative(Quantity::Scale, scale)?;
        for s in &mut self.spindles[range] {
            s.scale = scale;
        }
        Ok(())
    }

    /// SPINDLE_BRAKE_ENGAGE (`on`: the spindle stops too) and
    /// SPINDLE_BRAKE_RELEASE.
    pub(super) fn spindle_brake(&mut self, spindle: i32, on: bool) -> CommandResult {
        let range = self.spindle_range(spindle)?;
        for s in &mut self.spindles[range] {
            if on {
                s.on = false;
                s.speed = 0.0;
            }
            s.brake = on;
        }
        Ok(())
    }

    /// Stops every spindle, brake applied (motion disables).
    pub(super) fn stop_spindles(&mut self) {
        for s in &mut self.spindles {
            if s.on {
                s.on = false;
                s.speed = 0.0;
                s.brake = true;
            }
            if s.orient == OrientState::InProgress {
                s.orient = OrientState::None;
            }
        }
        self.atspeed_next_feed = false;
    }

    /// Whether every running spindle reports `spindle.N.at-speed`.
    pub(super) fn spindles_at_speed(&self) -> bool {
        (0..self.cfg.num_spindles).all(|n| !self.spindles[n].on || self.inputs.spindle_at_speed[n])
    }

    /// Spindle `n` as commanded.
    ///
    /// # Panics
    /// If `n` is not below [`MAX_SPINDLES`].
    pub fn spindle(&self, n: usize) -> Spindle {
        self.spindles[n]
    }

    /// Whether the next feed move will wait for the spindle at speed.
    pub fn atspeed_next_feed(&self) -> bool {
        self.atspeed_next_feed
    }

    /// What spindle `n`'s output pins show: the override applies when the
    /// executing move (or, with none, the moves queued next) has it
    /// enabled (M51), `spindle.N.inhibit` holds the speed at 0.
    ///
    /// # Panics
    /// If `n` is not below [`MAX_SPINDLES`].
    pub fn spindle_output(&self, n: usize) -> SpindleOutput {
        let s = self.spindles[n];
        let enables = match self.state {
            MotionState::Coord => self.tp.status().enables.unwrap_or(self.enables_new),
            _ => self.enables_new,
        };
        let scale = if enables & SS_ENABLED != 0 {
            s.scale
        } else {
            1.0
        };
        let on = s.on && s.speed != 0.0 && scale != 0.0;
        let commanded = self.spindle_speed_now(n);
        let speed = if !on || self.inputs.spindle_inhibit[n] {
            0.0
        } else {
            commanded * scale
        };
        SpindleOutput {
            on,
            forward: on && s.speed > 0.0,
            reverse: on && s.speed < 0.0,
            brake: s.brake,
            speed,
            cmd_rps: if s.on { commanded / 60.0 } else { 0.0 },
            orient: s.orient == OrientState::InProgress,
            locked: s.orient == OrientState::Complete,
            orient_angle: s.orient_angle,
            orient_mode: s.orient_mode,
        }
    }
}
