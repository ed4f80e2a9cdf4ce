//! hm2_modbus against pymodbus 3 (a third-party Modbus RTU server, the
//! script mb2hal's tests use: drivers/serial/tests/peer/pymodbus_server.py)
//! on a pseudo-terminal plugged into a simulated PktUART's line: reads of
//! every kind show the server's datastore, writes reach it.
//!
//! pymodbus comes from the workspace's Python environment
//! (target/python-venv, filled by scripts/install-deps); without it the
//! test is reported as ignored.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

#[cfg(pymodbus_peer)]
mod with_pymodbus {
    use std::io::{BufRead, BufReader, Write};
    use std::path::Path;
    use std::process::{Child, Command as Proc, Stdio};
    use std::time::{Duration, Instant};

    use hostmot2::md;
    use hostmot2::modbus::engine::Engine;
    use hostmot2::modbus::line::Versions;
    use hostmot2::modbus::mbccb::{Command, HalType, Mbccb, ModbusType, PinSpec};
    use hostmot2::modbus::rtu::crc16;
    use hostmot2::modbus::values::Value;
    use hostmot2::pktuart::link::BURST_READS;
    use hostmot2::pktuart::{PktUartFirmware, PktUartLink, PktUartPort};
    use hostmot2::sim::pktuart::{LineSettings, SerialPeer};
    use hostmot2::sim::pty_peer::PtyPeer;
    use hostmot2::sim::{self, Bench};
    use hostmot2::transport::Transport;

    struct Kill(Child);
    impl Drop for Kill {
        fn drop(&mut self) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }

    fn pin(name: &str, htype: HalType, regofs: u8) -> PinSpec {
        PinSpec {
            name: name.into(),
            htype,
            mtype: ModbusType(0),
            flags: 0,
            regofs,
        }
    }

    fn cmd(func: u8, addr: u16, regcnt: u16, pins: Vec<PinSpec>) -> Command {
        Command {
            mbid: 1,
            func,
            flags: 0,
            addr,
            regcnt,
            interval_us: 0,
            timeout_us: 100_000,
            pins,
        }
    }

    #[test]
    fn reads_and_writes_reach_pymodbus() {
        let script =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../serial/tests/peer/pymodbus_server.py");
        let mut child = Proc::new(env!("PYMODBUS_PYTHON"))
            .arg(script)
            .args(["rtu", "19200"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        let mut out = BufReader::new(child.stdout.take().unwrap());
        let _guard = Kill(child);
        let mut line = || {
            let mut l = String::new();
            out.read_line(&mut l).unwrap();
            l.trim().to_string()
        };
        let pty = line().strip_prefix("pty ").unwrap().to_string();
        assert_eq!(line(), "ready");
        let mut peer = PtyPeer::open(Path::new(&pty)).unwrap();
        // Until the server answers a read of holding register 0.
        let mut req = vec![1, 3, 0, 0, 0, 1];
        req.extend_from_slice(&crc16(&req).to_le_bytes());
        let ls = LineSettings {
            baud: 19_200,
            parity: 0,
            stop_bits: 1,
        };
        let end = Instant::now() + Duration::from_secs(20);
        while peer.frame(&req, &ls).is_empty() {
            assert!(Instant::now() < end, "pymodbus never answered");
        }

        let file = Mbccb {
            baudrate: 19_200,
            format: 0,
            txdelay: 0,
            rxdelay: 0,
            drvdelay: 0,
            icdelay: 0,
            inits: Vec::new(),
            commands: vec![
                cmd(
                    3,
                    0,
                    2,
                    vec![pin("hr0", HalType::U32, 0), pin("hr1", HalType::S32, 1)],
                ),
                cmd(4, 3, 1, vec![pin("ir3", HalType::Float, 0)]),
                cmd(
                    1,
                    0,
                    4,
                    (0..4)
                        .map(|i| pin(&format!("co{i}"), HalType::Bit, 0))
                        .collect(),
                ),
                cmd(
                    2,
                    0,
                    4,
                    (0..4)
                        .map(|i| pin(&format!("di{i}"), HalType::Bit, 0))
                        .collect(),
                ),
                cmd(6, 10, 1, vec![pin("w10", HalType::U32, 0)]),
            ],
            warnings: Vec::new(),
        };
        let spec = sim::boards::preset("5i25-pktuart").unwrap();
        let idrom = spec.idrom();
        let (board, mut t) = sim::board(spec, Box::new(Bench::default()));
        let mds = md::read_all(&mut t, &idrom).unwrap();
        let inst = PktUartFirmware::discover(&mds, "hm2_5i25.0")
            .unwrap()
            .instances[0]
            .clone();
        let port = PktUartPort::new(inst.clone());
        let mut e = Engine::new(file, Versions { rx: 3, tx: 3 });
        let (rx, tx) = e.configs();
        port.configure(&mut t, &rx, &tx, true).unwrap();
        board.with(|m| m.pktuart(0).unwrap().attach(Box::new(peer)));
        let w = e.pins.iter().position(|p| p.spec.name == "w10").unwrap();
        e.pins[w].value = Value::U32(4321);
        // The link's traffic as the board's bursts carry it.
        t.reserve(BURST_READS, BURST_READS, 0, 0);
        let mut link = PktUartLink::new(inst);
        for _ in 0..400 {
            link.run_period(&mut t, |l| e.process(l, 1_000_000))
                .unwrap();
            board.advance(1_000_000);
        }
        let v = |n: &str| e.pins.iter().find(|p| p.spec.name == n).unwrap().value;
        assert!(!e.global.fault, "{:?}", e.commands);
        assert_eq!(v("hr0"), Value::U32(100));
        assert_eq!(v("hr1"), Value::S32(101));
        assert_eq!(v("ir3"), Value::Float(203.0));
        let co: Vec<Value> = (0..4).map(|i| v(&format!("co{i}"))).collect();
        assert_eq!(co, [false, true, false, true].map(Value::Bit));
        let di: Vec<Value> = (0..4).map(|i| v(&format!("di{i}"))).collect();
        assert_eq!(di, [true, false, true, true].map(Value::Bit));
        writeln!(stdin, "6 10 1").unwrap();
        assert_eq!(line(), "6 10 4321");
    }
}

#[cfg(not(pymodbus_peer))]
#[test]
#[ignore = "pymodbus is not in the workspace's Python environment (scripts/install-deps)"]
fn reads_and_writes_reach_pymodbus() {}
