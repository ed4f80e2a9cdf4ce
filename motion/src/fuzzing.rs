//! The bodies of the fuzz targets of `fuzz/` for the parsers of outside
//! bytes this crate has besides the compensation files
//! ([`crate::comp_file::fuzz_comp_file`]): each takes any bytes, never
//! panics on its own, and panics on a broken invariant (checked in the
//! body).

use crate::channel::{
    checksum, decode_command, decode_reply, decode_status, encode_command, encode_reply,
    CMD_VERSION, CMD_WORDS, REPLY_VERSION, REPLY_WORDS, STATUS_VERSION, STATUS_WORDS,
};
use crate::command::{parse, CLI_NAMES};
use crate::kins::Pose;

/// `motion-cmd` command lines, words separated by NUL bytes, the first
/// the command: a line that parses names a command whose command line,
/// if it has one, parses back to a command with the same record (NaNs
/// aside: the line does not keep their sign); the
/// words are also read as the arguments of a command chosen by the first
/// byte, so every form is reached.
pub fn command_line(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let words: Vec<String> = text.split('\0').map(String::from).collect();
    let Some((name, args)) = words.split_first() else {
        return;
    };
    let mut goal = Pose::ZERO;
    goal.0[2] = 1.5;
    let chosen = CLI_NAMES[usize::from(data.first().copied().unwrap_or(0)) % CLI_NAMES.len()];
    for (name, args) in [(name.as_str(), args), (chosen, &words[..])] {
        match parse(name, args, goal) {
            Ok(cmd) => {
                assert!(CLI_NAMES.contains(&cmd.name()), "{cmd:?}");
                if let Some(line) = cmd.to_cli() {
                    let again = parse(&line[0], &line[1..], goal)
                        .unwrap_or_else(|e| panic!("{line:?} of {cmd:?} does not parse: {e}"));
                    assert_eq!(
                        nan_blind(encode_command(1, &again)),
                        nan_blind(encode_command(1, &cmd)),
                        "{line:?}"
                    );
                }
            }
            Err(e) => assert!(!e.to_string().is_empty()),
        }
    }
}

/// A command record with every NaN argument made the same NaN and the
/// checksum left out: a command line writes a NaN as `NaN`, without its
/// sign or payload.
fn nan_blind(mut w: [u64; CMD_WORDS]) -> [u64; CMD_WORDS] {
    for word in &mut w[4..CMD_WORDS - 1] {
        if f64::from_bits(*word).is_nan() {
            *word = f64::NAN.to_bits();
        }
    }
    w[CMD_WORDS - 1] = 0;
    w
}

/// Little-endian words from `data`, zero-padded to `n`.
fn words(data: &[u8], n: usize) -> Vec<u64> {
    let mut w = vec![0u64; n];
    for (word, chunk) in w.iter_mut().zip(data.chunks(8)) {
        let mut b = [0u8; 8];
        b[..chunk.len()].copy_from_slice(chunk);
        *word = u64::from_le_bytes(b);
    }
    w
}

/// Command, answer and status records from the shared memory: as read,
/// and with the version word set and the checksum sealed (so decoding
/// gets past them; the first byte picks the opcode). A record that
/// decodes encodes to one that decodes to the same record again; a
/// status that decodes prints.
pub fn records(data: &[u8]) {
    let mut cmd = [0u64; CMD_WORDS];
    cmd.copy_from_slice(&words(data, CMD_WORDS));
    let _ = decode_command(&cmd);
    cmd[0] = CMD_VERSION;
    cmd[2] = u64::from(data.first().copied().unwrap_or(0) % 64);
    cmd[CMD_WORDS - 1] = checksum(&cmd[..CMD_WORDS - 1]);
    if let Ok((serial, c)) = decode_command(&cmd) {
        let once = encode_command(serial, &c);
        let again = decode_command(&once).map(|(s, c)| encode_command(s, &c));
        assert_eq!(again, Ok(once), "{c:?}");
    }

    let mut reply = [0u64; REPLY_WORDS];
    reply.copy_from_slice(&words(data, REPLY_WORDS));
    let _ = decode_reply(&reply);
    reply[0] = REPLY_VERSION;
    reply[2] %= 64;
    reply[REPLY_WORDS - 1] = checksum(&reply[..REPLY_WORDS - 1]);
    if let Ok((serial, result)) = decode_reply(&reply) {
        let once = encode_reply(serial, &result);
        let again = decode_reply(&once).map(|(s, r)| encode_reply(s, &r));
        assert_eq!(again, Ok(once), "{result:?}");
        if let Err(r) = result {
            assert!(!r.to_string().is_empty());
        }
    }

    let mut status = words(data, STATUS_WORDS);
    let _ = decode_status(&status);
    status[0] = STATUS_VERSION;
    status[1] %= 17;
    status[2] %= 4;
    if let Ok(s) = decode_status(&status) {
        assert!(!s.to_string().is_empty());
    }
}
