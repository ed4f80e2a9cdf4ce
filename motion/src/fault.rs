//! The last fault the controller reported, kept beside its last message:
//! a later harmless message (a homing abort, a jog message) replaces the
//! last message, not the fault that disabled the machine.
//!
//! A fault is a message that stops a running program
//! ([`Event::stops_a_program`]). The record is five words, as the status
//! snapshot carries them: how many faults were reported, the last one's
//! wire word, its message number (the message count when it was
//! reported, so a reader can tell which messages came after it), and for
//! a following error the error and the limit it exceeded (IEEE bits;
//! zero otherwise).

use std::fmt;
use std::sync::atomic::{fence, AtomicU64, Ordering::*};

use crate::events::Event;

/// Words of a fault record.
pub const FAULT_WORDS: usize = 5;

/// What a following error was when it tripped, in machine units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowingErrorTrip {
    /// The joint's following error (command minus feedback).
    pub error: f64,
    /// The limit it exceeded, scaled by the commanded velocity
    /// (FERROR × |velocity| / MAX_VELOCITY, at least MIN_FERROR).
    pub limit: f64,
}

/// The last fault the controller reported.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fault {
    /// The fault's message.
    pub event: Event,
    /// Its message number: 1 for the first message the controller
    /// reported, counting every message, faults or not.
    pub number: u64,
    /// For a following error: the error and the limit when it tripped.
    pub following: Option<FollowingErrorTrip>,
}

impl Fault {
    /// The fault a record stands for: `None` when no fault was reported
    /// (all zero, as a snapshot from a controller without fault words
    /// reads) or when the wire word is not a fault's.
    pub fn from_words(w: &[u64; FAULT_WORDS]) -> Option<Fault> {
        if w[0] == 0 {
            return None;
        }
        let event = Event::from_word(w[1]).filter(Event::stops_a_program)?;
        let following = match event {
            Event::JointFollowingError { .. } if w[3] != 0 || w[4] != 0 => {
                Some(FollowingErrorTrip {
                    error: f64::from_bits(w[3]),
                    limit: f64::from_bits(w[4]),
                })
            }
            _ => None,
        };
        Some(Fault {
            event,
            number: w[2],
            following,
        })
    }
}

impl fmt::Display for Fault {
    /// The message in LinuxCNC's words, and for a following error how
    /// large it was: `joint 2 following error (error 0.3412, limit 0.3333)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.event)?;
        if let Some(t) = self.following {
            write!(f, " (error {:.6}, limit {:.6})", t.error, t.limit)?;
        }
        Ok(())
    }
}

/// The controller's side of the record: written by the realtime side (one
/// producer), read by the snapshot. Lock-free: the count is written last
/// and read first and last, so a reader that sees it unchanged has one
/// fault's words.
#[derive(Debug, Default)]
pub struct FaultCell {
    count: AtomicU64,
    word: AtomicU64,
    number: AtomicU64,
    error: AtomicU64,
    limit: AtomicU64,
}

impl FaultCell {
    /// Records `event`, reported as message `number`. Realtime-safe.
    pub(crate) fn record(&self, event: Event, number: u64, trip: Option<FollowingErrorTrip>) {
        let n = self.count.load(Relaxed);
        // An odd count marks the words as being written.
        self.count.store(n | 1, Relaxed);
        fence(Release);
        self.word.store(event.encode(), Relaxed);
        self.number.store(number, Relaxed);
        let (e, l) = trip.map_or((0, 0), |t| (t.error.to_bits(), t.limit.to_bits()));
        self.error.store(e, Relaxed);
        self.limit.store(l, Relaxed);
        self.count.store((n | 1) + 1, Release);
    }

    /// The record's words (see the module); the count word is the number
    /// of faults reported. Realtime-safe: a reader racing the writer
    /// tries a few times, then returns the count of the faults before
    /// the one being written, without words (the next snapshot has it).
    pub fn words(&self) -> [u64; FAULT_WORDS] {
        for _ in 0..4 {
            let c1 = self.count.load(Acquire);
            let w = [
                c1 / 2,
                self.word.load(Relaxed),
                self.number.load(Relaxed),
                self.error.load(Relaxed),
                self.limit.load(Relaxed),
            ];
            fence(Acquire);
            if c1 & 1 == 0 && self.count.load(Relaxed) == c1 {
                return w;
            }
        }
        // The writer is mid-record: report the faults before this one.
        let prev = self.count.load(Acquire) / 2;
        [prev, 0, 0, 0, 0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_round_trips_with_its_following_error() {
        let c = FaultCell::default();
        assert_eq!(c.words(), [0; FAULT_WORDS]);
        assert_eq!(Fault::from_words(&c.words()), None);
        let trip = FollowingErrorTrip {
            error: 0.5,
            limit: 0.25,
        };
        c.record(Event::JointFollowingError { joint: 2 }, 7, Some(trip));
        let f = Fault::from_words(&c.words()).unwrap();
        assert_eq!(c.words()[0], 1);
        assert_eq!(f.event, Event::JointFollowingError { joint: 2 });
        assert_eq!((f.number, f.following), (7, Some(trip)));
        assert_eq!(
            f.to_string(),
            "joint 2 following error (error 0.500000, limit 0.250000)"
        );
        c.record(Event::JointOnLimit { joint: 0 }, 9, None);
        let f = Fault::from_words(&c.words()).unwrap();
        assert_eq!(c.words()[0], 2);
        assert_eq!((f.number, f.following), (9, None));
        assert_eq!(f.to_string(), "joint 0 on limit switch error");
    }

    #[test]
    fn a_record_of_a_message_that_is_no_fault_is_none() {
        let jog = Event::JogStopped { immediate: true }.encode();
        assert_eq!(Fault::from_words(&[1, jog, 1, 0, 0]), None);
        assert_eq!(Fault::from_words(&[1, u64::MAX, 1, 0, 0]), None);
    }
}
