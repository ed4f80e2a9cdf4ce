//! The fuzz target bodies of this crate, run over their seeds and many
//! generated inputs: none may panic.

use hal_ppmc::fuzzing::{board_ids, sim_spec};

/// A small deterministic generator (xorshift), so a failure repeats.
fn inputs(n: usize, seed: u64) -> impl Iterator<Item = Vec<u8>> {
    let mut x = seed;
    (0..n).map(move |i| {
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let len = (next() % 24) as usize + i % 3;
        (0..len).map(|_| next() as u8).collect()
    })
}

#[test]
fn board_ids_never_panic() {
    for seed in [
        &[0x14u8, 0x99, 0x21, 0x32, 0, 0x43, 0x99, 0xFF, 0x54][..],
        &[0x73],
        &[],
        &[0x1F; 16],
    ] {
        board_ids(seed);
    }
    for mut v in inputs(100_000, 0x9E37_79B9_7F4A_7C15) {
        // Mostly plausible IDs: the kind nibble from 0..6.
        for b in v.iter_mut().step_by(2) {
            *b = (*b % 0x70) | (*b & 0x0F);
        }
        board_ids(&v);
    }
}

#[test]
fn sim_specs_never_panic() {
    for seed in [
        "ppmc",
        "upc:2+usc",
        "dac+dac+dac+dac+dac+dac+dac+dac+dac+dac+dac+dac+dac+dac+dac+dac+dac",
        "usc:15",
        ":",
        "+",
    ] {
        sim_spec(seed.as_bytes());
    }
    let words = [
        "ppmc", "usc", "upc", "encoder", "dac", "dio", "+", ":", "2", "4", "x",
    ];
    for v in inputs(20_000, 7) {
        let text: String = v.iter().map(|b| words[*b as usize % words.len()]).collect();
        sim_spec(text.as_bytes());
        sim_spec(&v);
    }
}
