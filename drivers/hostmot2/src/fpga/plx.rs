//! Configuring the FPGA through a PLX bridge's user lines (hardware.md
//! 5.1), in LinuxCNC's steps: reset (/PROGRAM pulse, then wait for the
//! FPGA to clear), then load (every bitstream byte, bit-reversed, to the
//! data port; then the DONE and /INIT checks).
//!
//! The bridge is reached through [`PortBus`]es: the card's I/O BARs 1
//! and 2 (each a `SysfsIoBar`) on real hardware, the simulated bridge
//! ([`crate::sim::plx::SimPlxBridge`], both BARs on one bus) in tests;
//! both are addressed by absolute port number, the BARs' starts given in
//! [`PlxPorts`]. A port
//! access that fails (the bus reads all ones and counts it) stops the
//! load at the step it happened in.

use hal_driver::bus::PortBus;

use super::{FpgaError, ProgramStep};
use crate::regs::{fpga_wait, plx9030, plx9054};

/// Which PLX bridge a card has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bridge {
    /// PLX 9030 (5i20, 4i65): /PROGRAM, /INIT, DONE, /WRITE, /LED on GPIO.
    Plx9030,
    /// PLX 9054 or 9056 (5i21, 5i22, 5i23, 4i68, 4i69, 3x20): /PROGRAM
    /// on USERo, DONE on USERi; no /INIT.
    Plx9054,
}

impl Bridge {
    /// The bridge a PCI device ID names, if it is a PLX one.
    pub fn of_device(vendor: u16, device: u16) -> Option<Bridge> {
        match (vendor, device) {
            (0x10B5, 0x9030) => Some(Bridge::Plx9030),
            (0x10B5, 0x9054 | 0x9056) => Some(Bridge::Plx9054),
            _ => None,
        }
    }

    /// The BAR of the configuration registers.
    pub fn ctrl_bar(self) -> usize {
        match self {
            Bridge::Plx9030 => plx9030::CTRL_BAR,
            Bridge::Plx9054 => plx9054::CTRL_BAR,
        }
    }

    /// The BAR of the data port.
    pub fn data_bar(self) -> usize {
        match self {
            Bridge::Plx9030 => plx9030::DATA_BAR,
            Bridge::Plx9054 => plx9054::DATA_BAR,
        }
    }

    /// The name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Bridge::Plx9030 => "PLX 9030",
            Bridge::Plx9054 => "PLX 9054",
        }
    }
}

/// A bridge's ports: the buses of its two BARs and where they start.
pub struct PlxPorts<'a> {
    /// The bridge.
    pub bridge: Bridge,
    /// The bus of the configuration registers (BAR 1).
    pub ctrl: &'a dyn PortBus,
    /// First port of the configuration registers.
    pub ctrl_base: u16,
    /// The bus of the data port (BAR 2).
    pub data: &'a dyn PortBus,
    /// The data port.
    pub data_base: u16,
}

impl PlxPorts<'_> {
    fn ctrl_port(&self) -> u16 {
        let off = match self.bridge {
            Bridge::Plx9030 => plx9030::GPIOC,
            Bridge::Plx9054 => plx9054::CNTRL,
        };
        self.ctrl_base.wrapping_add(off)
    }

    /// Reads the control register, failing if the bus could not.
    fn read(&self, step: ProgramStep) -> Result<u32, FpgaError> {
        let before = self.ctrl.errors();
        let v = self.ctrl.inl(self.ctrl_port());
        check(self.ctrl, before, step)?;
        Ok(v)
    }

    fn write(&self, step: ProgramStep, value: u32) -> Result<(), FpgaError> {
        let before = self.ctrl.errors();
        self.ctrl.outl(self.ctrl_port(), value);
        check(self.ctrl, before, step)
    }

    /// Streams the bitstream, each byte bit-reversed (the cards wire the
    /// FPGA's data bus in the other order).
    fn stream(&self, bitstream: &[u8]) -> Result<(), FpgaError> {
        let before = self.data.errors();
        for &b in bitstream {
            self.data.outb(self.data_base, b.reverse_bits());
        }
        check(self.data, before, ProgramStep::Load)
    }
}

/// Fails `step` if `bus` counted a failed access since `before`.
fn check(bus: &dyn PortBus, before: u64, step: ProgramStep) -> Result<(), FpgaError> {
    if bus.errors() != before {
        return Err(FpgaError::Program {
            step,
            reason: format!("a port access failed on {}", bus.describe()),
        });
    }
    Ok(())
}

fn fail(step: ProgramStep, reason: impl Into<String>) -> FpgaError {
    FpgaError::Program {
        step,
        reason: reason.into(),
    }
}

/// Resets the FPGA, then loads `bitstream` into it; returns once DONE
/// is high.
pub fn program(ports: &PlxPorts<'_>, bitstream: &[u8]) -> Result<(), FpgaError> {
    match ports.bridge {
        Bridge::Plx9030 => {
            reset_9030(ports)?;
            load_9030(ports, bitstream)
        }
        Bridge::Plx9054 => {
            reset_9054(ports)?;
            load_9054(ports, bitstream)
        }
    }
}

fn reset_9030(p: &PlxPorts<'_>) -> Result<(), FpgaError> {
    use plx9030::{DONE, INIT, LED, PROGRAM, WRITE};
    let step = ProgramStep::Reset;
    let c = p.read(step)?;
    // /PROGRAM low clears the FPGA; /WRITE and /LED stay high (off).
    p.write(step, (c & !PROGRAM) | WRITE | LED)?;
    let c = p.read(step)?;
    if c & DONE != 0 {
        return Err(fail(step, "DONE stayed high with /PROGRAM low"));
    }
    if c & INIT != 0 {
        return Err(fail(step, "/INIT stayed high with /PROGRAM low"));
    }
    p.write(step, c | PROGRAM)?;
    for _ in 0..fpga_wait::INIT_READS {
        if p.read(step)? & INIT != 0 {
            return Ok(());
        }
    }
    Err(fail(
        ProgramStep::WaitInit,
        format!(
            "/INIT did not rise within {} reads after /PROGRAM was released (the FPGA did not clear)",
            fpga_wait::INIT_READS
        ),
    ))
}

fn load_9030(p: &PlxPorts<'_>, bitstream: &[u8]) -> Result<(), FpgaError> {
    use plx9030::{DONE, INIT, LED, WRITE};
    let c = p.read(ProgramStep::Load)?;
    // /WRITE low routes the data port to the FPGA; /LED low lights it.
    p.write(ProgramStep::Load, c & !(WRITE | LED))?;
    p.stream(bitstream)?;
    let c = p.read(ProgramStep::CheckDone)?;
    if c & INIT == 0 {
        return Err(fail(
            ProgramStep::CheckDone,
            format!(
                "/INIT went low after {} bytes: the FPGA found a CRC error in the bitstream",
                bitstream.len()
            ),
        ));
    }
    if c & DONE == 0 {
        return Err(fail(
            ProgramStep::CheckDone,
            format!(
                "DONE did not rise after {} bytes (a bitstream for another part, or cut short?)",
                bitstream.len()
            ),
        ));
    }
    p.write(ProgramStep::CheckDone, c | WRITE | LED)
}

fn reset_9054(p: &PlxPorts<'_>) -> Result<(), FpgaError> {
    use plx9054::{DONE, DONE_ENABLE, PROGRAM, PROGRAM_ENABLE};
    let step = ProgramStep::Reset;
    let c = p.read(step)? | DONE_ENABLE | PROGRAM_ENABLE;
    p.write(step, c & !PROGRAM)?;
    if p.read(step)? & DONE != 0 {
        return Err(fail(step, "DONE stayed high with /PROGRAM low"));
    }
    p.write(step, c | PROGRAM)?;
    // No /INIT on this bridge: the FPGA's clearing time is waited out.
    for _ in 0..fpga_wait::INIT_READS {
        p.read(ProgramStep::WaitInit)?;
    }
    Ok(())
}

fn load_9054(p: &PlxPorts<'_>, bitstream: &[u8]) -> Result<(), FpgaError> {
    p.stream(bitstream)?;
    for _ in 0..fpga_wait::DONE_READS {
        if p.read(ProgramStep::CheckDone)? & plx9054::DONE != 0 {
            return Ok(());
        }
    }
    Err(fail(
        ProgramStep::CheckDone,
        format!(
            "DONE did not rise within {} reads after {} bytes (a bitstream for another part, \
             cut short, or with a CRC error?)",
            fpga_wait::DONE_READS,
            bitstream.len()
        ),
    ))
}

/// Sets READY# input enable in every local address space descriptor
/// where a 5i20's or 4i65's old EEPROM left it clear, as LinuxCNC does
/// at probe (hardware.md 5.1); returns how many it set.
pub fn fix_9030_ready(p: &PlxPorts<'_>) -> Result<usize, FpgaError> {
    let step = ProgramStep::BridgeSetup;
    let mut fixed = 0;
    for off in plx9030::LAS_BRD {
        let port = p.ctrl_base.wrapping_add(off);
        let before = p.ctrl.errors();
        let v = p.ctrl.inl(port);
        if v & plx9030::LAS_BRD_READY == 0 {
            p.ctrl.outl(port, v | plx9030::LAS_BRD_READY);
            fixed += 1;
        }
        check(p.ctrl, before, step)?;
    }
    Ok(fixed)
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use super::*;

    /// A bus that records every access and answers control-register
    /// reads from a script (then repeats its last answer).
    struct Mock {
        log: Mutex<Vec<(char, u16, u32)>>,
        answers: Mutex<Vec<u32>>,
    }

    impl Mock {
        fn new(answers: &[u32]) -> Mock {
            Mock {
                log: Mutex::new(Vec::new()),
                answers: Mutex::new(answers.iter().rev().copied().collect()),
            }
        }
        fn log(&self) -> Vec<(char, u16, u32)> {
            self.log.lock().unwrap().clone()
        }
    }

    impl PortBus for Mock {
        fn inb(&self, _: u16) -> u8 {
            0
        }
        fn outb(&self, port: u16, value: u8) {
            self.log.lock().unwrap().push(('b', port, value as u32));
        }
        fn inw(&self, _: u16) -> u16 {
            0
        }
        fn outw(&self, _: u16, _: u16) {}
        fn inl(&self, port: u16) -> u32 {
            let mut a = self.answers.lock().unwrap();
            let v = if a.len() > 1 {
                a.pop()
            } else {
                a.last().copied()
            };
            let v = v.unwrap_or(0);
            self.log.lock().unwrap().push(('r', port, v));
            v
        }
        fn outl(&self, port: u16, value: u32) {
            self.log.lock().unwrap().push(('w', port, value));
        }
        fn errors(&self) -> u64 {
            0
        }
        fn describe(&self) -> String {
            "mock".into()
        }
    }

    fn ports(bridge: Bridge, bus: &Mock) -> PlxPorts<'_> {
        PlxPorts {
            bridge,
            ctrl: bus,
            ctrl_base: 0x1000,
            data: bus,
            data_base: 0x2000,
        }
    }

    #[test]
    fn the_9030_sequence_drives_the_gpio_bits_as_linuxcnc_does() {
        use plx9030::{DONE, INIT, LED, PROGRAM, WRITE};
        let gpioc = 0x1000 + plx9030::GPIOC;
        // Idle; cleared (DONE, /INIT low); /INIT still low once, then
        // high; then before the load; then DONE and /INIT high.
        let bus = Mock::new(&[
            PROGRAM | WRITE | LED,
            WRITE | LED,
            PROGRAM,
            PROGRAM | INIT,
            PROGRAM | INIT | WRITE | LED,
            INIT | DONE,
        ]);
        program(&ports(Bridge::Plx9030, &bus), &[0x01, 0x80, 0xF0]).unwrap();
        let log = bus.log();
        assert_eq!(
            log[1],
            ('w', gpioc, WRITE | LED),
            "/PROGRAM low, /WRITE and /LED high"
        );
        assert_eq!(
            log[3],
            ('w', gpioc, WRITE | LED | PROGRAM),
            "/PROGRAM released"
        );
        let load = log.iter().position(|e| e.0 == 'b').unwrap();
        assert_eq!(
            log[load - 1],
            ('w', gpioc, PROGRAM | INIT),
            "/WRITE and /LED low"
        );
        let bytes: Vec<u32> = log.iter().filter(|e| e.0 == 'b').map(|e| e.2).collect();
        assert_eq!(bytes, [0x80, 0x01, 0x0F], "bit-reversed to the data port");
        assert!(log.iter().filter(|e| e.0 == 'b').all(|e| e.1 == 0x2000));
        assert_eq!(log.last(), Some(&('w', gpioc, INIT | DONE | WRITE | LED)));
    }

    #[test]
    fn the_9030_refuses_an_fpga_that_does_not_clear() {
        use plx9030::{DONE, INIT};
        for (answer, want) in [(DONE, "DONE stayed high"), (INIT, "/INIT stayed high")] {
            let bus = Mock::new(&[0, answer]);
            let e = program(&ports(Bridge::Plx9030, &bus), &[1]).unwrap_err();
            assert_eq!(
                e,
                FpgaError::Program {
                    step: ProgramStep::Reset,
                    reason: format!("{want} with /PROGRAM low"),
                }
            );
        }
    }

    #[test]
    fn the_9054_sequence_sets_the_user_pin_directions_and_polls_done() {
        use plx9054::{DONE, DONE_ENABLE, PROGRAM, PROGRAM_ENABLE};
        let cntrl = 0x1000 + plx9054::CNTRL;
        let mut answers = vec![0x1234, 0];
        answers.extend(std::iter::repeat_n(0, fpga_wait::INIT_READS as usize + 5));
        answers.push(DONE);
        let bus = Mock::new(&answers);
        program(&ports(Bridge::Plx9054, &bus), &[0xAA]).unwrap();
        let log = bus.log();
        let en = 0x1234 | DONE_ENABLE | PROGRAM_ENABLE;
        assert_eq!(
            log[1],
            ('w', cntrl, en & !PROGRAM),
            "/PROGRAM low, both directions set"
        );
        assert_eq!(log[3], ('w', cntrl, en | PROGRAM), "/PROGRAM released");
        let reads_before_data = log
            .iter()
            .take_while(|e| e.0 != 'b')
            .filter(|e| e.0 == 'r')
            .count();
        assert_eq!(reads_before_data as u32, 2 + fpga_wait::INIT_READS);
        assert!(log.contains(&('b', 0x2000, 0x55)));
        // DONE never rising: the DONE wait is bounded.
        let bus = Mock::new(&[0]);
        let e = program(&ports(Bridge::Plx9054, &bus), &[1]).unwrap_err();
        assert!(
            matches!(
                e,
                FpgaError::Program {
                    step: ProgramStep::CheckDone,
                    ..
                }
            ),
            "{e}"
        );
        let reads = bus.log().iter().filter(|e| e.0 == 'r').count() as u32;
        assert_eq!(reads, 2 + fpga_wait::INIT_READS + fpga_wait::DONE_READS);
    }
}
