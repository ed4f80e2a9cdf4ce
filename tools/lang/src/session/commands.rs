//! What each halcmd command does: the dispatcher, and one method per
//! group of commands (host requests, signals and pins, user programs, the
//! session's own commands).

use std::path::Path;
use std::time::Duration;

use hal_core::{AliasKind, ComponentKind, HalError, HalType};

use super::table::COMMANDS;
use super::{CmdResult, Session};
use crate::error::LangError;
use crate::lexer::unquote;
use crate::values::parse_value;

/// How long `unload` and `unloadusr` wait for a user component to leave.
const UNLOAD_LIMIT: Duration = Duration::from_secs(10);

impl Session<'_> {
    /// Runs one command (its words, arrows still in).
    pub(super) fn dispatch(&mut self, w: &[&str]) -> CmdResult {
        let Some(spec) = COMMANDS.iter().find(|c| c.name == w[0]) else {
            // `name = value` is setp.
            if w.len() == 3 && w[1] == "=" {
                return self.setp(w[0], w[2]);
            }
            return Err(LangError::UnknownCommand {
                name: w[0].to_string(),
            });
        };
        let args = spec.arguments(&w[1..])?;
        let a = args.as_slice();
        match spec.name {
            "loadrt" | "unloadrt" | "setthread" | "unload" | "addf" | "delf" | "initf"
            | "start" | "stop" => self.host_command(spec.name, a),
            "newsig" | "delsig" | "sets" | "setp" | "net" | "linkpp" | "linkps" | "linksp"
            | "unlinkp" | "alias" | "unalias" => self.signal_command(spec.name, a),
            "loadusr" | "waitusr" | "unloadusr" => self.user_command(spec.name, a),
            "echo"
            | "unecho"
            | "print"
            | "source"
            | "lock"
            | "unlock"
            | "quit"
            | "exit"
            | "debug"
            | "setexact_for_test_suite_only" => self.session_command(spec.name, a),
            cmd => {
                // show, list, save, getp, gets, ptype, stype, status, help.
                let text = crate::format::render(&self.inst, cmd, a, self.opts.script)?;
                let _ = self.w_out().write_all(text.as_bytes());
                Ok(())
            }
        }
    }

    /// Commands the host carries out: modules, functions, threads.
    fn host_command(&mut self, name: &str, a: &[&str]) -> CmdResult {
        match name {
            "loadrt" => {
                let unquoted: Vec<String> = a.iter().map(|s| unquote(s)).collect();
                let mut v = vec!["loadrt"];
                v.extend(unquoted.iter().map(String::as_str));
                // LinuxCNC numbers components from one counter that its
                // helper processes also draw from: each loadrt uses two
                // numbers before the module's own.
                let next = self.inst.next_component_id().saturating_add(2);
                self.inst.advance_component_ids(next)?;
                self.host(&v).map_err(|e| {
                    self.lib_error(&e.to_string());
                    LangError::halcmd(format!("insmod for {} failed, returned -1", a[0]))
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
            "start" => self.host(&["start"]),
            _ => self.host(&["stop"]),
        }
    }

    /// Commands on signals, pins, parameters and their aliases, done on the
    /// segment directly.
    fn signal_command(&mut self, name: &str, a: &[&str]) -> CmdResult {
        match name {
            "newsig" => {
                let t = HalType::from_name(a[1])
                    .ok_or_else(|| LangError::halcmd(format!("Unknown signal type '{}'", a[1])))?;
                let r = self.inst.newsig(a[0], t);
                self.lib_or(r, "newsig failed")
            }
            "delsig" if a[0] == "all" => Ok(self.inst.delsig_all()?),
            "delsig" => Ok(self.inst.delsig(a[0])?),
            "sets" => self.sets(a[0], a[1]),
            "setp" => self.setp(a[0], a[1]),
            "net" => self.net(a[0], &a[1..]),
            // Obsolete form: a signal named after the first pin.
            "linkpp" => self.connect(a[0], a),
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
            what => self.alias(what, a),
        }
    }

    /// `sets SIGNAL VALUE`.
    fn sets(&mut self, name: &str, value: &str) -> CmdResult {
        let t = self
            .inst
            .signal_type(name)
            .map_err(|_| LangError::NoSignal {
                name: name.to_string(),
            })?;
        if t == HalType::Port {
            return self.sets_port(name, value);
        }
        let v = parse_value(t, value).map_err(|source| LangError::BadValue {
            what: "signal",
            name: name.to_string(),
            source,
        })?;
        self.inst.set_signal(name, v).map_err(|e| match e {
            HalError::SignalDriven { .. } => LangError::NotWritable {
                what: "signal",
                name: name.to_string(),
            },
            other => other.into(),
        })
    }

    /// `sets` on a port signal: makes its buffer of VALUE bytes. As
    /// LinuxCNC's, a refusal is reported at the line, then `sets failed`.
    fn sets_port(&mut self, name: &str, value: &str) -> CmdResult {
        let refused = match parse_value(HalType::Port, value) {
            Err(_) => format!("value '{value}' invalid for PORT"),
            Ok(size) => match self.inst.set_signal(name, size) {
                // A linked writer does not stop it: the buffer is no value
                // the writer drives (LinuxCNC sizes it all the same).
                Ok(()) => return Ok(()),
                Err(e @ (HalError::PortAllocated { .. } | HalError::BadPortSize { .. })) => {
                    e.to_string()
                }
                Err(other) => return Err(other.into()),
            },
        };
        self.report(&refused);
        Err(LangError::halcmd("sets failed"))
    }

    /// `alias` and `unalias`: as LinuxCNC's do_alias_cmd, the library's
    /// message, then "alias failed" (or "unalias failed") at the line.
    fn alias(&mut self, what: &str, a: &[&str]) -> CmdResult {
        let kind = match a[0] {
            "pin" => AliasKind::Pin,
            "param" => AliasKind::Param,
            other => {
                return Err(LangError::halcmd(format!(
                    "{what}: unknown type '{other}', use pin or param"
                )))
            }
        };
        let r = if what == "alias" {
            self.inst.alias(kind, a[1], a[2])
        } else {
            self.inst.unalias(kind, a[1])
        };
        self.lib_or(r, &format!("{what} failed"))
    }

    /// `loadusr`, `waitusr`, `unloadusr`: programs that join the instance.
    fn user_command(&mut self, name: &str, a: &[&str]) -> CmdResult {
        match name {
            "loadusr" => self.loadusr(a),
            "waitusr" => crate::usr::wait_gone(&self.inst, a[0], self.opts.stop.as_ref()),
            _ => crate::usr::unload(&self.inst, a[0], UNLOAD_LIMIT),
        }
    }

    /// `loadusr [OPTIONS] PROGRAM [ARGS...]`. A program that nobody waits
    /// for is handed to the host, which ends it with the instance; if the
    /// host cannot adopt it, it ends with this session.
    fn loadusr(&mut self, a: &[&str]) -> CmdResult {
        let spec = crate::usr::parse(a)?;
        // A user program registers with LinuxCNC's id counter twice.
        let next = self.inst.next_component_id().saturating_add(2);
        self.inst.advance_component_ids(next)?;
        self.inst
            .check_unlocked(hal_core::lock_bits::LOAD, "loadusr")?;
        let _ = self.w_out().flush();
        if let Some(child) = crate::usr::run(&self.inst, &spec, self.opts.stop.as_ref())? {
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

    /// The session's own commands: echo, print, source, lock, quit, ...
    fn session_command(&mut self, name: &str, a: &[&str]) -> CmdResult {
        match name {
            "echo" | "unecho" => {
                self.echo = name == "echo";
                let text = if self.echo { "Echo on" } else { "Echo off" };
                let _ = writeln!(self.w_out(), "{text}");
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
            "source" => self.source(a[0]),
            "lock" | "unlock" => {
                let level = crate::lock::next_level(
                    self.inst.lock_level(),
                    name == "lock",
                    a.first().copied(),
                )?;
                self.inst.set_lock_level(level);
                Ok(())
            }
            "quit" | "exit" => {
                self.done = true;
                Ok(())
            }
            "setexact_for_test_suite_only" => self.setexact(),
            // debug
            _ => Ok(()),
        }
    }

    /// `source FILE`: its commands run here, reported under its name.
    fn source(&mut self, file: &str) -> CmdResult {
        let text = crate::lexer::read_text(file).map_err(|source| LangError::File {
            command: "source",
            file: file.to_string(),
            source,
        })?;
        let name = Path::new(file).to_string_lossy().into_owned();
        if self.run_text(Some(&name), &text) {
            Ok(())
        } else {
            Err(LangError::halcmd(format!("source {file} failed")))
        }
    }

    /// `setexact_for_test_suite_only`: LinuxCNC refuses once a base period
    /// exists, that is once any thread was ever created. Thread periods
    /// are always exact here: only the warning remains to be given.
    fn setexact(&mut self) -> CmdResult {
        if self.inst.base_period() != 0 {
            return Err(LangError::halcmd(
                "HAL_LIB: Cannot run 'setexact' after a thread has been created",
            ));
        }
        let at = self.location();
        let _ = writeln!(
            self.w_err(),
            "{}Warning: HAL_LIB: HAL will pretend that the exact base period requested is possible.\nThis mode is not suitable for running real hardware.",
            at
        );
        Ok(())
    }

    /// `unload NAME|all`: a user component is stopped, a realtime one
    /// unloaded with its module.
    fn unload(&mut self, name: &str) -> CmdResult {
        if name == "all" {
            crate::usr::unload(&self.inst, name, UNLOAD_LIMIT)?;
            return self.host(&["unloadrt", name]);
        }
        match self.inst.component(name)? {
            None => Err(LangError::halcmd(format!(
                "component '{name}' is not loaded"
            ))),
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
            LangError::halcmd(what)
        })
    }

    /// A segment operation's failure, reported like [`Self::host_or`].
    pub(super) fn lib_or<T>(&mut self, r: hal_core::Result<T>, what: &str) -> CmdResult {
        r.map(|_| ()).map_err(|e| {
            self.lib_error(&e.to_string());
            LangError::halcmd(what)
        })
    }
}
