//! Executing a block, in LinuxCNC's order: comment, spindle mode, feed
//! mode, feed rate, spindle speed, tool selection, M-codes, G-codes (in
//! their own order), then stopping codes.

mod comment;
mod context;
mod g7x;
mod mcodes;
mod modes;
mod motion;
mod offsets;
mod spindle;
mod stop;
mod threading;
mod tools;

pub(crate) use context::SavedState;

use crate::block::Block;
use crate::canon::Canon;
use crate::codes::*;
use crate::comp::Queued;
use std::ops::Range;

use crate::error::{InterpError, Result};
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
            let spindles = self
                .selected_spindles(block, false)
                .ok_or(InterpError::SpindleNumber("Spindle Mode command"))?;
            self.convert_spindle_mode(block, spindles, canon);
        }
        if block.g_modes[GM_FEED_MODE] != -1 {
            let spindle = self
                .selected_spindles(block, false)
                .ok_or(InterpError::SpindleNumber("Spindle Feed command"))?
                .start;
            self.convert_feed_mode(block.g_modes[GM_FEED_MODE], spindle, canon);
        }
        if block.f_flag && self.s.feed_mode != FeedMode::InverseTime {
            self.s.feed_rate = block.f_number;
            self.enqueue(canon, Queued::SetFeedRate(block.f_number));
        }
        if block.s_flag {
            let spindles = self
                .selected_spindles(block, true)
                .ok_or(InterpError::SpindleNumber("Spindle speed command"))?;
            for n in spindles {
                self.s.spindles[n].speed = block.s_number;
                self.enqueue(canon, Queued::SetSpindleSpeed(n as i32, block.s_number));
            }
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

    /// The spindles a block's `$` word selects (spindle 0 without one;
    /// every spindle for `$-1` where `all` allows it), the number cut to
    /// an integer as LinuxCNC does; None when no such spindle exists.
    pub(crate) fn selected_spindles(&self, block: &Block, all: bool) -> Option<Range<usize>> {
        let count = self.s.spindles.len();
        match block.dollar() {
            None => Some(0..1),
            Some(-1) if all => Some(0..count),
            Some(n) => usize::try_from(n)
                .ok()
                .filter(|&n| n < count)
                .map(|n| n..n + 1),
        }
    }

    fn convert_spindle_mode(
        &mut self,
        block: &Block,
        spindles: Range<usize>,
        canon: &mut dyn Canon,
    ) {
        let (mode, limit) = if block.g_modes[GM_SPINDLE_MODE] == G_97 {
            (SpindleMode::ConstantRpm, 0.0)
        } else if block.d_flag {
            (SpindleMode::ConstantSurface, block.d_number.abs())
        } else {
            (SpindleMode::ConstantSurface, 1e30)
        };
        for n in spindles {
            self.s.spindles[n].mode = mode;
            self.enqueue(canon, Queued::SetSpindleMode(n as i32, limit));
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
                    self.convert_reload_tool_data(canon)
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
