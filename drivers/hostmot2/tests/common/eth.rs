//! A simulated Ethernet board served over UDP on 127.0.0.1 (a port of
//! its own), registered through `EthTransport` on a HAL instance and
//! driven cycle by cycle without threads.

use hal_core::{Host, HostConfig, MsgLevel, RtLog, Value};
use hostmot2::board::Board;
use hostmot2::config;
use hostmot2::eth::boards::lookup;
use hostmot2::eth::EthTransport;
use hostmot2::firmware::Debug;
use hostmot2::log::{BoardLog, MessageLog};
use hostmot2::sim::boards;
use hostmot2::sim::eth::{EthBoard, EthIdentity};
use hostmot2::sim::eth_server::{self, Faults, Running};
use hostmot2::sim::{machine, Hm2Model};

use super::PERIOD;

/// A read timeout generous enough that a loaded machine never misses a
/// reply that was sent (tests count only the faults they inject).
pub const TEST_TIMEOUT_NS: i32 = 100_000_000;

/// The simulated Ethernet board `preset` (its machine connected), served.
pub fn serve(preset: &str, faults: Faults) -> Running {
    let spec = boards::preset(preset).expect("preset");
    let model = Hm2Model::with_world(spec, Box::new(machine::preset(preset)));
    let identity = EthIdentity::new(boards::eth_name(preset).expect("an Ethernet preset"));
    eth_server::spawn(
        EthBoard::new(model, identity).with_period(PERIOD as u64),
        faults,
    )
    .expect("a UDP socket on 127.0.0.1")
}

/// A board on the network.
pub struct EthRig {
    /// Its board.
    pub board: Board,
    /// The simulator serving it.
    pub server: Running,
    /// The HAL name prefix.
    pub prefix: String,
    /// Realtime messages.
    pub log: RtLog,
    /// The host.
    pub host: Host,
}

impl EthRig {
    /// Registers the simulated board `preset` with `config`.
    pub fn new(tag: &str, preset: &str, config: &str) -> EthRig {
        let server = serve(preset, Faults::default());
        let host = Host::create(HostConfig::for_tests(tag)).unwrap();
        let name = boards::eth_name(preset).unwrap();
        let llio = lookup(name).unwrap().llio(0);
        let prefix = llio.name.clone();
        let log = RtLog::new(1024);
        log.set_level(MsgLevel::All);
        let b = host.new_rt_component("hm2_eth").unwrap();
        let mut t = EthTransport::connect(server.addr()).unwrap();
        t.set_name(name);
        t.errors().export(b.component(), &prefix).unwrap();
        let mut msgs = MessageLog::default();
        let board = Board::open(
            b.component(),
            llio,
            &config::parse(config).unwrap(),
            Debug::default(),
            Box::new(t),
            BoardLog::new(log.clone(), &prefix),
            &mut msgs,
        )
        .unwrap_or_else(|e| panic!("{e}: {msgs:?}"));
        b.ready().unwrap();
        let rig = EthRig {
            board,
            server,
            prefix,
            log,
            host,
        };
        rig.set_param("packet-read-timeout", Value::S32(TEST_TIMEOUT_NS));
        rig
    }

    /// One servo cycle: read-request, read, write.
    pub fn cycle(&mut self) {
        self.board.read_request();
        self.board.read();
        self.board.write(PERIOD);
    }

    /// `n` cycles.
    pub fn cycles(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }

    fn full(&self, name: &str) -> String {
        format!("{}.{name}", self.prefix)
    }

    /// Sets pin `<prefix>.<name>`.
    pub fn set_pin(&self, name: &str, v: Value) {
        self.host.instance().set_pin(&self.full(name), v).unwrap();
    }

    /// Sets param `<prefix>.<name>`.
    pub fn set_param(&self, name: &str, v: Value) {
        self.host.instance().set_param(&self.full(name), v).unwrap();
    }

    /// Pin `<prefix>.<name>`.
    pub fn pin(&self, name: &str) -> Value {
        self.host.instance().pin_value(&self.full(name)).unwrap()
    }

    /// Param `<prefix>.<name>`.
    pub fn param(&self, name: &str) -> Value {
        self.host.instance().param_value(&self.full(name)).unwrap()
    }

    /// A register of the simulated board.
    pub fn reg(&self, addr: usize) -> u32 {
        self.server.shared().with(|b| b.model().read32(addr))
    }

    /// The realtime messages said so far.
    pub fn messages(&self) -> Vec<String> {
        let mut v = Vec::new();
        self.log.drain(|_, t| v.push(t.to_string()));
        v
    }
}
