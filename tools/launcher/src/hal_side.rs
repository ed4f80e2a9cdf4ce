//! Running a machine's HAL files in LinuxCNC's order: every
//! `[HAL]HALFILE` (`.hal` through halcmd, `.tcl` through haltcl, `.py`
//! with Python), with `[HAL]TWOPASS` processing if set, then every
//! `[HAL]HALCMD` line; later `POSTGUI_HALFILE` and, at exit, `SHUTDOWN`.

use std::cell::RefCell;
use std::process::Command;
use std::rc::Rc;

use hal_lang::haltcl::{self, TclJob};
use hal_lang::ini::Ini;
use hal_lang::lexer::tokenize;
use hal_lang::Session;

use crate::halfiles::{HalFile, SearchPath};
use crate::old_format::HalRenames;
use crate::rules::{Phase, Rules};
use crate::LaunchError;

/// Runs a machine's HAL files on a session whose filter is `rules`.
pub struct HalSide<'a> {
    /// The machine's INI file.
    pub ini: &'a Ini,
    /// Where HAL files are looked for.
    pub search: SearchPath,
    /// The rules the session applies.
    pub rules: Rc<RefCell<Rules>>,
    /// Keep going after a failed file or command (`-k`).
    pub keep_going: bool,
    /// Say what is done.
    pub verbose: bool,
    /// The pin renames of an old-format configuration, for its own files.
    pub renames: Option<&'a HalRenames>,
}

impl HalSide<'_> {
    fn note(&self, msg: &str) {
        if self.verbose {
            eprintln!("{msg}");
        }
    }

    /// The files `[HAL]key` names, found. An empty entry (`HALFILE =`,
    /// as LinuxCNC's pluto_inch.ini has) names no file: it is passed over
    /// with a note, as LinuxCNC does not fail on it either.
    fn named_files(&self, key: &str) -> Result<Vec<HalFile>, LaunchError> {
        let mut files = Vec::new();
        for e in self.ini.all("HAL", key) {
            if e.value.trim().is_empty() {
                eprintln!("{}: note: [HAL]{key} is empty: no file to run", e.origin);
                continue;
            }
            files.push(self.search.resolve(e)?);
        }
        Ok(files)
    }

    /// Every `[HAL]HALFILE`, with TWOPASS if `[HAL]TWOPASS` is set.
    pub fn halfiles(&self, session: &mut Session<'_>) -> Result<(), LaunchError> {
        let files = self.named_files("HALFILE")?;
        match self
            .ini
            .entry("HAL", "TWOPASS")
            .filter(|e| !e.value.is_empty())
        {
            Some(e) => self.twopass(session, &files, &e.value),
            None => {
                let mut result = Ok(());
                for f in &files {
                    let r = self.run_file(session, f);
                    if r.is_err() && !self.keep_going {
                        return r;
                    }
                    result = result.and(r);
                }
                result
            }
        }
    }

    /// TWOPASS: pass 0 gathers `loadrt`s (a `.hal` file marked
    /// `#NOTWOPASS` runs whole instead, keeping going), the gathered
    /// modules load, pass 1 runs the rest.
    fn twopass(
        &self,
        session: &mut Session<'_>,
        files: &[HalFile],
        options: &str,
    ) -> Result<(), LaunchError> {
        // LinuxCNC's twopass.tcl names the options it knows, and says so
        // (and which files it found) on stdout.
        let lower = options.to_ascii_lowercase();
        let known: Vec<&str> = ["verbose", "nodelete"]
            .into_iter()
            .filter(|k| lower.contains(k))
            .collect();
        let verbose = self.verbose || known.contains(&"verbose");
        session.say(&format!(
            "twopass:invoked with <{}> options",
            known.join(" ")
        ));
        let mut notwopass = Vec::new();
        for f in files {
            session.say(&format!(
                "twopass:found {}",
                f.twopass_name(&self.search.ini_dir)
            ));
            if f.kind() == "hal" {
                let text = hal_lang::lexer::read_text(&f.path)
                    .map_err(|e| LaunchError::read(&f.path, e))?;
                if crate::twopass::is_notwopass(&text) {
                    session.say(&format!(
                        "twopass:Sourcing {} WITHOUT twopass processing",
                        f.twopass_name(&self.search.ini_dir)
                    ));
                    notwopass.push(f.path.clone());
                }
            }
        }
        let mut failed = Vec::new();
        self.rules.borrow_mut().phase = Phase::Pass0;
        for f in files {
            let r = if notwopass.contains(&f.path) {
                if verbose {
                    eprintln!("twopass: {} is #NOTWOPASS: run whole now", f.display_name());
                }
                self.rules.borrow_mut().phase = Phase::Normal;
                let keep = std::mem::replace(&mut session.opts.keep_going, true);
                let r = self.run_file(session, f);
                session.opts.keep_going = keep;
                self.rules.borrow_mut().phase = Phase::Pass0;
                r
            } else {
                self.run_file(session, f)
            };
            if let Err(e) = r {
                self.rules.borrow_mut().phase = Phase::Normal;
                return Err(e);
            }
        }
        self.rules.borrow_mut().phase = Phase::Normal;
        let loads = self.rules.borrow().twopass.load_commands();
        for words in loads {
            if verbose {
                eprintln!("twopass: {}", words.join(" "));
            }
            if !session.run_words(&words) {
                failed.push(words.join(" "));
            }
        }
        self.rules.borrow_mut().twopass.finish_pass0();
        if !failed.is_empty() && !self.keep_going {
            return Err(LaunchError::Failed(format!(
                "twopass: {}",
                failed.join("; ")
            )));
        }
        self.rules.borrow_mut().phase = Phase::Pass1;
        let mut result = Ok(());
        for f in files.iter().filter(|f| !notwopass.contains(&f.path)) {
            let r = self.run_file(session, f);
            if r.is_err() && !self.keep_going {
                result = r;
                break;
            }
            result = result.and(r);
        }
        self.rules.borrow_mut().phase = Phase::Normal;
        result
    }

    /// Runs one HAL, Tcl or Python file.
    pub fn run_file(&self, session: &mut Session<'_>, f: &HalFile) -> Result<(), LaunchError> {
        if session.stop_requested() {
            return Err(LaunchError::StoppedDuringStart);
        }
        self.note(&format!("running {}", f.display_name()));
        let failed = || LaunchError::Failed(format!("{}: [HAL] file {} failed", f.origin, f.spec));
        match f.kind().as_str() {
            "hal" => {
                if !f.args.is_empty() {
                    eprintln!(
                        "{}: note: arguments after a .hal file are not used: {}",
                        f.origin,
                        f.args.join(" ")
                    );
                }
                let text = hal_lang::lexer::read_text(&f.path)
                    .map_err(|e| LaunchError::read(&f.path, e))?;
                let name = f.display_name();
                let renames = self.renames.filter(|_| !self.search.in_library(&f.path));
                let ok = match renames {
                    None => session.run_text(Some(&name), &text),
                    Some(r) => {
                        let (lines, changed) = r.convert_text(&text);
                        if changed > 0 {
                            eprintln!(
                                "linuxcnc: note: {name}: {changed} line(s) read with the \
                                 current pin names (old-format configuration)"
                            );
                        }
                        session.run_lines(Some(&name), &lines)
                    }
                };
                if ok {
                    Ok(())
                } else {
                    Err(failed())
                }
            }
            "tcl" => {
                let phase = self.rules.borrow().phase;
                let twopass = match phase {
                    Phase::Normal => None,
                    Phase::Pass0 | Phase::Pass0Tcl => Some(0),
                    Phase::Pass1 => Some(1),
                };
                let job = TclJob {
                    script: Some(f.path.clone()),
                    argv: f.args.clone(),
                    prompt: false,
                    twopass,
                };
                if phase == Phase::Pass0 {
                    self.rules.borrow_mut().phase = Phase::Pass0Tcl;
                }
                let r = haltcl::run(session, Some(self.ini), &job);
                self.rules.borrow_mut().phase = phase;
                r.map_err(|e| match e {
                    haltcl::HaltclError::Failed { .. } => failed(),
                    haltcl::HaltclError::Stopped { .. } => LaunchError::StoppedDuringStart,
                    other => LaunchError::Tcl(other),
                })
            }
            "py" => {
                let mut cmd = Command::new("python3");
                cmd.arg(&f.path)
                    .args(&f.args)
                    .env("HAL_INSTANCE", session.instance().name());
                hal_lang::usr::end_with_parent(&mut cmd, nix::sys::signal::Signal::SIGTERM);
                let mut child = cmd
                    .spawn()
                    .map_err(|e| LaunchError::read(std::path::Path::new("python3"), e))?;
                let status = loop {
                    match child.try_wait() {
                        Ok(Some(status)) => break status,
                        Ok(None) if session.stop_requested() => {
                            let _ = child.kill();
                            let _ = child.wait();
                            return Err(LaunchError::StoppedDuringStart);
                        }
                        Ok(None) => std::thread::sleep(std::time::Duration::from_millis(20)),
                        Err(e) => return Err(LaunchError::read(&f.path, e)),
                    }
                };
                if status.success() {
                    Ok(())
                } else {
                    Err(failed())
                }
            }
            other => Err(LaunchError::HalFile {
                origin: f.origin.clone(),
                key: "[HAL]HALFILE".into(),
                spec: f.spec.clone(),
                reason: format!("unknown kind of file '.{other}' (use .hal, .tcl or .py)"),
            }),
        }
    }

    /// Every `[HAL]HALCMD` line, in order, as one halcmd command each.
    pub fn halcmds(&self, session: &mut Session<'_>) -> Result<(), LaunchError> {
        let mut result = Ok(());
        for e in self.ini.all("HAL", "HALCMD") {
            if session.stop_requested() {
                return Err(LaunchError::StoppedDuringStart);
            }
            let at = e.origin.file.to_string();
            let words = match tokenize(&e.value, Some(self.ini)) {
                Ok(w) => w,
                Err(err) => {
                    return Err(LaunchError::Failed(format!(
                        "{}: [HAL]HALCMD: {err}",
                        e.origin
                    )))
                }
            };
            if !session.run_words_at(Some(&at), e.origin.line, &words) {
                let err =
                    LaunchError::Failed(format!("{}: [HAL]HALCMD = {} failed", e.origin, e.value));
                if !self.keep_going {
                    return Err(err);
                }
                result = Err(err);
            }
        }
        result
    }

    /// Every file of `[HAL]key` (`POSTGUI_HALFILE`, `SHUTDOWN`), in order.
    pub fn files_of(&self, session: &mut Session<'_>, key: &str) -> Result<(), LaunchError> {
        let mut result = Ok(());
        for e in self.ini.all("HAL", key) {
            if e.value.trim().is_empty() {
                eprintln!("{}: note: [HAL]{key} is empty: no file to run", e.origin);
                continue;
            }
            let r = self
                .search
                .resolve(e)
                .and_then(|f| self.run_file(session, &f));
            if r.is_err() && !self.keep_going {
                return r;
            }
            result = result.and(r);
        }
        result
    }
}
