//! Our master on a real wire: `loadrt lcec` (raw socket) on one end of a
//! veth pair, `ethercat-sim` on the other, in a network namespace this
//! test makes for its own thread (so copies of the test run side by
//! side). A mixed segment (coupler, digital in and out, three CiA 402
//! drives) comes to OP and the three drives are enabled and follow CSP
//! commands. Then faults over the wire, each seen on the pins within
//! [`FAULT_BOUND`]:
//! * the slaves' end of the pair down: link-up, all-op, every slave's
//!   state pins and the drives' enable go false; with the link back the
//!   segment is in OP, the drives disabled (their controlword went
//!   safe) until a fault reset and a new enable, and they move again;
//! * the line cut before the first drive (the simulator's `cut 3`): the
//!   drives lost and faulted while the link stays up; back after
//!   `cut none` and a fault reset;
//! * the simulator killed, the carrier still up: the link is down;
//! * the simulator started again (every slave in INIT without its
//!   station address, as after a power cycle): the master brings the
//!   segment back to OP on its own, and after a fault reset the drives
//!   move again.
//!
//! Needs root (a network namespace and a veth pair): without it
//! (build.rs probes for it) the test is reported as ignored.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, MsgLevel, Value};
use hal_ethercat::hal::MODULE;

mod common {
    pub mod pins;
    pub mod veth;
    pub mod wait;
}
use common::pins::{bit, float, pin, set};
use common::veth;
use common::wait::wait_within;

/// The simulator's segment: the same slaves, in the same order, as
/// [`CONF`].
const SEGMENT: &str = "EK1100\nEL1008\nEL2008\nservo serial=1\nservo serial=2\nservo serial=3\n";

/// The drives' names in [`CONF`], with a CSP command for each (mm) and
/// one after the fault.
const DRIVES: [(&str, f64, f64); 3] = [("X", 2.5, -1.0), ("Y", -4.25, 3.0), ("Z", 10.0, 0.5)];

const CONF: &str = r#"<masters>
  <master idx="0" appTimePeriod="4000000" refClockSyncCycles="250">
    <slave idx="0" type="EK1100" name="D0"/>
    <slave idx="1" type="EL1008" name="D1"/>
    <slave idx="2" type="EL2008" name="D2"/>
    <slave idx="3" type="basic_cia402" vid="00000e5c" pid="00000402" name="X">
      <modParam name="mode" value="csp"/>
    </slave>
    <slave idx="4" type="basic_cia402" vid="00000e5c" pid="00000402" name="Y">
      <modParam name="mode" value="csp"/>
    </slave>
    <slave idx="5" type="basic_cia402" vid="00000e5c" pid="00000402" name="Z">
      <modParam name="mode" value="csp"/>
    </slave>
  </master>
</masters>
"#;

/// The servo period, as `appTimePeriod` in [`CONF`]. A frame not back
/// within the period is lost, and three lost in a row take the link
/// down: 4 ms rather than 1 ms, so that two copies of this test on a
/// loaded two-core machine (the simulator a process that must be
/// scheduled) do not see a link fault nobody injected.
const PERIOD_NS: i64 = 4_000_000;

/// The drives' positions on the segment.
const DRIVE_POSITIONS: std::ops::Range<usize> = 3..6;
/// EL2008's first output, as the simulator holds it.
const DOUT_0: &str = "7000:01";
/// A CiA 402 drive's controlword.
const CONTROLWORD: &str = "6040:00";

/// The slaves' names in [`CONF`].
const SLAVES: [&str; 6] = ["D0", "D1", "D2", "X", "Y", "Z"];

/// How long the pins may take to say the link is down: the master
/// declares it after three lost frames, 12 ms; this allows for a loaded
/// test machine without letting a pin that never changes pass.
const FAULT_BOUND: Duration = Duration::from_secs(2);

/// Puts the calling thread (and the threads and processes it starts
/// from now on) in a new network namespace; its sockets and interfaces
/// are invisible to every other test.
fn own_network_namespace() {
    // unshare(2) changes only the calling thread's network namespace; the
    // process's other threads (the test harness) keep theirs.
    if let Err(e) = nix::sched::unshare(nix::sched::CloneFlags::CLONE_NEWNET) {
        panic!("unshare(CLONE_NEWNET): {e} (build.rs found it possible at build time)");
    }
}

fn sh(script: &str) {
    let out = Command::new("sh").args(["-c", script]).output().unwrap();
    assert!(
        out.status.success(),
        "{script}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The running `ethercat-sim`, killed when dropped, so a failed test
/// leaves no simulator behind.
struct Sim(Child, PathBuf);

impl Drop for Sim {
    fn drop(&mut self) {
        // Already gone when the test killed it: nothing to do.
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

impl Sim {
    /// Sends a command to the simulator's standard input.
    fn say(&mut self, line: &str) {
        let stdin = self.0.stdin.as_mut().unwrap();
        writeln!(stdin, "{line}").unwrap();
        stdin.flush().unwrap();
    }

    /// The value of object `at` (`INDEX:SUB`, hexadecimal) of slave
    /// `slave` as the simulator holds it: what the master last wrote
    /// there over the wire.
    fn show(&mut self, slave: usize, at: &str) -> u64 {
        let key = format!("ethercat-sim: slave {slave} {at} = 0x");
        let answers = |log: &Path| {
            let text = std::fs::read_to_string(log).unwrap_or_default();
            text.lines()
                .filter_map(|l| l.strip_prefix(&key))
                .map(|v| u64::from_str_radix(v, 16).unwrap())
                .collect::<Vec<_>>()
        };
        let before = answers(&self.1).len();
        self.say(&format!("show {slave} {at}"));
        let mut got = Vec::new();
        wait_within(&format!("the simulator to show {at}"), LONG, || {
            got = answers(&self.1);
            got.len() > before
        });
        got[before]
    }
}

/// `ethercat-sim` on `iface`, its output in `dir/sim.log`, once it
/// answers.
fn start_sim(dir: &Path, iface: &str) -> Sim {
    let seg = dir.join("segment.txt");
    std::fs::write(&seg, SEGMENT).unwrap();
    let log = dir.join("sim.log");
    let sim = Sim(
        Command::new(env!("CARGO_BIN_EXE_ethercat-sim"))
            .args(["--iface", iface])
            .arg(&seg)
            .stdin(Stdio::piped())
            .stdout(std::fs::File::create(&log).unwrap())
            .stderr(std::fs::File::create(dir.join("sim.err")).unwrap())
            .spawn()
            .unwrap(),
        log.clone(),
    );
    wait_within("ethercat-sim to answer", Duration::from_secs(10), || {
        std::fs::read_to_string(&log).is_ok_and(|s| s.contains(veth::SIM_READY))
    });
    sim
}

/// [`wait_within`], and on a timeout the master's and slaves' state pins.
fn wait_or(what: &str, limit: Duration, h: &Host, mut cond: impl FnMut() -> bool) -> Duration {
    let start = Instant::now();
    while !cond() {
        if start.elapsed() >= limit {
            let mut names = vec![
                "lcec.0.link-up".to_string(),
                "lcec.0.all-op".into(),
                "lcec.all-op".into(),
                "lcec.0.slaves-responding".into(),
            ];
            names.extend(SLAVES.iter().map(|s| format!("lcec.0.{s}.slave-state-op")));
            for (d, ..) in DRIVES {
                for p in [
                    "srv-enabled",
                    "srv-fault",
                    "srv-target-position",
                    "srv-actual-position",
                ] {
                    names.push(format!("lcec.0.{d}.{p}"));
                }
            }
            let pins: Vec<String> = names
                .iter()
                .map(|n| format!("{n} = {:?}", pin(h, n)))
                .collect();
            panic!(
                "timed out ({limit:?}) waiting for {what}:\n{}",
                pins.join("\n")
            );
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    start.elapsed()
}

const LONG: Duration = Duration::from_secs(30);

/// Every slave in OP, on the master's pins and each slave's.
fn all_op(h: &Host) -> bool {
    bit(h, "lcec.0.all-op")
        && bit(h, "lcec.all-op")
        && bit(h, "lcec.0.link-up")
        && SLAVES
            .iter()
            .all(|s| bit(h, &format!("lcec.0.{s}.slave-state-op")))
}

/// Enables the three drives and moves each to its command (index 1 of
/// [`DRIVES`], or 2).
fn enable_and_move(h: &Host, second: bool) {
    for (d, ..) in DRIVES {
        set(h, &format!("lcec.0.{d}.srv-enable"), Value::Bit(true));
    }
    for (d, ..) in DRIVES {
        wait_or(&format!("{d} enabled"), LONG, h, || {
            bit(h, &format!("lcec.0.{d}.srv-enabled"))
        });
    }
    for (d, a, b) in DRIVES {
        let to = if second { b } else { a };
        set(
            h,
            &format!("lcec.0.{d}.srv-target-position"),
            Value::Float(to),
        );
    }
    for (d, a, b) in DRIVES {
        let to = if second { b } else { a };
        let name = format!("lcec.0.{d}.srv-actual-position");
        wait_or(&format!("{d} at {to}"), LONG, h, || {
            (float(h, &name) - to).abs() < 1e-3
        });
    }
}

fn conf_file(dir: &Path) -> PathBuf {
    let p = dir.join("ethercat-conf.xml");
    std::fs::write(&p, CONF).unwrap();
    p
}

#[test]
#[cfg_attr(
    not(netns),
    ignore = "needs root: a network namespace and a veth pair (build.rs found neither possible)"
)]
fn our_master_on_a_veth_pair_brings_a_mixed_segment_to_op_moves_three_drives_and_survives_faults() {
    own_network_namespace();
    let id = std::process::id();
    // Interface names: at most 15 bytes; unique per process besides.
    let (m_if, s_if) = (format!("ecm{id:x}"), format!("ecs{id:x}"));
    sh(&veth::veth_script(&m_if, &s_if));
    let dir = std::env::temp_dir().join(format!("hal-ecat-veth-{id}"));
    std::fs::create_dir_all(&dir).unwrap();
    let mut sim = start_sim(&dir, &s_if);
    let file = conf_file(&dir);

    let h = Host::create(HostConfig::for_tests("lcec-veth")).unwrap();
    h.rt_log().set_level(MsgLevel::Info);
    h.loadrt(
        &MODULE,
        &[
            &format!("config={}", file.display()),
            &format!("iface={m_if}"),
        ],
    )
    .unwrap();
    h.create_thread("servo", PERIOD_NS, true, None).unwrap();
    h.addf("lcec.read-all", "servo", -1).unwrap();
    h.addf("lcec.write-all", "servo", -1).unwrap();
    h.start().unwrap();

    wait_or("all slaves in OP", LONG, &h, || all_op(&h));
    assert_eq!(pin(&h, "lcec.0.slaves-responding"), Value::U32(6));
    for (d, ..) in DRIVES {
        set(
            &h,
            &format!("lcec.0.{d}.srv-pos-scale"),
            Value::Float(1000.0),
        );
    }
    enable_and_move(&h, false);
    // What the master writes reaches the slaves: an output on, the
    // drives' controlword "enable operation".
    set(&h, "lcec.0.D2.dout-0", Value::Bit(true));
    wait_within("dout-0 on the wire", LONG, || sim.show(2, DOUT_0) == 1);
    for p in DRIVE_POSITIONS {
        assert_eq!(sim.show(p, CONTROLWORD) & 0x0f, 0x0f, "drive at {p}");
    }

    pull_the_link(&h, &mut sim, &s_if);
    cut_the_line(&h, &mut sim);
    kill_the_sim(&h, &mut sim);
    restart_the_sim(&h, &mut sim, &dir, &s_if);

    h.stop();
    h.unloadrt("lcec").unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every pin that says the link is down: the master's, every slave's
/// state, the drives disabled, nobody responding.
fn link_down_seen(h: &Host) -> bool {
    !bit(h, "lcec.0.link-up")
        && !bit(h, "lcec.0.all-op")
        && !bit(h, "lcec.all-op")
        && pin(h, "lcec.0.slaves-responding") == Value::U32(0)
        && SLAVES.iter().all(|s| {
            !bit(h, &format!("lcec.0.{s}.slave-state-op"))
                && !bit(h, &format!("lcec.0.{s}.slave-online"))
        })
        && DRIVES
            .iter()
            .all(|(d, ..)| !bit(h, &format!("lcec.0.{d}.srv-enabled")))
}

/// Waits until the servo thread has run `n` more cycles (the master's
/// `mono-time-lo` changes every cycle), so that a pin set before was
/// seen by `lcec.write-all` at least `n - 1` times.
fn cycles(h: &Host, n: usize) {
    for _ in 0..n {
        let before = pin(h, "lcec.0.mono-time-lo");
        wait_within("a servo cycle", LONG, || {
            pin(h, "lcec.0.mono-time-lo") != before
        });
    }
}

/// The drives faulted by a lost link or slave: disabled until a fault
/// reset (their controlword went safe, so they do not come back on
/// their own), then cleared.
fn fault_reset_drives(h: &Host) {
    for (d, ..) in DRIVES {
        assert!(!bit(h, &format!("lcec.0.{d}.srv-enabled")), "{d}");
        set(h, &format!("lcec.0.{d}.srv-enable"), Value::Bit(false));
        set(h, &format!("lcec.0.{d}.srv-fault-reset"), Value::Bit(true));
    }
    // The enable low and the reset high for whole cycles: the drive
    // layer acts on an edge of each.
    cycles(h, 3);
    for (d, ..) in DRIVES {
        wait_within(&format!("{d}'s fault cleared"), LONG, || {
            !bit(h, &format!("lcec.0.{d}.srv-fault"))
        });
        set(h, &format!("lcec.0.{d}.srv-fault-reset"), Value::Bit(false));
    }
    cycles(h, 3);
}

/// The slaves' end of the pair down (every frame lost, the simulator
/// waiting), then up: the pins say so within [`FAULT_BOUND`]; once the
/// link is back the segment is in OP and the drives move after a fault
/// reset.
fn pull_the_link(h: &Host, sim: &mut Sim, s_if: &str) {
    sh(&format!("ip link set {s_if} down"));
    let took = wait_or("the pins to say the link is down", FAULT_BOUND, h, || {
        link_down_seen(h)
    });
    println!("link down seen on the pins after {took:?}");
    sh(&format!("ip link set {s_if} up"));
    wait_or("all slaves in OP again", LONG, h, || all_op(h));
    assert_eq!(pin(h, "lcec.0.slaves-responding"), Value::U32(6));
    // The drives' controlword on the wire is safe: none is told to
    // enable operation. The simulated ESC applies a frame's outputs when
    // the next frame arrives (sim/esc.rs, begin_frame), so right after
    // all-op it may still hold the last outputs of before the outage
    // (0xf); hence a wait within the bound rather than the first look.
    for p in DRIVE_POSITIONS {
        wait_within("the controlword safe on the wire", FAULT_BOUND, || {
            sim.show(p, CONTROLWORD) & 0x0f != 0x0f
        });
    }
    fault_reset_drives(h);
    enable_and_move(h, true);
}

/// The line cut before the first drive (`cut 3` on the simulator's
/// standard input): the working counter falls short, the three drives
/// are lost and disabled within [`FAULT_BOUND`], the link stays up; the
/// line whole again and a fault reset bring them back.
fn cut_the_line(h: &Host, sim: &mut Sim) {
    sim.say("cut 3");
    let took = wait_or("the drives lost", FAULT_BOUND, h, || {
        !bit(h, "lcec.0.all-op")
            && DRIVES.iter().all(|(d, ..)| {
                !bit(h, &format!("lcec.0.{d}.slave-oper"))
                    && !bit(h, &format!("lcec.0.{d}.srv-enabled"))
                    && bit(h, &format!("lcec.0.{d}.srv-fault"))
            })
    });
    println!("the cut seen on the pins after {took:?}");
    assert!(bit(h, "lcec.0.link-up"));
    // The working counter is the segment's: the master cannot tell which
    // slave is short, so the reachable EL2008's output goes safe too,
    // on the wire.
    wait_within("dout-0 safe on the wire", FAULT_BOUND, || {
        sim.show(2, DOUT_0) == 0
    });
    sim.say("cut none");
    wait_or("all slaves in OP after the cut", LONG, h, || all_op(h));
    wait_within("dout-0 on the wire again", LONG, || {
        sim.show(2, DOUT_0) == 1
    });
    fault_reset_drives(h);
    enable_and_move(h, false);
}

/// The simulator killed: nothing answers though the carrier stays up;
/// the pins say the link is down within [`FAULT_BOUND`].
fn kill_the_sim(h: &Host, sim: &mut Sim) {
    sim.0.kill().unwrap();
    sim.0.wait().unwrap();
    let took = wait_or("the pins to say nothing answers", FAULT_BOUND, h, || {
        link_down_seen(h)
    });
    println!("the simulator's end seen on the pins after {took:?}");
}

/// A new simulator on the same segment file, as a segment powered up
/// again: its slaves in INIT with no station address. The master brings
/// them back to OP by itself (no fault reset needed for that); the
/// drives stay disabled until a fault reset and a new enable, then move.
fn restart_the_sim(h: &Host, sim: &mut Sim, dir: &Path, s_if: &str) {
    *sim = start_sim(dir, s_if);
    let took = wait_or("all slaves in OP after the restart", LONG, h, || all_op(h));
    println!("the restarted segment in OP after {took:?}");
    assert_eq!(pin(h, "lcec.0.slaves-responding"), Value::U32(6));
    for p in DRIVE_POSITIONS {
        assert_eq!(
            sim.show(p, CONTROLWORD) & 0x0f,
            0,
            "the drive at {p} is not enabled by a restart"
        );
    }
    fault_reset_drives(h);
    // The restarted drives stand at 0: the command comes to where they
    // are before they follow it (as motion's does while disabled). The
    // pins may still hold the old drives' positions for a few cycles
    // after all-op: wait until they read the new ones, or the command
    // would go to a stale position the drive layer never tracks onto
    // (it holds an enabled drive until the command comes within
    // tolerance of where the drive is).
    for (d, ..) in DRIVES {
        let name = format!("lcec.0.{d}.srv-actual-position");
        wait_or(&format!("{d} reading its restarted drive"), LONG, h, || {
            float(h, &name).abs() < 1e-9
        });
        let at = float(h, &name);
        set(
            h,
            &format!("lcec.0.{d}.srv-target-position"),
            Value::Float(at),
        );
    }
    enable_and_move(h, false);
    // Outputs reach the restarted EL2008 again.
    wait_within("dout-0 on the wire after the restart", LONG, || {
        sim.show(2, DOUT_0) == 1
    });
}
