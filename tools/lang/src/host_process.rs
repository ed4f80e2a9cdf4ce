//! Starting and stopping the host process of an instance.

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use crate::error::{LangError, Result};
use crate::protocol::{Client, ClientError};

/// The `hal-host` binary next to the running executable.
pub fn host_binary() -> PathBuf {
    let exe = std::env::current_exe().unwrap_or_default();
    let dir = exe.parent().map(PathBuf::from).unwrap_or_default();
    // Test binaries live in target/*/deps; the tools one level up.
    for cand in [dir.join("hal-host"), dir.join("../hal-host")] {
        if cand.exists() {
            return cand;
        }
    }
    PathBuf::from("hal-host")
}

/// Starts a host for `instance` and waits until it answers. A detached
/// host gets a session of its own, so it outlives the shell that started
/// it (`realtime start`).
pub fn start_host(instance: &str, detached: bool) -> Result<Child> {
    start(instance, detached, false)
}

/// Starts a host for `instance` in a process group of its own, so that
/// Ctrl-C in the terminal reaches only the caller, which then shuts the
/// host down in order (the launcher brings the machine to its safe state
/// first). The host still goes if the caller dies.
pub fn start_host_own_group(instance: &str) -> Result<Child> {
    start(instance, false, true)
}

fn start(instance: &str, detached: bool, own_group: bool) -> Result<Child> {
    if Client::connect(instance).is_ok() {
        return Err(LangError::AlreadyRunning {
            instance: instance.to_string(),
        });
    }
    let mut cmd = Command::new(host_binary());
    cmd.args(["--instance", instance]);
    use std::os::unix::process::CommandExt;
    if !detached {
        // If halrun dies, its host goes too (SIGTERM: a clean shutdown).
        // SAFETY: prctl and setpgid are async-signal-safe and touch no memory
        // of ours.
        unsafe {
            cmd.pre_exec(move || {
                libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM);
                if own_group {
                    libc::setpgid(0, 0);
                }
                Ok(())
            });
        }
    }
    if detached {
        // A detached host writes its notes to a log beside its socket.
        hal_core::paths::ensure_runtime_dir()?;
        let log_path = log_path(instance)?;
        let log = hal_core::paths::create_log(&log_path)?;
        let log2 = log.try_clone().map_err(|source| LangError::Log {
            path: log_path.clone(),
            source,
        })?;
        cmd.stdin(Stdio::null()).stdout(log).stderr(log2);
        // SAFETY: setsid is async-signal-safe and touches no memory of ours.
        unsafe {
            cmd.pre_exec(|| {
                libc::setsid();
                Ok(())
            });
        }
    }
    let mut child = cmd.spawn().map_err(|source| LangError::HostSpawn {
        binary: host_binary(),
        source,
    })?;
    let end = std::time::Instant::now() + Duration::from_secs(20);
    loop {
        if let Ok(Some(status)) = child.try_wait() {
            // A detached host said why in its log.
            let why = if detached {
                log_path(instance)
                    .ok()
                    .and_then(|p| std::fs::read_to_string(p).ok())
                    .map(|t| format!(": {}", t.trim_end()))
                    .unwrap_or_default()
            } else {
                String::new()
            };
            return Err(LangError::HostExited { status, why });
        }
        match Client::wait_for(instance, Duration::from_millis(100)) {
            Ok(_) => return Ok(child),
            Err(_) if std::time::Instant::now() < end => {}
            Err(e) => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(e.into());
            }
        }
    }
}

/// Where a detached host of `instance` writes its messages.
pub fn log_path(instance: &str) -> Result<PathBuf> {
    Ok(hal_core::paths::log(instance)?)
}

/// Asks the host of `instance` to stop everything and exit, and waits up
/// to `limit` until it has released everything: its segment, its socket
/// and its lock (the host closes our connection only after that). On
/// success a new host can start for the instance at once.
///
/// A host that does not answer the request within `limit` counts as
/// still running too; the error carries its process id, so the caller
/// can end it ([`kill_host`]).
pub fn stop_host(instance: &str, limit: Duration) -> std::result::Result<(), ClientError> {
    let mut c = Client::connect(instance)?;
    let pid = c.peer_pid();
    let still_running = || ClientError::StillRunning {
        instance: instance.to_string(),
        limit_s: limit.as_secs_f64(),
        pid,
    };
    let end = std::time::Instant::now() + limit;
    match c.call_within(&["shutdown".to_string()], limit) {
        Ok(()) => {}
        Err(ClientError::Io { source, .. })
            if matches!(
                source.kind(),
                std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
            ) =>
        {
            return Err(still_running())
        }
        Err(e) => return Err(e),
    }
    let closed = c.wait_closed(end.saturating_duration_since(std::time::Instant::now()));
    // The connection also closes if the host dies; then check that the
    // lock is free (a dead host's segment is reclaimed by the next one).
    let mut alive = hal_core::Instance::attach(instance).is_ok();
    while closed && alive && std::time::Instant::now() < end {
        std::thread::sleep(Duration::from_millis(5));
        alive = hal_core::Instance::attach(instance).is_ok();
    }
    if !closed || alive {
        return Err(still_running());
    }
    Ok(())
}

/// Ends a host that did not stop when asked: SIGKILL to process `pid`,
/// then waits up to `limit` for it to be gone. Its drivers get no safe
/// state, which is why this is the last resort after [`stop_host`]; the
/// next host of the instance reclaims what it left. True once it is gone.
pub fn kill_host(pid: i32, limit: Duration) -> bool {
    use nix::sys::signal::{kill, Signal};
    use nix::unistd::Pid;
    let pid = Pid::from_raw(pid);
    if kill(pid, Signal::SIGKILL).is_err() {
        return kill(pid, None).is_err();
    }
    let end = std::time::Instant::now() + limit;
    while std::time::Instant::now() < end {
        if holds_nothing(pid.as_raw()) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    false
}

/// Whether process `pid` has let go of everything it held: it is gone, or
/// it is a zombie its parent has yet to reap and none of its threads is
/// still exiting. The leader of a killed multi-threaded process turns
/// zombie first; its other threads, still on their way out, keep the
/// shared file table, and with it the host's socket and lock, open until
/// the last of them has left (each leaves `/proc/PID/task` when it has).
fn holds_nothing(pid: i32) -> bool {
    let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
        return true;
    };
    let zombie = stat
        .rsplit_once(')')
        .is_some_and(|(_, r)| r.trim_start().starts_with('Z'));
    if !zombie {
        return false;
    }
    match std::fs::read_dir(format!("/proc/{pid}/task")) {
        Ok(tasks) => tasks.count() <= 1,
        Err(_) => true,
    }
}
