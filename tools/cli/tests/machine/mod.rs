//! A machine started with `linuxcnc MACHINE.ini` on an instance of its
//! own, the tools that talk to it, and its orderly stop.
#![allow(dead_code)]

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Output, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

#[path = "../common/mod.rs"]
mod common;
#[allow(unused_imports)]
pub use common::{instance, root};

/// A scratch directory of this test (removed by `Scratch::drop`).
pub struct Scratch(pub PathBuf);

impl Scratch {
    /// A new empty directory named after `tag`.
    pub fn new(tag: &str) -> Scratch {
        let d = std::env::temp_dir().join(format!("launcher-{}", instance(tag)));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        Scratch(d)
    }

    /// Writes `name` (creating directories).
    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, text).unwrap();
        p
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A copy of configs/sim/mill in `s`, without its parameter file (the
/// interpreter writes one beside the INI file); returns the INI file.
pub fn mill_copy(s: &Scratch) -> PathBuf {
    let src = root().join("configs/sim/mill");
    for entry in std::fs::read_dir(&src).unwrap().flatten() {
        let name = entry.file_name();
        let name = name.to_str().unwrap();
        if !name.starts_with("sim.var") {
            std::fs::copy(entry.path(), s.0.join(name)).unwrap();
        }
    }
    s.0.join("mill.ini")
}

fn env(cmd: &mut Command, instance: &str) {
    cmd.env("HAL_INSTANCE", instance)
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (16u64 << 20).to_string());
}

/// Runs one of the tools on `instance`.
pub fn tool(bin: &str, args: &[&str], instance: &str, dir: Option<&Path>) -> Output {
    let mut cmd = Command::new(bin);
    cmd.args(args);
    env(&mut cmd, instance);
    if let Some(d) = dir {
        cmd.current_dir(d);
    }
    cmd.output().expect("the tool runs")
}

/// (success, stdout, stderr) of an output.
pub fn text(o: &Output) -> (bool, String, String) {
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A running `linuxcnc`.
pub struct Machine {
    pub instance: String,
    child: Option<Child>,
    stderr: Arc<Mutex<String>>,
}

impl Machine {
    /// Starts `linuxcnc ini` and waits until it answers `task-cmd status`
    /// (or exits, which fails the test unless `expect_failure`).
    pub fn start(ini: &Path, tag: &str) -> Machine {
        let m = Machine::spawn(ini, tag, &[]);
        m.wait_ready();
        m
    }

    /// Starts `linuxcnc ARGS ini` without waiting.
    pub fn spawn(ini: &Path, tag: &str, args: &[&str]) -> Machine {
        let instance = instance(tag);
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_linuxcnc"));
        cmd.args(args)
            .arg(ini)
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        env(&mut cmd, &instance);
        let mut child = cmd.spawn().expect("linuxcnc starts");
        let stderr = Arc::new(Mutex::new(String::new()));
        let mut pipe = child.stderr.take().unwrap();
        let sink = stderr.clone();
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            while let Ok(n) = pipe.read(&mut buf) {
                if n == 0 {
                    break;
                }
                sink.lock()
                    .unwrap()
                    .push_str(&String::from_utf8_lossy(&buf[..n]));
            }
        });
        Machine {
            instance,
            child: Some(child),
            stderr,
        }
    }

    /// The launcher's process id.
    pub fn pid(&self) -> i32 {
        self.child.as_ref().unwrap().id() as i32
    }

    /// What it wrote to stderr so far.
    pub fn stderr(&self) -> String {
        self.stderr.lock().unwrap().clone()
    }

    /// What it wrote to stderr, once it holds `needle` (or after 10 s):
    /// the reader thread may not have caught up with lines written before
    /// the launcher answered.
    pub fn stderr_with(&self, needle: &str) -> String {
        let end = Instant::now() + Duration::from_secs(10);
        loop {
            let text = self.stderr();
            if text.contains(needle) || Instant::now() > end {
                return text;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    fn wait_ready(&self) {
        let end = Instant::now() + Duration::from_secs(60);
        loop {
            let (ok, _, _) = self.task(&["status"]);
            if ok {
                return;
            }
            let exited = self.child.as_ref().map(|c| c.id()).is_some_and(|pid| {
                !Path::new(&format!("/proc/{pid}")).exists()
                    || std::fs::read_to_string(format!("/proc/{pid}/stat"))
                        .is_ok_and(|s| s.contains(") Z "))
            });
            assert!(!exited, "linuxcnc exited at start-up:\n{}", self.stderr());
            assert!(
                Instant::now() < end,
                "linuxcnc did not come up:\n{}",
                self.stderr()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// `task-cmd ARGS`: (success, stdout, stderr).
    pub fn task(&self, args: &[&str]) -> (bool, String, String) {
        text(&tool(
            env!("CARGO_BIN_EXE_task-cmd"),
            args,
            &self.instance,
            None,
        ))
    }

    /// `task-cmd ARGS`, which must succeed; its stdout.
    pub fn task_ok(&self, args: &[&str]) -> String {
        let (ok, out, err) = self.task(args);
        assert!(
            ok,
            "task-cmd {args:?}: {err}\n--- linuxcnc:\n{}",
            self.stderr()
        );
        out
    }

    /// `halcmd ARGS`, which must succeed; its stdout.
    pub fn halcmd(&self, args: &[&str]) -> String {
        let (ok, out, err) = text(&tool(
            env!("CARGO_BIN_EXE_halcmd"),
            args,
            &self.instance,
            None,
        ));
        assert!(ok, "halcmd {args:?}: {err}");
        out
    }

    /// `halcmd getp NAME`, trimmed.
    pub fn getp(&self, name: &str) -> String {
        self.halcmd(&["getp", name]).trim().to_string()
    }

    /// Waits (up to 10 s) until `halcmd getp NAME` reads `want`; returns
    /// the last value read (a pin another process updates every cycle).
    pub fn wait_getp(&self, name: &str, want: &str) -> String {
        let end = Instant::now() + Duration::from_secs(10);
        loop {
            let v = self.getp(name);
            if v == want || Instant::now() > end {
                return v;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// `motion-cmd ARGS`, which must succeed; its stdout.
    pub fn motion(&self, args: &[&str]) -> String {
        let (ok, out, err) = text(&tool(
            env!("CARGO_BIN_EXE_motion-cmd"),
            args,
            &self.instance,
            None,
        ));
        assert!(
            ok,
            "motion-cmd {args:?}: {out}{err}\n--- the machine's stderr:\n{}",
            self.stderr()
        );
        out
    }

    /// Whether the threads run: the motion controller's heartbeat (the
    /// servo cycles it ran) moves.
    /// E-stop reset, machine on, every joint homed and in position.
    pub fn on_and_homed(&self) {
        assert!(self.threads_run(), "threads run");
        self.task_ok(&["estop-reset"]);
        self.task_ok(&["machine-on"]);
        self.motion(&["home", "-1"]);
        self.motion(&["-t", "60", "wait", "all-homed"]);
        self.motion(&["-t", "30", "wait", "in-position"]);
    }

    pub fn threads_run(&self) -> bool {
        let beat = || {
            let out = self.motion(&["status"]);
            out.split_whitespace()
                .skip_while(|w| *w != "heartbeat")
                .nth(1)
                .and_then(|v| v.parse::<u64>().ok())
                .unwrap_or(0)
        };
        let a = beat();
        let end = Instant::now() + Duration::from_secs(10);
        while Instant::now() < end {
            std::thread::sleep(Duration::from_millis(20));
            if beat() > a {
                return true;
            }
        }
        false
    }

    /// Sends `signal` (SIGTERM, SIGINT) and waits for the exit; returns
    /// the status and everything written to stderr.
    pub fn stop_with(self, signal: nix::sys::signal::Signal) -> (ExitStatus, String) {
        let pid = self.child.as_ref().unwrap().id() as i32;
        nix::sys::signal::kill(nix::unistd::Pid::from_raw(pid), signal).unwrap();
        self.wait_exit()
    }

    /// Waits for an exit without signalling (a start-up that fails).
    pub fn wait_exit(mut self) -> (ExitStatus, String) {
        let mut child = self.child.take().unwrap();
        let end = Instant::now() + Duration::from_secs(60);
        let status = loop {
            if let Some(s) = child.try_wait().unwrap() {
                break s;
            }
            assert!(
                Instant::now() < end,
                "linuxcnc did not exit:\n{}",
                self.stderr()
            );
            std::thread::sleep(Duration::from_millis(20));
        };
        std::thread::sleep(Duration::from_millis(50));
        (status, self.stderr())
    }

    /// SIGTERM; asserts a clean exit and that the instance is gone.
    pub fn stop(self) -> String {
        let instance = self.instance.clone();
        let (status, err) = self.stop_with(nix::sys::signal::Signal::SIGTERM);
        assert!(status.success(), "linuxcnc exited with {status}:\n{err}");
        assert!(
            hal_core::Instance::attach(&instance).is_err(),
            "the instance is gone"
        );
        err
    }
}

impl Drop for Machine {
    fn drop(&mut self) {
        if let Some(mut c) = self.child.take() {
            let _ = nix::sys::signal::kill(
                nix::unistd::Pid::from_raw(c.id() as i32),
                nix::sys::signal::Signal::SIGTERM,
            );
            let _ = c.wait();
        }
    }
}

/// The children of process `parent` whose command name starts with
/// `name`, from /proc.
pub fn children_named(parent: i32, name: &str) -> Vec<i32> {
    let mut out = Vec::new();
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<i32>() else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
            continue;
        };
        let (Some(open), Some(close)) = (stat.find('('), stat.rfind(')')) else {
            continue;
        };
        let comm = &stat[open + 1..close];
        let ppid = stat[close + 1..]
            .split_whitespace()
            .nth(1)
            .and_then(|p| p.parse::<i32>().ok());
        if ppid == Some(parent) && comm.starts_with(name) {
            out.push(pid);
        }
    }
    out
}

/// Whether process `pid` still runs (a zombie does not).
pub fn running(pid: i32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|s| {
        s.rsplit_once(')')
            .is_some_and(|(_, r)| !r.trim_start().starts_with('Z'))
    })
}
