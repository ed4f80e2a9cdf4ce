//! canservo's cycle cost and bus load, for 6 drives in CSP moving on the
//! simulated bus. Prints figures; asserts nothing about speed.
//!
//! * `read` + `write` CPU time per servo period, on the in-process bus
//!   (the drives' own simulation runs outside the timed part, as real
//!   drives run outside the host), and on a replay bus that hands the
//!   engine one recorded period's frames and swallows what it sends
//!   (the engine alone).
//! * Frames and worst-case bit times per period, and the shortest period
//!   at which six drives fit on a 1 Mbit/s bus.
//!
//! Run: `cargo bench -p hal-canservo`.

use hal_canservo::bus::CanBus;
use hal_canservo::engine::{DriveInputs, Engine, EngineConfig};
use hal_canservo::frame::Frame;
use hal_canservo::rig::Rig;
use hal_canservo::startup::Mode;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

const DRIVES: [u8; 6] = [1, 2, 3, 4, 5, 6];
const PERIODS: usize = 20_000;
const PERIOD_NS: u64 = 1_000_000;

/// Hands out the same recorded frames every period.
struct ReplayBus {
    frames: Vec<Frame>,
    queue: Mutex<VecDeque<Frame>>,
}

impl CanBus for ReplayBus {
    fn send(&self, _: &Frame) -> bool {
        true
    }
    fn try_recv(&self) -> Option<Frame> {
        self.queue.lock().ok()?.pop_front()
    }
    fn recv_timeout(&self, _: Duration) -> Option<Frame> {
        self.try_recv()
    }
    fn errors(&self) -> u64 {
        0
    }
    fn describe(&self) -> String {
        "replay".into()
    }
    fn tick(&self, _: u64) {
        if let Ok(mut q) = self.queue.lock() {
            q.clear();
            q.extend(self.frames.iter().copied());
        }
    }
}

fn stats(mut ns: Vec<u64>) -> (f64, u64, u64) {
    ns.sort_unstable();
    let mean = ns.iter().sum::<u64>() as f64 / ns.len() as f64;
    (mean, ns[ns.len() / 2], ns[ns.len() * 99 / 100])
}

fn main() {
    let mut rig = Rig::new(&DRIVES, Mode::Csp).expect("six simulated drives come up");
    for i in &mut rig.inputs {
        i.scale = 1000.0;
        i.enable = true;
    }
    rig.run_until(50, |r| r.engine.status().iter().all(|s| s.enabled))
        .expect("all six enable");

    // The in-process bus: time the engine, not the drives.
    let start_stats = rig.bus.stats();
    let mut times = Vec::with_capacity(PERIODS);
    for k in 0..PERIODS {
        let p = (k as f64 * 1e-3 * 2.0 * std::f64::consts::PI).sin() * 5.0;
        for i in &mut rig.inputs {
            i.position_cmd = p;
        }
        rig.bus.clock().advance(PERIOD_NS);
        rig.bus.pump();
        rig.now_ns = rig.bus.now_ns();
        let t = Instant::now();
        rig.engine.read(rig.now_ns, &rig.inputs);
        rig.engine.write(rig.now_ns, PERIOD_NS as i64, &rig.inputs);
        times.push(t.elapsed().as_nanos() as u64);
    }
    let end_stats = rig.bus.stats();
    assert!(
        rig.engine.status().iter().all(|s| !s.amp_fault),
        "no drive faulted"
    );
    let (mean, median, p99) = stats(times);
    let frames = (end_stats.frames - start_stats.frames) as f64 / PERIODS as f64;
    let bits = (end_stats.wire_bits - start_stats.wire_bits) as f64 / PERIODS as f64;

    // Record one period of realtime traffic for the replay: what the
    // drives send after the last write's SYNC.
    let probe = rig.bus.open(hal_canservo::bus::Filters::realtime(&DRIVES));
    let mut recorded = Vec::new();
    rig.bus.clock().advance(PERIOD_NS);
    rig.bus.pump();
    while let Some(f) = probe.try_recv() {
        recorded.push(f);
    }

    // The engine alone on the replayed frames.
    let replay = Arc::new(ReplayBus {
        frames: recorded.clone(),
        queue: Mutex::new(VecDeque::new()),
    });
    let mut engine = Engine::without_startup(replay, &DRIVES, Mode::Csp, EngineConfig::default());
    let inputs = [DriveInputs {
        enable: true,
        scale: 1000.0,
        ..DriveInputs::default()
    }; 6];

    let period_min_us = bits; // 1 bit time = 1 µs at 1 Mbit/s
    let at_70 = (bits / 0.7 / 250.0).ceil() * 250.0;
    println!(
        "canservo: 6 drives, CSP, {PERIODS} periods of {} us",
        PERIOD_NS / 1000
    );
    println!(
        "  {:<48} {median:8} ns median, {p99} ns p99 (mean {mean:.0} ns: preemption on a loaded machine)",
        "read + write per period, in-process bus"
    );
    hal_driver::bench::per_call(
        &format!(
            "read + write per period, engine alone ({} frames)",
            recorded.len()
        ),
        PERIODS as u64,
        |k| {
            let now = (k + 1) * PERIOD_NS;
            engine.read(now, &inputs);
            engine.write(now, PERIOD_NS as i64, &inputs);
        },
    );
    println!(
        "  frames per period: {frames:.2} (6 RPDO + SYNC + 12 TPDO + heartbeats), \
         {bits:.0} bit times worst case (stuffing included)"
    );
    println!(
        "  on a 1 Mbit/s bus six drives need at least {period_min_us:.0} us per period; \
         at most 70 % bus load: {at_70:.0} us"
    );
}
