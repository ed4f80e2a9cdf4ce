//! A halcmd session: options, output streams, and the command dispatcher.

use std::io::Write;
use std::path::Path;

use hal_core::{AliasKind, HalError, HalType, Instance, PinDir};

use super::format;
use super::ini::Ini;
use super::lexer::{logical_lines, tokenize, unquote, without_comment};
use super::values::parse_value;
use crate::protocol::{Client, ClientError};

/// Options that change how commands run and report.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// Keep going after a failed command (`-k`).
    pub keep_going: bool,
    /// Print nothing but errors... (`-q`, the default) or nothing at all (`-Q`).
    pub silent: bool,
    /// Report each command's success (`-v`).
    pub verbose: bool,
    /// Script-friendly `show` output (`-s`).
    pub script: bool,
    /// The INI file for `[SECTION]KEY` substitution (`-i`).
    pub ini: Option<Ini>,
}

/// The outcome of one command.
pub type CmdResult = Result<(), String>;

/// Executes halcmd commands.
pub struct Session<'o> {
    inst: Instance,
    client: Option<Client>,
    pub opts: Options,
    out: &'o mut dyn Write,
    err: &'o mut dyn Write,
    echo: bool,
    /// Programs started by `loadusr` that nobody waited for.
    children: Vec<std::process::Child>,
    /// Where commands come from, for messages (`test.hal`, or none).
    source: Option<String>,
    line: usize,
}

impl<'o> Session<'o> {
    /// A session on a running instance.
    pub fn new(
        inst: Instance,
        opts: Options,
        out: &'o mut dyn Write,
        err: &'o mut dyn Write,
    ) -> Self {
        Session {
            inst,
            client: None,
            opts,
            out,
            err,
            echo: false,
            children: Vec::new(),
            source: None,
            line: 0,
        }
    }

    /// The instance this session works on.
    pub fn instance(&self) -> &Instance {
        &self.inst
    }

    fn host(&mut self, words: &[&str]) -> CmdResult {
        if self.client.is_none() {
            self.client = Some(Client::connect(self.inst.name()).map_err(|e| e.to_string())?);
        }
        let words: Vec<String> = words.iter().map(|s| s.to_string()).collect();
        let client = self.client.as_mut().expect("connected above");
        match client.call(&words) {
            Ok(()) => Ok(()),
            Err(ClientError::Refused(m)) => Err(m),
            Err(e) => {
                self.client = None;
                Err(e.to_string())
            }
        }
    }

    /// Writes a HAL library error line (no file and line), unless `-Q`.
    fn lib_error(&mut self, msg: &str) {
        if !self.opts.silent {
            let _ = writeln!(self.err, "HAL: ERROR: {msg}");
        }
    }

    /// Writes an error message with the file and line prefix, unless `-Q`.
    pub fn report(&mut self, msg: &str) {
        if self.opts.silent {
            return;
        }
        let prefix = match &self.source {
            Some(f) => format!("{f}:{}: ", self.line),
            None => String::new(),
        };
        let _ = writeln!(self.err, "{prefix}{msg}");
    }

    /// Runs every command of a file's text; `name` labels messages. Returns
    /// false if a command failed (and, without `-k`, stops there).
    pub fn run_text(&mut self, name: Option<&str>, text: &str) -> bool {
        let saved = (self.source.take(), self.line);
        self.source = name.map(str::to_string);
        let mut ok = true;
        for line in logical_lines(text) {
            self.line = line.number;
            if self.echo {
                let _ = writeln!(
                    self.err,
                    "({})<echo>: {}",
                    line.number,
                    without_comment(&line.text)
                );
            }
            let words = match tokenize(&line.text, self.opts.ini.as_ref()) {
                Ok(w) => w,
                Err(e) => {
                    self.report(&e.to_string());
                    ok = false;
                    if self.opts.keep_going {
                        continue;
                    }
                    break;
                }
            };
            if words.is_empty() {
                continue;
            }
            if !self.run_words(&words) {
                ok = false;
                if !self.opts.keep_going {
                    break;
                }
            }
        }
        (self.source, self.line) = saved;
        ok
    }

    /// Runs one command given as words; reports its error.
    pub fn run_words(&mut self, words: &[String]) -> bool {
        let w: Vec<&str> = words.iter().map(String::as_str).collect();
        let result = self.dispatch(&w);
        let _ = self.out.flush();
        match result {
            Ok(()) => {
                if self.opts.verbose {
                    let _ = writeln!(self.err, "{}'{}' done", self.location(), words.join(" "));
                }
                true
            }
            Err(msg) => {
                self.report(&msg);
                false
            }
        }
    }

    fn dispatch(&mut self, w: &[&str]) -> CmdResult {
        // `name = value` is setp.
        if w.len() == 3 && w[1] == "=" {
            return self.setp(w[0], w[2]);
        }
        let args = &w[1..];
        let need = |n: usize| -> CmdResult {
            if args.len() < n {
                Err(format!(
                    "{} requires at least {n} arguments, {} given",
                    w[0],
                    args.len()
                ))
            } else {
                Ok(())
            }
        };
        match w[0] {
            "loadrt" => {
                need(1)?;
                let unquoted: Vec<String> = args.iter().map(|a| unquote(a)).collect();
                let mut v = vec!["loadrt"];
                v.extend(unquoted.iter().map(String::as_str));
                // LinuxCNC numbers components from one counter that its
                // helper processes also draw from: each loadrt uses two
                // numbers before the module's own.
                let next = self.inst.next_component_id().saturating_add(2);
                self.inst.advance_component_ids(next).map_err(msg)?;
                self.host(&v).map_err(|e| {
                    self.lib_error(&e.to_string());
                    format!("insmod for {} failed, returned -1", args[0])
                })
            }
            "unloadrt" => {
                need(1)?;
                self.host(&["unloadrt", args[0]])
            }
            "unload" => {
                need(1)?;
                let user = args[0] == "all"
                    || self
                        .inst
                        .components()
                        .map_err(msg)?
                        .iter()
                        .any(|c| c.name == args[0] && c.kind == hal_core::ComponentKind::User);
                if user {
                    super::usr::unload(&self.inst, args[0], std::time::Duration::from_secs(10))?;
                }
                if args[0] == "all" || !user {
                    self.host(&["unloadrt", args[0]])?;
                }
                Ok(())
            }
            "addf" => {
                need(2)?;
                let mut v = vec!["addf", args[0], args[1]];
                if let Some(p) = args.get(2) {
                    v.push(p);
                }
                self.host_or(&v, "addf failed")
            }
            "delf" => {
                need(1)?;
                let mut v = vec!["delf", args[0]];
                if let Some(t) = args.get(1) {
                    v.push(t);
                }
                self.host_or(&v, "delf failed")
            }
            "initf" => {
                need(2)?;
                self.host_or(&["initf", args[0], args[1]], "initf failed")
            }
            "linkpp" => {
                // Obsolete form: a signal named after the first pin.
                need(2)?;
                let pins: Vec<&str> = args.iter().copied().filter(|a| !is_arrow(a)).collect();
                if pins.len() != 2 {
                    return Err("linkpp requires exactly 2 pins".into());
                }
                self.connect(pins[0], &pins)
            }
            "start" => self.host(&["start"]),
            "stop" => self.host(&["stop"]),
            "setexact_for_test_suite_only" => {
                if !self.inst.threads().map_err(msg)?.is_empty() {
                    return Err(
                        "HAL_LIB: Cannot run 'setexact' after a thread has been created".into(),
                    );
                }
                let _ = writeln!(
                    self.err,
                    "{}Warning: HAL_LIB: HAL will pretend that the exact base period requested is possible.\nThis mode is not suitable for running real hardware.",
                    self.location()
                );
                self.host(&["setexact"])
            }
            "newsig" => {
                need(2)?;
                let t = HalType::from_name(args[1])
                    .ok_or_else(|| format!("Unknown signal type '{}'", args[1]))?;
                self.inst.newsig(args[0], t).map_err(|e| {
                    self.lib_error(&e.to_string());
                    "newsig failed".to_string()
                })
            }
            "delsig" => {
                need(1)?;
                if args[0] == "all" {
                    self.inst.delsig_all().map_err(msg)
                } else {
                    self.inst.delsig(args[0]).map_err(msg)
                }
            }
            "sets" => {
                need(2)?;
                let name = args[0];
                let t = self
                    .inst
                    .signal_type(name)
                    .map_err(|_| format!("signal '{name}': not found"))?;
                let v = parse_value(t, args[1]).map_err(|e| format!("signal '{name}': {e}"))?;
                self.inst.set_signal(name, v).map_err(|e| match e {
                    HalError::SignalDriven { .. } => format!("signal '{name}': not writable"),
                    other => other.to_string(),
                })
            }
            "setp" => {
                need(2)?;
                self.setp(args[0], args[1])
            }
            "net" => {
                need(1)?;
                self.net(args[0], &args[1..])
            }
            "linkps" => {
                need(2)?;
                let sig = args
                    .iter()
                    .skip(1)
                    .find(|a| !is_arrow(a))
                    .ok_or("linkps: missing signal")?;
                let r = self.inst.link(args[0], sig);
                self.lib_or(r, "link failed")
            }
            "linksp" => {
                need(2)?;
                let pin = args
                    .iter()
                    .skip(1)
                    .find(|a| !is_arrow(a))
                    .ok_or("linksp: missing pin")?;
                let r = self.inst.link(pin, args[0]);
                self.lib_or(r, "link failed")
            }
            "unlinkp" => {
                need(1)?;
                let r = self.inst.unlink(args[0]);
                self.lib_or(r, "unlink failed")
            }
            "alias" | "unalias" => {
                need(if w[0] == "alias" { 3 } else { 2 })?;
                let kind = match args[0] {
                    "pin" => AliasKind::Pin,
                    "param" => AliasKind::Param,
                    other => {
                        return Err(format!(
                            "{}: unknown type '{other}', use pin or param",
                            w[0]
                        ))
                    }
                };
                if w[0] == "alias" {
                    self.inst.alias(kind, args[1], args[2]).map_err(msg)
                } else {
                    self.inst.unalias(kind, args[1]).map_err(msg)
                }
            }
            "echo" => {
                self.echo = true;
                let _ = writeln!(self.out, "Echo on");
                Ok(())
            }
            "unecho" => {
                self.echo = false;
                let _ = writeln!(self.out, "Echo off");
                Ok(())
            }
            "print" => {
                let text = if args.is_empty() {
                    "(null)".to_string()
                } else {
                    args.join(" ")
                };
                let _ = writeln!(self.err, "{}HALCMD MSG: {text}", self.location());
                Ok(())
            }
            "source" => {
                need(1)?;
                let text = std::fs::read_to_string(args[0])
                    .map_err(|e| format!("source {}: {e}", args[0]))?;
                let name = Path::new(args[0]).to_string_lossy().into_owned();
                if self.run_text(Some(&name), &text) {
                    Ok(())
                } else {
                    Err(format!("source {} failed", args[0]))
                }
            }
            "loadusr" => {
                let spec = super::usr::parse(args)?;
                // A user program registers with LinuxCNC's id counter twice.
                let next = self.inst.next_component_id().saturating_add(2);
                self.inst.advance_component_ids(next).map_err(msg)?;
                let _ = self.out.flush();
                if let Some(child) = super::usr::run(&self.inst, &spec)? {
                    self.children.push(child);
                }
                Ok(())
            }
            "waitusr" => {
                need(1)?;
                super::usr::wait_gone(&self.inst, args[0])
            }
            "unloadusr" => {
                need(1)?;
                super::usr::unload(&self.inst, args[0], std::time::Duration::from_secs(10))
            }
            "lock" | "unlock" | "debug" => Ok(()),
            "show" | "list" | "save" | "getp" | "gets" | "ptype" | "stype" | "status" | "help" => {
                let text = format::render(&self.inst, w, &self.opts)?;
                let _ = self.out.write_all(text.as_bytes());
                Ok(())
            }
            other => Err(format!("Unknown command '{other}'")),
        }
    }

    /// A host request whose refusal is reported as LinuxCNC reports a
    /// failing HAL library call: the library's message unprefixed, then
    /// `what` with the file and line.
    fn host_or(&mut self, words: &[&str], what: &str) -> CmdResult {
        self.host(words).map_err(|e| {
            self.lib_error(&e.to_string());
            what.to_string()
        })
    }

    /// A segment operation's failure, reported like [`Self::host_or`].
    fn lib_or<T>(&mut self, r: hal_core::Result<T>, what: &str) -> CmdResult {
        r.map(|_| ()).map_err(|e| {
            self.lib_error(&e.to_string());
            what.to_string()
        })
    }

    fn location(&self) -> String {
        match &self.source {
            Some(f) => format!("{f}:{}: ", self.line),
            None => String::new(),
        }
    }

    fn setp(&mut self, name: &str, value: &str) -> CmdResult {
        // A param wins over a pin of the same name.
        let (_, t, is_param) = format::lookup(&self.inst, name)?
            .ok_or_else(|| format!("parameter or pin '{name}': not found"))?;
        let what = if is_param { "parameter" } else { "pin" };
        let v = parse_value(t, value).map_err(|e| format!("{what} '{name}': {e}"))?;
        let r = if is_param {
            self.inst.set_param(name, v)
        } else {
            self.inst.set_pin(name, v)
        };
        r.map_err(|e| match e {
            HalError::ParamReadOnly { .. }
            | HalError::PinIsOutput { .. }
            | HalError::PinConnected { .. } => {
                format!("{what} '{name}': not writable")
            }
            other => other.to_string(),
        })
    }

    /// `net SIGNAL PIN...`: the user-facing checks, then [`Self::connect`].
    fn net(&mut self, signal: &str, items: &[&str]) -> CmdResult {
        let pins: Vec<&str> = items.iter().copied().filter(|a| !is_arrow(a)).collect();
        if pins.is_empty() {
            return Err("'net' requires at least one pin, none given".into());
        }
        if format::lookup(&self.inst, signal)?.is_some_and(|(_, _, is_param)| !is_param) {
            return Err(format!(
                "Signal name '{signal}' must not be the same as a pin.  Did you omit the signal name?"
            ));
        }
        self.connect(signal, &pins)
    }

    /// Links `pins` to `signal`, creating it with the first pin's type.
    /// Everything is checked before anything changes.
    fn connect(&mut self, signal: &str, pins: &[&str]) -> CmdResult {
        // Check everything first, so that a failing net changes nothing.
        let existing = self.inst.signal(signal).map_err(msg)?;
        let mut sig_type = existing.as_ref().map(|s| s.hal_type);
        let mut writer: Option<String> = existing.as_ref().and_then(|s| {
            s.pins
                .iter()
                .find(|(_, d)| *d == PinDir::Out)
                .map(|(n, _)| n.clone())
        });
        let mut bidir: Option<String> = existing.as_ref().and_then(|s| {
            s.pins
                .iter()
                .find(|(_, d)| *d == PinDir::Io)
                .map(|(n, _)| n.clone())
        });
        for p in pins {
            let info = self
                .inst
                .pin(p)
                .map_err(msg)?
                .ok_or_else(|| format!("Pin '{p}' does not exist"))?;
            if let Some(s) = &info.signal {
                if s != signal {
                    return Err(format!("Pin '{p}' was already linked to signal '{s}'"));
                }
                continue;
            }
            match sig_type {
                Some(t) if t != info.hal_type => {
                    return Err(format!(
                        "Signal '{signal}' of type '{t}' cannot add pin '{p}' of type '{}'",
                        info.hal_type
                    ))
                }
                _ => sig_type = Some(info.hal_type),
            }
            match info.dir {
                PinDir::Out => {
                    if let Some(w) = &writer {
                        return Err(format!(
                            "Signal '{signal}' can not add OUT pin '{p}', it already has OUT pin '{w}'"
                        ));
                    }
                    if let Some(b) = &bidir {
                        return Err(format!(
                            "Signal '{signal}' can not add OUT pin '{p}', it already has I/O pin '{b}'"
                        ));
                    }
                    writer = Some(p.to_string());
                }
                PinDir::Io => {
                    if let Some(w) = &writer {
                        return Err(format!(
                            "Signal '{signal}' can not add I/O pin '{p}', it already has OUT pin '{w}'"
                        ));
                    }
                    bidir.get_or_insert_with(|| p.to_string());
                }
                PinDir::In => {}
            }
        }
        if existing.is_none() {
            let t = sig_type.ok_or_else(|| {
                format!("net: signal '{signal}' does not exist and no pin gives its type")
            })?;
            self.inst.newsig(signal, t).map_err(msg)?;
        }
        for p in pins {
            self.inst.link(p, signal).map_err(msg)?;
        }
        Ok(())
    }
}

/// Words halcmd treats as arrows and ignores (`=>`, `<=`, `<=>`, `==>`, ...).
fn is_arrow(s: &str) -> bool {
    s.starts_with('<') || s.starts_with('=')
}

impl Drop for Session<'_> {
    /// Programs started by `loadusr` without waiting end with the session.
    fn drop(&mut self) {
        for child in &mut self.children {
            if let Ok(None) = child.try_wait() {
                let _ = nix::sys::signal::kill(
                    nix::unistd::Pid::from_raw(child.id() as i32),
                    nix::sys::signal::Signal::SIGTERM,
                );
            }
        }
        for child in &mut self.children {
            let _ = child.wait();
        }
    }
}

fn msg(e: HalError) -> String {
    e.to_string()
}
