//! The module parameters: which lines, in which direction, with which
//! electrical settings.
//!
//! LinuxCNC's lists, each comma-separated line names as `gpioinfo` prints
//! them (case-sensitive, up to 128 names each): `inputs=`, `outputs=`,
//! `invert=`, `reset=`, `opendrain=`, `opensource=`, `biasdisable=`,
//! `pulldown=`, `pullup=`. Every name in the modifier lists must be one
//! of the lines in `inputs=` or `outputs=`. Empty items (a trailing comma)
//! are ignored.
//!
//! Refused, each with the list and the name: a line listed twice or as
//! both input and output; `invert`, `reset`, `opendrain` or `opensource`
//! on a line that is not an output (LinuxCNC documents them as outputs
//! only); open drain together with open source; more than one bias flag
//! on a line; no lines at all.

use hal_driver::params::Params;
use hal_driver::DriverError;

use crate::error::GpioError;

/// The most names a list takes (LinuxCNC's limit).
pub const MAX_NAMES: usize = 128;

/// Input or output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    /// `inputs=`.
    Input,
    /// `outputs=`.
    Output,
}

/// How an output drives its pin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Drive {
    /// Drives both levels (the default).
    #[default]
    PushPull,
    /// `opendrain=`: drives low, floats high.
    OpenDrain,
    /// `opensource=`: drives high, floats low.
    OpenSource,
}

/// The line's internal bias.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bias {
    /// Left as the chip has it (the default).
    #[default]
    AsIs,
    /// `biasdisable=`.
    Disabled,
    /// `pullup=`.
    PullUp,
    /// `pulldown=`.
    PullDown,
}

/// One line as the parameters describe it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LineSpec {
    /// The line's name, as `gpioinfo` prints it.
    pub name: String,
    /// Its item number in `inputs=` or `outputs=`, for messages.
    pub item: usize,
    /// Input or output.
    pub direction: Direction,
    /// `invert=`: the HAL value is the inverse of the electrical level.
    pub invert: bool,
    /// `reset=`: `hal_gpio.reset` returns it to its inactive level.
    pub reset: bool,
    /// Push-pull, open drain or open source.
    pub drive: Drive,
    /// Internal bias.
    pub bias: Bias,
}

/// Every line, inputs first, each list in the order given.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Config {
    /// The lines.
    pub lines: Vec<LineSpec>,
}

impl Config {
    /// The lines of one direction, in order.
    pub fn of(&self, direction: Direction) -> impl Iterator<Item = &LineSpec> {
        self.lines.iter().filter(move |l| l.direction == direction)
    }

    /// Whether any output is in `reset=`.
    pub fn has_reset(&self) -> bool {
        self.lines.iter().any(|l| l.reset)
    }

    /// The line called `name`.
    pub fn line(&self, name: &str) -> Option<&LineSpec> {
        self.lines.iter().find(|l| l.name == name)
    }
}

/// The list parameters in LinuxCNC's order, for the module's table.
pub const LISTS: [&str; 9] = [
    "inputs",
    "outputs",
    "invert",
    "reset",
    "opendrain",
    "opensource",
    "biasdisable",
    "pulldown",
    "pullup",
];

/// The non-empty items of list `param`, with their item numbers.
fn items<'a>(args: &'a hal_core::ModuleArgs, param: &str) -> Vec<(usize, &'a str)> {
    args.str_array(param)
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.is_empty())
        .map(|(i, s)| (i, s.as_str()))
        .collect()
}

/// Reads the lists from `args` (parsed against the module's table).
pub fn parse(module: &'static str, args: &hal_core::ModuleArgs) -> Result<Config, DriverError> {
    let p = Params::new(module, args);
    let mut cfg = Config::default();
    for (param, direction) in [("inputs", Direction::Input), ("outputs", Direction::Output)] {
        for (i, name) in items(args, param) {
            if let Some(prev) = cfg.line(name) {
                let why = if prev.direction == direction {
                    format!("listed twice in {param}=")
                } else {
                    "listed in both inputs= and outputs=".to_string()
                };
                return Err(p.item_error(param, i, name, why));
            }
            cfg.lines.push(LineSpec {
                name: name.to_string(),
                item: i,
                direction,
                invert: false,
                reset: false,
                drive: Drive::PushPull,
                bias: Bias::AsIs,
            });
        }
    }
    if cfg.lines.is_empty() {
        return Err(p.error(
            "inputs",
            "no lines given: list line names in inputs= and/or outputs=",
        ));
    }
    for param in &LISTS[2..] {
        let mut seen: Vec<&str> = Vec::new();
        for (i, name) in items(args, param) {
            if seen.contains(&name) {
                return Err(p.item_error(param, i, name, format!("listed twice in {param}=")));
            }
            seen.push(name);
            let Some(line) = cfg.lines.iter_mut().find(|l| l.name == name) else {
                return Err(p.item_error(param, i, name, "not a line of inputs= or outputs="));
            };
            apply(line, param).map_err(|why| p.item_error(param, i, name, why))?;
        }
    }
    Ok(cfg)
}

/// Applies modifier list `param` to `line`.
fn apply(line: &mut LineSpec, param: &str) -> Result<(), GpioError> {
    let output_only = matches!(param, "invert" | "reset" | "opendrain" | "opensource");
    if output_only && line.direction != Direction::Output {
        return Err(GpioError::OutputOnly {
            param: param.to_string(),
        });
    }
    let bias = |line: &mut LineSpec, b: Bias| {
        if line.bias != Bias::AsIs {
            return Err(GpioError::TwoBiases {
                first: bias_param(line.bias),
                second: param.to_string(),
            });
        }
        line.bias = b;
        Ok(())
    };
    let drive = |line: &mut LineSpec, d: Drive| {
        if line.drive != Drive::PushPull {
            return Err(GpioError::TwoDrives);
        }
        line.drive = d;
        Ok(())
    };
    match param {
        "invert" => line.invert = true,
        "reset" => line.reset = true,
        "opendrain" => drive(line, Drive::OpenDrain)?,
        "opensource" => drive(line, Drive::OpenSource)?,
        "biasdisable" => bias(line, Bias::Disabled)?,
        "pulldown" => bias(line, Bias::PullDown)?,
        "pullup" => bias(line, Bias::PullUp)?,
        other => {
            return Err(GpioError::UnknownList {
                param: other.to_string(),
            })
        }
    }
    Ok(())
}

/// The parameter that sets bias `b`.
fn bias_param(b: Bias) -> &'static str {
    match b {
        Bias::AsIs => "none",
        Bias::Disabled => "biasdisable",
        Bias::PullUp => "pullup",
        Bias::PullDown => "pulldown",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_core::module::{ModuleArgs, ParamDecl, ParamKind};

    fn decls() -> Vec<ParamDecl> {
        LISTS
            .iter()
            .map(|n| ParamDecl {
                name: n,
                kind: ParamKind::StrArray(MAX_NAMES),
                help: "",
            })
            .collect()
    }

    fn parse_args(a: &[&str]) -> hal_core::Result<Config> {
        let decls: &'static [ParamDecl] = Box::leak(decls().into_boxed_slice());
        let args = ModuleArgs::parse("hal_gpio", decls, a)?;
        parse("hal_gpio", &args).map_err(|e| e.into_hal("hal_gpio"))
    }

    #[test]
    fn the_documented_example() {
        let c = parse_args(&[
            "inputs=GPIO5,GPIO6",
            "outputs=GPIO20,GPIO21,GPIO22",
            "invert=GPIO20",
            "reset=GPIO21,GPIO22",
            "pullup=GPIO5",
            "opendrain=GPIO22",
        ])
        .unwrap();
        let names: Vec<_> = c.lines.iter().map(|l| l.name.as_str()).collect();
        assert_eq!(names, ["GPIO5", "GPIO6", "GPIO20", "GPIO21", "GPIO22"]);
        let l = |n| c.line(n).unwrap();
        assert_eq!(l("GPIO5").direction, Direction::Input);
        assert_eq!(l("GPIO5").bias, Bias::PullUp);
        assert!(l("GPIO20").invert && !l("GPIO20").reset);
        assert!(l("GPIO21").reset && !l("GPIO21").invert);
        assert_eq!(l("GPIO22").drive, Drive::OpenDrain);
        assert!(c.has_reset());
        assert_eq!(c.of(Direction::Output).count(), 3);
    }

    #[test]
    fn empty_items_are_ignored() {
        let c = parse_args(&["outputs=A,,B,", "invert=,B"]).unwrap();
        assert_eq!(c.lines.len(), 2);
        assert!(c.line("B").unwrap().invert);
    }

    #[test]
    fn every_mistake_names_list_item_and_line() {
        let cases: &[(&[&str], &str)] = &[
            (&[], "parameter 'inputs': no lines given"),
            (&["outputs="], "no lines given"),
            (
                &["inputs=A,B,A"],
                "parameter 'inputs': item 2 \"A\": listed twice in inputs=",
            ),
            (
                &["inputs=A", "outputs=B,A"],
                "parameter 'outputs': item 1 \"A\": listed in both inputs= and outputs=",
            ),
            (
                &["inputs=A", "invert=A"],
                "parameter 'invert': item 0 \"A\": invert= applies to outputs only",
            ),
            (&["inputs=A", "reset=A"], "reset= applies to outputs only"),
            (
                &["inputs=A", "opendrain=A"],
                "opendrain= applies to outputs only",
            ),
            (
                &["outputs=A", "invert=C"],
                "parameter 'invert': item 0 \"C\": not a line of inputs= or outputs=",
            ),
            (
                &["outputs=A", "opendrain=A", "opensource=A"],
                "parameter 'opensource': item 0 \"A\": cannot be both open drain and open source",
            ),
            (
                &["inputs=A", "pullup=A", "pulldown=A"],
                "parameter 'pullup': item 0 \"A\": has two bias settings (pulldown and pullup)",
            ),
            (
                &["inputs=A", "biasdisable=A", "pullup=A"],
                "has two bias settings (biasdisable and pullup)",
            ),
            (
                &["outputs=A", "reset=A,A"],
                "parameter 'reset': item 1 \"A\": listed twice in reset=",
            ),
        ];
        for (args, want) in cases {
            let e = parse_args(args).unwrap_err().to_string();
            assert!(e.contains(want), "{args:?}: {e}");
            assert!(e.starts_with("hal_gpio: "), "{e}");
        }
    }

    #[test]
    fn bias_and_drive_apply_to_inputs_and_outputs_as_the_kernel_allows() {
        let c = parse_args(&[
            "inputs=I",
            "outputs=O,P",
            "pulldown=I,O",
            "biasdisable=P",
            "opensource=P",
        ])
        .unwrap();
        assert_eq!(c.line("I").unwrap().bias, Bias::PullDown);
        assert_eq!(c.line("O").unwrap().bias, Bias::PullDown);
        assert_eq!(c.line("P").unwrap().bias, Bias::Disabled);
        assert_eq!(c.line("P").unwrap().drive, Drive::OpenSource);
    }

    #[test]
    fn more_than_128_names_is_refused() {
        let many: Vec<String> = (0..129).map(|i| format!("L{i}")).collect();
        let e = parse_args(&[&format!("inputs={}", many.join(","))])
            .unwrap_err()
            .to_string();
        assert!(e.contains("can only take 128"), "{e}");
    }
}
