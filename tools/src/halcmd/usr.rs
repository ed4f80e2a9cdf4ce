//! `loadusr`, `waitusr`, `unloadusr`: user-space programs that join the
//! instance as components of their own.

use std::process::{Child, Command};
use std::time::{Duration, Instant};

use hal_core::{ComponentKind, Instance};

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
    pub program: String,
    pub args: Vec<String>,
}

/// Parses `loadusr`'s arguments.
pub fn parse(args: &[&str]) -> Result<LoadUsr, String> {
    let mut out = LoadUsr::default();
    let mut i = 0;
    while i < args.len() {
        match args[i] {
            "-W" => out.wait_ready = true,
            "-w" => out.wait_exit = true,
            "-i" => out.ignore_status = true,
            "-n" => {
                i += 1;
                out.name = Some(args.get(i).ok_or("loadusr: -n needs a name")?.to_string());
            }
            a if a.starts_with('-') && out.program.is_empty() => {
                return Err(format!("loadusr: unknown option '{a}'"))
            }
            _ => {
                out.program = args[i].to_string();
                out.args = args[i + 1..].iter().map(|s| s.replace('"', "")).collect();
                break;
            }
        }
        i += 1;
    }
    if out.program.is_empty() {
        return Err("loadusr: needs a program to run".into());
    }
    Ok(out)
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

/// Starts the program and waits as asked. Returns the child if nobody
/// waited for it to exit.
pub fn run(inst: &Instance, spec: &LoadUsr) -> Result<Option<Child>, String> {
    let mut child = Command::new(&spec.program)
        .args(&spec.args)
        .env("HAL_INSTANCE", inst.name())
        .env("PATH", child_path())
        .spawn()
        .map_err(|e| format!("loadusr: cannot run '{}': {e}", spec.program))?;
    if spec.wait_ready {
        let name = spec.name.clone().unwrap_or_else(|| {
            std::path::Path::new(&spec.program)
                .file_name()
                .map(|f| f.to_string_lossy().into_owned())
                .unwrap_or_default()
        });
        loop {
            let ready = inst
                .components()
                .map_err(|e| e.to_string())?
                .iter()
                .any(|c| c.name == name && c.ready);
            if ready {
                break;
            }
            if let Ok(Some(status)) = child.try_wait() {
                return Err(format!(
                    "{} exited ({status}) without becoming ready",
                    spec.program
                ));
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    if spec.wait_exit {
        let status = child.wait().map_err(|e| format!("loadusr: {e}"))?;
        if !status.success() && !spec.ignore_status {
            return Err(format!("{} exited with {status}", spec.program));
        }
        return Ok(None);
    }
    Ok(Some(child))
}

/// Waits until user component `name` is gone (`waitusr`).
pub fn wait_gone(inst: &Instance, name: &str) -> Result<(), String> {
    let pid_of = |inst: &Instance| -> Result<Option<i32>, String> {
        Ok(inst
            .components()
            .map_err(|e| e.to_string())?
            .into_iter()
            .find(|c| c.name == name && c.kind == ComponentKind::User)
            .map(|c| c.pid))
    };
    if pid_of(inst)?.is_none() {
        return Err(format!(
            "waitusr: component '{name}' not found or not a user component"
        ));
    }
    while let Some(pid) = pid_of(inst)? {
        // A process killed outright leaves its component behind: stop
        // waiting once the process is gone.
        if pid > 0 && nix::sys::signal::kill(nix::unistd::Pid::from_raw(pid), None).is_err() {
            return Ok(());
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    Ok(())
}

/// Sends SIGTERM to user component `name` (or every one, for `all`) and
/// waits up to `limit` for it to leave.
pub fn unload(inst: &Instance, name: &str, limit: Duration) -> Result<(), String> {
    let targets: Vec<(String, i32)> = inst
        .components()
        .map_err(|e| e.to_string())?
        .into_iter()
        .filter(|c| c.kind == ComponentKind::User && (name == "all" || c.name == name))
        .map(|c| (c.name, c.pid))
        .collect();
    if targets.is_empty() && name != "all" {
        return Err(format!("unloadusr: component '{name}' not found"));
    }
    let me = std::process::id() as i32;
    for (_, pid) in &targets {
        if *pid > 0 && *pid != me {
            let _ = nix::sys::signal::kill(
                nix::unistd::Pid::from_raw(*pid),
                nix::sys::signal::Signal::SIGTERM,
            );
        }
    }
    let end = Instant::now() + limit;
    for (n, pid) in targets {
        if pid == me {
            continue;
        }
        while inst
            .components()
            .map_err(|e| e.to_string())?
            .iter()
            .any(|c| c.name == n)
        {
            if Instant::now() > end {
                return Err(format!("unloadusr: '{n}' did not exit"));
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
}
