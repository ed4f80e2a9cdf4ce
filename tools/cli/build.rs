//! Decides whether the golden tests (`tests/golden.rs`) can run (see
//! build-support/golden_corpus.rs), and whether LinuxCNC's own sample
//! configurations are there for `tests/linuxcnc_configs.rs`.

include!("../../build-support/golden_corpus.rs");

/// LinuxCNC's sample configurations, from the peer (scripts/linuxcnc-peer
/// install: $LINUXCNC_PEER_PREFIX, else target/linuxcnc-peer): their
/// directory reaches the tests as `HAL_PEER_SAMPLE_CONFIGS`, and the
/// cfg `hal_no_peer_configs` is set when they are not there, so that
/// the tests that run them are reported as ignored.
fn peer_sample_configs() {
    use std::path::PathBuf;
    println!("cargo::rustc-check-cfg=cfg(hal_no_peer_configs)");
    println!("cargo::rerun-if-env-changed=LINUXCNC_PEER_PREFIX");
    let prefix = std::env::var_os("LINUXCNC_PEER_PREFIX")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let here = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
            here.join("../../target/linuxcnc-peer")
        });
    let dir = prefix.join("usr/share/doc/linuxcnc/examples/sample-configs");
    // Looked at again when the peer is (re)installed; a missing path
    // would rerun this script, and rebuild the crate, on every build.
    if prefix.exists() {
        println!("cargo::rerun-if-changed={}", prefix.display());
    }
    println!("cargo::rustc-env=HAL_PEER_SAMPLE_CONFIGS={}", dir.display());
    if !dir.join("sim").is_dir() {
        println!("cargo::rustc-cfg=hal_no_peer_configs");
    }
}

fn main() {
    golden_corpus(2);
    peer_sample_configs();
}
