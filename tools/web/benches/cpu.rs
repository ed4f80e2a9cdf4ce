//! hal-web's CPU use, which issue 33 wants bounded, and the servo
//! thread's timing with and without a page connected: 1000 pins written
//! by a realtime function every cycle of a 1 ms thread; hal-web serving
//! first no page, then one page's live stream of all 1000 pins at 20 Hz
//! with the pins changing (the worst case: each tick reads and sends all
//! 1000 values), then standing still (each tick reads them and sends
//! nothing). hal-web's figure is its own user and system time over the
//! phase (from /proc), as a share of one core; the servo thread's is its
//! wake-up latency histogram over the phase (bucket upper edges).
//!
//! `cargo bench -p hal-web --bench cpu` (a release build of hal-web);
//! `HAL_WEB_BENCH_SECS` sets each phase's length (default 20 s).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, Out};
use hal_scope::latency::stats::ThreadStats;

/// Pins the page watches.
const PINS: usize = 1000;
/// The stream's rate (hal-web's fastest).
const HZ: u32 = 20;
/// The thread that writes the pins, and whose timing is shown.
const SERVO: &str = "servo-thread";
/// Linux reports process times in units of USER_HZ, 100 a second on
/// every architecture (the /proc ABI, whatever the kernel's own HZ).
const USER_HZ: f64 = 100.0;

/// hal-web's user plus system time so far, in USER_HZ ticks.
fn cpu_ticks(pid: u32) -> u64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).expect("hal-web's stat");
    // After the command name (in parentheses, maybe with spaces): state,
    // then ... utime and stime, the 12th and 13th fields from the state.
    let rest = &stat[stat.rfind(')').expect("a command name") + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    f[11].parse::<u64>().expect("utime") + f[12].parse::<u64>().expect("stime")
}

/// Starts hal-web on `instance` and reads where it listens.
fn start_web(instance: &str) -> (Child, SocketAddr) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hal-web"))
        .args(["-p", "0"])
        .env("HAL_INSTANCE", instance)
        .stdout(Stdio::piped())
        .spawn()
        .expect("hal-web starts");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let first = lines.next().expect("hal-web says where").expect("a line");
    std::thread::spawn(move || for _ in lines {});
    let url = first
        .split_whitespace()
        .find(|w| w.starts_with("http://"))
        .expect("an address");
    let addr = url
        .trim_start_matches("http://")
        .trim_end_matches('/')
        .parse()
        .expect("an address");
    (child, addr)
}

/// Opens the stream of every pin and counts its events and bytes on a
/// thread of its own.
fn open_stream(addr: SocketAddr, events: Arc<AtomicU64>, bytes: Arc<AtomicU64>) {
    let items: Vec<_> = (0..PINS)
        .map(|i| serde_json::json!({"kind": "pin", "name": format!("bench.{i}")}))
        .collect();
    let body = serde_json::json!({ "items": items, "hz": HZ }).to_string();
    let mut s = TcpStream::connect(addr).expect("hal-web answers");
    let head = format!(
        "POST /api/stream HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\n\r\n",
        body.len()
    );
    s.write_all(head.as_bytes()).expect("request sent");
    s.write_all(body.as_bytes()).expect("request sent");
    std::thread::spawn(move || {
        let mut buf = [0u8; 65536];
        while let Ok(n) = s.read(&mut buf) {
            if n == 0 {
                return;
            }
            bytes.fetch_add(n as u64, Ordering::Relaxed);
            let found = buf[..n].windows(5).filter(|w| w == b"data:").count();
            events.fetch_add(found as u64, Ordering::Relaxed);
        }
    });
}

/// What a phase measures: hal-web's CPU and the stream's traffic, and
/// the servo thread's wake-up latency during the phase.
struct Probe<'a> {
    host: &'a Host,
    pid: u32,
    counters: [Arc<AtomicU64>; 2],
}

/// The servo thread's histogram now.
fn servo_histogram(host: &Host) -> Vec<u64> {
    let threads = host.instance().threads().unwrap_or_default();
    threads
        .into_iter()
        .find(|t| t.name == SERVO)
        .map(|t| t.latency_histogram)
        .unwrap_or_default()
}

impl Probe<'_> {
    /// Runs one phase of `secs` and prints its figures.
    fn phase(&self, label: &str, secs: u64) {
        let load = |i: usize| self.counters[i].load(Ordering::Relaxed);
        let (e0, b0, h0) = (load(0), load(1), servo_histogram(self.host));
        let t0 = Instant::now();
        let c0 = cpu_ticks(self.pid);
        std::thread::sleep(Duration::from_secs(secs));
        let wall = t0.elapsed().as_secs_f64();
        let cpu = (cpu_ticks(self.pid) - c0) as f64 / USER_HZ;
        let events = (load(0) - e0) as f64 / wall;
        let kb = (load(1) - b0) as f64 / wall / 1000.0;
        let histogram: Vec<u64> = servo_histogram(self.host)
            .iter()
            .zip(h0.iter().chain(std::iter::repeat(&0)))
            .map(|(now, then)| now - then)
            .collect();
        let servo = ThreadStats {
            name: SERVO.into(),
            period_ns: 1_000_000,
            cycles: histogram.iter().sum(),
            overruns: 0,
            min_ns: None,
            max_ns: None,
            histogram,
        };
        let us = |p: f64| servo.percentile_ns(p).map_or(0.0, |n| n as f64 / 1000.0);
        println!(
            "  {label:<34} hal-web {:5.2} % of one core ({events:4.1} events/s, {kb:5.0} kB/s); \
             servo latency p50 {:.0} us, p99 {:.0} us, p99.9 {:.0} us, max < {:.0} us",
            100.0 * cpu / wall,
            us(0.5),
            us(0.99),
            us(0.999),
            us(1.0)
        );
    }
}

/// The host: 1000 pins a realtime function writes every servo cycle
/// while `changing` says so.
fn bench_host(name: &str, changing: Arc<AtomicBool>) -> hal_core::Result<Host> {
    let host = Host::create(HostConfig::new(name))?;
    let mut b = host.new_rt_component("bench")?;
    let pins = (0..PINS)
        .map(|i| b.component().pin::<f64, Out>(&format!("bench.{i}")))
        .collect::<hal_core::Result<Vec<_>>>()?;
    let mut step = 0u64;
    b.funct("bench.write", true, move |_| {
        if changing.load(Ordering::Relaxed) {
            step += 1;
            for (i, p) in pins.iter().enumerate() {
                p.set((step * PINS as u64 + i as u64) as f64 * 0.001);
            }
        }
    })?;
    b.ready()?;
    host.create_thread(SERVO, 1_000_000, true, None)?;
    host.addf("bench.write", SERVO, -1)?;
    host.start()?;
    Ok(host)
}

fn main() -> hal_core::Result<()> {
    let secs: u64 = std::env::var("HAL_WEB_BENCH_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let name = format!("bench-web-{}", std::process::id());
    let changing = Arc::new(AtomicBool::new(true));
    let host = bench_host(&name, changing.clone())?;
    let (mut web, addr) = start_web(&name);
    let probe = Probe {
        host: &host,
        pid: web.id(),
        counters: [Arc::new(AtomicU64::new(0)), Arc::new(AtomicU64::new(0))],
    };
    println!(
        "hal-web: {PINS} pins written every cycle of a 1 ms servo thread (realtime: {}), \
         one page watching all of them at {HZ} Hz; {secs} s a phase",
        host.is_realtime()
    );
    probe.phase("no page connected:", secs);
    open_stream(addr, probe.counters[0].clone(), probe.counters[1].clone());
    let start = Instant::now();
    while probe.counters[0].load(Ordering::Relaxed) == 0 && start.elapsed().as_secs() < 30 {
        std::thread::sleep(Duration::from_millis(10));
    }
    probe.phase("page open, pins changing:", secs);
    changing.store(false, Ordering::Relaxed);
    probe.phase("page open, pins standing still:", secs);
    println!("  (goal of issue 33: hal-web under 5 % of one core)");
    let _ = web.kill();
    let _ = web.wait();
    host.stop();
    Ok(())
}
