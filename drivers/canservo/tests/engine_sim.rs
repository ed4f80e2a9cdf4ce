//! The cyclic engine against simulated drives on simulated time: power
//! states up and down, CSP following a trajectory, PV, drive-internal
//! homing, and every fault path raising the fault within one period and
//! leaving the drive disabled.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use hal_canservo::bus::Filter;
use hal_canservo::bus::SimBus;
use hal_canservo::drivefile::DriveFile;
use hal_canservo::engine::{faults, EngineConfig};
use hal_canservo::frame::Frame;
use hal_canservo::power::PowerState;
use hal_canservo::regs::{cw, err, obj};
use hal_canservo::rig::Rig;
use hal_canservo::sim::{Injection, SimDriveConfig};
use hal_canservo::startup::{Mode, NodePlan, StartupConfig};
use hal_driver::plant::Switch;

const SCALE: f64 = 1000.0; // counts per mm

fn rig(nodes: &[u8], mode: Mode) -> Rig {
    let mut r = Rig::new(nodes, mode).unwrap();
    for i in &mut r.inputs {
        i.scale = SCALE;
    }
    r
}

fn power(r: &Rig, node: u8) -> PowerState {
    r.drive(node, |d, _| d.power_state())
}

/// Enables drive 0 and runs until it is in Operation enabled.
fn enable(r: &mut Rig) {
    r.inputs[0].enable = true;
    r.run_until(20, |r| r.status(0).enabled)
        .expect("drive enables");
}

#[test]
fn the_enable_pin_walks_the_power_states_up_and_down() {
    let mut r = rig(&[1], Mode::Csp);
    r.cycles(3);
    assert_eq!(power(&r, 1), PowerState::SwitchOnDisabled);
    assert_eq!(r.status(0).state, Some(PowerState::SwitchOnDisabled));
    r.inputs[0].enable = true;
    let mut seen = vec![power(&r, 1)];
    for _ in 0..20 {
        r.cycle();
        let p = power(&r, 1);
        if seen.last() != Some(&p) {
            seen.push(p);
        }
    }
    assert_eq!(
        seen,
        vec![
            PowerState::SwitchOnDisabled,
            PowerState::ReadyToSwitchOn,
            PowerState::SwitchedOn,
            PowerState::OperationEnabled
        ]
    );
    let st = r.status(0);
    assert!(
        st.enabled
            && !st.amp_fault
            && st.mode_display == 8
            && st.state == Some(PowerState::OperationEnabled)
    );
    assert_eq!(st.statusword & 0x6F, 0x27);
    r.inputs[0].enable = false;
    r.cycles(3);
    assert_eq!(
        power(&r, 1),
        PowerState::SwitchOnDisabled,
        "disable voltage"
    );
    assert_eq!(r.engine.last_command(0).0, cw::DISABLE_VOLTAGE);
    assert!(!r.status(0).enabled);
}

#[test]
fn csp_follows_a_commanded_trajectory() {
    let mut r = rig(&[1, 2], Mode::Csp);
    r.inputs[1].enable = true;
    enable(&mut r);
    r.run_until(20, |r| r.status(1).enabled).unwrap();
    // A trapezoid to 20 mm at 50 mm/s, 500 mm/s², on drive 0; drive 1
    // holds still.
    let (v, a, dt) = (50.0, 500.0, 1e-3);
    let mut pos = 0.0f64;
    let mut vel = 0.0f64;
    let mut worst = 0.0f64;
    for _ in 0..1000 {
        let left = 20.0 - pos;
        let stop = vel * vel / (2.0 * a);
        vel = if left <= stop + 1e-9 {
            (vel - a * dt).max(0.0)
        } else {
            (vel + a * dt).min(v)
        };
        pos = (pos + vel * dt).min(20.0);
        r.inputs[0].position_cmd = pos;
        r.cycle();
        let lag = (r.status(0).position_fb - pos).abs();
        worst = worst.max(lag);
    }
    r.cycles(200);
    let st = r.status(0);
    assert!(
        (st.position_fb - 20.0).abs() < 0.005,
        "reached {}",
        st.position_fb
    );
    assert!(worst < 0.2, "lag stays small: {worst} mm");
    assert!(st.velocity_fb.abs() < 0.5);
    assert!(
        r.status(1).position_fb.abs() < 0.005,
        "the other drive held"
    );
    assert!(!st.amp_fault && !r.status(1).amp_fault);
}

#[test]
fn the_target_starts_at_the_actual_position_and_waits_for_the_command() {
    let mut r = rig(&[1], Mode::Csp);
    r.drive(1, |d, _| d.set_motor_position(5000.0));
    r.inputs[0].position_cmd = 0.0; // far from the actual 5 mm
    enable(&mut r);
    r.cycles(50);
    assert!(
        (r.status(0).position_fb - 5.0).abs() < 0.01,
        "held at 5 mm, no jump"
    );
    assert_eq!(r.engine.last_command(0).1, 5000);
    r.inputs[0].position_cmd = 5.002;
    r.cycles(50);
    assert!(
        (r.status(0).position_fb - 5.002).abs() < 0.002,
        "follows once in step"
    );
}

#[test]
fn pv_runs_at_the_commanded_velocity() {
    let mut r = rig(&[3], Mode::Pv);
    enable(&mut r);
    r.inputs[0].velocity_cmd = 40.0; // mm/s
    r.cycles(300);
    let st = r.status(0);
    assert_eq!(st.mode_display, 3);
    assert!((st.velocity_fb - 40.0).abs() < 0.5, "{}", st.velocity_fb);
    assert!(st.statusword & 0x0400 != 0, "target reached");
    let p0 = st.position_fb;
    r.cycles(100);
    assert!(
        (r.status(0).position_fb - p0 - 4.0).abs() < 0.1,
        "moved 4 mm in 0.1 s"
    );
    r.inputs[0].velocity_cmd = 0.0;
    r.cycles(300);
    assert!(r.status(0).velocity_fb.abs() < 0.05);
    assert!(r.status(0).statusword & 0x1000 != 0, "speed zero");
}

#[test]
fn csv_follows_velocity_commands() {
    let mut r = rig(&[4], Mode::Csv);
    enable(&mut r);
    r.inputs[0].velocity_cmd = -25.0;
    r.cycles(200);
    assert_eq!(r.status(0).mode_display, 9);
    assert!(
        (r.status(0).velocity_fb + 25.0).abs() < 0.5,
        "{}",
        r.status(0).velocity_fb
    );
}

#[test]
fn drive_internal_homing_echoes_the_command_and_hands_over_cleanly() {
    let bus = SimBus::new();
    let mut cfg = SimDriveConfig::new(1);
    // The home switch is closed from motor position 30 mm up.
    cfg.home_switch = Some(Switch::at_or_above(30_000.0));
    bus.add_drive(cfg);
    let file = DriveFile::parse(
        std::path::Path::new("x.sdo"),
        "6098:00 i8 19\n6099:01 u32 40000\n6099:02 u32 4000\n607C:00 i32 -2000\n",
    )
    .unwrap();
    let plans = vec![NodePlan {
        node: 1,
        mode: Mode::Csp,
        file: Some(file),
    }];
    let mut r = Rig::with(
        bus,
        plans,
        StartupConfig::default(),
        EngineConfig::default(),
    )
    .unwrap();
    r.inputs[0].scale = SCALE;
    r.drive(1, |d, _| d.set_motor_position(10_000.0));
    r.inputs[0].position_cmd = 10.0;
    enable(&mut r);
    r.inputs[0].home = true;
    let mut echoed = 0;
    let mut moved = false;
    let n = r
        .run_until(3000, |r| {
            let st = r.status(0);
            if st.homing && st.position_fb == r.inputs[0].position_cmd {
                echoed += 1;
            }
            !r.inputs[0].home
        })
        .expect("homing completes and clears home");
    assert!(n > 100, "the drive searched for the switch ({n} cycles)");
    assert!(echoed > 100, "position-fb echoed the command while homing");
    let st = r.status(0);
    assert!(st.home_complete && !st.amp_fault);
    // Home is the switch edge at 30 mm, which the drive now calls -2 mm.
    assert!((st.position_fb + 2.0).abs() < 0.05, "{}", st.position_fb);
    // The command still says 10; the drive holds until it is in step.
    r.cycles(20);
    assert!((r.status(0).position_fb + 2.0).abs() < 0.05);
    assert_eq!(r.status(0).mode_display, 8, "back in CSP");
    r.inputs[0].position_cmd = r.status(0).position_fb;
    r.cycles(5);
    r.inputs[0].position_cmd = 0.0;
    r.run_until(500, |r| {
        moved = (r.status(0).position_fb).abs() < 0.01;
        moved
    });
    assert!(moved, "follows the command again after homing");
}

/// What every fault test checks after the cause: the fault in the
/// period it became visible, quick stop first, then disabled.
fn assert_tripped_and_disabled(r: &mut Rig, node: u8, code: u32, reason: &str) {
    let st = r.status(0);
    assert!(st.amp_fault, "amp-fault raised");
    assert_eq!(st.fault_code, code, "fault code");
    let lines = r.log_lines();
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with(&format!("canservo.0 (node {node}): ")) && l.contains(reason)),
        "log says node and cause: {lines:?}"
    );
    let first = r.engine.last_command(0).0;
    assert!(
        first == cw::QUICK_STOP_CMD || first == cw::DISABLE_VOLTAGE,
        "quick stop or disable voltage: {first:#x}"
    );
    // Quick stop, then disable voltage at the latest after quick_stop_ns
    // (1 s), however little the master hears from the drive.
    r.cycles(1100);
    let p = power(r, node);
    assert!(
        matches!(p, PowerState::SwitchOnDisabled | PowerState::Fault),
        "the drive ends disabled: {p:?}"
    );
    assert!(r.status(0).amp_fault, "the latch holds until reset");
    assert_eq!(r.engine.last_command(0).0, cw::DISABLE_VOLTAGE);
}

fn moving_rig(mode: Mode) -> Rig {
    let mut r = rig(&[7], mode);
    enable(&mut r);
    r.inputs[0].position_cmd = 0.0;
    r.cycles(5);
    r
}

#[test]
fn emcy_faults_in_one_period() {
    let mut r = moving_rig(Mode::Csp);
    r.drive(7, |d, out| d.inject(Injection::OverCurrent, out));
    r.cycle();
    assert_eq!(r.status(0).error_code, 0x2310);
    assert_tripped_and_disabled(
        &mut r,
        7,
        faults::EMCY.code,
        "EMCY received: error code 0x2310 (continuous over-current)",
    );
}

#[test]
fn a_drive_in_fault_without_emcy_faults_in_one_period() {
    let mut r = moving_rig(Mode::Csp);
    // EMCY switched off in the drive: only the statusword tells.
    r.drive(7, |d, _| d.set_object(obj::COB_ID_EMCY, 0, 0x8000_0087));
    r.drive(7, |d, out| d.inject(Injection::OverCurrent, out));
    r.cycle(); // the TPDO sampled at the last SYNC still shows enabled
    r.cycle();
    assert_tripped_and_disabled(
        &mut r,
        7,
        faults::DRIVE_FAULT.code,
        "drive in Fault: error code 0x2310",
    );
}

#[test]
fn a_following_error_in_the_drive_faults() {
    let mut r = moving_rig(Mode::Csp);
    r.drive(7, |d, out| d.inject(Injection::FollowingError, out));
    r.inputs[0].position_cmd = 0.5;
    let n = r.run_until(200, |r| r.status(0).amp_fault).expect("faults");
    assert!(n < 100, "{n}");
    assert_eq!(r.status(0).error_code, 0x8611);
    assert_tripped_and_disabled(&mut r, 7, faults::EMCY.code, "0x8611 (following error)");
}

#[test]
fn a_missed_heartbeat_faults_within_a_period_of_the_timeout() {
    let mut r = moving_rig(Mode::Csp);
    r.drive(7, |d, out| d.inject(Injection::HeartbeatLoss, out));
    let n = r
        .run_until(1000, |r| r.status(0).amp_fault)
        .expect("faults");
    // Heartbeat every 100 ms, timeout 300 ms: the last one came at most
    // 100 ms before the loss, so the fault comes 200 to 300 ms after it,
    // in the period the timeout passes.
    assert!((200..=301).contains(&n), "{n} periods");
    assert_tripped_and_disabled(&mut r, 7, faults::HEARTBEAT.code, "heartbeat missed");
}

#[test]
fn missing_tpdos_fault_after_the_configured_count() {
    let mut r = moving_rig(Mode::Csp);
    r.bus.lose(Filter::exact(0x187), 1000);
    r.cycle();
    r.cycle();
    assert!(!r.status(0).amp_fault, "two misses are tolerated");
    r.cycle();
    assert_tripped_and_disabled(
        &mut r,
        7,
        faults::TPDO_MISSING.code,
        "TPDO missing after SYNC",
    );
}

#[test]
fn bus_off_faults_every_drive_in_one_period() {
    let mut r = rig(&[1, 2], Mode::Csp);
    r.inputs[1].enable = true;
    enable(&mut r);
    r.run_until(20, |r| r.status(1).enabled).unwrap();
    r.bus.set_bus_off(true);
    r.cycle();
    assert!(r.status(0).amp_fault && r.status(1).amp_fault);
    assert_eq!(r.status(1).fault_code, faults::BUS_OFF.code);
    let lines = r.log_lines();
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("canservo.1 (node 2): CAN bus off")),
        "{lines:?}"
    );
    // The bus comes back; the drives lost their master's SYNC and
    // heartbeat meanwhile and stopped themselves.
    r.bus.set_bus_off(false);
    r.cycles(400);
    for n in [1, 2] {
        assert!(matches!(
            power(&r, n),
            PowerState::SwitchOnDisabled | PowerState::Fault
        ));
    }
}

#[test]
fn controller_errors_and_missing_acks_fault_in_one_period() {
    for (frame, code) in [
        (
            Frame::error(err::CRTL, [0, err::CRTL_RX_OVERFLOW, 0, 0, 0, 0, 0, 0]),
            faults::CONTROLLER.code,
        ),
        (
            Frame::error(err::CRTL, [0, err::CRTL_TX_PASSIVE, 0, 0, 0, 0, 0, 0]),
            faults::CONTROLLER.code,
        ),
        (
            Frame::error(err::TX_TIMEOUT, [0; 8]),
            faults::CONTROLLER.code,
        ),
        (Frame::error(err::ACK, [0; 8]), faults::NO_ACK.code),
    ] {
        let mut r = moving_rig(Mode::Csp);
        r.bus.inject_error(Frame::error(
            err::CRTL,
            [0, err::CRTL_RX_WARNING, 0, 0, 0, 0, 0, 0],
        ));
        r.cycle();
        assert!(!r.status(0).amp_fault, "a warning level alone is no fault");
        r.bus.inject_error(frame);
        r.cycle();
        assert_eq!(r.status(0).fault_code, code, "{frame}");
        assert_tripped_and_disabled(&mut r, 7, code, "CAN");
    }
}

#[test]
fn a_rebooted_drive_faults_in_one_period() {
    let mut r = moving_rig(Mode::Csp);
    // The drive loses power for a moment: its boot-up says it left
    // Operational.
    r.drive(7, |d, out| d.power_up(out));
    r.cycle();
    assert!(r.status(0).amp_fault);
    assert_eq!(r.status(0).fault_code, faults::NMT_STATE.code);
    r.cycles(10);
    assert_ne!(power(&r, 7), PowerState::OperationEnabled);
}

#[test]
fn fault_reset_recovers_only_with_an_explicit_edge_and_a_new_enable() {
    let mut r = moving_rig(Mode::Csp);
    r.drive(7, |d, out| d.inject(Injection::OverCurrent, out));
    r.cycles(50);
    assert_eq!(power(&r, 7), PowerState::Fault);
    // Holding enable does nothing.
    r.cycles(50);
    assert!(r.status(0).amp_fault);
    r.inputs[0].fault_reset = true;
    r.run_until(20, |r| !r.status(0).amp_fault)
        .expect("reset clears the fault");
    r.inputs[0].fault_reset = false;
    r.cycles(5);
    assert_eq!(
        power(&r, 7),
        PowerState::SwitchOnDisabled,
        "not re-enabled while enable stayed high"
    );
    r.inputs[0].enable = false;
    r.cycle();
    enable(&mut r);
    assert_eq!(power(&r, 7), PowerState::OperationEnabled);
    // A persisting cause keeps the drive in Fault.
    r.drive(7, |d, out| d.inject(Injection::UnderVoltage, out));
    r.cycles(50);
    r.inputs[0].fault_reset = true;
    r.cycles(100);
    assert!(r.status(0).amp_fault && power(&r, 7) == PowerState::Fault);
}

#[test]
fn a_communication_fault_resets_without_a_helper_and_supervision_restarts() {
    let mut r = moving_rig(Mode::Csp);
    r.bus.lose(Filter::exact(0x187), 5);
    r.cycles(5);
    assert_eq!(r.status(0).fault_code, faults::TPDO_MISSING.code);
    r.inputs[0].fault_reset = true;
    r.cycles(2);
    assert!(!r.status(0).amp_fault);
    r.cycles(20);
    assert!(!r.status(0).amp_fault, "TPDOs flow again");
}

#[test]
fn a_wrong_thread_period_faults() {
    let mut r = Rig::with(
        SimBus::with_drives(&[1]),
        vec![NodePlan {
            node: 1,
            mode: Mode::Csp,
            file: None,
        }],
        StartupConfig::default(),
        EngineConfig {
            period_ns: 1_000_000,
            ..EngineConfig::default()
        },
    )
    .unwrap();
    r.cycles(3);
    assert_eq!(r.status(0).fault_code, 0);
    r.period_ns = 2_000_000;
    r.cycles(2);
    assert_eq!(r.status(0).fault_code, faults::PERIOD.code);
}

#[test]
fn an_unplugged_bus_faults_for_missing_acks_in_one_period() {
    let mut r = moving_rig(Mode::Csp);
    r.drive(7, |d, _| d.set_present(false));
    r.cycle(); // this write's frames find nobody to acknowledge them
    r.cycle();
    assert_eq!(r.status(0).fault_code, faults::NO_ACK.code);
    assert!(r
        .log_lines()
        .iter()
        .any(|l| l.contains("no acknowledge on the CAN bus")));
}

#[test]
fn frames_that_cannot_be_sent_fault_after_three_periods() {
    let mut r = moving_rig(Mode::Csp);
    // A transmit queue that never drains: everything on the wire is held
    // back for an hour, and the wire is full.
    r.bus.set_latency(3_600_000_000_000);
    for _ in 0..16_384 {
        r.bus.inject(Frame::new(0x7FF, &[]));
    }
    r.cycles(3);
    assert!(!r.status(0).amp_fault, "seen at the third write");
    r.cycle();
    assert_eq!(r.status(0).fault_code, faults::TX_FAILED.code);
    assert!(r.engine.bus_errors() >= 6);
}

#[test]
fn latency_below_a_period_is_harmless_and_above_it_faults() {
    let mut r = moving_rig(Mode::Csp);
    r.bus.set_latency(400_000);
    r.cycles(50);
    assert!(
        !r.status(0).amp_fault,
        "TPDOs 0.4 ms late still come before the next read"
    );
    r.bus.set_latency(4_000_000);
    let n = r.run_until(20, |r| r.status(0).amp_fault).expect("faults");
    assert_eq!(n, 3, "three periods without TPDOs");
    assert_eq!(r.status(0).fault_code, faults::TPDO_MISSING.code);
}
