//! M62 to M68 and M66 on the simulated mill: outputs at once and with
//! the next move (`motion.digital-out-NN`, `motion.analog-out-NN`), and
//! a program waiting on `motion.digital-in-NN` / reading
//! `motion.analog-in-NN` into #5399, with the timeout's −1.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use machine::{mill_copy, Machine, Scratch};
use std::time::{Duration, Instant};

fn float(m: &Machine, pin: &str) -> f64 {
    m.getp(pin).parse().unwrap()
}

fn run(m: &Machine, prog: &std::path::Path) {
    m.task_ok(&["open", prog.to_str().unwrap()]);
    m.task_ok(&["run"]);
}

fn wait_done(m: &Machine) -> (bool, String) {
    let (ok, out, err) = m.task(&["-t", "60", "wait-done"]);
    (ok, format!("{out}{err}"))
}

#[test]
fn outputs_follow_the_program_and_m66_waits_on_inputs() {
    let s = Scratch::new("motion-io");
    let ini = mill_copy(&s);
    let main = s.write(
        "io.ngc",
        "G21 G90\nM64 P0\nG1 X2 F600\nM62 P1\nG1 X4\nM67 E0 Q2.5\nG1 X5\n\
         M66 P2 L3 Q30\nM68 E1 Q#5399\nG0 X6\nM65 P0\nM2\n",
    );
    let timeout = s.write(
        "timeout.ngc",
        "G21 G90\nM66 P3 L3 Q0.3\nM68 E1 Q#5399\nM66 E0 L0\nM68 E2 Q#5399\nM2\n",
    );
    let bad = s.write("bad.ngc", "G21 G90\nG0 X1\nM66 P9 L0\nM2\n");
    let m = Machine::start(&ini, "motion-io");
    m.on_and_homed();
    m.task_ok(&["mode", "auto"]);

    run(&m, &main);
    // Waiting at M66 on digital-in-02, after X5.
    let end = Instant::now() + Duration::from_secs(30);
    while (float(&m, "joint.0.pos-cmd") - 5.0).abs() > 1e-9 {
        assert!(Instant::now() < end, "X5 not reached\n{}", m.stderr());
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(300));
    assert!((float(&m, "joint.0.pos-cmd") - 5.0).abs() < 1e-9, "waits");
    assert_eq!(m.getp("motion.digital-out-00"), "TRUE");
    assert_eq!(m.getp("motion.digital-out-01"), "TRUE");
    assert_eq!(float(&m, "motion.analog-out-00"), 2.5);
    assert!(m.task_ok(&["status"]).contains("interp: RUNNING"));
    m.halcmd(&["setp", "motion.digital-in-02", "TRUE"]);
    let (ok, out) = wait_done(&m);
    assert!(ok, "{out}\n--- linuxcnc:\n{}", m.stderr());
    assert!((float(&m, "joint.0.pos-cmd") - 6.0).abs() < 1e-9);
    assert_eq!(float(&m, "motion.analog-out-01"), 1.0, "#5399 read 1");
    assert_eq!(m.getp("motion.digital-out-00"), "FALSE");

    // The timeout gives -1; an analog input is read at once.
    m.halcmd(&["setp", "motion.analog-in-00", "3.25"]);
    run(&m, &timeout);
    let (ok, out) = wait_done(&m);
    assert!(ok, "{out}\n--- linuxcnc:\n{}", m.stderr());
    assert_eq!(float(&m, "motion.analog-out-01"), -1.0);
    assert_eq!(float(&m, "motion.analog-out-02"), 3.25);

    // An input motion does not have stops the program at its line.
    run(&m, &bad);
    let (ok, out) = wait_done(&m);
    assert!(!ok && out.contains("bad.ngc:3"), "{out}");
    m.stop();
}
