//! `counter` (deprecated in LinuxCNC, still loadable): a unidirectional
//! pulse counter with index reset, position and velocity.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Io, Out, Pin, Result};

use crate::cmath::ScaleCache;

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

/// What update-counters uses for one channel.
struct CountChan {
    phase_a: Pin<bool, In>,
    phase_z: Pin<bool, In>,
    index_enable: Pin<bool, Io>,
    rawcounts: Pin<i32, Out>,
    shared: Arc<Shared>,
    /// `phase-A` and `phase-Z` at the previous call, for edge detection.
    old_a: bool,
    old_z: bool,
}

/// What capture-position uses for one channel.
struct CaptureChan {
    index_enable: Pin<bool, Io>,
    reset: Pin<bool, In>,
    rawcounts: Pin<i32, Out>,
    counts: Pin<i32, Out>,
    position: Pin<f64, Out>,
    velocity: Pin<f64, Out>,
    position_scale: Pin<f64, Io>,
    shared: Arc<Shared>,
    /// `rawcounts` at the previous call, for the velocity.
    last_count: i32,
    /// `1 / position-scale`; LinuxCNC starts from old scale 1.0,
    /// reciprocal 1.0.
    scale: ScaleCache,
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
        let phase_a = c.pin(&p("phase-A"))?;
        let phase_z = c.pin(&p("phase-Z"))?;
        let index_enable: Pin<bool, Io> = c.pin(&p("index-enable"))?;
        let reset = c.pin(&p("reset"))?;
        let rawcounts: Pin<i32, Out> = c.pin(&p("rawcounts"))?;
        update.push(CountChan {
            phase_a,
            phase_z,
            index_enable: index_enable.clone(),
            rawcounts: rawcounts.clone(),
            shared: shared.clone(),
            old_a: false,
            old_z: false,
        });
        capture.push(CaptureChan {
            index_enable,
            reset,
            rawcounts,
            counts: c.pin(&p("counts"))?,
            position: c.pin(&p("position"))?,
            velocity: c.pin(&p("velocity"))?,
            position_scale: c.pin_init(&p("position-scale"), 1.0)?,
            shared,
            last_count: 0,
            scale: ScaleCache::new(1.0, 1.0),
        });
    }
    b.funct("counter.update-counters", false, move |_| {
        for ch in update.iter_mut() {
            let (pa, pz) = (ch.phase_a.get(), ch.phase_z.get());
            if !ch.old_a && pa {
                ch.rawcounts.set(ch.rawcounts.get().wrapping_add(1));
            }
            ch.old_a = pa;
            if ch.shared.reset_on_index.load(Relaxed) && !ch.old_z && pz {
                ch.shared
                    .last_index_count
                    .store(ch.rawcounts.get(), Relaxed);
                ch.index_enable.set(false);
            }
            ch.old_z = pz;
        }
    })?;
    b.funct("counter.capture-position", true, move |ctx| {
        for ch in capture.iter_mut() {
            if ch.reset.get() {
                ch.rawcounts.set(0);
                ch.shared.last_index_count.store(0, Relaxed);
                ch.last_count = 0;
            }
            let raw = ch.rawcounts.get();
            let counts = raw.wrapping_sub(ch.shared.last_index_count.load(Relaxed));
            ch.counts.set(counts);
            let moved = raw.wrapping_sub(ch.last_count);
            ch.last_count = raw;
            let old_ps = ch.position_scale.get();
            let mut ps = old_ps;
            let scale = ch.scale.check(&mut ps, 1.0);
            if ps.to_bits() != old_ps.to_bits() {
                ch.position_scale.set(ps);
            }
            ch.position.set(counts as f64 * scale);
            ch.velocity
                .set(((moved as f64 * scale) * 1e9) / ctx.period() as f64);
            ch.shared
                .reset_on_index
                .store(ch.index_enable.get(), Relaxed);
        }
    })?;
    b.ready()
}
