//! The INI dialect of `_panelui.ini`, as LinuxCNC reads it (ConfigObj):
//! sections nest by the number of brackets (`[TOP]`, `[[group]]`,
//! `[[[button]]]`), a value with an unquoted comma is a list
//! (`TRUE_COMMAND = continuous_jog, 0, 1`), quotes keep commas and `#`,
//! an unquoted `#` starts a comment, and a key or a section may appear
//! only once where it is. Every refusal names the line.

use std::fmt;

/// The most lines a panel file may have: far more than any panel needs.
const MAX_LINES: usize = 100_000;

/// A value: one word, or a list (a value with an unquoted comma).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Value {
    /// A value without an unquoted comma.
    One(String),
    /// The items of a value with unquoted commas, each trimmed.
    List(Vec<String>),
}

impl Value {
    /// The items: one for [`Value::One`].
    pub fn items(&self) -> Vec<&str> {
        match self {
            Value::One(s) => vec![s.as_str()],
            Value::List(v) => v.iter().map(String::as_str).collect(),
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::One(s) => f.write_str(s),
            Value::List(v) => f.write_str(&v.join(", ")),
        }
    }
}

/// `KEY = value` with its line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entry {
    /// The key as written.
    pub key: String,
    /// The value.
    pub value: Value,
    /// The line (1-based).
    pub line: usize,
}

/// A section: its entries and the sections nested in it, in file order.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Section {
    /// The name between the brackets (empty for the file itself).
    pub name: String,
    /// The line of its header (0 for the file itself).
    pub line: usize,
    /// Its `KEY = value` lines.
    pub entries: Vec<Entry>,
    /// Its nested sections.
    pub sections: Vec<Section>,
}

impl Section {
    /// The entry `key` (compared without case), if there is one.
    pub fn get(&self, key: &str) -> Option<&Entry> {
        self.entries
            .iter()
            .find(|e| e.key.eq_ignore_ascii_case(key))
    }
}

/// What is wrong with a line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SyntaxError {
    /// The line (1-based).
    pub line: usize,
    /// What is wrong.
    pub why: LineProblem,
}

/// What is wrong with a line of a panel file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LineProblem {
    /// The file is longer than a panel file can be.
    #[error("more than {0} lines")]
    TooLong(usize),
    /// `[name` without its `]`.
    #[error("section header {0:?} has no closing ']'")]
    Unclosed(String),
    /// `[[name]` or `[name]]`.
    #[error(
        "section header {header:?} opens with {depth} '[' but does not close with {depth} ']'"
    )]
    Unbalanced {
        /// The header as written.
        header: String,
        /// How many `[` open it.
        depth: usize,
    },
    /// Something other than a comment after a header.
    #[error("unexpected {0:?} after the section header")]
    AfterHeader(String),
    /// `[]`.
    #[error("a section header without a name")]
    NoName,
    /// A `[` inside a section name.
    #[error("section name {0:?} holds a '['")]
    BracketInName(String),
    /// A section more than one level below the one before it.
    #[error("section [{name}] is nested {depth} deep inside a section {inside} deep")]
    TooDeep {
        /// The section.
        name: String,
        /// Its depth.
        depth: usize,
        /// The depth of the section it is in.
        inside: usize,
    },
    /// A section name given twice in one parent.
    #[error("section [{name}] appears twice here (first at line {first})")]
    SectionTwice {
        /// The section.
        name: String,
        /// The line of the first.
        first: usize,
    },
    /// A key given twice in one section.
    #[error("{key} is given twice in this section (first at line {first})")]
    KeyTwice {
        /// The key.
        key: String,
        /// The line of the first.
        first: usize,
    },
    /// Neither a header nor `KEY = value`.
    #[error("{0:?} is neither a [section] header nor KEY = value")]
    NotAnEntry(String),
    /// ` = value`.
    #[error("a value without a key")]
    NoKey,
    /// A key with a quote, bracket or `#`.
    #[error("key {0:?} holds a quote, bracket or '#'")]
    BadKey(String),
    /// `"""` or `'''`.
    #[error("multi-line (triple-quoted) values are not supported")]
    TripleQuoted,
    /// A quote left open.
    #[error("the quote {quote} in {value:?} is not closed")]
    OpenQuote {
        /// The quote character.
        quote: char,
        /// The value.
        value: String,
    },
    /// Something but a comma or comment after a quoted item.
    #[error("unexpected {found:?} after a quoted item in {value:?}")]
    AfterQuote {
        /// What follows the item.
        found: char,
        /// The value.
        value: String,
    },
    /// `ab"c`.
    #[error("a quote inside the unquoted item of {0:?}")]
    QuoteInItem(String),
    /// `a,,b`.
    #[error("an empty item in the list {0:?}")]
    EmptyItem(String),
}

/// Reads a panel file's text into its sections.
pub fn parse(text: &str) -> Result<Section, SyntaxError> {
    let mut root = Section::default();
    // The path of indices from the root to the section lines go into.
    let mut path: Vec<usize> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        if line > MAX_LINES {
            return Err(SyntaxError {
                line,
                why: LineProblem::TooLong(MAX_LINES),
            });
        }
        let bad = |why: LineProblem| SyntaxError { line, why };
        let t = raw.trim();
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        if t.starts_with('[') {
            let (depth, name) = header(t).map_err(bad)?;
            if depth > path.len() + 1 {
                return Err(bad(LineProblem::TooDeep {
                    name,
                    depth,
                    inside: path.len(),
                }));
            }
            path.truncate(depth - 1);
            let parent = walk(&mut root, &path);
            if let Some(first) = parent.sections.iter().find(|s| s.name == name) {
                return Err(bad(LineProblem::SectionTwice {
                    first: first.line,
                    name,
                }));
            }
            parent.sections.push(Section {
                name,
                line,
                ..Section::default()
            });
            path.push(parent.sections.len() - 1);
            continue;
        }
        let (key, value) = entry(t).map_err(bad)?;
        let section = walk(&mut root, &path);
        if let Some(first) = section.entries.iter().find(|e| e.key == key) {
            return Err(bad(LineProblem::KeyTwice {
                first: first.line,
                key,
            }));
        }
        section.entries.push(Entry { key, value, line });
    }
    Ok(root)
}

fn walk<'a>(root: &'a mut Section, path: &[usize]) -> &'a mut Section {
    let mut s = root;
    for &i in path {
        s = &mut s.sections[i];
    }
    s
}

/// A section header: its depth and name; a comment may follow it.
fn header(t: &str) -> Result<(usize, String), LineProblem> {
    let depth = t.chars().take_while(|&c| c == '[').count();
    let rest = &t[depth..];
    let close = "]".repeat(depth);
    let Some(end) = rest.find(']') else {
        return Err(LineProblem::Unclosed(t.to_string()));
    };
    let name = rest[..end].trim();
    let after = &rest[end..];
    if !after.starts_with(&close) || after[depth..].starts_with(']') {
        return Err(LineProblem::Unbalanced {
            header: t.to_string(),
            depth,
        });
    }
    let tail = after[depth..].trim();
    if !(tail.is_empty() || tail.starts_with('#')) {
        return Err(LineProblem::AfterHeader(tail.to_string()));
    }
    if name.is_empty() {
        return Err(LineProblem::NoName);
    }
    if name.contains('[') {
        return Err(LineProblem::BracketInName(name.to_string()));
    }
    Ok((depth, name.to_string()))
}

/// `KEY = value`.
fn entry(t: &str) -> Result<(String, Value), LineProblem> {
    let Some((k, v)) = t.split_once('=') else {
        return Err(LineProblem::NotAnEntry(t.to_string()));
    };
    let key = k.trim();
    if key.is_empty() {
        return Err(LineProblem::NoKey);
    }
    if key.contains(['"', '\'', '[', ']', '#']) {
        return Err(LineProblem::BadKey(key.to_string()));
    }
    Ok((key.to_string(), value(v.trim())?))
}

/// A value: items split at unquoted commas, quotes removed, an unquoted
/// `#` ending it.
fn value(v: &str) -> Result<Value, LineProblem> {
    if v.starts_with("\"\"\"") || v.starts_with("'''") {
        return Err(LineProblem::TripleQuoted);
    }
    let mut items: Vec<String> = Vec::new();
    let mut commas = 0;
    let mut chars = v.chars().peekable();
    loop {
        while chars.next_if(|c| c.is_whitespace()).is_some() {}
        let mut item = String::new();
        match chars.peek() {
            Some(&q) if q == '"' || q == '\'' => {
                chars.next();
                let mut closed = false;
                for c in chars.by_ref() {
                    if c == q {
                        closed = true;
                        break;
                    }
                    item.push(c);
                }
                if !closed {
                    return Err(LineProblem::OpenQuote {
                        quote: q,
                        value: v.to_string(),
                    });
                }
                while chars.next_if(|c| c.is_whitespace()).is_some() {}
                match chars.peek() {
                    None | Some(',') | Some('#') => {}
                    Some(c) => {
                        return Err(LineProblem::AfterQuote {
                            found: *c,
                            value: v.to_string(),
                        })
                    }
                }
            }
            _ => {
                while let Some(c) = chars.next_if(|c| *c != ',' && *c != '#') {
                    if c == '"' || c == '\'' {
                        return Err(LineProblem::QuoteInItem(v.to_string()));
                    }
                    item.push(c);
                }
                item.truncate(item.trim_end().len());
            }
        }
        match chars.next() {
            Some(',') => {
                commas += 1;
                items.push(item);
            }
            // End of the value, or a comment.
            _ => {
                // `a, b,` ends with an empty place: not an item.
                if !(item.is_empty() && commas > 0) {
                    items.push(item);
                }
                break;
            }
        }
    }
    if commas == 0 {
        return Ok(Value::One(items.pop().unwrap_or_default()));
    }
    if items.iter().any(String::is_empty) {
        return Err(LineProblem::EmptyItem(v.to_string()));
    }
    Ok(Value::List(items))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_sections_lists_and_comments() {
        let s = parse(
            "[HAL_PREFIX]\n    NAME = panelui  # the prefix\n[RADIO_BUTTONS]\n  [[g]]\n\
             \x20   KEY = NONE\n    [[[a]]]\n      TRUE_COMMAND = mdi, g53 g0 z0, g53 g0 x2\n\
             [TOGGLE_BUTTONS]\n  [[t]]\n    X = \"a, b\" , 'c#d'\n    ONE = solo,\n",
        )
        .unwrap();
        assert_eq!(s.sections.len(), 3);
        assert_eq!(
            s.sections[0].get("name").unwrap().value,
            Value::One("panelui".into())
        );
        let a = &s.sections[1].sections[0].sections[0];
        assert_eq!((a.name.as_str(), a.line), ("a", 6));
        assert_eq!(
            a.get("TRUE_COMMAND").unwrap().value,
            Value::List(vec!["mdi".into(), "g53 g0 z0".into(), "g53 g0 x2".into()])
        );
        let t = &s.sections[2].sections[0];
        assert_eq!(t.get("X").unwrap().value.items(), ["a, b", "c#d"]);
        assert_eq!(
            t.get("ONE").unwrap().value,
            Value::List(vec!["solo".into()])
        );
    }

    #[test]
    fn a_lower_level_section_closes_the_deeper_ones() {
        let s = parse("[A]\n[[b]]\n[[[c]]]\n[[d]]\nK = 1\n[E]\n").unwrap();
        assert_eq!(s.sections[0].sections[1].name, "d");
        assert_eq!(s.sections[0].sections[1].entries[0].line, 5);
        assert_eq!(s.sections[1].name, "E");
    }

    #[test]
    fn bad_lines_are_named() {
        let cases = [
            ("[A]\n[[[b]]]\n", 2, "nested 3 deep"),
            ("[A\n", 1, "no closing"),
            ("[[A]\n", 1, "does not close with 2"),
            ("[A]]\n", 1, "does not close with 1"),
            ("[A] x\n", 1, "unexpected"),
            ("[]\n", 1, "without a name"),
            (
                "[A]\nK = 1\nK = 2\n",
                3,
                "twice in this section (first at line 2)",
            ),
            ("[A]\n[A]\n", 2, "appears twice"),
            ("[A]\njust words\n", 2, "neither a [section]"),
            ("[A]\nK = \"open\n", 2, "not closed"),
            ("[A]\nK = a,,b\n", 2, "empty item"),
            ("[A]\nK = '''x\n", 2, "triple-quoted"),
            ("[A]\n = 3\n", 2, "without a key"),
            ("[A]\nK = ab\"c\n", 2, "a quote inside"),
        ];
        for (text, line, why) in cases {
            let e = parse(text).unwrap_err();
            assert_eq!(e.line, line, "{text:?}: {e:?}");
            assert!(e.why.to_string().contains(why), "{text:?}: {}", e.why);
        }
    }

    #[test]
    fn empty_values_and_plain_words() {
        let s = parse("[A]\nE =\nW = R0C2 # key\n").unwrap();
        assert_eq!(
            s.sections[0].get("e").unwrap().value,
            Value::One(String::new())
        );
        assert_eq!(
            s.sections[0].get("w").unwrap().value,
            Value::One("R0C2".into())
        );
    }
}
