//! The values behind hm2_modbus's HAL pins: what the realtime function
//! reads from its input pins before a period and writes to its output
//! pins after it. Kept apart from HAL so the engine runs in tests as it
//! runs in a HAL.

use super::mbccb::{pinf, Command, HalType, PinSpec};
use super::rtu;
use super::values::{self, Value};

/// One data pin of a command, with its scaling pins.
#[derive(Debug, Clone, PartialEq)]
pub struct DataPin {
    /// From the file.
    pub spec: PinSpec,
    /// An output pin (read functions) or an input pin (write functions).
    pub output: bool,
    /// The pin.
    pub value: Value,
    /// `<name>.offset` (in), if the pin has scaling.
    pub offset: Option<Value>,
    /// `<name>.scale` (in), if the pin has scaling; starts at 1.0.
    pub scale: Option<f64>,
    /// `<name>.scaled` (out), read pins with scaling only.
    pub scaled: Option<f64>,
}

impl DataPin {
    /// The pin `spec` of a command with function `func`.
    pub fn new(spec: &PinSpec, func: u8) -> DataPin {
        let output = matches!(
            func,
            rtu::R_COILS | rtu::R_INPUTS | rtu::R_REGISTERS | rtu::R_INPUTREGS
        );
        let scaling = spec.flags & pinf::SCALE != 0
            && matches!(spec.htype, HalType::Float | HalType::S32 | HalType::S64)
            && !matches!(
                func,
                rtu::R_COILS | rtu::R_INPUTS | rtu::W_COIL | rtu::W_COILS
            );
        DataPin {
            spec: spec.clone(),
            output,
            value: Value::zero(spec.htype),
            offset: scaling.then(|| Value::zero(values::offset_type(spec, output))),
            scale: scaling.then_some(1.0),
            scaled: (scaling && output).then_some(0.0),
        }
    }

    /// The offset and scale to apply (0 and 1 without scaling pins).
    pub fn scaling(&self) -> (Value, f64) {
        (
            self.offset.unwrap_or(Value::Bit(false)),
            self.scale.unwrap_or(1.0),
        )
    }
}

/// The pins of one command: `hm2_modbus.N.command.MM.*`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CommandPins {
    /// `disable` (in): disables the command on a rising edge.
    pub disable: bool,
    /// `disabled` (out).
    pub disabled: bool,
    /// `reset` (in): clears the errors and re-enables on a rising edge.
    pub reset: bool,
    /// `errors` (out): consecutive errors.
    pub errors: u32,
    /// `error-code` (out): errno of the last error.
    pub error_code: u32,
}

/// The instance's own pins and parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GlobalPins {
    /// `suspend` (in).
    pub suspend: bool,
    /// `reset` (in).
    pub reset: bool,
    /// `fault` (out).
    pub fault: bool,
    /// `fault-command` (out).
    pub fault_command: u32,
    /// `last-error-code` (out).
    pub last_error_code: u32,
}

/// All data pins of a file's commands, in order, and where each
/// command's first pin is.
pub fn data_pins(commands: &[Command]) -> (Vec<DataPin>, Vec<usize>) {
    let mut pins = Vec::new();
    let mut first = Vec::with_capacity(commands.len());
    for c in commands {
        first.push(pins.len());
        pins.extend(c.pins.iter().map(|p| DataPin::new(p, c.func)));
    }
    (pins, first)
}
