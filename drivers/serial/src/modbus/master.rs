//! [`Master`]: one RTU transaction at a time on a [`SerialLine`], with the
//! silence between frames, reply and byte timeouts, retries, and a line
//! that is reopened after it failed.

use std::time::Duration;

use super::frame::{self, ReplyLength};
use crate::error::{Result, SerialError};
use crate::line::SerialLine;
use crate::regs::modbus::{BROADCAST, MAX_FRAME};

/// Timing and retry policy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MasterConfig {
    /// How long to wait for the first byte of a reply, counted from the
    /// end of the request.
    pub response_timeout: Duration,
    /// How long a reply may pause between two of its bytes before it
    /// counts as cut short. (Modbus allows 1.5 characters; USB adapters
    /// deliver in bursts, so this is wider.)
    pub byte_timeout: Duration,
    /// How often a failed transaction (no reply, bad CRC, wrong reply, a
    /// busy slave) is sent again.
    pub retries: u32,
    /// Silence before every request, in character times (Modbus: 3.5).
    pub gap_chars: f64,
    /// After the line failed, how long to wait between attempts to open
    /// it again.
    pub reopen_interval: Duration,
    /// Print every frame in hex on stderr.
    pub debug: bool,
}

impl Default for MasterConfig {
    fn default() -> MasterConfig {
        MasterConfig {
            response_timeout: Duration::from_millis(100),
            byte_timeout: Duration::from_millis(20),
            retries: 2,
            gap_chars: 3.5,
            reopen_interval: Duration::from_millis(500),
            debug: false,
        }
    }
}

/// What the master has done so far.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MasterStats {
    /// Transactions asked for.
    pub transactions: u64,
    /// Transactions that failed after all retries.
    pub failed: u64,
    /// Requests sent again.
    pub retries: u64,
    /// Attempts without a reply.
    pub timeouts: u64,
    /// Replies with a bad CRC.
    pub crc_errors: u64,
    /// Exception replies.
    pub exceptions: u64,
    /// Times the line itself failed.
    pub line_failures: u64,
    /// Times the line was opened again.
    pub reopens: u64,
}

/// A Modbus RTU master (it also carries the HY protocol, which uses the
/// same framing).
pub struct Master<L: SerialLine> {
    line: L,
    config: MasterConfig,
    stats: MasterStats,
    /// Line clock at the end of the last byte sent or received.
    last_activity: Duration,
    /// Set while the line is failed; when to try opening it again.
    reopen_at: Option<Duration>,
    down_reason: String,
}

impl<L: SerialLine> Master<L> {
    /// A master on `line`.
    pub fn new(line: L, config: MasterConfig) -> Master<L> {
        Master {
            line,
            config,
            stats: MasterStats::default(),
            last_activity: Duration::ZERO,
            reopen_at: None,
            down_reason: String::new(),
        }
    }

    /// The line.
    pub fn line(&self) -> &L {
        &self.line
    }

    /// The line, to change (tests; idling through the line's clock).
    pub fn line_mut(&mut self) -> &mut L {
        &mut self.line
    }

    /// The policy.
    pub fn config(&self) -> &MasterConfig {
        &self.config
    }

    /// The policy, to change between transactions (mb2hal's timeouts
    /// are per transaction).
    pub fn config_mut(&mut self) -> &mut MasterConfig {
        &mut self.config
    }

    /// The counters.
    pub fn stats(&self) -> MasterStats {
        self.stats
    }

    /// Whether the line is failed (waiting to be reopened).
    pub fn line_is_down(&self) -> bool {
        self.reopen_at.is_some()
    }

    /// One transaction: sends `function` with `data` to `slave` and
    /// returns the reply's bytes between function code and CRC, retrying
    /// as [`MasterConfig::retries`] allows. A broadcast returns nothing.
    pub fn transact(
        &mut self,
        slave: u8,
        function: u8,
        data: &[u8],
        reply: ReplyLength,
    ) -> Result<Vec<u8>> {
        self.stats.transactions += 1;
        let mut attempt = 0;
        loop {
            match self.attempt(slave, function, data, reply) {
                Ok(v) => return Ok(v),
                Err(e) => {
                    match &e {
                        SerialError::Timeout { .. } => self.stats.timeouts += 1,
                        SerialError::Crc { .. } => self.stats.crc_errors += 1,
                        SerialError::Exception { .. } => self.stats.exceptions += 1,
                        _ => {}
                    }
                    if self.config.debug {
                        eprintln!("{}: {e}", self.line.describe());
                    }
                    if e.is_retryable() && attempt < self.config.retries {
                        attempt += 1;
                        self.stats.retries += 1;
                        continue;
                    }
                    self.stats.failed += 1;
                    return Err(e);
                }
            }
        }
    }

    /// Opens a failed line again when it is time to try.
    fn ensure_open(&mut self) -> Result<()> {
        let Some(at) = self.reopen_at else {
            return Ok(());
        };
        let down = |m: &Self| SerialError::LineDown {
            device: m.line.describe().to_string(),
            reason: m.down_reason.clone(),
        };
        if self.line.now() < at {
            return Err(down(self));
        }
        match self.line.reopen() {
            Ok(()) => {
                self.reopen_at = None;
                self.stats.reopens += 1;
                self.last_activity = self.line.now();
                Ok(())
            }
            Err(e) => {
                self.down_reason = why_down(&e);
                self.reopen_at = Some(self.line.now() + self.config.reopen_interval);
                Err(down(self))
            }
        }
    }

    fn line_failed(&mut self, e: SerialError) -> SerialError {
        self.stats.line_failures += 1;
        self.down_reason = why_down(&e);
        self.reopen_at = Some(self.line.now() + self.config.reopen_interval);
        e
    }

    fn attempt(
        &mut self,
        slave: u8,
        function: u8,
        data: &[u8],
        reply: ReplyLength,
    ) -> Result<Vec<u8>> {
        self.ensure_open()?;
        let gap = self.line.settings().silence(self.config.gap_chars);
        let quiet = self.line.now().saturating_sub(self.last_activity);
        if quiet < gap {
            self.line.idle(gap - quiet);
        }
        self.line.discard_input();
        let request = frame::request(slave, function, data);
        if self.config.debug {
            eprintln!("{} > {}", self.line.describe(), hex(&request));
        }
        if let Err(e) = self.line.send(&request) {
            return Err(self.line_failed(e));
        }
        self.last_activity = self.line.now();
        if slave == BROADCAST {
            return Ok(Vec::new());
        }
        let mut buf = [0u8; MAX_FRAME];
        let got = self.receive_reply(slave, function, reply, &mut buf)?;
        self.last_activity = self.line.now();
        if self.config.debug {
            eprintln!("{} < {}", self.line.describe(), hex(&buf[..got]));
        }
        frame::check_reply(slave, function, &buf[..got]).map(<[u8]>::to_vec)
    }

    /// Reads one reply into `buf`; returns its length.
    fn receive_reply(
        &mut self,
        slave: u8,
        function: u8,
        rule: ReplyLength,
        buf: &mut [u8; MAX_FRAME],
    ) -> Result<usize> {
        let mut got = 0;
        loop {
            let want = frame::next_read_len(rule, &buf[..got]);
            if want == 0 {
                return Ok(got);
            }
            let timeout = if got == 0 {
                self.config.response_timeout
            } else {
                self.config.byte_timeout
            };
            let n = match self.line.receive(&mut buf[got..got + want], timeout) {
                Ok(n) => n,
                Err(e) => return Err(self.line_failed(e)),
            };
            if n == 0 {
                self.last_activity = self.line.now();
                return Err(if got == 0 {
                    SerialError::Timeout {
                        slave,
                        function,
                        waited_ms: timeout.as_millis() as u64,
                    }
                } else {
                    SerialError::Truncated {
                        slave,
                        function,
                        got,
                        expected: frame::reply_len(rule, &buf[..got]).unwrap_or(got + 1),
                    }
                });
            }
            got += n;
        }
    }
}

/// Why the line is down, without repeating the device's name.
fn why_down(e: &SerialError) -> String {
    match e {
        SerialError::Io { op, source, .. } => format!("{op} failed: {source}"),
        SerialError::Open { reason, .. } => reason.clone(),
        other => other.to_string(),
    }
}

/// Bytes as `[01][03]...`, as LinuxCNC's debug output shows frames.
pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("[{b:02X}]")).collect()
}
