//! Canned cycles G73, G74, G81-G89 in the XY, YZ and XZ planes, with
//! R and Z (or the plane's third axis), L repeats in incremental mode,
//! and G98/G99 retract levels.
//!
//! The code works in the plane's (aa, bb, cc) coordinates: (X, Y, Z) in
//! G17, (Y, Z, X) in G19, (Z, X, Y) in G18. The lathe cycles G70-G72
//! are in [`lathe`].

pub(crate) mod lathe;

use crate::block::Block;
use crate::canon::{Canon, Direction, MotionMode, Plane, Pose, Units};
use crate::codes::*;
use crate::error::{InterpError, Result};
use crate::find::d2r;
use crate::interp::Interp;
use crate::setup::{DistanceMode, FeedMode, RetractMode, Side};

/// Peck retract distance above the hole bottom (G73, G83), inches.
const G83_RAPID_DELTA: f64 = 0.010;

/// How a plane maps (aa, bb, cc) to machine axes, and its names.
struct PlaneAxes {
    plane: Plane,
    third: char,
    third_lower: &'static str,
    name: &'static str,
}

fn plane_axes(plane: Plane) -> Option<PlaneAxes> {
    match plane {
        Plane::Xy => Some(PlaneAxes {
            plane,
            third: 'Z',
            third_lower: "z",
            name: "xy",
        }),
        Plane::Yz => Some(PlaneAxes {
            plane,
            third: 'X',
            third_lower: "x",
            name: "yz",
        }),
        Plane::Xz => Some(PlaneAxes {
            plane,
            third: 'Y',
            third_lower: "y",
            name: "xz",
        }),
        _ => None,
    }
}

impl Interp {
    /// (aa, bb, cc) of a pose in the cycle plane.
    fn cycle_coords(plane: Plane, p: &Pose) -> (f64, f64, f64) {
        match plane {
            Plane::Yz => (p.y, p.z, p.x),
            Plane::Xz => (p.z, p.x, p.y),
            _ => (p.x, p.y, p.z),
        }
    }

    fn cycle_pose(&self, plane: Plane, aa: f64, bb: f64, cc: f64) -> Pose {
        let (x, y, z) = match plane {
            Plane::Yz => (cc, aa, bb),
            Plane::Xz => (bb, cc, aa),
            _ => (aa, bb, cc),
        };
        Pose {
            x,
            y,
            z,
            ..self.s.current
        }
    }

    fn cycle_feed(
        &mut self,
        canon: &mut dyn Canon,
        line: i32,
        plane: Plane,
        aa: f64,
        bb: f64,
        cc: f64,
    ) {
        let p = self.cycle_pose(plane, aa, bb, cc);
        canon.straight_feed(line, &p);
    }

    fn cycle_traverse(
        &mut self,
        canon: &mut dyn Canon,
        line: i32,
        plane: Plane,
        aa: f64,
        bb: f64,
        cc: f64,
    ) {
        let p = self.cycle_pose(plane, aa, bb, cc);
        canon.straight_traverse(line, &p);
    }

    /// A canned cycle block.
    pub(crate) fn convert_cycle(
        &mut self,
        motion: i32,
        block: &mut Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        if self.s.feed_rate == 0.0 {
            return Err(InterpError::CycleZeroFeed);
        }
        if self.s.feed_mode == FeedMode::InverseTime {
            return Err(InterpError::CycleInverseTime);
        }
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::CycleWithComp);
        }
        if !block.r_flag {
            if self.s.motion_mode == motion {
                block.r_number = self.s.cycle_r;
            } else {
                return Err(InterpError::CycleNoR);
            }
        }
        if block.l_number == 0 {
            return Err(InterpError::CycleZeroRepeats);
        }
        if block.l_number == -1 {
            block.l_number = 1;
        }
        let Some(axes) = plane_axes(self.s.plane) else {
            return Err(InterpError::Unsupported(
                "canned cycles in the UV, UW and VW planes are not supported",
            ));
        };
        for (flag, word) in [
            (block.u_flag, "a U"),
            (block.v_flag, "a V"),
            (block.w_flag, "a W"),
        ] {
            if flag {
                return Err(InterpError::CycleAxisInPlane(word, axes.name));
            }
        }
        self.convert_cycle_plane(motion, block, &axes, canon)?;
        self.s.cycle_l = block.l_number;
        self.s.cycle_r = block.r_number;
        self.s.motion_mode = motion;
        Ok(())
    }

    fn convert_cycle_plane(
        &mut self,
        motion: i32,
        block: &mut Block,
        axes: &PlaneAxes,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let plane = axes.plane;
        let (cc_flag, cc_word) = match plane {
            Plane::Yz => (block.x_flag, block.x_number),
            Plane::Xz => (block.y_flag, block.y_number),
            _ => (block.z_flag, block.z_number),
        };
        if self.s.motion_mode != motion && !cc_flag {
            return Err(InterpError::CycleAxisUnspecified(axes.third, axes.name));
        }
        let cc_number = if cc_flag { cc_word } else { self.s.cycle_cc };
        let (cur_aa, cur_bb, cur_cc) = Self::cycle_coords(plane, &self.s.current);
        let mut old_cc = if self.s.cycle_il_flag {
            self.s.cycle_il
        } else {
            self.s.cycle_il = cur_cc;
            self.s.cycle_il_flag = true;
            cur_cc
        };
        let layout = self.cycle_layout(block, plane, cc_number, old_cc);
        let Layout { r, cc, .. } = layout;
        if r < cc {
            return Err(InterpError::CycleRBelow(axes.third_lower, axes.name));
        }
        let line = block.line_number;
        let mut current_cc = cur_cc;
        if old_cc < r {
            let p = self.cycle_pose(plane, cur_aa, cur_bb, r);
            canon.straight_traverse(line, &p);
            old_cc = r;
            current_cc = r;
        }
        let clear_cc = if self.s.retract_mode == RetractMode::RPlane {
            r
        } else {
            old_cc
        };
        let (save_mode, save_tolerance) = canon.motion_control_mode();
        if save_mode != MotionMode::ExactPath {
            canon.set_motion_control_mode(MotionMode::ExactPath, 0.0);
        }
        let params = self.cycle_parameters(motion, block)?;
        self.check_cycle_size(motion, block.l_number, &layout, &params)?;
        let heights = (current_cc, clear_cc);
        let (aa, bb) = self.cycle_repeats(motion, block, &layout, heights, &params, canon)?;
        let end = self.cycle_pose(plane, aa, bb, clear_cc);
        self.s.current = end;
        self.s.cycle_cc = cc_number;
        if save_mode != MotionMode::ExactPath {
            canon.set_motion_control_mode(save_mode, save_tolerance);
            canon.set_naivecam_tolerance(self.s.naivecam_tolerance);
        }
        Ok(())
    }

    /// Where the holes go: the first position (or the start of the
    /// increments), R, the bottom, and the per-repeat increments, from the
    /// block's words in the distance mode.
    fn cycle_layout(&self, block: &Block, plane: Plane, cc_number: f64, old_cc: f64) -> Layout {
        let (cur_aa, cur_bb, _) = Self::cycle_coords(plane, &self.s.current);
        let (aa_flag, aa_word, bb_flag, bb_word) = match plane {
            Plane::Yz => (block.y_flag, block.y_number, block.z_flag, block.z_number),
            Plane::Xz => (block.z_flag, block.z_number, block.x_flag, block.x_number),
            _ => (block.x_flag, block.x_number, block.y_flag, block.y_number),
        };
        if self.s.distance_mode == DistanceMode::Absolute {
            let (aa, bb) = if block.radius_flag || block.theta_flag {
                // Polar words are for G17 only (checked earlier).
                let radius = if block.radius_flag {
                    block.radius
                } else {
                    cur_bb.hypot(cur_aa)
                };
                let theta = if block.theta_flag {
                    d2r(block.theta)
                } else {
                    cur_bb.atan2(cur_aa)
                };
                (radius * theta.cos(), radius * theta.sin())
            } else {
                (
                    if aa_flag { aa_word } else { cur_aa },
                    if bb_flag { bb_word } else { cur_bb },
                )
            };
            return Layout {
                aa,
                bb,
                r: block.r_number,
                cc: cc_number,
                ..Layout::default()
            };
        }
        let r = block.r_number + old_cc;
        Layout {
            aa: cur_aa,
            bb: cur_bb,
            r,
            cc: r + cc_number,
            aa_inc: if aa_flag { aa_word } else { 0.0 },
            bb_inc: if bb_flag { bb_word } else { 0.0 },
            radius_inc: if block.radius_flag { block.radius } else { 0.0 },
            theta_inc: if block.theta_flag {
                d2r(block.theta)
            } else {
                0.0
            },
        }
    }

    /// The L repeats: move to each hole and run the cycle there; the last
    /// hole's position. `heights` are the tool's height at the start and
    /// the clearance height.
    fn cycle_repeats(
        &mut self,
        motion: i32,
        block: &Block,
        layout: &Layout,
        heights: (f64, f64),
        params: &CycleParams,
        canon: &mut dyn Canon,
    ) -> Result<(f64, f64)> {
        let (current_cc, clear_cc) = heights;
        let Layout {
            mut aa,
            mut bb,
            r,
            cc,
            ..
        } = *layout;
        let plane = self.s.plane;
        let line = block.line_number;
        for repeat in (1..=block.l_number).rev() {
            aa += layout.aa_inc;
            bb += layout.bb_inc;
            if layout.radius_inc != 0.0 || layout.theta_inc != 0.0 {
                (aa, bb) = polar_step(aa, bb, layout.radius_inc, layout.theta_inc)?;
            }
            // The first hole is reached at the height the tool is at (if
            // above R), the others at the clearance height.
            if repeat == block.l_number && current_cc > r {
                self.cycle_traverse(canon, line, plane, aa, bb, current_cc);
                self.cycle_traverse(canon, line, plane, aa, bb, r);
            } else {
                self.cycle_traverse(canon, line, plane, aa, bb, clear_cc);
                if clear_cc > r {
                    self.cycle_traverse(canon, line, plane, aa, bb, r);
                }
            }
            let hole = Hole {
                plane,
                aa,
                bb,
                r,
                clear: clear_cc,
                bottom: cc,
            };
            self.cycle_body(motion, &hole, params, line, canon)?;
        }
        Ok((aa, bb))
    }

    /// Refuses a block whose holes and pecks add up to more moves than
    /// [`crate::Config::max_cycle_moves`] allows, before it drills one hole.
    fn check_cycle_size(
        &self,
        motion: i32,
        holes: i32,
        layout: &Layout,
        params: &CycleParams,
    ) -> Result<()> {
        let moves = cycle_move_count(motion, holes, layout.r, layout.cc, params.delta);
        let limit = self.config.max_cycle_moves;
        if moves > f64::from(limit) {
            return Err(InterpError::CycleTooLong {
                code: motion / 10,
                moves,
                limit,
            });
        }
        Ok(())
    }

    /// P, Q, I/J/K words a cycle needs, taken from the block or kept
    /// from the previous block of the same cycle.
    fn cycle_parameters(&mut self, motion: i32, block: &mut Block) -> Result<CycleParams> {
        let same = self.s.motion_mode == motion;
        let mut params = CycleParams::default();
        match motion {
            G_82 | G_86 | G_88 | G_89 => {
                if !same && block.p_number == -1.0 {
                    return Err(InterpError::CycleDwellMissing(motion / 10));
                }
                if block.p_number == -1.0 {
                    block.p_number = self.s.cycle_p;
                }
                self.s.cycle_p = block.p_number;
                params.dwell = block.p_number;
            }
            G_74 | G_84 => {
                if block.p_number == -1.0 {
                    block.p_number = self.s.cycle_p;
                }
                self.s.cycle_p = block.p_number;
                params.dwell = block.p_number;
            }
            G_73 | G_83 => {
                if !same && block.q_number == -1.0 {
                    return Err(InterpError::CycleQMissing(motion / 10));
                }
                if block.q_number == -1.0 {
                    block.q_number = self.s.cycle_q;
                }
                self.s.cycle_q = block.q_number;
                params.delta = block.q_number;
            }
            G_87 => {
                if !same {
                    for (flag, letter) in [
                        (block.i_flag, 'I'),
                        (block.j_flag, 'J'),
                        (block.k_flag, 'K'),
                    ] {
                        if !flag {
                            return Err(InterpError::G87WordMissing(letter));
                        }
                    }
                }
                let i = if block.i_flag {
                    block.i_number
                } else {
                    self.s.cycle_i
                };
                let j = if block.j_flag {
                    block.j_number
                } else {
                    self.s.cycle_j
                };
                let k = if block.k_flag {
                    block.k_number
                } else {
                    self.s.cycle_k
                };
                (self.s.cycle_i, self.s.cycle_j, self.s.cycle_k) = (i, j, k);
                params.offset = (i, j);
                params.middle = k;
                params.middle_incremental = self.s.distance_mode == DistanceMode::Incremental;
            }
            _ => {}
        }
        Ok(params)
    }

    fn cycle_body(
        &mut self,
        motion: i32,
        h: &Hole,
        p: &CycleParams,
        line: i32,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let Hole {
            plane,
            aa,
            bb,
            r,
            clear,
            bottom,
        } = *h;
        match motion {
            G_81 => {
                self.cycle_feed(canon, line, plane, aa, bb, bottom);
                self.cycle_traverse(canon, line, plane, aa, bb, clear);
            }
            G_82 => {
                self.cycle_feed(canon, line, plane, aa, bb, bottom);
                canon.dwell(p.dwell);
                self.cycle_traverse(canon, line, plane, aa, bb, clear);
            }
            G_73 | G_83 => self.peck(motion, h, p.delta, line, canon)?,
            G_74 | G_84 => self.tap(motion, h, p.dwell, line, canon)?,
            G_85 => {
                self.cycle_feed(canon, line, plane, aa, bb, bottom);
                self.cycle_feed(canon, line, plane, aa, bb, r);
                self.cycle_traverse(canon, line, plane, aa, bb, clear);
            }
            G_86 => {
                let dir = self.spindle_turning_for(86)?;
                self.cycle_feed(canon, line, plane, aa, bb, bottom);
                canon.dwell(p.dwell);
                canon.stop_spindle_turning(0);
                self.cycle_traverse(canon, line, plane, aa, bb, clear);
                start_spindle(canon, dir);
            }
            G_87 => {
                let dir = self.spindle_turning_for(87)?;
                let (oa, ob) = (aa + p.offset.0, bb + p.offset.1);
                let middle = if p.middle_incremental {
                    bottom + p.middle
                } else {
                    p.middle
                };
                self.cycle_traverse(canon, line, plane, oa, ob, r);
                canon.stop_spindle_turning(0);
                canon.orient_spindle(0, 0.0, canon_direction(dir));
                self.cycle_traverse(canon, line, plane, oa, ob, bottom);
                self.cycle_traverse(canon, line, plane, aa, bb, bottom);
                start_spindle(canon, dir);
                self.cycle_feed(canon, line, plane, aa, bb, middle);
                self.cycle_feed(canon, line, plane, aa, bb, bottom);
                canon.stop_spindle_turning(0);
                canon.orient_spindle(0, 0.0, canon_direction(dir));
                self.cycle_traverse(canon, line, plane, oa, ob, bottom);
                self.cycle_traverse(canon, line, plane, oa, ob, clear);
                self.cycle_traverse(canon, line, plane, aa, bb, clear);
                start_spindle(canon, dir);
            }
            G_88 => {
                let dir = self.spindle_turning_for(88)?;
                self.cycle_feed(canon, line, plane, aa, bb, bottom);
                canon.dwell(p.dwell);
                canon.stop_spindle_turning(0);
                canon.program_stop();
                start_spindle(canon, dir);
            }
            _ => {
                self.cycle_feed(canon, line, plane, aa, bb, bottom);
                canon.dwell(p.dwell);
                self.cycle_feed(canon, line, plane, aa, bb, clear);
            }
        }
        Ok(())
    }

    /// G73 (chip breaking) and G83 (full retract) peck drilling.
    fn peck(
        &mut self,
        motion: i32,
        h: &Hole,
        delta: f64,
        line: i32,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        if delta <= 0.0 {
            return Err(InterpError::CycleQNotPositive);
        }
        let rapid_delta = if self.s.length_units == Units::Mm {
            G83_RAPID_DELTA * 25.4
        } else {
            G83_RAPID_DELTA
        };
        let Hole {
            plane,
            aa,
            bb,
            r,
            clear,
            bottom,
        } = *h;
        let mut depth = r - delta;
        while depth > bottom {
            self.cycle_feed(canon, line, plane, aa, bb, depth);
            if motion == G_83 {
                self.cycle_traverse(canon, line, plane, aa, bb, r);
            }
            self.cycle_traverse(canon, line, plane, aa, bb, depth + rapid_delta);
            depth -= delta;
        }
        self.cycle_feed(canon, line, plane, aa, bb, bottom);
        self.cycle_traverse(canon, line, plane, aa, bb, clear);
        Ok(())
    }

    /// G74 (left hand) and G84 (right hand) tapping: feed in, reverse
    /// the spindle, feed out, restore it.
    fn tap(
        &mut self,
        motion: i32,
        h: &Hole,
        dwell: f64,
        line: i32,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let turning = self.s.spindles[0].turning;
        if motion == G_84 && turning == Direction::CounterClockwise {
            return Err(InterpError::G84CounterClockwise);
        }
        if motion == G_74 && turning == Direction::Clockwise {
            return Err(InterpError::G74Clockwise);
        }
        if turning == Direction::Stopped {
            return Err(InterpError::TapSpindleNotTurning(motion / 10));
        }
        let Hole {
            plane,
            aa,
            bb,
            clear,
            bottom,
            ..
        } = *h;
        canon.disable_feed_override();
        canon.disable_speed_override(0);
        self.cycle_feed(canon, line, plane, aa, bb, bottom);
        canon.stop_spindle_turning(0);
        start_spindle(canon, reverse(turning));
        canon.dwell(dwell);
        self.cycle_feed(canon, line, plane, aa, bb, clear);
        canon.stop_spindle_turning(0);
        start_spindle(canon, turning);
        canon.enable_feed_override();
        canon.enable_speed_override(0);
        Ok(())
    }

    fn spindle_turning_for(&self, cycle: i32) -> Result<Direction> {
        match self.s.spindles[0].turning {
            Direction::Stopped => Err(InterpError::CycleSpindleNotTurning(cycle)),
            d => Ok(d),
        }
    }
}

/// The holes of one cycle block, in the plane's coordinates.
#[derive(Debug, Clone, Copy, Default)]
struct Layout {
    aa: f64,
    bb: f64,
    r: f64,
    cc: f64,
    aa_inc: f64,
    bb_inc: f64,
    radius_inc: f64,
    theta_inc: f64,
}

/// About how many moves a cycle block makes: per hole, the traverses to
/// it and back plus, for the peck cycles (G73, G83), two or three moves a
/// peck. A peck too small to change the depth at the hole's size would
/// never reach the bottom, so it counts as endless.
fn cycle_move_count(motion: i32, holes: i32, r: f64, bottom: f64, delta: f64) -> f64 {
    let per_hole = match motion {
        G_73 | G_83 if delta > 0.0 => {
            let size = r.abs().max(bottom.abs());
            if delta <= size * 4.0 * f64::EPSILON {
                return f64::INFINITY;
            }
            let pecks = ((r - bottom) / delta).ceil().max(0.0);
            let per_peck = if motion == G_83 { 3.0 } else { 2.0 };
            pecks * per_peck + 4.0
        }
        _ => 8.0,
    };
    f64::from(holes.max(0)) * per_hole
}

/// One repeat's polar increments: the radius grows by `radius_inc`,
/// then the angle by `theta_inc` (radians), about the origin.
fn polar_step(aa: f64, bb: f64, radius_inc: f64, theta_inc: f64) -> Result<(f64, f64)> {
    let (mut aa, mut bb) = (aa, bb);
    if radius_inc != 0.0 {
        if aa == 0.0 && bb == 0.0 {
            return Err(InterpError::PolarIncrementalAtOrigin);
        }
        let theta = bb.atan2(aa);
        let radius = bb.hypot(aa) + radius_inc;
        (aa, bb) = (radius * theta.cos(), radius * theta.sin());
    }
    if theta_inc != 0.0 {
        if aa == 0.0 && bb == 0.0 {
            return Err(InterpError::PolarIncrementalAtOrigin);
        }
        let theta = bb.atan2(aa) + theta_inc;
        let radius = bb.hypot(aa);
        (aa, bb) = (radius * theta.cos(), radius * theta.sin());
    }
    Ok((aa, bb))
}

/// LinuxCNC's CANON_DIRECTION number (stopped 1, clockwise 2,
/// counterclockwise 3), which ORIENT_SPINDLE prints in G87.
fn canon_direction(d: Direction) -> i32 {
    match d {
        Direction::Stopped => 1,
        Direction::Clockwise => 2,
        Direction::CounterClockwise => 3,
    }
}

fn reverse(d: Direction) -> Direction {
    match d {
        Direction::Clockwise => Direction::CounterClockwise,
        Direction::CounterClockwise => Direction::Clockwise,
        Direction::Stopped => Direction::Stopped,
    }
}

fn start_spindle(canon: &mut dyn Canon, d: Direction) {
    match d {
        Direction::Clockwise => canon.start_spindle_clockwise(0),
        Direction::CounterClockwise => canon.start_spindle_counterclockwise(0),
        Direction::Stopped => canon.stop_spindle_turning(0),
    }
}

/// Where one hole of a cycle is, in the plane's coordinates.
#[derive(Debug, Clone, Copy)]
struct Hole {
    plane: Plane,
    aa: f64,
    bb: f64,
    r: f64,
    clear: f64,
    bottom: f64,
}

/// The cycle-specific words.
#[derive(Debug, Clone, Copy, Default)]
struct CycleParams {
    dwell: f64,
    delta: f64,
    offset: (f64, f64),
    middle: f64,
    middle_incremental: bool,
}
