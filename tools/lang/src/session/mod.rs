//! A halcmd session: options, output streams, and the command dispatcher.

mod commands;
mod signals;
mod table;

use std::cell::RefCell;
use std::io::Write;
use std::rc::Rc;

use hal_core::Instance;

use crate::error::Result;
use crate::ini::Ini;
use crate::lexer::{logical_lines, tokenize, without_comment, Line};
use crate::protocol::{Client, ClientError, HostLink};

pub use table::command_names;

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
    /// A stop request (the launcher's SIGTERM): once set, no further
    /// command runs and waits (`loadusr -W`, `waitusr`, haltcl) end.
    pub stop: Option<hal_core::userspace::ExitSignals>,
}

/// The outcome of one command.
pub type CmdResult = Result<()>;

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
    fn check(&mut self, inst: &Instance, words: &[String], at: &str) -> Result<Verdict>;
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

    /// Whether a stop was requested ([`Options::stop`]).
    pub fn stop_requested(&self) -> bool {
        self.opts.stop.as_ref().is_some_and(|s| s.requested())
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
            let client = Client::connect(self.inst.name())?;
            self.client = Some(Box::new(client));
        }
        let words: Vec<String> = words.iter().map(|s| s.to_string()).collect();
        let client = self.client.as_mut().expect("connected above");
        match client.call(&words) {
            Ok(()) => Ok(()),
            // Refused by the host, or before sending: the link is still good.
            Err(e @ (ClientError::Refused(_) | ClientError::BadArgument { .. })) => Err(e.into()),
            Err(e) => {
                self.client = None;
                Err(e.into())
            }
        }
    }

    /// Writes a line to the session's output, where commands write
    /// theirs (the launcher's TWOPASS reports it in LinuxCNC's words, on
    /// stdout, as LinuxCNC's twopass.tcl prints them).
    pub fn say(&mut self, line: &str) {
        let out = self.w_out();
        let _ = writeln!(out, "{line}");
        let _ = out.flush();
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
        self.run_lines(name, &logical_lines(text))
    }

    /// Runs logical lines of a file (as [`logical_lines`] cuts them),
    /// each reported under its own line number; several may share one
    /// (a line the launcher rewrote into two commands). Returns false
    /// if a command failed (and, without `-k`, stops there).
    pub fn run_lines(&mut self, name: Option<&str>, lines: &[Line]) -> bool {
        let saved = (self.source.take(), self.line);
        self.source = name.map(str::to_string);
        let mut ok = true;
        for line in lines {
            self.line = line.number;
            if self.stop_requested() {
                self.report("stop requested: the rest of the file is not run");
                ok = false;
                break;
            }
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
        if self.stop_requested() {
            return false;
        }
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
            Err(e) => {
                self.report(&e.to_string());
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
            Err(e) => {
                self.report(&e.to_string());
                false
            }
        }
    }

    fn location(&self) -> String {
        match &self.source {
            Some(f) => format!("{f}:{}: ", self.line),
            None => String::new(),
        }
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
