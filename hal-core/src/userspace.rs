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
