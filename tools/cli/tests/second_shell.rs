//! `realtime start`, then halcmd from other processes on the running
//! instance while its threads run, then `realtime stop`.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use common::{halcmd, run};

#[test]
fn halcmd_works_on_a_running_instance_from_another_process() {
    let inst = common::instance("shell");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    assert!(!run(realtime, &["status"], &inst).status.success());
    assert!(run(realtime, &["start"], &inst).status.success());
    assert!(run(realtime, &["status"], &inst).status.success());
    let second = run(realtime, &["start"], &inst);
    assert!(!second.status.success(), "a second start is refused");

    halcmd(&["loadrt", "threads", "name1=t", "period1=1000000"], &inst);
    halcmd(&["loadrt", "threadtest"], &inst);
    halcmd(&["addf", "threadtest.0.increment", "t"], &inst);
    halcmd(&["start"], &inst);
    // Threads run: the counter moves between two looks.
    let a = halcmd(&["getp", "threadtest.0.count"], &inst);
    std::thread::sleep(std::time::Duration::from_millis(50));
    let b = halcmd(&["getp", "threadtest.0.count"], &inst);
    assert_ne!(a, b, "the thread runs");
    // net, setp and show from this shell while it runs.
    halcmd(&["loadrt", "and2"], &inst);
    halcmd(&["addf", "and2.0", "t"], &inst);
    halcmd(&["net", "x", "and2.0.out"], &inst);
    halcmd(&["setp", "and2.0.in0", "1"], &inst);
    halcmd(&["setp", "and2.0.in1", "TRUE"], &inst);
    std::thread::sleep(std::time::Duration::from_millis(50));
    let show = halcmd(&["show", "pin", "and2.0.out"], &inst);
    assert!(show.contains("TRUE  and2.0.out ==> x"), "{show}");
    assert_eq!(halcmd(&["gets", "x"], &inst), "TRUE\n");
    let err = run(env!("CARGO_BIN_EXE_halcmd"), &["sets", "x", "0"], &inst);
    assert!(!err.status.success());
    assert!(String::from_utf8_lossy(&err.stderr).contains("signal 'x': not writable"));

    assert!(run(realtime, &["stop"], &inst).status.success());
    assert!(!run(realtime, &["status"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
    let gone = run(env!("CARGO_BIN_EXE_halcmd"), &["show"], &inst);
    assert!(String::from_utf8_lossy(&gone.stderr).contains("realtime not running"));
}

#[test]
fn halmeter_shows_a_pin_signal_and_param() {
    let inst = common::instance("meter");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    assert!(run(realtime, &["start"], &inst).status.success());
    halcmd(&["loadrt", "mult2"], &inst);
    halcmd(&["net", "prod", "mult2.0.out"], &inst);
    halcmd(&["setp", "mult2.0.in0", "2.5"], &inst);
    let meter = env!("CARGO_BIN_EXE_halmeter");
    let pin = run(meter, &["-n", "2", "-p", "1", "pin", "mult2.0.in0"], &inst);
    assert_eq!(
        String::from_utf8_lossy(&pin.stdout),
        "mult2.0.in0 = 2.5\nmult2.0.in0 = 2.5\n"
    );
    let sig = run(meter, &["-n", "1", "prod"], &inst);
    assert_eq!(String::from_utf8_lossy(&sig.stdout), "prod = 0\n");
    let param = run(meter, &["-n", "1", "param", "mult2.0.tmax"], &inst);
    assert_eq!(String::from_utf8_lossy(&param.stdout), "mult2.0.tmax = 0\n");
    let missing = run(meter, &["-n", "1", "nope"], &inst);
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr)
        .contains("no pin, signal or parameter named 'nope'"));
    assert!(run(realtime, &["stop"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}
