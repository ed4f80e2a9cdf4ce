//! The launcher's rules for the commands of a machine's HAL files: GUI
//! components that a headless machine does not start (and the lines that
//! would connect them), TWOPASS's two passes, and `loadrt tpmod`/`homemod`
//! when the launcher loaded them already. Every skipped line is recorded,
//! so the launcher can say what it skipped and which pins were left
//! without the GUI partner they would have had.

use std::collections::BTreeSet;

use hal_core::Instance;
use hal_lang::session::{CommandFilter, Verdict};
use hal_lang::usr;
use hal_lang::LangError;

use crate::twopass::TwoPass;

/// Programs that need a display, or are user interfaces a headless
/// machine does not run.
const GUI_PROGRAMS: &[&str] = &[
    "axis",
    "axis-remote",
    "touchy",
    "gmoccapy",
    "gscreen",
    "qtvcp",
    "tklinuxcnc",
    "mini",
    "keystick",
    "pyvcp",
    "gladevcp",
    "hal_manualtoolchange",
    "halshow",
    "halscope",
    "sim_pin",
    "simulate_probe",
    "hal-histogram",
    "linuxcnctop",
    "tooledit",
    "classicladder",
    "lineardelta",
    "rotarydelta",
];

/// HAL component names of GUIs: their pins never exist here.
const GUI_COMPONENTS: &[&str] = &[
    "axisui",
    "pyvcp",
    "gladevcp",
    "touchy",
    "gmoccapy",
    "gscreen",
    "qtdragon",
    "qtplasmac",
    "hal_manualtoolchange",
    "halui",
    // The 3-D views LinuxCNC's vismach programs (pumagui, scaragui...)
    // create their pins under.
    "vismach",
];

/// Which pass of TWOPASS runs (or none).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Ordinary processing.
    Normal,
    /// TWOPASS pass 0: gather `loadrt`, run `loadusr`, skip the rest.
    Pass0,
    /// TWOPASS pass 0 in a Tcl file: gather `loadrt`, put `addf` off to
    /// pass 1, run the rest. As under LinuxCNC's twopass.tcl, the Tcl
    /// side hides the bare halcmd commands in this pass, so what reaches
    /// the session is `loadrt`, `loadusr`, `addf` and what the script
    /// asks of `hal` by name (`hal save`, `hal list`...), which runs.
    Pass0Tcl,
    /// TWOPASS pass 1: everything but the `loadrt`s of pass 0 and the
    /// `loadusr`s.
    Pass1,
}

/// A line that was not run because of a GUI.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Skipped {
    /// File and line.
    pub at: String,
    /// The command as written.
    pub command: String,
    /// The GUI pins it named (empty for a `loadusr`).
    pub gui_pins: Vec<String>,
}

/// The rules, shared between the launcher and its halcmd session.
#[derive(Debug)]
pub struct Rules {
    /// The TWOPASS pass.
    pub phase: Phase,
    /// What TWOPASS gathered.
    pub twopass: TwoPass,
    /// Component names (pin prefixes) of GUIs not started.
    gui_comps: BTreeSet<String>,
    /// Modules the launcher loaded itself (tpmod, homemod).
    preloaded: Vec<String>,
    /// Lines skipped because of a GUI.
    pub skipped: Vec<Skipped>,
    /// Signals that lost GUI pins: (signal, the pins dropped).
    pub dropped: Vec<(String, Vec<String>)>,
}

impl Default for Rules {
    fn default() -> Self {
        Rules {
            phase: Phase::Normal,
            twopass: TwoPass::new(),
            gui_comps: GUI_COMPONENTS.iter().map(|s| s.to_string()).collect(),
            preloaded: Vec::new(),
            skipped: Vec::new(),
            dropped: Vec::new(),
        }
    }
}

/// The program of a command line, without directory.
fn base(program: &str) -> &str {
    program.rsplit('/').next().unwrap_or(program)
}

/// Whether `program` (a base name) is a GUI: one of [`GUI_PROGRAMS`], or a
/// vismach 3-D view (`scaragui`, `xyzac-trt-gui`, `vismach`...), which
/// LinuxCNC's sim configs start with `loadusr -W NAMEgui`.
fn is_gui_program(program: &str) -> bool {
    let program = program.strip_suffix(".py").unwrap_or(program);
    GUI_PROGRAMS.contains(&program) || program == "vismach" || program.ends_with("gui")
}

/// Python modules that only a program with a window imports: vismach
/// (a machine's own 3-D view), GTK, Tk and Qt.
const GUI_MODULES: &[&str] = &[
    "vismach", "gtk", "gobject", "gi", "tkinter", "Tkinter", "PyQt5", "PyQt6", "qtvcp",
];

/// Whether `program` (as a `loadusr` names it) is a machine's own GUI
/// program: a Python script beside the configuration that imports a
/// module of [`GUI_MODULES`] (LinuxCNC's rolfmill starts its 3-D view with
/// `loadusr -W ./rolfmill`, craftsman its tool change dialog with
/// `loadusr -W ./craftsman_toolchange`). Only a file named by a path, or
/// found in the working directory (the INI file's), is looked at, and
/// only its first 64 KiB.
fn is_gui_script(program: &str) -> bool {
    let path = std::path::Path::new(program);
    if !path.is_file() {
        return false;
    }
    let Ok(text) = hal_core::files::read_user_text(path, 64 << 10, "program") else {
        // Larger than a script, or not readable: not a GUI script.
        return false;
    };
    text.lines().any(|line| {
        let line = line.trim_start();
        let modules = if let Some(rest) = line.strip_prefix("from ") {
            rest.split_whitespace().next().unwrap_or("")
        } else if let Some(rest) = line.strip_prefix("import ") {
            rest.split('#').next().unwrap_or("")
        } else {
            return false;
        };
        modules
            .split(',')
            .map(|m| m.trim().split(['.', ' ']).next().unwrap_or(""))
            .any(|m| GUI_MODULES.contains(&m))
    })
}

/// The HAL component a GUI panel command creates (`[DISPLAY]GLADEVCP`,
/// `[DISPLAY]EMBED_TAB_COMMAND`): the name given with `-c` or `-Wn`, else
/// `gladevcp` for a GladeVCP panel, else the screen name a QtVCP panel is
/// given last. `None` for a command that makes no HAL component (an
/// xterm, an on-screen keyboard).
pub fn panel_component(command: &str, gladevcp_default: bool) -> Option<String> {
    let words: Vec<&str> = command.split_whitespace().collect();
    let named = words
        .windows(2)
        .find(|w| w[0] == "-c" || w[0] == "-Wn")
        .map(|w| w[1].to_string());
    if named.is_some() {
        return named;
    }
    let program = words
        .iter()
        .map(|w| base(w))
        .find(|w| *w == "gladevcp" || *w == "qtvcp");
    match program {
        Some("gladevcp") => Some("gladevcp".to_string()),
        Some(_) => words.last().map(|w| w.to_string()),
        None if gladevcp_default => Some("gladevcp".to_string()),
        None => None,
    }
}

impl Rules {
    /// Treats `name.*` pins as those of a GUI that is not started.
    pub fn add_gui_component(&mut self, name: &str) {
        self.gui_comps.insert(name.to_string());
    }

    /// Records a module the launcher loaded, so a HAL file's own `loadrt`
    /// of it is accepted.
    pub fn preloaded(&mut self, module: &str) {
        self.preloaded.push(module.to_string());
    }

    /// Whether `name` is a pin (or param) of a GUI not started: it does
    /// not exist and its component is a GUI's.
    fn is_gui_name(&self, inst: &Instance, name: &str) -> bool {
        let Some((comp, _)) = name.split_once('.') else {
            return false;
        };
        if !self.gui_comps.contains(comp) {
            return false;
        }
        let exists =
            inst.pin(name).ok().flatten().is_some() || inst.param(name).ok().flatten().is_some();
        !exists
    }

    fn skip(&mut self, at: &str, words: &[String], gui_pins: Vec<String>) -> Verdict {
        self.skipped.push(Skipped {
            at: at.to_string(),
            command: words.join(" "),
            gui_pins,
        });
        Verdict::Skip
    }

    /// The GUI rules: a GUI program is not started (its component name is
    /// remembered); a line naming pins of a GUI not started loses them.
    fn gui(&mut self, inst: &Instance, words: &[String], at: &str) -> Option<Verdict> {
        let cmd = words.first()?.as_str();
        match cmd {
            "loadusr" => {
                let args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
                let spec = usr::parse(&args).ok()?;
                let program = base(&spec.program);
                let nogui = spec.args.iter().any(|a| a == "--nogui");
                if !(is_gui_program(program) || is_gui_script(&spec.program)) || nogui {
                    return None;
                }
                // pyvcp and gladevcp name their component with -c.
                let named_c = spec
                    .args
                    .iter()
                    .position(|a| a == "-c")
                    .and_then(|i| spec.args.get(i + 1));
                let comp = spec
                    .name
                    .clone()
                    .or_else(|| named_c.cloned())
                    .unwrap_or_else(|| usr::guess_comp_name(program).to_string());
                self.add_gui_component(&comp);
                Some(self.skip(at, words, Vec::new()))
            }
            "net" => {
                let (gui, kept): (Vec<&String>, Vec<&String>) = words[2.min(words.len())..]
                    .iter()
                    .partition(|w| self.is_gui_name(inst, w));
                if gui.is_empty() {
                    return None;
                }
                let gui: Vec<String> = gui.into_iter().cloned().collect();
                self.dropped.push((words[1].clone(), gui.clone()));
                let pins: Vec<&String> = kept
                    .into_iter()
                    .filter(|w| !(w.starts_with('<') || w.starts_with('=')))
                    .collect();
                self.skipped.push(Skipped {
                    at: at.to_string(),
                    command: words.join(" "),
                    gui_pins: gui,
                });
                if pins.is_empty() {
                    return Some(Verdict::Skip);
                }
                let mut v = vec!["net".to_string(), words[1].clone()];
                v.extend(pins.into_iter().cloned());
                Some(Verdict::RunInstead(v))
            }
            "setp" | "getp" | "ptype" | "unlinkp" | "linkps" | "linksp" | "linkpp" => {
                let gui: Vec<String> = words[1..]
                    .iter()
                    .filter(|w| self.is_gui_name(inst, w))
                    .cloned()
                    .collect();
                (!gui.is_empty()).then(|| self.skip(at, words, gui))
            }
            // `name = value` is setp.
            _ if words.len() == 3 && words[1] == "=" && self.is_gui_name(inst, cmd) => {
                Some(self.skip(at, words, vec![cmd.to_string()]))
            }
            _ => None,
        }
    }

    /// Pins left on signals that lost their GUI partners: (pin, signal,
    /// the GUI pins it would have been connected to).
    pub fn orphans(&self, inst: &Instance) -> Vec<(String, String, Vec<String>)> {
        let mut out: Vec<(String, String, Vec<String>)> = Vec::new();
        for (signal, gui) in &self.dropped {
            let Ok(Some(info)) = inst.signal(signal) else {
                continue;
            };
            for (pin, _) in &info.pins {
                match out.iter_mut().find(|(p, s, _)| p == pin && s == signal) {
                    Some(entry) => entry.2.extend(gui.iter().cloned()),
                    None => out.push((pin.clone(), signal.clone(), gui.clone())),
                }
            }
        }
        out
    }
}

impl CommandFilter for Rules {
    fn check(&mut self, inst: &Instance, words: &[String], at: &str) -> Result<Verdict, LangError> {
        let Some(cmd) = words.first().map(String::as_str) else {
            return Ok(Verdict::Run);
        };
        let module = words.get(1).map(String::as_str).unwrap_or("");
        if cmd == "loadrt" && self.preloaded.iter().any(|m| m == module) {
            return Ok(Verdict::Skip);
        }
        match (self.phase, cmd) {
            (Phase::Pass0 | Phase::Pass0Tcl, "loadrt") => {
                self.twopass
                    .gather(&words[1..])
                    .map_err(|e| LangError::Filter(Box::new(e)))?;
                return Ok(Verdict::Skip);
            }
            (Phase::Pass0, "loadusr" | "source" | "quit" | "exit") => {}
            (Phase::Pass0, _) | (Phase::Pass0Tcl, "addf") => return Ok(Verdict::Skip),
            (Phase::Pass1, "loadrt") if self.twopass.loaded_in_pass0(module) => {
                return Ok(Verdict::Skip)
            }
            (Phase::Pass1, "loadusr") => return Ok(Verdict::Skip),
            _ => {}
        }
        Ok(self.gui(inst, words, at).unwrap_or(Verdict::Run))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panel_components_are_named_as_the_panels_name_them() {
        let cases = [
            (
                "halcmd loadusr -Wn gladevcp8 gladevcp -c gladevcp8 -x {XID} ./m.ui",
                false,
                Some("gladevcp8"),
            ),
            ("gladevcp -x {XID} gremlin_view.ui", false, Some("gladevcp")),
            ("qtvcp vismach_scara", false, Some("vismach_scara")),
            ("xterm -into {XID} -e top", false, None),
            // [DISPLAY]GLADEVCP holds only gladevcp's arguments.
            ("-u handler.py panel.ui", true, Some("gladevcp")),
            ("-c gladevcp show.ui", true, Some("gladevcp")),
        ];
        for (command, glade, want) in cases {
            assert_eq!(
                panel_component(command, glade).as_deref(),
                want,
                "{command}"
            );
        }
    }

    #[test]
    fn a_script_that_imports_a_gui_toolkit_is_a_gui() {
        let dir = std::env::temp_dir().join(format!("rules-gui-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scripts = [
            (
                "mill",
                "#!/usr/bin/env python3\nfrom vismach import *\n",
                true,
            ),
            ("dialog", "import sys, os \nimport gettext, gobject\n", true),
            ("panel", "from gi.repository import Gtk\n", true),
            ("helper", "#!/bin/sh\nexec halcmd show\n", false),
            (
                "worker",
                "import hal, time  # no window\nfrom math import pi\n",
                false,
            ),
        ];
        for (name, text, gui) in scripts {
            std::fs::write(dir.join(name), text).unwrap();
            assert_eq!(
                is_gui_script(&dir.join(name).display().to_string()),
                gui,
                "{name}"
            );
        }
        assert!(!is_gui_script(&dir.join("absent").display().to_string()));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn vismach_pins_are_a_guis() {
        let rules = Rules::default();
        assert!(rules.gui_comps.contains("vismach"));
    }
}
