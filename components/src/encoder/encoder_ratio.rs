//! `encoder_ratio`: the electronic-gearbox error between a master and a
//! slave quadrature encoder (components.md §12.2).
//!
//! `encoder-ratio.sample` (integer) decodes both encoders (x4) and moves
//! a raw error by fixed increments ([`RatioSampler`]); `encoder-ratio.update`
//! (floating point) scales the raw error to slave revolutions and refreshes
//! the increments from the ppr / teeth pins ([`RatioUpdate`]).

use std::sync::atomic::{AtomicI32, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Io, Out, Pin, Result};

use super::quadrature::{QuadDecoder, QuadMode, Step};
use super::{CHANNEL_PARAMS, MAX_CHAN};
use crate::halcomp::channel_names;

/// The `encoder_ratio` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "encoder_ratio",
    params: CHANNEL_PARAMS,
    help: "electronic gear ratio error between two encoders (num_chan=1-8, default 1, or names=)",
    load,
};

/// The increments the sample function applies, set by the update function.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Increments {
    /// Subtracted per forward master count (while enabled).
    pub master_inc: i32,
    /// Added per forward slave count.
    pub slave_inc: i32,
}

/// The pins the sample function reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RatioInputs {
    /// `master-A`.
    pub master_a: bool,
    /// `master-B`.
    pub master_b: bool,
    /// `slave-A`.
    pub slave_a: bool,
    /// `slave-B`.
    pub slave_b: bool,
    /// `enable`: whether master counts move the error.
    pub enable: bool,
}

/// The sample half of a channel: the two decoders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RatioSampler {
    master: QuadDecoder,
    slave: QuadDecoder,
}

impl RatioSampler {
    /// A channel as loaded.
    pub fn new() -> RatioSampler {
        RatioSampler::default()
    }

    /// One sample call: decodes both encoders and updates `raw_error`.
    /// The master decoder follows its inputs even while disabled.
    #[inline]
    pub fn sample(&mut self, inp: &RatioInputs, inc: Increments, raw_error: &mut i32) {
        let m = self.master.step(inp.master_a, inp.master_b, QuadMode::X4);
        if inp.enable {
            match m {
                Step::Up => *raw_error = raw_error.wrapping_sub(inc.master_inc),
                Step::Down => *raw_error = raw_error.wrapping_add(inc.master_inc),
                Step::None => {}
            }
        }
        match self.slave.step(inp.slave_a, inp.slave_b, QuadMode::X4) {
            Step::Up => *raw_error = raw_error.wrapping_add(inc.slave_inc),
            Step::Down => *raw_error = raw_error.wrapping_sub(inc.slave_inc),
            Step::None => {}
        }
    }
}

/// The gear definition pins the update function reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Gearing {
    /// `master-ppr`.
    pub master_ppr: u32,
    /// `slave-ppr`.
    pub slave_ppr: u32,
    /// `master-teeth`.
    pub master_teeth: u32,
    /// `slave-teeth`.
    pub slave_teeth: u32,
}

/// The update half of a channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RatioUpdate {
    out_scale: f64,
}

impl Default for RatioUpdate {
    fn default() -> Self {
        RatioUpdate { out_scale: 1.0 }
    }
}

impl RatioUpdate {
    /// A channel as loaded.
    pub fn new() -> RatioUpdate {
        RatioUpdate::default()
    }

    /// One update call: the new `error` (None: leave the pin unchanged,
    /// when the scale is not positive) and the increments for the sample
    /// function. The increments and scale are refreshed after the error is
    /// computed, so a gearing change shows one update later.
    #[inline]
    pub fn update(&mut self, raw_error: i32, g: &Gearing) -> (Option<f64>, Increments) {
        let error = (self.out_scale > 0.0).then(|| raw_error as f64 / self.out_scale);
        let inc = Increments {
            master_inc: g.master_teeth.wrapping_mul(g.slave_ppr) as i32,
            slave_inc: g.slave_teeth.wrapping_mul(g.master_ppr) as i32,
        };
        self.out_scale = g
            .master_ppr
            .wrapping_mul(g.slave_ppr)
            .wrapping_mul(g.slave_teeth) as f64;
        (error, inc)
    }
}

/// State the two functions of a channel share.
#[derive(Default)]
struct Shared {
    raw_error: AtomicI32,
    master_inc: AtomicI32,
    slave_inc: AtomicI32,
}

struct SampleChan {
    master_a: Pin<bool, In>,
    master_b: Pin<bool, In>,
    slave_a: Pin<bool, In>,
    slave_b: Pin<bool, In>,
    enable: Pin<bool, In>,
    sampler: RatioSampler,
    shared: Arc<Shared>,
}

struct UpdateChan {
    error: Pin<f64, Out>,
    master_ppr: Pin<u32, Io>,
    slave_ppr: Pin<u32, Io>,
    master_teeth: Pin<u32, Io>,
    slave_teeth: Pin<u32, Io>,
    upd: RatioUpdate,
    shared: Arc<Shared>,
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let names = channel_names("encoder_ratio", "encoder-ratio", 1, MAX_CHAN, args)?;
    let mut b = host.new_rt_component("encoder_ratio")?;
    let mut samples = Vec::with_capacity(names.len());
    let mut updates = Vec::with_capacity(names.len());
    for name in &names {
        let c = b.component();
        let p = |item: &str| format!("{name}.{item}");
        let shared = Arc::new(Shared::default());
        samples.push(SampleChan {
            master_a: c.pin(&p("master-A"))?,
            master_b: c.pin(&p("master-B"))?,
            slave_a: c.pin(&p("slave-A"))?,
            slave_b: c.pin(&p("slave-B"))?,
            enable: c.pin(&p("enable"))?,
            sampler: RatioSampler::new(),
            shared: shared.clone(),
        });
        updates.push(UpdateChan {
            error: c.pin(&p("error"))?,
            master_ppr: c.pin(&p("master-ppr"))?,
            slave_ppr: c.pin(&p("slave-ppr"))?,
            master_teeth: c.pin(&p("master-teeth"))?,
            slave_teeth: c.pin(&p("slave-teeth"))?,
            upd: RatioUpdate::new(),
            shared,
        });
    }
    b.funct("encoder-ratio.sample", false, move |_| {
        for ch in samples.iter_mut() {
            let inp = RatioInputs {
                master_a: ch.master_a.get(),
                master_b: ch.master_b.get(),
                slave_a: ch.slave_a.get(),
                slave_b: ch.slave_b.get(),
                enable: ch.enable.get(),
            };
            let inc = Increments {
                master_inc: ch.shared.master_inc.load(Relaxed),
                slave_inc: ch.shared.slave_inc.load(Relaxed),
            };
            // Only this function writes raw_error.
            let mut e = ch.shared.raw_error.load(Relaxed);
            ch.sampler.sample(&inp, inc, &mut e);
            ch.shared.raw_error.store(e, Relaxed);
        }
    })?;
    b.funct("encoder-ratio.update", true, move |_| {
        for ch in updates.iter_mut() {
            let g = Gearing {
                master_ppr: ch.master_ppr.get(),
                slave_ppr: ch.slave_ppr.get(),
                master_teeth: ch.master_teeth.get(),
                slave_teeth: ch.slave_teeth.get(),
            };
            let (error, inc) = ch.upd.update(ch.shared.raw_error.load(Relaxed), &g);
            if let Some(e) = error {
                ch.error.set(e);
            }
            ch.shared.master_inc.store(inc.master_inc, Relaxed);
            ch.shared.slave_inc.store(inc.slave_inc, Relaxed);
        }
    })?;
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;

    const FWD: [(bool, bool); 4] = [(true, false), (true, true), (false, true), (false, false)];

    fn gear() -> Gearing {
        // Master 100 ppr, slave 50 ppr, 2:1 teeth (slave turns half).
        Gearing {
            master_ppr: 100,
            slave_ppr: 50,
            master_teeth: 1,
            slave_teeth: 2,
        }
    }

    #[test]
    fn matched_motion_gives_zero_error() {
        let mut s = RatioSampler::new();
        let mut u = RatioUpdate::new();
        let mut e = 0;
        let (err, inc) = u.update(e, &gear());
        assert_eq!(err, Some(0.0));
        assert_eq!(
            inc,
            Increments {
                master_inc: 50,
                slave_inc: 200
            }
        );
        // One master revolution (400 counts) against half a slave
        // revolution (100 counts).
        for i in 0..400 {
            let (a, b) = FWD[i % 4];
            let (sa, sb) = FWD[(i / 4) % 4];
            s.sample(
                &RatioInputs {
                    master_a: a,
                    master_b: b,
                    slave_a: sa,
                    slave_b: sb,
                    enable: true,
                },
                inc,
                &mut e,
            );
        }
        assert_eq!(e, -400 * 50 + 100 * 200);
        assert_eq!(u.update(e, &gear()).0, Some(0.0));
    }

    #[test]
    fn error_is_in_slave_revolutions_and_disabled_master_is_ignored() {
        let mut s = RatioSampler::new();
        let mut u = RatioUpdate::new();
        let (_, inc) = u.update(0, &gear());
        let mut e = 0;
        for &(a, b) in &FWD {
            s.sample(
                &RatioInputs {
                    master_a: a,
                    master_b: b,
                    enable: false,
                    ..Default::default()
                },
                inc,
                &mut e,
            );
        }
        assert_eq!(e, 0);
        for &(sa, sb) in &FWD {
            s.sample(
                &RatioInputs {
                    slave_a: sa,
                    slave_b: sb,
                    master_b: true,
                    ..Default::default()
                },
                inc,
                &mut e,
            );
        }
        assert_eq!(e, 4 * 200);
        // out_scale = 100 * 50 * 2 = 10000 counts-products per slave rev.
        let (err, _) = u.update(e, &gear());
        assert_eq!(err, Some(800.0 / 10000.0));
    }

    #[test]
    fn first_update_uses_unit_scale_and_changes_lag_one_update() {
        let mut u = RatioUpdate::new();
        assert_eq!(u.update(7, &gear()).0, Some(7.0));
        assert_eq!(u.update(7, &Gearing::default()).0, Some(7.0 / 10000.0));
        // Scale 0 now: error is left alone.
        assert_eq!(u.update(7, &gear()).0, None);
    }

    #[test]
    fn products_wrap_as_u32() {
        let mut u = RatioUpdate::new();
        let g = Gearing {
            master_ppr: 0x1_0000,
            slave_ppr: 0x1_0000,
            master_teeth: 3,
            slave_teeth: 1,
        };
        let (_, inc) = u.update(0, &g);
        assert_eq!(inc.master_inc, 0x3_0000);
        // 2^32 wraps to 0: the next error is not computed.
        assert_eq!(u.update(5, &g).0, None);
        let g = Gearing {
            master_teeth: 0xFFFF_FFFF,
            slave_ppr: 1,
            ..g
        };
        assert_eq!(u.update(0, &g).1.master_inc, -1);
    }

    #[test]
    fn raw_error_wraps() {
        let mut s = RatioSampler::new();
        let mut e = i32::MAX;
        s.sample(
            &RatioInputs {
                slave_a: true,
                ..Default::default()
            },
            Increments {
                master_inc: 0,
                slave_inc: 1,
            },
            &mut e,
        );
        assert_eq!(e, i32::MIN);
    }

    #[test]
    fn loads_and_rejects_bad_params() {
        let h = crate::testing::host();
        h.loadrt(&MODULE, &[] as &[&str]).unwrap();
        let inst = h.instance();
        assert!(inst.pin_value("encoder-ratio.0.slave-teeth").is_ok());
        assert!(inst.pin_value("encoder-ratio.1.error").is_err());
        let f: Vec<String> = inst.functs().unwrap().into_iter().map(|f| f.name).collect();
        assert!(f.contains(&"encoder-ratio.sample".to_string()));
        assert!(f.contains(&"encoder-ratio.update".to_string()));
        let h = crate::testing::host();
        assert!(h.loadrt(&MODULE, &["num_chan=9".to_string()]).is_err());
        assert!(h
            .loadrt(&MODULE, &["names=a,b,c,d,e,f,g,h,i".to_string()])
            .is_err());
        h.loadrt(&MODULE, &["num_chan=8".to_string()]).unwrap();
        assert!(h.instance().pin_value("encoder-ratio.7.enable").is_ok());
    }
}
