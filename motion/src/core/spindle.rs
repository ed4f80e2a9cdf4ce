//! The spindles: SPINDLE_ON, SPINDLE_OFF, SPINDLE_SCALE and the brake
//! commands, the at-speed barrier they set for the next feed move, and
//! what the `spindle.N.*` outputs show each cycle (reference "Spindle
//! commands", §4.3 and `output_to_hal`).
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
}

impl Default for Spindle {
    fn default() -> Self {
        Spindle {
            on: false,
            speed: 0.0,
            brake: false,
            scale: 1.0,
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
}

impl MotionCore {
    /// The spindles a command names: `spindle` or, for −1, every one.
    fn spindle_range(&self, spindle: i32) -> Result<std::ops::Range<usize>, Reject> {
        let n = self.cfg.num_spindles;
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
            s.speed = speed;
            s.brake = false;
        }
        self.atspeed_next_feed = wait;
        Ok(())
    }

    /// SPINDLE_OFF: stop, brake applied.
    pub(super) fn spindle_off(&mut self, spindle: i32) -> CommandResult {
        let range = self.spindle_range(spindle)?;
        for s in &mut self.spindles[range] {
            s.on = false;
            s.speed = 0.0;
            s.brake = true;
        }
        self.atspeed_next_feed = false;
        Ok(())
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
        let speed = if !on || self.inputs.spindle_inhibit[n] {
            0.0
        } else {
            s.speed * scale
        };
        SpindleOutput {
            on,
            forward: on && s.speed > 0.0,
            reverse: on && s.speed < 0.0,
            brake: s.brake,
            speed,
            cmd_rps: if s.on { s.speed / 60.0 } else { 0.0 },
        }
    }
}
