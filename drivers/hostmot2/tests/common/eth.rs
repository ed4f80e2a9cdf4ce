//! A simulated Ethernet board served over UDP on 127.0.0.1 (a port of
//! its own), registered through `EthTransport` on a HAL instance and
//! driven cycle by cycle without threads.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use hal_core::{Host, HostConfig, MsgLevel, RtLog, Value};

use super::Named as _;
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
    serve_spec(preset, boards::preset(preset).expect("preset"), faults)
}

/// The Ethernet board `preset` running firmware `spec`, served.
pub fn serve_spec(preset: &str, spec: hostmot2::image::FirmwareSpec, faults: Faults) -> Running {
    let model = Hm2Model::with_world(spec, Box::new(machine::preset(preset)));
    let identity = EthIdentity::new(boards::eth_name(preset).expect("an Ethernet preset"));
    eth_server::spawn(
        EthBoard::new(model, identity).with_period(PERIOD as u64),
        faults,
    )
    .expect("a UDP socket on 127.0.0.1")
}

/// Waits until `server` has executed every datagram sent to it so far:
/// a round trip comes back after them, unless the kernel delivered an
/// earlier loopback datagram from another CPU's queue later, so there
/// is a second one after a moment.
pub fn sync(server: &Running) {
    let mut t = EthTransport::connect(server.addr()).unwrap();
    let mut w = [0u16; 1];
    for _ in 0..2 {
        t.read16(hostmot2::lbp16::space::COMM_CTRL, false, 0, &mut w)
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
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

impl super::Named for EthRig {
    fn host(&self) -> &Host {
        &self.host
    }

    fn prefix(&self) -> &str {
        &self.prefix
    }
}

impl EthRig {
    /// Registers the simulated board `preset` with `config`.
    pub fn new(tag: &str, preset: &str, config: &str) -> EthRig {
        EthRig::with_spec(tag, preset, boards::preset(preset).expect("preset"), config)
    }

    /// Registers the board `preset` running `spec` with `config`.
    pub fn with_spec(
        tag: &str,
        preset: &str,
        spec: hostmot2::image::FirmwareSpec,
        config: &str,
    ) -> EthRig {
        let server = serve_spec(preset, spec, Faults::default());
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

    /// A register of the simulated board, once it has executed every
    /// datagram sent so far.
    pub fn reg(&self, addr: usize) -> u32 {
        self.sync();
        self.server.shared().with(|b| b.model().read32(addr))
    }

    /// Runs `f` on the simulated board's Smart Serial card at `port`, `channel`.
    pub fn remote<R>(
        &self,
        port: usize,
        channel: usize,
        f: impl FnOnce(&mut hostmot2::sim::sserial::SimRemote) -> R,
    ) -> R {
        self.server.shared().with(|b| {
            f(b.model()
                .sserial()
                .remote(port, channel)
                .expect("a card there"))
        })
    }

    /// Waits until the simulator has executed every datagram sent so far
    /// (its socket is one queue: a round trip of a request sent now
    /// comes back after them).
    pub fn sync(&self) {
        sync(&self.server);
    }

    /// The realtime messages said so far.
    pub fn messages(&self) -> Vec<String> {
        let mut v = Vec::new();
        self.log.drain(|_, t| v.push(t.to_string()));
        v
    }
}
