//! `loadusr`, `waitusr`, `unloadusr`: user-space programs that join the
//! instance as components of their own.

use std::process::{Child, Command};
use std::time::{Duration, Instant};

use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, Instance};

use crate::error::{LangError, Result};
use crate::lexer::unquote;

/// Options of one `loadusr`.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct LoadUsr {
    /// `-W`: wait until the component is ready.
    pub wait_ready: bool,
    /// `-w`: wait until the program exits.
    pub wait_exit: bool,
    /// `-i`: ignore the program's exit status (with `-w`).
    pub ignore_status: bool,
    /// `-n NAME`: the component name to wait for.
    pub name: Option<String>,
    /// The program to start, looked up in PATH.
    pub program: String,
    /// Its arguments.
    pub args: Vec<String>,
}

/// Parses `loadusr`'s arguments as LinuxCNC does with `getopt("+wWin:")`:
/// flags may be combined in one word (`-Wn name`, `-wi`), `-n` takes the
/// rest of its word or the next word, and the first word that is not an
/// option (or the word after `--`) is the program.
pub fn parse(args: &[&str]) -> Result<LoadUsr> {
    let mut out = LoadUsr::default();
    let mut i = 0;
    while let Some(word) = args.get(i) {
        i += 1;
        if *word == "--" {
            break;
        }
        let Some(flags) = word.strip_prefix('-').filter(|f| !f.is_empty()) else {
            // Not an option: the program.
            i -= 1;
            break;
        };
        for (at, c) in flags.char_indices() {
            match c {
                'W' => out.wait_ready = true,
                'w' => out.wait_exit = true,
                'i' => out.ignore_status = true,
                'n' => {
                    let rest = &flags[at + 1..];
                    let name = if rest.is_empty() {
                        i += 1;
                        *args
                            .get(i - 1)
                            .ok_or_else(|| LangError::halcmd("loadusr: -n needs a name"))?
                    } else {
                        rest
                    };
                    out.name = Some(name.to_string());
                    break;
                }
                other => {
                    return Err(LangError::halcmd(format!(
                        "loadusr: unknown option '-{other}'"
                    )))
                }
            }
        }
    }
    let (program, rest) = args[i..]
        .split_first()
        .ok_or_else(|| LangError::halcmd("loadusr: needs a program to run"))?;
    out.program = program.to_string();
    out.args = rest.iter().map(|a| unquote(a)).collect();
    Ok(out)
}

/// The component a program is expected to register when `-W` has no
/// `-n`: its file name without directory and extension, as LinuxCNC
/// guesses (`loadusr -W ./foo.py` waits for `foo`).
pub fn guess_comp_name(program: &str) -> &str {
    let base = program.rsplit('/').next().unwrap_or(program);
    base.rfind('.').map_or(base, |dot| &base[..dot])
}

/// PATH with the directory of the running tools first, so that programs
/// of this suite are found next to halcmd.
fn child_path() -> std::ffi::OsString {
    let mut dirs = Vec::new();
    if let Some(dir) = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(|p| p.to_path_buf()))
    {
        dirs.push(dir.clone());
        if dir.ends_with("deps") {
            if let Some(parent) = dir.parent() {
                dirs.push(parent.to_path_buf());
            }
        }
    }
    if let Some(p) = std::env::var_os("PATH") {
        dirs.extend(std::env::split_paths(&p));
    }
    std::env::join_paths(dirs).unwrap_or_default()
}

/// Makes the program `cmd` starts receive `signal` when this process
/// dies, however it dies (kill -9 included): a Tcl or Python file started
/// by the launcher must not run on as an orphan. A parent already gone
/// by the time the child starts makes the child exit at once.
pub fn end_with_parent(cmd: &mut Command, signal: nix::sys::signal::Signal) {
    use std::os::unix::process::CommandExt;
    let parent = nix::unistd::Pid::this();
    // SAFETY: prctl, getppid and _exit are async-signal-safe and touch no
    // memory of ours.
    unsafe {
        cmd.pre_exec(move || {
            nix::sys::prctl::set_pdeathsig(signal)?;
            if nix::unistd::getppid() != parent {
                libc::_exit(1);
            }
            Ok(())
        });
    }
}

/// The error of a wait a stop request ended.
fn stopped(what: &str) -> LangError {
    LangError::halcmd(format!("{what}: stop requested; no longer waiting"))
}

/// Starts the program and waits as asked (until `stop` is requested, if
/// given). Returns the child if nobody waited for it to exit.
pub fn run(inst: &Instance, spec: &LoadUsr, stop: Option<&ExitSignals>) -> Result<Option<Child>> {
    let stop_requested = || stop.is_some_and(ExitSignals::requested);
    let mut child = Command::new(&spec.program)
        .args(&spec.args)
        .env("HAL_INSTANCE", inst.name())
        .env("PATH", child_path())
        .spawn()
        .map_err(|source| LangError::Spawn {
            program: spec.program.clone(),
            source,
        })?;
    if spec.wait_ready {
        let name = spec
            .name
            .as_deref()
            .unwrap_or_else(|| guess_comp_name(&spec.program));
        loop {
            let ready = inst.component(name)?.is_some_and(|c| c.ready);
            if ready {
                break;
            }
            if let Ok(Some(status)) = child.try_wait() {
                return Err(LangError::halcmd(format!(
                    "{} exited ({status}) without becoming ready",
                    spec.program
                )));
            }
            if stop_requested() {
                end_child(&mut child);
                return Err(stopped(&format!("loadusr -W {}", spec.program)));
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    if spec.wait_exit {
        let status = loop {
            match child.try_wait() {
                Ok(Some(status)) => break status,
                Ok(None) if stop_requested() => {
                    end_child(&mut child);
                    return Err(stopped(&format!("loadusr -w {}", spec.program)));
                }
                Ok(None) => std::thread::sleep(Duration::from_millis(10)),
                Err(e) => return Err(LangError::halcmd(format!("loadusr: {e}"))),
            }
        };
        if !status.success() && !spec.ignore_status {
            return Err(LangError::halcmd(format!(
                "{} exited with {status}",
                spec.program
            )));
        }
        return Ok(None);
    }
    Ok(Some(child))
}

/// Ends a program the caller stopped waiting for: SIGTERM, a moment to
/// leave, then SIGKILL.
pub(crate) fn end_child(child: &mut Child) {
    let pid = nix::unistd::Pid::from_raw(child.id() as i32);
    let _ = nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGTERM);
    for _ in 0..100 {
        if let Ok(Some(_)) = child.try_wait() {
            return;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// Waits until user component `name` is gone (`waitusr`), or until
/// `stop` is requested.
pub fn wait_gone(inst: &Instance, name: &str, stop: Option<&ExitSignals>) -> Result<()> {
    let pid_of = |inst: &Instance| -> Result<Option<i32>> {
        Ok(inst
            .component(name)?
            .filter(|c| c.kind == ComponentKind::User)
            .map(|c| c.pid))
    };
    if pid_of(inst)?.is_none() {
        return Err(LangError::halcmd(format!(
            "waitusr: component '{name}' not found or not a user component"
        )));
    }
    while let Some(pid) = pid_of(inst)? {
        // A process killed outright leaves its component behind: stop
        // waiting once the process is gone.
        if pid > 0 && nix::sys::signal::kill(nix::unistd::Pid::from_raw(pid), None).is_err() {
            return Ok(());
        }
        if stop.is_some_and(ExitSignals::requested) {
            return Err(stopped(&format!("waitusr {name}")));
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    Ok(())
}

/// Sends SIGTERM to user component `name` (or every one, for `all`) and
/// waits up to `limit` for it to leave.
pub fn unload(inst: &Instance, name: &str, limit: Duration) -> Result<()> {
    let users = if name == "all" {
        inst.components()?
    } else {
        inst.component(name)?.into_iter().collect()
    };
    let targets: Vec<(String, i32)> = users
        .into_iter()
        .filter(|c| c.kind == ComponentKind::User)
        .map(|c| (c.name, c.pid))
        .collect();
    if targets.is_empty() && name != "all" {
        return Err(LangError::halcmd(format!(
            "unloadusr: component '{name}' not found"
        )));
    }
    let me = std::process::id() as i32;
    for (n, pid) in &targets {
        if *pid > 0 && *pid != me {
            let sent = nix::sys::signal::kill(
                nix::unistd::Pid::from_raw(*pid),
                nix::sys::signal::Signal::SIGTERM,
            );
            if sent == Err(nix::errno::Errno::EPERM) {
                return Err(LangError::halcmd(format!(
                    "unloadusr: '{n}' is process {pid} of another user: permission denied"
                )));
            }
        }
    }
    let end = Instant::now() + limit;
    for (n, pid) in targets {
        if pid == me {
            continue;
        }
        while inst.component(&n)?.is_some() {
            if Instant::now() > end {
                return Err(LangError::halcmd(format!("unloadusr: '{n}' did not exit")));
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_loadusr_options() {
        let l = parse(&["-W", "-n", "meter", "halmeter", "pin", "x"]).unwrap();
        assert!(l.wait_ready && !l.wait_exit);
        assert_eq!(l.name.as_deref(), Some("meter"));
        assert_eq!(l.program, "halmeter");
        assert_eq!(l.args, ["pin", "x"]);
        let l = parse(&["-w", "-i", "sh", "runstreamer"]).unwrap();
        assert!(l.wait_exit && l.ignore_status);
        assert!(parse(&["-w"]).is_err());
        assert!(parse(&["-x", "prog"]).is_err());
    }

    #[test]
    fn flags_combine_in_one_word_as_with_getopt() {
        // The example of the HAL manual: `loadusr -Wn spindle prog`.
        let l = parse(&["-Wn", "spindle", "prog", "-x"]).unwrap();
        assert!(l.wait_ready && !l.wait_exit && !l.ignore_status);
        assert_eq!(l.name.as_deref(), Some("spindle"));
        assert_eq!(l.program, "prog");
        assert_eq!(l.args, ["-x"], "options end at the program");
        // -n takes the rest of its word.
        let l = parse(&["-wiWnmeter", "halmeter"]).unwrap();
        assert!(l.wait_exit && l.ignore_status && l.wait_ready);
        assert_eq!(l.name.as_deref(), Some("meter"));
        assert_eq!(l.program, "halmeter");
        // `--` ends the options; the word after it is the program.
        let l = parse(&["-w", "--", "-odd-name", "a"]).unwrap();
        assert!(l.wait_exit);
        assert_eq!(
            (l.program.as_str(), l.args.as_slice()),
            ("-odd-name", &["a".to_string()][..])
        );
        assert_eq!(
            parse(&["-Wn"]).unwrap_err().to_string(),
            "loadusr: -n needs a name"
        );
        assert_eq!(
            parse(&["-Wx", "prog"]).unwrap_err().to_string(),
            "loadusr: unknown option '-x'"
        );
        assert_eq!(
            parse(&["-W"]).unwrap_err().to_string(),
            "loadusr: needs a program to run"
        );
        // Arguments lose their quotes, as before the program runs.
        assert_eq!(parse(&["sh", "\"a b\""]).unwrap().args, ["a b"]);
    }

    #[test]
    fn the_guessed_component_name_has_no_directory_or_extension() {
        assert_eq!(guess_comp_name("foo.py"), "foo");
        assert_eq!(guess_comp_name("/usr/bin/halmeter"), "halmeter");
        assert_eq!(guess_comp_name("./dir.d/prog"), "prog");
        assert_eq!(guess_comp_name("a.b.c"), "a.b");
    }
}
