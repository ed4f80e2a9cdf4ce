//! Fuzz targets for every parser of outside bytes in the suite.
//!
//! A target is a function from bytes to nothing that panics when it finds
//! a bug: a panic in the code under test, or a broken invariant the
//! target checks (a failed `loadrt` that left something loaded, a token
//! list that does not survive a round trip). Each target lives in a
//! module of its own under [`targets`] and is registered there with one
//! line; see the crate's README for how to add one.
//!
//! The same target runs under two engines through bolero:
//!
//! * `cargo test --release -p hal-fuzz` (stable Rust): every stored
//!   corpus file, then [`CASES`] inputs made by [`mutate::Mutator`] from
//!   the corpus (or by the target's own generator), each from a random
//!   seed that a failure prints.
//! * `cargo bolero test` (libFuzzer, coverage-guided; a nightly compiler
//!   or `--rustc-bootstrap`): raw bytes, starting from the same corpus.

#![forbid(unsafe_code)]

pub mod corpus;
pub mod mutate;
pub mod registry;
pub mod snapshot;
pub mod targets;

/// How many generated inputs `cargo test` runs per target, after the
/// stored corpus: 100000 in an optimised build (`cargo test --release`,
/// as CI runs it), 1000 as a smoke run in a debug build, where the
/// dispatcher target is about five times slower.
/// `BOLERO_RANDOM_ITERATIONS` overrides it.
pub const CASES: usize = if cfg!(debug_assertions) {
    1_000
} else {
    100_000
};

/// 0 to 256 random bytes: the generator of the targets whose input is
/// binary (register images, bus replies), which the mutator's text edits
/// and an empty corpus would keep short.
pub fn random_bytes(rng: &mut fastrand::Rng) -> Vec<u8> {
    let len = rng.usize(..=256);
    std::iter::repeat_with(|| rng.u8(..)).take(len).collect()
}

/// A seed from `seeds` with one to eight random bytes written over it,
/// or (one time in eight, or with no seeds) [`random_bytes`]: the
/// generator of binary targets whose crate provides seed inputs.
pub fn edited_seed(rng: &mut fastrand::Rng, seeds: &[Vec<u8>]) -> Vec<u8> {
    if seeds.is_empty() || rng.u8(..8) == 0 {
        return random_bytes(rng);
    }
    let mut s = seeds[rng.usize(..seeds.len())].clone();
    if !s.is_empty() {
        for _ in 0..rng.usize(1..=8) {
            let at = rng.usize(..s.len());
            s[at] = rng.u8(..);
        }
    }
    s
}

/// One fuzz target.
pub struct Target {
    /// The target's name: its module, its test and its corpus directory
    /// (`fuzz/corpus/<name>/`).
    pub name: &'static str,
    /// Runs one input; panics on a finding.
    pub run: fn(&[u8]),
    /// Byte strings that mean something to the parser (keywords,
    /// operators, edge-case numbers); the mutator splices them in.
    pub dictionary: &'static [&'static str],
    /// Builds an input from scratch for the stable engine, next to the
    /// mutated corpus files, where well-formed inputs need knowledge the
    /// corpus cannot carry (the parameter tables of every module).
    pub generate: Option<fn(&mut fastrand::Rng) -> Vec<u8>>,
}

/// Declares the target modules of [`targets`]: each gets `pub mod`, an
/// entry in [`targets::ALL`] and a test that runs it (under libFuzzer
/// when built by cargo-bolero, else the corpus plus [`CASES`] mutations).
#[macro_export]
macro_rules! register_targets {
    ($($name:ident),* $(,)?) => {
        $(pub mod $name;)*

        /// Every target, in registration order.
        pub const ALL: &[&$crate::Target] = &[$(&$name::TARGET),*];

        #[cfg(test)]
        mod tests {
            $(
                #[test]
                fn $name() {
                    let target: &'static $crate::Target = &super::$name::TARGET;
                    #[cfg(fuzzing)]
                    bolero::check!().for_each(|input: &[u8]| (target.run)(input));
                    #[cfg(not(fuzzing))]
                    {
                        let corpus = $crate::corpus::replay(target);
                        bolero::check!()
                            .with_generator($crate::mutate::Mutator::new(target, corpus))
                            .with_iterations($crate::CASES)
                            .for_each(|input: &$crate::mutate::Input| (target.run)(&input.0));
                    }
                }
            )*
        }
    };
}

/// The host configuration of a target's instance, with a segment of
/// `shm_size` bytes. The targets use LinuxCNC's 2 MiB: a fuzzed `count=`
/// in the thousands then runs out of memory (and is rolled back) in
/// milliseconds, where a larger segment would let it build thousands of
/// pins into sorted lists first. Under `cargo test`, a
/// name no other test uses (removed when the test ends). Under libFuzzer,
/// which ends the process without running destructors, a fixed name per
/// target, so the next run reclaims the segment the last one left.
pub fn host_config(tag: &str, shm_size: u64) -> hal_core::HostConfig {
    let mut config = hal_core::HostConfig::for_tests(tag);
    if cfg!(fuzzing) {
        config.instance = format!("fuzz-{tag}");
    }
    config.shm_size = shm_size;
    config
}
