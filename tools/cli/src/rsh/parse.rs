//! One request line of linuxcncrsh's protocol, taken apart.

use super::vocab::{lookup, Entry};

/// The longest request line read; longer ones are refused whole.
pub const MAX_LINE: usize = 4096;

/// A request line, parsed.
#[derive(Debug, Clone, PartialEq)]
pub enum Request<'a> {
    /// Nothing but blanks.
    Empty,
    /// `hello PASSWORD CLIENT VERSION`; `None` when the words are wrong.
    Hello(Option<[&'a str; 3]>),
    /// `get SUB ARGS...`; the subcommand word as given when unknown.
    Get(Result<&'static Entry, &'a str>, Vec<&'a str>),
    /// `set SUB ARGS...`.
    Set(Result<&'static Entry, &'a str>, Vec<&'a str>),
    /// `quit`.
    Quit,
    /// `shutdown`.
    Shutdown,
    /// `help [TOPIC]`.
    Help(Option<&'a str>),
    /// A word that is no command (or `get`/`set` without a subcommand).
    Unknown(&'a str),
}

/// Parses one line (its end-of-line characters already removed).
pub fn parse(line: &str) -> Request<'_> {
    let mut words = line.split_whitespace();
    let Some(first) = words.next() else {
        return Request::Empty;
    };
    let rest: Vec<&str> = words.collect();
    match first.to_ascii_lowercase().as_str() {
        "hello" => Request::Hello(match rest.as_slice() {
            [pw, client, version] => Some([pw, client, version]),
            _ => None,
        }),
        verb @ ("get" | "set") => {
            let Some((sub, args)) = rest.split_first() else {
                return Request::Unknown(first);
            };
            let sub = lookup(sub).ok_or(*sub);
            if verb == "get" {
                Request::Get(sub, args.to_vec())
            } else {
                Request::Set(sub, args.to_vec())
            }
        }
        "quit" => Request::Quit,
        "shutdown" => Request::Shutdown,
        "help" => Request::Help(rest.first().copied()),
        _ => Request::Unknown(first),
    }
}

/// For `set mdi`: the text after the subcommand word, as typed (G-code
/// keeps its spacing).
pub fn tail_after_sub(line: &str) -> &str {
    let t = line.trim_start();
    let t = t
        .split_once(char::is_whitespace)
        .map_or("", |(_, r)| r)
        .trim_start();
    t.split_once(char::is_whitespace)
        .map_or("", |(_, r)| r)
        .trim()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rsh::vocab::Sub;

    #[test]
    fn words_are_matched_without_case() {
        assert_eq!(
            parse("HeLLo EMC me 1.0"),
            Request::Hello(Some(["EMC", "me", "1.0"]))
        );
        assert_eq!(parse("hello EMC"), Request::Hello(None));
        match parse("SET Mode mdi") {
            Request::Set(Ok(e), args) => {
                assert_eq!(e.sub, Sub::Mode);
                assert_eq!(args, ["mdi"]);
            }
            other => panic!("{other:?}"),
        }
        assert!(matches!(
            parse("get nosuch"),
            Request::Get(Err("nosuch"), _)
        ));
        assert_eq!(parse("frobnicate"), Request::Unknown("frobnicate"));
        assert_eq!(parse("set"), Request::Unknown("set"));
        assert_eq!(parse("  \t "), Request::Empty);
    }

    #[test]
    fn mdi_text_keeps_its_spacing() {
        assert_eq!(tail_after_sub("set mdi g0  x1 (a  b)"), "g0  x1 (a  b)");
        assert_eq!(tail_after_sub("set mdi"), "");
    }
}
