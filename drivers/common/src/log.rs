//! Where a driver's messages go, in whichever host it runs.
//!
//! In our host a [`LogSink`] is the host's realtime log
//! ([`hal_core::RtLog`]: a bounded ring a host thread prints from); in
//! LinuxCNC it is `rtapi_print_msg`, which is realtime-safe there. Both
//! paths format into a buffer on the caller's stack: no allocation, lock
//! or system call in a realtime function.

use std::fmt;

use hal_core::{MsgLevel, RtLog};

/// A host's realtime-safe message path; cloning gives another handle to
/// the same path.
#[derive(Clone)]
pub struct LogSink {
    to: Target,
}

#[derive(Clone)]
enum Target {
    /// Our host's realtime log.
    Host(RtLog),
    /// A foreign host's print function (LinuxCNC's `rtapi_print_msg`).
    Foreign(fn(MsgLevel, fmt::Arguments<'_>)),
}

impl fmt::Debug for LogSink {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self.to {
            Target::Host(_) => "LogSink(host log)",
            Target::Foreign(_) => "LogSink(foreign)",
        })
    }
}

impl LogSink {
    /// Messages printed by `print`, a foreign host's realtime-safe print
    /// function.
    pub fn foreign(print: fn(MsgLevel, fmt::Arguments<'_>)) -> LogSink {
        LogSink {
            to: Target::Foreign(print),
        }
    }

    /// Says `args` at `level`; realtime-safe.
    pub fn log(&self, level: MsgLevel, args: fmt::Arguments<'_>) {
        match &self.to {
            Target::Host(log) => {
                log.log(level, args);
            }
            Target::Foreign(print) => print(level, args),
        }
    }

    /// [`log`](Self::log) at `Err`.
    pub fn err(&self, args: fmt::Arguments<'_>) {
        self.log(MsgLevel::Err, args)
    }

    /// [`log`](Self::log) at `Warn`.
    pub fn warn(&self, args: fmt::Arguments<'_>) {
        self.log(MsgLevel::Warn, args)
    }

    /// [`log`](Self::log) at `Info`.
    pub fn info(&self, args: fmt::Arguments<'_>) {
        self.log(MsgLevel::Info, args)
    }
}

impl From<RtLog> for LogSink {
    fn from(log: RtLog) -> LogSink {
        LogSink {
            to: Target::Host(log),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

    #[test]
    fn host_log_and_foreign_print_both_receive() {
        let log = RtLog::new(4);
        let sink = LogSink::from(log.clone());
        sink.err(format_args!("board {} lost", 2));
        let mut said = Vec::new();
        log.drain(|l, t| said.push((l, t.to_string())));
        assert_eq!(said, vec![(MsgLevel::Err, "board 2 lost".to_string())]);

        static CALLS: AtomicUsize = AtomicUsize::new(0);
        fn print(level: MsgLevel, args: fmt::Arguments<'_>) {
            assert_eq!(level, MsgLevel::Warn);
            assert_eq!(args.to_string(), "careful");
            CALLS.fetch_add(1, Relaxed);
        }
        let sink = LogSink::foreign(print);
        sink.warn(format_args!("careful"));
        assert_eq!(CALLS.load(Relaxed), 1);
        assert_eq!(format!("{sink:?}"), "LogSink(foreign)");
    }
}
