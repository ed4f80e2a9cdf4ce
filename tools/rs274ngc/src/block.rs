//! One block (line) of a program as read: the words found, with their
//! values already evaluated, and the O-word control item if any.
//!
//! The layout follows LinuxCNC's: a flag per word plus its value, and for
//! the words LinuxCNC marks absent by a sentinel (P, Q: -1; L, H: -1) the
//! same sentinel, because several of its checks compare against it.

use crate::codes::{G_GROUPS, M_GROUPS};

/// Number of arguments an O-word call may pass (#1 to #30).
pub const SUB_PARAMS: usize = 30;

/// The kinds of O-word lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[allow(missing_docs)]
pub enum OType {
    #[default]
    None,
    Sub,
    Endsub,
    Call,
    Do,
    While,
    If,
    Elseif,
    Else,
    Endif,
    Break,
    Continue,
    Endwhile,
    Return,
    Repeat,
    Endrepeat,
    M98,
    M99,
    /// A bare Fanuc-style program number line (`O1000`).
    Fanuc,
}

impl OType {
    /// The name LinuxCNC's messages use for this kind (`while`, `if`).
    pub fn name(self) -> &'static str {
        match self {
            OType::None => "none",
            OType::Sub => "sub",
            OType::Endsub => "endsub",
            OType::Call => "call",
            OType::Do => "do",
            OType::While => "while",
            OType::If => "if",
            OType::Elseif => "elseif",
            OType::Else => "else",
            OType::Endif => "endif",
            OType::Break => "break",
            OType::Continue => "continue",
            OType::Endwhile => "endwhile",
            OType::Return => "return",
            OType::Repeat => "repeat",
            OType::Endrepeat => "endrepeat",
            OType::M98 => "98",
            OType::M99 => "99",
            OType::Fanuc => "",
        }
    }
}

/// A block as read from one line.
#[derive(Debug, Clone)]
#[allow(missing_docs)] // the fields are the words of the same letter
pub struct Block {
    pub a_flag: bool,
    pub a_number: f64,
    pub b_flag: bool,
    pub b_number: f64,
    pub c_flag: bool,
    pub c_number: f64,
    /// The last comment of the line, without its parentheses.
    pub comment: Option<Vec<u8>>,
    pub d_flag: bool,
    pub d_number: f64,
    pub dollar_flag: bool,
    pub dollar_number: f64,
    pub e_flag: bool,
    pub e_number: f64,
    pub f_flag: bool,
    pub f_number: f64,
    /// G-codes read, by modal group; -1 where none.
    pub g_modes: [i32; G_GROUPS],
    pub h_flag: bool,
    pub h_number: i32,
    pub i_flag: bool,
    pub i_number: f64,
    pub j_flag: bool,
    pub j_number: f64,
    pub k_flag: bool,
    pub k_number: f64,
    pub l_flag: bool,
    pub l_number: i32,
    /// The N number, -1 where none.
    pub n_number: i32,
    /// The line (sequence) number the block was read from.
    pub line_number: i32,
    /// The motion this block will make (its own G-code of group 1, or the
    /// modal one when it has axis words); -1 where none.
    pub motion_to_be: i32,
    pub m_count: usize,
    /// M-codes read, by modal group; -1 where none.
    pub m_modes: [i32; M_GROUPS],
    pub user_m: bool,
    pub p_flag: bool,
    pub p_number: f64,
    pub q_flag: bool,
    pub q_number: f64,
    pub r_flag: bool,
    pub r_number: f64,
    pub s_flag: bool,
    pub s_number: f64,
    pub t_flag: bool,
    pub t_number: i32,
    pub u_flag: bool,
    pub u_number: f64,
    pub v_flag: bool,
    pub v_number: f64,
    pub w_flag: bool,
    pub w_number: f64,
    pub x_flag: bool,
    pub x_number: f64,
    pub y_flag: bool,
    pub y_number: f64,
    pub z_flag: bool,
    pub z_number: f64,
    /// Polar radius (`@`).
    pub radius_flag: bool,
    pub radius: f64,
    /// Polar angle (`^`).
    pub theta_flag: bool,
    pub theta: f64,
    /// Byte offset of the line in its file (where loops come back to).
    pub offset: u64,
    pub o_type: OType,
    /// The O-word's full name: global names as written, local ones
    /// prefixed with their subroutine's name and `#`.
    pub o_name: String,
    /// Arguments of an O-word call.
    pub params: Vec<f64>,
}

impl Default for Block {
    fn default() -> Self {
        Block {
            a_flag: false,
            a_number: 0.0,
            b_flag: false,
            b_number: 0.0,
            c_flag: false,
            c_number: 0.0,
            comment: None,
            d_flag: false,
            d_number: 0.0,
            dollar_flag: false,
            dollar_number: 0.0,
            e_flag: false,
            e_number: 0.0,
            f_flag: false,
            f_number: 0.0,
            g_modes: [-1; G_GROUPS],
            h_flag: false,
            h_number: -1,
            i_flag: false,
            i_number: 0.0,
            j_flag: false,
            j_number: 0.0,
            k_flag: false,
            k_number: 0.0,
            l_flag: false,
            l_number: -1,
            n_number: -1,
            line_number: -1,
            motion_to_be: -1,
            m_count: 0,
            m_modes: [-1; M_GROUPS],
            user_m: false,
            p_flag: false,
            p_number: -1.0,
            q_flag: false,
            q_number: -1.0,
            r_flag: false,
            r_number: 0.0,
            s_flag: false,
            s_number: 0.0,
            t_flag: false,
            t_number: 0,
            u_flag: false,
            u_number: 0.0,
            v_flag: false,
            v_number: 0.0,
            w_flag: false,
            w_number: 0.0,
            x_flag: false,
            x_number: 0.0,
            y_flag: false,
            y_number: 0.0,
            z_flag: false,
            z_number: 0.0,
            radius_flag: false,
            radius: 0.0,
            theta_flag: false,
            theta: 0.0,
            offset: 0,
            o_type: OType::None,
            o_name: String::new(),
            params: Vec::new(),
        }
    }
}

impl Block {
    /// True if any axis word (X Y Z A B C U V W) is present.
    pub fn has_axis(&self) -> bool {
        self.x_flag
            || self.y_flag
            || self.z_flag
            || self.a_flag
            || self.b_flag
            || self.c_flag
            || self.u_flag
            || self.v_flag
            || self.w_flag
    }

    /// The spindle the `$` word names, cut to an integer (as LinuxCNC
    /// does: `$1.6` is spindle 1, `$-1.5` means every spindle); None
    /// without a `$` word.
    pub fn dollar(&self) -> Option<i32> {
        self.dollar_flag.then_some(self.dollar_number as i32)
    }
}

/// C's `round_to_int`: round half away from zero, then truncate to `i32`.
pub fn round_to_int(x: f64) -> i32 {
    if x < 0.0 {
        (x - 0.5) as i32
    } else {
        (x + 0.5) as i32
    }
}
