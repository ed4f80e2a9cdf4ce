//! G- and M-code numbers and their modal groups.
//!
//! G-codes are kept as ten times their number (G38.2 is 382), as in
//! LinuxCNC, so the decimal ones are exact integers.

#![allow(missing_docs)] // the names say what they are

pub const G_0: i32 = 0;
pub const G_1: i32 = 10;
pub const G_2: i32 = 20;
pub const G_3: i32 = 30;
pub const G_4: i32 = 40;
pub const G_5: i32 = 50;
pub const G_5_1: i32 = 51;
pub const G_5_2: i32 = 52;
pub const G_5_3: i32 = 53;
pub const G_7: i32 = 70;
pub const G_8: i32 = 80;
pub const G_10: i32 = 100;
pub const G_17: i32 = 170;
pub const G_17_1: i32 = 171;
pub const G_18: i32 = 180;
pub const G_18_1: i32 = 181;
pub const G_19: i32 = 190;
pub const G_19_1: i32 = 191;
pub const G_20: i32 = 200;
pub const G_21: i32 = 210;
pub const G_28: i32 = 280;
pub const G_28_1: i32 = 281;
pub const G_30: i32 = 300;
pub const G_30_1: i32 = 301;
pub const G_33: i32 = 330;
pub const G_33_1: i32 = 331;
pub const G_38_2: i32 = 382;
pub const G_38_3: i32 = 383;
pub const G_38_4: i32 = 384;
pub const G_38_5: i32 = 385;
pub const G_40: i32 = 400;
pub const G_41: i32 = 410;
pub const G_41_1: i32 = 411;
pub const G_42: i32 = 420;
pub const G_42_1: i32 = 421;
pub const G_43: i32 = 430;
pub const G_43_1: i32 = 431;
pub const G_43_2: i32 = 432;
pub const G_49: i32 = 490;
pub const G_52: i32 = 520;
pub const G_53: i32 = 530;
pub const G_54: i32 = 540;
pub const G_55: i32 = 550;
pub const G_56: i32 = 560;
pub const G_57: i32 = 570;
pub const G_58: i32 = 580;
pub const G_59: i32 = 590;
pub const G_59_1: i32 = 591;
pub const G_59_2: i32 = 592;
pub const G_59_3: i32 = 593;
pub const G_61: i32 = 610;
pub const G_61_1: i32 = 611;
pub const G_64: i32 = 640;
pub const G_70: i32 = 700;
pub const G_71: i32 = 710;
pub const G_71_1: i32 = 711;
pub const G_71_2: i32 = 712;
pub const G_72: i32 = 720;
pub const G_72_1: i32 = 721;
pub const G_72_2: i32 = 722;
pub const G_73: i32 = 730;
pub const G_74: i32 = 740;
pub const G_76: i32 = 760;
pub const G_80: i32 = 800;
pub const G_81: i32 = 810;
pub const G_82: i32 = 820;
pub const G_83: i32 = 830;
pub const G_84: i32 = 840;
pub const G_85: i32 = 850;
pub const G_86: i32 = 860;
pub const G_87: i32 = 870;
pub const G_88: i32 = 880;
pub const G_89: i32 = 890;
pub const G_90: i32 = 900;
pub const G_90_1: i32 = 901;
pub const G_91: i32 = 910;
pub const G_91_1: i32 = 911;
pub const G_92: i32 = 920;
pub const G_92_1: i32 = 921;
pub const G_92_2: i32 = 922;
pub const G_92_3: i32 = 923;
pub const G_93: i32 = 930;
pub const G_94: i32 = 940;
pub const G_95: i32 = 950;
pub const G_96: i32 = 960;
pub const G_97: i32 = 970;
pub const G_98: i32 = 980;
pub const G_99: i32 = 990;

/// Indices into a block's G-mode array: the modal groups.
pub const GM_MODAL_0: usize = 0;
pub const GM_MOTION: usize = 1;
pub const GM_SET_PLANE: usize = 2;
pub const GM_DISTANCE_MODE: usize = 3;
pub const GM_IJK_DISTANCE_MODE: usize = 4;
pub const GM_FEED_MODE: usize = 5;
pub const GM_LENGTH_UNITS: usize = 6;
pub const GM_CUTTER_COMP: usize = 7;
pub const GM_TOOL_LENGTH_OFFSET: usize = 8;
/// G92.1, G92.2, G92.3: a group of their own in LinuxCNC 2.9 (they may
/// share a block with G92, G52, G10, G28 and run after them).
pub const GM_G92_RESET: usize = 9;
pub const GM_RETRACT_MODE: usize = 10;
pub const GM_COORD_SYSTEM: usize = 12;
pub const GM_CONTROL_MODE: usize = 13;
pub const GM_SPINDLE_MODE: usize = 14;
pub const GM_LATHE_DIAMETER_MODE: usize = 15;

/// Number of G modal group slots in a block.
pub const G_GROUPS: usize = 16;
/// Number of M modal group slots in a block.
pub const M_GROUPS: usize = 11;

/// The modal group of a G-code (times ten), or `None` for an unknown code.
pub fn g_group(code: i32) -> Option<usize> {
    let group = match code {
        G_4 | G_10 | G_28 | G_28_1 | G_30 | G_30_1 | G_52 | G_53 | G_92 | G_5_3 => GM_MODAL_0,
        G_92_1 | G_92_2 | G_92_3 => GM_G92_RESET,
        G_0 | G_1 | G_2 | G_3 | G_5 | G_5_1 | G_5_2 | G_33 | G_33_1 | G_38_2 | G_38_3 | G_38_4
        | G_38_5 | G_70 | G_71 | G_71_1 | G_71_2 | G_72 | G_72_1 | G_72_2 | G_73 | G_74 | G_76 => {
            GM_MOTION
        }
        G_80..=G_89 if code % 10 == 0 => GM_MOTION,
        G_17 | G_17_1 | G_18 | G_18_1 | G_19 | G_19_1 => GM_SET_PLANE,
        G_90 | G_91 => GM_DISTANCE_MODE,
        G_90_1 | G_91_1 => GM_IJK_DISTANCE_MODE,
        G_93 | G_94 | G_95 => GM_FEED_MODE,
        G_20 | G_21 => GM_LENGTH_UNITS,
        G_40 | G_41 | G_41_1 | G_42 | G_42_1 => GM_CUTTER_COMP,
        G_43 | G_43_1 | G_43_2 | G_49 => GM_TOOL_LENGTH_OFFSET,
        G_98 | G_99 => GM_RETRACT_MODE,
        G_54 | G_55 | G_56 | G_57 | G_58 | G_59 | G_59_1 | G_59_2 | G_59_3 => GM_COORD_SYSTEM,
        G_61 | G_61_1 | G_64 => GM_CONTROL_MODE,
        G_96 | G_97 => GM_SPINDLE_MODE,
        G_7 | G_8 => GM_LATHE_DIAMETER_MODE,
        _ => return None,
    };
    Some(group)
}

/// The modal group of an M-code, or `None` for an unknown code.
pub fn m_group(code: i32) -> Option<usize> {
    let group = match code {
        0 | 1 | 2 | 30 | 60 | 99 => 4,
        62..=68 => 5,
        6 | 61 => 6,
        3 | 4 | 5 | 19 | 70..=73 => 7,
        7..=9 => 8,
        48..=53 => 9,
        100..=199 => 10,
        _ => return None,
    };
    Some(group)
}

/// True for the canned cycles (G73, G74, G81 to G89).
pub fn is_cycle(motion: i32) -> bool {
    motion == G_73 || motion == G_74 || ((G_81..=G_89).contains(&motion) && motion % 10 == 0)
}

/// The text of a G-code (times ten) as LinuxCNC writes it: `G38.2`, `G1`.
pub fn g_text(code: i32) -> String {
    if code % 10 != 0 {
        format!("G{}.{}", code / 10, code % 10)
    } else {
        format!("G{}", code / 10)
    }
}
