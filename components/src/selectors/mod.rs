//! Selectors (reference section 5): mux2, mux4, mux8, mux16 (with Gray
//! code and debounce), mux_generic (any input/output type, C-style
//! config), select8 (one-hot decoder). In their own files: demux,
//! demux_generic, enum (in `enums`), output_buffer, multiswitch.

pub mod demux;
pub mod demux_generic;
pub mod enums;
pub mod multiswitch;
pub mod mux_generic;
pub mod output_buffer;

use hal_core::{In, Pin, Result};

use crate::cmath::f64_to_i32;
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The number select bits spell, `sel0` (the first) the least
/// significant. At most 32 bits.
#[inline]
pub fn bits_value(bits: impl IntoIterator<Item = bool>) -> u32 {
    bits.into_iter()
        .enumerate()
        .fold(0, |v, (i, b)| v | u32::from(b) << i)
}

/// Builds a mux with `sels` select bits and 2^sels float inputs.
fn mux(inst: &mut Inst<'_, '_>, sels: usize) -> Result<()> {
    let sel: Vec<Pin<bool, In>> = if sels == 1 {
        vec![inst.pin_in("sel")?]
    } else {
        (0..sels)
            .map(|i| inst.pin_in(&format!("sel{i}")))
            .collect::<Result<_>>()?
    };
    let inputs: Vec<Pin<f64, In>> = (0..1usize << sels)
        .map(|i| inst.pin_in(&format!("in{i}")))
        .collect::<Result<_>>()?;
    let out = inst.pin_out::<f64>("out")?;
    inst.funct("_", false, move |_| {
        out.set(inputs[bits_value(sel.iter().map(Pin::get)) as usize].get());
    })
}

macro_rules! muxes {
    ($($ty:ident $static:ident $name:literal $sels:literal;)*) => {$(
        #[doc = concat!("`", $name, "`: out = in<k>, k from the select bits.")]
        pub struct $ty;
        impl HalComp for $ty {
            const NAME: &'static str = $name;
            fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
                mux(inst, $sels)
            }
        }
        halcomp_module!(pub $static, $ty, "selects one of several float inputs");
    )*};
}

muxes! {
    Mux2 MUX2 "mux2" 1;
    Mux4 MUX4 "mux4" 2;
    Mux8 MUX8 "mux8" 3;
}

/// Inputs of one mux16 call, besides the data inputs.
#[derive(Debug, Clone, Copy, Default)]
pub struct Mux16In {
    /// `sel0` .. `sel3`.
    pub sel: [bool; 4],
    /// `use-graycode`.
    pub use_graycode: bool,
    /// `suppress-no-input`.
    pub suppress_no_input: bool,
    /// `debounce-time` in seconds.
    pub debounce_time: f64,
}

/// What one mux16 call writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Mux16Out {
    /// New value of the `selected` param, if written.
    pub selected: Option<i32>,
    /// New value of the `elapsed` param, if written.
    pub elapsed: Option<f64>,
    /// The data input to copy to `out-f`/`out-s`, if the outputs change.
    pub input: Option<usize>,
}

/// mux16's per-instance state.
///
/// Quirks kept from LinuxCNC: `lastnum` only changes through the debounce
/// path (so with no debounce it stays 0), and a selection that returns to
/// `lastnum` mid-debounce is output at once without clearing the timer,
/// which the next change then continues.
#[derive(Debug, Clone, Default)]
pub struct Mux16 {
    delaytime: f64,
    lastnum: i32,
    running: bool,
}

impl Mux16 {
    /// The selected input number from the select bits (binary, or Gray
    /// code with `sel3` as the most significant bit).
    pub fn number(sel: [bool; 4], graycode: bool) -> i32 {
        let bits = if graycode {
            // Each binary bit is the XOR of the Gray bits from the top
            // down to it.
            let b3 = sel[3];
            let b2 = b3 ^ sel[2];
            let b1 = b2 ^ sel[1];
            [b1 ^ sel[0], b1, b2, b3]
        } else {
            sel
        };
        bits_value(bits) as i32
    }

    /// One call with period `fperiod` seconds.
    pub fn update(&mut self, i: &Mux16In, fperiod: f64) -> Mux16Out {
        let mut r = Mux16Out::default();
        if i.suppress_no_input && !i.sel.iter().any(|&s| s) {
            return r;
        }
        let num = Self::number(i.sel, i.use_graycode);
        r.selected = Some(num);
        if i.debounce_time != 0.0 && num != self.lastnum {
            if !self.running {
                self.running = true;
                self.delaytime = 0.0;
            }
            if self.delaytime < i.debounce_time {
                self.delaytime += fperiod;
                r.elapsed = Some(self.delaytime);
                return r;
            }
            self.running = false;
            self.lastnum = num;
        }
        r.input = Some(num as usize);
        r
    }
}

/// `mux16`: selects one of 16 floats by four select bits, with optional
/// Gray code decoding and debounce.
pub struct Mux16Comp;
impl HalComp for Mux16Comp {
    const NAME: &'static str = "mux16";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let use_graycode = inst.pin_in::<bool>("use-graycode")?;
        let suppress = inst.pin_in::<bool>("suppress-no-input")?;
        let debounce_time = inst.pin_in::<f64>("debounce-time")?;
        let sel: Vec<Pin<bool, In>> = (0..4)
            .map(|i| inst.pin_in(&format!("sel{i}")))
            .collect::<Result<_>>()?;
        let out_f = inst.pin_out::<f64>("out-f")?;
        let out_s = inst.pin_out::<i32>("out-s")?;
        let inputs: Vec<Pin<f64, In>> = (0..16)
            .map(|i| inst.pin_in(&format!("in{i:02}")))
            .collect::<Result<_>>()?;
        let elapsed = inst.param_ro::<f64>("elapsed", 0.0)?;
        let selected = inst.param_ro::<i32>("selected", 0)?;
        let mut state = Mux16::default();
        inst.funct("_", true, move |ctx| {
            let i = Mux16In {
                sel: [sel[0].get(), sel[1].get(), sel[2].get(), sel[3].get()],
                use_graycode: use_graycode.get(),
                suppress_no_input: suppress.get(),
                debounce_time: debounce_time.get(),
            };
            let r = state.update(&i, ctx.fperiod());
            if let Some(s) = r.selected {
                selected.set(s);
            }
            if let Some(e) = r.elapsed {
                elapsed.set(e);
            }
            if let Some(k) = r.input {
                let v = inputs[k].get();
                out_f.set(v);
                // Plain C truncation, not limited despite the man page.
                out_s.set(f64_to_i32(v));
            }
        })
    }
}
halcomp_module!(pub MUX16, Mux16Comp, "select from one of sixteen input values");

/// `select8` for one call: `out<i>` is TRUE only for `i == sel` while
/// enabled.
pub fn select8(enable: bool, sel: i32) -> [bool; 8] {
    std::array::from_fn(|i| enable && sel == i as i32)
}

/// `select8`: 8-way one-hot decoder of an s32.
pub struct Select8;
impl HalComp for Select8 {
    const NAME: &'static str = "select8";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let enable = inst.pin_in_init::<bool>("enable", true)?;
        let sel = inst.pin_in::<i32>("sel")?;
        let outs: Vec<Pin<bool, hal_core::Out>> = (0..8)
            .map(|i| inst.pin_out(&format!("out{i}")))
            .collect::<Result<_>>()?;
        inst.funct("_", false, move |_| {
            let v = select8(enable.get(), sel.get());
            for (pin, v) in outs.iter().zip(v) {
                pin.set(v);
            }
        })
    }
}
halcomp_module!(pub SELECT8, Select8, "8-bit binary match detector");

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![
        &MUX2,
        &MUX4,
        &MUX8,
        &MUX16,
        &mux_generic::MODULE,
        &SELECT8,
        &demux::MODULE,
        &output_buffer::MODULE,
        &multiswitch::MODULE,
        &demux_generic::MODULE,
        &enums::MODULE,
    ]
}

#[cfg(test)]
mod tests;
