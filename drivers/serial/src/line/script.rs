//! [`ScriptLine`]: a line whose far end is a script of bytes, for tests
//! of exact replies and for the fuzz targets. What the master sends is
//! kept; every receive hands out the next chunk of the script, or
//! nothing (a timeout) when the script is used up. Time moves only by
//! what the master waits for.

use std::collections::VecDeque;
use std::time::Duration;

use super::{LineSettings, Parity, SerialLine};
use crate::error::Result;

/// A scripted line.
pub struct ScriptLine {
    settings: LineSettings,
    chunks: VecDeque<Vec<u8>>,
    sent: Vec<Vec<u8>>,
    now: Duration,
}

impl ScriptLine {
    /// A line that answers with `chunks`, one per receive.
    pub fn new(chunks: impl IntoIterator<Item = Vec<u8>>) -> ScriptLine {
        ScriptLine {
            settings: LineSettings::new(38_400, Parity::None),
            chunks: chunks.into_iter().collect(),
            sent: Vec::new(),
            now: Duration::ZERO,
        }
    }

    /// Adds chunks to the script.
    pub fn push(&mut self, chunk: Vec<u8>) {
        self.chunks.push_back(chunk);
    }

    /// The frames the master sent.
    pub fn sent(&self) -> &[Vec<u8>] {
        &self.sent
    }
}

impl SerialLine for ScriptLine {
    fn describe(&self) -> &str {
        "script"
    }

    fn settings(&self) -> &LineSettings {
        &self.settings
    }

    fn send(&mut self, bytes: &[u8]) -> Result<()> {
        self.now += self.settings.transmit_time(bytes.len());
        self.sent.push(bytes.to_vec());
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize> {
        let Some(chunk) = self.chunks.front_mut() else {
            self.now += timeout;
            return Ok(0);
        };
        let n = chunk.len().min(buf.len());
        buf[..n].copy_from_slice(&chunk[..n]);
        chunk.drain(..n);
        if chunk.is_empty() {
            self.chunks.pop_front();
        }
        self.now += self.settings.transmit_time(n);
        if n == 0 {
            self.now += timeout;
        }
        Ok(n)
    }

    fn discard_input(&mut self) {}

    fn idle(&mut self, d: Duration) {
        self.now += d;
    }

    fn now(&self) -> Duration {
        self.now
    }

    fn reopen(&mut self) -> Result<()> {
        Ok(())
    }

    fn errors(&self) -> u64 {
        0
    }
}
