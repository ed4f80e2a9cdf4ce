//! `xhc-hb04` as `loadusr` runs it: its own process, attached to a
//! private HAL instance, with no pendant plugged in.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, Instance, Value};
use hal_driver::testing::wait;

const PATIENCE: Duration = Duration::from_secs(60);

/// The driver's process, killed if the test ends early.
struct Proc(Child);

impl Proc {
    /// SIGTERM, as `unloadusr` sends it; the exit status.
    fn terminate(&mut self) -> i32 {
        let pid = nix::unistd::Pid::from_raw(i32::try_from(self.0.id()).unwrap());
        nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGTERM).unwrap();
        let end = Instant::now() + PATIENCE;
        loop {
            if let Ok(Some(st)) = self.0.try_wait() {
                return st.code().unwrap_or(-1);
            }
            assert!(Instant::now() < end, "xhc-hb04 did not exit on SIGTERM");
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

fn layout2() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lib/hallib/xhc-hb04-layout2.cfg")
}

#[test]
fn without_a_pendant_the_pins_exist_and_step_sizes_work() {
    let host = Host::create(HostConfig::for_tests("xhc-proc")).unwrap();
    let inst: Instance = host.instance().clone();
    let child = Command::new(env!("CARGO_BIN_EXE_xhc-hb04"))
        .args(["-H", "-s", "4", "-I"])
        .arg(layout2())
        .env("HAL_INSTANCE", inst.name())
        .env("HAL_NO_REALTIME", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    let mut p = Proc(child);
    wait("xhc-hb04 ready", || {
        inst.component("xhc-hb04").unwrap().is_some_and(|c| c.ready)
    });
    let get = |pin: &str| inst.pin_value(&format!("xhc-hb04.{pin}")).unwrap();
    let pendants = hal_usb::xhc::device::find(
        Path::new(hal_usb::xhc::device::SYS_HIDRAW),
        Path::new("/dev"),
    );
    if pendants.is_empty() {
        assert_eq!(get("connected"), Value::Bit(false));
    } else {
        eprintln!("a pendant is plugged in ({pendants:?}): connected not checked");
    }
    assert_eq!(get("require_pendant"), Value::Bit(false));
    for pin in [
        "button-half-z",
        "button-macro-7",
        "jog.enable-off",
        "x.pos-absolute",
    ] {
        inst.pin_value(&format!("xhc-hb04.{pin}")).unwrap();
    }
    // Sequence 4 is 1, 5, 10, 20, 50, 100: up twice, down three times.
    wait("the first step size", || get("stepsize") == Value::S32(1));
    let pulse = |pin: &str| {
        let name = format!("xhc-hb04.{pin}");
        inst.set_pin(&name, Value::Bit(true)).unwrap();
        std::thread::sleep(Duration::from_millis(100));
        inst.set_pin(&name, Value::Bit(false)).unwrap();
        std::thread::sleep(Duration::from_millis(100));
    };
    pulse("stepsize-up");
    pulse("stepsize-up");
    wait("step size 10", || get("stepsize") == Value::S32(10));
    assert_eq!(get("jog.scale"), Value::Float(0.01));
    for _ in 0..3 {
        pulse("stepsize-down");
    }
    wait("step size 100 (wrapped)", || {
        get("stepsize") == Value::S32(100)
    });
    assert_eq!(p.terminate(), 0);
}

#[test]
fn a_bad_button_file_is_refused_with_its_line() {
    let dir = std::env::temp_dir().join(format!("xhc-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cfg = dir.join("bad.cfg");
    std::fs::write(&cfg, "[XHC-HB04]\nBUTTON=01:button-a\nBUTTON=zz:button-b\n").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_xhc-hb04"))
        .args(["-H", "-I"])
        .arg(&cfg)
        .env("HAL_INSTANCE", "xhc-bad-never-started")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("bad.cfg:3") && err.contains("'zz'"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
