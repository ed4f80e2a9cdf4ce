//! Digital inputs and outputs.

use hal_core::{HalHost, HostParam, HostPin, In, Ours, Out, PinFactory, Result, Rw};

use crate::naming::{ChannelNames, Interface};

/// A canonical digital input channel.
pub struct DigIn<H: HalHost = Ours> {
    input: H::Pin<bool, Out>,
    input_not: H::Pin<bool, Out>,
}

impl Interface for DigIn {
    const IO_TYPE: &'static str = "digin";
}

impl<H: HalHost> DigIn<H> {
    /// Exports channel `chan`'s `in` and `in-not` pins on `comp`.
    pub fn export(comp: &impl PinFactory<H>, names: &ChannelNames, chan: usize) -> Result<Self> {
        Ok(DigIn {
            input: comp.pin(&names.item(chan, "in"))?,
            input_not: comp.pin_init(&names.item(chan, "in-not"), true)?,
        })
    }

    /// Publishes the hardware level.
    #[inline]
    pub fn update(&self, level: bool) {
        self.input.set(level);
        self.input_not.set(!level);
    }
}

/// A canonical digital output channel.
pub struct DigOut<H: HalHost = Ours> {
    out: H::Pin<bool, In>,
    invert: H::Param<bool, Rw>,
}

impl Interface for DigOut {
    const IO_TYPE: &'static str = "digout";
}

impl<H: HalHost> DigOut<H> {
    /// Exports channel `chan`'s `out` pin and `invert` param on `comp`.
    pub fn export(comp: &impl PinFactory<H>, names: &ChannelNames, chan: usize) -> Result<Self> {
        Ok(DigOut {
            out: comp.pin(&names.item(chan, "out"))?,
            invert: comp.param(&names.item(chan, "invert"), false)?,
        })
    }

    /// The level to drive the hardware with: `out XOR invert`.
    #[inline]
    pub fn level(&self) -> bool {
        self.out.get() != self.invert.get()
    }

    /// The level of the safe state: `out` FALSE, inverted if asked.
    #[inline]
    pub fn safe_level(&self) -> bool {
        self.invert.get()
    }

    /// `level` of each of `outs` (up to 32) as one word, output i on bit
    /// i: what a driver writes to a port register.
    #[inline]
    pub fn pack(outs: &[DigOut<H>], level: impl Fn(&DigOut<H>) -> bool) -> u32 {
        outs.iter()
            .take(32)
            .enumerate()
            .fold(0, |w, (i, o)| if level(o) { w | 1 << i } else { w })
    }
}
