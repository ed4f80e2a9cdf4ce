//! A realtime-safe message path: realtime functions say what happened
//! without allocating, locking or making a system call, and a
//! non-realtime thread of the host prints it.
//!
//! [`RtLog`] is a bounded multi-producer ring of fixed-size records (a
//! level and up to [`MSG_BYTES`] bytes of text). A producer formats into a
//! buffer on its own stack, claims a slot with one compare-and-swap and
//! copies the text in with plain atomic stores; when the ring is full (or
//! the message is above the log's level) the message is dropped and
//! counted, never waited for. The consumer ([`RtLog::drain`]) takes whole
//! records in order. The slot protocol is the bounded queue of D. Vyukov:
//! each slot carries a sequence number that says whose turn it is.
//!
//! Why not `crossbeam_queue::ArrayQueue`: under contention its producers
//! back off with `thread::yield_now`, a system call a realtime function
//! must not make; this ring never waits (a lost race retries the CAS, a
//! full ring drops the message).
//!
//! Levels are LinuxCNC's (`rtapi_msg_level_t`): `Err` 1, `Warn` 2, `Info`
//! 3, `Dbg` 4, `All` 5; a message is kept when its level is at most the
//! log's level, `Err` by default (halcmd `debug N` sets it in LinuxCNC).
//!
//! The host owns one log ([`crate::Host::rt_log`]); its first call starts
//! a thread that drains the log every [`DRAIN_INTERVAL`] into the host's
//! stderr (the log file of a host started by `realtime start`) and keeps
//! the newest [`HISTORY`] messages for [`RtLog::history`].

use std::collections::VecDeque;
use std::fmt::{self, Write as _};
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, AtomicU8, Ordering::*};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::Duration;

/// Most bytes of text one message keeps; longer text is cut at a
/// character boundary.
pub const MSG_BYTES: usize = 248;
/// Messages the host's log holds before producers start dropping.
pub const DEFAULT_CAPACITY: usize = 256;
/// How often the host's drain thread empties the log.
pub const DRAIN_INTERVAL: Duration = Duration::from_millis(20);
/// How many drained messages [`RtLog::history`] keeps.
pub const HISTORY: usize = 256;

const WORDS: usize = MSG_BYTES / 8;

/// A message level, as LinuxCNC's `rtapi_msg_level_t`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
#[repr(u8)]
pub enum MsgLevel {
    /// Nothing is logged (as a threshold only).
    None = 0,
    /// Errors: something failed; the default threshold.
    Err = 1,
    /// Warnings.
    Warn = 2,
    /// Information.
    Info = 3,
    /// Debugging detail.
    Dbg = 4,
    /// Everything.
    All = 5,
}

impl MsgLevel {
    /// The level with number `n` (0..=5; larger numbers are `All`).
    pub fn from_number(n: u8) -> MsgLevel {
        match n {
            0 => MsgLevel::None,
            1 => MsgLevel::Err,
            2 => MsgLevel::Warn,
            3 => MsgLevel::Info,
            4 => MsgLevel::Dbg,
            _ => MsgLevel::All,
        }
    }
}

/// One slot of the ring: whose turn it is, the level and length, the text.
struct Slot {
    /// Vyukov's sequence: `pos` = free for the producer of position
    /// `pos`; `pos + 1` = holds that producer's message.
    seq: AtomicU64,
    /// Level in bits 0..8, text length in bits 8..16.
    meta: AtomicU32,
    text: [AtomicU64; WORDS],
}

struct Ring {
    slots: Box<[Slot]>,
    /// Next position a producer claims.
    head: AtomicU64,
    /// Next position the consumer reads (only the consumer moves it).
    tail: AtomicU64,
    level: AtomicU8,
    dropped: AtomicU64,
    /// Serialises consumers (the drain thread and explicit flushes).
    consumer: Mutex<VecDeque<(MsgLevel, String)>>,
}

/// A realtime-safe message log; cloning gives another handle to the same
/// log.
#[derive(Clone)]
pub struct RtLog {
    ring: Arc<Ring>,
}

impl fmt::Debug for RtLog {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RtLog")
            .field("capacity", &self.ring.slots.len())
            .field("level", &self.level())
            .field("dropped", &self.dropped())
            .finish()
    }
}

/// A fixed buffer that `write!` fills up to its size, cutting at a
/// character boundary.
struct StackText {
    buf: [u8; MSG_BYTES],
    len: usize,
}

impl fmt::Write for StackText {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let room = MSG_BYTES - self.len;
        let mut take = s.len().min(room);
        while !s.is_char_boundary(take) {
            take -= 1;
        }
        self.buf[self.len..self.len + take].copy_from_slice(&s.as_bytes()[..take]);
        self.len += take;
        if take < s.len() {
            // Stop formatting: the rest would not fit either.
            Err(fmt::Error)
        } else {
            Ok(())
        }
    }
}

impl RtLog {
    /// A log holding up to `capacity` undrained messages (at least 2).
    pub fn new(capacity: usize) -> RtLog {
        let capacity = capacity.max(2);
        let slots = (0..capacity as u64)
            .map(|i| Slot {
                seq: AtomicU64::new(i),
                meta: AtomicU32::new(0),
                text: std::array::from_fn(|_| AtomicU64::new(0)),
            })
            .collect();
        RtLog {
            ring: Arc::new(Ring {
                slots,
                head: AtomicU64::new(0),
                tail: AtomicU64::new(0),
                level: AtomicU8::new(MsgLevel::Err as u8),
                dropped: AtomicU64::new(0),
                consumer: Mutex::new(VecDeque::new()),
            }),
        }
    }

    /// The threshold: messages above it are not logged.
    pub fn level(&self) -> MsgLevel {
        MsgLevel::from_number(self.ring.level.load(Relaxed))
    }

    /// Sets the threshold.
    pub fn set_level(&self, level: MsgLevel) {
        self.ring.level.store(level as u8, Relaxed);
    }

    /// Messages lost because the ring was full (not those filtered out by
    /// the level).
    pub fn dropped(&self) -> u64 {
        self.ring.dropped.load(Relaxed)
    }

    /// Logs a message; realtime-safe (no allocation, lock or system call,
    /// provided the arguments' `Display` impls make none). Returns whether
    /// the message was kept: false when filtered by the level or dropped
    /// because the ring is full.
    pub fn log(&self, level: MsgLevel, args: fmt::Arguments<'_>) -> bool {
        if level == MsgLevel::None || level as u8 > self.ring.level.load(Relaxed) {
            return false;
        }
        let mut text = StackText {
            buf: [0; MSG_BYTES],
            len: 0,
        };
        // An error only means the text was cut; keep what fits.
        let _ = text.write_fmt(args);
        self.push(level, &text.buf[..text.len])
    }

    /// [`log`](Self::log) at `Err`.
    pub fn err(&self, args: fmt::Arguments<'_>) -> bool {
        self.log(MsgLevel::Err, args)
    }

    /// [`log`](Self::log) at `Warn`.
    pub fn warn(&self, args: fmt::Arguments<'_>) -> bool {
        self.log(MsgLevel::Warn, args)
    }

    /// [`log`](Self::log) at `Info`.
    pub fn info(&self, args: fmt::Arguments<'_>) -> bool {
        self.log(MsgLevel::Info, args)
    }

    /// [`log`](Self::log) at `Dbg`.
    pub fn dbg(&self, args: fmt::Arguments<'_>) -> bool {
        self.log(MsgLevel::Dbg, args)
    }

    fn push(&self, level: MsgLevel, bytes: &[u8]) -> bool {
        let ring = &*self.ring;
        let cap = ring.slots.len() as u64;
        let mut pos = ring.head.load(Relaxed);
        let slot = loop {
            let slot = &ring.slots[(pos % cap) as usize];
            let seq = slot.seq.load(Acquire);
            if seq == pos {
                match ring
                    .head
                    .compare_exchange_weak(pos, pos + 1, Relaxed, Relaxed)
                {
                    Ok(_) => break slot,
                    Err(now) => pos = now,
                }
            } else if seq < pos {
                // The consumer has not freed this slot yet: full.
                ring.dropped.fetch_add(1, Relaxed);
                return false;
            } else {
                // Another producer took this position; try the next.
                pos = ring.head.load(Relaxed);
            }
        };
        for (i, word) in slot.text.iter().enumerate() {
            let start = i * 8;
            if start >= bytes.len() {
                break;
            }
            let mut w = [0u8; 8];
            let end = (start + 8).min(bytes.len());
            w[..end - start].copy_from_slice(&bytes[start..end]);
            word.store(u64::from_le_bytes(w), Relaxed);
        }
        slot.meta
            .store(level as u32 | (bytes.len() as u32) << 8, Relaxed);
        slot.seq.store(pos + 1, Release);
        true
    }

    fn consumer(&self) -> MutexGuard<'_, VecDeque<(MsgLevel, String)>> {
        self.ring.consumer.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Takes every complete message in order, oldest first, and hands
    /// each to `f`; also keeps it for [`history`](Self::history). Returns
    /// how many were taken. Not realtime-safe (it allocates the text).
    pub fn drain(&self, mut f: impl FnMut(MsgLevel, &str)) -> usize {
        let mut history = self.consumer();
        let ring = &*self.ring;
        let cap = ring.slots.len() as u64;
        let mut n = 0;
        loop {
            let pos = ring.tail.load(Relaxed);
            let slot = &ring.slots[(pos % cap) as usize];
            if slot.seq.load(Acquire) != pos + 1 {
                break;
            }
            let meta = slot.meta.load(Relaxed);
            let len = ((meta >> 8) as usize).min(MSG_BYTES);
            let mut bytes = Vec::with_capacity(len);
            for word in &slot.text {
                bytes.extend_from_slice(&word.load(Relaxed).to_le_bytes());
                if bytes.len() >= len {
                    break;
                }
            }
            bytes.truncate(len);
            slot.seq.store(pos + cap, Release);
            ring.tail.store(pos + 1, Relaxed);
            let level = MsgLevel::from_number(meta as u8);
            let text = String::from_utf8_lossy(&bytes).into_owned();
            f(level, &text);
            if history.len() == HISTORY {
                history.pop_front();
            }
            history.push_back((level, text));
            n += 1;
        }
        n
    }

    /// The newest drained messages, oldest first.
    pub fn history(&self) -> Vec<(MsgLevel, String)> {
        self.consumer().iter().cloned().collect()
    }
}

/// Writes one drained message to stderr, with a newline if it has none.
fn print(_level: MsgLevel, text: &str) {
    if text.ends_with('\n') {
        eprint!("{text}");
    } else {
        eprintln!("{text}");
    }
}

/// The host's log and its drain thread, started on first use.
pub(crate) struct RtLogService {
    log: RtLog,
    stop: Arc<AtomicBool>,
    thread: Mutex<Option<JoinHandle<()>>>,
    started: AtomicBool,
}

impl RtLogService {
    pub(crate) fn new() -> RtLogService {
        RtLogService {
            log: RtLog::new(DEFAULT_CAPACITY),
            stop: Arc::new(AtomicBool::new(false)),
            thread: Mutex::new(None),
            started: AtomicBool::new(false),
        }
    }

    /// The log without starting the drain thread: for a producer made
    /// before anything is logged (the executors' delay report), whose
    /// messages are printed once [`handle`](Self::handle) or
    /// [`flush`](Self::flush) runs.
    pub(crate) fn ring(&self) -> RtLog {
        self.log.clone()
    }

    /// The log, starting the drain thread the first time.
    pub(crate) fn handle(&self) -> RtLog {
        if !self.started.swap(true, AcqRel) {
            let log = self.log.clone();
            let stop = self.stop.clone();
            let spawned = std::thread::Builder::new()
                .name("hal-rtlog".into())
                .spawn(move || {
                    while !stop.load(Acquire) {
                        std::thread::sleep(DRAIN_INTERVAL);
                        log.drain(print);
                    }
                });
            match spawned {
                Ok(j) => *self.thread.lock().unwrap_or_else(|e| e.into_inner()) = Some(j),
                // Without the thread, messages still reach stderr at
                // every flush and at shutdown.
                Err(e) => eprintln!("HAL: cannot start the realtime message thread: {e}"),
            }
        }
        self.log.clone()
    }

    /// Prints what is waiting now.
    pub(crate) fn flush(&self) {
        self.log.drain(print);
    }

    /// Stops the drain thread and prints what is left.
    pub(crate) fn stop(&self) {
        self.stop.store(true, Release);
        let j = self.thread.lock().unwrap_or_else(|e| e.into_inner()).take();
        if let Some(j) = j {
            let _ = j.join();
        }
        self.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drained(log: &RtLog) -> Vec<(MsgLevel, String)> {
        let mut v = Vec::new();
        log.drain(|l, t| v.push((l, t.to_string())));
        v
    }

    #[test]
    fn messages_come_out_in_order_with_levels() {
        let log = RtLog::new(8);
        log.set_level(MsgLevel::Info);
        assert!(log.err(format_args!("hm2_5i25.0: watchdog has bit")));
        assert!(log.info(format_args!("count {}", 42)));
        assert!(!log.dbg(format_args!("filtered")));
        assert!(!log.log(MsgLevel::None, format_args!("never")));
        assert_eq!(
            drained(&log),
            vec![
                (MsgLevel::Err, "hm2_5i25.0: watchdog has bit".to_string()),
                (MsgLevel::Info, "count 42".to_string())
            ]
        );
        assert!(drained(&log).is_empty());
        assert_eq!(log.history().len(), 2);
    }

    #[test]
    fn a_full_ring_drops_and_counts_and_recovers() {
        let log = RtLog::new(3);
        for i in 0..5 {
            let kept = log.err(format_args!("m{i}"));
            assert_eq!(kept, i < 3, "{i}");
        }
        assert_eq!(log.dropped(), 2);
        let got: Vec<String> = drained(&log).into_iter().map(|(_, t)| t).collect();
        assert_eq!(got, ["m0", "m1", "m2"]);
        // Slots are reused after the drain, many times over.
        for lap in 0..10 {
            assert!(log.err(format_args!("lap {lap}")));
            assert_eq!(drained(&log)[0].1, format!("lap {lap}"));
        }
    }

    #[test]
    fn long_text_is_cut_at_a_character_boundary() {
        let log = RtLog::new(2);
        let long = "é".repeat(200); // 400 bytes
        log.err(format_args!("{long}"));
        let (_, t) = drained(&log).remove(0);
        assert!(
            t.len() <= MSG_BYTES && t.len() >= MSG_BYTES - 1,
            "{}",
            t.len()
        );
        assert!(t.chars().all(|c| c == 'é'));
    }

    #[test]
    fn many_producers_lose_nothing_that_fits() {
        let log = RtLog::new(4096);
        std::thread::scope(|s| {
            for p in 0..4 {
                let log = log.clone();
                s.spawn(move || {
                    for i in 0..500 {
                        assert!(log.err(format_args!("{p}:{i}")));
                    }
                });
            }
        });
        let got = drained(&log);
        assert_eq!(got.len(), 2000);
        // Each producer's messages stay in its own order.
        for p in 0..4 {
            let mine: Vec<usize> = got
                .iter()
                .filter_map(|(_, t)| t.strip_prefix(&format!("{p}:")))
                .map(|n| n.parse().unwrap())
                .collect();
            assert_eq!(mine, (0..500).collect::<Vec<_>>());
        }
    }

    #[test]
    fn producers_and_a_consumer_at_once() {
        let log = RtLog::new(16);
        let mut got = Vec::new();
        std::thread::scope(|s| {
            let producer = {
                let log = log.clone();
                s.spawn(move || {
                    let mut kept = 0u32;
                    for i in 0..2000 {
                        if log.err(format_args!("{i}")) {
                            kept += 1;
                        }
                    }
                    kept
                })
            };
            while !producer.is_finished() {
                log.drain(|_, t| got.push(t.parse::<u32>().unwrap()));
            }
            let kept = producer.join().unwrap();
            log.drain(|_, t| got.push(t.parse::<u32>().unwrap()));
            assert_eq!(got.len() as u32, kept);
            assert_eq!(kept as u64 + log.dropped(), 2000);
        });
        assert!(got.windows(2).all(|w| w[0] < w[1]), "in order");
    }

    #[test]
    fn the_host_drains_its_log_and_flushes_at_shutdown() {
        let host = crate::Host::create(crate::HostConfig::for_tests("rtlog")).unwrap();
        let log = host.rt_log();
        assert!(log.err(format_args!("drv.0: said once")));
        let end = std::time::Instant::now() + Duration::from_secs(10);
        while log.history().is_empty() {
            assert!(std::time::Instant::now() < end, "drain thread never ran");
            std::thread::sleep(Duration::from_millis(5));
        }
        assert_eq!(log.history()[0].1, "drv.0: said once");
        // A message logged just before shutdown is still printed.
        assert!(log.err(format_args!("drv.0: last words")));
        host.shutdown();
        assert_eq!(log.history().last().unwrap().1, "drv.0: last words");
    }
}
