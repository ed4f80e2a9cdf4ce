//! Executing a block, in LinuxCNC's order: comment, spindle mode, feed
//! mode, feed rate, spindle speed, tool selection, M-codes, G-codes (in
//! their own order), then stopping codes.

mod comment;
mod context;
mod mcodes;
mod modes;
mod motion;
mod offsets;
mod stop;
mod threading;
mod tools;

pub(crate) use context::SavedState;

use crate::block::Block;
use crate::canon::Canon;
use crate::codes::*;
use crate::comp::Queued;
use crate::error::Result;
use crate::interp::{Interp, Status};
use crate::setup::{FeedMode, SpindleMode};

impl Interp {
    /// Execute one block.
    pub(crate) fn execute_block(
        &mut self,
        block: &mut Block,
        canon: &mut dyn Canon,
    ) -> Result<Status> {
        block.line_number = self.s.sequence_number;
        if let Some(comment) = block.comment.clone() {
            self.convert_comment(&comment, canon)?;
        }
        if block.g_modes[GM_SPINDLE_MODE] != -1 {
            self.check_spindle_number(block, "Invalid spindle ($) number in Spindle Mode command")?;
            self.convert_spindle_mode(block, canon);
        }
        if block.g_modes[GM_FEED_MODE] != -1 {
            self.check_spindle_number(block, "Invalid spindle ($) number in Spindle Feed command")?;
            self.convert_feed_mode(block.g_modes[GM_FEED_MODE], canon);
        }
        if block.f_flag && self.s.feed_mode != FeedMode::InverseTime {
            self.s.feed_rate = block.f_number;
            self.enqueue(canon, Queued::SetFeedRate(block.f_number));
        }
        if block.s_flag {
            if block.dollar_flag && (block.dollar_number < -1.0 || block.dollar_number >= 1.0) {
                return Err(crate::error::InterpError::Unsupported(
                    "Invalid spindle ($) number in Spindle speed command",
                ));
            }
            self.s.speed = block.s_number;
            self.enqueue(canon, Queued::SetSpindleSpeed(block.s_number));
        }
        if block.t_flag {
            self.convert_tool_select(block, canon)?;
        }
        self.convert_m(block, canon)?;
        self.convert_g(block, canon)?;
        if block.m_modes[4] != -1 {
            if let Some(status) = self.convert_stop(block, canon)? {
                return Ok(status);
            }
        }
        if self.s.probe_flag || self.s.input_flag || self.s.toolchange_flag {
            return Ok(Status::ExecuteFinish);
        }
        Ok(Status::Ok)
    }

    /// Only spindle 0 exists: `$0` (or no `$`) is accepted.
    fn check_spindle_number(&self, block: &Block, message: &'static str) -> Result<()> {
        if block.dollar_flag && (block.dollar_number < 0.0 || block.dollar_number >= 1.0) {
            return Err(crate::error::InterpError::Unsupported(message));
        }
        Ok(())
    }

    fn convert_spindle_mode(&mut self, block: &Block, canon: &mut dyn Canon) {
        if block.g_modes[GM_SPINDLE_MODE] == G_97 {
            self.s.spindle_mode = SpindleMode::ConstantRpm;
            self.enqueue(canon, Queued::SetSpindleMode(0.0));
        } else {
            self.s.spindle_mode = SpindleMode::ConstantSurface;
            let limit = if block.d_flag {
                block.d_number.abs()
            } else {
                1e30
            };
            self.enqueue(canon, Queued::SetSpindleMode(limit));
        }
    }

    /// The G-codes of a block other than G93/G94/G95, in order.
    fn convert_g(&mut self, block: &mut Block, canon: &mut dyn Canon) -> Result<()> {
        if block.g_modes[GM_MODAL_0] == G_4 {
            self.enqueue(canon, Queued::Dwell(block.p_number));
        }
        if block.g_modes[GM_SET_PLANE] != -1 {
            self.convert_set_plane(block.g_modes[GM_SET_PLANE], canon)?;
        }
        if block.g_modes[GM_LENGTH_UNITS] != -1 {
            self.convert_length_units(block.g_modes[GM_LENGTH_UNITS], canon)?;
        }
        if block.g_modes[GM_LATHE_DIAMETER_MODE] != -1 {
            self.convert_lathe_diameter_mode(block, canon);
        }
        if block.g_modes[GM_CUTTER_COMP] != -1 {
            self.convert_cutter_compensation(block, canon)?;
        }
        if block.g_modes[GM_TOOL_LENGTH_OFFSET] != -1 {
            self.convert_tool_length_offset(block.g_modes[GM_TOOL_LENGTH_OFFSET], block, canon)?;
        }
        if block.g_modes[GM_COORD_SYSTEM] != -1 {
            self.convert_coordinate_system(block.g_modes[GM_COORD_SYSTEM], canon)?;
        }
        if block.g_modes[GM_CONTROL_MODE] != -1 {
            self.convert_control_mode(
                block.g_modes[GM_CONTROL_MODE],
                block.p_number,
                block.q_number,
                canon,
            )?;
        }
        if block.g_modes[GM_DISTANCE_MODE] != -1 {
            self.convert_distance_mode(block.g_modes[GM_DISTANCE_MODE], canon);
        }
        if block.g_modes[GM_IJK_DISTANCE_MODE] != -1 {
            self.convert_ijk_distance_mode(block.g_modes[GM_IJK_DISTANCE_MODE], canon);
        }
        if block.g_modes[GM_RETRACT_MODE] != -1 {
            self.convert_retract_mode(block.g_modes[GM_RETRACT_MODE], canon)?;
        }
        if block.g_modes[GM_MODAL_0] != -1 {
            self.convert_modal_0(block.g_modes[GM_MODAL_0], block, canon)?;
        }
        if block.g_modes[GM_G92_RESET] != -1 {
            self.convert_axis_offsets(block.g_modes[GM_G92_RESET], block, canon)?;
        }
        if block.motion_to_be != -1 {
            self.convert_motion(block.motion_to_be, block, canon)?;
        }
        Ok(())
    }

    fn convert_modal_0(
        &mut self,
        code: i32,
        block: &mut Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        match code {
            G_10 => {
                if matches!(block.l_number, 1 | 10 | 11) {
                    self.convert_setup_tool(block, canon)
                } else if block.l_number == 0 {
                    Err(crate::error::InterpError::Unsupported(
                        "G10 L0 (reload the tool table) is not supported",
                    ))
                } else {
                    self.convert_setup(block, canon)
                }
            }
            G_28 | G_30 => self.convert_home(code, block, canon),
            G_28_1 | G_30_1 => self.convert_savehome(code),
            G_52 | G_92 => self.convert_axis_offsets(code, block, canon),
            G_5_3 => self.convert_nurbs_end(block, canon),
            _ => Ok(()),
        }
    }
}
