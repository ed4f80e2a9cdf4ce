//! A command's request built from its pins, and its reply parsed onto
//! them. Replies are checked for length, device, function, CRC and
//! exception before a pin changes; the errors are the errno values the
//! `error-code` pins show.

use super::mbccb::Command;
use super::pins::DataPin;
use super::rtu::{self, crc_ok};
use super::values::{self, Value};

/// errno values of the pins.
pub mod errno {
    /// Line error (overrun, start bit, parity).
    pub const EIO: u32 = 5;
    /// Unsupported function in the reply.
    pub const EBADF: u32 = 9;
    /// Disabled by hand.
    pub const EAGAIN: u32 = 11;
    /// Internal inconsistency.
    pub const EINVAL: u32 = 22;
    /// Reply bigger than the buffer.
    pub const EFBIG: u32 = 27;
    /// Reply too short or with a wrong length.
    pub const ERANGE: u32 = 34;
    /// Inter-character gap too long.
    pub const ENOMSG: u32 = 42;
    /// Reply to another function.
    pub const ECHRNG: u32 = 44;
    /// Bad CRC.
    pub const EBADE: u32 = 52;
    /// Every command disabled.
    pub const ENODATA: u32 = 61;
    /// Exception reply.
    pub const EBADMSG: u32 = 74;
    /// Reply over 256 bytes.
    pub const EOVERFLOW: u32 = 75;
    /// Request does not fit 253 bytes.
    pub const EMSGSIZE: u32 = 90;
    /// No reply in time.
    pub const ETIMEDOUT: u32 = 110;
}

/// Builds `cmd`'s request (without CRC) into `out` from `pins` (the
/// command's own); returns its length.
pub fn build(
    cmd: &Command,
    pins: &[DataPin],
    out: &mut [u8; rtu::MAX_FRAME],
) -> Result<usize, u32> {
    out[0] = cmd.mbid;
    out[1] = cmd.func;
    out[2..4].copy_from_slice(&cmd.addr.to_be_bytes());
    let bit = |p: &DataPin| matches!(p.value, Value::Bit(true));
    let n = pins.len();
    let len = match cmd.func {
        rtu::R_COILS | rtu::R_INPUTS => {
            out[4..6].copy_from_slice(&(n as u16).to_be_bytes());
            6
        }
        rtu::R_REGISTERS | rtu::R_INPUTREGS => {
            out[4..6].copy_from_slice(&cmd.regcnt.to_be_bytes());
            6
        }
        rtu::W_COIL => {
            let v: u16 = if pins.first().is_some_and(bit) {
                0xFF00
            } else {
                0
            };
            out[4..6].copy_from_slice(&v.to_be_bytes());
            6
        }
        rtu::W_REGISTER => {
            let p = pins.first().ok_or(errno::EINVAL)?;
            put_value(p, &mut out[4..6]);
            6
        }
        rtu::W_COILS => {
            let bytes = n.div_ceil(8);
            if 7 + bytes > rtu::MAX_FRAME - 2 {
                return Err(errno::EMSGSIZE);
            }
            out[4..6].copy_from_slice(&(n as u16).to_be_bytes());
            out[6] = bytes as u8;
            out[7..7 + bytes].fill(0);
            for (i, p) in pins.iter().enumerate() {
                out[7 + i / 8] |= u8::from(bit(p)) << (i % 8);
            }
            7 + bytes
        }
        rtu::W_REGISTERS => {
            let bytes = 2 * cmd.regcnt as usize;
            if 7 + bytes > rtu::MAX_FRAME - 2 {
                return Err(errno::EMSGSIZE);
            }
            out[4..6].copy_from_slice(&cmd.regcnt.to_be_bytes());
            out[6] = bytes as u8;
            out[7..7 + bytes].fill(0);
            for p in pins {
                let at = 7 + 2 * p.spec.regofs as usize;
                let end = at + 2 * p.spec.mtype.regs() as usize;
                put_value(p, out.get_mut(at..end).ok_or(errno::EINVAL)?);
            }
            7 + bytes
        }
        _ => return Err(errno::EINVAL),
    };
    Ok(len)
}

fn put_value(p: &DataPin, out: &mut [u8]) {
    let (offset, scale) = p.scaling();
    let send = values::from_pin(&p.spec, p.value, offset, scale);
    let clamp = p.spec.flags & super::mbccb::pinf::CLAMP != 0;
    values::encode(p.spec.mtype, send, clamp, out);
}

/// Checks a reply to `cmd` and moves its data onto `pins`. The error is
/// the errno to show.
pub fn parse(cmd: &Command, reply: &[u8], pins: &mut [DataPin]) -> Result<(), u32> {
    if reply.len() < 5 {
        return Err(errno::ERANGE);
    }
    if reply[0] != cmd.mbid {
        return Err(errno::ERANGE);
    }
    if reply[1] & 0x7F != cmd.func {
        return Err(errno::ECHRNG);
    }
    if !crc_ok(reply) {
        return Err(errno::EBADE);
    }
    if reply[1] & 0x80 != 0 {
        return Err(errno::EBADMSG);
    }
    let body = &reply[..reply.len() - 2];
    match cmd.func {
        rtu::R_COILS | rtu::R_INPUTS => {
            let bytes = pins.len().div_ceil(8);
            if body[2] as usize != bytes || body.len() != 3 + bytes {
                return Err(errno::ERANGE);
            }
            for (i, p) in pins.iter_mut().enumerate() {
                p.value = Value::Bit(body[3 + i / 8] >> (i % 8) & 1 != 0);
            }
        }
        rtu::R_REGISTERS | rtu::R_INPUTREGS => {
            let bytes = 2 * cmd.regcnt as usize;
            if body[2] as usize != bytes || body.len() != 3 + bytes {
                return Err(errno::ERANGE);
            }
            for p in pins.iter_mut() {
                let at = 3 + 2 * p.spec.regofs as usize;
                let raw = values::decode(p.spec.mtype, body.get(at..).ok_or(errno::EINVAL)?);
                let (offset, scale) = p.scaling();
                let (v, scaled) = values::to_pin(&p.spec, raw, offset, scale);
                p.value = v;
                if p.scaled.is_some() {
                    p.scaled = scaled;
                }
            }
        }
        rtu::W_COIL | rtu::W_REGISTER | rtu::W_COILS | rtu::W_REGISTERS => {
            if body.len() != 6 || body[2..4] != cmd.addr.to_be_bytes() {
                return Err(errno::ERANGE);
            }
        }
        _ => return Err(errno::EBADF),
    }
    Ok(())
}
