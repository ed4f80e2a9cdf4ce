//! hm2_eth on a simulated 7i96S with a 7I76 on Smart Serial, over UDP on
//! 127.0.0.1: per cycle, the host CPU time of `read-request`, `read` and
//! `write` (the calling thread's CPU clock, so the wait for the reply
//! does not count), the bytes each way, and the round trip from sending
//! the request to having the reply (p50, p99, max over 10,000 cycles).
//!
//! `cargo bench -p hostmot2 --bench eth_bench [-- one-cpu]`. The
//! simulator answers from a thread of the same process (so its work is not
//! in the CPU figures but is in the round trip); all five step generators
//! move, the 7I76's outputs and spindle are driven, its inputs read.
//!
//! What the figures include, and why they vary so much between machines:
//! on loopback, sending a datagram runs the kernel's delivery to the
//! simulator's socket and the wake-up of its thread in the sender's
//! context, so `read-request` and `write` are charged for them; `read`
//! is charged for putting the thread to sleep and waking it when it has
//! to wait for the reply. Where the simulator's thread sleeps on another
//! CPU that has gone idle, every wake-up crosses CPUs (an IPI; in a VM,
//! exits to the hypervisor on both ends), which on a quiet 2-vCPU VM
//! multiplies the CPU figures and the round trip several times over the
//! same bench on a busy machine, where the other CPU is awake anyway.
//! Real hardware answers from the card, so the host pays for its own
//! sendto/recv only. `one-cpu` runs both threads on one CPU (no
//! cross-CPU wake-ups; a switch to the simulator and back instead). The
//! output gives the load average, the placement and the cost of one read
//! of the thread CPU clock (each figure includes one).
#![allow(
    clippy::unwrap_used,
    reason = "benchmark code: a failed unwrap stops the run"
)]

use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, MsgLevel, RtLog, Value};
use hostmot2::board::Board;
use hostmot2::config;
use hostmot2::eth::boards::lookup;
use hostmot2::eth::EthTransport;
use hostmot2::firmware::Debug;
use hostmot2::lbp16::parse;
use hostmot2::log::{BoardLog, MessageLog};
use hostmot2::sim::eth::{EthBoard, EthIdentity};
use hostmot2::sim::eth_server::{self, Faults};
use hostmot2::sim::{boards, machine, Hm2Model};
use nix::time::{clock_gettime, ClockId};

const PERIOD: i64 = 1_000_000;
const CYCLES: usize = 10_000;

/// The calling thread's CPU time, ns.
fn cpu_ns() -> u64 {
    let t = clock_gettime(ClockId::CLOCK_THREAD_CPUTIME_ID).expect("thread CPU clock");
    t.tv_sec() as u64 * 1_000_000_000 + t.tv_nsec() as u64
}

fn percentile(sorted: &[u64], p: f64) -> u64 {
    let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

// Long on purpose: a benchmark script, set-up then each figure in turn,
// all on the one simulated board and transport.
fn main() {
    let one_cpu = std::env::args().any(|a| a == "one-cpu");
    if one_cpu {
        // Before the simulator's thread exists, so that it inherits it.
        let cpu = hal_core::realtime::default_cpu().unwrap_or(0);
        hal_core::realtime::pin_to_cpu(cpu).unwrap();
    }
    let spec = boards::preset("7i96s").unwrap();
    let model = Hm2Model::with_world(spec, Box::new(machine::preset("7i96s")));
    let server = eth_server::spawn(
        EthBoard::new(model, EthIdentity::new("7I96S")).with_period(PERIOD as u64),
        Faults::default(),
    )
    .unwrap();
    let host = Host::create(HostConfig::for_tests("hm2-eth-bench")).unwrap();
    let llio = lookup("7I96S").unwrap().llio(0);
    let log = RtLog::new(64);
    log.set_level(MsgLevel::None);
    let b = host.new_rt_component("hm2_eth").unwrap();
    let mut t = EthTransport::connect(server.addr()).unwrap();
    t.errors().export(b.component(), &llio.name).unwrap();
    let mut board = Board::open(
        b.component(),
        llio,
        &config::Config::default(),
        Debug::default(),
        Box::new(t),
        BoardLog::new(log, "hm2_7i96s.0"),
        &mut MessageLog::default(),
    )
    .unwrap();
    b.ready().unwrap();
    let i = host.instance();
    let set = |n: &str, v| {
        let full = format!("hm2_7i96s.0.{n}");
        if i.set_pin(&full, v).is_err() {
            i.set_param(&full, v).unwrap();
        }
    };
    // A read timeout that a shared machine never exceeds: the figures
    // are about cost and round trip, not about missed deadlines.
    set("packet-read-timeout", Value::S32(100_000_000));
    for k in 0..5 {
        set(&format!("stepgen.{k:02}.enable"), Value::Bit(true));
        set(&format!("stepgen.{k:02}.control-type"), Value::Bit(true));
        set(&format!("stepgen.{k:02}.velocity-cmd"), Value::Float(0.5));
    }
    for k in (0..16).step_by(3) {
        set(&format!("7i76.0.0.output-{k:02}"), Value::Bit(true));
    }
    set("7i76.0.0.spinout", Value::Float(4.0));
    set("7i76.0.0.spinena", Value::Bit(true));

    // Warm up, then one cycle's datagrams as the simulator sees them.
    for _ in 0..200 {
        board.read_request();
        board.read();
        board.write(PERIOD);
    }
    server.shared().with(|b| b.record(true));
    board.read_request();
    board.read();
    board.write(PERIOD);
    board.read_request();
    board.read();
    let seen = server.shared().with(|b| {
        let seen = b.take_recorded();
        b.record(false);
        seen
    });
    let is_request = |d: &Vec<u8>| parse(d).flatten().any(|c| !c.cmd.write);
    let request = seen.iter().find(|d| is_request(d)).expect("a request");
    let writes = seen
        .iter()
        .find(|d| !is_request(d))
        .expect("a write datagram");
    let reply: usize = parse(request)
        .flatten()
        .filter(|c| !c.cmd.write)
        .map(|c| c.cmd.data_len())
        .sum();
    board.write(PERIOD);

    let (mut req_cpu, mut read_cpu, mut write_cpu, mut rtt) = (
        Vec::with_capacity(CYCLES),
        Vec::with_capacity(CYCLES),
        Vec::with_capacity(CYCLES),
        Vec::with_capacity(CYCLES),
    );
    for _ in 0..CYCLES {
        let wall = Instant::now();
        let c0 = cpu_ns();
        board.read_request();
        let c1 = cpu_ns();
        board.read();
        let c2 = cpu_ns();
        let round_trip = wall.elapsed();
        board.write(PERIOD);
        let c3 = cpu_ns();
        req_cpu.push(c1 - c0);
        read_cpu.push(c2 - c1);
        write_cpu.push(c3 - c2);
        rtt.push(round_trip.as_nanos() as u64);
    }
    let errors = i.pin_value("hm2_7i96s.0.packet-error-total").unwrap();
    let state = i
        .pin_value("hm2_7i96s.0.sserial.port-0.port_state")
        .unwrap();

    let mut clock_reads: Vec<u64> = (0..1000)
        .map(|_| {
            let t0 = cpu_ns();
            cpu_ns().saturating_sub(t0)
        })
        .collect();
    clock_reads.sort_unstable();
    println!(
        "hm2_eth, simulated 7i96S with a 7I76 on Smart Serial, UDP on 127.0.0.1, {CYCLES} cycles"
    );
    println!(
        "  simulator thread {}; load average {}; one thread CPU clock read {} ns",
        if one_cpu {
            "on the bench's CPU"
        } else {
            "on any CPU"
        },
        std::fs::read_to_string("/proc/loadavg")
            .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
            .unwrap_or_default(),
        percentile(&clock_reads, 0.5)
    );
    println!("  host CPU per cycle (thread CPU clock)     median      p99");
    for (what, v) in [
        ("read-request", &mut req_cpu),
        ("read (after the reply came)", &mut read_cpu),
        ("write", &mut write_cpu),
    ] {
        v.sort_unstable();
        println!(
            "  {what:<40} {:>6} ns {:>7} ns",
            percentile(v, 0.5),
            percentile(v, 0.99)
        );
    }
    println!("  bytes per cycle (UDP payload)");
    println!("  {:<40} {:>6}", "request (host to board)", request.len());
    println!("  {:<40} {:>6}", "reply (board to host)", reply);
    println!("  {:<40} {:>6}", "write (host to board)", writes.len());
    rtt.sort_unstable();
    let us = |ns: u64| Duration::from_nanos(ns).as_secs_f64() * 1e6;
    println!("  round trip, request sent to reply read");
    println!(
        "  {:<40} p50 {:.1} us, p99 {:.1} us, max {:.1} us",
        "",
        us(percentile(&rtt, 0.5)),
        us(percentile(&rtt, 0.99)),
        us(*rtt.last().unwrap())
    );
    println!("  packet errors {errors:?}, Smart Serial port state {state:?}");
}
