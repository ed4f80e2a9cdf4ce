//! Decides whether the golden tests (`tests/golden.rs`) can run (see
//! build-support/golden_corpus.rs).

include!("../../build-support/golden_corpus.rs");

fn main() {
    golden_corpus(2);
}
