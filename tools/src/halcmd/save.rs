//! `save`: the instance written back as halcmd commands.

use hal_core::{ComponentKind, HalType, Instance, PinDir, SignalInfo};

use super::format::show_value;

type R = Result<String, String>;

fn e(err: hal_core::HalError) -> String {
    err.to_string()
}

/// `data_type` of LinuxCNC: the type name padded to five.
fn t5(t: HalType) -> String {
    format!("{:<5}", t.name())
}

/// The arrow from a pin's side (`linka`).
fn arrow_pin(d: PinDir) -> &'static str {
    match d {
        PinDir::In => "<==",
        PinDir::Out => "==>",
        PinDir::Io => "<=>",
    }
}

/// The arrow from a signal's side (`neta`).
fn arrow_sig(d: PinDir) -> &'static str {
    match d {
        PinDir::In => "==>",
        PinDir::Out => "<==",
        PinDir::Io => "<=>",
    }
}

fn comps(inst: &Instance) -> R {
    let mut cs = inst.components().map_err(e)?;
    cs.sort_by_key(|c| c.id);
    let mut out = String::from("# components\n");
    for c in cs.iter().filter(|c| c.kind != ComponentKind::User) {
        match &c.loadrt_args {
            Some(a) => out.push_str(&format!("loadrt {a}\n")),
            None => out.push_str(&format!(
                "#loadrt {}  (not loaded by loadrt, no args saved)\n",
                c.name
            )),
        }
    }
    Ok(out)
}

fn aliases(inst: &Instance) -> R {
    let mut out = String::from("# pin aliases\n");
    for p in inst.pins().map_err(e)? {
        if let Some(o) = p.orig_name {
            out.push_str(&format!("alias pin {o} {}\n", p.name));
        }
    }
    out.push_str("# param aliases\n");
    for p in inst.params().map_err(e)? {
        if let Some(o) = p.orig_name {
            out.push_str(&format!("alias param {o} {}\n", p.name));
        }
    }
    Ok(out)
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

fn links(inst: &Instance, arrows: bool) -> R {
    let mut out = String::from("# links\n");
    for p in inst.pins().map_err(e)? {
        if let Some(s) = p.signal {
            let a = if arrows { arrow_pin(p.dir) } else { "" };
            out.push_str(&format!("linkps {} {a} {s}\n", p.name));
        }
    }
    Ok(out)
}

fn nets(sigs: &[SignalInfo], arrows: bool) -> String {
    let mut out = String::from("# nets\n");
    for s in sigs {
        out.push_str(&format!("newsig {} {}\n", s.name, t5(s.hal_type)));
        for (pin, dir) in &s.pins {
            let a = if arrows { arrow_sig(*dir) } else { "" };
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

fn params(inst: &Instance) -> R {
    let mut out = String::from("# parameter values\n");
    for p in inst.params().map_err(e)? {
        if p.dir == hal_core::ParamDir::Rw {
            out.push_str(&format!("setp {} {:>20}\n", p.name, show_value(p.value)));
        }
    }
    Ok(out)
}

fn threads(inst: &Instance) -> R {
    let mut out = String::from("# realtime thread/function links\n");
    for t in inst.threads().map_err(e)? {
        for f in &t.functs {
            out.push_str(&format!("addf {f} {}\n", t.name));
        }
        for f in &t.init_functs {
            out.push_str(&format!("initf {f} {}\n", t.name));
        }
    }
    Ok(out)
}

fn unconnected(inst: &Instance) -> R {
    let mut out = String::from("# unconnected pin values\n");
    for p in inst.pins().map_err(e)? {
        if p.signal.is_none() && p.dir != PinDir::Out {
            out.push_str(&format!("setp {} {:>20}\n", p.name, show_value(p.value)));
        }
    }
    Ok(out)
}

/// Renders `save [TYPE]`.
pub fn save(inst: &Instance, kind: Option<&str>) -> R {
    let sigs = || inst.signals().map_err(e);
    Ok(match kind.unwrap_or("all") {
        "comp" => comps(inst)?,
        "alias" => aliases(inst)?,
        "sig" | "signal" => signals(&sigs()?, false),
        "sigu" => signals(&sigs()?, true),
        "link" => links(inst, false)?,
        "linka" => links(inst, true)?,
        "net" => nets(&sigs()?, false),
        "neta" => nets(&sigs()?, true),
        "netl" => net_lines(&sigs()?, false),
        "netla" | "netal" => net_lines(&sigs()?, true),
        "param" | "parameter" => params(inst)?,
        "thread" => threads(inst)?,
        "unconnectedinpins" => unconnected(inst)?,
        "all" => {
            let s = sigs()?;
            [
                comps(inst)?,
                aliases(inst)?,
                signals(&s, true),
                net_lines(&s, true),
                params(inst)?,
                threads(inst)?,
            ]
            .concat()
        }
        "allu" => {
            let s = sigs()?;
            [
                comps(inst)?,
                aliases(inst)?,
                signals(&s, true),
                net_lines(&s, true),
                params(inst)?,
                unconnected(inst)?,
                threads(inst)?,
            ]
            .concat()
        }
        other => return Err(format!("Unknown 'save' type '{other}'")),
    })
}
