//! The layer's parsers of outside bytes under random and mutated input
//! (100 000 cases): the bodies in `hal_driver::fuzzing`, run here
//! until the workspace's fuzz crate takes them.

use hal_driver::fuzzing;
use proptest::prelude::*;

const CASES: u32 = 100_000;

/// Text shaped like the real files, so the parser gets past its first
/// check: `0x`-prefixed hex words, other short words, separators.
fn sysfs_like() -> impl Strategy<Value = Vec<u8>> {
    const HEX: &[u8] = b"0123456789abcdefABCDEF";
    const ODD: &[u8] = b"0x+-[]gz \t\n";
    let word = (
        any::<bool>(),
        prop::collection::vec(prop::sample::select(HEX), 0..18),
        prop::collection::vec(prop::sample::select(ODD), 0..3),
        prop::sample::select(&b" \t\n"[..]),
    );
    prop::collection::vec(word, 0..16).prop_map(|words| {
        let mut out = Vec::new();
        for (prefix, digits, odd, sep) in words {
            if prefix {
                out.extend_from_slice(b"0x");
            }
            out.extend(digits);
            out.extend(odd);
            out.push(sep);
        }
        out
    })
}

fn any_input() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![prop::collection::vec(any::<u8>(), 0..96), sysfs_like()]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: CASES, failure_persistence: None, ..ProptestConfig::default() })]

    /// One input feeds every body, so each sees all 100 000 cases for
    /// the cost of generating them once.
    #[test]
    fn every_parser_of_outside_bytes(bytes in any_input()) {
        fuzzing::resource_file(&bytes);
        fuzzing::id_file(&bytes);
        fuzzing::lockdown_file(&bytes);
        fuzzing::number_token(&bytes);
    }
}
