//! Stopping codes: M0, M1, M60 (pause), M2, M30 (end and reset the
//! modes LinuxCNC resets), M99 at the top level (loop the program in
//! task, end it in standalone rs274).

use crate::block::Block;
use crate::canon::{Canon, Plane};
use crate::comp::Queued;
use crate::error::Result;
use crate::find::{rotate, sub_pose};
use crate::interp::{Interp, Status};
use crate::setup::{DistanceMode, FeedMode, Side};
use crate::source::Line;

impl Interp {
    /// Execute the block's stopping code; `Some(Exit)` at program end.
    pub(crate) fn convert_stop(
        &mut self,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<Option<Status>> {
        let (cx, cy, _) = self.comp_get_current();
        self.move_endpoint_and_flush(canon, cx, cy)?;
        self.dequeue_canons(canon);
        match block.m_modes[4] {
            0 => canon.program_stop(),
            60 => {
                canon.pallet_shuttle();
                canon.program_stop();
            }
            1 => canon.optional_program_stop(),
            99 if self.config.loop_on_main_m99 => {
                if let Some(source) = self.source.as_mut() {
                    source.seek(0)?;
                    self.s.sequence_number = 0;
                }
            }
            code => {
                self.reset_at_end(canon);
                if code == 30 {
                    canon.pallet_shuttle();
                }
                canon.program_end();
                self.check_final_percent(canon)?;
                self.unwind_call();
                return Ok(Some(Status::Exit));
            }
        }
        Ok(None)
    }

    /// The resets of M2 and M30.
    fn reset_at_end(&mut self, canon: &mut dyn Canon) {
        let s = &mut self.s;
        crate::find::add_pose(&mut s.current, &s.origin_offset);
        rotate(&mut s.current.x, &mut s.current.y, s.rotation_xy);
        s.origin_index = 1;
        self.params.set(5220, 1.0);
        let origin = self.user_pose_from_params(5221);
        let rotation = self.params.get(5230);
        let s = &mut self.s;
        s.origin_offset = origin;
        s.rotation_xy = rotation;
        rotate(&mut s.current.x, &mut s.current.y, -rotation);
        sub_pose(&mut s.current, &origin);
        canon.set_g5x_offset(1, &origin);
        canon.set_xy_rotation(rotation);
        if s.plane != Plane::Xy {
            canon.select_plane(Plane::Xy);
            s.plane = Plane::Xy;
        }
        s.distance_mode = DistanceMode::Absolute;
        s.feed_mode = FeedMode::UnitsPerMinute;
        canon.set_feed_mode(0, 0);
        s.feed_rate = 0.0;
        canon.set_feed_rate(0.0);
        if !s.feed_override {
            canon.enable_feed_override();
            s.feed_override = true;
        }
        // LinuxCNC 2.9 re-enables only the feed override here: M49 or
        // M51 P0 outlive the program end for the spindle speed.
        s.cutter_comp_side = Side::Off;
        s.cutter_comp_firstmove = true;
        self.stop_all_spindles(canon, true);
        let s = &mut self.s;
        s.motion_mode = crate::codes::G_1;
        if s.mist {
            canon.mist_off();
            s.mist = false;
        }
        if s.flood {
            canon.flood_off();
            s.flood = false;
        }
        if self.config.disable_g92_persistence {
            for i in 5210..=5219 {
                self.params.set(i, 0.0);
            }
        }
    }

    /// A program that started with `%` should end with one: say so in a
    /// comment when the closing line is missing.
    fn check_final_percent(&mut self, canon: &mut dyn Canon) -> Result<()> {
        if !self.s.percent_flag {
            return Ok(());
        }
        let Some(source) = self.source.as_mut() else {
            return Ok(());
        };
        loop {
            match source.read_line()? {
                None => {
                    self.enqueue(
                        canon,
                        Queued::Comment(
                            "interpreter: percent sign missing from end of file".into(),
                        ),
                    );
                    return Ok(());
                }
                Some(Line::TooLong(_)) => continue,
                Some(Line::Text(text)) => {
                    let trimmed: Vec<u8> = text
                        .iter()
                        .copied()
                        .filter(|&b| !crate::source::is_c_space(b))
                        .collect();
                    if text.last() == Some(&b'%') && trimmed == b"%" {
                        return Ok(());
                    }
                }
            }
        }
    }
}
