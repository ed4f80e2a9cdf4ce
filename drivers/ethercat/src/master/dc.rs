//! Distributed clocks on the master.
//!
//! At bring-up EtherCrab measures the propagation delays, writes each
//! DC slave's system time offset (0x0920) and delay (0x0928), and takes
//! the first slave with DC as the reference clock. Here, in PRE-OP,
//! each slave whose `<dcConf>` asks for it gets its SYNC unit set up as
//! IgH's master does it: activation off (0x0981), the first pulse
//! ([`START_DELAY_NS`] after the reference clock's time now, on a whole
//! SYNC0 cycle, plus the shift) in 0x0990, the cycles in 0x09A0 and
//! 0x09A4, then the AssignActivate word into 0x0980/0x0981.
//!
//! Each cycle the frame carries an FRMW of the reference clock's system
//! time to the other slaves (EtherCrab's `tx_rx_sync_system_time`); when
//! SYNC is in use the helper also writes the application time (the servo
//! thread's time on the EtherCAT time base) to the reference clock every
//! `refClockSyncCycles` cycles, and reads the largest clock difference
//! (a broadcast read of 0x092C) for `dc-sync-diff`.

use std::time::Duration;

use ethercrab::{Command, MainDevice, SubDevice, SubDeviceRef};

use super::io::Io;
use crate::error::{Error, Result};
use crate::regs;

/// How far in the future the first SYNC0 pulse is set (as IgH does).
pub const START_DELAY_NS: u64 = 100_000_000;

/// A slave's `<dcConf>`, the cycles in ns.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DcPlan {
    /// AssignActivate: low byte to 0x0980, high byte to 0x0981 (0x0300:
    /// cyclic operation and SYNC0; 0x0700: and SYNC1). 0: no SYNC.
    pub assign_activate: u16,
    /// SYNC0 cycle (ns).
    pub sync0_cycle_ns: u64,
    /// SYNC0 shift (ns).
    pub sync0_shift_ns: i64,
    /// SYNC1 cycle (ns).
    pub sync1_cycle_ns: u64,
}

/// The reference clock: the position and station address of the first
/// slave with distributed clocks, if any.
pub(crate) fn reference<'a, S>(slaves: impl Iterator<Item = SubDeviceRef<'a, S>>) -> Option<u16>
where
    S: std::ops::Deref<Target = SubDevice>,
{
    for sd in slaves {
        if sd.dc_support().any() {
            return Some(sd.configured_address());
        }
    }
    None
}

/// The first SYNC0 pulse: `delay` after `now`, on a whole `cycle`, plus
/// `shift`.
pub fn start_time(now: u64, delay: u64, cycle: u64, shift: i64) -> u64 {
    let t = now.saturating_add(delay);
    let aligned = match cycle {
        0 => t,
        c => (t / c + 1).saturating_mul(c),
    };
    aligned.saturating_add_signed(shift)
}

/// Sets up the SYNC unit of slave `sd` (`position`, `name`) from `plan`,
/// the reference clock at `reference`.
pub(crate) fn configure_sync<S: std::ops::Deref<Target = SubDevice>>(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    sd: &SubDeviceRef<'_, S>,
    (position, name): (u16, &str),
    plan: &DcPlan,
    reference: Option<u16>,
) -> Result<()> {
    if plan.assign_activate == 0 {
        return Ok(());
    }
    let fail = |reason: String| Error::SlaveMismatch {
        position,
        name: name.to_string(),
        reason,
    };
    if !sd.dc_support().enhanced() {
        return Err(fail(format!(
            "<dcConf assignActivate=\"{:x}\"> asks for SYNC signals, but the slave has no DC sync unit",
            plan.assign_activate
        )));
    }
    let Some(reference) = reference else {
        return Err(fail(
            "<dcConf> needs a reference clock and no slave has DC".into(),
        ));
    };
    let cycle = |ns: u64, what: &str| {
        u32::try_from(ns).map_err(|_| fail(format!("{what} {ns} ns is longer than 4.29 s")))
    };
    let sync0 = cycle(plan.sync0_cycle_ns, "sync0Cycle")?;
    let sync1 = cycle(plan.sync1_cycle_ns, "sync1Cycle")?;
    let step = |what: &str, e: ethercrab::error::Error| fail(format!("DC set-up, {what}: {e}"));
    io.block_on(sd.register_write(regs::DC_ACTIVATION, 0u8))
        .map_err(|e| step("deactivating SYNC", e))?;
    let now: u64 = io
        .block_on(Command::fprd(reference, regs::DC_SYSTEM_TIME).receive::<u64>(md))
        .map_err(|e| step("reading the reference clock", e))?;
    let start = start_time(now, START_DELAY_NS, u64::from(sync0), plan.sync0_shift_ns);
    io.block_on(sd.register_write(regs::DC_START_TIME, start))
        .map_err(|e| step("the start time", e))?;
    io.block_on(sd.register_write(regs::DC_SYNC0_CYCLE, sync0))
        .map_err(|e| step("the SYNC0 cycle", e))?;
    io.block_on(sd.register_write(regs::DC_SYNC1_CYCLE, sync1))
        .map_err(|e| step("the SYNC1 cycle", e))?;
    io.block_on(sd.register_write(regs::DC_CYCLIC_UNIT_CONTROL, plan.assign_activate))
        .map_err(|e| step("AssignActivate", e))?;
    Ok(())
}

/// Monitor reads that may go missing in a row before `dc-sync-diff`
/// says the clocks are not heard from ([`NOT_HEARD`]).
pub const MONITOR_MISSES: u32 = 10;
/// `dc-sync-diff` while no monitor read comes back.
pub const NOT_HEARD: u32 = u32::MAX;

/// What the helper keeps between cycles for the clocks.
#[derive(Debug, Default)]
pub(crate) struct DcCycle {
    /// The reference clock's station address.
    pub(crate) reference: Option<u16>,
    /// Some slave's SYNC unit was set up.
    pub(crate) in_use: bool,
    /// Write the application time to the reference clock every this
    /// many cycles (0: never).
    pub(crate) sync_every: u32,
    pub(crate) cycles: u32,
    pub(crate) misses: u32,
}

impl DcCycle {
    /// After a cycle's frame: the application time (CLOCK_MONOTONIC now
    /// plus `base`, the servo thread's clock on the EtherCAT time base)
    /// to the reference clock when due, then the monitor read if
    /// `monitor`. Returns the new `dc-sync-diff`, or None when there is
    /// nothing to say.
    pub(crate) fn after_frame(
        &mut self,
        md: &MainDevice<'_>,
        io: &mut Io<'_>,
        base: i64,
        monitor: bool,
        timeout: Duration,
    ) -> Option<u32> {
        let reference = self.reference.filter(|_| self.in_use)?;
        self.cycles = self.cycles.wrapping_add(1);
        if self.sync_every > 0 && self.cycles % self.sync_every == 0 {
            let app_time = (hal_core::clock::monotonic_ns() as i64).wrapping_add(base) as u64;
            let write = Command::fpwr(reference, regs::DC_SYSTEM_TIME)
                .ignore_wkc()
                .send(md, app_time);
            let _ = io.block_on(super::serve::with_deadline(
                write,
                std::time::Instant::now() + timeout,
            ));
        }
        if !monitor {
            return None;
        }
        let read = Command::brd(regs::DC_SYSTEM_TIME_DIFFERENCE)
            .ignore_wkc()
            .receive::<u32>(md);
        match io.block_on(super::serve::with_deadline(
            read,
            std::time::Instant::now() + timeout,
        )) {
            Some(Ok(v)) => {
                self.misses = 0;
                Some(v & 0x7FFF_FFFF)
            }
            _ => {
                self.misses += 1;
                (self.misses >= MONITOR_MISSES).then_some(NOT_HEARD)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_pulse_is_on_a_whole_cycle_plus_the_shift() {
        assert_eq!(start_time(1_234_567, 100_000, 1_000_000, 0), 2_000_000);
        assert_eq!(start_time(1_234_567, 100_000, 1_000_000, -300), 1_999_700);
        assert_eq!(start_time(5, 10, 0, 7), 22);
        assert_eq!(start_time(u64::MAX - 1, 10, 1000, 0), u64::MAX);
    }
}
