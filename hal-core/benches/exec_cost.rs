//! Prints the executor's cost per function for the lists the side-by-side
//! benchmark runs (bench/side-by-side.sh): chains of sum2-shaped and
//! and2-shaped functions, each output through a signal into the next
//! one's input, built in the order `loadrt sum2 count=N` and its `addf`
//! and `net` lines build them, with the same closures as the components.
//!
//! `cargo bench -p hal-core --bench exec_cost` alternates, for each shape
//! and for timing on and off, runs of a 1 ms thread with the chain and
//! without it, and prints (with N functions - without) / N at the 10th
//! percentile and the median of the thread's own time. The 10th
//! percentile moves less with the load of a shared machine.
//!
//! `cargo bench -p hal-core --bench exec_cost -- one SHAPE TIMING N SECS`
//! runs one configuration only (SHAPE sum2, and2 or trivial; TIMING timed
//! or untimed; N functions, 0 for the thread alone) and prints how many
//! cycles ran: bench/exec-instructions.sh runs it under callgrind to count
//! the instructions per cycle and per function.

use std::hint::black_box;
use std::time::Duration;

use hal_core::*;

/// The function shapes of the benchmark.
#[derive(Clone, Copy, PartialEq)]
enum Shape {
    /// out = (in0 * gain0 + in1 * gain1) + offset, as `sum2`.
    Sum2,
    /// out = in0 && in1, as `and2`.
    And2,
    /// Adds one to its own output pin.
    Trivial,
}

impl Shape {
    fn parse(s: &str) -> Option<Shape> {
        match s {
            "sum2" => Some(Shape::Sum2),
            "and2" => Some(Shape::And2),
            "trivial" => Some(Shape::Trivial),
            _ => None,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Shape::Sum2 => "sum2",
            Shape::And2 => "and2",
            Shape::Trivial => "trivial",
        }
    }
}

/// Loads `n` instances of `shape` as one component, as a halcomp module
/// does (each instance's pins, params and function in turn).
fn load(host: &Host, shape: Shape, n: usize) -> Result<()> {
    let name = shape.name();
    let mut b = host.new_rt_component(name)?;
    for i in 0..n {
        let c = b.component();
        let p = format!("{name}.{i}");
        match shape {
            Shape::Sum2 => {
                let in0: Pin<f64, In> = c.pin(&format!("{p}.in0"))?;
                let in1: Pin<f64, In> = c.pin(&format!("{p}.in1"))?;
                let out: Pin<f64, Out> = c.pin(&format!("{p}.out"))?;
                let gain0: Param<f64, Rw> = c.param(&format!("{p}.gain0"), 1.0)?;
                let gain1: Param<f64, Rw> = c.param(&format!("{p}.gain1"), 1.0)?;
                let offset: Param<f64, Rw> = c.param(&format!("{p}.offset"), 0.0)?;
                b.funct(&p, true, move |_| {
                    out.set((in0.get() * gain0.get() + in1.get() * gain1.get()) + offset.get())
                })?;
            }
            Shape::And2 => {
                let in0: Pin<bool, In> = c.pin(&format!("{p}.in0"))?;
                let in1: Pin<bool, In> = c.pin(&format!("{p}.in1"))?;
                let out: Pin<bool, Out> = c.pin(&format!("{p}.out"))?;
                b.funct(&p, false, move |_| out.set(in0.get() && in1.get()))?;
            }
            Shape::Trivial => {
                let out: Pin<u32, Out> = c.pin(&format!("{p}.out"))?;
                b.funct(&p, false, move |_| out.set(out.get().wrapping_add(1)))?;
            }
        }
    }
    b.ready()
}

/// A host with a 1 ms thread `t` running `n` chained functions of
/// `shape` and, last, a function that pushes the thread's time of the
/// previous cycle into the ring `rec.times`.
fn build(tag: &str, shape: Shape, n: usize, timed: bool) -> Result<Host> {
    let host = Host::create(HostConfig::new(&format!(
        "bench-exec-{tag}-{}",
        std::process::id()
    )))?;
    host.create_thread("t", 1_000_000, true, None)?;
    host.set_function_timing(timed);
    load(&host, shape, n)?;
    let inst = host.instance();
    let name = shape.name();
    for i in 0..n {
        host.addf(&format!("{name}.{i}"), "t", -1)?;
        if i > 0 && shape != Shape::Trivial {
            inst.newsig(
                &format!("c{i}"),
                if shape == Shape::Sum2 {
                    HalType::Float
                } else {
                    HalType::Bit
                },
            )?;
            inst.link(&format!("{name}.{}.out", i - 1), &format!("c{i}"))?;
            inst.link(&format!("{name}.{i}.in0"), &format!("c{i}"))?;
        }
    }
    let mut b = host.new_rt_component("rec")?;
    let time: Pin<i32, In> = b.component().pin("rec.thread-time")?;
    let mut ring = RingWriter::create(b.component(), "rec.times", 1 << 16, 1)?;
    b.funct("rec", false, move |_| {
        black_box(ring.push(&[time.get() as u64]));
    })?;
    b.ready()?;
    inst.newsig("thread-time", HalType::S32)?;
    inst.link("t.time", "thread-time")?;
    inst.link("rec.thread-time", "thread-time")?;
    host.addf("rec", "t", -1)?;
    Ok(host)
}

/// Runs the host's threads for `run` and returns the thread times the
/// recorder saw, sorted (the first cycles, which fault pages in, left
/// out), and the number of cycles that ran.
fn thread_times(host: &Host, run: Duration) -> Result<(Vec<f64>, u64)> {
    let mut reader = RingReader::open(host.instance(), "rec.times")?;
    host.start()?;
    std::thread::sleep(run);
    host.stop();
    let cycles = host.instance().threads()?[0].cycles;
    let mut v = Vec::new();
    let mut rec = [0u64];
    while reader.pop(&mut rec) {
        v.push(rec[0] as f64);
    }
    v.drain(..v.len().min(3));
    v.sort_by(f64::total_cmp);
    Ok((v, cycles))
}

fn percentile(v: &[f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v[((v.len() - 1) as f64 * p).round() as usize]
}

/// One configuration alone (see the header): prints its cycle count and
/// thread time.
fn one(args: &[String]) -> Result<()> {
    let usage = "usage: exec_cost one sum2|and2|trivial timed|untimed N SECS";
    let (Some(shape), Some(timing), Some(n), Some(secs)) = (
        args.first().and_then(|s| Shape::parse(s)),
        args.get(1).map(|s| s == "timed"),
        args.get(2).and_then(|s| s.parse::<usize>().ok()),
        args.get(3).and_then(|s| s.parse::<f64>().ok()),
    ) else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    let host = build("one", shape, n, timing)?;
    let (times, cycles) = thread_times(&host, Duration::from_secs_f64(secs))?;
    println!(
        "cycles {cycles} thread-time-p50 {:.0} realtime {}",
        percentile(&times, 0.5),
        host.is_realtime()
    );
    host.shutdown();
    Ok(())
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "one") {
        return one(&args[i + 1..]);
    }
    const N: usize = 100;
    const ROUNDS: usize = 3;
    const RUN: Duration = Duration::from_millis(1500);
    println!(
        "executor cost per function: {N} chained functions on a 1 ms thread, \
         (thread time with them - without) / {N}, {ROUNDS} alternating rounds of {} s, \
         median of the rounds; load average {}",
        RUN.as_secs_f64(),
        loadavg()
    );
    for shape in [Shape::Sum2, Shape::And2, Shape::Trivial] {
        for timed in [true, false] {
            let mut p10 = Vec::new();
            let mut p50 = Vec::new();
            for _ in 0..ROUNDS {
                let full = build("full", shape, N, timed)?;
                let (f, _) = thread_times(&full, RUN)?;
                full.shutdown();
                let empty = build("empty", shape, 0, timed)?;
                let (e, _) = thread_times(&empty, RUN)?;
                empty.shutdown();
                p10.push((percentile(&f, 0.1) - percentile(&e, 0.1)) / N as f64);
                p50.push((percentile(&f, 0.5) - percentile(&e, 0.5)) / N as f64);
            }
            p10.sort_by(f64::total_cmp);
            p50.sort_by(f64::total_cmp);
            println!(
                "  {:<7} {:<8}: p10 {:5.1} ns, p50 {:5.1} ns per function",
                shape.name(),
                if timed { "timed" } else { "untimed" },
                p10[ROUNDS / 2],
                p50[ROUNDS / 2]
            );
        }
    }
    println!("  (load average after: {})", loadavg());
    Ok(())
}

fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}
