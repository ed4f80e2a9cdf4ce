//! The fuzz targets of `hal_serial::fuzzing`, 100 000 cases each, until
//! the workspace's `fuzz/` crate runs them: random bytes as replies on
//! the line, as requests to the simulated drive, as command lines, as
//! mb2hal INI files and as Modbus TCP replies.

#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

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

/// mb2hal INI text: its sections and keys with values, and noise.
fn mb2hal_ini() -> impl Strategy<Value = Vec<u8>> {
    const WORDS: &[&str] = &[
        "[MB2HAL_INIT]\n",
        "[TRANSACTION_00]\n",
        "[TRANSACTION_01]\n",
        "TOTAL_TRANSACTIONS=",
        "VERSION=",
        "HAL_MODULE_NAME=",
        "INIT_DEBUG=",
        "SLOWDOWN=",
        "LINK_TYPE=",
        "TCP_IP=",
        "TCP_PORT=",
        "SERIAL_PORT=",
        "SERIAL_BAUD=",
        "SERIAL_PARITY=",
        "MB_SLAVE_ID=",
        "FIRST_ELEMENT=",
        "NELEMENTS=",
        "PIN_NAMES=",
        "MB_TX_CODE=",
        "HAL_TX_NAME=",
        "MAX_UPDATE_RATE=",
        "DEBUG=",
        "tcp",
        "serial",
        "1.1",
        "1",
        "2",
        "0",
        "65535",
        "126",
        "2000",
        "-1",
        "nan",
        "a,b",
        "a,,a",
        "fnct_01_read_coils",
        "fnct_05_write_single_coil",
        "fnct_16_write_multiple_registers",
        "/dev/x",
        "127.0.0.1",
        "\n",
        "\n",
    ];
    let word = prop_oneof![
        6 => (0..WORDS.len()).prop_map(|i| WORDS[i].as_bytes().to_vec()),
        1 => vec(any::<u8>(), 0..6),
    ];
    prop_oneof![
        vec(word, 0..60).prop_map(|words| words.concat()),
        // A file that works, with a few bytes changed: most of these get
        // through the INI reader into mb2hal's checks.
        vec((any::<usize>(), any::<u8>()), 0..4).prop_map(|edits| {
            let mut f = VALID_INI.as_bytes().to_vec();
            for (at, b) in edits {
                let i = at % f.len();
                f[i] = b;
            }
            f
        }),
    ]
}

/// An mb2hal file with two links and every kind of transaction.
const VALID_INI: &str = "[MB2HAL_INIT]\nVERSION=1.1\nTOTAL_TRANSACTIONS=3\n\
[TRANSACTION_00]\nLINK_TYPE=tcp\nTCP_IP=127.0.0.1\nTCP_PORT=5020\nMB_SLAVE_ID=1\n\
FIRST_ELEMENT=0\nNELEMENTS=3\nMB_TX_CODE=fnct_03_read_holding_registers\n\
[TRANSACTION_01]\nFIRST_ELEMENT=2\nPIN_NAMES=a,b\nMB_TX_CODE=fnct_02_read_discrete_inputs\n\
[TRANSACTION_02]\nLINK_TYPE=serial\nSERIAL_PORT=/dev/x\nSERIAL_BAUD=9600\nMB_SLAVE_ID=2\n\
FIRST_ELEMENT=9\nNELEMENTS=1\nMB_TX_CODE=fnct_06_write_single_register\n";

/// Modbus TCP replies: random bytes, or a header for transaction 1 from
/// unit 1 with a random PDU (its length mostly right).
fn tcp_reply() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        vec(any::<u8>(), 0..300),
        (any::<u8>(), vec(any::<u8>(), 0..40), any::<bool>()).prop_map(|(sel, pdu, right)| {
            let len = if right {
                pdu.len() as u16 + 1
            } else {
                pdu.len() as u16 ^ 3
            };
            let mut out = vec![sel, 0, 1, 0, 0];
            out.extend_from_slice(&len.to_be_bytes());
            out.push(1);
            out.extend_from_slice(&pdu);
            out
        }),
    ]
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

    #[test]
    fn mb2hal_ini_files(bytes in mb2hal_ini()) {
        fuzzing::mb2hal_ini(&bytes);
    }

    #[test]
    fn modbus_tcp_replies(bytes in tcp_reply()) {
        fuzzing::modbus_tcp_reply(&bytes);
    }
}

#[test]
fn the_seed_ini_file_is_accepted() {
    let mut read = |_: &std::path::Path| Ok(VALID_INI.to_string());
    let ini = hal_lang::ini::Ini::parse_with(std::path::Path::new("seed.ini"), &mut read).unwrap();
    let c = hal_serial::mb2hal::config::Config::from_ini(&ini).unwrap();
    assert_eq!(c.transactions.len(), 3);
    assert_eq!(c.links().len(), 2);
}
