//! `loadrt canservo backend=sim ...` in a HAL host with a running servo
//! thread: pins, params, enable, CSP, homing through the `home` pin, a
//! fault through the pins, the helper's diagnosis, parameter errors and
//! a failing load leaving nothing behind.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::sync::Arc;
use std::time::{Duration, Instant};

use hal_canservo::bus::SimBus;
use hal_canservo::sim::Injection;
use hal_canservo::MODULE;
use hal_core::{Host, HostConfig, MsgLevel, Value};

fn host(tag: &str) -> Host {
    let h = Host::create(HostConfig::for_tests(tag)).unwrap();
    h.rt_log().set_level(MsgLevel::Info);
    h
}

fn start(host: &Host) {
    host.create_thread("servo", 1_000_000, true, None).unwrap();
    host.addf("canservo.read", "servo", -1).unwrap();
    host.addf("canservo.write", "servo", -1).unwrap();
    host.start().unwrap();
}

fn pin(host: &Host, name: &str) -> Value {
    host.instance().pin_value(name).unwrap()
}

fn set(host: &Host, name: &str, v: Value) {
    host.instance().set_pin(name, v).unwrap();
}

fn float(host: &Host, name: &str) -> f64 {
    match pin(host, name) {
        Value::Float(f) => f,
        v => panic!("{name} is {v:?}"),
    }
}

/// Waits (up to 20 s of wall time) until `cond` holds.
fn wait(what: &str, mut cond: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(20);
    while !cond() {
        assert!(Instant::now() < end, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(2));
    }
}

fn sim_bus(host: &Host) -> Arc<SimBus> {
    hal_driver::sim::find::<SimBus>(host.instance().name(), "canservo")
        .expect("published simulated bus")
}

#[test]
fn pins_params_and_a_move() {
    let host = host("cs-move");
    host.loadrt(&MODULE, &["backend=sim", "nodes=3,5", "scale=1000,2000"])
        .unwrap();
    let pins: Vec<String> = host
        .instance()
        .pins()
        .unwrap()
        .into_iter()
        .map(|p| p.name)
        .collect();
    for p in [
        "canservo.0.enable",
        "canservo.0.position-cmd",
        "canservo.1.position-fb",
        "canservo.1.velocity-fb",
        "canservo.1.amp-fault",
        "canservo.1.fault-reset",
        "canservo.1.fault-code",
        "canservo.1.error-code",
        "canservo.1.state",
        "canservo.1.statusword",
        "canservo.1.status.operation-enabled",
        "canservo.1.status.mode-bit-13",
        "canservo.1.mode",
        "canservo.1.home",
        "canservo.1.home-complete",
        "canservo.bus-errors",
    ] {
        assert!(pins.contains(&p.to_string()), "{p} missing");
    }
    let inst = host.instance();
    assert_eq!(inst.param_value("canservo.1.node").unwrap(), Value::U32(5));
    assert_eq!(
        inst.param_value("canservo.1.serial-number").unwrap(),
        Value::U32(5)
    );
    assert_eq!(
        inst.param_value("canservo.1.vendor-id").unwrap(),
        Value::U32(0x0048_414C)
    );
    assert_eq!(
        inst.param_value("canservo.1.position-scale").unwrap(),
        Value::Float(2000.0)
    );
    start(&host);
    wait("switch on disabled", || {
        pin(&host, "canservo.0.state") == Value::S32(2)
    });
    assert_eq!(pin(&host, "canservo.0.mode"), Value::S32(8));
    set(&host, "canservo.0.enable", Value::Bit(true));
    wait("enabled", || {
        pin(&host, "canservo.0.enabled") == Value::Bit(true)
    });
    assert_eq!(
        pin(&host, "canservo.0.status.operation-enabled"),
        Value::Bit(true)
    );
    assert_eq!(pin(&host, "canservo.0.state"), Value::S32(5));
    set(&host, "canservo.0.position-cmd", Value::Float(0.5));
    wait("the move", || {
        (float(&host, "canservo.0.position-fb") - 0.5).abs() < 0.002
    });
    let counts = sim_bus(&host).with_drive(3, |d, _| d.position()).unwrap();
    assert!((counts - 500.0).abs() < 3.0, "{counts} counts");
    host.stop();
    host.unloadrt("canservo").unwrap();
    let bus = sim_bus_gone(&host);
    assert!(bus, "the simulated bus goes with the module");
}

fn sim_bus_gone(host: &Host) -> bool {
    hal_driver::sim::find::<SimBus>(host.instance().name(), "canservo").is_none()
}

#[test]
fn unload_quick_stops_and_disables() {
    let host = host("cs-unload");
    host.loadrt(&MODULE, &["backend=sim", "nodes=1"]).unwrap();
    let bus = sim_bus(&host);
    start(&host);
    set(&host, "canservo.0.enable", Value::Bit(true));
    wait("enabled", || {
        pin(&host, "canservo.0.enabled") == Value::Bit(true)
    });
    host.stop();
    host.unloadrt("canservo").unwrap();
    let state = bus.with_drive(1, |d, _| d.power_state()).unwrap();
    assert_eq!(state, hal_canservo::power::PowerState::SwitchOnDisabled);
}

/// A drive file that makes a drive hold in quick stop active once it has
/// stopped (option code 6), as many drives do: only disable voltage
/// takes its power stage off.
fn holding_drive_file(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("canservo-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("hold.sdo");
    std::fs::write(&file, "605A:00 i16 6\n").unwrap();
    file
}

/// Three holding drives, loaded, enabled and running.
fn three_enabled_holding_drives(host: &Host, tag: &str) -> Arc<SimBus> {
    let f = holding_drive_file(tag).display().to_string();
    host.loadrt(
        &MODULE,
        &[
            "backend=sim",
            "nodes=1,2,3",
            &format!("drive_file={f},{f},{f}"),
        ],
    )
    .unwrap();
    let bus = sim_bus(host);
    start(host);
    for d in 0..3 {
        set(host, &format!("canservo.{d}.enable"), Value::Bit(true));
    }
    wait("enabled", || {
        (0..3).all(|d| pin(host, &format!("canservo.{d}.enabled")) == Value::Bit(true))
    });
    bus
}

/// The log's text once it holds `needle` (the log's thread may lag a
/// moment behind), or after 5 s.
fn log_with(host: &Host, needle: &str) -> String {
    let end = Instant::now() + Duration::from_secs(5);
    loop {
        let text = host
            .rt_log()
            .history()
            .into_iter()
            .map(|(_, t)| t)
            .collect::<Vec<_>>()
            .join("\n");
        if text.contains(needle) || Instant::now() > end {
            return text;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn unload_disables_every_drive_through_a_full_transmit_queue() {
    let host = host("cs-txfull");
    let bus = three_enabled_holding_drives(&host, "txfull");
    host.stop();
    // Two frames in flight at most, each a millisecond on the wire: the
    // quick-stop rounds (three RPDOs and SYNC) no longer fit, and neither
    // do the disable-voltage rounds without waiting for room.
    bus.set_latency(1_000_000);
    bus.set_tx_limit(2);
    host.unloadrt("canservo").unwrap();
    for node in 1..=3 {
        let (state, cw) = bus
            .with_drive(node, |d, _| (d.power_state(), d.controlword()))
            .unwrap();
        assert_eq!(
            (state, cw),
            (hal_canservo::power::PowerState::SwitchOnDisabled, 0),
            "node {node}"
        );
    }
    let log = log_with(&host, "every drive confirmed disable voltage");
    assert!(
        log.contains("every drive confirmed disable voltage") && !log.contains("not confirmed"),
        "{log}"
    );
}

#[test]
fn a_drive_that_never_confirms_disable_voltage_is_named() {
    let host = host("cs-mute");
    let bus = three_enabled_holding_drives(&host, "mute");
    host.stop();
    bus.with_drive(2, |d, out| d.inject(Injection::Mute, out));
    let began = Instant::now();
    host.unloadrt("canservo").unwrap();
    let took = began.elapsed();
    assert!(took < Duration::from_secs(8), "unload took {took:?}");
    let log = log_with(&host, "canservo.1 (node 2): disable voltage not confirmed");
    assert!(
        log.contains(
            "canservo.1 (node 2): disable voltage not confirmed within 2.0 s \
             (it sent no statusword after it); the drive may still be powered"
        ),
        "{log}"
    );
    assert!(
        !log.contains("canservo.0 (node 1): disable voltage not"),
        "{log}"
    );
    assert!(
        !log.contains("canservo.2 (node 3): disable voltage not"),
        "{log}"
    );
}

#[test]
fn homing_through_the_home_pin() {
    let host = host("cs-home");
    let dir = std::env::temp_dir().join(format!("canservo-home-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("x.sdo");
    std::fs::write(
        &file,
        "6098:00 i8 19\n6099:01 u32 50000\n6099:02 u32 5000\n607C:00 i32 0\n",
    )
    .unwrap();
    host.loadrt(
        &MODULE,
        &[
            "backend=sim",
            "nodes=1",
            "scale=1000",
            "sim_home=2000",
            &format!("drive_file={}", file.display()),
        ],
    )
    .unwrap();
    start(&host);
    set(&host, "canservo.0.enable", Value::Bit(true));
    wait("enabled", || {
        pin(&host, "canservo.0.enabled") == Value::Bit(true)
    });
    set(&host, "canservo.0.home", Value::Bit(true));
    wait("homing", || {
        pin(&host, "canservo.0.homing") == Value::Bit(true)
    });
    wait("home cleared", || {
        pin(&host, "canservo.0.home") == Value::Bit(false)
    });
    assert_eq!(pin(&host, "canservo.0.home-complete"), Value::Bit(true));
    assert!(float(&host, "canservo.0.position-fb").abs() < 0.01);
    let motor = sim_bus(&host)
        .with_drive(1, |d, _| d.object(0x6064, 0))
        .unwrap();
    assert!(
        motor.abs() < 10,
        "the drive's own position is home: {motor}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_fault_shows_on_the_pins_and_in_the_log() {
    let host = host("cs-fault");
    host.loadrt(&MODULE, &["backend=sim", "nodes=2", "diag_ms=0"])
        .unwrap();
    start(&host);
    set(&host, "canservo.0.enable", Value::Bit(true));
    wait("enabled", || {
        pin(&host, "canservo.0.enabled") == Value::Bit(true)
    });
    sim_bus(&host).with_drive(2, |d, out| d.inject(Injection::OverCurrent, out));
    wait("amp-fault", || {
        pin(&host, "canservo.0.amp-fault") == Value::Bit(true)
    });
    assert_eq!(pin(&host, "canservo.0.fault-code"), Value::U32(6));
    assert_eq!(pin(&host, "canservo.0.error-code"), Value::U32(0x2310));
    wait("the helper's diagnosis", || {
        host.rt_log().history().iter().any(|(_, l)| {
            l.contains("canservo.0 (node 2): error register 0x03")
                && l.contains("newest 0x2310 (continuous over-current)")
        })
    });
    host.flush_rt_log();
    let log = host.rt_log().history();
    assert!(
        log.iter().any(|(_, l)| l == "canservo.0 (node 2): EMCY received: error code 0x2310 (continuous over-current); drive disabled"),
        "{log:?}"
    );
    wait("fault state", || {
        pin(&host, "canservo.0.state") == Value::S32(8)
    });
    set(&host, "canservo.0.fault-reset", Value::Bit(true));
    wait("reset", || {
        pin(&host, "canservo.0.amp-fault") == Value::Bit(false)
    });
    assert_eq!(
        pin(&host, "canservo.0.enabled"),
        Value::Bit(false),
        "enable must be re-asserted"
    );
}

#[test]
fn a_communication_fault_is_recovered_by_the_helper() {
    let host = host("cs-restart");
    host.loadrt(&MODULE, &["backend=sim", "nodes=4", "diag_ms=0"])
        .unwrap();
    start(&host);
    set(&host, "canservo.0.enable", Value::Bit(true));
    wait("enabled", || {
        pin(&host, "canservo.0.enabled") == Value::Bit(true)
    });
    // The drive reboots: it comes back pre-operational with its default
    // PDO mapping, which only a full start-up repairs.
    let bus = sim_bus(&host);
    bus.with_drive(4, |d, out| d.power_up(out));
    wait("amp-fault", || {
        pin(&host, "canservo.0.amp-fault") == Value::Bit(true)
    });
    assert_eq!(pin(&host, "canservo.0.fault-code"), Value::U32(5));
    set(&host, "canservo.0.enable", Value::Bit(false));
    set(&host, "canservo.0.fault-reset", Value::Bit(true));
    wait("brought up again", || {
        pin(&host, "canservo.0.amp-fault") == Value::Bit(false)
    });
    set(&host, "canservo.0.enable", Value::Bit(true));
    wait("enabled again", || {
        pin(&host, "canservo.0.enabled") == Value::Bit(true)
    });
    host.flush_rt_log();
    assert!(host
        .rt_log()
        .history()
        .iter()
        .any(|(_, l)| l == "canservo.0 (node 4): brought up again after the fault reset"));
}

#[test]
fn a_node_reset_from_the_bus_needs_one_fault_reset() {
    let host = host("cs-nmt");
    host.loadrt(&MODULE, &["backend=sim", "nodes=6", "diag_ms=0"])
        .unwrap();
    start(&host);
    set(&host, "canservo.0.enable", Value::Bit(true));
    wait("enabled", || {
        pin(&host, "canservo.0.enabled") == Value::Bit(true)
    });
    // Someone resets the node's communication: it leaves Operational,
    // and, being enabled, faults itself (0x6007) with EMCY 0x8130.
    sim_bus(&host).inject(hal_canservo::frame::Frame::new(0, &[0x82, 6]));
    wait("amp-fault", || {
        pin(&host, "canservo.0.amp-fault") == Value::Bit(true)
    });
    set(&host, "canservo.0.enable", Value::Bit(false));
    set(&host, "canservo.0.fault-reset", Value::Bit(true));
    // One reset edge: the node is brought up again, then its CiA 402
    // fault is reset.
    wait("recovered", || {
        pin(&host, "canservo.0.amp-fault") == Value::Bit(false)
    });
    assert_eq!(pin(&host, "canservo.0.state"), Value::S32(2));
    set(&host, "canservo.0.enable", Value::Bit(true));
    wait("enabled again", || {
        pin(&host, "canservo.0.enabled") == Value::Bit(true)
    });
}

#[test]
fn parameter_errors_and_failed_loads_leave_nothing() {
    let host = host("cs-bad");
    for (args, want) in [
        (
            vec!["backend=sim"],
            "canservo: parameter 'nodes': no drives given",
        ),
        (
            vec!["backend=sim", "nodes=1", "mode=xyz"],
            "item 0 \"xyz\": not csp, pv or csv",
        ),
        (
            vec!["iface=nocan7", "nodes=1"],
            "canservo: CAN interface 'nocan7': no such network interface",
        ),
    ] {
        let e = host.loadrt(&MODULE, &args).unwrap_err().to_string();
        assert!(e.contains(want), "{args:?}: {e}");
        assert!(
            host.loaded_components().is_empty(),
            "nothing loaded after {args:?}"
        );
        assert!(host.instance().pins().unwrap().is_empty());
    }
}

#[test]
fn the_sim_only_form_never_opens_a_socket() {
    let host = host("cs-simonly");
    // No such interface: MODULE would fail to open it.
    let args = ["iface=nocan7", "backend=socketcan", "nodes=2"];
    assert!(host.loadrt(&MODULE, &args).is_err());
    host.loadrt(&hal_canservo::hal::SIM_ONLY_MODULE, &args)
        .unwrap();
    assert_eq!(
        host.instance().param_value("canservo.0.node").unwrap(),
        Value::U32(2)
    );
    sim_bus(&host);
    host.unloadrt("canservo").unwrap();
    let e = host
        .loadrt(&hal_canservo::hal::SIM_ONLY_MODULE, &["nodes=0"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("canservo: parameter 'nodes'"), "{e}");
    assert!(host.loaded_components().is_empty());
}
