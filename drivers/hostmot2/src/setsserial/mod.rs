//! `setsserial`: sets a Smart Serial remote's non-volatile parameter or
//! flashes its firmware, on a board a hostmot2 driver has loaded
//! (LinuxCNC's `setsserial`):
//!
//! ```text
//! loadrt hostmot2 use_serial_numbers=1
//! loadrt hm2_pci config="firmware=hm2/5i23/svss8_8.bit"
//! loadrt setsserial cmd="set hm2_8i20.001f.nvmaxcurrent 750"
//! ```
//!
//! The remote is named as the driver names its objects
//! (`hm2_5i23.0.8i20.0.1`, or `hm2_8i20.001f` by unit number; either
//! form is found whatever `use_serial_numbers` says), the parameter by
//! the name of the remote's global after it (`nvmaxcurrent`), the value
//! in decimal or `0x` hex (a float global takes a decimal number). The
//! new value is in the remote's EEPROM: the driver's param shows it
//! after the board is loaded again.
//!
//! `flash <remote> <file>.BIN` writes a remote firmware file found
//! under the firmware directory (`/lib/firmware`, or `firmware_dir=`)
//! into the remote's flash. It needs hostmot2 loaded with
//! `sserial_baudrate=115200`, which puts discovery in setup mode (any
//! Mesa remote is found, none is started), and Smart Serial firmware
//! version 34 on the FPGA (37 for an 8I20). Progress is logged per block.
//!
//! # Loading, and what stays loaded
//!
//! LinuxCNC's setsserial always fails to load, on purpose, so that it
//! never stays loaded. Here the load succeeds when the command did and
//! fails with what went wrong and at which step otherwise; either way it
//! makes no component, pin, function or thread, and holds nothing. The
//! host lists the module as loaded after a success (it records every
//! successful `loadrt`); `unloadrt setsserial` clears that before the
//! next command.
//!
//! The command runs with the board's lock held, so its functions skip
//! their cycles meanwhile; its Smart Serial ports are stopped and put
//! back to idle, and those whose `run` is TRUE start again at the next
//! `write`.

pub mod command;
pub mod flash;
pub mod ops;

use std::io::Read;
use std::path::{Path, PathBuf};

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl};
use hal_core::HalError;
use hal_driver::module::{self, DriverHost, DriverModule, Exporter, LoadEnv};

use crate::error::{Hm2Error, Result};
use crate::modules::sserial::discovery::{RemoteFound, SserialFirmware};
use crate::modules::sserial::remote_prefix;
use crate::registry::{self, SserialAccess};
use crate::sserial::records::{data_type as dt, DataRecord};
use crate::sserial::{access, legacy};
use command::Command;
use ops::Channel;

const SETSSERIAL: &str = "setsserial";

/// Largest remote firmware file read.
pub const MAX_BIN_BYTES: u64 = 1 << 20;

/// setsserial's module parameters (one table, read by both hosts).
#[macro_export]
macro_rules! setsserial_params {
    ($($then:tt)*) => { $($then)*! {
        cmd: Str = "\"set <remote>.<parameter> <value>\" or \"flash <remote> <file>.BIN\"",
        firmware_dir: Str = "where flash finds its file (default /lib/firmware)",
    } };
}

/// The `setsserial` module.
#[derive(Debug)]
pub struct HalSetsserial;

/// The `setsserial` module.
pub static SETSSERIAL_MODULE: ModuleDef = module::module_def::<HalSetsserial>();

impl DriverModule for HalSetsserial {
    const NAME: &'static str = SETSSERIAL;
    const HELP: &'static str =
        "sets a Smart Serial remote's EEPROM parameter or flashes its firmware (hostmot2 loaded first)";
    const PARAMS: &'static [ParamDecl] = setsserial_params!(hal_driver::param_table);
    type Opened = ();

    fn open(args: &ModuleArgs, env: &LoadEnv) -> hal_core::Result<()> {
        let core = crate::hal::core(env, SETSSERIAL)?;
        let dir = args
            .str("firmware_dir")
            .filter(|d| !d.is_empty())
            .map_or_else(|| PathBuf::from(crate::fpga::FIRMWARE_DIR), PathBuf::from);
        let log = env.log();
        let cmd = args.str("cmd").unwrap_or("");
        let done = run(env.instance(), cmd, core.sserial_baudrate, &dir, &mut |m| {
            log.info(format_args!("setsserial: {m}"))
        });
        match done {
            Ok(what) => {
                log.info(format_args!("setsserial: {what}"));
                Ok(())
            }
            Err(e) => {
                log.err(format_args!("{e}"));
                Err(HalError::module_failed(SETSSERIAL, e))
            }
        }
    }

    fn export<H: DriverHost>(_: (), _: &mut Exporter<'_, H>) -> hal_core::Result<()> {
        Ok(())
    }
}

/// A remote found by name on a registered board.
struct Found {
    board: std::sync::Arc<dyn SserialAccess>,
    name: String,
    /// Both HAL names (by place, by unit number).
    names: [String; 2],
    port: u8,
    remote: RemoteFound,
}

/// The HAL names of `r` on `port` of `board`: by board, port and
/// channel, and by unit number.
fn names(board: &str, r: &RemoteFound, port: u8) -> [String; 2] {
    [
        remote_prefix(board, r, port, false),
        remote_prefix(board, r, port, true),
    ]
}

/// Every remote of HAL `instance`'s boards.
fn remotes(instance: &str) -> Vec<Found> {
    let mut v = Vec::new();
    for (board_name, board) in registry::boards_of(instance) {
        let Some(fw) = board.sserial() else { continue };
        for p in &fw.ports {
            for r in &p.remotes {
                let names = names(&board_name, r, p.index);
                v.push(Found {
                    board: board.clone(),
                    name: names[0].clone(),
                    names,
                    port: p.index,
                    remote: r.clone(),
                });
            }
        }
    }
    v
}

/// The remote `wanted` names: itself, or a prefix of it followed by a
/// dot when `with_rest` (its parameter follows); the rest after the dot.
fn find(instance: &str, wanted: &str, with_rest: bool) -> Result<(Found, String)> {
    let mut all = remotes(instance);
    let hit = all.iter().enumerate().find_map(|(i, f)| {
        f.names.iter().find_map(|n| {
            let rest = if with_rest {
                wanted.strip_prefix(n.as_str())?.strip_prefix('.')?
            } else if wanted == n {
                ""
            } else {
                return None;
            };
            Some((i, rest.to_string()))
        })
    });
    if let Some((i, rest)) = hit {
        return Ok((all.swap_remove(i), rest));
    }
    let known: Vec<&str> = all.iter().map(|f| f.name.as_str()).collect();
    Err(Hm2Error::NoSuchRemote {
        name: wanted.to_string(),
        known: if known.is_empty() {
            "none".into()
        } else {
            known.join(", ")
        },
    })
}

/// Runs `cmd` on HAL `instance`'s boards; what it did, or why not.
pub fn run(
    instance: &str,
    cmd: &str,
    baud: Option<u32>,
    firmware_dir: &Path,
    say: &mut dyn FnMut(String),
) -> Result<String> {
    match command::parse(cmd)? {
        Command::Set { target, value } => set(instance, &target, &value),
        Command::Flash { remote, file } => {
            if baud != Some(crate::modules::sserial::discovery::SETUP_BAUD) {
                return Err(Hm2Error::FlashNeedsSetupMode { baud });
            }
            let (found, _) = find(instance, &remote, false)?;
            let path = bin_path(firmware_dir, &file)?;
            let image = read_bin(&path)?;
            flash_remote(found, &image, say)
        }
    }
}

/// Sets `<remote>.<global>` to `value`.
fn set(instance: &str, target: &str, value: &str) -> Result<String> {
    let (found, global) = find(instance, target, true)?;
    let (rec, _) = found
        .remote
        .globals
        .iter()
        .find(|(g, _)| found.remote.hal_name(g).eq_ignore_ascii_case(&global))
        .ok_or_else(|| Hm2Error::NoSuchGlobal {
            remote: found.name.clone(),
            global: global.clone(),
            known: found
                .remote
                .globals
                .iter()
                .map(|(g, _)| found.remote.hal_name(g))
                .reduce(|a, b| format!("{a}, {b}"))
                .unwrap_or_else(|| "none".into()),
        })?;
    let writable = if rec.is_out() {
        Ok(())
    } else {
        Err(ValueProblem::ReadOnly)
    };
    let raw = writable
        .and_then(|()| raw_value(rec, value))
        .map_err(|reason| Hm2Error::BadGlobalValue {
            remote: found.name.clone(),
            global: global.clone(),
            value: value.to_string(),
            reason,
        })?;
    let name = found.name.clone();
    let (addr, bits) = (rec.addr, rec.bits);
    on_channel(&found, &mut |ch| {
        let step = |s: &'static str| {
            let name = name.clone();
            move |e| Hm2Error::SetsserialStep {
                remote: name,
                step: s.to_string(),
                source: Box::new(e),
            }
        };
        ch.start_setup().map_err(step("setup start"))?;
        ch.access(access::EEPROM).map_err(step("NV access on"))?;
        let wrote = ch
            .write_value(addr, bits, raw)
            .map_err(step("writing the value"));
        // Back to RAM even when the write failed.
        let off = ch.access(access::RAM).map_err(step("NV access off"));
        wrote?;
        off?;
        ch.stop_all().map_err(step("stop"))
    })?;
    Ok(format!(
        "{name}.{global} set to {value} in the remote's EEPROM (reload the board to see it)"
    ))
}

/// Why a value cannot be written to a global.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ValueProblem {
    /// The remote only reports the global.
    #[error("the remote only reports this parameter")]
    ReadOnly,
    /// A float global and no finite number.
    #[error("not a finite number")]
    NotFinite,
    /// A float global of a width other than 32 or 64 bits.
    #[error("a float of {bits} bits cannot be written")]
    FloatWidth {
        /// The global's width.
        bits: u32,
    },
    /// An integer global and no integer.
    #[error("not a decimal or 0x hex integer")]
    NotInteger,
    /// An integer the global's width and sign cannot hold.
    #[error("outside {}..={} ({bits} bits)", range_of(*signed, *bits).0, range_of(*signed, *bits).1)]
    OutOfRange {
        /// Whether the global is signed.
        signed: bool,
        /// The global's width (1 to 64).
        bits: u32,
    },
}

/// The values a global of `bits` bits takes.
fn range_of(signed: bool, bits: u32) -> (i128, i128) {
    let bits = bits.clamp(1, 64);
    if signed {
        (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
    } else {
        (0, (1i128 << bits) - 1)
    }
}

/// The raw bits `value` gives global `r`.
fn raw_value(r: &DataRecord, value: &str) -> std::result::Result<u64, ValueProblem> {
    let bits = r.bits.clamp(1, 64) as u32;
    if matches!(r.data_type, dt::FLOAT | dt::NV_FLOAT) {
        let v: f64 = value
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or(ValueProblem::NotFinite)?;
        return match bits {
            32 => Ok((v as f32).to_bits() as u64),
            64 => Ok(v.to_bits()),
            bits => Err(ValueProblem::FloatWidth { bits }),
        };
    }
    let v = command::parse_int(value).ok_or(ValueProblem::NotInteger)?;
    let signed = matches!(r.data_type, dt::SIGNED | dt::NV_SIGNED);
    let (lo, hi) = range_of(signed, bits);
    if !(lo..=hi).contains(&v) {
        return Err(ValueProblem::OutOfRange { signed, bits });
    }
    let mask = if bits == 64 {
        u64::MAX
    } else {
        (1u64 << bits) - 1
    };
    Ok(v as u64 & mask)
}

/// Runs `job` on the channel of `found`, on its board.
fn on_channel(found: &Found, job: &mut dyn FnMut(&mut Channel<'_>) -> Result<()>) -> Result<()> {
    let mut out = None;
    let (port, chan, mode) = (found.port, found.remote.channel, found.remote.mode);
    let ran = found.board.setup_job(&mut |t, fw: &SserialFirmware| {
        let mut ch = Channel {
            t,
            md: fw.md,
            port,
            chan,
            mode,
        };
        out = Some(job(&mut ch));
    });
    match out {
        Some(r) if ran => r,
        _ => Err(Hm2Error::NoSuchRemote {
            name: found.name.clone(),
            known: "its board has no Smart Serial module any more".into(),
        }),
    }
}

/// Flashes `image` into `found`.
fn flash_remote(found: Found, image: &[u8], say: &mut dyn FnMut(String)) -> Result<String> {
    let is_8i20 = found.remote.raw_name.to_le_bytes() == legacy::EIGHT_I20;
    let needed = if is_8i20 { 37 } else { 34 };
    let name = found.name.clone();
    let port = found.port;
    let mut done = None;
    on_channel(&found, &mut |ch| {
        let version = ch.sslbp_version().map_err(|e| Hm2Error::SetsserialStep {
            remote: name.clone(),
            step: "reading the Smart Serial firmware version".into(),
            source: Box::new(e),
        })?;
        if version < needed {
            return Err(Hm2Error::SslbpTooOld {
                remote: name.clone(),
                port,
                version,
                needed,
            });
        }
        let r = flash::flash(ch, &name, image, say);
        // Stop the port whatever happened: the remote restarts at the
        // next load.
        let _ = ch.stop_all();
        done = Some(r?);
        Ok(())
    })?;
    let d = done.ok_or_else(|| Hm2Error::NoSuchRemote {
        name: name.clone(),
        known: "the board did not run the command".into(),
    })?;
    Ok(format!(
        "{name}: flashed {} bytes: {} blocks of {} bytes written, {} empty ones skipped (reload the board to run the new firmware)",
        image.len(),
        d.written,
        d.erase_size,
        d.skipped
    ))
}

/// The path of `file` under `dir`, as `firmware=` resolves names.
fn bin_path(dir: &Path, file: &str) -> Result<PathBuf> {
    crate::fpga::resolve(dir, file).map_err(|e| Hm2Error::RemoteFirmwareFile {
        path: dir.join(file),
        reason: e.to_string(),
    })
}

/// Reads the regular file at `path`, at most [`MAX_BIN_BYTES`].
pub fn read_bin(path: &Path) -> Result<Vec<u8>> {
    use std::os::unix::fs::OpenOptionsExt;
    let bad = |reason: String| Hm2Error::RemoteFirmwareFile {
        path: path.to_path_buf(),
        reason,
    };
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(nix::fcntl::OFlag::O_NONBLOCK.bits())
        .open(path)
        .map_err(|e| bad(e.to_string()))?;
    if !file.metadata().map_err(|e| bad(e.to_string()))?.is_file() {
        return Err(bad("not a regular file".into()));
    }
    let mut bytes = Vec::new();
    file.take(MAX_BIN_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| bad(e.to_string()))?;
    if bytes.len() as u64 > MAX_BIN_BYTES {
        return Err(bad(format!("larger than {MAX_BIN_BYTES} bytes")));
    }
    if bytes.is_empty() {
        return Err(bad("empty".into()));
    }
    Ok(bytes)
}
