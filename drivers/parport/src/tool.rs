//! The parallel-port bring-up tool's logic: open a port as hal_parport
//! would, show its inputs, drive its outputs, and check a loopback plug.

use std::sync::Arc;

use crate::cfg::{self, CfgError, Mode};
use crate::clock::{Clock, MonotonicClock};
use crate::driver::{Inputs, Outputs, PortDriver};
use crate::port::PortError;
use crate::regs::{pin_reg, PinReg, CONTROL_PINS};
use crate::select::{self, linux_ports, SysPaths};
use crate::sim::Plug;

/// An opened port with its driver.
pub struct Port {
    /// The driver over the opened backend.
    pub driver: PortDriver,
    /// The port's direction from the cfg string (`out`, `in`, `epp`, `x`).
    pub mode: Mode,
    /// Which backend and device were opened, as the tool prints it.
    pub description: String,
}

/// Opens the first port of a hal_parport cfg string (`"0"`,
/// `"0x378 x raw"`, `"0 simloop"`) and initialises it as the driver does.
pub fn open(spec: &str) -> Result<Port, PortError> {
    let specs = cfg::parse(spec)?;
    let spec = specs.first().ok_or(CfgError::Empty)?;
    let choice = select::choose(spec, &SysPaths::system())?;
    let clock: Arc<dyn Clock> = Arc::new(MonotonicClock);
    let opened = select::open(&choice, spec.mode, clock.clone())?;
    let description = opened.io.describe();
    let driver = PortDriver::new(spec.mode, opened.io, clock);
    driver.init()?;
    Ok(Port {
        driver,
        mode: spec.mode,
        description,
    })
}

/// Parses a `set` argument, `PIN=0` or `PIN=1`, for a port in `mode`:
/// the pin must be one of its outputs.
pub fn parse_level(arg: &str, mode: Mode) -> Result<(u8, bool), PortError> {
    let (pin, level) = arg.split_once('=').ok_or_else(|| PortError::NotPinLevel {
        arg: arg.to_string(),
    })?;
    let pin: u8 = pin.parse().map_err(|_| PortError::NotAPin {
        text: pin.to_string(),
    })?;
    if !is_output(mode, pin) {
        return Err(PortError::NotAnOutput {
            pin,
            mode: mode.name(),
        });
    }
    let high = match level {
        "1" => true,
        "0" => false,
        _ => {
            return Err(PortError::NotALevel {
                text: level.to_string(),
            })
        }
    };
    Ok((pin, high))
}

/// The ports Linux knows, one line each.
pub fn list() -> Vec<String> {
    let ports = linux_ports(&SysPaths::system());
    ports
        .iter()
        .map(|p| {
            let dev = format!("/dev/parport{}", p.num);
            let access = if std::path::Path::new(&dev).exists() {
                match std::fs::OpenOptions::new()
                    .read(true)
                    .write(true)
                    .open(&dev)
                {
                    Ok(_) => "usable",
                    Err(_) => "no permission (see udev/README.md)",
                }
            } else {
                "no device node (load ppdev)"
            };
            let hi = p
                .base_hi
                .map(|h| format!(", ECR base {h:#x}"))
                .unwrap_or_default();
            format!("parport{}: base {:#x}{hi}, {dev}: {access}", p.num, p.base)
        })
        .collect()
}

/// The level of input pin `pin` in a reading, if it is an input: status
/// pins always, data and control pins when the mode reads them.
pub fn input_level(inputs: &Inputs, pin: u8) -> Option<bool> {
    let bit = |byte: u8, b: u8| byte & (1 << b) != 0;
    match pin_reg(pin)? {
        PinReg::Status(b) => Some(bit(inputs.status, b)),
        PinReg::Data(b) => inputs.data.map(|d| bit(d, b)),
        PinReg::Control(b) => inputs.control.map(|c| bit(c, b)),
    }
}

/// The input pins of a mode, in DB-25 order.
pub fn input_pins(mode: Mode) -> Vec<u8> {
    (1..=17u8)
        .filter(|&p| match pin_reg(p) {
            Some(PinReg::Status(_)) => true,
            Some(PinReg::Data(_)) => !mode.data_out(),
            Some(PinReg::Control(_)) => mode.control_in(),
            None => false,
        })
        .collect()
}

/// Whether `pin` is an output in `mode`.
pub fn is_output(mode: Mode, pin: u8) -> bool {
    match pin_reg(pin) {
        Some(PinReg::Data(_)) => mode.data_out(),
        Some(PinReg::Control(_)) => !mode.control_in(),
        _ => false,
    }
}

/// Outputs with `levels` (pin, high) applied and every other output low.
pub fn outputs_for(levels: &[(u8, bool)]) -> Outputs {
    let mut o = Outputs::default();
    for &(pin, _) in levels.iter().filter(|(_, high)| *high) {
        match pin_reg(pin) {
            Some(PinReg::Data(b)) => o.data |= 1 << b,
            Some(PinReg::Control(b)) => o.control |= 1 << b,
            _ => {}
        }
    }
    o
}

/// One line showing every input of a reading.
pub fn format_inputs(mode: Mode, inputs: &Inputs) -> String {
    input_pins(mode)
        .into_iter()
        .map(|p| {
            format!(
                "{p:02}:{}",
                input_level(inputs, p).map_or('?', |h| if h { '1' } else { '0' })
            )
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The result of checking one wire of the loopback plug.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WireCheck {
    /// DB-25 pin number of the output.
    pub out_pin: u8,
    /// DB-25 pin number of the input wired to it.
    pub in_pin: u8,
    /// The input followed the output high and low.
    pub ok: bool,
}

/// Drives each output wired to an input through the test plug high and
/// low, alone, and checks that the input follows. Wires without an output
/// and an input in this mode are skipped.
pub fn selftest(port: &Port) -> Vec<WireCheck> {
    let mut results = Vec::new();
    for &(a, b) in Plug::loopback().wires() {
        let (out_pin, in_pin) = if is_output(port.mode, a) && input_pins(port.mode).contains(&b) {
            (a, b)
        } else if is_output(port.mode, b) && input_pins(port.mode).contains(&a) {
            (b, a)
        } else {
            continue;
        };
        let mut ok = true;
        for level in [true, false, true, false] {
            // Control lines idle high (released): on the plug they share
            // a net with a data pin, and a low one would hold it down.
            let mut levels: Vec<(u8, bool)> = CONTROL_PINS
                .iter()
                .filter(|&&p| p != out_pin && is_output(port.mode, p))
                .map(|&p| (p, true))
                .collect();
            levels.push((out_pin, level));
            port.driver.write(&outputs_for(&levels));
            std::thread::sleep(std::time::Duration::from_micros(50));
            ok &= input_level(&port.driver.read(), in_pin) == Some(level);
        }
        results.push(WireCheck {
            out_pin,
            in_pin,
            ok,
        });
    }
    port.driver.write(&Outputs::default());
    results
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pins_of_each_mode() {
        assert_eq!(input_pins(Mode::Out), [10, 11, 12, 13, 15]);
        assert_eq!(input_pins(Mode::X), [1, 10, 11, 12, 13, 14, 15, 16, 17]);
        assert_eq!(input_pins(Mode::In).len(), 13);
        assert!(is_output(Mode::Out, 1) && is_output(Mode::Out, 9) && !is_output(Mode::Out, 10));
        assert!(!is_output(Mode::X, 14) && !is_output(Mode::In, 5));
        let o = outputs_for(&[(2, true), (9, true), (14, true), (3, false)]);
        assert_eq!((o.data, o.control), (0x81, 0x02));
    }

    #[test]
    fn a_loopback_plug_passes_and_an_open_port_fails() {
        let port = open("0 out simloop").unwrap();
        let r = selftest(&port);
        assert_eq!(r.len(), 5, "{r:?}");
        assert!(r.iter().all(|w| w.ok), "{r:?}");
        let port = open("0 x simloop").unwrap();
        let r = selftest(&port);
        assert_eq!(r.len(), 9, "every wire is testable in x mode: {r:?}");
        assert!(r.iter().all(|w| w.ok), "{r:?}");
        // No plug: inputs float high and do not follow the outputs.
        let port = open("0 out sim").unwrap();
        assert!(selftest(&port).iter().all(|w| !w.ok));
    }

    #[test]
    fn bad_port_specs_are_refused() {
        assert!(matches!(open("zz"), Err(PortError::Cfg(_))));
        assert!(matches!(open(""), Err(PortError::Cfg(CfgError::Empty))));
    }

    #[test]
    fn set_arguments_name_what_is_wrong() {
        assert_eq!(parse_level("2=1", Mode::Out).unwrap(), (2, true));
        assert_eq!(parse_level("17=0", Mode::Out).unwrap(), (17, false));
        let message = |arg: &str, mode| parse_level(arg, mode).unwrap_err().to_string();
        assert_eq!(message("2", Mode::Out), "'2': expected PIN=0|1");
        assert_eq!(message("x=1", Mode::Out), "'x' is not a pin number");
        assert_eq!(
            message("10=1", Mode::Out),
            "pin 10 is not an output in out mode"
        );
        assert_eq!(
            message("2=1", Mode::In),
            "pin 2 is not an output in in mode"
        );
        assert_eq!(message("2=high", Mode::Out), "'high': use 0 or 1");
    }
}
