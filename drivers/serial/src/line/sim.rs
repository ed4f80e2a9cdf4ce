//! [`SimLine`]: a line to a [`VfdSim`] in the same process, on simulated
//! time. Bytes take their transmission time on the wire, the drive
//! answers after its turnaround, a timeout passes in an instant of wall
//! time, and an unplugged drive makes the line fail like a tty whose
//! device went away.

use std::collections::VecDeque;
use std::io;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use hal_driver::sim::SimClock;

use super::{LineSettings, SerialLine};
use crate::error::{Result, SerialError};
use crate::sim::VfdSim;

/// A line to a simulated drive.
pub struct SimLine {
    name: String,
    settings: LineSettings,
    sim: Arc<Mutex<VfdSim>>,
    clock: Arc<SimClock>,
    /// Bytes on their way to the master, with their arrival times.
    inbox: VecDeque<(u64, u8)>,
    open: bool,
    errors: u64,
}

impl SimLine {
    /// A line to `sim` with the simulator's settings, on a clock of its
    /// own that starts at 0.
    pub fn new(sim: Arc<Mutex<VfdSim>>) -> SimLine {
        let settings = *lock(&sim).settings();
        SimLine {
            name: "sim".into(),
            settings,
            sim,
            clock: Arc::new(SimClock::new(0, 0)),
            inbox: VecDeque::new(),
            open: true,
            errors: 0,
        }
    }

    /// The line's clock (tests read it to see how long things took).
    pub fn clock(&self) -> &Arc<SimClock> {
        &self.clock
    }

    fn now_ns(&self) -> u64 {
        self.clock.peek()
    }

    /// Moves time to `t` (never back) and lets the drive run to it.
    fn advance_to(&self, t: u64) {
        let now = self.now_ns();
        if t > now {
            self.clock.advance(t - now);
        }
        lock(&self.sim).advance_to(self.now_ns());
    }

    fn fail(&mut self, op: &'static str) -> SerialError {
        self.errors += 1;
        self.open = false;
        self.inbox.clear();
        SerialError::Io {
            device: self.name.clone(),
            op,
            source: io::Error::new(
                io::ErrorKind::BrokenPipe,
                "the simulated drive is unplugged",
            ),
        }
    }

    fn check_open(&mut self) -> Result<()> {
        if !self.open {
            return Err(SerialError::LineDown {
                device: self.name.clone(),
                reason: "closed after an earlier failure".into(),
            });
        }
        Ok(())
    }
}

fn lock(sim: &Mutex<VfdSim>) -> MutexGuard<'_, VfdSim> {
    sim.lock().unwrap_or_else(|p| p.into_inner())
}

impl SerialLine for SimLine {
    fn describe(&self) -> &str {
        &self.name
    }

    fn settings(&self) -> &LineSettings {
        &self.settings
    }

    fn send(&mut self, bytes: &[u8]) -> Result<()> {
        self.check_open()?;
        if lock(&self.sim).unplugged() {
            return Err(self.fail("write"));
        }
        let end = self.now_ns() + self.settings.transmit_time(bytes.len()).as_nanos() as u64;
        self.advance_to(end);
        let reply = {
            let mut sim = lock(&self.sim);
            sim.feed(bytes, end);
            // The master falls silent after its frame: the drive sees the
            // frame end at the latest after 3.5 characters.
            let gap = self.settings.silence(3.5).as_nanos() as u64;
            sim.poll(end).or_else(|| sim.poll(end + gap))
        };
        if let Some(reply) = reply {
            let start = end + reply.delay.as_nanos() as u64;
            let per_char = self.settings.char_time().as_nanos() as u64;
            for (i, b) in reply.bytes.into_iter().enumerate() {
                self.inbox.push_back((start + per_char * (i as u64 + 1), b));
            }
        }
        Ok(())
    }

    fn receive(&mut self, buf: &mut [u8], timeout: Duration) -> Result<usize> {
        self.check_open()?;
        if lock(&self.sim).unplugged() {
            return Err(self.fail("read"));
        }
        let deadline = self.now_ns() + timeout.as_nanos() as u64;
        match self.inbox.front() {
            Some(&(arrival, _)) if arrival <= deadline => {
                self.advance_to(arrival);
                let now = self.now_ns();
                let mut n = 0;
                while n < buf.len() && self.inbox.front().is_some_and(|&(t, _)| t <= now) {
                    if let Some((_, b)) = self.inbox.pop_front() {
                        buf[n] = b;
                        n += 1;
                    }
                }
                Ok(n)
            }
            _ => {
                self.advance_to(deadline);
                Ok(0)
            }
        }
    }

    fn discard_input(&mut self) {
        let now = self.now_ns();
        while self.inbox.front().is_some_and(|&(t, _)| t <= now) {
            self.inbox.pop_front();
        }
    }

    fn idle(&mut self, d: Duration) {
        self.advance_to(self.now_ns() + d.as_nanos() as u64);
    }

    fn now(&self) -> Duration {
        Duration::from_nanos(self.now_ns())
    }

    fn reopen(&mut self) -> Result<()> {
        if lock(&self.sim).unplugged() {
            self.errors += 1;
            return Err(SerialError::Open {
                device: self.name.clone(),
                reason: "no such device".into(),
            });
        }
        self.open = true;
        self.inbox.clear();
        Ok(())
    }

    fn errors(&self) -> u64 {
        self.errors
    }
}
