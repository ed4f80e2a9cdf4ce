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
