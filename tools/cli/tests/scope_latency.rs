//! halscope (headless) and latency-test end to end, each test on a
//! private instance of its own.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::process::Command;

use hal_host::testing::InProcessHost;

use common::scope::{csv_rows, halscope, temp_dir};

const SIGGEN: &str = "\
loadrt siggen
loadrt threads name1=servo-thread period1=1000000
addf siggen.0.update servo-thread
setp siggen.0.frequency 50
net sq siggen.0.square
";

#[test]
fn halscope_triggers_on_a_siggen_square_with_pre_trigger() {
    let host = InProcessHost::start("scope-own");
    let (ok, _, err) = host.run("setup.hal", &format!("{SIGGEN}start\n"), false);
    assert!(ok, "{err}");
    let dir = temp_dir("scope-own-files");
    let csv = dir.join("c.csv");
    let png = dir.join("c.png");
    let vcd = dir.join("c.vcd");
    let (ok, out) = halscope(
        &host.instance,
        &[
            "--pins",
            "sq,siggen.0.sine,siggen.0.clock",
            "--thread",
            "servo-thread",
            "--trigger",
            "sq:rising:0.5",
            "--samples",
            "100",
            "--pre",
            "20%",
            "--out",
            csv.to_str().unwrap(),
            "--out",
            png.to_str().unwrap(),
            "--out",
            vcd.to_str().unwrap(),
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
    // Consecutive samples, 1 ms apart, the trigger sample at 0 ms.
    for (i, (tag, t, _)) in rows.iter().enumerate() {
        assert_eq!(*tag, rows[0].0 + i as u32, "{text}");
        assert!((t - (i as f64 - 20.0)).abs() < 1e-9, "{text}");
    }
    let square = |i: usize| rows[i].2[0].parse::<f64>().unwrap();
    // 20 pre-trigger samples; the trigger is where the square goes up.
    assert!(square(19) < 0.5 && square(20) >= 0.5, "{text}");
    // 50 Hz at 1 kHz: the square holds each level for 10 samples.
    assert!(
        (20..30).all(|i| square(i) >= 0.5) && square(30) < 0.5,
        "{text}"
    );
    // The clock is a bit pin, recorded as 0/1.
    assert!(rows.iter().all(|r| r.2[2] == "0" || r.2[2] == "1"));
    let png_bytes = std::fs::read(&png).unwrap();
    assert!(png_bytes.starts_with(b"\x89PNG\r\n\x1a\n"));
    let vcd_text = std::fs::read_to_string(&vcd).unwrap();
    assert!(vcd_text.contains("$var real 64 ! sq $end"), "{vcd_text}");
    assert!(
        vcd_text.contains("$var wire 1 # siggen.0.clock $end"),
        "{vcd_text}"
    );
    assert!(vcd_text.contains("trigger at 20000000 ns"), "{vcd_text}");
    // Nothing of halscope's stays behind: no sampler, no signals of its own.
    let inst = host.instance();
    assert!(inst.component("sampler").unwrap().is_none());
    assert!(inst
        .signals()
        .unwrap()
        .iter()
        .all(|s| !s.name.starts_with("halscope-")));
    assert!(inst.pin("siggen.0.sine").unwrap().unwrap().signal.is_none());
    // A second capture works the same (nothing was left loaded).
    let (ok, out) = halscope(
        &host.instance,
        &[
            "--pins",
            "sq",
            "--thread",
            "servo-thread",
            "--samples",
            "5",
            "--out",
            csv.to_str().unwrap(),
        ],
    );
    assert!(ok, "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn halscope_refuses_what_it_cannot_capture() {
    let host = InProcessHost::start("scope-bad");
    let (ok, _, err) = host.run("setup.hal", &format!("{SIGGEN}start\n"), false);
    assert!(ok, "{err}");
    let dir = temp_dir("scope-bad-files");
    let csv = dir.join("c.csv");
    let csv = csv.to_str().unwrap();
    for (args, says) in [
        (
            vec!["--pins", "nope", "--thread", "servo-thread"],
            "neither a pin nor a signal",
        ),
        (
            vec!["--pins", "siggen.0.amplitude", "--thread", "servo-thread"],
            "input on no signal",
        ),
        (
            vec!["--pins", "sq", "--thread", "fast"],
            "thread 'fast' does not exist",
        ),
        (
            vec![
                "--pins",
                "sq",
                "--thread",
                "servo-thread",
                "--trigger",
                "x:rising:1",
            ],
            "not a captured name",
        ),
    ] {
        let mut a = args.clone();
        a.extend(["--out", csv]);
        let (ok, out) = halscope(&host.instance, &a);
        assert!(!ok && out.contains(says), "{args:?}: {out}");
    }
    // A trigger that never comes times out, and the sampler goes again.
    let (ok, out) = halscope(
        &host.instance,
        &[
            "--pins",
            "sq",
            "--thread",
            "servo-thread",
            "--trigger",
            "sq:rising:5",
            "--timeout",
            "0.3",
            "--out",
            csv,
        ],
    );
    assert!(!ok && out.contains("no trigger"), "{out}");
    assert!(host.instance().component("sampler").unwrap().is_none());
    assert!(!std::path::Path::new(csv).exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn halscope_csv_matches_halsampler_of_the_same_pins() {
    let host = InProcessHost::start("scope-chan");
    let setup = "\
loadrt siggen
loadrt threads name1=servo-thread period1=1000000
loadrt sampler cfg=fb,fb depth=60000,60000
setp siggen.0.frequency 37
net tri siggen.0.triangle sampler.0.pin.0 sampler.1.pin.0
net clk siggen.0.clock sampler.0.pin.1 sampler.1.pin.1
addf siggen.0.update servo-thread
addf sampler.0 servo-thread
addf sampler.1 servo-thread
start
";
    let (ok, _, err) = host.run("setup.hal", setup, false);
    assert!(ok, "{err}");
    let dir = temp_dir("scope-chan-files");
    let csv = dir.join("c.csv");
    let (ok, out) = halscope(
        &host.instance,
        &[
            "--channel",
            "0",
            "--trigger",
            "tri:falling:0",
            "--samples",
            "60",
            "--pre",
            "25%",
            "--out",
            csv.to_str().unwrap(),
        ],
    );
    assert!(ok, "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("sample,time_ms,tri,clk\n"), "{text}");
    let rows = csv_rows(&text);
    assert_eq!(rows.len(), 60);
    let tri = |i: usize| rows[i].2[0].parse::<f64>().unwrap();
    assert!(tri(14) > 0.0 && tri(15) <= 0.0, "{text}");
    // Channel 1 sampled the same pins in the same cycles: halsampler's
    // lines with the same sample numbers hold the same values.
    let last = rows.last().unwrap().0 + 1;
    let out = Command::new(env!("CARGO_BIN_EXE_halsampler"))
        .args(["-c", "1", "-t", "-n", &last.to_string()])
        .env("HAL_INSTANCE", &host.instance)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let sampled: Vec<Vec<String>> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| l.split_whitespace().map(str::to_string).collect())
        .collect();
    assert_eq!(sampled.len(), last as usize);
    for (tag, _, values) in &rows {
        let line = &sampled[*tag as usize];
        assert_eq!(line[0], tag.to_string());
        assert_eq!(&line[1..], &values[..], "sample {tag}");
    }
    // halscope used the channel as it was: the configuration's sampler stays.
    assert!(host.instance().component("sampler").unwrap().is_some());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Figures of one thread in latency-test's summary table.
fn table_row(stdout: &str, thread: &str) -> Vec<String> {
    stdout
        .lines()
        .find(|l| l.starts_with(thread))
        .unwrap_or_else(|| panic!("no row for {thread}:\n{stdout}"))
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

#[test]
fn latency_test_short_run_writes_png_and_csv_of_the_threads_histograms() {
    let dir = temp_dir("latency-files");
    let (png, csv) = (dir.join("l.png"), dir.join("l.csv"));
    let out = Command::new(env!("CARGO_BIN_EXE_latency-test"))
        .args([
            "-d",
            "0.5",
            "--png",
            png.to_str().unwrap(),
            "--csv",
            csv.to_str().unwrap(),
            "200us",
            "1ms",
        ])
        .env("HAL_NO_REALTIME", "1")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("verdict: largest latency"), "{stdout}");
    assert!(
        stdout.contains("SCHED_OTHER") && stdout.contains("WITHOUT realtime"),
        "{stdout}"
    );
    let hist =
        hal_scope::latency::report::parse_histogram_csv(&std::fs::read_to_string(&csv).unwrap())
            .unwrap();
    let names: Vec<&str> = hist.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["base-thread", "servo-thread"]);
    for (name, counts) in &hist {
        // Columns: name, period, unit, cycles, min, p50, p99, p99.9, max, overruns.
        let row = table_row(&stdout, name);
        let cycles: u64 = row[3].parse().unwrap();
        let total: u64 = counts.iter().sum();
        assert!(total > 0, "{name} ran no cycle");
        // Every cycle's wake-up is in the histogram (the last may still
        // be in flight when the table was read: the table's count comes
        // from the same settled snapshot, so they agree).
        assert_eq!(total, cycles, "{name}: {stdout}");
        let first = counts.iter().position(|&n| n > 0).unwrap();
        let last = counts.iter().rposition(|&n| n > 0).unwrap();
        let min_us: f64 = row[4].parse().unwrap();
        let max_us: f64 = row[8].parse().unwrap();
        let floor = |b: usize| hal_core::latency_bucket_floor_us(b) as f64;
        assert!(
            min_us + 0.05 >= floor(first) && min_us < floor(first + 1) + 0.05,
            "{name}: min {min_us} bucket {first}"
        );
        assert!(
            max_us + 0.05 >= floor(last) && max_us < floor(last + 1) + 0.05,
            "{name}: max {max_us} bucket {last}"
        );
    }
    assert!(std::fs::read(&png)
        .unwrap()
        .starts_with(b"\x89PNG\r\n\x1a\n"));
    let _ = std::fs::remove_dir_all(&dir);
}
