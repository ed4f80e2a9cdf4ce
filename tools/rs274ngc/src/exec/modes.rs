//! The modal G-codes that only switch modes: plane, units, lathe
//! diameter mode, cutter compensation, distance modes, feed mode,
//! retract mode, path control mode, coordinate system.

use crate::block::Block;
use crate::canon::{Canon, MotionMode, Plane, Units};
use crate::codes::*;
use crate::comp::Queued;
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::setup::{DistanceMode, FeedMode, RetractMode, Side};

/// 1/25.4 as LinuxCNC multiplies by it.
const INCH_PER_MM: f64 = 1.0 / 25.4;
const MM_PER_INCH: f64 = 25.4;

impl Interp {
    pub(crate) fn convert_set_plane(&mut self, code: i32, canon: &mut dyn Canon) -> Result<()> {
        let comp = self.s.cutter_comp_side != Side::Off;
        let plane = self.s.plane;
        if comp
            && ((code == G_17 && plane != Plane::Xy)
                || (code == G_18 && plane != Plane::Xz)
                || (code == G_19 && plane != Plane::Yz))
        {
            return Err(InterpError::PlaneWithComp);
        }
        if comp && code == G_19 {
            return Err(InterpError::CompPlane);
        }
        let new = match code {
            G_17 => Plane::Xy,
            G_18 => Plane::Xz,
            G_19 => Plane::Yz,
            G_17_1 => Plane::Uv,
            G_18_1 => Plane::Uw,
            _ => Plane::Vw,
        };
        canon.select_plane(new);
        self.s.plane = new;
        Ok(())
    }

    pub(crate) fn convert_length_units(&mut self, code: i32, canon: &mut dyn Canon) -> Result<()> {
        let (units, k) = if code == G_20 {
            (Units::Inches, INCH_PER_MM)
        } else {
            (Units::Mm, MM_PER_INCH)
        };
        canon.use_length_units(units);
        if self.s.length_units == units {
            return Ok(());
        }
        let s = &mut self.s;
        s.length_units = units;
        for v in [
            &mut s.current.x,
            &mut s.current.y,
            &mut s.current.z,
            &mut s.program_x,
            &mut s.program_y,
            &mut s.program_z,
        ] {
            *v *= k;
        }
        self.comp.scale(k);
        let s = &mut self.s;
        s.cutter_comp_radius *= k;
        for p in [&mut s.axis_offset, &mut s.origin_offset] {
            p.x *= k;
            p.y *= k;
            p.z *= k;
        }
        for v in [
            &mut s.current.u,
            &mut s.current.v,
            &mut s.current.w,
            &mut s.axis_offset.u,
            &mut s.axis_offset.v,
            &mut s.axis_offset.w,
            &mut s.origin_offset.u,
            &mut s.origin_offset.v,
            &mut s.origin_offset.w,
        ] {
            *v *= k;
        }
        s.tool_offset = canon.tool_length_offset();
        s.feed_rate = canon.feed_rate();
        Ok(())
    }

    pub(crate) fn convert_lathe_diameter_mode(&mut self, block: &mut Block, canon: &mut dyn Canon) {
        let to_diameter = block.g_modes[GM_LATHE_DIAMETER_MODE] == G_7;
        if to_diameter == self.s.lathe_diameter_mode {
            return;
        }
        let k = if to_diameter { 0.5 } else { 2.0 };
        if block.x_flag {
            block.x_number *= k;
        }
        if block.motion_to_be == G_76 {
            block.i_number *= k;
            block.j_number *= k;
            block.k_number *= k;
        }
        canon.comment(if to_diameter {
            "interpreter: Lathe diameter mode changed to diameter"
        } else {
            "interpreter: Lathe diameter mode changed to radius"
        });
        self.s.lathe_diameter_mode = to_diameter;
    }

    pub(crate) fn convert_cutter_compensation(
        &mut self,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        match block.g_modes[GM_CUTTER_COMP] {
            G_40 => self.comp_off(canon),
            G_41 | G_41_1 => self.comp_on(Side::Left, block, canon),
            _ => self.comp_on(Side::Right, block, canon),
        }
    }

    fn comp_on(&mut self, mut side: Side, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        let code = block.g_modes[GM_CUTTER_COMP];
        if self.s.plane != Plane::Xy && self.s.plane != Plane::Xz {
            return Err(InterpError::CompPlane);
        }
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::CompAlreadyOn);
        }
        let (mut radius, orientation) = if code == G_41_1 || code == G_42_1 {
            if !block.d_flag {
                return Err(InterpError::CompNoD(code / 10));
            }
            let orientation = if block.l_number != -1 {
                if self.s.plane != Plane::Xz {
                    return Err(InterpError::CompLathePlaneL(code / 10));
                }
                block.l_number
            } else {
                0
            };
            (block.d_number / 2.0, orientation)
        } else {
            let index = if block.d_flag {
                let tool = crate::read::c_int(block.d_number + 0.5);
                if (tool as f64 - block.d_number).abs() >= 0.0001 {
                    return Err(InterpError::CompDNotWhole(code / 10));
                }
                if tool < 0 {
                    return Err(InterpError::CompNegativeD);
                }
                self.find_tool_index(tool)?
            } else {
                0
            };
            let entry = self.s.tool(index);
            let orientation = entry.orientation;
            if self.s.plane != Plane::Xz && orientation != 0 && orientation != 9 {
                return Err(InterpError::CompLathePlane(code / 10));
            }
            (self.user_to_program_len(entry.diameter) / 2.0, orientation)
        };
        if radius < 0.0 {
            radius = -radius;
            side = if side == Side::Right {
                Side::Left
            } else {
                Side::Right
            };
        }
        let text = if side == Side::Right {
            "interpreter: cutter radius compensation on right"
        } else {
            "interpreter: cutter radius compensation on left"
        };
        self.enqueue(canon, Queued::Comment(text.into()));
        self.s.cutter_comp_radius = radius;
        self.s.cutter_comp_orientation = orientation;
        self.s.cutter_comp_side = side;
        Ok(())
    }

    pub(crate) fn convert_distance_mode(&mut self, code: i32, canon: &mut dyn Canon) {
        let (mode, text) = if code == G_90 {
            (
                DistanceMode::Absolute,
                "interpreter: distance mode changed to absolute",
            )
        } else {
            (
                DistanceMode::Incremental,
                "interpreter: distance mode changed to incremental",
            )
        };
        if self.s.distance_mode != mode {
            self.enqueue(canon, Queued::Comment(text.into()));
            self.s.distance_mode = mode;
        }
    }

    pub(crate) fn convert_ijk_distance_mode(&mut self, code: i32, canon: &mut dyn Canon) {
        let (mode, text) = if code == G_90_1 {
            (
                DistanceMode::Absolute,
                "interpreter: IJK distance mode changed to absolute",
            )
        } else {
            (
                DistanceMode::Incremental,
                "interpreter: IJK distance mode changed to incremental",
            )
        };
        if self.s.ijk_distance_mode != mode {
            self.enqueue(canon, Queued::Comment(text.into()));
            self.s.ijk_distance_mode = mode;
        }
    }

    /// G93, G94, G95; `spindle` is the one G95 follows (its `$` word).
    pub(crate) fn convert_feed_mode(&mut self, code: i32, spindle: usize, canon: &mut dyn Canon) {
        match code {
            G_93 => {
                self.enqueue(
                    canon,
                    Queued::Comment("interpreter: feed mode set to inverse time".into()),
                );
                self.s.feed_mode = FeedMode::InverseTime;
                self.enqueue(canon, Queued::SetFeedMode(0, 0));
            }
            G_94 => {
                self.enqueue(
                    canon,
                    Queued::Comment("interpreter: feed mode set to units per minute".into()),
                );
                self.s.feed_mode = FeedMode::UnitsPerMinute;
                self.enqueue(canon, Queued::SetFeedMode(0, 0));
                self.s.feed_rate = 0.0;
                self.enqueue(canon, Queued::SetFeedRate(0.0));
            }
            _ => {
                self.enqueue(
                    canon,
                    Queued::Comment("interpreter: feed mode set to units per revolution".into()),
                );
                self.s.feed_mode = FeedMode::UnitsPerRevolution;
                self.s.feed_spindle = spindle;
                self.enqueue(canon, Queued::SetFeedMode(spindle as i32, 1));
                self.s.feed_rate = 0.0;
                self.enqueue(canon, Queued::SetFeedRate(0.0));
            }
        }
    }

    pub(crate) fn convert_retract_mode(&mut self, code: i32, canon: &mut dyn Canon) -> Result<()> {
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::RetractWithComp);
        }
        if code == G_98 {
            self.enqueue(
                canon,
                Queued::Comment("interpreter: retract mode set to old_z".into()),
            );
            self.s.retract_mode = RetractMode::OldZ;
        } else {
            self.enqueue(
                canon,
                Queued::Comment("interpreter: retract mode set to r_plane".into()),
            );
            self.s.retract_mode = RetractMode::RPlane;
        }
        Ok(())
    }

    pub(crate) fn convert_control_mode(
        &mut self,
        code: i32,
        p: f64,
        q: f64,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::ControlModeWithComp);
        }
        match code {
            G_61 => {
                canon.set_motion_control_mode(MotionMode::ExactPath, 0.0);
                self.s.control_mode = MotionMode::ExactPath;
            }
            G_61_1 => {
                canon.set_motion_control_mode(MotionMode::ExactStop, 0.0);
                self.s.control_mode = MotionMode::ExactStop;
            }
            _ => {
                let tolerance = if p >= 0.0 { p } else { 0.0 };
                canon.set_motion_control_mode(MotionMode::Continuous, tolerance);
                let naive = if q >= 0.0 {
                    q
                } else if p >= 0.0 {
                    p
                } else {
                    0.0
                };
                canon.set_naivecam_tolerance(naive);
                self.s.control_mode = MotionMode::Continuous;
                self.s.tolerance = tolerance;
                self.s.naivecam_tolerance = naive;
            }
        }
        Ok(())
    }

    pub(crate) fn convert_coordinate_system(
        &mut self,
        code: i32,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::CoordSystemWithComp);
        }
        let origin = match code {
            G_54 => 1,
            G_55 => 2,
            G_56 => 3,
            G_57 => 4,
            G_58 => 5,
            G_59 => 6,
            G_59_1 => 7,
            G_59_2 => 8,
            _ => 9,
        };
        if origin == self.s.origin_index {
            self.enqueue(
                canon,
                Queued::Comment("interpreter: continuing to use same coordinate system".into()),
            );
            return Ok(());
        }
        self.s.current = self.find_current_in_system(origin, false);
        self.s.origin_index = origin;
        self.params.set(5220, origin as f64);
        let base = 5200 + origin as usize * 20;
        self.s.origin_offset = self.user_pose_from_params(base + 1);
        self.s.rotation_xy = self.params.get(base + 10);
        canon.set_g5x_offset(origin, &self.s.origin_offset);
        canon.set_g92_offset(&self.s.axis_offset);
        canon.set_xy_rotation(self.s.rotation_xy);
        Ok(())
    }
}
