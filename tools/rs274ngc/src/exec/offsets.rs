//! Offsets and reference points: G10 L2/L20 (work offsets), G10
//! L1/L10/L11 (tool table), G52 and G92.x (axis offsets), G28/G30 and
//! G28.1/G30.1 (reference points).

use crate::block::Block;
use crate::canon::{Canon, Pose};
use crate::codes::*;
use crate::comp::Queued;
use crate::error::{InterpError, Result};
use crate::find::{rotate, sub_pose};
use crate::interp::Interp;
use crate::setup::Side;

/// The nine axis words of a block: (flag, value) in X Y Z A B C U V W order.
fn axis_words(b: &Block) -> [(bool, f64); 9] {
    [
        (b.x_flag, b.x_number),
        (b.y_flag, b.y_number),
        (b.z_flag, b.z_number),
        (b.a_flag, b.a_number),
        (b.b_flag, b.b_number),
        (b.c_flag, b.c_number),
        (b.u_flag, b.u_number),
        (b.v_flag, b.v_number),
        (b.w_flag, b.w_number),
    ]
}

fn pose_axes(p: &mut Pose) -> [&mut f64; 9] {
    [
        &mut p.x, &mut p.y, &mut p.z, &mut p.a, &mut p.b, &mut p.c, &mut p.u, &mut p.v, &mut p.w,
    ]
}

/// Linear (true) or rotary axis, in X..W order.
const LINEAR: [bool; 9] = [true, true, true, false, false, false, true, true, true];

impl Interp {
    fn to_program(&self, linear: bool, u: f64) -> f64 {
        if linear {
            self.user_to_program_len(u)
        } else {
            u
        }
    }

    fn to_user(&self, linear: bool, p: f64) -> f64 {
        if linear {
            self.program_to_user_len(p)
        } else {
            p
        }
    }

    /// G10 L2 / L20: set a work coordinate system's origin.
    pub(crate) fn convert_setup(&mut self, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        if block.i_flag || block.j_flag {
            return Err(InterpError::G10L2Ij);
        }
        let mut p_int = (block.p_number + 0.0001) as i32;
        if p_int == 0 {
            p_int = self.s.origin_index;
        }
        if self.s.cutter_comp_side != Side::Off && p_int == self.s.origin_index {
            return Err(InterpError::ActiveCoordSystemWithComp);
        }
        let l20 = block.l_number == 20;
        let base = 5200 + p_int as usize * 20;
        let cur = self.find_current_in_system(p_int, false);
        let r = if block.r_flag {
            if l20 {
                return Err(InterpError::G10L20R);
            }
            self.params.set(base + 10, block.r_number);
            block.r_number
        } else {
            self.params.get(base + 10)
        };
        let words = axis_words(block);
        let mut new = Pose::ZERO;
        if l20 {
            let (mut oldx, mut oldy) = (cur.x, cur.y);
            let mut x = if block.x_flag { block.x_number } else { cur.x };
            let mut y = if block.y_flag { block.y_number } else { cur.y };
            rotate(&mut oldx, &mut oldy, r);
            rotate(&mut x, &mut y, r);
            new.x = oldx + self.user_to_program_len(self.params.get(base + 1)) - x;
            new.y = oldy + self.user_to_program_len(self.params.get(base + 2)) - y;
            self.params.set(base + 1, self.program_to_user_len(new.x));
            self.params.set(base + 2, self.program_to_user_len(new.y));
            if p_int == self.s.origin_index {
                let (cx, cy) = (&mut self.s.current.x, &mut self.s.current.y);
                rotate(cx, cy, self.s.rotation_xy);
                self.s.rotation_xy = 0.0;
            }
        } else {
            for (i, &(flag, value)) in words.iter().enumerate().take(2) {
                let v = if flag {
                    self.params
                        .set(base + 1 + i, self.program_to_user_len(value));
                    value
                } else {
                    self.user_to_program_len(self.params.get(base + 1 + i))
                };
                *pose_axes(&mut new)[i] = v;
            }
        }
        let cur_axes = [
            cur.x, cur.y, cur.z, cur.a, cur.b, cur.c, cur.u, cur.v, cur.w,
        ];
        for i in 2..9 {
            let (flag, value) = words[i];
            let linear = LINEAR[i];
            let v = if flag {
                let v = if l20 {
                    cur_axes[i] + self.to_program(linear, self.params.get(base + 1 + i)) - value
                } else {
                    value
                };
                self.params.set(base + 1 + i, self.to_user(linear, v));
                v
            } else {
                self.to_program(linear, self.params.get(base + 1 + i))
            };
            *pose_axes(&mut new)[i] = v;
        }
        if p_int == self.s.origin_index {
            let s = &mut self.s;
            rotate(&mut s.current.x, &mut s.current.y, s.rotation_xy);
            crate::find::add_pose(&mut s.current, &s.origin_offset);
            s.origin_offset = new;
            sub_pose(&mut s.current, &new);
            canon.set_g5x_offset(p_int, &new);
            rotate(&mut s.current.x, &mut s.current.y, -r);
            s.rotation_xy = r;
            canon.set_xy_rotation(r);
        } else {
            self.enqueue(
                canon,
                Queued::Comment("interpreter: setting coordinate system origin".into()),
            );
        }
        Ok(())
    }

    /// G52, G92, G92.1, G92.2, G92.3: the axis offset.
    pub(crate) fn convert_axis_offsets(
        &mut self,
        code: i32,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        // With compensation on, G52 and G92 are refused and (as in
        // LinuxCNC 2.9) G92.1, G92.2 and G92.3 do nothing.
        if self.s.cutter_comp_side != Side::Off {
            if matches!(code, G_52 | G_92) {
                return Err(InterpError::AxisOffsetsWithComp);
            }
            return Ok(());
        }
        let words = axis_words(block);
        match code {
            G_52 | G_92 => {
                self.params.set(5210, 1.0);
                let s = &mut self.s;
                let mut cur = pose_axes(&mut s.current);
                let mut off = [
                    s.axis_offset.x,
                    s.axis_offset.y,
                    s.axis_offset.z,
                    s.axis_offset.a,
                    s.axis_offset.b,
                    s.axis_offset.c,
                    s.axis_offset.u,
                    s.axis_offset.v,
                    s.axis_offset.w,
                ];
                for i in 0..9 {
                    let (flag, value) = words[i];
                    if !flag {
                        continue;
                    }
                    if code == G_52 {
                        *cur[i] += off[i] - value;
                        off[i] = value;
                    } else {
                        off[i] = *cur[i] + off[i] - value;
                        *cur[i] = value;
                    }
                }
                cur = pose_axes(&mut s.current);
                let _ = &mut cur;
                s.axis_offset = Pose {
                    x: off[0],
                    y: off[1],
                    z: off[2],
                    a: off[3],
                    b: off[4],
                    c: off[5],
                    u: off[6],
                    v: off[7],
                    w: off[8],
                };
                canon.set_g92_offset(&s.axis_offset);
                for (i, v) in off.into_iter().enumerate() {
                    self.params.set(5211 + i, self.to_user(LINEAR[i], v));
                }
            }
            G_92_1 | G_92_2 => {
                self.params.set(5210, 0.0);
                let s = &mut self.s;
                crate::find::add_pose(&mut s.current, &s.axis_offset);
                canon.set_g92_offset(&Pose::ZERO);
                s.axis_offset = Pose::ZERO;
                if code == G_92_1 {
                    for i in 5211..=5219 {
                        self.params.set(i, 0.0);
                    }
                }
            }
            _ => {
                self.params.set(5210, 1.0);
                let stored = self.user_pose_from_params(5211);
                let s = &mut self.s;
                crate::find::add_pose(&mut s.current, &s.axis_offset);
                sub_pose(&mut s.current, &stored);
                s.axis_offset = stored;
                canon.set_g92_offset(&s.axis_offset);
            }
        }
        Ok(())
    }

    /// G28 / G30: through the given point to reference point 1 / 2.
    pub(crate) fn convert_home(
        &mut self,
        code: i32,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let mut end = self.find_ends(block)?;
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::HomeWithComp);
        }
        canon.straight_traverse(block.line_number, &end);
        self.s.current = end;
        let base = if code == G_28 { 5161 } else { 5181 };
        let home = self.find_relative(&self.user_pose_from_params(base));
        let words = axis_words(block);
        let any = words.iter().any(|(f, _)| *f);
        let home_axes = [
            home.x, home.y, home.z, home.a, home.b, home.c, home.u, home.v, home.w,
        ];
        for (i, slot) in pose_axes(&mut end).into_iter().enumerate() {
            if words[i].0 || !any {
                *slot = home_axes[i];
            }
        }
        canon.straight_traverse(block.line_number, &end);
        self.s.current = end;
        Ok(())
    }

    /// G28.1 / G30.1: store the current machine position as a reference point.
    pub(crate) fn convert_savehome(&mut self, code: i32) -> Result<()> {
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::SaveHomeWithComp);
        }
        let m = self.machine_position();
        let machine = [m.x, m.y, m.z, m.a, m.b, m.c, m.u, m.v, m.w];
        let base = if code == G_28_1 { 5161 } else { 5181 };
        for (i, v) in machine.into_iter().enumerate() {
            self.params.set(base + i, self.to_user(LINEAR[i], v));
        }
        Ok(())
    }
}
