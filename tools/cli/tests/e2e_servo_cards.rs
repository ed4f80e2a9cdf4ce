//! End-to-end: the servo machines on the simulated MOTENC-100 and
//! Servo-To-Go (tests/motenc-servo, tests/stg-servo; the machines are
//! configs/sim/*-servo-machine.hal) home on switch and index and reach
//! their commanded positions; the samples equal `expected` byte for byte.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use common::*;

/// The machine's samples (pos-cmd, pos-fb and home-state of three
/// joints per row) and the lines after them.
fn samples(text: &str) -> (Vec<Vec<f64>>, Vec<&str>) {
    let mut lines = text
        .lines()
        .skip_while(|l| l.starts_with("accepted (serial"));
    let n: usize = lines
        .next()
        .unwrap()
        .trim()
        .parse()
        .expect("the sample count");
    let rows: Vec<Vec<f64>> = lines
        .by_ref()
        .take(n)
        .map(|l| l.split_whitespace().map(|f| f.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), n);
    assert!(rows.iter().all(|r| r.len() == 9), "9 columns");
    (rows, lines.collect())
}

/// What every servo card machine must show.
fn homes_and_reaches_its_positions(name: &str, fault: &str, encoders: [&str; 3]) {
    let text = run_exact(name);
    let (rows, tail) = samples(&text);
    let state = |r: &Vec<f64>, j: usize| r[6 + j] as i32;
    // Z (sequence 0) homes alone, then X and Y together.
    let first_busy = |j: usize| rows.iter().position(|r| state(r, j) != 0).unwrap();
    let last_busy = |j: usize| rows.iter().rposition(|r| state(r, j) != 0).unwrap();
    assert!(last_busy(2) < first_busy(0), "{name}");
    assert_eq!(first_busy(0), first_busy(1), "{name}");
    // Every joint: search, back off, latch on the switch, wait for the
    // index, final move.
    for j in 0..3 {
        let mut seen: Vec<i32> = rows.iter().map(|r| state(r, j)).collect();
        seen.dedup();
        let mut it = seen.iter();
        for s in [7, 10, 12, 18, 21] {
            assert!(
                it.any(|v| *v == s),
                "{name}: joint {j} misses state {s}: {seen:?}"
            );
        }
    }
    // The servo loops follow within 0.1 mm everywhere.
    for r in &rows {
        for j in 0..3 {
            assert!((r[j] - r[3 + j]).abs() < 0.1, "{name}: joint {j} in {r:?}");
        }
    }
    // At HOME (45, 0, -2) after homing; then X 12.5 back, Y at 7.25, Z up
    // to its soft limit 0.5, the motors within 0.01 mm.
    assert!(rows.iter().any(|r| r[..3] == [45.0, 0.0, -2.0]), "{name}");
    let last = rows.last().unwrap();
    assert_eq!(last[..3], [32.5, 7.25, 0.5], "{name}");
    for j in 0..3 {
        assert!((last[j] - last[3 + j]).abs() <= 0.01, "{name}: {last:?}");
        assert!(
            text.contains(&format!("TRUE  joint.{j}.homed\n")),
            "{name}: {j}"
        );
    }
    // No fault; the encoders count from the index, which is HOME_OFFSET
    // (50, 20, 0) in joint positions.
    let values: Vec<&str> = tail.iter().rev().take(4).rev().copied().collect();
    assert_eq!(values[0], "FALSE", "{name}: {fault}");
    for (k, want) in [32.5 - 50.0, 7.25 - 20.0, 0.5].into_iter().enumerate() {
        let got: f64 = values[1 + k].parse().unwrap();
        assert!(
            (got - want).abs() <= 0.01,
            "{name}: {} = {got}",
            encoders[k]
        );
    }
}

#[test]
fn motenc_servo_machine_homes_on_index_and_reaches_its_positions() {
    homes_and_reaches_its_positions(
        "motenc-servo",
        "motenc.0.fault",
        [
            "motenc.0.enc-00-position",
            "motenc.0.enc-01-position",
            "motenc.0.enc-02-position",
        ],
    );
}

#[test]
fn stg_servo_machine_homes_on_index_and_reaches_its_positions() {
    homes_and_reaches_its_positions(
        "stg-servo",
        "stg.fault",
        ["stg.0.position", "stg.1.position", "stg.2.position"],
    );
}

/// configs/sim/motenc-servo.hal, stg-servo.hal and ppmc-usc-stepper.hal
/// (a stepper machine on a simulated Pico USC), as a user runs them: the
/// joints reach X 20, Y 10, Z -10 and the boards report no fault.
#[test]
fn the_servo_card_configs_run() {
    let dir = root().join("configs/sim");
    std::thread::scope(|s| {
        for (file, fault) in [
            ("motenc-servo.hal", "motenc.0.fault"),
            ("stg-servo.hal", "stg.fault"),
            ("ppmc-usc-stepper.hal", "ppmc.0.fault"),
        ] {
            let dir = &dir;
            s.spawn(move || {
                let out = halrun(dir, &["-f", file], file.trim_end_matches(".hal"));
                let text = String::from_utf8_lossy(&out.stdout);
                let err = String::from_utf8_lossy(&out.stderr);
                assert!(out.status.success(), "{file}: {err}");
                for (j, pos) in [(0, 20.0), (1, 10.0), (2, -10.0)] {
                    let fb: f64 = text
                        .lines()
                        .find(|l| l.ends_with(&format!("joint.{j}.pos-fb")))
                        .and_then(|l| l.split_whitespace().nth(3))
                        .and_then(|v| v.parse().ok())
                        .unwrap_or_else(|| panic!("{file}: no joint.{j}.pos-fb in\n{text}"));
                    assert!((fb - pos).abs() <= 0.01, "{file}: joint {j} at {fb}");
                }
                assert!(
                    text.lines().any(|l| l.contains(" FALSE ")
                        && l.ends_with(&format!("{fault} ==> board-fault"))),
                    "{file}: {text}"
                );
            });
        }
    });
}
