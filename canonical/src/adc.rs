//! Analog inputs and outputs.

use hal_core::{HalHost, HostParam, HostPin, In, Ours, Out, PinFactory, Result, Rw};

use crate::naming::{ChannelNames, Interface};

/// A canonical analog input channel.
pub struct AdcIn<H: HalHost = Ours> {
    value: H::Pin<f64, Out>,
    scale: H::Param<f64, Rw>,
    offset: H::Param<f64, Rw>,
    bit_weight: H::Param<f64, Rw>,
    hw_offset: H::Param<f64, Rw>,
}

impl Interface for AdcIn {
    const IO_TYPE: &'static str = "adcin";
}

impl<H: HalHost> AdcIn<H> {
    /// Exports channel `chan` on `comp`. `bit_weight` and `hw_offset` are
    /// the converter's defaults (volts per count, volts at count 0).
    pub fn export(
        comp: &impl PinFactory<H>,
        names: &ChannelNames,
        chan: usize,
        bit_weight: f64,
        hw_offset: f64,
    ) -> Result<Self> {
        Ok(AdcIn {
            value: comp.pin(&names.item(chan, "value"))?,
            scale: comp.param(&names.item(chan, "scale"), 1.0)?,
            offset: comp.param(&names.item(chan, "offset"), 0.0)?,
            bit_weight: comp.param(&names.item(chan, "bit_weight"), bit_weight)?,
            hw_offset: comp.param(&names.item(chan, "hw_offset"), hw_offset)?,
        })
    }

    /// Publishes a reading in volts: `value = volts * scale - offset`.
    #[inline]
    pub fn update_volts(&self, volts: f64) {
        self.value.set(volts * self.scale.get() - self.offset.get());
    }

    /// Publishes a reading in converter counts.
    #[inline]
    pub fn update_counts(&self, counts: i64) {
        self.update_volts(counts as f64 * self.bit_weight.get() - self.hw_offset.get());
    }
}

/// Which optional params an analog output has.
#[derive(Debug, Clone, Copy)]
pub struct AdcOutOptions {
    /// Export `high_limit` and `low_limit` with these defaults (volts).
    pub limits: Option<(f64, f64)>,
    /// Export `bit_weight` and `hw_offset` with these defaults, and the
    /// converter's count range.
    pub converter: Option<Converter>,
}

/// A digital-to-analog converter's characteristics.
#[derive(Debug, Clone, Copy)]
pub struct Converter {
    /// Volts per count: the default of the `bit_weight` param.
    pub bit_weight: f64,
    /// Volts at count 0: the default of the `hw_offset` param.
    pub hw_offset: f64,
    /// Lowest count the converter takes; outputs clamp to it.
    pub min_count: i64,
    /// Highest count the converter takes; outputs clamp to it.
    pub max_count: i64,
}

/// A canonical analog output channel.
pub struct AdcOut<H: HalHost = Ours> {
    value: H::Pin<f64, In>,
    enable: H::Pin<bool, In>,
    scale: H::Param<f64, Rw>,
    offset: H::Param<f64, Rw>,
    limits: Option<Limits<H>>,
    converter: Option<ConverterParams<H>>,
}

impl Interface for AdcOut {
    const IO_TYPE: &'static str = "adcout";
}

/// The exported `high_limit` and `low_limit` params.
type Limits<H> = (
    <H as HalHost>::Param<f64, Rw>,
    <H as HalHost>::Param<f64, Rw>,
);

/// The exported converter params (`bit_weight`, `hw_offset`) and the
/// converter's count range.
struct ConverterParams<H: HalHost> {
    bit_weight: H::Param<f64, Rw>,
    hw_offset: H::Param<f64, Rw>,
    min: i64,
    max: i64,
}

impl<H: HalHost> AdcOut<H> {
    /// Exports channel `chan` on `comp`.
    pub fn export(
        comp: &impl PinFactory<H>,
        names: &ChannelNames,
        chan: usize,
        opts: AdcOutOptions,
    ) -> Result<Self> {
        let limits = match opts.limits {
            Some((hi, lo)) => Some((
                comp.param(&names.item(chan, "high_limit"), hi)?,
                comp.param(&names.item(chan, "low_limit"), lo)?,
            )),
            None => None,
        };
        let converter = match opts.converter {
            Some(c) => Some(ConverterParams {
                bit_weight: comp.param(&names.item(chan, "bit_weight"), c.bit_weight)?,
                hw_offset: comp.param(&names.item(chan, "hw_offset"), c.hw_offset)?,
                min: c.min_count,
                max: c.max_count,
            }),
            None => None,
        };
        Ok(AdcOut {
            value: comp.pin(&names.item(chan, "value"))?,
            enable: comp.pin(&names.item(chan, "enable"))?,
            scale: comp.param(&names.item(chan, "scale"), 1.0)?,
            offset: comp.param(&names.item(chan, "offset"), 0.0)?,
            limits,
            converter,
        })
    }

    /// The volts to output, or `None` while disabled (hardware zero).
    #[inline]
    pub fn volts(&self) -> Option<f64> {
        if !self.enable.get() {
            return None;
        }
        let mut v = self.value.get() * self.scale.get() + self.offset.get();
        // A NaN from upstream must not reach the hardware: output 0 V.
        if v.is_nan() {
            v = 0.0;
        }
        if let Some((hi, lo)) = &self.limits {
            // Not f64::clamp: it panics when the user sets low above high.
            if v > hi.get() {
                v = hi.get();
            }
            if v < lo.get() {
                v = lo.get();
            }
        }
        Some(v)
    }

    /// Converter counts for the current output, clamped to the converter's
    /// range; disabled gives the count closest to 0 V. `None` if no
    /// converter was declared.
    #[inline]
    pub fn counts(&self) -> Option<i64> {
        let c = self.converter.as_ref()?;
        let (min, max) = (&c.min, &c.max);
        let volts = self.volts().unwrap_or(0.0);
        let bw = c.bit_weight.get();
        let raw = if bw != 0.0 {
            ((volts - c.hw_offset.get()) / bw).round()
        } else {
            0.0
        };
        // A NaN bit_weight or hw_offset (bad params) gives the lowest count.
        let raw = if raw.is_nan() { *min as f64 } else { raw };
        Some((raw.max(*min as f64).min(*max as f64)) as i64)
    }
}
