//! The integrators' per-thread switches: function timing on/off, the CPU
//! a thread runs on, and what a thread does with missed deadlines.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::sync::atomic::{AtomicU64, Ordering::*};
use std::sync::{Arc, Mutex};

use common::*;
use hal_core::*;

fn s32(v: Value) -> i32 {
    match v {
        Value::S32(v) => v,
        v => panic!("not s32: {v:?}"),
    }
}

#[test]
fn timing_off_leaves_time_at_zero_and_runs_every_function() {
    let host = host("timing");
    let mut b = host.new_rt_component("tm").unwrap();
    let counts: Vec<Arc<AtomicU64>> = (0..3).map(|_| Arc::new(AtomicU64::new(0))).collect();
    for (i, n) in counts.iter().enumerate() {
        let n = n.clone();
        b.funct(&format!("tm.f{i}"), false, move |_| {
            n.fetch_add(1, Relaxed);
            // Long enough that a timed function's `.time` is never 0.
            std::hint::black_box((0..200u64).sum::<u64>());
        })
        .unwrap();
    }
    b.ready().unwrap();
    host.create_thread("t", 200_000, true, None).unwrap();
    for i in 0..3 {
        host.addf(&format!("tm.f{i}"), "t", -1).unwrap();
    }
    assert_eq!(
        host.thread_options("t").unwrap(),
        (true, MissedDeadline::Skip)
    );
    host.set_thread_timing("t", false).unwrap();
    assert!(!host.thread_options("t").unwrap().0);
    host.start().unwrap();
    assert!(wait_until(30.0, || counts
        .iter()
        .all(|n| n.load(Relaxed) >= 200)));
    host.stop();
    let inst = host.instance();
    let cycles = inst.threads().unwrap()[0].cycles;
    for (i, n) in counts.iter().enumerate() {
        assert_eq!(n.load(Relaxed), cycles, "tm.f{i} ran every cycle");
        assert_eq!(s32(inst.pin_value(&format!("tm.f{i}.time")).unwrap()), 0);
        assert_eq!(s32(inst.param_value(&format!("tm.f{i}.tmax")).unwrap()), 0);
    }
    // The thread's own time is still measured.
    assert!(s32(inst.param_value("t.tmax").unwrap()) > 0);

    // Back on, the functions are timed again, through a signal too.
    inst.newsig("f1-time", HalType::S32).unwrap();
    inst.link("tm.f1.time", "f1-time").unwrap();
    host.set_thread_timing("t", true).unwrap();
    host.start().unwrap();
    assert!(wait_until(30.0, || {
        s32(inst.param_value("tm.f2.tmax").unwrap()) > 0
            && s32(inst.signal_value("f1-time").unwrap()) > 0
    }));
    host.stop();
}

#[test]
fn timing_switch_for_every_thread_applies_to_later_threads() {
    let host = host("timing-all");
    host.create_thread("a", 1_000_000, true, None).unwrap();
    host.set_function_timing(false);
    host.create_thread("b", 2_000_000, true, None).unwrap();
    assert!(!host.thread_options("a").unwrap().0);
    assert!(!host.thread_options("b").unwrap().0);
    host.set_function_timing(true);
    assert!(host.thread_options("a").unwrap().0);
    assert!(host.set_thread_timing("nope", false).is_err());
}

#[test]
fn the_cpu_choice_is_applied() {
    let allowed = realtime::allowed_cpus();
    let want = *allowed.last().expect("some CPU");
    let host = host("cpu");
    host.create_thread("t", 1_000_000, true, Some(want))
        .unwrap();
    host.create_thread("u", 2_000_000, true, None).unwrap();
    assert!(wait_until(30.0, || host
        .thread_affinity("t")
        .unwrap()
        .is_some()));
    assert_eq!(host.thread_affinity("t").unwrap().unwrap(), vec![want]);
    // Without realtime and without RTAPI_CPU_NUMBER, a thread may run
    // anywhere the process may.
    assert!(wait_until(30.0, || host
        .thread_affinity("u")
        .unwrap()
        .is_some()));
    assert_eq!(host.thread_affinity("u").unwrap().unwrap(), allowed);
    // Moved while it exists, and back.
    let first = allowed[0];
    host.set_thread_cpu("u", Some(first)).unwrap();
    assert_eq!(host.thread_affinity("u").unwrap().unwrap(), vec![first]);
    host.set_thread_cpu("u", None).unwrap();
    assert_eq!(host.thread_affinity("u").unwrap().unwrap(), allowed);
    // A CPU the process may not use is refused with a reason.
    let e = host.set_thread_cpu("u", Some(100_000)).unwrap_err();
    assert!(e.to_string().contains("100000"), "{e}");
}

#[test]
fn rtapi_cpu_number_places_every_thread_and_is_checked() {
    let allowed = realtime::allowed_cpus();
    let want = allowed[0];
    let mut cfg = HostConfig::for_tests("cpu-env");
    cfg.rt_cpu = Some(want.to_string());
    let host = Host::create(cfg).unwrap();
    host.create_thread("t", 1_000_000, true, None).unwrap();
    assert!(wait_until(30.0, || host
        .thread_affinity("t")
        .unwrap()
        .is_some()));
    assert_eq!(host.thread_affinity("t").unwrap().unwrap(), vec![want]);

    let mut bad = HostConfig::for_tests("cpu-env-bad");
    bad.rt_cpu = Some("eleven".into());
    let e = Host::create(bad).err().expect("refused");
    assert!(e.to_string().contains("RTAPI_CPU_NUMBER"), "{e}");
}

/// Runs a 1 ms thread whose function stalls for 5 ms on its third call and
/// records the deadline of every cycle; returns the deadlines and the
/// overrun count.
fn stall_once(policy: MissedDeadline) -> (Vec<u64>, u64) {
    let host = host("missed");
    let deadlines = Arc::new(Mutex::new(Vec::new()));
    let d2 = deadlines.clone();
    let mut b = host.new_rt_component("st").unwrap();
    b.funct("st.f", false, move |ctx| {
        let mut d = d2.lock().unwrap();
        d.push(ctx.deadline_ns());
        if d.len() == 3 {
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
    })
    .unwrap();
    b.ready().unwrap();
    host.create_thread("t", 1_000_000, true, None).unwrap();
    host.addf("st.f", "t", -1).unwrap();
    host.set_missed_deadline("t", policy).unwrap();
    assert_eq!(host.thread_options("t").unwrap().1, policy);
    host.start().unwrap();
    assert!(wait_until(30.0, || deadlines.lock().unwrap().len() >= 20));
    host.stop();
    let overruns = host.instance().threads().unwrap()[0].overruns;
    let d = deadlines.lock().unwrap().clone();
    (d, overruns)
}

#[test]
fn catch_up_runs_every_cycle_and_counts_late_ones() {
    let (d, overruns) = stall_once(MissedDeadline::CatchUp);
    assert!(
        d.windows(2).all(|w| w[1] - w[0] == 1_000_000),
        "one cycle per period, none skipped: {d:?}"
    );
    assert!(overruns >= 1, "overruns {overruns}");
}

#[test]
fn skip_drops_missed_deadlines_and_counts_each() {
    let (d, overruns) = stall_once(MissedDeadline::Skip);
    let skipped: u64 = d.windows(2).map(|w| (w[1] - w[0]) / 1_000_000 - 1).sum();
    assert!(skipped >= 4, "the stall's deadlines are skipped: {d:?}");
    assert!(
        overruns >= skipped,
        "overruns {overruns}, skipped {skipped}"
    );
    assert!(d.windows(2).all(|w| (w[1] - w[0]) % 1_000_000 == 0));
}
