//! The trigger and the record, as an oscilloscope keeps them: the
//! pre-trigger part fills first (a trigger before it is full is not taken),
//! the trigger sample is the first one at or past the level in the edge's
//! direction (the one before it on the other side), and the record ends
//! `samples` samples after its start.

use std::collections::VecDeque;

use hal_components::infra::scope_rt::layout;
use hal_core::HalType;

/// The direction the trigger signal crosses the level in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Edge {
    /// From below the level to at or above it.
    Rising,
    /// From above the level to at or below it.
    Falling,
}

/// A trigger as the command line names it.
#[derive(Debug, Clone, PartialEq)]
pub struct TriggerSpec {
    /// The captured pin (or its column number) it watches.
    pub name: String,
    /// The edge.
    pub edge: Edge,
    /// The level.
    pub level: f64,
}

/// A trigger on one column of the records.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trigger {
    /// The column (0 = first pin).
    pub column: usize,
    /// Its type, to read the value.
    pub hal_type: HalType,
    /// The edge.
    pub edge: Edge,
    /// The level.
    pub level: f64,
}

/// A sample value as a number (bits as 0 and 1): scope_rt's reading,
/// so both ways of capturing trigger alike.
pub use hal_components::infra::scope_rt::layout::numeric;

impl Trigger {
    /// Whether going from `prev` to `now` fires the trigger.
    pub fn fires(&self, prev: f64, now: f64) -> bool {
        layout::fires(self.edge == Edge::Rising, self.level, prev, now)
    }
}

/// A record being captured. Records are sampler FIFO records: the sample
/// number, then one word per column.
#[derive(Debug)]
pub struct Capture {
    samples: usize,
    pre: usize,
    trigger: Option<Trigger>,
    rows: VecDeque<Vec<u64>>,
    triggered: bool,
    last_number: Option<u64>,
    prev_value: Option<f64>,
}

impl Capture {
    /// A record of `samples` samples, `pre` of them before the trigger
    /// (ignored without a trigger: the record starts at once).
    pub fn new(samples: usize, pre: usize, trigger: Option<Trigger>) -> Capture {
        let pre = if trigger.is_some() {
            pre.min(samples.saturating_sub(1))
        } else {
            0
        };
        Capture {
            samples,
            pre,
            trigger,
            rows: VecDeque::with_capacity(samples),
            triggered: trigger.is_none(),
            last_number: None,
            prev_value: None,
        }
    }

    /// Forgets everything and waits for a new trigger (after lost samples).
    pub fn restart(&mut self) {
        self.rows.clear();
        self.triggered = self.trigger.is_none();
        self.last_number = None;
        self.prev_value = None;
    }

    /// Whether the record is complete.
    pub fn done(&self) -> bool {
        self.triggered && self.rows.len() >= self.samples
    }

    /// The samples still missing from a triggered record; `None` while
    /// the trigger has not come.
    pub fn missing(&self) -> Option<usize> {
        self.triggered
            .then(|| self.samples.saturating_sub(self.rows.len()))
    }

    /// Whether the trigger has come.
    pub fn triggered(&self) -> bool {
        self.triggered
    }

    /// Takes one FIFO record. A gap in the sample numbers (the FIFO
    /// overflowed) restarts the capture.
    pub fn push(&mut self, record: &[u64]) {
        if self.done() {
            return;
        }
        let number = record.first().copied().unwrap_or(0);
        if self
            .last_number
            .is_some_and(|l| number != (l as u32).wrapping_add(1) as u64)
        {
            self.restart();
        }
        self.last_number = Some(number);
        if let Some(trig) = self.trigger.filter(|_| !self.triggered) {
            let now = record
                .get(1 + trig.column)
                .map_or(0.0, |&b| numeric(trig.hal_type, b));
            let armed = self.rows.len() >= self.pre;
            if armed && self.prev_value.is_some_and(|p| trig.fires(p, now)) {
                self.triggered = true;
            } else if self.rows.len() >= self.pre {
                // Keep only the last `pre` samples before a trigger.
                self.rows.pop_front();
            }
            self.prev_value = Some(now);
        }
        if self.pre == 0 && !self.triggered {
            return;
        }
        self.rows.push_back(record.to_vec());
    }

    /// The finished record: rows and the index of the trigger sample.
    pub fn into_record(self) -> (Vec<Vec<u64>>, usize) {
        (self.rows.into(), self.pre)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(n: u64) -> Vec<u64> {
        // Period 10: 0 for five samples, 1 for five.
        vec![n, f64::to_bits(if (n / 5) % 2 == 1 { 1.0 } else { 0.0 })]
    }

    fn trig(edge: Edge) -> Option<Trigger> {
        Some(Trigger {
            column: 0,
            hal_type: HalType::Float,
            edge,
            level: 0.5,
        })
    }

    #[test]
    fn rising_edge_with_pre_trigger() {
        let mut c = Capture::new(8, 3, trig(Edge::Rising));
        let mut n = 1;
        while !c.done() {
            c.push(&square(n));
            n += 1;
        }
        assert_eq!(c.missing(), Some(0));
        let (rows, at) = c.into_record();
        assert_eq!(at, 3);
        let numbers: Vec<u64> = rows.iter().map(|r| r[0]).collect();
        // First rise at sample 5 (4 -> 5); three samples before it.
        assert_eq!(numbers, [2, 3, 4, 5, 6, 7, 8, 9]);
    }

    #[test]
    fn missing_counts_down_from_the_trigger() {
        let mut c = Capture::new(8, 3, trig(Edge::Rising));
        for n in 1..=4 {
            c.push(&square(n));
            assert_eq!(c.missing(), None, "sample {n}");
        }
        // The rise at 5: three samples before it and itself are in.
        c.push(&square(5));
        assert_eq!(c.missing(), Some(4));
        c.push(&square(6));
        assert_eq!(c.missing(), Some(3));
        // Without a trigger a record is triggered from the start.
        assert_eq!(Capture::new(5, 0, None).missing(), Some(5));
    }

    #[test]
    fn pre_trigger_must_fill_before_arming() {
        // The rise at 5 comes with only 4 samples seen; pre = 6 waits
        // for the next rise at 15.
        let mut c = Capture::new(10, 6, trig(Edge::Rising));
        let mut n = 1;
        while !c.done() {
            c.push(&square(n));
            n += 1;
        }
        let (rows, at) = c.into_record();
        assert_eq!(rows[at][0], 15);
        assert_eq!(rows[0][0], 9);
    }

    #[test]
    fn falling_edge_without_pre_and_gap_restarts() {
        // The first fall is at 10 (9 -> 10); with 10 lost, 11 has no
        // predecessor and the next fall, at 20, triggers.
        let mut c = Capture::new(4, 0, trig(Edge::Falling));
        for n in 1..=25 {
            if n != 10 {
                c.push(&square(n));
            }
            if n == 11 {
                assert!(!c.triggered());
            }
        }
        let (rows, at) = c.into_record();
        assert_eq!((at, rows[0][0]), (0, 20));
        assert_eq!(rows.len(), 4);
    }

    #[test]
    fn no_trigger_records_at_once() {
        let mut c = Capture::new(3, 2, None);
        for n in 7..20 {
            c.push(&square(n));
        }
        let (rows, at) = c.into_record();
        assert_eq!((at, rows.len(), rows[0][0]), (0, 3, 7));
    }
}
