//! Bringing back slaves that lost their configuration: a drive
//! power-cycled, a cable replugged, the whole segment restarted. Such a
//! slave comes back in INIT with no station address, so it no longer
//! answers the state check each cycle's frame carries (its AL state
//! reads 0) while frames come back.
//!
//! At bring-up, once the segment is in OP, each slave's sync manager
//! and FMMU registers are kept ([`Recovery::new`]). In the helper, after
//! each cycle whose frame came back, [`Recovery::step`] moves every
//! slave that needs it one step through the same bring-up, between
//! cycles (the realtime side never waits for it, and the other slaves
//! keep exchanging data):
//!
//! 1. a slave that does not answer at its station address is looked
//!    for at its position (auto-increment address); found, it gets its
//!    station address back and its SII identity is checked against the
//!    one found at bring-up: a different device is refused, and
//!    [`super::Cyclic::refused`] says what sits there;
//! 2. INIT: the mailbox sync managers, then PRE-OP;
//! 3. PRE-OP: the configuration's SDO writes, the process data sync
//!    managers and FMMUs as kept, its DC clock's offset and delay, the
//!    SYNC unit (`<dcConf>`), then SAFE-OP;
//! 4. SAFE-OP: OP.
//!
//! The progress shows in the slave's AL state (the state pins) as each
//! cycle reads it. A step that does not happen within the state
//! time-out starts over after [`RETRY`]; a position where nothing
//! answers is looked at again every [`RETRY`].

use std::sync::atomic::Ordering::*;
use std::time::{Duration, Instant};

use ethercrab::{Command, MainDevice, SubIndex};

use super::io::Io;
use super::{dc, Group, MasterConfig, Shared, SlaveInfo};
use crate::error::{Error, Result};
use crate::regs::{self, al, sm};

/// How long before a slave that could not be brought back is tried
/// again.
pub const RETRY: Duration = Duration::from_millis(500);

/// A slave's registers as bring-up left them.
#[derive(Debug, Clone, Default)]
struct Kept {
    /// Sync managers 0.. (8 bytes each).
    sms: Vec<u8>,
    /// FMMUs 0.. (16 bytes each).
    fmmus: Vec<u8>,
}

/// Where one slave's recovery stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    /// Nothing to do, or waiting until `next` to look again.
    Idle { next: Option<Instant> },
    /// PRE-OP asked; waiting for it.
    PreOp { until: Instant },
    /// SAFE-OP asked.
    SafeOp { until: Instant },
    /// OP asked.
    Op { until: Instant },
}

/// Why the last try to bring a slave back failed (it is tried again
/// after [`RETRY`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Failure {
    /// Nothing answers at its position (or its station address could
    /// not be set).
    NotFound = 1,
    /// A different device sits at its position ([`super::Cyclic::refused`]).
    Refused = 2,
    /// It did not reach PRE-OP (its mailbox set-up refused).
    PreOp = 3,
    /// Its PRE-OP configuration failed: the SDO writes, the sync
    /// managers and FMMUs, the clocks.
    Configuration = 4,
    /// It did not reach SAFE-OP (its process data set-up refused).
    SafeOp = 5,
    /// It did not reach OP.
    Op = 6,
}

impl Failure {
    /// The failure of code `v` (0 or unknown: none).
    pub fn from_code(v: u8) -> Option<Failure> {
        Some(match v {
            1 => Failure::NotFound,
            2 => Failure::Refused,
            3 => Failure::PreOp,
            4 => Failure::Configuration,
            5 => Failure::SafeOp,
            6 => Failure::Op,
            _ => return None,
        })
    }

    /// What failed, for the log.
    pub fn describe(self) -> &'static str {
        match self {
            Failure::NotFound => "no answer at its station address nor at its position",
            Failure::Refused => "a different device sits at its position",
            Failure::PreOp => "it did not reach PRE-OP (mailbox set-up)",
            Failure::Configuration => {
                "its PRE-OP configuration failed (SDO writes, sync managers, FMMUs, clocks)"
            }
            Failure::SafeOp => "it did not reach SAFE-OP (process data set-up)",
            Failure::Op => "it did not reach OP",
        }
    }
}

/// Publishes slave `i`'s last failure (None: brought back).
fn report(shared: &Shared, i: usize, f: Option<Failure>) {
    let code = f.map_or(0, |f| f as u8);
    if let Some(a) = shared.recovery.get(i) {
        if a.load(Relaxed) != code {
            a.store(code, Relaxed);
        }
    }
}

/// What step 1 found at a slave's position.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Found {
    /// The slave, brought to INIT with its mailbox set up, PRE-OP asked.
    Started,
    /// The slave with its address and in PRE-OP, SAFE-OP or OP: nothing
    /// to bring back.
    Configured,
    /// A different device (refused).
    Refused,
}

/// The recovery of every slave of a master.
#[derive(Debug, Default)]
pub(super) struct Recovery {
    kept: Vec<Kept>,
    stages: Vec<Stage>,
}

/// The error of a recovery step (the step is tried again later; the
/// error says which step failed and why).
fn fail(step: &str, e: impl std::fmt::Display) -> Error {
    Error::Master {
        iface: String::new(),
        step: format!("bringing a slave back: {step}"),
        reason: e.to_string(),
    }
}

impl Recovery {
    /// Keeps each slave's sync manager and FMMU registers (the segment
    /// in OP, as bring-up left it).
    pub(super) fn new(md: &MainDevice<'_>, io: &mut Io<'_>, slaves: &[SlaveInfo]) -> Recovery {
        let kept = slaves
            .iter()
            .map(|s| Kept {
                sms: without_status(read_block(
                    md,
                    io,
                    s.station,
                    regs::SM_COUNT,
                    regs::SM_BASE,
                    regs::SM_LEN,
                )),
                fmmus: read_block(
                    md,
                    io,
                    s.station,
                    regs::FMMU_COUNT,
                    regs::FMMU_BASE,
                    regs::FMMU_LEN,
                ),
            })
            .collect();
        Recovery {
            kept,
            stages: vec![Stage::Idle { next: None }; slaves.len()],
        }
    }

    /// Whether slave `i` is being brought back (a fault reset leaves it
    /// alone meanwhile).
    pub(super) fn busy(&self, i: usize) -> bool {
        !matches!(self.stages.get(i), None | Some(Stage::Idle { .. }))
    }

    /// One step for every slave that needs one, after a cycle whose
    /// frame came back.
    pub(super) fn step(
        &mut self,
        md: &MainDevice<'_>,
        io: &mut Io<'_>,
        group: &Group,
        shared: &Shared,
        slaves: &[SlaveInfo],
        cfg: &MasterConfig,
    ) {
        let now = Instant::now();
        for (i, s) in slaves.iter().enumerate() {
            let state = shared.states.get(i).map_or(0, |a| a.load(Relaxed)) & al::STATE_MASK;
            let Some(stage) = self.stages.get(i).copied() else {
                continue;
            };
            let until = now + cfg.state_timeout;
            let (next, failed) = match stage {
                Stage::Idle { next } => {
                    if state == al::OP {
                        // Back (on its own, or the line whole again).
                        report(shared, i, None);
                    }
                    let lost = state == 0 || state == al::INIT;
                    if !lost || next.is_some_and(|t| now < t) {
                        (stage, None)
                    } else {
                        match self.find(md, io, group, shared, i, s) {
                            Ok(Found::Started) => (Stage::PreOp { until }, None),
                            // Its state check was lost, not the slave.
                            Ok(Found::Configured) => (Stage::Idle { next: None }, None),
                            Ok(Found::Refused) => (stage, Some(Failure::Refused)),
                            Err(_) => (stage, Some(Failure::NotFound)),
                        }
                    }
                }
                Stage::PreOp { until: t } => match state {
                    al::PREOP => match self.configure(md, io, group, i, s, cfg) {
                        Ok(()) => (Stage::SafeOp { until }, None),
                        Err(_) => (stage, Some(Failure::Configuration)),
                    },
                    _ if now > t => (stage, Some(Failure::PreOp)),
                    _ => (stage, None),
                },
                Stage::SafeOp { until: t } => match state {
                    al::SAFEOP => match request(md, io, s.station, al::OP) {
                        Ok(()) => (Stage::Op { until }, None),
                        Err(_) => (stage, Some(Failure::Op)),
                    },
                    _ if now > t => (stage, Some(Failure::SafeOp)),
                    _ => (stage, None),
                },
                Stage::Op { until: t } => match state {
                    al::OP => {
                        report(shared, i, None);
                        (Stage::Idle { next: None }, None)
                    }
                    _ if now > t => (stage, Some(Failure::Op)),
                    _ => (stage, None),
                },
            };
            self.stages[i] = match failed {
                None => next,
                Some(f) => {
                    report(shared, i, Some(f));
                    if !matches!(stage, Stage::Idle { .. }) {
                        // Half brought up: back to INIT, so that the
                        // next try starts from the beginning.
                        let _ = request(md, io, s.station, al::INIT | al::ERROR);
                    }
                    Stage::Idle {
                        next: Some(now + RETRY),
                    }
                }
            };
        }
    }

    /// Step 1: finds the slave at its position, gives it its station
    /// address, checks its identity, sets up its mailbox and asks for
    /// PRE-OP. An error: nothing answers there (or a step failed).
    #[allow(clippy::too_many_arguments, reason = "the helper's state, passed down")]
    fn find(
        &mut self,
        md: &MainDevice<'_>,
        io: &mut Io<'_>,
        group: &Group,
        shared: &Shared,
        i: usize,
        s: &SlaveInfo,
    ) -> Result<Found> {
        // EtherCrab's APxx take the position and count down themselves.
        let auto = s.position;
        let station: u16 = io
            .block_on(Command::aprd(auto, regs::STATION_ADDRESS).receive::<u16>(md))
            .map_err(|e| fail("looking at the position", e))?;
        if station == s.station {
            // It kept its address: only a slave in INIT is brought up
            // again (one in PRE-OP or SAFE-OP waits for a fault reset;
            // one in OP lost a state check, not its configuration).
            let status: u16 = io
                .block_on(Command::fprd(s.station, regs::AL_STATUS).receive::<u16>(md))
                .map_err(|e| fail("reading the AL status", e))?;
            if status as u8 & al::STATE_MASK != al::INIT {
                return Ok(Found::Configured);
            }
        } else {
            io.block_on(Command::apwr(auto, regs::STATION_ADDRESS).send(md, s.station))
                .map_err(|e| fail("setting the station address", e))?;
        }
        // Back to INIT (acknowledging any error) before anything else.
        io.block_on(
            Command::fpwr(s.station, regs::AL_CONTROL).send(md, u16::from(al::INIT | al::ERROR)),
        )
        .map_err(|e| fail("asking for INIT", e))?;
        let found = read_identity(md, io, group, i)?;
        let refused = found != (s.identity.0, s.identity.1);
        if let (Some(flag), Some(what)) = (shared.refused.get(i), shared.found.get(i)) {
            what.store((u64::from(found.0) << 32) | u64::from(found.1), Relaxed);
            flag.store(refused, Release);
        }
        if refused {
            return Ok(Found::Refused);
        }
        let Some(kept) = self.kept.get(i) else {
            return Err(fail("its registers", "not kept at bring-up"));
        };
        for (k, sm_regs) in kept.sms.chunks(usize::from(regs::SM_LEN)).enumerate() {
            let mailbox = is_mailbox(sm_regs);
            if mailbox {
                write_block(md, io, s.station, regs::SM_BASE, regs::SM_LEN, k, sm_regs)?;
            }
        }
        request(md, io, s.station, al::PREOP)?;
        Ok(Found::Started)
    }

    /// Step 3: in PRE-OP, the configuration's SDO writes, the process
    /// data sync managers and the FMMUs as kept, the SYNC unit; then
    /// SAFE-OP is asked.
    fn configure(
        &self,
        md: &MainDevice<'_>,
        io: &mut Io<'_>,
        group: &Group,
        i: usize,
        s: &SlaveInfo,
        cfg: &MasterConfig,
    ) -> Result<()> {
        let plan = cfg.slaves.iter().find(|p| usize::from(p.position) == i);
        let sd = group
            .subdevice(md, i)
            .map_err(|e| fail("the slave's handle", e))?;
        for w in plan.map_or(&[][..], |p| p.sdos.as_slice()) {
            let sub = match w.sub {
                Some(n) => SubIndex::Index(n),
                None => SubIndex::Complete,
            };
            io.block_on(sd.sdo_write(w.index, sub, w.data.as_slice()))
                .map_err(|e| fail("an SDO write of the configuration", e))?;
        }
        let Some(kept) = self.kept.get(i) else {
            return Err(fail("its registers", "not kept at bring-up"));
        };
        for (k, sm_regs) in kept.sms.chunks(usize::from(regs::SM_LEN)).enumerate() {
            let mailbox = is_mailbox(sm_regs);
            if !mailbox {
                write_block(md, io, s.station, regs::SM_BASE, regs::SM_LEN, k, sm_regs)?;
            }
        }
        for (k, f) in kept.fmmus.chunks(usize::from(regs::FMMU_LEN)).enumerate() {
            write_block(md, io, s.station, regs::FMMU_BASE, regs::FMMU_LEN, k, f)?;
        }
        let reference = md_reference(group, md);
        if sd.dc_support().any() {
            restore_clock(md, io, s.station, sd.propagation_delay(), reference)?;
        }
        if let Some((p, d)) = plan.and_then(|p| p.dc.map(|d| (p, d))) {
            dc::configure_sync(md, io, &sd, (p.position, &p.name), &d, reference)
                .map_err(|e| fail("the SYNC unit", e))?;
        }
        request(md, io, s.station, al::SAFEOP)
    }
}

/// The reference clock's station address: the first slave with DC.
fn md_reference(group: &Group, md: &MainDevice<'_>) -> Option<u16> {
    dc::reference(group.iter(md))
}

/// The DC clock of a slave that lost its configuration: its system
/// time offset set again so that its system time is the reference
/// clock's (the reference itself: the application time), and its
/// propagation delay as measured at bring-up. The drift control then
/// keeps it in step, as before.
fn restore_clock(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    station: u16,
    delay: u32,
    reference: Option<u16>,
) -> Result<()> {
    let read = |io: &mut Io<'_>, at: u16, reg: u16| {
        io.block_on(Command::fprd(at, reg).receive::<u64>(md))
            .map_err(|e| fail("reading the DC clock", e))
    };
    let target = match reference {
        Some(r) if r != station => read(io, r, regs::DC_SYSTEM_TIME)?,
        _ => ethercrab::std::ethercat_now(),
    };
    let system = read(io, station, regs::DC_SYSTEM_TIME)?;
    let offset = read(io, station, regs::DC_SYSTEM_TIME_OFFSET)?;
    let local = system.wrapping_sub(offset);
    io.block_on(
        Command::fpwr(station, regs::DC_SYSTEM_TIME_OFFSET).send(md, target.wrapping_sub(local)),
    )
    .map_err(|e| fail("the DC system time offset", e))?;
    io.block_on(Command::fpwr(station, regs::DC_SYSTEM_TIME_DELAY).send(md, delay))
        .map_err(|e| fail("the DC propagation delay", e))
}

/// Asks slave `station` for AL state `to`.
fn request(md: &MainDevice<'_>, io: &mut Io<'_>, station: u16, to: u8) -> Result<()> {
    io.block_on(Command::fpwr(station, regs::AL_CONTROL).send(md, u16::from(to)))
        .map_err(|e| fail(&format!("asking for {}", al::name(to)), e))
}

/// The vendor id and product code in the SII of the slave at `i`'s
/// station address (words 8 and 10).
fn read_identity(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    group: &Group,
    i: usize,
) -> Result<(u32, u32)> {
    let sd = group
        .subdevice(md, i)
        .map_err(|e| fail("the slave's handle", e))?;
    let mut words = [0u8; 8];
    let n = io
        .block_on(sd.eeprom_read_raw(md, 8, &mut words))
        .map_err(|e| fail("reading the SII identity", e))?;
    if n < 8 {
        return Err(fail("reading the SII identity", format!("{n} bytes of 8")));
    }
    let vendor = u32::from_le_bytes([words[0], words[1], words[2], words[3]]);
    let product = u32::from_le_bytes([words[4], words[5], words[6], words[7]]);
    Ok((vendor, product))
}

/// Reads `count` blocks of `len` bytes from `base` (the count in
/// register `count_reg`); empty when the slave does not answer.
fn read_block(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    station: u16,
    count_reg: u16,
    base: u16,
    len: u16,
) -> Vec<u8> {
    let Ok(count) = io.block_on(Command::fprd(station, count_reg).receive::<u8>(md)) else {
        return Vec::new();
    };
    let bytes = u16::from(count.min(16)) * len;
    if bytes == 0 {
        return Vec::new();
    }
    match io.block_on(Command::fprd(station, base).receive_slice(md, bytes)) {
        Ok(data) => data.to_vec(),
        Err(_) => Vec::new(),
    }
}

/// Whether a sync manager's registers set it up as a mailbox.
fn is_mailbox(sm_regs: &[u8]) -> bool {
    sm_regs
        .get(usize::from(sm::CONTROL))
        .is_some_and(|c| c & sm::MODE_MASK == sm::MODE_MAILBOX)
}

/// Sync manager registers with their status bytes cleared: the status
/// (a mailbox full, a buffer written) is the slave's to report, not
/// configuration to write back.
fn without_status(mut sms: Vec<u8>) -> Vec<u8> {
    for sm_regs in sms.chunks_mut(usize::from(regs::SM_LEN)) {
        if let Some(b) = sm_regs.get_mut(usize::from(sm::STATUS)) {
            *b = 0;
        }
    }
    sms
}

/// Writes block `k` (`len` bytes from `base`) of slave `station`.
fn write_block(
    md: &MainDevice<'_>,
    io: &mut Io<'_>,
    station: u16,
    base: u16,
    len: u16,
    k: usize,
    data: &[u8],
) -> Result<()> {
    let at = base + len * k as u16;
    io.block_on(Command::fpwr(station, at).send(md, data))
        .map_err(|e| fail(&format!("writing registers {at:#06x}"), e))
}
