//! An in-process Modbus RTU slave for a simulated PktUART's line: coils,
//! discrete inputs, holding and input registers, answering the eight
//! functions hm2_modbus uses (exception 1 for others, 2 for addresses past
//! its tables), silent on a bad CRC, on another device's address, on a
//! broadcast, and while `silent` is set or the line is not at its
//! settings.

use std::any::Any;

use super::pktuart::{LineSettings, RxFrame, SerialPeer};
use crate::modbus::rtu::{self, crc16};

/// The slave's tables and behaviour.
#[derive(Debug, Clone)]
pub struct ModbusSlave {
    /// Device address.
    pub id: u8,
    /// Coils (function 1, 5, 15).
    pub coils: Vec<bool>,
    /// Discrete inputs (function 2).
    pub inputs: Vec<bool>,
    /// Holding registers (3, 6, 16).
    pub holding: Vec<u16>,
    /// Input registers (4).
    pub input_regs: Vec<u16>,
    /// Answers nothing while set (a cable pulled).
    pub silent: bool,
    /// The line it listens at; frames at other settings go unheard.
    pub line: Option<LineSettings>,
    /// Corrupts the CRC of its answers while set.
    pub bad_crc: bool,
    /// Requests it has answered.
    pub answered: u64,
    /// Requests it took for itself (answered or not), in order.
    pub requests: Vec<Vec<u8>>,
    /// Time from the request's end to the answer.
    pub turnaround_ns: u64,
}

impl ModbusSlave {
    /// A slave at `id` with `n` of each object, all zero.
    pub fn new(id: u8, n: usize) -> ModbusSlave {
        ModbusSlave {
            id,
            coils: vec![false; n],
            inputs: vec![false; n],
            holding: vec![0; n],
            input_regs: vec![0; n],
            silent: false,
            line: None,
            bad_crc: false,
            answered: 0,
            requests: Vec::new(),
            turnaround_ns: 200_000,
        }
    }

    /// The answer PDU (address, function, data; no CRC) to `req`.
    fn answer(&mut self, req: &[u8]) -> Vec<u8> {
        let f = req[1];
        let word = |i: usize| {
            req.get(i..i + 2)
                .map(|b| u16::from_be_bytes([b[0], b[1]]) as usize)
        };
        let mut out = vec![self.id, f];
        let (Some(addr), Some(count)) = (word(2), word(4)) else {
            return vec![self.id, f | 0x80, 3];
        };
        let bits = |t: &[bool], out: &mut Vec<u8>| -> bool {
            if count == 0 || count > 2000 || addr + count > t.len() {
                return false;
            }
            out.push(count.div_ceil(8) as u8);
            for chunk in t[addr..addr + count].chunks(8) {
                out.push(
                    chunk
                        .iter()
                        .enumerate()
                        .fold(0, |a, (i, b)| a | u8::from(*b) << i),
                );
            }
            true
        };
        let regs = |t: &[u16], out: &mut Vec<u8>| -> bool {
            if count == 0 || count > 125 || addr + count > t.len() {
                return false;
            }
            out.push((count * 2) as u8);
            for v in &t[addr..addr + count] {
                out.extend_from_slice(&v.to_be_bytes());
            }
            true
        };
        let ok = match f {
            rtu::R_COILS => bits(&self.coils, &mut out),
            rtu::R_INPUTS => bits(&self.inputs, &mut out),
            rtu::R_REGISTERS => regs(&self.holding, &mut out),
            rtu::R_INPUTREGS => regs(&self.input_regs, &mut out),
            rtu::W_COIL if addr < self.coils.len() && (count == 0 || count == 0xFF00) => {
                self.coils[addr] = count == 0xFF00;
                out.extend_from_slice(&req[2..6]);
                true
            }
            rtu::W_REGISTER if addr < self.holding.len() => {
                self.holding[addr] = count as u16;
                out.extend_from_slice(&req[2..6]);
                true
            }
            rtu::W_COILS => self.write_coils(req, addr, count, &mut out),
            rtu::W_REGISTERS => self.write_regs(req, addr, count, &mut out),
            5 | 6 => false,
            _ => return vec![self.id, f | 0x80, 1],
        };
        if ok {
            out
        } else {
            vec![self.id, f | 0x80, 2]
        }
    }

    fn write_coils(&mut self, req: &[u8], addr: usize, count: usize, out: &mut Vec<u8>) -> bool {
        let data = req.get(7..).unwrap_or(&[]);
        if count == 0 || addr + count > self.coils.len() || data.len() < count.div_ceil(8) {
            return false;
        }
        for i in 0..count {
            self.coils[addr + i] = data[i / 8] >> (i % 8) & 1 != 0;
        }
        out.extend_from_slice(&req[2..6]);
        true
    }

    fn write_regs(&mut self, req: &[u8], addr: usize, count: usize, out: &mut Vec<u8>) -> bool {
        let data = req.get(7..).unwrap_or(&[]);
        if count == 0 || addr + count > self.holding.len() || data.len() < count * 2 {
            return false;
        }
        for i in 0..count {
            self.holding[addr + i] = u16::from_be_bytes([data[2 * i], data[2 * i + 1]]);
        }
        out.extend_from_slice(&req[2..6]);
        true
    }
}

impl SerialPeer for ModbusSlave {
    fn frame(&mut self, frame: &[u8], line: &LineSettings) -> Vec<RxFrame> {
        if self.line.is_some_and(|l| l != *line) || frame.len() < 4 || !rtu::crc_ok(frame) {
            return Vec::new();
        }
        let body = &frame[..frame.len() - 2];
        if body[0] != self.id && body[0] != 0 {
            return Vec::new();
        }
        self.requests.push(body.to_vec());
        if self.silent || body[0] == 0 {
            if body[0] == 0 {
                self.answer(body);
            }
            return Vec::new();
        }
        let mut out = self.answer(body);
        let crc = crc16(&out) ^ u16::from(self.bad_crc);
        out.extend_from_slice(&crc.to_le_bytes());
        self.answered += 1;
        vec![RxFrame {
            bytes: out,
            errors: 0,
            ichar_bits: 2,
            turnaround_ns: self.turnaround_ns,
        }]
    }

    fn as_any(&mut self) -> &mut dyn Any {
        self
    }
}
