// Included by the build scripts of the crates whose tests run LinuxCNC's
// own sample configurations or read their files.

/// LinuxCNC's sample configurations, from the peer (scripts/linuxcnc-peer
/// install: $LINUXCNC_PEER_PREFIX, else target/linuxcnc-peer): their
/// directory reaches the tests as `HAL_PEER_SAMPLE_CONFIGS`, and the
/// cfg `hal_no_peer_configs` is set when they are not there, so that
/// the tests that run them are reported as ignored. The crate being
/// built is `depth` directories below the workspace root.
fn peer_sample_configs(depth: usize) {
    use std::path::PathBuf;
    println!("cargo::rustc-check-cfg=cfg(hal_no_peer_configs)");
    println!("cargo::rerun-if-env-changed=LINUXCNC_PEER_PREFIX");
    let prefix = std::env::var_os("LINUXCNC_PEER_PREFIX")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let here = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
            let mut root = here;
            for _ in 0..depth {
                root.pop();
            }
            root.join("target/linuxcnc-peer")
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
