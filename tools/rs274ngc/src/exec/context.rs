//! M70 (save modal state), M71 (forget it), M72 (restore it) and M73
//! (save, and restore on return from the subroutine). Restoring issues
//! the G- and M-codes that bring the modes back, as LinuxCNC does.

use crate::canon::{Canon, Direction, MotionMode, Plane, Units};
use crate::codes::*;
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::setup::{DistanceMode, FeedMode, RetractMode, Side, SpindleMode};

/// The modal state M70/M73 keep.
#[derive(Debug, Clone, PartialEq)]
pub struct SavedState {
    g: [i32; 16],
    m: [i32; 9],
    feed: f64,
    speed: f64,
}

impl Interp {
    fn snapshot(&self) -> SavedState {
        let s = &self.s;
        let mut g = [-1; 16];
        g[1] = s.motion_mode;
        g[3] = match s.plane {
            Plane::Xy => G_17,
            Plane::Xz => G_18,
            Plane::Yz => G_19,
            Plane::Uv => G_17_1,
            Plane::Uw => G_18_1,
            Plane::Vw => G_19_1,
        };
        g[4] = match s.cutter_comp_side {
            Side::Right => G_42,
            Side::Left => G_41,
            Side::Off => G_40,
        };
        g[5] = if s.length_units == Units::Inches {
            G_20
        } else {
            G_21
        };
        g[6] = if s.distance_mode == DistanceMode::Absolute {
            G_90
        } else {
            G_91
        };
        g[7] = match s.feed_mode {
            FeedMode::InverseTime => G_93,
            FeedMode::UnitsPerMinute => G_94,
            FeedMode::UnitsPerRevolution => G_95,
        };
        g[8] = if s.origin_index < 7 {
            530 + 10 * s.origin_index
        } else {
            584 + s.origin_index
        };
        g[9] = if s.tool_offset == crate::canon::Pose::ZERO {
            G_49
        } else {
            G_43
        };
        g[10] = if s.retract_mode == RetractMode::OldZ {
            G_98
        } else {
            G_99
        };
        g[11] = match s.control_mode {
            MotionMode::ExactPath => G_61,
            MotionMode::ExactStop => G_61_1,
            MotionMode::Continuous => G_64,
        };
        g[13] = if s.spindles[0].mode == SpindleMode::ConstantRpm {
            G_97
        } else {
            G_96
        };
        g[14] = if s.ijk_distance_mode == DistanceMode::Absolute {
            G_90_1
        } else {
            G_91_1
        };
        g[15] = if s.lathe_diameter_mode { G_7 } else { G_8 };
        let mut m = [-1; 9];
        m[2] = match s.spindles[0].turning {
            Direction::Clockwise => 3,
            Direction::CounterClockwise => 4,
            Direction::Stopped => 5,
        };
        m[4] = if s.mist {
            7
        } else if s.flood {
            -1
        } else {
            9
        };
        m[5] = if s.flood { 8 } else { -1 };
        m[6] = if s.feed_override && s.speed_override {
            48
        } else {
            49
        };
        m[7] = if s.adaptive_feed { 52 } else { -1 };
        m[8] = if s.feed_hold { 53 } else { -1 };
        SavedState {
            g,
            m,
            feed: s.feed_rate,
            speed: s.spindles[0].speed,
        }
    }

    /// M70-M73.
    pub(crate) fn convert_modal_state(&mut self, code: i32, canon: &mut dyn Canon) -> Result<()> {
        let level = self.flow.call_level;
        match code {
            70 | 73 => {
                let state = self.snapshot();
                let frame = &mut self.flow.contexts[level];
                frame.saved_state = Some(state);
                if code == 73 && level > 0 {
                    frame.restore_on_return = true;
                }
            }
            71 => self.flow.contexts[level].saved_state = None,
            _ => {
                let Some(state) = self.flow.contexts[level].saved_state.clone() else {
                    return Err(InterpError::M72NoContext);
                };
                self.restore_state(&state, canon)?;
            }
        }
        Ok(())
    }

    /// Bring the modes back to `state` by executing G- and M-codes.
    pub(crate) fn restore_state(
        &mut self,
        state: &SavedState,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let now = self.snapshot();
        if now.g[5] != state.g[5] {
            self.execute_internal(&format!("G{}", state.g[5] / 10), canon)?;
        }
        let mut cmd = String::new();
        if state.feed != now.feed {
            cmd.push_str(&format!(" F{}", crate::cfmt::f(state.feed, 1)));
        }
        if state.speed != now.speed {
            cmd.push_str(&format!(" S{}", crate::cfmt::f(state.speed, 0)));
        }
        for i in [2usize, 4, 5, 6, 7, 8] {
            if state.m[i] != now.m[i] && state.m[i] != -1 {
                cmd.push_str(&format!("M{}\n", state.m[i]));
            }
        }
        for i in [3usize, 4, 6, 7, 8, 9, 10, 11, 13, 14, 15] {
            if state.g[i] != now.g[i] && state.g[i] != -1 {
                cmd.push(' ');
                cmd.push_str(&g_text(state.g[i]));
            }
        }
        for line in cmd.split('\n').filter(|l| !l.is_empty()) {
            self.execute_internal(line, canon)
                .map_err(|e| InterpError::RestoreFailed(line.to_string(), e.to_string()))?;
        }
        Ok(())
    }

    /// Read and execute a generated line, keeping the line being run.
    fn execute_internal(&mut self, text: &str, canon: &mut dyn Canon) -> Result<()> {
        let raw = std::mem::take(&mut self.raw_line);
        let clean = std::mem::take(&mut self.clean);
        let block = std::mem::take(&mut self.block);
        let length = self.line_length;
        let result = self
            .read_mdi(text.as_bytes(), canon)
            .and_then(|_| self.execute(canon));
        self.raw_line = raw;
        canon.set_line_text(&self.raw_line);
        self.clean = clean;
        self.block = block;
        self.line_length = length;
        result.map(|_| ())
    }
}
