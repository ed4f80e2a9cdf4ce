//! Command and answer records: a [`Command`] as [`CMD_WORDS`] words and
//! back, an answer as [`REPLY_WORDS`] words and back, each validated word
//! by word. Which words a command's fields take comes from the command
//! table (`Command::write_args`, `Command::from_args`), a rejection's from the
//! refusal table (`Reject::to_wire`, `Reject::from_wire`).

use super::{checksum, ARGS, CMD_VERSION, CMD_WORDS, MAX_ARGS, REPLY_VERSION, REPLY_WORDS};
use crate::command::{Command, Reject, WireError};

/// The record of `cmd` with serial number `serial`.
pub fn encode_command(serial: u64, cmd: &Command) -> [u64; CMD_WORDS] {
    let mut args = [0.0; MAX_ARGS];
    let (op, slot, n) = cmd.write_args(&mut args);
    let mut w = [0u64; CMD_WORDS];
    w[0] = CMD_VERSION;
    w[1] = serial;
    w[2] = op;
    w[3] = slot.map_or(0, |j| i64::from(j) as u64);
    for (word, a) in w[ARGS..ARGS + n].iter_mut().zip(args) {
        *word = a.to_bits();
    }
    w[CMD_WORDS - 1] = checksum(&w[..CMD_WORDS - 1]);
    w
}

/// Validates and decodes a command record. The error carries the serial
/// word as read (to address the answer) and what was wrong.
pub fn decode_command(w: &[u64; CMD_WORDS]) -> Result<(u64, Command), (u64, WireError)> {
    let serial = w[1];
    let err = |e| Err((serial, e));
    if w[0] != CMD_VERSION {
        return err(WireError::BadVersion { found: w[0] });
    }
    if checksum(&w[..CMD_WORDS - 1]) != w[CMD_WORDS - 1] {
        return err(WireError::BadChecksum);
    }
    if serial == 0 {
        return err(WireError::ZeroSerial);
    }
    let jw = w[3] as i64;
    let joint = i32::try_from(jw).map_err(|_| (serial, WireError::BadJoint { value: w[3] }))?;
    let mut a = [0.0; MAX_ARGS];
    for (i, v) in a.iter_mut().enumerate() {
        *v = f64::from_bits(w[ARGS + i]);
    }
    let (cmd, takes_joint, n) = match Command::from_args(w[2], joint, &a) {
        Ok(Some(c)) => c,
        Ok(None) => return err(WireError::UnknownOpcode { opcode: w[2] }),
        Err(i) => return err(WireError::BadInteger { index: ARGS + i }),
    };
    if !takes_joint && w[3] != 0 {
        return err(WireError::BadJoint { value: w[3] });
    }
    if let Some(index) = (ARGS + n..CMD_WORDS - 1).find(|&i| w[i] != 0) {
        return err(WireError::UnusedWordSet { index });
    }
    Ok((serial, cmd))
}

/// The answer record for the command `serial`.
pub fn encode_reply(serial: u64, result: &Result<(), Reject>) -> [u64; REPLY_WORDS] {
    let mut w = [0u64; REPLY_WORDS];
    w[0] = REPLY_VERSION;
    w[1] = serial;
    if let Err(r) = result {
        let (code, n, f) = r.to_wire();
        w[2] = code;
        w[3] = n[0];
        w[4] = n[1];
        for i in 0..3 {
            w[5 + i] = f[i].to_bits();
        }
    }
    w[REPLY_WORDS - 1] = checksum(&w[..REPLY_WORDS - 1]);
    w
}

/// Validates and decodes an answer record: (serial, result).
pub fn decode_reply(w: &[u64; REPLY_WORDS]) -> Result<(u64, Result<(), Reject>), WireError> {
    if w[0] != REPLY_VERSION {
        return Err(WireError::BadVersion { found: w[0] });
    }
    if checksum(&w[..REPLY_WORDS - 1]) != w[REPLY_WORDS - 1] {
        return Err(WireError::BadChecksum);
    }
    if w[2] == 0 {
        if let Some(index) = (3..REPLY_WORDS - 1).find(|&i| w[i] != 0) {
            return Err(WireError::UnusedWordSet { index });
        }
        return Ok((w[1], Ok(())));
    }
    let f = [
        f64::from_bits(w[5]),
        f64::from_bits(w[6]),
        f64::from_bits(w[7]),
    ];
    let r =
        Reject::from_wire(w[2], [w[3], w[4]], f).ok_or(WireError::UnknownCode { code: w[2] })?;
    Ok((w[1], Err(r)))
}
