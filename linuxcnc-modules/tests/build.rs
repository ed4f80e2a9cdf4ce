//! Tells the tests whether LinuxCNC can run here: cfg `linuxcnc_peer`
//! when LinuxCNC is unpacked (scripts/linuxcnc-peer install; its prefix
//! is $LINUXCNC_PEER_PREFIX, else target/linuxcnc-peer) and the build
//! runs as root (the peer needs a private mount namespace). Without it
//! the tests are reported as ignored, with that reason.

use std::path::PathBuf;

fn main() {
    println!("cargo:rustc-check-cfg=cfg(linuxcnc_peer)");
    println!("cargo:rerun-if-env-changed=LINUXCNC_PEER_PREFIX");
    let prefix = std::env::var_os("LINUXCNC_PEER_PREFIX")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let here = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
            here.join("../../target/linuxcnc-peer")
        });
    let rtapi_app = prefix.join("usr/bin/rtapi_app");
    println!("cargo:rerun-if-changed={}", rtapi_app.display());
    if rtapi_app.exists() && is_root() {
        println!("cargo:rustc-cfg=linuxcnc_peer");
    }
}

/// Whether this process's effective uid is 0.
fn is_root() -> bool {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("Uid:"))
                .and_then(|l| l.split_whitespace().nth(2).map(|e| e == "0"))
        })
        .unwrap_or(false)
}
