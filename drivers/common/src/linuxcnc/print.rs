//! Messages through LinuxCNC's `rtapi_print_msg`.
//!
//! The text is formatted into a buffer on the caller's stack (cut at
//! [`MSG_BYTES`]) and handed over as `"%s\n"`: no allocation, and
//! `rtapi_print_msg` is realtime-safe in `rtapi_app` (a realtime thread's
//! messages go through a lock-free queue). LinuxCNC filters by its own
//! message level, whose numbers are [`MsgLevel`]'s. Before LinuxCNC's
//! functions were found (only a load outside `rtapi_app` gets there) the
//! text goes to stderr.

use std::ffi::c_int;
use std::fmt::{self, Write};

use hal_core::MsgLevel;

use super::api;

/// Most bytes of one message.
pub(crate) const MSG_BYTES: usize = 480;

/// A message being formatted on the stack, NUL-terminated.
struct Text {
    buf: [u8; MSG_BYTES + 1],
    len: usize,
}

impl Write for Text {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for &b in s.as_bytes() {
            // A NUL would end the C string early; stop at it.
            if self.len == MSG_BYTES || b == 0 {
                return Err(fmt::Error);
            }
            self.buf[self.len] = b;
            self.len += 1;
        }
        Ok(())
    }
}

/// Says `args` at `level` through `rtapi_print_msg`.
pub(crate) fn say(level: MsgLevel, args: fmt::Arguments<'_>) {
    let mut text = Text {
        buf: [0; MSG_BYTES + 1],
        len: 0,
    };
    // An error only means the text was cut; say what fits.
    let _ = text.write_fmt(args);
    text.buf[text.len] = 0;
    match api::loaded() {
        // SAFETY: rtapi_print_msg with "%s\n" and a NUL-terminated
        // buffer that outlives the call.
        Some(a) => unsafe { (a.print_msg)(level as c_int, c"%s\n".as_ptr(), text.buf.as_ptr()) },
        None => eprintln!("{}", String::from_utf8_lossy(&text.buf[..text.len])),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_text_is_cut_and_nul_ends_it() {
        let mut t = Text {
            buf: [0; MSG_BYTES + 1],
            len: 0,
        };
        assert!(t.write_fmt(format_args!("{}", "x".repeat(600))).is_err());
        assert_eq!(t.len, MSG_BYTES);
        let mut t = Text {
            buf: [0; MSG_BYTES + 1],
            len: 0,
        };
        let _ = t.write_str("ab\0cd");
        assert_eq!(&t.buf[..t.len], b"ab");
        say(
            MsgLevel::Err,
            format_args!("outside rtapi_app this goes to stderr"),
        );
    }
}
