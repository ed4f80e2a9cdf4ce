//! Motion: G0/G1 lines, G2/G3 arcs and helices, G38.x probing, G5.x
//! splines, and the entries of the canned, threading and lathe cycles.

use crate::block::Block;
use crate::canon::{Arc, Canon, ControlPoint, Plane, Pose};
use crate::codes::*;
use crate::comp::Queued;
use crate::error::{InterpError, Result};
use crate::find::{find_arc_length, find_straight_length};
use crate::interp::Interp;
use crate::setup::{DistanceMode, FeedMode, Side};

impl Interp {
    pub(crate) fn convert_motion(
        &mut self,
        motion: i32,
        block: &mut Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        if !is_cycle(motion) {
            self.s.cycle_il_flag = false;
        }
        match motion {
            G_0 | G_1 => self.convert_straight(motion, block, canon),
            G_33 => self.convert_synched_straight(block, canon),
            G_33_1 => self.convert_rigid_tap(block, canon),
            G_76 => self.convert_threading_cycle(block, canon),
            G_70 | G_71 | G_71_1 | G_71_2 | G_72 | G_72_1 | G_72_2 => {
                self.convert_g7x(block, canon)
            }
            G_2 | G_3 => self.convert_arc(motion, block, canon),
            G_38_2 | G_38_3 | G_38_4 | G_38_5 => self.convert_probe(motion, block, canon),
            G_80 => {
                self.enqueue(
                    canon,
                    Queued::Comment("interpreter: motion mode set to none".into()),
                );
                self.s.motion_mode = G_80;
                Ok(())
            }
            G_5 | G_5_1 => self.convert_spline(motion, block, canon),
            G_5_2 => self.convert_nurbs(block),
            _ => self.convert_cycle(motion, block, canon),
        }
    }

    /// Inverse time: the feed rate that makes a move last 1/F minutes.
    pub(crate) fn inverse_time_rate_straight(
        &mut self,
        canon: &mut dyn Canon,
        block: &Block,
        end: &Pose,
    ) {
        if self.s.feed_mode != FeedMode::InverseTime {
            return;
        }
        // With cutter compensation the programmed (uncompensated) path
        // sets the time, as in LinuxCNC.
        let comp = self.s.cutter_comp_side != Side::Off && self.s.cutter_comp_radius > 0.0;
        let start = if comp && !self.s.cutter_comp_firstmove {
            Pose {
                x: self.s.program_x,
                y: self.s.program_y,
                z: self.s.program_z,
                ..self.s.current
            }
        } else {
            self.s.current
        };
        let length = find_straight_length(end, &start);
        let rate = (length * block.f_number).max(0.1);
        self.enqueue(canon, Queued::SetFeedRate(rate));
        self.s.feed_rate = rate;
    }

    pub(crate) fn inverse_time_rate_arc(
        &mut self,
        canon: &mut dyn Canon,
        block: &Block,
        start: (f64, f64, f64),
        center: (f64, f64),
        turn: i32,
        end: (f64, f64, f64),
    ) {
        if self.s.feed_mode != FeedMode::InverseTime {
            return;
        }
        let length = find_arc_length(
            start.0, start.1, start.2, center.0, center.1, turn, end.0, end.1, end.2,
        );
        let rate = (length * block.f_number).max(0.1);
        self.enqueue(canon, Queued::SetFeedRate(rate));
        self.s.feed_rate = rate;
    }

    pub(crate) fn convert_straight(
        &mut self,
        mv: i32,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        self.s.arc_not_allowed = false;
        if mv == G_1 {
            match self.s.feed_mode {
                FeedMode::UnitsPerMinute => {
                    if self.s.feed_rate == 0.0 {
                        return Err(InterpError::G1ZeroFeed);
                    }
                }
                FeedMode::UnitsPerRevolution => {
                    if self.s.feed_rate == 0.0 {
                        return Err(InterpError::G1ZeroFeed);
                    }
                    if self.s.spindles[self.s.feed_spindle].speed == 0.0 {
                        return Err(InterpError::ZeroSpeedFeedPerRev);
                    }
                }
                FeedMode::InverseTime => {
                    if !block.f_flag {
                        return Err(InterpError::FMissingInverseG1);
                    }
                }
            }
        }
        self.s.motion_mode = mv;
        let end = self.find_ends(block)?;
        if mv == G_1 {
            self.inverse_time_rate_straight(canon, block, &end);
        }
        if self.s.cutter_comp_side != Side::Off && self.s.cutter_comp_radius > 0.0 {
            self.straight_with_comp(mv, block, canon, &end)
        } else {
            if mv == G_0 {
                canon.straight_traverse(block.line_number, &end);
            } else {
                canon.straight_feed(block.line_number, &end);
            }
            self.s.current = end;
            Ok(())
        }
    }

    /// A G0 or G1 (`mv`) to `end` through cutter radius compensation.
    pub(crate) fn straight_with_comp(
        &mut self,
        mv: i32,
        block: &Block,
        canon: &mut dyn Canon,
        end: &Pose,
    ) -> Result<()> {
        if block.g_modes[GM_MODAL_0] == G_53 {
            return Err(InterpError::G53WithComp);
        }
        let p = match self.s.plane {
            Plane::Xz => (end.z, end.x, end.y),
            Plane::Xy => (end.x, end.y, end.z),
            _ => return Err(InterpError::CompPlane),
        };
        if self.s.cutter_comp_firstmove {
            self.straight_comp1(canon, mv, block.line_number, p, end)
        } else {
            self.straight_comp2(canon, mv, block.line_number, p, end)
        }
    }

    pub(crate) fn convert_arc(
        &mut self,
        mv: i32,
        block: &mut Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        if self.s.arc_not_allowed {
            return Err(InterpError::ArcAfterCompOff);
        }
        let ijk = block.i_flag || block.j_flag || block.k_flag;
        let first = self.s.cutter_comp_firstmove;
        if matches!(self.s.plane, Plane::Uv | Plane::Vw | Plane::Uw) {
            return Err(InterpError::ArcInUvwPlane);
        }
        if !block.r_flag && !ijk {
            return Err(InterpError::ArcNoRijk);
        }
        if block.r_flag && ijk {
            return Err(InterpError::ArcMixedFormat);
        }
        self.check_arc_feed(block.f_flag)?;
        let absolute = self.s.ijk_distance_mode == DistanceMode::Absolute;
        if ijk {
            let (given, missing_a, missing_b, a_flag, b_flag) = match self.s.plane {
                Plane::Xy => (
                    block.k_flag.then_some(InterpError::ArcKInXy),
                    'I',
                    'J',
                    block.i_flag,
                    block.j_flag,
                ),
                Plane::Yz => (
                    block.i_flag.then_some(InterpError::ArcIInYz),
                    'J',
                    'K',
                    block.j_flag,
                    block.k_flag,
                ),
                _ => (
                    block.j_flag.then_some(InterpError::ArcJInXz),
                    'I',
                    'K',
                    block.i_flag,
                    block.k_flag,
                ),
            };
            if let Some(e) = given {
                return Err(e);
            }
            if !a_flag || !b_flag {
                let missing = if !a_flag { missing_a } else { missing_b };
                if absolute {
                    return Err(InterpError::ArcAbsoluteCenterMissing(missing));
                }
                match missing {
                    'I' => block.i_number = 0.0,
                    'J' => block.j_number = 0.0,
                    _ => block.k_number = 0.0,
                }
            }
        } else {
            match self.s.plane {
                Plane::Xy => {
                    if !block.x_flag && !block.y_flag && !block.radius_flag && !block.theta_flag {
                        return Err(InterpError::ArcXyMissing);
                    }
                }
                Plane::Yz => {
                    if !block.y_flag && !block.z_flag {
                        return Err(InterpError::ArcYzMissing);
                    }
                }
                _ => {
                    if !block.x_flag && !block.z_flag {
                        return Err(InterpError::ArcXzMissing);
                    }
                }
            }
        }
        let end = self.find_ends(block)?;
        self.s.motion_mode = mv;
        let comp = self.s.cutter_comp_side != Side::Off && self.s.cutter_comp_radius != 0.0;
        match self.s.plane {
            Plane::Xy | Plane::Xz if comp => {
                let (e, offset) = if self.s.plane == Plane::Xy {
                    ((end.x, end.y, end.z), (block.i_number, block.j_number))
                } else {
                    ((end.z, end.x, end.y), (block.k_number, block.i_number))
                };
                if first {
                    self.arc_comp1(canon, block, mv, e, offset, &end)
                } else {
                    self.arc_comp2(canon, block, mv, e, offset, &end)
                }
            }
            _ => self.convert_arc2(mv, block, canon, &end),
        }
    }

    /// An arc without compensation in any of the three planes.
    fn convert_arc2(
        &mut self,
        mv: i32,
        block: &Block,
        canon: &mut dyn Canon,
        end: &Pose,
    ) -> Result<()> {
        let c = self.s.current;
        let (cur, e, offset) = match self.s.plane {
            Plane::Xy => (
                (c.x, c.y, c.z),
                (end.x, end.y, end.z),
                (block.i_number, block.j_number),
            ),
            Plane::Xz => (
                (c.z, c.x, c.y),
                (end.z, end.x, end.y),
                (block.k_number, block.i_number),
            ),
            _ => (
                (c.y, c.z, c.x),
                (end.y, end.z, end.x),
                (block.j_number, block.k_number),
            ),
        };
        let (center, turn) = self.arc_data(block, mv, (cur.0, cur.1), (e.0, e.1), offset)?;
        self.inverse_time_rate_arc(canon, block, cur, center, turn, e);
        let arc = Arc {
            first_end: e.0,
            second_end: e.1,
            first_axis: center.0,
            second_axis: center.1,
            rotation: turn,
            axis_end_point: e.2,
            rest: *end,
        };
        canon.arc_feed(block.line_number, &arc);
        self.s.current = *end;
        Ok(())
    }

    fn convert_probe(&mut self, code: i32, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        let probe_type = (code - G_38_2) as u8;
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::ProbeWithComp);
        }
        if self.s.feed_rate == 0.0 {
            return Err(InterpError::ProbeZeroFeed);
        }
        if self.s.feed_mode == FeedMode::UnitsPerRevolution {
            return Err(InterpError::ProbeFeedPerRev);
        }
        let end = self.find_ends(block)?;
        if probe_type & 1 == 0 && self.s.current == end {
            return Err(InterpError::ProbeTooClose);
        }
        canon.turn_probe_on();
        canon.straight_probe(block.line_number, &end, probe_type);
        canon.turn_probe_off();
        self.s.motion_mode = code;
        self.s.probe_flag = true;
        Ok(())
    }

    /// G5 (cubic) and G5.1 (quadratic) splines, as NURBS feeds.
    fn convert_spline(&mut self, mv: i32, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::SplineWithComp);
        }
        match self.s.feed_mode {
            FeedMode::UnitsPerMinute if self.s.feed_rate == 0.0 => {
                return Err(InterpError::ArcZeroFeed)
            }
            FeedMode::InverseTime if !block.f_flag => return Err(InterpError::FMissingInverseArc),
            _ => {}
        }
        if self.s.plane != Plane::Xy {
            return Err(InterpError::SplinePlane);
        }
        if block.z_flag || block.a_flag || block.b_flag || block.c_flag {
            return Err(InterpError::SplineAxes);
        }
        let (cx, cy) = (self.s.current.x, self.s.current.y);
        let point = |x, y| ControlPoint { x, y, weight: 1.0 };
        let mut points = vec![point(cx, cy)];
        let order;
        let end;
        if mv == G_5_1 {
            if !block.i_flag || !block.j_flag {
                return Err(InterpError::SplineIjG51);
            }
            end = self.find_ends(block)?;
            points.push(point(cx + block.i_number, cy + block.j_number));
            order = 3;
        } else {
            let (x1, y1) = if !block.i_flag || !block.j_flag {
                if block.i_flag || block.j_flag {
                    return Err(InterpError::SplineIj);
                }
                (cx + self.s.cycle_i, cy + self.s.cycle_j)
            } else {
                (cx + block.i_number, cy + block.j_number)
            };
            end = self.find_ends(block)?;
            if !block.p_flag || !block.q_flag {
                return Err(InterpError::SplinePq);
            }
            points.push(point(x1, y1));
            points.push(point(end.x + block.p_number, end.y + block.q_number));
            self.s.cycle_i = -block.p_number;
            self.s.cycle_j = -block.q_number;
            order = 4;
        }
        points.push(point(end.x, end.y));
        canon.nurbs_feed(block.line_number, &points, order);
        self.s.current.x = end.x;
        self.s.current.y = end.y;
        Ok(())
    }

    /// G5.2: collect NURBS control points.
    fn convert_nurbs(&mut self, block: &Block) -> Result<()> {
        if block.x_flag != block.y_flag {
            return Err(InterpError::NurbsXy);
        }
        let collecting = self.s.motion_mode == G_5_2 && !self.s.nurbs_points.is_empty();
        if !block.x_flag && block.p_number > 0.0 && collecting {
            return Err(InterpError::NurbsPOnlyFirst);
        }
        if block.p_number <= 0.0 && collecting {
            return Err(InterpError::NurbsWeight);
        }
        if self.s.feed_mode == FeedMode::UnitsPerMinute && self.s.feed_rate == 0.0 {
            return Err(InterpError::NurbsZeroFeed);
        }
        if self.s.motion_mode != G_5_2 {
            self.s.nurbs_points.clear();
        }
        if self.s.nurbs_points.is_empty() {
            let weight = if !block.x_flag && block.p_number > 0.0 {
                block.p_number
            } else {
                1.0
            };
            self.s.nurbs_points.push(ControlPoint {
                x: self.s.current.x,
                y: self.s.current.y,
                weight,
            });
            self.s.nurbs_order = 3;
        }
        if block.l_number != -1 && block.l_number > 3 {
            self.s.nurbs_order = block.l_number as u32;
        }
        if block.x_flag && block.y_flag {
            let end = self.find_ends(block)?;
            self.s.nurbs_points.push(ControlPoint {
                x: end.x,
                y: end.y,
                weight: block.p_number,
            });
        }
        self.s.motion_mode = G_5_2;
        Ok(())
    }

    /// G5.3: end the NURBS and feed along it.
    pub(crate) fn convert_nurbs_end(&mut self, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        if self.s.motion_mode != G_5_2 {
            return Err(InterpError::NurbsEndWithoutStart);
        }
        let order = self.s.nurbs_order;
        if (self.s.nurbs_points.len() as u32) < order {
            return Err(InterpError::NurbsTooFewPoints(order));
        }
        if let Some(last) = self.s.nurbs_points.last() {
            self.s.current.x = last.x;
            self.s.current.y = last.y;
        }
        let points = std::mem::take(&mut self.s.nurbs_points);
        canon.nurbs_feed(block.line_number, &points, order);
        self.s.motion_mode = -1;
        Ok(())
    }
}
