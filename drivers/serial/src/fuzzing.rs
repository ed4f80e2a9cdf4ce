//! Bodies of the fuzz targets for this crate's parsers of outside bytes:
//! whatever comes back on the serial line, whatever reaches the
//! simulated drive, and the components' command lines. Each takes
//! arbitrary bytes, must never panic, and checks what it can about the
//! outcome. Until the workspace's `fuzz/` crate is on main they run from
//! this crate's proptest (`tests/fuzz_serial.rs`, 100 000 cases each);
//! the fuzz crate can call them as they are.

use crate::crc;
use crate::line::{LineSettings, Parity, ScriptLine};
use crate::modbus::{Master, MasterConfig};
use crate::sim::{Protocol, VfdSim};
use crate::SerialError;

/// Bytes on the line as the reply to one transaction. The first byte
/// picks the transaction, the retries and how the bytes are cut into
/// reads; the rest is the line's answer. An accepted reply is always a
/// whole frame from the slave asked with a valid CRC.
pub fn modbus_reply(bytes: &[u8]) {
    let Some((&sel, answer)) = bytes.split_first() else {
        return;
    };
    let chunk = usize::from(sel >> 4) + 1;
    let line = ScriptLine::new(answer.chunks(chunk).map(<[u8]>::to_vec));
    let config = MasterConfig {
        retries: u32::from(sel & 1),
        ..MasterConfig::default()
    };
    let mut m = Master::new(line, config);
    let count = u16::from(sel >> 5) + 1;
    let outcome: Result<(), SerialError> = match sel % 8 {
        0 => m.read_registers(1, 0x03, 0x3000, count).map(|v| {
            assert_eq!(v.len(), usize::from(count));
        }),
        1 => m.write_register(1, 0x2000, 5000),
        2 => m.write_registers(1, 0x1000, &[1, 2]),
        3 => m.hy_read_parameter(1, 5).map(drop),
        4 => m.hy_write_control(1, 0x01).map(drop),
        5 => m.hy_read_status(1, 3).map(drop),
        6 => m.hy_write_frequency(1, 20_000).map(drop),
        _ => m
            .read_registers(1, 0x04, 0, 125)
            .map(|v| assert_eq!(v.len(), 125)),
    };
    match outcome {
        Ok(()) => {
            // The accepted reply starts where some attempt began to read.
            let whole = (0..answer.len()).any(|i| {
                answer[i] == 1
                    && (4..=(answer.len() - i).min(256)).any(|n| crc::is_valid(&answer[i..i + n]))
            });
            assert!(whole, "an accepted reply is a whole frame from slave 1");
        }
        Err(e) => {
            assert!(!e.to_string().is_empty());
            assert!(e.code() < 0);
        }
    }
    assert_eq!(m.stats().transactions, 1);
    assert!(
        m.line().sent().len() <= 2,
        "one request and at most one retry"
    );
}

/// Bytes arriving at the simulated drive, in pieces with gaps between
/// some of them, for both protocols: every answer is a whole frame from
/// the drive's address with a valid CRC.
pub fn slave_request(bytes: &[u8]) {
    for protocol in [Protocol::Hy, Protocol::ModbusGt] {
        let mut sim = VfdSim::new(protocol, 1, LineSettings::new(19_200, Parity::Even));
        let mut now = 0u64;
        for piece in bytes.chunks(7) {
            // A piece whose first byte is odd comes after a long silence.
            now += if piece[0] & 1 == 1 {
                3_000_000
            } else {
                500_000
            };
            sim.feed(piece, now);
            for at in [now, now + 2_500_000] {
                if let Some(reply) = sim.poll(at) {
                    assert!(crc::is_valid(&reply.bytes), "{:02X?}", reply.bytes);
                    assert_eq!(reply.bytes[0], 1);
                    assert!(reply.bytes.len() <= 256);
                }
            }
        }
    }
}

/// A command line (arguments separated by NUL bytes) for both
/// components: parsed or refused with a message, never a panic.
pub fn command_line(bytes: &[u8]) {
    use crate::vfd::Parsed;
    let text = String::from_utf8_lossy(bytes);
    let args: Vec<String> = text.split('\0').map(str::to_string).collect();
    match crate::vfd::hy::parse_options(&args) {
        Ok(Parsed::Run(o)) => {
            assert!(o.serial.slave >= 1 && o.registers.len() <= 10);
            assert!((5..=8).contains(&o.serial.settings.data_bits));
        }
        Ok(Parsed::Help | Parsed::Version) => {}
        Err(e) => assert!(!e.to_string().is_empty()),
    }
    match crate::vfd::gt::parse_options(&args) {
        Ok(Parsed::Run(o)) => assert!(o.min_freq <= o.max_freq && o.motor_max_speed > 0.0),
        Ok(Parsed::Help | Parsed::Version) => {}
        Err(e) => assert!(!e.to_string().is_empty()),
    }
}

/// An mb2hal INI file (`#INCLUDE`s of anything fail): a configuration
/// whose every transaction fits its function, names valid pins and
/// stays in the address space, or a refusal with a message.
pub fn mb2hal_ini(bytes: &[u8]) {
    use crate::mb2hal::config::Config;
    use std::path::Path;
    let text = String::from_utf8_lossy(bytes).into_owned();
    let mut read = |p: &Path| -> std::io::Result<String> {
        if p == Path::new("fuzz.ini") {
            Ok(text.clone())
        } else {
            Err(std::io::ErrorKind::NotFound.into())
        }
    };
    let ini = match hal_lang::ini::Ini::parse_with(Path::new("fuzz.ini"), &mut read) {
        Ok(ini) => ini,
        Err(e) => return assert!(!e.to_string().is_empty()),
    };
    match Config::from_ini(&ini) {
        Ok(c) => {
            assert!(!c.transactions.is_empty() && c.transactions.len() <= 100);
            for tx in &c.transactions {
                let n = usize::from(tx.count());
                assert!(n >= 1 && n <= usize::from(tx.code.max_count()));
                assert_eq!(n, tx.elements.len());
                assert!(usize::from(tx.first) + n - 1 <= 65535);
                for e in &tx.elements {
                    let pin = format!("{}.{}.{e}.bit-inv", c.module_name, tx.hal_name);
                    assert!(hal_core::name::validate("pin", &pin).is_ok(), "{pin}");
                }
            }
            let links: usize = c.links().iter().map(|(_, txs)| txs.len()).sum();
            assert_eq!(links, c.transactions.len());
        }
        Err(e) => assert!(!e.to_string().is_empty()),
    }
}

/// Bytes from a Modbus TCP server as the reply to one transaction. The
/// first byte picks the transaction and how the bytes are cut into
/// reads; the rest is what the socket delivers. An accepted reply
/// answers the transaction asked with the values it asked for.
pub fn modbus_tcp_reply(bytes: &[u8]) {
    use crate::mb2hal::tcp::{MbapClient, ScriptWire};
    use crate::modbus::functions as f;
    let Some((&sel, answer)) = bytes.split_first() else {
        return;
    };
    let chunk = usize::from(sel >> 4) + 1;
    let wire = ScriptWire::new(answer.chunks(chunk).map(<[u8]>::to_vec));
    let mut c = MbapClient::new(wire, "fuzz:502");
    let count = u16::from(sel >> 5) + 1;
    let outcome: Result<(), SerialError> = match sel % 8 {
        0 => f::read_bits(&mut c, 1, 0x01, 0, count).map(|v| assert_eq!(v.len(), count.into())),
        1 => f::read_bits(&mut c, 1, 0x02, 7, 17).map(|v| assert_eq!(v.len(), 17)),
        2 => {
            f::read_registers(&mut c, 1, 0x03, 0, count).map(|v| assert_eq!(v.len(), count.into()))
        }
        3 => f::read_registers(&mut c, 1, 0x04, 0, 125).map(|v| assert_eq!(v.len(), 125)),
        4 => f::write_coil(&mut c, 1, 3, true),
        5 => f::write_register(&mut c, 1, 3, 0x1234),
        6 => f::write_coils(&mut c, 1, 3, &[true, false, true]),
        _ => f::write_registers(&mut c, 1, 3, &[1, 2, 3]),
    };
    match outcome {
        Ok(()) => assert!(answer.len() >= 9, "a reply has a header and a PDU"),
        Err(e) => {
            assert!(!e.to_string().is_empty());
            assert!(e.code() < 0);
        }
    }
    assert!(
        c.wire().sent.len() <= 7 + 253,
        "one request, never a second"
    );
}
