//! No tool panics, whatever its arguments or its output.
//!
//! Every binary of the workspace — listed by `cargo metadata`, so a binary
//! another branch adds is covered without touching this file — runs with
//! hostile arguments (huge, negative, NaN, infinite, empty, 100 kB,
//! non-UTF-8), alone, in pairs, as the value of every option its help text
//! names, and in the argument lists of its [`Probe`]; then the tools that
//! print run on a live instance with their standard output already closed,
//! as `tool | head -1` leaves it. A run fails if the program panics, dies of
//! a signal other than SIGPIPE, or hangs.
//!
//! To teach the test a new binary's subcommands, add a [`Probe`] to
//! [`PROBES`].
//!
//! A binary of another package is run if cargo built it (`cargo test`
//! builds the binaries of packages that have integration tests; `.ci/run`
//! builds all of them first and sets `HAL_REQUIRE_ALL_BINS=1`, which turns a
//! missing binary into a failure).

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use common::bins::present_bins;

use std::ffi::OsString;
use std::io::Read;
use std::os::unix::ffi::OsStringExt;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// What the test knows about one binary beyond what its help says.
struct Probe {
    /// The binary's name.
    bin: &'static str,
    /// Argument lists run with every hostile value in place of `{}`.
    templates: &'static [&'static [&'static str]],
    /// Options never given a hostile value, each with the reason.
    skip_options: &'static [(&'static str, &'static str)],
    /// Argument lists run on the live instance with standard output closed.
    live: &'static [&'static [&'static str]],
    /// Why the binary is not run without arguments, if it is not.
    no_bare_run: Option<&'static str>,
}

const PROBES: &[Probe] = &[
    Probe {
        bin: "halcmd",
        templates: &[
            &["setp", "{}", "{}"],
            &["sets", "{}", "{}"],
            &["loadrt", "{}"],
            &["loadrt", "and2", "count={}"],
            &["-f", "{}"],
            &["-i", "{}"],
            &["-h", "{}"],
            &["show", "{}"],
            &["addf", "{}", "{}", "{}"],
            &["loadusr", "-n", "{}", "{}"],
        ],
        skip_options: &[],
        no_bare_run: None,
        live: &[
            &["show"],
            &["-s", "show", "pin"],
            &["list", "pin"],
            &["save"],
            &["-h"],
        ],
    },
    Probe {
        bin: "halrun",
        templates: &[&["-f", "{}"], &["-i", "{}", "{}"], &["-I", "{}"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["-h"]],
    },
    Probe {
        bin: "realtime",
        templates: &[&["{}", "start"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["status"], &["--help"]],
    },
    Probe {
        bin: "hal-host",
        templates: &[],
        skip_options: &[
            (
                "--instance",
                "a valid name starts a host that serves until stopped",
            ),
            ("-i", "the same as --instance"),
        ],
        no_bare_run: Some("it serves the instance until stopped"),
        live: &[&["--help"]],
    },
    Probe {
        bin: "halmeter",
        templates: &[
            &["-n", "{}", "pin", "x"],
            &["-p", "{}", "x"],
            &["pin", "{}"],
        ],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["-n", "3", "-p", "1", "pin", "joint.0.motor-pos-cmd"]],
    },
    Probe {
        bin: "halsampler",
        templates: &[&["-n", "{}"], &["-c", "{}"], &["-t", "{}"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["-n", "20"]],
    },
    Probe {
        bin: "halstreamer",
        templates: &[&["-c", "{}"], &["-N", "{}"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["-h"]],
    },
    Probe {
        bin: "motion-cmd",
        templates: &[
            &["-t", "{}", "status"],
            &["-i", "{}", "status"],
            &["watch", "-n", "{}", "-c", "{}"],
            &["wait", "{}"],
            &["wait", "homed", "{}"],
            &["jog-incr", "{}", "{}", "{}"],
            &["axis-jog-abs", "{}", "{}", "{}"],
            &["set-homing-params", "0", "HOME_SEQUENCE={}"],
            &["scale", "{}"],
        ],
        skip_options: &[],
        no_bare_run: None,
        live: &[
            &["status"],
            &["watch", "-n", "5", "-c", "3"],
            &["-t", "1e308", "status"],
            &["--help"],
        ],
    },
    Probe {
        bin: "hal-board",
        templates: &[
            &["idrom", "{}"],
            &["read", "{}", "{}"],
            &["watch", "{}", "{}"],
        ],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["list"], &["--help"]],
    },
    Probe {
        bin: "parport-tool",
        templates: &[&["read", "{}"], &["watch", "{}"], &["list", "{}"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["list"], &["--help"]],
    },
    Probe {
        bin: "task-cmd",
        templates: &[&["-t", "{}", "state"], &["{}", "{}"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["--help"]],
    },
    Probe {
        bin: "classicladder",
        templates: &[&["--nogui", "{}"], &["{}"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["--help"]],
    },
    Probe {
        bin: "halui",
        templates: &[&["-ini", "{}"], &["{}"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["--help"]],
    },
    Probe {
        bin: "linuxcnc",
        templates: &[&["{}"], &["-v", "{}"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["-h"]],
    },
    Probe {
        bin: "haltcl",
        templates: &[&["-i", "{}", "{}"]],
        skip_options: &[],
        no_bare_run: None,
        live: &[&["-h"]],
    },
    Probe {
        bin: "hal-fuzz-seed",
        templates: &[],
        skip_options: &[(
            "--write",
            "it rewrites fuzz/corpus/ in the source tree from the directory given",
        )],
        no_bare_run: None,
        live: &[],
    },
    Probe {
        bin: "hm2-eth-sim",
        templates: &[],
        // Fault rates, timings and the seed take any number: a value the
        // simulator accepts starts it serving until stopped.
        skip_options: &[
            ("--period-ns", "an accepted value serves until stopped"),
            ("--drop-requests", "an accepted value serves until stopped"),
            ("--drop-writes", "an accepted value serves until stopped"),
            ("--drop-replies", "an accepted value serves until stopped"),
            ("--delay", "an accepted value serves until stopped"),
            ("--delay-us", "an accepted value serves until stopped"),
            ("--duplicate", "an accepted value serves until stopped"),
            ("--seed", "an accepted value serves until stopped"),
        ],
        no_bare_run: Some("it answers on its UDP port until stopped"),
        live: &[&["--help"]],
    },
    Probe {
        bin: "linuxcncrsh",
        templates: &[],
        // A port, name, password, session count or folder it accepts
        // starts the server, which serves until stopped.
        skip_options: &[
            ("--port", "an accepted port serves until stopped"),
            ("-p", "the same as --port"),
            ("--name", "any name is accepted and serves until stopped"),
            ("-n", "the same as --name"),
            (
                "--connectpw",
                "any password is accepted and serves until stopped",
            ),
            ("-w", "the same as --connectpw"),
            (
                "--enablepw",
                "any password is accepted and serves until stopped",
            ),
            ("-e", "the same as --enablepw"),
            ("--sessions", "an accepted count serves until stopped"),
            ("-s", "the same as --sessions"),
            ("--path", "any folder is accepted and serves until stopped"),
            ("-d", "the same as --path"),
        ],
        no_bare_run: Some("it serves on TCP port 5007 until stopped, as LinuxCNC's"),
        live: &[&["--help"]],
    },
    Probe {
        bin: "xhc-hb04",
        templates: &[&["-H", "-I", "{}"], &["-H", "-s", "{}"]],
        skip_options: &[(
            "--instance",
            "an accepted name leaves it waiting for the pendant until stopped",
        )],
        no_bare_run: Some("without -H it waits for the pendant until stopped, as LinuxCNC's"),
        live: &[&["--help"]],
    },
    Probe {
        bin: "latency-test",
        templates: &[
            &["-d", "{}"],
            &["-d", "0.05", "--png", "{}"],
            &["-d", "0.05", "--csv", "{}"],
        ],
        skip_options: &[
            (
                "--png",
                "without -d it measures until Ctrl-C (a template gives -d)",
            ),
            (
                "--csv",
                "without -d it measures until Ctrl-C (a template gives -d)",
            ),
        ],
        no_bare_run: Some("it measures until Ctrl-C"),
        live: &[&["--help"], &["-d", "0.05"]],
    },
];

/// The hostile arguments.
fn hostile() -> Vec<OsString> {
    let mut v: Vec<OsString> = [
        "1e308",
        "-1e308",
        "1e-400",
        "99999999999999999999999",
        "-99999999999999999999999",
        "18446744073709551616",
        "-9223372036854775809",
        "-1",
        "-0",
        "nan",
        "NaN",
        "inf",
        "-inf",
        "",
        "0x",
    ]
    .into_iter()
    .map(OsString::from)
    .collect();
    v.push(OsString::from("9".repeat(100_000)));
    v.push(OsString::from_vec(vec![0xff, 0xfe, b'7', 0x80]));
    v
}

/// How one run ended.
struct Outcome {
    status: Option<std::process::ExitStatus>,
    stdout: String,
    stderr: String,
    hung: bool,
}

/// Where a run's standard output goes.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Out {
    /// /dev/null.
    Discard,
    /// A pipe whose reader has gone.
    Closed,
    /// Kept, for the help texts.
    Capture,
}

impl Outcome {
    /// What was wrong with the run, if anything.
    fn fault(&self, closed_stdout: bool) -> Option<String> {
        if self.hung {
            return Some("did not end within the limit".into());
        }
        if closed_stdout && self.stderr.contains("os error 32") {
            return Some("complained about the closed stdout instead of ending quietly".into());
        }
        if self.stderr.contains("panicked at") {
            return Some("panicked".into());
        }
        let status = self.status?;
        if status.code() == Some(101) {
            return Some("exit status 101 (a panic's)".into());
        }
        match status.signal() {
            Some(libc::SIGPIPE) | None => None,
            Some(sig) => Some(format!("killed by signal {sig}")),
        }
    }
}

/// The working directory of every run, under cargo's scratch directory
/// for tests: files a tool writes (latency-test's PNG and CSV, halscope's
/// outputs) land there, never in the source tree.
///
/// Each binary gets a directory of its own: a file one tool writes under a
/// hostile name (latency-test's `--csv 1e308`) must not become the input
/// another tool reads under that name (`linuxcnc 1e308` would start a
/// machine from it and run until stopped).
fn scratch_cwd(exe: &Path) -> PathBuf {
    let name = exe
        .file_name()
        .map_or_else(|| "tool".into(), |n| n.to_os_string());
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("no_panic-cwd")
        .join(name);
    std::fs::create_dir_all(&d).expect("scratch directory");
    d
}

static NEXT_INSTANCE: AtomicUsize = AtomicUsize::new(0);

/// Runs `exe args` with standard input empty, standard output discarded
/// or (with `closed_stdout`) a pipe whose reader is already gone.
fn run(exe: &Path, args: &[OsString], instance: &str, out: Out) -> Outcome {
    let stdout = match out {
        Out::Closed => {
            let (reader, writer) = nix::unistd::pipe().expect("pipe");
            drop(reader);
            Stdio::from(writer)
        }
        Out::Discard => Stdio::null(),
        Out::Capture => Stdio::piped(),
    };
    let mut child = Command::new(exe)
        .args(args)
        .current_dir(scratch_cwd(exe))
        .env("HAL_INSTANCE", instance)
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (4u64 << 20).to_string())
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts");
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut buf = Vec::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_end(&mut buf);
            }
            buf
        })
    };
    let err_reader = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let out_reader = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    // Generous: many runs share two loaded cores; a hang waits it out.
    // HAL_NOPANIC_LIMIT_S shortens it when hunting a hang.
    let limit = std::env::var("HAL_NOPANIC_LIMIT_S")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(60);
    let end = Instant::now() + Duration::from_secs(limit);
    let mut hung = false;
    let status = loop {
        if let Ok(Some(s)) = child.try_wait() {
            break Some(s);
        }
        if Instant::now() > end {
            hung = true;
            // SIGTERM first: a host shuts down in order.
            let _ = nix::sys::signal::kill(
                nix::unistd::Pid::from_raw(child.id() as i32),
                nix::sys::signal::Signal::SIGTERM,
            );
            std::thread::sleep(Duration::from_secs(2));
            let _ = child.kill();
            break child.wait().ok();
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let text = |r: std::thread::JoinHandle<Vec<u8>>| {
        String::from_utf8_lossy(&r.join().unwrap_or_default()).into_owned()
    };
    Outcome {
        status,
        stdout: text(out_reader),
        stderr: text(err_reader),
        hung,
    }
}

/// Option words (`-x`, `--long`) in a help or usage text.
fn options_in(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for word in text.split(|c: char| c.is_whitespace() || "[]|,()=<>{}'\"`".contains(c)) {
        let w = word.trim_end_matches(['.', ':', ';']);
        let body = w.trim_start_matches('-');
        let dashes = w.len() - body.len();
        if (dashes == 1 || dashes == 2)
            && body.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
            && body.chars().all(|c| c.is_ascii_alphanumeric() || c == '-')
            && !found.iter().any(|f| f == w)
        {
            found.push(w.to_string());
        }
    }
    found
}

fn substitute(template: &[&str], value: &OsString) -> Vec<OsString> {
    template
        .iter()
        .map(|w| {
            if *w == "{}" {
                value.clone()
            } else {
                OsString::from(w)
            }
        })
        .collect()
}

fn show(args: &[OsString]) -> String {
    args.iter()
        .map(|a| {
            let s = a.to_string_lossy();
            if s.len() > 40 {
                format!("<{} bytes>", a.len())
            } else {
                format!("{s:?}")
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The argument lists for one binary: plain, from its help, from its probe.
fn cases_for(bin: &str, exe: &Path) -> Vec<Vec<OsString>> {
    let probe = PROBES.iter().find(|p| p.bin == bin);
    let values = hostile();
    let mut cases: Vec<Vec<OsString>> = vec![vec!["-h".into()], vec!["--help".into()]];
    if probe.and_then(|p| p.no_bare_run).is_none() {
        cases.push(vec![]);
    }
    for v in &values {
        cases.push(vec![v.clone()]);
        cases.push(vec![v.clone(), v.clone()]);
    }
    // The options the binary itself names.
    let mut help = String::new();
    for args in [&["--help"][..], &["-h"][..], &["-?"][..]] {
        let args: Vec<OsString> = args.iter().map(OsString::from).collect();
        let o = run(exe, &args, "t-nopanic-help-none", Out::Capture);
        help.push_str(&o.stdout);
        help.push_str(&o.stderr);
    }
    let skip = probe.map_or(&[][..], |p| p.skip_options);
    for opt in options_in(&help) {
        if skip.iter().any(|(o, _)| *o == opt) {
            continue;
        }
        for v in &values {
            cases.push(vec![OsString::from(&opt), v.clone()]);
        }
    }
    for t in probe.map_or(&[][..], |p| p.templates) {
        for v in &values {
            cases.push(substitute(t, v));
        }
    }
    cases
}

/// Runs `jobs` on a few threads; returns the failures.
fn run_all(jobs: Vec<(String, PathBuf, Vec<OsString>, String, Out)>) -> Vec<String> {
    let queue = Mutex::new(jobs.into_iter());
    let failures = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..4 {
            s.spawn(|| loop {
                let Some((bin, exe, args, instance, closed)) =
                    queue.lock().unwrap_or_else(|e| e.into_inner()).next()
                else {
                    return;
                };
                let outcome = run(&exe, &args, &instance, closed);
                let closed = closed == Out::Closed;
                if let Some(fault) = outcome.fault(closed) {
                    let tail: String = outcome
                        .stderr
                        .lines()
                        .take(6)
                        .collect::<Vec<_>>()
                        .join("\n    ");
                    failures
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push(format!(
                            "{bin} {}{}: {fault}\n    {tail}",
                            show(&args),
                            if closed { " (stdout closed)" } else { "" }
                        ));
                }
            });
        }
    });
    failures.into_inner().unwrap_or_else(|e| e.into_inner())
}

/// Fails with every failed run listed, if any of `count` runs failed.
fn assert_none_failed(count: usize, failures: &[String]) {
    assert!(
        failures.is_empty(),
        "{} of {count} runs failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn no_binary_panics_on_hostile_arguments() {
    let began = Instant::now();
    let mut jobs = Vec::new();
    let pid = std::process::id();
    for (name, exe) in present_bins() {
        for args in cases_for(&name, &exe) {
            let n = NEXT_INSTANCE.fetch_add(1, SeqCst);
            // An instance nobody runs: tools that start one (halrun,
            // linuxcnc) get one of their own.
            let instance = format!("t-nopanic-{pid}-{n}");
            jobs.push((name.clone(), exe.clone(), args, instance, Out::Discard));
        }
    }
    let count = jobs.len();
    let failures = run_all(jobs);
    eprintln!(
        "{count} runs with hostile arguments in {:.1} s",
        began.elapsed().as_secs_f64()
    );
    assert_none_failed(count, &failures);
}

#[test]
fn no_binary_panics_on_a_closed_stdout() {
    let inst = common::instance("nopanic-live");
    common::start_motion_instance(&inst);
    common::halcmd(&["loadrt", "sampler", "depth=64", "cfg=f"], &inst);
    common::halcmd(&["net", "j0pos", "sampler.0.pin.0"], &inst);
    common::halcmd(&["addf", "sampler.0", "servo-thread"], &inst);
    let mut jobs = Vec::new();
    for (name, exe) in present_bins() {
        let probe = PROBES.iter().find(|p| p.bin == name);
        let mut lists: Vec<Vec<OsString>> = vec![vec!["--help".into()], vec!["-h".into()]];
        for l in probe.map_or(&[][..], |p| p.live) {
            lists.push(l.iter().map(OsString::from).collect());
        }
        for args in lists {
            jobs.push((name.clone(), exe.clone(), args, inst.clone(), Out::Closed));
        }
    }
    let count = jobs.len();
    let failures = run_all(jobs);
    let realtime = env!("CARGO_BIN_EXE_realtime");
    assert!(common::run(realtime, &["stop"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
    assert_none_failed(count, &failures);
}

#[test]
fn option_words_are_found_in_help_texts() {
    assert_eq!(
        options_in("usage: x [-i INSTANCE] [-t SECONDS]\n  -n, --count N  (--x=1) - -- -5"),
        ["-i", "-t", "-n", "--count", "--x"]
    );
}

#[test]
fn halcmd_h_prints_its_usage_and_command_help() {
    let none = "t-nopanic-usage-none";
    let out = common::run(env!("CARGO_BIN_EXE_halcmd"), &["-h"], none);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("Usage:\n  halcmd [options]"), "{text}");
    for want in [
        "-f [FILE]",
        "-k ",
        "-h, --help [COMMAND]",
        "loadrt MODULE",
        "net SIGNAL PIN",
    ] {
        assert!(text.contains(want), "no '{want}' in\n{text}");
    }
    let one = common::run(env!("CARGO_BIN_EXE_halcmd"), &["-h", "setp"], none);
    assert!(one.status.success());
    assert!(String::from_utf8_lossy(&one.stdout).starts_with("setp NAME VALUE"));
    let bad = common::run(env!("CARGO_BIN_EXE_halcmd"), &["-h", "nope"], none);
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("No help for unknown command 'nope'"));
}
