//! The simulated 8I20 as a remote card: no tables (PTOC and GTOC 0),
//! its globals where LinuxCNC's built-in table
//! ([`legacy`](crate::sserial::legacy)) puts them, one mode, and its
//! power stage ([`EightI20`]) run on each process-data transfer.

use super::super::eight_i20::{EightI20, Limits};
use super::{Mode, RemoteKind, SimRemote};
use crate::sserial::legacy;

/// Size of the memory of a card without tables (its globals sit higher).
const LEGACY_MEMORY: usize = 0x1000;
/// The simulated 8I20's maximum current, 0.01 A (20 A).
const EIGHT_I20_MAX_CURRENT: u16 = 2000;
/// The simulated 8I20's globals (voltages and currents in hundredths).
const EIGHT_I20_MEMORY: &[(&str, u32)] = &[
    ("swrevision", 42),
    ("nvmaxcurrent", 2000),
    ("nvbusundervmax", 6000),
    ("nvbusundervmin", 5000),
    ("nvbusoverv", 39000),
    ("nvbrakeonv", 37000),
    ("nvbrakeoffv", 36000),
    ("nvrembaudrate", 9),
    ("nvkqp", 100),
    ("nvkqihi", 20),
    ("nvkqilo", 10),
    ("nvkqil", 500),
    ("nvkdp", 100),
    ("nvkdihi", 20),
    ("nvkdilo", 10),
    ("nvkdil", 500),
];

impl SimRemote {
    /// An 8I20: no tables, its globals at the addresses LinuxCNC knows,
    /// one mode; values from [`EIGHT_I20_MEMORY`].
    pub(super) fn eight_i20(unit: u32) -> SimRemote {
        let raw = u32::from_le_bytes(legacy::EIGHT_I20);
        let b = legacy::built_in(raw).unwrap_or(legacy::BuiltIn {
            process: Vec::new(),
            globals: Vec::new(),
        });
        let mut r = SimRemote::new(RemoteKind::SevenI76, unit);
        r.kind = RemoteKind::EightI20;
        r.unit = unit;
        r.memory = vec![0u8; LEGACY_MEMORY];
        r.gtoc = 0;
        r.params = b
            .globals
            .iter()
            .map(|g| (g.name.clone(), g.addr, g.bits))
            .collect();
        for (name, v) in EIGHT_I20_MEMORY {
            r.set_global(name, *v);
        }
        r.set_global("unitnumber", unit);
        let max_amps = EIGHT_I20_MAX_CURRENT as f32 / 100.0;
        let at = legacy::EIGHT_I20_MAX_CURRENT_AT as usize;
        r.memory[at..at + 2].copy_from_slice(&EIGHT_I20_MAX_CURRENT.to_le_bytes());
        let mut process = b.process;
        if let Some(c) = process.get_mut(legacy::EIGHT_I20_CURRENT) {
            c.min = -max_amps;
            c.max = max_amps;
        }
        r.modes = vec![Mode::new(0, process)];
        r.drive = Some(EightI20::default());
        r
    }

    /// A 16-bit value of the card's memory in hundredths.
    fn hundredths(&self, addr: u16) -> f64 {
        self.read_memory(addr, 2) as f64 / 100.0
    }

    /// An 8I20's limits, from its memory.
    fn drive_limits(&self) -> Limits {
        let nv = |name: &str| {
            self.params
                .iter()
                .find(|(n, _, _)| n == name)
                .map_or(0.0, |&(_, a, _)| self.hundredths(a))
        };
        Limits {
            max_current: self.hundredths(legacy::EIGHT_I20_MAX_CURRENT_AT),
            under_min: nv("nvbusundervmin"),
            under_max: nv("nvbusundervmax"),
            over: nv("nvbusoverv"),
            brake_on: nv("nvbrakeonv"),
            brake_off: nv("nvbrakeoffv"),
        }
    }

    /// Runs an 8I20's power stage on the commands just received and
    /// puts what it reports in its input fields.
    pub(super) fn run_drive(&mut self) {
        let limits = self.drive_limits();
        let angle = self.value("angle").unwrap_or(0.0);
        let current = self.value("current").unwrap_or(0.0);
        let Some(d) = self.drive.as_mut() else {
            return;
        };
        d.command(angle, current, &limits);
        self.run_drive_report();
    }

    /// Puts what an 8I20 reports in its input fields.
    pub(super) fn run_drive_report(&mut self) {
        let Some(inputs) = self.drive.as_ref().map(EightI20::inputs) else {
            return;
        };
        for (name, v) in inputs {
            self.set_value(&name, v);
        }
    }
}
