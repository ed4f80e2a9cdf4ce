//! `hy_vfd`'s command line, as LinuxCNC's program reads it.

use std::time::Duration;

use crate::error::{Result, SerialError};
use crate::line::{LineSettings, Parity};
use crate::modbus::MasterConfig;
use crate::opts::{self, Found, OptSpec};
use crate::vfd::{Parsed, SerialOptions, SERIAL_SPECS};

use super::NAME;

/// Speeds `-r` accepts.
pub const RATES: &[&str] = &[
    "110", "300", "600", "1200", "2400", "4800", "9600", "19200", "38400", "57600", "115200",
];

/// Most `-x` register writes.
pub const MAX_EXTRA_REGISTERS: usize = 10;

/// The command line.
#[derive(Debug, Clone, PartialEq)]
pub struct HyOptions {
    /// Device, line, address, timeouts; `-g` dumps frames.
    pub serial: SerialOptions,
    /// `-n`: the component's name.
    pub name: String,
    /// `-F`: PD005 to write, Hz (0: read it).
    pub max_freq: f64,
    /// `-f`: PD011 to write, Hz (0: read it).
    pub min_freq: f64,
    /// `-B`: PD004 to write, Hz (0: read it).
    pub base_freq: f64,
    /// `-V`: PD141 to write, V (0: read it).
    pub motor_voltage: f64,
    /// `-I`: PD142 to write, A (0: read it).
    pub motor_current: f64,
    /// `-S`: the motor's speed at the maximum frequency, rpm (0: from
    /// PD144).
    pub motor_speed: f64,
    /// `-P`: PD143 to write (0: read it).
    pub motor_poles: u32,
    /// `-x PDnnn=value`: parameters to write once enabled.
    pub registers: Vec<(u8, u16)>,
    /// `-y`: print PD001..PD183 when enabled.
    pub regdump: bool,
    /// `--period`: the loop's sleep (LinuxCNC: a fixed 0.1 s).
    pub period: Duration,
}

/// The usage text.
pub const USAGE: &str = "\
Usage: hy_vfd [OPTIONS]
Connects a Huanyang HY-series VFD to the HAL over its RS-485 protocol.
Options whose values come from a list take any unique beginning (--rate 5 is 57600).

Options:
  -d, --device PATH         serial device (default /dev/ttyS0); 'sim' for a simulated VFD
  -n, --name NAME           HAL component name, prefix of every pin (default hy_vfd)
  -r, --rate N              110 .. 115200 (default 19200; must match PD164)
  -b, --bits N              data bits, 5 to 8 (default 8; PD165)
  -p, --parity P            even, odd or none (default even; PD165)
  -s, --stopbits N          1 or 2 (default 1; PD165)
  -t, --target N            address of the VFD, 1 to 254 (default 1; PD163)
  -F, --max-frequency HZ    write PD005 (otherwise read it)
  -f, --min-frequency HZ    write PD011 (otherwise read it)
  -B, --base-frequency HZ   write PD004 (otherwise read it)
  -V, --motor-voltage V     write PD141 (otherwise read it)
  -I, --motor-current A     write PD142 (otherwise read it)
  -S, --motor-speed RPM     the motor's speed at the max frequency; writes PD144 (its speed at 50 Hz)
  -P, --motor-poles N       write PD143 (otherwise read it)
  -x, --register PDnnn=mmm  write a parameter once enabled (up to 10 times)
  -y, --regdump             print PD001..PD183 once enabled
  -g, --debug               print every frame in hex
      --period SECONDS      time between cycles, 0.001 to 1 (default 0.1)
      --response-timeout MS wait this long for a reply (default 100)
      --retries N           send a failed request again N times (default 2)
      --instance NAME       the HAL instance (default $HAL_INSTANCE, else 'default')
  -h, --help                print this help and exit
      --version             print the version and exit
";

const SPECS: &[OptSpec] = &[
    OptSpec::value('n', "name"),
    OptSpec::value('F', "max-frequency"),
    OptSpec::value('f', "min-frequency"),
    OptSpec::value('B', "base-frequency"),
    OptSpec::value('V', "motor-voltage"),
    OptSpec::value('I', "motor-current"),
    OptSpec::value('S', "motor-speed"),
    OptSpec::value('P', "motor-poles"),
    OptSpec::value('x', "register"),
    OptSpec::flag('y', "regdump"),
    OptSpec::flag('g', "debug"),
    OptSpec::long_value("period"),
    OptSpec::flag('h', "help"),
];

/// Checks a component name given with `-n`: HAL's character set, and
/// room for the longest pin suffix.
pub fn component_name(f: &Found) -> Result<String> {
    let v = opts::value(f);
    hal_core::name::validate("component", v).map_err(|e| opts::bad(f, e.to_string()))?;
    if v.len() > 200 {
        return Err(opts::bad(f, "longer than 200 characters"));
    }
    Ok(v.to_string())
}

/// `PDnnn=mmm`.
fn register(f: &Found) -> Result<(u8, u16)> {
    let v = opts::value(f);
    let parsed = v
        .strip_prefix("PD")
        .and_then(|r| r.split_once('='))
        .and_then(|(n, m)| Some((n.parse::<u8>().ok()?, m.parse::<u16>().ok()?)));
    parsed.ok_or_else(|| opts::bad(f, "expected PDnnn=value, nnn 0..255, value 0..65535"))
}

impl HyOptions {
    /// LinuxCNC's defaults: /dev/ttyS0 at 19 200 baud 8E1, address 1.
    pub fn defaults() -> HyOptions {
        HyOptions {
            serial: SerialOptions::new(
                LineSettings::new(19_200, Parity::Even),
                MasterConfig::default(),
            ),
            name: NAME.into(),
            max_freq: 0.0,
            min_freq: 0.0,
            base_freq: 0.0,
            motor_voltage: 0.0,
            motor_current: 0.0,
            motor_speed: 0.0,
            motor_poles: 0,
            registers: Vec::new(),
            regdump: false,
            period: Duration::from_millis(100),
        }
    }
}

/// Parses the command line (without the program name); None when help
/// was asked for.
pub fn parse_options(args: &[String]) -> Result<Parsed<HyOptions>> {
    let specs: Vec<OptSpec> = SERIAL_SPECS.iter().chain(SPECS).copied().collect();
    let mut o = HyOptions::defaults();
    let u16_max = f64::from(u16::MAX);
    for f in opts::parse(&specs, args)? {
        if o.serial.take(&f, RATES, 254)? {
            continue;
        }
        match f.long {
            "name" => o.name = component_name(&f)?,
            "max-frequency" => o.max_freq = opts::number(&f, 0.0, 655.35)?,
            "min-frequency" => o.min_freq = opts::number(&f, 0.0, 655.35)?,
            "base-frequency" => o.base_freq = opts::number(&f, 0.0, 400.0)?,
            "motor-voltage" => o.motor_voltage = opts::number(&f, 0.0, u16_max / 10.0)?,
            "motor-current" => o.motor_current = opts::number(&f, 0.0, u16_max / 10.0)?,
            "motor-speed" => o.motor_speed = opts::number(&f, 0.0, u16_max)?,
            "motor-poles" => o.motor_poles = opts::integer(&f, 0, 255)? as u32,
            "register" => {
                if o.registers.len() == MAX_EXTRA_REGISTERS {
                    return Err(opts::bad(&f, "too many direct register writes, max is 10"));
                }
                o.registers.push(register(&f)?);
            }
            "regdump" => o.regdump = true,
            "debug" => o.serial.master.debug = true,
            "period" => o.period = Duration::from_secs_f64(opts::number(&f, 0.001, 1.0)?),
            "version" => return Ok(Parsed::Version),
            _ => return Ok(Parsed::Help),
        }
    }
    if o.min_freq > 0.0 && o.max_freq > 0.0 && o.min_freq > o.max_freq {
        return Err(SerialError::Usage(format!(
            "min frequency ({}) must be less than max frequency ({})",
            o.min_freq, o.max_freq
        )));
    }
    Ok(Parsed::Run(o))
}
