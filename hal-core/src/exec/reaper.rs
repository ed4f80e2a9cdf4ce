//! The host's reaper: a thread that removes user-space components whose
//! process died without removing them (see `objects::owner`).

use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use crate::error::{HalError, Result};
use crate::objects::Instance;

/// How often the reaper looks for dead owners. A killed component's pins
/// disappear within this time.
const INTERVAL: Duration = Duration::from_millis(100);

/// The reaper thread; stopped by [`Reaper::stop`] or on drop.
pub(crate) struct Reaper {
    /// Set to true to stop; the condvar wakes the thread early.
    stop: Arc<(Mutex<bool>, Condvar)>,
    join: Mutex<Option<JoinHandle<()>>>,
}

impl Reaper {
    pub(crate) fn start(inst: Instance) -> Result<Reaper> {
        let stop = Arc::new((Mutex::new(false), Condvar::new()));
        let flag = stop.clone();
        let join = std::thread::Builder::new()
            .name("hal-reaper".into())
            .spawn(move || run(inst, &flag))
            .map_err(|e| HalError::io("starting the reaper thread", "", e))?;
        Ok(Reaper {
            stop,
            join: Mutex::new(Some(join)),
        })
    }

    /// Stops the thread and waits for it.
    pub(crate) fn stop(&self) {
        {
            let (m, cv) = &*self.stop;
            *m.lock().unwrap_or_else(|e| e.into_inner()) = true;
            cv.notify_all();
        }
        let join = self.join.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some(j) = join {
            let _ = j.join();
        }
    }
}

impl Drop for Reaper {
    fn drop(&mut self) {
        self.stop();
    }
}

fn run(inst: Instance, stop: &(Mutex<bool>, Condvar)) {
    let (m, cv) = stop;
    // A failure is reported once, not every interval, until it clears.
    let mut failing = false;
    let mut stopped = m.lock().unwrap_or_else(|e| e.into_inner());
    while !*stopped {
        let (guard, _) = cv
            .wait_timeout(stopped, INTERVAL)
            .unwrap_or_else(|e| e.into_inner());
        stopped = guard;
        if *stopped {
            break;
        }
        drop(stopped);
        match inst.reap_dead_components() {
            Ok(names) => {
                failing = false;
                for name in names {
                    eprintln!(
                        "HAL: user component '{name}' removed: its process ended without removing it"
                    );
                }
            }
            Err(e) if !failing => {
                failing = true;
                eprintln!("HAL: checking for dead user components failed: {e}");
            }
            Err(_) => {}
        }
        stopped = m.lock().unwrap_or_else(|e| e.into_inner());
    }
}
