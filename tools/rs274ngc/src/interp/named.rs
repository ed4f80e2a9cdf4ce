//! Named parameters as the interpreter sees them: the store's local and
//! global ones, and the predefined read-only ones (`#<_x>`,
//! `#<_metric>`, ...) computed from the modal state.

use super::Interp;
use crate::canon::{Direction, Plane, Pose, Units};
use crate::codes::{G_17, G_17_1, G_18, G_18_1, G_19, G_19_1, G_40, G_41, G_42};
use crate::error::{InterpError, Result};
use crate::setup::{DistanceMode, FeedMode, RetractMode, Side, SpindleMode};

/// LinuxCNC's version as `#<_vmajor>` and `#<_vminor>` report it.
const VERSION_MAJOR: f64 = 2.9;
const VERSION_MINOR: f64 = 0.0;

impl Interp {
    /// The value of a predefined read-only parameter, if `name` is one.
    fn predefined(&self, name: &str) -> Option<f64> {
        let s = &self.s;
        let truth = |b: bool| if b { 1.0 } else { 0.0 };
        let machine = self.machine_position();
        Some(match name {
            "_vmajor" => VERSION_MAJOR,
            "_vminor" => VERSION_MINOR,
            "_line" => s.sequence_number as f64,
            "_motion_mode" => s.motion_mode as f64,
            "_plane" => f64::from(match s.plane {
                Plane::Xy => G_17,
                Plane::Xz => G_18,
                Plane::Yz => G_19,
                Plane::Uv => G_17_1,
                Plane::Uw => G_18_1,
                Plane::Vw => G_19_1,
            }),
            "_ccomp" => f64::from(match s.cutter_comp_side {
                Side::Right => G_42,
                Side::Left => G_41,
                Side::Off => G_40,
            }),
            "_metric" => truth(s.length_units == Units::Mm),
            "_imperial" => truth(s.length_units == Units::Inches),
            "_absolute" => truth(s.distance_mode == DistanceMode::Absolute),
            "_incremental" => truth(s.distance_mode == DistanceMode::Incremental),
            "_inverse_time" => truth(s.feed_mode == FeedMode::InverseTime),
            "_units_per_minute" => truth(s.feed_mode == FeedMode::UnitsPerMinute),
            "_units_per_rev" => truth(s.feed_mode == FeedMode::UnitsPerRevolution),
            "_coord_system" => {
                if s.origin_index < 7 {
                    (530 + 10 * s.origin_index) as f64
                } else {
                    (584 + s.origin_index) as f64
                }
            }
            "_tool_offset" => truth(s.tool_offset != Pose::ZERO),
            "_retract_r_plane" => truth(s.retract_mode == RetractMode::RPlane),
            "_retract_old_z" => truth(s.retract_mode == RetractMode::OldZ),
            "_spindle_rpm_mode" => truth(s.spindles[0].mode == SpindleMode::ConstantRpm),
            "_spindle_css_mode" => truth(s.spindles[0].mode == SpindleMode::ConstantSurface),
            "_ijk_absolute_mode" => truth(s.ijk_distance_mode == DistanceMode::Absolute),
            "_lathe_diameter_mode" => truth(s.lathe_diameter_mode),
            "_lathe_radius_mode" => truth(!s.lathe_diameter_mode),
            "_spindle_on" => truth(s.spindles[0].turning != Direction::Stopped),
            "_spindle_cw" => truth(s.spindles[0].turning == Direction::Clockwise),
            "_mist" => truth(s.mist),
            "_flood" => truth(s.flood),
            "_speed_override" => truth(s.speed_override),
            "_feed_override" => truth(s.feed_override),
            "_adaptive_feed" => truth(s.adaptive_feed),
            "_feed_hold" => truth(s.feed_hold),
            "_feed" => s.feed_rate,
            "_rpm" => s.spindles[0].speed.abs(),
            "_current_tool" => s.tool(0).toolno as f64,
            "_current_pocket" => self.pocket_number(s.current_pocket),
            "_selected_pocket" => self.pocket_number(s.selected_pocket),
            "_selected_tool" => s.selected_tool as f64,
            "_x" => s.current.x,
            "_y" => s.current.y,
            "_z" => s.current.z,
            "_a" => s.current.a,
            "_b" => s.current.b,
            "_c" => s.current.c,
            "_u" => s.current.u,
            "_v" => s.current.v,
            "_w" => s.current.w,
            "_abs_x" => machine.x,
            "_abs_y" => machine.y,
            "_abs_z" => machine.z,
            "_abs_a" => machine.a,
            "_abs_b" => machine.b,
            "_abs_c" => machine.c,
            "_value" => self.flow.return_value,
            "_value_returned" => truth(self.flow.value_returned),
            "_call_level" => self.flow.call_level as f64,
            "_remap_level" => 0.0,
            "_task" => 0.0,
            _ => return self.ini_param(name),
        })
    }

    /// `#<_ini[section]key>`: the INI value, read-only, when FEATURES
    /// allows it; section and key are looked up in upper case.
    fn ini_param(&self, name: &str) -> Option<f64> {
        if !self.config.features.ini_vars || name.len() <= 7 {
            return None;
        }
        let prefix = name.get(..5)?;
        if !prefix.eq_ignore_ascii_case("_ini[") {
            return None;
        }
        let close = name.get(6..)?.find(']')? + 6;
        let upper = name.to_ascii_uppercase();
        let key = (upper[5..close].to_string(), upper[close + 1..].to_string());
        let value = self.config.ini_values.get(&key)?;
        crate::cfmt::scan_double(value.trim()).map(|(v, _)| v)
    }

    /// What `#<_current_pocket>`/`#<_selected_pocket>` give for the tool
    /// table entry at `index`: its pocket (P), or a negative index (nothing
    /// selected) as it is; with a random changer the entry number itself
    /// (0 for nothing), as LinuxCNC 2.9's standalone interpreter.
    fn pocket_number(&self, index: i32) -> f64 {
        if self.config.random_toolchanger {
            f64::from(index.max(0))
        } else if index < 0 {
            f64::from(index)
        } else {
            f64::from(self.s.tool(index).pocketno)
        }
    }

    /// The current position in machine coordinates: the current point
    /// plus the G52/G92 offset, rotated by the coordinate system's
    /// rotation, plus the work and tool offsets (as LinuxCNC computes it).
    pub(crate) fn machine_position(&self) -> Pose {
        let s = &self.s;
        let mut m = s.current;
        crate::find::add_pose(&mut m, &s.axis_offset);
        crate::find::rotate(&mut m.x, &mut m.y, s.rotation_xy);
        crate::find::add_pose(&mut m, &s.origin_offset);
        crate::find::add_pose(&mut m, &s.tool_offset);
        m
    }

    /// Look a named parameter up: `Some(value)` if it exists.
    pub(crate) fn find_named_param(&self, name: &str) -> Result<Option<f64>> {
        if let Some(value) = self.predefined(name) {
            return Ok(Some(value));
        }
        Ok(self
            .params
            .find_named(name, self.flow.call_level)
            .map(|n| n.value))
    }

    /// Create a named parameter about to be assigned (no-op if it exists).
    pub(crate) fn add_named_param(&mut self, name: &str) {
        if self.predefined(name).is_some() {
            return;
        }
        self.params.add_named(name, self.flow.call_level);
    }

    /// Assign a named parameter (at execution of its line).
    pub(crate) fn store_named_param(&mut self, name: &str, value: f64) -> Result<()> {
        if self.predefined(name).is_some() {
            return Err(InterpError::NamedParameterReadonly(name.to_string()));
        }
        self.params.store_named(name, value, self.flow.call_level)
    }

    /// Numbered parameter value.
    pub(crate) fn numbered_param(&self, index: usize) -> f64 {
        self.params.get(index)
    }

    /// Nine consecutive parameters from `first` (X..W), converted from
    /// user to program units.
    pub(crate) fn user_pose_from_params(&self, first: usize) -> Pose {
        let p = |i: usize| self.params.get(first + i);
        Pose {
            x: self.user_to_program_len(p(0)),
            y: self.user_to_program_len(p(1)),
            z: self.user_to_program_len(p(2)),
            a: p(3),
            b: p(4),
            c: p(5),
            u: self.user_to_program_len(p(6)),
            v: self.user_to_program_len(p(7)),
            w: self.user_to_program_len(p(8)),
        }
    }
}
