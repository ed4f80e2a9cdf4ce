//! Random I2C replies never panic a chip driver and never make it write
//! what it must not (`hal_i2c::fuzzing::random_replies`), 100 000 cases,
//! run here until the workspace's fuzz crate takes the body.

use proptest::prelude::*;

const CASES: u32 = 100_000;

proptest! {
    #![proptest_config(ProptestConfig { cases: CASES, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_replies_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..96)) {
        hal_i2c::fuzzing::random_replies(&bytes);
    }
}
