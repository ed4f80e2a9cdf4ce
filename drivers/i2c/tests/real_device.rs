//! The I2C drivers on the kernel's i2c-dev, against i2c-stub: a register
//! file per chip address that speaks SMBus only (byte data, word data,
//! I2C block data), which is all these drivers use. The stub holds what
//! the driver wrote and answers reads with what the test put there, so
//! the tests check each chip's register traffic through a real kernel
//! interface, byte order included; the chips' behaviour itself is the
//! register models' part (`sim_hal.rs`).
//!
//! Needs root and i2c-stub: the VM rig has both; `.ci/run` runs this
//! binary there. The first test reloads i2c-stub with the addresses
//! these tests need (0x20, 0x40, 0x48, 0x49). Elsewhere the tests are
//! ignored, with the reason; run on purpose outside the rig they fail.
//!
//! ```text
//! vmrig run -- target/debug/deps/real_device-<hash> --include-ignored --test-threads=1
//! ```
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::PathBuf;
use std::process::Command;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

mod common;

use common::*;

use hal_core::{RtLog, Value};
use hal_i2c::bus::I2cBus;
use hal_i2c::chips::{DioCmd, Mcp23017Chip};
use hal_i2c::hal::{ads1115, mcp23017, pca9685};
use hal_i2c::linux::LinuxBus;
use hal_i2c::regs::{ads1115 as ads, mcp23017 as mcp, pca9685 as pca};
use hal_i2c::worker::{ChipRunner, Task};

const ADDRS: &str = "0x20,0x40,0x48,0x49";

/// The stub's bus number, after loading it with [`ADDRS`]; outside the
/// rig the test fails, saying why.
fn stub_bus() -> u32 {
    stub_bus_once().expect(
        "not in the VM rig (no VMRIG_I2C_DEV, or not root); run this binary \
         through ../shared/tools/vmrig to test on i2c-stub",
    )
}

fn stub_bus_once() -> Option<u32> {
    static BUS: OnceLock<Option<u32>> = OnceLock::new();
    *BUS.get_or_init(|| {
        // SAFETY: geteuid has no preconditions and cannot fail.
        let root = unsafe { libc::geteuid() } == 0;
        if std::env::var_os("VMRIG_I2C_DEV").is_none() || !root {
            return None;
        }
        let _ = Command::new("rmmod").arg("i2c_stub").status();
        let ok = Command::new("modprobe")
            .args(["i2c-stub", &format!("chip_addr={ADDRS}")])
            .status()
            .map(|s| s.success())
            .unwrap_or(false);
        assert!(ok, "modprobe i2c-stub chip_addr={ADDRS} failed");
        let end = Instant::now() + Duration::from_secs(30);
        loop {
            if let Some(n) = find_stub() {
                if LinuxBus::path_of(n).exists() {
                    return Some(n);
                }
            }
            assert!(Instant::now() < end, "no i2c-stub bus appeared");
            std::thread::sleep(Duration::from_millis(10));
        }
    })
}

fn find_stub() -> Option<u32> {
    for e in std::fs::read_dir("/sys/bus/i2c/devices").ok()?.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(n) = name.strip_prefix("i2c-") else {
            continue;
        };
        let label = std::fs::read_to_string(e.path().join("name")).unwrap_or_default();
        if label.trim() == "SMBus stub driver" {
            return n.parse().ok();
        }
    }
    None
}

/// A bus of our own on the stub, for putting values in and reading what
/// the driver wrote.
fn peek(bus: u32, addrs: &[u8]) -> LinuxBus {
    let b = LinuxBus::open(&LinuxBus::path_of(bus)).unwrap();
    for &a in addrs {
        b.claim(a).unwrap();
    }
    b
}

#[test]
#[ignore = "needs root and i2c-stub: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn pca9685_set_up_and_channels_on_the_stub() {
    let n = stub_bus();
    let h = host("rd-pca");
    h.loadrt(
        &pca9685::MODULE,
        &[&format!("bus={n}"), "address=0x40", "freq=50", "invert=1"],
    )
    .unwrap();
    let s = peek(n, &[0x40]);
    let byte = |r| s.read_byte_data(0x40, r).unwrap();
    assert_eq!(
        byte(pca::MODE1),
        pca::MODE1_AI,
        "awake, auto-increment, no all-call"
    );
    assert_eq!(byte(pca::PRE_SCALE), 121);
    assert_eq!(byte(pca::MODE2), pca::MODE2_INVRT | pca::MODE2_OUTDRV);
    assert_eq!(byte(pca::ALL_LED_OFF_H), pca::FULL);
    run(&h, &["pca9685.0.read", "pca9685.0.write"]);
    let p = "pca9685.0.pwmgen";
    set(&h, &format!("{p}.00.value"), Value::Float(0.25));
    set(&h, &format!("{p}.00.enable"), Value::Bit(true));
    set(&h, &format!("{p}.15.value"), Value::Float(1.0));
    set(&h, &format!("{p}.15.enable"), Value::Bit(true));
    let ch = |c: usize| -> Vec<u8> { (0..4).map(|k| byte(pca::led_on_l(c) + k)).collect() };
    wait_for("channels written", || {
        ch(0) == [0, 0, 0x00, 0x04] && ch(15) == [0, 0x10, 0, 0]
    });
    assert_eq!(ch(7), [0, 0, 0, 0x10], "disabled: full off");
    assert_eq!(
        h.instance().pin_value("pca9685.0.errors").unwrap(),
        Value::U32(0)
    );
    h.stop();
    h.unloadrt("pca9685").unwrap();
    assert_eq!(ch(0), [0, 0, 0, 0x10], "unload: full off");
    assert_eq!(ch(15), [0, 0, 0, 0x10]);
}

#[test]
#[ignore = "needs root and i2c-stub: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn mcp23017_directions_inputs_and_outputs_on_the_stub() {
    let n = stub_bus();
    let s = peek(n, &[0x20]);
    // What the pins read: GPB0 and GPB2 high.
    s.write_word_data(0x20, mcp::GPIOA, 0x0500).unwrap();
    let h = host("rd-mcp");
    h.loadrt(
        &mcp23017::MODULE,
        &[
            &format!("bus={n}"),
            "address=0x20",
            "dir=0x7f00",
            "pullup=0x0300",
        ],
    )
    .unwrap();
    assert_eq!(s.read_byte_data(0x20, mcp::IOCON).unwrap(), 0);
    assert_eq!(s.read_word_data(0x20, mcp::IODIRA).unwrap(), 0x7f00);
    assert_eq!(s.read_word_data(0x20, mcp::GPPUA).unwrap(), 0x0300);
    assert_eq!(
        s.read_word_data(0x20, mcp::OLATA).unwrap(),
        0,
        "outputs start safe"
    );
    let m = "mcp23017.0";
    h.instance()
        .set_param(&format!("{m}.digout.15.invert"), Value::Bit(true))
        .unwrap();
    run(&h, &[&format!("{m}.read"), &format!("{m}.write")]);
    set(&h, &format!("{m}.digout.00.out"), Value::Bit(true));
    wait_for("outputs written", || {
        s.read_word_data(0x20, mcp::OLATA).unwrap() == 0x8001
    });
    let bit = |p: &str| {
        h.instance()
            .pin_value(&format!("{m}.digin.{p}.in"))
            .unwrap()
    };
    wait_for("inputs read", || bit("08") == Value::Bit(true));
    assert_eq!(bit("09"), Value::Bit(false));
    assert_eq!(bit("10"), Value::Bit(true));
    s.write_word_data(0x20, mcp::GPIOA, 0x0200).unwrap();
    wait_for("inputs change", || {
        bit("09") == Value::Bit(true) && bit("08") == Value::Bit(false)
    });
    h.stop();
    h.unloadrt("mcp23017").unwrap();
    assert_eq!(
        s.read_word_data(0x20, mcp::OLATA).unwrap(),
        0x8000,
        "unload: every output at its invert level"
    );
}

#[test]
#[ignore = "needs root and i2c-stub: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn ads1115_words_go_most_significant_byte_first() {
    let n = stub_bus();
    let s = peek(n, &[0x48]);
    // The conversion register holds 0x1234 as the chip sends it: 0x12
    // first. An SMBus word carries the first byte in its low half.
    s.write_word_data(0x48, ads::CONVERSION, 0x1234u16.swap_bytes())
        .unwrap();
    let h = host("rd-ads");
    h.loadrt(
        &ads1115::MODULE,
        &[
            &format!("bus={n}"),
            "address=0x48",
            "range=2048",
            "rate=128",
            "channels=1",
        ],
    )
    .unwrap();
    run(&h, &["ads1115.0.read"]);
    let lsb = 2.048 / 32768.0;
    wait_for("conversion", || {
        h.instance().pin_value("ads1115.0.adcin.0.value").unwrap()
            == Value::Float(0x1234 as f64 * lsb)
    });
    // The configuration as it went out: MSB first.
    let cfg = s.read_word_data(0x48, ads::CONFIG).unwrap().swap_bytes();
    assert_eq!(
        cfg & 0x7FFF,
        0x4000 | (2 << 9) | 0x0100 | (4 << 5) | 3,
        "{cfg:#06x}"
    );
    assert_eq!(
        s.read_byte_data(0x48, ads::CONFIG).unwrap(),
        (cfg >> 8) as u8
    );
    assert_eq!(
        h.instance().pin_value("ads1115.0.fault").unwrap(),
        Value::Bit(false)
    );
}

#[test]
#[ignore = "needs root and i2c-stub: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn a_chip_that_does_not_answer_fails_the_load_naming_it() {
    let n = stub_bus();
    let h = host("rd-missing");
    let e = h
        .loadrt(&ads1115::MODULE, &[&format!("bus={n}"), "address=0x4a"])
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!(
            "ads1115: ads1115.0: /dev/i2c-{n} address 0x4a: setting the chip up failed: "
        )),
        "{e}"
    );
    assert!(e.contains("no answer"), "{e}");
    assert!(h.loaded_components().is_empty());
}

#[test]
#[ignore = "needs root and i2c-stub: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn an_address_a_kernel_driver_holds_is_refused() {
    let n = stub_bus();
    // The kernel refuses I2C_SLAVE only while a driver is bound: give
    // 0x49 to the EEPROM driver.
    let at24 = Command::new("modprobe").arg("at24").status();
    if !at24.map(|s| s.success()).unwrap_or(false) {
        eprintln!("SKIPPED: no at24 module to bind to the address");
        return;
    }
    let dev = PathBuf::from(format!("/sys/bus/i2c/devices/i2c-{n}"));
    std::fs::write(dev.join("new_device"), "24c02 0x49").unwrap();
    let h = host("rd-busy");
    let e = h
        .loadrt(&ads1115::MODULE, &[&format!("bus={n}"), "address=0x49"])
        .unwrap_err()
        .to_string();
    std::fs::write(dev.join("delete_device"), "0x49").unwrap();
    assert!(
        e.contains("address 0x49: ") && e.contains("kernel driver owns this address"),
        "{e}"
    );
    h.loadrt(&ads1115::MODULE, &[&format!("bus={n}"), "address=0x49"])
        .unwrap();
}

#[test]
#[ignore = "needs root and i2c-stub: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn a_chip_lost_at_run_time_latches_and_the_helper_keeps_going() {
    let n = stub_bus();
    // A chip that answered once and then stopped: no stub chip at 0x4b,
    // so every transfer gets the kernel's no-answer error.
    let bus = LinuxBus::open(&LinuxBus::path_of(n)).unwrap();
    bus.claim(0x4b).unwrap();
    let log = RtLog::new(8);
    let (runner, mut rt) = ChipRunner::new(
        "mcp23017.9",
        Mcp23017Chip::new(0x4b, 0xff00, 0),
        log.clone(),
    );
    rt.cmd.publish(DioCmd { out: 1, safe: 0 });
    let mut now = 0;
    for _ in 0..5 {
        runner.service(&bus, now);
        now += hal_i2c::worker::RETRY_NS;
    }
    let st = *rt.status.latest();
    assert!(st.fault);
    assert_eq!(st.errors, 5, "every retry counted");
    let mut said = Vec::new();
    log.drain(|_, t| said.push(t.to_string()));
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(
        said[0].contains(&format!("mcp23017.9: /dev/i2c-{n} address 0x4b: ")),
        "{said:?}"
    );
    assert!(said[0].contains("no answer"), "{said:?}");
    assert_eq!(bus.errors(), 5);
}
