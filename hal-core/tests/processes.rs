//! Several processes on one instance.

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
