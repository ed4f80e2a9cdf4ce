//! A simulated PktUART's line carried to a serial device (a
//! pseudo-terminal): each frame the board sends is written to it, and
//! whatever comes back before the line has been quiet for a while is
//! the answer. So an outside Modbus slave (pymodbus in the tests) can be
//! on the other end. The wait happens inside simulated time's step; the
//! simulator is no realtime code.

use std::any::Any;
use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::AsFd;
use std::os::unix::fs::OpenOptionsExt;
use std::path::Path;
use std::time::{Duration, Instant};

use nix::poll::{ppoll, PollFd, PollFlags};
use nix::sys::time::TimeSpec;

use super::pktuart::{LineSettings, RxFrame, SerialPeer};

/// The longest answer taken.
const MAX_ANSWER: usize = 512;

/// A serial device on a PktUART's line.
#[derive(Debug)]
pub struct PtyPeer {
    dev: File,
    /// How long to wait for the first byte of an answer.
    pub answer_wait: Duration,
    /// Silence that ends an answer.
    pub quiet: Duration,
    /// Frames answered.
    pub answered: u64,
}

impl PtyPeer {
    /// Opens `path` (a raw pseudo-terminal or serial device).
    pub fn open(path: &Path) -> std::io::Result<PtyPeer> {
        let dev = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(nix::fcntl::OFlag::O_NOCTTY.bits() | nix::fcntl::OFlag::O_NONBLOCK.bits())
            .open(path)?;
        Ok(PtyPeer {
            dev,
            answer_wait: Duration::from_millis(500),
            quiet: Duration::from_millis(30),
            answered: 0,
        })
    }

    /// Waits up to `d` for bytes; true if some are there.
    fn wait(&self, d: Duration) -> bool {
        let mut fds = [PollFd::new(self.dev.as_fd(), PollFlags::POLLIN)];
        matches!(ppoll(&mut fds, Some(TimeSpec::from_duration(d)), None), Ok(n) if n > 0)
    }

    /// Drops whatever is waiting (a late answer to an earlier frame).
    fn drain(&mut self) {
        let mut buf = [0u8; 256];
        while let Ok(n) = self.dev.read(&mut buf) {
            if n == 0 {
                break;
            }
        }
    }
}

impl SerialPeer for PtyPeer {
    fn frame(&mut self, frame: &[u8], _line: &LineSettings) -> Vec<RxFrame> {
        self.drain();
        if self.dev.write_all(frame).is_err() {
            return Vec::new();
        }
        let mut answer = Vec::new();
        let end = Instant::now() + self.answer_wait;
        let mut wait = self.answer_wait;
        let mut buf = [0u8; 256];
        while answer.len() < MAX_ANSWER && self.wait(wait) {
            match self.dev.read(&mut buf) {
                Ok(n) if n > 0 => answer.extend_from_slice(&buf[..n]),
                _ => break,
            }
            wait = self
                .quiet
                .min(end.saturating_duration_since(Instant::now()) + self.quiet);
        }
        if answer.is_empty() {
            return Vec::new();
        }
        self.answered += 1;
        answer.truncate(MAX_ANSWER);
        vec![RxFrame {
            bytes: answer,
            errors: 0,
            ichar_bits: 0,
            turnaround_ns: 0,
        }]
    }

    fn as_any(&mut self) -> &mut dyn Any {
        self
    }
}
