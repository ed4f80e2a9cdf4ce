//! The VFD components as `loadusr` runs them: the real programs, in
//! their own processes, attached to a HAL instance, talking to the
//! simulated drive through a real pseudo-terminal (the kernel's tty
//! layer, termios, poll). The drive is unplugged mid-run (the pty pair
//! closes and its by-id style link disappears) and plugged back.
//!
//! This is the crate's real-device test binary: `.ci/run` also runs it
//! inside the VM rig (`../shared/tools/vmrig`), on the rig's kernel.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, Instance, Value};
use hal_serial::line::{LineSettings, Parity};
use hal_serial::sim::{Protocol, PtyVfd, RunCommand, VfdSim};

/// Generous: the VM rig runs under TCG, many times slower than the host.
const PATIENCE: Duration = Duration::from_secs(60);

fn wait_for(what: &str, mut cond: impl FnMut() -> bool) {
    let end = Instant::now() + PATIENCE;
    while !cond() {
        assert!(Instant::now() < end, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// A directory only this user can write, for the device link.
struct PrivateDir(PathBuf);

impl PrivateDir {
    fn new(tag: &str) -> PrivateDir {
        use std::os::unix::fs::DirBuilderExt;
        let p = std::env::temp_dir().join(format!(
            "hal-serial-{tag}-{}-{}",
            std::process::id(),
            Instant::now().elapsed().as_nanos()
        ));
        std::fs::DirBuilder::new().mode(0o700).create(&p).unwrap();
        PrivateDir(p)
    }
}

impl Drop for PrivateDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A component process, killed if the test ends early.
struct Proc(Child);

impl Proc {
    fn start(bin: &str, args: &[&str], instance: &str) -> Proc {
        let child = Command::new(bin)
            .args(args)
            .env("HAL_INSTANCE", instance)
            .env("HAL_NO_REALTIME", "1")
            .stdout(Stdio::null())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("the component starts");
        Proc(child)
    }

    fn alive(&mut self) -> bool {
        matches!(self.0.try_wait(), Ok(None))
    }

    /// SIGTERM, as `unloadusr` sends it; the exit status.
    fn terminate(&mut self) -> i32 {
        let pid = nix::unistd::Pid::from_raw(self.0.id() as i32);
        nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGTERM).unwrap();
        let end = Instant::now() + PATIENCE;
        loop {
            if let Ok(Some(st)) = self.0.try_wait() {
                return st.code().unwrap_or(-1);
            }
            assert!(
                Instant::now() < end,
                "the component did not exit on SIGTERM"
            );
            std::thread::sleep(Duration::from_millis(5));
        }
    }
}

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

struct Hal {
    _host: Host,
    inst: Instance,
    name: String,
}

impl Hal {
    fn new(tag: &str) -> Hal {
        let host = Host::create(HostConfig::for_tests(tag)).unwrap();
        let inst = host.instance().clone();
        let name = inst.name().to_string();
        Hal {
            _host: host,
            inst,
            name,
        }
    }

    fn ready(&self, comp: &str) -> bool {
        self.inst.component(comp).unwrap().is_some_and(|c| c.ready)
    }

    fn gone(&self, comp: &str) -> bool {
        self.inst.component(comp).unwrap().is_none()
    }

    fn get(&self, pin: &str) -> Value {
        self.inst.pin_value(pin).unwrap()
    }

    fn bit(&self, pin: &str) -> bool {
        self.get(pin) == Value::Bit(true)
    }

    fn set(&self, pin: &str, v: Value) {
        self.inst.set_pin(pin, v).unwrap();
    }
}

#[test]
fn hy_vfd_on_a_pty_survives_an_unplugged_line() {
    let hal = Hal::new("tty-hy");
    let dir = PrivateDir::new("hy");
    let link = dir.0.join("ttyUSB-vfd");
    let settings = LineSettings::new(19_200, Parity::Even);
    let pty = PtyVfd::start_linked(VfdSim::new(Protocol::Hy, 1, settings), &link).unwrap();
    let device = link.to_string_lossy().into_owned();
    let mut p = Proc::start(
        env!("CARGO_BIN_EXE_hy_vfd"),
        &[
            "-d",
            &device,
            "-n",
            "spindle",
            "--period",
            "0.02",
            "--response-timeout",
            "50",
            "--retries",
            "1",
        ],
        &hal.name,
    );
    wait_for("the component to be ready", || hal.ready("spindle"));
    hal.set("spindle.enable", Value::Bit(true));
    hal.set("spindle.spindle-on", Value::Bit(true));
    hal.set("spindle.spindle-forward", Value::Bit(true));
    hal.set("spindle.speed-command", Value::Float(12_000.0));
    wait_for("at-speed", || hal.bit("spindle.spindle-at-speed"));
    // hycomm-ok needs more than ten good reads and writes in a row.
    wait_for("hycomm-ok", || hal.bit("spindle.hycomm-ok"));
    assert!(hal.bit("spindle.modbus-ok"));
    assert!(!hal.bit("spindle.fault"));
    assert_eq!(hal.get("spindle.max-freq"), Value::Float(400.0));

    pty.unplug();
    wait_for("the fault pin", || hal.bit("spindle.fault"));
    assert!(!hal.bit("spindle.modbus-ok"));
    assert!(!hal.bit("spindle.spindle-at-speed"));
    // Nothing hangs: the component keeps cycling while the line is gone.
    let errors = || match hal.get("spindle.error-count") {
        Value::S32(n) => n,
        other => panic!("{other:?}"),
    };
    let before = errors();
    wait_for("more failed cycles", || errors() > before);
    assert!(p.alive());

    pty.replug().unwrap();
    wait_for("the drive to answer again", || {
        hal.bit("spindle.modbus-ok") && !hal.bit("spindle.fault")
    });
    wait_for("at-speed again", || hal.bit("spindle.spindle-at-speed"));
    assert_eq!(pty.with(|s| s.model().command()), RunCommand::Forward);

    assert_eq!(p.terminate(), 0);
    assert!(hal.gone("spindle"), "the component leaves the HAL");
    assert_eq!(
        pty.with(|s| s.model().command()),
        RunCommand::Stop,
        "the spindle is stopped on exit"
    );
}

#[test]
fn hy_gt_vfd_on_a_pty_runs_and_stops() {
    let hal = Hal::new("tty-gt");
    let settings = LineSettings::new(38_400, Parity::None);
    let pty = PtyVfd::start(VfdSim::new(Protocol::ModbusGt, 1, settings)).unwrap();
    let device = pty.device();
    let mut p = Proc::start(
        env!("CARGO_BIN_EXE_hy_gt_vfd"),
        &[
            "-d",
            &device,
            "-S",
            "24000",
            "-F",
            "400",
            "-f",
            "120",
            "--response-timeout",
            "50",
        ],
        &hal.name,
    );
    wait_for("the component to be ready", || hal.ready("hy_gt_vfd"));
    hal.set("hy_gt_vfd.period-seconds", Value::Float(0.02));
    hal.set("hy_gt_vfd.spindle-on", Value::Bit(true));
    hal.set("hy_gt_vfd.speed-cmd", Value::Float(9_000.0));
    wait_for("at-speed", || hal.bit("hy_gt_vfd.at-speed"));
    assert_eq!(hal.get("hy_gt_vfd.freq-cmd"), Value::Float(150.0));
    assert!(hal.bit("hy_gt_vfd.modbus-ok"));
    pty.unplug();
    wait_for("the fault pin", || hal.bit("hy_gt_vfd.fault"));
    assert!(p.alive());
    assert_eq!(p.terminate(), 0, "exits cleanly even with the line gone");
    assert!(hal.gone("hy_gt_vfd"));
}

#[test]
fn the_sim_device_runs_without_hardware() {
    let hal = Hal::new("tty-sim");
    let _p = Proc::start(
        env!("CARGO_BIN_EXE_hy_vfd"),
        &["-d", "sim", "--period", "0.02"],
        &hal.name,
    );
    wait_for("the component to be ready", || hal.ready("hy_vfd"));
    hal.set("hy_vfd.enable", Value::Bit(true));
    hal.set("hy_vfd.spindle-on", Value::Bit(true));
    hal.set("hy_vfd.spindle-reverse", Value::Bit(true));
    hal.set("hy_vfd.speed-command", Value::Float(9_000.0));
    wait_for("at-speed", || hal.bit("hy_vfd.spindle-at-speed"));
    assert!(hal.bit("hy_vfd.CNST-running-rf"));
}

#[test]
fn bad_command_lines_and_missing_devices_are_refused() {
    let hal = Hal::new("tty-bad");
    let run = |bin: &str, args: &[&str]| {
        let out = Command::new(bin)
            .args(args)
            .env("HAL_INSTANCE", &hal.name)
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (code, err) = run(env!("CARGO_BIN_EXE_hy_vfd"), &["-r", "13"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("hy_vfd: ERROR: invalid -r: 13"), "{err}");
    let (code, err) = run(
        env!("CARGO_BIN_EXE_hy_vfd"),
        &["-d", "/nonexistent/ttyUSB9"],
    );
    assert_eq!(code, Some(1));
    assert!(
        err.contains(
            "hy_vfd: ERROR: cannot open serial device /nonexistent/ttyUSB9: no such device"
        ),
        "{err}"
    );
    let (code, err) = run(env!("CARGO_BIN_EXE_hy_gt_vfd"), &["-d", "sim"]);
    assert_eq!(code, Some(1));
    assert!(
        err.contains("hy_gt_vfd: ERROR: must specify --motor-max-speed"),
        "{err}"
    );
    assert!(hal
        .inst
        .components()
        .unwrap()
        .iter()
        .all(|c| c.name != "hy_vfd"));
    let out = Command::new(env!("CARGO_BIN_EXE_hy_vfd"))
        .arg("-h")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("Usage: hy_vfd"));
}
