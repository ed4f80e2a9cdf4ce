//! [`rejects!`]: generates everything about a refusal from its one
//! description in [`super::reject`].
//!
//! A refusal travels as a reason code, two integer detail words (`n0`,
//! `n1`) and three float detail words (`f0`..`f2`); each field of a
//! refusal names the word it travels in (`n` is both integer words, for a
//! value that needs two). Unused words are zero.

use super::{ConfigProblem, Direction, Feature, Quantity, WireError};

/// A rejection as it travels: reason code, integer details, float
/// details.
pub type RejectWire = (u64, [u64; 2], [f64; 3]);

/// A value that travels in one integer detail word.
pub(crate) trait IntDetail: Sized {
    /// The word.
    fn to_word(self) -> u64;
    /// The value of a word; `None` if no value has it.
    fn from_word(w: u64) -> Option<Self>;
}

impl IntDetail for usize {
    fn to_word(self) -> u64 {
        self as u64
    }
    fn from_word(w: u64) -> Option<Self> {
        usize::try_from(w).ok()
    }
}

/// Sign-extended, as the command record's joint word.
impl IntDetail for i32 {
    fn to_word(self) -> u64 {
        i64::from(self) as u64
    }
    fn from_word(w: u64) -> Option<Self> {
        i32::try_from(w as i64).ok()
    }
}

impl IntDetail for bool {
    fn to_word(self) -> u64 {
        u64::from(self)
    }
    fn from_word(w: u64) -> Option<Self> {
        match w {
            0 => Some(false),
            1 => Some(true),
            _ => None,
        }
    }
}

/// The coded enums travel as their codes.
macro_rules! int_detail_by_code {
    ($($t:ty),*) => {$(
        impl IntDetail for $t {
            fn to_word(self) -> u64 {
                self.code()
            }
            fn from_word(w: u64) -> Option<Self> {
                Self::from_code(w)
            }
        }
    )*};
}

int_detail_by_code!(Direction, Quantity, Feature, ConfigProblem);

/// A value that travels in both integer detail words.
pub(crate) trait PairDetail: Sized {
    /// The two words.
    fn to_words(self) -> [u64; 2];
    /// The value of two words; `None` if no value has them.
    fn from_words(w: [u64; 2]) -> Option<Self>;
}

impl PairDetail for WireError {
    fn to_words(self) -> [u64; 2] {
        let (code, detail) = self.code();
        [code, detail]
    }
    fn from_words(w: [u64; 2]) -> Option<Self> {
        WireError::from_code(w[0], w[1])
    }
}

/// Stores field value `$v` in detail word `$slot` of the wire tuple `$w`.
macro_rules! put_detail {
    ($w:ident, n0, $v:expr) => {
        $w.1[0] = $crate::vocab::reject_macro::IntDetail::to_word($v)
    };
    ($w:ident, n1, $v:expr) => {
        $w.1[1] = $crate::vocab::reject_macro::IntDetail::to_word($v)
    };
    ($w:ident, n, $v:expr) => {
        $w.1 = $crate::vocab::reject_macro::PairDetail::to_words($v)
    };
    ($w:ident, f0, $v:expr) => {
        $w.2[0] = $v
    };
    ($w:ident, f1, $v:expr) => {
        $w.2[1] = $v
    };
    ($w:ident, f2, $v:expr) => {
        $w.2[2] = $v
    };
}

/// Reads a field value from detail word `$slot` (`?` on a word no value
/// has).
macro_rules! get_detail {
    ($n:ident, $f:ident, n0) => {
        $crate::vocab::reject_macro::IntDetail::from_word($n[0])?
    };
    ($n:ident, $f:ident, n1) => {
        $crate::vocab::reject_macro::IntDetail::from_word($n[1])?
    };
    ($n:ident, $f:ident, n) => {
        $crate::vocab::reject_macro::PairDetail::from_words($n)?
    };
    ($n:ident, $f:ident, f0) => {
        $f[0]
    };
    ($n:ident, $f:ident, f1) => {
        $f[1]
    };
    ($n:ident, $f:ident, f2) => {
        $f[2]
    };
}

/// Declares the refusal enum from one description per refusal:
///
/// ```text
/// /// docs
/// Variant { /// docs
///           field: Type = slot, ... } = code, "short name" => "text", args...;
/// ```
///
/// and generates its reason code ([`Reject::code`](super::Reject::code)),
/// its wire form and back ([`Reject::to_wire`](super::Reject::to_wire),
/// [`Reject::from_wire`](super::Reject::from_wire)), the short names of the
/// codes ([`result_name`](super::result_name)) and its text (`Display`;
/// the text is a format string over the fields, with extra arguments
/// where a field is shown otherwise).
macro_rules! rejects {
    (
        $(#[doc = $doc:literal])*
        #[derive($($derive:ident),*)]
        pub enum $name:ident {
            $(
                $(#[doc = $vdoc:literal])*
                $variant:ident $({
                    $(
                        $(#[doc = $fdoc:literal])*
                        $field:ident : $ty:ty = $slot:ident
                    ),+ $(,)?
                })? = $code:literal, $short:literal => $text:literal $(, $arg:expr)*;
            )+
        }
    ) => {
        $(#[doc = $doc])*
        #[derive($($derive),*)]
        pub enum $name {
            $(
                $(#[doc = $vdoc])*
                $variant $({
                    $(
                        $(#[doc = $fdoc])*
                        $field: $ty,
                    )+
                })?,
            )+
        }

        impl $name {
            /// The reason code on the wire (never 0, which means accepted).
            pub fn code(&self) -> u64 {
                match self {
                    $($name::$variant { .. } => $code,)+
                }
            }

            /// (code, two integer details, three float details).
            pub fn to_wire(self) -> $crate::vocab::RejectWire {
                let mut w: $crate::vocab::RejectWire = (0, [0; 2], [0.0; 3]);
                match self {
                    $($name::$variant { $($($field,)+)? } => {
                        w.0 = $code;
                        $($($crate::vocab::reject_macro::put_detail!(w, $slot, $field);)+)?
                    })+
                }
                w
            }

            /// The refusal of a reason code and its details; `None` if the
            /// code or a detail is not one a refusal has.
            pub fn from_wire(code: u64, n: [u64; 2], f: [f64; 3]) -> Option<$name> {
                Some(match code {
                    $($code => $name::$variant {
                        $($($field: $crate::vocab::reject_macro::get_detail!(n, f, $slot),)+)?
                    },)+
                    _ => return None,
                })
            }
        }

        /// Short name of a result code (0 accepted, else a reason code), for
        /// status displays.
        pub fn result_name(code: u64) -> &'static str {
            match code {
                0 => "accepted",
                $($code => concat!("rejected: ", $short),)+
                _ => "unknown",
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                match *self {
                    $($name::$variant { $($($field,)+)? } => write!(f, $text $(, $arg)*),)+
                }
            }
        }
    };
}

pub(crate) use {get_detail, put_detail, rejects};
