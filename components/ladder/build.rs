//! Finds LinuxCNC's sample configurations (from the peer that
//! scripts/linuxcnc-peer installs: $LINUXCNC_PEER_PREFIX, else
//! target/linuxcnc-peer) for tests/samples.rs, which reads their .clp
//! projects: the directory reaches the tests as
//! `HAL_PEER_SAMPLE_CONFIGS`, and cfg `hal_no_peer_configs` is set when
//! it is not there, so those tests are reported as ignored.

include!("../../build-support/peer_configs.rs");

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    peer_sample_configs(2);
}
