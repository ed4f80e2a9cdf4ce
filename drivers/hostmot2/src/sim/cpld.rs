//! The simulated 7I43's CPLD with the FPGA's configuration port behind
//! it ([`crate::epp::cpld`] has the registers): it answers the port's EPP
//! cycles while the FPGA runs no design, takes a bitstream for the
//! simulated part of [`super::xilinx`], and hands the port to the FPGA
//! once DONE rises. [`super::epp::EppPortModel`] routes the cycles here.

use super::xilinx::ConfigPort;
use crate::epp::cpld::{CPLD_DATA, PART_400K};

/// The CPLD and the FPGA's configuration state.
#[derive(Debug)]
pub struct SimCpld {
    fpga: ConfigPort,
    big: bool,
    register: u8,
    answering: bool,
}

impl SimCpld {
    /// The CPLD of a card with FPGA `part`; `running`: the FPGA already
    /// runs a design (loaded from the card's EEPROM), so the design, not
    /// the CPLD, answers the port.
    pub fn new(part: &str, running: bool) -> SimCpld {
        SimCpld {
            fpga: ConfigPort::new(part),
            big: part == PART_400K,
            register: CPLD_DATA,
            answering: !running,
        }
    }

    /// Whether the CPLD answers the port's cycles (no design runs).
    pub fn answers(&self) -> bool {
        self.answering
    }

    /// An address cycle: the CPLD decodes bit 0.
    pub fn address(&mut self, v: u8) {
        self.register = v & 1;
    }

    /// A data read: the FPGA's size or its DONE.
    pub fn read(&self) -> u8 {
        if self.register == CPLD_DATA {
            u8::from(self.big)
        } else {
            u8::from(self.fpga.done())
        }
    }

    /// A data write: a configuration byte, or /PROGRAM. When DONE rises
    /// the FPGA takes the port.
    pub fn write(&mut self, v: u8) {
        if self.register == CPLD_DATA {
            self.fpga.take(v);
            if self.fpga.done() {
                self.answering = false;
            }
        } else if v & 1 == 0 {
            self.fpga.hold();
        } else {
            // The CPLD's loader waits instead of watching /INIT: the part
            // is ready by the time anything is sent.
            self.fpga.release(Some(0));
            self.fpga.poll();
        }
    }

    /// A running design saw the release key: it stops and the CPLD
    /// answers again, with the FPGA cleared.
    pub fn take_port_back(&mut self) {
        self.fpga.hold();
        self.fpga.release(Some(0));
        self.fpga.poll();
        self.answering = true;
    }

    /// The design the FPGA was loaded with through the CPLD, once DONE.
    pub fn design(&self) -> Option<&str> {
        self.fpga.design()
    }
}
