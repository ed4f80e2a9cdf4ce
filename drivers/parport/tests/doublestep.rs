//! DoubleStep: a stepgen-like generator asks for a step in most periods
//! (`stepspace` 0), `write` raises the step pin and `reset` lowers it
//! `reset-time` later in the same period, so one step fits in each period.

mod common;

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Arc;

use common::*;
use hal_core::{HalType, Out, Pin, Value};
use hal_parport::cfg::Mode;
use hal_parport::clock::{Clock, SimClock};
use hal_parport::driver::{Outputs, PortDriver};
use hal_parport::regs;
use hal_parport::sim::{SimConfig, SimPort};

/// Whether the generator asks for a step in period `n`: two steps, one
/// period without, repeated (consecutive steps need the reset to be
/// remembered, or the second rising edge would never be written).
fn step_in(n: u64) -> bool {
    n % 3 != 2
}

#[test]
fn stepgen_like_toggling_through_write_and_reset_in_a_hal_thread() {
    const PERIOD: i64 = 200_000;
    const RESET_TIME: u32 = 20_000;
    let host = host("dstep");
    loadrt(&host, "0 sim").unwrap();
    let sim = sim(&host, 0);
    let periods = Arc::new(AtomicU64::new(0));
    {
        let mut b = host.new_rt_component("stepper").unwrap();
        let step: Pin<bool, Out> = b.component().pin("stepper.step").unwrap();
        let n = periods.clone();
        b.funct("stepper.make-pulses", false, move |_| {
            step.set(step_in(n.fetch_add(1, Relaxed)));
        })
        .unwrap();
        b.ready().unwrap();
    }
    let inst = host.instance();
    inst.newsig("xstep", HalType::Bit).unwrap();
    inst.link("stepper.step", "xstep").unwrap();
    inst.link("parport.0.pin-02-out", "xstep").unwrap();
    setp(&host, "parport.0.pin-02-out-reset", Value::Bit(true));
    setp(&host, "parport.0.reset-time", Value::U32(RESET_TIME));
    run(
        &host,
        PERIOD,
        &["stepper.make-pulses", "parport.0.write", "parport.0.reset"],
    );
    let end = std::time::Instant::now() + std::time::Duration::from_secs(20);
    while periods.load(Relaxed) < 60 {
        assert!(std::time::Instant::now() < end, "thread too slow");
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    host.stop();
    let ran = periods.load(Relaxed);
    let steps = (0..ran).filter(|&n| step_in(n)).count();
    assert_eq!(
        param(&host, "parport.0.reset-time"),
        Value::U32(RESET_TIME),
        "below period/4: unchanged"
    );

    let data = sim.writes_to(regs::DATA);
    assert_eq!(data.len(), 2 * steps, "one rise and one fall per step");
    let mut widths = Vec::new();
    for (k, pair) in data.chunks(2).enumerate() {
        assert_eq!((pair[0].value, pair[1].value), (0x01, 0x00), "step {k}");
        let width = pair[1].time_ns - pair[0].time_ns;
        assert!(width >= RESET_TIME as u64, "step {k}: {width} ns");
        widths.push(width);
        if k > 0 {
            assert!(pair[0].time_ns > data[2 * k - 1].time_ns);
        }
    }
    widths.sort_unstable();
    eprintln!(
        "{steps} steps in {ran} periods of {PERIOD} ns; pulse width min {} median {} max {} ns (reset-time {RESET_TIME})",
        widths[0],
        widths[widths.len() / 2],
        widths[widths.len() - 1]
    );
    // The control register is written once (first write), never reset.
    assert_eq!(sim.writes_to(regs::CONTROL).len(), 1);
}

#[test]
fn deterministic_timeline_on_a_simulated_clock() {
    const PERIOD: u64 = 50_000;
    const RESET_TIME: u32 = 5_000;
    const POLL: u64 = 100;
    let clock = Arc::new(SimClock::new(0, POLL));
    let sim = Arc::new(SimPort::new(SimConfig::new(0x378), clock.clone()));
    let drv = PortDriver::new(Mode::Out, sim.clone(), clock.clone());
    let mut rt = RESET_TIME;
    for n in 0..9u64 {
        // Each period starts at n * PERIOD on the simulated clock.
        let now = clock.peek();
        clock.advance(n * PERIOD - now.min(n * PERIOD));
        let step = step_in(n);
        drv.write(&Outputs {
            data: step as u8,
            data_reset_mask: 0x01,
            data_reset_val: 0,
            ..Outputs::default()
        });
        rt = drv.reset(rt, PERIOD as i64);
    }
    assert_eq!(rt, RESET_TIME);
    let d = sim.writes_to(regs::DATA);
    let timeline: Vec<(u64, u8)> = d.iter().map(|w| (w.time_ns, w.value)).collect();
    eprintln!("data writes (ns, byte): {timeline:?}");
    let steps: Vec<u64> = (0..9).filter(|&n| step_in(n)).collect();
    assert_eq!(d.len(), 2 * steps.len());
    for (pair, n) in d.chunks(2).zip(steps) {
        let start = n * PERIOD;
        // The rise is logged by the write at the start of the period...
        assert!(pair[0].time_ns >= start && pair[0].time_ns < start + 5 * POLL);
        assert_eq!(pair[0].value, 1);
        // ...and the fall no earlier than reset-time after the write's
        // timestamp (taken just after the register write), within one
        // poll of the busy-wait.
        let written = pair[0].time_ns + POLL;
        assert!(pair[1].time_ns >= written + RESET_TIME as u64, "{pair:?}");
        assert!(
            pair[1].time_ns <= written + RESET_TIME as u64 + 2 * POLL,
            "{pair:?}"
        );
        assert_eq!(pair[1].value, 0);
    }
    // A reset-time above period/4 is clamped to 12500 ns.
    assert_eq!(drv.reset(40_000, PERIOD as i64), 12_500);
    let _ = clock.now_ns();
}
