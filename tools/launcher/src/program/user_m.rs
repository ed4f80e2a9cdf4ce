//! User M-codes M100 to M199, as LinuxCNC's task runs them: at start-up
//! task looks for an executable file named `M1nn` (capital M, no
//! extension) in the program prefix directory, then in each directory of
//! `[RS274NGC]USER_M_PATH`; the first one found serves M1nn for as long
//! as task runs. The program runs with P and Q as its two arguments,
//! printed as C's `%f` prints them (`1.500000`; an absent word is
//! `-1.000000`), and the program waits until it exits. A non-zero exit
//! or a signal fails the run.

use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus};

/// The first user M-code number.
const FIRST: i32 = 100;
/// How many user M-codes there are (M100 to M199).
const COUNT: usize = 100;
/// Directories of `[RS274NGC]USER_M_PATH` LinuxCNC searches at most.
pub const MAX_USER_M_DIRS: usize = 5;

/// The programs found for M100 to M199.
#[derive(Debug, Clone, Default)]
pub struct UserMCodes {
    programs: Vec<Option<PathBuf>>,
}

impl UserMCodes {
    /// Looks for `M100` ... `M199` in `dirs`, in order; the first
    /// executable file of a name wins. Files without an execute bit for
    /// their owner are passed over, as LinuxCNC does.
    pub fn scan(dirs: &[PathBuf]) -> UserMCodes {
        let programs = (0..COUNT)
            .map(|i| {
                let name = format!("M{}", FIRST as usize + i);
                dirs.iter()
                    .map(|d| d.join(&name))
                    .find(|p| is_executable(p))
            })
            .collect();
        UserMCodes { programs }
    }

    /// The program for M`number`, if one was found.
    pub fn program(&self, number: i32) -> Option<&Path> {
        let i = usize::try_from(number.checked_sub(FIRST)?).ok()?;
        self.programs.get(i)?.as_deref()
    }
}

fn is_executable(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o100 != 0)
}

/// P or Q as the user program's argument: six decimals, as C's `%f`.
pub fn argument(value: f64) -> String {
    format!("{value:.6}")
}

/// A user M-code program that task started and waits for.
#[derive(Debug)]
pub struct Running {
    child: Child,
}

impl Running {
    /// Starts `program` with P and Q as its arguments.
    pub fn start(program: &Path, p: f64, q: f64) -> std::io::Result<Running> {
        let child = Command::new(program)
            .arg(argument(p))
            .arg(argument(q))
            .stdin(std::process::Stdio::null())
            .spawn()?;
        Ok(Running { child })
    }

    /// How it exited, once it has; `None` while it runs.
    pub fn poll(&mut self) -> std::io::Result<Option<ExitStatus>> {
        self.child.try_wait()
    }

    /// Interrupts it (SIGINT, as LinuxCNC's task abandons a system
    /// command on abort); it is reaped by [`Abandoned::reap`].
    pub fn interrupt(self) -> Child {
        let pid = nix::unistd::Pid::from_raw(self.child.id() as i32);
        // It may have exited already; then there is nothing to stop.
        let _ = nix::sys::signal::kill(pid, nix::sys::signal::Signal::SIGINT);
        self.child
    }
}

/// Programs interrupted by an abort, reaped once they exit so that no
/// zombie is left behind.
#[derive(Debug, Default)]
pub struct Abandoned(Vec<Child>);

impl Abandoned {
    /// Keeps `child` until it has exited.
    pub fn push(&mut self, child: Child) {
        self.0.push(child);
    }

    /// Reaps those that have exited.
    pub fn reap(&mut self) {
        self.0.retain_mut(|c| matches!(c.try_wait(), Ok(None)));
    }
}

/// Why a user M-code program failed, in words.
pub fn exit_text(status: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(code), _) => format!("exited with status {code}"),
        (None, Some(sig)) => format!("was killed by signal {sig}"),
        (None, None) => "ended abnormally".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments_print_as_c_percent_f() {
        assert_eq!(argument(123.456), "123.456000");
        assert_eq!(argument(-1.0), "-1.000000");
        assert_eq!(argument(0.0), "0.000000");
    }

    #[test]
    fn the_first_executable_file_of_a_name_wins() {
        let base = std::env::temp_dir().join(format!("user-m-scan-{}", std::process::id()));
        let (a, b) = (base.join("a"), base.join("b"));
        std::fs::create_dir_all(&a).unwrap();
        std::fs::create_dir_all(&b).unwrap();
        let write = |p: PathBuf, mode: u32| {
            std::fs::write(&p, "#!/bin/sh\n").unwrap();
            std::fs::set_permissions(&p, std::fs::Permissions::from_mode(mode)).unwrap();
        };
        write(a.join("M101"), 0o644);
        write(b.join("M101"), 0o755);
        write(a.join("M102"), 0o755);
        write(b.join("M102"), 0o755);
        write(a.join("m103"), 0o755);
        let codes = UserMCodes::scan(&[a.clone(), b.clone()]);
        assert_eq!(codes.program(101), Some(b.join("M101").as_path()));
        assert_eq!(codes.program(102), Some(a.join("M102").as_path()));
        assert_eq!(codes.program(103), None);
        assert_eq!(codes.program(99), None);
        assert_eq!(codes.program(200), None);
        std::fs::remove_dir_all(&base).unwrap();
    }
}
