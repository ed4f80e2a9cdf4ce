//! LED (hardware.md 5.9.6): pins `led.CR01`, `CR02`, ... (bit IN);
//! LED k is bit 31 − k of the register, written when a pin changes.

use hal_core::{HalHost, HostPin, In, Ours, PinFactory, Result as HalResult};

use crate::firmware::ModuleUse;
use crate::md::ModuleDescriptor;
use crate::modules::{put, Export};
use crate::transport::{Transport, TransportError};

/// The LED module.
pub struct Leds<H: HalHost = Ours> {
    md: ModuleDescriptor,
    pins: Vec<H::Pin<bool, In>>,
    written: Option<u32>,
}

impl<H: HalHost> Leds<H> {
    /// Exports one pin per LED in use.
    pub fn export<F: PinFactory<H>>(x: &mut Export<'_, F>, m: &ModuleUse) -> HalResult<Leds<H>> {
        let pins = (0..m.instances.min(32))
            .map(|k| x.comp.pin(&x.name(&format!("led.CR{:02}", k + 1))))
            .collect::<HalResult<Vec<_>>>()?;
        Ok(Leds {
            md: m.md,
            pins,
            written: None,
        })
    }

    /// The register value the pins ask for.
    pub fn word(&self) -> u32 {
        self.pins
            .iter()
            .enumerate()
            .fold(0, |w, (k, p)| if p.get() { w | 1 << (31 - k) } else { w })
    }

    /// Writes the register at load.
    pub fn force_write(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        self.written = None;
        self.write_config(t)
    }

    /// Queues the register if a pin changed.
    pub fn write_config(&mut self, t: &mut dyn Transport) -> Result<(), TransportError> {
        let w = self.word();
        if self.written != Some(w) {
            put(t, self.md.reg(0), w)?;
            self.written = Some(w);
        }
        Ok(())
    }
}
