//! What the interpreter reports about itself: where a refusal happened,
//! the active modal codes, and unit conversions between the machine's
//! (user) units and the program's.

use std::fmt;
use std::path::PathBuf;

use super::Interp;
use crate::canon::{Canon, Plane, Pose, Units};
use crate::codes::*;
use crate::setup::{DistanceMode, FeedMode, RetractMode, Side, SpindleMode};

/// A place in a program: file, 1-based line and column, and the word.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The program or subroutine file.
    pub file: PathBuf,
    /// 1-based line number.
    pub line: usize,
    /// 1-based column of the word.
    pub column: usize,
    /// The word (upper case), e.g. `G1`, `X-2`, `#1=`.
    pub word: String,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.column)?;
        if !self.word.is_empty() {
            write!(f, ": {}", self.word)?;
        }
        Ok(())
    }
}

/// The active modal codes, as LinuxCNC's status reports them.
#[derive(Debug, Clone, PartialEq)]
pub struct ActiveCodes {
    /// G-codes (times ten): motion, plane, distance, IJK distance, feed
    /// mode, units, cutter comp, tool length, coordinate system, control
    /// mode, retract mode, spindle mode, lathe mode.
    pub g: Vec<i32>,
    /// M-codes: spindle, coolant (mist, flood), overrides.
    pub m: Vec<i32>,
    /// Feed rate and spindle speed.
    pub feed: f64,
    /// Spindle speed.
    pub speed: f64,
    /// The blend tolerance in effect (G64 P; 0 for none).
    pub tolerance: f64,
    /// The naive-CAM tolerance in effect (G64 Q).
    pub naivecam_tolerance: f64,
}

impl Interp {
    /// Machine (user) units to program units.
    pub(crate) fn user_to_program_len(&self, u: f64) -> f64 {
        u / self.s.external_length_units / self.s.length_units.mm_per_unit()
    }

    /// Program units to machine (user) units.
    pub(crate) fn program_to_user_len(&self, p: f64) -> f64 {
        p * self.s.length_units.mm_per_unit() * self.s.external_length_units
    }

    /// A tool table pose (user units) in program units.
    pub(crate) fn user_pose_to_program(&self, p: &Pose) -> Pose {
        Pose {
            x: self.user_to_program_len(p.x),
            y: self.user_to_program_len(p.y),
            z: self.user_to_program_len(p.z),
            a: p.a,
            b: p.b,
            c: p.c,
            u: self.user_to_program_len(p.u),
            v: self.user_to_program_len(p.v),
            w: self.user_to_program_len(p.w),
        }
    }

    /// Copy the world's tool table and refresh the tool parameters.
    pub(crate) fn load_tool_table(&mut self, canon: &mut dyn Canon) {
        self.s.tool_table = canon.tool_table();
        if self.s.tool_table.is_empty() {
            self.s.tool_table.push(crate::canon::ToolEntry::EMPTY);
        }
        self.set_tool_parameters();
    }

    /// #5400-#5413 from the tool in the spindle.
    pub(crate) fn set_tool_parameters(&mut self) {
        let t = self.s.tool(0);
        let toolno = if self.config.random_toolchanger {
            if t.toolno >= 0 {
                t.toolno
            } else {
                -1
            }
        } else if t.toolno > 0 {
            t.toolno
        } else {
            0
        };
        let values = [
            toolno as f64,
            t.offset.x,
            t.offset.y,
            t.offset.z,
            t.offset.a,
            t.offset.b,
            t.offset.c,
            t.offset.u,
            t.offset.v,
            t.offset.w,
            t.diameter,
            t.frontangle,
            t.backangle,
            t.orientation as f64,
        ];
        for (i, v) in values.into_iter().enumerate() {
            self.params.set(5400 + i, v);
        }
    }

    /// After a probe: where it stopped, and #5061-#5070.
    pub(crate) fn set_probe_data(&mut self, canon: &mut dyn Canon) {
        self.s.current = canon.position();
        let p = canon.probe_position();
        let values = [p.x, p.y, p.z, p.a, p.b, p.c, p.u, p.v, p.w];
        for (i, v) in values.into_iter().enumerate() {
            self.params.set(5061 + i, v);
        }
        self.params
            .set(5070, if canon.probe_tripped() { 1.0 } else { 0.0 });
    }

    /// The active modal codes.
    pub fn active_codes(&self) -> ActiveCodes {
        let s = &self.s;
        let g = vec![
            s.motion_mode,
            match s.plane {
                Plane::Xy => G_17,
                Plane::Xz => G_18,
                Plane::Yz => G_19,
                Plane::Uv => G_17_1,
                Plane::Uw => G_18_1,
                Plane::Vw => G_19_1,
            },
            if s.distance_mode == DistanceMode::Absolute {
                G_90
            } else {
                G_91
            },
            if s.ijk_distance_mode == DistanceMode::Absolute {
                G_90_1
            } else {
                G_91_1
            },
            match s.feed_mode {
                FeedMode::InverseTime => G_93,
                FeedMode::UnitsPerMinute => G_94,
                FeedMode::UnitsPerRevolution => G_95,
            },
            match s.length_units {
                Units::Inches => G_20,
                _ => G_21,
            },
            match s.cutter_comp_side {
                Side::Off => G_40,
                Side::Left => G_41,
                Side::Right => G_42,
            },
            if s.tool_offset == Pose::ZERO {
                G_49
            } else {
                G_43
            },
            if s.origin_index < 7 {
                530 + 10 * s.origin_index
            } else {
                584 + s.origin_index
            },
            match s.control_mode {
                crate::canon::MotionMode::ExactPath => G_61,
                crate::canon::MotionMode::ExactStop => G_61_1,
                crate::canon::MotionMode::Continuous => G_64,
            },
            if s.retract_mode == RetractMode::OldZ {
                G_98
            } else {
                G_99
            },
            if s.spindles[0].mode == SpindleMode::ConstantSurface {
                G_96
            } else {
                G_97
            },
            if s.lathe_diameter_mode { G_7 } else { G_8 },
        ];
        let m = vec![
            match s.spindles[0].turning {
                crate::canon::Direction::Clockwise => 3,
                crate::canon::Direction::CounterClockwise => 4,
                crate::canon::Direction::Stopped => 5,
            },
            if s.mist { 7 } else { 9 },
            if s.flood { 8 } else { 9 },
            if s.feed_override && s.speed_override {
                48
            } else {
                49
            },
        ];
        ActiveCodes {
            g,
            m,
            feed: s.feed_rate,
            speed: s.spindles[0].speed,
            tolerance: s.tolerance,
            naivecam_tolerance: s.naivecam_tolerance,
        }
    }
}
