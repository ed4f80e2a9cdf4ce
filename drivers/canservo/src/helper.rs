//! The non-realtime helper: one thread per bus that does the SDO work
//! after start-up, so it never delays a servo period. It owns its own
//! endpoint (a second socket, or a second endpoint of the simulated bus),
//! so its frames and waits never touch the realtime endpoint, and it
//! talks to the realtime side only through [`DriveShared`] atomics.
//!
//! Its jobs:
//! * restarts: after a communication fault and an explicit fault reset,
//!   bring the node up again from NMT reset ([`startup::restart_node`]);
//! * diagnosis: when a drive faults, read its error register (0x1001) and
//!   the newest error history entry (0x1003:1) and log them with their
//!   meaning;
//! * polling: read each drive's error register every `diag` period, for
//!   the `error-register` pin.

use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use hal_driver::LogSink;

use crate::bus::CanBus;
use crate::codes::ErrorCode;
use crate::engine::{DriveShared, Restart};
use crate::regs::obj;
use crate::sdo::SdoClient;
use crate::startup::{self, NodePlan, StartupConfig};

/// One drive as the helper knows it.
#[derive(Debug, Clone)]
pub struct HelperDrive {
    /// Its HAL index (canservo.N).
    pub index: usize,
    /// How to bring it up.
    pub plan: NodePlan,
    /// What it shares with the realtime side.
    pub shared: Arc<DriveShared>,
}

/// The running helper; dropping it stops and joins the thread.
#[derive(Debug)]
pub struct Helper {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Helper {
    /// Starts the helper on `bus` (an endpoint with
    /// [`Filters::setup`](crate::bus::Filters::setup) filters).
    pub fn spawn(
        bus: Box<dyn CanBus>,
        drives: Vec<HelperDrive>,
        startup: StartupConfig,
        diag: Option<Duration>,
        log: LogSink,
    ) -> std::io::Result<Helper> {
        let stop = Arc::new(AtomicBool::new(false));
        let s = stop.clone();
        let thread = std::thread::Builder::new()
            .name("canservo-helper".into())
            .spawn(move || run(&*bus, &drives, &startup, diag, &log, &s))?;
        Ok(Helper {
            stop,
            thread: Some(thread),
        })
    }
}

impl Drop for Helper {
    fn drop(&mut self) {
        self.stop.store(true, Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn run(
    bus: &dyn CanBus,
    drives: &[HelperDrive],
    startup: &StartupConfig,
    diag: Option<Duration>,
    log: &LogSink,
    stop: &AtomicBool,
) {
    let mut next_poll = Instant::now();
    while !stop.load(Relaxed) {
        for d in drives {
            if d.shared.restart() == Restart::Requested {
                d.shared.set_restart(Restart::Running);
                match startup::restart_node(bus, startup, &d.plan) {
                    Ok(_) => d.shared.set_restart(Restart::Done),
                    Err(e) => {
                        log.err(format_args!(
                            "canservo.{} (node {}): bringing it up again failed: {e}",
                            d.index, d.plan.node
                        ));
                        d.shared.set_restart(Restart::Failed);
                    }
                }
            }
            if d.shared.take_diagnosis() {
                diagnose(bus, d, startup.sdo_timeout, log);
            }
        }
        if let Some(period) = diag {
            if Instant::now() >= next_poll {
                next_poll = Instant::now() + period;
                for d in drives {
                    if stop.load(Relaxed) {
                        return;
                    }
                    let sdo = SdoClient::new(bus, d.plan.node, startup.sdo_timeout);
                    if let Ok(r) = sdo.read_u8(obj::ERROR_REGISTER, 0) {
                        d.shared.error_register.store(u32::from(r), Relaxed);
                    }
                }
            }
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Logs a faulted drive's error register and newest error.
fn diagnose(bus: &dyn CanBus, d: &HelperDrive, timeout: Duration, log: &LogSink) {
    let sdo = SdoClient::new(bus, d.plan.node, timeout);
    let (Ok(register), Ok(count)) = (
        sdo.read_u8(obj::ERROR_REGISTER, 0),
        sdo.read_u8(obj::ERROR_HISTORY, 0),
    ) else {
        return;
    };
    d.shared.error_register.store(u32::from(register), Relaxed);
    let newest = if count > 0 {
        sdo.read_u32(obj::ERROR_HISTORY, 1).ok()
    } else {
        None
    };
    match newest {
        Some(e) => log.info(format_args!(
            "canservo.{} (node {}): error register {register:#04x}, {count} error(s) in history, newest {}",
            d.index,
            d.plan.node,
            ErrorCode(e as u16)
        )),
        None => log.info(format_args!(
            "canservo.{} (node {}): error register {register:#04x}, error history empty",
            d.index, d.plan.node
        )),
    };
}
