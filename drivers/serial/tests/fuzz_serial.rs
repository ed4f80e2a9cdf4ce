//! The fuzz targets of `hal_serial::fuzzing`, 100 000 cases each, until
//! the workspace's `fuzz/` crate runs them: random bytes as replies on
//! the line, as requests to the simulated drive, and as command lines.

use hal_serial::crc;
use hal_serial::fuzzing;
use proptest::collection::vec;
use proptest::prelude::*;

const CASES: u32 = 100_000;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: CASES,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Either random bytes, or a frame from slave 1 with random contents and
/// (mostly) a right CRC, perhaps followed by more bytes: these get past
/// the CRC check into the reply decoding.
fn reply_bytes() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        vec(any::<u8>(), 0..300),
        (
            any::<u8>(),
            vec(any::<u8>(), 1..20),
            any::<bool>(),
            vec(any::<u8>(), 0..12)
        )
            .prop_map(|(sel, body, good_crc, tail)| {
                let mut f = vec![1];
                f.extend_from_slice(&body);
                crc::append(&mut f);
                if !good_crc {
                    let last = f.len() - 1;
                    f[last] ^= 0x5A;
                }
                let mut out = vec![sel];
                out.extend_from_slice(&f);
                out.extend_from_slice(&tail);
                out
            }),
    ]
}

/// Either random bytes, or requests to slave 1 with right CRCs.
fn request_bytes() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        vec(any::<u8>(), 0..200),
        vec(vec(any::<u8>(), 1..10), 1..6).prop_map(|frames| {
            let mut out = Vec::new();
            for body in frames {
                let mut f = vec![1];
                f.extend_from_slice(&body);
                crc::append(&mut f);
                out.extend_from_slice(&f);
            }
            out
        }),
    ]
}

/// Command-line words: the options the components know, values, and
/// noise bytes.
fn command_line() -> impl Strategy<Value = Vec<u8>> {
    const WORDS: &[&str] = &[
        "-r", "-p", "-t", "-x", "-F", "-f", "-S", "-n", "-d", "-b", "-s", "-gy", "--period",
        "--re", "--rate=5", "--target", "PD14=3", "PD300=1", "38400", "1", "0", "-3", "1e9", "nan",
        "odd", "E", "sim", "--", "",
    ];
    let word = prop_oneof![
        3 => (0..WORDS.len()).prop_map(|i| WORDS[i].as_bytes().to_vec()),
        1 => vec(any::<u8>(), 0..8),
    ];
    vec(word, 0..10).prop_map(|words| words.join(&0u8))
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn replies_on_the_line(bytes in reply_bytes()) {
        fuzzing::modbus_reply(&bytes);
    }

    #[test]
    fn requests_to_the_simulated_drive(bytes in request_bytes()) {
        fuzzing::slave_request(&bytes);
    }

    #[test]
    fn command_lines(bytes in command_line()) {
        fuzzing::command_line(&bytes);
    }
}
