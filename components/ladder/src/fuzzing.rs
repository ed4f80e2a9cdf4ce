//! The fuzz-target body for the `.clp` parser (`hal-fuzz`'s
//! `classicladder_clp`): any bytes are parsed, checked against two
//! module sizes, and what passes is encoded, decoded as the realtime side
//! does, and scanned; nothing may panic, and a decoded program must be
//! the one encoded.

use std::sync::atomic::AtomicU64;

use crate::model::{Program, Sizes};
use crate::runtime::Engine;
use crate::{clp, compile, handoff};

/// The target body.
pub fn clp_bundle(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(project) = clp::parse(&text) else {
        return;
    };
    let small = Sizes {
        rungs: 8,
        bits: 8,
        words: 4,
        timers: 2,
        monostables: 2,
        counters: 2,
        timers_iec: 2,
        inputs: 4,
        outputs: 4,
        exprs: 4,
        sections: 2,
        symbols: 8,
        s32_in: 2,
        s32_out: 2,
        float_in: 2,
        float_out: 2,
        error_bits: 2,
    };
    for sizes in [small, Sizes::default()] {
        let Ok(c) = compile::compile(&project, &sizes) else {
            continue;
        };
        let words: Vec<AtomicU64> = (0..handoff::region_words(&sizes))
            .map(|_| AtomicU64::new(0))
            .collect();
        handoff::init(&words, &sizes);
        let body = handoff::encode(&c.program, &sizes);
        assert!(
            handoff::publish(&words, &body).is_some(),
            "the region holds the program"
        );
        let mut back = Program::empty(&sizes);
        let decoded = handoff::decode(&words, &sizes, &mut back);
        assert!(decoded.is_ok(), "a checked program decodes: {decoded:?}");
        assert!(back == c.program, "the decoded program is the one encoded");
        let mut e = Engine::new(&sizes);
        e.install(&back);
        for dt in [1, 1000, 60_000] {
            e.scan(&back, dt);
        }
    }
}

#[cfg(test)]
mod tests {
    const TIMERS: &str = "_FILES_CLASSICLADDER\n_FILE-rung_0.csv\n#VER=2.0\n#NEXTRUNG=-1\n\
        1-0-50/0 , 9-0-0/0 , 99-0-0/0 , 13-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 50-0-60/0\n\
        0-0-0/0 , 0-0-0/0 , 99-0-0/0 , 99-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0 , 0-0-0/0\n\
        3-0-50/1 , 9-0-0/0 , 99-0-0/0 , 11-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 52-0-0/0\n\
        _/FILE-rung_0.csv\n_FILE-timers_iec.csv\n1,2,0\n_/FILE-timers_iec.csv\n\
        _FILE-sections.csv\n000,0,-1,0,0,0\n_/FILE-sections.csv\n_/FILES_CLASSICLADDER\n";

    #[test]
    fn a_good_project_goes_the_whole_way() {
        let p = crate::clp::parse(TIMERS).unwrap();
        crate::compile::compile(&p, &crate::model::Sizes::default()).unwrap();
        super::clp_bundle(TIMERS.as_bytes());
        super::clp_bundle(b"_FILES_CLASSICLADDER\n_FILE-rung_0.csv\n");
    }

    /// Found by the fuzzer in CI: a sub-routine number past numSections
    /// compiled, then came back from the hand-off cut to 24 bits.
    #[test]
    fn a_sub_routine_number_past_num_sections_is_refused() {
        let text = TIMERS.replace("000,0,-1,0,0,0", "000,0,2147483647,0,0,0");
        let p = crate::clp::parse(&text).unwrap();
        let err = crate::compile::compile(&p, &crate::model::Sizes::default())
            .expect_err("refused")
            .to_string();
        assert!(err.contains("sub-routine number 2147483647"), "{err}");
        super::clp_bundle(text.as_bytes());
    }
}
