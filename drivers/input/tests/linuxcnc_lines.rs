//! The `hal_input` lines of LinuxCNC's shipped configurations, through a
//! halcmd session and `loadusr` on simulated devices (`HAL_INPUT_SIM`):
//! sim/tracking-test.hal's mouse on /dev/input/event1 (`-RK 1`, wheel and
//! axes reset by the right button) and plasma-5i20.hal's joypad
//! (`loadusr hal_input -W -KRAL Dual`, where `-W` reaches hal_input).
//!
//! Alone in its test binary: it sets `HAL_INPUT_SIM` for the programs
//! `loadusr` starts.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::io::Write;
use std::path::Path;

use hal_core::Value;
use hal_driver::testing::wait;
use hal_host::testing::InProcessHost;
use hal_input::regs::{Event, EV_KEY, EV_REL, EV_SYN};

const DEVICES: &str = "\
device AT Translated Set 2 keyboard
phys isa0060/serio0/input0
id 0011 0001 0001 ab41
keys KEY_A KEY_B
leds LED_NUML
device Sim USB Optical Mouse
phys usb-0000:00:14.0-2/input0
id 0003 046d c077 0111
keys BTN_LEFT BTN_RIGHT BTN_MIDDLE
rel REL_X REL_Y REL_WHEEL
events mouse.fifo
device Logitech Logitech Dual Action
phys usb-0000:00:14.0-3/input0
id 0003 046d c216 0110
keys BTN_TRIGGER BTN_THUMB BTN_THUMB2
abs ABS_X 0 255 0 15 128
abs ABS_Y 0 255 0 15 128
abs ABS_HAT0X -1 1 0 0 0
";

const TRACKING_TEST: &str = "\
loadusr -W hal_input -RK 1
net x-mouse input.0.rel-x-position
net y-mouse input.0.rel-y-position
net z-mouse input.0.rel-wheel-position
net click input.0.btn-right
net click input.0.rel-wheel-reset
net click input.0.rel-x-reset
net click input.0.rel-y-reset
";

fn run(host: &InProcessHost, file: &str, text: &str) {
    let (ok, _, err) = host.run(file, text, false);
    assert!(ok, "{file}: {err}");
}

fn records(events: &[(u16, u16, i32)]) -> Vec<u8> {
    events
        .iter()
        .chain([(EV_SYN, 0, 0)].iter())
        .flat_map(|&(kind, code, value)| Event { kind, code, value }.to_record())
        .collect()
}

#[test]
fn linuxcncs_hal_input_lines_run_on_simulated_devices() {
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("lcnc-lines-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("mouse.fifo");
    nix::unistd::mkfifo(&fifo, nix::sys::stat::Mode::from_bits_truncate(0o600)).unwrap();
    let desc = dir.join("devices.txt");
    std::fs::write(&desc, DEVICES).unwrap();
    std::env::set_var("HAL_INPUT_SIM", &desc);

    let host = InProcessHost::start("lcnc-lines");
    let inst = host.instance();

    // tracking-test.hal: the mouse's axes and wheel, its buttons; -RK
    // makes no LED pins.
    run(&host, "tracking-test.hal", TRACKING_TEST);
    assert!(inst.pin("input.0.btn-left").unwrap().is_some());
    assert!(inst.pin("input.0.rel-x-counts").unwrap().is_some());
    let mut w = std::fs::OpenOptions::new().write(true).open(&fifo).unwrap();
    w.write_all(&records(&[(EV_REL, 0, 5), (EV_REL, 1, -2), (EV_REL, 8, 1)]))
        .unwrap();
    wait("the mouse moved", || {
        inst.signal_value("x-mouse").unwrap() == Value::Float(5.0)
            && inst.signal_value("y-mouse").unwrap() == Value::Float(-2.0)
            && inst.signal_value("z-mouse").unwrap() == Value::Float(1.0)
    });
    // The right button resets the counts while held.
    w.write_all(&records(&[(EV_KEY, 0x111, 1)])).unwrap();
    wait("the reset", || {
        inst.signal_value("click").unwrap() == Value::Bit(true)
            && inst.signal_value("x-mouse").unwrap() == Value::Float(0.0)
    });
    w.write_all(&records(&[(EV_KEY, 0x111, 0), (EV_REL, 0, 3)]))
        .unwrap();
    wait("counting again", || {
        inst.signal_value("x-mouse").unwrap() == Value::Float(3.0)
    });
    run(&host, "unload.hal", "unloadusr hal_input\n");
    assert!(inst.component("hal_input").unwrap().is_none());

    // plasma-5i20.hal: `-W` is hal_input's argument there (a subset
    // option naming no feature, overridden by -KRAL); loadusr does not
    // wait.
    run(
        &host,
        "plasma-5i20.hal",
        "loadusr hal_input -W -KRAL Dual\n",
    );
    wait("the joypad's hal_input ready", || {
        inst.component("hal_input")
            .unwrap()
            .is_some_and(|c| c.ready)
    });
    for pin in [
        "btn-trigger",
        "btn-thumb2-not",
        "abs-x-position",
        "abs-hat0x-is-neg",
    ] {
        assert!(
            inst.pin(&format!("input.0.{pin}")).unwrap().is_some(),
            "{pin}"
        );
    }
    assert_eq!(
        inst.pin_value("input.0.abs-x-scale").unwrap(),
        Value::Float(127.5)
    );
    run(&host, "unload.hal", "unloadusr hal_input\n");

    drop(w);
    drop(inst);
    drop(host);
    std::fs::remove_dir_all(&dir).unwrap();
}
