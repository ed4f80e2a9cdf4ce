//! canservo inside LinuxCNC on a real kernel CAN interface: `canservo.so`
//! in LinuxCNC's own halrun, talking over `vcan0` in the VM rig
//! (../shared/tools/vmrig) to a CiA 402 drive simulated by a separate
//! process (`canservo-sim`). Start-up (boot-up, identity, SDO set-up),
//! power up to Operation enabled in a LinuxCNC thread, a position
//! command followed, and unload leaving the drive disabled.
//!
//! One drive, on a 20 ms thread: with two, or at 4 ms, LinuxCNC's
//! ordinary (not realtime) thread on the rig's emulated CPU missed the
//! drives' TPDOs and heartbeats, and the drives were faulted and
//! disabled, as they must be then.
//!
//! `scripts/test-all` runs this binary in the rig with
//! `--include-ignored`; elsewhere it is reported as ignored, with the
//! reason. It also needs LinuxCNC unpacked (scripts/linuxcnc-peer) and
//! root, as the other tests here.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::io::{BufRead, BufReader, Read};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

use hal_linuxcnc_tests::{getp_values, linuxcnc, Modules};

/// The CAN interface the rig made; run on purpose without it, the test
/// fails saying so.
fn vcan() -> String {
    let iface = std::env::var("VMRIG_CAN_IF").unwrap_or_else(|_| "vcan0".into());
    assert!(
        std::path::Path::new("/sys/class/net").join(&iface).exists(),
        "no CAN interface {iface}: run this binary through ../shared/tools/vmrig, which makes vcan0"
    );
    iface
}

/// `canservo-sim` as cargo built it: beside this test binary's
/// directory (`target/<profile>/canservo-sim`).
fn sim_program() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let program = exe
        .parent()
        .and_then(|deps| deps.parent())
        .unwrap()
        .join("canservo-sim");
    assert!(
        program.exists(),
        "{} is missing: build it first (cargo build -p hal-canservo --bin canservo-sim)",
        program.display()
    );
    program
}

/// The drives' process, killed if the test ends early.
struct Drives {
    child: Child,
    out: BufReader<std::process::ChildStdout>,
}

impl Drives {
    fn start(iface: &str, nodes: &str) -> Drives {
        let mut child = Command::new(sim_program())
            .args(["--iface", iface, "--nodes", nodes, "--home", "2000"])
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let mut out = BufReader::new(child.stdout.take().unwrap());
        let mut line = String::new();
        out.read_line(&mut line).unwrap();
        assert!(line.starts_with("canservo-sim: "), "{line}");
        Drives { child, out }
    }

    /// SIGTERM; what it printed on the way out (each drive's last
    /// controlword and state).
    fn stop(mut self) -> String {
        let pid = nix::unistd::Pid::from_raw(self.child.id() as i32);
        nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGTERM).unwrap();
        let mut rest = String::new();
        self.out.read_to_string(&mut rest).unwrap();
        rest
    }
}

impl Drop for Drives {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A shell script LinuxCNC's halrun runs with `loadusr -w` (halcmd would
/// take `$(...)` in a HAL line for an environment variable): waits, up to
/// 120 s by the clock (the rig emulates its CPU: one halcmd run can take
/// a second there, so a count of tries would not bound the wait), until
/// LinuxCNC's own halcmd reads pin `$1` as `$3` (`$2` = is), or between
/// `$3` and `$4` (`$2` = between).
const WAIT_SCRIPT: &str = r#"#!/bin/bash
end=$(( $(date +%s) + 120 ))
while [ "$(date +%s)" -lt "$end" ]; do
    v=$(halcmd getp "$1")
    case $2 in
    is) [ "$v" = "$3" ] && exit 0 ;;
    between) awk -v v="$v" -v lo="$3" -v hi="$4" 'BEGIN { exit !(v > lo && v < hi) }' && exit 0 ;;
    esac
    sleep 0.1
done
echo "waited 120 s for $1 $2 $3 $4; it reads $v" >&2
exit 1
"#;

/// Writes the wait script where LinuxCNC's user (nobody) can run it.
fn wait_script(dir: &tempfile::TempDir) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let path = dir.path().join("wait-for.sh");
    std::fs::write(&path, WAIT_SCRIPT).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

#[test]
#[ignore = "needs vcan0 and LinuxCNC: runs in the VM rig (../shared/tools/vmrig), as scripts/test-all does"]
fn canservo_in_linuxcnc_drives_a_separate_process_over_vcan() {
    let iface = vcan();
    let drives = Drives::start(&iface, "7");
    let modules = Modules::stage(&[("canservo", "lcnc_canservo")]);
    // Slow-machine settings, as the driver's own rig test has them, and a
    // 20 ms period: LinuxCNC's thread here is an ordinary one, and on the
    // rig's emulated CPU, with other work on the host, a cycle of read
    // and write took up to 38 ms; at 4 ms the thread ran late
    // continuously, the drive's TPDOs and heartbeats were missed and it
    // was faulted and disabled (rightly, but then there is no move to
    // check). At 20 ms a cycle took about 5 ms.
    let mut hal = format!(
        "loadrt threads name1=t period1=20000000
loadrt canservo iface={iface} nodes=7 scale=1000 period_ns=20000000 sdo_timeout_ms=2000 boot_timeout_ms=3000 heartbeat_timeout_ms=5000 master_heartbeat_ms=300 tpdo_misses=50 diag_ms=500
getp canservo.0.serial-number
addf canservo.read t
addf canservo.write t
start
setp canservo.0.enable 1
"
    );
    let dir = tempfile::tempdir().unwrap();
    let wait = wait_script(&dir);
    let wait = wait.display();
    hal += &format!("loadusr -w {wait} canservo.0.enabled is TRUE\n");
    hal += "getp canservo.0.enabled\n";
    for step in 1..=5 {
        hal += &format!(
            "setp canservo.0.position-cmd {}\nloadusr -w sleep 0.2\n",
            f64::from(step) * 0.05
        );
    }
    hal += &format!("loadusr -w {wait} canservo.0.position-fb between 0.247 0.253\n");
    hal += "getp canservo.0.position-fb\ngetp canservo.0.amp-fault\n";
    hal += "stop\nunloadrt canservo\n";
    let run = linuxcnc(&modules, &hal);
    let said = drives.stop();
    assert!(
        run.ok,
        "LinuxCNC's halrun failed:\n{}\n{}",
        run.stdout, run.stderr
    );
    let values = getp_values(&run.stdout);
    assert_eq!(values.len(), 4, "{values:?}\n{}", run.stderr);
    assert_eq!(values[0], "7", "the drive's serial number, read by SDO");
    assert_eq!(values[1], "TRUE", "the drive enabled\n{}", run.stderr);
    let fb: f64 = values[2].parse().unwrap();
    assert!(
        (fb - 0.25).abs() < 0.003,
        "position-fb {fb}\n{}",
        run.stderr
    );
    assert_eq!(values[3], "FALSE", "the drive did not fault");
    // The safe state at unload: the last controlword the drive got is
    // 0x0000 (disable voltage). The master's heartbeat ends with the
    // module, and halrun's own exit takes seconds on the emulated CPU, so
    // by the time the drive process is stopped it may also have taken the
    // missing heartbeat as a fault: either state follows a disabled
    // drive. Without the safe state the last controlword would be 0x000f
    // (operation enabled).
    let disabled = ["switch on disabled", "fault"].iter().any(|state| {
        said.contains(&format!(
            "canservo-sim: node 7: controlword 0x0000, {state}\n"
        ))
    });
    assert!(
        disabled,
        "the drive did not end disabled after unloadrt:\n{said}\n{}",
        run.stderr
    );
}
