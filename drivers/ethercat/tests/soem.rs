//! SOEM, a third-party EtherCAT master (pysoem 1.1.13, scripts/soem-peer),
//! runs our simulated segment over a real veth pair: `ethercat-sim` on
//! one end, SOEM on the other, in a network namespace of the test's own
//! (`unshare --user --map-root-user --net`, so no root and no interface
//! outside it). SOEM must find every slave with its identity, read,
//! write and be refused SDOs as from real devices, map the process data
//! from the slaves' own PDO assignment, bring the segment to OP, and run
//! a CiA 402 drive from switch-on-disabled to operation enabled through
//! its controlword.
//!
//! Without pysoem installed the test is reported as ignored.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

mod common {
    pub mod veth;
}
use common::veth;

/// The segment: a coupler, digital in and out, analog in and out, a drive.
const SEGMENT: &str = "EK1100\nEL1008\nEL2008\nEL3102\nEL4102\nservo serial=77\n";

/// SOEM's side: prints `key value` lines for the test to check.
const MASTER: &str = r#"
import struct, sys, pysoem

def say(key, value):
    print(key, value, flush=True)

m = pysoem.Master()
m.open(sys.argv[1])
say("slaves", m.config_init())
for i, s in enumerate(m.slaves):
    say(f"slave{i}", f"{s.man:#x}:{s.id:#x}")
drive = m.slaves[5]

# SOEM gives up on a mailbox answer after its receive timeout; the
# simulator is an ordinary process, which a loaded test machine can
# hold back past it (one run in the whole suite lost the first read so).
# A read that got no answer (WkcError) is asked again; an abort is not.
def sdo_read(index, sub):
    for attempt in range(5):
        try:
            return drive.sdo_read(index, sub)
        except pysoem.WkcError:
            if attempt == 4:
                raise

say("vendor", hex(struct.unpack("<I", sdo_read(0x1018, 1))[0]))
say("serial", struct.unpack("<I", sdo_read(0x1018, 4))[0])
drive.sdo_write(0x6060, 0, struct.pack("<b", 8))
say("mode", struct.unpack("<b", sdo_read(0x6060, 0))[0])
try:
    drive.sdo_read(0x5555, 0)
    say("abort", "none")
except pysoem.SdoError as e:
    say("abort", hex(e.abort_code))
say("iomap", m.config_map())
for i, s in enumerate(m.slaves):
    say(f"bytes{i}", f"{len(s.output)}/{len(s.input)}")
m.state = pysoem.SAFEOP_STATE
m.write_state()
say("safeop", m.state_check(pysoem.SAFEOP_STATE, 500000) == pysoem.SAFEOP_STATE)
m.send_processdata()
m.receive_processdata(20000)
m.state = pysoem.OP_STATE
m.write_state()
op = False
for _ in range(500):
    m.send_processdata()
    m.receive_processdata(20000)
    if m.state_check(pysoem.OP_STATE, 5000) == pysoem.OP_STATE:
        op = True
        break
say("op", op)

def cycle(controlword):
    out = bytearray(drive.output)
    out[0:2] = struct.pack("<H", controlword)
    out[10] = 8
    drive.output = bytes(out)
    wkc = m.send_processdata() and m.receive_processdata(20000)
    return wkc, struct.unpack("<H", drive.input[0:2])[0]

# Shutdown, switch on, enable operation: the statusword answers each
# (masked with 0x6F: ready to switch on 0x21, switched on 0x23,
# operation enabled 0x27).
for name, word, want in [("shutdown", 0x06, 0x21), ("switch-on", 0x07, 0x23), ("enable", 0x0F, 0x27)]:
    status = None
    for _ in range(500):
        wkc, status = cycle(word)
        if status & 0x6F == want:
            break
    say(name, f"{status:#06x}")
say("wkc", f"{wkc}/{m.expected_wkc}")
cycle(0x00)
m.state = pysoem.INIT_STATE
m.write_state()
m.close()
"#;

/// The namespace's script after the veth pair (ecmaster, ecslave): the
/// simulator on one end, SOEM on the other; the simulator's own output
/// follows SOEM's.
const RUN: &str = r#"
"$SIM" --iface ecslave segment.txt >sim.log 2>&1 &
sim=$!
for _ in $(seq 100); do
    grep -qF "$SIM_READY" sim.log && break
    sleep 0.05
done
timeout 120 "$PYTHON" master.py ecmaster
rc=$?
kill "$sim"
wait "$sim"
echo "sim-exit $?"
cat sim.log >&2
exit $rc
"#;

fn run_in_namespace(dir: &Path, python: &str) -> (bool, String, String) {
    std::fs::write(dir.join("segment.txt"), SEGMENT).unwrap();
    std::fs::write(dir.join("master.py"), MASTER).unwrap();
    let script = format!("set -u\n{}{RUN}", veth::veth_script("ecmaster", "ecslave"));
    std::fs::write(dir.join("run.sh"), script).unwrap();
    let out = Command::new("timeout")
        .args([
            "180",
            "unshare",
            "--user",
            "--map-root-user",
            "--net",
            "bash",
            "run.sh",
        ])
        .current_dir(dir)
        .env("SIM", env!("CARGO_BIN_EXE_ethercat-sim"))
        .env("PYTHON", python)
        .env("SIM_READY", veth::SIM_READY)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
#[cfg_attr(
    not(soem_peer),
    ignore = "needs pysoem installed (scripts/soem-peer install)"
)]
fn soem_brings_the_simulated_segment_to_op_and_enables_the_drive() {
    let Some(python) = option_env!("SOEM_PEER_PYTHON") else {
        panic!("pysoem was not installed when this test was built: run scripts/soem-peer install");
    };
    let dir = std::env::temp_dir().join(format!("hal-soem-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (ok, stdout, stderr) = run_in_namespace(&dir, python);
    std::fs::remove_dir_all(&dir).unwrap();
    let said: HashMap<&str, &str> = stdout.lines().filter_map(|l| l.split_once(' ')).collect();
    let context = format!("SOEM said:\n{stdout}\nstderr:\n{stderr}");
    assert!(ok, "the run failed\n{context}");
    let want = [
        ("slaves", "6"),
        // Beckhoff's vendor id and the terminals' product codes.
        ("slave0", "0x2:0x44c2c52"),
        ("slave1", "0x2:0x3f03052"),
        ("slave2", "0x2:0x7d83052"),
        ("slave3", "0x2:0xc1e3052"),
        ("slave4", "0x2:0x10063052"),
        ("slave5", "0xe5c:0x402"),
        ("vendor", "0xe5c"),
        ("serial", "77"),
        ("mode", "8"),
        // "object does not exist", as an abort SOEM recognises.
        ("abort", "0x6020000"),
        // Outputs/inputs in bytes, from each slave's PDO assignment.
        ("bytes0", "0/0"),
        ("bytes1", "0/1"),
        ("bytes2", "1/0"),
        ("bytes3", "0/6"),
        ("bytes4", "4/0"),
        ("bytes5", "11/13"),
        ("iomap", "36"),
        ("safeop", "True"),
        ("op", "True"),
        ("shutdown", "0x0231"),
        ("switch-on", "0x0233"),
        // Operation enabled; bit 12 in CSP: the drive follows the
        // command value.
        ("enable", "0x1237"),
        // LRW: 2 per slave written, 1 per slave read, 3 for the drive
        // (both); SOEM expects at least its own count.
        ("wkc", "9/6"),
    ];
    for (key, value) in want {
        assert_eq!(said.get(key).copied(), Some(value), "{key}\n{context}");
    }
    assert!(stdout.contains("sim-exit 0"), "{context}");
}
