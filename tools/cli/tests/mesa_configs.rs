//! LinuxCNC's own Mesa sample configurations, kept in
//! tests/linuxcnc-configs with only the simulator word added to their
//! `[HOSTMOT2]DRIVER` or `loadrt hm2_pci` line, run headless through
//! `linuxcnc` on the simulated cards: PLX cards whose FPGA is loaded from
//! `firmware=`, a 3x20, the EPP 7I43 (through its CPLD) and 7I90, the
//! Ethernet 7I93 and 7I96S (`hm2_eth sim=`, in process), and a Smithy
//! mill.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{root, Machine};

fn config(dir: &str, ini: &str) -> std::path::PathBuf {
    root().join("tests/linuxcnc-configs").join(dir).join(ini)
}

/// Runs one of LinuxCNC's hm2-servo or hm2-stepper samples, kept in
/// tests/linuxcnc-configs unchanged but for the simulator word on its
/// `[HOSTMOT2]DRIVER` line, and jogs joint 0 by `step`: the joint's
/// feedback, read back through the simulated card's encoders (servo) or
/// step generators (stepper), must land within `within` of it.
fn mesa_sample_follows_a_jog(dir: &str, ini: &str, step: f64, within: f64) -> Machine {
    let tag = format!("{dir}-{}", ini.trim_end_matches(".ini"));
    let m = Machine::start(&config(dir, ini), &tag);
    assert!(m.threads_run(), "{tag}: threads run\n{}", m.stderr());
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    assert_eq!(m.getp("motion.motion-enabled"), "TRUE", "{tag}");
    m.motion(&["jog-incr", "0", "0.5", &step.to_string()]);
    m.motion(&["-t", "30", "wait", "in-position"]);
    let fb: f64 = m.getp("joint.0.pos-fb").parse().unwrap();
    assert!(
        (fb - step).abs() < within,
        "{tag}: joint 0 follows the jog to {step}: {fb}\n{}",
        m.stderr()
    );
    m
}

/// LinuxCNC's hm2-servo sample for a 5i20 (its `firmware=hm2/5i20/SVST8_4.BIT`),
/// unchanged but for `sim=5i20` on the driver line: the simulated card's
/// FPGA is loaded through its simulated PLX bridge, and the three servo
/// loops close through its encoders and PWM generators.
#[test]
fn hm2_servo_5i20_runs_on_the_simulated_card() {
    let m = mesa_sample_follows_a_jog("hm2-servo", "5i20.ini", 0.1, 0.002);
    assert_eq!(m.getp("hm2_5i20.0.encoder.00.scale"), "81920");
    assert_eq!(m.getp("hm2_5i20.0.pwmgen.pwm_frequency"), "40000");
    m.stop();
}

/// The other cards of LinuxCNC's hm2-servo sample: each INI names its
/// card's firmware (a 5i23, a 4i65 and a 4i68 through their PLX bridges,
/// a 3x20's 1M-gate SV24, a 7i43-4's and a 7i43-2's SVST4_4 through the
/// CPLD over EPP, a 5i22-1's and a 5i22-1.5's SVST8_8, a 7I90 over EPP with its own
/// firmware), and the servo loops close on the simulated card the same
/// way.
#[test]
fn hm2_servo_samples_for_the_other_cards_close_their_loops() {
    for (ini, prefix) in [
        ("5i23.ini", "hm2_5i23.0"),
        ("4i65.ini", "hm2_4i65.0"),
        ("4i68.ini", "hm2_4i68.0"),
        ("3x20-small.ini", "hm2_3x20.0"),
        ("7i43-big.ini", "hm2_7i43.0"),
        ("7i43-small.ini", "hm2_7i43.0"),
        ("5i22-small.ini", "hm2_5i22.0"),
        ("5i22-big.ini", "hm2_5i22.0"),
        ("7i90.ini", "hm2_7i90.0"),
    ] {
        let m = mesa_sample_follows_a_jog("hm2-servo", ini, 0.1, 0.002);
        assert_eq!(
            m.getp(&format!("{prefix}.encoder.00.scale")),
            "81920",
            "{ini}"
        );
        m.stop();
    }
}

/// LinuxCNC's hm2-stepper sample for a 5i22-1.5 (its
/// `firmware=hm2/5i22-1.5/SVST8_8.BIT`), unchanged but for `sim=5i22-1.5`:
/// the step generators' feedback follows a jog, and the watchdog's
/// `has_bit` feeds the e-stop latch without tripping it.
#[test]
fn hm2_stepper_5i22_runs_on_the_simulated_card() {
    let m = mesa_sample_follows_a_jog("hm2-stepper", "5i22-big.ini", 0.2, 0.001);
    assert_eq!(m.getp("hm2_5i22.0.watchdog.has_bit"), "FALSE");
    m.stop();
}

/// The other cards of LinuxCNC's hm2-stepper sample: a 5i20, a 4i65, a
/// 5i22-1 (sim=5i22, the 1M-gate card), a 7i43-2 over EPP (sim=7i43-2,
/// loaded through its CPLD), a 7i90 over EPP, a 5i23, and a 7I90 on a
/// Raspberry Pi's SPI (hm2_rpspi sim=7i90, its hm2-stepper-rpspi.hal
/// passing spiclk_rate=); each one's step generators follow a jog.
#[test]
fn hm2_stepper_samples_for_the_other_cards_follow_a_jog() {
    for (ini, prefix) in [
        ("5i20.ini", "hm2_5i20.0"),
        ("4i65.ini", "hm2_4i65.0"),
        ("5i22-small.ini", "hm2_5i22.0"),
        ("5i22-big.ini", "hm2_5i22.0"),
        ("7i43-small.ini", "hm2_7i43.0"),
        ("7i90.ini", "hm2_7i90.0"),
        ("5i23.ini", "hm2_5i23.0"),
        ("7i90-rpi-spi.ini", "hm2_7i90.0"),
    ] {
        let m = mesa_sample_follows_a_jog("hm2-stepper", ini, 0.2, 0.001);
        assert_eq!(
            m.getp(&format!("{prefix}.watchdog.has_bit")),
            "FALSE",
            "{ini}"
        );
        m.stop();
    }
}

/// LinuxCNC's Ethernet servo samples (hm2-servo-eth.hal with `loadrt
/// hm2_eth board_ip=... config=...`), unchanged but for `sim=7i93` or
/// `sim=7i96s` on the DRIVER line: the board is simulated inside the HAL
/// process and reached through hm2_eth's LBP16 datagrams, and the three
/// servo loops close through its encoders and PWM generators.
#[test]
fn hm2_servo_ethernet_samples_close_their_loops() {
    for (ini, prefix) in [("7i93.ini", "hm2_7i93.0"), ("7i96s.ini", "hm2_7i96s.0")] {
        let m = mesa_sample_follows_a_jog("hm2-servo", ini, 0.1, 0.002);
        assert_eq!(
            m.getp(&format!("{prefix}.encoder.00.scale")),
            "81920",
            "{ini}"
        );
        assert_eq!(
            m.getp(&format!("{prefix}.packet-error-total")),
            "0",
            "{ini}"
        );
        m.stop();
    }
}

/// LinuxCNC's Ethernet stepper samples (hm2-stepper-eth.hal), unchanged
/// but for `sim=7i93` or `sim=7i96s`: the step generators' feedback
/// follows a jog and the watchdog feeds the e-stop latch untripped.
#[test]
fn hm2_stepper_ethernet_samples_follow_a_jog() {
    for (ini, prefix) in [("7i93.ini", "hm2_7i93.0"), ("7i96s.ini", "hm2_7i96s.0")] {
        let m = mesa_sample_follows_a_jog("hm2-stepper", ini, 0.2, 0.001);
        assert_eq!(
            m.getp(&format!("{prefix}.watchdog.has_bit")),
            "FALSE",
            "{ini}"
        );
        m.stop();
    }
}

/// LinuxCNC's Smithy 622 mill (`by_machine/smithy`: a 5i20 with
/// `firmware=hm2/5i20/SVST2_4_7I47.BIT`, raw GPIO for its panel),
/// unchanged but for `sim=5i20` on its `hm2_pci` line: it loads and its
/// threads run. Machine-on is not checked: its E-stop chain and limit
/// switches are inputs (gpio.037, gpio.024 to .034) that the simulated
/// card leaves undriven, where the real machine wires its switches.
#[test]
fn smithy_622_loads_and_runs_on_the_simulated_5i20() {
    let dir = "smithy-622";
    let m = Machine::start(&config(dir, "622.ini"), dir);
    assert!(m.threads_run(), "{dir}: threads run\n{}", m.stderr());
    assert_eq!(m.getp("hm2_5i20.0.stepgen.00.position-scale"), "63500");
    assert_eq!(m.getp("charge-pump.enable"), "FALSE");
    m.stop();
}

/// LinuxCNC's hm2-modbus sample for a 7I96S with a brushless DC motor
/// driver on its RS-485 port (`7i96s-modbus-bldc.ini`, from LinuxCNC's
/// master), unchanged but for `sim=7i96s` on the DRIVER line, in a scratch
/// copy where its `.mbccs` is compiled to the `.mbccb` the INI names, as
/// LinuxCNC's README for the sample asks. The steppers follow a jog while
/// hm2_modbus runs on the simulated card's PktUART; nothing answers on
/// the line, so the motor driver's read command counts failed exchanges
/// and the machine stays on.
#[test]
fn hm2_modbus_sample_runs_on_the_simulated_7i96s() {
    let s = machine::Scratch::new("hm2-modbus-bldc");
    let src = root().join("tests/linuxcnc-configs/hm2-modbus");
    for entry in std::fs::read_dir(&src).unwrap().flatten() {
        std::fs::copy(entry.path(), s.0.join(entry.file_name())).unwrap();
    }
    let source = std::fs::read_to_string(s.0.join("brushless-dc-motor-driver.mbccs")).unwrap();
    let (file, warnings) = hostmot2::modbus::mbccs::compile(&source).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    std::fs::write(
        s.0.join("brushless-dc-motor-driver.mbccb"),
        hostmot2::modbus::encode::encode(&file),
    )
    .unwrap();

    let m = Machine::start(&s.0.join("7i96s-modbus-bldc.ini"), "hm2-modbus-bldc");
    assert!(m.threads_run(), "threads run\n{}", m.stderr());
    // The sample's second HAL file scaled the pins and lifted the suspend.
    assert_eq!(m.getp("hm2_modbus.0.bldc.rtpwm.scale"), "0.1");
    assert_eq!(m.getp("hm2_modbus.0.suspend"), "FALSE");
    m.task_ok(&["estop-reset"]);
    m.task_ok(&["machine-on"]);
    m.motion(&["jog-incr", "0", "0.5", "0.2"]);
    m.motion(&["-t", "30", "wait", "in-position"]);
    let fb: f64 = m.getp("joint.0.pos-fb").parse().unwrap();
    assert!((fb - 0.2).abs() < 0.001, "joint 0 follows the jog: {fb}");

    // No device answers: the read command's exchanges time out.
    let began = std::time::Instant::now();
    let errors = loop {
        let n: u32 = m.getp("hm2_modbus.0.command.00.errors").parse().unwrap();
        if n > 0 || began.elapsed() > std::time::Duration::from_secs(20) {
            break n;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    };
    assert!(errors > 0, "the unanswered command counts its failures");
    assert_eq!(m.getp("motion.motion-enabled"), "TRUE");
    assert_eq!(m.getp("hm2_7i96s.0.packet-error-total"), "0");
    m.stop();
}
