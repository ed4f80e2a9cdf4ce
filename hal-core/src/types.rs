//! HAL value types, pin directions and parameter directions, with the
//! encoding every value cell in the segment uses.

use std::fmt;

/// The type of a pin, parameter or signal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HalType {
    /// `bit`: a boolean.
    Bit,
    /// `float`: an f64.
    Float,
    /// `s32`: a signed 32-bit integer.
    S32,
    /// `u32`: an unsigned 32-bit integer.
    U32,
    /// `s64`: a signed 64-bit integer.
    S64,
    /// `u64`: an unsigned 64-bit integer.
    U64,
    /// `port`: a one-way byte stream between an output and an input pin
    /// ([`crate::PortIn`], [`crate::PortOut`]); its value is the size of
    /// its signal's buffer.
    Port,
}

impl HalType {
    /// Every type that holds a value (every type but `port`), in
    /// LinuxCNC's order: what parameters, rings and conversions take.
    pub const ALL: [HalType; 6] = [
        HalType::Bit,
        HalType::Float,
        HalType::S32,
        HalType::U32,
        HalType::S64,
        HalType::U64,
    ];

    /// The name halcmd uses (`bit`, `float`, `s32`, ...).
    pub fn name(self) -> &'static str {
        match self {
            HalType::Bit => "bit",
            HalType::Float => "float",
            HalType::S32 => "s32",
            HalType::U32 => "u32",
            HalType::S64 => "s64",
            HalType::U64 => "u64",
            HalType::Port => "port",
        }
    }

    /// Parses a halcmd type name.
    pub fn from_name(name: &str) -> Option<HalType> {
        HalType::ALL
            .into_iter()
            .chain([HalType::Port])
            .find(|t| t.name() == name)
    }

    /// The type's number in the segment's records and in the layouts
    /// other shared structures build on them (1 bit, 2 float, 3 s32,
    /// 4 u32, 5 s64, 6 u64, 7 port). Not LinuxCNC's numbering, which
    /// puts the port at 5.
    pub fn code(self) -> u32 {
        match self {
            HalType::Bit => 1,
            HalType::Float => 2,
            HalType::S32 => 3,
            HalType::U32 => 4,
            HalType::S64 => 5,
            HalType::U64 => 6,
            HalType::Port => 7,
        }
    }

    /// The type numbered `code` by [`HalType::code`].
    pub fn from_code(code: u32) -> Option<HalType> {
        HalType::ALL
            .into_iter()
            .chain([HalType::Port])
            .find(|t| t.code() == code)
    }
}

impl fmt::Display for HalType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Direction of a pin, seen from the component that owns it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PinDir {
    /// Read by its component, driven by a signal or `setp`.
    In,
    /// Written by its component only; at most one per signal.
    Out,
    /// Read and written by its component; shares a signal with other I/O pins but no output pin.
    Io,
}

impl PinDir {
    /// The label `show pin` uses (`IN`, `OUT`, `I/O`).
    pub fn label(self) -> &'static str {
        match self {
            PinDir::In => "IN",
            PinDir::Out => "OUT",
            PinDir::Io => "I/O",
        }
    }

    pub(crate) fn code(self) -> u32 {
        match self {
            PinDir::In => 16,
            PinDir::Out => 32,
            PinDir::Io => 48,
        }
    }

    pub(crate) fn from_code(code: u32) -> Option<PinDir> {
        [PinDir::In, PinDir::Out, PinDir::Io]
            .into_iter()
            .find(|d| d.code() == code)
    }
}

impl fmt::Display for PinDir {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}

/// Whether a parameter may be changed from outside its component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ParamDir {
    /// Read-only: only the owning component writes it.
    Ro,
    /// Read-write: `setp` may change it.
    Rw,
}

impl ParamDir {
    /// The label `show param` uses (`RO`, `RW`).
    pub fn label(self) -> &'static str {
        match self {
            ParamDir::Ro => "RO",
            ParamDir::Rw => "RW",
        }
    }

    pub(crate) fn code(self) -> u32 {
        match self {
            ParamDir::Ro => 64,
            ParamDir::Rw => 192,
        }
    }

    pub(crate) fn from_code(code: u32) -> Option<ParamDir> {
        [ParamDir::Ro, ParamDir::Rw]
            .into_iter()
            .find(|d| d.code() == code)
    }
}

/// A typed HAL value, as read from or written to a pin, param or signal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A `bit` value.
    Bit(bool),
    /// A `float` value.
    Float(f64),
    /// An `s32` value.
    S32(i32),
    /// A `u32` value.
    U32(u32),
    /// An `s64` value.
    S64(i64),
    /// A `u64` value.
    U64(u64),
    /// A `port`: the size in bytes of its signal's buffer (0: none yet).
    Port(u32),
}

impl Value {
    /// The type of this value.
    pub fn hal_type(self) -> HalType {
        match self {
            Value::Bit(_) => HalType::Bit,
            Value::Float(_) => HalType::Float,
            Value::S32(_) => HalType::S32,
            Value::U32(_) => HalType::U32,
            Value::S64(_) => HalType::S64,
            Value::U64(_) => HalType::U64,
            Value::Port(_) => HalType::Port,
        }
    }

    /// The zero value of a type.
    pub fn zero(t: HalType) -> Value {
        Value::from_bits(t, 0)
    }

    /// The 64-bit cell encoding of this value.
    pub fn to_bits(self) -> u64 {
        match self {
            Value::Bit(b) => b as u64,
            Value::Float(f) => f.to_bits(),
            Value::S32(v) => v as i64 as u64,
            Value::U32(v) => v as u64,
            Value::S64(v) => v as u64,
            Value::U64(v) => v,
            // A buffer's place is the segment's business: the value says
            // only its size.
            Value::Port(size) => u64::from(size),
        }
    }

    /// Decodes a cell of type `t`. Any bit pattern decodes to some value, so
    /// a corrupted cell can never cause undefined behaviour.
    pub fn from_bits(t: HalType, bits: u64) -> Value {
        match t {
            HalType::Bit => Value::Bit(bits != 0),
            HalType::Float => Value::Float(f64::from_bits(bits)),
            HalType::S32 => Value::S32(bits as i32),
            HalType::U32 => Value::U32(bits as u32),
            HalType::S64 => Value::S64(bits as i64),
            HalType::U64 => Value::U64(bits),
            HalType::Port => Value::Port(bits as u32),
        }
    }
}

/// A Rust type that can be the value of a pin or parameter.
pub trait PinValue: Copy + Send + Sync + 'static {
    /// The HAL type this Rust type stands for.
    const HAL_TYPE: HalType;
    /// Encodes into a value cell.
    fn to_bits(self) -> u64;
    /// Decodes a value cell.
    fn from_bits(bits: u64) -> Self;
}

macro_rules! pin_value {
    ($t:ty, $ht:ident, |$v:ident| $enc:expr, |$b:ident| $dec:expr) => {
        impl PinValue for $t {
            const HAL_TYPE: HalType = HalType::$ht;
            #[inline(always)]
            fn to_bits(self) -> u64 {
                let $v = self;
                $enc
            }
            #[inline(always)]
            fn from_bits($b: u64) -> Self {
                $dec
            }
        }
    };
}

pin_value!(bool, Bit, |v| v as u64, |b| b != 0);
pin_value!(f64, Float, |v| v.to_bits(), |b| f64::from_bits(b));
pin_value!(i32, S32, |v| v as i64 as u64, |b| b as i32);
pin_value!(u32, U32, |v| v as u64, |b| b as u32);
pin_value!(i64, S64, |v| v as u64, |b| b as i64);
pin_value!(u64, U64, |v| v, |b| b);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip() {
        for t in HalType::ALL.into_iter().chain([HalType::Port]) {
            assert_eq!(HalType::from_code(t.code()), Some(t));
            assert_eq!(HalType::from_name(t.name()), Some(t));
        }
        assert_eq!(HalType::from_code(0), None);
        assert_eq!(HalType::from_name("double"), None);
    }

    #[test]
    fn values_round_trip_through_cells() {
        let vals = [
            Value::Bit(true),
            Value::Float(-0.0),
            Value::Float(1e300),
            Value::S32(i32::MIN),
            Value::U32(u32::MAX),
            Value::S64(i64::MIN),
            Value::U64(u64::MAX),
        ];
        for v in vals {
            let back = Value::from_bits(v.hal_type(), v.to_bits());
            assert_eq!(back.to_bits(), v.to_bits());
        }
        assert_eq!(i32::from_bits((-5i32).to_bits()), -5);
        assert_eq!(Value::from_bits(HalType::Bit, 7), Value::Bit(true));
    }
}
