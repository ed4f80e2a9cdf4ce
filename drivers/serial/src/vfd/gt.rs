//! `hy_gt_vfd`: a Huanyang GT-series VFD over standard Modbus RTU, with
//! LinuxCNC's options and pins.
//!
//! ```text
//! loadusr -Wn spindle-vfd hy_gt_vfd -n spindle-vfd -d /dev/ttyUSB0 -S 24000 -F 400 -f 120
//! net spindle-speed spindle.0.speed-out => spindle-vfd.speed-cmd
//! net spindle-on    spindle.0.on        => spindle-vfd.spindle-on
//! net spindle-ready spindle-vfd.at-speed => spindle.0.at-speed
//! ```
//!
//! Each cycle writes the run command (register 0x1000: 1 forward, 5
//! stop) and the frequency (0x2000, in 1/100 % of `-F`), then reads the
//! status registers into pins, then sleeps `period-seconds`.
//!
//! Pin names follow LinuxCNC's program, which differs from its manual
//! page in two names: `period-seconds` (the page says `period`) and
//! `dc-bus-voltage` (`dc-bus-volts`). HAL files that run under LinuxCNC
//! use the program's names.
//!
//! Beyond LinuxCNC: a negative `speed-cmd` runs the spindle in reverse
//! (control value 2; LinuxCNC sends a garbage frequency); `-n` names the
//! component (LinuxCNC's is always `hy_gt_vfd`); the frequency is
//! clamped to `-f`..`-F`; writes come before reads, so at-speed uses
//! readings taken after the command; a drive that stops answering ends
//! the cycle at once instead of timing out on every register; the pins
//! `modbus-ok`, `fault` and `last-error`; `--response-timeout MS` and
//! `--retries N`; `-d sim` for a simulated drive.

use std::time::Duration;

use hal_core::{Component, In, Out, Pin};

use super::{options_or_exit, serve, Cycle, Link, SerialOptions, SERIAL_SPECS};
use crate::error::{Result, SerialError};
use crate::line::{LineSettings, Parity, SerialLine};
use crate::modbus::{Master, MasterConfig};
use crate::opts::{self, OptSpec};
use crate::regs::gt;
use crate::regs::modbus::READ_HOLDING_REGISTERS;
use crate::sim::{Protocol, VfdParams, VfdSim};

/// The program's and component's default name.
pub const NAME: &str = "hy_gt_vfd";

/// Speeds `-r` accepts.
pub const RATES: &[&str] = &["1200", "2400", "4800", "9600", "19200", "38400"];

/// At-speed tolerance, as a fraction of the command.
const AT_SPEED_TOLERANCE: f64 = 0.02;

/// The status registers read every cycle: address, pin, scale.
const READINGS: &[(u16, &str, f64)] = &[
    (gt::OUTPUT_FREQUENCY, "freq-fb", 0.01),
    (gt::DC_BUS_VOLTAGE, "dc-bus-voltage", 0.1),
    (gt::OUTPUT_VOLTAGE, "output-voltage", 1.0),
    (gt::OUTPUT_CURRENT, "output-current", 1.0),
    (gt::SPEED, "speed-fb", 1.0),
    (gt::OUTPUT_POWER, "output-power", 1.0),
    (gt::INPUT_TERMINAL, "input-terminal", 1.0),
    (gt::OUTPUT_TERMINAL, "output-terminal", 1.0),
    (gt::AI1, "AI1", 1.0),
    (gt::AI2, "AI2", 1.0),
    (gt::HDI_FREQUENCY, "HDI-frequency", 1.0),
    (gt::EXTERNAL_COUNTER, "external-counter", 1.0),
    (gt::FAULT_INFO, "fault-info", 1.0),
];

/// The command line.
#[derive(Debug, Clone, PartialEq)]
pub struct GtOptions {
    /// Device, line, address, timeouts.
    pub serial: SerialOptions,
    /// `-n`: the component's name.
    pub name: String,
    /// `-S`: motor speed at the maximum frequency, rpm.
    pub motor_max_speed: f64,
    /// `-F`: maximum frequency, Hz.
    pub max_freq: f64,
    /// `-f`: minimum frequency, Hz.
    pub min_freq: f64,
}

/// The usage text.
pub const USAGE: &str = "\
Usage: hy_gt_vfd [OPTIONS]
Connects a Huanyang GT-series VFD to the HAL over Modbus RTU.
Required:
  -S, --motor-max-speed RPM   motor speed at the maximum frequency (VFD P2.03)
  -F, --max-frequency HZ      maximum output frequency (VFD P0.03)
  -f, --min-frequency HZ      minimum output frequency (VFD P0.05)
Optional:
  -d, --device PATH           serial device (default /dev/ttyS0); 'sim' for a simulated VFD
  -r, --rate RATE             1200, 2400, 4800, 9600, 19200 or 38400 (default 38400)
  -b, --bits N                data bits, 5 to 8 (default 8)
  -p, --parity P              even, odd or none (default none)
  -s, --stopbits N            1 or 2 (default 1)
  -t, --target N              Modbus address of the VFD, 1 to 247 (default 1)
  -n, --name NAME             HAL component name (default hy_gt_vfd)
  -v, --verbose               print every frame
      --response-timeout MS   wait this long for a reply (default 100)
      --retries N             send a failed request again N times (default 5)
  -h, --help                  show this help
";

const SPECS: &[OptSpec] = &[
    OptSpec::value('S', "motor-max-speed"),
    OptSpec::value('F', "max-frequency"),
    OptSpec::value('f', "min-frequency"),
    OptSpec::value('n', "name"),
    OptSpec::flag('v', "verbose"),
    OptSpec::flag('h', "help"),
];

/// The default timing: LinuxCNC's five retries and ten characters of
/// silence between transactions (the GT manual is unclear between 3.5
/// bits and 3.5 characters).
pub fn default_master() -> MasterConfig {
    MasterConfig {
        retries: 5,
        gap_chars: 10.0,
        ..MasterConfig::default()
    }
}

/// Parses the command line (without the program name); None when help
/// was asked for.
pub fn parse_options(args: &[String]) -> Result<Option<GtOptions>> {
    let specs: Vec<OptSpec> = SERIAL_SPECS.iter().chain(SPECS).copied().collect();
    let mut o = GtOptions {
        serial: SerialOptions::new(LineSettings::new(38_400, Parity::None), default_master()),
        name: NAME.into(),
        motor_max_speed: 0.0,
        max_freq: 0.0,
        min_freq: 0.0,
    };
    for f in opts::parse(&specs, args)? {
        if o.serial.take(&f, RATES, 247)? {
            continue;
        }
        match f.long {
            "motor-max-speed" => o.motor_max_speed = positive(&f)?,
            "max-frequency" => o.max_freq = positive(&f)?,
            "min-frequency" => o.min_freq = positive(&f)?,
            "name" => o.name = super::hy::component_name(&f)?,
            "verbose" => o.serial.master.debug = true,
            _ => return Ok(None),
        }
    }
    for (v, opt) in [
        (o.motor_max_speed, "--motor-max-speed"),
        (o.max_freq, "--max-frequency"),
        (o.min_freq, "--min-frequency"),
    ] {
        if v == 0.0 {
            return Err(SerialError::Usage(format!("must specify {opt}")));
        }
    }
    if o.min_freq > o.max_freq {
        return Err(SerialError::Usage(format!(
            "min frequency ({}) must be less than max frequency ({})",
            o.min_freq, o.max_freq
        )));
    }
    Ok(Some(o))
}

fn positive(f: &opts::Found) -> Result<f64> {
    let v = opts::number(f, 0.0, 1e6)?;
    if v == 0.0 {
        return Err(opts::bad(f, "must not be zero"));
    }
    Ok(v)
}

/// A simulated GT drive set up as the options say (P0.03 = `-F`, P0.05
/// = `-f`, P2.03 = `-S`).
pub fn sim_drive(o: &GtOptions) -> VfdSim {
    let mut sim = VfdSim::new(Protocol::ModbusGt, o.serial.slave, o.serial.settings);
    let params = VfdParams {
        max_freq_hz: o.max_freq,
        min_freq_hz: o.min_freq,
        base_freq_hz: o.max_freq,
        rpm_at_max_freq: o.motor_max_speed,
        ..VfdParams::default()
    };
    sim.model_mut().set_params(params);
    sim
}

/// The HAL side.
struct GtPins {
    period: Pin<f64, In>,
    speed_cmd: Pin<f64, In>,
    freq_cmd: Pin<f64, Out>,
    at_speed: Pin<bool, Out>,
    spindle_on: Pin<bool, In>,
    modbus_errors: Pin<u32, Out>,
    readings: Vec<Pin<f64, Out>>,
    /// `fault-info-code` (LinuxCNC 2.10): 0x5000 as a number, beside the
    /// float `fault-info`.
    fault_info_code: Pin<u32, Out>,
}

/// The component: options, pins, the master, the link's health.
pub struct GtVfd<L: SerialLine> {
    opts: GtOptions,
    pins: GtPins,
    master: Master<L>,
    link: Link,
}

/// Index of `speed-fb` and `fault-info` in [`READINGS`].
const SPEED_FB: usize = 4;
const FAULT_INFO: usize = 12;

impl<L: SerialLine> GtVfd<L> {
    /// Exports the pins on `comp` and takes the line.
    pub fn new(comp: &Component, opts: GtOptions, line: L) -> hal_core::Result<GtVfd<L>> {
        let p = |n: &str| format!("{}.{n}", opts.name);
        let pins = GtPins {
            period: comp.pin_init(&p("period-seconds"), 0.1)?,
            speed_cmd: comp.pin(&p("speed-cmd"))?,
            freq_cmd: comp.pin(&p("freq-cmd"))?,
            at_speed: comp.pin(&p("at-speed"))?,
            spindle_on: comp.pin(&p("spindle-on"))?,
            modbus_errors: comp.pin(&p("modbus-errors"))?,
            readings: READINGS
                .iter()
                .map(|(_, name, _)| comp.pin(&p(name)))
                .collect::<hal_core::Result<_>>()?,
            fault_info_code: comp.pin(&p("fault-info-code"))?,
        };
        let link = Link::new(comp, &opts.name)?;
        let master = Master::new(line, opts.serial.master);
        Ok(GtVfd {
            opts,
            pins,
            master,
            link,
        })
    }

    /// The master (tests reach the line through it).
    pub fn master_mut(&mut self) -> &mut Master<L> {
        &mut self.master
    }

    fn slave(&self) -> u8 {
        self.opts.serial.slave
    }

    /// Sends the run command and the frequency for the pins' state;
    /// returns false when the drive was not heard.
    fn command(&mut self) -> bool {
        let speed = self.pins.speed_cmd.get();
        let on = self.pins.spindle_on.get();
        let (control, freq) = if on {
            let hz = (speed.abs() / self.opts.motor_max_speed * self.opts.max_freq)
                .clamp(self.opts.min_freq, self.opts.max_freq);
            let hz = if hz.is_finite() {
                hz
            } else {
                self.opts.min_freq
            };
            let dir = if speed < 0.0 {
                gt::RUN_REVERSE
            } else {
                gt::RUN_FORWARD
            };
            (dir, hz.copysign(if speed < 0.0 { -1.0 } else { 1.0 }))
        } else {
            (gt::STOP, 0.0)
        };
        self.pins.freq_cmd.set(freq);
        let slave = self.slave();
        let r = self.master.write_register(slave, gt::CONTROL, control);
        if !self.check(r) {
            return false;
        }
        if on {
            let value = (freq.abs() / self.opts.max_freq * f64::from(gt::FREQUENCY_FULL_SCALE))
                .round()
                .min(f64::from(gt::FREQUENCY_FULL_SCALE)) as u16;
            let r = self.master.write_register(slave, gt::FREQUENCY, value);
            if !self.check(r) {
                return false;
            }
        }
        true
    }

    /// Notes a failure; false when the cycle should end (the drive was
    /// not heard, so the next requests would only wait too).
    fn check<T>(&mut self, r: Result<T>) -> bool {
        match r {
            Ok(_) => true,
            Err(e) => {
                self.link.failed(&e);
                !self.link.lost()
            }
        }
    }

    /// Reads the status registers into their pins.
    fn read_status(&mut self) {
        let slave = self.slave();
        for (i, &(address, _, scale)) in READINGS.iter().enumerate() {
            let r = self
                .master
                .read_registers(slave, READ_HOLDING_REGISTERS, address, 1);
            match r {
                Ok(v) => {
                    self.pins.readings[i].set(f64::from(v[0]) * scale);
                    if i == FAULT_INFO {
                        // LinuxCNC reads the register a second time for
                        // this pin; one read serves both, so they agree.
                        self.pins.fault_info_code.set(u32::from(v[0]));
                    }
                }
                Err(e) => {
                    self.link.failed(&e);
                    if self.link.lost() {
                        return;
                    }
                }
            }
        }
    }

    fn update_at_speed(&mut self) {
        let cmd = self.pins.speed_cmd.get().abs();
        let fb = self.pins.readings[SPEED_FB].get();
        let at = self.link.ok()
            && self.pins.spindle_on.get()
            && cmd > 0.0
            && ((cmd - fb).abs() / cmd) < AT_SPEED_TOLERANCE;
        self.pins.at_speed.set(at);
    }
}

impl<L: SerialLine> Cycle for GtVfd<L> {
    fn cycle(&mut self) {
        self.link.begin_cycle();
        if self.command() {
            self.read_status();
        }
        let fault = if self.link.lost() {
            0
        } else {
            self.pins.readings[FAULT_INFO].get() as u32
        };
        if self.link.lost() {
            // Outputs safe before the fault pin says why.
            self.pins.at_speed.set(false);
        }
        self.link.end_cycle(fault);
        self.update_at_speed();
        let st = self.master.stats();
        self.pins
            .modbus_errors
            .set((st.failed + st.retries).min(u64::from(u32::MAX)) as u32);
    }

    fn period(&self) -> Duration {
        let p = self.pins.period.get();
        Duration::from_secs_f64(if p.is_finite() {
            p.clamp(0.001, 2.0)
        } else {
            0.1
        })
    }

    fn shutdown(&mut self) {
        let slave = self.slave();
        let _ = self.master.write_register(slave, gt::CONTROL, gt::STOP);
    }
}

/// The program: parses `args` (with the program name first), opens the
/// line, attaches to the HAL instance and runs until told to stop.
/// Returns the exit status.
pub fn main(args: &[String]) -> i32 {
    let parsed = parse_options(args.get(1..).unwrap_or(&[]));
    let o = match options_or_exit(NAME, USAGE, parsed) {
        Ok(o) => o,
        Err(status) => return status,
    };
    let banner = format!(
        "{}: device='{}', {}, address={}",
        o.name, o.serial.device, o.serial.settings, o.serial.slave
    );
    serve(
        NAME,
        &o.name,
        &o.serial,
        Some(banner),
        || sim_drive(&o),
        |comp, line| GtVfd::new(comp, o.clone(), line),
    )
}
