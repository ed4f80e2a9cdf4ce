//! Spindle-synchronised motion: G33 (a move locked to the spindle), G33.1
//! (rigid tapping) and the G76 multi-pass threading cycle, emitted as
//! LinuxCNC's interpreter emits them: START_SPEED_FEED_SYNCH before each
//! synchronised feed, STOP_SPEED_FEED_SYNCH after it.

use crate::block::Block;
use crate::canon::{Canon, Direction, Pose};
use crate::codes::*;
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::setup::Side;

/// Canon moves one G76 pass makes at most (for the size limit).
const MOVES_PER_PASS: usize = 6;

/// G76's words once checked, in radius and program units.
struct Thread {
    /// Thread pitch: distance per spindle revolution along Z.
    pitch: f64,
    /// Offset of the thread crest from the drive line (negative: an
    /// external thread).
    crest: f64,
    /// Depth of the first pass beyond the crest.
    first_depth: f64,
    /// Depth of the last (full) pass beyond the crest.
    full_depth: f64,
    /// Passes get deeper as pass number to the power 1/degression.
    degression: f64,
    /// tan of the compound slide angle.
    compound: f64,
    /// Extra passes at full depth (H).
    spring_passes: i32,
    /// Length along Z of the entry and exit tapers (0: none).
    entry_taper: f64,
    exit_taper: f64,
}

impl Interp {
    /// The spindle a synchronised move follows: its `$` word, else 0.
    fn synched_spindle(&self, block: &Block) -> Option<i32> {
        self.selected_spindles(block, false).map(|r| r.start as i32)
    }

    fn spindle_turning(&self, spindle: i32) -> bool {
        self.s.spindles[spindle as usize].turning != Direction::Stopped
    }

    /// G33: one straight feed locked to the spindle, `K` per revolution.
    pub(crate) fn convert_synched_straight(
        &mut self,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let Some((spindle, end)) = self.begin_synched(G_33, "G33", "G33 move", block, canon)?
        else {
            return Ok(());
        };
        canon.start_speed_feed_synch(spindle, block.k_number, false);
        canon.straight_feed(block.line_number, &end);
        canon.stop_speed_feed_synch();
        self.s.current = end;
        Ok(())
    }

    /// What G33 and G33.1 (`mode`, named `name` in messages) do first.
    /// With cutter compensation on, LinuxCNC sends the move through it
    /// unchecked, as a plain feed without synchronisation: done here, and
    /// `None`. Otherwise the spindle the move is locked to (which must be
    /// turning) and the end point.
    fn begin_synched(
        &mut self,
        mode: i32,
        name: &'static str,
        move_name: &'static str,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<Option<(i32, Pose)>> {
        self.s.arc_not_allowed = false;
        if self.comp_active() {
            self.s.motion_mode = mode;
            let end = self.find_ends(block)?;
            self.straight_with_comp(mode, block, canon, &end)?;
            return Ok(None);
        }
        let spindle = self
            .synched_spindle(block)
            .ok_or(InterpError::SpindleNumber(move_name))?;
        if !self.spindle_turning(spindle) {
            return Err(InterpError::SpindleNotTurning(name));
        }
        self.s.motion_mode = mode;
        let end = self.find_ends(block)?;
        Ok(Some((spindle, end)))
    }

    /// Cutter radius compensation is on with a tool radius.
    fn comp_active(&self) -> bool {
        self.s.cutter_comp_side != Side::Off && self.s.cutter_comp_radius > 0.0
    }

    /// G33.1: rigid tapping to the end point and back; the position does
    /// not change.
    pub(crate) fn convert_rigid_tap(&mut self, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        let Some((spindle, end)) =
            self.begin_synched(G_33_1, "G33.1", "G33.1 move", block, canon)?
        else {
            return Ok(());
        };
        let scale = if block.i_flag { block.i_number } else { 1.0 };
        canon.start_speed_feed_synch(spindle, block.k_number, false);
        canon.rigid_tap(block.line_number, (end.x, end.y, end.z), scale);
        canon.stop_speed_feed_synch();
        Ok(())
    }

    /// G76: the threading cycle, from the current position (the drive
    /// line and the thread's start) to the block's Z.
    pub(crate) fn convert_threading_cycle(
        &mut self,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        self.s.arc_not_allowed = false;
        if self.comp_active() {
            return self.threading_with_comp(block, canon);
        }
        let spindle = self
            .synched_spindle(block)
            .ok_or(InterpError::G76SpindleNumber)?;
        if !self.spindle_turning(spindle) {
            return Err(InterpError::G76SpindleNotTurning(spindle));
        }
        if block.a_flag || block.b_flag || block.c_flag {
            return Err(InterpError::G76Rotary);
        }
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::G76WithComp);
        }
        let thread = self.thread_words(block)?;
        self.s.motion_mode = G_76;
        let end = self.find_ends(block)?;
        let start = self.s.current;
        let limit = self.config.max_cycle_moves;
        let passes = thread
            .pass_depths(limit as usize / MOVES_PER_PASS)
            .ok_or(InterpError::ThreadTooLong { limit })?;
        let pass = Pass {
            thread: &thread,
            spindle,
            line: block.line_number,
            start,
            end_z: end.z,
        };
        for depth in passes {
            pass.cut(canon, depth);
        }
        canon.straight_traverse(block.line_number, &end);
        self.s.current = end;
        Ok(())
    }

    /// G76 with compensation on: LinuxCNC takes the block for a straight
    /// move through compensation, which checks an entry move's length and
    /// then refuses the motion code.
    fn threading_with_comp(&mut self, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        let end = self.find_ends(block)?;
        self.straight_with_comp(G_76, block, canon, &end)
    }

    /// G76's words, checked in LinuxCNC's order; in diameter mode I, J
    /// and K are diameters.
    fn thread_words(&self, block: &Block) -> Result<Thread> {
        let scale = if self.s.lathe_diameter_mode { 0.5 } else { 1.0 };
        let crest = block.i_number * scale;
        let first_depth = block.j_number * scale;
        let full_depth = block.k_number * scale;
        if crest == 0.0 {
            return Err(InterpError::G76IZero);
        }
        if first_depth <= 0.0 {
            return Err(InterpError::G76JNotPositive);
        }
        if full_depth <= first_depth {
            return Err(InterpError::G76KNotAboveJ);
        }
        let taper = if block.e_flag && block.e_number > 0.0 {
            block.e_number
        } else {
            0.0
        };
        let l = if block.l_flag { block.l_number } else { 0 };
        Ok(Thread {
            pitch: block.p_number,
            crest,
            first_depth,
            full_depth,
            degression: if block.r_flag && block.r_number >= 1.0 {
                block.r_number
            } else {
                1.0
            },
            compound: if block.q_flag {
                block.q_number.to_radians().tan()
            } else {
                0.0
            },
            spring_passes: if block.h_flag { block.h_number } else { 0 },
            entry_taper: if l & 1 != 0 { taper } else { 0.0 },
            exit_taper: if l & 2 != 0 { taper } else { 0.0 },
        })
    }
}

impl Thread {
    /// +1 for an internal thread (passes cut outwards), -1 for external.
    fn inward(&self) -> f64 {
        if self.crest < 0.0 {
            -1.0
        } else {
            1.0
        }
    }

    /// The tool's X offset from the drive line at `depth`.
    fn offset(&self, depth: f64) -> f64 {
        self.crest + self.inward() * depth
    }

    /// The depth of every pass: growing by the degression rule while short
    /// of the full depth (compared as offsets from the drive line, as
    /// LinuxCNC does), then the full depth and the spring passes. None
    /// when that is more than `max_passes`.
    fn pass_depths(&self, max_passes: usize) -> Option<Vec<f64>> {
        let full = self.inward() * self.offset(self.full_depth);
        let mut depths = Vec::new();
        let mut n = 1.0_f64;
        let mut depth = self.first_depth;
        while self.inward() * self.offset(depth) < full {
            if depths.len() >= max_passes {
                return None;
            }
            depths.push(depth);
            n += 1.0;
            depth = self.first_depth * n.powf(1.0 / self.degression);
        }
        // H-1 (or less) leaves out even the pass at full depth.
        let last = usize::try_from(self.spring_passes.saturating_add(1)).unwrap_or(0);
        if depths.len().saturating_add(last) > max_passes {
            return None;
        }
        depths.extend(std::iter::repeat_n(self.full_depth, last));
        Some(depths)
    }
}

/// What every pass of one G76 shares.
struct Pass<'a> {
    thread: &'a Thread,
    spindle: i32,
    line: i32,
    /// Where the cycle started: the drive line's X, the thread's start Z.
    start: Pose,
    end_z: f64,
}

impl Pass<'_> {
    fn at(&self, x: f64, z: f64) -> Pose {
        Pose { x, z, ..self.start }
    }

    /// One pass at `depth`: to the start (shifted along Z by the compound
    /// angle), down (or along the entry taper), along the thread locked
    /// to the spindle, out (along the exit taper), back to the retract X.
    fn cut(&self, canon: &mut dyn Canon, depth: f64) {
        let t = self.thread;
        let toward_end = if self.end_z > self.start.z { 1.0 } else { -1.0 };
        let offset = t.offset(depth);
        // LinuxCNC shifts along Z by the depth as measured back from the
        // offset, rounding included (it decides the sign of a zero).
        let depth = t.inward() * (offset - t.crest);
        let z_start = self.start.z + toward_end * depth * t.compound;
        let z_end = self.end_z + toward_end * (depth - t.full_depth) * t.compound;
        let x_cut = self.start.x + offset;
        let x_crest = x_cut - t.inward() * t.full_depth;
        let x_retract = self.start.x + offset - t.offset(t.full_depth);
        let taper_rate = |length: f64| t.pitch * length.hypot(t.full_depth) / length;
        canon.straight_traverse(self.line, &self.at(x_retract, z_start));
        if t.entry_taper > 0.0 {
            canon.disable_feed_override();
            canon.start_speed_feed_synch(self.spindle, taper_rate(t.entry_taper), false);
            canon.straight_feed(self.line, &self.at(x_crest, z_start));
            let z = z_start + toward_end * t.entry_taper;
            canon.straight_feed(self.line, &self.at(x_cut, z));
        } else {
            canon.straight_traverse(self.line, &self.at(x_cut, z_start));
            canon.disable_feed_override();
        }
        canon.start_speed_feed_synch(self.spindle, t.pitch, false);
        if t.exit_taper > 0.0 {
            let z = z_end - toward_end * t.exit_taper;
            canon.straight_feed(self.line, &self.at(x_cut, z));
            canon.start_speed_feed_synch(self.spindle, taper_rate(t.exit_taper), false);
            canon.straight_feed(self.line, &self.at(x_crest, z_end));
        } else {
            canon.straight_feed(self.line, &self.at(x_cut, z_end));
        }
        canon.stop_speed_feed_synch();
        canon.straight_traverse(self.line, &self.at(x_retract, z_end));
        canon.enable_feed_override();
    }
}
