//! Handles that do not know which HAL they live in.
//!
//! A driver written once runs in two hosts: ours (this crate's
//! [`Instance`](crate::Instance) in shared memory) and LinuxCNC's
//! `rtapi_app`, whose pins live in LinuxCNC's own shared memory. Code that
//! should run in both is generic over a [`HalHost`]: its pins are
//! `H::Pin<T, D>`, its parameters `H::Param<T, A>`, and it creates them
//! through a [`PinFactory<H>`]. Each host's handles are concrete types, so
//! the generic code is monomorphised per host: a pin access stays the few
//! loads it is in either host, with no dynamic dispatch and no allocation.
//!
//! [`Ours`] is this crate's host: its pins are [`Pin`], its parameters
//! [`Param`], and a [`Component`] is its pin factory. Interfaces generic
//! over the host take `Ours` as their default, so code that names
//! `DigOut` or `Encoder` without a host keeps meaning ours.
//!
//! ```
//! use hal_core::{HalHost, HostPin, In, Out, PinFactory, Result};
//!
//! /// A tiny block written once for every host.
//! struct Double<H: HalHost> { input: H::Pin<f64, In>, output: H::Pin<f64, Out> }
//!
//! impl<H: HalHost> Double<H> {
//!     fn export(f: &impl PinFactory<H>, prefix: &str) -> Result<Self> {
//!         Ok(Double { input: f.pin(&format!("{prefix}.in"))?, output: f.pin(&format!("{prefix}.out"))? })
//!     }
//!     fn run(&self) { self.output.set(2.0 * self.input.get()) }
//! }
//! # fn main() -> Result<()> {
//! # let host = hal_core::Host::create(hal_core::HostConfig::for_tests("hosted-doc"))?;
//! let comp = host.instance().new_component("dbl", hal_core::ComponentKind::User)?;
//! let d = Double::export(&comp, "dbl")?; // Double<Ours>, inferred from the factory
//! host.instance().set_pin("dbl.in", hal_core::Value::Float(1.5))?;
//! d.run();
//! assert_eq!(host.instance().pin_value("dbl.out")?, hal_core::Value::Float(3.0));
//! # Ok(()) }
//! ```

use crate::error::Result;
use crate::handles::{Direction, ParamAccess, Writable};
use crate::objects::Component;
use crate::types::PinValue;
use crate::{Param, Pin};

/// A HAL whose pins and parameters realtime code can hold: ours
/// ([`Ours`]) or a foreign one (LinuxCNC's, in the driver layer).
pub trait HalHost: Sized + Send + Sync + 'static {
    /// A pin of value type `T` and direction `D` in this host.
    type Pin<T: PinValue, D: Direction>: HostPin<T, D>;
    /// A parameter of value type `T` and access `A` in this host.
    type Param<T: PinValue, A: ParamAccess>: HostParam<T, A>;
}

/// A pin handle of some host. Every access is realtime-safe.
pub trait HostPin<T: PinValue, D: Direction>: Clone + Send + Sync + 'static {
    /// The pin's current value (its signal's, if linked).
    fn get(&self) -> T;

    /// Writes an output or bidirectional pin (its signal, if linked).
    fn set(&self, v: T)
    where
        D: Writable;

    /// Writes the pin whatever its direction. A few components correct
    /// their own inputs (a limited frequency, a cleared strobe); this is
    /// for them.
    fn overwrite(&self, v: T);
}

/// A parameter handle of some host. The owning component may always
/// write it; `A` says whether `setp` may.
pub trait HostParam<T: PinValue, A: ParamAccess>: Clone + Send + Sync + 'static {
    /// The parameter's value.
    fn get(&self) -> T;
    /// Sets the parameter.
    fn set(&self, v: T);
}

/// Creates pins and parameters of host `H`: a component under
/// construction.
pub trait PinFactory<H: HalHost> {
    /// Creates a pin with value zero (FALSE, 0, 0.0).
    fn pin<T: PinValue, D: Direction>(&self, name: &str) -> Result<H::Pin<T, D>> {
        self.pin_init(name, T::from_bits(0))
    }

    /// Creates a pin with an initial value.
    fn pin_init<T: PinValue, D: Direction>(&self, name: &str, init: T) -> Result<H::Pin<T, D>>;

    /// Creates a parameter with an initial value.
    fn param<T: PinValue, A: ParamAccess>(&self, name: &str, init: T) -> Result<H::Param<T, A>>;
}

/// This crate's host: pins and parameters in our shared-memory instance.
#[derive(Debug, Clone, Copy, Default)]
pub struct Ours;

impl HalHost for Ours {
    type Pin<T: PinValue, D: Direction> = Pin<T, D>;
    type Param<T: PinValue, A: ParamAccess> = Param<T, A>;
}

impl<T: PinValue, D: Direction> HostPin<T, D> for Pin<T, D> {
    #[inline(always)]
    fn get(&self) -> T {
        Pin::get(self)
    }

    #[inline(always)]
    fn set(&self, v: T)
    where
        D: Writable,
    {
        Pin::set(self, v)
    }

    #[inline(always)]
    fn overwrite(&self, v: T) {
        self.store_any(v)
    }
}

impl<T: PinValue, A: ParamAccess> HostParam<T, A> for Param<T, A> {
    #[inline(always)]
    fn get(&self) -> T {
        Param::get(self)
    }

    #[inline(always)]
    fn set(&self, v: T) {
        Param::set(self, v)
    }
}

impl PinFactory<Ours> for Component {
    fn pin<T: PinValue, D: Direction>(&self, name: &str) -> Result<Pin<T, D>> {
        Component::pin(self, name)
    }

    fn pin_init<T: PinValue, D: Direction>(&self, name: &str, init: T) -> Result<Pin<T, D>> {
        Component::pin_init(self, name, init)
    }

    fn param<T: PinValue, A: ParamAccess>(&self, name: &str, init: T) -> Result<Param<T, A>> {
        Component::param(self, name, init)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ComponentKind, Host, HostConfig, In, Out, Rw, Value};

    /// Generic code reaches our handles through the traits.
    fn copy<H: HalHost>(from: &H::Pin<u32, In>, to: &H::Pin<u32, Out>, gain: &H::Param<u32, Rw>) {
        to.set(from.get() * gain.get());
    }

    #[test]
    fn our_handles_through_the_host_traits() {
        let host = Host::create(HostConfig::for_tests("hosted-traits")).unwrap();
        let inst = host.instance();
        let c = inst.new_component("gen", ComponentKind::User).unwrap();
        let a: Pin<u32, In> = PinFactory::<Ours>::pin(&c, "gen.a").unwrap();
        let b: Pin<u32, Out> = PinFactory::<Ours>::pin_init(&c, "gen.b", 9).unwrap();
        let g: Param<u32, Rw> = PinFactory::<Ours>::param(&c, "gen.gain", 3).unwrap();
        assert_eq!(inst.pin_value("gen.b").unwrap(), Value::U32(9));
        inst.set_pin("gen.a", Value::U32(5)).unwrap();
        copy::<Ours>(&a, &b, &g);
        assert_eq!(inst.pin_value("gen.b").unwrap(), Value::U32(15));
        HostPin::overwrite(&a, 7);
        assert_eq!(inst.pin_value("gen.a").unwrap(), Value::U32(7));
        HostParam::set(&g, 4);
        assert_eq!(HostParam::get(&g), 4);
    }
}
