//! Several processes on one instance.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::time::{Duration, Instant};

use common::*;
use hal_core::*;

const A: f64 = 1.0000000000000002; // bits 0x3FF0000000000001
const B: f64 = -2.5e300; // high and low halves both differ from A's

#[test]
fn a_reader_never_sees_a_torn_float() {
    if let Some((role, name)) = child_role() {
        if role == "writer" {
            let inst = Instance::attach(&name).unwrap();
            let comp = inst.new_component("writer", ComponentKind::User).unwrap();
            let out: Pin<f64, Out> = comp.pin("writer.out").unwrap();
            inst.link("writer.out", "x").unwrap();
            comp.ready().unwrap();
            let end = Instant::now() + Duration::from_millis(1500);
            while Instant::now() < end {
                for _ in 0..1000 {
                    out.set(A);
                    out.set(B);
                }
            }
        }
        return;
    }
    let host = host("torn");
    let inst = host.instance().clone();
    inst.newsig("x", HalType::Float).unwrap();
    let comp = inst.new_component("reader", ComponentKind::User).unwrap();
    let input: Pin<f64, In> = comp.pin("reader.in").unwrap();
    inst.link("reader.in", "x").unwrap();
    let mut child = spawn_child("a_reader_never_sees_a_torn_float", "writer", inst.name());
    let (mut seen_a, mut seen_b, mut reads) = (0u64, 0u64, 0u64);
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(20) {
        let v = input.get();
        reads += 1;
        if v.to_bits() == A.to_bits() {
            seen_a += 1;
        } else if v.to_bits() == B.to_bits() {
            seen_b += 1;
        } else {
            assert_eq!(v, 0.0, "torn value {v:e} ({:#x})", v.to_bits());
        }
        if reads % 4096 == 0 && child.try_wait().unwrap().is_some() {
            break;
        }
    }
    assert!(child.wait().unwrap().success());
    assert!(
        seen_a > 1000 && seen_b > 1000,
        "a {seen_a}, b {seen_b} of {reads}"
    );
}

#[test]
fn a_process_killed_holding_the_lock_does_not_wedge_the_instance() {
    if let Some((role, name)) = child_role() {
        if role == "stall" {
            let inst = Instance::attach(&name).unwrap();
            let _ = inst.debug_stall_mid_change("half-made", Duration::from_secs(60));
        }
        return;
    }
    let host = host("killed");
    let inst = host.instance().clone();
    inst.newsig("before", HalType::Bit).unwrap();
    let next_id = inst.next_component_id();
    let generation = inst.generation();
    let mut child = spawn_child(
        "a_process_killed_holding_the_lock_does_not_wedge_the_instance",
        "stall",
        inst.name(),
    );
    // Wait until the child holds the lock mid-change: a structural
    // operation from a thread of ours would block until then.
    std::thread::sleep(Duration::from_millis(500));
    let probe = {
        let inst = inst.clone();
        std::thread::spawn(move || {
            let t = Instant::now();
            let sigs = inst.signals().unwrap();
            (t.elapsed(), sigs)
        })
    };
    std::thread::sleep(Duration::from_millis(300));
    assert!(!probe.is_finished(), "the child should be holding the lock");
    nix::sys::signal::kill(
        nix::unistd::Pid::from_raw(child.id() as i32),
        nix::sys::signal::Signal::SIGKILL,
    )
    .unwrap();
    child.wait().unwrap();
    let (waited, sigs) = probe.join().unwrap();
    assert!(waited < Duration::from_secs(30));
    let names: Vec<_> = sigs.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["before"], "the half-made change was rolled back");
    assert_eq!(inst.next_component_id(), next_id);
    assert_eq!(inst.generation(), generation);
    // And the instance keeps working.
    inst.newsig("after", HalType::Bit).unwrap();
    assert_eq!(inst.signals().unwrap().len(), 2);
}

#[test]
fn a_user_space_component_leaves_cleanly_on_sigterm() {
    if let Some((role, name)) = child_role() {
        if role == "uspace" {
            let exit = hal_core::userspace::ExitSignals::install().unwrap();
            let inst = Instance::attach(&name).unwrap();
            let comp = inst.new_component("uspace", ComponentKind::User).unwrap();
            let _p: Pin<bool, Out> = comp.pin("uspace.alive").unwrap();
            inst.link("uspace.alive", "alive").unwrap();
            comp.ready().unwrap();
            while !exit.requested() {
                std::thread::sleep(Duration::from_millis(5));
            }
        }
        return;
    }
    let host = host("sigterm");
    let inst = host.instance().clone();
    inst.newsig("alive", HalType::Bit).unwrap();
    let mut child = spawn_child(
        "a_user_space_component_leaves_cleanly_on_sigterm",
        "uspace",
        inst.name(),
    );
    assert!(wait_until(20.0, || inst.components().unwrap().iter().any(
        |c| c.name == "uspace" && c.ready && c.pid == child.id() as i32
    )));
    assert_eq!(inst.signals().unwrap()[0].writers, 1);
    nix::sys::signal::kill(
        nix::unistd::Pid::from_raw(child.id() as i32),
        nix::sys::signal::Signal::SIGTERM,
    )
    .unwrap();
    assert!(child.wait().unwrap().success());
    assert!(inst
        .components()
        .unwrap()
        .iter()
        .all(|c| c.name != "uspace"));
    assert!(inst.pins().unwrap().is_empty());
    assert_eq!(inst.signals().unwrap()[0].writers, 0);
}

#[test]
fn the_host_removes_a_killed_user_space_component() {
    if let Some((role, name)) = child_role() {
        if role == "doomed" {
            let inst = Instance::attach(&name).unwrap();
            let comp = inst.new_component("doomed", ComponentKind::User).unwrap();
            let out: Pin<f64, Out> = comp.pin("doomed.out").unwrap();
            let _param: Param<i32, Rw> = comp.param("doomed.gain", 3).unwrap();
            let _region = comp.region("doomed.buffer", 64).unwrap();
            inst.link("doomed.out", "fed").unwrap();
            out.set(2.5);
            comp.ready().unwrap();
            // Waits to be killed; never leaves on its own.
            loop {
                std::thread::sleep(Duration::from_secs(1));
            }
        }
        return;
    }
    let host = host("reap");
    let inst = host.instance().clone();
    inst.newsig("fed", HalType::Float).unwrap();
    // A live user component of this very process must survive the reaper.
    let mine = inst.new_component("mine", ComponentKind::User).unwrap();
    let _p: Pin<bool, In> = mine.pin("mine.in").unwrap();
    let mut child = spawn_child(
        "the_host_removes_a_killed_user_space_component",
        "doomed",
        inst.name(),
    );
    assert!(wait_until(20.0, || inst
        .component("doomed")
        .unwrap()
        .is_some_and(|c| c.ready)));
    assert_eq!(inst.signals().unwrap()[0].writers, 1);
    nix::sys::signal::kill(
        nix::unistd::Pid::from_raw(child.id() as i32),
        nix::sys::signal::Signal::SIGKILL,
    )
    .unwrap();
    child.wait().unwrap();
    assert!(wait_until(20.0, || inst
        .component("doomed")
        .unwrap()
        .is_none()));
    let pins: Vec<String> = inst.pins().unwrap().into_iter().map(|p| p.name).collect();
    assert_eq!(pins, ["mine.in"], "only the live component's pin is left");
    assert!(inst.param("doomed.gain").unwrap().is_none());
    assert!(inst.region("doomed.buffer").is_err());
    let fed = &inst.signals().unwrap()[0];
    assert_eq!((fed.writers, fed.value), (0, Value::Float(2.5)));
    // The reaper keeps running and leaves the live component alone.
    std::thread::sleep(Duration::from_millis(300));
    assert!(inst.component("mine").unwrap().is_some());
    drop(mine);
    assert!(inst.component("mine").unwrap().is_none());
}

#[test]
fn a_dead_owners_component_is_reaped_on_request_and_a_live_one_is_not() {
    let host = host("reap-now");
    let inst = host.instance().clone();
    let live = inst.new_component("live", ComponentKind::User).unwrap();
    // A second handle on the instance has its own open file, like
    // another process; its components are alive while it holds them.
    let other = Instance::attach(inst.name()).unwrap();
    let theirs = other.new_component("theirs", ComponentKind::User).unwrap();
    assert!(inst.reap_dead_components().unwrap().is_empty());
    drop(theirs);
    drop(live);
    assert!(inst.components().unwrap().is_empty());
    // A record reused by a new component is claimed afresh.
    let again = other.new_component("again", ComponentKind::User).unwrap();
    assert!(inst.reap_dead_components().unwrap().is_empty());
    assert_eq!(again.name(), "again");
}

/// Writes `bytes` at `offset` of the instance's segment file, as a stray
/// process of the group could.
fn scribble(instance: &str, offset: u64, bytes: &[u8]) {
    use std::os::unix::fs::FileExt;
    let f = std::fs::OpenOptions::new()
        .write(true)
        .open(hal_core::paths::segment(instance))
        .unwrap();
    f.write_all_at(bytes, offset).unwrap();
}

#[test]
fn a_lock_word_naming_an_impossible_owner_is_recovered() {
    let host = host("lockword");
    let inst = host.instance().clone();
    inst.newsig("before", HalType::Bit).unwrap();
    // The lock word sits at offset 64 of the segment. 0x55 names thread
    // 85 (none, or a kernel thread, or a process without the segment);
    // 0x3fffffff a thread id above any pid_max; 0x80000055 thread 85 with
    // the waiters bit set.
    for (i, word) in [0x55u32, 0x3fff_ffff, 0x8000_0055].into_iter().enumerate() {
        scribble(inst.name(), 64, &word.to_le_bytes());
        let t = Instant::now();
        inst.newsig(&format!("after-{i}"), HalType::Bit).unwrap();
        let waited = t.elapsed();
        // STALE_AFTER (1 s) plus the checks; far below "forever".
        assert!(waited < Duration::from_secs(10), "waited {waited:?}");
        assert!(
            waited >= Duration::from_millis(900),
            "recovered before the word was seen unchanged for a second: {waited:?}"
        );
    }
    let names: Vec<_> = inst
        .signals()
        .unwrap()
        .into_iter()
        .map(|s| s.name)
        .collect();
    assert_eq!(names, ["after-0", "after-1", "after-2", "before"]);
    // Unharmed afterwards: no more waiting.
    let t = Instant::now();
    inst.newsig("quick", HalType::Bit).unwrap();
    assert!(t.elapsed() < Duration::from_millis(500));
}

#[test]
fn a_live_holder_is_never_robbed_of_the_lock() {
    if let Some((role, name)) = child_role() {
        if role == "stall" {
            let inst = Instance::attach(&name).unwrap();
            let _ = inst.debug_stall_mid_change("half-made", Duration::from_secs(4));
        }
        return;
    }
    let host = host("liveholder");
    let inst = host.instance().clone();
    let mut child = spawn_child(
        "a_live_holder_is_never_robbed_of_the_lock",
        "stall",
        inst.name(),
    );
    std::thread::sleep(Duration::from_millis(500));
    let t = Instant::now();
    let sigs = inst.signals().unwrap();
    // The holder gave up its change after 4 s; only then did we get in.
    assert!(
        t.elapsed() >= Duration::from_millis(2500),
        "{:?}",
        t.elapsed()
    );
    assert!(sigs.is_empty(), "the abandoned change was rolled back");
    assert!(child.wait().unwrap().success());
}
