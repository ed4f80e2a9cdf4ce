//! The driver on a real kernel CAN interface: `vcan0` inside the VM rig
//! (../shared/tools/vmrig), with the simulated drives as a separate
//! process (`canservo-sim`). One test binary, so the rig boots once;
//! `scripts/test-all` runs it there with `--include-ignored
//! --test-threads=1` (the tests share vcan0). Elsewhere the tests are
//! reported as ignored, with the reason; run on purpose without a vcan0
//! they fail.
//!
//! Steps of the first, on one bus and so in one test: a node missing at
//! start-up is named; start-up of two drives through `loadrt canservo
//! iface=vcan0`; power up, a CSP move, feedback, a fault injected on the
//! bus (a node reset), recovery through the helper; unload leaves the
//! drives disabled. The second unloads three enabled drives through a
//! full transmit queue to a deliberately slow receiver: each drive must
//! end with disable voltage received.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hal_canservo::MODULE;
use hal_core::{Host, HostConfig, MsgLevel, Value};

/// The CAN interface the rig made; a test asked to run without it fails.
fn vcan() -> String {
    let iface = std::env::var("VMRIG_CAN_IF").unwrap_or_else(|_| "vcan0".into());
    assert!(
        std::path::Path::new("/sys/class/net").join(&iface).exists(),
        "no CAN interface {iface}: run this binary through ../shared/tools/vmrig, which makes vcan0"
    );
    iface
}

/// The simulated drives' process, killed when dropped.
struct SimProcess {
    child: Child,
    out: BufReader<std::process::ChildStdout>,
}

impl SimProcess {
    fn start(iface: &str, nodes: &str, extra: &[&str]) -> SimProcess {
        let mut child = Command::new(env!("CARGO_BIN_EXE_canservo-sim"))
            .args(["--iface", iface, "--nodes", nodes, "--home", "2000"])
            .args(extra)
            .stdout(Stdio::piped())
            .spawn()
            .expect("canservo-sim starts");
        let mut line = String::new();
        let mut out = BufReader::new(child.stdout.take().expect("stdout"));
        out.read_line(&mut line).expect("its first line");
        assert!(line.starts_with("canservo-sim: "), "{line}");
        SimProcess { child, out }
    }

    /// Makes it a slow receiver (its `--read-delay-us` starts).
    fn slow_down(&self) {
        let pid = nix::unistd::Pid::from_raw(self.child.id() as i32);
        nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGUSR1).unwrap();
    }

    /// Stops it with SIGTERM; what it printed on the way out (each
    /// drive's last controlword and state).
    fn stop(mut self) -> String {
        let pid = nix::unistd::Pid::from_raw(self.child.id() as i32);
        nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGTERM).unwrap();
        let mut rest = String::new();
        std::io::Read::read_to_string(&mut self.out, &mut rest).unwrap();
        rest
    }
}

impl Drop for SimProcess {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
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
        // Generous: the rig emulates its CPU and shares a loaded host.
        "heartbeat_timeout_ms=5000".into(),
        "master_heartbeat_ms=300".into(),
        "tpdo_misses=50".into(),
        "diag_ms=500".into(),
    ]
}

// Long on purpose: one end-to-end scenario on one bus and drive process
// (a missing node, start-up, a CSP move, a reset node), each step needing
// the state the last one left.
#[test]
#[ignore = "needs vcan0: runs in the VM rig (../shared/tools/vmrig), as scripts/test-all does"]
fn start_up_and_csp_over_vcan_with_a_separate_drive_process() {
    let iface = vcan();
    let _sim = SimProcess::start(&iface, "1,2", &[]);
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
    // Once in a CI run (under TCG) node 2 did not come back within the
    // wait: say where it stands if that happens again.
    let end = Instant::now() + Duration::from_secs(60);
    while pin(&host, "canservo.1.enabled") != Value::Bit(true) {
        assert!(
            Instant::now() < end,
            "node 2 was not enabled again: {} / {:?}",
            describe(&host, 1),
            host.rt_log().history()
        );
        std::thread::sleep(Duration::from_millis(5));
    }

    host.stop();
    host.unloadrt("canservo").unwrap();
}

/// Runs `tc ARGS`; the rig has iproute2 (in /sbin for some users).
fn tc(args: &[&str]) -> std::process::Output {
    for prog in ["tc", "/usr/sbin/tc", "/sbin/tc"] {
        if let Ok(out) = Command::new(prog).args(args).output() {
            return out;
        }
    }
    panic!("no tc (iproute2) to shape vcan0's transmit queue");
}

#[test]
#[ignore = "needs vcan0: runs in the VM rig (../shared/tools/vmrig), as scripts/test-all does"]
fn unload_disables_slow_drives_through_a_full_transmit_queue() {
    let iface = vcan();
    // Drives that hold in quick stop active once stopped (option code 6,
    // as many real drives are set up): only disable voltage takes their
    // power stage off. Before the unload their process turns slow (a
    // frame every 3 ms, slower than the safe state's quick-stop rounds
    // come), so its socket queue overflows and drops frames.
    let dir = std::env::temp_dir().join(format!("canservo-vcan-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let hold = dir.join("hold.sdo");
    std::fs::write(&hold, "605A:00 i16 6\n").unwrap();
    let sim = SimProcess::start(&iface, "5,6,7", &["--read-delay-us", "3000"]);
    let host = Host::create(HostConfig::for_tests("canservo-vcan-slow")).unwrap();
    host.rt_log().set_level(MsgLevel::Info);
    let h = hold.display().to_string();
    let mut a = args(&iface, "5,6,7");
    a.retain(|s| {
        !s.starts_with("period_ns") && !s.starts_with("scale") && !s.starts_with("master")
    });
    a.extend([
        "scale=1000,1000,1000".to_string(),
        // A slow cycle the slow receiver keeps up with in operation.
        "period_ns=20000000".to_string(),
        // Drives fault after three of these without the master's
        // heartbeat: more than the pause between stop and unload.
        "master_heartbeat_ms=2000".to_string(),
        format!("drive_file={h},{h},{h}"),
    ]);
    host.loadrt(&MODULE, &a).unwrap();
    host.create_thread("servo", 20_000_000, true, None).unwrap();
    host.addf("canservo.read", "servo", -1).unwrap();
    host.addf("canservo.write", "servo", -1).unwrap();
    host.start().unwrap();
    let inst = host.instance();
    for d in 0..3 {
        inst.set_pin(&format!("canservo.{d}.enable"), Value::Bit(true))
            .unwrap();
    }
    let end = Instant::now() + Duration::from_secs(120);
    while (0..3).any(|d| pin(&host, &format!("canservo.{d}.enabled")) != Value::Bit(true)) {
        assert!(
            Instant::now() < end,
            "the drives did not enable: {} / {} / {} / {:?}",
            describe(&host, 0),
            describe(&host, 1),
            describe(&host, 2),
            host.rt_log().history()
        );
        std::thread::sleep(Duration::from_millis(10));
    }

    // A transmit queue of 50 frames drained at 100 kbit/s (about 780
    // frames a second): the quick-stop rounds and the drives' answers
    // overflow it, so sends fail with ENOBUFS.
    let _ = Command::new("modprobe").arg("sch_tbf").status();
    let shaped = tc(&[
        "qdisc", "replace", "dev", &iface, "root", "tbf", "rate", "32kbit", "burst", "1600",
        "limit", "800",
    ]);
    assert!(
        shaped.status.success(),
        "tc: {}",
        String::from_utf8_lossy(&shaped.stderr)
    );
    sim.slow_down();
    host.stop();
    host.unloadrt("canservo").unwrap();
    let _ = tc(&["qdisc", "del", "dev", &iface, "root"]);

    let said = sim.stop();
    for node in [5, 6, 7] {
        let line = format!("canservo-sim: node {node}: controlword 0x0000, switch on disabled");
        assert!(
            said.contains(&line),
            "node {node} did not end disabled:\n{said}\n{:?}",
            host.rt_log().history()
        );
    }
    // The engine's log (its thread may lag a moment behind).
    let log = || -> Vec<String> {
        host.rt_log()
            .history()
            .into_iter()
            .map(|(_, t)| t)
            .collect()
    };
    let end = Instant::now() + Duration::from_secs(10);
    while !log()
        .iter()
        .any(|l| l.contains("every drive confirmed disable voltage"))
    {
        assert!(Instant::now() < end, "{:?}", log());
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(
        !log().iter().any(|l| l.contains("not confirmed")),
        "{:?}",
        log()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
