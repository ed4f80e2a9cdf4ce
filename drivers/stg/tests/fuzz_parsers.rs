//! This crate's parsers of outside bytes under random input (100 000
//! cases): the bodies in `hal_stg::fuzzing`, run here until the
//! workspace's fuzz crate takes them.

use hal_stg::fuzzing;
use proptest::prelude::*;

/// Up to 16 bytes: mostly the ones that matter (I/O letters,
/// signature-shaped bytes), sometimes anything. Made from two words, a
/// length and a shape, which proptest generates far faster than vectors.
fn input() -> impl Strategy<Value = Vec<u8>> {
    (any::<u64>(), any::<u64>(), 0usize..17, 0u8..3).prop_map(|(a, b, len, shape)| {
        let raw: Vec<u8> = a.to_le_bytes().into_iter().chain(b.to_le_bytes()).collect();
        raw[..len]
            .iter()
            .map(|&r| match shape {
                0 => b"IiOoX-\xc3\xa9"[r as usize % 8],
                1 => (r & 0xF0) | ((r >> 1) & 0x07) | 0x08 & r,
                _ => r,
            })
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 100_000, failure_persistence: None, ..ProptestConfig::default() })]

    /// One input feeds every body.
    #[test]
    fn every_parser_of_outside_bytes(bytes in input()) {
        fuzzing::dio_param(&bytes);
        fuzzing::board_test_register(&bytes);
    }
}
