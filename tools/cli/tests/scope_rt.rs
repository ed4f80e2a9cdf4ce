//! halscope (headless) driving scope_rt, the realtime half a
//! configuration loads (`loadrt scope_rt`, `addf scope.sample THREAD`):
//! records of a siggen through the shared region, with the trigger
//! point, pre-trigger and sample rate multiplier checked; and its
//! refusals. Each test on a private instance.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use hal_host::testing::InProcessHost;

use common::scope::{csv_rows, halscope, temp_dir};

/// siggen at 50 Hz in a 1 ms thread, scope_rt's function after it.
fn setup(num_samples: &str) -> String {
    format!(
        "loadrt siggen
loadrt scope_rt {num_samples}
loadrt threads name1=servo-thread period1=1000000 name2=other period2=2000000
addf siggen.0.update servo-thread
addf scope.sample servo-thread
setp siggen.0.frequency 50
net sq siggen.0.square
"
    )
}

#[test]
fn halscope_records_a_siggen_through_scope_rt_with_its_trigger() {
    let host = InProcessHost::start("scope-rt");
    let (ok, _, err) = host.run("setup.hal", &format!("{}start\n", setup("")), false);
    assert!(ok, "{err}");
    let dir = temp_dir("scope-rt-files");
    let csv = dir.join("c.csv");
    let (ok, out) = halscope(
        &host.instance,
        &[
            "--pins",
            "sq,siggen.0.sine,siggen.0.clock",
            "--trigger",
            "sq:rising:0.5",
            "--samples",
            "100",
            "--pre",
            "20%",
            "--out",
            csv.to_str().unwrap(),
        ],
    );
    assert!(ok, "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.starts_with("sample,time_ms,sq,siggen.0.sine,siggen.0.clock\n"),
        "{text}"
    );
    let rows = csv_rows(&text);
    assert_eq!(rows.len(), 100);
    for (i, (tag, t, _)) in rows.iter().enumerate() {
        assert_eq!(*tag, i as u32, "{text}");
        assert!((t - (i as f64 - 20.0)).abs() < 1e-9, "{text}");
    }
    let square = |i: usize| rows[i].2[0].parse::<f64>().unwrap();
    // 20 samples before the trigger; it is where the square goes up,
    // which it holds for 10 samples of 1 ms at 50 Hz.
    assert!(square(19) < 0.5 && square(20) >= 0.5, "{text}");
    assert!(
        (20..30).all(|i| square(i) >= 0.5) && square(30) < 0.5,
        "{text}"
    );
    assert!(rows.iter().all(|r| r.2[2] == "0" || r.2[2] == "1"));
    // The sine is a sine: consecutive samples 2π·50/1000 apart in phase.
    let sine = |i: usize| rows[i].2[1].parse::<f64>().unwrap();
    let step = 2.0 * std::f64::consts::PI * 50.0 / 1000.0;
    for i in 1..99 {
        let second = sine(i + 1) - 2.0 * step.cos() * sine(i) + sine(i - 1);
        assert!(second.abs() < 1e-6, "sample {i}: {text}");
    }
    // scope_rt sampled: halscope loaded no sampler of its own.
    let inst = host.instance();
    assert!(inst.component("sampler").unwrap().is_none());

    // Every 2nd period: the square holds a level for 5 samples 2 ms apart.
    let (ok, out) = halscope(
        &host.instance,
        &[
            "--pins",
            "sq",
            "--thread",
            "servo-thread",
            "--mult",
            "2",
            "--trigger",
            "0:falling:0.5",
            "--samples",
            "30",
            "--pre",
            "34%",
            "--out",
            csv.to_str().unwrap(),
        ],
    );
    assert!(ok, "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows = csv_rows(&text);
    assert_eq!(rows.len(), 30);
    assert!((rows[11].1 - rows[10].1 - 2.0).abs() < 1e-9, "{text}");
    let square = |i: usize| rows[i].2[0].parse::<f64>().unwrap();
    // The trigger sample is the 11th (34% of 30 before it).
    assert!(square(9) >= 0.5 && square(10) < 0.5, "{text}");
    assert!(
        (10..15).all(|i| square(i) < 0.5) && square(15) >= 0.5,
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn halscope_refuses_what_scope_rt_cannot_record() {
    let host = InProcessHost::start("scope-rt-refuse");
    let (ok, _, err) = host.run(
        "setup.hal",
        &format!("{}start\n", setup("num_samples=100")),
        false,
    );
    assert!(ok, "{err}");
    let dir = temp_dir("scope-rt-refuse-files");
    let csv = dir.join("c.csv");
    let csv = csv.to_str().unwrap();
    let refused = |args: &[&str], want: &str| {
        let mut v = args.to_vec();
        v.extend(["--out", csv]);
        let (ok, out) = halscope(&host.instance, &v);
        assert!(!ok && out.contains(want), "{args:?}: {out}");
    };
    // 100 words hold 50 samples of 2 channels.
    refused(
        &["--pins", "sq,siggen.0.sine", "--samples", "51"],
        "num_samples",
    );
    refused(
        &["--pins", "sq", "--thread", "other"],
        "scope_rt samples in 'servo-thread'",
    );
    let many: Vec<String> = (0..17).map(|_| "sq".to_string()).collect();
    refused(&["--pins", &many.join(",")], "1 to 16 channels");
    refused(&["--pins", "nothing.here"], "no pin, signal or parameter");
    refused(
        &["--pins", "sq", "--trigger", "x:rising:0"],
        "not a captured name",
    );
    // Bare, as LinuxCNC's configurations start its GUI: what this one is.
    let (ok, out) = halscope(&host.instance, &[]);
    assert!(!ok && out.contains("headless"), "{out}");
    // The record fits: 50 samples of 2 channels.
    let (ok, out) = halscope(
        &host.instance,
        &[
            "--pins",
            "sq,siggen.0.sine",
            "--samples",
            "50",
            "--out",
            csv,
        ],
    );
    assert!(ok, "{out}");
    assert_eq!(csv_rows(&std::fs::read_to_string(csv).unwrap()).len(), 50);
    // A stopped thread: scope.sample does not run.
    let (ok, _, err) = host.run("stop.hal", "stop\n", false);
    assert!(ok, "{err}");
    refused(&["--pins", "sq", "--samples", "5"], "does not run");
    // scope.sample in no thread.
    let (ok, _, err) = host.run("delf.hal", "delf scope.sample servo-thread\n", false);
    assert!(ok, "{err}");
    refused(&["--pins", "sq"], "addf scope.sample");
    let _ = std::fs::remove_dir_all(&dir);
}
