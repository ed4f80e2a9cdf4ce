//! iocontrol's second tool changer protocol, as LinuxCNC's `iov2` has it
//! (`[EMCIO]EMCIO = iov2`): an abort from the controller that the changer
//! acknowledges (`emc-abort` / `emc-abort-ack`, with `emc-reason`), a
//! fault from the changer that iocontrol acknowledges and remembers until
//! it is cleared (`toolchanger-fault` / `-fault-ack`, `-reason`,
//! `-faulted`, `-clear-fault`), and, with `-support-start-change`, a
//! handshake at the very start of an M6 (`start-change` / `-ack`).
//!
//! A remembered fault aborts the next tool change: a positive reason is a
//! soft fault (the program goes on without the change), zero or a
//! negative one a hard fault (the program stops).

use hal_core::{Component, In, Out, Pin};
use hal_lang::ini::Ini;

/// Which iocontrol the configuration asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Flavour {
    /// `iov2`: it has the `state` pin and no `tool-from-pocket`.
    pub iov2: bool,
    /// The version 2 protocol and its pins (`iov2` unless
    /// `[EMCIO]PROTOCOL_VERSION` is 1).
    pub v2: bool,
    /// `-support-start-change`: M6 begins with the start-change handshake.
    pub start_change: bool,
}

impl Flavour {
    /// LinuxCNC's plain `io`.
    pub const IO: Flavour = Flavour {
        iov2: false,
        v2: false,
        start_change: false,
    };

    /// The flavour `[EMCIO]EMCIO` and `PROTOCOL_VERSION` name. Anything
    /// but `iov2` (`io`, a missing key, another program) is plain `io`; a
    /// protocol version that is not a whole number is ignored, as
    /// LinuxCNC's iov2 ignores it.
    pub fn from_ini(ini: &Ini) -> Flavour {
        let Some(value) = ini.get("EMCIO", "EMCIO") else {
            return Flavour::IO;
        };
        let mut words = value.split_whitespace();
        let program = words.next().unwrap_or("");
        let name = program.rsplit('/').next().unwrap_or(program);
        if name != "iov2" {
            return Flavour::IO;
        }
        let version = ini
            .get("EMCIO", "PROTOCOL_VERSION")
            .and_then(|v| v.trim().parse::<i32>().ok())
            .unwrap_or(2);
        let v2 = version > 1;
        Flavour {
            iov2: true,
            v2,
            start_change: v2 && words.any(|w| w == "-support-start-change"),
        }
    }
}

/// The `state` pin's values.
pub mod state {
    /// No handshake.
    pub const IDLE: i32 = 0;
    /// `tool-prepare` is up.
    pub const PREPARING: i32 = 1;
    /// `start-change` is up.
    pub const START_CHANGE: i32 = 2;
    /// `tool-change` is up.
    pub const CHANGING: i32 = 3;
    /// `emc-abort` is up, waiting for `emc-abort-ack`.
    pub const WAIT_FOR_ABORT_ACK: i32 = 4;
}

/// `emc-reason` of an abort asked by the operator or by task (LinuxCNC's
/// `EMC_ABORT_TASK_ABORT`).
pub const REASON_TASK_ABORT: i32 = 8;
/// `emc-reason` of a change given up because the changer had faulted
/// (LinuxCNC's user range starts at 100; iov2 uses the first code).
pub const REASON_TOOLCHANGER_FAULT: i32 = 101;

/// The protocol's inputs, read once per cycle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct V2Inputs {
    /// `emc-abort-ack`.
    pub emc_abort_ack: bool,
    /// `toolchanger-fault`.
    pub toolchanger_fault: bool,
    /// `toolchanger-reason`.
    pub toolchanger_reason: i32,
    /// `toolchanger-clear-fault`.
    pub toolchanger_clear_fault: bool,
    /// `start-change-ack`.
    pub start_change_ack: bool,
}

/// The protocol's outputs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct V2Outputs {
    /// `emc-abort`.
    pub emc_abort: bool,
    /// `emc-reason`.
    pub emc_reason: i32,
    /// `toolchanger-fault-ack`.
    pub toolchanger_fault_ack: bool,
    /// `toolchanger-faulted`: a fault was seen and not yet cleared.
    pub toolchanger_faulted: bool,
    /// `start-change`.
    pub start_change: bool,
}

/// The protocol's pins.
pub struct V2Pins {
    emc_abort: Pin<bool, Out>,
    emc_abort_ack: Pin<bool, In>,
    emc_reason: Pin<i32, Out>,
    toolchanger_fault: Pin<bool, In>,
    toolchanger_fault_ack: Pin<bool, Out>,
    toolchanger_reason: Pin<i32, In>,
    toolchanger_faulted: Pin<bool, Out>,
    toolchanger_clear_fault: Pin<bool, In>,
    start_change: Pin<bool, Out>,
    start_change_ack: Pin<bool, In>,
}

impl V2Pins {
    /// Makes the pins on iocontrol's component (LinuxCNC's names and
    /// directions).
    pub fn create(c: &Component) -> hal_core::Result<V2Pins> {
        let p = |n: &str| format!("iocontrol.0.{n}");
        Ok(V2Pins {
            emc_abort: c.pin(&p("emc-abort"))?,
            emc_abort_ack: c.pin(&p("emc-abort-ack"))?,
            emc_reason: c.pin(&p("emc-reason"))?,
            toolchanger_fault: c.pin(&p("toolchanger-fault"))?,
            toolchanger_fault_ack: c.pin(&p("toolchanger-fault-ack"))?,
            toolchanger_reason: c.pin(&p("toolchanger-reason"))?,
            toolchanger_faulted: c.pin(&p("toolchanger-faulted"))?,
            toolchanger_clear_fault: c.pin(&p("toolchanger-clear-fault"))?,
            start_change: c.pin(&p("start-change"))?,
            start_change_ack: c.pin(&p("start-change-ack"))?,
        })
    }

    /// Reads the inputs.
    pub fn inputs(&self) -> V2Inputs {
        V2Inputs {
            emc_abort_ack: self.emc_abort_ack.get(),
            toolchanger_fault: self.toolchanger_fault.get(),
            toolchanger_reason: self.toolchanger_reason.get(),
            toolchanger_clear_fault: self.toolchanger_clear_fault.get(),
            start_change_ack: self.start_change_ack.get(),
        }
    }

    /// Writes the outputs.
    pub fn write(&self, o: &V2Outputs) {
        self.emc_abort.set(o.emc_abort);
        self.emc_reason.set(o.emc_reason);
        self.toolchanger_fault_ack.set(o.toolchanger_fault_ack);
        self.toolchanger_faulted.set(o.toolchanger_faulted);
        self.start_change.set(o.start_change);
    }
}

/// The protocol's own state: the fault remembered and the last reason.
#[derive(Debug, Clone, Copy, Default)]
pub struct V2State {
    /// The changer's last fault reason (0 once cleared).
    pub reason: i32,
}

/// What one cycle of the protocol saw.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct V2Step {
    /// The changer acknowledged the controller's abort.
    pub abort_acked: bool,
    /// The changer acknowledged the start of a change.
    pub start_change_acked: bool,
}

impl V2State {
    /// The fault and handshake lines of one cycle.
    pub fn step(&mut self, inp: &V2Inputs, out: &mut V2Outputs) -> V2Step {
        if inp.toolchanger_fault {
            self.reason = inp.toolchanger_reason;
            out.toolchanger_fault_ack = true;
            out.toolchanger_faulted = true;
        } else {
            out.toolchanger_fault_ack = false;
        }
        if inp.toolchanger_clear_fault {
            out.toolchanger_faulted = false;
            self.reason = 0;
        }
        let mut seen = V2Step::default();
        if out.emc_abort && inp.emc_abort_ack {
            out.emc_abort = false;
            seen.abort_acked = true;
        }
        if out.start_change && inp.start_change_ack {
            out.start_change = false;
            seen.start_change_acked = true;
        }
        seen
    }
}

/// The text of a hard toolchanger fault: `[TASK]IO_ERROR` (LinuxCNC's
/// default "toolchanger error %d") with the reason in place of its `%d`.
pub fn hard_fault_text(template: &str, reason: i32) -> String {
    if reason < 0 {
        template.replacen("%d", &reason.to_string(), 1)
    } else {
        format!("M6: toolchanger hard fault, reason={reason}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::iocontrol::{IoControl, IoEvent, IoInputs, IoRequest, Started, ToolTable};

    fn flavour(emcio: &str) -> Flavour {
        Flavour::from_ini(&Ini::parse(&format!("[EMCIO]\n{emcio}\n")))
    }

    #[test]
    fn the_flavour_comes_from_emcio_and_protocol_version() {
        assert_eq!(flavour("EMCIO = io"), Flavour::IO);
        assert_eq!(flavour(""), Flavour::IO);
        let demo = flavour("EMCIO = iov2 -support-start-change\nPROTOCOL_VERSION = 1.1");
        assert_eq!(
            demo,
            Flavour {
                iov2: true,
                v2: true,
                start_change: true
            },
            "1.1 is not a whole number: the default version 2 holds"
        );
        let v1 = flavour("EMCIO = /usr/bin/iov2 -support-start-change\nPROTOCOL_VERSION = 1");
        assert_eq!(
            v1,
            Flavour {
                iov2: true,
                v2: false,
                start_change: false
            }
        );
    }

    fn iov2(start_change: bool) -> IoControl {
        let table = ToolTable::parse("T1 P5\nT2 P3\n".as_bytes(), "t.tbl", false).unwrap();
        let mut io = IoControl::new(table, None);
        io.set_flavour(Flavour {
            iov2: true,
            v2: true,
            start_change,
        });
        io
    }

    fn inputs(f: impl FnOnce(&mut IoInputs)) -> IoInputs {
        let mut i = IoInputs {
            emc_enable_in: true,
            lube_level: true,
            ..IoInputs::default()
        };
        f(&mut i);
        i
    }

    #[test]
    fn a_fault_since_the_prepare_gives_the_next_change_up() {
        let mut io = iov2(false);
        io.request(&IoRequest::Prepare { tool: 2 }).unwrap();
        assert_eq!(io.outputs().state, state::PREPARING);
        io.step(&inputs(|i| i.tool_prepared = true));
        assert_eq!(io.outputs().state, state::IDLE);
        // The changer faults while the operator waits: acknowledged at
        // once, remembered after the line drops.
        io.step(&inputs(|i| {
            i.v2.toolchanger_fault = true;
            i.v2.toolchanger_reason = -3;
        }));
        let o = *io.outputs();
        assert!(o.v2.toolchanger_fault_ack && o.v2.toolchanger_faulted);
        io.step(&inputs(|_| {}));
        let o = *io.outputs();
        assert!(!o.v2.toolchanger_fault_ack && o.v2.toolchanger_faulted);
        // M6: the change is given up in the cycle it starts.
        assert!(matches!(
            io.request(&IoRequest::Load),
            Ok(Started::Waiting(_))
        ));
        let events = io.step(&inputs(|i| i.v2.toolchanger_reason = -3));
        assert_eq!(events, [IoEvent::ChangeFaulted { reason: -3 }]);
        let o = *io.outputs();
        assert!(!o.tool_change && o.v2.emc_abort);
        assert_eq!(o.v2.emc_reason, REASON_TOOLCHANGER_FAULT);
        assert_eq!(o.state, state::WAIT_FOR_ABORT_ACK);
        assert_eq!(io.tool_in_spindle(), 0, "no tool was loaded");
        // The changer acknowledges the abort; the operator clears the fault.
        io.step(&inputs(|i| i.v2.emc_abort_ack = true));
        assert!(!io.outputs().v2.emc_abort);
        assert_eq!(io.outputs().state, state::IDLE);
        io.step(&inputs(|i| i.v2.toolchanger_clear_fault = true));
        assert!(!io.outputs().v2.toolchanger_faulted);
        // Now the change goes through.
        io.request(&IoRequest::Load).unwrap();
        let events = io.step(&inputs(|i| i.tool_changed = true));
        assert_eq!(events, [IoEvent::Changed { tool: 2 }]);
    }

    #[test]
    fn an_abort_is_told_to_the_changer_before_its_lines_drop() {
        let mut io = iov2(true);
        assert_eq!(
            io.request(&IoRequest::StartChange),
            Ok(Started::Waiting(crate::iocontrol::Handshake::StartChange))
        );
        assert!(io.outputs().v2.start_change);
        assert_eq!(io.outputs().state, state::START_CHANGE);
        let events = io.step(&inputs(|i| i.v2.start_change_ack = true));
        assert_eq!(events, [IoEvent::StartChangeAcked]);
        assert!(!io.outputs().v2.start_change);
        io.request(&IoRequest::Prepare { tool: 1 }).unwrap();
        io.request(&IoRequest::Abort).unwrap();
        let o = *io.outputs();
        assert!(o.v2.emc_abort && !o.tool_prepare);
        assert_eq!(o.v2.emc_reason, REASON_TASK_ABORT);
        assert_eq!(o.state, state::WAIT_FOR_ABORT_ACK);
        // Without -support-start-change the request is done at once.
        let mut plain = iov2(false);
        assert_eq!(plain.request(&IoRequest::StartChange), Ok(Started::Done));
        assert!(!plain.outputs().v2.start_change);
    }

    #[test]
    fn a_hard_fault_reads_as_io_error_says() {
        assert_eq!(
            hard_fault_text("Toolchanger fault %d", -7),
            "Toolchanger fault -7"
        );
        assert_eq!(
            hard_fault_text("toolchanger error %d", 0),
            "M6: toolchanger hard fault, reason=0"
        );
    }
}
