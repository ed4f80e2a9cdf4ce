//! The Modbus master of one hm2_modbus instance: a state machine stepped
//! once per servo period that never waits. The init list runs once (when
//! the instance first leaves suspend), then the commands run in a loop:
//! a command whose interval is due is built from its pins, sent, its
//! transmission awaited, its reply awaited within its timeout, parsed
//! onto its pins, and the next command follows. A write whose data did
//! not change is skipped unless it has `resend`.
//!
//! Faults: each failed exchange counts on the command's `errors` pin,
//! sets its `error-code` and the instance's `fault`, `fault-command` and
//! `last-error-code`; the fifth consecutive one disables the command
//! (`disabled`) until its `reset` or the instance's `reset` rises. A
//! timeout also clears the PktUART and waits 25 ms before the next
//! command. Read pins keep their last good value; `fault` clears with the
//! next good reply.
//!
//! Where this differs from LinuxCNC's hm2_modbus: `error-code` shows
//! every error as it happens (its man page says "the last error"; the C
//! sets it only when it disables the command); `fault` rises on any
//! failed exchange, not only on a timeout; a reply from another device
//! counts as an error (ERANGE) instead of a silent resend; init replies
//! are checked (device, function, CRC, exception), their data unused.
//!
//! The engine never reaches the board itself: its [`Port`] is a
//! [`PktUartLink`] whose status words and frame data come in the board's
//! read burst and whose writes go in its write burst (see
//! [`super`] for the timing).

use super::frame::{self, errno};
use super::line::{Line, Versions};
use super::mbccb::{flags, format, Init, Mbccb};
use super::pins::{data_pins, CommandPins, DataPin, GlobalPins};
use super::rtu::{self, crc16};
use crate::pktuart::config::LineConfig;
use crate::pktuart::link::{PktUartLink, Status};
use crate::regs::pktuart::rcr;
use crate::transport::TransportError;

/// Consecutive errors that disable a command.
pub const MAX_ERRORS: u32 = 5;
/// The wait after a timeout's PktUART clear.
const RESET_WAIT_NS: i64 = 25_000_000;

/// What the engine needs of a PktUART: what its board's read burst
/// brought this period, writes staged for the board's write burst, and
/// frames fetched over the next read bursts. None of it waits or talks
/// to the board.
pub trait Port {
    /// The mode/status words of this period's read burst, once; `None`
    /// when no burst arrived since the last period.
    fn take_status(&mut self) -> Option<Status>;
    /// Stages both directions' settings, clearing the FIFOs when `flush`.
    fn configure(
        &mut self,
        rx: &LineConfig,
        tx: &LineConfig,
        flush: bool,
    ) -> Result<(), TransportError>;
    /// Stages the abort of both directions (and drops a fetch under way).
    fn clear(&mut self) -> Result<(), TransportError>;
    /// Stages one frame.
    fn send(&mut self, frame: &[u8]) -> Result<(), TransportError>;
    /// Whether a frame is being fetched.
    fn fetching(&self) -> bool;
    /// Fetches the next received frame into `out`: `None` while it is on
    /// its way (the first call asks for it), then its count word and the
    /// bytes stored.
    fn fetch_frame(&mut self, out: &mut [u8]) -> Result<Option<(u32, usize)>, TransportError>;
}

impl Port for PktUartLink {
    fn take_status(&mut self) -> Option<Status> {
        PktUartLink::take_status(self)
    }
    fn configure(
        &mut self,
        rx: &LineConfig,
        tx: &LineConfig,
        flush: bool,
    ) -> Result<(), TransportError> {
        PktUartLink::configure(self, rx, tx, flush)
    }
    fn clear(&mut self) -> Result<(), TransportError> {
        PktUartLink::clear(self)
    }
    fn send(&mut self, frame: &[u8]) -> Result<(), TransportError> {
        PktUartLink::send(self, frame)
    }
    fn fetching(&self) -> bool {
        PktUartLink::fetching(self)
    }
    fn fetch_frame(&mut self, out: &mut [u8]) -> Result<Option<(u32, usize)>, TransportError> {
        PktUartLink::fetch_frame(self, out)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Start,
    Delay,
    WaitSent,
    WaitReply,
    ResetWait,
}

/// Per-command running state.
#[derive(Debug, Clone)]
struct Running {
    first_pin: usize,
    disabled: bool,
    errors: u32,
    prev_reset: bool,
    prev_disable: bool,
    /// Nanoseconds until due (due when negative).
    interval_ns: i64,
    /// The last request sent (for change detection); `len` 0 = none.
    last: [u8; rtu::MAX_FRAME],
    len: usize,
}

/// One hm2_modbus instance's engine and pin values.
pub struct Engine {
    file: Mbccb,
    versions: Versions,
    /// The line as configured now (the parameters).
    pub line: Line,
    /// Data pins, all commands' in order.
    pub pins: Vec<DataPin>,
    /// Per-command pins.
    pub commands: Vec<CommandPins>,
    /// The instance's pins.
    pub global: GlobalPins,
    run: Vec<Running>,
    in_init: bool,
    idx: usize,
    state: State,
    timeout_ns: i64,
    suspended: bool,
    prev_reset: bool,
    /// Set once the init list has run (or there is none).
    inits_done: bool,
    frame: [u8; rtu::MAX_FRAME],
    frame_len: usize,
    rx: [u8; rtu::MAX_FRAME],
    /// Replies that arrived with no request outstanding (dropped).
    pub stray_frames: u64,
}

impl Engine {
    /// An engine for `file` on a PktUART of these versions.
    pub fn new(file: Mbccb, versions: Versions) -> Engine {
        let parity = match file.format & (format::PARITY_EN | format::PARITY_ODD) {
            0 => 0,
            f if f & format::PARITY_ODD != 0 => 1,
            _ => 2,
        };
        let stop = if file.format & format::STOP_BITS2 != 0 {
            2
        } else {
            1
        };
        let manual = [file.rxdelay, file.txdelay, file.drvdelay, file.icdelay].map(u32::from);
        let mut line = Line::new(file.baudrate, parity, stop, manual, versions);
        line.full_duplex = file.format & format::DUPLEX != 0;
        let (pins, first) = data_pins(&file.commands);
        let run = file
            .commands
            .iter()
            .zip(first)
            .map(|(c, first_pin)| Running {
                first_pin,
                disabled: c.flags & flags::DISABLED != 0,
                errors: 0,
                prev_reset: false,
                prev_disable: false,
                interval_ns: -1,
                last: [0; rtu::MAX_FRAME],
                len: 0,
            })
            .collect::<Vec<_>>();
        let commands = run
            .iter()
            .map(|r| CommandPins {
                disabled: r.disabled,
                error_code: if r.disabled { errno::EAGAIN } else { 0 },
                ..CommandPins::default()
            })
            .collect();
        let global = GlobalPins {
            suspend: file.format & format::SUSPEND != 0,
            ..GlobalPins::default()
        };
        Engine {
            in_init: !file.inits.is_empty(),
            inits_done: file.inits.is_empty(),
            file,
            versions,
            line,
            pins,
            commands,
            global,
            run,
            idx: 0,
            state: State::Start,
            timeout_ns: 0,
            suspended: true,
            prev_reset: false,
            frame: [0; rtu::MAX_FRAME],
            frame_len: 0,
            rx: [0; rtu::MAX_FRAME],
            stray_frames: 0,
        }
    }

    /// The file it runs.
    pub fn file(&self) -> &Mbccb {
        &self.file
    }

    /// The data pins of command `c`.
    pub fn command_pins(&self, c: usize) -> &[DataPin] {
        let first = self.run[c].first_pin;
        &self.pins[first..first + self.file.commands[c].pins.len()]
    }

    /// The initial line configuration (load time).
    pub fn configs(&self) -> (LineConfig, LineConfig) {
        self.line.configs()
    }

    /// One servo period of `period_ns`.
    pub fn process(&mut self, port: &mut dyn Port, period_ns: i64) {
        let status = port.take_status();
        if self.suspended {
            if self.global.suspend {
                return;
            }
            self.suspended = false;
            self.write_flush_all();
        }
        if !self.in_init {
            for r in &mut self.run {
                r.interval_ns = r.interval_ns.saturating_sub(period_ns);
            }
            self.global_reset_edge();
        }
        self.timeout_ns = self.timeout_ns.saturating_sub(period_ns);
        if let Err(e) = self.step(port, status) {
            // The board did not answer: the board driver reports that;
            // here the exchange is lost and the port is cleared.
            let _ = e;
            self.fail(errno::EIO);
            self.reset_port(port);
        }
    }

    fn step(&mut self, port: &mut dyn Port, status: Option<Status>) -> Result<(), TransportError> {
        match self.state {
            State::Start => self.start(port, status),
            State::Delay => {
                if self.timeout_ns < 0 {
                    self.global.fault = false;
                    self.next();
                }
                Ok(())
            }
            State::WaitSent => {
                if status.is_none_or(|s| s.tx_busy()) {
                    self.check_timeout(port);
                    return Ok(());
                }
                if self.expects_answer() {
                    self.state = State::WaitReply;
                    self.wait_reply(port, status)
                } else {
                    self.next();
                    Ok(())
                }
            }
            State::WaitReply => self.wait_reply(port, status),
            State::ResetWait => {
                if self.timeout_ns < 0 {
                    self.next();
                }
                Ok(())
            }
        }
    }

    fn expects_answer(&self) -> bool {
        let (mbid, fl) = if self.in_init {
            match &self.file.inits[self.idx] {
                Init::Packet { mbid, flags, .. } => (*mbid, *flags),
                _ => return false,
            }
        } else {
            let c = &self.file.commands[self.idx];
            (c.mbid, c.flags)
        };
        if mbid == 0 {
            fl & flags::BCANSWER != 0
        } else {
            fl & flags::NOANSWER == 0
        }
    }

    fn start(&mut self, port: &mut dyn Port, status: Option<Status>) -> Result<(), TransportError> {
        let Some(status) = status else {
            // No news from the board this period: nothing is started.
            return Ok(());
        };
        if port.fetching() || status.rx_frames() > 0 {
            // Out of band: nothing was asked. Dropped once it is in.
            if port.fetch_frame(&mut self.rx)?.is_some() {
                self.stray_frames += 1;
            }
            return Ok(());
        }
        if self.in_init {
            return self.start_init(port);
        }
        if self.run.iter().all(|r| r.disabled) {
            self.global.fault = true;
            self.global.last_error_code = errno::ENODATA;
            self.global.fault_command = 0;
            self.poll_command_edges();
            return Ok(());
        }
        for _ in 0..self.run.len() {
            if !self.run[self.idx].disabled && self.try_send(port)? {
                return Ok(());
            }
            if self.advance_loop() {
                return Ok(());
            }
        }
        Ok(())
    }

    /// Sends the current loop command if it is due and has something to
    /// say; true if it started an exchange (or a delay).
    fn try_send(&mut self, port: &mut dyn Port) -> Result<bool, TransportError> {
        let i = self.idx;
        let cmd = &self.file.commands[i];
        if cmd.func == 0 {
            self.timeout_ns = i64::from(cmd.timeout_us) * 1000;
            self.state = State::Delay;
            return Ok(true);
        }
        if self.run[i].interval_ns >= 0 {
            return Ok(false);
        }
        let r = &mut self.run[i];
        r.interval_ns = if cmd.interval_us == u32::MAX {
            i64::MAX
        } else {
            r.interval_ns
                .saturating_add(i64::from(cmd.interval_us) * 1000)
                .max(-1)
        };
        let first = r.first_pin;
        let pins = &self.pins[first..first + cmd.pins.len()];
        let len = match frame::build(cmd, pins, &mut self.frame) {
            Ok(n) => n,
            Err(code) => {
                self.run[i].disabled = true;
                self.commands[i].disabled = true;
                self.fail(code);
                return Ok(false);
            }
        };
        let is_write = matches!(
            cmd.func,
            rtu::W_COIL | rtu::W_REGISTER | rtu::W_COILS | rtu::W_REGISTERS
        );
        let r = &mut self.run[i];
        let same = r.len == len && r.last[..len] == self.frame[..len];
        if is_write && same && cmd.flags & flags::RESEND == 0 {
            return Ok(false);
        }
        r.last[..len].copy_from_slice(&self.frame[..len]);
        r.len = len;
        self.send_frame(port, len, cmd.timeout_us)?;
        Ok(true)
    }

    fn send_frame(
        &mut self,
        port: &mut dyn Port,
        len: usize,
        timeout_us: u32,
    ) -> Result<(), TransportError> {
        let crc = crc16(&self.frame[..len]).to_le_bytes();
        self.frame[len..len + 2].copy_from_slice(&crc);
        self.frame_len = len + 2;
        port.send(&self.frame[..self.frame_len])?;
        self.timeout_ns = i64::from(timeout_us) * 1000;
        self.state = State::WaitSent;
        Ok(())
    }

    fn start_init(&mut self, port: &mut dyn Port) -> Result<(), TransportError> {
        match &self.file.inits[self.idx] {
            Init::Delay { us } => {
                self.timeout_ns = i64::from(*us) * 1000;
                self.state = State::Delay;
            }
            Init::Comms {
                baud,
                flags: fl,
                rxdelay,
                txdelay,
                drvdelay,
                icdelay,
            } => {
                let parity = match *fl & (flags::PARITY_EN | flags::PARITY_ODD) {
                    0 => 0,
                    f if f & flags::PARITY_ODD != 0 => 1,
                    _ => 2,
                };
                let stop = if *fl & flags::STOP_BITS2 != 0 { 2 } else { 1 };
                let manual = [
                    u32::from(*rxdelay),
                    u32::from(*txdelay),
                    u32::from(*drvdelay),
                    *icdelay,
                ];
                let full = self.line.full_duplex;
                self.line = Line::new(*baud, parity, stop, manual, self.versions);
                self.line.full_duplex = full;
                let (rx, tx) = self.line.configs();
                port.configure(&rx, &tx, false)?;
                self.next();
            }
            Init::Packet {
                pdu, timeout_us, ..
            } => {
                let (len, t) = (pdu.len(), *timeout_us);
                self.frame[..len].copy_from_slice(pdu);
                self.send_frame(port, len, t)?;
            }
        }
        Ok(())
    }

    fn wait_reply(
        &mut self,
        port: &mut dyn Port,
        status: Option<Status>,
    ) -> Result<(), TransportError> {
        // A reply seen in time is fetched whatever the time left.
        if !port.fetching() && status.is_none_or(|s| s.rx_frames() == 0) {
            self.check_timeout(port);
            return Ok(());
        }
        let Some((count, n)) = port.fetch_frame(&mut self.rx)? else {
            return Ok(());
        };
        let size = (count & rcr::NBYTES_MASK) as usize;
        let ichar = count >> rcr::ICHAR_SHIFT;
        let result = if count & rcr::ERRORS != 0 {
            Err(errno::EIO)
        } else if size > rtu::MAX_FRAME {
            Err(errno::EOVERFLOW)
        } else if self.line.icdelay != 0 && ichar > self.line.icdelay {
            Err(errno::ENOMSG)
        } else if self.in_init {
            // Init replies are only checked, their data is not used.
            let c = &self.frame;
            let ok = n >= 5
                && self.rx[0] == c[0]
                && self.rx[1] & 0x7F == c[1]
                && rtu::crc_ok(&self.rx[..n]);
            if !ok {
                Err(errno::EBADE)
            } else if self.rx[1] & 0x80 != 0 {
                Err(errno::EBADMSG)
            } else {
                Ok(())
            }
        } else {
            let i = self.idx;
            let first = self.run[i].first_pin;
            let cmd = &self.file.commands[i];
            frame::parse(
                cmd,
                &self.rx[..n],
                &mut self.pins[first..first + cmd.pins.len()],
            )
        };
        match result {
            Ok(()) => {
                if !self.in_init {
                    self.run[self.idx].errors = 0;
                    self.commands[self.idx].errors = 0;
                }
                self.global.fault = false;
            }
            Err(code) => self.fail(code),
        }
        self.next();
        Ok(())
    }

    fn check_timeout(&mut self, port: &mut dyn Port) {
        if self.timeout_ns >= 0 {
            return;
        }
        let fl = if self.in_init {
            match &self.file.inits[self.idx] {
                Init::Packet { flags, .. } => *flags,
                _ => 0,
            }
        } else {
            self.file.commands[self.idx].flags
        };
        if fl & flags::TIMESOUT != 0 {
            self.next();
            return;
        }
        self.fail(errno::ETIMEDOUT);
        self.reset_port(port);
    }

    fn reset_port(&mut self, port: &mut dyn Port) {
        // A failed clear leaves the next exchange to find out.
        let _ = port.clear();
        self.timeout_ns = RESET_WAIT_NS;
        self.state = State::ResetWait;
    }

    /// Records an error of the current command.
    fn fail(&mut self, code: u32) {
        self.global.fault = true;
        self.global.fault_command = self.idx as u32;
        self.global.last_error_code = code;
        if self.in_init {
            return;
        }
        let i = self.idx;
        let r = &mut self.run[i];
        r.len = 0; // resend next time
        if self.file.commands[i].interval_us == u32::MAX {
            r.interval_ns = -1;
        }
        r.errors += 1;
        if r.errors >= MAX_ERRORS {
            r.disabled = true;
        }
        let p = &mut self.commands[i];
        p.errors = r.errors;
        p.error_code = code;
        p.disabled = r.disabled;
    }

    /// Moves to the next command (the init list runs into the loop).
    fn next(&mut self) {
        self.state = State::Start;
        if self.in_init {
            self.idx += 1;
            if self.idx >= self.file.inits.len() {
                self.in_init = false;
                self.inits_done = true;
                self.idx = 0;
            }
            return;
        }
        self.advance_loop();
    }

    /// Advances the loop index past disabled commands, taking each
    /// visited command's reset and disable edges; true when it wrapped.
    fn advance_loop(&mut self) -> bool {
        let n = self.run.len();
        loop {
            self.idx += 1;
            let i = self.idx % n;
            self.command_edges(i);
            if self.idx >= n {
                self.idx = 0;
                if self.global.suspend {
                    self.suspended = true;
                }
                return true;
            }
            if !self.run[self.idx].disabled {
                return false;
            }
        }
    }

    fn poll_command_edges(&mut self) {
        for i in 0..self.run.len() {
            self.command_edges(i);
        }
    }

    fn command_edges(&mut self, i: usize) {
        let (reset, disable) = (self.commands[i].reset, self.commands[i].disable);
        let r = &mut self.run[i];
        let p = &mut self.commands[i];
        if reset != r.prev_reset {
            r.prev_reset = reset;
            if reset {
                *r = Running {
                    disabled: false,
                    errors: 0,
                    ..r.clone()
                };
                *p = CommandPins {
                    disabled: false,
                    errors: 0,
                    error_code: 0,
                    ..*p
                };
                self.write_flush(i);
            }
        }
        let r = &mut self.run[i];
        let p = &mut self.commands[i];
        if disable != r.prev_disable {
            r.prev_disable = disable;
            if disable {
                r.disabled = true;
                r.errors = 0;
                *p = CommandPins {
                    disabled: true,
                    errors: 0,
                    error_code: errno::EAGAIN,
                    ..*p
                };
            }
        }
    }

    fn global_reset_edge(&mut self) {
        let reset = self.global.reset;
        if reset == self.prev_reset {
            return;
        }
        self.prev_reset = reset;
        if !reset {
            return;
        }
        for i in 0..self.run.len() {
            if self.run[i].disabled {
                self.run[i].disabled = false;
                self.commands[i].disabled = false;
                self.write_flush(i);
            }
            self.run[i].errors = 0;
            self.commands[i].errors = 0;
            self.commands[i].error_code = 0;
        }
    }

    /// With `writeflush`, takes a write command's current pin values as
    /// already sent, so only changes go out.
    fn write_flush(&mut self, i: usize) {
        let cmd = &self.file.commands[i];
        let is_write = matches!(
            cmd.func,
            rtu::W_COIL | rtu::W_REGISTER | rtu::W_COILS | rtu::W_REGISTERS
        );
        if !is_write || cmd.flags & flags::WFLUSH == 0 {
            return;
        }
        let first = self.run[i].first_pin;
        let pins = &self.pins[first..first + cmd.pins.len()];
        let mut buf = [0u8; rtu::MAX_FRAME];
        if let Ok(n) = frame::build(cmd, pins, &mut buf) {
            let r = &mut self.run[i];
            r.last = buf;
            r.len = n;
        }
    }

    fn write_flush_all(&mut self) {
        for i in 0..self.run.len() {
            self.write_flush(i);
        }
    }

    /// Whether the init list has run.
    pub fn inits_done(&self) -> bool {
        self.inits_done
    }
}
