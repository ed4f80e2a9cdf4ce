//! The VFD simulator: a byte-stream slave that speaks either protocol
//! over a model of the drive and its spindle.
//!
//! * [`VfdModel`] (in `model`): the inverter's ramps and the spindle
//!   motor (the driver layer's `DcMotor` plant), protocol-free.
//! * [`VfdSim`]: the slave on the line. It assembles request frames from
//!   the bytes it receives (by the length the function implies, or by a
//!   silence of 3.5 characters), checks address and CRC (a bad CRC gets
//!   no answer, as on a real bus), answers through the GT register map
//!   ([`gt_slave`]) or the HY protocol ([`hy_slave`]), and misbehaves on
//!   request ([`Faults`]): silence, bad CRCs, wrong function codes,
//!   truncated replies, exceptions, late replies, a dead or unplugged
//!   line. It logs every request frame, so tests check the master's
//!   bytes exactly.
//! * Two ways onto a line: [`crate::line::SimLine`] (in-process,
//!   simulated time) and [`PtyVfd`] (a pseudo-terminal pair served by a
//!   thread in wall time; the master opens the other end as a real tty).

pub mod gt_slave;
pub mod hy_slave;
mod model;
mod pty;

use std::time::Duration;

pub use model::{RunCommand, VfdModel, VfdParams};
pub use pty::PtyVfd;

use crate::crc;
use crate::line::LineSettings;
use crate::regs::modbus as mb;
use gt_slave::GtRegisters;
use hy_slave::HyParameters;

/// The protocol a simulated drive speaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Protocol {
    /// Standard Modbus RTU with the GT series' register map.
    ModbusGt,
    /// The HY series' own function codes (LinuxCNC's `hy_vfd`).
    Hy,
}

/// Misbehaviour to inject. Counters apply to the next N requests that
/// reach this slave.
#[derive(Debug, Clone, Default)]
pub struct Faults {
    /// Requests to leave unanswered.
    pub silent: u32,
    /// Replies to send with a wrong CRC.
    pub bad_crc: u32,
    /// Replies to send with a wrong function code.
    pub wrong_function: u32,
    /// Replies to cut short (the last three bytes never come).
    pub truncate: u32,
    /// Requests to refuse with this exception code: (code, count).
    pub exception: Option<(u8, u32)>,
    /// Extra delay before every reply.
    pub reply_delay: Duration,
    /// Stop answering anything (a cut cable) until cleared.
    pub dead: bool,
}

/// A reply on its way: its bytes start after `delay`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimReply {
    /// The whole frame.
    pub bytes: Vec<u8>,
    /// Time from the end of the request to the first byte.
    pub delay: Duration,
}

/// How many request frames the log keeps.
const LOG_CAP: usize = 4096;

/// A simulated VFD on a serial line.
#[derive(Debug)]
pub struct VfdSim {
    protocol: Protocol,
    slave: u8,
    settings: LineSettings,
    model: VfdModel,
    gt: GtRegisters,
    hy: HyParameters,
    /// Injected misbehaviour.
    pub faults: Faults,
    unplugged: bool,
    rx: Vec<u8>,
    last_byte_ns: u64,
    now_ns: u64,
    requests: Vec<Vec<u8>>,
    crc_errors: u64,
}

impl VfdSim {
    /// A stopped drive with the default spindle ([`VfdParams::default`])
    /// at address `slave` on a line with `settings`.
    pub fn new(protocol: Protocol, slave: u8, settings: LineSettings) -> VfdSim {
        let params = VfdParams::default();
        VfdSim {
            protocol,
            slave,
            settings,
            model: VfdModel::new(params),
            gt: GtRegisters::default(),
            hy: HyParameters::for_model(&params),
            faults: Faults::default(),
            unplugged: false,
            rx: Vec::new(),
            last_byte_ns: 0,
            now_ns: 0,
            requests: Vec::new(),
            crc_errors: 0,
        }
    }

    /// The protocol.
    pub fn protocol(&self) -> Protocol {
        self.protocol
    }

    /// The line settings it was made for.
    pub fn settings(&self) -> &LineSettings {
        &self.settings
    }

    /// The drive and motor.
    pub fn model(&self) -> &VfdModel {
        &self.model
    }

    /// The drive and motor, to change (trip a fault, change constants).
    pub fn model_mut(&mut self) -> &mut VfdModel {
        &mut self.model
    }

    /// The GT registers of the drive's own.
    pub fn gt_registers(&self) -> &GtRegisters {
        &self.gt
    }

    /// The HY function parameters.
    pub fn hy_parameters(&self) -> &HyParameters {
        &self.hy
    }

    /// Sets an HY function parameter as if from the keypad.
    pub fn set_hy_parameter(&mut self, n: u8, value: u16) {
        self.hy.pd[usize::from(n)] = value;
        let params = self.hy.model_params(self.model.params());
        self.model.set_params(params);
    }

    /// Unplugs (true) or plugs back (false) the line: an unplugged line
    /// fails every read and write and cannot be opened.
    pub fn set_unplugged(&mut self, unplugged: bool) {
        self.unplugged = unplugged;
        self.rx.clear();
    }

    /// Whether the line is unplugged.
    pub fn unplugged(&self) -> bool {
        self.unplugged
    }

    /// Every request frame received so far (whole frames, CRC included).
    pub fn requests(&self) -> &[Vec<u8>] {
        &self.requests
    }

    /// Forgets the logged requests.
    pub fn clear_requests(&mut self) {
        self.requests.clear();
    }

    /// Frames dropped for a bad CRC.
    pub fn crc_errors(&self) -> u64 {
        self.crc_errors
    }

    /// The model's time.
    pub fn now_ns(&self) -> u64 {
        self.now_ns
    }

    /// Lets the model run up to `now_ns`.
    pub fn advance_to(&mut self, now_ns: u64) {
        if now_ns > self.now_ns {
            self.model.advance(now_ns - self.now_ns);
            self.now_ns = now_ns;
        }
    }

    fn frame_gap_ns(&self) -> u64 {
        self.settings.silence(3.5).as_nanos() as u64
    }

    /// Bytes arriving at `now_ns`. After a silence of 3.5 characters
    /// they start a new frame.
    pub fn feed(&mut self, bytes: &[u8], now_ns: u64) {
        if bytes.is_empty() {
            return;
        }
        if !self.rx.is_empty() && now_ns.saturating_sub(self.last_byte_ns) >= self.frame_gap_ns() {
            self.rx.clear();
        }
        self.rx.extend_from_slice(bytes);
        self.last_byte_ns = now_ns;
        if self.rx.len() > mb::MAX_FRAME {
            let cut = self.rx.len() - mb::MAX_FRAME;
            self.rx.drain(..cut);
        }
    }

    /// The length of the request at the start of the receive buffer, if
    /// its function says it.
    fn request_len(&self) -> Option<usize> {
        let b = &self.rx;
        match self.protocol {
            Protocol::Hy => b.get(2).map(|&len| usize::from(len) + 5),
            Protocol::ModbusGt => match *b.get(1)? {
                0x01..=0x06 => Some(8),
                0x0F | 0x10 => b.get(6).map(|&n| usize::from(n) + 9),
                _ => None,
            },
        }
    }

    /// Takes the next complete request (by its length, or everything
    /// after a silence) at `now_ns` and answers it.
    pub fn poll(&mut self, now_ns: u64) -> Option<SimReply> {
        self.advance_to(now_ns);
        loop {
            let by_len = self.request_len().filter(|&n| self.rx.len() >= n);
            let silent = !self.rx.is_empty()
                && now_ns.saturating_sub(self.last_byte_ns) >= self.frame_gap_ns();
            let n = match (by_len, silent) {
                (Some(n), _) => n,
                (None, true) => self.rx.len(),
                (None, false) => return None,
            };
            let frame: Vec<u8> = self.rx.drain(..n).collect();
            if let Some(reply) = self.process(frame) {
                return Some(reply);
            }
            if self.rx.is_empty() {
                return None;
            }
        }
    }

    /// Checks one frame and builds the answer, if any.
    fn process(&mut self, frame: Vec<u8>) -> Option<SimReply> {
        if frame.len() < 4 || !crc::is_valid(&frame) {
            self.crc_errors += 1;
            return None;
        }
        let address = frame[0];
        if address != self.slave && address != mb::BROADCAST {
            return None;
        }
        if self.requests.len() < LOG_CAP {
            self.requests.push(frame.clone());
        }
        if self.faults.dead || self.unplugged {
            return None;
        }
        if self.faults.silent > 0 {
            self.faults.silent -= 1;
            return None;
        }
        let request = &frame[1..frame.len() - 2];
        let function = request[0];
        let injected = match &mut self.faults.exception {
            Some((code, count)) if *count > 0 => {
                *count -= 1;
                Some(*code)
            }
            _ => None,
        };
        let answer = match injected {
            Some(code) => Err(code),
            None => match self.protocol {
                Protocol::ModbusGt => gt_slave::handle(&mut self.gt, &mut self.model, request),
                Protocol::Hy => hy_slave::handle(&mut self.hy, &mut self.model, request),
            },
        };
        if address == mb::BROADCAST {
            return None;
        }
        let mut reply = vec![self.slave];
        match answer {
            Ok(pdu) => reply.extend_from_slice(&pdu),
            Err(code) => reply.extend_from_slice(&[function | mb::EXCEPTION_FLAG, code]),
        }
        if self.faults.wrong_function > 0 {
            self.faults.wrong_function -= 1;
            reply[1] ^= 0x40;
        }
        crc::append(&mut reply);
        if self.faults.bad_crc > 0 {
            self.faults.bad_crc -= 1;
            let last = reply.len() - 1;
            reply[last] ^= 0xFF;
        }
        if self.faults.truncate > 0 {
            self.faults.truncate -= 1;
            reply.truncate(reply.len().saturating_sub(3));
        }
        Some(SimReply {
            bytes: reply,
            delay: self.settings.silence(3.5) + self.faults.reply_delay,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::line::Parity;

    fn frame(body: &[u8]) -> Vec<u8> {
        let mut f = body.to_vec();
        crc::append(&mut f);
        f
    }

    #[test]
    fn answers_whole_frames_and_drops_bad_ones() {
        let mut s = VfdSim::new(
            Protocol::ModbusGt,
            1,
            LineSettings::new(38_400, Parity::None),
        );
        let req = frame(&[1, 0x06, 0x20, 0x00, 0x13, 0x88]);
        s.feed(&req[..3], 0);
        assert_eq!(s.poll(0), None, "incomplete");
        s.feed(&req[3..], 100_000);
        let r = s.poll(100_000).expect("a reply");
        assert_eq!(r.bytes, req, "write single register echoes");
        assert_eq!(s.gt_registers().frequency, 5000);
        let mut bad = req.clone();
        bad[7] ^= 1;
        s.feed(&bad, 10_000_000);
        assert_eq!(s.poll(10_000_000), None);
        assert_eq!(s.crc_errors(), 1);
        // Another slave's request gets no answer but is not an error.
        s.feed(&frame(&[2, 0x06, 0x20, 0x00, 0, 0]), 20_000_000);
        assert_eq!(s.poll(20_000_000), None);
        assert_eq!(s.crc_errors(), 1);
        assert_eq!(s.requests().len(), 1);
    }

    #[test]
    fn unknown_functions_end_by_silence_and_get_an_exception() {
        let mut s = VfdSim::new(
            Protocol::ModbusGt,
            1,
            LineSettings::new(19_200, Parity::Even),
        );
        let req = frame(&[1, 0x2B, 0x0E, 0x01, 0x00]);
        s.feed(&req, 0);
        assert_eq!(s.poll(0), None, "length unknown until the line is silent");
        let r = s.poll(5_000_000).unwrap();
        assert_eq!(r.bytes, frame(&[1, 0xAB, 0x01]));
    }

    #[test]
    fn hy_requests_are_framed_by_their_length_byte() {
        let mut s = VfdSim::new(Protocol::Hy, 1, LineSettings::new(19_200, Parity::Even));
        s.feed(&frame(&[1, 0x01, 0x03, 5, 0, 0]), 0);
        let r = s.poll(0).unwrap();
        // PD005 = 400.00 Hz.
        assert_eq!(r.bytes, frame(&[1, 0x01, 0x03, 5, 0x9C, 0x40]));
    }
}
