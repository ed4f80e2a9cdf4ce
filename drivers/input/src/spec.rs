//! The command line (`hal_input [-KRAL] inputspec ...`) and how an
//! inputspec picks its device, as LinuxCNC's hal_input does: a path that
//! exists, a number N for `/dev/input/eventN`, else a substring or shell
//! pattern of the device's name, its phys, its id string
//! (`Bus=BUS_USB Vendor=046d Product=c21d Version=0111`) or
//! `vendor:product`, the `N`th match with `:N`; `+` first asks for the
//! device alone.

use std::path::{Path, PathBuf};

use crate::device::{Catalogue, InputDevice};
use crate::error::{InputError, Result};
use crate::names;

/// Which features of a device get pins (`-KRAL`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Parts {
    /// `K`: keys and buttons.
    pub keys: bool,
    /// `R`: relative axes.
    pub rel: bool,
    /// `A`: absolute axes.
    pub abs: bool,
    /// `L`: LEDs.
    pub leds: bool,
}

impl Parts {
    /// Every feature: what an inputspec without a subset option gets.
    pub const ALL: Parts = Parts {
        keys: true,
        rel: true,
        abs: true,
        leds: true,
    };
}

/// One device asked for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DeviceSpec {
    /// The inputspec as given (with `+` and `:N`).
    pub spec: String,
    /// Its features.
    pub parts: Parts,
}

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Options {
    /// The devices, in order: device `i` gets pins `input.i.*`.
    pub devices: Vec<DeviceSpec>,
    /// `--sim FILE`: look the devices up among simulated ones.
    pub sim: Option<PathBuf>,
    /// Warnings about the command line (letters that name no feature).
    pub warnings: Vec<String>,
}

/// A command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    /// Run.
    Run(Options),
    /// `-h`, `--help`.
    Help,
    /// `--version`.
    Version,
}

/// Reads a subset option's letters. As LinuxCNC's, a letter that names
/// no feature selects nothing (LinuxCNC's own plasma-5i20 configuration
/// passes `-W` before `-KRAL`); it is warned about.
fn subset(word: &str, warnings: &mut Vec<String>) -> Parts {
    let letters = &word[1..];
    for c in letters.chars().filter(|c| !"KRAL".contains(*c)) {
        warnings.push(format!(
            "'{word}': '{c}' is no feature (K keys, R relative axes, A absolute axes, L LEDs); ignored"
        ));
    }
    Parts {
        keys: letters.contains('K'),
        rel: letters.contains('R'),
        abs: letters.contains('A'),
        leds: letters.contains('L'),
    }
}

/// Reads the command line (without the program name).
pub fn parse_args(args: &[String]) -> Result<Command> {
    let mut o = Options {
        devices: Vec::new(),
        sim: None,
        warnings: Vec::new(),
    };
    let mut parts: Option<(Parts, String)> = None;
    let mut i = 0;
    while i < args.len() {
        if let Some(found) = hal_core::userspace::instance_option(args, i, false) {
            let (name, used) = found?;
            hal_core::userspace::select_instance(&name)?;
            i += used;
            continue;
        }
        let a = args[i].as_str();
        match a {
            "-h" | "--help" => return Ok(Command::Help),
            "--version" => return Ok(Command::Version),
            "--sim" => {
                let file = args
                    .get(i + 1)
                    .ok_or_else(|| InputError::Usage("option --sim needs a file".into()))?;
                o.sim = Some(PathBuf::from(file));
                i += 1;
            }
            _ if a.starts_with("--") => {
                return Err(InputError::Usage(format!("unknown option '{a}'")));
            }
            _ if a.starts_with('-') => parts = Some((subset(a, &mut o.warnings), a.to_string())),
            "" | "+" => {
                return Err(InputError::Usage(format!(
                    "inputspec '{a}' is empty: it would match every device"
                )))
            }
            _ => {
                let p = parts.take().map_or(Parts::ALL, |(p, _)| p);
                o.devices.push(DeviceSpec {
                    spec: a.to_string(),
                    parts: p,
                });
            }
        }
        i += 1;
    }
    if let Some((_, word)) = parts {
        return Err(InputError::Usage(format!(
            "subset option '{word}' is not followed by an inputspec"
        )));
    }
    if o.devices.is_empty() {
        return Err(InputError::Usage("no inputspec given".into()));
    }
    Ok(Command::Run(o))
}

/// Whether `text` matches the shell pattern `pat` (`*`, `?`, `[abc]`,
/// `[a-z]`, `[!...]`), as Python's `fnmatch` does on Linux (case
/// sensitive; a `[` without its `]` is itself).
pub fn glob_match(pat: &str, text: &str) -> bool {
    let p: Vec<char> = pat.chars().collect();
    let t: Vec<char> = text.chars().collect();
    let (mut pi, mut ti) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while ti < t.len() {
        let step = match p.get(pi) {
            Some('*') => {
                star = Some((pi, ti));
                pi += 1;
                continue;
            }
            Some('?') => Some(1),
            Some('[') => match class(&p[pi..], t[ti]) {
                Some((matched, len)) => matched.then_some(len),
                None => (t[ti] == '[').then_some(1),
            },
            Some(c) => (*c == t[ti]).then_some(1),
            None => None,
        };
        match (step, star) {
            (Some(len), _) => {
                pi += len;
                ti += 1;
            }
            (None, Some((sp, st))) => {
                pi = sp + 1;
                ti = st + 1;
                star = Some((sp, st + 1));
            }
            (None, None) => return false,
        }
    }
    p[pi..].iter().all(|c| *c == '*')
}

/// A `[...]` class at the start of `p`: whether `c` is in it and the
/// class's length, or `None` when it has no closing `]`.
fn class(p: &[char], c: char) -> Option<(bool, usize)> {
    let mut i = 1;
    let negate = matches!(p.get(i), Some('!'));
    if negate {
        i += 1;
    }
    let first = i;
    let mut hit = false;
    while let Some(&x) = p.get(i) {
        if x == ']' && i > first {
            return Some((hit != negate, i + 1));
        }
        if p.get(i + 1) == Some(&'-') && p.get(i + 2).is_some_and(|e| *e != ']') {
            let end = p[i + 2];
            hit |= x <= c && c <= end;
            i += 3;
        } else {
            hit |= x == c;
            i += 1;
        }
    }
    None
}

/// Whether `pattern` picks a device by `text`: a substring or a shell
/// pattern of it.
fn matches(pattern: &str, text: &str) -> bool {
    text.contains(pattern) || glob_match(pattern, text)
}

/// The device an inputspec (without `+`) names in `cat`.
pub fn find(cat: &dyn Catalogue, spec: &str) -> Result<Box<dyn InputDevice>> {
    let direct = Path::new(spec);
    if cat.exists(direct) {
        return cat.open(direct);
    }
    let numbered = PathBuf::from(format!("/dev/input/event{spec}"));
    if cat.exists(&numbered) {
        return cat.open(&numbered);
    }
    // `TEXT:N` picks the Nth match; a colon not followed by a number is
    // part of the text (a phys such as `usb-0000:00:14.0-1/input0`, an
    // id `046d:c21d`), where LinuxCNC's stops with a Python error.
    let (pattern, mut index) = match spec.rsplit_once(':') {
        Some((p, n)) => match n.parse::<usize>() {
            Ok(i) => (p, i),
            Err(_) => (spec, 0),
        },
        None => (spec, 0),
    };
    let mut opened = 0;
    let mut last_failure = String::new();
    let nodes = cat.nodes();
    if nodes.is_empty() {
        return Err(InputError::NoDevices {
            dir: cat.describe(),
        });
    }
    for node in &nodes {
        let dev = match cat.open(node) {
            Ok(d) => d,
            Err(e) => {
                last_failure = crate::chain(&e);
                continue;
            }
        };
        opened += 1;
        let who = dev.identity();
        let texts = [
            Some(who.name.clone()),
            who.phys.clone(),
            Some(names::id_string(&who.id)),
            Some(names::short_id(&who.id)),
        ];
        // Each device counts once towards `:N`, by the first of its
        // texts that matches.
        if texts.iter().flatten().any(|t| matches(pattern, t)) {
            if index == 0 {
                return Ok(dev);
            }
            index -= 1;
        }
    }
    if opened == 0 {
        return Err(InputError::NothingOpens {
            dir: cat.describe(),
            count: nodes.len(),
            why: last_failure,
        });
    }
    Err(InputError::NoMatch {
        spec: pattern.to_string(),
        checked: opened,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(w: &[&str]) -> Vec<String> {
        w.iter().map(|s| s.to_string()).collect()
    }

    fn run(w: &[&str]) -> Options {
        match parse_args(&words(w)).unwrap() {
            Command::Run(o) => o,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn subsets_apply_to_the_next_inputspec_only() {
        let o = run(&["-RK", "1", "Dual", "-L", "+keyboard:1"]);
        let parts: Vec<Parts> = o.devices.iter().map(|d| d.parts).collect();
        assert_eq!(
            parts,
            [
                Parts {
                    keys: true,
                    rel: true,
                    abs: false,
                    leds: false
                },
                Parts::ALL,
                Parts {
                    keys: false,
                    rel: false,
                    abs: false,
                    leds: true
                },
            ]
        );
        assert_eq!(o.devices[2].spec, "+keyboard:1");
        assert!(o.warnings.is_empty());
    }

    #[test]
    fn plasma_5i20s_stray_w_is_warned_about_and_overridden() {
        let o = run(&["-W", "-KRAL", "Dual"]);
        assert_eq!(o.devices[0].parts, Parts::ALL);
        assert_eq!(o.warnings.len(), 1, "{:?}", o.warnings);
        assert!(o.warnings[0].contains("'W'"));
    }

    #[test]
    fn bad_command_lines_are_refused() {
        for bad in [
            &[][..],
            &["-K"],
            &["1", "-A"],
            &["--bogus", "1"],
            &[""],
            &["+"],
            &["--sim"],
        ] {
            let e = parse_args(&words(bad));
            assert!(e.is_err(), "{bad:?}: {e:?}");
        }
        assert_eq!(parse_args(&words(&["-h"])).unwrap(), Command::Help);
        assert_eq!(
            parse_args(&words(&["x", "--version"])).unwrap(),
            Command::Version
        );
        let e = parse_args(&words(&["--no-such-option"])).unwrap_err();
        assert!(e.to_string().contains("'--no-such-option'"));
    }

    #[test]
    fn shell_patterns_as_fnmatch() {
        // A pattern matches the whole text, as fnmatch: the man page's
        // example needs a leading `*` for an i8042 keyboard's phys.
        assert!(!glob_match("serio*/input0", "isa0060/serio0/input0"));
        assert!(glob_match("*serio*/input0", "isa0060/serio0/input0"));
        assert!(glob_match("Logi?ech*", "Logitech Gamepad F310"));
        assert!(glob_match("[LM]ouse", "Louse"));
        assert!(glob_match("[!L]ouse", "Mouse"));
        assert!(!glob_match("[!L]ouse", "Louse"));
        assert!(glob_match("event[0-9]", "event7"));
        assert!(glob_match("a[b", "a[b"));
        assert!(glob_match("[]]x", "]x"));
        assert!(!glob_match("Mouse", "USB Mouse"));
        assert!(glob_match("*", ""));
        assert!(!glob_match("?", ""));
    }
}
