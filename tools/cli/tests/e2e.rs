//! End-to-end HAL-file tests from the workspace's tests/ folder.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use common::*;

fn case(name: &str) -> std::path::PathBuf {
    root().join("tests").join(name)
}

#[test]
fn fast_thread_increments_slow_thread_resets() {
    let out = halrun(&case("threads"), &["-f", "test.hal"], "threads");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let values: Vec<u32> = text
        .lines()
        .map(|l| {
            l.trim()
                .parse()
                .unwrap_or_else(|_| panic!("not a number: {l:?}"))
        })
        .collect();
    assert_eq!(values.len(), 3500, "exactly 3500 samples");
    assert_eq!(values[0], 1);
    let mut resets = 0;
    for w in values.windows(2) {
        if w[1] == 1 {
            resets += 1;
        } else {
            assert_eq!(
                w[1],
                w[0] + 1,
                "a sample is neither the previous + 1 nor a reset"
            );
        }
    }
    assert!(resets >= 100, "only {resets} resets in 3500 fast periods");
}

#[test]
fn streamer_to_sampler_round_trip() {
    run_exact("stream-roundtrip");
}

#[test]
fn nets_change_while_threads_run() {
    run_exact("nets");
}

#[test]
fn linuxcnc_twopass_test_prints_what_linuxcnc_prints() {
    // LinuxCNC's tests/twopass: `halrun test.ini`, expected from its halrun.
    let dir = case("twopass");
    let out = halrun(&dir, &["test.ini"], "twopass");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let expected = std::fs::read_to_string(dir.join("expected")).unwrap();
    assert_eq!(String::from_utf8_lossy(&out.stdout), expected, "{stderr}");
}

const SHOW: &str =
    "show pin\nshow param\nshow sig\nshow funct\nshow thread\nshow alias\nlist comp\n";

#[test]
fn save_then_reload_gives_the_same_show() {
    let tmp = std::env::temp_dir().join(instance("save-reload"));
    std::fs::create_dir_all(&tmp).unwrap();
    let src = case("save-reload").join("test.hal");
    let first = format!("source {}\nsave allu saved.hal\n{SHOW}", src.display());
    std::fs::write(tmp.join("first.hal"), first).unwrap();
    let a = halrun(&tmp, &["-f", "first.hal"], "save-a");
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    let saved = std::fs::read_to_string(tmp.join("saved.hal")).unwrap();
    assert!(saved.contains("loadrt and2 count=2"), "{saved}");
    assert!(
        saved.contains("alias pin and2.1.in1 spare-input"),
        "{saved}"
    );
    std::fs::write(tmp.join("second.hal"), format!("source saved.hal\n{SHOW}")).unwrap();
    let b = halrun(&tmp, &["-f", "second.hal"], "save-b");
    assert!(b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
    assert_eq!(
        String::from_utf8_lossy(&a.stdout),
        String::from_utf8_lossy(&b.stdout),
        "reloaded configuration differs; saved file:\n{saved}"
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn killing_halrun_takes_its_host_down() {
    let dir = std::env::temp_dir().join(instance("killed"));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("wait.hal"),
        "loadrt threads\nloadusr -w sleep 30\n",
    )
    .unwrap();
    let name = instance("killed-run");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_halrun"))
        .args(["-f", "wait.hal"])
        .current_dir(&dir)
        .env("HAL_INSTANCE", &name)
        .env("HAL_NO_REALTIME", "1")
        .spawn()
        .unwrap();
    let up = (0..500).any(|_| {
        std::thread::sleep(std::time::Duration::from_millis(10));
        hal_core::Instance::attach(&name).is_ok_and(|i| !i.threads().unwrap_or_default().is_empty())
    });
    assert!(up, "the instance came up");
    child.kill().unwrap();
    child.wait().unwrap();
    let gone = (0..500).any(|_| {
        std::thread::sleep(std::time::Duration::from_millis(10));
        hal_core::Instance::attach(&name).is_err()
    });
    assert!(gone, "the host outlived halrun");
    let _ = std::fs::remove_dir_all(dir);
}

// ---------------------------------------------------------------------
// Components end to end: stepgen, encoder and pid fed by streamer and
// recorded by sampler, checked for exact output and for the properties
// the components guarantee (components.md 3.1, 3.2, 3.5).
// ---------------------------------------------------------------------

/// The test's HAL file.
fn hal_file(name: &str) -> String {
    std::fs::read_to_string(case(name).join("test.hal")).unwrap()
}

/// The lines of a HAL file split into words, comments skipped.
fn hal_commands(hal: &str) -> impl Iterator<Item = Vec<&str>> {
    hal.lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
}

/// The value of `setp <name> <value>` in a HAL file.
fn setp_value<T: std::str::FromStr>(hal: &str, name: &str) -> T {
    hal_commands(hal)
        .find(|w| w.len() == 3 && w[0] == "setp" && w[1] == name)
        .map(|w| num(w[2]))
        .unwrap_or_else(|| panic!("test.hal has no `setp {name}`"))
}

/// The value of `key=value` on a `loadrt` line of a HAL file.
fn loadrt_value<T: std::str::FromStr>(hal: &str, key: &str) -> T {
    let prefix = format!("{key}=");
    hal_commands(hal)
        .filter(|w| w.first() == Some(&"loadrt"))
        .flat_map(|w| w.into_iter())
        .find_map(|w| w.strip_prefix(&prefix).map(num))
        .unwrap_or_else(|| panic!("test.hal has no loadrt {key}="))
}

/// N of `loadusr -w halsampler -n N`.
fn sample_count(hal: &str) -> usize {
    hal_commands(hal)
        .find(|w| w.len() == 5 && w[..4] == ["loadusr", "-w", "halsampler", "-n"])
        .map(|w| num(w[4]))
        .expect("test.hal runs halsampler -n N")
}

/// The whitespace-separated fields of the first `n` lines of `text`
/// (halsampler rows), each line required to have `cols` fields.
fn sampled_rows(text: &str, n: usize, cols: usize) -> Vec<Vec<&str>> {
    let rows: Vec<Vec<&str>> = text
        .lines()
        .take(n)
        .map(|l| l.split_whitespace().collect())
        .collect();
    assert_eq!(rows.len(), n, "exactly {n} samples");
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), cols, "sample {i} has {} fields: {r:?}", r.len());
    }
    rows
}

/// A sampled bit (`0` or `1`).
fn bit(field: &str) -> bool {
    match field {
        "0" => false,
        "1" => true,
        _ => panic!("not a bit: {field:?}"),
    }
}

/// A sampled or configured number.
fn num<T: std::str::FromStr>(field: &str) -> T {
    field
        .parse()
        .unwrap_or_else(|_| panic!("not a number: {field:?}"))
}

/// A stepgen timing parameter in whole base periods, rounded up as
/// update-freq rounds it (components.md 3.1 `ceil_mult`).
fn periods(ns: u32, period: u32) -> usize {
    if ns == 0 {
        0
    } else {
        ((ns - 1) / period + 1) as usize
    }
}

/// Checks a type-0 position-mode stepgen run: sampled columns
/// position-cmd, step, dir, counts every base period, then `getp` of
/// steplen, stepspace, dirsetup and dirhold. Properties (components.md
/// 3.1): the timing parameters were rounded up to whole periods; every
/// step pulse lasts at least steplen and every gap at least stepspace;
/// dir changes only dirhold after the last falling edge and dirsetup
/// before the next rising edge; the signed number of steps (dir is high
/// for the negative direction) equals `counts` at every sample, and each
/// commanded position × position-scale once its move has finished (a move
/// cut short by a new command must at least be heading for it); dir
/// changes exactly where the motion turns around.
fn check_stepgen_exact(name: &str) {
    let text = run_exact(name);
    let hal = hal_file(name);
    let period: u32 = loadrt_value(&hal, "period1");
    let scale: f64 = setp_value(&hal, "stepgen.0.position-scale");
    let n = sample_count(&hal);
    let timing = check_rounded_timing(name, &text, &hal, n, period);

    let rows = sampled_rows(&text, n, 4);
    let cmd: Vec<f64> = rows.iter().map(|r| num(r[0])).collect();
    let step: Vec<bool> = rows.iter().map(|r| bit(r[1])).collect();
    let dir: Vec<bool> = rows.iter().map(|r| bit(r[2])).collect();
    let counts: Vec<i32> = rows.iter().map(|r| num(r[3])).collect();

    let edges = Edges::of(&step, &dir);
    assert!(!step[n - 1], "{name}: the last pulse ended");
    assert_eq!(edges.rising.len(), edges.falling.len());
    check_pulse_timing(name, &step, &edges, timing);
    check_counts_follow_steps(name, &edges, &dir, &counts);
    let targets = check_moves(name, &cmd, &counts, scale);
    check_dir_follows_motion(name, &edges, &dir, &counts, &targets);
}

/// Checks the four `getp` lines after the `n` samples: steplen,
/// stepspace, dirsetup and dirhold rounded up to whole periods. Returns
/// them in periods.
fn check_rounded_timing(name: &str, text: &str, hal: &str, n: usize, period: u32) -> [usize; 4] {
    let requested: Vec<u32> = ["steplen", "stepspace", "dirsetup", "dirhold"]
        .iter()
        .map(|p| setp_value(hal, &format!("stepgen.0.{p}")))
        .collect();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), n + 4, "{name}: samples plus four getp lines");
    let rounded: Vec<u32> = lines[n..].iter().map(|l| num(l.trim())).collect();
    let want: Vec<u32> = requested
        .iter()
        .map(|&v| periods(v, period) as u32 * period)
        .collect();
    assert_eq!(
        rounded, want,
        "{name}: timing parameters rounded up to periods"
    );
    for (r, q) in rounded.iter().zip(&requested) {
        assert!(r > q, "{name}: the test wants values that need rounding");
    }
    let timing = [0, 1, 2, 3].map(|i| periods(requested[i], period));
    assert!(timing.iter().all(|&t| t >= 2));
    timing
}

/// The sample indices where step rises and falls and where dir changes;
/// the pins start low before the first sample.
struct Edges {
    rising: Vec<usize>,
    falling: Vec<usize>,
    dir_changes: Vec<usize>,
}

impl Edges {
    fn of(step: &[bool], dir: &[bool]) -> Edges {
        let n = step.len();
        let was = |v: &[bool], i: usize| i > 0 && v[i - 1];
        Edges {
            rising: (0..n).filter(|&i| step[i] && !was(step, i)).collect(),
            falling: (0..n).filter(|&i| !step[i] && was(step, i)).collect(),
            dir_changes: (0..n).filter(|&i| dir[i] != was(dir, i)).collect(),
        }
    }
}

/// Every pulse lasts steplen, every gap stepspace; dir changes dirhold
/// after a falling edge and dirsetup before a rising one (`timing` in
/// periods, in that parameter order: steplen, stepspace, dirsetup, dirhold).
fn check_pulse_timing(name: &str, step: &[bool], edges: &Edges, timing: [usize; 4]) {
    let [steplen, stepspace, dirsetup, dirhold] = timing;
    let Edges {
        rising,
        falling,
        dir_changes,
    } = edges;
    for (k, (&r, &f)) in rising.iter().zip(falling).enumerate() {
        assert!(r < f);
        assert!(
            f - r >= steplen,
            "{name}: pulse at sample {r} lasts {} periods < steplen {steplen}",
            f - r
        );
        if let Some(&next) = rising.get(k + 1) {
            assert!(
                next - f >= stepspace,
                "{name}: gap at sample {f} lasts {} periods < stepspace {stepspace}",
                next - f
            );
        }
    }
    for &d in dir_changes {
        assert!(!step[d], "{name}: dir changed during a pulse at sample {d}");
        if let Some(&f) = falling.iter().rev().find(|&&f| f <= d) {
            assert!(
                d - f >= dirhold,
                "{name}: dir changed {} periods after the falling edge at {f} (dirhold {dirhold})",
                d - f
            );
        }
        if let Some(&r) = rising.iter().find(|&&r| r > d) {
            assert!(
                r - d >= dirsetup,
                "{name}: dir changed {} periods before the rising edge at {r} (dirsetup {dirsetup})",
                r - d
            );
        }
    }
}

/// The signed step count equals `counts` at every sample.
fn check_counts_follow_steps(name: &str, edges: &Edges, dir: &[bool], counts: &[i32]) {
    let mut net = 0i32;
    for (i, &count) in counts.iter().enumerate() {
        if edges.rising.binary_search(&i).is_ok() {
            net += if dir[i] { -1 } else { 1 };
        }
        assert_eq!(net, count, "{name}: steps so far vs counts at sample {i}");
    }
}

/// Each command segment either reaches its position exactly, or is cut
/// short by the next command while still heading for it (a reversal in
/// mid-move); the last one is reached. Returns each segment's target in
/// counts.
fn check_moves(name: &str, cmd: &[f64], counts: &[i32], scale: f64) -> Vec<i32> {
    let n = cmd.len();
    let mut targets = vec![];
    let mut from = 0i32;
    let mut cut_short = 0;
    for i in 0..n {
        if i + 1 == n || cmd[i + 1] != cmd[i] {
            let want = (cmd[i] * scale).round() as i32;
            let got = counts[i];
            if got != want {
                assert!(
                    i + 1 < n && (got - from).signum() == (want - from).signum(),
                    "{name}: position {} (sample {i}): at {got}, neither reached nor on the way from {from}",
                    cmd[i]
                );
                cut_short += 1;
            }
            targets.push(want);
            from = got;
        }
    }
    assert!(targets.len() >= 4, "{name}: at least three moves");
    assert!(
        cut_short >= 1,
        "{name}: one move is reversed before it ends"
    );
    targets
}

/// dir follows the direction of motion: it changes exactly where the
/// count sequence turns around (it starts low, i.e. forward), and the net
/// steps are the final position.
fn check_dir_follows_motion(
    name: &str,
    edges: &Edges,
    dir: &[bool],
    counts: &[i32],
    targets: &[i32],
) {
    let mut heading = 1;
    let mut turns = 0;
    for w in counts.windows(2) {
        let d = (w[1] - w[0]).signum();
        if d != 0 && d != heading {
            turns += 1;
            heading = d;
        }
    }
    assert!(turns >= 2, "{name}: the motion reverses at least twice");
    assert_eq!(
        edges.dir_changes.len(),
        turns,
        "{name}: dir changes {:?}",
        edges.dir_changes
    );
    let forward = edges.rising.iter().filter(|&&r| !dir[r]).count() as i32;
    let backward = edges.rising.iter().filter(|&&r| dir[r]).count() as i32;
    let last = *targets.last().unwrap();
    assert_eq!(
        forward - backward,
        last,
        "{name}: net steps = final position × position-scale"
    );
    assert_eq!(counts[counts.len() - 1], last);
}

#[test]
fn stepgen_exact_25us_base_thread() {
    check_stepgen_exact("stepgen-exact-25us");
}

#[test]
fn stepgen_exact_50us_base_thread() {
    check_stepgen_exact("stepgen-exact-50us");
}

/// One row of the encoder test stream: phase A, phase B, phase Z.
type QuadRow = (bool, bool, bool);

/// The forward quadrature cycle (A leads B), as (A, B).
const QUAD_FORWARD: [(bool, bool); 4] =
    [(false, false), (true, false), (true, true), (false, true)];

/// The stream of `tests/encoder-modes/input`: 6 idle rows, 48 forward
/// edges held 2 rows each with an index pulse on the rows after edge 28,
/// 20 reverse edges held 3 rows each with a second index pulse after the
/// 8th, 12 forward edges one row each, 10 idle rows.
fn encoder_stream() -> Vec<QuadRow> {
    let mut rows = Vec::new();
    let mut phase = 0usize;
    let idle = |rows: &mut Vec<QuadRow>, phase: usize, n: usize| {
        let (a, b) = QUAD_FORWARD[phase];
        rows.extend(std::iter::repeat_n((a, b, false), n));
    };
    // (direction, edges, rows per state, edge after which Z is high)
    let moves: [(isize, usize, usize, Option<usize>); 3] =
        [(1, 48, 2, Some(28)), (-1, 20, 3, Some(8)), (1, 12, 1, None)];
    idle(&mut rows, phase, 6);
    for (dir, edges, hold, z_after) in moves {
        for e in 1..=edges {
            phase = (phase as isize + dir).rem_euclid(4) as usize;
            let (a, b) = QUAD_FORWARD[phase];
            rows.extend(std::iter::repeat_n((a, b, z_after == Some(e)), hold));
        }
    }
    idle(&mut rows, phase, 10);
    rows
}

/// The stream as halstreamer input text.
fn encoder_input_text(rows: &[QuadRow]) -> String {
    rows.iter()
        .map(|&(a, b, z)| format!("{} {} {}\n", a as u8, b as u8, z as u8))
        .collect()
}

/// Raw counts after each row, decoded independently of the component:
/// x4 counts every edge, x1 counts only A rising / falling while B is
/// low, counter mode counts A rising edges up only.
fn expected_raw_counts(rows: &[QuadRow]) -> [Vec<i32>; 3] {
    let pos = |a: bool, b: bool| QUAD_FORWARD.iter().position(|&p| p == (a, b)).unwrap();
    let (mut x4, mut x1, mut ctr) = (0i32, 0i32, 0i32);
    let mut out = [vec![], vec![], vec![]];
    let mut prev = (false, false);
    for &(a, b, _) in rows {
        match (pos(a, b) + 4 - pos(prev.0, prev.1)) % 4 {
            1 => x4 += 1,
            3 => x4 -= 1,
            0 => {}
            _ => panic!("the stream skips a quadrature state"),
        }
        match (prev, (a, b)) {
            ((false, false), (true, false)) => x1 += 1,
            ((true, false), (false, false)) => x1 -= 1,
            _ => {}
        }
        if a && !prev.0 {
            ctr += 1;
        }
        prev = (a, b);
        out[0].push(x4);
        out[1].push(x1);
        out[2].push(ctr);
    }
    out
}

#[test]
fn encoder_counts_in_every_mode_and_index_resets_once() {
    let name = "encoder-modes";
    let stream = encoder_stream();
    let input_path = case(name).join("input");
    let text = encoder_input_text(&stream);
    if std::env::var_os("E2E_WRITE_INPUT").is_some() {
        std::fs::write(&input_path, &text).unwrap();
    }
    assert_eq!(
        std::fs::read_to_string(&input_path).unwrap(),
        text,
        "{name}/input is not what encoder_stream() makes (E2E_WRITE_INPUT=1 rewrites it)"
    );

    let out = run_exact(name);
    let n = sample_count(&hal_file(name));
    assert_eq!(n, stream.len(), "one sample per streamed row");
    let rows = sampled_rows(&out, n, 9);
    let raw = expected_raw_counts(&stream);

    // The index fires on the first rising edge of Z (the component arms
    // at its first capture-position, before any Z in the stream).
    let z_rises: Vec<usize> = (1..n)
        .filter(|&i| stream[i].2 && !stream[i - 1].2)
        .collect();
    assert_eq!(z_rises.len(), 2, "two index pulses in the stream");
    let index_row = z_rises[0];

    for (i, r) in rows.iter().enumerate() {
        let inputs = (bit(r[0]), bit(r[1]), bit(r[2]));
        assert_eq!(inputs, stream[i], "streamed row {i} sampled back");
        for ch in 0..3 {
            let reference = if i >= index_row {
                raw[ch][index_row]
            } else {
                0
            };
            let want = raw[ch][i] - reference;
            let got: i32 = num(r[3 + ch]);
            assert_eq!(got, want, "encoder.{ch}.counts at sample {i}");
        }
        for ch in 0..2 {
            assert_eq!(
                bit(r[6 + ch]),
                i < index_row,
                "encoder.{ch}.index-enable at sample {i} (index at {index_row})"
            );
        }
        let raw0: i32 = num(r[8]);
        assert_eq!(raw0, raw[0][i], "encoder.0.rawcounts is never reset");
    }
    // At the index edge the counts are exactly zero in every mode.
    for ch in 0..3 {
        assert_eq!(
            num::<i32>(rows[index_row][3 + ch]),
            0,
            "encoder.{ch} zeroed"
        );
    }
    // Totals: x4 48 - 20 + 12 = 40 edges, x1 12 - 5 + 3 = 10 cycles,
    // counter 12 + 5 + 3 = 20 rising A edges.
    assert_eq!([raw[0][n - 1], raw[1][n - 1], raw[2][n - 1]], [40, 10, 20]);

    // encoder.2 was armed with setp on its unconnected pin: cleared too.
    let tail: Vec<&str> = out.lines().skip(n).map(str::trim).collect();
    assert_eq!(tail.len(), 2, "two getp lines: {tail:?}");
    assert!(
        ["0", "FALSE"].contains(&tail[0]),
        "encoder.2.index-enable: {}",
        tail[0]
    );
    assert_eq!(num::<i32>(tail[1]), raw[2][n - 1], "encoder.2.rawcounts");
}

/// Checks one loop of `pid-plant` from its sampled columns.
struct Loop<'a> {
    name: &'a str,
    cmd: &'a [f64],
    output: Vec<f64>,
    feedback: Vec<f64>,
    error: Vec<f64>,
    saturated: Vec<bool>,
}

impl Loop<'_> {
    /// After each command step, the feedback settles to the command and
    /// the error to 0 within `tol` in at most `settle` samples, and stays
    /// there until the next step; the output is never saturated then.
    fn settles(&self, settle: usize, tol: f64) {
        let n = self.cmd.len();
        let steps: Vec<usize> = (1..n).filter(|&i| self.cmd[i] != self.cmd[i - 1]).collect();
        assert!(steps.len() >= 2, "the command steps at least twice");
        for (k, &s) in steps.iter().enumerate() {
            let end = steps.get(k + 1).copied().unwrap_or(n);
            assert!(end - s > settle, "segment long enough to settle");
            for i in s + settle..end {
                let c = self.cmd[i];
                assert!(
                    (self.feedback[i] - c).abs() <= tol,
                    "{}: feedback {} vs command {c} at sample {i}",
                    self.name,
                    self.feedback[i]
                );
                assert!(
                    self.error[i].abs() <= tol,
                    "{}: error {} at sample {i}",
                    self.name,
                    self.error[i]
                );
                assert!(!self.saturated[i], "{}: saturated at {i}", self.name);
            }
            // The step really moved the plant (not settled from the start).
            assert!(
                (self.feedback[s] - self.cmd[s]).abs() > 0.1,
                "{}: feedback already at the command at sample {s}",
                self.name
            );
        }
    }
}

#[test]
fn pid_drives_integrator_and_lag_plants_to_the_command() {
    let name = "pid-plant";
    let out = run_exact(name);
    let hal = hal_file(name);
    let n = sample_count(&hal);
    let rows = sampled_rows(&out, n, 9);
    let col = |c: usize| -> Vec<f64> { rows.iter().map(|r| num(r[c])).collect() };
    let cmd = col(0);
    let loop0 = Loop {
        name: "pid.0 + integ",
        cmd: &cmd,
        output: col(1),
        feedback: col(2),
        error: col(3),
        saturated: rows.iter().map(|r| bit(r[4])).collect(),
    };
    let loop1 = Loop {
        name: "pid.1 + lowpass",
        cmd: &cmd,
        output: col(5),
        feedback: col(6),
        error: col(7),
        saturated: rows.iter().map(|r| bit(r[8])).collect(),
    };
    loop0.settles(200, 1e-5);
    loop1.settles(200, 1e-5);

    // Loop 0's output is the integrator's speed: limited to maxoutput,
    // and while saturated the plant ramps by exactly maxoutput × period.
    let maxoutput: f64 = setp_value(&hal, "pid.0.maxoutput");
    let period_s = loadrt_value::<f64>(&hal, "period1") * 1e-9;
    let mut saturated_samples = 0;
    for i in 1..n {
        assert!(loop0.output[i].abs() <= maxoutput, "pid.0.output at {i}");
        if loop0.saturated[i] {
            saturated_samples += 1;
            assert_eq!(loop0.output[i].abs(), maxoutput, "saturated output at {i}");
            let moved = (loop0.feedback[i] - loop0.feedback[i - 1]).abs();
            assert!(
                (moved - maxoutput * period_s).abs() < 2e-6,
                "ramp of {moved} per period at sample {i}"
            );
        }
    }
    assert!(saturated_samples >= 20, "the 1.0 step saturates loop 0");
    // Loop 1 needs its integral term: with P alone a lag plant keeps a
    // steady-state error, so a non-zero output holds the plant at the
    // command.
    let last = n - 1;
    assert!((loop1.output[last] - cmd[last]).abs() < 1e-5);
    assert!(loop1.output[last].abs() > 0.1);
}

/// motmod homes and jogs a three-joint stepper machine through stepgen and
/// the simulated parallel port: the samples (taken while anything moves)
/// equal `expected`, and they show the homing sequences in order, the
/// feedback following the command, and the jogs ending where commanded.
#[test]
fn motion_homes_and_jogs_a_three_joint_machine() {
    let name = "motion-home-jog";
    let text = run_exact(name);
    let mut lines = text.lines().filter(|l| !l.starts_with("accepted (serial"));
    let n: usize = num(lines.next().expect("the sample count"));
    let body: String = lines.map(|l| format!("{l}\n")).collect();
    let rows = sampled_rows(&body, n, 9);
    let f = |r: &Vec<&str>, c: usize| num::<f64>(r[c]);
    let state = |r: &Vec<&str>, j: usize| num::<i32>(r[6 + j]);
    // Z (sequence 0) homes alone, then X and Y (sequence 1) together.
    let first_busy = |j: usize| rows.iter().position(|r| state(r, j) != 0).expect("homed");
    let last_busy = |j: usize| rows.iter().rposition(|r| state(r, j) != 0).expect("homed");
    assert!(last_busy(2) < first_busy(0));
    assert_eq!(first_busy(0), first_busy(1));
    // Every state of each path, in order.
    let visits = |j: usize, path: &[i32]| {
        let mut seen: Vec<i32> = rows.iter().map(|r| state(r, j)).collect();
        seen.dedup();
        let mut it = seen.iter();
        for s in path {
            assert!(it.any(|v| v == s), "joint {j} misses state {s}: {seen:?}");
        }
    };
    visits(0, &[7, 10, 12, 21]); // search, backoff, rise latch, final move
    visits(1, &[7, 14, 21]); // search, fall latch, final move
    visits(2, &[7, 14, 21]);
    // The feedback follows the command to within the following error
    // limit (0.05 at rest) plus the 0.02-unit step.
    for r in &rows {
        for j in 0..3 {
            let err = (f(r, j) - f(r, 3 + j)).abs();
            assert!(err < 0.5, "joint {j} error {err} in {r:?}");
        }
    }
    // Homed at HOME: X 9, Y 0, Z -1; then X jogged 2.5 back, Y to 2.25, Z
    // to its upper soft limit 0.5.
    let last = rows.last().unwrap();
    assert_eq!([f(last, 0), f(last, 1), f(last, 2)], [6.5, 2.25, 0.5]);
    for j in 0..3 {
        assert!((f(last, j) - f(last, 3 + j)).abs() <= 0.02);
    }
    assert!(rows
        .iter()
        .any(|r| (f(r, 0), f(r, 1), f(r, 2)) == (9.0, 0.0, -1.0)));
    for j in 0..3 {
        assert!(text.contains(&format!("TRUE  joint.{j}.homed\n")), "{j}");
    }
}

// ---------------------------------------------------------------------
// hostmot2 machines on the simulated Mesa boards (configs/sim/hm2-*).
// ---------------------------------------------------------------------

/// The samples of a machine test: the count line, then 9 columns
/// (pos-cmd, pos-fb, home-state of three joints).
fn machine_rows(text: &str) -> Vec<Vec<&str>> {
    let mut lines = text.lines().filter(|l| !l.starts_with("accepted (serial"));
    let n: usize = num(lines.next().expect("the sample count"));
    let rest = &text[text.find(&format!("{n}\n")).unwrap() + format!("{n}\n").len()..];
    sampled_rows(rest, n, 9)
}

/// What a hm2 machine test checks: per joint the homing states it must
/// pass through in order, the largest following error, where the joints
/// are once homed and at the end.
struct MachineRun<'a> {
    states: [&'a [i32]; 3],
    max_error: f64,
    homed_at: [f64; 3],
    ends_at: [f64; 3],
}

/// Runs tests/<name> exactly and checks its samples: Z (sequence 0)
/// homes alone, then X and Y together; every joint passes through its
/// states; the following error stays below `max_error`; the joints stand
/// at `homed_at` after homing and end within 0.01 of `ends_at`, homed.
fn check_machine(name: &str, want: &MachineRun) -> String {
    let text = run_exact(name);
    let rows = machine_rows(&text);
    let f = |r: &Vec<&str>, c: usize| num::<f64>(r[c]);
    let state = |r: &Vec<&str>, j: usize| num::<i32>(r[6 + j]);
    let first_busy = |j: usize| rows.iter().position(|r| state(r, j) != 0).unwrap();
    let last_busy = |j: usize| rows.iter().rposition(|r| state(r, j) != 0).unwrap();
    assert!(last_busy(2) < first_busy(0));
    assert_eq!(first_busy(0), first_busy(1));
    for (j, path) in want.states.iter().enumerate() {
        let mut seen: Vec<i32> = rows.iter().map(|r| state(r, j)).collect();
        seen.dedup();
        let mut it = seen.iter();
        for s in *path {
            assert!(it.any(|v| v == s), "joint {j} misses state {s}: {seen:?}");
        }
    }
    for r in &rows {
        for j in 0..3 {
            let err = (f(r, j) - f(r, 3 + j)).abs();
            assert!(err < want.max_error, "joint {j} error {err} in {r:?}");
        }
    }
    let [hx, hy, hz] = want.homed_at;
    assert!(rows
        .iter()
        .any(|r| (f(r, 0), f(r, 1), f(r, 2)) == (hx, hy, hz)));
    let last = rows.last().unwrap();
    assert_eq!([f(last, 0), f(last, 1), f(last, 2)], want.ends_at);
    for j in 0..3 {
        assert!((f(last, j) - f(last, 3 + j)).abs() <= 0.01, "{last:?}");
        assert!(text.contains(&format!("TRUE  joint.{j}.homed\n")), "{j}");
    }
    text
}

#[test]
fn hm2_servo_machine_homes_on_index_and_reaches_its_positions() {
    // Each joint homes through the encoder's index (IndexSearchWait, 18);
    // the servo loops follow within 0.1 mm; homed at HOME (45, 0, -2),
    // then X 12.5 back, Y to 7.25, Z up to 0.5.
    let index_homing: &[i32] = &[7, 10, 12, 18, 21];
    let text = check_machine(
        "hm2-servo",
        &MachineRun {
            states: [index_homing; 3],
            max_error: 0.1,
            homed_at: [45.0, 0.0, -2.0],
            ends_at: [32.5, 7.25, 0.5],
        },
    );
    // The watchdog never bit; the encoders count from the index, which
    // is HOME_OFFSET (50, 20, 0) in joint positions.
    let tail: Vec<&str> = text.lines().rev().take(4).collect();
    assert_eq!(tail[3], "FALSE");
    let enc = |k: usize| num::<f64>(tail[2 - k]);
    assert!((enc(0) - (32.5 - 50.0)).abs() <= 0.01, "{tail:?}");
    assert!((enc(1) - (7.25 - 20.0)).abs() <= 0.01, "{tail:?}");
    assert!((enc(2) - 0.5).abs() <= 0.01, "{tail:?}");
}

#[test]
fn hm2_stepper_machine_homes_and_reaches_its_positions() {
    // X and Z latch on the switch closing, Y on it opening; the step
    // generators follow within a tenth of a unit.
    let text = check_machine(
        "hm2-stepper",
        &MachineRun {
            states: [&[7, 10, 12, 21], &[7, 14, 21], &[7, 10, 12, 21]],
            max_error: 0.1,
            homed_at: [9.0, 0.0, 8.0],
            ends_at: [6.5, 2.25, 9.5],
        },
    );
    assert!(text.ends_with("\nFALSE\n"), "the watchdog never bit");
}

/// The stepper machine of hm2-stepper over EPP (hm2_7i90 with a
/// simulated 7I90 behind a simulated parallel port): the same commands
/// give the same samples as on the PCI simulator, and the watchdog never
/// bit.
#[test]
fn hm2_epp_stepper_machine_samples_as_on_the_pci_simulator() {
    let got = run_exact("hm2-epp-stepper");
    let pci = std::fs::read_to_string(case("hm2-stepper").join("expected")).unwrap();
    assert_eq!(machine_rows(&got), machine_rows(&pci));
    assert!(got.ends_with("\nFALSE\n"), "the watchdog never bit");
}

/// The stepper machine of hm2-stepper over SPI (hm2_rpspi with a
/// simulated 7C80 behind a simulated SPI link): the same commands give
/// the same samples as on the PCI simulator, and the watchdog never bit.
#[test]
fn hm2_spi_stepper_machine_samples_as_on_the_pci_simulator() {
    let got = run_exact("hm2-spi-stepper");
    let pci = std::fs::read_to_string(case("hm2-stepper").join("expected")).unwrap();
    assert_eq!(machine_rows(&got), machine_rows(&pci));
    assert!(got.ends_with("\nFALSE\n"), "the watchdog never bit");
}

/// The README's simulated mill runs the shipped pocket program: the
/// samples match the expected file exactly; every commanded point lies
/// in the pocket (or on the way in and out), the cut is at Z -1, and the
/// summary stays within the machine's limits.
#[test]
fn the_simulated_mill_runs_the_shipped_pocket() {
    let name = "motion-part-program";
    let text = run_exact(name);
    let mut lines = text.lines().filter(|l| !l.starts_with("accepted (serial"));
    let n: usize = num(lines.next().expect("the sample count"));
    let rest: Vec<&str> = lines.collect();
    let rows: Vec<Vec<f64>> = rest
        .iter()
        .take_while(|l| !l.starts_with("summary: "))
        .map(|l| l.split_whitespace().map(num::<f64>).collect())
        .collect();
    assert_eq!(rows.len(), n.div_ceil(25), "every 25th of {n} samples");
    let mut cut = false;
    for r in &rows {
        assert_eq!(r.len(), 9);
        let (x, y, z) = (r[0], r[1], r[2]);
        assert!((-1e-6..=16.0 + 1e-6).contains(&x), "{r:?}");
        assert!((-1e-6..=10.0 + 1e-6).contains(&y), "{r:?}");
        assert!((-1.0 - 1e-9..=1.0 + 1e-9).contains(&z), "{r:?}");
        cut |= z == -1.0;
        for j in 0..3 {
            assert!(r[6 + j].abs() < 0.1, "following error in {r:?}");
        }
    }
    assert!(cut, "the pocket is cut at Z -1");
    let summary = rest
        .iter()
        .find_map(|l| l.strip_prefix("summary: "))
        .expect("the summary line");
    let figures: Vec<f64> = summary
        .split(|c: char| !(c.is_ascii_digit() || c == '.'))
        .filter(|w| !w.is_empty() && *w != ".")
        .map(num)
        .collect();
    // seconds, ferror, speed, measured speed, acceleration (and the 2 of s^2)
    assert!((figures[0] - n as f64 * 0.001).abs() < 1e-9, "{summary}");
    assert!(figures[1] < 0.1, "{summary}");
    assert!(
        figures[2] <= 10.0 + 0.002,
        "the sampled speed (6 decimals): {summary}"
    );
    // The positions are printed to 6 decimals: their second difference
    // is off by up to 2e-6 per period², 2 units/s² at 1 ms. The planner
    // keeps 100 on the unrounded positions (motion's own tests); lines
    // blended at both ends use all of it, as in LinuxCNC.
    assert!(
        (99.0..=100.0 + 2.0).contains(&figures[4]),
        "the sampled acceleration (6 decimals): {summary}"
    );
    for j in 0..3 {
        assert!(text.contains(&format!("TRUE  joint.{j}.homed\n")), "{j}");
    }
}

#[test]
fn hm2_eth_stepper_machine_over_udp_samples_as_on_the_pci_simulator() {
    // The simulator listens on a port of this test's own.
    let port = std::net::UdpSocket::bind("127.0.0.1:0")
        .and_then(|s| s.local_addr())
        .unwrap()
        .port();
    let name = "hm2-eth-stepper";
    let dir = case(name);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_halrun"))
        .args(["-f", "test.hal"])
        .current_dir(&dir)
        .env("HAL_INSTANCE", instance(name))
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (8u64 << 20).to_string())
        .env("HM2_ETH_SIM_PORT", port.to_string())
        .output()
        .expect("halrun runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{name}: halrun failed: {stderr}");
    let got = String::from_utf8_lossy(&out.stdout).into_owned();
    let expected = std::fs::read_to_string(dir.join("expected")).unwrap();
    assert_eq!(got, expected, "{name}: stdout differs (stderr: {stderr})");
    // Sample for sample what the same machine does on the PCI simulator.
    let pci = std::fs::read_to_string(case("hm2-stepper").join("expected")).unwrap();
    assert_eq!(machine_rows(&got), machine_rows(&pci));
    assert!(
        got.ends_with("\nFALSE\n0\n"),
        "the watchdog never bit, no packet error"
    );
}
