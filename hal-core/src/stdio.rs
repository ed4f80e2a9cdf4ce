//! A standard output that may close under a tool (`halcmd show | head
//! -1`): what every program of the suite, from halcmd to a driver's
//! bring-up tool, does at that edge. (Arguments that may not be UTF-8 are
//! [`crate::userspace`]'s.)
//!
//! A tool whose standard output is closed ends quietly, as `yes | head`
//! does: [`closed_stdout`] lets SIGPIPE end the process (Rust ignores the
//! signal, so otherwise the next `println!` would panic). Tools print
//! through [`outln!`](crate::outln) and [`out!`](crate::out), or write to
//! [`stdout`], which do this for them.

use std::io::{self, Write};

/// Ends the process as SIGPIPE would have: no message, status of a
/// process killed by SIGPIPE.
pub fn closed_stdout() -> ! {
    // SAFETY: restoring the default action of SIGPIPE and raising it
    // touches no memory of ours; the process ends here.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        libc::raise(libc::SIGPIPE);
    }
    std::process::exit(128 + libc::SIGPIPE);
}

/// Checks the result of a write to standard output: a closed pipe ends the
/// process quietly; other errors are returned.
pub fn checked(r: io::Result<()>) -> io::Result<()> {
    match r {
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => closed_stdout(),
        other => other,
    }
}

/// Writes formatted text to standard output (flushed); ends the process
/// quietly if standard output is closed. Used by [`out!`](crate::out) and
/// [`outln!`](crate::outln).
pub fn write_out(args: std::fmt::Arguments<'_>, newline: bool) {
    let mut out = io::stdout().lock();
    let r = out
        .write_fmt(args)
        .and_then(|()| {
            if newline {
                out.write_all(b"\n")
            } else {
                Ok(())
            }
        })
        .and_then(|()| out.flush());
    // Any other failure (a full disk behind a redirection) loses the text,
    // as C's printf does: never a panic.
    let _ = checked(r);
}

/// `println!` that ends the process quietly on a closed standard output.
#[macro_export]
macro_rules! outln {
    () => { $crate::stdio::write_out(format_args!(""), true) };
    ($($arg:tt)*) => { $crate::stdio::write_out(format_args!($($arg)*), true) };
}

/// `print!` (flushed) that ends the process quietly on a closed standard
/// output.
#[macro_export]
macro_rules! out {
    ($($arg:tt)*) => { $crate::stdio::write_out(format_args!($($arg)*), false) };
}

/// Standard output as a `Write` that ends the process quietly when the
/// reader has gone.
pub fn stdout() -> Stdout {
    Stdout(io::stdout())
}

/// See [`stdout`].
#[derive(Debug)]
pub struct Stdout(io::Stdout);

impl Write for Stdout {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self.0.write(buf) {
            Err(e) if e.kind() == io::ErrorKind::BrokenPipe => closed_stdout(),
            other => other,
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        checked(self.0.flush())
    }
}

impl Stdout {
    /// Whether standard output is a terminal.
    pub fn is_terminal(&self) -> bool {
        std::io::IsTerminal::is_terminal(&self.0)
    }
}
