//! ClassicLadder `.clp` project bundles, parsed, checked, handed over
//! and scanned ([`hal_ladder::fuzzing::clp_bundle`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "classicladder_clp",
    run: hal_ladder::fuzzing::clp_bundle,
    dictionary: &[
        "_FILES_CLASSICLADDER\n",
        "_/FILES_CLASSICLADDER\n",
        "_FILE-rung_0.csv\n",
        "_/FILE-rung_0.csv\n",
        "_FILE-sections.csv\n",
        "_/FILE-sections.csv\n",
        "_FILE-arithmetic_expressions.csv\n",
        "_/FILE-arithmetic_expressions.csv\n",
        "_FILE-timers_iec.csv\n",
        "_/FILE-timers_iec.csv\n",
        "#VER=2.0\n",
        "#NEXTRUNG=",
        "000,0,-1,0,0,0\n",
        " , ",
        "1-0-50/0",
        "9-0-0/0",
        "50-0-60/0",
        "99-0-0/0",
        "10-0-0/0",
        "12-0-0/0",
        "13-0-0/0",
        "20-0-0/0",
        "60-0-0/0",
        "54-0-0/0",
        "55-0-0/0",
        "-1-",
        "@200/0@",
        "@270/0@",
        ":=",
        "<>",
        "MINI(",
        "%TM0.Q",
        "$FF",
    ],
    generate: None,
};
