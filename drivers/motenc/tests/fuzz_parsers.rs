//! This crate's parsers of outside bytes under random input (100 000
//! cases): the bodies in `hal_motenc::fuzzing`, run here until the
//! workspace's fuzz crate takes them.

use hal_motenc::fuzzing;
use proptest::prelude::*;

/// Up to 16 bytes: register words that look like a board's (versions 0,
/// 1 and all ones, small status words), board kind names, or anything.
/// Made from two words, a length and a shape, which proptest generates
/// far faster than vectors.
fn input() -> impl Strategy<Value = Vec<u8>> {
    (any::<u64>(), any::<u64>(), 0usize..17, 0u8..3).prop_map(|(a, b, len, shape)| {
        let mut raw: Vec<u8> = a.to_le_bytes().into_iter().chain(b.to_le_bytes()).collect();
        match shape {
            0 => {
                let version: u32 = [0, 1, u32::MAX, a as u32 & 3][(a >> 40) as usize % 4];
                raw[..4].copy_from_slice(&version.to_le_bytes());
            }
            1 => {
                let names: [&[u8]; 4] = [b"100", b"LITE", b"motenc-100", b"lite "];
                let name = names[(b % 4) as usize];
                raw[..name.len()].copy_from_slice(name);
                return raw[..name.len().max(len.min(name.len()))].to_vec();
            }
            _ => {}
        }
        raw[..len].to_vec()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 100_000, failure_persistence: None, ..ProptestConfig::default() })]

    /// One input feeds every body.
    #[test]
    fn every_parser_of_outside_bytes(bytes in input()) {
        fuzzing::registers(&bytes);
        fuzzing::board_kind_item(&bytes);
    }
}
