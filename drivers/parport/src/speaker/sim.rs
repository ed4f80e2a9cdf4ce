//! The simulated PC speaker: system control port B (0x61) and the
//! interval timer's channel 2 registers (0x42, 0x43), as the chipset
//! decodes them. Writes to 0x61 set its low four bits (bit 0 gates PIT
//! channel 2, bit 1 drives the speaker); a read also shows the refresh
//! toggle (bit 4, flipping at each read) and the timer output (bit 5,
//! low: the timer is not programmed). The model counts the speaker's
//! clicks: each time bit 1 goes from 0 to 1.

use hal_driver::sim::{BoardModel, PortModel, Width};

/// System control port B.
pub const PORT_B: u16 = 0x61;
/// PIT channel 2's counter.
pub const PIT2_COUNTER: u16 = 0x42;
/// The PIT's mode register.
pub const PIT_MODE: u16 = 0x43;

/// The speaker's side of a simulated PC.
#[derive(Debug, Default)]
pub struct SpeakerModel {
    port_b: u8,
    refresh: bool,
    clicks: u64,
    /// The last byte written to the PIT's mode and channel 2 registers.
    pit: [u8; 2],
}

impl SpeakerModel {
    /// A speaker at rest: gate and data off, no click yet.
    pub fn new() -> SpeakerModel {
        SpeakerModel::default()
    }

    /// Clicks so far (speaker data bit set after being clear).
    pub fn clicks(&self) -> u64 {
        self.clicks
    }

    /// The writable bits of port B as last written.
    pub fn port_b(&self) -> u8 {
        self.port_b
    }

    /// The last bytes written to the PIT's mode register and channel 2.
    pub fn pit(&self) -> [u8; 2] {
        self.pit
    }
}

impl BoardModel for SpeakerModel {
    fn describe(&self) -> String {
        "simulated PC speaker (port 0x61)".into()
    }
}

impl PortModel for SpeakerModel {
    fn read(&mut self, port: u16, width: Width) -> u32 {
        match (port, width) {
            (PORT_B, Width::Byte) => {
                self.refresh = !self.refresh;
                u32::from(self.port_b & 0x0f) | if self.refresh { 0x10 } else { 0 }
            }
            (PIT2_COUNTER, Width::Byte) => u32::from(self.pit[1]),
            _ => u32::MAX,
        }
    }

    fn write(&mut self, port: u16, width: Width, value: u32) {
        match (port, width) {
            (PORT_B, Width::Byte) => {
                let v = value as u8 & 0x0f;
                if v & 2 != 0 && self.port_b & 2 == 0 {
                    self.clicks += 1;
                }
                self.port_b = v;
            }
            (PIT_MODE, Width::Byte) => self.pit[0] = value as u8,
            (PIT2_COUNTER, Width::Byte) => self.pit[1] = value as u8,
            _ => {}
        }
    }
}
