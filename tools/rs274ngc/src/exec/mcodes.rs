//! M-codes other than the stopping ones, in LinuxCNC's order: I/O
//! (M62-M68), tool change (M6, M61), spindle (M3 M4 M5 M19, in
//! spindle.rs) and modal state save/restore (M70-M73), coolant (M7 M8
//! M9), overrides (M48-M53), user M-codes (M100-M199).

use crate::block::{round_to_int, Block};
use crate::canon::{Canon, InputKind};
use crate::comp::Queued;
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::setup::Side;

impl Interp {
    pub(crate) fn convert_m(&mut self, block: &Block, canon: &mut dyn Canon) -> Result<()> {
        let comp = self.s.cutter_comp_side != Side::Off;
        self.convert_io(block, canon, comp)?;
        match block.m_modes[6] {
            6 => self.convert_tool_change(canon)?,
            61 => self.convert_set_tool_number(block, canon)?,
            _ => {}
        }
        match block.m_modes[7] {
            3 | 4 | 5 | 19 => self.convert_spindle_m(block, canon)?,
            70..=73 => self.convert_modal_state(block.m_modes[7], canon)?,
            _ => {}
        }
        match block.m_modes[8] {
            7 => {
                self.enqueue(canon, Queued::MistOn);
                self.s.mist = true;
            }
            8 => {
                self.enqueue(canon, Queued::FloodOn);
                self.s.flood = true;
            }
            9 => {
                self.enqueue(canon, Queued::MistOff);
                self.s.mist = false;
                self.enqueue(canon, Queued::FloodOff);
                self.s.flood = false;
            }
            _ => {}
        }
        self.convert_overrides(block, canon, comp)?;
        if block.m_modes[10] != -1 {
            let number = block.m_modes[10];
            if !canon.user_m_code_defined(number) {
                return Err(InterpError::UnknownM(number));
            }
            canon.user_m_code(number, block.p_number, block.q_number);
        }
        Ok(())
    }

    fn convert_io(&mut self, block: &Block, canon: &mut dyn Canon, comp: bool) -> Result<()> {
        let p = round_to_int(block.p_number);
        match block.m_modes[5] {
            62..=65 => {
                let m = block.m_modes[5];
                if comp {
                    return Err(match m {
                        62 => InterpError::M62WithComp,
                        63 => InterpError::M63WithComp,
                        _ => InterpError::M64WithComp,
                    });
                }
                if !block.p_flag {
                    return Err(InterpError::NoPWithM(m));
                }
                match m {
                    62 => canon.set_motion_output_bit(p),
                    63 => canon.clear_motion_output_bit(p),
                    64 => canon.set_aux_output_bit(p),
                    _ => canon.clear_aux_output_bit(p),
                }
            }
            66 => self.convert_wait_input(block, canon, comp)?,
            67 | 68 => {
                let m = block.m_modes[5];
                if comp {
                    return Err(if m == 67 {
                        InterpError::M67WithComp
                    } else {
                        InterpError::M68WithComp
                    });
                }
                let e = round_to_int(block.e_number);
                if !block.e_flag || e < 0 {
                    return Err(InterpError::AnalogIndex(m));
                }
                if m == 67 {
                    canon.set_motion_output_value(e, block.q_number);
                } else {
                    canon.set_aux_output_value(e, block.q_number);
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// M66: wait for an input.
    fn convert_wait_input(
        &mut self,
        block: &Block,
        canon: &mut dyn Canon,
        comp: bool,
    ) -> Result<()> {
        if block.p_flag && block.e_flag {
            return Err(InterpError::M66BothInputs);
        }
        let l = round_to_int(block.l_number as f64);
        if block.q_number <= 0.0 && block.l_flag && l > 0 {
            return Err(InterpError::M66ZeroTimeout);
        }
        if block.e_flag && block.l_flag && l != 0 {
            return Err(InterpError::M66AnalogWait);
        }
        let p = round_to_int(block.p_number);
        let e = round_to_int(block.e_number);
        if (block.p_flag && p < 0) || (block.e_flag && e < 0) || (!block.p_flag && !block.e_flag) {
            return Err(InterpError::M66NoInput);
        }
        if block.p_flag {
            let wait_type = if block.l_flag { l } else { 0 };
            let timeout = if block.q_number > 0.0 {
                block.q_number
            } else {
                0.0
            };
            if comp {
                return Err(InterpError::M66DigitalWithComp);
            }
            if canon
                .wait_input(p, InputKind::Digital, wait_type, timeout)
                .is_err()
            {
                return Err(InterpError::M66DigitalRange);
            }
            self.s.input_flag = true;
            self.s.input_index = p;
            self.s.input_digital = true;
        } else {
            if comp {
                return Err(InterpError::M66AnalogWithComp);
            }
            if canon.wait_input(e, InputKind::Analog, 0, 0.0).is_err() {
                return Err(InterpError::M66AnalogRange);
            }
            self.s.input_flag = true;
            self.s.input_index = e;
            self.s.input_digital = false;
        }
        Ok(())
    }

    fn convert_overrides(
        &mut self,
        block: &Block,
        canon: &mut dyn Canon,
        comp: bool,
    ) -> Result<()> {
        let m = block.m_modes[9];
        if m == -1 {
            return Ok(());
        }
        let enable = match m {
            48 => true,
            49 => false,
            _ => block.p_number != 0.0,
        };
        if comp {
            return Err(if enable {
                InterpError::EnableOverridesWithComp
            } else {
                InterpError::DisableOverridesWithComp
            });
        }
        let count = self.s.spindles.len() as i32;
        match (m, enable) {
            (48, _) => {
                canon.enable_feed_override();
                (0..count).for_each(|n| canon.enable_speed_override(n));
                (self.s.feed_override, self.s.speed_override) = (true, true);
            }
            (49, _) => {
                canon.disable_feed_override();
                (0..count).for_each(|n| canon.disable_speed_override(n));
                (self.s.feed_override, self.s.speed_override) = (false, false);
            }
            (50, true) => canon.enable_feed_override(),
            (50, false) => canon.disable_feed_override(),
            (51, _) => {
                let n = self
                    .selected_spindles(block, false)
                    .ok_or(InterpError::SpindleNumber("M51 command"))?
                    .start as i32;
                if enable {
                    canon.enable_speed_override(n);
                } else {
                    canon.disable_speed_override(n);
                }
            }
            (52, true) => canon.enable_adaptive_feed(),
            (52, false) => canon.disable_adaptive_feed(),
            (53, true) => canon.enable_feed_hold(),
            _ => canon.disable_feed_hold(),
        }
        let s = &mut self.s;
        match m {
            50 => s.feed_override = enable,
            51 => s.speed_override = enable,
            52 => s.adaptive_feed = enable,
            53 => s.feed_hold = enable,
            _ => {}
        }
        Ok(())
    }
}
