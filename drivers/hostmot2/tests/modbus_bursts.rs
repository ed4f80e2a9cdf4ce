//! hm2_modbus makes no immediate register access once loaded: its
//! PktUART's status, frames and writes ride in the board's one read and
//! one write burst per period. A transport wrapper counts the immediate
//! accesses (each a UDP round trip on hm2_eth) and the bursts while full
//! Modbus exchanges (read holding registers, write registers) run
//! against the simulated slave: in a servo thread on the simulated PCI
//! board, and cycle by cycle on a simulated Ethernet board over UDP.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Arc;
use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, MsgLevel, RtLog, Value as V};
use hal_driver::sim::SimBoard;
use hostmot2::board::Board;
use hostmot2::config::Config;
use hostmot2::eth::EthTransport;
use hostmot2::firmware::Debug;
use hostmot2::hal::{publish_board, SharedBoard};
use hostmot2::log::{BoardLog, MessageLog};
use hostmot2::modbus::encode::encode;
use hostmot2::modbus::engine::Engine;
use hostmot2::modbus::hal::HM2_MODBUS_MODULE;
use hostmot2::modbus::line::Versions;
use hostmot2::modbus::values::Value;
use hostmot2::sim::eth_server::Faults;
use hostmot2::sim::modbus_slave::ModbusSlave;
use hostmot2::sim::{boards, Bench, Hm2Model, SimHm2};
use hostmot2::transport::{CallCounts, CountingTransport};
use hostmot2::window::WindowTransport;

const PERIOD: i64 = 1_000_000;

use common::modbus_file::file;

fn slave() -> ModbusSlave {
    let mut s = ModbusSlave::new(7, 16);
    s.holding[2] = 0x1234;
    s.holding[3] = 0xBEEF;
    s
}

fn wait(what: &str, mut ok: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(20);
    while !ok() {
        assert!(Instant::now() < end, "{what} never happened");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// `loadrt hm2_modbus` on a simulated 5i25 with PktUARTs whose transport
/// counts its calls; the board's `read` and `write` exported as hm2_pci
/// exports them.
struct PciRig {
    host: Host,
    sim: Arc<SimHm2>,
    counts: Arc<CallCounts>,
    periods: Arc<AtomicU64>,
    _board: Arc<SharedBoard<hal_core::Ours>>,
    _dir: tempfile::TempDir,
}

impl PciRig {
    fn new(tag: &str) -> PciRig {
        let host = Host::create(HostConfig::for_tests(tag)).unwrap();
        let spec = boards::preset("5i25-pktuart").unwrap();
        let llio = spec.llio(0);
        let prefix = llio.name.clone();
        let sim = Arc::new(SimBoard::new(Hm2Model::with_world(
            spec,
            Box::new(Bench::default()),
        )));
        let t = CountingTransport::new(WindowTransport::new(sim.clone()));
        let counts = t.counts();
        let log = RtLog::new(256);
        log.set_level(MsgLevel::Err);
        let mut b = host.new_rt_component("hm2_pci").unwrap();
        let board = Board::open(
            b.component(),
            llio,
            &Config::default(),
            Debug::default(),
            Box::new(t),
            BoardLog::new(log, &prefix),
            &mut MessageLog::default(),
        )
        .unwrap();
        let board = Arc::new(SharedBoard::new(board, None));
        publish_board(host.instance().name(), &board);
        let periods = Arc::new(AtomicU64::new(0));
        let (bd, s, n) = (board.clone(), sim.clone(), periods.clone());
        b.funct(&format!("{prefix}.read"), true, move |ctx| {
            s.advance(ctx.period() as u64);
            bd.with(|b| b.read());
            n.fetch_add(1, Relaxed);
        })
        .unwrap();
        let bd = board.clone();
        b.funct(&format!("{prefix}.write"), true, move |ctx| {
            bd.with(|b| b.write(ctx.period()));
        })
        .unwrap();
        b.ready().unwrap();
        sim.with(|m| m.pktuart(0).unwrap().attach(Box::new(slave())));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("f.mbccb");
        std::fs::write(&path, encode(&file())).unwrap();
        host.loadrt(
            &HM2_MODBUS_MODULE,
            &[
                "ports=hm2_5i25.0.pktuart.0".to_string(),
                format!("mbccbs={}", path.display()),
            ],
        )
        .unwrap();
        PciRig {
            host,
            sim,
            counts,
            periods,
            _board: board,
            _dir: dir,
        }
    }

    fn pin(&self, name: &str) -> V {
        self.host
            .instance()
            .pin_value(&format!("hm2_modbus.0.{name}"))
            .unwrap()
    }

    fn holding(&self, i: usize) -> u16 {
        self.sim
            .with(|m| m.pktuart(0).unwrap().peer::<ModbusSlave>().unwrap().holding[i])
    }
}

#[test]
fn in_a_servo_thread_hm2_modbus_makes_no_immediate_access() {
    let rig = PciRig::new("hm2-modbus-bursts");
    // Loading set the PktUART up directly: the wrapper sees those.
    let at_load = rig.counts.immediate();
    assert!(at_load > 0, "load-time set-up is counted");
    let h = &rig.host;
    h.create_thread("servo", PERIOD, true, None).unwrap();
    h.addf("hm2_5i25.0.read", "servo", -1).unwrap();
    h.addf("hm2_modbus.0.process", "servo", -1).unwrap();
    h.addf("hm2_5i25.0.write", "servo", -1).unwrap();
    let (reads0, writes0) = (
        rig.counts.read_bursts.load(Relaxed),
        rig.counts.write_bursts.load(Relaxed),
    );
    h.start().unwrap();
    wait("the register read", || rig.pin("in.b") == V::U32(0xBEEF));
    assert_eq!(rig.pin("in.a"), V::U32(0x1234));
    h.instance()
        .set_pin("hm2_modbus.0.out.a", V::U32(0x55AA))
        .unwrap();
    h.instance()
        .set_pin("hm2_modbus.0.out.b", V::U32(77))
        .unwrap();
    wait("the register write", || {
        rig.holding(10) == 0x55AA && rig.holding(11) == 77
    });
    h.stop();
    assert_eq!(rig.pin("fault"), V::Bit(false));
    assert_eq!(
        rig.counts.immediate(),
        at_load,
        "no immediate access while running"
    );
    // One read and one write burst per period, nothing else.
    let periods = rig.periods.load(Relaxed);
    assert!(periods > 0);
    assert_eq!(rig.counts.read_bursts.load(Relaxed) - reads0, periods);
    assert_eq!(rig.counts.write_bursts.load(Relaxed) - writes0, periods);
    // Unloading detaches the PktUART; loading again attaches it anew.
    h.unloadrt("hm2_modbus").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("g.mbccb");
    std::fs::write(&path, encode(&file())).unwrap();
    let files = format!("mbccbs={}", path.display());
    h.loadrt(
        &HM2_MODBUS_MODULE,
        &["ports=hm2_5i25.0.pktuart.0", files.as_str()],
    )
    .unwrap();
}

#[test]
fn one_pktuart_serves_one_hm2_modbus_instance() {
    let rig = PciRig::new("hm2-modbus-bursts-twice");
    rig.host.unloadrt("hm2_modbus").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("f.mbccb");
    std::fs::write(&path, encode(&file())).unwrap();
    let files = format!("mbccbs={},{}", path.display(), path.display());
    // The same port twice in one load: refused, nothing left loaded.
    let e = rig
        .host
        .loadrt(
            &HM2_MODBUS_MODULE,
            &[
                "ports=hm2_5i25.0.pktuart.1,hm2_5i25.0.pktuart.1",
                files.as_str(),
            ],
        )
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("'hm2_5i25.0.pktuart.1' is already in use"),
        "{e}"
    );
    // The refused load let go of the port it had attached.
    let one = format!("mbccbs={}", path.display());
    rig.host
        .loadrt(
            &HM2_MODBUS_MODULE,
            &["ports=hm2_5i25.0.pktuart.1", one.as_str()],
        )
        .unwrap();
}

/// The Ethernet path: a 7I96S (its firmware has a PktUART), served over
/// UDP by the simulator, its transport counted; the engine stepped on
/// its link between the board's `read` and `write`, as the servo thread
/// runs them.
#[test]
fn over_ethernet_each_period_is_one_request_and_one_write_datagram() {
    let spec = boards::preset("7i96s").unwrap();
    let server = common::eth::serve_spec("7i96s", spec, Faults::default());
    server
        .shared()
        .with(|b| b.model().pktuart(0).unwrap().attach(Box::new(slave())));
    let host = Host::create(HostConfig::for_tests("hm2-modbus-bursts-eth")).unwrap();
    let name = boards::eth_name("7i96s").unwrap();
    let llio = hostmot2::eth::boards::lookup(name).unwrap().llio(0);
    let prefix = llio.name.clone();
    let b = host.new_rt_component("hm2_eth").unwrap();
    let mut t = EthTransport::connect(server.addr()).unwrap();
    t.set_name(name);
    t.errors().export(b.component(), &prefix).unwrap();
    let t = CountingTransport::new(t);
    let counts = t.counts();
    let log = RtLog::new(256);
    let mut board = Board::open(
        b.component(),
        llio,
        &Config::default(),
        Debug::default(),
        Box::new(t),
        BoardLog::new(log, &prefix),
        &mut MessageLog::default(),
    )
    .unwrap();
    b.ready().unwrap();
    host.instance()
        .set_param(
            &format!("{prefix}.packet-read-timeout"),
            hal_core::Value::S32(common::eth::TEST_TIMEOUT_NS),
        )
        .unwrap();
    let inst = board.firmware().pktuart.instances[0].clone();
    let id = board.attach_pktuart(&inst).unwrap();
    let mut engine = Engine::new(file(), Versions { rx: 3, tx: 3 });
    // Set-up staged into the first write burst (hm2_modbus does it
    // directly at load).
    let (rx, tx) = engine.configs();
    board
        .pktuart_link(id)
        .unwrap()
        .configure(&rx, &tx, true)
        .unwrap();
    let set = |e: &mut Engine, n: &str, v: u32| {
        e.pins.iter_mut().find(|p| p.spec.name == n).unwrap().value = Value::U32(v);
    };
    set(&mut engine, "out.a", 4321);
    set(&mut engine, "out.b", 8);
    let before = (counts.immediate(), counts.bursts());
    let n = 300;
    for _ in 0..n {
        board.read_request();
        board.read();
        engine.process(board.pktuart_link(id).unwrap(), PERIOD);
        board.write(PERIOD);
    }
    let v = |n: &str| engine.pins.iter().find(|p| p.spec.name == n).unwrap().value;
    assert_eq!(v("in.a"), Value::U32(0x1234));
    assert_eq!(v("in.b"), Value::U32(0xBEEF));
    assert!(!engine.global.fault, "{:?}", engine.commands);
    common::eth::sync(&server);
    let held = server.shared().with(|b| {
        let s = b.model().pktuart(0).unwrap();
        let s = s.peer::<ModbusSlave>().unwrap();
        (s.holding[10], s.holding[11], s.answered)
    });
    assert_eq!((held.0, held.1), (4321, 8));
    assert!(held.2 > 10, "exchanges went on: {}", held.2);
    assert_eq!(counts.immediate(), before.0, "no immediate access");
    assert_eq!(counts.bursts() - before.1, 2 * n, "two datagrams a period");
    assert_eq!(
        host.instance()
            .param_value(&format!("{prefix}.io_error"))
            .unwrap(),
        hal_core::Value::Bit(false)
    );
}
