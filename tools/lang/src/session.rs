//! A halcmd session: options, output streams, and the command dispatcher.

use std::cell::RefCell;
use std::io::Write;
use std::path::Path;
use std::rc::Rc;
use std::time::Duration;

use hal_core::{AliasKind, ComponentKind, HalError, HalType, Instance, PinDir};

use crate::format;
use crate::ini::Ini;
use crate::lexer::{logical_lines, tokenize, unquote, without_comment};
use crate::values::parse_value;
use crate::protocol::{Client, ClientError, HostLink};

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

/// What a [`CommandFilter`] decides about a command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Verdict {
    /// Run it as written.
    Run,
    /// Run these words instead.
    RunInstead(Vec<String>),
    /// Do not run it; it counts as done.
    Skip,
}

/// A hook that sees every command of a session before it runs: the
/// launcher's TWOPASS processing and its rules for GUI components that a
/// headless machine does not start. `at` is the file and line (`f.hal:3`),
/// or empty for commands from elsewhere.
pub trait CommandFilter {
    /// Decides about `words`; an error fails the command with that message.
    fn check(&mut self, inst: &Instance, words: &[String], at: &str) -> Result<Verdict, String>;
}

/// A shared handle on a filter (the launcher keeps another to read what the
/// filter collected).
pub type SharedFilter<'o> = Rc<RefCell<dyn CommandFilter + 'o>>;

/// Executes halcmd commands.
pub struct Session<'o> {
    inst: Instance,
    /// Where host requests go; the socket, connected on first use.
    client: Option<Box<dyn HostLink + 'o>>,
    /// How commands run and report; `-k` and friends may change mid-file.
    pub opts: Options,
    out: &'o mut dyn Write,
    err: &'o mut dyn Write,
    echo: bool,
    /// Programs started by `loadusr` that nobody waited for and the host
    /// could not adopt: they end with the session.
    children: Vec<std::process::Child>,
    /// Programs the host adopted: they outlive the session, as in
    /// LinuxCNC, and end with `unloadusr` or the instance. Kept only to
    /// reap those that end while the session lasts.
    adopted: Vec<std::process::Child>,
    /// Where commands come from, for messages (`test.hal`, or none).
    source: Option<String>,
    line: usize,
    /// Set by `quit`/`exit`: no more commands are read.
    done: bool,
    filter: Option<SharedFilter<'o>>,
    /// Output and error text kept instead of written (see [`Session::captured`]).
    capture: Option<(Vec<u8>, Vec<u8>)>,
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
            adopted: Vec::new(),
            source: None,
            line: 0,
            done: false,
            filter: None,
            capture: None,
        }
    }

    /// Sends the session's host requests through `link` instead of the
    /// host's socket (the fuzz targets run a host in their own process).
    pub fn with_host_link(mut self, link: Box<dyn HostLink + 'o>) -> Self {
        self.client = Some(link);
        self
    }

    /// The instance this session works on.
    pub fn instance(&self) -> &Instance {
        &self.inst
    }

    /// Whether `quit` or `exit` ended the session's input.
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// Reads commands again after `quit` or `exit`.
    pub fn resume(&mut self) {
        self.done = false;
    }

    /// Routes every later command through `filter` first.
    pub fn set_filter(&mut self, filter: SharedFilter<'o>) {
        self.filter = Some(filter);
    }

    /// Runs `f` with the session's output and error text kept instead of
    /// written; returns its result and the text (haltcl's `hal` command
    /// returns it to Tcl).
    pub fn captured<R>(&mut self, f: impl FnOnce(&mut Self) -> R) -> (R, String, String) {
        let saved = self.capture.replace((Vec::new(), Vec::new()));
        let r = f(self);
        let (out, err) = std::mem::replace(&mut self.capture, saved).unwrap_or_default();
        (
            r,
            String::from_utf8_lossy(&out).into_owned(),
            String::from_utf8_lossy(&err).into_owned(),
        )
    }

    /// Runs one command as if it were line `line` of `file` (haltcl passes
    /// the Tcl script's position).
    pub fn run_words_at(&mut self, file: Option<&str>, line: usize, words: &[String]) -> bool {
        let saved = (self.source.take(), self.line);
        self.source = file.map(str::to_string);
        self.line = line;
        let ok = self.run_words(words);
        (self.source, self.line) = saved;
        ok
    }

    fn w_out(&mut self) -> &mut dyn Write {
        match &mut self.capture {
            Some((out, _)) => out,
            None => &mut *self.out,
        }
    }

    fn w_err(&mut self) -> &mut dyn Write {
        match &mut self.capture {
            Some((_, err)) => err,
            None => &mut *self.err,
        }
    }

    fn host(&mut self, words: &[&str]) -> CmdResult {
        if self.client.is_none() {
            let client = Client::connect(self.inst.name()).map_err(|e| e.to_string())?;
            self.client = Some(Box::new(client));
        }
        let words: Vec<String> = words.iter().map(|s| s.to_string()).collect();
        let client = self.client.as_mut().expect("connected above");
        match client.call(&words) {
            Ok(()) => Ok(()),
            Err(ClientError::Refused(m)) => Err(m),
            // Refused before sending: the link is still good.
            Err(e @ ClientError::BadArgument { .. }) => Err(e.to_string()),
            Err(e) => {
                self.client = None;
                Err(e.to_string())
            }
        }
    }

    /// Writes a HAL library error line (no file and line), unless `-Q`.
    fn lib_error(&mut self, msg: &str) {
        if !self.opts.silent {
            let _ = writeln!(self.w_err(), "HAL: ERROR: {msg}");
        }
    }

    /// Writes an error message with the file and line prefix, unless `-Q`.
    pub fn report(&mut self, msg: &str) {
        if !self.opts.silent {
            let at = self.location();
            let _ = writeln!(self.w_err(), "{at}{msg}");
        }
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
                    self.w_err(),
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
            if self.done {
                break;
            }
        }
        (self.source, self.line) = saved;
        ok
    }

    /// Runs one command given as words; reports its error.
    pub fn run_words(&mut self, words: &[String]) -> bool {
        let verdict = match self.filter.clone() {
            Some(f) => {
                let at = self.location();
                let at = at.trim_end_matches(": ");
                let v = f.borrow_mut().check(&self.inst, words, at);
                v
            }
            None => Ok(Verdict::Run),
        };
        let replaced;
        let words = match verdict {
            Ok(Verdict::Run) => words,
            Ok(Verdict::RunInstead(w)) => {
                replaced = w;
                &replaced[..]
            }
            Ok(Verdict::Skip) => return true,
            Err(msg) => {
                self.report(&msg);
                return false;
            }
        };
        if words.is_empty() {
            return true;
        }
        let w: Vec<&str> = words.iter().map(String::as_str).collect();
        let result = self.dispatch(&w);
        let _ = self.w_out().flush();
        match result {
            Ok(()) => {
                if self.opts.verbose {
                    let at = self.location();
                    let _ = writeln!(self.w_err(), "{at}'{}' done", words.join(" "));
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
        let Some(spec) = COMMANDS.iter().find(|c| c.name == w[0]) else {
            // `name = value` is setp.
            if w.len() == 3 && w[1] == "=" {
                return self.setp(w[0], w[2]);
            }
            return Err(format!("Unknown command '{}'", w[0]));
        };
        let args = spec.arguments(&w[1..])?;
        let a = args.as_slice();
        match spec.name {
            "loadrt" => {
                let unquoted: Vec<String> = a.iter().map(|s| unquote(s)).collect();
                let mut v = vec!["loadrt"];
                v.extend(unquoted.iter().map(String::as_str));
                // LinuxCNC numbers components from one counter that its
                // helper processes also draw from: each loadrt uses two
                // numbers before the module's own.
                let next = self.inst.next_component_id().saturating_add(2);
                self.inst.advance_component_ids(next).map_err(msg)?;
                self.host(&v).map_err(|e| {
                    self.lib_error(&e.to_string());
                    format!("insmod for {} failed, returned -1", a[0])
                })
            }
            "unloadrt" => self.host(&["unloadrt", a[0]]),
            "setthread" => {
                let mut v = vec!["setthread"];
                v.extend(a.iter().copied());
                self.host(&v)
            }
            "unload" => self.unload(a[0]),
            "addf" => {
                // A position after the thread is optional; LinuxCNC
                // ignores anything beyond it.
                let mut v = vec!["addf", a[0], a[1]];
                v.extend(a.get(2).copied());
                self.host_or(&v, "addf failed")
            }
            "delf" => {
                let mut v = vec!["delf"];
                v.extend(a.iter().copied());
                self.host_or(&v, "delf failed")
            }
            "initf" => self.host_or(&["initf", a[0], a[1]], "initf failed"),
            // Obsolete form: a signal named after the first pin.
            "linkpp" => self.connect(a[0], a),
            "start" => self.host(&["start"]),
            "stop" => self.host(&["stop"]),
            "setexact_for_test_suite_only" => {
                // LinuxCNC refuses once a base period exists, that is once
                // any thread was ever created.
                if self.inst.base_period() != 0 {
                    return Err(
                        "HAL_LIB: Cannot run 'setexact' after a thread has been created".into(),
                    );
                }
                // Thread periods are always exact here: only the warning
                // remains to be given.
                let at = self.location();
                let _ = writeln!(
                    self.w_err(),
                    "{}Warning: HAL_LIB: HAL will pretend that the exact base period requested is possible.\nThis mode is not suitable for running real hardware.",
                    at
                );
                Ok(())
            }
            "newsig" => {
                let t = HalType::from_name(a[1])
                    .ok_or_else(|| format!("Unknown signal type '{}'", a[1]))?;
                let r = self.inst.newsig(a[0], t);
                self.lib_or(r, "newsig failed")
            }
            "delsig" => {
                if a[0] == "all" {
                    self.inst.delsig_all().map_err(msg)
                } else {
                    self.inst.delsig(a[0]).map_err(msg)
                }
            }
            "sets" => {
                let name = a[0];
                let t = self
                    .inst
                    .signal_type(name)
                    .map_err(|_| format!("signal '{name}': not found"))?;
                let v = parse_value(t, a[1]).map_err(|e| format!("signal '{name}': {e}"))?;
                self.inst.set_signal(name, v).map_err(|e| match e {
                    HalError::SignalDriven { .. } => format!("signal '{name}': not writable"),
                    other => other.to_string(),
                })
            }
            "setp" => self.setp(a[0], a[1]),
            "net" => self.net(a[0], &a[1..]),
            "linkps" => {
                let r = self.inst.link(a[0], a[1]);
                self.lib_or(r, "link failed")
            }
            "linksp" => {
                let r = self.inst.link(a[1], a[0]);
                self.lib_or(r, "link failed")
            }
            "unlinkp" => {
                let r = self.inst.unlink(a[0]);
                self.lib_or(r, "unlink failed")
            }
            "alias" | "unalias" => {
                let what = spec.name;
                let kind = match a[0] {
                    "pin" => AliasKind::Pin,
                    "param" => AliasKind::Param,
                    other => {
                        return Err(format!("{what}: unknown type '{other}', use pin or param"))
                    }
                };
                // As LinuxCNC's do_alias_cmd: the library's message, then
                // "alias failed" (or "unalias failed") at the line.
                let r = if what == "alias" {
                    self.inst.alias(kind, a[1], a[2])
                } else {
                    self.inst.unalias(kind, a[1])
                };
                self.lib_or(r, &format!("{what} failed"))
            }
            "echo" => {
                self.echo = true;
                let _ = writeln!(self.w_out(), "Echo on");
                Ok(())
            }
            "unecho" => {
                self.echo = false;
                let _ = writeln!(self.w_out(), "Echo off");
                Ok(())
            }
            "print" => {
                let text = if a.is_empty() {
                    "(null)".to_string()
                } else {
                    a.join(" ")
                };
                let at = self.location();
                let _ = writeln!(self.w_err(), "{at}HALCMD MSG: {text}");
                Ok(())
            }
            "source" => {
                let text =
                    crate::lexer::read_text(a[0]).map_err(|e| format!("source {}: {e}", a[0]))?;
                let name = Path::new(a[0]).to_string_lossy().into_owned();
                if self.run_text(Some(&name), &text) {
                    Ok(())
                } else {
                    Err(format!("source {} failed", a[0]))
                }
            }
            "loadusr" => {
                let spec = crate::usr::parse(a)?;
                // A user program registers with LinuxCNC's id counter twice.
                let next = self.inst.next_component_id().saturating_add(2);
                self.inst.advance_component_ids(next).map_err(msg)?;
                self.inst
                    .check_unlocked(hal_core::lock_bits::LOAD, "loadusr")
                    .map_err(msg)?;
                let _ = self.w_out().flush();
                if let Some(child) = crate::usr::run(&self.inst, &spec)? {
                    self.adopted
                        .retain_mut(|c| !matches!(c.try_wait(), Ok(Some(_))));
                    let pid = child.id().to_string();
                    match self.host(&["adopt", &pid, &spec.program]) {
                        Ok(()) => self.adopted.push(child),
                        Err(_) => self.children.push(child),
                    }
                }
                Ok(())
            }
            "waitusr" => crate::usr::wait_gone(&self.inst, a[0]),
            "unloadusr" => crate::usr::unload(&self.inst, a[0], UNLOAD_LIMIT),
            "lock" | "unlock" => {
                let level = crate::lock::next_level(
                    self.inst.lock_level(),
                    spec.name == "lock",
                    a.first().copied(),
                )?;
                self.inst.set_lock_level(level);
                Ok(())
            }
            "quit" | "exit" => {
                self.done = true;
                Ok(())
            }
            "debug" => Ok(()),
            cmd => {
                // show, list, save, getp, gets, ptype, stype, status, help.
                let text = format::render(&self.inst, cmd, a, self.opts.script)?;
                let _ = self.w_out().write_all(text.as_bytes());
                Ok(())
            }
        }
    }

    /// `unload NAME|all`: a user component is stopped, a realtime one
    /// unloaded with its module.
    fn unload(&mut self, name: &str) -> CmdResult {
        if name == "all" {
            crate::usr::unload(&self.inst, name, UNLOAD_LIMIT)?;
            return self.host(&["unloadrt", name]);
        }
        match self.inst.component(name).map_err(msg)? {
            None => Err(format!("component '{name}' is not loaded")),
            Some(c) if c.kind == ComponentKind::User => {
                crate::usr::unload(&self.inst, name, UNLOAD_LIMIT)
            }
            Some(_) => self.host(&["unloadrt", name]),
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
            HalError::Locked { .. } => format!("{what} '{name}': {e}"),
            other => other.to_string(),
        })
    }

    /// `net SIGNAL PIN...` (arrows already removed): the user-facing
    /// checks, then [`Self::connect`].
    fn net(&mut self, signal: &str, pins: &[&str]) -> CmdResult {
        if pins.is_empty() {
            return Err("'net' requires at least one pin, none given".into());
        }
        if self.inst.pin(signal).map_err(msg)?.is_some() {
            return Err(format!(
                "Signal name '{signal}' must not be the same as a pin.  Did you omit the signal name?"
            ));
        }
        self.connect(signal, pins)
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

/// Words halcmd treats as arrows and drops (`=>`, `<=`, `<=>`, `==>`, ...):
/// any word starting with `<` or `=`, as LinuxCNC's parser.
fn is_arrow(s: &str) -> bool {
    s.starts_with('<') || s.starts_with('=')
}

/// How long `unload` and `unloadusr` wait for a user component to leave.
const UNLOAD_LIMIT: Duration = Duration::from_secs(10);

/// More arguments may follow the counted ones (LinuxCNC's `A_PLUS`).
const PLUS: u8 = 1;
/// Fewer arguments may be given (`A_OPTIONAL`).
const OPTIONAL: u8 = 2;
/// Arrows are dropped before counting (`A_REMOVE_ARROWS`).
const ARROWS: u8 = 4;

/// A command and the arguments it takes, as in LinuxCNC's command table.
struct CommandSpec {
    name: &'static str,
    /// How many arguments it takes.
    args: usize,
    /// [`PLUS`], [`OPTIONAL`], [`ARROWS`].
    flags: u8,
}

const fn cmd(name: &'static str, args: usize, flags: u8) -> CommandSpec {
    CommandSpec { name, args, flags }
}

/// Every command, with its argument count. `print` takes any words (they
/// are printed joined); `initf` takes no position, which this host does
/// not support.
const COMMANDS: &[CommandSpec] = &[
    cmd("addf", 2, PLUS),
    cmd("alias", 3, 0),
    cmd("debug", 1, OPTIONAL),
    cmd("delf", 2, OPTIONAL),
    cmd("delsig", 1, 0),
    cmd("echo", 0, 0),
    cmd("exit", 0, OPTIONAL | PLUS),
    cmd("getp", 1, 0),
    cmd("gets", 1, 0),
    cmd("help", 1, OPTIONAL),
    cmd("initf", 2, 0),
    cmd("linkpp", 2, ARROWS),
    cmd("linkps", 2, ARROWS),
    cmd("linksp", 2, ARROWS),
    cmd("list", 1, PLUS),
    cmd("loadrt", 1, PLUS),
    cmd("loadusr", 0, PLUS),
    cmd("lock", 1, OPTIONAL),
    cmd("net", 1, PLUS | ARROWS),
    cmd("newsig", 2, 0),
    cmd("print", 0, PLUS),
    cmd("quit", 0, OPTIONAL | PLUS),
    cmd("ptype", 1, 0),
    cmd("save", 2, OPTIONAL),
    cmd("setexact_for_test_suite_only", 0, 0),
    cmd("setp", 2, 0),
    cmd("sets", 2, 0),
    cmd("setthread", 2, PLUS),
    cmd("show", 1, OPTIONAL | PLUS),
    cmd("source", 1, 0),
    cmd("start", 0, 0),
    cmd("status", 1, OPTIONAL),
    cmd("stop", 0, 0),
    cmd("stype", 1, 0),
    cmd("unalias", 2, 0),
    cmd("unecho", 0, 0),
    cmd("unlinkp", 1, 0),
    cmd("unload", 1, 0),
    cmd("unloadrt", 1, 0),
    cmd("unloadusr", 1, 0),
    cmd("unlock", 1, OPTIONAL),
    cmd("waitusr", 1, 0),
];

/// Every command's name, as `hal --commands` lists them.
pub fn command_names() -> Vec<String> {
    COMMANDS.iter().map(|c| c.name.to_string()).collect()
}

impl CommandSpec {
    /// The arguments of one use of the command (arrows dropped if it takes
    /// none), or LinuxCNC's message when there are too few or too many.
    fn arguments<'w>(&self, words: &[&'w str]) -> Result<Vec<&'w str>, String> {
        let args: Vec<&str> = words
            .iter()
            .copied()
            .filter(|w| self.flags & ARROWS == 0 || !is_arrow(w))
            .collect();
        let given = args.len();
        let (plus, optional) = (self.flags & PLUS != 0, self.flags & OPTIONAL != 0);
        let bound = if given < self.args && !optional {
            if plus {
                "at least "
            } else {
                ""
            }
        } else if given > self.args && !plus {
            if optional {
                "at most "
            } else {
                ""
            }
        } else {
            return Ok(args);
        };
        Err(format!(
            "{} requires {bound}{} arguments, {given} given",
            self.name, self.args
        ))
    }
}

impl Drop for Session<'_> {
    /// Programs started by `loadusr` without waiting that the host did not
    /// adopt end with the session; adopted ones live on.
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
