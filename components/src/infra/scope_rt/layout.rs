//! The one description of scope_rt's shared region, used by both sides:
//! the realtime `scope.sample` function and the halscope that drives it.
//!
//! The region (named [`REGION`]) is an array of 64-bit words: a header of
//! [`HEADER_WORDS`] words, then the sample buffer of `num_samples` words.
//! A record of `n` channels keeps sample `k` of the ring in the `n` words
//! from `HEADER_WORDS + k * n`; the ring holds `num_samples / n` samples.
//!
//! | word | written by | holds |
//! |---|---|---|
//! | [`w::MAGIC`], [`w::VERSION`], [`w::HEADER`], [`w::BUF_LEN`] | scope_rt at load | identity: [`MAGIC`], [`VERSION`], [`HEADER_WORDS`], `num_samples` |
//! | [`w::STATE`] | both | a [`State`]: the tool writes `Arm` and `Reset`, the function the rest |
//! | [`w::MULT`] .. [`w::TRIG_EDGE`], [`w::CHAN_WORD`], [`w::CHAN_TYPE`] | the tool, before `Arm` | the capture's settings |
//! | [`w::START`] .. [`w::PERIOD`] | the function | the record's place in the ring, a fault, a call count |
//!
//! The function copies the settings when it sees `Arm` and checks them
//! (a bad one stops with state `Fault` and a [`Fault`] code); the tool's
//! reader checks every word it uses ([`Status::parse`]) and reads a record
//! only inside the buffer ([`record`]). Neither side trusts the other.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use hal_core::{HalType, Value};

use crate::error::CompError;

/// The region's name in the instance.
pub const REGION: &str = "scope_rt.shm";
/// The first word: "HALSCOPE" in little-endian bytes.
pub const MAGIC: u64 = u64::from_le_bytes(*b"HALSCOPE");
/// The layout's version; a region of another version is refused.
pub const VERSION: u64 = 1;
/// Words before the sample buffer.
pub const HEADER_WORDS: usize = 64;
/// Most channels in a record.
pub const MAX_CHANNELS: usize = 16;
/// `num_samples` when `loadrt` does not say (LinuxCNC's default).
pub const DEFAULT_NUM_SAMPLES: i64 = 16000;
/// The largest `num_samples` taken (128 MiB of buffer).
pub const MAX_NUM_SAMPLES: i64 = 1 << 24;

/// Word indexes of the header.
pub mod w {
    /// [`super::MAGIC`].
    pub const MAGIC: usize = 0;
    /// [`super::VERSION`].
    pub const VERSION: usize = 1;
    /// [`super::HEADER_WORDS`].
    pub const HEADER: usize = 2;
    /// The buffer's length in words (`num_samples`).
    pub const BUF_LEN: usize = 3;
    /// A [`super::State`].
    pub const STATE: usize = 4;
    /// Sample every MULT-th call.
    pub const MULT: usize = 5;
    /// Samples in a record.
    pub const REC_LEN: usize = 6;
    /// Samples before the trigger.
    pub const PRE_TRIG: usize = 7;
    /// Channels in a record.
    pub const CHANNELS: usize = 8;
    /// The trigger's channel, from 1; 0: none (the record starts at once).
    pub const TRIG_CHAN: usize = 9;
    /// The trigger's level, as f64 bits.
    pub const TRIG_LEVEL: usize = 10;
    /// 1: rising edge, 0: falling edge.
    pub const TRIG_EDGE: usize = 11;
    /// The ring index of the record's first sample.
    pub const START: usize = 12;
    /// Samples in the record so far.
    pub const SAMPLES: usize = 13;
    /// The trigger sample's place in the record.
    pub const TRIG_POS: usize = 14;
    /// A [`super::Fault`] code.
    pub const FAULT: usize = 15;
    /// Calls of the function, counted always.
    pub const CALLS: usize = 16;
    /// The thread's period in ns, at the last call.
    pub const PERIOD: usize = 17;
    /// 16 words: the segment offset of each channel's value cell.
    pub const CHAN_WORD: usize = 20;
    /// 16 words: each channel's type code ([`super::type_code`]).
    pub const CHAN_TYPE: usize = 36;
}

/// Where the sampling is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    /// Nothing to do.
    Idle = 0,
    /// The tool asks for a record with the settings it wrote.
    Arm = 1,
    /// Filling the samples before the trigger.
    PreTrig = 2,
    /// Waiting for the trigger, keeping the last pre-trigger samples.
    TrigWait = 3,
    /// Filling the samples after the trigger.
    PostTrig = 4,
    /// The record is complete.
    Done = 5,
    /// The tool stops the sampling; the function answers with `Idle`.
    Reset = 6,
    /// The settings were refused: see [`w::FAULT`].
    Fault = 7,
}

impl State {
    /// The state a word holds, if it is one.
    pub fn from_word(v: u64) -> Option<State> {
        Some(match v {
            0 => State::Idle,
            1 => State::Arm,
            2 => State::PreTrig,
            3 => State::TrigWait,
            4 => State::PostTrig,
            5 => State::Done,
            6 => State::Reset,
            7 => State::Fault,
            _ => return None,
        })
    }
}

/// Why the function refused the settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// None.
    None = 0,
    /// Channels not in 1 to 16.
    Channels = 1,
    /// A record shorter than 2 samples or longer than the ring.
    RecLen = 2,
    /// Pre-trigger samples not fewer than the record's.
    PreTrig = 3,
    /// A trigger channel past the channels.
    TrigChan = 4,
    /// A channel type code that names no type.
    Type = 5,
    /// A multiplier of 0 or past 2^31.
    Mult = 6,
    /// A state word that names no state.
    State = 7,
}

impl Fault {
    /// The fault a word holds, if it is one.
    pub fn from_word(v: u64) -> Option<Fault> {
        Some(match v {
            0 => Fault::None,
            1 => Fault::Channels,
            2 => Fault::RecLen,
            3 => Fault::PreTrig,
            4 => Fault::TrigChan,
            5 => Fault::Type,
            6 => Fault::Mult,
            7 => Fault::State,
            _ => return None,
        })
    }

    /// What it means.
    pub fn describe(self) -> &'static str {
        match self {
            Fault::None => "no fault",
            Fault::Channels => "the channel count is not 1 to 16",
            Fault::RecLen => "the record is shorter than 2 samples or longer than the buffer holds",
            Fault::PreTrig => "the pre-trigger samples are not fewer than the record's",
            Fault::TrigChan => "the trigger channel is not one of the channels",
            Fault::Type => "a channel's type code names no HAL type",
            Fault::Mult => "the sample rate multiplier is not 1 to 2147483647",
            Fault::State => "the state word named no state",
        }
    }
}

/// A type's code in [`w::CHAN_TYPE`]: the segment's own numbering.
pub fn type_code(t: HalType) -> u64 {
    u64::from(t.code())
}

/// The type a code names, if any.
pub fn type_of(code: u64) -> Option<HalType> {
    u32::try_from(code).ok().and_then(HalType::from_code)
}

/// A sample's value as a number (a bit as 0 or 1), for the trigger.
pub fn numeric(t: HalType, bits: u64) -> f64 {
    match Value::from_bits(t, bits) {
        Value::Bit(b) => f64::from(u8::from(b)),
        Value::Float(f) => f,
        Value::S32(v) => f64::from(v),
        Value::U32(v) | Value::Port(v) => f64::from(v),
        Value::S64(v) => v as f64,
        Value::U64(v) => v as f64,
    }
}

/// Whether going from `prev` to `now` crosses `level` on the edge:
/// rising, from below to at or above; falling, from above to at or below.
pub fn fires(rising: bool, level: f64, prev: f64, now: f64) -> bool {
    if rising {
        prev < level && now >= level
    } else {
        prev > level && now <= level
    }
}

/// Fills a new region's header for a buffer of `buf_len` words.
pub fn init(words: &[AtomicU64], buf_len: u64) {
    for (i, v) in [
        (w::MAGIC, MAGIC),
        (w::VERSION, VERSION),
        (w::HEADER, HEADER_WORDS as u64),
        (w::BUF_LEN, buf_len),
        (w::STATE, State::Idle as u64),
        (w::MULT, 1),
    ] {
        if let Some(word) = words.get(i) {
            word.store(v, Relaxed);
        }
    }
}

/// A trigger as the tool sets it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriggerSetting {
    /// The channel, from 0.
    pub channel: usize,
    /// The level.
    pub level: f64,
    /// Rising (true) or falling edge.
    pub rising: bool,
}

/// A capture's settings, as the tool writes them.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// Per channel: the segment offset of its value cell and its type.
    pub channels: Vec<(u64, HalType)>,
    /// Samples in the record.
    pub rec_len: usize,
    /// Samples before the trigger.
    pub pre_trig: usize,
    /// Sample every `mult`-th call.
    pub mult: u32,
    /// The trigger; none starts the record at once.
    pub trigger: Option<TriggerSetting>,
}

impl Settings {
    /// Checks the settings against a buffer of `buf_len` words, as the
    /// function will.
    pub fn check(&self, buf_len: u64) -> Result<(), CompError> {
        let bad = |setting, value: usize, reason: String| CompError::ScopeSetting {
            setting,
            value: value as u64,
            reason,
        };
        let n = self.channels.len();
        if n == 0 || n > MAX_CHANNELS {
            return Err(bad("channels", n, format!("give 1 to {MAX_CHANNELS}")));
        }
        let ring = buf_len / n as u64;
        if self.rec_len < 2 || self.rec_len as u64 > ring {
            return Err(bad(
                "samples",
                self.rec_len,
                format!(
                    "give 2 to {ring}: num_samples={buf_len} words hold {ring} samples of {n} \
                     channels (load scope_rt with a larger num_samples for more)"
                ),
            ));
        }
        if self.pre_trig >= self.rec_len {
            return Err(bad(
                "pre-trigger samples",
                self.pre_trig,
                format!("give fewer than the record's {}", self.rec_len),
            ));
        }
        if self.mult == 0 || self.mult > i32::MAX as u32 {
            return Err(bad(
                "sample rate multiplier",
                self.mult as usize,
                "give 1 to 2147483647".into(),
            ));
        }
        if let Some(t) = self.trigger.filter(|t| t.channel >= n) {
            return Err(bad(
                "trigger channel",
                t.channel,
                format!("give a channel from 0 to {}", n - 1),
            ));
        }
        Ok(())
    }

    /// Writes the settings into `words` (after checking them against the
    /// region's buffer). The state word is left alone.
    pub fn write(&self, words: &[AtomicU64]) -> Result<(), CompError> {
        let buf_len = words.get(w::BUF_LEN).map_or(0, |v| v.load(Relaxed));
        self.check(buf_len)?;
        if words.len() < HEADER_WORDS {
            return Err(CompError::ScopeShm {
                field: "region length",
                value: words.len() as u64,
                expected: format!("at least {HEADER_WORDS} words"),
            });
        }
        let st = |i: usize, v: u64| words[i].store(v, Relaxed);
        st(w::MULT, u64::from(self.mult));
        st(w::REC_LEN, self.rec_len as u64);
        st(w::PRE_TRIG, self.pre_trig as u64);
        st(w::CHANNELS, self.channels.len() as u64);
        match self.trigger {
            Some(t) => {
                st(w::TRIG_CHAN, t.channel as u64 + 1);
                st(w::TRIG_LEVEL, t.level.to_bits());
                st(w::TRIG_EDGE, u64::from(t.rising));
            }
            None => st(w::TRIG_CHAN, 0),
        }
        for (i, (off, t)) in self.channels.iter().enumerate() {
            st(w::CHAN_WORD + i, *off);
            st(w::CHAN_TYPE + i, type_code(*t));
        }
        Ok(())
    }
}

/// The region as the tool reads it: identity checked, state and record
/// place within bounds.
#[derive(Debug, Clone, PartialEq)]
pub struct Status {
    /// The state.
    pub state: State,
    /// The buffer's length in words.
    pub buf_len: usize,
    /// The function's calls so far.
    pub calls: u64,
    /// The thread's period in ns at the last call.
    pub period_ns: u64,
    /// The fault, in state `Fault`.
    pub fault: Fault,
    /// The record's channel types (in state `Done`; empty otherwise).
    pub types: Vec<HalType>,
    /// Samples in the record.
    pub samples: usize,
    /// The record's first sample in the ring.
    pub start: usize,
    /// The trigger sample's place in the record.
    pub trig_pos: usize,
}

fn field(words: &[u64], i: usize, name: &'static str) -> Result<u64, CompError> {
    words.get(i).copied().ok_or_else(|| CompError::ScopeShm {
        field: name,
        value: words.len() as u64,
        expected: format!("past the end of a region of that many words (it is word {i})"),
    })
}

fn within(name: &'static str, value: u64, lo: u64, hi: u64) -> Result<usize, CompError> {
    if (lo..=hi).contains(&value) {
        Ok(value as usize)
    } else {
        Err(CompError::ScopeShm {
            field: name,
            value,
            expected: format!("expected {lo} to {hi}"),
        })
    }
}

/// The state and fault words, checked.
fn state_and_fault(words: &[u64]) -> Result<(State, Fault), CompError> {
    let state_word = field(words, w::STATE, "the state")?;
    let state = State::from_word(state_word).ok_or_else(|| CompError::ScopeShm {
        field: "the state",
        value: state_word,
        expected: "expected 0 to 7".into(),
    })?;
    let fault_word = field(words, w::FAULT, "the fault code")?;
    let fault = Fault::from_word(fault_word).ok_or_else(|| CompError::ScopeShm {
        field: "the fault code",
        value: fault_word,
        expected: "expected 0 to 7".into(),
    })?;
    Ok((state, fault))
}

/// The state and fault of a live region, from its header alone: what a
/// tool polling for the end of a record needs, without copying the
/// samples each time (a region may hold millions of words).
pub fn poll(words: &[AtomicU64]) -> Result<(State, Fault), CompError> {
    let mut header = [0u64; HEADER_WORDS];
    for (h, w) in header.iter_mut().zip(words) {
        *h = w.load(Relaxed);
    }
    state_and_fault(&header[..words.len().min(HEADER_WORDS)])
}

impl Status {
    /// Reads a copy of the region's words, checking every word used:
    /// identity, buffer length against the copy's, and in state `Done`
    /// the record's channels, types and place in the ring.
    pub fn parse(words: &[u64]) -> Result<Status, CompError> {
        let magic = field(words, w::MAGIC, "the magic number")?;
        if magic != MAGIC {
            return Err(CompError::ScopeShm {
                field: "the magic number",
                value: magic,
                expected: format!("expected {MAGIC:#x} (\"HALSCOPE\"): not a scope_rt region"),
            });
        }
        let version = field(words, w::VERSION, "the layout version")?;
        if version != VERSION {
            return Err(CompError::ScopeShm {
                field: "the layout version",
                value: version,
                expected: format!(
                    "this halscope reads version {VERSION}: scope_rt and halscope come from \
                     different builds"
                ),
            });
        }
        let header = field(words, w::HEADER, "the header length")?;
        within(
            "the header length",
            header,
            HEADER_WORDS as u64,
            HEADER_WORDS as u64,
        )?;
        let room = (words.len().saturating_sub(HEADER_WORDS)) as u64;
        let buf_len = within(
            "the buffer length",
            field(words, w::BUF_LEN, "the buffer length")?,
            1,
            room,
        )?;
        let (state, fault) = state_and_fault(words)?;
        let mut st = Status {
            state,
            buf_len,
            calls: field(words, w::CALLS, "the call count")?,
            period_ns: field(words, w::PERIOD, "the period")?,
            fault,
            types: Vec::new(),
            samples: 0,
            start: 0,
            trig_pos: 0,
        };
        if state == State::Done {
            st.read_record_place(words)?;
        }
        Ok(st)
    }

    fn read_record_place(&mut self, words: &[u64]) -> Result<(), CompError> {
        let n = within(
            "the channel count",
            field(words, w::CHANNELS, "the channel count")?,
            1,
            MAX_CHANNELS as u64,
        )?;
        let ring = (self.buf_len / n) as u64;
        for i in 0..n {
            let code = field(words, w::CHAN_TYPE + i, "a channel type")?;
            self.types
                .push(type_of(code).ok_or_else(|| CompError::ScopeShm {
                    field: "a channel type",
                    value: code,
                    expected: "expected 1 to 7".into(),
                })?);
        }
        self.samples = within(
            "the sample count",
            field(words, w::SAMPLES, "the sample count")?,
            1,
            ring,
        )?;
        self.start = within(
            "the record start",
            field(words, w::START, "the record start")?,
            0,
            ring - 1,
        )?;
        self.trig_pos = within(
            "the trigger position",
            field(words, w::TRIG_POS, "the trigger position")?,
            0,
            self.samples as u64 - 1,
        )?;
        Ok(())
    }
}

/// The record of a `Done` region `words` as `st` found it: one row per
/// sample, one word per channel, oldest first. Reads only inside the
/// buffer: the ring's samples wrap at `buf_len / channels`.
pub fn record(words: &[u64], st: &Status) -> Result<Vec<Vec<u64>>, CompError> {
    let n = st.types.len();
    if st.state != State::Done || n == 0 {
        return Err(CompError::ScopeShm {
            field: "the state",
            value: st.state as u64,
            expected: "expected 5 (a complete record)".into(),
        });
    }
    let ring = st.buf_len / n;
    let buffer = words
        .get(HEADER_WORDS..HEADER_WORDS + st.buf_len)
        .ok_or_else(|| CompError::ScopeShm {
            field: "the buffer length",
            value: st.buf_len as u64,
            expected: format!("more than the {} words of the region", words.len()),
        })?;
    let mut rows = Vec::with_capacity(st.samples.min(ring));
    for k in 0..st.samples.min(ring) {
        let at = (st.start + k) % ring * n;
        let row = buffer.get(at..at + n).ok_or_else(|| CompError::ScopeShm {
            field: "the record start",
            value: st.start as u64,
            expected: format!("a sample inside the {ring}-sample ring"),
        })?;
        rows.push(row.to_vec());
    }
    Ok(rows)
}
