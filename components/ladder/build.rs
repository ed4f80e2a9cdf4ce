//! Finds LinuxCNC's sample configurations (from the peer that
//! scripts/linuxcnc-peer installs: $LINUXCNC_PEER_PREFIX, else
//! target/linuxcnc-peer) for tests/samples.rs, which reads their .clp
//! projects: the directory reaches the tests as
//! `HAL_PEER_SAMPLE_CONFIGS`, and cfg `hal_no_peer_configs` is set when
//! it is not there, so those tests are reported as ignored.

use std::path::PathBuf;

fn main() {
    println!("cargo::rustc-check-cfg=cfg(hal_no_peer_configs)");
    println!("cargo::rerun-if-env-changed=LINUXCNC_PEER_PREFIX");
    println!("cargo::rerun-if-changed=build.rs");
    let prefix = std::env::var_os("LINUXCNC_PEER_PREFIX")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let here = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
            here.join("../../target/linuxcnc-peer")
        });
    let dir = prefix.join("usr/share/doc/linuxcnc/examples/sample-configs");
    if prefix.exists() {
        println!("cargo::rerun-if-changed={}", prefix.display());
    }
    println!("cargo::rustc-env=HAL_PEER_SAMPLE_CONFIGS={}", dir.display());
    if !dir.join("sim").is_dir() {
        println!("cargo::rustc-cfg=hal_no_peer_configs");
    }
}
