//! Prints ns per hostmot2 `read` and `write` for a 5i24 with 8 encoders,
//! 8 step generators, 8 PWM generators and 72 I/O, and the register
//! accesses of one cycle.
//!
//! `cargo bench -p hostmot2` runs the board's cycle functions directly
//! (no thread), all modules enabled and moving, timed with hal-driver's
//! `bench::per_call` (mean ns; the machine may be shared), twice:
//!
//! * on the simulated transport (the firmware model behind hal-driver's
//!   SimBoard, as `hm2_pci sim=5i24` runs), whose time includes the
//!   model's work;
//! * on a plain memory window that only stores words (what the driver
//!   alone costs; a real BAR adds the bus's latency per access).
#![allow(
    clippy::unwrap_used,
    reason = "benchmark code: a failed unwrap stops the run"
)]

use std::sync::Arc;

use std::time::Instant;

use hal_core::{Host, HostConfig, MsgLevel, RtLog, Value};
use hal_driver::bench::per_call;
use hal_driver::sim::{AccessLog, SimBoard};
use hostmot2::board::Board;
use hostmot2::config;
use hostmot2::firmware::Debug;
use hostmot2::image::Memory;
use hostmot2::log::{BoardLog, MessageLog};
use hostmot2::sim::{boards, machine, Hm2Model};
use hostmot2::transport::Transport;
use hostmot2::window::WindowTransport;

const PERIOD: i64 = 1_000_000;
const N: u64 = 20_000;

fn register(host: &Host, t: Box<dyn Transport>) -> Board {
    let spec = boards::preset("5i24").unwrap();
    let log = RtLog::new(64);
    log.set_level(MsgLevel::None);
    let b = host.new_rt_component("hm2_pci").unwrap();
    let board = Board::open(
        b.component(),
        spec.llio(0),
        &config::Config::default(),
        Debug::default(),
        t,
        BoardLog::new(log, "hm2_5i24.0"),
        &mut MessageLog::default(),
    )
    .unwrap();
    b.ready().unwrap();
    board
}

/// Every module enabled and commanded to move.
fn enable_all(host: &Host) {
    let i = host.instance();
    for k in 0..8 {
        let p = |n: &str| format!("hm2_5i24.0.{n}");
        i.set_pin(&p(&format!("stepgen.{k:02}.enable")), Value::Bit(true))
            .unwrap();
        i.set_pin(
            &p(&format!("stepgen.{k:02}.control-type")),
            Value::Bit(true),
        )
        .unwrap();
        i.set_pin(
            &p(&format!("stepgen.{k:02}.velocity-cmd")),
            Value::Float(0.5),
        )
        .unwrap();
        i.set_pin(&p(&format!("pwmgen.{k:02}.enable")), Value::Bit(true))
            .unwrap();
        i.set_pin(&p(&format!("pwmgen.{k:02}.value")), Value::Float(0.3))
            .unwrap();
    }
    for io in 64..72 {
        let p = format!("hm2_5i24.0.gpio.{io:03}.is_output");
        i.set_param(&p, Value::Bit(io % 2 == 0)).unwrap();
    }
}

/// Read and write times of one run, ns per call.
struct Times {
    read: Vec<u64>,
    write: Vec<u64>,
}

fn pct(v: &mut [u64], p: usize) -> f64 {
    v.sort_unstable();
    v[(v.len() - 1) * p / 100] as f64
}

/// Runs `N` cycles (read, write, then `between`), timing read and
/// write separately.
fn cycles(board: &mut Board, mut between: impl FnMut()) -> Times {
    for _ in 0..N / 10 {
        board.read();
        board.write(PERIOD);
        between();
    }
    let mut t = Times {
        read: Vec::with_capacity(N as usize),
        write: Vec::with_capacity(N as usize),
    };
    for _ in 0..N {
        let t0 = Instant::now();
        board.read();
        let t1 = Instant::now();
        board.write(PERIOD);
        let t2 = Instant::now();
        between();
        t.read.push((t1 - t0).as_nanos() as u64);
        t.write.push((t2 - t1).as_nanos() as u64);
    }
    t
}

/// Prints the median and the 10th percentile of each call: the machine
/// is shared, and a mean counts every preemption; the low percentile is
/// what a call costs when nothing preempts it.
fn report(what: &str, mut t: Times) {
    let (r50, r10) = (pct(&mut t.read, 50), pct(&mut t.read, 10));
    let (w50, w10) = (pct(&mut t.write, 50), pct(&mut t.write, 10));
    println!("  {what}:                 median      p10");
    println!("    read                        {r50:8.0} ns {r10:8.0} ns");
    println!("    write                       {w50:8.0} ns {w10:8.0} ns");
    println!(
        "    read + write                {:8.0} ns {:8.0} ns",
        r50 + w50,
        r10 + w10
    );
}

fn main() {
    println!(
        "hostmot2 on a 5i24: 8 encoders, 8 stepgens, 8 PWM generators, 72 I/O ({N} calls each)"
    );

    let host = Host::create(HostConfig::for_tests("hm2-bench-sim")).unwrap();
    let spec = boards::preset("5i24").unwrap();
    let sim = Arc::new(
        SimBoard::new(Hm2Model::with_world(
            spec,
            Box::new(machine::preset("5i24")),
        ))
        .with_log(AccessLog::new(1024)),
    );
    let mut board = register(&host, Box::new(WindowTransport::new(sim.clone())));
    enable_all(&host);
    println!("  simulated transport (the firmware model's work included):");
    let r = per_call("read", N, |_| board.read());
    let w = per_call("write", N, |_| board.write(PERIOD));
    println!("  {:<48} {:8.1} ns", "read + write", r + w);
    per_call("read, write and 1 ms of simulated time", N / 10, |_| {
        board.read();
        board.write(PERIOD);
        sim.advance(PERIOD as u64);
    });
    report(
        "per cycle, simulated",
        cycles(&mut board, || sim.advance(PERIOD as u64)),
    );
    let before = board.stats();
    sim.clear_log();
    board.read();
    let reads = sim.access_count();
    sim.clear_log();
    board.write(PERIOD);
    let writes = sim.access_count();
    let after = board.stats();
    println!(
        "  one cycle: {reads} register reads in {} bursts, {writes} register writes in {} bursts",
        after.read_bursts - before.read_bursts,
        after.write_bursts - before.write_bursts
    );
    drop(board);
    drop(host);

    let host = Host::create(HostConfig::for_tests("hm2-bench-mem")).unwrap();
    let image = boards::preset("5i24").unwrap().image();
    let mem = Arc::new(SimBoard::new(Memory(image)));
    let mut board = register(&host, Box::new(WindowTransport::new(mem)));
    enable_all(&host);
    println!("  plain memory window (the driver alone):");
    let r = per_call("read", N, |_| board.read());
    let w = per_call("write", N, |_| board.write(PERIOD));
    println!("  {:<48} {:8.1} ns", "read + write", r + w);
    report("per cycle, the driver alone", cycles(&mut board, || ()));
}
