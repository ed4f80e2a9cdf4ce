//! haltcl: Tcl HAL files on Debian's own Tcl.
//!
//! A `tclsh8.6` child runs the script after a prelude
//! (`prelude.tcl`) that defines the `hal` command and, as LinuxCNC's
//! haltcl, every halcmd command as a Tcl command where Tcl has none of
//! that name, the INI values as arrays (`$::KINS(KINEMATICS)`, each a list
//! of every value of the key, as LinuxCNC's `parse_ini`) and `::argv`.
//! Every `hal` call comes back over a pipe to this process and runs on a
//! halcmd [`Session`], so a Tcl file sees exactly halcmd's commands,
//! checks and messages (and the launcher's TWOPASS and headless rules).
//! The command's output is the Tcl result; a failed command is a Tcl error
//! whose message names the script's file and line. Running Tcl in a child
//! keeps a script's `exit` from ending the caller, and needs no Tcl
//! library at build time.

use std::fs::File;
use std::io::{BufRead, BufReader, Write};
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::Command;

use hal_core::files::limits;

use crate::ini::Ini;
use crate::lexer::split_words;
use crate::Session;

/// The Tcl side of the bridge.
const PRELUDE: &str = include_str!("prelude.tcl");

/// The fds the prelude reads and writes (requests, answers, the prelude).
const REQUEST_FD: RawFd = 3;
const ANSWER_FD: RawFd = 4;
const PRELUDE_FD: RawFd = 5;

/// Why a Tcl file could not be run.
#[derive(Debug, thiserror::Error)]
pub enum HaltclError {
    /// No Tcl interpreter was found.
    #[error("haltcl needs Tcl 8.6 ({tried}); on Debian: apt install tcl8.6")]
    NoTcl {
        /// The programs looked for.
        tried: String,
    },
    /// The interpreter could not be started, or the pipes set up.
    #[error("haltcl: starting {program}: {source}")]
    Spawn {
        /// The interpreter.
        program: String,
        /// What went wrong.
        #[source]
        source: std::io::Error,
    },
    /// The Tcl file cannot be read (missing, not a regular file, too
    /// large).
    #[error("haltcl: {0}")]
    Script(#[from] hal_core::files::FileError),
    /// A stop was requested while the script ran: it was ended.
    #[error("{script}: stop requested; the Tcl script was ended")]
    Stopped {
        /// The script.
        script: String,
    },
    /// The script failed (its error was printed) or called `exit` with a
    /// non-zero status.
    #[error("{script}: the Tcl script failed (exit status {status})")]
    Failed {
        /// The script.
        script: String,
        /// Its exit status (-1 if killed by a signal).
        status: i32,
    },
    /// The child broke the request protocol.
    #[error("haltcl: bad request from tclsh: {0}")]
    Protocol(String),
}

/// What to run.
#[derive(Debug, Clone, Default)]
pub struct TclJob {
    /// The Tcl file; `None` reads commands from stdin.
    pub script: Option<PathBuf>,
    /// The script's `::argv`.
    pub argv: Vec<String>,
    /// Prompt with `haltcl: ` when reading stdin.
    pub prompt: bool,
    /// The `[HAL]TWOPASS` pass (0 or 1) the file runs in, if any: the
    /// script sees it as `[::tp::passnumber]`, as under LinuxCNC's
    /// twopass.tcl.
    pub twopass: Option<u8>,
}

/// The tclsh to run: `$HALTCL_TCLSH`, else `tclsh8.6`, else `tclsh`.
fn find_tclsh() -> Result<PathBuf, HaltclError> {
    if let Some(p) = std::env::var_os("HALTCL_TCLSH").filter(|p| !p.is_empty()) {
        return Ok(PathBuf::from(p));
    }
    let names = ["tclsh8.6", "tclsh"];
    let path = std::env::var_os("PATH").unwrap_or_default();
    for name in names {
        for dir in std::env::split_paths(&path) {
            let cand = dir.join(name);
            if cand.is_file() {
                return Ok(cand);
            }
        }
    }
    Err(HaltclError::NoTcl {
        tried: format!("$HALTCL_TCLSH, {} on PATH", names.join(", ")),
    })
}

/// A pipe whose ends are moved above the standard fds and close on exec.
fn high_pipe() -> std::io::Result<(OwnedFd, OwnedFd)> {
    let (r, w) = nix::unistd::pipe2(nix::fcntl::OFlag::O_CLOEXEC).map_err(std::io::Error::from)?;
    Ok((raise(r)?, raise(w)?))
}

/// Duplicates `fd` to a number of 10 or more (close-on-exec), so that
/// mapping it onto 3, 4 or 5 in the child never overwrites another.
fn raise(fd: OwnedFd) -> std::io::Result<OwnedFd> {
    let new = nix::fcntl::fcntl(&fd, nix::fcntl::FcntlArg::F_DUPFD_CLOEXEC(10))
        .map_err(std::io::Error::from)?;
    // SAFETY: fcntl returned a new descriptor that nothing else owns.
    Ok(unsafe { OwnedFd::from_raw_fd(new) })
}

/// Runs a Tcl HAL file (or an interactive Tcl session) whose `hal`
/// commands execute on `session`.
pub fn run(session: &mut Session<'_>, ini: Option<&Ini>, job: &TclJob) -> Result<(), HaltclError> {
    if let Some(script) = &job.script {
        // tclsh sources the file itself; this read refuses what is not a
        // regular file or is too large before tclsh ever sees it.
        hal_core::files::read_user_file(script, limits::TCL, "Tcl HAL file")?;
    }
    let tclsh = find_tclsh()?;
    let spawn_err = |source| HaltclError::Spawn {
        program: tclsh.display().to_string(),
        source,
    };
    let (req_r, req_w) = high_pipe().map_err(spawn_err)?;
    let (ans_r, ans_w) = high_pipe().map_err(spawn_err)?;
    let (pre_r, pre_w) = high_pipe().map_err(spawn_err)?;
    // The prelude fits in the pipe, so it is written whole before the
    // child starts and the write end closed: tclsh reads it to EOF.
    File::from(pre_w)
        .write_all(PRELUDE.as_bytes())
        .map_err(spawn_err)?;
    let fds = [
        (req_w.as_raw_fd(), REQUEST_FD),
        (ans_r.as_raw_fd(), ANSWER_FD),
        (pre_r.as_raw_fd(), PRELUDE_FD),
    ];
    let mut cmd = Command::new(&tclsh);
    cmd.arg(format!("/dev/fd/{PRELUDE_FD}"))
        .env("HAL_INSTANCE", session.instance().name());
    if let Some(path) = ini.and_then(Ini::path) {
        cmd.env("INI_FILE_NAME", path);
    }
    // tclsh ends with us, even when we are killed outright: a script in
    // a loop must not spin on as an orphan.
    crate::usr::end_with_parent(&mut cmd, nix::sys::signal::Signal::SIGKILL);
    // SAFETY: dup2 is async-signal-safe and touches no memory of ours; the
    // source descriptors are all 10 or above, so none is overwritten
    // before it is copied.
    unsafe {
        cmd.pre_exec(move || {
            for (from, to) in fds {
                if libc::dup2(from, to) < 0 {
                    return Err(std::io::Error::last_os_error());
                }
            }
            Ok(())
        });
    }
    let mut child = cmd.spawn().map_err(spawn_err)?;
    // Our copies of the child's ends go, so EOF means the child is gone.
    drop((req_w, ans_r, pre_r));
    let mut requests = BufReader::new(File::from(req_r));
    let mut answers = File::from(ans_w);
    let name = job
        .script
        .as_deref()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| "haltcl".to_string());
    let served = serve(session, ini, job, &mut requests, &mut answers);
    drop(answers);
    if let Err(Served::Stopped) = served {
        crate::usr::end_child(&mut child);
        return Err(HaltclError::Stopped { script: name });
    }
    let status = child.wait().map_err(spawn_err)?;
    if let Err(Served::Failed(e)) = served {
        return Err(e);
    }
    match status.code() {
        Some(0) => Ok(()),
        code => Err(HaltclError::Failed {
            script: name,
            status: code.unwrap_or(-1),
        }),
    }
}

/// Why serving the child ended early.
enum Served {
    /// The protocol broke.
    Failed(HaltclError),
    /// The session's stop was requested.
    Stopped,
}

impl From<HaltclError> for Served {
    fn from(e: HaltclError) -> Served {
        Served::Failed(e)
    }
}

/// Waits until a request can be read, looking at the session's stop
/// request every 100 ms (a script in a loop sends none).
fn wait_for_request(session: &Session<'_>, requests: &BufReader<File>) -> Result<(), Served> {
    use nix::poll::{poll, PollFd, PollFlags, PollTimeout};
    use std::os::fd::AsFd;
    loop {
        if !requests.buffer().is_empty() {
            return Ok(());
        }
        if session.stop_requested() {
            return Err(Served::Stopped);
        }
        let mut fds = [PollFd::new(requests.get_ref().as_fd(), PollFlags::POLLIN)];
        match poll(&mut fds, PollTimeout::from(100u8)) {
            Ok(0) | Err(nix::errno::Errno::EINTR) => {}
            // Readable, hung up or failed: the read says which.
            _ => return Ok(()),
        }
    }
}

/// Answers the child's requests until it closes its end.
fn serve(
    session: &mut Session<'_>,
    ini: Option<&Ini>,
    job: &TclJob,
    requests: &mut BufReader<File>,
    answers: &mut impl Write,
) -> Result<(), Served> {
    loop {
        wait_for_request(session, requests)?;
        let Some(fields) = read_request(requests)? else {
            break;
        };
        if session.stop_requested() {
            return Err(Served::Stopped);
        }
        let (ok, reply) = answer(session, ini, job, &fields)?;
        // A child that died mid-request cannot read the answer: not an
        // error of ours; its exit status tells.
        if write_answer(answers, ok, &reply).is_err() {
            break;
        }
    }
    Ok(())
}

fn answer(
    session: &mut Session<'_>,
    ini: Option<&Ini>,
    job: &TclJob,
    fields: &[String],
) -> Result<(bool, Vec<String>), HaltclError> {
    match fields.first().map(String::as_str) {
        Some("commands") => Ok((true, crate::session::command_names())),
        Some("ini") => Ok((true, ini.map(ini_fields).unwrap_or_default())),
        Some("parse-ini") if fields.len() == 2 => match Ini::load(Path::new(&fields[1])) {
            Ok(parsed) => Ok((true, ini_fields(&parsed))),
            Err(e) => Ok((false, vec![e.to_string()])),
        },
        Some("job") => {
            let mut v = vec![
                job.script
                    .as_deref()
                    .map(|p| p.display().to_string())
                    .unwrap_or_default(),
                if job.prompt { "1" } else { "0" }.to_string(),
                job.twopass.map(|p| p.to_string()).unwrap_or_default(),
            ];
            v.extend(job.argv.iter().cloned());
            Ok((true, v))
        }
        Some("hal") if fields.len() >= 4 => {
            let file = fields[1].as_str();
            let line: usize = fields[2]
                .parse()
                .map_err(|_| HaltclError::Protocol(format!("bad line number {:?}", fields[2])))?;
            let words = hal_words(&fields[3..]);
            let at = (!file.is_empty()).then(|| short_name(file));
            let (ok, out, err) = session.captured(|s| s.run_words_at(at.as_deref(), line, &words));
            if ok {
                Ok((
                    true,
                    vec![out.strip_suffix('\n').unwrap_or(&out).to_string()],
                ))
            } else {
                let mut msg = err.trim_end().to_string();
                if msg.is_empty() {
                    msg = format!("hal {} failed", words.join(" "));
                }
                Ok((false, vec![msg]))
            }
        }
        other => Err(HaltclError::Protocol(format!("unknown request {other:?}"))),
    }
}

/// Every INI entry as (section, key, value) fields.
fn ini_fields(ini: &Ini) -> Vec<String> {
    let mut v = Vec::new();
    for e in ini.entries() {
        v.extend([e.section.clone(), e.key.clone(), e.value.clone()]);
    }
    v
}

/// The words of a `hal` call as halcmd would see them. `loadrt`'s
/// arguments are joined and split again, as LinuxCNC's module loader
/// does, so that an INI value with spaces (`loadrt $::KINS(KINEMATICS)`,
/// a one-element Tcl list `{trivkins coordinates=xz}`) and a quoted
/// `config="..."` split by Tcl both load as written in halcmd.
fn hal_words(words: &[String]) -> Vec<String> {
    if words.first().map(String::as_str) != Some("loadrt") {
        return words.to_vec();
    }
    let joined: Vec<&str> = words[1..]
        .iter()
        .map(|w| {
            w.strip_prefix('{')
                .and_then(|x| x.strip_suffix('}'))
                .unwrap_or(w)
        })
        .collect();
    let mut out = vec!["loadrt".to_string()];
    match split_words(&joined.join(" ")) {
        Ok(w) => out.extend(w),
        Err(_) => out.extend(words[1..].iter().cloned()),
    }
    out
}

/// A script path as messages show it: relative to the working directory
/// when it is below it.
fn short_name(file: &str) -> String {
    let p = Path::new(file);
    std::env::current_dir()
        .ok()
        .and_then(|cwd| p.strip_prefix(cwd).ok().map(|r| r.display().to_string()))
        .unwrap_or_else(|| file.to_string())
}

/// Reads one request: a line with the field count, then each field as a
/// line with its byte length and the bytes. `None` at EOF.
fn read_request(r: &mut impl BufRead) -> Result<Option<Vec<String>>, HaltclError> {
    let mut line = String::new();
    let n = read_count(r, &mut line)?;
    let Some(n) = n else { return Ok(None) };
    let mut fields = Vec::with_capacity(n.min(4096));
    for _ in 0..n {
        let len = read_count(r, &mut line)?
            .ok_or_else(|| HaltclError::Protocol("request cut short".into()))?;
        if len > 1 << 24 {
            return Err(HaltclError::Protocol(format!("field of {len} bytes")));
        }
        let mut buf = vec![0u8; len];
        r.read_exact(&mut buf)
            .map_err(|e| HaltclError::Protocol(format!("reading a field: {e}")))?;
        fields.push(
            String::from_utf8(buf)
                .map_err(|_| HaltclError::Protocol("field is not UTF-8".into()))?,
        );
    }
    Ok(Some(fields))
}

fn read_count(r: &mut impl BufRead, line: &mut String) -> Result<Option<usize>, HaltclError> {
    line.clear();
    let n = r
        .read_line(line)
        .map_err(|e| HaltclError::Protocol(format!("reading: {e}")))?;
    if n == 0 {
        return Ok(None);
    }
    line.trim_end()
        .parse()
        .map(Some)
        .map_err(|_| HaltclError::Protocol(format!("bad count {line:?}")))
}

fn write_answer(w: &mut impl Write, ok: bool, fields: &[String]) -> std::io::Result<()> {
    let mut out = format!("{} {}\n", if ok { "ok" } else { "err" }, fields.len()).into_bytes();
    for f in fields {
        out.extend_from_slice(format!("{}\n", f.len()).as_bytes());
        out.extend_from_slice(f.as_bytes());
    }
    w.write_all(&out)?;
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn requests_and_answers_round_trip() {
        let mut input: &[u8] = b"3\n3\nhal0\n6\nloadrt";
        let fields = read_request(&mut input).unwrap().unwrap();
        assert_eq!(fields, ["hal", "", "loadrt"]);
        assert!(read_request(&mut input).unwrap().is_none());
        let mut bad: &[u8] = b"x\n";
        assert!(read_request(&mut bad).is_err());
        let mut out = Vec::new();
        write_answer(&mut out, false, &["é".to_string()]).unwrap();
        assert_eq!(out, "err 1\n2\né".as_bytes());
    }

    #[test]
    fn loadrt_words_split_like_halcmd() {
        let w = |v: &[&str]| hal_words(&v.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        assert_eq!(
            w(&["loadrt", "{trivkins coordinates=xz}"]),
            ["loadrt", "trivkins", "coordinates=xz"]
        );
        assert_eq!(
            w(&[
                "loadrt",
                "hm2_pci",
                "config=\"num_encoders=1",
                "num_pwmgens=0\""
            ]),
            [
                "loadrt",
                "hm2_pci",
                "config=\"num_encoders=1 num_pwmgens=0\""
            ]
        );
        assert_eq!(w(&["net", "a b", "c"]), ["net", "a b", "c"]);
    }
}
