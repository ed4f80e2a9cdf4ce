//! Helpers for user-space component processes: leave the instance
//! consistent when asked to exit.
//!
//! A user-space component is a [`crate::Component`] created through
//! [`crate::Instance::attach`]; dropping it removes it and everything it
//! owns. SIGTERM or SIGINT would kill the process before that drop, so
//! [`ExitSignals`] turns them into a flag the component's loop polls.

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Arc;

use crate::error::{HalError, Result};

/// A flag set by SIGTERM, SIGINT or SIGHUP.
#[derive(Clone)]
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

    /// Whether an exit was requested.
    pub fn requested(&self) -> bool {
        self.flag.load(Relaxed)
    }
}
