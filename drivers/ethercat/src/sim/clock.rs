//! The distributed clock of one simulated ESC: its local time (which
//! runs a few ppm off, as a real quartz does), the system time the
//! master's offset (0x0920), delay (0x0928) and drift control (writes to
//! 0x0910) make of it, the receive time latches (0x0900, 0x0918), and the
//! SYNC0/SYNC1 unit (0x0980 assignment, 0x0981 activation, 0x0990 start
//! time, 0x09A0/0x09A4 cycles, 0x098E status).
//!
//! The SYNC unit keeps what the master activated: the start time and the
//! cycles as they were when 0x0981 was written. A start time already in
//! the past at activation never fires (a real ESC waits for the 32-bit
//! time to wrap, four seconds); the slave refuses SAFE-OP for it, for a
//! SYNC0 cycle under [`MIN_SYNC0_CYCLE_NS`], for SYNC0 without cyclic
//! operation, and, when its device needs SYNC0, for no SYNC0 at all.

use crate::regs::{self, al_code, dc};

/// The shortest SYNC0 cycle a simulated slave accepts.
pub const MIN_SYNC0_CYCLE_NS: u32 = 50_000;

/// What the master activated, as 0x0981 was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Activation {
    /// The activation byte (0x0981).
    pub flags: u8,
    /// The first SYNC0 pulse, in system time.
    pub start: u64,
    /// SYNC0 cycle (ns).
    pub sync0_cycle: u32,
    /// SYNC1 cycle (ns).
    pub sync1_cycle: u32,
    /// The start time had passed when the unit was activated.
    pub start_in_past: bool,
}

/// The clock and SYNC unit of one ESC.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct DcClock {
    /// Local time = simulated time × (1 + ppm) + this.
    local_offset: i64,
    /// How far this quartz runs off, in parts per million.
    ppm: i64,
    /// Correction the drift control has applied to system time.
    correction: i64,
    /// Local time at the last frame's arrival.
    arrival: i64,
    /// Simulated time of the last frame's arrival.
    arrived_at: i64,
    /// The SYNC unit, once activated.
    activation: Option<Activation>,
    /// SYNC0 events seen by the last read of the status register.
    events_read: u64,
    /// Writes of system time (drift control inputs) since power on.
    writes: u64,
}

fn le_u64(mem: &[u8], at: u16) -> u64 {
    let a = usize::from(at);
    let mut b = [0u8; 8];
    b.copy_from_slice(&mem[a..a + 8]);
    u64::from_le_bytes(b)
}

fn le_u32(mem: &[u8], at: u16) -> u32 {
    let a = usize::from(at);
    u32::from_le_bytes([mem[a], mem[a + 1], mem[a + 2], mem[a + 3]])
}

impl DcClock {
    /// The clock of the slave at `position`: each starts at its own
    /// time and runs at its own rate (-20..+20 ppm).
    pub(crate) fn new(position: u16) -> DcClock {
        DcClock {
            local_offset: i64::from(position + 1) * 1_000_000_007,
            ppm: (i64::from(position % 5) - 2) * 10,
            ..DcClock::default()
        }
    }

    /// Power on: the drift correction and the SYNC unit are gone.
    pub(crate) fn reset(&mut self) {
        self.correction = 0;
        self.activation = None;
        self.events_read = 0;
        self.writes = 0;
    }

    /// Writes of system time since power on.
    pub(crate) fn writes(&self) -> u64 {
        self.writes
    }

    /// A frame arrives at simulated time `now_ns`.
    pub(crate) fn arrive(&mut self, now_ns: u64) {
        let now = now_ns as i64;
        self.arrived_at = now;
        self.arrival = self.local_at(now);
    }

    /// Local time at simulated time `now`.
    fn local_at(&self, now: i64) -> i64 {
        let drift = i128::from(now) * i128::from(self.ppm) / 1_000_000;
        now.wrapping_add(drift as i64)
            .wrapping_add(self.local_offset)
    }

    /// The quartz runs `ppm` parts per million fast (negative: slow)
    /// from the last frame on: local time goes on from where it is, at
    /// the new rate.
    pub(crate) fn set_ppm(&mut self, ppm: i64) {
        let before = self.local_at(self.arrived_at);
        self.ppm = ppm;
        let after = self.local_at(self.arrived_at);
        self.local_offset = self.local_offset.wrapping_add(before.wrapping_sub(after));
    }

    /// Local time jumps by `ns` (a disturbed or replaced clock).
    pub(crate) fn step(&mut self, ns: i64) {
        self.local_offset = self.local_offset.wrapping_add(ns);
        self.arrival = self.arrival.wrapping_add(ns);
    }

    /// The system time now: local time plus the master's offset and the
    /// drift correction.
    pub(crate) fn system_time(&self, mem: &[u8]) -> i64 {
        let offset = le_u64(mem, regs::DC_SYSTEM_TIME_OFFSET) as i64;
        self.arrival
            .wrapping_add(offset)
            .wrapping_add(self.correction)
    }

    /// The master's system time arrives (`bytes` of it: 4 or 8): the
    /// difference drives the local clock towards it (a quarter of it per
    /// write, as a filter) and shows in 0x092C (sign bit and magnitude).
    pub(crate) fn drift_control(&mut self, mem: &mut [u8], received: u64, bytes: usize) {
        let delay = i64::from(le_u32(mem, regs::DC_SYSTEM_TIME_DELAY));
        let local = self.system_time(mem);
        let diff = if bytes >= 8 {
            (received as i64).wrapping_add(delay).wrapping_sub(local)
        } else {
            // A 32-bit write compares the low halves.
            i64::from(
                (received as u32)
                    .wrapping_add(delay as u32)
                    .wrapping_sub(local as u32) as i32,
            )
        };
        self.correction = self.correction.wrapping_add(diff / 4);
        self.writes += 1;
        let magnitude = diff.unsigned_abs().min(0x7FFF_FFFF) as u32;
        let sign = if diff < 0 { 1u32 << 31 } else { 0 };
        let a = usize::from(regs::DC_SYSTEM_TIME_DIFFERENCE);
        mem[a..a + 4].copy_from_slice(&(magnitude | sign).to_le_bytes());
    }

    /// A write to port 0's receive time latches every port's: port 0 when
    /// the frame came in, port 1 `downstream_ns` later when it came back.
    pub(crate) fn latch_receive_times(&self, mem: &mut [u8], downstream_ns: i64) {
        let arrival = self.arrival;
        let back = arrival + downstream_ns;
        let a = usize::from(regs::DC_RECEIVE_TIME_PORT0);
        mem[a..a + 4].copy_from_slice(&(arrival as u32).to_le_bytes());
        mem[a + 4..a + 8].copy_from_slice(&(back as u32).to_le_bytes());
        let pu = usize::from(regs::DC_RECEIVE_TIME_PU);
        mem[pu..pu + 8].copy_from_slice(&(arrival as u64).to_le_bytes());
    }

    /// 0x0981 was written: the unit starts with the start time and cycles
    /// the registers hold now, or stops.
    pub(crate) fn activate(&mut self, mem: &[u8]) {
        let flags = mem[usize::from(regs::DC_ACTIVATION)];
        if flags & (dc::SYNC0 | dc::SYNC1 | dc::CYCLIC) == 0 {
            self.activation = None;
            self.events_read = 0;
            return;
        }
        let start = le_u64(mem, regs::DC_START_TIME);
        self.activation = Some(Activation {
            flags,
            start,
            sync0_cycle: le_u32(mem, regs::DC_SYNC0_CYCLE),
            sync1_cycle: le_u32(mem, regs::DC_SYNC1_CYCLE),
            start_in_past: (start as i64) < self.system_time(mem),
        });
    }

    /// What the master activated, if anything.
    pub(crate) fn activation(&self) -> Option<Activation> {
        self.activation
    }

    /// SYNC0 pulses so far (0 before the start time, and for a unit
    /// whose start time had passed).
    pub(crate) fn sync0_events(&self, mem: &[u8]) -> u64 {
        let Some(a) = self.activation else {
            return 0;
        };
        let now = self.system_time(mem);
        if a.flags & dc::SYNC0 == 0 || a.start_in_past || now < a.start as i64 {
            return 0;
        }
        let since = (now - a.start as i64) as u64;
        match a.sync0_cycle {
            0 => 1,
            c => since / u64::from(c) + 1,
        }
    }

    /// The SYNC0 status register (0x098E) as read now: bit 0 set when a
    /// pulse came since the last read.
    pub(crate) fn read_status(&mut self, mem: &mut [u8]) {
        let events = self.sync0_events(mem);
        mem[usize::from(regs::DC_SYNC0_STATUS)] = u8::from(events > self.events_read);
        self.events_read = events;
    }

    /// The check before SAFE-OP: the AL status code that refuses it, if
    /// any, for a slave with (`capable`) or without DC that needs SYNC0
    /// or not.
    pub(crate) fn check(&self, capable: bool, needs_sync0: bool) -> Option<u16> {
        let Some(a) = self.activation else {
            return needs_sync0.then_some(al_code::INVALID_DC_SYNC);
        };
        if !capable || a.flags & dc::CYCLIC == 0 {
            return Some(al_code::INVALID_DC_SYNC);
        }
        if a.flags & dc::SYNC0 != 0 {
            if a.sync0_cycle != 0 && a.sync0_cycle < MIN_SYNC0_CYCLE_NS {
                return Some(al_code::DC_SYNC0_CYCLE);
            }
            if a.start_in_past {
                return Some(al_code::INVALID_DC_SYNC);
            }
        } else if needs_sync0 {
            return Some(al_code::INVALID_DC_SYNC);
        }
        None
    }
}
