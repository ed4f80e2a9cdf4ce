//! Finding end points and positions: where a block's axis words take
//! the tool in the current coordinate system (absolute, incremental,
//! G53 machine coordinates, polar), machine points seen from the current
//! system, and the arc geometry helpers those moves need.

use crate::block::Block;
use crate::canon::Pose;
use crate::codes::{GM_MODAL_0, G_53};
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::setup::{DistanceMode, Side};

/// Rotate (x, y) by `theta` degrees about the origin.
pub fn rotate(x: &mut f64, y: &mut f64, theta: f64) {
    let t = theta * std::f64::consts::PI / 180.0;
    let xx = *x * t.cos() - *y * t.sin();
    let yy = *x * t.sin() + *y * t.cos();
    *x = xx;
    *y = yy;
}

/// Degrees to radians as LinuxCNC's `D2R` does it (in double).
pub fn d2r(degrees: f64) -> f64 {
    degrees * std::f64::consts::PI / 180.0
}

/// The angle, in radians (negative clockwise), swept by an arc from
/// (x1, y1) to (x2, y2) about (cx, cy) with `turn` turns.
pub fn find_turn(x1: f64, y1: f64, cx: f64, cy: f64, turn: i32, x2: f64, y2: f64) -> f64 {
    if turn == 0 {
        return 0.0;
    }
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut alpha = (y1 - cy).atan2(x1 - cx);
    let mut beta = (y2 - cy).atan2(x2 - cx);
    if turn > 0 {
        if beta <= alpha {
            beta += two_pi;
        }
        (beta - alpha) + ((turn - 1) as f64 * two_pi)
    } else {
        if alpha <= beta {
            alpha += two_pi;
        }
        (beta - alpha) + ((turn + 1) as f64 * two_pi)
    }
}

/// Length of an arc or helix (rotary axes ignored).
#[allow(clippy::too_many_arguments)]
pub fn find_arc_length(
    x1: f64,
    y1: f64,
    z1: f64,
    cx: f64,
    cy: f64,
    turn: i32,
    x2: f64,
    y2: f64,
    z2: f64,
) -> f64 {
    let radius = (cx - x1).hypot(cy - y1);
    let theta = find_turn(x1, y1, cx, cy, turn, x2, y2);
    if z2 == z1 {
        radius * theta.abs()
    } else {
        (radius * theta).hypot(z2 - z1)
    }
}

/// Length of a straight move as inverse-time feed counts it: XYZ if
/// they move, else UVW, else the rotary axes.
pub fn find_straight_length(end: &Pose, start: &Pose) -> f64 {
    const TINY: f64 = 1e-7;
    let sq = |v: f64| v.powi(2);
    if (start.x - end.x).abs() > TINY
        || (start.y - end.y).abs() > TINY
        || (start.z - end.z).abs() > TINY
    {
        (sq(end.x - start.x) + sq(end.y - start.y) + sq(end.z - start.z)).sqrt()
    } else if (start.u - end.u).abs() > TINY
        || (start.v - end.v).abs() > TINY
        || (start.w - end.w).abs() > TINY
    {
        (sq(end.u - start.u) + sq(end.v - start.v) + sq(end.w - start.w)).sqrt()
    } else {
        (sq(end.a - start.a) + sq(end.b - start.b) + sq(end.c - start.c)).sqrt()
    }
}

impl Interp {
    /// The point a block's axis words name, in the current coordinate
    /// system and program units.
    pub(crate) fn find_ends(&self, block: &Block) -> Result<Pose> {
        let s = &self.s;
        let middle = !s.cutter_comp_firstmove;
        let comp = s.cutter_comp_side != Side::Off;
        let xy = s.plane == crate::canon::Plane::Xy;
        let xz = s.plane == crate::canon::Plane::Xz;
        let mut p = Pose::ZERO;
        if block.g_modes[GM_MODAL_0] == G_53 {
            return self.find_ends_machine(block);
        }
        let base_x = if comp && middle {
            s.program_x
        } else {
            s.current.x
        };
        let base_y = if comp && middle && xy {
            s.program_y
        } else {
            s.current.y
        };
        let base_z = if comp && middle && xz {
            s.program_z
        } else {
            s.current.z
        };
        if s.distance_mode == DistanceMode::Absolute {
            p.x = if block.x_flag { block.x_number } else { base_x };
            p.y = if block.y_flag { block.y_number } else { base_y };
            self.polar_absolute(block, &mut p)?;
            p.z = if block.z_flag { block.z_number } else { base_z };
            let pick = |flag: bool, n: f64, cur: f64| if flag { n } else { cur };
            p.a = pick(block.a_flag, block.a_number, s.current.a);
            p.b = pick(block.b_flag, block.b_number, s.current.b);
            p.c = pick(block.c_flag, block.c_number, s.current.c);
            p.u = pick(block.u_flag, block.u_number, s.current.u);
            p.v = pick(block.v_flag, block.v_number, s.current.v);
            p.w = pick(block.w_flag, block.w_number, s.current.w);
        } else {
            let add = |flag: bool, n: f64, cur: f64| if flag { cur + n } else { cur };
            p.x = add(block.x_flag, block.x_number, base_x);
            p.y = add(block.y_flag, block.y_number, base_y);
            polar_incremental(block, &mut p)?;
            p.z = add(block.z_flag, block.z_number, base_z);
            p.a = add(block.a_flag, block.a_number, s.current.a);
            p.b = add(block.b_flag, block.b_number, s.current.b);
            p.c = add(block.c_flag, block.c_number, s.current.c);
            p.u = add(block.u_flag, block.u_number, s.current.u);
            p.v = add(block.v_flag, block.v_number, s.current.v);
            p.w = add(block.w_flag, block.w_number, s.current.w);
        }
        Ok(p)
    }

    /// The end point of a G53 move: machine coordinates in the block,
    /// brought back into the current coordinate system.
    fn find_ends_machine(&self, block: &Block) -> Result<Pose> {
        let s = &self.s;
        let mut p = Pose::ZERO;
        if block.radius_flag || block.theta_flag {
            return Err(InterpError::Unsupported(
                "Cannot use polar coordinates with G53",
            ));
        }
        let mut cx = s.current.x + s.axis_offset.x;
        let mut cy = s.current.y + s.axis_offset.y;
        rotate(&mut cx, &mut cy, s.rotation_xy);
        p.x = if block.x_flag {
            block.x_number - s.origin_offset.x - s.tool_offset.x
        } else {
            cx
        };
        p.y = if block.y_flag {
            block.y_number - s.origin_offset.y - s.tool_offset.y
        } else {
            cy
        };
        rotate(&mut p.x, &mut p.y, -s.rotation_xy);
        p.x -= s.axis_offset.x;
        p.y -= s.axis_offset.y;
        let machine = |flag: bool, n: f64, o: f64, a: f64, t: f64, cur: f64| {
            if flag {
                n - o - a - t
            } else {
                cur
            }
        };
        p.z = machine(
            block.z_flag,
            block.z_number,
            s.origin_offset.z,
            s.axis_offset.z,
            s.tool_offset.z,
            s.current.z,
        );
        p.a = machine(
            block.a_flag,
            block.a_number,
            s.origin_offset.a,
            s.axis_offset.a,
            0.0,
            s.current.a,
        );
        p.b = machine(
            block.b_flag,
            block.b_number,
            s.origin_offset.b,
            s.axis_offset.b,
            0.0,
            s.current.b,
        );
        p.c = machine(
            block.c_flag,
            block.c_number,
            s.origin_offset.c,
            s.axis_offset.c,
            0.0,
            s.current.c,
        );
        p.u = machine(
            block.u_flag,
            block.u_number,
            s.origin_offset.u,
            s.axis_offset.u,
            s.tool_offset.u,
            s.current.u,
        );
        p.v = machine(
            block.v_flag,
            block.v_number,
            s.origin_offset.v,
            s.axis_offset.v,
            s.tool_offset.v,
            s.current.v,
        );
        p.w = machine(
            block.w_flag,
            block.w_number,
            s.origin_offset.w,
            s.axis_offset.w,
            s.tool_offset.w,
            s.current.w,
        );
        Ok(p)
    }

    fn polar_absolute(&self, block: &Block, p: &mut Pose) -> Result<()> {
        if !(block.radius_flag || block.theta_flag) {
            return Ok(());
        }
        if block.x_flag || block.y_flag {
            return Err(InterpError::Unsupported(
                "Cannot specify X or Y words with polar coordinate",
            ));
        }
        if block.radius_flag && block.theta_flag {
            p.x = block.radius * d2r(block.theta).cos();
            p.y = block.radius * d2r(block.theta).sin();
        } else if block.radius_flag {
            if p.y == 0.0 && p.x == 0.0 {
                return Err(InterpError::Unsupported(
                    "Must specify angle in polar coordinate if at the origin",
                ));
            }
            let theta = p.y.atan2(p.x);
            p.x = block.radius * theta.cos();
            p.y = block.radius * theta.sin();
        } else {
            let radius = p.y.hypot(p.x);
            p.x = radius * d2r(block.theta).cos();
            p.y = radius * d2r(block.theta).sin();
        }
        Ok(())
    }

    /// A machine point seen from the current coordinate system with the
    /// current tool length offset.
    pub(crate) fn find_relative(&self, m: &Pose) -> Pose {
        let s = &self.s;
        let mut x = m.x - s.origin_offset.x - s.tool_offset.x;
        let mut y = m.y - s.origin_offset.y - s.tool_offset.y;
        rotate(&mut x, &mut y, -s.rotation_xy);
        Pose {
            x: x - s.axis_offset.x,
            y: y - s.axis_offset.y,
            z: m.z - s.origin_offset.z - s.axis_offset.z - s.tool_offset.z,
            a: m.a - s.origin_offset.a - s.axis_offset.a,
            b: m.b - s.origin_offset.b - s.axis_offset.b,
            c: m.c - s.origin_offset.c - s.axis_offset.c,
            u: m.u - s.origin_offset.u - s.axis_offset.u - s.tool_offset.u,
            v: m.v - s.origin_offset.v - s.axis_offset.v - s.tool_offset.v,
            w: m.w - s.origin_offset.w - s.axis_offset.w - s.tool_offset.w,
        }
    }

    /// Where the current point would be in coordinate system `system`
    /// (1..9); with `without_tlo` as if no tool length offset applied.
    pub(crate) fn find_current_in_system(&self, system: i32, without_tlo: bool) -> Pose {
        let s = &self.s;
        let c = &s.current;
        let mut p = Pose {
            x: c.x + s.axis_offset.x,
            y: c.y + s.axis_offset.y,
            z: c.z + s.axis_offset.z,
            a: c.a + s.axis_offset.a,
            b: c.b + s.axis_offset.b,
            c: c.c + s.axis_offset.c,
            u: c.u + s.axis_offset.u,
            v: c.v + s.axis_offset.v,
            w: c.w + s.axis_offset.w,
        };
        rotate(&mut p.x, &mut p.y, s.rotation_xy);
        add_pose(&mut p, &s.origin_offset);
        if without_tlo {
            add_pose(&mut p, &s.tool_offset);
        }
        let base = 5200 + system as usize * 20;
        let target = self.user_pose_from_params(base + 1);
        sub_pose(&mut p, &target);
        rotate(&mut p.x, &mut p.y, -self.params.get(base + 10));
        if self.params.get(5210) != 0.0 {
            let g92 = self.user_pose_from_params(5211);
            sub_pose(&mut p, &g92);
        }
        p
    }
}

fn polar_incremental(block: &Block, p: &mut Pose) -> Result<()> {
    if (block.radius_flag || block.theta_flag) && (block.x_flag || block.y_flag) {
        return Err(InterpError::Unsupported(
            "Cannot specify X or Y words with polar coordinate",
        ));
    }
    if block.radius_flag {
        if p.y == 0.0 && p.x == 0.0 {
            return Err(InterpError::PolarIncrementalAtOrigin);
        }
        let theta = p.y.atan2(p.x);
        let radius = p.y.hypot(p.x) + block.radius;
        p.x = radius * theta.cos();
        p.y = radius * theta.sin();
    }
    if block.theta_flag {
        if p.y == 0.0 && p.x == 0.0 {
            return Err(InterpError::Unsupported(
                "G91 motion with polar coordinates is indeterminate when at the origin",
            ));
        }
        let theta = p.y.atan2(p.x) + d2r(block.theta);
        let radius = p.y.hypot(p.x);
        p.x = radius * theta.cos();
        p.y = radius * theta.sin();
    }
    Ok(())
}

/// `p += q` on all axes.
pub(crate) fn add_pose(p: &mut Pose, q: &Pose) {
    p.x += q.x;
    p.y += q.y;
    p.z += q.z;
    p.a += q.a;
    p.b += q.b;
    p.c += q.c;
    p.u += q.u;
    p.v += q.v;
    p.w += q.w;
}

/// `p -= q` on all axes.
pub(crate) fn sub_pose(p: &mut Pose, q: &Pose) {
    p.x -= q.x;
    p.y -= q.y;
    p.z -= q.z;
    p.a -= q.a;
    p.b -= q.b;
    p.c -= q.c;
    p.u -= q.u;
    p.v -= q.v;
    p.w -= q.w;
}
