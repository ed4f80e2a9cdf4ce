//! PktUART and hm2_modbus on the simulated board: the PktUART's registers
//! (frames out, frames in with their count words, clear, BadPop), the
//! mbccb parser against files in LinuxCNC's layout, and the Modbus engine
//! running commands against the simulator's in-process Modbus slave,
//! through timeouts, disabling, reset and suspend.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::Arc;

use hostmot2::image::{FirmwareSpec, ModuleSpec};
use hostmot2::md;
use hostmot2::modbus::encode::encode;
use hostmot2::modbus::engine::{Engine, MAX_ERRORS};
use hostmot2::modbus::frame::errno;
use hostmot2::modbus::line::Versions;
use hostmot2::modbus::mbccb::{
    self, flags, format, Command, HalType, Init, Mbccb, ModbusType, PinSpec,
};
use hostmot2::modbus::values::Value;
use hostmot2::pktuart::link::BURST_READS;
use hostmot2::pktuart::{LineConfig, PktUartFirmware, PktUartLink, PktUartPort};
use hostmot2::regs::{gtag, pktuart as r};
use hostmot2::sim::modbus_slave::ModbusSlave;
use hostmot2::sim::{self, Bench, SimHm2, SimTransport};
use hostmot2::transport::Transport;
use hostmot2::{Hm2Error, MbccbProblem};

const PERIOD: i64 = 1_000_000;

/// The simulated 7i96s without its own PktUART: each test gives it the
/// PktUARTs it needs.
fn without_pktuart() -> FirmwareSpec {
    let mut s = sim::boards::preset("7i96s").unwrap();
    s.modules
        .retain(|m| m.gtag != gtag::PKTUART_TX && m.gtag != gtag::PKTUART_RX);
    s
}

fn spec(version: u8) -> FirmwareSpec {
    let mut s = without_pktuart();
    s.modules
        .push(ModuleSpec::standard(gtag::PKTUART_TX, version, 2));
    s.modules
        .push(ModuleSpec::standard(gtag::PKTUART_RX, version, 2));
    s
}

struct Rig {
    sim: Arc<SimHm2>,
    t: SimTransport,
    port: PktUartPort,
}

fn rig(version: u8) -> Rig {
    let s = spec(version);
    let idrom = s.idrom();
    let (sim, mut t) = sim::board(s, Box::new(Bench::default()));
    let mds = md::read_all(&mut t, &idrom).unwrap();
    let fw = PktUartFirmware::discover(&mds, "hm2_7i96s.0").unwrap();
    assert_eq!(fw.instances.len(), 2);
    let inst = fw.by_name("hm2_7i96s.0.pktuart.0").unwrap().clone();
    Rig {
        sim,
        t,
        port: PktUartPort::new(inst),
    }
}

fn line(baud: u32) -> LineConfig {
    LineConfig {
        baud,
        parity: 2,
        stop_bits2: false,
        if_delay: 40,
        drive_delay: 1,
        rx_enable: true,
        rx_mask: true,
    }
}

#[test]
fn pktuart_is_found_in_the_descriptors() {
    let r = rig(3);
    let i = r.port.instance();
    assert_eq!(i.tx, [0x6000, 0x6100, 0x6200, 0x6300]);
    assert_eq!(i.rx, [0x6400, 0x6500, 0x6600, 0x6700]);
    assert_eq!(i.version_word(), 0x33);
    // One half alone is refused.
    let mut s = without_pktuart();
    s.modules.push(ModuleSpec::standard(gtag::PKTUART_TX, 3, 1));
    let idrom = s.idrom();
    let (_sim, mut t) = sim::board(s, Box::new(Bench::default()));
    let mds = md::read_all(&mut t, &idrom).unwrap();
    let e = PktUartFirmware::discover(&mds, "x").unwrap_err();
    assert!(matches!(e, Hm2Error::PktUartHalves { tx: 1, rx: 0 }), "{e}");
    // Version 1 is refused.
    let s = spec(1);
    let idrom = s.idrom();
    let (_sim, mut t) = sim::board(s, Box::new(Bench::default()));
    let mds = md::read_all(&mut t, &idrom).unwrap();
    assert!(PktUartFirmware::discover(&mds, "x").is_err());
}

#[test]
fn frames_go_out_and_answers_come_in_with_their_count_words() {
    let mut r = rig(3);
    r.port
        .configure(&mut r.t, &line(115_200), &line(115_200), true)
        .unwrap();
    let mut slave = ModbusSlave::new(7, 16);
    slave.holding[2] = 0xBEEF;
    r.sim
        .with(|m| m.pktuart(0).unwrap().attach(Box::new(slave)));
    let mut req = vec![7, 3, 0, 2, 0, 1];
    let crc = hostmot2::modbus::rtu::crc16(&req);
    req.extend_from_slice(&crc.to_le_bytes());
    let mut scratch = [0u32; 64];
    r.port.send(&mut r.t, &req, &mut scratch).unwrap();
    assert_ne!(r.port.tx_status(&mut r.t).unwrap() & r::tx::BUSY, 0);
    // 8 bytes of 11 bits at 115200: 764 us on the wire.
    r.sim.advance(700_000);
    assert_ne!(r.port.tx_status(&mut r.t).unwrap() & r::tx::BUSY, 0);
    r.sim.advance(100_000);
    assert_eq!(r.port.tx_status(&mut r.t).unwrap() & r::tx::BUSY, 0);
    assert_eq!(r::nframes(r.port.rx_status(&mut r.t).unwrap()), 0);
    r.sim.advance(2_000_000);
    let status = r.port.rx_status(&mut r.t).unwrap();
    assert_eq!(r::nframes(status), 1);
    assert_ne!(status & r::rx::HAS_DATA, 0);
    let count = r.port.pop_frame_size(&mut r.t).unwrap();
    assert_eq!(count & r::rcr::NBYTES_MASK, 7);
    assert_eq!(count & r::rcr::ERRORS, 0);
    let mut buf = [0u8; 16];
    assert_eq!(r.port.read_frame(&mut r.t, 7, &mut buf).unwrap(), 7);
    assert_eq!(&buf[..5], &[7, 3, 2, 0xBE, 0xEF]);
    assert!(hostmot2::modbus::rtu::crc_ok(&buf[..7]));
    // The FIFO is empty now: another pop sets BadPop.
    r.port.read_frame(&mut r.t, 4, &mut buf).unwrap();
    assert_ne!(r.port.rx_status(&mut r.t).unwrap() & r::rx::BAD_POP, 0);
    // Clear resets it.
    r.port.clear(&mut r.t).unwrap();
    assert_eq!(r.port.rx_status(&mut r.t).unwrap() & r::rx::BAD_POP, 0);
    let sent = r.sim.with(|m| m.pktuart(0).unwrap().sent.clone());
    assert_eq!(sent, vec![req]);
}

#[test]
fn a_disabled_receiver_takes_nothing_and_a_cleared_transmitter_sends_nothing() {
    let mut r = rig(3);
    let mut rx = line(19200);
    rx.rx_enable = false;
    r.port.configure(&mut r.t, &rx, &line(19200), true).unwrap();
    r.sim.with(|m| {
        m.pktuart(0)
            .unwrap()
            .attach(Box::new(ModbusSlave::new(1, 4)))
    });
    let mut req = vec![1, 1, 0, 0, 0, 2];
    let crc = hostmot2::modbus::rtu::crc16(&req);
    req.extend_from_slice(&crc.to_le_bytes());
    let mut scratch = [0u32; 64];
    r.port.send(&mut r.t, &req, &mut scratch).unwrap();
    r.sim.advance(50_000_000);
    assert_eq!(r::nframes(r.port.rx_status(&mut r.t).unwrap()), 0);
    r.port.send(&mut r.t, &req, &mut scratch).unwrap();
    r.port.clear(&mut r.t).unwrap();
    r.sim.advance(50_000_000);
    assert_eq!(r.sim.with(|m| m.pktuart(0).unwrap().sent.len()), 1);
}

fn pin(name: &str, htype: HalType, mtype: u8, fl: u8, regofs: u8) -> PinSpec {
    PinSpec {
        name: name.into(),
        htype,
        mtype: ModbusType(mtype),
        flags: fl,
        regofs,
    }
}

fn cmd(mbid: u8, func: u8, addr: u16, regcnt: u16, pins: Vec<PinSpec>) -> Command {
    Command {
        mbid,
        func,
        flags: 0,
        addr,
        regcnt,
        interval_us: 0,
        timeout_us: 50_000,
        pins,
    }
}

/// A file: read 4 coils, read a float (F_ABCD, scaled) and a u16, write
/// two registers (s32 clamped, u32), write a coil.
fn sample_file() -> Mbccb {
    let bit = |n: &str| pin(n, HalType::Bit, 0, 0, 0);
    Mbccb {
        baudrate: 38_400,
        format: format::PARITY_EN,
        txdelay: 0,
        rxdelay: 0,
        drvdelay: 0,
        icdelay: 0,
        inits: vec![
            Init::Packet {
                mbid: 5,
                func: 6,
                flags: 0,
                timeout_us: 50_000,
                pdu: vec![5, 6, 0, 9, 0x12, 0x34],
            },
            Init::Delay { us: 3_000 },
        ],
        commands: vec![
            cmd(
                5,
                1,
                0,
                0,
                vec![
                    bit("relay.state-00"),
                    bit("relay.state-01"),
                    bit("relay.state-02"),
                    bit("relay.state-03"),
                ],
            ),
            cmd(
                5,
                3,
                4,
                3,
                vec![
                    pin("vfd.freq", HalType::Float, 0x22, 3, 0),
                    pin("vfd.status", HalType::U32, 0x00, 2, 2),
                ],
            ),
            cmd(
                5,
                16,
                10,
                3,
                vec![
                    pin("vfd.cmd", HalType::S32, 0x10, 2, 0),
                    pin("vfd.speed", HalType::U32, 0x02, 2, 1),
                ],
            ),
            cmd(5, 5, 8, 0, vec![bit("relay.out")]),
        ],
        warnings: Vec::new(),
    }
}

fn slave() -> ModbusSlave {
    let mut s = ModbusSlave::new(5, 32);
    s.coils[1] = true;
    s.coils[3] = true;
    let f = 12.5f32.to_bits();
    s.holding[4] = (f >> 16) as u16;
    s.holding[5] = f as u16;
    s.holding[6] = 0x8001;
    s
}

/// The engine on a PktUART link whose bursts the test carries as a
/// board's `read` and `write` would.
struct Bus {
    rig: Rig,
    engine: Engine,
    link: PktUartLink,
}

impl Bus {
    fn new(file: Mbccb) -> Bus {
        let mut rig = rig(3);
        let bytes = encode(&file);
        let parsed = mbccb::parse(&bytes).unwrap();
        assert_eq!(parsed, file);
        let engine = Engine::new(parsed, Versions { rx: 3, tx: 3 });
        let (rx, tx) = engine.configs();
        rig.port.configure(&mut rig.t, &rx, &tx, true).unwrap();
        rig.sim
            .with(|m| m.pktuart(0).unwrap().attach(Box::new(slave())));
        rig.t.reserve(BURST_READS, BURST_READS, 0, 0);
        let link = PktUartLink::new(rig.port.instance().clone());
        Bus { rig, engine, link }
    }

    /// One period: the read burst, the engine, the write burst.
    fn cycle(&mut self) {
        let e = &mut self.engine;
        self.link
            .run_period(&mut self.rig.t, |l| e.process(l, PERIOD))
            .unwrap();
        self.rig.sim.advance(PERIOD as u64);
    }

    fn run(&mut self, n: usize) {
        for _ in 0..n {
            self.cycle();
        }
    }

    fn slave<R>(&self, f: impl FnOnce(&mut ModbusSlave) -> R) -> R {
        self.rig
            .sim
            .with(|m| f(m.pktuart(0).unwrap().peer::<ModbusSlave>().unwrap()))
    }

    fn value(&self, name: &str) -> Value {
        self.engine
            .pins
            .iter()
            .find(|p| p.spec.name == name)
            .unwrap()
            .value
    }

    fn set(&mut self, name: &str, v: Value) {
        self.engine
            .pins
            .iter_mut()
            .find(|p| p.spec.name == name)
            .unwrap()
            .value = v;
    }
}

#[test]
fn the_engine_runs_inits_then_reads_and_writes_through_the_slave() {
    let mut b = Bus::new(sample_file());
    assert_eq!(b.engine.line.parity, 2);
    // 38400 baud: 1750 us -> 68 bit times, rx one less, tx one more.
    assert_eq!((b.engine.line.rxdelay, b.engine.line.txdelay), (67, 69));
    b.run(60);
    assert!(b.engine.inits_done());
    assert_eq!(b.slave(|s| s.holding[9]), 0x1234, "init packet written");
    assert_eq!(b.value("relay.state-01"), Value::Bit(true));
    assert_eq!(b.value("relay.state-02"), Value::Bit(false));
    assert_eq!(b.value("relay.state-03"), Value::Bit(true));
    assert_eq!(b.value("vfd.freq"), Value::Float(12.5));
    assert_eq!(b.value("vfd.status"), Value::U32(0x8001));
    let freq = b
        .engine
        .pins
        .iter()
        .find(|p| p.spec.name == "vfd.freq")
        .unwrap();
    assert_eq!(freq.scaled, Some(12.5));
    assert!(!b.engine.global.fault);
    // Writes go out when pins change, clamped to their type.
    b.set("vfd.cmd", Value::S32(-70_000));
    b.set("vfd.speed", Value::U32(0x0001_0002));
    b.set("relay.out", Value::Bit(true));
    b.run(60);
    assert_eq!(b.slave(|s| s.holding[10]), 0x8000, "s16 clamped");
    assert_eq!(b.slave(|s| (s.holding[11], s.holding[12])), (1, 2));
    assert!(b.slave(|s| s.coils[8]));
    // Unchanged writes are not repeated; reads are.
    let writes = |s: &ModbusSlave| s.requests.iter().filter(|r| r[1] == 16).count();
    let before = b.slave(|s| writes(s));
    b.run(60);
    assert_eq!(b.slave(|s| writes(s)), before);
    b.slave(|s| s.holding[6] = 7);
    b.run(60);
    assert_eq!(b.value("vfd.status"), Value::U32(7));
    // Scaling: scaled = (value - offset) * scale.
    let i = b
        .engine
        .pins
        .iter()
        .position(|p| p.spec.name == "vfd.freq")
        .unwrap();
    b.engine.pins[i].offset = Some(Value::Float(2.5));
    b.engine.pins[i].scale = Some(2.0);
    b.run(60);
    assert_eq!(b.engine.pins[i].scaled, Some(20.0));
}

#[test]
fn lost_communication_faults_disables_after_five_and_reset_brings_it_back() {
    let mut b = Bus::new(sample_file());
    b.run(60);
    assert!(!b.engine.global.fault);
    b.slave(|s| s.silent = true);
    b.run(1500);
    assert!(b.engine.global.fault);
    assert_eq!(b.engine.global.last_error_code, errno::ETIMEDOUT);
    for c in [0, 1] {
        let p = b.engine.commands[c];
        assert!(p.disabled, "command {c} disabled");
        assert_eq!(p.errors, MAX_ERRORS);
        assert_eq!(p.error_code, errno::ETIMEDOUT);
    }
    // Read pins keep their last good value.
    assert_eq!(b.value("vfd.freq"), Value::Float(12.5));
    b.slave(|s| s.silent = false);
    b.slave(|s| s.holding[6] = 99);
    b.engine.global.reset = true;
    b.run(100);
    b.engine.global.reset = false;
    assert!(!b.engine.global.fault);
    assert!(!b.engine.commands[1].disabled);
    assert_eq!(b.engine.commands[1].errors, 0);
    assert_eq!(b.value("vfd.status"), Value::U32(99));
}

#[test]
fn bad_replies_count_as_errors_with_their_codes() {
    let mut b = Bus::new(sample_file());
    b.run(60);
    b.slave(|s| s.bad_crc = true);
    b.run(30);
    assert_eq!(b.engine.commands[0].error_code, errno::EBADE);
    assert!(b.engine.commands[0].errors > 0);
    b.slave(|s| s.bad_crc = false);
    b.run(60);
    assert_eq!(b.engine.commands[0].errors, 0);
    // An address past the slave's table: exception reply.
    let mut f = sample_file();
    f.commands[1].addr = 30;
    let mut b = Bus::new(f);
    b.run(60);
    assert_eq!(b.engine.commands[1].error_code, errno::EBADMSG);
}

#[test]
fn suspend_holds_everything_and_writeflush_sends_only_changes() {
    let mut f = sample_file();
    f.format |= format::SUSPEND;
    for c in &mut f.commands {
        c.flags |= flags::WFLUSH;
    }
    let mut b = Bus::new(f);
    assert!(b.engine.global.suspend);
    b.set("vfd.cmd", Value::S32(5));
    b.run(50);
    assert_eq!(b.slave(|s| s.requests.len()), 0, "nothing while suspended");
    b.engine.global.suspend = false;
    b.run(60);
    assert!(
        b.slave(|s| s.requests.iter().any(|r| r[1] == 6)),
        "inits after suspend"
    );
    assert!(
        !b.slave(|s| s.requests.iter().any(|r| r[1] == 16)),
        "flushed writes wait for a change"
    );
    b.set("vfd.cmd", Value::S32(6));
    b.run(30);
    assert_eq!(b.slave(|s| s.holding[10]), 6);
    // The disable pin stops a command with EAGAIN.
    b.engine.commands[0].disable = true;
    b.run(30);
    assert!(b.engine.commands[0].disabled);
    assert_eq!(b.engine.commands[0].error_code, errno::EAGAIN);
}

#[test]
fn mbccb_refusals_name_the_offset_and_field() {
    let good = encode(&sample_file());
    assert!(mbccb::parse(&good).is_ok());
    let check = |bytes: &[u8], offset: usize, text: &str| {
        let e = mbccb::parse(bytes).unwrap_err();
        match &e {
            Hm2Error::Mbccb { offset: o, .. } => assert_eq!(*o, offset, "{e}"),
            _ => panic!("{e}"),
        }
        assert!(e.to_string().contains(text), "{e}");
    };
    let mut b = good.clone();
    b[0] = b'X';
    check(&b, 0, "signature");
    check(&good[..40], 40, "ends after 40 bytes");
    let mut b = good.clone();
    b[17] = 0xFF; // rxdelay 0x00FF ok; make it 0x04FF
    b[16] = 0x04;
    check(&b, 16, "rxdelay");
    let mut b = good.clone();
    b.push(0);
    check(&b, good.len(), "expected");
    // The first command's function (after two init records).
    let mut b = good.clone();
    b[64 + 64 + 1] = 7;
    check(&b, 64 + 64 + 1, "command 0 function");
    // A pin name with an upper-case letter.
    let mut b = good.clone();
    let at = b.windows(5).position(|w| w == b"relay").unwrap();
    b[at] = b'R';
    let e = mbccb::parse(&b).unwrap_err();
    assert!(
        matches!(&e, Hm2Error::Mbccb { what: MbccbProblem::PinName { command: 0, pin: 0, .. }, offset } if *offset == at - 1),
        "{e}"
    );
}

mod hal_load {
    use super::*;
    use hal_core::Value as V;
    use hal_core::{Host, HostConfig};
    use hostmot2::hal::{HM2_PCI_MODULE, HOSTMOT2_MODULE};
    use hostmot2::modbus::hal::HM2_MODBUS_MODULE;
    use std::time::{Duration, Instant};

    fn host(tag: &str) -> (Host, Arc<SimHm2>) {
        let h = Host::create(HostConfig::for_tests(tag)).unwrap();
        h.loadrt(&HOSTMOT2_MODULE, &[] as &[&str]).unwrap();
        h.loadrt(&HM2_PCI_MODULE, &["sim=5i25-pktuart"]).unwrap();
        let sim = hal_driver::sim::find::<SimHm2>(h.instance().name(), "hm2_5i25.0").unwrap();
        sim.with(|m| m.pktuart(0).unwrap().attach(Box::new(slave())));
        (h, sim)
    }

    fn file(dir: &tempfile::TempDir, bytes: &[u8]) -> String {
        let p = dir.path().join("test.mbccb");
        std::fs::write(&p, bytes).unwrap();
        p.to_str().unwrap().to_string()
    }

    fn wait(what: &str, mut ok: impl FnMut() -> bool) {
        let end = Instant::now() + Duration::from_secs(20);
        while !ok() {
            assert!(Instant::now() < end, "{what} never happened");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    #[test]
    fn loadrt_hm2_modbus_runs_the_file_in_a_servo_thread() {
        let (h, sim) = host("hm2-modbus-run");
        let dir = tempfile::tempdir().unwrap();
        let path = file(&dir, &encode(&sample_file()));
        h.loadrt(
            &HM2_MODBUS_MODULE,
            &["ports=hm2_5i25.0.pktuart.0", &format!("mbccbs={path}")],
        )
        .unwrap();
        let inst = h.instance();
        assert_eq!(
            inst.param_value("hm2_modbus.0.baudrate").unwrap(),
            V::U32(38_400)
        );
        assert_eq!(inst.param_value("hm2_modbus.0.parity").unwrap(), V::U32(2));
        assert_eq!(
            inst.param_value("hm2_modbus.0.rxdelay").unwrap(),
            V::U32(67)
        );
        for p in [
            "hm2_modbus.0.fault",
            "hm2_modbus.0.fault-command",
            "hm2_modbus.0.last-error-code",
            "hm2_modbus.0.reset",
            "hm2_modbus.0.suspend",
            "hm2_modbus.0.command.03.error-code",
            "hm2_modbus.0.vfd.freq.scaled",
            "hm2_modbus.0.vfd.freq.offset",
            "hm2_modbus.0.relay.state-03",
        ] {
            assert!(inst.pin(p).unwrap().is_some(), "{p}");
        }
        h.create_thread("servo", 1_000_000, true, None).unwrap();
        h.addf("hm2_5i25.0.read", "servo", -1).unwrap();
        h.addf("hm2_modbus.0.process", "servo", -1).unwrap();
        h.addf("hm2_5i25.0.write", "servo", -1).unwrap();
        h.start().unwrap();
        let pin = |n: &str| inst.pin_value(&format!("hm2_modbus.0.{n}")).unwrap();
        wait("the float read", || pin("vfd.freq") == V::Float(12.5));
        assert_eq!(pin("relay.state-01"), V::Bit(true));
        assert_eq!(pin("vfd.status"), V::U32(0x8001));
        inst.set_pin("hm2_modbus.0.vfd.cmd", V::S32(1234)).unwrap();
        let held = |i: usize| {
            sim.with(|m| m.pktuart(0).unwrap().peer::<ModbusSlave>().unwrap().holding[i])
        };
        wait("the register write", || held(10) == 1234);
        sim.with(|m| m.pktuart(0).unwrap().peer::<ModbusSlave>().unwrap().silent = true);
        wait("the fault", || pin("fault") == V::Bit(true));
        wait("the disabling", || {
            pin("command.00.disabled") == V::Bit(true)
        });
        assert_eq!(pin("last-error-code"), V::U32(errno::ETIMEDOUT));
        h.stop();
    }

    #[test]
    fn loadrt_hm2_modbus_refuses_what_it_cannot_run() {
        let (h, _sim) = host("hm2-modbus-refuse");
        let dir = tempfile::tempdir().unwrap();
        let good = file(&dir, &encode(&sample_file()));
        let err = |args: &[&str]| h.loadrt(&HM2_MODBUS_MODULE, args).unwrap_err().to_string();
        assert!(err(&[]).contains("at least one valid pktuart port"));
        assert!(err(&["ports=hm2_5i25.0.pktuart.0"]).contains("missing mbccb file"));
        let e = err(&["ports=hm2_5i25.0.pktuart.7", &format!("mbccbs={good}")]);
        assert!(e.contains("'hm2_5i25.0.pktuart.7' does not exist"), "{e}");
        let bad = dir.path().join("bad.mbccb");
        std::fs::write(
            &bad,
            b"MesaMB02 and then some more bytes to pass the size check ........",
        )
        .unwrap();
        let e = err(&[
            "ports=hm2_5i25.0.pktuart.0",
            &format!("mbccbs={}", bad.display()),
        ]);
        assert!(
            e.contains("byte offset 0") && e.contains("signature"),
            "{e}"
        );
        let e = err(&["ports=hm2_5i25.0.pktuart.0", "mbccbs=/nonexistent/x.mbccb"]);
        assert!(e.contains("cannot read mbccb file"), "{e}");
        // Nothing stayed loaded.
        assert!(h.instance().pin("hm2_modbus.0.fault").unwrap().is_none());
    }
}

/// The sample command file kept in the tree (hm2_modbus's man page loads
/// it) is the fuzz target's seed; `HAL_UPDATE_MAN=1` rewrites it.
#[test]
fn the_sample_mbccb_in_the_tree_is_current() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/sample.mbccb");
    let want = hostmot2::fuzzing::seed_mbccbs().remove(0);
    if std::env::var_os("HAL_UPDATE_MAN").is_some() {
        std::fs::write(&path, &want).unwrap();
    }
    assert_eq!(
        std::fs::read(&path).unwrap(),
        want,
        "run with HAL_UPDATE_MAN=1"
    );
    assert!(mbccb::parse(&want).is_ok());
}

/// `config="num_pktuarts=N"` limits the PktUARTs as LinuxCNC does: the
/// first N, and more than the firmware has refuses the board.
#[test]
fn num_pktuarts_takes_the_first_n() {
    use hal_core::{Host, HostConfig};
    use hostmot2::hal::{HM2_PCI_MODULE, HOSTMOT2_MODULE};
    use hostmot2::modbus::hal::HM2_MODBUS_MODULE;
    let h = Host::create(HostConfig::for_tests("hm2-modbus-num")).unwrap();
    h.loadrt(&HOSTMOT2_MODULE, &[] as &[&str]).unwrap();
    let e = h
        .loadrt(
            &HM2_PCI_MODULE,
            &["sim=5i25-pktuart", "config=num_pktuarts=3"],
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("num_pktuarts=3, but only 2"), "{e}");
    h.loadrt(
        &HM2_PCI_MODULE,
        &["sim=5i25-pktuart", "config=num_pktuarts=1"],
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("f.mbccb");
    std::fs::write(&path, encode(&sample_file())).unwrap();
    let files = format!("mbccbs={}", path.display());
    let e = h
        .loadrt(&HM2_MODBUS_MODULE, &["ports=hm2_5i25.0.pktuart.1", &files])
        .unwrap_err()
        .to_string();
    assert!(e.contains("does not exist"), "{e}");
    h.loadrt(&HM2_MODBUS_MODULE, &["ports=hm2_5i25.0.pktuart.0", &files])
        .unwrap();
}

/// Broadcasts expect no answer, `timesout` commands may go unanswered
/// without an error, and an `interval="once"` command runs once.
#[test]
fn broadcast_timesout_and_once_behave_as_documented() {
    let mut f = sample_file();
    f.inits.clear();
    let mut bc = cmd(0, 16, 20, 1, vec![pin("all.v", HalType::U32, 0x00, 0, 0)]);
    bc.flags = 0;
    let mut quiet = cmd(9, 3, 0, 1, vec![pin("ghost.v", HalType::U32, 0x00, 0, 0)]);
    quiet.flags = flags::TIMESOUT;
    let mut once = cmd(5, 4, 0, 1, vec![pin("vfd.once", HalType::U32, 0x00, 0, 0)]);
    once.interval_us = u32::MAX;
    f.commands = vec![bc, quiet, once];
    let mut b = Bus::new(f);
    b.set("all.v", Value::U32(77));
    b.run(300);
    assert_eq!(b.slave(|s| s.holding[20]), 77, "broadcast write taken");
    assert!(!b.engine.global.fault, "{:?}", b.engine.global);
    assert_eq!(b.engine.commands[0].errors, 0);
    assert_eq!(b.engine.commands[1].errors, 0, "timesout: no error");
    let reads4 = b.slave(|s| s.requests.iter().filter(|r| r[1] == 4).count());
    assert_eq!(reads4, 1, "once means once");
    // Without timesout the silent device counts errors.
    let mut f = sample_file();
    f.inits.clear();
    f.commands = vec![cmd(
        9,
        3,
        0,
        1,
        vec![pin("ghost.v", HalType::U32, 0x00, 0, 0)],
    )];
    let mut b = Bus::new(f);
    b.run(300);
    assert!(b.engine.global.fault);
    assert!(b.engine.commands[0].errors > 0);
}
