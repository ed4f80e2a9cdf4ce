//! `latencybins`: a histogram of the latency of the thread it runs in:
//! each call's lateness against the period, in `nsbinsize` ns bins, on
//! both sides of zero up to `maxbinnumber` bins, with the counts beyond,
//! the extremes and the variance. A script reads it bin by bin through
//! `index`/`check`, as for histobins.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Bins available on each side.
pub const AVAILABLE_BINS: i32 = 1000;

/// The outputs (pins of the same names).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(missing_docs)]
pub struct LatencyOutputs {
    pub check: i32,
    pub latency: i32,
    pub latency_max: i32,
    pub latency_min: i32,
    pub pbinvalue: i32,
    pub nbinvalue: i32,
    pub pextra: i32,
    pub nextra: i32,
    pub variance: i32,
}

/// The histogram.
#[derive(Debug, Clone)]
pub struct LatencyHistogram {
    last_timer: i64,
    first: bool,
    pbins: Vec<i32>,
    nbins: Vec<i32>,
    nsamples: u32,
    sum: u64,
    sq_sum: u64,
}

impl Default for LatencyHistogram {
    fn default() -> Self {
        LatencyHistogram {
            last_timer: 0,
            first: true,
            pbins: vec![0; AVAILABLE_BINS as usize + 1],
            nbins: vec![0; AVAILABLE_BINS as usize + 1],
            nsamples: 0,
            sum: 0,
            sq_sum: 0,
        }
    }
}

impl LatencyHistogram {
    /// One call at time `now` (ns) in a thread of `period` ns.
    #[allow(clippy::too_many_arguments)]
    pub fn step(
        &mut self,
        now: i64,
        period: i64,
        maxbinnumber: i32,
        index: i32,
        reset: bool,
        nsbinsize: i32,
        o: &mut LatencyOutputs,
    ) {
        let lat = (now.wrapping_sub(self.last_timer).wrapping_sub(period)) as i32;
        self.last_timer = now;
        let binmax = maxbinnumber.min(AVAILABLE_BINS);
        if reset {
            self.first = true;
        }
        if self.first || nsbinsize == 0 {
            self.first = false;
            o.latency = 0;
            o.latency_min = i32::MAX;
            o.latency_max = i32::MIN;
            o.pextra = 0;
            o.nextra = 0;
            if binmax >= 0 {
                self.pbins[..=binmax as usize].fill(0);
                self.nbins[..=binmax as usize].fill(0);
            }
            self.nsamples = 0;
            self.sum = 0;
            self.sq_sum = 0;
        } else {
            o.latency = lat;
            let i = lat.wrapping_div(nsbinsize);
            o.latency_max = o.latency_max.max(lat);
            o.latency_min = o.latency_min.min(lat);
            let (bins, extra, k) = if i >= 0 {
                (&mut self.pbins, &mut o.pextra, i)
            } else {
                (&mut self.nbins, &mut o.nextra, i.wrapping_neg())
            };
            if k > binmax || k < 0 {
                *extra = extra.wrapping_add(1);
            } else {
                bins[k as usize] = bins[k as usize].wrapping_add(1);
            }
            self.nsamples = self.nsamples.wrapping_add(1);
            self.sum = self.sum.wrapping_add(lat as i64 as u64);
            self.sq_sum = self
                .sq_sum
                .wrapping_add(lat.wrapping_mul(lat) as i64 as u64);
            if self.nsamples > 1 {
                let n = u64::from(self.nsamples);
                let dividend = self
                    .sq_sum
                    .wrapping_sub(self.sum.wrapping_mul(self.sum) / n);
                o.variance = (dividend / (n - 1)) as i32;
            }
        }
        o.check = index;
        (o.pbinvalue, o.nbinvalue) = if index >= 0 && index <= binmax {
            (self.pbins[index as usize], self.nbins[index as usize])
        } else {
            (-1, -1)
        };
    }
}

/// The `latencybins` component.
pub struct Latencybins;
impl HalComp for Latencybins {
    const NAME: &'static str = "latencybins";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let maxbinnumber = inst.pin_in_init::<i32>("maxbinnumber", AVAILABLE_BINS)?;
        let index = inst.pin_in::<i32>("index")?;
        let reset = inst.pin_in::<bool>("reset")?;
        let nsbinsize = inst.pin_in::<i32>("nsbinsize")?;
        let names = [
            "check",
            "latency",
            "latency-max",
            "latency-min",
            "pbinvalue",
            "nbinvalue",
            "pextra",
            "nextra",
            "variance",
        ];
        let pins: Vec<hal_core::Pin<i32, hal_core::Out>> = names
            .iter()
            .map(|n| inst.pin_out(n))
            .collect::<Result<_>>()?;
        let _available = inst.pin_out_init::<i32>("availablebins", AVAILABLE_BINS)?;
        let mut h = LatencyHistogram::default();
        inst.funct("_", false, move |ctx| {
            let mut o = LatencyOutputs {
                check: pins[0].get(),
                latency: pins[1].get(),
                latency_max: pins[2].get(),
                latency_min: pins[3].get(),
                pbinvalue: pins[4].get(),
                nbinvalue: pins[5].get(),
                pextra: pins[6].get(),
                nextra: pins[7].get(),
                variance: pins[8].get(),
            };
            h.step(
                ctx.now_ns() as i64,
                ctx.period(),
                maxbinnumber.get(),
                index.get(),
                reset.get(),
                nsbinsize.get(),
                &mut o,
            );
            let v = [
                o.check,
                o.latency,
                o.latency_max,
                o.latency_min,
                o.pbinvalue,
                o.nbinvalue,
                o.pextra,
                o.nextra,
                o.variance,
            ];
            for (p, v) in pins.iter().zip(v) {
                p.set(v);
            }
        })
    }
}
halcomp_module!(pub MODULE, Latencybins, "comp utility for scripts/latency-histogram");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::S32;

    #[test]
    fn bins_latency_both_ways() {
        let mut h = LatencyHistogram::default();
        let mut o = LatencyOutputs::default();
        let p = 1_000_000;
        let mut t = 0;
        let mut call = |h: &mut LatencyHistogram, late: i64, index: i32, o: &mut LatencyOutputs| {
            t += p + late;
            h.step(t, p, 10, index, false, 1000, o);
        };
        call(&mut h, 0, 0, &mut o); // resets
        call(&mut h, 2500, 2, &mut o);
        assert_eq!((o.latency, o.pbinvalue), (2500, 1));
        call(&mut h, -1500, 1, &mut o);
        assert_eq!((o.latency, o.nbinvalue), (-1500, 1));
        call(&mut h, 50_000, 1, &mut o);
        assert_eq!(o.pextra, 1);
        assert_eq!((o.latency_min, o.latency_max), (-1500, 50_000));
        call(&mut h, 0, 11, &mut o);
        assert_eq!((o.pbinvalue, o.nbinvalue, o.check), (-1, -1, 11));
        assert!(o.variance > 0);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("latencybins");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "latencybins.0",
            &[
                "maxbinnumber s32 in 1000",
                "index s32 in 0",
                "reset bit in 0",
                "nsbinsize s32 in 0",
                "check s32 out 0",
                "latency s32 out 0",
                "latency-max s32 out 0",
                "latency-min s32 out 0",
                "pbinvalue s32 out 0",
                "nbinvalue s32 out 0",
                "pextra s32 out 0",
                "nextra s32 out 0",
                "variance s32 out 0",
                "availablebins s32 out 1000",
            ],
        );
        h.thread(&["latencybins.0"]);
        h.set("latencybins.0.nsbinsize", S32(1000));
        h.set("latencybins.0.index", S32(5));
        h.expect(&[], "latencybins.0.check", S32(5));
        assert_ne!(h.get("latencybins.0.latency-min"), S32(0));
    }
}
