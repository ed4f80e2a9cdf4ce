//! `save`: the instance written back as halcmd commands.

use hal_core::{
    ComponentInfo, ComponentKind, HalType, Instance, ParamInfo, PinDir, PinInfo, SignalInfo,
    ThreadInfo,
};

use crate::error::{LangError, Result};
use crate::format::{pin_arrow, show_value, sig_arrow, thread_switches};

/// `data_type` of LinuxCNC: the type name padded to five.
fn t5(t: HalType) -> String {
    format!("{:<5}", t.name())
}

fn comps(comps: &[ComponentInfo]) -> String {
    let mut cs: Vec<&ComponentInfo> = comps
        .iter()
        .filter(|c| c.kind != ComponentKind::User)
        .collect();
    cs.sort_by_key(|c| c.id);
    let mut out = String::from("# components\n");
    for c in cs {
        match &c.loadrt_args {
            Some(a) => out.push_str(&format!("loadrt {a}\n")),
            None => out.push_str(&format!(
                "#loadrt {}  (not loaded by loadrt, no args saved)\n",
                c.name
            )),
        }
    }
    out
}

fn aliases(pins: &[PinInfo], params: &[ParamInfo]) -> String {
    let mut out = String::from("# pin aliases\n");
    for p in pins {
        if let Some(o) = &p.orig_name {
            out.push_str(&format!("alias pin {o} {}\n", p.name));
        }
    }
    out.push_str("# param aliases\n");
    for p in params {
        if let Some(o) = &p.orig_name {
            out.push_str(&format!("alias param {o} {}\n", p.name));
        }
    }
    out
}

fn signals(sigs: &[SignalInfo], unlinked_only: bool) -> String {
    let mut out = String::from("# signals\n");
    for s in sigs {
        if !unlinked_only || (s.writers == 0 && s.readers == 0) {
            out.push_str(&format!("newsig {} {}\n", s.name, t5(s.hal_type)));
        }
    }
    out
}

fn links(pins: &[PinInfo], arrows: bool) -> String {
    let mut out = String::from("# links\n");
    for p in pins {
        if let Some(s) = &p.signal {
            let a = if arrows { pin_arrow(p.dir) } else { "" };
            out.push_str(&format!("linkps {} {a} {s}\n", p.name));
        }
    }
    out
}

fn nets(sigs: &[SignalInfo], arrows: bool) -> String {
    let mut out = String::from("# nets\n");
    for s in sigs {
        out.push_str(&format!("newsig {} {}\n", s.name, t5(s.hal_type)));
        for (pin, dir) in &s.pins {
            let a = if arrows { sig_arrow(*dir) } else { "" };
            out.push_str(&format!("linksp {} {a} {pin}\n", s.name));
        }
    }
    out
}

/// One `net` line per signal with pins: writers, then I/O pins, then
/// readers, with `=>` after the writer side when asked for.
fn net_lines(sigs: &[SignalInfo], arrows: bool) -> String {
    let mut out = String::from("# nets\n");
    for s in sigs.iter().filter(|s| !s.pins.is_empty()) {
        let mut line = format!("net {}", s.name);
        let mut state = false;
        for (pin, _) in s.pins.iter().filter(|(_, d)| *d == PinDir::Out) {
            line.push_str(&format!(" {pin}"));
            state = true;
        }
        let mut first_io = true;
        let mut any_io = false;
        for (pin, _) in s.pins.iter().filter(|(_, d)| *d == PinDir::Io) {
            line.push(' ');
            if arrows {
                if state {
                    line.push_str("=> ");
                    state = false;
                } else if !first_io {
                    line.push_str("<=> ");
                }
            }
            line.push_str(pin);
            first_io = false;
            any_io = true;
        }
        if any_io {
            state = true;
        }
        for (pin, _) in s.pins.iter().filter(|(_, d)| *d == PinDir::In) {
            line.push(' ');
            if arrows && state {
                line.push_str("=> ");
                state = false;
            }
            line.push_str(pin);
        }
        out.push_str(&line);
        out.push('\n');
    }
    out
}

fn params(params: &[ParamInfo]) -> String {
    let mut out = String::from("# parameter values\n");
    for p in params {
        if p.dir == hal_core::ParamDir::Rw {
            out.push_str(&format!("setp {} {:>20}\n", p.name, show_value(p.value)));
        }
    }
    out
}

fn threads(threads: &[ThreadInfo]) -> String {
    let mut out = String::from("# realtime thread/function links\n");
    for t in threads {
        for f in &t.functs {
            out.push_str(&format!("addf {f} {}\n", t.name));
        }
        for f in &t.init_functs {
            out.push_str(&format!("initf {f} {}\n", t.name));
        }
        let switches = thread_switches(t);
        if !switches.is_empty() {
            out.push_str(&format!("setthread {} {switches}\n", t.name));
        }
    }
    out
}

fn unconnected(pins: &[PinInfo]) -> String {
    let mut out = String::from("# unconnected pin values\n");
    for p in pins {
        if p.signal.is_none() && p.dir != PinDir::Out {
            out.push_str(&format!("setp {} {:>20}\n", p.name, show_value(p.value)));
        }
    }
    out
}

/// Renders `save [TYPE]`; each kind of object is read once.
pub fn save(inst: &Instance, kind: Option<&str>) -> Result<String> {
    Ok(match kind.unwrap_or("all") {
        "comp" => comps(&inst.components()?),
        "alias" => aliases(&inst.pins()?, &inst.params()?),
        "sig" | "signal" => signals(&inst.signals()?, false),
        "sigu" => signals(&inst.signals()?, true),
        "link" => links(&inst.pins()?, false),
        "linka" => links(&inst.pins()?, true),
        "net" => nets(&inst.signals()?, false),
        "neta" => nets(&inst.signals()?, true),
        "netl" => net_lines(&inst.signals()?, false),
        "netla" | "netal" => net_lines(&inst.signals()?, true),
        "param" | "parameter" => params(&inst.params()?),
        "thread" => threads(&inst.threads()?),
        "unconnectedinpins" => unconnected(&inst.pins()?),
        kind @ ("all" | "allu") => {
            // One snapshot of pins, params and signals serves every
            // section that lists them.
            let pins = inst.pins()?;
            let pars = inst.params()?;
            let sigs = inst.signals()?;
            let mut out = comps(&inst.components()?);
            out += &aliases(&pins, &pars);
            out += &signals(&sigs, true);
            out += &net_lines(&sigs, true);
            out += &params(&pars);
            if kind == "allu" {
                out += &unconnected(&pins);
            }
            out += &threads(&inst.threads()?);
            out
        }
        other => {
            return Err(LangError::UnknownKind {
                command: "save",
                kind: other.to_string(),
            })
        }
    })
}
