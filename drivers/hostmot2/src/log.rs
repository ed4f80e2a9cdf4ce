//! Messages a board produces while it registers, with LinuxCNC's levels.
//!
//! Registration runs outside realtime, so it collects its messages here;
//! the HAL binding prints them with the board's prefix (`hm2/hm2_5i25.0: `)
//! whether registration succeeds or fails, as LinuxCNC's log shows both
//! the warnings and the error that stopped a load.

/// LinuxCNC's message levels (`RTAPI_MSG_*`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    /// An error.
    Err = 1,
    /// A warning.
    Warn = 2,
    /// Information (the pin list, "registered").
    Info = 3,
    /// Debugging (IDROM and descriptor dumps, when asked for).
    Dbg = 4,
}

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
