//! Prints the HAL core's figures: pin access through a signal, executor
//! cost per function (timing on and off), a thread's fixed cost per cycle
//! (alone and with a sampler-style ring function), and the 1 ms thread's
//! wake-up latency with and without realtime scheduling.
//!
//! `cargo bench -p hal-core` runs everything (about 30 s);
//! `cargo bench -p hal-core -- quick` skips the 10 s latency runs;
//! `cargo bench -p hal-core -- latency` runs only them (`HAL_NO_SHORT_SLICE=1`
//! shows the non-realtime tail without the executor's short slice).

use std::hint::black_box;
use std::time::{Duration, Instant};

use hal_core::*;

fn main() -> Result<()> {
    let quick = std::env::args().any(|a| a == "quick");
    if std::env::args().any(|a| a == "latency") {
        println!("\nwake-up latency of a lone 1 ms thread over 5 s (us)");
        latency(RealtimeMode::Auto)?;
        return latency(RealtimeMode::Off);
    }
    let name = format!("bench-{}", std::process::id());
    let host = Host::create(HostConfig::new(&name))?;
    println!(
        "HAL core benchmark (instance '{name}', realtime: {})",
        host.is_realtime()
    );
    pin_access(&host)?;
    executor_cost(&host)?;
    thread_cost()?;
    if !quick {
        println!("\nwake-up latency of a lone 1 ms thread over 5 s (us)");
        latency(RealtimeMode::Auto)?;
        latency(RealtimeMode::Off)?;
    }
    Ok(())
}

fn pin_access(host: &Host) -> Result<()> {
    let inst = host.instance();
    let c = inst.new_component("pins", ComponentKind::User)?;
    let out: Pin<f64, Out> = c.pin("pins.out")?;
    let input: Pin<f64, In> = c.pin("pins.in")?;
    inst.newsig("pins.sig", HalType::Float)?;
    inst.link("pins.out", "pins.sig")?;
    inst.link("pins.in", "pins.sig")?;
    const N: u64 = 200_000_000;
    let t = Instant::now();
    let mut acc = 0.0;
    for _ in 0..N {
        acc += black_box(&input).get();
    }
    black_box(acc);
    let read = t.elapsed().as_nanos() as f64 / N as f64;
    let t = Instant::now();
    for i in 0..N {
        black_box(&out).set(i as f64);
    }
    let write = t.elapsed().as_nanos() as f64 / N as f64;
    println!("\npin access through a signal ({N} each)");
    println!("  read : {read:.2} ns");
    println!("  write: {write:.2} ns");
    Ok(())
}

/// Median of the thread times a cycle-recording function pushed into
/// `trivial.times` during `run` (the first cycles, which fault pages in,
/// left out); `None` if no cycle ran.
fn median_thread_time(host: &Host, run: Duration) -> Result<Option<f64>> {
    let mut reader = RingReader::open(host.instance(), "trivial.times")?;
    host.start()?;
    std::thread::sleep(run);
    host.stop();
    let mut v = Vec::new();
    let mut rec = [0u64];
    while reader.pop(&mut rec) {
        v.push(rec[0] as f64);
    }
    v.drain(..v.len().min(2));
    v.sort_by(f64::total_cmp);
    Ok((!v.is_empty()).then(|| v[v.len() / 2]))
}

/// Executor cost per function: 100 trivial functions (each adds one to
/// its own pin) on a 1 ms thread, timed and untimed, as the thread's own
/// time with them minus its time without them, divided by 100; beside it
/// the floor: the same 100 calls through plain function pointers in a
/// loop once per ms on a thread placed as the HAL's, no HAL.
fn executor_cost(host: &Host) -> Result<()> {
    const FUNCTS: usize = 100;
    const RUN: Duration = Duration::from_secs(2);
    let mut b = host.new_rt_component("trivial")?;
    for i in 0..FUNCTS {
        let p: Pin<u32, Out> = b.component().pin(&format!("trivial.{i}.count"))?;
        b.funct(&format!("trivial.{i}"), false, move |_| {
            p.set(p.get().wrapping_add(1))
        })?;
    }
    // Records the thread's own time of the previous cycle.
    let time: Pin<i32, In> = b.component().pin("trivial.thread-time")?;
    let mut ring = RingWriter::create(b.component(), "trivial.times", 1 << 16, 1)?;
    b.funct("trivial.record", false, move |_| {
        ring.push(&[time.get() as u64]);
    })?;
    b.ready()?;
    let inst = host.instance();
    host.create_thread("cost", 1_000_000, true, None)?;
    inst.newsig("cost-time", HalType::S32)?;
    inst.link("cost.time", "cost-time")?;
    inst.link("trivial.thread-time", "cost-time")?;
    host.addf("trivial.record", "cost", -1)?;
    println!(
        "\nexecutor cost per function, {FUNCTS} trivial functions on a 1 ms thread \
         (thread time with them - without, / {FUNCTS}; medians of {} s)",
        RUN.as_secs()
    );
    let mut empty = [None, None];
    for (k, timing) in [true, false].into_iter().enumerate() {
        host.set_function_timing(timing);
        empty[k] = median_thread_time(host, RUN)?;
    }
    for i in 0..FUNCTS {
        host.addf(&format!("trivial.{i}"), "cost", -1)?;
    }
    for (k, timing) in [true, false].into_iter().enumerate() {
        host.set_function_timing(timing);
        let full = median_thread_time(host, RUN)?;
        match (full, empty[k]) {
            (Some(full), Some(empty)) => println!(
                "  timing {:<3}: {:.1} ns per function (thread time {full:.0} ns, without them {empty:.0} ns)",
                if timing { "on" } else { "off" },
                (full - empty) / FUNCTS as f64
            ),
            _ => println!("  timing {}: no cycles ran", if timing { "on" } else { "off" }),
        }
    }
    host.set_function_timing(true);
    host.unload("trivial")?;
    host.delete_thread("cost")?;
    let floor = plain_call_floor(FUNCTS, RUN, host.is_realtime());
    println!("  floor     : {floor:.1} ns per call (plain function pointers, no HAL)");
    Ok(())
}

/// Adds one to a counter: the floor's trivial function.
#[inline(never)]
fn bump(counter: &std::sync::atomic::AtomicU32) {
    counter.store(
        counter
            .load(std::sync::atomic::Ordering::Relaxed)
            .wrapping_add(1),
        std::sync::atomic::Ordering::Relaxed,
    );
}

/// Per-call cost of `n` calls through plain function pointers, once per
/// ms on a thread placed as a HAL thread (its CPU, SCHED_FIFO when
/// `realtime`): the median over `run` of each cycle's time / n.
fn plain_call_floor(n: usize, run: Duration, realtime: bool) -> f64 {
    use std::sync::atomic::AtomicU32;
    let clock = clock::TickClock::calibrate();
    let worker = std::thread::spawn(move || {
        if let Some(cpu) = hal_core::realtime::default_cpu() {
            let _ = hal_core::realtime::pin_to_cpu(cpu);
        }
        if realtime {
            let _ = hal_core::realtime::set_fifo(TOP_PRIORITY);
        }
        let counters: Vec<AtomicU32> = (0..n).map(|_| AtomicU32::new(0)).collect();
        // A plain call: the function and its argument.
        type Call<'a> = (fn(&AtomicU32), &'a AtomicU32);
        let calls: Vec<Call<'_>> = counters
            .iter()
            .map(|c| (bump as fn(&AtomicU32), c))
            .collect();
        let mut per_call = Vec::new();
        let mut next = clock::monotonic_ns();
        let end = next + run.as_nanos() as u64;
        while next < end {
            next += 1_000_000;
            clock::sleep_until(next);
            let t0 = clock.now();
            for (f, c) in black_box(&calls) {
                f(c);
            }
            per_call.push(clock.to_ns(clock.now().wrapping_sub(t0)) as f64 / n as f64);
        }
        per_call.drain(..per_call.len().min(2));
        per_call.sort_by(f64::total_cmp);
        per_call
            .get(per_call.len() / 2)
            .copied()
            .unwrap_or(f64::NAN)
    });
    worker.join().unwrap_or(f64::NAN)
}

/// CPU time the kernel has charged to this process's thread named `comm`,
/// in ns (`/proc/self/task/*/schedstat`, first field).
fn thread_cpu_ns(comm: &str) -> Option<u64> {
    for task in std::fs::read_dir("/proc/self/task").ok()? {
        let dir = task.ok()?.path();
        let name = std::fs::read_to_string(dir.join("comm")).unwrap_or_default();
        if name.trim_end() == comm {
            let stat = std::fs::read_to_string(dir.join("schedstat")).ok()?;
            return stat.split_whitespace().next()?.parse().ok();
        }
    }
    None
}

/// A 1 ms thread's whole cost per cycle as the kernel charges it (wake-up,
/// the executor's bookkeeping, its time/tmax, the histogram, the
/// functions), with one empty function and with a sampler-style function
/// (four pins through signals into a ring that another thread drains).
fn thread_cost() -> Result<()> {
    const RUN: Duration = Duration::from_secs(3);
    println!(
        "\nthread cost per cycle, 1 ms thread, {} s each (CPU time charged to the thread)",
        RUN.as_secs()
    );
    for (label, sampler) in [("one empty function", false), ("sampler, 4 pins", true)] {
        let host = Host::create(HostConfig::new(&format!("bench-th-{}", std::process::id())))?;
        let inst = host.instance();
        let mut b = host.new_rt_component("smp")?;
        let c = b.component();
        if sampler {
            let pins: Vec<Pin<f64, In>> = (0..4)
                .map(|i| c.pin(&format!("smp.in.{i}")))
                .collect::<Result<_>>()?;
            let mut ring = RingWriter::create(c, "smp.fifo", 4000, 5)?;
            let mut row = [0u64; 5];
            let mut n = 0u64;
            b.funct("smp.f", false, move |_| {
                for (slot, p) in row[1..].iter_mut().zip(&pins) {
                    *slot = p.get().to_bits();
                }
                n += 1;
                row[0] = n;
                black_box(ring.push(&row));
                black_box(ring.len());
            })?;
        } else {
            b.funct("smp.f", false, |_| {})?;
        }
        b.ready()?;
        if sampler {
            for i in 0..4 {
                inst.newsig(&format!("smp-{i}"), HalType::Float)?;
                inst.link(&format!("smp.in.{i}"), &format!("smp-{i}"))?;
            }
        }
        host.create_thread("fixed", 1_000_000, true, None)?;
        host.addf("smp.f", "fixed", -1)?;
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let drain = sampler.then(|| {
            let mut reader = RingReader::open(inst, "smp.fifo").expect("ring");
            let stop = stop.clone();
            std::thread::spawn(move || {
                let mut rec = [0u64; 5];
                while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                    while reader.pop(&mut rec) {}
                    std::thread::sleep(Duration::from_millis(20));
                }
            })
        });
        host.start()?;
        std::thread::sleep(Duration::from_millis(200));
        let (c0, n0) = (thread_cpu_ns("hal-fixed"), inst.threads()?[0].cycles);
        std::thread::sleep(RUN);
        let (c1, n1) = (thread_cpu_ns("hal-fixed"), inst.threads()?[0].cycles);
        host.stop();
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        if let Some(d) = drain {
            let _ = d.join();
        }
        match (c0, c1) {
            (Some(c0), Some(c1)) if n1 > n0 => println!(
                "  {label:<20}: {:.0} ns per cycle ({} cycles, realtime: {})",
                (c1 - c0) as f64 / (n1 - n0) as f64,
                n1 - n0,
                host.is_realtime()
            ),
            _ => println!("  {label:<20}: no figure (schedstat unavailable or no cycles)"),
        }
        host.shutdown();
    }
    Ok(())
}

fn latency(mode: RealtimeMode) -> Result<()> {
    let mut config = HostConfig::new(&format!("bench-lat-{}", std::process::id()));
    config.realtime = mode;
    let lat = Host::create(config)?;
    let mut b = lat.new_rt_component("idle")?;
    b.funct("idle.servo", false, |_| {})?;
    b.ready()?;
    lat.create_thread("servo", 1_000_000, true, None)?;
    lat.addf("idle.servo", "servo", -1)?;
    lat.start()?;
    std::thread::sleep(Duration::from_secs(5));
    lat.stop();
    for t in lat.instance().threads()? {
        let total: u64 = t.latency_histogram.iter().sum();
        let pct = |p: f64| -> u64 {
            let want = (total as f64 * p).ceil() as u64;
            let mut seen = 0;
            for (b, n) in t.latency_histogram.iter().enumerate() {
                seen += n;
                if seen >= want.max(1) {
                    return latency_bucket_floor_us(b);
                }
            }
            0
        };
        println!(
            "  realtime {:<5}: min {:.1}, p50 {}, p99 {}, p99.9 {}, max {:.1} ({} cycles, {} overruns)",
            lat.is_realtime(),
            t.latency_min_ns.unwrap_or(0) as f64 / 1000.0,
            pct(0.5),
            pct(0.99),
            pct(0.999),
            t.latency_max_ns.unwrap_or(0) as f64 / 1000.0,
            t.cycles,
            t.overruns
        );
    }
    lat.shutdown();
    Ok(())
}
