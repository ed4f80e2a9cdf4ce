//! Turning HAL file text into commands: line continuation, comments,
//! quoting and variable substitution, as halcmd does.

use crate::ini::Ini;

/// A lexing error, with the reason; the texts are LinuxCNC's.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LexError {
    /// A `"` without its closing partner.
    #[error("unterminated quoted string")]
    UnterminatedQuote,
    /// `$NAME` or `$(NAME)` of a variable that is not set.
    #[error("Environment variable '{0}' not found.")]
    NoEnv(String),
    /// `[SECTION]KEY` that the INI file does not have.
    #[error("Ini variable '[{0}]{1}' not found.")]
    NoIni(String, String),
    /// `[SECTION]KEY` with no INI file given.
    #[error("Ini variable '[{0}]{1}' not found (no INI file given: use -i).")]
    NoIniFile(String, String),
    /// `$(` or `[SECTION](` without the closing parenthesis.
    #[error("Missing close parenthesis.")]
    Malformed(String),
}

/// A logical line: its number (of its first physical line) and its text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Line {
    /// Number of its first physical line, counting from 1.
    pub number: usize,
    /// Its text, continuation lines joined.
    pub text: String,
}

/// The text of HAL file or INI bytes. halcmd works on bytes, as
/// LinuxCNC's does: bytes that are not UTF-8 (a Latin-1 comment in an old
/// config) become U+FFFD instead of failing the whole file, so a comment
/// stays a comment and a name with such a byte gets the name's error.
pub fn hal_text(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(bytes)
}

/// Reads a HAL file as [`hal_text`]: a regular file of at most
/// [`limits::HAL`](hal_core::files::limits::HAL) bytes, anything else
/// refused with the reason (the caller names the file).
pub fn read_text(path: impl AsRef<std::path::Path>) -> std::io::Result<String> {
    use hal_core::files::{limits, read_user_text};
    Ok(read_user_text(path.as_ref(), limits::HAL, "HAL file")?)
}

/// Joins lines ending in a backslash with the next one.
pub fn logical_lines(text: &str) -> Vec<Line> {
    let mut out = Vec::new();
    let mut pending: Option<Line> = None;
    for (i, raw) in text.lines().enumerate() {
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        let (body, continues) = match raw.strip_suffix('\\') {
            Some(b) => (b, true),
            None => (raw, false),
        };
        let line = match pending.take() {
            Some(mut l) => {
                l.text.push_str(body);
                l
            }
            None => Line {
                number: i + 1,
                text: body.to_string(),
            },
        };
        if continues {
            pending = Some(line);
        } else {
            out.push(line);
        }
    }
    if let Some(l) = pending {
        out.push(l);
    }
    out
}

/// Splits a line into words as halcmd does. First the comment goes (a
/// `#` that starts a word, outside quotes); then `$VAR`, `$(VAR)`,
/// `[SECTION]KEY` and `[SECTION](KEY)` are substituted on the whole line,
/// so a value with spaces becomes several words (`loadrt [KINS]KINEMATICS`
/// with `KINEMATICS = trivkins coordinates=xz` loads trivkins with its
/// parameter); then whitespace separates words except inside `"..."`
/// runs, whose quotes stay in the word (commands that want them gone, like
/// `loadrt`, remove them).
pub fn tokenize(line: &str, ini: Option<&Ini>) -> Result<Vec<String>, LexError> {
    let text = substitute(without_comment(line), ini)?;
    split_words(&text)
}

/// Splits already substituted text at whitespace outside `"..."` runs.
pub fn split_words(text: &str) -> Result<Vec<String>, LexError> {
    let mut words = Vec::new();
    let mut cur = String::new();
    let mut in_word = false;
    let mut quoted = false;
    for c in text.chars() {
        if quoted {
            cur.push(c);
            quoted = c != '"';
        } else if c.is_whitespace() {
            if in_word {
                words.push(std::mem::take(&mut cur));
                in_word = false;
            }
        } else {
            in_word = true;
            quoted = c == '"';
            cur.push(c);
        }
    }
    if quoted {
        return Err(LexError::UnterminatedQuote);
    }
    if in_word {
        words.push(cur);
    }
    Ok(words)
}

/// Replaces every `$VAR`, `$(VAR)`, `[SECTION]KEY` and `[SECTION](KEY)`
/// in `text`. A `$` or `[` that does not start one of these forms stays
/// as written, and so does text inside `"..."` (LinuxCNC substitutes
/// there too; keeping it lets `loadusr sh -c "..."` pass a shell its own
/// `$(...)`).
pub fn substitute(text: &str, ini: Option<&Ini>) -> Result<String, LexError> {
    if !text.contains(['$', '[']) {
        return Ok(text.to_string());
    }
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut quoted = false;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == '"' {
            quoted = !quoted;
        }
        if quoted {
            out.push(c);
            i += 1;
            continue;
        }
        match c {
            '$' => {
                let (value, used) = env_subst(&chars[i..])?;
                out.push_str(&value);
                i += used;
            }
            '[' => match ini_subst(&chars[i..], ini)? {
                Some((value, used)) => {
                    out.push_str(&value);
                    i += used;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            },
            _ => {
                out.push(c);
                i += 1;
            }
        }
    }
    Ok(out)
}

/// The line without its comment, as echo mode prints it.
pub fn without_comment(line: &str) -> &str {
    let mut quoted = false;
    let mut word_start = true;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '#' if !quoted && word_start => return line[..i].trim_end(),
            _ => {}
        }
        word_start = !quoted && c.is_whitespace();
    }
    line.trim_end()
}

/// A word with every `"` removed.
pub fn unquote(word: &str) -> String {
    word.replace('"', "")
}

/// Characters of a variable name after `$` or `[SECTION]` (LinuxCNC's set).
fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-')
}

/// `$VAR` or `$(VAR)` at the start of `s`; returns the value and the
/// number of characters used.
fn env_subst(s: &[char]) -> Result<(String, usize), LexError> {
    let (name, used) = if s.get(1) == Some(&'(') {
        let end = s
            .iter()
            .position(|&c| c == ')')
            .ok_or_else(|| LexError::Malformed(s.iter().collect()))?;
        (s[2..end].iter().collect::<String>(), end + 1)
    } else {
        let n = s[1..].iter().take_while(|&&c| is_name_char(c)).count();
        if n == 0 {
            return Ok(("$".to_string(), 1));
        }
        (s[1..1 + n].iter().collect::<String>(), 1 + n)
    };
    std::env::var(&name)
        .map(|v| (v, used))
        .map_err(|_| LexError::NoEnv(name))
}

/// `[SECTION]KEY` or `[SECTION](KEY)` at the start of `s`, or `None` if
/// the text is not of that form.
fn ini_subst(s: &[char], ini: Option<&Ini>) -> Result<Option<(String, usize)>, LexError> {
    let Some(close) = s.iter().position(|&c| c == ']') else {
        return Ok(None);
    };
    let section: String = s[1..close].iter().collect();
    if !section.chars().all(is_name_char) {
        return Ok(None);
    }
    let rest = &s[close + 1..];
    let (key, used) = if rest.first() == Some(&'(') {
        let Some(end) = rest.iter().position(|&c| c == ')') else {
            return Err(LexError::Malformed(s.iter().collect()));
        };
        (rest[1..end].iter().collect::<String>(), close + 1 + end + 1)
    } else {
        let n = rest.iter().take_while(|&&c| is_name_char(c)).count();
        if n == 0 {
            return Ok(None);
        }
        (rest[..n].iter().collect::<String>(), close + 1 + n)
    };
    let Some(ini) = ini else {
        return Err(LexError::NoIniFile(section, key));
    };
    let found = if section.is_empty() {
        ini.get_in_any(&key)
    } else {
        ini.get(&section, &key)
    };
    match found {
        Some(v) => Ok(Some((v.to_string(), used))),
        None => Err(LexError::NoIni(section, key)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(s: &str) -> Vec<String> {
        tokenize(s, None).unwrap()
    }

    #[test]
    fn splits_quotes_and_comments() {
        assert_eq!(
            words("net  a  b.c => d # comment"),
            ["net", "a", "b.c", "=>", "d"]
        );
        assert_eq!(
            words(r#"print "hello world""#),
            ["print", r#""hello world""#]
        );
        assert_eq!(
            words(r#"loadrt sampler cfg="ff b" depth=3"#),
            ["loadrt", "sampler", r#"cfg="ff b""#, "depth=3"]
        );
        assert_eq!(
            words(r#"print "a \"quoted\" word""#),
            ["print", r#""a \"quoted\" word""#]
        );
        assert_eq!(words("   # only a comment"), Vec::<String>::new());
        assert_eq!(words("setp a#b 1"), ["setp", "a#b", "1"]);
        assert_eq!(
            tokenize("print \"open", None),
            Err(LexError::UnterminatedQuote)
        );
        assert_eq!(without_comment("setp a 1 # c"), "setp a 1");
        assert_eq!(without_comment("# only"), "");
        assert_eq!(
            without_comment(r##"print "# not" # yes"##),
            r##"print "# not""##
        );
        assert_eq!(unquote(r#"cfg="ff""#), "cfg=ff");
    }

    #[test]
    fn continuation_keeps_the_first_line_number() {
        let lines = logical_lines("a \\\nb \\\nc\nd\n");
        assert_eq!(
            lines,
            [
                Line {
                    number: 1,
                    text: "a b c".into()
                },
                Line {
                    number: 4,
                    text: "d".into()
                }
            ]
        );
    }

    #[test]
    fn substitutes_environment_and_ini() {
        std::env::set_var("HALCMD_LEXER_TEST", "xyz");
        assert_eq!(
            words("a $HALCMD_LEXER_TEST $(HALCMD_LEXER_TEST).b"),
            ["a", "xyz", "xyz.b"]
        );
        assert!(matches!(
            tokenize("$NO_SUCH_VAR_HALCMD", None),
            Err(LexError::NoEnv(_))
        ));
        let ini = Ini::parse("[AXIS_X]\nMAX_VEL = 12.5\n[EMC]\nNAME=m\n");
        assert_eq!(
            tokenize("setp x [AXIS_X]MAX_VEL", Some(&ini)).unwrap(),
            ["setp", "x", "12.5"]
        );
        assert_eq!(
            tokenize("a [EMC](NAME).b", Some(&ini)).unwrap(),
            ["a", "m.b"]
        );
        assert!(matches!(
            tokenize("a [EMC]NOPE", Some(&ini)),
            Err(LexError::NoIni(..))
        ));
        assert!(matches!(
            tokenize("a [EMC]NAME", None),
            Err(LexError::NoIniFile(..))
        ));
        // Not a substitution: left alone.
        assert_eq!(words("a [ b"), ["a", "[", "b"]);
    }

    #[test]
    fn substitution_happens_on_the_whole_line_before_splitting() {
        let ini = Ini::parse(
            "[KINS]\nKINEMATICS = trivkins coordinates=xz kinstype=both\n\
             [EMCMOT]\nEMCMOT = motmod\nSERVO_PERIOD = 1000000\n[P]\nQ = \"a b\"\n",
        );
        assert_eq!(
            tokenize("loadrt [KINS]KINEMATICS # kins", Some(&ini)).unwrap(),
            ["loadrt", "trivkins", "coordinates=xz", "kinstype=both"]
        );
        assert_eq!(
            tokenize(
                "loadrt [EMCMOT]EMCMOT servo_period_nsec=[EMCMOT]SERVO_PERIOD num_joints=2",
                Some(&ini)
            )
            .unwrap(),
            [
                "loadrt",
                "motmod",
                "servo_period_nsec=1000000",
                "num_joints=2"
            ]
        );
        // A quoted value stays one word; a key ends where name characters do.
        assert_eq!(
            tokenize("print [P]Q,[]EMCMOT", Some(&ini)).unwrap(),
            ["print", "\"a b\",motmod"]
        );
        // Quoted text is left alone.
        assert_eq!(
            tokenize("loadusr sh -c \"x $(y) [P]Q\"", Some(&ini)).unwrap(),
            ["loadusr", "sh", "-c", "\"x $(y) [P]Q\""]
        );
        std::env::set_var("HALCMD_LEXER_SPACES", "x y");
        assert_eq!(words("a $HALCMD_LEXER_SPACES"), ["a", "x", "y"]);
        assert_eq!(
            LexError::NoIni("A".into(), "B".into()).to_string(),
            "Ini variable '[A]B' not found."
        );
    }
}
