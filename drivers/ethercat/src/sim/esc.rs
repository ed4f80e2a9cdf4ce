//! One simulated slave controller (ESC) with its device: 8 KiB of
//! registers and process RAM, the SII EEPROM behind its interface
//! registers, the AL state machine with the checks a real slave makes
//! before each transition (mailbox sync managers for PRE-OP, process
//! data sync managers against the PDO assignment for SAFE-OP), FMMUs
//! that map logical addresses to process RAM bit by bit, the mailbox
//! (CoE SDO server, emergencies) and the DC clock.
//!
//! A datagram reaches the ESC through [`Esc::physical`] (APxx, FPxx,
//! BRD/BWR/BRW, ARMW/FRMW register access) or [`Esc::logical`]
//! (LRD/LWR/LRW through the FMMUs); each returns the working counter
//! increment. Nothing here panics on any address, length or value.

use super::clock::{Activation, DcClock};
use super::device::{Device, ASSIGN_INPUTS, ASSIGN_OUTPUTS};
use super::mailbox::MailboxServer;
use super::od::{copy_bits, AssignedPdo, Mapped};
use crate::regs::{self, al, al_code, dl_status, features, fmmu, sii as sii_bits, sm};

/// Register and process RAM size.
pub const MEMORY: usize = 0x2000;
/// FMMUs.
pub const FMMUS: u16 = 8;
/// Sync managers.
pub const SYNC_MANAGERS: u16 = 8;

/// The process data watchdog (an ESC's default, 100 ms): outputs not
/// refreshed by a frame for this long are cleared, so that a slave
/// whose master vanished does not act on the last outputs of before
/// when frames come again.
pub const OUTPUT_WATCHDOG_NS: u64 = 100_000_000;

/// A physical access: read, write or both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// Read into the datagram.
    Read,
    /// Write from the datagram.
    Write,
    /// Read, then write (xxRW).
    ReadWrite,
}

/// One ESC.
#[derive(Debug)]
pub struct Esc {
    /// The device behind the ESC.
    pub device: Device,
    mem: Vec<u8>,
    eeprom: Vec<u8>,
    mailbox: MailboxServer,
    clock: DcClock,
    last_tick_ns: Option<u64>,
    layout_out: Vec<Mapped>,
    layout_in: Vec<Mapped>,
    position: u16,
    /// How long a frame takes to come back from the slaves after this
    /// one (port 1's receive time minus port 0's).
    downstream_ns: i64,
    /// The watchdog expired and no frame has written the outputs since.
    silent: bool,
    /// The outputs' process RAM as the first frame after the last
    /// silence wrote it.
    after_silence: Option<Vec<u8>>,
}

fn put16(mem: &mut [u8], at: u16, v: u16) {
    let a = usize::from(at);
    mem[a..a + 2].copy_from_slice(&v.to_le_bytes());
}

fn get16(mem: &[u8], at: u16) -> u16 {
    let a = usize::from(at);
    u16::from_le_bytes([mem[a], mem[a + 1]])
}

impl Esc {
    /// An ESC at `position` on the segment, in INIT, EEPROM loaded.
    pub fn new(device: Device, position: u16) -> Esc {
        let eeprom = device.sii().encode();
        let mut esc = Esc {
            mailbox: MailboxServer::new(device.mailbox),
            device,
            mem: vec![0; MEMORY],
            eeprom,
            clock: DcClock::new(position),
            last_tick_ns: None,
            layout_out: Vec::new(),
            layout_in: Vec::new(),
            position,
            downstream_ns: 0,
            silent: false,
            after_silence: None,
        };
        esc.power_on();
        esc
    }

    /// Power cycle: registers cleared, INIT, station address 0, the
    /// EEPROM's alias loaded; the device's dictionary keeps its defaults
    /// only if it was never changed (a real device forgets what was
    /// written in PRE-OP, as this one does by re-creating its mailbox).
    pub fn power_on(&mut self) {
        self.mem.iter_mut().for_each(|b| *b = 0);
        let m = &mut self.mem;
        m[usize::from(regs::TYPE)] = 0x11;
        m[usize::from(regs::REVISION)] = 0x01;
        m[usize::from(regs::FMMU_COUNT)] = FMMUS as u8;
        m[usize::from(regs::SM_COUNT)] = SYNC_MANAGERS as u8;
        m[usize::from(regs::RAM_SIZE)] = 8;
        m[usize::from(regs::PORT_DESCRIPTOR)] = 0x0F; // ports 0, 1: MII
        let f = if self.device.dc {
            features::DC | features::DC_64 | features::ENHANCED_DC_SYNC
        } else {
            0
        };
        put16(m, regs::FEATURES, f | features::FMMU_BIT_OPERATION);
        let alias = u16::from_le_bytes([self.eeprom[8], self.eeprom[9]]);
        put16(m, regs::STATION_ALIAS, alias);
        put16(m, regs::SII_CONTROL, sii_bits::READ_8);
        self.set_al(al::INIT, al_code::NONE);
        self.mailbox = MailboxServer::new(self.device.mailbox);
        self.last_tick_ns = None;
        self.clock.reset();
    }

    /// The station address the master configured.
    pub fn station_address(&self) -> u16 {
        get16(&self.mem, regs::STATION_ADDRESS)
    }

    /// The AL state (low nibble) and whether an error is indicated.
    pub fn al_state(&self) -> (u8, bool) {
        let s = self.mem[usize::from(regs::AL_STATUS)];
        (s & al::STATE_MASK, s & al::ERROR != 0)
    }

    /// The AL status code.
    pub fn al_code(&self) -> u16 {
        get16(&self.mem, regs::AL_STATUS_CODE)
    }

    /// The EEPROM image.
    pub fn eeprom(&self) -> &[u8] {
        &self.eeprom
    }

    fn set_al(&mut self, state: u8, code: u16) {
        let err = if code != al_code::NONE { al::ERROR } else { 0 };
        self.mem[usize::from(regs::AL_STATUS)] = state | err;
        put16(&mut self.mem, regs::AL_STATUS_CODE, code);
    }

    /// Drops to SAFE-OP with an error and `code`, as a slave does on a
    /// local fault (sync manager watchdog, sync error).
    pub fn raise_al_error(&mut self, code: u16) {
        let (state, _) = self.al_state();
        let to = if state == al::OP { al::SAFEOP } else { state };
        self.set_al(to, code);
    }

    /// DL status for a slave with the next one connected or not.
    pub fn set_links(&mut self, downstream: bool) {
        let mut s = dl_status::PDI_OPERATIONAL | dl_status::link(0) | dl_status::communication(0);
        if downstream {
            s |= dl_status::link(1) | dl_status::communication(1);
        } else {
            s |= dl_status::loop_closed(1);
        }
        put16(&mut self.mem, regs::DL_STATUS, s);
    }

    /// A frame arrives at simulated time `now_ns`: the device runs (the
    /// outputs of the last frame apply, inputs are refreshed), pending
    /// mailbox replies move into the mailbox.
    pub fn begin_frame(&mut self, now_ns: u64) {
        self.clock.arrive(now_ns);
        let dt = self.last_tick_ns.map_or(0, |t| now_ns.saturating_sub(t));
        self.last_tick_ns = Some(now_ns);
        let (state, _) = self.al_state();
        let op = state == al::OP;
        if op && dt > OUTPUT_WATCHDOG_NS {
            self.clear_outputs();
            self.silent = true;
        }
        if op {
            self.unpack_outputs();
        }
        self.device.app.cycle(&mut self.device.od, op, now_ns, dt);
        if state == al::SAFEOP || op {
            self.pack_inputs();
        }
        while let Some(e) = self.device.app.take_emergency() {
            self.mailbox.queue_emergency(&e, self.station_address());
        }
        self.refresh_mailbox();
    }

    fn sm(&self, n: u16) -> (u16, u16, u8, bool) {
        let base = regs::SM_BASE + n * regs::SM_LEN;
        (
            get16(&self.mem, base + sm::START),
            get16(&self.mem, base + sm::LENGTH),
            self.mem[usize::from(base + sm::CONTROL)],
            self.mem[usize::from(base + sm::ACTIVATE)] & sm::ENABLE != 0,
        )
    }

    /// The outputs the master sent first after the last silence of the
    /// watchdog's length (the process RAM of the outputs as that frame
    /// wrote it), if there was one: what a slave acts on first when its
    /// master comes back.
    pub fn outputs_after_silence(&self) -> Option<&[u8]> {
        self.after_silence.as_deref()
    }

    /// The watchdog expired: the outputs' process RAM goes to zero.
    fn clear_outputs(&mut self) {
        let start = usize::from(self.device.outputs_at).min(MEMORY);
        let end = (start + self.device.image_bytes().0).min(MEMORY);
        self.mem[start..end].fill(0);
    }

    fn unpack_outputs(&mut self) {
        let start = usize::from(self.device.outputs_at);
        let mut bit = 0usize;
        for (i, s, bits) in &self.layout_out {
            if *i != 0 {
                if let Some(e) = self.device.od.entry(*i, *s) {
                    let mut v = vec![0u8; e.value.len()];
                    copy_bits(&self.mem[start..], bit, &mut v, 0, usize::from(*bits));
                    self.device.od.set(*i, *s, {
                        let mut b = [0u8; 8];
                        for (k, x) in v.iter().take(8).enumerate() {
                            b[k] = *x;
                        }
                        u64::from_le_bytes(b)
                    });
                }
            }
            bit += usize::from(*bits);
        }
    }

    fn pack_inputs(&mut self) {
        let start = usize::from(self.device.inputs_at);
        let mut bit = 0usize;
        for (i, s, bits) in &self.layout_in {
            if *i != 0 {
                if let Some(e) = self.device.od.entry(*i, *s) {
                    copy_bits(&e.value, 0, &mut self.mem[start..], bit, usize::from(*bits));
                }
            }
            bit += usize::from(*bits);
        }
    }

    /// Whether process RAM at `addr` belongs to an enabled sync manager
    /// that may carry process data now (SAFE-OP and OP only).
    fn in_enabled_sm(&self, addr: u16) -> bool {
        let (state, _) = self.al_state();
        (0..SYNC_MANAGERS).any(|n| {
            let (start, len, control, enabled) = self.sm(n);
            let mailbox = control & sm::MODE_MASK == sm::MODE_MAILBOX;
            let allowed = mailbox || state == al::SAFEOP || state == al::OP;
            enabled
                && allowed
                && addr >= start
                && u32::from(addr) < u32::from(start) + u32::from(len)
        })
    }

    /// A register or RAM access at `ado`; returns the working counter
    /// increment (1 read, 1 write, 3 read-write).
    pub fn physical(&mut self, ado: u16, data: &mut [u8], access: Access) -> u16 {
        let at = usize::from(ado);
        if matches!(access, Access::Read | Access::ReadWrite) {
            self.before_read(ado, data.len());
            for (k, d) in data.iter_mut().enumerate() {
                *d = self.mem.get(at + k).copied().unwrap_or(0);
            }
            self.after_read(ado, data.len());
        }
        if matches!(access, Access::Write | Access::ReadWrite) {
            self.write(ado, data);
        }
        match access {
            Access::Read | Access::Write => 1,
            Access::ReadWrite => 3,
        }
    }

    /// Registers computed when read.
    fn before_read(&mut self, ado: u16, len: usize) {
        let end = u32::from(ado) + len as u32;
        let overlaps =
            |reg: u16, n: u32| u32::from(ado) < u32::from(reg) + n && end > u32::from(reg);
        if overlaps(regs::DC_SYSTEM_TIME, 8) {
            let t = self.system_time() as u64;
            let a = usize::from(regs::DC_SYSTEM_TIME);
            self.mem[a..a + 8].copy_from_slice(&t.to_le_bytes());
        }
        if overlaps(regs::DC_SYNC0_STATUS, 1) {
            self.clock.read_status(&mut self.mem);
        }
    }

    /// Reading the last byte of a full slave → master mailbox empties it.
    fn after_read(&mut self, ado: u16, len: usize) {
        let (start, mlen, control, enabled) = self.sm(1);
        if !enabled || control & sm::MODE_MASK != sm::MODE_MAILBOX || mlen == 0 {
            return;
        }
        let last = u32::from(start) + u32::from(mlen) - 1;
        if u32::from(ado) <= last && u32::from(ado) + len as u32 > last {
            let status = usize::from(regs::SM_BASE + regs::SM_LEN + sm::STATUS);
            if self.mem[status] & sm::STATUS_FULL != 0 {
                self.mem[status] &= !sm::STATUS_FULL;
                self.mailbox.consumed();
                self.refresh_mailbox();
            }
        }
    }

    /// The system time now (local time of this frame plus offset and
    /// drift correction).
    pub fn system_time(&self) -> i64 {
        self.clock.system_time(&self.mem)
    }

    /// The local clock runs `ppm` parts per million fast (negative:
    /// slow) from now on, against the simulated time (the host's).
    pub fn set_clock_ppm(&mut self, ppm: i64) {
        self.clock.set_ppm(ppm);
    }

    /// The local clock jumps by `ns`.
    pub fn step_clock(&mut self, ns: i64) {
        self.clock.step(ns);
    }

    /// What the master activated in the SYNC unit, if anything.
    pub fn sync_activation(&self) -> Option<Activation> {
        self.clock.activation()
    }

    /// How often the master wrote this slave's system time (the drift
    /// control's input) since power on.
    pub fn system_time_writes(&self) -> u64 {
        self.clock.writes()
    }

    /// SYNC0 pulses so far, at the time of the last frame.
    pub fn sync0_events(&self) -> u64 {
        self.clock.sync0_events(&self.mem)
    }

    /// `len` bytes of registers from `at` as they are (no side effect of
    /// a read; past the end, nothing).
    pub fn registers(&self, at: u16, len: usize) -> &[u8] {
        let a = usize::from(at).min(MEMORY);
        &self.mem[a..(a + len).min(MEMORY)]
    }

    fn writable(addr: usize) -> bool {
        let a = addr as u16;
        !(a < 0x0010
            || (regs::DL_STATUS..regs::DL_STATUS + 2).contains(&a)
            || (regs::AL_STATUS..regs::AL_STATUS + 6).contains(&a)
            || (regs::FEATURES..regs::FEATURES + 2).contains(&a))
    }

    fn write(&mut self, ado: u16, data: &[u8]) {
        let at = usize::from(ado);
        // The system time register takes writes as the drift control's
        // input, not as a value to hold (on a slave with DC).
        let touches =
            |reg: u16, n: usize| at < usize::from(reg) + n && at + data.len() > usize::from(reg);
        let system_time_write =
            self.device.dc && touches(regs::DC_SYSTEM_TIME, 4) && data.len() >= 4;
        for (k, d) in data.iter().enumerate() {
            let a = at + k;
            if a < MEMORY && Esc::writable(a) && !(system_time_write && (0x910..0x918).contains(&a))
            {
                self.mem[a] = *d;
            }
        }
        if touches(regs::AL_CONTROL, 2) {
            self.al_request();
        }
        if touches(regs::SII_CONTROL, 2) {
            self.sii_command();
        }
        if touches(regs::DC_RECEIVE_TIME_PORT0, 4) {
            self.clock
                .latch_receive_times(&mut self.mem, self.downstream_ns);
        }
        if touches(regs::DC_ACTIVATION, 1) {
            self.clock.activate(&self.mem);
        }
        if system_time_write && at == usize::from(regs::DC_SYSTEM_TIME) {
            let mut b = [0u8; 8];
            for (k, x) in data.iter().take(8).enumerate() {
                b[k] = *x;
            }
            self.clock
                .drift_control(&mut self.mem, u64::from_le_bytes(b), data.len());
        }
        self.mailbox_written(ado, data.len());
    }

    fn reg4(&self, at: u16) -> [u8; 4] {
        let a = usize::from(at);
        [
            self.mem[a],
            self.mem[a + 1],
            self.mem[a + 2],
            self.mem[a + 3],
        ]
    }

    fn sii_command(&mut self) {
        let control = get16(&self.mem, regs::SII_CONTROL);
        let word = u32::from_le_bytes(self.reg4(regs::SII_ADDRESS)) as usize;
        let mut status = sii_bits::READ_8 | (control & sii_bits::WRITE_ENABLE);
        match control & sii_bits::CMD_MASK {
            0 => {}
            sii_bits::CMD_READ => {
                let d = usize::from(regs::SII_DATA);
                for k in 0..8 {
                    self.mem[d + k] = self.eeprom.get(word * 2 + k).copied().unwrap_or(0xFF);
                }
            }
            sii_bits::CMD_WRITE => {
                if control & sii_bits::WRITE_ENABLE == 0 {
                    status |= sii_bits::WRITE_ERROR;
                } else if word * 2 + 2 <= self.eeprom.len() {
                    let d = usize::from(regs::SII_DATA);
                    self.eeprom[word * 2] = self.mem[d];
                    self.eeprom[word * 2 + 1] = self.mem[d + 1];
                } else {
                    status |= sii_bits::COMMAND_ERROR;
                }
            }
            sii_bits::CMD_RELOAD => {
                let alias = u16::from_le_bytes([self.eeprom[8], self.eeprom[9]]);
                put16(&mut self.mem, regs::STATION_ALIAS, alias);
            }
            _ => status |= sii_bits::COMMAND_ERROR,
        }
        put16(&mut self.mem, regs::SII_CONTROL, status);
    }

    /// An AL control write: the requested state, checked as a slave does.
    fn al_request(&mut self) {
        let request = self.mem[usize::from(regs::AL_CONTROL)];
        let want = request & al::STATE_MASK;
        let ack = request & al::ERROR != 0;
        let (state, error) = self.al_state();
        if error && !ack && want > state {
            // An indicated error must be acknowledged before going up.
            return;
        }
        let code = match (state, want) {
            (_, al::INIT) => {
                self.set_al(al::INIT, al_code::NONE);
                self.mailbox.reset();
                return;
            }
            (_, al::BOOT) => Some(al_code::BOOTSTRAP_NOT_SUPPORTED),
            (s, w) if s == w => None,
            (al::INIT, al::PREOP) => self.check_mailbox(),
            (al::PREOP, al::SAFEOP) => self
                .check_process_data()
                .or_else(|| self.clock.check(self.device.dc, self.device.needs_sync0)),
            (al::SAFEOP, al::OP) => None,
            (al::SAFEOP | al::OP, al::PREOP) | (al::OP, al::SAFEOP) => None,
            (_, al::SAFEOP | al::OP | al::PREOP) => Some(al_code::INVALID_STATE_CHANGE),
            _ => Some(al_code::UNKNOWN_STATE),
        };
        match code {
            None => {
                if want == al::SAFEOP && state == al::PREOP {
                    self.layout_out = flatten(self.device.od.assigned(ASSIGN_OUTPUTS));
                    self.layout_in = flatten(self.device.od.assigned(ASSIGN_INPUTS));
                    self.pack_inputs();
                }
                self.set_al(want, al_code::NONE);
            }
            Some(c) => self.set_al(state, c),
        }
    }

    fn check_mailbox(&self) -> Option<u16> {
        if !self.device.mailbox {
            return None;
        }
        let (s0, l0, c0, e0) = self.sm(0);
        let (s1, l1, c1, e1) = self.sm(1);
        let ok0 = e0
            && s0 == super::device::MAILBOX_OUT
            && l0 == super::device::MAILBOX_SIZE
            && c0 & 0x0F == 0x06;
        let ok1 = e1
            && s1 == super::device::MAILBOX_IN
            && l1 == super::device::MAILBOX_SIZE
            && c1 & 0x0F == 0x02;
        (!(ok0 && ok1)).then_some(al_code::INVALID_MAILBOX_CONFIG)
    }

    fn check_process_data(&self) -> Option<u16> {
        let (out_bytes, in_bytes) = self.device.image_bytes();
        let (o, i) = self.device.pd_sync_managers();
        let check = |n: u8, bytes: usize, at: u16, write: bool| -> bool {
            let (start, len, control, enabled) = self.sm(u16::from(n));
            if bytes == 0 {
                return !enabled || len == 0;
            }
            let dir_ok = (control & sm::DIR_MASK == sm::DIR_WRITE) == write;
            enabled
                && usize::from(len) == bytes
                && start == at
                && dir_ok
                && control & sm::MODE_MASK == 0
        };
        if !check(o, out_bytes, self.device.outputs_at, true) {
            return Some(al_code::INVALID_OUTPUT_CONFIG);
        }
        if !check(i, in_bytes, self.device.inputs_at, false) {
            return Some(al_code::INVALID_INPUT_CONFIG);
        }
        None
    }

    /// A write that reached the last byte of the master → slave mailbox
    /// delivers the request.
    fn mailbox_written(&mut self, ado: u16, len: usize) {
        let (start, mlen, control, enabled) = self.sm(0);
        if !enabled
            || control & sm::MODE_MASK != sm::MODE_MAILBOX
            || mlen == 0
            || !self.device.mailbox
        {
            return;
        }
        let last = u32::from(start) + u32::from(mlen) - 1;
        if !(u32::from(ado) <= last && u32::from(ado) + len as u32 > last) {
            return;
        }
        let (state, _) = self.al_state();
        if state == al::INIT {
            return;
        }
        let s = usize::from(start);
        let request = self.mem[s..s + usize::from(mlen)].to_vec();
        let address = self.station_address();
        self.mailbox
            .request(&request, &mut self.device.od, state == al::PREOP, address);
        self.refresh_mailbox();
    }

    /// Moves the next reply into the slave → master mailbox if it is empty.
    fn refresh_mailbox(&mut self) {
        let (start, mlen, _, enabled) = self.sm(1);
        let status = usize::from(regs::SM_BASE + regs::SM_LEN + sm::STATUS);
        if !enabled || self.mem[status] & sm::STATUS_FULL != 0 {
            return;
        }
        if let Some(reply) = self.mailbox.next_reply() {
            let s = usize::from(start);
            let n = usize::from(mlen).min(MEMORY.saturating_sub(s));
            for k in 0..n {
                self.mem[s + k] = reply.get(k).copied().unwrap_or(0);
            }
            self.mem[status] |= sm::STATUS_FULL;
        }
    }

    /// A logical datagram through the FMMUs; returns the working counter
    /// increment (LRD 1, LWR 1, LRW 1 read + 2 write).
    pub fn logical(&mut self, address: u32, data: &mut [u8], read: bool, write: bool) -> u16 {
        let (mut did_read, mut did_write) = (false, false);
        for n in 0..FMMUS {
            let base = regs::FMMU_BASE + n * regs::FMMU_LEN;
            let b = usize::from(base);
            if self.mem[b + usize::from(fmmu::ACTIVATE)] & 1 == 0 {
                continue;
            }
            let log_start = u32::from_le_bytes(self.reg4(base + fmmu::LOGICAL_START));
            let len = u32::from(get16(&self.mem, base + fmmu::LENGTH));
            let start_bit = u32::from(self.mem[b + usize::from(fmmu::LOGICAL_START_BIT)] & 7);
            let stop_bit = u32::from(self.mem[b + usize::from(fmmu::LOGICAL_STOP_BIT)] & 7);
            let phys = get16(&self.mem, base + fmmu::PHYSICAL_START);
            let phys_bit = usize::from(self.mem[b + usize::from(fmmu::PHYSICAL_START_BIT)] & 7);
            let kind = self.mem[b + usize::from(fmmu::TYPE)];
            if len == 0 || !self.in_enabled_sm(phys) {
                continue;
            }
            // The FMMU's logical bits: from start_bit of the first byte to
            // stop_bit of the last.
            let first = u64::from(log_start) * 8 + u64::from(start_bit);
            let last = (u64::from(log_start) + u64::from(len) - 1) * 8 + u64::from(stop_bit);
            let d_first = u64::from(address) * 8;
            let d_last = d_first + data.len() as u64 * 8;
            let lo = first.max(d_first);
            let hi = (last + 1).min(d_last);
            if lo >= hi {
                continue;
            }
            let bits = (hi - lo) as usize;
            let data_bit = (lo - d_first) as usize;
            let phys_bit = phys_bit + (lo - first) as usize;
            let p = usize::from(phys);
            if kind & fmmu::READ != 0 && read {
                copy_bits(&self.mem[p.min(MEMORY)..], phys_bit, data, data_bit, bits);
                did_read = true;
            }
            if kind & fmmu::WRITE != 0 && write {
                let start = p.min(MEMORY);
                copy_bits(data, data_bit, &mut self.mem[start..], phys_bit, bits);
                did_write = true;
            }
        }
        if did_write && self.silent {
            self.silent = false;
            let start = usize::from(self.device.outputs_at).min(MEMORY);
            let end = (start + self.device.image_bytes().0).min(MEMORY);
            self.after_silence = Some(self.mem[start..end].to_vec());
        }
        let w = if read && write { 2 } else { 1 };
        u16::from(did_read) + if did_write { w } else { 0 }
    }

    /// Sets how long frames take to come back from downstream.
    pub fn set_downstream_ns(&mut self, ns: i64) {
        self.downstream_ns = ns;
    }

    /// The position this ESC was created at.
    pub fn position(&self) -> u16 {
        self.position
    }
}

fn flatten(pdos: Vec<AssignedPdo>) -> Vec<Mapped> {
    pdos.into_iter().flat_map(|(_, e)| e).collect()
}
