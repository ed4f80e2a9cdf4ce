//! `[DISPLAY]DISPLAY` when it names a program of the configuration's own
//! (a path such as `./test-ui.py`, or a name in the configuration's
//! `bin/` directory) rather than one of LinuxCNC's GUIs: the launcher runs
//! it once task runs, as LinuxCNC's script does, `PROGRAM -ini INIFILE
//! ARGS...` in the configuration's directory, keeps task running while it
//! runs, and stops the machine when it exits, with its exit status. Its
//! POSTGUI files are left to it, as LinuxCNC leaves them to its GUIs. The
//! GUIs themselves stay skipped on this headless machine.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus};

use hal_lang::ini::Ini;

use crate::error::LaunchError;

/// The display program a configuration asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DisplayProgram {
    /// The program as the INI file names it.
    pub program: String,
    /// The words after it.
    pub args: Vec<String>,
    /// Where it was named, for messages.
    pub origin: String,
}

/// LinuxCNC's user interfaces, skipped on this headless machine even when
/// named by a path.
const GUIS: &[&str] = &[
    "axis",
    "touchy",
    "gmoccapy",
    "gscreen",
    "qtvcp",
    "qtplasmac",
    "tklinuxcnc",
    "tkemc",
    "keystick",
    "xemc",
    "mini",
    "dummy",
    "halui",
];

/// Display programs of this suite, run from the launcher's own directory
/// when named without a path (LinuxCNC's are on its PATH the same way).
const OWN: &[&str] = &["linuxcncrsh"];

/// The display program `ini` names, if it is one the launcher runs (a
/// path, or a program in `CONFIG_DIR/bin`); `None` for LinuxCNC's GUIs
/// and for no `[DISPLAY]DISPLAY`.
pub fn display_program(ini: &Ini) -> Option<DisplayProgram> {
    let e = ini.entry("DISPLAY", "DISPLAY")?;
    let mut words = e.value.split_whitespace();
    let program = words.next()?.to_string();
    let base = program.rsplit('/').next().unwrap_or(&program);
    if GUIS.contains(&base) {
        return None;
    }
    let in_bin = !program.contains('/') && ini.dir().join("bin").join(&program).is_file();
    if !program.contains('/') && !in_bin && !OWN.contains(&program.as_str()) {
        return None;
    }
    Some(DisplayProgram {
        program,
        args: words.map(str::to_string).collect(),
        origin: e.origin.to_string(),
    })
}

/// Where the Python modules built beside this program are (a build's
/// `target/python-dist`, which `packaging/python-wheel` fills), if there.
fn python_dist() -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?;
    let dist = exe.parent()?.parent()?.join("python-dist");
    dist.join("hal")
        .join("__init__.py")
        .is_file()
        .then_some(dist)
}

/// `dirs` in front of the search path in `var` (colon-separated); the
/// path as it was if a directory cannot be in one (it holds a colon).
fn prepend(dirs: &[PathBuf], var: &str) -> OsString {
    let mut paths = dirs.to_vec();
    if let Some(old) = std::env::var_os(var) {
        paths.extend(std::env::split_paths(&old));
    }
    std::env::join_paths(&paths).unwrap_or_else(|_| std::env::var_os(var).unwrap_or_default())
}

/// Where the display looks for programs first: the configuration's
/// `bin/` (as LinuxCNC's script puts it), then this launcher's own
/// directory, so `halcmd` and the other tools it calls are this suite's.
fn search_dirs(config_dir: &Path) -> Vec<PathBuf> {
    let mut dirs = vec![config_dir.join("bin")];
    if let Some(own) = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(Path::to_path_buf))
    {
        dirs.push(own);
    }
    dirs
}

/// Starts the display program in the configuration's directory with
/// `-ini INIFILE` and its words, on HAL instance `instance`.
pub fn start(
    d: &DisplayProgram,
    ini: &Ini,
    ini_file: &Path,
    instance: &str,
) -> Result<Child, LaunchError> {
    let dir = ini.dir();
    let in_bin = dir.join("bin").join(&d.program);
    let own = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(|p| p.join(&d.program)));
    let program = if d.program.contains('/') {
        dir.join(&d.program)
    } else if in_bin.is_file() || !OWN.contains(&d.program.as_str()) {
        in_bin
    } else {
        own.unwrap_or(in_bin)
    };
    let mut cmd = Command::new(&program);
    cmd.arg("-ini")
        .arg(ini_file)
        .args(&d.args)
        .current_dir(&dir)
        .env("HAL_INSTANCE", instance)
        .env("INI_FILE_NAME", ini_file)
        .env("PATH", prepend(&search_dirs(&dir), "PATH"));
    if let Some(dist) = python_dist() {
        cmd.env("PYTHONPATH", prepend(&[dist], "PYTHONPATH"));
    }
    eprintln!(
        "linuxcnc: starting the display program {} ({})",
        program.display(),
        d.origin
    );
    cmd.spawn().map_err(|source| LaunchError::Display {
        program,
        origin: d.origin.clone(),
        source,
    })
}

/// The exit status LinuxCNC's script gives for the display's: its code,
/// or 128 plus the signal that ended it (as the shell reports it).
pub fn exit_code(status: ExitStatus) -> i32 {
    use std::os::unix::process::ExitStatusExt;
    status
        .code()
        .or_else(|| status.signal().map(|s| 128 + s))
        .unwrap_or(1)
}

/// Asks a display still running at shutdown to end (SIGTERM), then kills
/// it after `grace`; returns its status.
pub fn stop(child: &mut Child, grace: std::time::Duration) -> Option<ExitStatus> {
    if let Ok(Some(s)) = child.try_wait() {
        return Some(s);
    }
    if let Ok(pid) = i32::try_from(child.id()) {
        let _ = nix::sys::signal::kill(
            nix::unistd::Pid::from_raw(pid),
            nix::sys::signal::Signal::SIGTERM,
        );
    }
    let end = std::time::Instant::now() + grace;
    while std::time::Instant::now() < end {
        if let Ok(Some(s)) = child.try_wait() {
            return Some(s);
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let _ = child.kill();
    child.wait().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_run_and_guis_are_skipped() {
        let d = |text: &str| display_program(&Ini::parse(text));
        let p = d("[DISPLAY]\nDISPLAY = ./test-ui.py --fast\n").unwrap();
        assert_eq!(p.program, "./test-ui.py");
        assert_eq!(p.args, ["--fast"]);
        assert_eq!(d("[DISPLAY]\nDISPLAY = axis\n"), None);
        assert_eq!(d("[DISPLAY]\nDISPLAY = gmoccapy -c x\n"), None);
        assert_eq!(d("[DISPLAY]\nDISPLAY = /usr/bin/axis\n"), None);
        assert_eq!(d("[DISPLAY]\nDISPLAY =\n"), None);
        let rsh = d("[DISPLAY]\nDISPLAY = linuxcncrsh --port 6001\n").unwrap();
        assert_eq!(
            (rsh.program.as_str(), rsh.args.as_slice()),
            (
                "linuxcncrsh",
                &["--port".to_string(), "6001".to_string()][..]
            )
        );
        assert_eq!(d("[EMC]\nMACHINE = m\n"), None);
    }

    #[test]
    fn exit_codes_follow_the_shell() {
        use std::os::unix::process::ExitStatusExt;
        assert_eq!(exit_code(ExitStatus::from_raw(3 << 8)), 3);
        assert_eq!(exit_code(ExitStatus::from_raw(15)), 128 + 15);
    }
}
