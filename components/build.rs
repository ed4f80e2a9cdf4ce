//! Decides whether the stepgen model's golden tests can run (see
//! build-support/golden_corpus.rs).

include!("../build-support/golden_corpus.rs");

fn main() {
    golden_corpus(1);
}
