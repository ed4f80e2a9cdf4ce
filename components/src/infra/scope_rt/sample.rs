//! `scope.sample`: the realtime state machine. It trusts nothing in the
//! region: the settings are copied and checked when the tool arms it, and
//! every later write goes to a place computed from that private copy.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use hal_core::{CellReader, HalType, Region};

use super::layout::{fires, numeric, type_of, w, Fault, State, HEADER_WORDS, MAX_CHANNELS};

/// The settings of the record being taken, copied at `Arm`.
#[derive(Clone, Copy)]
struct Armed {
    channels: usize,
    cells: [u64; MAX_CHANNELS],
    types: [HalType; MAX_CHANNELS],
    /// Samples the ring holds.
    ring: usize,
    rec_len: usize,
    pre_trig: usize,
    mult: u64,
    /// Channel, level, rising.
    trigger: Option<(usize, f64, bool)>,
}

/// The function: the region and its private state.
pub(super) struct Sampler {
    region: Region,
    machine: Machine,
}

/// The state machine's private state.
struct Machine {
    reader: CellReader,
    armed: Option<Armed>,
    mult_count: u64,
    /// Ring index of the next sample.
    curr: usize,
    start: usize,
    samples: usize,
    /// The trigger channel's value at the last sample.
    prev: Option<f64>,
    calls: u64,
}

fn ld(words: &[AtomicU64], i: usize) -> u64 {
    words.get(i).map_or(0, |v| v.load(Relaxed))
}

fn st(words: &[AtomicU64], i: usize, v: u64) {
    if let Some(word) = words.get(i) {
        word.store(v, Relaxed);
    }
}

/// The settings in `words`, checked against a buffer of `buf_len` words.
fn arm(words: &[AtomicU64], buf_len: usize) -> Result<Armed, Fault> {
    let channels = ld(words, w::CHANNELS) as usize;
    if !(1..=MAX_CHANNELS).contains(&channels) {
        return Err(Fault::Channels);
    }
    let ring = buf_len / channels;
    let rec_len = ld(words, w::REC_LEN);
    if rec_len < 2 || rec_len > ring as u64 {
        return Err(Fault::RecLen);
    }
    let pre_trig = ld(words, w::PRE_TRIG);
    if pre_trig >= rec_len {
        return Err(Fault::PreTrig);
    }
    let mult = ld(words, w::MULT);
    if mult == 0 || mult > i32::MAX as u64 {
        return Err(Fault::Mult);
    }
    let trig_chan = ld(words, w::TRIG_CHAN);
    if trig_chan > channels as u64 {
        return Err(Fault::TrigChan);
    }
    let mut cells = [0u64; MAX_CHANNELS];
    let mut types = [HalType::Bit; MAX_CHANNELS];
    for i in 0..channels {
        cells[i] = ld(words, w::CHAN_WORD + i);
        types[i] = type_of(ld(words, w::CHAN_TYPE + i)).ok_or(Fault::Type)?;
    }
    let trigger = (trig_chan > 0).then(|| {
        (
            trig_chan as usize - 1,
            f64::from_bits(ld(words, w::TRIG_LEVEL)),
            ld(words, w::TRIG_EDGE) != 0,
        )
    });
    Ok(Armed {
        channels,
        cells,
        types,
        ring,
        rec_len: rec_len as usize,
        pre_trig: pre_trig as usize,
        mult,
        trigger,
    })
}

impl Sampler {
    pub(super) fn new(region: Region) -> Sampler {
        Sampler {
            machine: Machine {
                reader: region.cell_reader(),
                armed: None,
                mult_count: 0,
                curr: 0,
                start: 0,
                samples: 0,
                prev: None,
                calls: 0,
            },
            region,
        }
    }

    /// One call of `scope.sample` in a thread of `period` ns.
    pub(super) fn run(&mut self, period: i64) {
        self.machine.run(self.region.words(), period);
    }
}

impl Machine {
    fn run(&mut self, words: &[AtomicU64], period: i64) {
        self.calls = self.calls.wrapping_add(1);
        st(words, w::CALLS, self.calls);
        st(words, w::PERIOD, period.max(0) as u64);
        let state_word = ld(words, w::STATE);
        let Some(state) = State::from_word(state_word) else {
            self.stop(words, Fault::State);
            return;
        };
        match state {
            State::Idle | State::Done | State::Fault => {}
            State::Reset => {
                self.armed = None;
                self.record_place(words);
                st(words, w::FAULT, Fault::None as u64);
                st(words, w::STATE, State::Idle as u64);
            }
            State::Arm => {
                let buf_len =
                    (ld(words, w::BUF_LEN) as usize).min(words.len().saturating_sub(HEADER_WORDS));
                match arm(words, buf_len) {
                    Ok(a) => {
                        self.armed = Some(a);
                        self.curr = 0;
                        self.start = 0;
                        self.samples = 0;
                        self.prev = None;
                        self.mult_count = 0;
                        st(words, w::TRIG_POS, 0);
                        self.record_place(words);
                        st(words, w::FAULT, Fault::None as u64);
                        let next = if a.pre_trig == 0 {
                            State::TrigWait
                        } else {
                            State::PreTrig
                        };
                        st(words, w::STATE, next as u64);
                    }
                    Err(f) => self.stop(words, f),
                }
            }
            State::PreTrig | State::TrigWait | State::PostTrig => self.sampling(words, state),
        }
    }

    /// Refuses the record: state `Fault` with `why`.
    fn stop(&mut self, words: &[AtomicU64], why: Fault) {
        self.armed = None;
        st(words, w::FAULT, why as u64);
        st(words, w::STATE, State::Fault as u64);
    }

    fn record_place(&self, words: &[AtomicU64]) {
        st(words, w::START, self.start as u64);
        st(words, w::SAMPLES, self.samples as u64);
    }

    /// A sampling state: takes a sample every `mult` calls.
    fn sampling(&mut self, words: &[AtomicU64], state: State) {
        let Some(a) = self.armed else {
            // Armed by another copy of the function state (a reload):
            // nothing to record with.
            self.stop(words, Fault::State);
            return;
        };
        self.mult_count += 1;
        if self.mult_count < a.mult {
            return;
        }
        self.mult_count = 0;
        let now = self.capture(words, &a);
        self.samples += 1;
        let next = match state {
            State::PreTrig => (self.samples >= a.pre_trig).then_some(State::TrigWait),
            State::TrigWait => {
                let fired = match a.trigger {
                    None => true,
                    Some((_, level, rising)) => self
                        .prev
                        .zip(now)
                        .is_some_and(|(p, n)| fires(rising, level, p, n)),
                };
                if fired {
                    st(words, w::TRIG_POS, (self.samples - 1) as u64);
                    Some(if self.samples >= a.rec_len {
                        State::Done
                    } else {
                        State::PostTrig
                    })
                } else {
                    // Keep only the last pre-trigger samples.
                    self.samples -= 1;
                    self.start = (self.start + 1) % a.ring;
                    None
                }
            }
            _ => (self.samples >= a.rec_len).then_some(State::Done),
        };
        self.prev = now;
        self.record_place(words);
        if let Some(s) = next {
            st(words, w::STATE, s as u64);
        }
    }

    /// Writes one sample at the ring's current place; the trigger
    /// channel's value as a number.
    fn capture(&mut self, words: &[AtomicU64], a: &Armed) -> Option<f64> {
        let base = HEADER_WORDS + self.curr * a.channels;
        let mut trig = None;
        for i in 0..a.channels {
            let bits = self.reader.read(a.cells[i]);
            st(words, base + i, bits);
            if a.trigger.is_some_and(|(c, _, _)| c == i) {
                trig = Some(numeric(a.types[i], bits));
            }
        }
        self.curr = (self.curr + 1) % a.ring;
        trig
    }
}
