//! `latency-test`'s command line, LinuxCNC's: `latency-test [-h|--help]
//! [base-period [servo-period]]`, periods in nanoseconds (a unit may be
//! added: `25us`, `1ms`). Options this suite adds for a headless run:
//! a duration, servo thread only, and the output files.

use std::time::Duration;

use crate::error::ScopeError as LatencyError;

/// LinuxCNC's default base period: 25 µs.
pub const DEFAULT_BASE_NS: i64 = 25_000;
/// LinuxCNC's default servo period: 1 ms.
pub const DEFAULT_SERVO_NS: i64 = 1_000_000;
/// Shortest base period accepted (LinuxCNC's latency-histogram minimum).
pub const MIN_BASE_NS: i64 = 5_000;
/// Shortest servo period accepted (LinuxCNC's latency-histogram minimum).
pub const MIN_SERVO_NS: i64 = 25_000;

/// The help text.
pub const HELP: &str = "\
usage: latency-test [options] [base-period [servo-period]]

Runs a base and a servo thread on a private HAL instance and measures how
late each thread wakes up against its deadline. Shows the minimum and
maximum live; at the end prints a summary, writes a histogram PNG and a
CSV, and says whether the figures allow software stepping, hardware
stepping only, or neither (LinuxCNC's thresholds).

Periods are in nanoseconds, or with a unit: ns, us, ms, s (default base
25000 = 25us, servo 1000000 = 1ms).

options:
  -d, --duration SECS  stop after SECS seconds (default: run until Ctrl-C)
  --nobase             servo thread only
  --png FILE           histogram image (default latency-test.png)
  --csv FILE           histogram table (default latency-test.csv)
  -h, --help           print this help and exit
  --version            print the version and exit

examples:
  latency-test                     25 us base, 1 ms servo, until Ctrl-C
  latency-test 50000 1000000       50 us base thread
  latency-test -d 600 25us 1ms     ten minutes, then the summary
  latency-test --nobase 1ms        servo thread only

While it runs, load the machine as it will be loaded in use: move
windows, copy large files, play a video. Run it for several minutes.
";

/// What the command line asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Base thread period in ns, `None` with `--nobase`.
    pub base_ns: Option<i64>,
    /// Servo thread period in ns.
    pub servo_ns: i64,
    /// How long to run; `None` until interrupted.
    pub duration: Option<Duration>,
    /// Where the histogram image goes.
    pub png: String,
    /// Where the histogram table goes.
    pub csv: String,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            base_ns: Some(DEFAULT_BASE_NS),
            servo_ns: DEFAULT_SERVO_NS,
            duration: None,
            png: "latency-test.png".into(),
            csv: "latency-test.csv".into(),
        }
    }
}

/// The parsed command line: run, or print the help.
#[derive(Debug, Clone, PartialEq)]
pub enum Parsed {
    /// Run with this configuration.
    Run(Config),
    /// `-h`/`--help`.
    Help,
    /// `--version`.
    Version,
}

/// A period: whole nanoseconds, or a number with a unit (`ns`, `us`,
/// `µs`, `ms`, `s`).
pub fn parse_period(s: &str) -> Option<i64> {
    let split = s
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(s.len());
    let (num, unit) = s.split_at(split);
    let scale = match unit {
        "" | "ns" => 1.0,
        "us" | "µs" => 1e3,
        "ms" => 1e6,
        "s" => 1e9,
        _ => return None,
    };
    if num.is_empty() {
        return None;
    }
    let v: f64 = num.parse().ok()?;
    let ns = (v * scale).round();
    (ns.is_finite() && ns >= 1.0 && ns <= i64::MAX as f64 / 2.0).then_some(ns as i64)
}

/// Parses the arguments after the program name.
pub fn parse(args: &[String]) -> Result<Parsed, LatencyError> {
    let usage = |m: String| LatencyError::Usage(m);
    let mut cfg = Config::default();
    let mut nobase = false;
    let mut periods = Vec::new();
    let mut i = 0;
    while i < args.len() {
        let a = args[i].as_str();
        let mut value = |what: &str| {
            i += 1;
            args.get(i)
                .cloned()
                .ok_or_else(|| usage(format!("{what} needs a value")))
        };
        match a {
            "-h" | "--help" | "-?" => return Ok(Parsed::Help),
            "--version" => return Ok(Parsed::Version),
            "-d" | "--duration" => {
                let v = value(a)?;
                let secs: f64 = v
                    .parse()
                    .ok()
                    .filter(|s: &f64| s.is_finite() && *s > 0.0 && *s < 1e9)
                    .ok_or_else(|| {
                        usage(format!("{a}: '{v}' is not a positive number of seconds"))
                    })?;
                cfg.duration = Some(Duration::from_secs_f64(secs));
            }
            "--nobase" => nobase = true,
            "--png" => cfg.png = value(a)?,
            "--csv" => cfg.csv = value(a)?,
            p if !p.starts_with('-') => periods.push(p.to_string()),
            other => return Err(usage(format!("unknown option '{other}'"))),
        }
        i += 1;
    }
    let period = |s: &String| {
        parse_period(s).ok_or_else(|| {
            usage(format!(
                "'{s}' is not a period (nanoseconds, or a number with ns, us, ms or s)"
            ))
        })
    };
    match (nobase, periods.as_slice()) {
        (_, []) => {}
        (true, [servo]) => cfg.servo_ns = period(servo)?,
        (false, [base]) => cfg.base_ns = Some(period(base)?),
        (false, [base, servo]) => {
            cfg.base_ns = Some(period(base)?);
            cfg.servo_ns = period(servo)?;
        }
        (true, _) => {
            return Err(usage(
                "--nobase takes at most one period, the servo's".into(),
            ))
        }
        (false, _) => return Err(usage("at most two periods: base and servo".into())),
    }
    if nobase {
        cfg.base_ns = None;
    }
    if cfg.servo_ns < MIN_SERVO_NS {
        return Err(usage(format!(
            "the servo period must be at least {MIN_SERVO_NS} ns, not {}",
            cfg.servo_ns
        )));
    }
    if let Some(base) = cfg.base_ns {
        if base < MIN_BASE_NS {
            return Err(usage(format!(
                "the base period must be at least {MIN_BASE_NS} ns, not {base}"
            )));
        }
        if base >= cfg.servo_ns {
            return Err(usage(format!(
                "the base period ({base} ns) must be shorter than the servo period ({} ns)",
                cfg.servo_ns
            )));
        }
    }
    Ok(Parsed::Run(cfg))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(args: &[&str]) -> Result<Parsed, LatencyError> {
        parse(&args.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    }

    fn run(args: &[&str]) -> Config {
        match p(args).unwrap() {
            Parsed::Run(c) => c,
            other => panic!("not a run: {other:?}"),
        }
    }

    #[test]
    fn linuxcnc_periods_and_defaults() {
        assert_eq!(run(&[]), Config::default());
        let c = run(&["50000", "1000000"]);
        assert_eq!((c.base_ns, c.servo_ns), (Some(50_000), 1_000_000));
        let c = run(&["40000"]);
        assert_eq!((c.base_ns, c.servo_ns), (Some(40_000), 1_000_000));
        let c = run(&["25us", "0.5ms"]);
        assert_eq!((c.base_ns, c.servo_ns), (Some(25_000), 500_000));
        assert_eq!(p(&["-h"]).unwrap(), Parsed::Help);
        assert_eq!(p(&["--help"]).unwrap(), Parsed::Help);
        assert_eq!(p(&["--version"]).unwrap(), Parsed::Version);
    }

    #[test]
    fn headless_options() {
        let c = run(&["-d", "2.5", "--png", "a.png", "--csv", "a.csv"]);
        assert_eq!(c.duration, Some(Duration::from_millis(2500)));
        assert_eq!((c.png.as_str(), c.csv.as_str()), ("a.png", "a.csv"));
        let c = run(&["--nobase", "2ms"]);
        assert_eq!((c.base_ns, c.servo_ns), (None, 2_000_000));
    }

    #[test]
    fn bad_arguments_say_what_is_wrong() {
        let msg = |a: &[&str]| p(a).unwrap_err().to_string();
        assert!(msg(&["fast"]).contains("'fast' is not a period"));
        assert!(msg(&["1000"]).contains("at least 5000"));
        assert!(msg(&["1000000", "50000"]).contains("must be shorter"));
        assert!(msg(&["1", "2", "3"]).contains("at most two"));
        assert!(msg(&["-d"]).contains("needs a value"));
        assert!(msg(&["-d", "-1"]).contains("positive number"));
        assert!(msg(&["--bogus"]).contains("unknown option"));
        assert!(msg(&["--nobase", "1ms", "2ms"]).contains("at most one"));
        assert_eq!(parse_period("12x"), None);
        assert_eq!(parse_period("ms"), None);
        assert_eq!(parse_period("1e99"), None);
        assert_eq!(parse_period("0"), None);
    }
}
