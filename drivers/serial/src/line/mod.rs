//! The bus of this crate: a serial line, as a small trait in the driver
//! layer's shape (hal-driver's guide, §1): accessors that describe it and
//! count its errors, a real backend ([`TtyLine`], on the `serialport`
//! crate) and a simulated one ([`SimLine`], a VFD model on simulated
//! time). The Modbus master never knows which it has. `ScriptLine`
//! (feature `testing`) plays back fixed bytes, for exact-reply tests and
//! the fuzz targets.
//!
//! The line also owns time, because RTU framing is timing: the silence
//! between frames ([`SerialLine::idle`]) and the reply timeouts pass on
//! the line's clock. On a tty that is the wall clock; on a [`SimLine`] it
//! is simulated time, so a test of timeouts and retries takes no wall
//! time at all.

#[cfg(any(test, feature = "testing"))]
mod script;
mod settings;
mod sim;
mod tty;

use std::time::Duration;

#[cfg(any(test, feature = "testing"))]
pub use script::ScriptLine;
pub use settings::{LineSettings, Parity};
pub use sim::SimLine;
pub use tty::TtyLine;

use crate::error::Result;

/// A serial line a master talks through.
pub trait SerialLine: Send {
    /// The device, for messages (`/dev/ttyUSB0`, `sim`).
    fn describe(&self) -> &str;

    /// Speed and character format.
    fn settings(&self) -> &LineSettings;

    /// Sends `bytes` (one frame).
    fn send(&mut self, bytes: &[u8]) -> Result<()>;

    /// Waits up to `timeout` for bytes and returns those that came (at
    /// most `buf.len()`); 0 when none came in time.
    fn receive(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize>;

    /// Drops whatever was received and not read yet.
    fn discard_input(&mut self);

    /// Keeps the line silent for `d`.
    fn idle(&mut self, d: Duration);

    /// The line clock: time since the line was made.
    fn now(&self) -> Duration;

    /// Opens the device again after a failure.
    fn reopen(&mut self) -> Result<()>;

    /// How many reads, writes and opens have failed.
    fn errors(&self) -> u64;
}

impl<L: SerialLine + ?Sized> SerialLine for Box<L> {
    fn describe(&self) -> &str {
        (**self).describe()
    }
    fn settings(&self) -> &LineSettings {
        (**self).settings()
    }
    fn send(&mut self, bytes: &[u8]) -> Result<()> {
        (**self).send(bytes)
    }
    fn receive(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize> {
        (**self).receive(buf, timeout)
    }
    fn discard_input(&mut self) {
        (**self).discard_input()
    }
    fn idle(&mut self, d: Duration) {
        (**self).idle(d)
    }
    fn now(&self) -> Duration {
        (**self).now()
    }
    fn reopen(&mut self) -> Result<()> {
        (**self).reopen()
    }
    fn errors(&self) -> u64 {
        (**self).errors()
    }
}
