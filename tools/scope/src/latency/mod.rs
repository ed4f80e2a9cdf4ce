//! `latency-test`: the headless latency test an integrator runs first on
//! a new PC.
//!
//! It starts a HAL host on a private instance with a base and a servo
//! thread (LinuxCNC's default periods: 25 µs and 1 ms), shows each
//! thread's wake-up latency live, and at the end prints a summary table,
//! writes a histogram PNG and a CSV, says what the figures allow (software
//! stepping, hardware stepping only, or neither, with LinuxCNC's
//! thresholds) and which realtime permissions were in force.
//!
//! The figures are the threads' own: every HAL thread measures how late
//! it woke against its absolute deadline, and keeps the minimum, the
//! maximum, an overrun count and a histogram in the segment
//! ([`hal_core::ThreadInfo`]). The test only reads them.
//!
//! Modules: [`args`] (the command line), [`stats`] (figures of a thread,
//! percentiles, the verdict), [`perms`] (what the host was allowed),
//! [`report`] (table and CSV), [`histplot`] (the PNG), [`session`] (the
//! private instance).

pub mod args;
pub mod histplot;
pub mod perms;
pub mod report;
pub mod session;
pub mod stats;

use std::io::Write;
use std::time::{Duration, Instant};

use args::Config;
use perms::Permissions;
use session::Session;
use stats::ThreadStats;

/// What can stop a latency test: the crate's [`ScopeError`], under the
/// name the latency test's code uses.
pub use crate::error::ScopeError as LatencyError;

/// How often the live line is refreshed on a terminal, and elsewhere.
const LIVE_TTY: Duration = Duration::from_millis(250);
const LIVE_LOG: Duration = Duration::from_secs(1);

/// Runs the threads of `session` until `cfg.duration` passes or
/// `interrupted` says so, showing the live line on `out` (rewritten in
/// place when `tty`). Then stops the threads and returns their final
/// figures and the permissions the host had in force.
pub fn measure(
    session: &Session,
    cfg: &Config,
    out: &mut dyn Write,
    tty: bool,
    interrupted: &dyn Fn() -> bool,
) -> Result<(Vec<ThreadStats>, Permissions), LatencyError> {
    let start = Instant::now();
    let every = if tty { LIVE_TTY } else { LIVE_LOG };
    let mut next_line = start + every;
    let mut perms = None;
    loop {
        let now = Instant::now();
        let done = cfg.duration.is_some_and(|d| now - start >= d) || interrupted();
        if !session.host_alive() {
            return Err(LatencyError::HostGone);
        }
        let snap = session.snapshot()?;
        // Each executor sets its scheduling before its first cycle.
        if perms.is_none() && !snap.is_empty() && snap.iter().all(|t| t.cycles > 0) {
            perms = session
                .host_pid()
                .map(|pid| perms::read(pid, session.thread_names()));
        }
        if now >= next_line || done {
            let line = report::live_line((now - start).as_secs_f64(), &snap);
            let _ = if tty {
                write!(out, "\r\x1b[2K{line}")
            } else {
                writeln!(out, "{line}")
            };
            let _ = out.flush();
            next_line = now + every;
        }
        if done {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    if tty {
        let _ = writeln!(out);
    }
    let perms = match perms {
        Some(p) => p,
        None => session
            .host_pid()
            .map(|pid| perms::read(pid, session.thread_names()))
            .unwrap_or_default(),
    };
    session.stop_threads()?;
    Ok((settled_snapshot(session)?, perms))
}

/// A snapshot taken once two in a row agree: a thread that was waking as
/// `stop` came may still count that wake-up.
fn settled_snapshot(session: &Session) -> Result<Vec<ThreadStats>, LatencyError> {
    let mut last = session.snapshot()?;
    let end = Instant::now() + Duration::from_secs(2);
    loop {
        std::thread::sleep(Duration::from_millis(5));
        let now = session.snapshot()?;
        if now == last || Instant::now() > end {
            return Ok(now);
        }
        last = now;
    }
}

/// Prints the summary, the verdict and the permissions to `out`, and
/// writes the PNG and the CSV `cfg` names. Returns where the bars of the
/// PNG went.
pub fn report(
    threads: &[ThreadStats],
    perms: &Permissions,
    cfg: &Config,
    out: &mut dyn Write,
) -> Result<histplot::Drawn, LatencyError> {
    let verdict = stats::verdict(threads);
    let verdict_text = match verdict {
        Some((v, max)) => format!(
            "largest latency {:.1} us: {}",
            max as f64 / 1000.0,
            v.sentence()
        ),
        None => "no thread ran a cycle: no verdict".to_string(),
    };
    let realtime = if perms.realtime() {
        "SCHED_FIFO"
    } else {
        "NO REALTIME"
    };
    let title = match verdict {
        Some((v, max)) => format!(
            "LATENCY TEST ({realtime}): MAX {:.1} US: {}",
            max as f64 / 1000.0,
            v.short()
        ),
        None => format!("LATENCY TEST ({realtime}): NO CYCLES"),
    };
    let drawn = histplot::draw(threads, &title, &cfg.png).map_err(|e| LatencyError::Output {
        path: cfg.png.clone(),
        source: Box::new(e),
    })?;
    std::fs::write(&cfg.csv, report::histogram_csv(threads)).map_err(|e| LatencyError::Output {
        path: cfg.csv.clone(),
        source: Box::new(e),
    })?;
    let _ = write!(out, "\n{}", report::summary_table(threads));
    let _ = writeln!(out, "\nverdict: {verdict_text}");
    let _ = write!(out, "permissions in force:\n{}", perms::describe(perms));
    let _ = writeln!(out, "histogram: {} and {}", cfg.png, cfg.csv);
    Ok(drawn)
}
