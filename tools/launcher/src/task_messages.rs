//! What LinuxCNC's error channel carries: task's errors (a program run
//! that failed, motion's fault and limit messages), the messages of a
//! program's `(MSG, ...)` comments and operator messages sent with
//! `message`. Each is numbered; `messages SEQ` answers those after SEQ,
//! one a line, `SEQ KIND TEXT`, with LinuxCNC's kind numbers.

use std::collections::VecDeque;

use crate::error::LaunchError;
use crate::task::TaskRequest;

/// LinuxCNC's OPERATOR_ERROR: an error for the operator.
pub const OPERATOR_ERROR: i32 = 11;
/// LinuxCNC's OPERATOR_TEXT: a note for the operator.
pub const OPERATOR_TEXT: i32 = 12;
/// LinuxCNC's OPERATOR_DISPLAY: a message to show (MSG comments).
pub const OPERATOR_DISPLAY: i32 = 13;

/// The most messages kept; older ones are dropped first.
const KEPT: usize = 256;
/// The longest message kept, in bytes (longer ones are cut).
const MAX_TEXT: usize = 1024;

/// The numbered messages, the newest `KEPT`.
#[derive(Debug, Default)]
pub struct MessageLog {
    last: u64,
    ring: VecDeque<(u64, i32, String)>,
}

impl MessageLog {
    /// Adds a message of `kind` (one line: control characters, newlines
    /// and the protocol's separators among them, become spaces).
    pub fn push(&mut self, kind: i32, text: &str) {
        let mut text: String = text
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        if text.len() > MAX_TEXT {
            let mut end = MAX_TEXT;
            while !text.is_char_boundary(end) {
                end -= 1;
            }
            text.truncate(end);
        }
        self.last += 1;
        if self.ring.len() == KEPT {
            self.ring.pop_front();
        }
        self.ring.push_back((self.last, kind, text));
    }

    /// The messages after `seq`, one a line; the first line is the
    /// number of the newest message (the SEQ to ask with next).
    pub fn since(&self, seq: u64) -> String {
        let mut out = format!("{}\n", self.last);
        for (n, kind, text) in self.ring.iter().filter(|m| m.0 > seq) {
            out.push_str(&format!("{n} {kind} {text}\n"));
        }
        out
    }
}

/// Parses `messages SEQ` and `message error|text|display TEXT...`;
/// `None` when `words` is neither.
pub(crate) fn parse(words: &[&str]) -> Option<Result<TaskRequest, LaunchError>> {
    let bad = |request: &'static str, why: String| LaunchError::BadArgument { request, why };
    match words {
        ["messages", seq] => Some(
            seq.parse::<u64>()
                .map(TaskRequest::Messages)
                .map_err(|_| bad("messages", format!("SEQ must be a number, not '{seq}'"))),
        ),
        ["messages", ..] => Some(Err(bad("messages", "takes 1 argument (SEQ)".into()))),
        ["message", kind, text @ ..] if !text.is_empty() => {
            let kind = match *kind {
                "error" => OPERATOR_ERROR,
                "text" => OPERATOR_TEXT,
                "display" => OPERATOR_DISPLAY,
                other => {
                    return Some(Err(bad(
                        "message",
                        format!("the kind must be error, text or display, not '{other}'"),
                    )))
                }
            };
            Some(Ok(TaskRequest::Message {
                kind,
                text: text.join(" "),
            }))
        }
        ["message", ..] => Some(Err(bad("message", "takes a kind and a text".into()))),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_are_numbered_and_read_from_a_point() {
        let mut log = MessageLog::default();
        assert_eq!(log.since(0), "0\n");
        log.push(OPERATOR_ERROR, "first\nline\u{1e}");
        log.push(OPERATOR_DISPLAY, "second");
        assert_eq!(log.since(0), "2\n1 11 first line \n2 13 second\n");
        assert_eq!(log.since(1), "2\n2 13 second\n");
        assert_eq!(log.since(2), "2\n");
        for i in 0..KEPT + 5 {
            log.push(OPERATOR_TEXT, &format!("m{i}"));
        }
        let all = log.since(0);
        assert_eq!(all.lines().count(), KEPT + 1);
        assert!(all.starts_with(&format!("{}\n", KEPT + 7)), "{all}");
        log.push(OPERATOR_TEXT, &"é".repeat(MAX_TEXT));
        assert!(log.since(KEPT as u64 + 7).len() < MAX_TEXT + 32);
    }

    #[test]
    fn requests_parse_and_refuse_bad_words() {
        let p = |w: &str| parse(&w.split(' ').collect::<Vec<_>>());
        assert_eq!(p("messages 4").unwrap().unwrap(), TaskRequest::Messages(4));
        assert_eq!(
            p("message display tool 3 please").unwrap().unwrap(),
            TaskRequest::Message {
                kind: OPERATOR_DISPLAY,
                text: "tool 3 please".into()
            }
        );
        assert!(p("messages x").unwrap().is_err());
        assert!(p("message shout hi").unwrap().is_err());
        assert!(p("message error").unwrap().is_err());
        assert!(p("mode auto").is_none());
    }
}
