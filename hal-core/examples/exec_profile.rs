//! A fixed amount of executor work, for instruction counting and for
//! before/after timing on a busy machine: one 1 ms thread runs `N` chained
//! sum2-style functions (two float inputs, three float parameters, one
//! output, each input linked to the previous function's output through a
//! signal) for `CYCLES` cycles, then stops.
//!
//!     valgrind --tool=callgrind target/release/examples/exec_profile 100 2000 on
//!     target/release/examples/exec_profile 100 2000 on cold
//!
//! Arguments: functions (default 100), cycles (default 2000), `on`/`off`
//! per-function timing (default on), `cold` to evict the caches before
//! every cycle. Comparing the executor's inclusive instruction count for
//! two function counts gives the cost per function independent of the
//! machine's load.
//!
//! Run natively, it prints the median and best time of the chain per
//! cycle: a function before the chain reads the TSC and one after it reads
//! it again, so the figure covers the functions and the executor's work
//! between them (its timing when on) and nothing else. With `cold`, a
//! function ahead of them first sweeps a buffer larger than the L2 cache,
//! as the other processes of a loaded machine do between two cycles, so
//! that the chain runs from L3 every time: a repeatable stand-in for a
//! busy machine.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Arc;
use std::time::Duration;

use hal_core::clock::TickClock;
use hal_core::*;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let functs: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let cycles: u64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(2000);
    let timing = args.get(3).map(String::as_str) != Some("off");
    let cold = args.iter().any(|a| a == "cold");
    let mut config = HostConfig::new(&format!("exec-profile-{}", std::process::id()));
    config.shm_size = 4 << 20;
    let host = Host::create(config)?;
    let inst = host.instance();
    let clock = TickClock::calibrate();
    let mut b = host.new_rt_component("sum")?;
    let mut buffer = vec![0u8; 6 << 20];
    b.funct("sum.evict", false, move |_| {
        for i in (0..buffer.len()).step_by(64) {
            buffer[i] = buffer[i].wrapping_add(1);
        }
        std::hint::black_box(&buffer);
    })?;
    let mark = Arc::new(AtomicU64::new(0));
    let m2 = mark.clone();
    b.funct("sum.mark", false, move |_| m2.store(clock.now(), Relaxed))?;
    for i in 0..functs {
        let c = b.component();
        let in0: Pin<f64, In> = c.pin(&format!("sum.{i}.in0"))?;
        let in1: Pin<f64, In> = c.pin(&format!("sum.{i}.in1"))?;
        let out: Pin<f64, Out> = c.pin(&format!("sum.{i}.out"))?;
        let gain0: Param<f64, Rw> = c.param(&format!("sum.{i}.gain0"), 1.0)?;
        let gain1: Param<f64, Rw> = c.param(&format!("sum.{i}.gain1"), 1.0)?;
        let offset: Param<f64, Rw> = c.param(&format!("sum.{i}.offset"), 0.0)?;
        b.funct(&format!("sum.{i}"), true, move |_| {
            out.set((in0.get() * gain0.get() + in1.get() * gain1.get()) + offset.get())
        })?;
    }
    let mut ring = RingWriter::create(b.component(), "sum.times", 1 << 16, 1)?;
    b.funct("sum.record", false, move |_| {
        let span = clock.to_ns(clock.now().wrapping_sub(mark.load(Relaxed)));
        ring.push(&[span]);
    })?;
    b.ready()?;
    inst.newsig("one", HalType::Float)?;
    for i in 0..functs {
        inst.newsig(&format!("s{i}"), HalType::Float)?;
        inst.link(&format!("sum.{i}.out"), &format!("s{i}"))?;
        inst.link(&format!("sum.{i}.in1"), "one")?;
        if i > 0 {
            inst.link(&format!("sum.{i}.in0"), &format!("s{}", i - 1))?;
        }
    }
    host.create_thread("t", 1_000_000, true, None)?;
    if cold {
        host.addf("sum.evict", "t", -1)?;
    }
    host.addf("sum.mark", "t", -1)?;
    for i in 0..functs {
        host.addf(&format!("sum.{i}"), "t", -1)?;
    }
    host.addf("sum.record", "t", -1)?;
    let mut reader = RingReader::open(inst, "sum.times")?;
    host.set_function_timing(timing);
    host.start()?;
    loop {
        std::thread::sleep(Duration::from_millis(20));
        let t = &inst.threads()?[0];
        if t.cycles >= cycles {
            break;
        }
    }
    host.stop();
    let t = &inst.threads()?[0];
    let mut times = Vec::new();
    let mut rec = [0u64];
    while reader.pop(&mut rec) {
        times.push(rec[0]);
    }
    // The first cycles fault pages in.
    times.drain(..times.len().min(10));
    times.sort_unstable();
    let at = |q: f64| {
        times
            .get((times.len() as f64 * q) as usize)
            .copied()
            .unwrap_or(0)
    };
    println!(
        "{} cycles, {} overruns, realtime {}; chain ns: median {} best {} p90 {}",
        t.cycles,
        t.overruns,
        host.is_realtime(),
        at(0.5),
        at(0.0),
        at(0.9)
    );
    Ok(())
}
