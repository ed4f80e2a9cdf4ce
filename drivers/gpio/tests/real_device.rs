//! hal_gpio on the kernel's GPIO character device, against chips of the
//! `gpio-sim` module that each test makes through configfs (named lines,
//! two banks), reading the electrical levels back through gpio-sim's
//! sysfs (`sim_gpioN/value`) and driving inputs through its `pull`.
//!
//! Needs root and gpio-sim: the VM rig (`../shared/tools/vmrig`) has
//! both; `scripts/test-all` runs this binary there with
//! `--include-ignored`. Elsewhere the tests are ignored, with the reason;
//! run on purpose without gpio-sim they fail.
//!
//! ```text
//! vmrig run -- target/debug/deps/real_device-<hash> --include-ignored --test-threads=1
//! ```
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::{Path, PathBuf};

mod common;

use common::*;
use hal_driver::sim::MonotonicClock;
use hal_gpio::cdev::CdevChips;
use hal_gpio::cfg::{Bias, Direction, Drive};
use hal_gpio::chip::{ChipSet, LineSetting};
use hal_gpio::driver::OutputBank;

const CONFIGFS: &str = "/sys/kernel/config/gpio-sim";

/// A gpio-sim device with named lines, removed when dropped.
struct GpioSim {
    dir: PathBuf,
    /// Per bank: chip name (`gpiochipN`) and the sysfs directory of its
    /// lines.
    banks: Vec<(String, PathBuf)>,
}

fn write(path: &Path, text: &str) {
    std::fs::write(path, text)
        .unwrap_or_else(|e| panic!("writing {text:?} to {}: {e}", path.display()));
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()))
        .trim()
        .to_string()
}

impl GpioSim {
    /// Fails the test, saying why, unless gpio-sim can be configured here.
    fn require() {
        assert!(
            Path::new(CONFIGFS).is_dir() && nix_is_root(),
            "no writable gpio-sim configfs at {CONFIGFS} (needs root and the gpio-sim \
             module); run this binary through the VM rig"
        );
    }

    /// A device `name` with one bank per entry of `banks`: (lines, named
    /// lines as (offset, name)).
    fn new(name: &str, banks: &[(u32, &[(u32, &str)])]) -> GpioSim {
        let dir = Path::new(CONFIGFS).join(name);
        let _ = Self::teardown(&dir);
        std::fs::create_dir(&dir).unwrap();
        for (b, (lines, names)) in banks.iter().enumerate() {
            let bank = dir.join(format!("bank{b}"));
            std::fs::create_dir(&bank).unwrap();
            write(&bank.join("num_lines"), &lines.to_string());
            write(&bank.join("label"), &format!("{name}-{b}"));
            for (offset, line) in names.iter() {
                let l = bank.join(format!("line{offset}"));
                std::fs::create_dir(&l).unwrap();
                write(&l.join("name"), line);
            }
        }
        write(&dir.join("live"), "1");
        let dev = read(&dir.join("dev_name"));
        let banks = (0..banks.len())
            .map(|b| {
                let chip = read(&dir.join(format!("bank{b}/chip_name")));
                let sysfs = Path::new("/sys/devices/platform").join(&dev).join(&chip);
                (chip, sysfs)
            })
            .collect();
        GpioSim { dir, banks }
    }

    fn teardown(dir: &Path) -> std::io::Result<()> {
        if !dir.exists() {
            return Ok(());
        }
        let _ = std::fs::write(dir.join("live"), "0");
        for bank in std::fs::read_dir(dir)? {
            let bank = bank?.path();
            if !bank.is_dir() {
                continue;
            }
            for line in std::fs::read_dir(&bank)? {
                let line = line?.path();
                if line.is_dir() {
                    std::fs::remove_dir(&line)?;
                }
            }
            std::fs::remove_dir(&bank)?;
        }
        std::fs::remove_dir(dir)
    }

    fn chip_path(&self, bank: usize) -> PathBuf {
        Path::new("/dev").join(&self.banks[bank].0)
    }

    /// gpio-sim's `value` of a line: its electrical level.
    fn value(&self, bank: usize, offset: u32) -> bool {
        read(&self.banks[bank].1.join(format!("sim_gpio{offset}/value"))) == "1"
    }

    /// gpio-sim's `pull` of a line, as text.
    fn pull(&self, bank: usize, offset: u32) -> String {
        read(&self.banks[bank].1.join(format!("sim_gpio{offset}/pull")))
    }

    /// Drives an input from outside.
    fn set_pull(&self, bank: usize, offset: u32, up: bool) {
        write(
            &self.banks[bank].1.join(format!("sim_gpio{offset}/pull")),
            if up { "pull-up" } else { "pull-down" },
        );
    }

    /// Takes the chip away (as an unplugged USB GPIO adapter would go).
    fn unplug(&self) {
        write(&self.dir.join("live"), "0");
    }
}

impl Drop for GpioSim {
    fn drop(&mut self) {
        if let Err(e) = Self::teardown(&self.dir) {
            eprintln!("removing {}: {e}", self.dir.display());
        }
    }
}

fn nix_is_root() -> bool {
    // SAFETY: geteuid has no preconditions and cannot fail.
    unsafe { libc::geteuid() == 0 }
}

/// The test device: bank 0 with inputs IN0..IN3 on lines 0..3 and
/// outputs OUT0..OUT3 on lines 8..11; bank 1 with IN9 on line 2 and OUT9
/// on line 5.
fn rig(name: &str) -> GpioSim {
    GpioSim::new(
        name,
        &[
            (
                16,
                &[
                    (0, "HAL_IN0"),
                    (1, "HAL_IN1"),
                    (2, "HAL_IN2"),
                    (3, "HAL_IN3"),
                    (8, "HAL_OUT0"),
                    (9, "HAL_OUT1"),
                    (10, "HAL_OUT2"),
                    (11, "HAL_OUT3"),
                ],
            ),
            (8, &[(2, "HAL_IN9"), (5, "HAL_OUT9")]),
        ],
    )
}

#[test]
#[ignore = "needs root and gpio-sim: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn inputs_follow_the_simulated_pins_across_two_chips() {
    GpioSim::require();
    let sim = rig("hal-gpio-in");
    let h = host("rd-in");
    h.loadrt(
        &hal_gpio::MODULE,
        &["inputs=HAL_IN0,HAL_IN1,HAL_IN9,HAL_IN3", "pullup=HAL_IN3"],
    )
    .unwrap();
    // The requested pull-up reached the chip: gpio-sim shows it.
    assert_eq!(sim.pull(0, 3), "pull-up");
    run(&h, 1_000_000, &["hal_gpio.read"]);
    sim.set_pull(0, 0, true);
    sim.set_pull(0, 1, false);
    sim.set_pull(1, 2, true);
    wait_for("inputs high", || {
        bit(&h, "hal_gpio.HAL_IN0-in")
            && !bit(&h, "hal_gpio.HAL_IN1-in")
            && bit(&h, "hal_gpio.HAL_IN9-in")
            && bit(&h, "hal_gpio.HAL_IN3-in")
    });
    assert!(!bit(&h, "hal_gpio.HAL_IN0-in-not") && bit(&h, "hal_gpio.HAL_IN1-in-not"));
    sim.set_pull(0, 0, false);
    sim.set_pull(1, 2, false);
    wait_for("inputs low", || {
        !bit(&h, "hal_gpio.HAL_IN0-in") && !bit(&h, "hal_gpio.HAL_IN9-in")
    });
    assert!(bit(&h, "hal_gpio.HAL_IN9-in-not"));
    h.stop();
    h.unloadrt("hal_gpio").unwrap();
}

#[test]
#[ignore = "needs root and gpio-sim: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn outputs_and_active_low_read_back_through_sysfs() {
    GpioSim::require();
    let sim = rig("hal-gpio-out");
    let h = host("rd-out");
    h.loadrt(
        &hal_gpio::MODULE,
        &["outputs=HAL_OUT0,HAL_OUT1,HAL_OUT9", "invert=HAL_OUT1"],
    )
    .unwrap();
    // Requested at their inactive levels: the inverted line is high.
    assert!(!sim.value(0, 8) && sim.value(0, 9) && !sim.value(1, 5));
    // The kernel holds the configuration: consumer and active-low.
    let chip = gpiocdev::Chip::from_path(sim.chip_path(0)).unwrap();
    let info = chip.line_info(9).unwrap();
    assert!(info.used && info.active_low, "{info:?}");
    assert_eq!(info.consumer, "hal_gpio");
    assert_eq!(info.direction, gpiocdev::line::Direction::Output);
    run(&h, 1_000_000, &["hal_gpio.write"]);
    set(&h, "hal_gpio.HAL_OUT0-out", true);
    set(&h, "hal_gpio.HAL_OUT1-out", true);
    set(&h, "hal_gpio.HAL_OUT9-out", true);
    wait_for("outputs driven", || {
        sim.value(0, 8) && !sim.value(0, 9) && sim.value(1, 5)
    });
    set(&h, "hal_gpio.HAL_OUT1-out", false);
    wait_for("inverted output released", || sim.value(0, 9));
    h.stop();
    h.unloadrt("hal_gpio").unwrap();
}

fn out(offset: u32, active_low: bool, drive: Drive, bias: Bias) -> LineSetting {
    LineSetting {
        offset,
        direction: Direction::Output,
        active_low,
        drive,
        bias,
    }
}

#[test]
#[ignore = "needs root and gpio-sim: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn write_reset_and_safe_state_on_the_kernel() {
    GpioSim::require();
    let sim = rig("hal-gpio-reset");
    let info = CdevChips::info(&sim.chip_path(0)).unwrap();
    let req = CdevChips
        .request(
            &info,
            &[
                out(8, false, Drive::PushPull, Bias::AsIs),
                out(9, true, Drive::PushPull, Bias::AsIs),
            ],
        )
        .unwrap();
    // Both are reset lines.
    let bank = OutputBank::new(req, 2, 0b11);
    let clock = MonotonicClock;
    bank.write(0b11, &clock).unwrap();
    assert!(
        sim.value(0, 8) && !sim.value(0, 9),
        "active: high, and low when inverted"
    );
    bank.reset(10_000, &clock).unwrap();
    assert!(
        !sim.value(0, 8) && sim.value(0, 9),
        "reset: back to inactive"
    );
    bank.write(0b01, &clock).unwrap();
    assert!(sim.value(0, 8));
    bank.go_safe();
    assert!(!sim.value(0, 8) && sim.value(0, 9), "safe: inactive");
    assert_eq!(bank.request().errors(), 0);
}

#[test]
#[ignore = "needs root and gpio-sim: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn drive_and_bias_flags_reach_the_kernel() {
    GpioSim::require();
    let sim = rig("hal-gpio-flags");
    let h = host("rd-flags");
    h.loadrt(
        &hal_gpio::MODULE,
        &[
            "inputs=HAL_IN0,HAL_IN1",
            "outputs=HAL_OUT0,HAL_OUT1,HAL_OUT2",
            "pulldown=HAL_IN0",
            "biasdisable=HAL_IN1",
            "opendrain=HAL_OUT0",
            "opensource=HAL_OUT1",
            "pullup=HAL_OUT0",
        ],
    )
    .unwrap();
    let chip = gpiocdev::Chip::from_path(sim.chip_path(0)).unwrap();
    let li = |o| chip.line_info(o).unwrap();
    use gpiocdev::line::{Bias as B, Drive as D};
    assert_eq!(li(0).bias, Some(B::PullDown));
    assert_eq!(li(1).bias, Some(B::Disabled));
    assert_eq!(li(8).drive, Some(D::OpenDrain));
    assert_eq!(li(8).bias, Some(B::PullUp));
    assert_eq!(li(9).drive, Some(D::OpenSource));
    assert_eq!(li(10).drive, Some(D::PushPull));
    assert_eq!(sim.pull(0, 0), "pull-down");
    // Open drain, inactive: driven low, whatever pulls from outside.
    // Active: released (gpio-sim then shows the outside pull, applied
    // again by writing it). Open source active: driven high.
    sim.set_pull(0, 8, true);
    assert!(!sim.value(0, 8), "open drain inactive drives low");
    run(&h, 1_000_000, &["hal_gpio.write"]);
    set(&h, "hal_gpio.HAL_OUT0-out", true);
    set(&h, "hal_gpio.HAL_OUT1-out", true);
    wait_for("open source driven", || sim.value(0, 9));
    wait_for("open drain released", || {
        sim.set_pull(0, 8, true);
        sim.value(0, 8)
    });
    h.stop();
    h.unloadrt("hal_gpio").unwrap();
    assert!(!li(8).used, "released at unload");
}

#[test]
#[ignore = "needs root and gpio-sim: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn names_found_nowhere_twice_or_busy_are_load_errors() {
    GpioSim::require();
    let _a = GpioSim::new(
        "hal-gpio-dup",
        &[(4, &[(1, "HAL_DUP")]), (4, &[(3, "HAL_DUP")])],
    );
    let sim = rig("hal-gpio-names");
    let h = host("rd-names");
    let e = h
        .loadrt(&hal_gpio::MODULE, &["outputs=HAL_OUT0,HAL_NOPE"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("parameter 'outputs': item 1 \"HAL_NOPE\": no GPIO line has this name"),
        "{e}"
    );
    let e = h
        .loadrt(&hal_gpio::MODULE, &["inputs=HAL_DUP"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("\"HAL_DUP\": the name is on more than one line ("),
        "{e}"
    );
    assert!(
        e.contains("[hal-gpio-dup-0] line 1 and ") && e.contains("[hal-gpio-dup-1] line 3"),
        "{e}"
    );
    // A line someone else holds: the error names the holder, and the
    // lines of the other requests are released again.
    let info = CdevChips::info(&sim.chip_path(1)).unwrap();
    let theirs = gpiocdev::Request::builder()
        .on_chip(&info.path)
        .with_consumer("other-user")
        .with_line(5)
        .as_input()
        .request()
        .unwrap();
    let e = h
        .loadrt(&hal_gpio::MODULE, &["inputs=HAL_IN0", "outputs=HAL_OUT9"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("requesting HAL_OUT9 on"), "{e}");
    assert!(e.contains("HAL_OUT9 is in use by \"other-user\""), "{e}");
    let chip = gpiocdev::Chip::from_path(sim.chip_path(0)).unwrap();
    assert!(!chip.line_info(0).unwrap().used, "HAL_IN0 released");
    assert!(h.loaded_components().is_empty());
    drop(theirs);
    h.loadrt(&hal_gpio::MODULE, &["inputs=HAL_IN0", "outputs=HAL_OUT9"])
        .unwrap();
}

#[test]
#[ignore = "needs root and gpio-sim: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn an_unplugged_chip_trips_the_fault_and_nothing_hangs() {
    GpioSim::require();
    let keep = rig("hal-gpio-keep");
    let gone = GpioSim::new(
        "hal-gpio-gone",
        &[(4, &[(0, "HAL_GONE_IN"), (1, "HAL_GONE_OUT")])],
    );
    let h = host("rd-gone");
    h.loadrt(
        &hal_gpio::MODULE,
        &["inputs=HAL_GONE_IN", "outputs=HAL_GONE_OUT,HAL_OUT0"],
    )
    .unwrap();
    set(&h, "hal_gpio.HAL_OUT0-out", true);
    run(&h, 1_000_000, &["hal_gpio.read", "hal_gpio.write"]);
    wait_for("output on", || keep.value(0, 8));
    gone.unplug();
    wait_for("fault said", || {
        h.flush_rt_log();
        h.rt_log()
            .history()
            .iter()
            .any(|(_, m)| m.contains("hal_gpio: reading GPIO lines failed"))
    });
    wait_for("other outputs inactive", || !keep.value(0, 8));
    assert!(h.fault().is_none(), "the thread runs on");
    h.stop();
    h.unloadrt("hal_gpio").unwrap();
}
