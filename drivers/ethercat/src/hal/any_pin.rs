//! A HAL pin or parameter of any of lcec's types and directions, made
//! from a [`PinSpec`]: the binding handles every pin as a number (a bit
//! is 0 or 1; s32 and u32 are exact in an f64), so one table of pins
//! serves every slave type.
//!
//! An output pin keeps the value it last wrote and writes only a
//! change: most of lcec's outputs (states, status bits) hold still from
//! one period to the next, and each write reaches the pin through the
//! HAL's shared memory, which a servo thread meets cold every period.
//! Nothing but its owner changes an output pin's value: the HAL refuses
//! `setp` on it and `sets` on its signal, a signal it joins takes its
//! value, and leaving a signal it keeps the signal's, which is its own.
//! (LinuxCNC gives a signal the value of its first pin only: an output
//! joining a signal that has readers shows the signal's value until it
//! writes. The binding forgets what it wrote, a slave at a time, every
//! so often, for that.)

use std::cell::Cell;

use hal_core::{HalHost, HostParam, HostPin, In, Io, Out, PinFactory, Result, Rw};

use crate::lcec::pins::{Kind, PinSpec, PinType, PinValue};

/// `v` rounded half away from zero, as `f64::round` does, saturated to
/// i64 (NaN: 0), without the library call `round` is on a CPU without
/// SSE4.1 (most pins this rounds are whole numbers already).
#[inline]
fn round(v: f64) -> i64 {
    let i = v as i64;
    // Exact: below 2^53 the difference is a representable fraction,
    // and above it every f64 is whole.
    let frac = v - i as f64;
    if frac >= 0.5 {
        i.saturating_add(1)
    } else if frac <= -0.5 {
        i.saturating_sub(1)
    } else {
        i
    }
}

/// One exported pin or parameter, in host `H`.
pub(crate) struct AnyPin<H: HalHost> {
    handle: Handle<H>,
    /// An output pin's value as last written (None: not yet).
    written: Cell<Option<f64>>,
}

/// The host's handle of each type and direction.
enum Handle<H: HalHost> {
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
        use Handle::*;
        let (bit, int, uint, float) = match spec.initial {
            PinValue::Bit(b) => (b, 0, 0, 0.0),
            PinValue::S32(v) => (false, v, 0, 0.0),
            PinValue::U32(v) => (false, 0, v, 0.0),
            PinValue::Float(v) => (false, 0, 0, v),
        };
        let handle = match (spec.ty, spec.kind) {
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
        };
        Ok(AnyPin {
            handle,
            written: Cell::new(None),
        })
    }

    /// The next `set` writes, whatever it was before.
    pub(crate) fn forget(&self) {
        self.written.set(None);
    }

    /// Whether an output pin must be written to hold `v` (and notes that
    /// it will).
    #[inline]
    fn changes(&self, v: f64) -> bool {
        match self.written.get() {
            Some(w) if w.to_bits() == v.to_bits() => false,
            _ => {
                self.written.set(Some(v));
                true
            }
        }
    }

    /// The value (a bit as 0 or 1).
    #[inline]
    pub(crate) fn get(&self) -> f64 {
        use Handle::*;
        if let Some(w) = self.written.get() {
            return w;
        }
        match &self.handle {
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
        use Handle::*;
        let int = || round(v).clamp(i64::from(i32::MIN), i64::from(i32::MAX)) as i32;
        let uint = || round(v).clamp(0, i64::from(u32::MAX)) as u32;
        match &self.handle {
            BitOut(p) => {
                let b = v != 0.0;
                if self.changes(f64::from(u8::from(b))) {
                    p.set(b);
                }
            }
            BitIo(p) => p.set(v != 0.0),
            BitParam(p) => p.set(v != 0.0),
            S32Out(p) => {
                let i = int();
                if self.changes(f64::from(i)) {
                    p.set(i);
                }
            }
            S32Io(p) => p.set(int()),
            S32Param(p) => p.set(int()),
            U32Out(p) => {
                let u = uint();
                if self.changes(f64::from(u)) {
                    p.set(u);
                }
            }
            U32Io(p) => p.set(uint()),
            U32Param(p) => p.set(uint()),
            FloatOut(p) => {
                if self.changes(v) {
                    p.set(v);
                }
            }
            FloatIo(p) => p.set(v),
            FloatParam(p) => p.set(v),
            BitIn(_) | S32In(_) | U32In(_) | FloatIn(_) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::round;

    #[test]
    fn rounding_is_f64_round_saturated() {
        for v in [
            0.0f64,
            0.49999999999999994,
            0.5,
            1.5,
            2.5,
            -0.5,
            -1.5,
            -2.4,
            1e15 + 0.5,
            -7.0,
            4.5e15,
            9.3e18,
            -9.3e18,
            1e300,
        ] {
            // `as` saturates, as `round` must.
            let want = v.round() as i64;
            assert_eq!(round(v), want, "{v}");
        }
        assert_eq!(round(f64::NAN), 0);
        assert_eq!(round(f64::INFINITY), i64::MAX);
    }
}
