//! mb2hal as `loadusr` runs it, against pymodbus 3.16 (a third-party
//! Modbus server, tests/peer/pymodbus_server.py): over Modbus TCP on
//! 127.0.0.1 and over Modbus RTU on pseudo-terminals. Every transaction
//! code runs both ways: the read pins show the server's values (the
//! values LinuxCNC's own mb2hal showed against the same datastore), the
//! written values reach the server with the function that should carry
//! them and read back through it. A server that is not there yet costs
//! errors, not the component; once it is up the link recovers.
//!
//! pymodbus comes from the workspace's Python environment
//! (target/python-venv, filled by scripts/install-deps); without it the
//! tests that start it are reported as ignored. A bad INI file and a
//! serial device that is not there need no server and always run.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, Instance, PinDir, Value};

const PATIENCE: Duration = Duration::from_secs(30);

fn wait_for(what: &str, mut cond: impl FnMut() -> bool) {
    let end = Instant::now() + PATIENCE;
    while !cond() {
        assert!(Instant::now() < end, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A process killed when the test ends.
struct Proc(Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The pymodbus server and its command channel.
struct Server {
    _proc: Proc,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
    /// For RTU: the pseudo-terminal the client opens.
    pty: Option<String>,
}

impl Server {
    #[cfg(pymodbus_peer)]
    fn start(args: &[&str]) -> Server {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/peer/pymodbus_server.py");
        let mut child = Command::new(env!("PYMODBUS_PYTHON"))
            .arg(script)
            .args(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("python starts");
        let stdin = child.stdin.take().unwrap();
        let stdout = BufReader::new(child.stdout.take().unwrap());
        let mut s = Server {
            _proc: Proc(child),
            stdin,
            stdout,
            pty: None,
        };
        loop {
            let line = s.line();
            if let Some(p) = line.strip_prefix("pty ") {
                s.pty = Some(p.to_string());
            } else if line == "ready" {
                return s;
            } else {
                panic!("pymodbus server said {line:?}");
            }
        }
    }

    #[cfg(not(pymodbus_peer))]
    fn start(_: &[&str]) -> Server {
        unreachable!("the tests that start pymodbus are ignored without it")
    }

    fn line(&mut self) -> String {
        let mut l = String::new();
        self.stdout.read_line(&mut l).unwrap();
        assert!(!l.is_empty(), "the pymodbus server ended");
        l.trim_end().to_string()
    }

    /// What writes with `function` brought to `count` addresses from
    /// `address` (-1: nothing yet).
    fn written(&mut self, function: u8, address: u16, count: u16) -> Vec<i64> {
        writeln!(self.stdin, "{function} {address} {count}").unwrap();
        let l = self.line();
        l.split_whitespace()
            .skip(2)
            .map(|w| w.parse().unwrap())
            .collect()
    }
}

/// A free TCP port on 127.0.0.1 (bound, noted, released).
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// A scratch directory.
struct Dir(PathBuf);

impl Dir {
    fn new(tag: &str) -> Dir {
        let p = std::env::temp_dir().join(format!("mb2hal-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).unwrap();
        Dir(p)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for Dir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Every transaction code: reads of the datastore's known values, and
/// writes to addresses that are read back by the transactions after
/// them. `link` is the first transaction's link keys.
fn every_code(module: &str, link: &str) -> String {
    format!(
        "\
[MB2HAL_INIT]
INIT_DEBUG=1
VERSION=1.1
HAL_MODULE_NAME={module}
SLOWDOWN=0.0
TOTAL_TRANSACTIONS=10

[TRANSACTION_00]
{link}
MB_SLAVE_ID=1
FIRST_ELEMENT=0
NELEMENTS=3
MB_TX_CODE=fnct_03_read_holding_registers
MB_RESPONSE_TIMEOUT_MS=500
MB_BYTE_TIMEOUT_MS=500
HAL_TX_NAME=holding
MAX_UPDATE_RATE=50
DEBUG=1

[TRANSACTION_01]
MB_TX_CODE=fnct_02_read_discrete_inputs
FIRST_ELEMENT=2
PIN_NAMES=a,b
HAL_TX_NAME=inputs

[TRANSACTION_02]
MB_TX_CODE=fnct_06_write_single_register
FIRST_ELEMENT=5
NELEMENTS=1

[TRANSACTION_03]
MB_TX_CODE=fnct_15_write_multiple_coils
FIRST_ELEMENT=0
NELEMENTS=2

[TRANSACTION_04]
MB_TX_CODE=fnct_01_read_coils
FIRST_ELEMENT=0
NELEMENTS=2

[TRANSACTION_05]
MB_TX_CODE=fnct_04_read_input_registers
FIRST_ELEMENT=1
NELEMENTS=2

[TRANSACTION_06]
MB_TX_CODE=fnct_05_write_single_coil
FIRST_ELEMENT=10
PIN_NAMES=lamp

[TRANSACTION_07]
MB_TX_CODE=fnct_16_write_multiple_registers
FIRST_ELEMENT=20
NELEMENTS=3

[TRANSACTION_08]
MB_TX_CODE=fnct_03_read_holding_registers
FIRST_ELEMENT=5
NELEMENTS=1
HAL_TX_NAME=back5

[TRANSACTION_09]
MB_TX_CODE=fnct_03_read_holding_registers
FIRST_ELEMENT=20
NELEMENTS=3
HAL_TX_NAME=back20
"
    )
}

/// The component's pins as LinuxCNC's mb2hal makes them for
/// [`every_code`]: (name, type, direction).
fn expected_pins() -> Vec<(String, &'static str, PinDir)> {
    use PinDir::{In, Out};
    let mut v: Vec<(String, &'static str, PinDir)> = Vec::new();
    let mut add = |name: &str, t: &'static str, d: PinDir| v.push((name.to_string(), t, d));
    for tx in [
        "holding", "inputs", "02", "03", "04", "05", "06", "07", "back5", "back20",
    ] {
        add(&format!("{tx}.num_errors"), "u32", Out);
    }
    for e in ["00", "01", "02"] {
        add(&format!("holding.{e}.float"), "float", Out);
        add(&format!("holding.{e}.int"), "s32", Out);
        add(&format!("07.{e}.float"), "float", In);
        add(&format!("07.{e}.int"), "s32", In);
        add(&format!("back20.{e}.float"), "float", Out);
        add(&format!("back20.{e}.int"), "s32", Out);
    }
    for e in ["a", "b"] {
        add(&format!("inputs.{e}.bit"), "bit", Out);
        add(&format!("inputs.{e}.bit-inv"), "bit", Out);
    }
    for e in ["00", "01"] {
        add(&format!("03.{e}.bit"), "bit", In);
        add(&format!("04.{e}.bit"), "bit", Out);
        add(&format!("04.{e}.bit-inv"), "bit", Out);
        add(&format!("05.{e}.float"), "float", Out);
        add(&format!("05.{e}.int"), "s32", Out);
    }
    add("02.00.float", "float", In);
    add("02.00.int", "s32", In);
    add("06.lamp.bit", "bit", In);
    add("back5.00.float", "float", Out);
    add("back5.00.int", "s32", Out);
    v.sort_by(|a, b| a.0.cmp(&b.0));
    v
}

/// A HAL instance of the test's own, and mb2hal in it.
struct Hal {
    _host: Host,
    inst: Instance,
    module: String,
}

impl Hal {
    fn new(tag: &str, module: &str) -> Hal {
        let host = Host::create(HostConfig::for_tests(tag)).unwrap();
        let inst = host.instance().clone();
        Hal {
            _host: host,
            inst,
            module: module.to_string(),
        }
    }

    /// Starts mb2hal on `ini`, as `loadusr -W` does.
    fn start(&self, ini: &Path) -> Proc {
        self.start_logged(ini, Stdio::inherit())
    }

    /// Starts mb2hal on `ini` with its messages to `stderr`.
    fn start_logged(&self, ini: &Path, stderr: Stdio) -> Proc {
        let child = Command::new(env!("CARGO_BIN_EXE_mb2hal"))
            .arg(format!("config={}", ini.display()))
            .env("HAL_INSTANCE", self.inst.name())
            .env("HAL_NO_REALTIME", "1")
            .stdout(Stdio::null())
            .stderr(stderr)
            .spawn()
            .expect("mb2hal starts");
        let mut p = Proc(child);
        wait_for("mb2hal to be ready", || {
            assert!(
                matches!(p.0.try_wait(), Ok(None)),
                "mb2hal ended before it was ready"
            );
            self.inst
                .component(&self.module)
                .unwrap()
                .is_some_and(|c| c.ready)
        });
        p
    }

    fn pin(&self, name: &str) -> String {
        format!("{}.{name}", self.module)
    }

    fn get(&self, name: &str) -> Value {
        self.inst.pin_value(&self.pin(name)).unwrap()
    }

    fn set(&self, name: &str, v: Value) {
        self.inst.set_pin(&self.pin(name), v).unwrap();
    }

    fn pins(&self) -> Vec<(String, &'static str, PinDir)> {
        let mut v: Vec<_> = self
            .inst
            .pins()
            .unwrap()
            .into_iter()
            .filter(|p| p.owner == self.module)
            .map(|p| {
                let t = match format!("{:?}", p.hal_type).to_lowercase().as_str() {
                    "bit" => "bit",
                    "float" => "float",
                    "s32" => "s32",
                    "u32" => "u32",
                    other => panic!("pin type {other}"),
                };
                (p.name[self.module.len() + 1..].to_string(), t, p.dir)
            })
            .collect();
        v.sort_by(|a, b| a.0.cmp(&b.0));
        v
    }
}

/// SIGTERM, as `unloadusr` sends it; the exit status.
fn terminate(p: &mut Proc) -> i32 {
    let pid = nix::unistd::Pid::from_raw(p.0.id() as i32);
    nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGTERM).unwrap();
    let end = Instant::now() + PATIENCE;
    loop {
        if let Ok(Some(st)) = p.0.try_wait() {
            return st.code().unwrap_or(-1);
        }
        assert!(Instant::now() < end, "mb2hal did not exit on SIGTERM");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The whole exchange on a running server: pins, reads, writes both
/// ways, errors, and a clean stop.
fn exercise(hal: &Hal, server: &mut Server, mut proc: Proc) {
    assert_eq!(hal.pins(), expected_pins());
    let int = |n: &str| match hal.get(n) {
        Value::S32(v) => v,
        other => panic!("{n} is {other:?}"),
    };
    let float = |n: &str| match hal.get(n) {
        Value::Float(v) => v,
        other => panic!("{n} is {other:?}"),
    };
    let bit = |n: &str| match hal.get(n) {
        Value::Bit(v) => v,
        other => panic!("{n} is {other:?}"),
    };
    // Reads: LinuxCNC's mb2hal showed these against the same datastore.
    wait_for("the holding registers", || int("holding.02.int") == 102);
    assert_eq!((int("holding.00.int"), int("holding.01.int")), (100, 101));
    assert_eq!(float("holding.01.float"), 101.0);
    wait_for("the input registers", || int("05.01.int") == 202);
    assert_eq!((float("05.00.float"), int("05.00.int")), (201.0, 201));
    wait_for("the discrete inputs", || {
        bit("inputs.a.bit") && bit("inputs.b.bit")
    });
    assert!(!bit("inputs.a.bit-inv") && !bit("inputs.b.bit-inv"));
    // fnct_15 writes coils 0 and 1 (false, false) before fnct_01 reads
    // them, so the read shows what was written.
    wait_for("coils 0 and 1 read back", || {
        !bit("04.00.bit") && !bit("04.01.bit") && bit("04.00.bit-inv")
    });
    // Writes, and the same values read back through the server.
    hal.set("02.00.float", Value::Float(1234.7));
    hal.set("02.00.int", Value::S32(10));
    hal.set("03.00.bit", Value::Bit(true));
    hal.set("06.lamp.bit", Value::Bit(true));
    hal.set("07.00.int", Value::S32(7));
    hal.set("07.01.float", Value::Float(70_000.0));
    hal.set("07.02.float", Value::Float(-5.0));
    hal.set("07.02.int", Value::S32(3));
    wait_for("register 5 written and read back", || {
        int("back5.00.int") == 1244
    });
    wait_for("registers 20..22 written and read back", || {
        (
            int("back20.00.int"),
            int("back20.01.int"),
            int("back20.02.int"),
        ) == (7, 65535, 0)
    });
    wait_for("coil 0 read back", || {
        bit("04.00.bit") && !bit("04.00.bit-inv")
    });
    assert!(!bit("04.01.bit"));
    wait_for("each write with its own function", || {
        server.written(6, 5, 1) == [1244]
            && server.written(15, 0, 2) == [1, 0]
            && server.written(5, 10, 1) == [1]
            && server.written(16, 20, 3) == [7, 65535, 0]
    });
    for tx in [
        "holding", "inputs", "02", "03", "04", "05", "06", "07", "back5", "back20",
    ] {
        assert_eq!(hal.get(&format!("{tx}.num_errors")), Value::U32(0), "{tx}");
    }
    assert_eq!(terminate(&mut proc), 0);
    assert!(hal.inst.component(&hal.module).unwrap().is_none());
}

#[test]
#[cfg_attr(
    not(pymodbus_peer),
    ignore = "needs pymodbus and pyserial in target/python-venv (scripts/install-deps)"
)]
fn every_transaction_code_over_tcp() {
    let port = free_port();
    let mut server = Server::start(&["tcp", &port.to_string()]);
    let dir = Dir::new("tcp");
    let ini = dir.write(
        "mb.ini",
        &every_code(
            "mbtcp",
            &format!("LINK_TYPE=tcp\nTCP_IP=127.0.0.1\nTCP_PORT={port}"),
        ),
    );
    let hal = Hal::new("mb2hal-tcp", "mbtcp");
    let proc = hal.start(&ini);
    exercise(&hal, &mut server, proc);
}

#[test]
#[cfg_attr(
    not(pymodbus_peer),
    ignore = "needs pymodbus and pyserial in target/python-venv (scripts/install-deps)"
)]
fn every_transaction_code_over_rtu_on_a_pty() {
    let mut server = Server::start(&["rtu", "115200"]);
    let pty = server.pty.clone().unwrap();
    let dir = Dir::new("rtu");
    let ini = dir.write(
        "mb.ini",
        &every_code(
            "mbrtu",
            &format!(
                "LINK_TYPE=serial\nSERIAL_PORT={pty}\nSERIAL_BAUD=115200\nSERIAL_BITS=8\nSERIAL_PARITY=none\nSERIAL_STOP=1\nSERIAL_DELAY_MS=0"
            ),
        ),
    );
    let hal = Hal::new("mb2hal-rtu", "mbrtu");
    let proc = hal.start(&ini);
    exercise(&hal, &mut server, proc);
}

#[test]
#[cfg_attr(
    not(pymodbus_peer),
    ignore = "needs pymodbus and pyserial in target/python-venv (scripts/install-deps)"
)]
fn a_late_server_and_a_refused_read_cost_errors_not_the_component() {
    let port = free_port();
    let dir = Dir::new("late");
    let ini = dir.write(
        "mb.ini",
        &format!(
            "[MB2HAL_INIT]\nTOTAL_TRANSACTIONS=2\nHAL_MODULE_NAME=mblate\nINIT_DEBUG=2\n\
             [TRANSACTION_00]\nLINK_TYPE=tcp\nTCP_IP=127.0.0.1\nTCP_PORT={port}\n\
             MB_SLAVE_ID=1\nFIRST_ELEMENT=0\nNELEMENTS=2\n\
             MB_TX_CODE=fnct_04_read_input_registers\n\
             [TRANSACTION_01]\nFIRST_ELEMENT=1000\nNELEMENTS=1\n\
             MB_TX_CODE=fnct_03_read_holding_registers\nMAX_UPDATE_RATE=20\n"
        ),
    );
    let hal = Hal::new("mb2hal-late", "mblate");
    let log = dir.0.join("stderr.txt");
    let mut proc = hal.start_logged(&ini, std::fs::File::create(&log).unwrap().into());
    let errors = || match hal.get("00.num_errors") {
        Value::U32(v) => v,
        other => panic!("{other:?}"),
    };
    wait_for("connection failures to count", || errors() >= 2);
    // The link's other transaction could not run either: it counts too.
    assert!(
        matches!(hal.get("01.num_errors"), Value::U32(n) if n >= 1),
        "{:?}",
        hal.get("01.num_errors")
    );
    // Backed off, not busy: a few attempts a second at most.
    let before = errors();
    std::thread::sleep(Duration::from_millis(500));
    assert!(errors() - before <= 3, "{before} -> {}", errors());
    let _server = Server::start(&["tcp", &port.to_string()]);
    wait_for("the link to recover", || {
        errors() == 0 && hal.get("00.01.int") == Value::S32(201)
    });
    // A register the server does not have: refused with an exception,
    // counted, while the other transaction on the link goes on working.
    let refused = || match hal.get("01.num_errors") {
        Value::U32(v) => v,
        other => panic!("{other:?}"),
    };
    let now = refused();
    wait_for("the refusals to count", || refused() >= now + 3);
    assert_eq!(errors(), 0);
    assert_eq!(hal.get("01.00.int"), Value::S32(0));
    assert_eq!(terminate(&mut proc), 0);
    // Each failure is said once, with the section, the code, the link
    // and the reason; so is the recovery.
    let said = std::fs::read_to_string(&log).unwrap();
    let refused = format!(
        "mb2hal: [TRANSACTION_00] fnct_04_read_input_registers (00) on tcp 127.0.0.1:{port}: \
         cannot connect to Modbus TCP server 127.0.0.1:{port}: "
    );
    assert_eq!(said.matches(&refused).count(), 1, "{said}");
    assert_eq!(
        said.matches("mb2hal: [TRANSACTION_00] works again").count(),
        1,
        "{said}"
    );
    let exception = format!(
        "mb2hal: [TRANSACTION_01] fnct_03_read_holding_registers (01) on tcp 127.0.0.1:{port}: \
         slave 1: function 0x03 refused: illegal data address (exception 0x02)\n"
    );
    assert_eq!(said.matches(&exception).count(), 1, "{said}");
    // INIT_DEBUG=2 shows each transaction as read, inherited keys too.
    let settings = format!(
        "mb2hal: [TRANSACTION_01] fnct_03_read_holding_registers on tcp 127.0.0.1:{port}, \
         slave 1, from 1000 x1 (00), timeouts 500 ms / 500 ms, rate 20 Hz, debug 1, \
         pins mblate.01.*\n"
    );
    assert!(said.contains(&settings), "{said}");
}

#[test]
fn a_bad_file_is_refused_before_the_component_exists() {
    let dir = Dir::new("bad");
    let ini = dir.write(
        "bad.ini",
        "[MB2HAL_INIT]\nTOTAL_TRANSACTIONS=1\n[TRANSACTION_00]\nLINK_TYPE=tcp\n\
         TCP_IP=127.0.0.1\nFIRST_ELEMENT=0\nNELEMENTS=1\nMB_TX_CODE=fnct_99\n",
    );
    let hal = Hal::new("mb2hal-bad", "mb2hal");
    let out = Command::new(env!("CARGO_BIN_EXE_mb2hal"))
        .arg(format!("config={}", ini.display()))
        .env("HAL_INSTANCE", hal.inst.name())
        .env("HAL_NO_REALTIME", "1")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(&format!(
            "{}:8: [TRANSACTION_00] MB_TX_CODE = fnct_99: not a transaction code",
            ini.display()
        )),
        "{err}"
    );
    assert!(hal.inst.component("mb2hal").unwrap().is_none());
    let out = Command::new(env!("CARGO_BIN_EXE_mb2hal"))
        .arg("config=/nonexistent/mb.ini")
        .env("HAL_INSTANCE", hal.inst.name())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent/mb.ini"));
}

#[test]
fn a_serial_device_that_is_not_there_costs_errors_not_the_component() {
    let dir = Dir::new("nodev");
    let ini = dir.write(
        "mb.ini",
        "[MB2HAL_INIT]\nTOTAL_TRANSACTIONS=1\nHAL_MODULE_NAME=mbnodev\n\
         [TRANSACTION_00]\nLINK_TYPE=serial\nSERIAL_PORT=/nonexistent/ttyUSB9\n\
         SERIAL_BAUD=19200\nSERIAL_PARITY=even\nMB_SLAVE_ID=1\nFIRST_ELEMENT=0\n\
         NELEMENTS=1\nMB_TX_CODE=fnct_05_write_single_coil\n",
    );
    let hal = Hal::new("mb2hal-nodev", "mbnodev");
    let log = dir.0.join("stderr.txt");
    let mut proc = hal.start_logged(&ini, std::fs::File::create(&log).unwrap().into());
    wait_for(
        "open failures to count",
        || matches!(hal.get("00.num_errors"), Value::U32(n) if n >= 2),
    );
    assert_eq!(terminate(&mut proc), 0);
    let said = std::fs::read_to_string(&log).unwrap();
    let want = "mb2hal: [TRANSACTION_00] fnct_05_write_single_coil (00) on serial \
                /nonexistent/ttyUSB9 19200 baud 8E1: cannot open serial device \
                /nonexistent/ttyUSB9: no such device";
    assert_eq!(said.matches(want).count(), 1, "{said}");
}
