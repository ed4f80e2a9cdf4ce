//! Prints what one servo period of `hm2_modbus.N.process` costs, and the
//! register traffic it causes, with the PktUART carried in the board's
//! bursts (as hm2_modbus runs it) and, for comparison, reached by
//! immediate accesses (as it ran before: one `Transport::read` or
//! `write` per register access, each a UDP round trip on hm2_eth).
//!
//! `cargo bench -p hostmot2 --bench modbus_bench`: a simulated 5i25 with
//! PktUARTs at 115200 baud, a simulated Modbus slave reading two holding
//! registers and writing two (a new value every 50 periods), for
//! `N` periods each; mean ns per call (the machine may be shared).
//!
//! * bursts: the board's `read`, `process` on the link, the board's
//!   `write`; the immediate accesses counted during the run (0) and the
//!   bursts (one read, one write per period).
//! * immediate: `process` on a port that reads the status words and
//!   frames and writes frames directly through the transport, as before;
//!   its time includes those accesses to the simulator.
#![allow(
    clippy::unwrap_used,
    reason = "benchmark code: a failed unwrap stops the run"
)]

use std::sync::Arc;
use std::time::Instant;

use hal_core::{Host, HostConfig, MsgLevel, RtLog};
use hal_driver::sim::SimBoard;
use hostmot2::board::Board;
use hostmot2::config::Config;
use hostmot2::firmware::Debug;
use hostmot2::log::{BoardLog, MessageLog};
use hostmot2::modbus::engine::{Engine, Port};
use hostmot2::modbus::line::Versions;
use hostmot2::modbus::values::Value;
use hostmot2::pktuart::link::Status;
use hostmot2::pktuart::{LineConfig, PktUartPort};
use hostmot2::regs::pktuart::rcr;
use hostmot2::sim::modbus_slave::ModbusSlave;
use hostmot2::sim::{boards, Bench, Hm2Model, SimHm2};
use hostmot2::transport::{CountingTransport, Transport, TransportError};
use hostmot2::window::WindowTransport;

const PERIOD: i64 = 1_000_000;
const N: u64 = 20_000;

#[path = "../tests/common/modbus_file.rs"]
mod modbus_file;
use modbus_file::file;

fn sim_board() -> Arc<SimHm2> {
    let spec = boards::preset("5i25-pktuart").unwrap();
    let sim = Arc::new(SimBoard::new(Hm2Model::with_world(
        spec,
        Box::new(Bench::default()),
    )));
    let mut s = ModbusSlave::new(7, 16);
    s.holding[2] = 0x1234;
    s.holding[3] = 0xBEEF;
    sim.with(|m| m.pktuart(0).unwrap().attach(Box::new(s)));
    sim
}

fn answered(sim: &SimHm2) -> u64 {
    sim.with(|m| {
        m.pktuart(0)
            .unwrap()
            .peer::<ModbusSlave>()
            .unwrap()
            .answered
    })
}

/// A new output value every 50 periods, so writes go out.
fn vary(e: &mut Engine, k: u64) {
    if k % 50 == 0 {
        let p = e.pins.iter_mut().find(|p| p.spec.name == "out.a").unwrap();
        p.value = Value::U32(k as u32);
    }
}

/// The PktUART reached by immediate accesses, as hm2_modbus did before
/// its traffic moved into the board's bursts.
struct Immediate<'a> {
    port: &'a PktUartPort,
    t: &'a mut dyn Transport,
    scratch: [u32; 64],
}

impl Port for Immediate<'_> {
    fn take_status(&mut self) -> Option<Status> {
        let tx_mode = self.port.tx_status(self.t).ok()?;
        let rx_mode = self.port.rx_status(self.t).ok()?;
        Some(Status { tx_mode, rx_mode })
    }
    fn configure(
        &mut self,
        rx: &LineConfig,
        tx: &LineConfig,
        flush: bool,
    ) -> Result<(), TransportError> {
        self.port.configure(self.t, rx, tx, flush)
    }
    fn clear(&mut self) -> Result<(), TransportError> {
        self.port.clear(self.t)
    }
    fn send(&mut self, frame: &[u8]) -> Result<(), TransportError> {
        self.port.send(self.t, frame, &mut self.scratch)
    }
    fn fetching(&self) -> bool {
        false
    }
    fn fetch_frame(&mut self, out: &mut [u8]) -> Result<Option<(u32, usize)>, TransportError> {
        let count = self.port.pop_frame_size(self.t)?;
        let size = (count & rcr::NBYTES_MASK) as usize;
        let n = self.port.read_frame(self.t, size, out)?;
        Ok(Some((count, n)))
    }
}

fn bursts() {
    let host = Host::create(HostConfig::for_tests("hm2-modbus-bench")).unwrap();
    let sim = sim_board();
    let spec = boards::preset("5i25-pktuart").unwrap();
    let t = CountingTransport::new(WindowTransport::new(sim.clone()));
    let counts = t.counts();
    let log = RtLog::new(64);
    log.set_level(MsgLevel::None);
    let b = host.new_rt_component("hm2_pci").unwrap();
    let mut board: Board = Board::open(
        b.component(),
        spec.llio(0),
        &Config::default(),
        Debug::default(),
        Box::new(t),
        BoardLog::new(log, "hm2_5i25.0"),
        &mut MessageLog::default(),
    )
    .unwrap();
    b.ready().unwrap();
    let (mut bare_ns, mut k) = (0u128, 0);
    for _ in 0..N {
        let t0 = Instant::now();
        board.read();
        board.write(PERIOD);
        bare_ns += t0.elapsed().as_nanos();
        k += 1;
    }
    let inst = board.firmware().pktuart.instances[0].clone();
    let id = board.attach_pktuart(&inst).unwrap();
    let mut e = Engine::new(file(), Versions { rx: 3, tx: 3 });
    let (rx, tx) = e.configs();
    let link = board.pktuart_link(id).unwrap();
    link.configure(&rx, &tx, true).unwrap();
    let (imm0, rb0, wb0) = (
        counts.immediate(),
        counts
            .read_bursts
            .load(std::sync::atomic::Ordering::Relaxed),
        counts
            .write_bursts
            .load(std::sync::atomic::Ordering::Relaxed),
    );
    let (mut board_ns, mut process_ns) = (0u128, 0u128);
    for k in 0..N {
        vary(&mut e, k);
        let t0 = Instant::now();
        board.read();
        let t1 = Instant::now();
        e.process(board.pktuart_link(id).unwrap(), PERIOD);
        let t2 = Instant::now();
        board.write(PERIOD);
        let t3 = Instant::now();
        sim.advance(PERIOD as u64);
        board_ns += (t1 - t0 + (t3 - t2)).as_nanos();
        process_ns += (t2 - t1).as_nanos();
    }
    let per = |x: u128| x as f64 / N as f64;
    let load = std::sync::atomic::Ordering::Relaxed;
    println!("  bursts (as hm2_modbus runs now):");
    println!(
        "    {:<52} {:8.1} ns",
        "hm2_modbus.0.process",
        per(process_ns)
    );
    println!(
        "    {:<52} {:8.1} ns",
        "board read + write, with the PktUART's words",
        per(board_ns)
    );
    println!(
        "    {:<52} {:8.1} ns",
        "board read + write, no PktUART attached",
        bare_ns as f64 / k as f64
    );
    println!(
        "    immediate accesses per period {:.2}; bursts per period: {:.2} read, {:.2} write; {} exchanges",
        (counts.immediate() - imm0) as f64 / N as f64,
        (counts.read_bursts.load(load) - rb0) as f64 / N as f64,
        (counts.write_bursts.load(load) - wb0) as f64 / N as f64,
        answered(&sim)
    );
    assert!(!e.global.fault, "{:?}", e.commands);
}

fn immediate() {
    let sim = sim_board();
    let spec = boards::preset("5i25-pktuart").unwrap();
    let idrom = spec.idrom();
    let mut t = CountingTransport::new(WindowTransport::new(sim.clone()));
    let counts = t.counts();
    let mds = hostmot2::md::read_all(&mut t, &idrom).unwrap();
    let inst = hostmot2::pktuart::PktUartFirmware::discover(&mds, "hm2_5i25.0")
        .unwrap()
        .instances[0]
        .clone();
    let port = PktUartPort::new(inst);
    let mut e = Engine::new(file(), Versions { rx: 3, tx: 3 });
    let (rx, tx) = e.configs();
    port.configure(&mut t, &rx, &tx, true).unwrap();
    let imm0 = counts.immediate();
    let mut process_ns = 0u128;
    for k in 0..N {
        vary(&mut e, k);
        let mut p = Immediate {
            port: &port,
            t: &mut t,
            scratch: [0; 64],
        };
        let t0 = Instant::now();
        e.process(&mut p, PERIOD);
        process_ns += t0.elapsed().as_nanos();
        sim.advance(PERIOD as u64);
    }
    println!("  immediate accesses (as hm2_modbus ran before):");
    println!(
        "    {:<52} {:8.1} ns",
        "hm2_modbus.0.process (its accesses included)",
        process_ns as f64 / N as f64
    );
    println!(
        "    immediate accesses per period {:.2} (each a round trip on hm2_eth); {} exchanges",
        (counts.immediate() - imm0) as f64 / N as f64,
        answered(&sim)
    );
    assert!(!e.global.fault, "{:?}", e.commands);
}

fn main() {
    println!(
        "hm2_modbus on a simulated 5i25, 115200 baud, read 2 + write 2 registers ({N} periods)"
    );
    bursts();
    immediate();
}
