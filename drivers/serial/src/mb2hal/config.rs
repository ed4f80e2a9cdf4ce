//! mb2hal's INI file, read as LinuxCNC's mb2hal reads it: the
//! `[MB2HAL_INIT]` section, then `[TRANSACTION_00]` ... up to
//! `TOTAL_TRANSACTIONS`. A transaction that leaves out a link key
//! (`LINK_TYPE`, `TCP_IP`, `TCP_PORT`, `SERIAL_*`), `MB_SLAVE_ID`, a
//! timeout, `MAX_UPDATE_RATE` or `DEBUG` takes the previous
//! transaction's; the first must name its link. Every refusal names the
//! file, line, section and key, with what would be accepted.

use std::time::Duration;

use hal_lang::ini::Ini;

use super::reader::Reader;
use crate::error::Result;
use crate::line::LineSettings;
use crate::regs::modbus as mb;

/// The section of the settings that are not a transaction's.
pub const INIT_SECTION: &str = "MB2HAL_INIT";
/// The most transactions one file may have (two-digit section numbers).
pub const MAX_TRANSACTIONS: usize = 100;
/// The reply and byte timeouts when none is given, in ms.
pub const DEFAULT_TIMEOUT_MS: u64 = 500;
/// Modbus TCP's port when none is given.
pub const DEFAULT_TCP_PORT: u16 = 502;
/// The unit identifier of a TCP transaction without `MB_SLAVE_ID`
/// (libmodbus's, which LinuxCNC's mb2hal uses).
pub const DEFAULT_TCP_UNIT: u8 = 255;
/// `VERSION = 1.1`, the first that reads `PIN_NAMES`.
pub const VERSION_PIN_NAMES: u32 = 1001;

/// A transaction's Modbus function, by LinuxCNC's `MB_TX_CODE` name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TxCode {
    /// `fnct_01_read_coils`.
    ReadCoils,
    /// `fnct_02_read_discrete_inputs`.
    ReadDiscreteInputs,
    /// `fnct_03_read_holding_registers`.
    ReadHoldingRegisters,
    /// `fnct_04_read_input_registers`.
    ReadInputRegisters,
    /// `fnct_05_write_single_coil`.
    WriteSingleCoil,
    /// `fnct_06_write_single_register`.
    WriteSingleRegister,
    /// `fnct_15_write_multiple_coils`.
    WriteMultipleCoils,
    /// `fnct_16_write_multiple_registers`.
    WriteMultipleRegisters,
}

impl TxCode {
    /// Every code, in number order.
    pub const ALL: [TxCode; 8] = [
        TxCode::ReadCoils,
        TxCode::ReadDiscreteInputs,
        TxCode::ReadHoldingRegisters,
        TxCode::ReadInputRegisters,
        TxCode::WriteSingleCoil,
        TxCode::WriteSingleRegister,
        TxCode::WriteMultipleCoils,
        TxCode::WriteMultipleRegisters,
    ];

    /// The `MB_TX_CODE` spelling.
    pub fn name(self) -> &'static str {
        match self {
            TxCode::ReadCoils => "fnct_01_read_coils",
            TxCode::ReadDiscreteInputs => "fnct_02_read_discrete_inputs",
            TxCode::ReadHoldingRegisters => "fnct_03_read_holding_registers",
            TxCode::ReadInputRegisters => "fnct_04_read_input_registers",
            TxCode::WriteSingleCoil => "fnct_05_write_single_coil",
            TxCode::WriteSingleRegister => "fnct_06_write_single_register",
            TxCode::WriteMultipleCoils => "fnct_15_write_multiple_coils",
            TxCode::WriteMultipleRegisters => "fnct_16_write_multiple_registers",
        }
    }

    /// The Modbus function code.
    pub fn function(self) -> u8 {
        match self {
            TxCode::ReadCoils => mb::READ_COILS,
            TxCode::ReadDiscreteInputs => mb::READ_DISCRETE_INPUTS,
            TxCode::ReadHoldingRegisters => mb::READ_HOLDING_REGISTERS,
            TxCode::ReadInputRegisters => mb::READ_INPUT_REGISTERS,
            TxCode::WriteSingleCoil => mb::WRITE_SINGLE_COIL,
            TxCode::WriteSingleRegister => mb::WRITE_SINGLE_REGISTER,
            TxCode::WriteMultipleCoils => mb::WRITE_MULTIPLE_COILS,
            TxCode::WriteMultipleRegisters => mb::WRITE_MULTIPLE_REGISTERS,
        }
    }

    /// The most elements one transaction may carry.
    pub fn max_count(self) -> u16 {
        match self {
            TxCode::ReadCoils | TxCode::ReadDiscreteInputs => mb::MAX_READ_BITS,
            TxCode::ReadHoldingRegisters | TxCode::ReadInputRegisters => mb::MAX_READ_COUNT,
            TxCode::WriteSingleCoil | TxCode::WriteSingleRegister => 1,
            TxCode::WriteMultipleCoils => mb::MAX_WRITE_BITS,
            TxCode::WriteMultipleRegisters => mb::MAX_WRITE_COUNT,
        }
    }

    /// Whether it reads from the slave (its pins are outputs).
    pub fn reads(self) -> bool {
        matches!(
            self,
            TxCode::ReadCoils
                | TxCode::ReadDiscreteInputs
                | TxCode::ReadHoldingRegisters
                | TxCode::ReadInputRegisters
        )
    }

    /// The code whose `MB_TX_CODE` spelling is `name`.
    pub fn from_name(name: &str) -> Option<TxCode> {
        TxCode::ALL.into_iter().find(|c| c.name() == name)
    }
}

/// How a transaction reaches its slave.
#[derive(Debug, Clone, PartialEq)]
pub enum LinkConfig {
    /// Modbus TCP.
    Tcp {
        /// `TCP_IP`: an address or a host name.
        ip: String,
        /// `TCP_PORT`.
        port: u16,
    },
    /// Modbus RTU on a serial line.
    Serial {
        /// `SERIAL_PORT`: the device path.
        port: String,
        /// `SERIAL_BAUD`, `SERIAL_BITS`, `SERIAL_PARITY`, `SERIAL_STOP`.
        settings: LineSettings,
        /// `SERIAL_DELAY_MS`: a pause after each transaction on the line.
        delay: Duration,
    },
}

impl LinkConfig {
    /// The link for messages: `tcp 127.0.0.1:502`, `serial /dev/ttyUSB0`.
    pub fn describe(&self) -> String {
        match self {
            LinkConfig::Tcp { ip, port } => format!("tcp {ip}:{port}"),
            LinkConfig::Serial { port, settings, .. } => format!("serial {port} {settings}"),
        }
    }
}

/// One `[TRANSACTION_NN]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Transaction {
    /// Its section, `TRANSACTION_NN`.
    pub section: String,
    /// Its link.
    pub link: LinkConfig,
    /// `MB_SLAVE_ID`.
    pub slave: u8,
    /// `FIRST_ELEMENT`: the first coil, input or register.
    pub first: u16,
    /// The element names, one per element: `PIN_NAMES`, else `00`, `01`,
    /// ... (`NELEMENTS` of them).
    pub elements: Vec<String>,
    /// `MB_TX_CODE`.
    pub code: TxCode,
    /// `MB_RESPONSE_TIMEOUT_MS`.
    pub response_timeout: Duration,
    /// `MB_BYTE_TIMEOUT_MS`.
    pub byte_timeout: Duration,
    /// `MAX_UPDATE_RATE`, Hz; 0 for as often as the link allows.
    pub max_update_rate: f64,
    /// `DEBUG`: 0 quiet, 1 errors, 2 every transaction, 3 every frame.
    pub debug: u8,
    /// `HAL_TX_NAME`, else the transaction's number in two digits.
    pub hal_name: String,
}

impl Transaction {
    /// How many elements it carries.
    pub fn count(&self) -> u16 {
        self.elements.len() as u16
    }

    /// The time between two runs; zero for no limit.
    pub fn period(&self) -> Duration {
        if self.max_update_rate > 0.0 {
            Duration::from_secs_f64(1.0 / self.max_update_rate)
        } else {
            Duration::ZERO
        }
    }
}

/// A whole mb2hal configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The file, as it was named.
    pub file: String,
    /// `INIT_DEBUG`: 0 errors only, 1 progress, 2 and 3 more detail.
    pub init_debug: u8,
    /// `VERSION`, as major × 1000 + minor (1.1 is 1001, as LinuxCNC
    /// shows it).
    pub version: u32,
    /// `HAL_MODULE_NAME`: the component's name, prefix of every pin.
    pub module_name: String,
    /// `SLOWDOWN`: a pause after every transaction.
    pub slowdown: Duration,
    /// The transactions, in section order.
    pub transactions: Vec<Transaction>,
    /// Keys and sections that were not understood and were skipped.
    pub warnings: Vec<String>,
}

impl Config {
    /// Reads the INI file at `path`.
    pub fn load(path: &std::path::Path) -> Result<Config> {
        let ini = Ini::load(path)?;
        Config::from_ini(&ini)
    }

    /// The configuration `ini` holds.
    pub fn from_ini(ini: &Ini) -> Result<Config> {
        let r = Reader::new(ini);
        let mut config = r.init()?;
        let total = r.total_transactions()?;
        for n in 0..total {
            let prev = config.transactions.last();
            let tx = r.transaction(n, prev, config.version, &config.module_name)?;
            r.check_unique(&config.transactions, &tx)?;
            config.transactions.push(tx);
        }
        config.warnings = r.warnings(total);
        Ok(config)
    }

    /// The links: each distinct link once, with the indexes of the
    /// transactions that use it, in order of first use.
    pub fn links(&self) -> Vec<(LinkConfig, Vec<usize>)> {
        let mut links: Vec<(LinkConfig, Vec<usize>)> = Vec::new();
        for (i, tx) in self.transactions.iter().enumerate() {
            match links.iter_mut().find(|(l, _)| *l == tx.link) {
                Some((_, txs)) => txs.push(i),
                None => links.push((tx.link.clone(), vec![i])),
            }
        }
        links
    }
}

#[cfg(test)]
#[path = "config_tests.rs"]
mod tests;
