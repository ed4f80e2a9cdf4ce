//! halcmd `setthread THREAD KEY=VALUE...`: the integrator switches of a
//! thread that already exists, whoever made it (`loadrt threads`, motmod's
//! servo and base threads, a program hosting HAL). The same switches as
//! `loadrt threads`'s `timingN`, `cpuN` and `missedN`:
//!
//! - `timing=0|1`: per-function `.time`/`.tmax` measured or not;
//! - `cpu=N|default`: the CPU the thread runs on, or back to the default
//!   placement (`RTAPI_CPU_NUMBER`, else the last CPU under realtime);
//! - `missed=skip|catch-up`: what a late cycle does.
//!
//! Every switch is checked before any is applied, so a bad line changes
//! nothing.

use hal_core::{realtime, Host, MissedDeadline};

use crate::error::HostError;

/// One line's switches, checked.
#[derive(Debug, Default, PartialEq)]
struct Switches {
    timing: Option<bool>,
    /// `Some(None)`: back to the default placement.
    cpu: Option<Option<usize>>,
    missed: Option<MissedDeadline>,
}

/// Parses `KEY=VALUE` words for `thread`; `allowed` are the CPUs this
/// process may use.
fn parse(thread: &str, words: &[String], allowed: &[usize]) -> Result<Switches, HostError> {
    if words.is_empty() {
        return Err(HostError::NoSwitch {
            thread: thread.to_string(),
        });
    }
    let mut s = Switches::default();
    for word in words {
        let (key, value) = word.split_once('=').ok_or_else(|| HostError::NotKeyValue {
            thread: thread.to_string(),
            word: word.to_string(),
        })?;
        let bad = |reason: &str| HostError::BadSwitch {
            thread: thread.to_string(),
            key: key.to_string(),
            value: value.to_string(),
            reason: reason.to_string(),
        };
        match key {
            "timing" => {
                s.timing = Some(match value {
                    "1" => true,
                    "0" => false,
                    _ => return Err(bad("expected 0 or 1")),
                })
            }
            "cpu" => {
                s.cpu = Some(if value == "default" {
                    None
                } else {
                    Some(
                        realtime::parse_cpu("cpu", value, allowed).map_err(|source| {
                            HostError::BadCpu {
                                thread: thread.to_string(),
                                source,
                            }
                        })?,
                    )
                })
            }
            "missed" => {
                s.missed = Some(
                    MissedDeadline::from_name(value)
                        .ok_or_else(|| bad("expected skip or catch-up"))?,
                )
            }
            _ => {
                return Err(HostError::UnknownSwitch {
                    thread: thread.to_string(),
                    key: key.to_string(),
                })
            }
        }
    }
    Ok(s)
}

/// Runs `setthread` on `host`; `words` are the thread's name and its
/// switches.
pub fn apply(host: &Host, words: &[String]) -> Result<(), HostError> {
    let Some((thread, switches)) = words.split_first() else {
        return Err(HostError::NoThread);
    };
    let s = parse(thread, switches, &realtime::allowed_cpus())?;
    // A thread's switches are configuration, as `addf` is; and the thread
    // must exist before anything changes.
    host.instance()
        .check_unlocked(hal_core::lock_bits::CONFIG, "setthread")?;
    host.thread_options(thread)?;
    if let Some(cpu) = s.cpu {
        host.set_thread_cpu(thread, cpu)?;
    }
    if let Some(on) = s.timing {
        host.set_thread_timing(thread, on)?;
    }
    if let Some(policy) = s.missed {
        host.set_missed_deadline(thread, policy)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(w: &[&str]) -> Vec<String> {
        w.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn switches_parse_and_bad_ones_name_the_word() {
        let allowed = [0, 1];
        assert_eq!(
            parse(
                "t",
                &words(&["timing=0", "cpu=1", "missed=catch-up"]),
                &allowed
            )
            .unwrap(),
            Switches {
                timing: Some(false),
                cpu: Some(Some(1)),
                missed: Some(MissedDeadline::CatchUp),
            }
        );
        assert_eq!(
            parse("t", &words(&["cpu=default"]), &allowed).unwrap().cpu,
            Some(None)
        );
        for (bad, says) in [
            ("timing=2", "timing='2'"),
            ("cpu=7", "cpu=7"),
            ("cpu=x", "cpu='x'"),
            ("missed=later", "missed='later'"),
            ("colour=red", "unknown switch 'colour'"),
            ("timing", "'timing' is not KEY=VALUE"),
        ] {
            let e = parse("t", &words(&["timing=1", bad]), &allowed)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(says) && e.starts_with("setthread t:"),
                "{bad}: {e}"
            );
        }
        let e = parse("t", &[], &allowed).unwrap_err().to_string();
        assert!(e.contains("no switch"), "{e}");
    }
}
