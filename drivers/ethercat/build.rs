//! Tells the tests whether SOEM can run here: cfg `soem_peer`, and its
//! Python in `SOEM_PEER_PYTHON`, when scripts/soem-peer installed pysoem
//! (its environment is $SOEM_PEER_PREFIX, else target/soem-peer).
//! Without it the tests against SOEM (tests/soem.rs) are reported as
//! ignored, with that reason.

use std::path::PathBuf;

fn main() {
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
