//! Reading `[MB2HAL_INIT]` and the `[TRANSACTION_NN]` sections into a
//! [`Config`]: typed values in range, keys inherited from the previous
//! transaction, and refusals that name the file, line, section and key.

use std::time::Duration;

use hal_lang::ini::{parse_int, Entry, Ini};

use super::config::{
    Config, LinkConfig, Transaction, TxCode, DEFAULT_TCP_PORT, DEFAULT_TCP_UNIT,
    DEFAULT_TIMEOUT_MS, INIT_SECTION, MAX_TRANSACTIONS, VERSION_PIN_NAMES,
};
use crate::error::{Result, SerialError};
use crate::line::{LineSettings, Parity};
use crate::regs::modbus as mb;

/// The keys of `[MB2HAL_INIT]`.
const INIT_KEYS: &[&str] = &[
    "INIT_DEBUG",
    "VERSION",
    "HAL_MODULE_NAME",
    "SLOWDOWN",
    "TOTAL_TRANSACTIONS",
];
/// The keys of a transaction section.
const TX_KEYS: &[&str] = &[
    "LINK_TYPE",
    "TCP_IP",
    "TCP_PORT",
    "SERIAL_PORT",
    "SERIAL_BAUD",
    "SERIAL_BITS",
    "SERIAL_PARITY",
    "SERIAL_STOP",
    "SERIAL_DELAY_MS",
    "MB_SLAVE_ID",
    "FIRST_ELEMENT",
    "NELEMENTS",
    "PIN_NAMES",
    "MB_TX_CODE",
    "MB_RESPONSE_TIMEOUT_MS",
    "MB_BYTE_TIMEOUT_MS",
    "HAL_TX_NAME",
    "MAX_UPDATE_RATE",
    "DEBUG",
];

/// Reads typed values with errors that say where.
pub(super) struct Reader<'a> {
    ini: &'a Ini,
    file: String,
}

/// A value, where it was written, and its first word.
struct Found<'a> {
    entry: &'a Entry,
}

impl Found<'_> {
    fn word(&self) -> &str {
        self.entry.value.split_whitespace().next().unwrap_or("")
    }
}

impl<'a> Reader<'a> {
    /// A reader of `ini`.
    pub(super) fn new(ini: &'a Ini) -> Reader<'a> {
        Reader {
            ini,
            file: ini.name(),
        }
    }

    fn get(&self, section: &str, key: &str) -> Option<Found<'a>> {
        self.ini.entry(section, key).map(|entry| Found { entry })
    }

    fn bad(&self, f: &Found<'_>, reason: impl Into<String>) -> SerialError {
        SerialError::Config {
            at: f.entry.origin.to_string(),
            section: f.entry.section.clone(),
            key: f.entry.key.clone(),
            value: f.entry.value.clone(),
            reason: reason.into(),
        }
    }

    fn missing(&self, section: &str, key: &str, reason: impl Into<String>) -> SerialError {
        SerialError::ConfigMissing {
            file: self.file.clone(),
            section: section.to_string(),
            key: key.to_string(),
            reason: reason.into(),
        }
    }

    /// A whole number in `lo..=hi`.
    fn int(&self, section: &str, key: &str, lo: i64, hi: i64) -> Result<Option<i64>> {
        let Some(f) = self.get(section, key) else {
            return Ok(None);
        };
        match parse_int(f.word()) {
            Some(v) if (lo..=hi).contains(&v) => Ok(Some(v)),
            Some(_) => Err(self.bad(&f, format!("out of range ({lo} to {hi})"))),
            None => Err(self.bad(&f, format!("not a whole number ({lo} to {hi})"))),
        }
    }

    /// A number in `lo..=hi`.
    fn real(&self, section: &str, key: &str, lo: f64, hi: f64) -> Result<Option<f64>> {
        let Some(f) = self.get(section, key) else {
            return Ok(None);
        };
        match f.word().parse::<f64>() {
            Ok(v) if (lo..=hi).contains(&v) => Ok(Some(v)),
            Ok(_) => Err(self.bad(&f, format!("out of range ({lo} to {hi})"))),
            Err(_) => Err(self.bad(&f, format!("not a number ({lo} to {hi})"))),
        }
    }

    /// The whole value, which must not be empty.
    fn text(&self, section: &str, key: &str) -> Result<Option<(String, Found<'a>)>> {
        let Some(f) = self.get(section, key) else {
            return Ok(None);
        };
        let v = f.entry.value.trim().to_string();
        if v.is_empty() {
            return Err(self.bad(&f, "empty"));
        }
        Ok(Some((v, f)))
    }

    /// A name that becomes part of HAL names.
    fn hal_word(&self, f: &Found<'_>, word: &str, what: &str) -> Result<()> {
        hal_core::name::validate("pin", word)
            .map_err(|e| self.bad(f, format!("not usable as {what}: {e}")))
    }

    pub(super) fn init(&self) -> Result<Config> {
        let s = INIT_SECTION;
        let init_debug = self.int(s, "INIT_DEBUG", 0, 3)?.unwrap_or(1) as u8;
        let version = match self.get(s, "VERSION") {
            None => 1000,
            Some(f) => match parse_version(f.word()) {
                Some(v @ (1000 | VERSION_PIN_NAMES)) => v,
                Some(_) => return Err(self.bad(&f, "this mb2hal reads versions 1.0 and 1.1")),
                None => return Err(self.bad(&f, "not a version (N.N, as 1.1)")),
            },
        };
        let module_name = match self.text(s, "HAL_MODULE_NAME")? {
            None => "mb2hal".to_string(),
            Some((v, f)) => {
                hal_core::name::validate("component", &v)
                    .map_err(|e| self.bad(&f, format!("not a component name: {e}")))?;
                v
            }
        };
        let slowdown = self.real(s, "SLOWDOWN", 0.0, 3600.0)?.unwrap_or(0.0);
        Ok(Config {
            file: self.file.clone(),
            init_debug,
            version,
            module_name,
            slowdown: Duration::from_secs_f64(slowdown),
            transactions: Vec::new(),
            warnings: Vec::new(),
        })
    }

    pub(super) fn total_transactions(&self) -> Result<usize> {
        match self.int(
            INIT_SECTION,
            "TOTAL_TRANSACTIONS",
            1,
            MAX_TRANSACTIONS as i64,
        )? {
            Some(n) => Ok(n as usize),
            None => Err(self.missing(
                INIT_SECTION,
                "TOTAL_TRANSACTIONS",
                "how many [TRANSACTION_NN] sections to run, 1 to 100",
            )),
        }
    }

    pub(super) fn transaction(
        &self,
        n: usize,
        prev: Option<&Transaction>,
        version: u32,
        module: &str,
    ) -> Result<Transaction> {
        let s = format!("TRANSACTION_{n:02}");
        if !self.ini.has_section(&s) {
            return Err(self.missing(
                &s,
                "",
                format!(
                    "[{INIT_SECTION}] TOTAL_TRANSACTIONS asks for {} or more",
                    n + 1
                ),
            ));
        }
        let link = self.link(&s, prev.map(|p| &p.link))?;
        let is_tcp = matches!(link, LinkConfig::Tcp { .. });
        let code = match self.get(&s, "MB_TX_CODE") {
            None => return Err(self.missing(&s, "MB_TX_CODE", codes_list())),
            Some(f) => TxCode::from_name(f.word()).ok_or_else(|| {
                self.bad(&f, format!("not a transaction code ({})", codes_list()))
            })?,
        };
        let slave = self.slave(&s, is_tcp, code, prev)?;
        let first = match self.int(&s, "FIRST_ELEMENT", 0, 65535)? {
            Some(v) => v as u16,
            None => return Err(self.missing(&s, "FIRST_ELEMENT", "the first address, 0 to 65535")),
        };
        let hal_name = match self.text(&s, "HAL_TX_NAME")? {
            None => format!("{n:02}"),
            Some((v, f)) => {
                self.hal_word(&f, &format!("{module}.{v}.num_errors"), "a HAL name")?;
                v
            }
        };
        let elements = self.elements(&s, code, first, version, &format!("{module}.{hal_name}"))?;
        let ms = |key: &str, inherited: Option<Duration>| -> Result<Duration> {
            Ok(match self.int(&s, key, 1, 60_000)? {
                Some(v) => Duration::from_millis(v as u64),
                None => inherited.unwrap_or(Duration::from_millis(DEFAULT_TIMEOUT_MS)),
            })
        };
        Ok(Transaction {
            link,
            slave,
            first,
            elements,
            code,
            response_timeout: ms("MB_RESPONSE_TIMEOUT_MS", prev.map(|p| p.response_timeout))?,
            byte_timeout: ms("MB_BYTE_TIMEOUT_MS", prev.map(|p| p.byte_timeout))?,
            max_update_rate: self
                .real(&s, "MAX_UPDATE_RATE", 0.0, 1e6)?
                .or(prev.map(|p| p.max_update_rate))
                .unwrap_or(0.0),
            debug: self
                .int(&s, "DEBUG", 0, 3)?
                .map(|v| v as u8)
                .or(prev.map(|p| p.debug))
                .unwrap_or(1),
            hal_name,
            section: s,
        })
    }

    /// `MB_SLAVE_ID`, inherited when it fits this link; a read from
    /// the RTU broadcast address is refused.
    fn slave(&self, s: &str, is_tcp: bool, code: TxCode, prev: Option<&Transaction>) -> Result<u8> {
        let max_slave = if is_tcp {
            255
        } else {
            i64::from(mb::MAX_SLAVE)
        };
        let inherited_slave = prev.map(|p| p.slave).filter(|&v| i64::from(v) <= max_slave);
        let slave = match self.int(s, "MB_SLAVE_ID", 0, max_slave)? {
            Some(v) => v as u8,
            None => match (inherited_slave, is_tcp) {
                (Some(v), _) => v,
                (None, true) => DEFAULT_TCP_UNIT,
                (None, false) => {
                    return Err(self.missing(s, "MB_SLAVE_ID", "the slave's address, 0 to 247"))
                }
            },
        };
        if slave == mb::BROADCAST && !is_tcp && code.reads() {
            let why = "address 0 is the broadcast: nobody answers a read";
            return Err(match self.get(s, "MB_SLAVE_ID") {
                Some(f) => self.bad(&f, why),
                None => self.missing(s, "MB_SLAVE_ID", why),
            });
        }
        Ok(slave)
    }

    /// `NELEMENTS` or `PIN_NAMES`: the element names.
    fn elements(
        &self,
        s: &str,
        code: TxCode,
        first: u16,
        version: u32,
        prefix: &str,
    ) -> Result<Vec<String>> {
        let max = code.max_count();
        let limit = |f: &Found<'_>, count: usize| -> Result<()> {
            if count > usize::from(max) {
                let single = max == 1;
                return Err(self.bad(
                    f,
                    if single {
                        format!("{} writes one element", code.name())
                    } else {
                        format!("{} carries at most {max} elements", code.name())
                    },
                ));
            }
            if usize::from(first) + count - 1 > 65535 {
                return Err(self.bad(
                    f,
                    format!("{count} elements from FIRST_ELEMENT = {first} run past address 65535"),
                ));
            }
            Ok(())
        };
        let count = self.int(s, "NELEMENTS", 1, 65536)?;
        if let Some((list, f)) = self.text(s, "PIN_NAMES")? {
            if version < VERSION_PIN_NAMES {
                return Err(self.bad(
                    &f,
                    format!("PIN_NAMES needs [{INIT_SECTION}] VERSION = 1.1"),
                ));
            }
            let names: Vec<String> = list.split(',').map(|w| w.trim().to_string()).collect();
            for (i, name) in names.iter().enumerate() {
                if name.is_empty() {
                    return Err(self.bad(&f, format!("name {} is empty", i + 1)));
                }
                self.hal_word(&f, &format!("{prefix}.{name}.bit-inv"), "a pin name")?;
                if names[..i].contains(name) {
                    return Err(self.bad(&f, format!("{name} is named twice")));
                }
            }
            if let Some(nf) = self.get(s, "NELEMENTS") {
                if count != Some(names.len() as i64) {
                    let reason = format!("PIN_NAMES names {} elements", names.len());
                    return Err(self.bad(&nf, reason));
                }
            }
            limit(&f, names.len())?;
            return Ok(names);
        }
        match (count, self.get(s, "NELEMENTS")) {
            (Some(c), Some(f)) => {
                limit(&f, c as usize)?;
                // LinuxCNC's numbering: two digits at least (00 .. 99, 100).
                Ok((0..c).map(|i| format!("{i:02}")).collect())
            }
            _ => Err(self.missing(
                s,
                "NELEMENTS",
                format!("or PIN_NAMES: how many elements, 1 to {max}"),
            )),
        }
    }

    /// The link keys, each inherited from the previous transaction's
    /// link when left out.
    fn link(&self, s: &str, prev: Option<&LinkConfig>) -> Result<LinkConfig> {
        let link_type = match self.get(s, "LINK_TYPE") {
            Some(f) => match f.word() {
                "tcp" => "tcp",
                "serial" => "serial",
                _ => return Err(self.bad(&f, "tcp or serial")),
            },
            None => match prev {
                Some(LinkConfig::Tcp { .. }) => "tcp",
                Some(LinkConfig::Serial { .. }) => "serial",
                None => {
                    return Err(self.missing(
                        s,
                        "LINK_TYPE",
                        "the first transaction names its link: tcp or serial",
                    ))
                }
            },
        };
        if link_type == "tcp" {
            let (prev_ip, prev_port) = match prev {
                Some(LinkConfig::Tcp { ip, port }) => (Some(ip.clone()), Some(*port)),
                _ => (None, None),
            };
            let ip = match self.text(s, "TCP_IP")? {
                Some((v, f)) => {
                    if v.split_whitespace().count() != 1 {
                        return Err(self.bad(&f, "one address or host name"));
                    }
                    v
                }
                None => prev_ip.ok_or_else(|| {
                    self.missing(s, "TCP_IP", "the server's address, as 192.168.1.10")
                })?,
            };
            let port = self.int(s, "TCP_PORT", 1, 65535)?.map(|p| p as u16);
            return Ok(LinkConfig::Tcp {
                ip,
                port: port.or(prev_port).unwrap_or(DEFAULT_TCP_PORT),
            });
        }
        self.serial_link(s, prev)
    }

    fn serial_link(&self, s: &str, prev: Option<&LinkConfig>) -> Result<LinkConfig> {
        let (prev_port, prev_settings, prev_delay) = match prev {
            Some(LinkConfig::Serial {
                port,
                settings,
                delay,
            }) => (Some(port.clone()), Some(*settings), Some(*delay)),
            _ => (None, None, None),
        };
        let port = match self.text(s, "SERIAL_PORT")? {
            Some((v, _)) => v,
            None => prev_port
                .ok_or_else(|| self.missing(s, "SERIAL_PORT", "the device, as /dev/ttyUSB0"))?,
        };
        let baud = match self.int(s, "SERIAL_BAUD", 50, 4_000_000)? {
            Some(b) => b as u32,
            None => prev_settings
                .map(|p| p.baud)
                .ok_or_else(|| self.missing(s, "SERIAL_BAUD", "the line's speed, as 19200"))?,
        };
        let data_bits = match self.int(s, "SERIAL_BITS", 5, 8)? {
            Some(b) => b as u8,
            None => prev_settings.map_or(8, |p| p.data_bits),
        };
        let parity = match self.get(s, "SERIAL_PARITY") {
            Some(f) => match f.word() {
                "even" => Parity::Even,
                "odd" => Parity::Odd,
                "none" => Parity::None,
                _ => return Err(self.bad(&f, "even, odd or none")),
            },
            None => prev_settings.map_or(Parity::None, |p| p.parity),
        };
        let stop_bits = match self.int(s, "SERIAL_STOP", 1, 2)? {
            Some(b) => b as u8,
            None => prev_settings.map_or(1, |p| p.stop_bits),
        };
        let delay = match self.int(s, "SERIAL_DELAY_MS", 0, 60_000)? {
            Some(ms) => Duration::from_millis(ms as u64),
            None => prev_delay.unwrap_or(Duration::ZERO),
        };
        Ok(LinkConfig::Serial {
            port,
            settings: LineSettings {
                baud,
                data_bits,
                parity,
                stop_bits,
            },
            delay,
        })
    }

    /// Refuses a HAL name used twice, and one serial port with two
    /// settings.
    pub(super) fn check_unique(&self, done: &[Transaction], tx: &Transaction) -> Result<()> {
        if let Some(other) = done.iter().find(|o| o.hal_name == tx.hal_name) {
            let reason = format!(
                "[{}] has the same name: pin names would clash",
                other.section
            );
            return Err(match self.get(&tx.section, "HAL_TX_NAME") {
                Some(f) => self.bad(&f, reason),
                None => self.missing(&tx.section, "HAL_TX_NAME", reason),
            });
        }
        let LinkConfig::Serial { port, .. } = &tx.link else {
            return Ok(());
        };
        let clash = done.iter().find(|o| {
            matches!(&o.link, LinkConfig::Serial { port: p, .. } if p == port) && o.link != tx.link
        });
        if let Some(other) = clash {
            let reason = format!(
                "[{}] uses {port} as {}: one device, one set of SERIAL_ settings",
                other.section,
                other.link.describe()
            );
            let key = self.get(&tx.section, "SERIAL_PORT");
            return Err(match key {
                Some(f) => self.bad(&f, reason),
                None => self.missing(&tx.section, "SERIAL_PORT", reason),
            });
        }
        Ok(())
    }

    /// Keys and sections that mean nothing to mb2hal.
    pub(super) fn warnings(&self, total: usize) -> Vec<String> {
        let mut out: Vec<String> = self.ini.warnings().iter().map(|w| w.to_string()).collect();
        for e in self.ini.entries() {
            let known = if e.section == INIT_SECTION {
                INIT_KEYS.contains(&e.key.as_str())
            } else if let Some(n) = tx_number(&e.section) {
                if n >= total {
                    continue;
                }
                TX_KEYS.contains(&e.key.as_str())
            } else {
                continue;
            };
            if !known {
                out.push(format!(
                    "{}: [{}] {} is not an mb2hal key: ignored",
                    e.origin, e.section, e.key
                ));
            }
        }
        for s in self.ini.sections() {
            if tx_number(s).is_some_and(|n| n >= total) {
                out.push(format!(
                    "{}: [{s}] is not run: [{INIT_SECTION}] TOTAL_TRANSACTIONS = {total}",
                    self.file
                ));
            }
        }
        out
    }
}

/// The number of a `TRANSACTION_NN` section.
pub(super) fn tx_number(section: &str) -> Option<usize> {
    let digits = section.strip_prefix("TRANSACTION_")?;
    if digits.len() < 2 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// `N.N[NN]` as major × 1000 + minor.
pub(super) fn parse_version(word: &str) -> Option<u32> {
    let (major, minor) = word.split_once('.')?;
    let ok = |s: &str, max: usize| {
        !s.is_empty() && s.len() <= max && s.bytes().all(|b| b.is_ascii_digit())
    };
    if !ok(major, 3) || !ok(minor, 3) {
        return None;
    }
    Some(major.parse::<u32>().ok()? * 1000 + minor.parse::<u32>().ok()?)
}

fn codes_list() -> String {
    TxCode::ALL.map(TxCode::name).join(", ")
}
