//! Messages with LinuxCNC's levels and prefixes.
//!
//! Registration runs outside realtime and collects its messages in a
//! [`MessageLog`]; the HAL binding prints them with the board's prefix
//! (`hm2/hm2_5i25.0: `) whether registration succeeds or fails, as
//! LinuxCNC's log shows both the warnings and the error that stopped a
//! load. Realtime functions say things through a [`BoardLog`]: the host's
//! realtime log ([`hal_core::RtLog`]) with that prefix in front. Both obey
//! the host's message level (errors only by default, as in LinuxCNC).

use std::fmt;
use std::sync::Arc;

use hal_driver::LogSink;

pub use hal_core::MsgLevel as Level;

/// One message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Message {
    /// Its level.
    pub level: Level,
    /// Its text, one line, without prefix.
    pub text: String,
}

/// The messages of one registration, in order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MessageLog {
    messages: Vec<Message>,
}

impl MessageLog {
    /// Adds a message; a text with several lines becomes several messages.
    pub fn push(&mut self, level: Level, text: impl AsRef<str>) {
        for line in text.as_ref().lines() {
            self.messages.push(Message {
                level,
                text: line.to_string(),
            });
        }
    }

    /// Adds an error.
    pub fn err(&mut self, text: impl AsRef<str>) {
        self.push(Level::Err, text)
    }

    /// Adds a warning.
    pub fn warn(&mut self, text: impl AsRef<str>) {
        self.push(Level::Warn, text)
    }

    /// Adds information.
    pub fn info(&mut self, text: impl AsRef<str>) {
        self.push(Level::Info, text)
    }

    /// Adds a debugging message.
    pub fn dbg(&mut self, text: impl AsRef<str>) {
        self.push(Level::Dbg, text)
    }

    /// The messages, in order.
    pub fn messages(&self) -> &[Message] {
        &self.messages
    }

    /// The messages of `level` or more important, each prefixed.
    pub fn lines(&self, prefix: &str, max: Level) -> Vec<String> {
        self.messages
            .iter()
            .filter(|m| m.level <= max)
            .map(|m| format!("{prefix}{}", m.text))
            .collect()
    }
}

/// The prefix of hostmot2's messages about a board: `hm2/<board>: `.
pub fn prefix(board: &str) -> String {
    format!("hm2/{board}: ")
}

/// A board's realtime message path.
#[derive(Clone)]
pub struct BoardLog {
    log: LogSink,
    prefix: Arc<str>,
}

impl BoardLog {
    /// Messages about `board` into `log`.
    pub fn new(log: impl Into<LogSink>, board: &str) -> BoardLog {
        BoardLog {
            log: log.into(),
            prefix: prefix(board).into(),
        }
    }

    /// Says something, realtime-safe (the host's level filters it).
    pub fn say(&self, level: Level, args: fmt::Arguments<'_>) {
        self.log.log(level, format_args!("{}{}", self.prefix, args))
    }

    /// The prefix, `hm2/<board>: `.
    pub fn prefix(&self) -> &str {
        &self.prefix
    }

    /// The log itself.
    pub fn log(&self) -> &LogSink {
        &self.log
    }

    /// Prints a registration's messages (they are not realtime).
    pub fn replay(&self, messages: &MessageLog) {
        for m in messages.messages() {
            self.say(m.level, format_args!("{}", m.text));
        }
    }
}
