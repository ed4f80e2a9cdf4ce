//! A simulated board registered on a HAL instance, driven cycle by cycle
//! without threads, so module tests are exact.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]
#![allow(dead_code)]

use std::sync::Arc;

use hal_core::{Host, HostConfig, MsgLevel, RtLog, Value};
use hal_driver::sim::{AccessLog, SimBoard};
use hostmot2::board::Board;
use hostmot2::config;
use hostmot2::firmware::Debug;
use hostmot2::image::FirmwareSpec;
use hostmot2::log::{BoardLog, MessageLog};
use hostmot2::sim::{Hm2Model, SimHm2, World};
use hostmot2::window::WindowTransport;

/// The servo period the rig runs at.
pub const PERIOD: i64 = 1_000_000;

/// A board on the simulator.
pub struct Rig {
    /// Its board.
    pub board: Board,
    /// The simulated board.
    pub sim: Arc<SimHm2>,
    /// The HAL name prefix (`hm2_5i25.0`).
    pub prefix: String,
    /// The board's realtime messages.
    pub log: RtLog,
    /// The host (last: dropped after the board).
    pub host: Host,
}

/// HAL objects of a board, by their names after its prefix.
pub trait Named {
    /// The host.
    fn host(&self) -> &Host;
    /// The board's prefix (`hm2_5i25.0`).
    fn prefix(&self) -> &str;

    /// `<prefix>.<name>`.
    fn full(&self, name: &str) -> String {
        format!("{}.{name}", self.prefix())
    }

    /// Sets pin `<prefix>.<name>`.
    fn set_pin(&self, name: &str, v: Value) {
        self.host().instance().set_pin(&self.full(name), v).unwrap();
    }

    /// Sets param `<prefix>.<name>`.
    fn set_param(&self, name: &str, v: Value) {
        self.host()
            .instance()
            .set_param(&self.full(name), v)
            .unwrap();
    }

    /// Sets pin or param `<prefix>.<name>`.
    fn set(&self, name: &str, v: Value) {
        let i = self.host().instance();
        if i.set_pin(&self.full(name), v).is_err() {
            i.set_param(&self.full(name), v).unwrap();
        }
    }

    /// Pin `<prefix>.<name>`.
    fn pin(&self, name: &str) -> Value {
        self.host().instance().pin_value(&self.full(name)).unwrap()
    }

    /// Param `<prefix>.<name>`.
    fn param(&self, name: &str) -> Value {
        self.host()
            .instance()
            .param_value(&self.full(name))
            .unwrap()
    }

    /// A bit pin.
    fn bit(&self, name: &str) -> bool {
        match self.pin(name) {
            Value::Bit(b) => b,
            v => panic!("{name} is {v:?}"),
        }
    }

    /// A float pin.
    fn float(&self, name: &str) -> f64 {
        match self.pin(name) {
            Value::Float(f) => f,
            v => panic!("{name} is {v:?}"),
        }
    }

    /// An s32 pin.
    fn s32(&self, name: &str) -> i32 {
        match self.pin(name) {
            Value::S32(v) => v,
            v => panic!("{name} is {v:?}"),
        }
    }
}

impl Named for Rig {
    fn host(&self) -> &Host {
        &self.host
    }

    fn prefix(&self) -> &str {
        &self.prefix
    }
}

impl Rig {
    /// Registers a board running `spec` wired to `world`, with `config`.
    pub fn new(tag: &str, spec: FirmwareSpec, world: Box<dyn World>, config: &str) -> Rig {
        let host = Host::create(HostConfig::for_tests(tag)).unwrap();
        let llio = spec.llio(0);
        let prefix = llio.name.clone();
        let sim = Arc::new(
            SimBoard::new(Hm2Model::with_world(spec, world)).with_log(AccessLog::new(100_000)),
        );
        let log = RtLog::new(1024);
        log.set_level(MsgLevel::All);
        let b = host.new_rt_component("hm2_pci").unwrap();
        let board = Board::open(
            b.component(),
            llio,
            &config::parse(config).unwrap(),
            Debug::default(),
            Box::new(WindowTransport::new(sim.clone())),
            BoardLog::new(log.clone(), &prefix),
            &mut MessageLog::default(),
        )
        .unwrap();
        b.ready().unwrap();
        Rig {
            board,
            sim,
            prefix,
            log,
            host,
        }
    }

    /// One servo cycle: read, write, then a period passes.
    pub fn cycle(&mut self) {
        self.board.read();
        self.board.write(PERIOD);
        self.sim.advance(PERIOD as u64);
    }

    /// `n` cycles.
    pub fn cycles(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }

    /// A register of the simulated board.
    pub fn reg(&self, addr: usize) -> u32 {
        self.sim.with(|m| m.read32(addr))
    }

    /// The realtime messages said so far.
    pub fn messages(&self) -> Vec<String> {
        let mut v = Vec::new();
        self.log.drain(|_, t| v.push(t.to_string()));
        v
    }

    /// The world, as a `W`.
    pub fn world<W: World, R>(&self, f: impl FnOnce(&mut W) -> R) -> R {
        self.sim
            .with(|m| f(m.world::<W>().expect("the world's type")))
    }
}

pub mod eth;
pub mod modbus_file;

/// A host of its own with the hostmot2 core loaded, as every board
/// driver needs before its own `loadrt`.
pub fn with_core(tag: &str) -> Host {
    let h = Host::create(HostConfig::for_tests(tag)).unwrap();
    h.loadrt(&hostmot2::hal::HOSTMOT2_MODULE, &[] as &[&str])
        .unwrap();
    h
}

/// Whether `pin` exists on `h`'s instance.
pub fn has_pin(h: &Host, pin: &str) -> bool {
    h.instance().pin(pin).unwrap().is_some()
}
