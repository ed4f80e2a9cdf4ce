//! `histobins`: a histogram of one input (float, s32, u32 or bit, chosen
//! by `pintype`) in `nbins` bins of `binsize` from `minvalue`, with the
//! counts above and below, the minimum, maximum, mean and variance. A
//! script reads the bins one at a time: it sets `index`, waits for
//! `check` to show it, then reads `binvalue`.

use hal_core::{In, Out, Pin, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Bins available.
pub const AVAILABLE_BINS: i32 = 200;

/// The settings one call reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HistoInputs {
    /// The value, already taken from the pin `pintype` selects.
    pub value: f64,
    /// Pin `nbins`.
    pub nbins: u32,
    /// Pin `binsize`.
    pub binsize: f64,
    /// Pin `minvalue`.
    pub minvalue: f64,
    /// Pin `index`.
    pub index: i32,
    /// Pin `reset`.
    pub reset: bool,
    /// Pin `method`: FALSE for Welford's running variance, TRUE for
    /// sums of squares.
    pub method: bool,
}

/// The outputs (pins of the same names).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(missing_docs)]
pub struct HistoOutputs {
    pub check: i32,
    pub input_error: bool,
    pub binvalue: f64,
    pub pextra: f64,
    pub nextra: f64,
    pub input_min: f64,
    pub input_max: f64,
    pub nsamples: u32,
    pub variance: f64,
    pub mean: f64,
}

/// The histogram.
#[derive(Debug, Clone)]
pub struct Histogram {
    // One slot past the last bin catches values exactly at the top, as
    // LinuxCNC's array does; it is never reported.
    bins: [i32; AVAILABLE_BINS as usize + 1],
    first: bool,
    last: (u32, f64, f64),
    maxvalue: f64,
    sum: f64,
    sq_sum: f64,
    m2: f64,
}

impl Default for Histogram {
    fn default() -> Self {
        Histogram {
            bins: [0; AVAILABLE_BINS as usize + 1],
            first: true,
            last: (0, 0.0, 0.0),
            maxvalue: 0.0,
            sum: 0.0,
            sq_sum: 0.0,
            m2: 0.0,
        }
    }
}

impl Histogram {
    /// One call.
    pub fn step(&mut self, i: &HistoInputs, o: &mut HistoOutputs) {
        o.check = i.index;
        if i.nbins > AVAILABLE_BINS as u32 || i.nbins < 1 {
            o.input_error = true;
            return;
        }
        o.input_error = false;
        if i.reset {
            self.first = true;
        }
        let v = i.value;
        if self.first || (i.nbins, i.binsize, i.minvalue) != self.last {
            self.maxvalue = i.minvalue + f64::from(i.nbins) * i.binsize;
            self.first = false;
            o.pextra = 0.0;
            o.nextra = 0.0;
            self.bins[..i.nbins as usize].fill(0);
            o.nsamples = 0;
            o.mean = 0.0;
            self.sum = 0.0;
            self.sq_sum = 0.0;
            o.variance = 0.0;
            o.input_min = 1e99;
            o.input_max = -1e99;
            self.m2 = 0.0;
        } else if v < i.minvalue {
            o.nextra += 1.0;
        } else if v > self.maxvalue {
            o.pextra += 1.0;
        } else {
            let idx = ((v - i.minvalue) / i.binsize) as i64;
            if let Some(b) = usize::try_from(idx).ok().and_then(|k| self.bins.get_mut(k)) {
                *b = b.wrapping_add(1);
            }
        }
        o.binvalue = if (0..i.nbins as i64).contains(&i64::from(i.index)) {
            f64::from(self.bins[i.index as usize])
        } else {
            -1.0
        };
        if v < o.input_min {
            o.input_min = v;
        }
        if v > o.input_max {
            o.input_max = v;
        }
        o.nsamples = o.nsamples.wrapping_add(1);
        if o.nsamples >= 2 {
            let n = f64::from(o.nsamples);
            if !i.method {
                let delta = v - o.mean;
                o.mean += delta / n;
                self.m2 += delta * (v - o.mean);
                o.variance = self.m2 / f64::from(o.nsamples - 1);
            } else {
                self.sum += v;
                self.sq_sum += v * v;
                o.variance = (self.sq_sum - (self.sum * self.sum) / n) / f64::from(o.nsamples - 1);
                o.mean = self.sum / n;
            }
        }
        self.last = (i.nbins, i.binsize, i.minvalue);
    }
}

/// The `histobins` component.
pub struct Histobins;
impl HalComp for Histobins {
    const NAME: &'static str = "histobins";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let pintype = inst.pin_in::<u32>("pintype")?;
        let input = inst.pin_in::<f64>("input")?;
        let input_signed = inst.pin_in::<i32>("input-signed")?;
        let input_unsigned = inst.pin_in::<u32>("input-unsigned")?;
        let input_bit = inst.pin_in::<bool>("input-bit")?;
        let nbins = inst.pin_in_init::<u32>("nbins", 20)?;
        let binsize = inst.pin_in_init::<f64>("binsize", 1.0)?;
        let minvalue = inst.pin_in::<f64>("minvalue")?;
        let index = inst.pin_in::<i32>("index")?;
        let check = inst.pin_out::<i32>("check")?;
        let reset = inst.pin_in::<bool>("reset")?;
        let method = inst.pin_in::<bool>("method")?;
        let input_error: Pin<bool, Out> = inst.pin_out("input-error")?;
        let floats: Vec<Pin<f64, Out>> = ["binvalue", "pextra", "nextra", "input-min", "input-max"]
            .iter()
            .map(|n| inst.pin_out(n))
            .collect::<Result<_>>()?;
        let nsamples = inst.pin_out::<u32>("nsamples")?;
        let variance = inst.pin_out::<f64>("variance")?;
        let mean = inst.pin_out::<f64>("mean")?;
        let _available = inst.pin_out_init::<i32>("availablebins", AVAILABLE_BINS)?;
        let value = move |t: u32, f: &Pin<f64, In>| match t {
            1 => f64::from(input_signed.get()),
            2 => f64::from(input_unsigned.get()),
            3 => f64::from(input_bit.get() as u8),
            _ => f.get(),
        };
        let mut h = Histogram::default();
        inst.funct("_", true, move |_| {
            let i = HistoInputs {
                value: value(pintype.get(), &input),
                nbins: nbins.get(),
                binsize: binsize.get(),
                minvalue: minvalue.get(),
                index: index.get(),
                reset: reset.get(),
                method: method.get(),
            };
            let mut o = HistoOutputs {
                check: check.get(),
                input_error: input_error.get(),
                binvalue: floats[0].get(),
                pextra: floats[1].get(),
                nextra: floats[2].get(),
                input_min: floats[3].get(),
                input_max: floats[4].get(),
                nsamples: nsamples.get(),
                variance: variance.get(),
                mean: mean.get(),
            };
            h.step(&i, &mut o);
            check.set(o.check);
            input_error.set(o.input_error);
            for (p, v) in
                floats
                    .iter()
                    .zip([o.binvalue, o.pextra, o.nextra, o.input_min, o.input_max])
            {
                p.set(v);
            }
            nsamples.set(o.nsamples);
            variance.set(o.variance);
            mean.set(o.mean);
        })
    }
}
halcomp_module!(pub MODULE, Histobins, "histogram bins utility for scripts/hal-histogram");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Float, S32, U32};

    fn input(value: f64, index: i32) -> HistoInputs {
        HistoInputs {
            value,
            nbins: 4,
            binsize: 1.0,
            minvalue: 0.0,
            index,
            reset: false,
            method: false,
        }
    }

    #[test]
    fn counts_into_bins_and_tracks_statistics() {
        let mut h = Histogram::default();
        let mut o = HistoOutputs::default();
        h.step(&input(0.5, 0), &mut o); // the first call only resets
        for v in [0.5, 1.5, 1.7, 9.0, -1.0] {
            h.step(&input(v, 1), &mut o);
        }
        assert_eq!((o.binvalue, o.pextra, o.nextra), (2.0, 1.0, 1.0));
        assert_eq!((o.input_min, o.input_max), (-1.0, 9.0));
        assert_eq!(o.nsamples, 6);
        h.step(&input(0.5, 7), &mut o);
        assert_eq!((o.binvalue, o.check), (-1.0, 7), "out of range index");
        // Welford and sums of squares agree.
        let mut a = Histogram::default();
        let mut b = Histogram::default();
        let (mut oa, mut ob) = (HistoOutputs::default(), HistoOutputs::default());
        for v in [1.0, 2.0, 4.0, 8.0] {
            a.step(&input(v, 0), &mut oa);
            b.step(
                &HistoInputs {
                    method: true,
                    ..input(v, 0)
                },
                &mut ob,
            );
        }
        assert!((oa.variance - ob.variance).abs() < 1e-9);
        assert!((oa.mean - ob.mean).abs() < 1e-12);
    }

    #[test]
    fn bad_bin_counts_stop_updates() {
        let mut h = Histogram::default();
        let mut o = HistoOutputs::default();
        h.step(
            &HistoInputs {
                nbins: 201,
                ..input(1.0, 0)
            },
            &mut o,
        );
        assert!(o.input_error);
        h.step(
            &HistoInputs {
                nbins: 0,
                ..input(1.0, 0)
            },
            &mut o,
        );
        assert!(o.input_error && o.nsamples == 0);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("histobins");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "histobins.0",
            &[
                "pintype u32 in 0",
                "input float in 0",
                "input-signed s32 in 0",
                "input-unsigned u32 in 0",
                "input-bit bit in 0",
                "nbins u32 in 20",
                "binsize float in 1",
                "minvalue float in 0",
                "index s32 in 0",
                "check s32 out 0",
                "reset bit in 0",
                "method bit in 0",
                "input-error bit out 0",
                "binvalue float out 0",
                "pextra float out 0",
                "nextra float out 0",
                "input-min float out 0",
                "input-max float out 0",
                "nsamples u32 out 0",
                "variance float out 0",
                "mean float out 0",
                "availablebins s32 out 200",
            ],
        );
        h.thread(&["histobins.0"]);
        h.set("histobins.0.pintype", U32(1));
        h.set("histobins.0.input-signed", S32(3));
        h.set("histobins.0.index", S32(3));
        h.run(3);
        assert_ne!(h.get("histobins.0.binvalue"), Float(0.0));
        assert_eq!(h.get("histobins.0.input-max"), Float(3.0));
    }
}
