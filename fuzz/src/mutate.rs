//! The input generator of the stable engine: corpus files changed by a
//! few random edits, the way a mutation fuzzer changes them, from one
//! seed per input.
//!
//! Random bytes rarely get past the first check of a text parser; an
//! edited HAL line reaches its deep paths. Each input starts from a
//! corpus file (sometimes two spliced, sometimes the target's own
//! generator), then gets 1 to 8 edits: bytes set, inserted or deleted,
//! ranges copied, words swapped for dictionary tokens or edge-case
//! numbers. bolero draws the seed; a failure prints it (and the input),
//! and `BOLERO_RANDOM_SEED=<seed>` replays it.

use std::fmt;

use bolero::generator::ValueGenerator;
use bolero::Driver;
use fastrand::Rng;

use crate::Target;

/// Longest input made; longer ones are cut.
pub const MAX_LEN: usize = 8192;

/// Numbers at the edges of what parsers handle: type limits and one
/// past, signs, radix prefixes, float extremes and spellings.
pub const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "-1",
    "+1",
    "2",
    "7",
    "8",
    "16",
    "255",
    "256",
    "2147483647",
    "2147483648",
    "-2147483648",
    "-2147483649",
    "4294967295",
    "4294967296",
    "-4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775808",
    "-9223372036854775809",
    "18446744073709551615",
    "18446744073709551616",
    "340282366920938463463374607431768211456",
    "0x0",
    "0x",
    "0x7fffffff",
    "0x80000000",
    "0xffffffff",
    "0x100000000",
    "0xffffffffffffffff",
    "0X1F",
    "0777",
    "08",
    "09",
    "0.5",
    ".5",
    "5.",
    "-.5e-3",
    "1e308",
    "1e309",
    "-1e309",
    "4.9e-324",
    "1e-400",
    "1e",
    "1e+",
    "nan",
    "NaN",
    "-nan",
    "inf",
    "-inf",
    "infinity",
    "0x1p3",
    "1_000",
    "1,2,3",
    ",,",
    "",
];

/// Characters that separate, quote or substitute in the suite's text
/// formats.
const SYNTAX: &[u8] = b" \t\n\r\"'#$()[]{}=<>\\,.;:_-+*/\0";

/// One generated input; prints as a byte string.
#[derive(Clone, PartialEq, Eq)]
pub struct Input(pub Vec<u8>);

impl fmt::Debug for Input {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "b\"{}\"", self.0.escape_ascii())
    }
}

/// Makes inputs for one target from its corpus and dictionary.
pub struct Mutator {
    corpus: Vec<Vec<u8>>,
    dictionary: &'static [&'static str],
    generate: Option<fn(&mut Rng) -> Vec<u8>>,
}

impl Mutator {
    /// A mutator over `corpus` (the target's stored inputs).
    pub fn new(target: &Target, corpus: Vec<Vec<u8>>) -> Mutator {
        Mutator {
            corpus,
            dictionary: target.dictionary,
            generate: target.generate,
        }
    }

    /// The input for `seed`.
    pub fn make(&self, seed: u64) -> Vec<u8> {
        let mut rng = Rng::with_seed(seed);
        let mut data = self.base(&mut rng);
        let edits = 1usize << rng.u32(0..4);
        for _ in 0..edits {
            self.edit(&mut rng, &mut data);
        }
        data.truncate(MAX_LEN);
        data
    }

    fn pick_corpus(&self, rng: &mut Rng) -> Vec<u8> {
        if self.corpus.is_empty() {
            Vec::new()
        } else {
            self.corpus[rng.usize(..self.corpus.len())].clone()
        }
    }

    /// Where an input starts: a corpus file, two spliced, or the
    /// target's generator.
    fn base(&self, rng: &mut Rng) -> Vec<u8> {
        if let Some(generate) = self.generate {
            if self.corpus.is_empty() || rng.u8(..4) == 0 {
                return generate(rng);
            }
        }
        let mut data = self.pick_corpus(rng);
        if rng.u8(..4) == 0 {
            let other = self.pick_corpus(rng);
            let at = rng.usize(..=data.len());
            data.splice(at..at, other);
        }
        data
    }

    fn token(&self, rng: &mut Rng) -> &'static [u8] {
        if !self.dictionary.is_empty() && rng.bool() {
            self.dictionary[rng.usize(..self.dictionary.len())].as_bytes()
        } else {
            NUMBERS[rng.usize(..NUMBERS.len())].as_bytes()
        }
    }

    /// A random range of `data`, at most `max` long.
    fn range(rng: &mut Rng, data: &[u8], max: usize) -> std::ops::Range<usize> {
        let start = rng.usize(..data.len());
        let len = rng.usize(1..=max.min(data.len() - start));
        start..start + len
    }

    fn edit(&self, rng: &mut Rng, data: &mut Vec<u8>) {
        let at = rng.usize(..=data.len());
        match rng.u8(..10) {
            0 if !data.is_empty() => {
                let i = rng.usize(..data.len());
                data[i] = rng.u8(..);
            }
            1 => data.insert(at, SYNTAX[rng.usize(..SYNTAX.len())]),
            2 => {
                let mut t = self.token(rng).to_vec();
                if rng.bool() {
                    t.insert(0, b' ');
                    t.push(b' ');
                }
                data.splice(at..at, t);
            }
            3 if !data.is_empty() => {
                let r = Self::range(rng, data, 16);
                data.drain(r);
            }
            4 if !data.is_empty() => {
                let r = Self::range(rng, data, 64);
                let copy = data[r].to_vec();
                let at = rng.usize(..=data.len());
                data.splice(at..at, copy);
            }
            5 if !data.is_empty() => {
                // Swap the word around a position for a token.
                let i = rng.usize(..data.len());
                let is_sep = |b: &u8| b.is_ascii_whitespace() || *b == b'=' || *b == b',';
                let start = data[..i].iter().rposition(is_sep).map_or(0, |p| p + 1);
                let end = data[i..]
                    .iter()
                    .position(is_sep)
                    .map_or(data.len(), |p| i + p);
                let t = self.token(rng).to_vec();
                data.splice(start..end, t);
            }
            6 => {
                let other = self.pick_corpus(rng);
                if !other.is_empty() {
                    let r = Self::range(rng, &other, 256);
                    data.splice(at..at, other[r].iter().copied());
                }
            }
            7 if !data.is_empty() => {
                let i = rng.usize(..data.len());
                data[i] ^= 1 << rng.u32(0..8);
            }
            8 => data.truncate(at),
            _ => data.insert(at, rng.u8(0x20..0x7f)),
        }
    }
}

impl ValueGenerator for Mutator {
    type Output = Input;

    fn generate<D: Driver>(&self, driver: &mut D) -> Option<Input> {
        let seed: u64 = driver.produce()?;
        Some(Input(self.make(seed)))
    }
}
