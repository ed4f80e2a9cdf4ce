//! LinuxCNC's panelui-demo sim configuration run unchanged (from a copy)
//! through `linuxcnc`: sim_matrix_kb's keycodes reach panelui through a
//! sampler; a key pressed on sim_matrix_kb's button pins changes
//! panelui's pins (a radio group that sets the MPG jog scale) and sends
//! task commands (flood coolant, the spindle, a jog). A panel file
//! naming an unknown command stops the start, naming its line.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use std::path::Path;
use std::time::{Duration, Instant};

use machine::{Machine, Scratch};

/// Copies the directory `from` into `to` (files only: the demo has no
/// subdirectories).
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap().flatten() {
        if entry.file_type().unwrap().is_file() {
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
}

fn demo_copy(tag: &str) -> Scratch {
    let src = Path::new(env!("HAL_PEER_SAMPLE_CONFIGS")).join("sim/axis/panelui-demo");
    let s = Scratch::new(tag);
    copy_dir(&src, &s.0);
    s
}

/// Waits (up to 10 s) for `pin` to read `want`, failing with the
/// machine's stderr.
fn wait(m: &Machine, pin: &str, want: &str) {
    let got = m.wait_getp(pin, want);
    assert_eq!(got, want, "{pin}\n{}", m.stderr());
}

/// Reads `pin` as a number until it is within 1e-9 of `want` or 10 s
/// pass, failing with the machine's stderr.
fn wait_num(m: &Machine, pin: &str, want: f64) {
    let end = Instant::now() + Duration::from_secs(10);
    loop {
        let v: f64 = m.getp(pin).parse().unwrap();
        if (v - want).abs() < 1e-9 {
            return;
        }
        assert!(
            Instant::now() < end,
            "{pin} = {v}, not {want}\n{}",
            m.stderr()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// A press and release of a sim_matrix_kb button: through its signal when
/// the HAL files net it, else its pin.
fn tap(m: &Machine, target: &str) {
    let cmd = if target.contains('.') { "setp" } else { "sets" };
    m.halcmd(&[cmd, target, "1"]);
    // sim_matrix_kb reports one change a servo cycle; the sampler keeps
    // every cycle: the release comes well after.
    std::thread::sleep(Duration::from_millis(100));
    m.halcmd(&[cmd, target, "0"]);
}

#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_panelui_demo_keys_drive_pins_and_task() {
    let s = demo_copy("ppanelui");
    let m = Machine::start(&s.0.join("panelui-demo.ini"), "ppanelui");
    // At start: each radio group's default chosen, the toggle's DEFAULT.
    wait(&m, "panelui.mpg_small-state", "TRUE");
    wait_num(&m, "panelui.mpg_scale", 0.0001);
    wait_num(&m, "panelui.mpg_scale-not", -0.0001);
    wait_num(&m, "joint.0.jog-scale", 0.0001);
    wait(&m, "panelui.select_x", "TRUE");
    wait(&m, "panelui.axis_select", "1");
    wait(&m, "panelui.tool_change", "TRUE");
    // No HOME_SEQUENCE: nothing here needs homing.
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);

    // R7C2 (mpg_med), netted to sim-mpg-m by custom_postgui.hal: the
    // group's output follows, and with it the jog scales it is netted to.
    tap(&m, "sim-mpg-m");
    wait(&m, "panelui.mpg_med-state", "TRUE");
    wait(&m, "panelui.mpg_small-state", "FALSE");
    wait_num(&m, "panelui.mpg_scale", 0.001);
    wait_num(&m, "joint.0.jog-scale", 0.001);
    wait_num(&m, "joint.1.jog-scale", -0.001);
    // R4C2 (select_z): the S32 group and the BIT pins.
    tap(&m, "sim-sel-z");
    wait(&m, "panelui.axis_select", "2");
    wait(&m, "panelui.axis_select-not", "-2");
    wait(&m, "panelui.select_z", "TRUE");
    wait(&m, "panelui.select_x", "FALSE");

    // R0C4 (flood), a toggle whose pin no HAL file nets: flood_on, then
    // flood_off on the next press.
    tap(&m, "sim-matrix-kb.0.button.c04.r00");
    wait(&m, "panelui.flood-state", "TRUE");
    wait(&m, "iocontrol.0.coolant-flood", "TRUE");
    tap(&m, "sim-matrix-kb.0.button.c04.r00");
    wait(&m, "panelui.flood-state", "FALSE");
    wait(&m, "iocontrol.0.coolant-flood", "FALSE");

    // R3C3 (spindle_fwd: SPINDLE_FORWARD_ADJUST, 200): starts the spindle
    // forward at 200 rpm; pressed again it goes faster.
    tap(&m, "sim-spindle-fwd");
    wait(&m, "spindle.0.forward", "TRUE");
    wait_num(&m, "spindle.0.speed-out", 200.0);
    tap(&m, "sim-spindle-fwd");
    let end = Instant::now() + Duration::from_secs(10);
    while m.getp("spindle.0.speed-out").parse::<f64>().unwrap() <= 200.0 {
        assert!(Instant::now() < end, "spindle faster\n{}", m.stderr());
        std::thread::sleep(Duration::from_millis(20));
    }
    // R1C3 (spindle_stop).
    tap(&m, "sim-spindle-stop");
    wait(&m, "spindle.0.on", "FALSE");

    // R3C2 (jog_z+, momentary: continuous_jog, 2, 1 while held): in joint
    // mode Z is joint 1 of COORDINATES = X Z; it jogs at mpg_med's
    // set_linear_jog_velocity (10 per minute) and stops on release.
    m.halcmd(&["sets", "sim-jog-z-pos", "1"]);
    let end = Instant::now() + Duration::from_secs(10);
    while m.getp("joint.1.pos-cmd").parse::<f64>().unwrap() < 0.02 {
        assert!(Instant::now() < end, "Z jogs\n{}", m.stderr());
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(m.getp("joint.0.pos-cmd").parse::<f64>().unwrap(), 0.0);
    m.halcmd(&["sets", "sim-jog-z-pos", "0"]);
    let end = Instant::now() + Duration::from_secs(10);
    let mut last = f64::NAN;
    loop {
        std::thread::sleep(Duration::from_millis(200));
        let z: f64 = m.getp("joint.1.pos-cmd").parse().unwrap();
        if z == last {
            break;
        }
        assert!(Instant::now() < end, "Z stops\n{}", m.stderr());
        last = z;
    }
    m.stop();
}

#[test]
#[cfg_attr(hal_no_peer_configs, ignore = "needs LinuxCNC's sample configurations")]
fn peer_panelui_demo_with_an_unknown_command_does_not_start() {
    let s = demo_copy("ppanelbad");
    let panel = s.0.join("_panelui.ini");
    let text = std::fs::read_to_string(&panel).unwrap();
    let line = text
        .lines()
        .position(|l| l.contains("TRUE_COMMAND = flood_on, NONE"))
        .unwrap()
        + 1;
    std::fs::write(
        &panel,
        text.replace(
            "TRUE_COMMAND = flood_on, NONE",
            "TRUE_COMMAND = flood_onn, NONE",
        ),
    )
    .unwrap();
    let m = Machine::spawn(&s.0.join("panelui-demo.ini"), "ppanelbad", &[]);
    let (status, stderr) = m.wait_exit();
    assert!(!status.success(), "{stderr}");
    let want = format!("_panelui.ini:{line}: TRUE_COMMAND: unknown command \"flood_onn\"");
    assert!(stderr.contains(&want), "{want}\n{stderr}");
}
