//! Messages the controller reports while it runs (LinuxCNC's
//! `reportError`), carried from the realtime function to whoever reads
//! them through a fixed-size lock-free ring: the realtime side never
//! allocates, locks or blocks, and a full ring drops the newest message
//! and counts it.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering::*};
use std::sync::Mutex;

use crate::command::Direction;
use crate::fault::{FaultCell, FollowingErrorTrip};
use crate::homing::{HomeFault, HomeState};

/// Something the controller reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// A hard limit switch tripped on an enabled joint; motion disabled.
    JointOnLimit {
        /// The joint number.
        joint: usize,
    },
    /// An amplifier fault on an enabled joint; motion disabled.
    JointAmpFault {
        /// The joint number.
        joint: usize,
    },
    /// Following error over the limit on an enabled joint; motion disabled.
    JointFollowingError {
        /// The joint number.
        joint: usize,
    },
    /// `motion.enable` went false while enabled; motion disabled.
    EnableInputStopped,
    /// A misc error input is true; motion disabled.
    MiscError {
        /// The input number.
        input: usize,
    },
    /// A spindle amplifier fault; motion disabled.
    SpindleAmpFault {
        /// The spindle number.
        spindle: usize,
    },
    /// A homed joint's command left its soft limits.
    SoftLimitExceeded {
        /// The joint number.
        joint: usize,
        /// The direction.
        dir: Direction,
    },
    /// `motion.jog-stop` or `motion.jog-stop-immediate` ended the jogs.
    JogStopped {
        /// Whether the jogs stopped at once (jog-stop-immediate).
        immediate: bool,
    },
    /// The probe input rose during a jog; the jogs were stopped.
    ProbeTrippedDuringJog,
    /// Switching kinematics (`motion.switchkins-type`) failed.
    KinsSwitchFailed {
        /// The kinematics type asked for.
        kins_type: i32,
    },
    /// Homing of `joint` failed in `state`; the sequence was aborted.
    HomingAborted {
        /// The joint number.
        joint: usize,
        /// What went wrong.
        fault: HomeFault,
        /// The homing state it was in.
        state: HomeState,
    },
    /// The inverse kinematics failed for the commanded pose in teleop or
    /// coordinated mode; motion disabled.
    InverseKinsFailed,
    /// The inverse kinematics gave a joint position that is not finite;
    /// motion disabled.
    NonFiniteJoint {
        /// The joint number.
        joint: usize,
    },
    /// The probe input rose during an axis (teleop) jog; the jogs were
    /// stopped at once.
    ProbeTrippedDuringAxisJog,
    /// The teleop or coordinated mode remembered over a disable could not
    /// be resumed on enable (joints no longer homed, or the kinematics
    /// failed): motion is in free mode.
    WorldModeDropped,
    /// A probing move ended without the input changing (G38.2: without
    /// contact; G38.4: without losing contact); the queue was aborted.
    ProbeNoContact {
        /// Whether the move looks for the input clearing (G38.4, G38.5).
        trip_on_clear: bool,
    },
    /// The probe input rose during a coordinated move that is not a
    /// probing move; the queue was aborted.
    ProbeTrippedDuringMove,
    /// `spindle.N.orient-fault` was non-zero while an M19 orientation
    /// ran; the orientation failed and the queue was aborted.
    SpindleOrientFault {
        /// The spindle number.
        spindle: usize,
        /// The fault code.
        fault: i32,
    },
    /// `axis.L.eoffset-enable` went false while the axis's external offset
    /// was not zero: the offset is held.
    EoffsetDisabledWhileApplied {
        /// The axis number (0..=8: X Y Z A B C U V W).
        axis: usize,
    },
    /// A locking indexer joint did not answer its unlock (`unlocking`:
    /// `joint.N.is-unlocked` stayed false) or its lock (it stayed true)
    /// within [`INDEXER_TIMEOUT`](crate::tp::INDEXER_TIMEOUT) seconds; the
    /// queue was aborted.
    IndexerTimeout {
        /// The joint number.
        joint: usize,
        /// Whether it was being unlocked (else locked).
        unlocking: bool,
    },
}

impl std::fmt::Display for Event {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Event::JointOnLimit { joint } => write!(f, "joint {joint} on limit switch error"),
            Event::JointAmpFault { joint } => write!(f, "joint {joint} amplifier fault"),
            Event::JointFollowingError { joint } => write!(f, "joint {joint} following error"),
            Event::EnableInputStopped => f.write_str("motion stopped by enable input"),
            Event::MiscError { input } => write!(f, "Motion Stopped by misc error {input}"),
            Event::SpindleAmpFault { spindle } => write!(f, "spindle {spindle} amplifier fault"),
            Event::SoftLimitExceeded { joint, dir } => {
                let d = match dir {
                    Direction::Positive => "POSITIVE",
                    Direction::Negative => "NEGATIVE",
                };
                write!(f, "Exceeded {d} soft limit ({joint})")
            }
            Event::JogStopped { immediate: false } => f.write_str("Jog aborted by jog-stop"),
            Event::JogStopped { immediate: true } => {
                f.write_str("Jog aborted by jog-stop-immediate")
            }
            Event::ProbeTrippedDuringJog => f.write_str("Probe tripped during a joint jog."),
            Event::KinsSwitchFailed { kins_type } => {
                write!(f, "kinematics switch to type {kins_type} failed")
            }
            Event::HomingAborted {
                joint,
                fault,
                state,
            } => write!(
                f,
                "homing of joint {joint} aborted in state {state}: {fault}"
            ),
            Event::InverseKinsFailed => {
                f.write_str("kinematicsInverse failed for the commanded pose; motion disabled")
            }
            Event::NonFiniteJoint { joint } => write!(
                f,
                "joint {joint} position is not a finite number after inverse kinematics; motion disabled"
            ),
            Event::ProbeTrippedDuringAxisJog => {
                f.write_str("Probe tripped during a coordinate jog.")
            }
            Event::WorldModeDropped => f.write_str(
                "teleop/coordinated mode could not be resumed on enable; motion is in free mode",
            ),
            Event::ProbeNoContact {
                trip_on_clear: false,
            } => f.write_str("G38.2 move finished without making contact"),
            Event::ProbeNoContact {
                trip_on_clear: true,
            } => f.write_str("G38.4 move finished without breaking contact"),
            Event::ProbeTrippedDuringMove => f.write_str("Probe tripped during non-probe move."),
            Event::SpindleOrientFault { fault, .. } => {
                write!(f, "fault {fault} during orient in progress")
            }
            Event::EoffsetDisabledWhileApplied { axis } => write!(
                f,
                "axis {} external offset disabled while not zero: it is held; to clear it, \
                 re-enable it and count it back to zero, pulse eoffset-clear, or turn the \
                 machine off and on",
                crate::kins::AXIS_LETTERS
                    .get(axis)
                    .map_or('?', |l| l.to_ascii_uppercase())
            ),
            Event::IndexerTimeout {
                joint,
                unlocking: true,
            } => write!(
                f,
                "locking indexer joint {joint}: joint.{joint}.is-unlocked did not become true \
                 within {} s of joint.{joint}.unlock; the move was aborted",
                crate::tp::INDEXER_TIMEOUT
            ),
            Event::IndexerTimeout {
                joint,
                unlocking: false,
            } => write!(
                f,
                "locking indexer joint {joint}: joint.{joint}.is-unlocked did not become false \
                 within {} s of dropping joint.{joint}.unlock; the program was aborted",
                crate::tp::INDEXER_TIMEOUT
            ),
        }
    }
}

impl Event {
    pub(crate) fn encode(self) -> u64 {
        let (code, a, b): (u64, u64, u64) = match self {
            Event::JointOnLimit { joint } => (1, joint as u64, 0),
            Event::JointAmpFault { joint } => (2, joint as u64, 0),
            Event::JointFollowingError { joint } => (3, joint as u64, 0),
            Event::EnableInputStopped => (4, 0, 0),
            Event::MiscError { input } => (5, input as u64, 0),
            Event::SpindleAmpFault { spindle } => (6, spindle as u64, 0),
            Event::SoftLimitExceeded { joint, dir } => {
                (7, joint as u64, u64::from(dir == Direction::Positive))
            }
            Event::JogStopped { immediate } => (8, 0, u64::from(immediate)),
            Event::ProbeTrippedDuringJog => (9, 0, 0),
            Event::KinsSwitchFailed { kins_type } => (10, 0, kins_type as u32 as u64),
            Event::HomingAborted {
                joint,
                fault,
                state,
            } => (
                11,
                joint as u64,
                (fault.code() << 8) | state.number() as u64,
            ),
            Event::InverseKinsFailed => (12, 0, 0),
            Event::NonFiniteJoint { joint } => (13, joint as u64, 0),
            Event::ProbeTrippedDuringAxisJog => (14, 0, 0),
            Event::WorldModeDropped => (15, 0, 0),
            Event::ProbeNoContact { trip_on_clear } => (16, 0, u64::from(trip_on_clear)),
            Event::ProbeTrippedDuringMove => (17, 0, 0),
            Event::SpindleOrientFault { spindle, fault } => {
                (18, spindle as u64, fault as u32 as u64)
            }
            Event::EoffsetDisabledWhileApplied { axis } => (19, axis as u64, 0),
            Event::IndexerTimeout { joint, unlocking } => (20, joint as u64, u64::from(unlocking)),
        };
        (code << 56) | ((a & 0xff_ffff) << 32) | (b & 0xffff_ffff)
    }

    /// The event a wire word (as the status snapshot carries it) stands
    /// for; `None` for 0 or a word no event encodes to.
    pub fn from_word(w: u64) -> Option<Event> {
        Event::decode(w)
    }

    /// Whether the event is a fault that stops a running program: a joint
    /// or spindle fault, a limit, the enable or a misc error input, a
    /// kinematics failure, a probe contact during a plain move. (Probe
    /// moves without contact and orient faults are reported by the
    /// program step that waits for them; jog and homing messages concern
    /// manual operation.)
    pub fn stops_a_program(&self) -> bool {
        matches!(
            self,
            Event::JointOnLimit { .. }
                | Event::JointAmpFault { .. }
                | Event::JointFollowingError { .. }
                | Event::EnableInputStopped
                | Event::MiscError { .. }
                | Event::SpindleAmpFault { .. }
                | Event::SoftLimitExceeded { .. }
                | Event::KinsSwitchFailed { .. }
                | Event::InverseKinsFailed
                | Event::NonFiniteJoint { .. }
                | Event::ProbeTrippedDuringMove
                | Event::IndexerTimeout { .. }
        )
    }

    fn decode(w: u64) -> Option<Event> {
        let a = ((w >> 32) & 0xff_ffff) as usize;
        let b = w & 0xffff_ffff;
        Some(match w >> 56 {
            1 => Event::JointOnLimit { joint: a },
            2 => Event::JointAmpFault { joint: a },
            3 => Event::JointFollowingError { joint: a },
            4 => Event::EnableInputStopped,
            5 => Event::MiscError { input: a },
            6 => Event::SpindleAmpFault { spindle: a },
            7 => Event::SoftLimitExceeded {
                joint: a,
                dir: if b == 1 {
                    Direction::Positive
                } else {
                    Direction::Negative
                },
            },
            8 => Event::JogStopped { immediate: b == 1 },
            9 => Event::ProbeTrippedDuringJog,
            10 => Event::KinsSwitchFailed {
                kins_type: b as u32 as i32,
            },
            11 => Event::HomingAborted {
                joint: a,
                fault: HomeFault::from_code(b >> 8)?,
                state: HomeState::from_number((b & 0xff) as i32)?,
            },
            12 => Event::InverseKinsFailed,
            13 => Event::NonFiniteJoint { joint: a },
            14 => Event::ProbeTrippedDuringAxisJog,
            15 => Event::WorldModeDropped,
            16 => Event::ProbeNoContact {
                trip_on_clear: b == 1,
            },
            17 => Event::ProbeTrippedDuringMove,
            18 => Event::SpindleOrientFault {
                spindle: a,
                fault: b as u32 as i32,
            },
            19 => Event::EoffsetDisabledWhileApplied { axis: a },
            20 => Event::IndexerTimeout {
                joint: a,
                unlocking: b == 1,
            },
            _ => return None,
        })
    }
}

/// How many messages the ring holds (LinuxCNC's error ring holds 32).
pub const EVENT_CAPACITY: usize = 64;

/// A single-producer ring of events. The realtime controller pushes;
/// readers take messages in order (readers serialise among themselves).
pub struct EventRing {
    slots: [AtomicU64; EVENT_CAPACITY],
    /// Messages written so far (the producer's index).
    head: AtomicUsize,
    /// Messages read so far.
    tail: AtomicUsize,
    dropped: AtomicU64,
    /// Messages reported so far, dropped ones included.
    reported: AtomicU64,
    /// The last message reported, encoded (0: none yet).
    last: AtomicU64,
    /// The last fault reported, kept when later messages are not faults.
    faults: FaultCell,
    reader: Mutex<()>,
}

impl Default for EventRing {
    fn default() -> Self {
        EventRing {
            slots: std::array::from_fn(|_| AtomicU64::new(0)),
            head: AtomicUsize::new(0),
            tail: AtomicUsize::new(0),
            dropped: AtomicU64::new(0),
            reported: AtomicU64::new(0),
            last: AtomicU64::new(0),
            faults: FaultCell::default(),
            reader: Mutex::new(()),
        }
    }
}

impl std::fmt::Debug for EventRing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EventRing")
            .field("head", &self.head.load(Relaxed))
            .field("tail", &self.tail.load(Relaxed))
            .finish()
    }
}

impl EventRing {
    /// Adds a message (realtime side; one producer). Drops it if the ring
    /// is full.
    pub fn push(&self, e: Event) {
        self.push_with(e, None);
    }

    /// Adds a following error with its size when it tripped (realtime
    /// side), so the fault record says how large it was.
    pub fn push_following_error(&self, joint: usize, trip: FollowingErrorTrip) {
        self.push_with(Event::JointFollowingError { joint }, Some(trip));
    }

    fn push_with(&self, e: Event, trip: Option<FollowingErrorTrip>) {
        // The count, the last message and the last fault are what another
        // process sees (through the status snapshot), whether or not the
        // ring is full.
        self.last.store(e.encode(), Relaxed);
        let number = self.reported.fetch_add(1, Release) + 1;
        if e.stops_a_program() {
            self.faults.record(e, number, trip);
        }
        let head = self.head.load(Relaxed);
        if head.wrapping_sub(self.tail.load(Acquire)) >= EVENT_CAPACITY {
            self.dropped.fetch_add(1, Relaxed);
            return;
        }
        self.slots[head % EVENT_CAPACITY].store(e.encode(), Relaxed);
        self.head.store(head.wrapping_add(1), Release);
    }

    /// Takes every waiting message, oldest first.
    pub fn drain(&self) -> Vec<Event> {
        let _g = self.reader.lock().unwrap_or_else(|e| e.into_inner());
        let mut out = Vec::new();
        let mut tail = self.tail.load(Relaxed);
        let head = self.head.load(Acquire);
        while tail != head {
            if let Some(e) = Event::decode(self.slots[tail % EVENT_CAPACITY].load(Relaxed)) {
                out.push(e);
            }
            tail = tail.wrapping_add(1);
        }
        self.tail.store(tail, Release);
        out
    }

    /// How many messages were reported so far, and the last one (its
    /// wire word, see [`Event::from_word`]; 0 before the first).
    pub fn reported(&self) -> (u64, u64) {
        let n = self.reported.load(Acquire);
        (n, self.last.load(Relaxed))
    }

    /// The last fault's record (see [`crate::fault`]).
    pub fn fault_words(&self) -> [u64; crate::fault::FAULT_WORDS] {
        self.faults.words()
    }

    /// How many messages were dropped because the ring was full.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_round_trip_through_the_ring_in_order() {
        let all = [
            Event::JointOnLimit { joint: 3 },
            Event::JointAmpFault { joint: 15 },
            Event::JointFollowingError { joint: 0 },
            Event::EnableInputStopped,
            Event::MiscError { input: 63 },
            Event::SpindleAmpFault { spindle: 7 },
            Event::SoftLimitExceeded {
                joint: 2,
                dir: Direction::Positive,
            },
            Event::SoftLimitExceeded {
                joint: 2,
                dir: Direction::Negative,
            },
            Event::JogStopped { immediate: true },
            Event::JogStopped { immediate: false },
            Event::ProbeTrippedDuringJog,
            Event::KinsSwitchFailed { kins_type: -2 },
            Event::HomingAborted {
                joint: 15,
                fault: HomeFault::SwitchActiveBeforeLatch,
                state: HomeState::RiseSearchStart,
            },
            Event::HomingAborted {
                joint: 0,
                fault: HomeFault::ProbeTripped,
                state: HomeState::Abort,
            },
            Event::InverseKinsFailed,
            Event::NonFiniteJoint { joint: 5 },
            Event::ProbeTrippedDuringAxisJog,
            Event::WorldModeDropped,
            Event::ProbeNoContact {
                trip_on_clear: true,
            },
            Event::ProbeTrippedDuringMove,
            Event::SpindleOrientFault {
                spindle: 1,
                fault: -7,
            },
            Event::EoffsetDisabledWhileApplied { axis: 8 },
            Event::IndexerTimeout {
                joint: 15,
                unlocking: true,
            },
            Event::IndexerTimeout {
                joint: 3,
                unlocking: false,
            },
        ];
        let r = EventRing::default();
        for e in all {
            r.push(e);
        }
        assert_eq!(r.drain(), all);
        assert!(r.drain().is_empty());
        assert_eq!(
            Event::JointFollowingError { joint: 1 }.to_string(),
            "joint 1 following error"
        );
    }

    #[test]
    fn a_full_ring_drops_the_newest_and_counts() {
        let r = EventRing::default();
        for j in 0..EVENT_CAPACITY + 5 {
            r.push(Event::JointAmpFault { joint: j });
        }
        let got = r.drain();
        assert_eq!(got.len(), EVENT_CAPACITY);
        assert_eq!(got[0], Event::JointAmpFault { joint: 0 });
        assert_eq!(r.dropped(), 5);
        r.push(Event::EnableInputStopped);
        assert_eq!(r.drain(), [Event::EnableInputStopped]);
    }

    #[test]
    fn the_count_and_last_event_include_dropped_ones() {
        let r = EventRing::default();
        assert_eq!(r.reported(), (0, 0));
        assert_eq!(Event::from_word(0), None);
        for j in 0..EVENT_CAPACITY + 2 {
            r.push(Event::JointAmpFault { joint: j });
        }
        let (n, last) = r.reported();
        assert_eq!(n, EVENT_CAPACITY as u64 + 2);
        assert_eq!(
            Event::from_word(last),
            Some(Event::JointAmpFault {
                joint: EVENT_CAPACITY + 1
            })
        );
        assert!(Event::JointFollowingError { joint: 0 }.stops_a_program());
        assert!(!Event::JogStopped { immediate: true }.stops_a_program());
    }
}
