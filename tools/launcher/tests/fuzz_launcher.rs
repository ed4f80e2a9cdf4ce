//! The parsers of the launcher's input files never panic, whatever the
//! bytes: INI files (with #INCLUDE), tool tables, TWOPASS's loadrt
//! gathering, the update of old-format configurations. Their bodies are the `fuzz_*` functions of the crate, for
//! the fuzz/ targets; here 10^5 cases each on stable, built from the
//! tokens that matter to each parser.

use hal_lang::ini::fuzz_parse as ini_fuzz;
use hal_launcher::fuzz::old_format_config as old_format_fuzz;
use hal_launcher::fuzz::tool_table as tooltable_fuzz;
use hal_launcher::fuzz::twopass_loadrt as fuzz_gather;
use proptest::prelude::*;

const CASES: u32 = 100_000;

/// Texts made of up to `n` tokens.
fn texts(tokens: &'static [&'static str], n: usize) -> impl Strategy<Value = String> {
    proptest::collection::vec(proptest::sample::select(tokens), 0..n).prop_map(|v| v.concat())
}

const INI: &[&str] = &[
    "[",
    "]",
    "[HAL]",
    "[A_1]",
    "=",
    " = ",
    "#",
    ";",
    "\\",
    "\\\n",
    "\n",
    " ",
    "\t",
    "KEY",
    "x",
    "0",
    "#INCLUDE ",
    "#INCLUDE a.inc\n",
    "#INCLUDE b\n",
    "\\x",
    "\\x4",
    "\\x41",
    "\\x00",
    "\\u",
    "\\ud83d",
    "\\ude00",
    "\\u0041",
    "\\U0001f600",
    "\\U0011ffff",
    "\\0",
    "\\377",
    "\\12",
    "\\t",
    "\\q",
    "é",
    "\r",
];

const TABLE: &[&str] = &[
    "T",
    "P",
    "D",
    "X",
    "Y",
    "Z",
    "A",
    "W",
    "I",
    "J",
    "Q",
    "K",
    "t",
    "p",
    "1",
    "0",
    "-",
    "+",
    ".",
    "e",
    "999",
    "1000",
    "2147483648",
    "-1",
    "1e999",
    "nan",
    "inf",
    ";",
    "comment",
    " ",
    "\t",
    "\n",
    "\r",
];

const TWOPASS: &[&str] = &[
    "loadrt ",
    "and2",
    "pid",
    " ",
    "count=",
    "num_chan=",
    "names=",
    "personality=",
    "debug=",
    "cfg=",
    "1",
    "-3",
    "x",
    ",",
    "=",
    "a",
    "9223372036854775807",
    "\n",
    "0x10",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: CASES, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn ini_files_never_panic(text in texts(INI, 40)) {
        ini_fuzz(text.as_bytes());
    }

    #[test]
    fn tool_tables_never_panic(text in texts(TABLE, 40)) {
        tooltable_fuzz(text.as_bytes());
    }

    #[test]
    fn twopass_gathering_never_panics(text in texts(TWOPASS, 30)) {
        fuzz_gather(text.as_bytes());
    }
}

/// Pieces of old-format INI and HAL files (one text serves as both).
const OLD_FORMAT: &[&str] = &[
    "[EMC]\nVERSION = $Revision$\n",
    "[EMC]\nVERSION = 1.0\n",
    "[TRAJ]\n",
    "COORDINATES = ",
    "AXES = ",
    "[AXIS_0]\n",
    "[AXIS_2]\n",
    "[JOINT_1]\n",
    "[KINS]\nJOINTS = 2\n",
    "HOME_SEQUENCE = ",
    "LOCKING_INDEXER = 1\n",
    "[RS274NGC]\nFEATURES = ",
    "MAX_VELOCITY = 5\n",
    "loadrt trivkins coordinates=",
    "loadrt gantrykins\n",
    "setp gantrykins.joint-",
    "setp axis.0.jog-scale 1\n",
    "net s axis.2.joint-pos-fb ",
    "halui.jog.1.plus ",
    "halui.joint.2.home ",
    "motion.spindle-on ",
    "[AXIS_2]SCALE",
    "num_joints=[TRAJ]AXES",
    "servo_period_nsec=1 ",
    "XYZ",
    "X Y Y Z",
    "\\\n",
    "#",
    "\n",
    " ",
    "0",
    "9",
    "-1",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 5_000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn old_format_updates_never_panic(text in texts(OLD_FORMAT, 40)) {
        old_format_fuzz(text.as_bytes());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 20_000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        ini_fuzz(&bytes);
        tooltable_fuzz(&bytes);
        fuzz_gather(&bytes);
        old_format_fuzz(&bytes);
    }
}
