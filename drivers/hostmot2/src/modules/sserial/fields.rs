//! A remote card's process data as HAL objects (hostmot2-more.md 2.5,
//! 2.7), named as LinuxCNC names them under the card's prefix
//! (`hm2_7i76e.0.7i76.0.0.`), and moved to and from the interface
//! registers each cycle.
//!
//! | type | HAL objects |
//! |---|---|
//! | bits | `<name>-NN` per bit; received: `<name>-NN-not`; sent: param `<name>-NN-invert` |
//! | unsigned, signed | float `<name>`, param `<name>-scalemax`; sent: params `<name>-maxlim`, `<name>-minlim` |
//! | boolean | bit `<name>`; received: `<name>-not`; sent: param `<name>-invert` |
//! | stream | u32 `<name>` |
//! | float | float `<name>` |
//! | encoder | `<name>.count`, `.rawcounts` (s32), `.position` (float), `.index-enable`, `.reset` (bit IO); params `.scale`, `.counts-per-rev` |
//!
//! Received data are HAL outputs, sent data HAL inputs, data both ways
//! HAL I/O pins. Pads take their bits and nothing else.

use hal_core::{
    HalHost, HostParam, HostPin, In, Io, Ours, Out, PinFactory, Result as HalResult, Rw,
};

use crate::sserial::data::{self, Unwrap};
use crate::sserial::records::{data_type as t, DataRecord};

/// A bit pin of either direction.
enum BitPin<H: HalHost = Ours> {
    Out(H::Pin<bool, Out>),
    In(H::Pin<bool, In>),
    Io(H::Pin<bool, Io>),
}

impl<H: HalHost> BitPin<H> {
    fn get(&self) -> bool {
        match self {
            BitPin::Out(p) => p.get(),
            BitPin::In(p) => p.get(),
            BitPin::Io(p) => p.get(),
        }
    }

    fn set(&self, v: bool) {
        match self {
            BitPin::Out(p) => p.set(v),
            BitPin::In(_) => {}
            BitPin::Io(p) => p.set(v),
        }
    }
}

/// A float pin of either direction.
enum FloatPin<H: HalHost = Ours> {
    Out(H::Pin<f64, Out>),
    In(H::Pin<f64, In>),
    Io(H::Pin<f64, Io>),
}

impl<H: HalHost> FloatPin<H> {
    fn get(&self) -> f64 {
        match self {
            FloatPin::Out(p) => p.get(),
            FloatPin::In(p) => p.get(),
            FloatPin::Io(p) => p.get(),
        }
    }

    fn set(&self, v: f64) {
        match self {
            FloatPin::Out(p) => p.set(v),
            FloatPin::In(_) => {}
            FloatPin::Io(p) => p.set(v),
        }
    }
}

/// A u32 pin of either direction.
enum WordPin<H: HalHost = Ours> {
    Out(H::Pin<u32, Out>),
    In(H::Pin<u32, In>),
    Io(H::Pin<u32, Io>),
}

impl<H: HalHost> WordPin<H> {
    fn get(&self) -> u32 {
        match self {
            WordPin::Out(p) => p.get(),
            WordPin::In(p) => p.get(),
            WordPin::Io(p) => p.get(),
        }
    }

    fn set(&self, v: u32) {
        match self {
            WordPin::Out(p) => p.set(v),
            WordPin::In(_) => {}
            WordPin::Io(p) => p.set(v),
        }
    }
}

/// An encoder's HAL objects and state.
struct Encoder<H: HalHost = Ours> {
    count: H::Pin<i32, Out>,
    rawcounts: H::Pin<i32, Out>,
    position: H::Pin<f64, Out>,
    index_enable: H::Pin<bool, Io>,
    reset: H::Pin<bool, Io>,
    scale: H::Param<f64, Rw>,
    counts_per_rev: H::Param<u32, Rw>,
    unwrap: Unwrap,
    offset: i64,
    /// The count when `index-enable` was seen set.
    armed_at: Option<i64>,
}

/// An analog output's `minlim` and `maxlim` parameters.
type Limits<H> = (
    <H as HalHost>::Param<f64, Rw>,
    <H as HalHost>::Param<f64, Rw>,
);

/// What a field is in HAL.
enum Kind<H: HalHost = Ours> {
    Pad,
    Bits {
        pins: Vec<BitPin<H>>,
        nots: Vec<H::Pin<bool, Out>>,
        inverts: Vec<H::Param<bool, Rw>>,
    },
    Number {
        pin: FloatPin<H>,
        signed: bool,
        scalemax: H::Param<f64, Rw>,
        limits: Option<Limits<H>>,
    },
    Boolean {
        pin: BitPin<H>,
        not: Option<H::Pin<bool, Out>>,
        invert: Option<H::Param<bool, Rw>>,
    },
    Stream(WordPin<H>),
    Float(FloatPin<H>),
    Encoder(Box<Encoder<H>>),
}

/// One process-data record.
pub struct Field<H: HalHost = Ours> {
    bits: u8,
    /// Bit offset in the received stream (if received).
    at_in: Option<usize>,
    /// Bit offset in the sent stream (if sent).
    at_out: Option<usize>,
    kind: Kind<H>,
}

fn bit_pin<H: HalHost, F: PinFactory<H>>(
    c: &F,
    name: &str,
    r: &DataRecord,
) -> HalResult<BitPin<H>> {
    Ok(match (r.is_in(), r.is_out()) {
        (true, true) => BitPin::Io(c.pin(name)?),
        (true, false) => BitPin::Out(c.pin(name)?),
        _ => BitPin::In(c.pin(name)?),
    })
}

fn float_pin<H: HalHost, F: PinFactory<H>>(
    c: &F,
    name: &str,
    r: &DataRecord,
) -> HalResult<FloatPin<H>> {
    Ok(match (r.is_in(), r.is_out()) {
        (true, true) => FloatPin::Io(c.pin(name)?),
        (true, false) => FloatPin::Out(c.pin(name)?),
        _ => FloatPin::In(c.pin(name)?),
    })
}

impl<H: HalHost> Field<H> {
    /// Exports the HAL objects of `r` named `base` (`<card>.<name>`), at
    /// the given bit offsets of the two streams.
    pub fn export(
        c: &impl PinFactory<H>,
        base: &str,
        r: &DataRecord,
        at_in: Option<usize>,
        at_out: Option<usize>,
    ) -> HalResult<Field<H>> {
        let (min, max) = if r.min == r.max {
            (0.0, 1.0)
        } else {
            (r.min as f64, r.max as f64)
        };
        let kind = match r.data_type {
            t::BITS => {
                let (mut pins, mut nots, mut inverts) = (Vec::new(), Vec::new(), Vec::new());
                for k in 0..r.bits as usize {
                    let name = format!("{base}-{k:02}");
                    pins.push(bit_pin(c, &name, r)?);
                    if r.is_in() && !r.is_out() {
                        nots.push(c.pin(&format!("{name}-not"))?);
                    }
                    if r.is_out() {
                        inverts.push(c.param(&format!("{name}-invert"), false)?);
                    }
                }
                Kind::Bits {
                    pins,
                    nots,
                    inverts,
                }
            }
            t::UNSIGNED | t::SIGNED => Kind::Number {
                pin: float_pin(c, base, r)?,
                signed: r.data_type == t::SIGNED,
                scalemax: c.param(&format!("{base}-scalemax"), max)?,
                limits: if r.is_out() {
                    Some((
                        c.param(&format!("{base}-minlim"), min)?,
                        c.param(&format!("{base}-maxlim"), max)?,
                    ))
                } else {
                    None
                },
            },
            t::BOOLEAN => Kind::Boolean {
                pin: bit_pin(c, base, r)?,
                not: if r.is_in() && !r.is_out() {
                    Some(c.pin(&format!("{base}-not"))?)
                } else {
                    None
                },
                invert: if r.is_out() {
                    Some(c.param(&format!("{base}-invert"), false)?)
                } else {
                    None
                },
            },
            t::STREAM => Kind::Stream(match (r.is_in(), r.is_out()) {
                (true, true) => WordPin::Io(c.pin(base)?),
                (true, false) => WordPin::Out(c.pin(base)?),
                _ => WordPin::In(c.pin(base)?),
            }),
            t::FLOAT => Kind::Float(float_pin(c, base, r)?),
            t::ENCODER => Kind::Encoder(Box::new(Encoder {
                count: c.pin(&format!("{base}.count"))?,
                rawcounts: c.pin(&format!("{base}.rawcounts"))?,
                position: c.pin(&format!("{base}.position"))?,
                index_enable: c.pin(&format!("{base}.index-enable"))?,
                reset: c.pin(&format!("{base}.reset"))?,
                scale: c.param(
                    &format!("{base}.scale"),
                    if r.max != 0.0 { r.max as f64 } else { 1.0 },
                )?,
                counts_per_rev: c.param(&format!("{base}.counts-per-rev"), 256u32)?,
                unwrap: Unwrap::default(),
                offset: 0,
                armed_at: None,
            })),
            _ => Kind::Pad,
        };
        Ok(Field {
            bits: r.bits,
            at_in,
            at_out,
            kind,
        })
    }

    /// Updates the HAL side from the received stream.
    pub fn receive(&mut self, words: &[u32]) {
        let Some(at) = self.at_in else {
            return;
        };
        let len = self.bits as usize;
        let raw = data::get_bits(words, at, len.min(64));
        match &mut self.kind {
            Kind::Pad => {}
            Kind::Bits { pins, nots, .. } => {
                for (k, p) in pins.iter().enumerate() {
                    let v = data::get_bits(words, at + k, 1) != 0;
                    p.set(v);
                    if let Some(n) = nots.get(k) {
                        n.set(!v);
                    }
                }
            }
            Kind::Number {
                pin,
                signed,
                scalemax,
                ..
            } => {
                let s = scalemax.get();
                pin.set(if *signed {
                    data::signed_value(raw, self.bits, s)
                } else {
                    data::unsigned_value(raw, self.bits, s)
                });
            }
            Kind::Boolean { pin, not, .. } => {
                let v = raw != 0;
                pin.set(v);
                if let Some(n) = not {
                    n.set(!v);
                }
            }
            Kind::Stream(p) => p.set(raw as u32),
            Kind::Float(p) => p.set(if self.bits == 64 {
                f64::from_bits(raw)
            } else {
                f32::from_bits(raw as u32) as f64
            }),
            Kind::Encoder(e) => {
                let total = e.unwrap.update(raw, self.bits);
                if e.reset.get() {
                    e.offset = total;
                }
                let cpr = e.counts_per_rev.get() as i64;
                if e.index_enable.get() && cpr > 0 {
                    // The zero moves to the first revision boundary the
                    // count crosses after index-enable was set.
                    let from = *e.armed_at.get_or_insert(total);
                    let (a, b) = (from.div_euclid(cpr), total.div_euclid(cpr));
                    if a != b {
                        e.offset = a.max(b) * cpr;
                        e.index_enable.set(false);
                        e.armed_at = None;
                    }
                } else {
                    e.armed_at = None;
                }
                let counts = total - e.offset;
                e.rawcounts.set(total as i32);
                e.count.set(counts as i32);
                let scale = e.scale.get();
                let scale = if scale.abs() < 1e-12 { 1.0 } else { scale };
                e.position.set(counts as f64 / scale);
            }
        }
    }

    /// Puts the HAL side into the sent stream.
    pub fn send(&self, words: &mut [u32]) {
        let Some(at) = self.at_out else {
            return;
        };
        let len = self.bits as usize;
        let raw = match &self.kind {
            Kind::Pad | Kind::Encoder(_) => 0,
            Kind::Bits { pins, inverts, .. } => {
                for (k, p) in pins.iter().enumerate() {
                    let inv = inverts.get(k).is_some_and(|i| i.get());
                    data::put_bits(words, at + k, 1, (p.get() ^ inv) as u64);
                }
                return;
            }
            Kind::Number {
                pin,
                signed,
                scalemax,
                limits,
            } => {
                let (min, max) = limits
                    .as_ref()
                    .map_or((f64::MIN, f64::MAX), |(lo, hi)| (lo.get(), hi.get()));
                let s = scalemax.get();
                if *signed {
                    data::signed_raw(pin.get(), self.bits, s, min, max)
                } else {
                    data::unsigned_raw(pin.get(), self.bits, s, min, max)
                }
            }
            Kind::Boolean { pin, invert, .. } => {
                (pin.get() ^ invert.as_ref().is_some_and(|i| i.get())) as u64
            }
            Kind::Stream(p) => p.get() as u64,
            Kind::Float(p) => {
                if self.bits == 64 {
                    p.get().to_bits()
                } else {
                    (p.get() as f32).to_bits() as u64
                }
            }
        };
        data::put_bits(words, at, len.min(64), raw);
    }
}
