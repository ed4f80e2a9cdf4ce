//! Threads and the executor: order, periods, overruns, structural changes
//! while running, faults, and mutual exclusion of HAL threads.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering::*};
use std::sync::{Arc, Mutex};

use common::*;
use hal_core::*;

#[test]
fn functions_run_in_insert_order_every_period() {
    let host = host("order");
    let log = Arc::new(Mutex::new(Vec::<u8>::new()));
    let mut b = host.new_rt_component("seq").unwrap();
    for (name, tag) in [
        ("seq.a", b'a'),
        ("seq.b", b'b'),
        ("seq.c", b'c'),
        ("seq.d", b'd'),
    ] {
        let log = log.clone();
        b.funct(name, false, move |_| log.lock().unwrap().push(tag))
            .unwrap();
    }
    b.ready().unwrap();
    assert_eq!(
        host.create_thread("fast", 200_000, true, None).unwrap(),
        200_000
    );
    host.addf("seq.b", "fast", -1).unwrap(); // b
    host.addf("seq.a", "fast", 1).unwrap(); // a b
    host.addf("seq.d", "fast", -1).unwrap(); // a b d
    host.addf("seq.c", "fast", -2).unwrap(); // a b c d
    assert_eq!(
        host.instance().threads().unwrap()[0].functs,
        ["seq.a", "seq.b", "seq.c", "seq.d"]
    );
    let beat = || match host.instance().pin_value("fast.threadbeat").unwrap() {
        Value::S64(v) => v,
        v => panic!("{v:?}"),
    };
    host.start().unwrap();
    assert!(wait_until(30.0, || beat() >= 1100));
    host.stop();
    let cycles = beat() as usize;
    let log = log.lock().unwrap();
    assert_eq!(log.len(), cycles * 4, "every function once per cycle");
    assert!(
        log.chunks(4).all(|c| c == b"abcd"),
        "order kept in every cycle"
    );
    let t = &host.instance().threads().unwrap()[0];
    assert_eq!(t.cycles as usize, cycles);
    assert_eq!(t.latency_histogram.iter().sum::<u64>(), t.cycles);
    // Per-function timing pins and params exist and were written.
    assert!(matches!(host.instance().param_value("seq.a.tmax").unwrap(), Value::S32(v) if v > 0));
}

#[test]
fn bad_addf_and_thread_requests_are_refused() {
    let host = host("addf");
    let mut b = host.new_rt_component("c").unwrap();
    b.funct("c.f", false, |_| {}).unwrap();
    b.funct_reentrant("c.r", false, |_| {}).unwrap();
    b.ready().unwrap();
    host.create_thread("t1", 100_000, true, None).unwrap();
    assert_eq!(
        host.create_thread("t2", 1_040_000, true, None).unwrap(),
        1_000_000,
        "rounded to a base multiple"
    );
    assert!(matches!(
        host.create_thread("t3", 50_000, true, None),
        Err(HalError::PeriodBelowBase { .. })
    ));
    assert!(matches!(
        host.create_thread("t3", 500_000, true, None),
        Err(HalError::ThreadOrder { .. })
    ));
    assert!(matches!(
        host.create_thread("t1", 2_000_000, true, None),
        Err(HalError::Duplicate { kind: "thread", .. })
    ));
    assert!(matches!(
        host.create_thread("t4", 0, true, None),
        Err(HalError::ZeroPeriod { .. })
    ));
    assert!(matches!(
        host.addf("c.f", "t1", 3),
        Err(HalError::BadPosition { .. })
    ));
    assert!(matches!(
        host.addf("c.f", "t1", 0),
        Err(HalError::BadPosition { .. })
    ));
    assert!(matches!(
        host.addf("nope", "t1", -1),
        Err(HalError::NotFound {
            kind: "function",
            ..
        })
    ));
    assert!(matches!(
        host.addf("c.f", "nope", -1),
        Err(HalError::NotFound { kind: "thread", .. })
    ));
    host.addf("c.f", "t1", -1).unwrap();
    assert!(matches!(
        host.addf("c.f", "t2", -1),
        Err(HalError::FunctInUse { .. })
    ));
    host.addf("c.r", "t1", -1).unwrap();
    host.addf("c.r", "t2", -1).unwrap();
    assert!(matches!(
        host.delf("c.f", Some("t2")),
        Err(HalError::FunctNotInThread { .. })
    ));
    host.delf("c.f", None).unwrap();
    host.addf("c.f", "t2", 1).unwrap();
    let th = host.instance().threads().unwrap();
    assert_eq!(th[0].name, "t2", "slowest first");
    assert_eq!(th[0].functs, ["c.f", "c.r"]);
    assert_eq!(th[1].functs, ["c.r"]);
    host.unload("c").unwrap();
    assert!(host
        .instance()
        .threads()
        .unwrap()
        .iter()
        .all(|t| t.functs.is_empty()));
    assert!(host.instance().functs().unwrap().is_empty());
    host.delete_thread("t2").unwrap();
    assert_eq!(host.instance().threads().unwrap().len(), 1);
    assert!(host
        .instance()
        .components()
        .unwrap()
        .iter()
        .all(|c| c.name != "__t2"));
}

#[test]
fn overruns_are_counted() {
    let host = host("overrun");
    let mut b = host.new_rt_component("slow").unwrap();
    let calls = Arc::new(AtomicU64::new(0));
    let c2 = calls.clone();
    b.funct("slow.sleep", false, move |_| {
        if c2.fetch_add(1, Relaxed) % 2 == 0 {
            std::thread::sleep(std::time::Duration::from_millis(3));
        }
    })
    .unwrap();
    b.ready().unwrap();
    host.create_thread("t", 1_000_000, true, None).unwrap();
    host.addf("slow.sleep", "t", -1).unwrap();
    host.start().unwrap();
    assert!(wait_until(10.0, || calls.load(Relaxed) >= 10));
    host.stop();
    let t = &host.instance().threads().unwrap()[0];
    assert!(t.overruns >= 5, "overruns {}", t.overruns);
    assert!(
        matches!(host.instance().param_value("t.tmax").unwrap(), Value::S32(v) if v >= 3_000_000)
    );
}

#[test]
fn nets_change_while_threads_run() {
    let host = host("livenet");
    let inst = host.instance().clone();
    let mut b = host.new_rt_component("cp").unwrap();
    let input: Pin<f64, In> = b.component().pin("cp.in").unwrap();
    let output: Pin<f64, Out> = b.component().pin("cp.out").unwrap();
    b.funct("cp", true, move |_| output.set(input.get() + 1.0))
        .unwrap();
    b.ready().unwrap();
    let src = inst.new_component("src", ComponentKind::User).unwrap();
    let drive: Pin<f64, Out> = src.pin("src.out").unwrap();
    let sink: Pin<f64, In> = src.pin("src.in").unwrap();
    host.create_thread("t", 100_000, true, None).unwrap();
    host.addf("cp", "t", -1).unwrap();
    host.start().unwrap();
    for i in 0..200 {
        inst.newsig("a", HalType::Float).unwrap();
        inst.newsig("b", HalType::Float).unwrap();
        inst.link("src.out", "a").unwrap();
        inst.link("cp.in", "a").unwrap();
        inst.link("cp.out", "b").unwrap();
        inst.link("src.in", "b").unwrap();
        drive.set(i as f64);
        assert!(
            wait_until(5.0, || sink.get() == i as f64 + 1.0),
            "value flows through the running thread"
        );
        if i % 2 == 0 {
            inst.delsig("a").unwrap();
            inst.delsig("b").unwrap();
        } else {
            for p in ["src.out", "cp.in", "cp.out", "src.in"] {
                inst.unlink(p).unwrap();
            }
            inst.delsig_all().unwrap();
        }
    }
    host.stop();
}

#[test]
fn a_panicking_function_halts_threads_and_calls_safe_state() {
    let host = host("panic");
    let safe = Arc::new(AtomicBool::new(false));
    let mut b = host.new_rt_component("bad").unwrap();
    let n = Arc::new(AtomicU64::new(0));
    let n2 = n.clone();
    b.funct("bad.f", false, move |_| {
        if n2.fetch_add(1, Relaxed) == 20 {
            panic!("deliberate test panic");
        }
    })
    .unwrap();
    let s2 = safe.clone();
    b.on_safe_state(move || s2.store(true, SeqCst));
    b.ready().unwrap();
    host.create_thread("t", 200_000, true, None).unwrap();
    host.addf("bad.f", "t", -1).unwrap();
    host.start().unwrap();
    assert!(
        wait_until(10.0, || safe.load(SeqCst)),
        "safe-state hook called"
    );
    assert_eq!(host.fault().as_deref(), Some("bad.f"));
    assert!(!host.is_running());
    assert!(
        host.instance()
            .threads()
            .unwrap()
            .iter()
            .all(|t| !t.running),
        "a halted thread is shown stopped"
    );
    let calls = n.load(SeqCst);
    std::thread::sleep(std::time::Duration::from_millis(20));
    assert_eq!(n.load(SeqCst), calls, "threads stay halted");
    assert!(matches!(host.start(), Err(HalError::Faulted { .. })));
    // The instance stays inspectable.
    assert_eq!(host.instance().functs().unwrap()[0].name, "bad.f");
}

#[test]
fn fast_thread_increments_slow_thread_resets_without_realtime() {
    threads_test(RealtimeMode::Off);
}

#[test]
fn fast_thread_increments_slow_thread_resets_with_realtime_if_permitted() {
    threads_test(RealtimeMode::Auto);
}

/// LinuxCNC's threads test: a fast thread increments a counter with a
/// read-modify-write, a slow one resets it. Every value the fast thread
/// sees is its previous value + 1, or 1 right after a reset.
/// The counter lives in one signal: the increment reads and writes it
/// through an io pin in the fast thread, the reset writes it through
/// another io pin in the slow thread.
fn threads_test(realtime: RealtimeMode) {
    let host = host_with("threads", realtime);
    let inst = host.instance().clone();
    let mut b = host.new_rt_component("threadtest").unwrap();
    let count: Pin<u32, Io> = b.component().pin("threadtest.0.count").unwrap();
    let zero: Pin<u32, Io> = b.component().pin("threadtest.0.zero").unwrap();
    let mut ring = RingWriter::create(b.component(), "threadtest.samples", 8192, 1).unwrap();
    b.funct("threadtest.0.increment", false, move |_| {
        let v = count.get().wrapping_add(1);
        count.set(v);
        ring.push(&[v as u64]);
    })
    .unwrap();
    b.funct("threadtest.0.reset", false, move |_| zero.set(0))
        .unwrap();
    b.ready().unwrap();
    inst.newsig("count", HalType::U32).unwrap();
    inst.link("threadtest.0.count", "count").unwrap();
    inst.link("threadtest.0.zero", "count").unwrap();
    let mut reader = RingReader::open(&inst, "threadtest.samples").unwrap();
    host.create_thread("fast", 100_000, true, None).unwrap();
    host.create_thread("slow", 1_000_000, true, None).unwrap();
    host.addf("threadtest.0.increment", "fast", -1).unwrap();
    host.addf("threadtest.0.reset", "slow", -1).unwrap();
    host.start().unwrap();
    let mut samples = Vec::new();
    let mut rec = [0u64; 1];
    let ok = wait_until(60.0, || {
        while reader.pop(&mut rec) {
            samples.push(rec[0] as u32);
        }
        samples.len() >= 3500
    });
    host.stop();
    assert!(ok, "got {} samples", samples.len());
    samples.truncate(3500);
    assert_eq!(samples[0], 1);
    let mut resets = 0;
    for w in samples.windows(2) {
        if w[1] == 1 {
            resets += 1;
        } else {
            assert_eq!(w[1], w[0] + 1, "increment raced with reset: {samples:?}");
        }
    }
    assert!(resets > 0);
}

#[test]
fn a_builder_dropped_after_addf_leaves_nothing_running() {
    let host = host("builderdrop");
    host.create_thread("t", 100_000, true, None).unwrap();
    let calls = Arc::new(AtomicU64::new(0));
    {
        let mut b = host.new_rt_component("half").unwrap();
        let c2 = calls.clone();
        b.funct("half.f", false, move |_| {
            c2.fetch_add(1, Relaxed);
        })
        .unwrap();
        host.addf("half.f", "t", -1).unwrap();
        host.start().unwrap();
        assert!(wait_until(10.0, || calls.load(Relaxed) > 10));
        // Dropped without ready(): as if its set-up failed.
    }
    let n = calls.load(Relaxed);
    std::thread::sleep(std::time::Duration::from_millis(20));
    assert_eq!(calls.load(Relaxed), n, "the function no longer runs");
    assert!(host.instance().threads().unwrap()[0].functs.is_empty());
    assert!(host.instance().functs().unwrap().is_empty());
    assert!(host
        .instance()
        .components()
        .unwrap()
        .iter()
        .all(|c| c.name != "half"));
    host.stop();
}

#[test]
fn init_functions_run_once_before_the_list() {
    let host = host("initf");
    let log = Arc::new(Mutex::new(Vec::<u8>::new()));
    let mut b = host.new_rt_component("c").unwrap();
    for (name, tag) in [("c.init", b'i'), ("c.cycle", b'c')] {
        let log = log.clone();
        b.funct(name, false, move |_| log.lock().unwrap().push(tag))
            .unwrap();
    }
    b.ready().unwrap();
    host.create_thread("t", 200_000, true, None).unwrap();
    host.addf("c.cycle", "t", -1).unwrap();
    host.initf("c.init", "t").unwrap();
    assert_eq!(
        host.instance().threads().unwrap()[0].init_functs,
        ["c.init"]
    );
    host.start().unwrap();
    assert!(wait_until(10.0, || log.lock().unwrap().len() >= 20));
    host.stop();
    let log = log.lock().unwrap();
    assert_eq!(log[0], b'i', "the init cycle comes first");
    assert!(
        log[1..].iter().all(|&t| t == b'c'),
        "init runs once and replaces the first cycle"
    );
    assert!(
        matches!(host.initf("c.init", "t"), Err(HalError::BadValue { .. })),
        "too late after the init cycle"
    );
}

#[test]
fn a_faster_thread_runs_first_when_both_are_due() {
    // Without realtime there are no priorities; the executor still keeps
    // LinuxCNC's order. Repeated, since the failure was a race.
    for round in 0..25 {
        let host = host("order-fast");
        let fast_calls = Arc::new(AtomicU64::new(0));
        let seen_by_slow = Arc::new(Mutex::new(Vec::new()));
        let mut b = host.new_rt_component("c").unwrap();
        let f = fast_calls.clone();
        b.funct("c.fast", false, move |_| {
            f.fetch_add(1, SeqCst);
        })
        .unwrap();
        let (f, s) = (fast_calls.clone(), seen_by_slow.clone());
        b.funct("c.slow", false, move |_| {
            s.lock().unwrap().push(f.load(SeqCst))
        })
        .unwrap();
        b.ready().unwrap();
        host.create_thread("fast", 100_000, true, None).unwrap();
        host.create_thread("slow", 500_000, true, None).unwrap();
        host.addf("c.fast", "fast", -1).unwrap();
        host.addf("c.slow", "slow", -1).unwrap();
        host.start().unwrap();
        assert!(wait_until(10.0, || !seen_by_slow
            .lock()
            .unwrap()
            .is_empty()));
        host.stop();
        let first = seen_by_slow.lock().unwrap()[0];
        assert!(
            first >= 1,
            "round {round}: the slow thread's first cycle ran before the fast thread's"
        );
    }
}

/// What the `owner` test module's closures hold, as the test sees it: weak
/// references that die with the module, and its function's call count.
struct Owned {
    funct_data: std::sync::Weak<AtomicU64>,
    hook_data: std::sync::Weak<AtomicU64>,
}

/// The last load of `owner` per instance (tests run side by side).
static OWNED: Mutex<Vec<(String, Owned)>> = Mutex::new(Vec::new());

fn load_owner(host: &Host, _: &ModuleArgs) -> Result<()> {
    let mut b = host.new_rt_component("own")?;
    let _: Pin<f64, Out> = b.component().pin("own.out")?;
    let _: Param<u32, Rw> = b.component().param("own.k", 3)?;
    let calls = Arc::new(AtomicU64::new(0));
    let in_hook = Arc::new(AtomicU64::new(0));
    let mut owned = OWNED.lock().unwrap();
    owned.retain(|(i, _)| i != host.instance().name());
    owned.push((
        host.instance().name().to_string(),
        Owned {
            funct_data: Arc::downgrade(&calls),
            hook_data: Arc::downgrade(&in_hook),
        },
    ));
    b.funct("own.tick", false, move |_| {
        calls.fetch_add(1, Relaxed);
    })?;
    b.on_safe_state(move || {
        in_hook.fetch_add(1, Relaxed);
    });
    b.ready()
}

static OWNER: ModuleDef = ModuleDef {
    name: "owner",
    params: &[],
    help: "a test module whose function and safe-state hook own data",
    load: load_owner,
};

/// Calls of `own.tick` so far, while the module is loaded.
fn owner_calls(host: &Host) -> Option<u64> {
    let owned = OWNED.lock().unwrap();
    let (_, o) = owned.iter().find(|(i, _)| i == host.instance().name())?;
    o.funct_data.upgrade().map(|c| c.load(Relaxed))
}

/// Asserts that nothing of `owner` is left: its closures' data dropped,
/// its objects found by no name.
fn assert_owner_gone(host: &Host, when: &str) {
    {
        let owned = OWNED.lock().unwrap();
        let (_, o) = owned
            .iter()
            .find(|(i, _)| i == host.instance().name())
            .unwrap();
        assert!(
            o.funct_data.upgrade().is_none(),
            "{when}: the function's data outlives the unload"
        );
        assert!(
            o.hook_data.upgrade().is_none(),
            "{when}: the safe-state hook's data outlives the unload"
        );
    }
    let inst = host.instance();
    assert!(inst.component("own").unwrap().is_none(), "{when}");
    assert!(inst.pin("own.out").unwrap().is_none(), "{when}");
    assert!(inst.param("own.k").unwrap().is_none(), "{when}");
    assert!(inst.pin_value("own.out").is_err(), "{when}");
    assert!(inst.functs().unwrap().iter().all(|f| f.name != "own.tick"));
    assert!(inst.threads().unwrap()[0].functs.is_empty(), "{when}");
    assert!(matches!(
        host.addf("own.tick", "t", -1),
        Err(HalError::NotFound {
            kind: "function",
            ..
        })
    ));
}

/// Regression: with threads stopped, a function taken out of a thread
/// stayed on the executor's list (rebuilt only at the next start), and
/// that list kept the function's closure, and all it held, alive after
/// `unloadrt`: on hardware, a device left open.
#[test]
fn unload_drops_what_the_module_owns_and_reload_works() {
    for when in ["stopped after running", "running", "never started"] {
        let host = host("ownership");
        host.create_thread("t", 100_000, true, None).unwrap();
        for round in 0..2 {
            host.loadrt(&OWNER, &[] as &[&str]).unwrap();
            let inst = host.instance();
            assert!(inst.component("own").unwrap().is_some(), "{when} {round}");
            assert_eq!(inst.param_value("own.k").unwrap(), Value::U32(3));
            host.addf("own.tick", "t", -1).unwrap();
            if when != "never started" {
                if !host.is_running() {
                    host.start().unwrap();
                }
                assert!(
                    wait_until(10.0, || owner_calls(&host).unwrap_or(0) > 5),
                    "{when} {round}: the function runs"
                );
            }
            if when == "stopped after running" {
                host.stop();
            }
            host.unloadrt("owner").unwrap();
            assert_owner_gone(&host, when);
        }
        host.stop();
    }
}

fn load_gone(host: &Host, _: &ModuleArgs) -> Result<()> {
    let mut b = host.new_rt_component("gone")?;
    for i in 0..4 {
        b.funct(&format!("gone.f{i}"), false, |_| {})?;
    }
    b.ready()
}

static GONE: ModuleDef = ModuleDef {
    name: "gone",
    params: &[],
    help: "a test module with four functions",
    load: load_gone,
};

/// Removing a component takes all its functions out of a thread in one
/// pass (teardown grew with N² when each function searched the list): the
/// others stay in order, and the list's end is kept, so a later append
/// lands last.
#[test]
fn unload_takes_every_function_out_of_an_interleaved_thread() {
    let host = host("interleaved");
    host.create_thread("t", 1_000_000, true, None).unwrap();
    let mut b = host.new_rt_component("keep").unwrap();
    for name in ["keep.a", "keep.b", "keep.c", "keep.late"] {
        b.funct(name, false, |_| {}).unwrap();
    }
    b.ready().unwrap();
    host.loadrt(&GONE, &[] as &[&str]).unwrap();
    for name in [
        "gone.f0", "keep.a", "gone.f1", "keep.b", "gone.f2", "keep.c", "gone.f3",
    ] {
        host.addf(name, "t", -1).unwrap();
    }
    host.unloadrt("gone").unwrap();
    let threads = host.instance().threads().unwrap();
    assert_eq!(threads[0].functs, ["keep.a", "keep.b", "keep.c"]);
    host.addf("keep.late", "t", -1).unwrap();
    assert_eq!(
        host.instance().threads().unwrap()[0].functs,
        ["keep.a", "keep.b", "keep.c", "keep.late"]
    );
    // A second, emptying removal leaves an empty list that takes appends.
    host.delf("keep.a", Some("t")).unwrap();
    host.delf("keep.b", Some("t")).unwrap();
    host.delf("keep.c", Some("t")).unwrap();
    host.delf("keep.late", Some("t")).unwrap();
    host.loadrt(&GONE, &[] as &[&str]).unwrap();
    host.addf("gone.f2", "t", -1).unwrap();
    host.unloadrt("gone").unwrap();
    assert!(host.instance().threads().unwrap()[0].functs.is_empty());
    host.addf("keep.b", "t", -1).unwrap();
    host.addf("keep.a", "t", -1).unwrap();
    assert_eq!(
        host.instance().threads().unwrap()[0].functs,
        ["keep.b", "keep.a"]
    );
}

#[test]
fn start_returns_with_every_thread_shown_running_and_stop_with_none() {
    let host = host("shownrun");
    for (name, period) in [("fast", 100_000), ("slow", 1_000_000), ("idle", 5_000_000)] {
        host.create_thread(name, period, true, None).unwrap();
    }
    let running = |host: &Host| -> Vec<(String, bool)> {
        let mut v: Vec<_> = host
            .instance()
            .threads()
            .unwrap()
            .into_iter()
            .map(|t| (t.name, t.running))
            .collect();
        v.sort();
        v
    };
    // Repeated, since the race this guards (a query between `start` and
    // a thread's first wake-up) is a matter of timing.
    for round in 0..50 {
        host.start().unwrap();
        assert!(
            running(&host).iter().all(|(_, r)| *r),
            "round {round}: right after start: {:?}",
            running(&host)
        );
        host.stop();
        assert!(
            running(&host).iter().all(|(_, r)| !*r),
            "round {round}: right after stop: {:?}",
            running(&host)
        );
    }
    // A thread made while the others run starts at once and says so.
    host.start().unwrap();
    host.create_thread("late", 10_000_000, true, None).unwrap();
    assert!(
        running(&host).iter().all(|(_, r)| *r),
        "{:?}",
        running(&host)
    );
    host.stop();
    host.create_thread("later", 20_000_000, true, None).unwrap();
    assert!(
        running(&host).iter().all(|(_, r)| !*r),
        "{:?}",
        running(&host)
    );
}

/// A cycle that ends after the thread's next deadline: under SCHED_FIFO
/// the host says so once, in LinuxCNC's words, however many cycles are
/// late; without realtime, late cycles are only counted (as in LinuxCNC,
/// which says nothing when it runs without SCHED_FIFO).
#[test]
fn a_late_realtime_cycle_is_reported_once() {
    let host = host_with("late", RealtimeMode::Auto);
    let log = host.rt_log();
    let mut b = host.new_rt_component("slowfunct").unwrap();
    let calls = Arc::new(AtomicUsize::new(0));
    let seen = calls.clone();
    b.funct("slowfunct.0.run", false, move |_| {
        seen.fetch_add(1, SeqCst);
        std::thread::sleep(std::time::Duration::from_millis(3));
    })
    .unwrap();
    b.ready().unwrap();
    host.create_thread("servo", 1_000_000, true, None).unwrap();
    host.addf("slowfunct.0.run", "servo", -1).unwrap();
    host.start().unwrap();
    assert!(
        wait_until(20.0, || calls.load(SeqCst) >= 5),
        "5 late cycles ran"
    );
    host.stop();
    host.flush_rt_log();
    let history = log.history();
    let reports: Vec<_> = history
        .iter()
        .filter(|(_, text)| text.starts_with("Unexpected realtime delay"))
        .collect();
    if host.is_realtime() {
        assert_eq!(reports.len(), 1, "said once: {history:?}");
        let (level, text) = reports[0];
        assert_eq!(*level, MsgLevel::Err);
        assert_eq!(
            text.as_str(),
            "Unexpected realtime delay on task 0 with period 1000000\n\
             This Message will only display once per session.\n\
             Run the Latency Test and resolve before continuing.\n"
        );
    } else {
        assert!(
            reports.is_empty(),
            "no report without realtime: {history:?}"
        );
    }
}
