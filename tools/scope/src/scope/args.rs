//! `halscope`'s headless command line (clap): which pins, which thread,
//! the trigger, the record length and pre-trigger share, the outputs.

use std::path::PathBuf;
use std::time::Duration;

use clap::Parser;

use super::capture::{Edge, TriggerSpec};
use super::ScopeError;

const EXAMPLES: &str = "\
Examples:
  halscope --pins siggen.0.square,siggen.0.sine --thread servo-thread \\
           --trigger siggen.0.square:rising:0.5 --samples 2000 --pre 20% \\
           --out capture.png --out capture.csv
  halscope --pins x-vel,x-step --thread base-thread --samples 4000 --out run.vcd
  halscope --channel 0 --trigger 0:falling:0 --samples 500 --out c.csv
      (capture through channel 0 of a sampler the HAL file loaded;
       trigger on its first column)
  halscope --pins siggen.0.sine --mult 4 --trigger 0:rising:0 --out s.csv
      (the HAL file loaded scope_rt and added scope.sample to a thread:
       it samples, every 4th period)

Names in --pins are pins or signals; the trigger names one of them (or
its column number). Without --trigger the capture starts at once.
When the configuration loaded scope_rt, --pins are captured through it
(at most 16, the record at most its num_samples / channels samples),
in the thread where scope.sample was added; otherwise halscope loads a
sampler of its own in --thread.";

/// Captures HAL pins at the full rate of a thread into a PNG, CSV or VCD
/// file, with an oscilloscope's trigger (level, edge, pre-trigger).
#[derive(Debug, Parser)]
#[command(name = "halscope", version, after_help = EXAMPLES)]
pub struct Args {
    /// Pins or signals to capture, comma separated (at most 21).
    #[arg(long, value_delimiter = ',', conflicts_with = "channel")]
    pub pins: Vec<String>,
    /// The thread to sample in (its period is the sample interval);
    /// with scope_rt loaded, where scope.sample runs (may be left out).
    #[arg(long, conflicts_with = "channel")]
    pub thread: Option<String>,
    /// Sample rate multiplier: record every Nth period of the thread
    /// (scope_rt only).
    #[arg(long, default_value_t = 1)]
    pub mult: u32,
    /// Capture through this channel of a `sampler` already loaded and
    /// netted by the HAL file (instead of --pins and --thread).
    #[arg(long)]
    pub channel: Option<usize>,
    /// Trigger: NAME:rising|falling:LEVEL (NAME a captured pin or its
    /// column number).
    #[arg(long)]
    pub trigger: Option<String>,
    /// Samples in the record.
    #[arg(long, default_value_t = 1000)]
    pub samples: usize,
    /// Share of the record before the trigger: `20%` or `0.2`.
    #[arg(long, default_value = "0%")]
    pub pre: String,
    /// Output files; the extension picks the format: .png, .csv, .vcd.
    #[arg(long, required = true)]
    pub out: Vec<PathBuf>,
    /// Give up when no trigger came after this many seconds (plus the
    /// time the record takes).
    #[arg(long, default_value_t = 10.0)]
    pub timeout: f64,
    /// HAL instance (default: $HAL_INSTANCE or 'default').
    #[arg(short, long, value_name = "NAME")]
    pub instance: Option<String>,
}

/// Most samples in one record.
pub const MAX_SAMPLES: usize = 10_000_000;

/// The output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A plot.
    Png,
    /// A table: sample, time, one column per pin.
    Csv,
    /// Value Change Dump, for waveform viewers.
    Vcd,
}

/// What the command line asks for, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// Where the samples come from.
    pub source: Source,
    /// The trigger, if any.
    pub trigger: Option<TriggerSpec>,
    /// Samples in the record.
    pub samples: usize,
    /// Samples before the trigger.
    pub pre: usize,
    /// Files to write.
    pub outputs: Vec<(PathBuf, Format)>,
    /// How long to wait for the record.
    pub timeout: Duration,
    /// Record every `mult`-th period (scope_rt only; 1 otherwise).
    pub mult: u32,
}

/// Where the samples come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// Pins or signals, captured through scope_rt when the configuration
    /// loaded it, else by a sampler of halscope's own in the thread.
    Own {
        /// Pins or signals.
        names: Vec<String>,
        /// The thread (may be left out with scope_rt).
        thread: Option<String>,
    },
    /// A channel of a sampler the configuration loaded.
    Channel(usize),
}

/// `20%` or `0.2` as a share in [0, 1].
pub fn parse_share(s: &str) -> Option<f64> {
    let v = match s.strip_suffix('%') {
        Some(p) => p.trim().parse::<f64>().ok()? / 100.0,
        None => s.trim().parse::<f64>().ok()?,
    };
    (0.0..=1.0).contains(&v).then_some(v)
}

/// `NAME:rising|falling:LEVEL`; the name may itself hold colons.
pub fn parse_trigger(s: &str) -> Option<TriggerSpec> {
    let (rest, level) = s.rsplit_once(':')?;
    let (name, edge) = rest.rsplit_once(':')?;
    let edge = match edge.to_ascii_lowercase().as_str() {
        "rising" | "rise" | "pos" | "+" => Edge::Rising,
        "falling" | "fall" | "neg" | "-" => Edge::Falling,
        _ => return None,
    };
    let level: f64 = level.parse().ok().filter(|l: &f64| l.is_finite())?;
    (!name.is_empty()).then(|| TriggerSpec {
        name: name.to_string(),
        edge,
        level,
    })
}

impl Args {
    /// Checks the arguments and turns them into a [`Request`].
    pub fn request(self) -> Result<Request, ScopeError> {
        let usage = |m: String| ScopeError::Usage(m);
        let source = match (self.channel, self.thread) {
            (Some(c), _) => Source::Channel(c),
            (None, thread) if !self.pins.is_empty() => {
                let names: Vec<String> = self
                    .pins
                    .iter()
                    .map(|p| p.trim().to_string())
                    .filter(|p| !p.is_empty())
                    .collect();
                if names.is_empty() {
                    return Err(usage("--pins names nothing to capture".into()));
                }
                Source::Own { names, thread }
            }
            (None, _) => return Err(usage("give --pins (and --thread), or --channel".into())),
        };
        if self.samples < 2 || self.samples > MAX_SAMPLES {
            return Err(usage(format!(
                "--samples {}: give 2 to {MAX_SAMPLES}",
                self.samples
            )));
        }
        let share = parse_share(&self.pre).ok_or_else(|| {
            usage(format!(
                "--pre '{}': give a share such as 20% or 0.2",
                self.pre
            ))
        })?;
        let trigger = match &self.trigger {
            None => None,
            Some(t) => Some(parse_trigger(t).ok_or_else(|| {
                usage(format!(
                    "--trigger '{t}': give NAME:rising:LEVEL or NAME:falling:LEVEL"
                ))
            })?),
        };
        // Without a trigger the record starts at once: nothing comes before.
        let pre = if trigger.is_some() {
            ((self.samples as f64 * share).round() as usize).min(self.samples - 1)
        } else {
            0
        };
        let outputs = self
            .out
            .into_iter()
            .map(|p| {
                let ext = p
                    .extension()
                    .and_then(|e| e.to_str())
                    .map(str::to_ascii_lowercase);
                let f = match ext.as_deref() {
                    Some("png") => Format::Png,
                    Some("csv") => Format::Csv,
                    Some("vcd") => Format::Vcd,
                    _ => {
                        return Err(usage(format!(
                            "--out {}: the name must end in .png, .csv or .vcd",
                            p.display()
                        )))
                    }
                };
                Ok((p, f))
            })
            .collect::<Result<Vec<_>, _>>()?;
        if self.mult == 0 || self.mult > i32::MAX as u32 {
            return Err(usage(format!("--mult {}: give 1 to 2147483647", self.mult)));
        }
        if self.mult > 1 && matches!(source, Source::Channel(_)) {
            return Err(usage(
                "--mult: a sampler channel samples every period; the multiplier is scope_rt's"
                    .into(),
            ));
        }
        if !(self.timeout.is_finite() && self.timeout > 0.0 && self.timeout < 1e7) {
            return Err(usage(format!(
                "--timeout {}: give a positive number of seconds",
                self.timeout
            )));
        }
        Ok(Request {
            source,
            trigger,
            samples: self.samples,
            pre,
            outputs,
            timeout: Duration::from_secs_f64(self.timeout),
            mult: self.mult,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn req(args: &[&str]) -> Result<Request, ScopeError> {
        let mut v = vec!["halscope"];
        v.extend(args);
        Args::try_parse_from(v)
            .map_err(|e| ScopeError::Usage(e.to_string()))?
            .request()
    }

    #[test]
    fn the_issue_example() {
        let r = req(&[
            "--pins",
            "a,b,c",
            "--thread",
            "servo-thread",
            "--trigger",
            "a:rising:0.5",
            "--samples",
            "1000",
            "--pre",
            "20%",
            "--out",
            "capture.png",
            "--out",
            "c.CSV",
        ])
        .unwrap();
        assert_eq!(
            r.source,
            Source::Own {
                names: vec!["a".into(), "b".into(), "c".into()],
                thread: Some("servo-thread".into())
            }
        );
        assert_eq!(r.pre, 200);
        assert_eq!(
            r.trigger,
            Some(TriggerSpec {
                name: "a".into(),
                edge: Edge::Rising,
                level: 0.5
            })
        );
        assert_eq!(r.outputs[1].1, Format::Csv);
    }

    #[test]
    fn bad_arguments_say_what() {
        let e = |a: &[&str]| req(a).unwrap_err().to_string();
        assert!(e(&["--out", "x.png"]).contains("--channel"));
        assert!(e(&["--pins", "a", "--mult", "0", "--out", "x.png"]).contains("--mult"));
        assert!(e(&["--channel", "1", "--mult", "2", "--out", "x.png"]).contains("scope_rt"));
        assert!(
            e(&["--pins", "a", "--thread", "t", "--out", "x.gif"]).contains(".png, .csv or .vcd")
        );
        assert!(e(&["--channel", "0", "--pre", "120%", "--out", "x.csv"]).contains("--pre"));
        assert!(
            e(&["--channel", "0", "--trigger", "a:up:1", "--out", "x.csv"]).contains("--trigger")
        );
        assert!(e(&["--channel", "0", "--samples", "1", "--out", "x.csv"]).contains("--samples"));
        assert!(e(&["--pins", ",", "--thread", "t", "--out", "x.csv"]).contains("nothing"));
        assert_eq!(parse_trigger("a:b:falling:-1.5").unwrap().name, "a:b");
        assert_eq!(parse_share("0.25"), Some(0.25));
        assert_eq!(parse_share("nan"), None);
    }
}
