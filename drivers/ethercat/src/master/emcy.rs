//! Emergency messages during cycles: every [`POLL_EVERY`]th cycle the
//! helper looks at one polled slave's slave → master mailbox, in turn,
//! after the cycle's frame and its inputs are published (the realtime
//! side never waits for it): an emergency reaches the drive's pins
//! within `POLL_EVERY` × (polled slaves) periods, at the cost of one
//! more frame every `POLL_EVERY` periods. The
//! mailbox status (sync manager 1's status byte) says whether the slave
//! wrote something; if so the helper reads the mailbox (which empties
//! it) and hands a CoE emergency's error code to the realtime side
//! through a lock-free slot per slave ([`Slots`]); anything else there
//! (a late SDO reply) is dropped.

use std::sync::atomic::{AtomicU64, Ordering::*};
use std::time::{Duration, Instant};

use ethercrab::{Command, MainDevice};

use super::io::Io;
use crate::regs::{self, sm};
use crate::wire::coe::{parse_response, SlaveMessage};

/// Cycles between two mailbox looks.
pub const POLL_EVERY: u32 = 4;

/// The latest emergency of each slave: a count in the high half, the
/// error code in the low 16 bits (0: none yet).
#[derive(Debug)]
pub(crate) struct Slots(Box<[AtomicU64]>);

impl Slots {
    /// Slots for `n` slaves.
    pub(crate) fn new(n: usize) -> Slots {
        Slots((0..n).map(|_| AtomicU64::new(0)).collect())
    }

    fn post(&self, slave: usize, code: u16) {
        if let Some(s) = self.0.get(slave) {
            let count = (s.load(Relaxed) >> 32).wrapping_add(1);
            s.store(count << 32 | u64::from(code), Release);
        }
    }

    /// Slave `slave`'s latest emergency as (count, code).
    pub(crate) fn latest(&self, slave: usize) -> (u32, u16) {
        let v = self.0.get(slave).map_or(0, |s| s.load(Acquire));
        ((v >> 32) as u32, v as u16)
    }
}

/// A slave whose mailbox is polled.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Polled {
    /// Its position.
    pub(crate) slave: usize,
    /// Its station address.
    pub(crate) station: u16,
    /// Its slave → master mailbox (start, bytes).
    pub(crate) mailbox: (u16, u16),
}

/// The helper's round of polled slaves.
#[derive(Debug, Default)]
pub(crate) struct MailboxPoll {
    pub(crate) polled: Vec<Polled>,
    next: usize,
    cycles: u32,
}

impl MailboxPoll {
    /// One slave's look, the next in turn.
    pub(crate) fn poll(
        &mut self,
        md: &MainDevice<'_>,
        io: &mut Io<'_>,
        slots: &Slots,
        timeout: Duration,
    ) {
        self.cycles = self.cycles.wrapping_add(1);
        if self.cycles % POLL_EVERY != 0 {
            return;
        }
        let Some(&p) = self.polled.get(self.next) else {
            return;
        };
        self.next = (self.next + 1) % self.polled.len();
        let status_at = regs::SM_BASE + regs::SM_LEN + sm::STATUS;
        let status = Command::fprd(p.station, status_at).receive::<u8>(md);
        let Some(Ok(status)) = io.block_on(super::serve::with_deadline(
            status,
            Instant::now() + timeout,
        )) else {
            return;
        };
        if status & sm::STATUS_FULL == 0 {
            return;
        }
        let (start, len) = p.mailbox;
        let read = async {
            Command::fprd(p.station, start)
                .receive_slice(md, len)
                .await
                .map(|pdu| parse_response(&pdu).map(|(_, m)| m))
        };
        if let Some(Ok(Ok(SlaveMessage::Emergency(e)))) =
            io.block_on(super::serve::with_deadline(read, Instant::now() + timeout))
        {
            slots.post(p.slave, e.code.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_emergency_counts_and_the_latest_code_stays() {
        let s = Slots::new(2);
        assert_eq!(s.latest(0), (0, 0));
        s.post(0, 0x2310);
        s.post(0, 0x4210);
        s.post(9, 1);
        assert_eq!(s.latest(0), (2, 0x4210));
        assert_eq!(s.latest(1), (0, 0));
        assert_eq!(s.latest(9), (0, 0));
    }
}
