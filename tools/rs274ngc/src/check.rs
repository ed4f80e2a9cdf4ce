//! Checks on a block once read: which motion it will make, and whether
//! its words fit together (LinuxCNC's enhance_block and check_items).

use crate::block::{round_to_int, Block, OType};
use crate::codes::*;
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::setup::DistanceMode;

/// Most M-codes one line may hold.
const MAX_EMS: usize = 4;

impl Interp {
    /// Decide the block's motion and check the use of axis words.
    pub(crate) fn enhance_block(&self, block: &mut Block) -> Result<()> {
        let polar = block.radius_flag || block.theta_flag;
        if polar {
            if self.s.plane != crate::canon::Plane::Xy {
                return Err(InterpError::PolarNotG17);
            }
            if block.x_flag {
                return Err(InterpError::PolarAndX);
            }
            if block.y_flag {
                return Err(InterpError::PolarAndY);
            }
        }
        let axis = block.has_axis();
        let ijk = block.i_flag || block.j_flag || block.k_flag;
        let mode0 = block.g_modes[GM_MODAL_0];
        let mode1 = block.g_modes[GM_MOTION];
        let covets_axes = matches!(mode0, G_10 | G_28 | G_30 | G_52 | G_92);
        if mode1 != -1 {
            if mode1 == G_80 {
                if (polar || axis) && !covets_axes {
                    return Err(InterpError::AxisWithG80);
                }
                if polar && mode0 == G_92 {
                    return Err(InterpError::PolarOnlyMotion);
                }
                if !axis && (mode0 == G_52 || mode0 == G_92) {
                    return Err(InterpError::AxesMissingG52G92);
                }
            } else {
                if covets_axes {
                    return Err(InterpError::TwoAxisGCodes);
                }
                let may_lack_axes = matches!(mode1, G_0 | G_1 | G_2 | G_3 | G_5_2)
                    || matches!(
                        mode1,
                        G_70 | G_71 | G_71_1 | G_71_2 | G_72 | G_72_1 | G_72_2
                    );
                if !axis && !polar && !may_lack_axes {
                    return Err(InterpError::AxesMissingMotion);
                }
            }
            block.motion_to_be = mode1;
        } else if covets_axes {
            if polar && mode0 == G_92 {
                return Err(InterpError::PolarOnlyMotion);
            }
            if !axis && (mode0 == G_52 || mode0 == G_92) {
                return Err(InterpError::AxesMissingG52G92);
            }
        } else if axis || polar {
            let g43_1 = block.g_modes[GM_TOOL_LENGTH_OFFSET] == G_43_1
                || block.g_modes[GM_TOOL_LENGTH_OFFSET] == G_43_2;
            if (self.s.motion_mode == -1 || self.s.motion_mode == G_80) && !g43_1 {
                return Err(InterpError::AxisWithoutGCode);
            }
            if !g43_1 {
                block.motion_to_be = self.s.motion_mode;
            }
        } else if ijk && (self.s.motion_mode == G_2 || self.s.motion_mode == G_3) {
            block.motion_to_be = self.s.motion_mode;
        }
        if polar && block.motion_to_be == -1 {
            return Err(InterpError::PolarOnlyMotion);
        }
        Ok(())
    }

    /// Check the block's G-codes, M-codes and other words.
    pub(crate) fn check_items(&self, block: &Block) -> Result<()> {
        self.check_g_codes(block)?;
        if block.m_count > MAX_EMS {
            return Err(InterpError::TooManyMCodes);
        }
        check_other_codes(block)
    }

    fn check_g_codes(&self, block: &Block) -> Result<()> {
        let mode0 = block.g_modes[GM_MODAL_0];
        let mode1 = block.g_modes[GM_MOTION];
        match mode0 {
            -1 => {}
            G_4 => {
                if block.p_number == -1.0 {
                    return Err(InterpError::DwellMissing);
                }
                if mode1 == G_2 || mode1 == G_3 {
                    return Err(InterpError::G4WithArc);
                }
            }
            G_10 => {
                let p = block.p_number;
                let p_int = if p >= 0.0 {
                    crate::read::c_int(p + 0.5)
                } else {
                    crate::read::c_int(p - 0.5)
                };
                let l = block.l_number;
                if !matches!(l, 0 | 1 | 2 | 10 | 11 | 20) {
                    return Err(InterpError::G10BadL);
                }
                if (p + 0.0001) - p_int as f64 > 0.0002 {
                    return Err(InterpError::G10PNotInteger);
                }
                if (l == 2 || l == 20) && !(0..=9).contains(&p_int) {
                    return Err(InterpError::G10PRangeCoord(l));
                }
                if (l == 1 || l == 10 || l == 11) && p_int < 1 {
                    return Err(InterpError::G10PRangeTool(l));
                }
            }
            G_5_3 if mode1 != G_5_2 && mode1 != -1 => {
                return Err(InterpError::NurbsInterrupted);
            }
            G_53 => {
                if block.motion_to_be != G_0 && block.motion_to_be != G_1 {
                    return Err(InterpError::G53NeedsG0G1);
                }
                if block.g_modes[GM_DISTANCE_MODE] == G_91
                    || (block.g_modes[GM_DISTANCE_MODE] != G_90
                        && self.s.distance_mode == DistanceMode::Incremental)
                {
                    return Err(InterpError::G53Incremental);
                }
            }
            _ => {}
        }
        Ok(())
    }
}

fn check_other_codes(block: &Block) -> Result<()> {
    let motion = block.motion_to_be;
    let cycle = is_cycle(motion);
    if block.a_flag && cycle {
        return Err(InterpError::AInCycle);
    }
    if block.b_flag && cycle {
        return Err(InterpError::BInCycle);
    }
    if block.c_flag && cycle {
        return Err(InterpError::CInCycle);
    }
    let g7 = block.g_modes[GM_CUTTER_COMP];
    let lathe_cycle = matches!(
        motion,
        G_70 | G_71 | G_71_1 | G_71_2 | G_72 | G_72_1 | G_72_2
    );
    // LinuxCNC 2.9 takes I (increment) and R (retract) with the roughing
    // cycles only, P (passes) with G70 only, and J, K, L with none.
    let roughing = lathe_cycle && motion != G_70;
    if block.d_flag
        && !matches!(g7, G_41 | G_42 | G_41_1 | G_42_1)
        && block.g_modes[GM_SPINDLE_MODE] != G_96
        && !lathe_cycle
    {
        return Err(InterpError::DWordUnused);
    }
    if block.dollar_flag
        && !matches!(block.m_modes[7], 3 | 4 | 5 | 19)
        && block.m_modes[9] != 51
        && !matches!(motion, G_33 | G_33_1 | G_76)
        && !block.s_flag
    {
        return Err(InterpError::DollarUnused);
    }
    let m5 = block.m_modes[5];
    // G33 and G33.1 take E too, though the message does not say so.
    if block.e_flag && !matches!(motion, G_76 | G_70 | G_33 | G_33_1) && !matches!(m5, 66..=68) {
        return Err(InterpError::EWordUnused);
    }
    let g8 = block.g_modes[GM_TOOL_LENGTH_OFFSET];
    if block.h_flag && g8 != G_43 && motion != G_76 && g8 != G_43_2 {
        return Err(InterpError::HWordUnused);
    }
    let g0 = block.g_modes[GM_MODAL_0];
    let arc_or_spline = matches!(motion, G_2 | G_3 | G_5 | G_5_1);
    if block.i_flag
        && !arc_or_spline
        && !matches!(motion, G_76 | G_87 | G_33_1)
        && g0 != G_10
        && !roughing
    {
        return Err(InterpError::IWordUnused);
    }
    if block.j_flag && !arc_or_spline && !matches!(motion, G_76 | G_87) && g0 != G_10 {
        return Err(InterpError::JWordUnused);
    }
    if block.k_flag && !matches!(motion, G_2 | G_3 | G_33 | G_33_1 | G_76 | G_87) {
        return Err(InterpError::KWordUnused);
    }
    // G74 takes no L (LinuxCNC's check predates it).
    if block.l_number != -1
        && !((cycle && motion != G_74) || motion == G_76 || motion == G_5_2)
        && g0 != G_10
        && !matches!(g7, G_41 | G_41_1 | G_42 | G_42_1)
        && m5 != 66
        && block.o_type != OType::M98
    {
        return Err(InterpError::LWordUnused);
    }
    if block.p_flag {
        check_p_word(block, motion)?;
    }
    check_q_r_and_threading(block, cycle, lathe_cycle, roughing)
}

/// The Q, R and S words and G33/G76's own words.
fn check_q_r_and_threading(
    block: &Block,
    cycle: bool,
    lathe_cycle: bool,
    roughing: bool,
) -> Result<()> {
    let motion = block.motion_to_be;
    let g0 = block.g_modes[GM_MODAL_0];
    let g7 = block.g_modes[GM_CUTTER_COMP];
    let m5 = block.m_modes[5];
    if block.q_number != -1.0
        && !matches!(motion, G_83 | G_73 | G_5 | G_76)
        && !lathe_cycle
        && !matches!(m5, 66..=68)
        && g0 != G_10
        && block.m_modes[6] != 61
        && block.g_modes[GM_CONTROL_MODE] != G_64
        && block.m_modes[7] != 19
        && !block.user_m
    {
        return Err(InterpError::QWordUnused);
    }
    if block.r_flag {
        let uses_r = matches!(motion, G_2 | G_3 | G_76 | G_73 | G_74)
            || cycle
            || roughing
            || matches!(g7, G_41_1 | G_42_1)
            || g0 == G_10
            || block.m_modes[7] == 19;
        if !uses_r {
            return Err(InterpError::RWordUnused);
        }
        if block.m_modes[7] == 19 && (block.r_number > 360.0 || block.r_number < 0.0) {
            return Err(InterpError::M19RRange);
        }
    }
    if !block.s_flag && block.g_modes[GM_SPINDLE_MODE] == G_96 {
        return Err(InterpError::SMissingG96);
    }
    if motion == G_33 || motion == G_33_1 {
        if !block.k_flag {
            return Err(InterpError::KMissingG33);
        }
        if block.f_flag {
            return Err(InterpError::FWithG33);
        }
    }
    if motion == G_76 {
        if block.p_number == -1.0 {
            return Err(InterpError::PMissingG76);
        }
        if !block.i_flag || !block.j_flag || !block.k_flag {
            return Err(InterpError::IjkMissingG76);
        }
    }
    Ok(())
}

fn check_p_word(block: &Block, motion: i32) -> Result<()> {
    let g0 = block.g_modes[GM_MODAL_0];
    let m9 = block.m_modes[9];
    let m5 = block.m_modes[5];
    let used = matches!(g0, G_10 | G_4)
        || block.g_modes[GM_CONTROL_MODE] == G_64
        || matches!(
            motion,
            G_76 | G_82 | G_86 | G_88 | G_89 | G_5 | G_5_2 | G_2 | G_3 | G_74 | G_84 | G_70
        )
        || matches!(m9, 50..=53)
        || matches!(m5, 62..=66)
        || block.m_modes[7] == 19
        || block.o_type == OType::M98
        || block.user_m;
    if !used {
        return Err(InterpError::PWordUnused);
    }
    let p_value = round_to_int(block.p_number);
    let arc = motion == G_2 || motion == G_3;
    if (arc || block.m_modes[7] == 19) && (p_value as f64 - block.p_number).abs() > 0.001 {
        return Err(InterpError::PNotIntegerArc);
    }
    if block.m_modes[7] == 19 && !(0..=2).contains(&p_value) {
        return Err(InterpError::M19PRange);
    }
    if arc && p_value < 1 {
        return Err(InterpError::ArcPTooSmall);
    }
    Ok(())
}
