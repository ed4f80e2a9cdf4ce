//! The halcmd parser and executor never panic, whatever the input.

mod common;

use common::InProcessHost;
use hal_core::HalType;
use hal_tools::halcmd::lexer::{logical_lines, tokenize};
use hal_tools::halcmd::values::parse_value;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn lexer_never_panics(text in "\\PC{0,200}") {
        for line in logical_lines(&text) {
            let _ = tokenize(&line.text, None);
        }
    }

    #[test]
    fn lexer_never_panics_on_syntax_characters(text in "[ \\t\"#$()\\[\\]=<>\\\\a-z0-9.\n]{0,120}") {
        for line in logical_lines(&text) {
            let _ = tokenize(&line.text, None);
        }
    }

    #[test]
    fn value_parser_never_panics(text in "\\PC{0,40}", t in 0usize..6) {
        let _ = parse_value(HalType::ALL[t], &text);
    }
}

/// Command words and arguments the sessions are built from. `save` and
/// `source` are left out: with a random second word they read or write
/// files in the working directory.
const WORDS: &[&str] = &[
    "loadrt",
    "unloadrt",
    "net",
    "newsig",
    "delsig",
    "sets",
    "gets",
    "setp",
    "getp",
    "ptype",
    "stype",
    "linkps",
    "linksp",
    "unlinkp",
    "addf",
    "delf",
    "show",
    "list",
    "alias",
    "unalias",
    "echo",
    "unecho",
    "print",
    "status",
    "help",
    "=",
    "=>",
    "<=",
    "<=>",
    "and2",
    "and2.0",
    "and2.0.in0",
    "and2.0.out",
    "mult2",
    "mult2.0.in0",
    "t",
    "bit",
    "float",
    "s32",
    "u64",
    "all",
    "pin",
    "sig",
    "param",
    "count=2",
    "names=a,b",
    "1",
    "-1",
    "0x10",
    "1e300",
    "TRUE",
    "\"q w\"",
    "x",
    "y",
    "threads",
    "name1=t",
    "period1=1000000",
    "conv_s32_u32",
    "comp",
    "funct",
    "thread",
    "-1",
    "2",
    "*",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn sessions_never_panic_and_leave_a_consistent_instance(
        lines in prop::collection::vec(prop::collection::vec(prop::sample::select(WORDS), 0..6), 1..12)
    ) {
        thread_local! {
            static HOST: InProcessHost = InProcessHost::start("fuzz");
        }
        HOST.with(|host| {
            let text: String = lines.iter().map(|l| l.join(" ") + "\n").collect();
            let _ = host.run("fuzz.hal", &text, true);
            let inst = host.instance();
            prop_assert!(inst.pins().is_ok());
            prop_assert!(inst.signals().is_ok());
            prop_assert!(inst.params().is_ok());
            prop_assert!(inst.threads().is_ok());
            // Clean up for the next case.
            let _ = host.run("reset.hal", "unloadrt all\ndelsig all\n", true);
            Ok(())
        })?;
    }
}
