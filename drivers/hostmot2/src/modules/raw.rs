//! Raw register access (`enable_raw` in the config string):
//! `raw.read_address` (u32 IN, low 16 bits), `raw.read_data` (u32 OUT,
//! updated every `read`), `raw.write_address`, `raw.write_data` (u32 IN),
//! `raw.write_strobe` (bit IN: written and cleared by `write`) and
//! `raw.dump_state` (bit IO: a summary of the board's state is logged and
//! the pin cleared).
//!
//! The read goes with the cycle's TRAM burst, so it costs no extra
//! transfer on a network transport.

use hal_core::{HalHost, HostPin, In, Io, Ours, Out, PinFactory, Result as HalResult};

use crate::modules::Export;
use crate::tram::Slot;
use crate::transport::{Transport, TransportError};

/// The raw access pins.
pub struct Raw<H: HalHost = Ours> {
    read_address: H::Pin<u32, In>,
    read_data: H::Pin<u32, Out>,
    write_address: H::Pin<u32, In>,
    write_data: H::Pin<u32, In>,
    write_strobe: H::Pin<bool, In>,
    dump_state: H::Pin<bool, Io>,
    slot: Slot,
}

/// The address a raw pin names: its low 16 bits, word-aligned.
#[inline]
fn address(pin: u32) -> u32 {
    pin & 0xFFFC
}

impl<H: HalHost> Raw<H> {
    /// Exports the pins and registers the read.
    pub fn export<F: PinFactory<H>>(x: &mut Export<'_, F>) -> HalResult<Raw<H>> {
        let c = x.comp;
        Ok(Raw {
            read_address: c.pin(&x.name("raw.read_address"))?,
            read_data: c.pin(&x.name("raw.read_data"))?,
            write_address: c.pin(&x.name("raw.write_address"))?,
            write_data: c.pin(&x.name("raw.write_data"))?,
            write_strobe: c.pin(&x.name("raw.write_strobe"))?,
            dump_state: c.pin(&x.name("raw.dump_state"))?,
            slot: x.tram.add_read(0, 1),
        })
    }

    /// The TRAM read word and where this cycle's read must go: (slot
    /// start, address).
    #[inline]
    pub fn target(&self) -> (usize, u32) {
        (self.slot.start, address(self.read_address.get()))
    }

    /// Publishes the word read.
    #[inline]
    pub fn process_read(&self, buf: &[u32]) {
        self.read_data.set(self.slot.of(buf)[0]);
    }

    /// Writes the strobed word, clearing the strobe; returns whether a
    /// state dump was asked for (and clears that pin).
    pub fn write(&self, t: &mut dyn Transport) -> Result<bool, TransportError> {
        if self.write_strobe.get() {
            t.queue_write(address(self.write_address.get()), &[self.write_data.get()])?;
            self.write_strobe.overwrite(false);
        }
        let dump = self.dump_state.get();
        if dump {
            self.dump_state.set(false);
        }
        Ok(dump)
    }
}
