//! RTU frames: building a request, knowing when a reply is complete, and
//! checking it (CRC, address, function, exception). Pure functions over
//! bytes, shared by the master and the fuzz targets.

use crate::crc;
use crate::error::{ExceptionCode, Result, SerialError};
use crate::regs::modbus::{EXCEPTION_FLAG, MAX_FRAME};

/// How a reply's length is known.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReplyLength {
    /// Always this many bytes, address and CRC included (write echoes).
    Fixed(usize),
    /// The third byte counts the data bytes that follow it: address,
    /// function, count, data, CRC (Modbus reads; every HY reply).
    CountAt2,
}

/// Length of an exception reply: address, function | 0x80, code, CRC.
pub const EXCEPTION_LEN: usize = 5;

/// A request frame: address, function, data, CRC (low byte first).
pub fn request(slave: u8, function: u8, data: &[u8]) -> Vec<u8> {
    let mut f = Vec::with_capacity(data.len() + 4);
    f.push(slave);
    f.push(function);
    f.extend_from_slice(data);
    crc::append(&mut f);
    f
}

/// The whole reply's length once `received` (its first bytes) tells it;
/// None while more bytes are needed to know. An exception reply is
/// recognised by its function byte.
pub fn reply_len(rule: ReplyLength, received: &[u8]) -> Option<usize> {
    if received.get(1).is_some_and(|f| f & EXCEPTION_FLAG != 0) {
        return Some(EXCEPTION_LEN);
    }
    match rule {
        ReplyLength::Fixed(n) => Some(n),
        ReplyLength::CountAt2 => received.get(2).map(|&n| usize::from(n) + 5),
    }
}

/// How many bytes to ask the line for next, with `received` in hand: up
/// to the end of the reply when its length is known, else up to the
/// byte that tells it. Never more than a frame can hold.
pub fn next_read_len(rule: ReplyLength, received: &[u8]) -> usize {
    let want = match (reply_len(rule, received), rule) {
        (Some(n), _) => n,
        (None, ReplyLength::Fixed(n)) => n,
        (None, ReplyLength::CountAt2) => 3,
    };
    want.min(MAX_FRAME).saturating_sub(received.len())
}

/// Checks a complete reply to `function` from `slave`; returns the bytes
/// between the function code and the CRC.
pub fn check_reply(slave: u8, function: u8, frame: &[u8]) -> Result<&[u8]> {
    let Some((carried, computed)) = crc::carried_and_computed(frame) else {
        return Err(SerialError::Truncated {
            slave,
            function,
            got: frame.len(),
            expected: EXCEPTION_LEN,
        });
    };
    if carried != computed {
        return Err(SerialError::Crc {
            slave,
            carried,
            computed,
        });
    }
    if frame.len() < 4 {
        return Err(SerialError::Truncated {
            slave,
            function,
            got: frame.len(),
            expected: EXCEPTION_LEN,
        });
    }
    if frame[0] != slave {
        return Err(SerialError::WrongSlave {
            expected: slave,
            found: frame[0],
        });
    }
    let body = &frame[2..frame.len() - 2];
    if frame[1] == function | EXCEPTION_FLAG {
        return match body {
            [code] => Err(SerialError::Exception {
                slave,
                function,
                code: ExceptionCode(*code),
            }),
            _ => Err(SerialError::BadReply {
                slave,
                function,
                what: format!("exception reply with {} code bytes", body.len()),
            }),
        };
    }
    if frame[1] != function {
        return Err(SerialError::WrongFunction {
            slave,
            expected: function,
            found: frame[1],
        });
    }
    Ok(body)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_known_from_the_first_bytes() {
        let rule = ReplyLength::CountAt2;
        assert_eq!(reply_len(rule, &[1, 3]), None);
        assert_eq!(reply_len(rule, &[1, 3, 4]), Some(9));
        assert_eq!(reply_len(rule, &[1, 0x83]), Some(5));
        assert_eq!(reply_len(ReplyLength::Fixed(8), &[]), Some(8));
        assert_eq!(next_read_len(rule, &[]), 3);
        assert_eq!(next_read_len(rule, &[1, 3, 250]), 252);
        assert_eq!(next_read_len(rule, &[1, 3, 255]), 253, "capped at a frame");
    }

    #[test]
    fn replies_are_checked_in_order() {
        let ok = request(1, 3, &[2, 0x12, 0x34]);
        assert_eq!(check_reply(1, 3, &ok).unwrap(), &[2, 0x12, 0x34]);
        assert!(matches!(
            check_reply(2, 3, &ok),
            Err(SerialError::WrongSlave {
                expected: 2,
                found: 1
            })
        ));
        assert!(matches!(
            check_reply(1, 4, &ok),
            Err(SerialError::WrongFunction { found: 3, .. })
        ));
        let exc = request(1, 0x83, &[2]);
        assert_eq!(exc, [0x01, 0x83, 0x02, 0xC0, 0xF1]);
        assert!(matches!(
            check_reply(1, 3, &exc),
            Err(SerialError::Exception {
                code: ExceptionCode(2),
                ..
            })
        ));
        let mut bad = ok.clone();
        bad[2] ^= 1;
        assert!(matches!(
            check_reply(1, 3, &bad),
            Err(SerialError::Crc { .. })
        ));
        assert!(matches!(
            check_reply(1, 3, &[1]),
            Err(SerialError::Truncated { .. })
        ));
    }
}
