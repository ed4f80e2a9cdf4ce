//! Simulated drives as their own process on a real or virtual CAN
//! interface (the `canservo-sim` binary): frames from the socket reach
//! every drive, what the drives send goes to the socket and to the
//! other drives, and time is the wall clock.

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::time::{Duration, Instant};

use super::SimDrive;
use crate::bus::CanBus;
use crate::frame::Frame;

/// Shortest simulated time one advance covers: frames are handled the
/// moment they arrive, time only needs to move this often, and each
/// advance has a fixed cost.
const MIN_ADVANCE_NS: u64 = 1_000_000;
/// Longest simulated time one advance covers. A process that falls
/// behind the wall clock (a slow or emulated machine) lets its drives'
/// time run slower rather than jump: a jump would age every heartbeat
/// still waiting in the socket and fault the drives for nothing.
const MAX_ADVANCE_NS: u64 = 2_000_000;

/// How the drives' process reads and steps.
#[derive(Debug, Clone, Copy)]
pub struct Pace {
    /// The longest wait for a frame between advances of time.
    pub step: Duration,
    /// A pause after each frame received while `slow` is set: a
    /// receiver turned slow, whose socket queue overflows (and drops
    /// frames) under a flood.
    pub read_delay: Duration,
}

/// Runs `drives` on `bus` until `stop` is set: powers them up (each
/// sends its boot-up message), then delivers frames as they arrive and
/// advances the drives with the wall clock (at most 2 ms per round),
/// waiting at most `pace.step` for a frame between advances, pausing
/// after each frame once `slow_now` is set. Returns the number of frames
/// the drives sent.
pub fn run(
    bus: &dyn CanBus,
    drives: &mut [SimDrive],
    stop: &AtomicBool,
    slow_now: &AtomicBool,
    pace: Pace,
) -> u64 {
    let step = pace.step;
    let slow = |_: &Frame| {
        if !pace.read_delay.is_zero() && slow_now.load(Relaxed) {
            std::thread::sleep(pace.read_delay);
        }
    };
    let mut out = Vec::new();
    let mut sent = 0u64;
    for d in drives.iter_mut() {
        d.power_up(&mut out);
    }
    let start = Instant::now();
    let mut last_ns = 0u64;
    while !stop.load(Relaxed) {
        sent += flush(bus, drives, &mut out);
        if let Some(f) = bus.recv_timeout(step) {
            slow(&f);
            deliver(drives, &f, None, &mut out);
            while let Some(f) = bus.try_recv() {
                slow(&f);
                deliver(drives, &f, None, &mut out);
                sent += flush(bus, drives, &mut out);
                if stop.load(Relaxed) {
                    break;
                }
            }
        }
        let now = start.elapsed().as_nanos() as u64;
        if now >= last_ns + MIN_ADVANCE_NS {
            let dt = (now - last_ns).min(MAX_ADVANCE_NS);
            for i in 0..drives.len() {
                let mut mine = Vec::new();
                drives[i].advance(dt, &mut mine);
                for f in &mine {
                    deliver(drives, f, Some(i), &mut Vec::new());
                }
                out.extend(mine);
            }
            last_ns += dt;
        }
    }
    sent + flush(bus, drives, &mut out)
}

/// `frame` reaches every drive but the one at index `from`.
fn deliver(drives: &mut [SimDrive], frame: &Frame, from: Option<usize>, out: &mut Vec<Frame>) {
    for (i, d) in drives.iter_mut().enumerate() {
        if Some(i) != from {
            d.receive(frame, out);
        }
    }
}

/// Sends what the drives produced (and lets the other drives see it).
fn flush(bus: &dyn CanBus, drives: &mut [SimDrive], out: &mut Vec<Frame>) -> u64 {
    let mut n = 0;
    while !out.is_empty() {
        let batch: Vec<Frame> = std::mem::take(out);
        for f in &batch {
            if bus.send(f) {
                n += 1;
            }
            let from = f.cob_id().map(|c| (c & 0x7F) as u8);
            let idx = drives.iter().position(|d| Some(d.node()) == from);
            deliver(drives, f, idx, out);
        }
    }
    n
}
