//! Starting and stopping the host process of an instance.

use std::path::PathBuf;
use std::process::{Child, Command};
use std::time::Duration;

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

/// Starts a host for `instance` and waits until it answers.
pub fn start_host(instance: &str) -> Result<Child, String> {
    if Client::connect(instance).is_ok() {
        return Err(format!(
            "realtime is already running for instance '{instance}'"
        ));
    }
    let mut child = Command::new(host_binary())
        .args(["--instance", instance])
        .spawn()
        .map_err(|e| format!("starting {}: {e}", host_binary().display()))?;
    match Client::wait_for(instance, Duration::from_secs(20)) {
        Ok(_) => Ok(child),
        Err(e) => {
            let _ = child.kill();
            let _ = child.wait();
            Err(e.to_string())
        }
    }
}

/// Asks the host of `instance` to stop everything and exit.
pub fn stop_host(instance: &str) -> Result<(), ClientError> {
    let mut c = Client::connect(instance)?;
    c.call(&["shutdown".to_string()])
}
