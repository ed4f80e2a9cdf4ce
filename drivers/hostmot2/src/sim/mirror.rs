//! Serving a simulated board through shared memory: the model's registers
//! are kept in a memory window (a file another process maps as a PCI BAR,
//! such as the VM rig's ivshmem backing file), so a driver that maps that
//! memory as a real BAR talks to the simulator.
//!
//! Shared memory has no access callbacks, so [`Mirror::step`] polls: a
//! word that differs from what the mirror last showed was written by the
//! driver and goes to the model's `write32`; then the model runs; then
//! every register whose value changed is shown again. A driver write
//! that lands on a register the model is changing in the same step, or
//! that repeats the value shown, is not seen; hostmot2's drivers rewrite
//! their per-cycle registers every cycle, so the mirror catches up.

use hal_driver::bus::RegWindow;

use super::Hm2Model;
use crate::image::WINDOW_WORDS;

/// A model served through a memory window.
pub struct Mirror {
    model: Hm2Model,
    shown: Vec<u32>,
    now: Vec<u32>,
    /// Byte offset of the register window in the memory.
    base: usize,
}

impl Mirror {
    /// Serves `model` at byte `base` of a window.
    pub fn new(mut model: Hm2Model, base: usize) -> Mirror {
        let shown = (0..WINDOW_WORDS).map(|i| model.read32(4 * i)).collect();
        Mirror {
            model,
            shown,
            now: vec![0; WINDOW_WORDS],
            base,
        }
    }

    /// Writes every register into `win` (at start).
    pub fn publish_all(&self, win: &impl RegWindow) {
        win.write_burst(self.base, &self.shown);
    }

    /// Takes the driver's writes, lets `dt_ns` pass, shows what changed.
    pub fn step(&mut self, win: &impl RegWindow, dt_ns: u64) {
        win.read_burst(self.base, &mut self.now);
        for (i, (&v, shown)) in self.now.iter().zip(self.shown.iter_mut()).enumerate() {
            if v != *shown {
                self.model.write32(4 * i, v);
                *shown = v;
            }
        }
        self.model.advance(dt_ns);
        for (i, shown) in self.shown.iter_mut().enumerate() {
            let v = self.model.read32(4 * i);
            if v != *shown {
                win.write32(self.base + 4 * i, v);
                *shown = v;
            }
        }
    }

    /// The model.
    pub fn model(&mut self) -> &mut Hm2Model {
        &mut self.model
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Memory;
    use crate::sim::boards;
    use hal_driver::sim::SimBoard;

    #[test]
    fn writes_reach_the_model_and_changes_come_back() {
        let mem = SimBoard::new(Memory(vec![0; 2 * WINDOW_WORDS]));
        let model = Hm2Model::new(boards::preset("5i25").unwrap());
        let mut m = Mirror::new(model, 0x1_0000);
        m.publish_all(&mem);
        assert_eq!(mem.read32(0x1_0100), 0x55AA_CAFE);
        // The driver arms the watchdog: 100 ticks.
        mem.write32(0x1_0C00, 99);
        m.step(&mem, 500);
        assert_eq!(mem.read32(0x1_0C00), 49, "counting down, shown");
        m.step(&mem, 1000);
        assert_eq!(mem.read32(0x1_0D00) & 1, 1, "bitten");
        // A stepgen rate integrates into the accumulator.
        mem.write32(0x1_2900, 0xFFFF_FFFF);
        mem.write32(0x1_2000, 0x0100_0000);
        m.step(&mem, 1_000_000);
        assert_ne!(mem.read32(0x1_2100), 0);
    }
}
