//! The driver on a real kernel CAN interface: `vcan0` inside the VM rig
//! (../shared/tools/vmrig), with the simulated drives as a separate
//! process (`canservo-sim`). One test binary, so the rig boots once;
//! `.ci/run` runs it there. Outside the rig (no vcan) it skips with a
//! message.
//!
//! Steps, on one bus and so in one test: a node missing at start-up is
//! named; start-up of two drives through `loadrt canservo iface=vcan0`;
//! power up, a CSP move, feedback, a fault injected on the bus (a node
//! reset), recovery through the helper; unload leaves the drives
//! disabled.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hal_canservo::MODULE;
use hal_core::{Host, HostConfig, MsgLevel, Value};

/// The CAN interface the rig made, if we are in it.
fn vcan() -> Option<String> {
    let iface = std::env::var("VMRIG_CAN_IF").unwrap_or_else(|_| "vcan0".into());
    if std::path::Path::new("/sys/class/net").join(&iface).exists() {
        Some(iface)
    } else {
        eprintln!(
            "SKIPPED: no CAN interface {iface} (run this binary through ../shared/tools/vmrig, \
             which makes vcan0, to test the SocketCAN path)"
        );
        None
    }
}

/// The simulated drives' process, killed when dropped.
struct SimProcess(Child);

impl SimProcess {
    fn start(iface: &str, nodes: &str) -> SimProcess {
        let mut child = Command::new(env!("CARGO_BIN_EXE_canservo-sim"))
            .args(["--iface", iface, "--nodes", nodes, "--home", "2000"])
            .stdout(Stdio::piped())
            .spawn()
            .expect("canservo-sim starts");
        let mut line = String::new();
        let out = child.stdout.take().expect("stdout");
        BufReader::new(out)
            .read_line(&mut line)
            .expect("its first line");
        assert!(line.starts_with("canservo-sim: "), "{line}");
        SimProcess(child)
    }
}

impl Drop for SimProcess {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn wait(what: &str, mut cond: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(60);
    while !cond() {
        assert!(Instant::now() < end, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The pins of drive `d` that tell what it is doing, for failures.
fn describe(host: &Host, d: usize) -> String {
    [
        "state",
        "statusword",
        "position-cmd",
        "position-fb",
        "amp-fault",
        "fault-code",
        "enabled",
        "mode",
    ]
    .iter()
    .map(|p| format!("{p}={:?}", pin(host, &format!("canservo.{d}.{p}"))))
    .collect::<Vec<_>>()
    .join(" ")
}

fn pin(host: &Host, name: &str) -> Value {
    host.instance().pin_value(name).unwrap()
}

fn float(host: &Host, name: &str) -> f64 {
    match pin(host, name) {
        Value::Float(f) => f,
        v => panic!("{name} is {v:?}"),
    }
}

/// Slow-machine settings: the rig emulates its CPU, so the thread runs
/// at 4 ms and every wait is generous.
fn args<'a>(iface: &'a str, nodes: &'a str) -> Vec<String> {
    vec![
        format!("iface={iface}"),
        format!("nodes={nodes}"),
        "scale=1000,1000".into(),
        "period_ns=4000000".into(),
        "sdo_timeout_ms=2000".into(),
        "boot_timeout_ms=3000".into(),
        "heartbeat_timeout_ms=2000".into(),
        "master_heartbeat_ms=300".into(),
        "tpdo_misses=50".into(),
        "diag_ms=500".into(),
    ]
}

// Long on purpose: one end-to-end scenario on one bus and drive process
// (a missing node, start-up, a CSP move, a reset node), each step needing
// the state the last one left.
#[test]
fn start_up_and_csp_over_vcan_with_a_separate_drive_process() {
    let Some(iface) = vcan() else { return };
    let _sim = SimProcess::start(&iface, "1,2");
    let host = Host::create(HostConfig::for_tests("canservo-vcan")).unwrap();
    host.rt_log().set_level(MsgLevel::Info);

    // Node 3 is not there.
    let mut a = args(&iface, "1,2,3");
    a.retain(|s| !s.starts_with("boot_timeout_ms"));
    a.push("boot_timeout_ms=500".into());
    let e = host.loadrt(&MODULE, &a).unwrap_err().to_string();
    assert!(
        e.contains("node 3 did not send a boot-up message within 500 ms"),
        "{e}"
    );
    assert!(host.loaded_components().is_empty());

    // Start-up of the two that are.
    host.loadrt(&MODULE, &args(&iface, "1,2")).unwrap();
    let inst = host.instance();
    assert_eq!(
        inst.param_value("canservo.1.serial-number").unwrap(),
        Value::U32(2)
    );
    assert_eq!(
        inst.param_value("canservo.0.product-code").unwrap(),
        Value::U32(0x402)
    );
    host.create_thread("servo", 4_000_000, true, None).unwrap();
    host.addf("canservo.read", "servo", -1).unwrap();
    host.addf("canservo.write", "servo", -1).unwrap();
    host.start().unwrap();
    // Both drives' first TPDOs: Switch on disabled, CSP, Operational.
    wait("switch on disabled, CSP, operational", || {
        (0..2).all(|d| {
            pin(&host, &format!("canservo.{d}.state")) == Value::S32(2)
                && pin(&host, &format!("canservo.{d}.mode")) == Value::S32(8)
                && pin(&host, &format!("canservo.{d}.nmt-state")) == Value::U32(5)
        })
    });

    // CSP: both drives follow a move.
    for d in 0..2 {
        inst.set_pin(&format!("canservo.{d}.enable"), Value::Bit(true))
            .unwrap();
    }
    let end = Instant::now() + Duration::from_secs(60);
    while pin(&host, "canservo.0.enabled") != Value::Bit(true)
        || pin(&host, "canservo.1.enabled") != Value::Bit(true)
    {
        assert!(
            Instant::now() < end,
            "the drives did not enable: {} / {} / {:?}",
            describe(&host, 0),
            describe(&host, 1),
            host.rt_log().history()
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    for step in 1..=50 {
        let p = f64::from(step) * 0.01;
        inst.set_pin("canservo.0.position-cmd", Value::Float(p))
            .unwrap();
        inst.set_pin("canservo.1.position-cmd", Value::Float(-p))
            .unwrap();
        std::thread::sleep(Duration::from_millis(8));
    }
    let end = Instant::now() + Duration::from_secs(60);
    while (float(&host, "canservo.0.position-fb") - 0.5).abs() > 0.003
        || (float(&host, "canservo.1.position-fb") + 0.5).abs() > 0.003
    {
        assert!(
            Instant::now() < end,
            "the moves did not arrive: {} / {} / {:?}",
            describe(&host, 0),
            describe(&host, 1),
            host.rt_log().history()
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    assert_eq!(pin(&host, "canservo.0.amp-fault"), Value::Bit(false));

    // A fault from the bus: someone resets node 2.
    let poke =
        hal_canservo::bus::SocketCanBus::open(&iface, &hal_canservo::bus::Filters::default())
            .unwrap();
    assert!(hal_canservo::bus::CanBus::send(
        &poke,
        &hal_canservo::frame::Frame::new(0, &[0x82, 2])
    ));
    wait("node 2 faulted", || {
        pin(&host, "canservo.1.amp-fault") == Value::Bit(true)
    });
    // The node's boot-up (left Operational) or its own EMCY 0x8130
    // (its reaction to leaving Operational while enabled), whichever the
    // master reads first.
    let code = pin(&host, "canservo.1.fault-code");
    assert!(code == Value::U32(5) || code == Value::U32(6), "{code:?}");
    assert_eq!(
        pin(&host, "canservo.0.amp-fault"),
        Value::Bit(false),
        "node 1 carries on"
    );
    inst.set_pin("canservo.1.enable", Value::Bit(false))
        .unwrap();
    inst.set_pin("canservo.1.fault-reset", Value::Bit(true))
        .unwrap();
    let end = Instant::now() + Duration::from_secs(60);
    while pin(&host, "canservo.1.amp-fault") != Value::Bit(false) {
        assert!(
            Instant::now() < end,
            "node 2 was not brought up again: {} / {:?}",
            describe(&host, 1),
            host.rt_log().history()
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let here = float(&host, "canservo.1.position-fb");
    inst.set_pin("canservo.1.position-cmd", Value::Float(here))
        .unwrap();
    inst.set_pin("canservo.1.enable", Value::Bit(true)).unwrap();
    wait("node 2 enabled again", || {
        pin(&host, "canservo.1.enabled") == Value::Bit(true)
    });

    host.stop();
    host.unloadrt("canservo").unwrap();
}
