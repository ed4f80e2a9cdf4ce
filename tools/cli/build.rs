//! Decides whether the golden tests (`tests/golden.rs`) can run (see
//! build-support/golden_corpus.rs), and whether LinuxCNC's own sample
//! configurations are there for `tests/linuxcnc_configs.rs`.

include!("../../build-support/golden_corpus.rs");
include!("../../build-support/peer_configs.rs");

fn main() {
    golden_corpus(2);
    peer_sample_configs(2);
}
