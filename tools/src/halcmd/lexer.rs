//! Turning HAL file text into commands: line continuation, comments,
//! quoting and variable substitution, as halcmd does.

use super::ini::Ini;

/// A lexing error, with the reason.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LexError {
    /// A `"` opens a string that the line never closes.
    #[error("unterminated quoted string")]
    UnterminatedQuote,
    /// `$VAR` or `$(VAR)` names a variable the environment lacks.
    #[error("environment variable '{0}' not found")]
    NoEnv(String),
    /// `[SECTION]KEY` names a key the INI file lacks (section, key).
    #[error("INI variable [{0}]{1} not found")]
    NoIni(String, String),
    /// `[SECTION]KEY` appears but halcmd was given no `-i` INI file (section, key).
    #[error("INI substitution [{0}]{1} used without an INI file (-i)")]
    NoIniFile(String, String),
    /// A `$(NAME` or `[SECTION](KEY` without its closing parenthesis.
    #[error("malformed substitution '{0}'")]
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

/// Splits a line into words as halcmd does: whitespace separates words
/// except inside `"..."` runs; the quotes stay in the word (commands that
/// want them gone, like `loadrt`, remove them); `#` at the start of a word
/// begins a comment. `$VAR`, `$(VAR)`, `[SECTION]KEY` and
/// `[SECTION](KEY)` are substituted outside quotes.
pub fn tokenize(line: &str, ini: Option<&Ini>) -> Result<Vec<String>, LexError> {
    let mut words = Vec::new();
    let mut cur = String::new();
    let mut in_word = false;
    let mut quoted = false;
    let chars: Vec<char> = line.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if quoted {
            cur.push(c);
            quoted = c != '"';
            i += 1;
            continue;
        }
        if c.is_whitespace() {
            if in_word {
                words.push(std::mem::take(&mut cur));
                in_word = false;
            }
            i += 1;
            continue;
        }
        if c == '#' && !in_word {
            break;
        }
        in_word = true;
        match c {
            '"' => {
                quoted = true;
                cur.push(c);
                i += 1;
            }
            '$' => {
                let (value, used) = env_subst(&chars[i..])?;
                cur.push_str(&value);
                i += used;
            }
            '[' => match ini_subst(&chars[i..], ini)? {
                Some((value, used)) => {
                    cur.push_str(&value);
                    i += used;
                }
                None => {
                    cur.push(c);
                    i += 1;
                }
            },
            _ => {
                cur.push(c);
                i += 1;
            }
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

fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
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
    if section.is_empty()
        || !section
            .chars()
            .all(|c| is_name_char(c) || c == '-' || c == '.')
    {
        return Ok(None);
    }
    let rest = &s[close + 1..];
    let (key, used) = if rest.first() == Some(&'(') {
        let Some(end) = rest.iter().position(|&c| c == ')') else {
            return Err(LexError::Malformed(s.iter().collect()));
        };
        (rest[1..end].iter().collect::<String>(), close + 1 + end + 1)
    } else {
        let n = rest
            .iter()
            .take_while(|&&c| !c.is_whitespace() && c != '"')
            .count();
        if n == 0 {
            return Ok(None);
        }
        (rest[..n].iter().collect::<String>(), close + 1 + n)
    };
    let Some(ini) = ini else {
        return Err(LexError::NoIniFile(section, key));
    };
    match ini.get(&section, &key) {
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
}
