//! A panel file's meaning: the HAL prefix (`[HAL_PREFIX]NAME`), the
//! buttons of `[TOGGLE_BUTTONS]`, `[MOMENTARY_BUTTONS]` and the groups of
//! `[RADIO_BUTTONS]` with their keys (`KEY = RnCm`), outputs, states and
//! commands, checked as a whole: every refusal names the line.

use super::commands::{self, Command};
use super::dialect::{Entry, Section, SyntaxError, Value};

/// A HAL pin type a button or a group drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PinKind {
    /// `BIT`.
    Bit,
    /// `S32`.
    S32,
    /// `U32`.
    U32,
    /// `FLOAT`.
    Float,
}

/// A value of a [`PinKind`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutValue {
    /// A bit.
    Bit(bool),
    /// A signed integer.
    S32(i32),
    /// An unsigned integer.
    U32(u32),
    /// A float.
    Float(f64),
}

/// What a button drives.
#[derive(Debug, Clone, PartialEq)]
pub enum Output {
    /// `OUTPUT = NONE`: only its state (and status pins).
    None,
    /// `OUTPUT = COMMAND`: a command when its state turns true or false.
    Command {
        /// `TRUE_COMMAND`.
        on: Option<Command>,
        /// `FALSE_COMMAND`.
        off: Option<Command>,
    },
    /// `OUTPUT = BIT/S32/U32/FLOAT`: the pins `NAME` and `NAME-not`.
    Pin {
        /// The pin type.
        kind: PinKind,
        /// `TRUE_STATE` (TRUE for a bit).
        on: OutValue,
        /// `FALSE_STATE` (FALSE for a bit).
        off: OutValue,
    },
}

/// How a button's state follows its key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Each press flips the state.
    Toggle,
    /// True while held.
    Momentary,
    /// A press makes it the one true button of group N.
    Radio(usize),
}

/// A button.
#[derive(Debug, Clone, PartialEq)]
pub struct Button {
    /// Its name: the pins' names after the prefix.
    pub name: String,
    /// Its key (row, column), if it has one.
    pub key: Option<(u8, u8)>,
    /// Toggle, momentary or radio.
    pub kind: Kind,
    /// What it drives.
    pub output: Output,
    /// Whether it has the pins `NAME-state` and `NAME-state-not`.
    pub status_pin: bool,
    /// `DEFAULT`: its state at start.
    pub default: bool,
    /// A radio button's `GROUP_OUTPUT`.
    pub group_output: f64,
}

/// A group of radio buttons.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Its name: its pins' names after the prefix.
    pub name: String,
    /// Its pins' type (`OUTPUT`; none for `NONE`).
    pub kind: Option<PinKind>,
    /// Its buttons (indices into [`PanelConfig::buttons`]).
    pub members: Vec<usize>,
    /// `DEFAULT`: the button true at start.
    pub default: usize,
}

/// A panel file read.
#[derive(Debug, Clone, PartialEq)]
pub struct PanelConfig {
    /// `[HAL_PREFIX]NAME` (default `panelui`).
    pub prefix: String,
    /// Every button.
    pub buttons: Vec<Button>,
    /// The radio groups.
    pub groups: Vec<Group>,
    /// Top-level sections panelui does not know (LinuxCNC passes over
    /// them with a note).
    pub unknown_sections: Vec<String>,
}

/// What is wrong, and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ConfigError {
    /// The line (1-based).
    pub line: usize,
    /// What is wrong.
    pub why: String,
}

impl From<SyntaxError> for ConfigError {
    fn from(e: SyntaxError) -> ConfigError {
        ConfigError {
            line: e.line,
            why: e.why.to_string(),
        }
    }
}

fn err<T>(line: usize, why: impl Into<String>) -> Result<T, ConfigError> {
    Err(ConfigError {
        line,
        why: why.into(),
    })
}

/// The keys a button may have.
const BUTTON_KEYS: &[&str] = &[
    "KEY",
    "OUTPUT",
    "STATUS_PIN",
    "TRUE_STATE",
    "FALSE_STATE",
    "TRUE_COMMAND",
    "FALSE_COMMAND",
    "DEFAULT",
    "GROUP",
    "GROUP_OUTPUT",
];

/// Reads a panel file's text. `handlers` are the functions of the
/// configuration's `panelui_handler.py`, which commands may name.
pub fn read(text: &str, handlers: &[String]) -> Result<PanelConfig, ConfigError> {
    let root = super::dialect::parse(text)?;
    if let Some(e) = root.entries.first() {
        return err(e.line, format!("{} is outside any section", e.key));
    }
    let mut cfg = PanelConfig {
        prefix: "panelui".into(),
        buttons: Vec::new(),
        groups: Vec::new(),
        unknown_sections: Vec::new(),
    };
    for top in &root.sections {
        match top.name.as_str() {
            "HAL_PREFIX" => cfg.prefix = prefix(top)?,
            "TOGGLE_BUTTONS" | "MOMENTARY_BUTTONS" => {
                let kind = if top.name == "TOGGLE_BUTTONS" {
                    Kind::Toggle
                } else {
                    Kind::Momentary
                };
                no_entries(top)?;
                for s in &top.sections {
                    no_subsections(s)?;
                    let b = button(s, kind, handlers)?;
                    add(&mut cfg, b, s.line)?;
                }
            }
            "RADIO_BUTTONS" => {
                no_entries(top)?;
                for g in &top.sections {
                    group(&mut cfg, g, handlers)?;
                }
            }
            "ZMQ_SETUP" => {
                if let Some(e) = top.get("ENABLE") {
                    if boolean(e)? {
                        return err(e.line, "ZeroMQ output (ENABLE = true) is not supported");
                    }
                }
            }
            other => cfg.unknown_sections.push(other.to_string()),
        }
    }
    Ok(cfg)
}

fn prefix(s: &Section) -> Result<String, ConfigError> {
    no_subsections(s)?;
    let mut name = "panelui".to_string();
    for e in &s.entries {
        if !e.key.eq_ignore_ascii_case("NAME") {
            return err(e.line, format!("[HAL_PREFIX] has only NAME, not {}", e.key));
        }
        let Value::One(v) = &e.value else {
            return err(e.line, "NAME is one word, not a list");
        };
        if v.is_empty() || v.contains(char::is_whitespace) {
            return err(e.line, format!("NAME {v:?} is not a HAL name"));
        }
        name = v.clone();
    }
    Ok(name)
}

fn no_entries(s: &Section) -> Result<(), ConfigError> {
    match s.entries.first() {
        Some(e) => err(
            e.line,
            format!("[{}] holds [[button]] sections, not {}", s.name, e.key),
        ),
        None => Ok(()),
    }
}

fn no_subsections(s: &Section) -> Result<(), ConfigError> {
    match s.sections.first() {
        Some(n) => err(n.line, format!("[{}] cannot hold a section", s.name)),
        None => Ok(()),
    }
}

/// A button's or group's name, part of its pins' names.
fn check_name(name: &str, line: usize) -> Result<(), ConfigError> {
    if name.chars().any(|c| c.is_whitespace() || c.is_control()) {
        return err(
            line,
            format!("{name:?} cannot be part of a HAL pin name (blank or control character)"),
        );
    }
    Ok(())
}

/// Adds a button, checking its name and key are its own.
fn add(cfg: &mut PanelConfig, b: Button, line: usize) -> Result<usize, ConfigError> {
    check_name(&b.name, line)?;
    if cfg.buttons.iter().any(|o| o.name == b.name) || cfg.groups.iter().any(|g| g.name == b.name) {
        return err(line, format!("the name {} is used twice", b.name));
    }
    if let Some((r, c)) = b.key {
        if let Some(o) = cfg.buttons.iter().find(|o| o.key == b.key) {
            return err(line, format!("key R{r}C{c} is already {}'s", o.name));
        }
    }
    cfg.buttons.push(b);
    Ok(cfg.buttons.len() - 1)
}

fn one(e: &Entry) -> Result<&str, ConfigError> {
    match &e.value {
        Value::One(v) => Ok(v),
        Value::List(_) => err(e.line, format!("{} is one word, not a list", e.key)),
    }
}

fn boolean(e: &Entry) -> Result<bool, ConfigError> {
    match one(e)?.to_ascii_lowercase().as_str() {
        "true" | "yes" | "on" | "1" => Ok(true),
        "false" | "no" | "off" | "0" | "none" => Ok(false),
        v => err(
            e.line,
            format!("{} must be true or false, not {v:?}", e.key),
        ),
    }
}

/// `KEY = RnCm` (row and column 0..7); `NONE` is no key.
fn key(e: &Entry) -> Result<Option<(u8, u8)>, ConfigError> {
    let v = one(e)?;
    if v.eq_ignore_ascii_case("none") {
        return Ok(None);
    }
    let up = v.to_ascii_uppercase();
    let parsed = up
        .strip_prefix('R')
        .and_then(|rest| rest.split_once('C'))
        .and_then(|(r, c)| Some((r.parse::<u8>().ok()?, c.parse::<u8>().ok()?)));
    match parsed {
        Some((r, c)) if r < 8 && c < 8 => Ok(Some((r, c))),
        _ => err(
            e.line,
            format!("KEY {v:?} is not RnCm with row and column 0..7 (or NONE)"),
        ),
    }
}

fn pin_kind(e: &Entry, allowed: &[&str]) -> Result<Option<PinKind>, ConfigError> {
    let v = one(e)?.to_ascii_uppercase();
    if !allowed.contains(&v.as_str()) {
        return err(
            e.line,
            format!("OUTPUT must be one of {}, not {v:?}", allowed.join(", ")),
        );
    }
    Ok(match v.as_str() {
        "BIT" => Some(PinKind::Bit),
        "S32" => Some(PinKind::S32),
        "U32" => Some(PinKind::U32),
        "FLOAT" => Some(PinKind::Float),
        _ => None,
    })
}

/// `TRUE_STATE`/`FALSE_STATE` as a value of `kind`.
fn state(e: Option<&Entry>, kind: PinKind, default: i32) -> Result<OutValue, ConfigError> {
    let Some(e) = e else {
        return Ok(match kind {
            PinKind::Bit => OutValue::Bit(default != 0),
            PinKind::S32 => OutValue::S32(default),
            PinKind::U32 => OutValue::U32(default.unsigned_abs()),
            PinKind::Float => OutValue::Float(f64::from(default)),
        });
    };
    let v = one(e)?;
    let bad = |what: &str| err(e.line, format!("{} must be {what}, not {v:?}", e.key));
    Ok(match kind {
        PinKind::Bit => OutValue::Bit(default != 0),
        PinKind::S32 => match v.parse() {
            Ok(n) => OutValue::S32(n),
            Err(_) => return bad("a whole number (S32)"),
        },
        PinKind::U32 => match v.parse() {
            Ok(n) => OutValue::U32(n),
            Err(_) => return bad("a whole number 0 or more (U32)"),
        },
        PinKind::Float => match v.parse::<f64>() {
            Ok(x) if x.is_finite() => OutValue::Float(x),
            _ => return bad("a number (FLOAT)"),
        },
    })
}

fn command(e: Option<&Entry>, handlers: &[String]) -> Result<Option<Command>, ConfigError> {
    let Some(e) = e else { return Ok(None) };
    commands::parse(&e.value.items(), handlers).map_err(|why| ConfigError {
        line: e.line,
        why: format!("{}: {why}", e.key),
    })
}

/// A button's section.
fn button(s: &Section, kind: Kind, handlers: &[String]) -> Result<Button, ConfigError> {
    for e in &s.entries {
        let up = e.key.to_ascii_uppercase();
        let radio_only = up == "GROUP" || up == "GROUP_OUTPUT";
        if !BUTTON_KEYS.contains(&up.as_str()) || (radio_only && !matches!(kind, Kind::Radio(_))) {
            return err(e.line, format!("button {} has no key {}", s.name, e.key));
        }
    }
    let Some(k) = s.get("KEY") else {
        return err(s.line, format!("button {} has no KEY", s.name));
    };
    let out = match s.get("OUTPUT") {
        Some(e) => (
            pin_kind(e, &["S32", "U32", "FLOAT", "BIT", "COMMAND", "NONE"])?,
            one(e)?.eq_ignore_ascii_case("COMMAND"),
        ),
        None => (Some(PinKind::S32), false),
    };
    let on_cmd = command(s.get("TRUE_COMMAND"), handlers)?;
    let off_cmd = command(s.get("FALSE_COMMAND"), handlers)?;
    let output = match out {
        (_, true) => Output::Command {
            on: on_cmd,
            off: off_cmd,
        },
        (None, false) => Output::None,
        (Some(kind), false) => Output::Pin {
            kind,
            on: state(s.get("TRUE_STATE"), kind, 1)?,
            off: state(s.get("FALSE_STATE"), kind, 0)?,
        },
    };
    let group_output = match s.get("GROUP_OUTPUT") {
        Some(e) => match one(e)?.parse::<f64>() {
            Ok(x) if x.is_finite() => x,
            _ => {
                return err(
                    e.line,
                    format!("GROUP_OUTPUT must be a number, not {}", e.value),
                )
            }
        },
        None if matches!(kind, Kind::Radio(_)) => {
            return err(
                s.line,
                format!("radio button {} has no GROUP_OUTPUT", s.name),
            )
        }
        None => 0.0,
    };
    Ok(Button {
        name: s.name.clone(),
        key: key(k)?,
        kind,
        output,
        status_pin: s
            .get("STATUS_PIN")
            .map(boolean)
            .transpose()?
            .unwrap_or(false),
        default: s.get("DEFAULT").map(boolean).transpose()?.unwrap_or(false),
        group_output,
    })
}

/// A `[[group]]` of `[RADIO_BUTTONS]` with its `[[[button]]]`s.
fn group(cfg: &mut PanelConfig, g: &Section, handlers: &[String]) -> Result<(), ConfigError> {
    for e in &g.entries {
        if !["KEY", "OUTPUT", "DEFAULT"].contains(&e.key.to_ascii_uppercase().as_str()) {
            return err(
                e.line,
                format!("radio group {} has no key {}", g.name, e.key),
            );
        }
    }
    check_name(&g.name, g.line)?;
    if cfg.buttons.iter().any(|b| b.name == g.name) || cfg.groups.iter().any(|o| o.name == g.name) {
        return err(g.line, format!("the name {} is used twice", g.name));
    }
    let kind = match g.get("OUTPUT") {
        Some(e) => pin_kind(e, &["S32", "U32", "FLOAT", "NONE"])?,
        None => Some(PinKind::S32),
    };
    if g.sections.is_empty() {
        return err(
            g.line,
            format!("radio group {} has no [[[button]]]", g.name),
        );
    }
    let index = cfg.groups.len();
    let mut members = Vec::new();
    for s in &g.sections {
        no_subsections(s)?;
        if let Some(e) = s.get("GROUP") {
            let named = one(e)?;
            if named != g.name {
                return err(
                    e.line,
                    format!("GROUP {named} is not the group {} the button is in", g.name),
                );
            }
        } else {
            return err(s.line, format!("radio button {} has no GROUP", s.name));
        }
        let b = button(s, Kind::Radio(index), handlers)?;
        check_group_output(&b, kind, s.line)?;
        members.push(add(cfg, b, s.line)?);
    }
    let Some(d) = g.get("DEFAULT") else {
        return err(
            g.line,
            format!("radio group {} has no DEFAULT button", g.name),
        );
    };
    let dname = one(d)?;
    let Some(&default) = members.iter().find(|&&m| cfg.buttons[m].name == dname) else {
        return err(
            d.line,
            format!("DEFAULT {dname} is not a button of group {}", g.name),
        );
    };
    cfg.groups.push(Group {
        name: g.name.clone(),
        kind,
        members,
        default,
    });
    Ok(())
}

/// A radio button's `GROUP_OUTPUT` must fit its group's pin.
fn check_group_output(b: &Button, kind: Option<PinKind>, line: usize) -> Result<(), ConfigError> {
    let x = b.group_output.trunc();
    let fits = match kind {
        Some(PinKind::S32) => x >= f64::from(i32::MIN) && x <= f64::from(i32::MAX),
        Some(PinKind::U32) => x >= 0.0 && x <= f64::from(u32::MAX),
        _ => true,
    };
    if fits {
        Ok(())
    } else {
        err(
            line,
            format!(
                "{}'s GROUP_OUTPUT {} does not fit the group's pin",
                b.name, b.group_output
            ),
        )
    }
}

/// Fuzz body: any bytes as a panel file; a file read has unique names
/// and keys, each group's default is one of its buttons, and pressing
/// any key leaves one button of each group true.
pub fn fuzz_config(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let handlers = ["user_cmd".to_string()];
    match read(&text, &handlers) {
        Ok(cfg) => {
            for (i, b) in cfg.buttons.iter().enumerate() {
                assert!(cfg.buttons[..i].iter().all(|o| o.name != b.name));
                if b.key.is_some() {
                    assert!(cfg.buttons[..i].iter().all(|o| o.key != b.key));
                }
            }
            for g in &cfg.groups {
                assert!(g.members.contains(&g.default));
            }
            // Every key pressed and released: one true button a group.
            let groups = cfg.groups.clone();
            let (mut panel, _) = super::panel::Panel::new(cfg);
            for code in 0..64 {
                for pressed in [true, false] {
                    let _ = panel.key(code / 8, code % 8, pressed);
                    for g in &groups {
                        let on = g.members.iter().filter(|&&m| panel.state(m)).count();
                        assert_eq!(on, 1, "group {}", g.name);
                    }
                }
            }
        }
        Err(e) => assert!(e.line >= 1 && !e.why.is_empty()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GROUP: &str = "\
[HAL_PREFIX]
    NAME = pad
[RADIO_BUTTONS]
    [[axis_select]]
        KEY = select_axis
        OUTPUT = S32
        DEFAULT = select_x
        [[[select_x]]]
            KEY = R5C2
            GROUP = axis_select
            GROUP_OUTPUT = 1
            OUTPUT = BIT
            TRUE_STATE = True
            STATUS_PIN = True
        [[[select_z]]]
            KEY = R4C2
            GROUP = axis_select
            GROUP_OUTPUT = 2
            OUTPUT = BIT
";

    #[test]
    fn a_group_reads_with_its_buttons() {
        let cfg = read(GROUP, &[]).unwrap();
        assert_eq!(cfg.prefix, "pad");
        assert_eq!(cfg.groups.len(), 1);
        let g = &cfg.groups[0];
        assert_eq!(
            (g.name.as_str(), g.kind, g.default),
            ("axis_select", Some(PinKind::S32), 0)
        );
        let x = &cfg.buttons[0];
        assert_eq!(
            (x.key, x.kind, x.status_pin),
            (Some((5, 2)), Kind::Radio(0), true)
        );
        assert_eq!(
            x.output,
            Output::Pin {
                kind: PinKind::Bit,
                on: OutValue::Bit(true),
                off: OutValue::Bit(false)
            }
        );
        assert_eq!(cfg.buttons[1].group_output, 2.0);
    }

    #[test]
    fn mistakes_are_refused_with_their_line() {
        let toggle = |body: &str| format!("[TOGGLE_BUTTONS]\n  [[b]]\n    KEY = R0C0\n{body}");
        let cases: Vec<(String, usize, &str)> = vec![
            (toggle("    TRUE_COMMAND = spindle_sideways, 1\n"), 4, "unknown command"),
            (toggle("    OUTPUT = ZMQ\n"), 4, "OUTPUT must be one of"),
            (toggle("    OUTPUT = S32\n    TRUE_STATE = 2.5\n"), 5, "whole number"),
            (toggle("    OUTPUT = U32\n    FALSE_STATE = -1\n"), 5, "0 or more"),
            (toggle("    STATUS_PIN = maybe\n"), 4, "true or false"),
            (toggle("    KEYS = R1C1\n"), 4, "has no key KEYS"),
            (toggle("    GROUP = g\n"), 4, "has no key GROUP"),
            ("[TOGGLE_BUTTONS]\n  [[b]]\n    KEY = R8C0\n".into(), 3, "row and column 0..7"),
            ("[TOGGLE_BUTTONS]\n  [[b]]\n    OUTPUT = BIT\n".into(), 2, "has no KEY"),
            (
                "[TOGGLE_BUTTONS]\n  [[a]]\n    KEY = R1C1\n  [[b]]\n    KEY = r1c1\n".into(),
                4,
                "key R1C1 is already a's",
            ),
            (
                "[TOGGLE_BUTTONS]\n  [[a]]\n    KEY = R1C1\n[MOMENTARY_BUTTONS]\n  [[a]]\n    KEY = R1C2\n"
                    .into(),
                5,
                "used twice",
            ),
            (GROUP.replace("DEFAULT = select_x", "DEFAULT = select_y"), 7, "not a button of group"),
            (GROUP.replace("GROUP = axis_select\n            GROUP_OUTPUT = 2", "GROUP = other\n            GROUP_OUTPUT = 2"), 17, "is not the group"),
            (GROUP.replace("GROUP_OUTPUT = 2", "GROUP_OUTPUT = two"), 18, "must be a number"),
            (GROUP.replace("OUTPUT = S32", "OUTPUT = BIT"), 6, "OUTPUT must be one of S32, U32, FLOAT, NONE"),
            ("NAME = x\n".into(), 1, "outside any section"),
            ("[TOGGLE_BUTTONS]\n  [[a b]]\n    KEY = R1C1\n".into(), 2, "HAL pin name"),
            ("[ZMQ_SETUP]\nENABLE = True\n".into(), 2, "not supported"),
        ];
        for (text, line, why) in cases {
            let e = read(&text, &[]).unwrap_err();
            assert_eq!(e.line, line, "{text}: {e:?}");
            assert!(e.why.contains(why), "{text}: {}", e.why);
        }
    }

    #[test]
    fn handler_functions_may_be_named_and_unknown_sections_noted() {
        let text = "[MOMENTARY_BUTTONS]\n  [[m]]\n    KEY = R3C5\n    OUTPUT = COMMAND\n\
                    \x20   TRUE_COMMAND = hello_world, 1, 2\n[EXTRA]\n";
        assert!(read(text, &[]).is_err());
        let cfg = read(text, &["hello_world".to_string()]).unwrap();
        assert_eq!(cfg.unknown_sections, ["EXTRA"]);
        assert!(matches!(
            &cfg.buttons[0].output,
            Output::Command { on: Some(Command::Handler(n)), off: None } if n == "hello_world"
        ));
    }
}
