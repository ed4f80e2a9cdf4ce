//! halcmd `setthread`: a thread's switches changed from a HAL file after the
//! thread exists, applied whole or not at all.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::time::{Duration, Instant};

use hal_core::Value;
use hal_host::testing::InProcessHost;

fn s32(v: Value) -> i32 {
    match v {
        Value::S32(v) => v,
        v => panic!("not s32: {v:?}"),
    }
}

/// Waits until thread `name` has run `n` more cycles than now.
fn wait_cycles(inst: &hal_core::Instance, name: &str, n: u64) {
    let cycles = |inst: &hal_core::Instance| {
        inst.threads()
            .unwrap()
            .into_iter()
            .find(|t| t.name == name)
            .map_or(0, |t| t.cycles)
    };
    let target = cycles(inst) + n;
    let deadline = Instant::now() + Duration::from_secs(30);
    while cycles(inst) < target {
        assert!(Instant::now() < deadline, "thread {name} stalled");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The CPUs the OS thread of HAL thread `name` (in this process) may use.
fn affinity_of(name: &str) -> Vec<usize> {
    for task in std::fs::read_dir("/proc/self/task").unwrap() {
        let dir = task.unwrap().path();
        let comm = std::fs::read_to_string(dir.join("comm")).unwrap_or_default();
        if comm.trim_end() == format!("hal-{name}") {
            let tid: i32 = dir.file_name().unwrap().to_str().unwrap().parse().unwrap();
            return hal_core::realtime::thread_affinity(tid).unwrap();
        }
    }
    panic!("no OS thread for HAL thread {name}");
}

#[test]
fn setthread_changes_a_running_threads_switches_and_refuses_bad_lines_whole() {
    let host = InProcessHost::start("setthread");
    let inst = host.instance();
    let cpu = hal_core::realtime::allowed_cpus()[0];
    let (ok, _, err) = host.run(
        "setup.hal",
        &format!(
            "loadrt threads name1=t period1=1000000 name2=u period2=1000000\n\
             loadrt sum2 count=2\n\
             addf sum2.0 t\n\
             addf sum2.1 u\n\
             setthread t timing=0 cpu={cpu} missed=catch-up\n\
             start\n"
        ),
        false,
    );
    assert!(ok, "{err}");
    wait_cycles(&inst, "t", 50);
    wait_cycles(&inst, "u", 50);
    let t = inst
        .threads()
        .unwrap()
        .into_iter()
        .find(|t| t.name == "t")
        .unwrap();
    assert_eq!(t.cpu, Some(cpu));
    assert_eq!(affinity_of("t"), vec![cpu]);
    assert_eq!(s32(inst.param_value("sum2.0.tmax").unwrap()), 0, "untimed");
    assert!(s32(inst.param_value("sum2.1.tmax").unwrap()) > 0, "timed");
    // `show thread` and `save thread` tell, for this thread only.
    let switches = format!("timing=0 cpu={cpu} missed=catch-up");
    let (ok, shown, err) = host.run("show.hal", "show thread", false);
    assert!(ok, "{err}");
    assert_eq!(shown.matches("switches:").count(), 1, "{shown}");
    assert!(
        shown.contains(&format!("switches: {switches}\n")),
        "{shown}"
    );
    let (ok, saved, err) = host.run("save.hal", "save thread", false);
    assert!(ok, "{err}");
    assert!(
        saved.contains(&format!("setthread t {switches}\n")),
        "{saved}"
    );
    assert!(!saved.contains("setthread u"), "{saved}");

    // Each bad line says what is wrong and changes nothing, not even the
    // good switches before the bad one.
    for (line, says) in [
        ("setthread t timing=1 missed=later", "missed='later'"),
        ("setthread t timing=1 cpu=100000", "cpu=100000"),
        ("setthread nosuch timing=1", "nosuch"),
        ("setthread t", "setthread"),
        ("setthread t timing=1 speed=2", "unknown switch 'speed'"),
    ] {
        let (ok, _, err) = host.run("bad.hal", line, false);
        assert!(!ok, "{line} was accepted");
        assert!(err.contains(says), "{line}: {err}");
    }
    wait_cycles(&inst, "t", 20);
    assert_eq!(
        s32(inst.param_value("sum2.0.tmax").unwrap()),
        0,
        "still untimed"
    );
    assert_eq!(affinity_of("t"), vec![cpu]);

    // Back to the defaults.
    let (ok, _, err) = host.run(
        "back.hal",
        "setthread t cpu=default timing=1 missed=skip",
        false,
    );
    assert!(ok, "{err}");
    wait_cycles(&inst, "t", 20);
    assert!(
        s32(inst.param_value("sum2.0.tmax").unwrap()) > 0,
        "timed again"
    );
    let t = inst
        .threads()
        .unwrap()
        .into_iter()
        .find(|t| t.name == "t")
        .unwrap();
    assert_eq!(t.cpu, None);
    let (_, shown, _) = host.run("show.hal", "show thread", false);
    assert!(!shown.contains("switches"), "{shown}");
    let (_, saved, _) = host.run("save.hal", "save thread", false);
    assert!(!saved.contains("setthread"), "{saved}");
}
