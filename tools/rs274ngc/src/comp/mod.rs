//! Cutter radius compensation (G41/G42, G41.1/G42.1) in the XY and XZ
//! planes: entry moves, convex corners closed with arcs, concave corners
//! found by clipping the held move, and the gouge refusals.
//!
//! The code thinks in the comp plane's (first, second, third)
//! coordinates: (X, Y, Z) in G17, (Z, X, Y) in G18.

mod queue;

pub(crate) use queue::{emit, CompGeometry, CompQueue, Queued};

use crate::block::{round_to_int, Block};
use crate::canon::{Canon, Plane, Pose};
use crate::codes::{G_0, G_1, G_2, G_3};
use crate::error::{InterpError, Result};
use crate::find::find_turn;
use crate::interp::Interp;
use crate::ld::{add_half_pis, scaled_sin_less_half_pi, sum_with_pi};
use crate::setup::{DistanceMode, Side};

/// Corners sharper than this (radians) count as concave.
const SMALL: f64 = 0.05;
/// Two numbers closer than this are equal.
const TOLERANCE_EQUAL: f64 = 0.0001;
const PI: f64 = std::f64::consts::PI;
const FRAC_PI_2: f64 = std::f64::consts::FRAC_PI_2;

fn tool_inside_arc(side: Side, turn: i32) -> bool {
    (side == Side::Left && turn > 0) || (side == Side::Right && turn < 0)
}

impl Interp {
    pub(crate) fn comp_geometry(&self) -> CompGeometry {
        CompGeometry {
            plane: self.s.plane,
            orientation: self.s.cutter_comp_orientation,
            radius: self.s.cutter_comp_radius,
            arc_slack: if self.s.length_units == crate::canon::Units::Mm {
                0.0254
            } else {
                0.001
            },
        }
    }

    /// Issue or hold back a non-motion canonical call.
    pub(crate) fn enqueue(&mut self, canon: &mut dyn Canon, q: Queued) {
        let g = self.comp_geometry();
        emit(&mut self.comp, g, canon, q);
    }

    pub(crate) fn dequeue_canons(&mut self, canon: &mut dyn Canon) {
        let g = self.comp_geometry();
        self.comp.dequeue(g, canon);
    }

    pub(crate) fn move_endpoint_and_flush(
        &mut self,
        canon: &mut dyn Canon,
        x: f64,
        y: f64,
    ) -> Result<()> {
        let g = self.comp_geometry();
        self.comp.move_endpoint_and_flush(g, x, y, canon)
    }

    /// (first, second, third) of the current point in the comp plane.
    pub(crate) fn comp_get_current(&self) -> (f64, f64, f64) {
        let c = &self.s.current;
        match self.s.plane {
            Plane::Xz => (c.z, c.x, c.y),
            _ => (c.x, c.y, c.z),
        }
    }

    fn comp_set_current(&mut self, x: f64, y: f64, z: f64) {
        let c = &mut self.s.current;
        match self.s.plane {
            Plane::Xz => (c.x, c.y, c.z) = (y, z, x),
            _ => (c.x, c.y, c.z) = (x, y, z),
        }
    }

    fn comp_get_programmed(&self) -> (f64, f64, f64) {
        let s = &self.s;
        match s.plane {
            Plane::Xz => (s.program_z, s.program_x, s.program_y),
            _ => (s.program_x, s.program_y, s.program_z),
        }
    }

    fn comp_set_programmed(&mut self, x: f64, y: f64, z: f64) {
        let s = &mut self.s;
        match s.plane {
            Plane::Xz => (s.program_x, s.program_y, s.program_z) = (y, z, x),
            _ => (s.program_x, s.program_y, s.program_z) = (x, y, z),
        }
    }

    /// A pose from comp-plane coordinates and the other axes of `rest`.
    fn plane_pose(&self, first: f64, second: f64, third: f64, rest: &Pose) -> Pose {
        let (x, y, z) = match self.s.plane {
            Plane::Xz => (second, third, first),
            _ => (first, second, third),
        };
        Pose { x, y, z, ..*rest }
    }

    #[allow(clippy::too_many_arguments)]
    fn enqueue_straight(
        &mut self,
        feed: bool,
        line: i32,
        d1: f64,
        d2: f64,
        x: f64,
        y: f64,
        z: f64,
        rest: &Pose,
    ) {
        let end = self.plane_pose(x, y, z, rest);
        self.comp.push(Queued::Straight {
            feed,
            line,
            dir: (d1, d2),
            end,
        });
    }

    #[allow(clippy::too_many_arguments)]
    fn enqueue_arc(
        &mut self,
        line: i32,
        original_turns: f64,
        end: (f64, f64),
        center: (f64, f64),
        turn: i32,
        end3: f64,
        rest: &Pose,
    ) {
        self.comp.push(Queued::ArcFeed {
            line,
            original_turns,
            end1: end.0,
            end2: end.1,
            center1: center.0,
            center2: center.1,
            turn,
            end3,
            rest: *rest,
        });
    }

    /// G40: flush the held moves and stop compensating.
    pub(crate) fn comp_off(&mut self, canon: &mut dyn Canon) -> Result<()> {
        self.enqueue(
            canon,
            Queued::Comment("interpreter: cutter radius compensation off".into()),
        );
        if self.s.cutter_comp_side != Side::Off
            && self.s.cutter_comp_radius > 0.0
            && !self.s.cutter_comp_firstmove
        {
            let (cx, cy, _) = self.comp_get_current();
            self.move_endpoint_and_flush(canon, cx, cy)?;
            self.dequeue_canons(canon);
            self.s.current.x = self.s.program_x;
            self.s.current.y = self.s.program_y;
            self.s.current.z = self.s.program_z;
            self.s.arc_not_allowed = true;
        }
        self.s.cutter_comp_side = Side::Off;
        self.s.cutter_comp_firstmove = true;
        Ok(())
    }

    /// The first straight move after compensation starts.
    pub(crate) fn straight_comp1(
        &mut self,
        canon: &mut dyn Canon,
        mv: i32,
        line: i32,
        p: (f64, f64, f64),
        rest: &Pose,
    ) -> Result<()> {
        let _ = canon;
        let radius = self.s.cutter_comp_radius;
        let side = self.s.cutter_comp_side;
        let (cx, cy, _) = self.comp_get_current();
        let (px, py, pz) = p;
        let distance = (px - cx).hypot(py - cy);
        if distance <= radius {
            return Err(InterpError::CompEntryTooShort);
        }
        if mv != G_0 && mv != G_1 {
            return Err(InterpError::CompMoveNotG0G1);
        }
        let alpha = add_half_pis(
            (py - cy).atan2(px - cx),
            if side == Side::Left { 1 } else { -1 },
        );
        let end_x = px + radius * alpha.cos();
        let end_y = py + radius * alpha.sin();
        self.comp.set_endpoint(cx, cy);
        self.enqueue_straight(
            mv == G_1,
            line,
            alpha.cos(),
            alpha.sin(),
            end_x,
            end_y,
            pz,
            rest,
        );
        self.s.cutter_comp_firstmove = false;
        self.comp_set_current(end_x, end_y, pz);
        self.set_rest(rest);
        self.comp_set_programmed(px, py, pz);
        Ok(())
    }

    fn set_rest(&mut self, rest: &Pose) {
        let c = &mut self.s.current;
        (c.a, c.b, c.c, c.u, c.v, c.w) = (rest.a, rest.b, rest.c, rest.u, rest.v, rest.w);
    }

    /// A straight move while compensating (not the first).
    pub(crate) fn straight_comp2(
        &mut self,
        canon: &mut dyn Canon,
        mv: i32,
        line: i32,
        p: (f64, f64, f64),
        rest: &Pose,
    ) -> Result<()> {
        let (cx, cy, cz) = self.comp_get_current();
        let (mut end_x, mut end_y) = (cx, cy);
        let (opx, opy, opz) = self.comp_get_programmed();
        let (px, py, pz) = p;
        // G33 and G33.1 are queued as feeds, except along the tool axis.
        let feed = mv != G_0;
        if py == opy && px == opx {
            if mv != G_0 && mv != G_1 {
                return Err(InterpError::CompMoveNotG0G1);
            }
            self.enqueue_straight(feed, line, px - opx, py - opy, cx, cy, pz, rest);
            let _ = opz;
        } else {
            let side = self.s.cutter_comp_side;
            let radius = self.s.cutter_comp_radius;
            let mut theta = (cy - opy).atan2(cx - opx);
            let mut alpha = (py - opy).atan2(px - opx);
            let (beta, gamma) = if side == Side::Left {
                if theta < alpha {
                    theta = add_half_pis(theta, 4);
                }
                (add_half_pis(theta - alpha, -1), FRAC_PI_2)
            } else {
                if alpha < theta {
                    alpha = add_half_pis(alpha, 4);
                }
                (add_half_pis(alpha - theta, -1), -FRAC_PI_2)
            };
            end_x = px + radius * (alpha + gamma).cos();
            end_y = py + radius * (alpha + gamma).sin();
            let mid_x = opx + radius * (alpha + gamma).cos();
            let mid_y = opy + radius * (alpha + gamma).sin();
            let front_arc_turn = match self.comp.front() {
                Some(Queued::ArcFeed { turn, .. }) => Some(*turn),
                _ => None,
            };
            let concave = if !(-SMALL..=PI + SMALL).contains(&beta) {
                true
            } else {
                beta > PI - SMALL
                    && front_arc_turn.is_some_and(|t| {
                        (side == Side::Right && t > 0) || (side == Side::Left && t < 0)
                    })
            };
            if !concave && beta > SMALL {
                self.move_endpoint_and_flush(canon, cx, cy)?;
                if mv == G_1 {
                    let turn = if side == Side::Left { -1 } else { 1 };
                    self.enqueue_arc(line, 0.0, (mid_x, mid_y), (opx, opy), turn, cz, rest);
                } else if mv == G_0 {
                    self.enqueue_straight(false, line, 0.0, 0.0, mid_x, mid_y, cz, rest);
                } else {
                    return Err(InterpError::CompMoveNotG0G1);
                }
                self.dequeue_canons(canon);
                self.comp.set_endpoint(mid_x, mid_y);
            } else if concave {
                if front_arc_turn.is_none() {
                    let halfcorner = add_half_pis(beta, 2) / 2.0;
                    if halfcorner == 0.0 {
                        return Err(InterpError::CompZeroCorner);
                    }
                    let retreat = radius / halfcorner.tan();
                    let mx = cx + retreat * (theta + gamma).cos();
                    let my = cy + retreat * (theta + gamma).sin();
                    self.move_endpoint_and_flush(canon, mx, my)?;
                } else {
                    let (mx, my) = self.arc_line_corner(side, radius, (px, py), (opx, opy))?;
                    self.move_endpoint_and_flush(canon, mx, my)?;
                }
            } else {
                self.dequeue_canons(canon);
                self.comp.set_endpoint(cx, cy);
            }
            self.enqueue_straight(feed, line, px - opx, py - opy, end_x, end_y, pz, rest);
        }
        self.comp_set_current(end_x, end_y, pz);
        self.set_rest(rest);
        self.comp_set_programmed(px, py, pz);
        Ok(())
    }

    /// Where the held (compensated) arc must end so the tool meets the
    /// new straight line in a concave corner.
    fn arc_line_corner(
        &self,
        side: Side,
        radius: f64,
        p: (f64, f64),
        op: (f64, f64),
    ) -> Result<(f64, f64)> {
        let Some(Queued::ArcFeed {
            end1,
            end2,
            center1,
            center2,
            turn,
            ..
        }) = self.comp.front().cloned()
        else {
            return Err(InterpError::CompBug);
        };
        let oldrad = (center2 - end2).hypot(center1 - end1);
        let base_dir = (p.1 - op.1).atan2(p.0 - op.0);
        let theta = add_half_pis(base_dir, if turn > 0 { 1 } else { -1 });
        let phi = (center2 - op.1).atan2(center1 - op.0);
        let inside = tool_inside_arc(side, turn);
        let oldrad_uncomp = if inside {
            oldrad + radius
        } else {
            oldrad - radius
        };
        let d = oldrad_uncomp * (theta - phi).cos();
        let (d2, sign) = if inside {
            (d - radius, if turn > 0 { -1.0 } else { 1.0 })
        } else {
            (d + radius, if turn > 0 { 1.0 } else { -1.0 })
        };
        let l = d2 / oldrad;
        if !(-1.0..=1.0).contains(&l) {
            return Err(InterpError::CompArcLineGouge);
        }
        let angle = add_half_pis(sign * l.acos() + theta, 2);
        Ok((
            center1 + oldrad * angle.cos(),
            center2 + oldrad * angle.sin(),
        ))
    }

    /// The arc data (centre, turn) of a programmed arc from `start`.
    pub(crate) fn arc_data(
        &self,
        block: &Block,
        mv: i32,
        start: (f64, f64),
        end: (f64, f64),
        offset: (f64, f64),
    ) -> Result<((f64, f64), i32)> {
        let turns = if block.p_flag {
            round_to_int(block.p_number)
        } else {
            1
        };
        let (radius_tol, spiral_tol) = self.arc_tolerances();
        if block.r_flag {
            crate::arc::arc_data_r(
                mv,
                self.s.plane,
                start,
                end,
                block.r_number,
                turns,
                radius_tol,
            )
        } else {
            crate::arc::arc_data_ijk(
                mv,
                self.s.plane,
                start,
                end,
                self.s.ijk_distance_mode == DistanceMode::Absolute,
                offset,
                turns,
                radius_tol,
                spiral_tol,
            )
        }
    }

    /// The first arc after compensation starts.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn arc_comp1(
        &mut self,
        canon: &mut dyn Canon,
        block: &Block,
        mv: i32,
        end: (f64, f64, f64),
        offset: (f64, f64),
        rest: &Pose,
    ) -> Result<()> {
        let side = self.s.cutter_comp_side;
        let tool_radius = self.s.cutter_comp_radius;
        let (_, spiral_tol) = self.arc_tolerances();
        let (cx, cy, cz) = self.comp_get_current();
        let (mut end_x, mut end_y, end_z) = end;
        if (end_x - cx).hypot(end_y - cy) <= tool_radius {
            return Err(InterpError::CompEntryArcTooSmall);
        }
        if block.r_flag && block.r_number.abs() <= tool_radius && tool_inside_arc_move(side, mv) {
            return Err(InterpError::ToolRadiusNotLessThanArc);
        }
        let ((center_x, center_y), turn) =
            self.arc_data(block, mv, (cx, cy), (end_x, end_y), offset)?;
        if !block.r_flag {
            let arc_radius = (center_x - cx).hypot(center_y - cy);
            if arc_radius <= tool_radius && tool_inside_arc_move(side, mv) {
                return Err(InterpError::ToolRadiusNotLessThanArc);
            }
        }
        self.inverse_time_rate_arc(
            canon,
            block,
            (cx, cy, cz),
            (center_x, center_y),
            turn,
            (end_x, end_y, end_z),
        );
        let gamma = if tool_inside_arc(side, turn) {
            (center_y - end_y).atan2(center_x - end_x)
        } else {
            (end_y - center_y).atan2(end_x - center_x)
        };
        self.s.cutter_comp_firstmove = false;
        self.comp_set_programmed(end_x, end_y, end_z);
        end_x += tool_radius * gamma.cos();
        end_y += tool_radius * gamma.sin();
        let b_len = (cy - end_y).hypot(cx - end_x) / 2.0;
        let ab_ang = (center_y - end_y).atan2(center_x - end_x);
        let a_ang = (cy - end_y).atan2(cx - end_x) - ab_ang;
        if a_ang.cos().abs() < TOLERANCE_EQUAL {
            return Err(InterpError::ToolRadiusNotLessThanArc);
        }
        let c_len = b_len / a_ang.cos();
        let ncx = end_x + c_len * ab_ang.cos();
        let ncy = end_y + c_len * ab_ang.sin();
        if ((ncx - end_x).hypot(ncy - end_y) - (ncx - cx).hypot(ncy - cy)).abs() > spiral_tol {
            return Err(InterpError::CompBug);
        }
        let orientation = self.s.cutter_comp_orientation;
        if orientation != 0 && orientation != 9 {
            self.enqueue_straight(true, block.line_number, 0.0, 0.0, cx, cy, cz, rest);
            self.comp.set_endpoint(cx, cy);
        }
        let sweep = find_turn(cx, cy, ncx, ncy, turn, end_x, end_y);
        self.enqueue_arc(
            block.line_number,
            sweep,
            (end_x, end_y),
            (ncx, ncy),
            turn,
            end_z,
            rest,
        );
        self.comp_set_current(end_x, end_y, end_z);
        self.set_rest(rest);
        Ok(())
    }

    /// An arc while compensating (not the first).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn arc_comp2(
        &mut self,
        canon: &mut dyn Canon,
        block: &Block,
        mv: i32,
        end: (f64, f64, f64),
        offset: (f64, f64),
        rest: &Pose,
    ) -> Result<()> {
        let (opx, opy, opz) = self.comp_get_programmed();
        let (cx, cy, cz) = self.comp_get_current();
        let (end_x, end_y, end_z) = end;
        let ((centerx, centery), turn) =
            self.arc_data(block, mv, (opx, opy), (end_x, end_y), offset)?;
        self.inverse_time_rate_arc(
            canon,
            block,
            (opx, opy, opz),
            (centerx, centery),
            turn,
            (end_x, end_y, end_z),
        );
        let side = self.s.cutter_comp_side;
        let tool_radius = self.s.cutter_comp_radius;
        let arc_radius = (centerx - end_x).hypot(centery - end_y);
        let (theta, mut delta, beta) = corner_angles(
            side,
            mv,
            (cx - opx, cy - opy),
            (centerx - opx, centery - opy),
        );
        let gamma;
        if tool_inside_arc_move(side, mv) {
            gamma = (centery - end_y).atan2(centerx - end_x);
            if arc_radius <= tool_radius {
                return Err(InterpError::ToolRadiusNotLessThanArc);
            }
        } else {
            gamma = (end_y - centery).atan2(end_x - centerx);
            delta = add_half_pis(delta, 2);
        }
        let new_end_x = end_x + tool_radius * gamma.cos();
        let new_end_y = end_y + tool_radius * gamma.sin();
        let line = block.line_number;
        let sweep = find_turn(opx, opy, centerx, centery, turn, end_x, end_y);
        let concave = !(-SMALL..=PI + SMALL).contains(&beta)
            || ((beta - PI).abs() < SMALL && !tool_inside_arc(side, turn));
        if concave {
            let front_is_arc = matches!(self.comp.front(), Some(Queued::ArcFeed { .. }));
            let (mx, my) = if !front_is_arc {
                line_arc_corner(
                    side,
                    turn,
                    arc_radius,
                    tool_radius,
                    beta,
                    theta,
                    (centerx, centery),
                )?
            } else {
                self.arc_arc_corner(side, turn, arc_radius, tool_radius, (centerx, centery))?
            };
            self.move_endpoint_and_flush(canon, mx, my)?;
        } else if beta > SMALL {
            let midx = opx + tool_radius * delta.cos();
            let midy = opy + tool_radius * delta.sin();
            self.dequeue_canons(canon);
            let corner_turn = if side == Side::Left { -1 } else { 1 };
            self.enqueue_arc(line, 0.0, (midx, midy), (opx, opy), corner_turn, cz, rest);
            self.dequeue_canons(canon);
            self.comp.set_endpoint(midx, midy);
        } else {
            self.dequeue_canons(canon);
            self.comp.set_endpoint(cx, cy);
        }
        self.enqueue_arc(
            line,
            sweep,
            (new_end_x, new_end_y),
            (centerx, centery),
            turn,
            end_z,
            rest,
        );
        self.comp_set_programmed(end_x, end_y, end_z);
        self.comp_set_current(new_end_x, new_end_y, end_z);
        self.set_rest(rest);
        Ok(())
    }

    fn arc_arc_corner(
        &self,
        side: Side,
        turn: i32,
        arc_radius: f64,
        tool_radius: f64,
        center: (f64, f64),
    ) -> Result<(f64, f64)> {
        let Some(Queued::ArcFeed {
            end1,
            end2,
            center1,
            center2,
            turn: prev_turn,
            ..
        }) = self.comp.front().cloned()
        else {
            return Err(InterpError::CompBug);
        };
        let oldrad = (center2 - end2).hypot(center1 - end1);
        let newrad = if tool_inside_arc(side, turn) {
            arc_radius - tool_radius
        } else {
            arc_radius + tool_radius
        };
        let arc_cc = (center2 - center.1).hypot(center1 - center.0);
        if oldrad == 0.0 || arc_cc == 0.0 {
            return Err(InterpError::CompArcSameCenter);
        }
        let a = (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (2.0 * oldrad * arc_cc);
        if !(-1.0..=1.0).contains(&a) {
            return Err(InterpError::CompArcArcGouge);
        }
        let pullback = a.acos();
        let cc_dir = (center.1 - center2).atan2(center.0 - center1);
        let dir = if tool_inside_arc(side, prev_turn) == (turn > 0) {
            cc_dir + pullback
        } else {
            cc_dir - pullback
        };
        Ok((center1 + oldrad * dir.cos(), center2 + oldrad * dir.sin()))
    }
}

fn tool_inside_arc_move(side: Side, mv: i32) -> bool {
    (side == Side::Left && mv == G_3) || (side == Side::Right && mv == G_2)
}

/// Where the held straight move must end so the tool meets the new arc
/// in a concave corner.
#[allow(clippy::too_many_arguments)]
fn line_arc_corner(
    side: Side,
    turn: i32,
    arc_radius: f64,
    tool_radius: f64,
    beta: f64,
    theta: f64,
    center: (f64, f64),
) -> Result<(f64, f64)> {
    let cy = scaled_sin_less_half_pi(arc_radius, beta);
    let (dist, angle) = if tool_inside_arc(side, turn) {
        let dist = arc_radius - tool_radius;
        let l = (cy + tool_radius) / dist;
        if !(-1.0..=1.0).contains(&l) {
            return Err(InterpError::CompArcConcave);
        }
        (
            dist,
            if turn > 0 {
                theta + l.asin()
            } else {
                theta - l.asin()
            },
        )
    } else {
        let dist = arc_radius + tool_radius;
        let l = (cy - tool_radius) / dist;
        if !(-1.0..=1.0).contains(&l) {
            return Err(InterpError::CompArcConcave);
        }
        (
            dist,
            if turn > 0 {
                sum_with_pi(theta, -l.asin())
            } else {
                sum_with_pi(theta, l.asin())
            },
        )
    };
    Ok((center.0 + dist * angle.cos(), center.1 + dist * angle.sin()))
}

/// The corner between the previous move (direction `from_current`, the
/// vector from the programmed point to the compensated one) and an arc
/// about a centre at `to_center` from the programmed point: the offset
/// direction `theta`, the centre's direction `delta`, and the turn
/// `beta` (negative or beyond pi for a concave corner).
fn corner_angles(
    side: Side,
    mv: i32,
    from_current: (f64, f64),
    to_center: (f64, f64),
) -> (f64, f64, f64) {
    let mut theta = from_current.1.atan2(from_current.0);
    theta = add_half_pis(theta, if side == Side::Left { -1 } else { 1 });
    let delta = to_center.1.atan2(to_center.0);
    let alpha = add_half_pis(delta, if mv == G_3 { -1 } else { 1 });
    let mut beta = if side == Side::Left {
        theta - alpha
    } else {
        alpha - theta
    };
    if beta > 1.5 * PI {
        beta = add_half_pis(beta, -4);
    } else if beta < -FRAC_PI_2 {
        beta = add_half_pis(beta, 4);
    }
    (theta, delta, beta)
}
