//! HAL file text through halcmd's lexer: bytes to text, continuation
//! lines, words, quotes, comments, `$VAR` and `[SECTION]KEY`
//! substitution, and every word through the value parser of each HAL
//! type (what `setp` and `sets` do with it).
//!
//! Checked besides "no panic": logical lines are numbered in increasing
//! order within the file; the echo form of a line is a prefix of it; a
//! parsed value has the type asked for; and on a line without
//! substitutions, a word is never empty and has whitespace only inside
//! quotes, and the words joined by single spaces split into the same
//! words again.

use hal_core::HalType;
use hal_lang::ini::Ini;
use hal_lang::lexer::{hal_text, logical_lines, tokenize, without_comment};
use hal_lang::parse_value;

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "halcmd_lexer",
    run,
    dictionary: &[
        "\\\n",
        "\"",
        "#",
        "$",
        "$(",
        "$HOME",
        "$(HOME)",
        "$(NO_SUCH_VAR_HAL_FUZZ)",
        "[EMCMOT]SERVO_PERIOD",
        "[AXIS_X](MAX_VELOCITY)",
        "[AXIS_X]",
        "[NOPE]KEY",
        "[]X",
        "=>",
        "<=",
        "<=>",
        "loadrt",
        "net",
        "setp",
        "sets",
        "TRUE",
        "FALSE",
    ],
    generate: None,
};

/// The INI file `[SECTION]KEY` substitutions are resolved against.
const INI_TEXT: &str = "\
[EMCMOT]
SERVO_PERIOD = 1000000
BASE_PERIOD = 25000
[AXIS_X]
MAX_VELOCITY = 10.5
SCALE = \"-2000 steps\"
[HAL]
HALFILE = core.hal
EMPTY =
";

fn run(input: &[u8]) {
    let text = hal_text(input);
    let ini = Ini::parse(&text);
    let _ = ini.get("EMCMOT", "SERVO_PERIOD");
    let ini = Ini::parse(INI_TEXT);
    let physical = text.lines().count();
    let mut last = 0;
    for line in logical_lines(&text) {
        assert!(
            line.number > last && line.number <= physical.max(1),
            "line {} after line {last} of {physical}",
            line.number
        );
        last = line.number;
        let echoed = without_comment(&line.text);
        assert!(line.text.starts_with(echoed), "echo {echoed:?} of {line:?}");
        for ini in [None, Some(&ini)] {
            let Ok(words) = tokenize(&line.text, ini) else {
                continue;
            };
            // A substituted value is pasted into its word whole, spaces
            // and all, so word shapes are checked without substitutions.
            let substitutes = line.text.contains(['$', '[']);
            for w in &words {
                if !substitutes {
                    check_word(w, &line.text);
                }
                for t in HalType::ALL {
                    if let Ok(v) = parse_value(t, w) {
                        assert_eq!(v.hal_type(), t, "{w:?} parsed as {v:?}");
                    }
                }
            }
            if !substitutes {
                let again = tokenize(&words.join(" "), ini).expect("rejoined words tokenize");
                assert_eq!(again, words, "words of {:?} do not survive a rejoin", line.text);
            }
        }
    }
}

/// A word is not empty and has whitespace only between quotes.
fn check_word(word: &str, line: &str) {
    assert!(!word.is_empty(), "empty word from {line:?}");
    let mut quoted = false;
    for c in word.chars() {
        if c == '"' {
            quoted = !quoted;
        }
        assert!(
            quoted || !c.is_whitespace(),
            "word {word:?} from {line:?} has whitespace outside quotes"
        );
    }
}
