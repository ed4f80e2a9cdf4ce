//! Tells the tests whether SOEM can run here: cfg `soem_peer`, and its
//! Python in `SOEM_PEER_PYTHON`, when scripts/soem-peer installed pysoem
//! (its environment is $SOEM_PEER_PREFIX, else target/soem-peer).
//! Without it the tests against SOEM (tests/soem.rs) are reported as
//! ignored, with that reason.
//!
//! Also whether this host lets the tests make a network namespace with a
//! veth pair in it (root, or CAP_SYS_ADMIN and CAP_NET_ADMIN, and the
//! veth driver): cfg `netns`. Without it the test of our master on a
//! veth pair (tests/veth_master.rs) is reported as ignored, with that
//! reason. The probe runs when this script does: set
//! `HAL_NETNS_PROBE` to anything new to run it again.

use std::path::PathBuf;

fn main() {
    soem_peer();
    netns();
}

/// cfg `netns` when `unshare --net` can make a namespace and a veth pair
/// in it.
fn netns() {
    println!("cargo:rustc-check-cfg=cfg(netns)");
    println!("cargo:rerun-if-env-changed=HAL_NETNS_PROBE");
    let made = std::process::Command::new("unshare")
        .args([
            "--net",
            "sh",
            "-c",
            "ip link add name ecprobe0 type veth peer name ecprobe1",
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if made {
        println!("cargo:rustc-cfg=netns");
    }
}

/// cfg `soem_peer` and `SOEM_PEER_PYTHON` when pysoem is installed.
fn soem_peer() {
    println!("cargo:rustc-check-cfg=cfg(soem_peer)");
    println!("cargo:rerun-if-env-changed=SOEM_PEER_PREFIX");
    let prefix = std::env::var_os("SOEM_PEER_PREFIX")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let here = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
            here.join("../../target/soem-peer")
        });
    let marker = prefix.join(".installed");
    println!("cargo:rerun-if-changed={}", marker.display());
    if marker.exists() {
        println!("cargo:rustc-cfg=soem_peer");
        println!(
            "cargo:rustc-env=SOEM_PEER_PYTHON={}",
            prefix.join("bin/python").display()
        );
    }
}
