//! scope_rt's shared region as halscope reads it
//! ([`hal_components::infra::scope_rt::layout`]): words from the input,
//! read as they are, and with the identity words made right so parsing
//! gets past them (the first byte picks which; its high bits set the
//! buffer's length). The reader refuses with a reason or gives a status
//! whose record it then reads: exactly `samples` rows of one word per
//! channel, found inside the buffer.

use hal_components::infra::scope_rt::layout::{self, w, State, Status, HEADER_WORDS};

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "scope_rt_region",
    run,
    // Whole words: zero, small integers (states, channel counts, type
    // codes), the magic number.
    dictionary: &[
        "\0\0\0\0\0\0\0\0",
        "\x01\0\0\0\0\0\0\0",
        "\x02\0\0\0\0\0\0\0",
        "\x05\0\0\0\0\0\0\0",
        "\x10\0\0\0\0\0\0\0",
        "HALSCOPE",
        "\x40\0\0\0\0\0\0\0",
    ],
    generate: Some(crate::random_bytes),
};

/// The words of `data` (little-endian, the last one zero-padded).
fn words(data: &[u8]) -> Vec<u64> {
    data.chunks(8)
        .map(|chunk| {
            let mut b = [0u8; 8];
            b[..chunk.len()].copy_from_slice(chunk);
            u64::from_le_bytes(b)
        })
        .collect()
}

fn run(data: &[u8]) {
    let Some((&pick, rest)) = data.split_first() else {
        return;
    };
    let mut region = words(rest);
    if pick & 1 == 1 {
        // Identity made right; the record's words as the input has them.
        if region.len() < HEADER_WORDS + 1 {
            region.resize(HEADER_WORDS + 1, 0);
        }
        let room = (region.len() - HEADER_WORDS) as u64;
        region[w::MAGIC] = layout::MAGIC;
        region[w::VERSION] = layout::VERSION;
        region[w::HEADER] = HEADER_WORDS as u64;
        region[w::BUF_LEN] = (u64::from(pick >> 1) % room) + 1;
        if pick & 2 == 2 {
            region[w::STATE] = State::Done as u64;
        }
    }
    let Ok(st) = Status::parse(&region) else {
        return;
    };
    assert!(st.buf_len + HEADER_WORDS <= region.len(), "{st:?}");
    if st.state != State::Done {
        return;
    }
    let rows = layout::record(&region, &st)
        .unwrap_or_else(|e| panic!("a parsed Done status whose record is refused: {e}; {st:?}"));
    assert_eq!(rows.len(), st.samples, "{st:?}");
    assert!(st.trig_pos < st.samples, "{st:?}");
    assert!(rows.iter().all(|r| r.len() == st.types.len()), "{st:?}");
}
