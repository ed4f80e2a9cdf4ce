//! [`TtyLine`]: a real serial device (`/dev/ttyS*`, `/dev/ttyUSB*`,
//! `/dev/ttyACM*`, a pseudo-terminal) through the `serialport` crate:
//! raw mode, the line's speed and format, exclusive access (TIOCEXCL and
//! flock, so a second program cannot talk over the VFD), and reads that
//! wait in `poll` with a timeout.
//!
//! A read or write error (an unplugged USB adapter, a closed pty) closes
//! the device; [`SerialLine::reopen`] opens it again by path, which
//! succeeds once the device is back (a USB adapter that comes back under
//! a stable name such as `/dev/serial/by-id/...`).

use std::io::{Read, Write};
use std::time::{Duration, Instant};

use serialport::{ClearBuffer, DataBits, FlowControl, SerialPort, StopBits, TTYPort};

use super::{LineSettings, Parity, SerialLine};
use crate::error::{Result, SerialError};

/// How long a write may take before the device counts as stuck.
const WRITE_TIMEOUT: Duration = Duration::from_secs(1);

/// A serial device opened by path.
pub struct TtyLine {
    path: String,
    settings: LineSettings,
    port: Option<TTYPort>,
    epoch: Instant,
    errors: u64,
}

impl TtyLine {
    /// Opens `path` with `settings`.
    pub fn open(path: &str, settings: LineSettings) -> Result<TtyLine> {
        let mut line = TtyLine {
            path: path.to_string(),
            settings,
            port: None,
            epoch: Instant::now(),
            errors: 0,
        };
        line.port = Some(line.open_port()?);
        Ok(line)
    }

    /// Whether the device is open (false after a failure until a reopen
    /// succeeds).
    pub fn is_open(&self) -> bool {
        self.port.is_some()
    }

    fn open_port(&mut self) -> Result<TTYPort> {
        let s = &self.settings;
        let data_bits = match s.data_bits {
            5 => DataBits::Five,
            6 => DataBits::Six,
            7 => DataBits::Seven,
            _ => DataBits::Eight,
        };
        let parity = match s.parity {
            Parity::None => serialport::Parity::None,
            Parity::Even => serialport::Parity::Even,
            Parity::Odd => serialport::Parity::Odd,
        };
        let stop_bits = if s.stop_bits == 2 {
            StopBits::Two
        } else {
            StopBits::One
        };
        let opened = serialport::new(&self.path, s.baud)
            .data_bits(data_bits)
            .parity(parity)
            .stop_bits(stop_bits)
            .flow_control(FlowControl::None)
            .timeout(WRITE_TIMEOUT)
            .exclusive(true)
            .open_native();
        opened.map_err(|e| {
            self.errors += 1;
            SerialError::Open {
                device: self.path.clone(),
                reason: explain_open_error(&e),
            }
        })
    }

    /// Closes the device after an I/O failure and says what failed.
    fn fail(&mut self, op: &'static str, source: std::io::Error) -> SerialError {
        self.errors += 1;
        self.close();
        SerialError::Io {
            device: self.path.clone(),
            op,
            source,
        }
    }

    fn close(&mut self) {
        if let Some(mut port) = self.port.take() {
            // TIOCEXCL outlives the descriptor while anyone else holds the
            // tty open; clear it so the next open (ours) is not refused.
            let _ = port.set_exclusive(false);
        }
    }

    fn port(&mut self) -> Result<&mut TTYPort> {
        let device = self.path.clone();
        self.port.as_mut().ok_or(SerialError::LineDown {
            device,
            reason: "closed after an earlier failure".into(),
        })
    }
}

/// An open error in words, with what to do about a permission problem.
fn explain_open_error(e: &serialport::Error) -> String {
    use serialport::ErrorKind as K;
    match e.kind() {
        K::Io(std::io::ErrorKind::PermissionDenied) => format!(
            "{}: serial ports belong to the group dialout; add the user to it \
             (sudo usermod -aG dialout $USER) and log in again",
            e.description
        ),
        K::Io(std::io::ErrorKind::NotFound) => "no such device".into(),
        K::NoDevice => format!(
            "{} (another program has it open, or it is gone)",
            e.description
        ),
        _ => e.description.clone(),
    }
}

impl SerialLine for TtyLine {
    fn describe(&self) -> &str {
        &self.path
    }

    fn settings(&self) -> &LineSettings {
        &self.settings
    }

    fn send(&mut self, bytes: &[u8]) -> Result<()> {
        let port = self.port()?;
        // write_all, then wait until the bytes are on the wire (tcdrain),
        // so the reply timeout starts when the request has gone.
        match port.write_all(bytes).and_then(|_| port.flush()) {
            Ok(()) => Ok(()),
            Err(e) => Err(self.fail("write", e)),
        }
    }

    fn receive(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize> {
        let port = self.port()?;
        if let Err(e) = port.set_timeout(timeout) {
            return Err(self.fail("read", e.into()));
        }
        match port.read(buf) {
            Ok(0) if !buf.is_empty() => Err(self.fail(
                "read",
                std::io::Error::new(std::io::ErrorKind::UnexpectedEof, "end of file"),
            )),
            Ok(n) => Ok(n),
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => Ok(0),
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => Ok(0),
            Err(e) => Err(self.fail("read", e)),
        }
    }

    fn discard_input(&mut self) {
        if let Some(port) = &self.port {
            let _ = port.clear(ClearBuffer::Input);
        }
    }

    fn idle(&mut self, d: Duration) {
        std::thread::sleep(d);
    }

    fn now(&self) -> Duration {
        self.epoch.elapsed()
    }

    fn reopen(&mut self) -> Result<()> {
        self.close();
        let port = self.open_port()?;
        self.port = Some(port);
        Ok(())
    }

    fn errors(&self) -> u64 {
        self.errors
    }
}

impl Drop for TtyLine {
    fn drop(&mut self) {
        self.close();
    }
}
