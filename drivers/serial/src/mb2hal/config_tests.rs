//! The INI file as mb2hal reads it: LinuxCNC's sample of the peer run
//! (inheritance, defaults, pin names), and every refusal with its words.

use std::path::Path;

use super::super::reader::{parse_version, tx_number};
use super::*;

/// Parses `text` as the file `mb.ini`.
fn parse(text: &str) -> Result<Config> {
    let mut read = |_: &Path| Ok(text.to_string());
    let ini = Ini::parse_with(Path::new("mb.ini"), &mut read)?;
    Config::from_ini(&ini)
}

/// The refusal of `text`, as printed.
fn refusal(text: &str) -> String {
    match parse(text) {
        Ok(c) => panic!("accepted: {c:?}"),
        Err(e) => e.to_string(),
    }
}

/// The INI of LinuxCNC's run against pymodbus (the peer's mb.ini).
const PEER: &str = "\
[MB2HAL_INIT]
INIT_DEBUG=3
VERSION=1.1
HAL_MODULE_NAME=mb2hal
SLOWDOWN=0.0
TOTAL_TRANSACTIONS=6

[TRANSACTION_00]
LINK_TYPE=tcp
TCP_IP=127.0.0.1
TCP_PORT=5020
MB_SLAVE_ID=1
FIRST_ELEMENT=0
NELEMENTS=3
MB_TX_CODE=fnct_03_read_holding_registers
MB_RESPONSE_TIMEOUT_MS=500
MB_BYTE_TIMEOUT_MS=500
HAL_TX_NAME=holding
MAX_UPDATE_RATE=0.0
DEBUG=1

[TRANSACTION_01]
MB_TX_CODE=fnct_02_read_discrete_inputs
FIRST_ELEMENT=2
PIN_NAMES=a,b
HAL_TX_NAME=inputs

[TRANSACTION_02]
MB_TX_CODE=fnct_06_write_single_register
FIRST_ELEMENT=5
NELEMENTS=1

[TRANSACTION_03]
MB_TX_CODE=fnct_15_write_multiple_coils
FIRST_ELEMENT=0
NELEMENTS=2

[TRANSACTION_04]
MB_TX_CODE=fnct_01_read_coils
FIRST_ELEMENT=0
NELEMENTS=2

[TRANSACTION_05]
MB_TX_CODE=fnct_04_read_input_registers
FIRST_ELEMENT=1
NELEMENTS=2
";

/// A file with `init` in [MB2HAL_INIT] (after TOTAL_TRANSACTIONS=1) and
/// `tx` as [TRANSACTION_00].
fn one(init: &str, tx: &str) -> String {
    format!("[MB2HAL_INIT]\nTOTAL_TRANSACTIONS=1\n{init}\n[TRANSACTION_00]\n{tx}\n")
}

const TCP: &str = "LINK_TYPE=tcp\nTCP_IP=127.0.0.1\nFIRST_ELEMENT=0\n";

#[test]
fn the_peer_file_reads_as_linuxcnc_read_it() {
    let c = parse(PEER).unwrap();
    assert_eq!(c.init_debug, 3);
    assert_eq!(c.version, 1001);
    assert_eq!(c.module_name, "mb2hal");
    assert_eq!(c.slowdown, Duration::ZERO);
    let names: Vec<_> = c.transactions.iter().map(|t| t.hal_name.as_str()).collect();
    assert_eq!(names, ["holding", "inputs", "02", "03", "04", "05"]);
    let tcp = LinkConfig::Tcp {
        ip: "127.0.0.1".into(),
        port: 5020,
    };
    for t in &c.transactions {
        // Every later transaction inherits the first one's link keys.
        assert_eq!(t.link, tcp, "{}", t.section);
        assert_eq!(t.slave, 1);
        assert_eq!(t.response_timeout, Duration::from_millis(500));
        assert_eq!(t.byte_timeout, Duration::from_millis(500));
        assert_eq!(t.debug, 1);
        assert_eq!(t.max_update_rate, 0.0);
    }
    let t = &c.transactions;
    assert_eq!(t[0].elements, ["00", "01", "02"]);
    assert_eq!(t[1].elements, ["a", "b"]);
    assert_eq!(
        (t[1].code, t[1].first, t[1].count()),
        (TxCode::ReadDiscreteInputs, 2, 2)
    );
    assert_eq!(t[2].code, TxCode::WriteSingleRegister);
    assert_eq!(t[5].code.function(), 0x04);
    assert_eq!(c.links(), vec![(tcp, vec![0, 1, 2, 3, 4, 5])]);
    assert!(c.warnings.is_empty(), "{:?}", c.warnings);
}

#[test]
fn defaults_are_linuxcncs() {
    let c = parse(&one(
        "",
        &format!("{TCP}NELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils"),
    ))
    .unwrap();
    assert_eq!((c.init_debug, c.version), (1, 1000));
    assert_eq!(c.module_name, "mb2hal");
    let t = &c.transactions[0];
    assert_eq!(
        t.link,
        LinkConfig::Tcp {
            ip: "127.0.0.1".into(),
            port: 502
        }
    );
    assert_eq!(t.slave, DEFAULT_TCP_UNIT);
    assert_eq!(t.response_timeout, Duration::from_millis(500));
    assert_eq!((t.debug, t.hal_name.as_str()), (1, "00"));
    assert_eq!(t.period(), Duration::ZERO);
}

#[test]
fn serial_links_inherit_and_share_one_device() {
    let text = "\
[MB2HAL_INIT]
TOTAL_TRANSACTIONS=3
[TRANSACTION_00]
LINK_TYPE=serial
SERIAL_PORT=/dev/ttyUSB0
SERIAL_BAUD=19200
SERIAL_PARITY=even
SERIAL_STOP=2
SERIAL_DELAY_MS=10
MB_SLAVE_ID=3
FIRST_ELEMENT=0
NELEMENTS=2
MB_TX_CODE=fnct_03_read_holding_registers
MAX_UPDATE_RATE=20
[TRANSACTION_01]
MB_SLAVE_ID=4
FIRST_ELEMENT=7
NELEMENTS=1
MB_TX_CODE=fnct_05_write_single_coil
[TRANSACTION_02]
LINK_TYPE=tcp
TCP_IP=10.0.0.2
FIRST_ELEMENT=7
NELEMENTS=1
MB_TX_CODE=fnct_05_write_single_coil
";
    let c = parse(text).unwrap();
    let t = &c.transactions;
    let LinkConfig::Serial {
        port,
        settings,
        delay,
    } = &t[0].link
    else {
        panic!("{:?}", t[0].link)
    };
    assert_eq!(port, "/dev/ttyUSB0");
    assert_eq!(settings.to_string(), "19200 baud 8E2");
    assert_eq!(*delay, Duration::from_millis(10));
    assert_eq!(t[1].link, t[0].link);
    assert_eq!((t[1].slave, t[1].max_update_rate), (4, 20.0));
    assert_eq!(t[0].period(), Duration::from_millis(50));
    // A TCP link after a serial one: the slave is inherited too.
    assert_eq!(t[2].slave, 4);
    assert_eq!(c.links().len(), 2);
    assert_eq!(c.links()[0].1, [0, 1]);
}

#[test]
fn every_refusal_names_file_line_section_and_key() {
    let cases: &[(&str, &str)] = &[
        (
            &one("", &format!("{TCP}NELEMENTS=1\nMB_TX_CODE=fnct_99")),
            "mb.ini:9: [TRANSACTION_00] MB_TX_CODE = fnct_99: not a transaction code (fnct_01_read_coils, fnct_02_read_discrete_inputs, fnct_03_read_holding_registers, fnct_04_read_input_registers, fnct_05_write_single_coil, fnct_06_write_single_register, fnct_15_write_multiple_coils, fnct_16_write_multiple_registers)",
        ),
        (
            "[MB2HAL_INIT]\nINIT_DEBUG=1\n",
            "mb.ini: [MB2HAL_INIT] TOTAL_TRANSACTIONS is missing (how many [TRANSACTION_NN] sections to run, 1 to 100)",
        ),
        (
            "[MB2HAL_INIT]\nTOTAL_TRANSACTIONS=0\n",
            "mb.ini:2: [MB2HAL_INIT] TOTAL_TRANSACTIONS = 0: out of range (1 to 100)",
        ),
        (
            "[MB2HAL_INIT]\nTOTAL_TRANSACTIONS=2\n[TRANSACTION_00]\nLINK_TYPE=tcp\nTCP_IP=h\nFIRST_ELEMENT=0\nNELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils\n",
            "mb.ini: [TRANSACTION_01] is missing ([MB2HAL_INIT] TOTAL_TRANSACTIONS asks for 2 or more)",
        ),
        (
            &one("", "FIRST_ELEMENT=0\nNELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils"),
            "mb.ini: [TRANSACTION_00] LINK_TYPE is missing (the first transaction names its link: tcp or serial)",
        ),
        (
            &one("", "LINK_TYPE=udp"),
            "mb.ini:5: [TRANSACTION_00] LINK_TYPE = udp: tcp or serial",
        ),
        (
            &one("", "LINK_TYPE=tcp"),
            "mb.ini: [TRANSACTION_00] TCP_IP is missing (the server's address, as 192.168.1.10)",
        ),
        (
            &one("", "LINK_TYPE=tcp\nTCP_IP=h\nTCP_PORT=70000"),
            "mb.ini:7: [TRANSACTION_00] TCP_PORT = 70000: out of range (1 to 65535)",
        ),
        (
            &one("", "LINK_TYPE=serial\nSERIAL_BAUD=9600"),
            "mb.ini: [TRANSACTION_00] SERIAL_PORT is missing (the device, as /dev/ttyUSB0)",
        ),
        (
            &one("", "LINK_TYPE=serial\nSERIAL_PORT=/dev/x"),
            "mb.ini: [TRANSACTION_00] SERIAL_BAUD is missing (the line's speed, as 19200)",
        ),
        (
            &one("", "LINK_TYPE=serial\nSERIAL_PORT=/dev/x\nSERIAL_BAUD=fast"),
            "mb.ini:7: [TRANSACTION_00] SERIAL_BAUD = fast: not a whole number (50 to 4000000)",
        ),
        (
            &one("", "LINK_TYPE=serial\nSERIAL_PORT=/dev/x\nSERIAL_BAUD=9600\nSERIAL_BITS=9"),
            "mb.ini:8: [TRANSACTION_00] SERIAL_BITS = 9: out of range (5 to 8)",
        ),
        (
            &one("", "LINK_TYPE=serial\nSERIAL_PORT=/dev/x\nSERIAL_BAUD=9600\nSERIAL_PARITY=mark"),
            "mb.ini:8: [TRANSACTION_00] SERIAL_PARITY = mark: even, odd or none",
        ),
        (
            &one("", "LINK_TYPE=serial\nSERIAL_PORT=/dev/x\nSERIAL_BAUD=9600\nSERIAL_STOP=3"),
            "mb.ini:8: [TRANSACTION_00] SERIAL_STOP = 3: out of range (1 to 2)",
        ),
        (
            &one("", "LINK_TYPE=serial\nSERIAL_PORT=/dev/x\nSERIAL_BAUD=9600\nMB_TX_CODE=fnct_01_read_coils"),
            "mb.ini: [TRANSACTION_00] MB_SLAVE_ID is missing (the slave's address, 0 to 247)",
        ),
        (
            &one("", "LINK_TYPE=serial\nSERIAL_PORT=/dev/x\nSERIAL_BAUD=9600\nMB_TX_CODE=fnct_01_read_coils\nMB_SLAVE_ID=0"),
            "mb.ini:9: [TRANSACTION_00] MB_SLAVE_ID = 0: address 0 is the broadcast: nobody answers a read",
        ),
        (
            &one("", "LINK_TYPE=serial\nSERIAL_PORT=/dev/x\nSERIAL_BAUD=9600\nMB_TX_CODE=fnct_01_read_coils\nMB_SLAVE_ID=248"),
            "mb.ini:9: [TRANSACTION_00] MB_SLAVE_ID = 248: out of range (0 to 247)",
        ),
        (
            &one("", "LINK_TYPE=tcp\nTCP_IP=h\nMB_TX_CODE=fnct_01_read_coils"),
            "mb.ini: [TRANSACTION_00] FIRST_ELEMENT is missing (the first address, 0 to 65535)",
        ),
        (
            &one("", &format!("{TCP}MB_TX_CODE=fnct_01_read_coils")),
            "mb.ini: [TRANSACTION_00] NELEMENTS is missing (or PIN_NAMES: how many elements, 1 to 2000)",
        ),
        (
            &one("", &format!("{TCP}MB_TX_CODE=fnct_03_read_holding_registers\nNELEMENTS=126")),
            "mb.ini:9: [TRANSACTION_00] NELEMENTS = 126: fnct_03_read_holding_registers carries at most 125 elements",
        ),
        (
            &one("", &format!("{TCP}MB_TX_CODE=fnct_06_write_single_register\nNELEMENTS=2")),
            "mb.ini:9: [TRANSACTION_00] NELEMENTS = 2: fnct_06_write_single_register writes one element",
        ),
        (
            &one("", "LINK_TYPE=tcp\nTCP_IP=h\nFIRST_ELEMENT=65535\nMB_TX_CODE=fnct_01_read_coils\nNELEMENTS=2"),
            "mb.ini:9: [TRANSACTION_00] NELEMENTS = 2: 2 elements from FIRST_ELEMENT = 65535 run past address 65535",
        ),
        (
            &one("", &format!("{TCP}MB_TX_CODE=fnct_01_read_coils\nPIN_NAMES=a,b")),
            "mb.ini:9: [TRANSACTION_00] PIN_NAMES = a,b: PIN_NAMES needs [MB2HAL_INIT] VERSION = 1.1",
        ),
        (
            &one("VERSION=1.1", &format!("{TCP}MB_TX_CODE=fnct_05_write_single_coil\nPIN_NAMES=a,b")),
            "mb.ini:9: [TRANSACTION_00] PIN_NAMES = a,b: fnct_05_write_single_coil writes one element",
        ),
        (
            &one("VERSION=1.1", &format!("{TCP}MB_TX_CODE=fnct_01_read_coils\nPIN_NAMES=a,,b")),
            "mb.ini:9: [TRANSACTION_00] PIN_NAMES = a,,b: name 2 is empty",
        ),
        (
            &one("VERSION=1.1", &format!("{TCP}MB_TX_CODE=fnct_01_read_coils\nPIN_NAMES=a,b,a")),
            "mb.ini:9: [TRANSACTION_00] PIN_NAMES = a,b,a: a is named twice",
        ),
        (
            &one("VERSION=1.1", &format!("{TCP}MB_TX_CODE=fnct_01_read_coils\nPIN_NAMES=a,b\nNELEMENTS=3")),
            "mb.ini:10: [TRANSACTION_00] NELEMENTS = 3: PIN_NAMES names 2 elements",
        ),
        (
            &one("VERSION=2.0", ""),
            "mb.ini:3: [MB2HAL_INIT] VERSION = 2.0: this mb2hal reads versions 1.0 and 1.1",
        ),
        (
            &one("VERSION=one", ""),
            "mb.ini:3: [MB2HAL_INIT] VERSION = one: not a version (N.N, as 1.1)",
        ),
        (
            &one("INIT_DEBUG=4", ""),
            "mb.ini:3: [MB2HAL_INIT] INIT_DEBUG = 4: out of range (0 to 3)",
        ),
        (
            &one("SLOWDOWN=-1", ""),
            "mb.ini:3: [MB2HAL_INIT] SLOWDOWN = -1: out of range (0 to 3600)",
        ),
        (
            &one("HAL_MODULE_NAME=a=b", ""),
            "mb.ini:3: [MB2HAL_INIT] HAL_MODULE_NAME = a=b: not a component name: ",
        ),
        (
            &one("", &format!("{TCP}NELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils\nMB_RESPONSE_TIMEOUT_MS=0")),
            "mb.ini:10: [TRANSACTION_00] MB_RESPONSE_TIMEOUT_MS = 0: out of range (1 to 60000)",
        ),
        (
            &one("", &format!("{TCP}NELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils\nMAX_UPDATE_RATE=fast")),
            "mb.ini:10: [TRANSACTION_00] MAX_UPDATE_RATE = fast: not a number (0 to 1000000)",
        ),
        (
            &one("", &format!("{TCP}NELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils\nDEBUG=9")),
            "mb.ini:10: [TRANSACTION_00] DEBUG = 9: out of range (0 to 3)",
        ),
        (
            &one("", &format!("{TCP}NELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils\nHAL_TX_NAME=a b")),
            "mb.ini:10: [TRANSACTION_00] HAL_TX_NAME = a b: not usable as a HAL name: ",
        ),
    ];
    let mut wrong = Vec::new();
    for (text, want) in cases {
        let got = refusal(text);
        if !got.starts_with(want) {
            wrong.push(format!("got  {got}\nwant {want}\nfor\n{text}"));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n\n"));
}

#[test]
fn clashes_between_transactions_are_refused() {
    let two = |a: &str, b: &str| {
        format!(
            "[MB2HAL_INIT]\nTOTAL_TRANSACTIONS=2\n[TRANSACTION_00]\n{a}\n[TRANSACTION_01]\n{b}\n"
        )
    };
    let serial = "LINK_TYPE=serial\nSERIAL_PORT=/dev/x\nSERIAL_BAUD=9600\nMB_SLAVE_ID=1\nFIRST_ELEMENT=0\nNELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils";
    assert_eq!(
        refusal(&two(serial, "SERIAL_BAUD=19200\nFIRST_ELEMENT=0\nNELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils")),
        "mb.ini: [TRANSACTION_01] SERIAL_PORT is missing ([TRANSACTION_00] uses /dev/x as serial /dev/x 9600 baud 8N1: one device, one set of SERIAL_ settings)"
    );
    assert_eq!(
        refusal(&two(
            &format!("{serial}\nHAL_TX_NAME=x"),
            "FIRST_ELEMENT=0\nNELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils\nHAL_TX_NAME=x"
        )),
        "mb.ini:16: [TRANSACTION_01] HAL_TX_NAME = x: [TRANSACTION_00] has the same name: pin names would clash"
    );
}

#[test]
fn unknown_keys_and_unused_sections_are_warned_about() {
    let text = format!(
        "{}FOO=1\n[TRANSACTION_01]\nLINK_TYPE=tcp\n",
        one(
            "",
            &format!("{TCP}NELEMENTS=1\nMB_TX_CODE=fnct_01_read_coils")
        )
    );
    let c = parse(&text).unwrap();
    assert_eq!(
        c.warnings,
        [
            "mb.ini:10: [TRANSACTION_00] FOO is not an mb2hal key: ignored",
            "mb.ini: [TRANSACTION_01] is not run: [MB2HAL_INIT] TOTAL_TRANSACTIONS = 1",
        ]
    );
}

#[test]
fn a_missing_file_is_named() {
    let e = Config::load(Path::new("/nonexistent/mb.ini")).unwrap_err();
    assert!(e.to_string().contains("/nonexistent/mb.ini"), "{e}");
}

#[test]
fn versions_read_as_linuxcnc_shows_them() {
    assert_eq!(parse_version("1.1"), Some(1001));
    assert_eq!(parse_version("1.0"), Some(1000));
    assert_eq!(parse_version("1.001"), Some(1001));
    assert_eq!(parse_version("1"), None);
    assert_eq!(parse_version("1.1234"), None);
    assert_eq!(tx_number("TRANSACTION_07"), Some(7));
    assert_eq!(tx_number("TRANSACTION_7"), None);
}
