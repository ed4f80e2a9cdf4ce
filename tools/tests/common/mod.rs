//! Running HAL files through halrun, each on an instance of its own.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicU32, Ordering};

static COUNTER: AtomicU32 = AtomicU32::new(0);

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// An instance name no other test uses.
pub fn instance(tag: &str) -> String {
    format!(
        "e2e-{tag}-{}-{}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    )
}

/// Runs `halrun ARGS` in `dir` on a fresh instance, without realtime
/// scheduling (tests run side by side).
pub fn halrun(dir: &Path, args: &[&str], tag: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_halrun"))
        .args(args)
        .current_dir(dir)
        .env("HAL_INSTANCE", instance(tag))
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (8u64 << 20).to_string())
        .output()
        .expect("halrun runs")
}

/// The error lines of LinuxCNC's stderr that describe the user's mistake:
/// without the lines about LinuxCNC's own process machinery.
pub fn meaningful_stderr(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| {
            !["dlopen", "rtapi_app", "insmod", "waitpid"]
                .iter()
                .any(|w| l.contains(w))
        })
        .map(str::to_string)
        .collect()
}

/// A host served on a background thread of this process, for tests that
/// drive a [`hal_tools::halcmd::Session`] directly.
pub struct InProcessHost {
    pub instance: String,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl InProcessHost {
    pub fn start(tag: &str) -> InProcessHost {
        let name = instance(tag);
        let mut cfg = hal_core::HostConfig::new(&name);
        cfg.shm_size = 8 << 20;
        cfg.realtime = hal_core::RealtimeMode::Off;
        let (tx, rx) = std::sync::mpsc::channel();
        let thread = std::thread::spawn(move || {
            hal_tools::hostd::serve(cfg, move || {
                let _ = tx.send(());
            })
            .expect("host serves");
        });
        rx.recv_timeout(std::time::Duration::from_secs(20))
            .expect("host ready");
        InProcessHost {
            instance: name,
            thread: Some(thread),
        }
    }

    pub fn instance(&self) -> hal_core::Instance {
        hal_core::Instance::attach(&self.instance).expect("attach")
    }

    /// Runs `text` as file `name`; returns (ok, stdout, stderr).
    pub fn run(&self, name: &str, text: &str, keep_going: bool) -> (bool, String, String) {
        let (mut out, mut err) = (Vec::new(), Vec::new());
        let opts = hal_tools::halcmd::Options {
            keep_going,
            ..Default::default()
        };
        let ok = {
            let mut s = hal_tools::halcmd::Session::new(self.instance(), opts, &mut out, &mut err);
            s.run_text(Some(name), text)
        };
        (
            ok,
            String::from_utf8_lossy(&out).into_owned(),
            String::from_utf8_lossy(&err).into_owned(),
        )
    }
}

impl Drop for InProcessHost {
    fn drop(&mut self) {
        let _ = hal_tools::launch::stop_host(&self.instance, std::time::Duration::from_secs(10));
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
