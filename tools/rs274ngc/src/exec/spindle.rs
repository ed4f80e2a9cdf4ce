//! The spindle M-codes (M3, M4, M5, M19) for the spindles a block's `$`
//! word selects, and the calls that stop every spindle (tool change,
//! program end).

use crate::block::Block;
use crate::canon::{Canon, Direction};
use crate::comp::Queued;
use crate::error::{InterpError, Result};
use crate::interp::Interp;

impl Interp {
    /// M3, M4, M5 (`$-1`: every spindle) and M19 (one spindle).
    pub(crate) fn convert_spindle_m(&mut self, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        let m = block.m_modes[7];
        if m == 19 {
            return self.orient_spindle(block, canon);
        }
        let spindles =
            self.selected_spindles(block, true)
                .ok_or_else(|| InterpError::SpindleOutOfRange {
                    m,
                    count: self.s.spindles.len(),
                    dollar: block.dollar().unwrap_or(0),
                })?;
        for n in spindles {
            let (call, turning) = match m {
                3 => (Queued::SpindleClockwise(n as i32), Direction::Clockwise),
                4 => (
                    Queued::SpindleCounterClockwise(n as i32),
                    Direction::CounterClockwise,
                ),
                _ => (Queued::SpindleStop(n as i32), Direction::Stopped),
            };
            self.enqueue(canon, call);
            self.s.spindles[n].turning = turning;
        }
        Ok(())
    }

    /// M19: orient one spindle (R angle, P direction) and wait Q seconds.
    fn orient_spindle(&mut self, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        let n = self
            .selected_spindles(block, false)
            .ok_or(InterpError::M19SpindleOutOfRange)?
            .start;
        // LinuxCNC takes every spindle for stopped after an M19.
        for spindle in &mut self.s.spindles {
            spindle.turning = Direction::Stopped;
        }
        if block.r_flag || block.p_flag {
            let angle = if block.r_flag {
                block.r_number + self.s.orient_offset
            } else {
                self.s.orient_offset
            };
            let mode = if block.p_flag {
                block.p_number as i32
            } else {
                0
            };
            canon.orient_spindle(n as i32, angle, mode);
        }
        if block.q_flag {
            if block.q_number <= 0.0 {
                return Err(InterpError::M19Q);
            }
            canon.wait_spindle_orient_complete(n as i32, block.q_number);
        }
        Ok(())
    }

    /// Stops every spindle, in order (a tool change, a program end).
    pub(crate) fn stop_all_spindles(&mut self, canon: &mut dyn Canon, reset_mode: bool) {
        for n in 0..self.s.spindles.len() {
            canon.stop_spindle_turning(n as i32);
            self.s.spindles[n].turning = Direction::Stopped;
            if reset_mode {
                canon.set_spindle_mode(n as i32, 0.0);
            }
        }
    }
}
