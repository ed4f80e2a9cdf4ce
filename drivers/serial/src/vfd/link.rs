//! [`Link`]: how a VFD component reports the health of its serial link
//! and of the drive: the `modbus-ok`, `fault` and `last-error` pins, the
//! driver layer's [`FaultLatch`] behind `fault`, and one message on
//! stderr per change (not one per failed request).

use hal_core::{Component, Out, Pin};
use hal_driver::fault::{Fault, FaultLatch};

use crate::error::SerialError;

/// The drive stopped answering or the line failed.
pub static LINK_LOST: Fault = Fault::new(
    1,
    "no answer from the VFD: spindle state unknown, at-speed held false \
     (set the drive's own communication timeout so it stops by itself)",
);
/// The drive reports a fault of its own.
pub static VFD_FAULT: Fault = Fault::new(2, "the VFD reports a fault");

/// The link's pins and state over one cycle.
pub struct Link {
    name: String,
    modbus_ok: Pin<bool, Out>,
    last_error: Pin<i32, Out>,
    latch: FaultLatch,
    /// A transaction of this cycle got no usable answer.
    lost: bool,
    /// A transaction of this cycle failed (refusals included).
    any_failure: bool,
    /// The message last printed, so a repeating failure is said once.
    said: Option<String>,
}

impl Link {
    /// Creates the pins `<prefix>.modbus-ok`, `<prefix>.fault` and
    /// `<prefix>.last-error` on `comp`.
    pub fn new(comp: &Component, prefix: &str) -> hal_core::Result<Link> {
        Ok(Link {
            name: prefix.to_string(),
            modbus_ok: comp.pin(&format!("{prefix}.modbus-ok"))?,
            last_error: comp.pin(&format!("{prefix}.last-error"))?,
            latch: FaultLatch::new(prefix).with_pin(comp.pin(&format!("{prefix}.fault"))?),
            lost: false,
            any_failure: false,
            said: None,
        })
    }

    /// Starts a cycle.
    pub fn begin_cycle(&mut self) {
        self.lost = false;
        self.any_failure = false;
    }

    /// Records a failed transaction. An exception reply is an answer
    /// (the link works; the request was refused); anything else means
    /// the drive was not heard.
    pub fn failed(&mut self, e: &SerialError) {
        self.last_error.set(e.code());
        self.any_failure = true;
        if !matches!(e, SerialError::Exception { .. }) {
            self.lost = true;
        }
        let msg = e.to_string();
        if self.said.as_deref() != Some(msg.as_str()) {
            eprintln!("{}: {msg}", self.name);
            self.said = Some(msg);
        }
    }

    /// Whether this cycle lost the drive so far.
    pub fn lost(&self) -> bool {
        self.lost
    }

    /// Ends a cycle: `modbus-ok` says whether every transaction was
    /// answered; `last-error` goes back to 0 after a cycle without any
    /// failure; `fault` whether the drive was lost or reports
    /// `drive_fault` (its fault code, 0 for none). Each change is said
    /// once.
    pub fn end_cycle(&mut self, drive_fault: u32) {
        self.modbus_ok.set(!self.lost);
        if !self.any_failure {
            self.last_error.set(0);
        }
        let want: Option<&'static Fault> = if self.lost {
            Some(&LINK_LOST)
        } else if drive_fault != 0 {
            Some(&VFD_FAULT)
        } else {
            None
        };
        if self.latch.fault() == want {
            return;
        }
        let old = self.latch.reset();
        match want {
            Some(f) => {
                self.latch.trip(f);
                if std::ptr::eq(f, &VFD_FAULT) {
                    eprintln!("{}: {} (code {drive_fault})", self.name, f.reason);
                } else {
                    eprintln!("{}: {}", self.name, f.reason);
                }
            }
            None if old.is_some_and(|f| std::ptr::eq(f, &LINK_LOST)) => {
                eprintln!("{}: the VFD answers again", self.name);
                self.said = None;
            }
            None => eprintln!("{}: the VFD's fault has cleared", self.name),
        }
    }

    /// Whether the link counts as working after the last cycle.
    pub fn ok(&self) -> bool {
        self.modbus_ok.get()
    }

    /// Whether the fault pin is up.
    pub fn faulted(&self) -> bool {
        self.latch.is_tripped()
    }
}
