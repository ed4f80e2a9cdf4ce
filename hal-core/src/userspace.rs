//! Helpers for user-space component processes: arguments that may not be
//! UTF-8, and leaving the instance consistent when asked to exit.
//!
//! A user-space component is a [`crate::Component`] created through
//! [`crate::Instance::attach`]; dropping it removes it and everything it
//! owns. SIGTERM or SIGINT would kill the process before that drop, so
//! [`ExitSignals`] turns them into a flag the component's loop polls.

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Arc;

use crate::error::{HalError, Result};

/// A flag set by SIGTERM, SIGINT or SIGHUP.
#[derive(Clone, Debug)]
pub struct ExitSignals {
    flag: Arc<AtomicBool>,
}

impl ExitSignals {
    /// Installs the handlers (they only set the flag).
    pub fn install() -> Result<ExitSignals> {
        let flag = Arc::new(AtomicBool::new(false));
        for sig in [
            signal_hook::consts::SIGTERM,
            signal_hook::consts::SIGINT,
            signal_hook::consts::SIGHUP,
        ] {
            signal_hook::flag::register(sig, flag.clone()).map_err(|e| HalError::Io {
                op: "installing signal handler",
                path: Default::default(),
                source: e,
            })?;
        }
        Ok(ExitSignals { flag })
    }

    /// A flag no signal sets: stopped only by [`request`](Self::request)
    /// (a caller's own stop, tests).
    pub fn unarmed() -> ExitSignals {
        ExitSignals {
            flag: Arc::new(AtomicBool::new(false)),
        }
    }

    /// Sets the flag, as a signal would.
    pub fn request(&self) {
        self.flag.store(true, Relaxed);
    }

    /// Whether an exit was requested.
    pub fn requested(&self) -> bool {
        self.flag.load(Relaxed)
    }
}

/// The program's arguments (without its name) as `String`s; an argument
/// that is not UTF-8 is an error that says which one (`std::env::args`
/// would panic on it).
pub fn args() -> std::result::Result<Vec<String>, String> {
    args_from(std::env::args_os().skip(1))
}

/// [`args`], or the error printed as `tool: ...` and the process ended
/// with status `code`.
pub fn args_or_exit(tool: &str, code: i32) -> Vec<String> {
    args().unwrap_or_else(|e| {
        eprintln!("{tool}: {e}");
        std::process::exit(code)
    })
}

/// [`args`] over any list of arguments.
pub fn args_from(
    args: impl IntoIterator<Item = std::ffi::OsString>,
) -> std::result::Result<Vec<String>, String> {
    args.into_iter()
        .enumerate()
        .map(|(i, a)| {
            a.into_string().map_err(|bad| {
                format!(
                    "argument {} ({}) is not valid UTF-8",
                    i + 1,
                    bad.to_string_lossy()
                )
            })
        })
        .collect()
}

/// What `--version` prints in every program of the suite: the program's
/// name and the suite's version, as clap's `--version` prints them.
pub fn version_line(program: &str) -> String {
    format!("{program} {}", env!("CARGO_PKG_VERSION"))
}

/// Makes `name` the HAL instance of this process and of every program it
/// starts (the host, `loadusr` programs), as `HAL_INSTANCE=name` in the
/// environment would: what every tool's `--instance NAME` does. The name
/// is checked first.
///
/// It sets an environment variable: call it while reading the command
/// line, before the program starts any thread.
pub fn select_instance(name: &str) -> Result<()> {
    crate::objects::validate_instance_name(name)?;
    std::env::set_var("HAL_INSTANCE", name);
    Ok(())
}

/// The value of the instance option at `args[i]`, if that word is one:
/// `--instance NAME`, `--instance=NAME` and, where `short` is true (every
/// tool whose `-i` is not LinuxCNC's INI file), `-i NAME`. Returns the
/// name and how many words the option took, or the refusal when the name
/// is missing.
pub fn instance_option(
    args: &[String],
    i: usize,
    short: bool,
) -> Option<std::result::Result<(String, usize), crate::HalError>> {
    let word = args.get(i)?;
    if let Some(name) = word.strip_prefix("--instance=") {
        return Some(Ok((name.to_string(), 1)));
    }
    if word == "--instance" || (short && word == "-i") {
        return Some(match args.get(i + 1) {
            Some(name) => Ok((name.clone(), 2)),
            None => Err(crate::HalError::InstanceNameMissing {
                option: word.clone(),
            }),
        });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(w: &[&str]) -> Vec<String> {
        w.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_instance_option_takes_every_spelling() {
        let a = words(&["--instance", "m1", "--instance=m2", "-i", "m3", "-i"]);
        let at = |i, short| instance_option(&a, i, short).map(|r| r.map_err(|e| e.to_string()));
        assert_eq!(at(0, false), Some(Ok(("m1".into(), 2))));
        assert_eq!(at(2, false), Some(Ok(("m2".into(), 1))));
        assert_eq!(at(3, false), None);
        assert_eq!(at(3, true), Some(Ok(("m3".into(), 2))));
        assert_eq!(at(5, true), Some(Err("-i needs an instance name".into())));
        assert_eq!(at(6, true), None);
    }

    #[test]
    fn the_version_line_names_the_program() {
        assert_eq!(
            version_line("halcmd"),
            format!("halcmd {}", env!("CARGO_PKG_VERSION"))
        );
    }
}
