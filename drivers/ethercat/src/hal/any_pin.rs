//! A HAL pin or parameter of any of lcec's types and directions, made
//! from a [`PinSpec`]: the binding handles every pin as a number (a bit
//! is 0 or 1; s32 and u32 are exact in an f64), so one table of pins
//! serves every slave type.

use hal_core::{HalHost, HostParam, HostPin, In, Io, Out, PinFactory, Result, Rw};

use crate::lcec::pins::{Kind, PinSpec, PinType, PinValue};

/// One exported pin or parameter, in host `H`.
pub(crate) enum AnyPin<H: HalHost> {
    BitIn(H::Pin<bool, In>),
    BitOut(H::Pin<bool, Out>),
    BitIo(H::Pin<bool, Io>),
    BitParam(H::Param<bool, Rw>),
    S32In(H::Pin<i32, In>),
    S32Out(H::Pin<i32, Out>),
    S32Io(H::Pin<i32, Io>),
    S32Param(H::Param<i32, Rw>),
    U32In(H::Pin<u32, In>),
    U32Out(H::Pin<u32, Out>),
    U32Io(H::Pin<u32, Io>),
    U32Param(H::Param<u32, Rw>),
    FloatIn(H::Pin<f64, In>),
    FloatOut(H::Pin<f64, Out>),
    FloatIo(H::Pin<f64, Io>),
    FloatParam(H::Param<f64, Rw>),
}

impl<H: HalHost> AnyPin<H> {
    /// Exports `spec` on `c` as `name`, with its initial value.
    pub(crate) fn export(c: &impl PinFactory<H>, name: &str, spec: &PinSpec) -> Result<Self> {
        use AnyPin::*;
        let (bit, int, uint, float) = match spec.initial {
            PinValue::Bit(b) => (b, 0, 0, 0.0),
            PinValue::S32(v) => (false, v, 0, 0.0),
            PinValue::U32(v) => (false, 0, v, 0.0),
            PinValue::Float(v) => (false, 0, 0, v),
        };
        Ok(match (spec.ty, spec.kind) {
            (PinType::Bit, Kind::In) => BitIn(c.pin_init(name, bit)?),
            (PinType::Bit, Kind::Out) => BitOut(c.pin_init(name, bit)?),
            (PinType::Bit, Kind::Io) => BitIo(c.pin_init(name, bit)?),
            (PinType::Bit, Kind::Param) => BitParam(c.param(name, bit)?),
            (PinType::S32, Kind::In) => S32In(c.pin_init(name, int)?),
            (PinType::S32, Kind::Out) => S32Out(c.pin_init(name, int)?),
            (PinType::S32, Kind::Io) => S32Io(c.pin_init(name, int)?),
            (PinType::S32, Kind::Param) => S32Param(c.param(name, int)?),
            (PinType::U32, Kind::In) => U32In(c.pin_init(name, uint)?),
            (PinType::U32, Kind::Out) => U32Out(c.pin_init(name, uint)?),
            (PinType::U32, Kind::Io) => U32Io(c.pin_init(name, uint)?),
            (PinType::U32, Kind::Param) => U32Param(c.param(name, uint)?),
            (PinType::Float, Kind::In) => FloatIn(c.pin_init(name, float)?),
            (PinType::Float, Kind::Out) => FloatOut(c.pin_init(name, float)?),
            (PinType::Float, Kind::Io) => FloatIo(c.pin_init(name, float)?),
            (PinType::Float, Kind::Param) => FloatParam(c.param(name, float)?),
        })
    }

    /// The value (a bit as 0 or 1).
    #[inline]
    pub(crate) fn get(&self) -> f64 {
        use AnyPin::*;
        match self {
            BitIn(p) => f64::from(u8::from(p.get())),
            BitOut(p) => f64::from(u8::from(p.get())),
            BitIo(p) => f64::from(u8::from(p.get())),
            BitParam(p) => f64::from(u8::from(p.get())),
            S32In(p) => f64::from(p.get()),
            S32Out(p) => f64::from(p.get()),
            S32Io(p) => f64::from(p.get()),
            S32Param(p) => f64::from(p.get()),
            U32In(p) => f64::from(p.get()),
            U32Out(p) => f64::from(p.get()),
            U32Io(p) => f64::from(p.get()),
            U32Param(p) => f64::from(p.get()),
            FloatIn(p) => p.get(),
            FloatOut(p) => p.get(),
            FloatIo(p) => p.get(),
            FloatParam(p) => p.get(),
        }
    }

    /// Whether the value is non-zero.
    #[inline]
    pub(crate) fn is_set(&self) -> bool {
        self.get() != 0.0
    }

    /// Writes the value (saturated to the pin's type; a bit is set when
    /// non-zero). Input pins are the HAL's to write: left alone.
    #[inline]
    pub(crate) fn set(&self, v: f64) {
        use AnyPin::*;
        let int = || v.round().clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32;
        let uint = || v.round().clamp(0.0, f64::from(u32::MAX)) as u32;
        match self {
            BitOut(p) => p.set(v != 0.0),
            BitIo(p) => p.set(v != 0.0),
            BitParam(p) => p.set(v != 0.0),
            S32Out(p) => p.set(int()),
            S32Io(p) => p.set(int()),
            S32Param(p) => p.set(int()),
            U32Out(p) => p.set(uint()),
            U32Io(p) => p.set(uint()),
            U32Param(p) => p.set(uint()),
            FloatOut(p) => p.set(v),
            FloatIo(p) => p.set(v),
            FloatParam(p) => p.set(v),
            BitIn(_) | S32In(_) | U32In(_) | FloatIn(_) => {}
        }
    }
}
