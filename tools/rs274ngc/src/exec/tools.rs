//! Tools: T (select), M6 (change), M61 (set current), G43/G43.1/G43.2/
//! G49 (length offsets), G10 L1/L10/L11 (tool table entries).

use crate::block::{round_to_int, Block};
use crate::canon::{Canon, Pose};
use crate::codes::*;
use crate::error::{InterpError, Result};
use crate::find::rotate;
use crate::interp::Interp;
use crate::setup::Side;

impl Interp {
    /// The tool table index holding tool `toolno` (0: the spindle for
    /// tool 0 on a non-random changer).
    pub(crate) fn find_tool_index(&self, toolno: i32) -> Result<i32> {
        // On a non-random changer T0 is the empty spindle (entry 0); on a
        // random one T0 is a tool like any other, looked up in the table
        // (the spindle's entry included), and an error when it has none.
        if toolno == 0 && !self.config.random_toolchanger {
            return Ok(0);
        }
        // Empty slots hold -1: no tool has a negative number.
        if toolno < 0 {
            return Err(InterpError::ToolNotFound(toolno));
        }
        let start = if self.config.random_toolchanger { 0 } else { 1 };
        self.s
            .tool_table
            .iter()
            .enumerate()
            .skip(start)
            .find(|(_, t)| t.toolno == toolno)
            .map(|(i, _)| i as i32)
            .ok_or(InterpError::ToolNotFound(toolno))
    }

    /// T word.
    pub(crate) fn convert_tool_select(
        &mut self,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let index = self.find_tool_index(block.t_number)?;
        canon.select_tool(block.t_number);
        self.s.selected_pocket = index;
        self.s.selected_tool = block.t_number;
        Ok(())
    }

    /// G10 L0: reload the tool table, refused while a tool is in the
    /// spindle (its offsets would change under it).
    pub(crate) fn convert_reload_tool_data(&mut self, canon: &mut dyn Canon) -> Result<()> {
        let loaded = self.s.tool(0).toolno;
        if loaded > 0 {
            return Err(InterpError::G10L0ToolLoaded(loaded));
        }
        canon.reload_tool_data();
        self.load_tool_table(canon);
        Ok(())
    }

    /// M6.
    pub(crate) fn convert_tool_change(&mut self, canon: &mut dyn Canon) -> Result<()> {
        if self.s.selected_pocket < 0 {
            return Err(InterpError::NoToolPrepared);
        }
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::ToolChangeWithComp);
        }
        canon.start_change();
        if !self.config.tool_change_with_spindle_on {
            self.stop_all_spindles(canon, false);
        }
        if self.config.tool_change_quill_up {
            let up = self.find_relative(&Pose::ZERO);
            canon.comment("AXIS,hide");
            let end = Pose {
                z: up.z,
                ..self.s.current
            };
            canon.straight_traverse(-1, &end);
            canon.comment("AXIS,show");
            self.s.current.z = up.z;
        }
        if self.config.tool_change_at_g30 {
            let end = self.find_relative(&self.user_pose_from_params(5181));
            canon.comment("AXIS,hide");
            canon.straight_traverse(-1, &end);
            canon.comment("AXIS,show");
            self.s.current = end;
        }
        canon.change_tool(self.s.selected_pocket);
        self.s.current_pocket = self.s.selected_pocket;
        self.s.toolchange_flag = true;
        self.set_tool_parameters();
        Ok(())
    }

    /// M61 Q<tool>: say which tool is in the spindle, without changing.
    pub(crate) fn convert_set_tool_number(
        &mut self,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let toolno = round_to_int(block.q_number);
        if toolno < 0 {
            return Err(InterpError::M61Q);
        }
        let index = self.find_tool_index(toolno)?;
        self.s.current_pocket = index;
        self.s.toolchange_flag = true;
        canon.change_tool_number(index);
        self.set_tool_parameters();
        Ok(())
    }

    /// G43, G43.1, G43.2, G49.
    pub(crate) fn convert_tool_length_offset(
        &mut self,
        code: i32,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        if self.s.cutter_comp_side != Side::Off {
            return Err(InterpError::ToolOffsetWithComp);
        }
        let offset = match code {
            G_49 => Pose::ZERO,
            G_43 => {
                let index = if block.h_flag {
                    self.find_tool_index(block.h_number)?
                } else if self.s.toolchange_flag {
                    self.s.current_pocket
                } else {
                    0
                };
                self.user_pose_to_program(&self.s.tool(index).offset)
            }
            G_43_1 => {
                let mut t = self.s.tool_offset;
                let words = [
                    (block.x_flag, block.x_number, &mut t.x),
                    (block.y_flag, block.y_number, &mut t.y),
                    (block.z_flag, block.z_number, &mut t.z),
                    (block.a_flag, block.a_number, &mut t.a),
                    (block.b_flag, block.b_number, &mut t.b),
                    (block.c_flag, block.c_number, &mut t.c),
                    (block.u_flag, block.u_number, &mut t.u),
                    (block.v_flag, block.v_number, &mut t.v),
                    (block.w_flag, block.w_number, &mut t.w),
                ];
                for (flag, value, slot) in words {
                    if flag {
                        *slot = value;
                    }
                }
                t
            }
            _ => self.g43_2_offset(block)?,
        };
        canon.use_tool_length_offset(&offset);
        let s = &mut self.s;
        let mut dx = s.tool_offset.x - offset.x;
        let mut dy = s.tool_offset.y - offset.y;
        rotate(&mut dx, &mut dy, -s.rotation_xy);
        s.current.x += dx;
        s.current.y += dy;
        s.current.z += s.tool_offset.z - offset.z;
        s.current.a += s.tool_offset.a - offset.a;
        s.current.b += s.tool_offset.b - offset.b;
        s.current.c += s.tool_offset.c - offset.c;
        s.current.u += s.tool_offset.u - offset.u;
        s.current.v += s.tool_offset.v - offset.v;
        s.current.w += s.tool_offset.w - offset.w;
        s.tool_offset = offset;
        Ok(())
    }

    /// G43.2: add a tool's offsets (H) or the axis words to the offset
    /// in effect.
    fn g43_2_offset(&self, block: &Block) -> Result<Pose> {
        let mut t = self.s.tool_offset;
        if block.h_flag {
            if block.has_axis() {
                return Err(InterpError::G432HAndAxes);
            }
            let index = self.find_tool_index(block.h_number)?;
            let add = self.user_pose_to_program(&self.s.tool(index).offset);
            crate::find::add_pose(&mut t, &add);
        } else if block.has_axis() {
            // LinuxCNC 2.9 looks the (absent, -1) H word up all the same,
            // so the axis-word form is refused with its message.
            self.find_tool_index(block.h_number)?;
            let words = [
                (block.x_flag, block.x_number, &mut t.x),
                (block.y_flag, block.y_number, &mut t.y),
                (block.z_flag, block.z_number, &mut t.z),
                (block.a_flag, block.a_number, &mut t.a),
                (block.b_flag, block.b_number, &mut t.b),
                (block.c_flag, block.c_number, &mut t.c),
                (block.u_flag, block.u_number, &mut t.u),
                (block.v_flag, block.v_number, &mut t.v),
                (block.w_flag, block.w_number, &mut t.w),
            ];
            for (flag, value, slot) in words {
                if flag {
                    *slot += value;
                }
            }
        } else {
            return Err(InterpError::G432Nothing);
        }
        Ok(t)
    }

    /// G10 L1 / L10 / L11: set a tool table entry.
    pub(crate) fn convert_setup_tool(
        &mut self,
        block: &Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let toolno = crate::read::c_int(block.p_number + 0.5);
        let index = self.find_tool_index(toolno)?;
        if !(block.has_axis() || block.r_flag || block.q_flag || block.i_flag || block.j_flag) {
            return Err(InterpError::G10L1NoOffsets);
        }
        let mut entry = self.s.tool(index);
        if block.l_number == 1 {
            let linear = |this: &Self, v: f64| this.program_to_user_len(v);
            let words = [
                (
                    block.x_flag,
                    linear(self, block.x_number),
                    &mut entry.offset.x,
                ),
                (
                    block.y_flag,
                    linear(self, block.y_number),
                    &mut entry.offset.y,
                ),
                (
                    block.z_flag,
                    linear(self, block.z_number),
                    &mut entry.offset.z,
                ),
                (block.a_flag, block.a_number, &mut entry.offset.a),
                (block.b_flag, block.b_number, &mut entry.offset.b),
                (block.c_flag, block.c_number, &mut entry.offset.c),
                (
                    block.u_flag,
                    linear(self, block.u_number),
                    &mut entry.offset.u,
                ),
                (
                    block.v_flag,
                    linear(self, block.v_number),
                    &mut entry.offset.v,
                ),
                (
                    block.w_flag,
                    linear(self, block.w_number),
                    &mut entry.offset.w,
                ),
            ];
            for (flag, value, slot) in words {
                if flag {
                    *slot = value;
                }
            }
        } else {
            self.touch_off_tool(block, &mut entry);
        }
        if block.r_flag {
            entry.diameter = self.program_to_user_len(block.r_number) * 2.0;
        }
        if block.i_flag {
            entry.frontangle = block.i_number;
        }
        if block.j_flag {
            entry.backangle = block.j_number;
        }
        if block.q_number != -1.0 {
            let q = crate::read::c_int(block.q_number + 0.5);
            if (q as f64 - block.q_number).abs() >= 0.0001 {
                return Err(InterpError::G10QNotInteger);
            }
            if q > 9 {
                return Err(InterpError::InvalidOrientation);
            }
            entry.orientation = q;
        }
        *self.s.tool_mut(index) = entry;
        canon.set_tool_table_entry(index, &entry);
        if !self.config.random_toolchanger && self.s.current_pocket == index {
            *self.s.tool_mut(0) = entry;
        }
        self.set_tool_parameters();
        if !self.config.random_toolchanger && index == self.s.current_pocket {
            canon.set_tool_table_entry(0, &entry);
        }
        Ok(())
    }

    /// G10 L10 / L11: offsets so the current position reads as the
    /// block's words (L11: in G59.3, ignoring G92).
    fn touch_off_tool(&self, block: &Block, entry: &mut crate::canon::ToolEntry) {
        let to_fixture = block.l_number == 11;
        let system = if to_fixture { 9 } else { self.s.origin_index };
        let mut t = self.find_current_in_system(system, true);
        if to_fixture && self.params.get(5210) != 0.0 {
            let g92 = self.user_pose_from_params(5211);
            crate::find::add_pose(&mut t, &g92);
        }
        let rot = self.params.get(5210 + system as usize * 20);
        let user = |v: f64| self.program_to_user_len(v);
        let prog = |v: f64| self.user_to_program_len(v);
        if block.x_flag && block.y_flag {
            let (mut tx, mut ty) = (t.x - block.x_number, t.y - block.y_number);
            rotate(&mut tx, &mut ty, rot);
            entry.offset.x = user(tx);
            entry.offset.y = user(ty);
        } else if block.x_flag || block.y_flag {
            let (mut ox, mut oy) = (prog(entry.offset.x), prog(entry.offset.y));
            rotate(&mut ox, &mut oy, -rot);
            let (mut tx, mut ty) = if block.x_flag {
                ox = 0.0;
                (t.x - block.x_number, 0.0)
            } else {
                oy = 0.0;
                (0.0, t.y - block.y_number)
            };
            rotate(&mut ox, &mut oy, rot);
            rotate(&mut tx, &mut ty, rot);
            entry.offset.x = user(tx + ox);
            entry.offset.y = user(ty + oy);
        }
        let rest = [
            (
                block.z_flag,
                t.z - block.z_number,
                &mut entry.offset.z,
                true,
            ),
            (
                block.a_flag,
                t.a - block.a_number,
                &mut entry.offset.a,
                false,
            ),
            (
                block.b_flag,
                t.b - block.b_number,
                &mut entry.offset.b,
                false,
            ),
            (
                block.c_flag,
                t.c - block.c_number,
                &mut entry.offset.c,
                false,
            ),
            (
                block.u_flag,
                t.u - block.u_number,
                &mut entry.offset.u,
                true,
            ),
            (
                block.v_flag,
                t.v - block.v_number,
                &mut entry.offset.v,
                true,
            ),
            (
                block.w_flag,
                t.w - block.w_number,
                &mut entry.offset.w,
                true,
            ),
        ];
        for (flag, value, slot, linear) in rest {
            if flag {
                *slot = if linear { user(value) } else { value };
            }
        }
    }
}
