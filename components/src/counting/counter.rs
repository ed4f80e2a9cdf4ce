//! `counter` (deprecated in LinuxCNC, still loadable): a unidirectional
//! pulse counter with index reset, position and velocity.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Io, Out, Pin, Result};

const PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "num_chan",
    kind: ParamKind::Int,
    help: "number of counter channels (1-8)",
}];

/// The `counter` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "counter",
    params: PARAMS,
    help: "unidirectional pulse counter (use encoder's counter mode instead)",
    load,
};

/// State both functions of a channel touch; they may run in different
/// threads, so it is atomic.
#[derive(Default)]
struct Shared {
    reset_on_index: AtomicBool,
    last_index_count: AtomicI32,
}

struct Channel {
    phase_a: Pin<bool, In>,
    phase_z: Pin<bool, In>,
    index_enable: Pin<bool, Io>,
    reset: Pin<bool, In>,
    rawcounts: Pin<i32, Out>,
    counts: Pin<i32, Out>,
    position: Pin<f64, Out>,
    velocity: Pin<f64, Out>,
    position_scale: Pin<f64, Io>,
    shared: Arc<Shared>,
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let n = args.int("num_chan").unwrap_or(1);
    if !(1..=8).contains(&n) {
        return Err(HalError::ModuleParam {
            module: "counter".into(),
            param: "num_chan".into(),
            reason: format!("{n} is out of range 1-8"),
        });
    }
    let mut b = host.new_rt_component("counter")?;
    let mut update = Vec::new();
    let mut capture = Vec::new();
    for i in 0..n {
        let c = b.component();
        let p = |item: &str| format!("counter.{i}.{item}");
        let shared = Arc::new(Shared::default());
        let ch = Channel {
            phase_a: c.pin(&p("phase-A"))?,
            phase_z: c.pin(&p("phase-Z"))?,
            index_enable: c.pin(&p("index-enable"))?,
            reset: c.pin(&p("reset"))?,
            rawcounts: c.pin(&p("rawcounts"))?,
            counts: c.pin(&p("counts"))?,
            position: c.pin(&p("position"))?,
            velocity: c.pin(&p("velocity"))?,
            position_scale: c.pin_init(&p("position-scale"), 1.0)?,
            shared,
        };
        update.push((
            ch.phase_a.clone(),
            ch.phase_z.clone(),
            ch.index_enable.clone(),
            ch.rawcounts.clone(),
            ch.shared.clone(),
            false,
            false,
        ));
        capture.push((ch, 0i32, 1.0f64, 1.0f64));
    }
    b.funct("counter.update-counters", false, move |_| {
        for (a, z, index_enable, raw, shared, old_a, old_z) in update.iter_mut() {
            let (pa, pz) = (a.get(), z.get());
            if !*old_a && pa {
                raw.set(raw.get().wrapping_add(1));
            }
            *old_a = pa;
            if shared.reset_on_index.load(Relaxed) && !*old_z && pz {
                shared.last_index_count.store(raw.get(), Relaxed);
                index_enable.set(false);
            }
            *old_z = pz;
        }
    })?;
    b.funct("counter.capture-position", true, move |ctx| {
        for (ch, last_count, old_scale, scale) in capture.iter_mut() {
            if ch.reset.get() {
                ch.rawcounts.set(0);
                ch.shared.last_index_count.store(0, Relaxed);
                *last_count = 0;
            }
            let raw = ch.rawcounts.get();
            let counts = raw.wrapping_sub(ch.shared.last_index_count.load(Relaxed));
            ch.counts.set(counts);
            let moved = raw.wrapping_sub(*last_count);
            *last_count = raw;
            let ps = ch.position_scale.get();
            if ps != *old_scale {
                *old_scale = ps;
                let ps = if ps > -1e-20 && ps < 1e-20 {
                    ch.position_scale.set(1.0);
                    1.0
                } else {
                    ps
                };
                *scale = 1.0 / ps;
            }
            ch.position.set(counts as f64 * *scale);
            ch.velocity
                .set(((moved as f64 * *scale) * 1e9) / ctx.period() as f64);
            ch.shared
                .reset_on_index
                .store(ch.index_enable.get(), Relaxed);
        }
    })?;
    b.ready()
}
