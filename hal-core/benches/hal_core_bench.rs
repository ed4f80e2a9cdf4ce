//! Prints the HAL core's figures: pin access through a signal, executor
//! cost per function (timing on and off), and thread wake-up latency.
//!
//! `cargo bench -p hal-core` runs everything (about 25 s);
//! `cargo bench -p hal-core -- quick` skips the 10 s latency run.

use std::hint::black_box;
use std::time::{Duration, Instant};

use hal_core::*;

fn main() -> Result<()> {
    let quick = std::env::args().any(|a| a == "quick");
    let name = format!("bench-{}", std::process::id());
    let host = Host::create(HostConfig::new(&name))?;
    println!(
        "HAL core benchmark (instance '{name}', realtime: {})",
        host.is_realtime()
    );
    pin_access(&host)?;
    executor_cost(&host)?;
    if !quick {
        latency(&host)?;
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

fn executor_cost(host: &Host) -> Result<()> {
    const FUNCTS: usize = 100;
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
    for i in 0..FUNCTS {
        host.addf(&format!("trivial.{i}"), "cost", -1)?;
    }
    host.addf("trivial.record", "cost", -1)?;
    println!("\nexecutor cost, {FUNCTS} trivial functions on one 1 ms thread, 2 s each");
    for timing in [true, false] {
        host.set_function_timing(timing);
        let mut reader = RingReader::open(inst, "trivial.times")?;
        host.start()?;
        std::thread::sleep(Duration::from_secs(2));
        host.stop();
        let mut v = Vec::new();
        let mut rec = [0u64];
        while reader.pop(&mut rec) {
            v.push(rec[0] as f64 / (FUNCTS + 1) as f64);
        }
        v.drain(..v.len().min(2)); // first cycles fault pages in
        v.sort_by(f64::total_cmp);
        if v.is_empty() {
            println!("  no cycles ran");
            continue;
        }
        println!(
            "  timing {:<3}: per function median {:.1} ns, best {:.1} ns, p99 {:.1} ns ({} cycles)",
            if timing { "on" } else { "off" },
            v[v.len() / 2],
            v[0],
            v[v.len() * 99 / 100],
            v.len()
        );
    }
    host.set_function_timing(true);
    host.unload("trivial")?;
    host.delete_thread("cost")
}

fn latency(host: &Host) -> Result<()> {
    // Thread creation rules want the fastest first and the first thread
    // fixes the base period, so latency gets a host of its own.
    let _ = host;
    let lat = Host::create(HostConfig::new(&format!(
        "bench-lat-{}",
        std::process::id()
    )))?;
    let mut b = lat.new_rt_component("idle")?;
    b.funct("idle.base", false, |_| {})?;
    b.funct("idle.servo", false, |_| {})?;
    b.ready()?;
    lat.create_thread("base", 50_000, true, None)?;
    lat.create_thread("servo", 1_000_000, true, None)?;
    lat.addf("idle.base", "base", -1)?;
    lat.addf("idle.servo", "servo", -1)?;
    println!("\nwake-up latency over 10 s, both threads running (us)");
    lat.start()?;
    std::thread::sleep(Duration::from_secs(10));
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
            "  {:<6} period {:>8} ns: min {:.1}, median {}, p99 {}, max {:.1} ({} cycles, {} overruns)",
            t.name,
            t.period,
            t.latency_min_ns.unwrap_or(0) as f64 / 1000.0,
            pct(0.5),
            pct(0.99),
            t.latency_max_ns.unwrap_or(0) as f64 / 1000.0,
            t.cycles,
            t.overruns
        );
    }
    println!("  (median and p99 are histogram bucket floors: 1 us resolution below 16 us)");
    Ok(())
}
