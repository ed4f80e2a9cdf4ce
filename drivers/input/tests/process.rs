//! `hal_input` as `loadusr` runs it: its own process on a private HAL
//! instance, with simulated devices whose events come through a FIFO as
//! the kernel's raw `input_event` records.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hal_core::{HalType, Host, HostConfig, Instance, Value};
use hal_driver::testing::wait;
use hal_input::regs::{Event, EV_ABS, EV_KEY, EV_REL, EV_SYN};

/// The program's process, killed if the test ends early.
struct Proc(Child);

impl Proc {
    /// The exit status and standard error, waiting up to a minute.
    fn finish(&mut self) -> (i32, String) {
        let end = Instant::now() + Duration::from_secs(60);
        loop {
            if let Ok(Some(st)) = self.0.try_wait() {
                let mut err = String::new();
                if let Some(mut e) = self.0.stderr.take() {
                    std::io::Read::read_to_string(&mut e, &mut err).unwrap();
                }
                return (st.code().unwrap_or(-1), err);
            }
            assert!(Instant::now() < end, "hal_input did not exit");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    fn terminate(&mut self) -> (i32, String) {
        let pid = nix::unistd::Pid::from_raw(i32::try_from(self.0.id()).unwrap());
        nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGTERM).unwrap();
        self.finish()
    }
}

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A scratch directory with a FIFO and a description naming it.
fn scratch(tag: &str) -> (PathBuf, PathBuf, PathBuf) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("pad.fifo");
    nix::unistd::mkfifo(&fifo, nix::sys::stat::Mode::from_bits_truncate(0o600)).unwrap();
    let desc = dir.join("devices.txt");
    std::fs::write(
        &desc,
        "device Sim Pad\nid 0003 046d c21d 0111\nkeys BTN_A BTN_B\n\
         abs ABS_X -100 100 0 0 0\nrel REL_WHEEL\nevents pad.fifo\n",
    )
    .unwrap();
    (dir, fifo, desc)
}

fn spawn(inst: &Instance, args: &[&str]) -> Proc {
    let child = Command::new(env!("CARGO_BIN_EXE_hal_input"))
        .args(args)
        .env("HAL_INSTANCE", inst.name())
        .env("HAL_NO_REALTIME", "1")
        .env_remove("HAL_INPUT_SIM")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    Proc(child)
}

fn records(events: &[Event]) -> Vec<u8> {
    events.iter().flat_map(|e| e.to_record()).collect()
}

fn ev(kind: u16, code: u16, value: i32) -> Event {
    Event { kind, code, value }
}

/// Starts hal_input on the scratch pad, ready; the FIFO's writer.
fn start(inst: &Instance, desc: &Path, fifo: &Path) -> (Proc, std::fs::File) {
    let p = spawn(inst, &["--sim", desc.to_str().unwrap(), "Sim Pad"]);
    wait("hal_input ready", || {
        inst.component("hal_input")
            .unwrap()
            .is_some_and(|c| c.ready)
    });
    // hal_input holds the FIFO open for reading: this open does not block.
    let w = std::fs::OpenOptions::new().write(true).open(fifo).unwrap();
    (p, w)
}

#[test]
fn raw_records_drive_the_pins_and_an_unplug_releases_them() {
    let host = Host::create(HostConfig::for_tests("hi-unplug")).unwrap();
    let inst = host.instance().clone();
    let (dir, fifo, desc) = scratch("hi-unplug");
    let (mut p, mut w) = start(&inst, &desc, &fifo);
    inst.newsig("jog-plus", HalType::Bit).unwrap();
    inst.link("input.0.btn-a", "jog-plus").unwrap();
    inst.newsig("jog-speed", HalType::Float).unwrap();
    inst.link("input.0.abs-x-position", "jog-speed").unwrap();
    let bytes = records(&[
        ev(EV_KEY, 0x130, 1),
        ev(EV_ABS, 0, 50),
        ev(EV_REL, 8, 3),
        ev(EV_SYN, 0, 0),
    ]);
    // Written in two pieces, the second starting mid-record: whole
    // records only are applied.
    w.write_all(&bytes[..30]).unwrap();
    std::thread::sleep(Duration::from_millis(50));
    w.write_all(&bytes[30..]).unwrap();
    wait("the button held", || {
        inst.signal_value("jog-plus").unwrap() == Value::Bit(true)
    });
    wait("the stick at half", || {
        inst.signal_value("jog-speed").unwrap() == Value::Float(0.5)
    });
    wait("three detents", || {
        inst.pin_value("input.0.rel-wheel-counts").unwrap() == Value::S32(3)
    });
    // Unplugged: the node goes away.
    std::fs::remove_file(&fifo).unwrap();
    let (code, err) = p.finish();
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("input.0: the device went away"), "{err}");
    assert!(err.contains("every key now reads released"), "{err}");
    assert_eq!(inst.signal_value("jog-plus").unwrap(), Value::Bit(false));
    assert_eq!(inst.signal_value("jog-speed").unwrap(), Value::Float(0.0));
    assert!(inst.component("hal_input").unwrap().is_none());
    drop(w);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sigterm_releases_the_keys_and_exits_cleanly() {
    let host = Host::create(HostConfig::for_tests("hi-term")).unwrap();
    let inst = host.instance().clone();
    let (dir, fifo, desc) = scratch("hi-term");
    let (mut p, mut w) = start(&inst, &desc, &fifo);
    inst.newsig("b", HalType::Bit).unwrap();
    inst.link("input.0.btn-b", "b").unwrap();
    w.write_all(&records(&[ev(EV_KEY, 0x131, 1), ev(EV_SYN, 0, 0)]))
        .unwrap();
    wait("B held", || {
        inst.signal_value("b").unwrap() == Value::Bit(true)
    });
    let (code, err) = p.terminate();
    assert_eq!(code, 0, "{err}");
    assert_eq!(inst.signal_value("b").unwrap(), Value::Bit(false));
    drop(w);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_missing_device_is_named_and_nothing_is_left_in_hal() {
    let host = Host::create(HostConfig::for_tests("hi-missing")).unwrap();
    let inst = host.instance().clone();
    let (dir, _fifo, desc) = scratch("hi-missing");
    let mut p = spawn(&inst, &["--sim", desc.to_str().unwrap(), "-K", "Joystick"]);
    let (code, err) = p.finish();
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("no input device matching 'Joystick' was found (1 devices checked)"),
        "{err}"
    );
    assert!(inst.component("hal_input").unwrap().is_none());
    let mut p = spawn(
        &inst,
        &["--sim", dir.join("none.txt").to_str().unwrap(), "x"],
    );
    let (code, err) = p.finish();
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("none.txt"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
