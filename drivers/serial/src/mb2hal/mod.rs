//! `mb2hal`: LinuxCNC's INI-driven Modbus master as a user-space
//! component. An INI file lists transactions (read coils, discrete
//! inputs, holding or input registers; write one or several coils or
//! registers) on Modbus TCP servers and RTU slaves; each becomes HAL
//! pins, and each link runs its transactions in a thread of its own.
//!
//! ```text
//! loadusr -W mb2hal config=mb2hal.ini
//! loadusr -Wn plc mb2hal config=plc.ini        (with HAL_MODULE_NAME=plc)
//! ```
//!
//! * [`config`]: the INI file (`[MB2HAL_INIT]`, `[TRANSACTION_NN]`,
//!   keys inherited from the previous transaction), refused with the
//!   file, line, section and key when wrong.
//! * [`tcp`]: Modbus TCP (MBAP framing, connection, timeouts).
//! * [`link`]: a link and its transactions in turn, with the update
//!   rates, pauses, and the back-off of a failed link.
//! * [`transaction`], [`hal`]: one transaction between its pins and the
//!   standard Modbus functions ([`crate::modbus::functions`]).
//!
//! Where this differs from LinuxCNC's mb2hal, on purpose: a failure is
//! said once and again only when it changes (LinuxCNC prints each), and
//! a link that fails is tried again after a pause that doubles from
//! 0.2 s to 5 s.

pub mod config;
pub mod hal;
pub mod link;
mod reader;
pub mod tcp;
pub mod transaction;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::Arc;
use std::time::Duration;

use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, Instance};

use crate::error::{Result, SerialError};
use config::Config;
use hal::TxPins;
use link::LinkRunner;

/// The program's name.
pub const NAME: &str = "mb2hal";

/// The help text.
pub const USAGE: &str = "\
Usage: mb2hal config=FILE [--instance NAME]
Runs the Modbus transactions an INI file lists, over Modbus TCP and RTU,
as HAL pins: LinuxCNC's mb2hal. Each link (a TCP server, a serial line)
runs its transactions in turn in a thread of its own; a link that fails
is tried again after a pause, and its transactions count the failures in
their num_errors pins.
The file has an [MB2HAL_INIT] section (INIT_DEBUG, VERSION,
HAL_MODULE_NAME, SLOWDOWN, TOTAL_TRANSACTIONS) and one [TRANSACTION_NN]
section per transaction from 00 (LINK_TYPE, TCP_IP, TCP_PORT,
SERIAL_PORT, SERIAL_BAUD, SERIAL_BITS, SERIAL_PARITY, SERIAL_STOP,
SERIAL_DELAY_MS, MB_SLAVE_ID, FIRST_ELEMENT, NELEMENTS or PIN_NAMES,
MB_TX_CODE, MB_RESPONSE_TIMEOUT_MS, MB_BYTE_TIMEOUT_MS, HAL_TX_NAME,
MAX_UPDATE_RATE, DEBUG). A transaction that leaves out a link key,
MB_SLAVE_ID, a timeout, MAX_UPDATE_RATE or DEBUG takes the previous
one's.
Arguments:
  config=FILE   the INI file (required)
Options:
      --instance NAME         the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help                  print this help and exit
      --version               print the version and exit
Pins:
  (MODULE is HAL_MODULE_NAME; TX is HAL_TX_NAME, else the transaction's number)
  MODULE.TX.num_errors        u32 out: failures since the last success
  MODULE.TX.NN.bit, .bit-inv  bit out: fnct_01_read_coils, fnct_02_read_discrete_inputs
  MODULE.TX.NN.float, .int    float, s32 out: fnct_03_read_holding_registers,
                              fnct_04_read_input_registers
  MODULE.TX.NN.bit            bit in: fnct_05_write_single_coil, fnct_15_write_multiple_coils
  MODULE.TX.NN.float, .int    float, s32 in: fnct_06_write_single_register,
                              fnct_16_write_multiple_registers (their sum, 0 to 65535)
  (NN counts from 00, or is a name of PIN_NAMES with VERSION = 1.1)
Examples:
  loadusr -W mb2hal config=mb2hal.ini
  loadusr -Wn plc mb2hal config=plc.ini   (HAL_MODULE_NAME = plc)
";

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    /// Run the file's transactions, in the instance named (else the
    /// environment's).
    Run {
        /// `config=FILE`.
        config: PathBuf,
        /// `--instance NAME`.
        instance: Option<String>,
    },
    /// `-h`, `--help`.
    Help,
    /// `--version`.
    Version,
}

/// Reads the command line (without the program name).
pub fn parse_args(args: &[String]) -> Result<Command> {
    let mut config = None;
    let mut instance = None;
    let mut i = 0;
    while i < args.len() {
        let a = &args[i];
        if a == "-h" || a == "--help" {
            return Ok(Command::Help);
        }
        if a == "--version" {
            return Ok(Command::Version);
        }
        if let Some(found) = hal_core::userspace::instance_option(args, i, false) {
            let (name, used) = found?;
            hal_core::validate_instance_name(&name).map_err(|e| SerialError::BadOption {
                option: "--instance".into(),
                value: name.clone(),
                reason: e.to_string(),
            })?;
            instance = Some(name);
            i += used;
            continue;
        }
        match a.strip_prefix("config=") {
            Some("") => return Err(SerialError::Usage("config= needs a file name".into())),
            Some(f) => config = Some(PathBuf::from(f)),
            None => return Err(SerialError::Usage(format!("unknown argument '{a}'"))),
        }
        i += 1;
    }
    match config {
        Some(config) => Ok(Command::Run { config, instance }),
        None => Err(SerialError::Usage("config=FILE is required".into())),
    }
}

/// The program: returns its exit status.
pub fn main(args: &[String]) -> i32 {
    let print = |text: &str| {
        let _ = std::io::Write::write_all(&mut std::io::stdout(), text.as_bytes());
    };
    match parse_args(args) {
        Ok(Command::Help) => {
            print(USAGE);
            0
        }
        Ok(Command::Version) => {
            print(&format!("{}\n", hal_core::userspace::version_line(NAME)));
            0
        }
        Ok(Command::Run { config, instance }) => match run(&config, instance.as_deref()) {
            Ok(()) => 0,
            Err(e) => {
                eprintln!("{NAME}: ERROR: {e}");
                1
            }
        },
        Err(e) => {
            eprint!("{USAGE}");
            eprintln!("{NAME}: ERROR: {e}");
            1
        }
    }
}

/// Reads the file, makes the component and its pins, runs every link
/// in a thread until SIGTERM (or the HAL host goes away).
pub fn run(path: &std::path::Path, instance: Option<&str>) -> Result<()> {
    let config = Config::load(path)?;
    for w in &config.warnings {
        eprintln!("{NAME}: warning: {w}");
    }
    let links = config.links();
    if config.init_debug >= 1 {
        let names: Vec<String> = links.iter().map(|(l, _)| l.describe()).collect();
        eprintln!(
            "{NAME}: {}: {} transactions on {} link(s): {}",
            config.file,
            config.transactions.len(),
            links.len(),
            names.join(", ")
        );
    }
    if config.init_debug >= 2 {
        for tx in &config.transactions {
            eprintln!(
                "{NAME}: [{}] {} on {}, slave {}, from {} x{} ({}), timeouts {} ms / {} ms, \
                 rate {} Hz, debug {}, pins {}.{}.*",
                tx.section,
                tx.code.name(),
                tx.link.describe(),
                tx.slave,
                tx.first,
                tx.count(),
                tx.elements.join(","),
                tx.response_timeout.as_millis(),
                tx.byte_timeout.as_millis(),
                tx.max_update_rate,
                tx.debug,
                config.module_name,
                tx.hal_name
            );
        }
    }
    let exit = ExitSignals::install()?;
    let inst = match instance {
        Some(name) => Instance::attach(name)?,
        None => Instance::attach_default()?,
    };
    let comp = inst.new_component(&config.module_name, ComponentKind::User)?;
    let mut runners = Vec::new();
    for (link, txs) in &links {
        let mut with_pins = Vec::new();
        for &i in txs {
            let tx = &config.transactions[i];
            with_pins.push((tx.clone(), TxPins::new(&comp, &config.module_name, tx)?));
        }
        runners.push(LinkRunner::new(link, with_pins, config.slowdown));
    }
    comp.ready()?;
    let stop = Arc::new(AtomicBool::new(false));
    let mut threads = Vec::new();
    for (n, mut r) in runners.into_iter().enumerate() {
        let flag = stop.clone();
        let t = std::thread::Builder::new()
            .name(format!("mb2hal-link{n}"))
            .spawn(move || r.run(&flag))
            .map_err(|e| {
                SerialError::Hal(hal_core::HalError::Io {
                    op: "starting a link thread",
                    path: Default::default(),
                    source: e,
                })
            });
        match t {
            Ok(t) => threads.push(t),
            Err(e) => {
                stop.store(true, Relaxed);
                for t in threads {
                    let _ = t.join();
                }
                return Err(e);
            }
        }
    }
    if config.init_debug >= 1 {
        eprintln!("{NAME}: running");
    }
    while !exit.requested() && inst.host_alive() {
        std::thread::sleep(Duration::from_millis(20));
    }
    stop.store(true, Relaxed);
    for t in threads {
        if t.join().is_err() {
            eprintln!("{NAME}: a link thread failed");
        }
    }
    drop(comp);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(w: &[&str]) -> Vec<String> {
        w.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_command_line_takes_config_and_instance() {
        assert_eq!(
            parse_args(&words(&["config=/tmp/mb.ini", "--instance", "m1"])).unwrap(),
            Command::Run {
                config: "/tmp/mb.ini".into(),
                instance: Some("m1".into())
            }
        );
        assert_eq!(parse_args(&words(&["--help"])).unwrap(), Command::Help);
        assert_eq!(
            parse_args(&words(&["--version"])).unwrap(),
            Command::Version
        );
        let e = parse_args(&words(&["--no-such-option"])).unwrap_err();
        assert!(e.to_string().contains("'--no-such-option'"), "{e}");
        assert!(parse_args(&words(&[])).is_err());
        assert!(parse_args(&words(&["config="])).is_err());
        let e = parse_args(&words(&["--instance", "bad/name", "config=x"])).unwrap_err();
        assert!(e.to_string().contains("bad/name"), "{e}");
    }
}
