//! hal-web's CPU use, which issue 33 wants under 5 % of one core with a
//! page watching 1000 pins at 20 Hz and a scope of 4 channels at 10 kHz,
//! and the servo thread's timing with and without a page connected.
//!
//! The instance: a 100 us thread (`fast-thread`, 10 kHz) running a
//! siggen whose sine, cosine, triangle and square the scope records, a
//! 1 ms `servo-thread` whose wake-up latency is shown, and 1000 float
//! pins of a component the bench writes every millisecond. hal-web serves
//! it through phases: no page; one page's live stream of all 1000 pins at
//! 20 Hz with the pins changing (each tick reads and sends all 1000
//! values); the same with the scope running as the page runs it in
//! normal mode (a record of 1000 samples, 10 ms/div, on the square's
//! rising edge, asked for again as soon as one arrives, in the binary
//! form the page takes: the case); the stream with the pins
//! standing still (each tick reads them and sends nothing). hal-web's
//! figure is its own user and system time over the phase (from /proc),
//! as a share of one core; the servo thread's is its wake-up latency
//! histogram over the phase (bucket upper edges).
//!
//! `cargo bench -p hal-web --bench cpu` (a release build of hal-web);
//! `HAL_WEB_BENCH_SECS` sets each phase's length (default 20 s).

#[path = "../tests/common/mod.rs"]
#[allow(
    clippy::unwrap_used,
    reason = "the tests' own helpers: a failed unwrap ends the bench"
)]
mod common;

use std::io::Read;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use common::Web;
use hal_core::{ComponentKind, HostConfig, Instance, Out};
use hal_scope::latency::stats::ThreadStats;

/// Pins the page watches.
const PINS: usize = 1000;
/// The stream's rate (hal-web's fastest).
const HZ: u32 = 20;
/// The thread whose timing is shown.
const SERVO: &str = "servo-thread";
/// The scope's thread: 100 us, 10 kHz.
const FAST: &str = "fast-thread";
/// The instance: the two threads and the siggen the scope records.
const SETUP: &str = "\
loadrt threads name1=fast-thread period1=100000 name2=servo-thread period2=1000000
loadrt siggen
addf siggen.0.update fast-thread
setp siggen.0.frequency 20
start
";
/// The scope's four channels.
const SCOPE_PINS: [&str; 4] = [
    "siggen.0.sine",
    "siggen.0.cosine",
    "siggen.0.triangle",
    "siggen.0.square",
];
/// Samples in a record: the page's default 10 ms/div over 10 divisions.
const SCOPE_SAMPLES: usize = 1000;
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

/// Serves `name` from this process (as `hal-host` would) until the bench
/// stops it.
fn start_host(name: &str) -> std::thread::JoinHandle<()> {
    let cfg = HostConfig::new(name);
    let (tx, rx) = std::sync::mpsc::channel();
    let thread = std::thread::spawn(move || {
        hal_host::serve(cfg, move || {
            let _ = tx.send(());
        })
        .expect("the host serves");
    });
    rx.recv_timeout(Duration::from_secs(20))
        .expect("the host is ready");
    thread
}

/// Runs `text` as a HAL file on `inst`.
fn run_hal(inst: &Instance, text: &str) {
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let ok = hal_lang::Session::new(inst.clone(), Default::default(), &mut out, &mut err)
        .run_text(Some("bench.hal"), text);
    assert!(
        ok,
        "the bench's HAL file: {}",
        String::from_utf8_lossy(&err)
    );
}

/// The 1000 pins, written every millisecond while `changing` says so,
/// until `done`.
fn start_writer(inst: &Instance, changing: Arc<AtomicBool>, done: Arc<AtomicBool>) {
    let comp = inst
        .new_component("bench", ComponentKind::User)
        .expect("the bench's component");
    let pins = (0..PINS)
        .map(|i| comp.pin::<f64, Out>(&format!("bench.{i}")))
        .collect::<hal_core::Result<Vec<_>>>()
        .expect("the bench's pins");
    comp.ready().expect("the bench's component is ready");
    std::thread::spawn(move || {
        let _comp = comp;
        let mut step = 0u64;
        while !done.load(Ordering::Relaxed) {
            if changing.load(Ordering::Relaxed) {
                step += 1;
                for (i, p) in pins.iter().enumerate() {
                    p.set((step * PINS as u64 + i as u64) as f64 * 0.001);
                }
            }
            std::thread::sleep(Duration::from_millis(1));
        }
    });
}

/// Opens the stream of every pin and counts its events and bytes on a
/// thread of its own.
fn open_stream(web: &Web, events: Arc<AtomicU64>, bytes: Arc<AtomicU64>) {
    let items: Vec<_> = (0..PINS)
        .map(|i| serde_json::json!({"kind": "pin", "name": format!("bench.{i}")}))
        .collect();
    let body = serde_json::json!({ "items": items, "hz": HZ }).to_string();
    let mut s = web.open_stream(&body);
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

/// Runs the scope as the page does in normal mode while `on` says so,
/// until `done`, counting its records and its failed captures (the
/// first failure's answer is printed).
fn start_scope(
    web: Arc<Web>,
    on: Arc<AtomicBool>,
    done: Arc<AtomicBool>,
    counts: [Arc<AtomicU64>; 2],
) -> std::thread::JoinHandle<()> {
    let body = serde_json::json!({
        "pins": SCOPE_PINS, "thread": FAST, "samples": SCOPE_SAMPLES,
        "trigger": "siggen.0.square:rising:0", "pre": "20%", "mode": "normal", "timeout": 10,
    })
    .to_string();
    std::thread::spawn(move || {
        while !done.load(Ordering::Relaxed) {
            if !on.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(20));
                continue;
            }
            let (status, answer) = web.post_binary("/api/scope", &body);
            let failed = status != 200;
            if failed && counts[1].load(Ordering::Relaxed) == 0 {
                let answer = String::from_utf8_lossy(&answer);
                println!("  the scope's capture failed ({status}): {answer}");
            }
            counts[usize::from(failed)].fetch_add(1, Ordering::Relaxed);
        }
    })
}

/// The servo thread's histogram now.
fn servo_histogram(inst: &Instance) -> Vec<u64> {
    let threads = inst.threads().unwrap_or_default();
    threads
        .into_iter()
        .find(|t| t.name == SERVO)
        .map(|t| t.latency_histogram)
        .unwrap_or_default()
}

/// What a phase measures: hal-web's CPU, the stream's traffic, the
/// scope's records, and the servo thread's wake-up latency.
struct Probe {
    inst: Instance,
    pid: u32,
    events: Arc<AtomicU64>,
    bytes: Arc<AtomicU64>,
    records: Arc<AtomicU64>,
    failures: Arc<AtomicU64>,
}

impl Probe {
    /// Runs one phase of `secs` and prints its figures.
    fn phase(&self, label: &str, secs: u64) {
        let counters = [&self.events, &self.bytes, &self.records, &self.failures];
        let at = || counters.map(|c| c.load(Ordering::Relaxed));
        let (n0, h0) = (at(), servo_histogram(&self.inst));
        let t0 = Instant::now();
        let c0 = cpu_ticks(self.pid);
        std::thread::sleep(Duration::from_secs(secs));
        let wall = t0.elapsed().as_secs_f64();
        let cpu = (cpu_ticks(self.pid) - c0) as f64 / USER_HZ;
        let n1 = at();
        let rate = |i: usize| (n1[i] - n0[i]) as f64 / wall;
        let histogram: Vec<u64> = servo_histogram(&self.inst)
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
            "  {label:<38} hal-web {:5.2} % | {:4.1} events/s {:5.0} kB/s | {:4.1} records/s \
             ({} failed) | servo p50 {:3.0} us p99 {:4.0} us p99.9 {:5.0} us max < {:5.0} us",
            100.0 * cpu / wall,
            rate(0),
            rate(1) / 1000.0,
            rate(2),
            n1[3] - n0[3],
            us(0.5),
            us(0.99),
            us(0.999),
            us(1.0)
        );
    }
}

fn main() {
    let secs: u64 = std::env::var("HAL_WEB_BENCH_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(20);
    let name = format!("bench-web-{}", std::process::id());
    let host = start_host(&name);
    let inst = Instance::attach(&name).expect("the bench's instance");
    run_hal(&inst, SETUP);
    let (changing, done) = (
        Arc::new(AtomicBool::new(true)),
        Arc::new(AtomicBool::new(false)),
    );
    start_writer(&inst, changing.clone(), done.clone());
    let web = Arc::new(Web::start(&name, &[]));
    let probe = Probe {
        inst: inst.clone(),
        pid: web.pid(),
        events: Arc::new(AtomicU64::new(0)),
        bytes: Arc::new(AtomicU64::new(0)),
        records: Arc::new(AtomicU64::new(0)),
        failures: Arc::new(AtomicU64::new(0)),
    };
    println!(
        "hal-web: {PINS} pins written every ms, one page watching all of them at {HZ} Hz, \
         a scope of 4 channels on a 100 us thread (10 kHz, {SCOPE_SAMPLES} samples a record); \
         {secs} s a phase; servo-thread: 1 ms"
    );
    probe.phase("no page connected:", secs);
    open_stream(&web, probe.events.clone(), probe.bytes.clone());
    let start = Instant::now();
    while probe.events.load(Ordering::Relaxed) == 0 && start.elapsed().as_secs() < 30 {
        std::thread::sleep(Duration::from_millis(10));
    }
    probe.phase("page open, pins changing:", secs);
    let scope_on = Arc::new(AtomicBool::new(true));
    let scope = start_scope(
        web.clone(),
        scope_on.clone(),
        done.clone(),
        [probe.records.clone(), probe.failures.clone()],
    );
    probe.phase("page open, pins changing, scope running:", secs);
    scope_on.store(false, Ordering::Relaxed);
    // The capture under way ends within a record.
    std::thread::sleep(Duration::from_secs(1));
    changing.store(false, Ordering::Relaxed);
    probe.phase("page open, pins standing still:", secs);
    println!("  (goal of issue 33: hal-web under 5 % of one core with the page and the scope)");
    done.store(true, Ordering::Relaxed);
    let _ = scope.join();
    // The last handle on hal-web: it is stopped.
    drop(web);
    let _ = hal_lang::host_process::stop_host(&name, Duration::from_secs(10));
    let _ = host.join();
}
