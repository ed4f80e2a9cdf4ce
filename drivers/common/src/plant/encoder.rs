//! [`QuadEncoder`]: a quadrature encoder on a shaft: position → A/B/Z
//! levels, the count edges a hardware counter sees, and the index pulse
//! once per revolution.
//!
//! Counts are quadrature counts (4 per line). The states run A/B = 00,
//! 10, 11, 01 as the count goes up (A leads B forward); Z is high for the
//! one count of each revolution where `count mod counts_per_rev == 0`.

/// What a move did, as a counter watching A/B/Z would see it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct EncoderMove {
    /// Quadrature edges, signed (positive forward).
    pub delta: i64,
    /// How many index pulses were entered on the way.
    pub index_pulses: u64,
    /// The count at the first index pulse entered, in the order of the
    /// motion (what an index latch would capture).
    pub first_index: Option<i64>,
}

/// A quadrature encoder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct QuadEncoder {
    counts_per_rev: i64,
    count: i64,
}

impl QuadEncoder {
    /// An encoder with `counts_per_rev` quadrature counts per revolution
    /// (at least 1), at count 0 (an index position).
    pub fn new(counts_per_rev: u32) -> QuadEncoder {
        QuadEncoder {
            counts_per_rev: counts_per_rev.max(1) as i64,
            count: 0,
        }
    }

    /// Counts per revolution.
    pub fn counts_per_rev(&self) -> u32 {
        self.counts_per_rev as u32
    }

    /// The count the shaft is at.
    pub fn count(&self) -> i64 {
        self.count
    }

    /// Turns the shaft to `revs` revolutions from the origin.
    pub fn set_revs(&mut self, revs: f64) -> EncoderMove {
        self.set_count((revs * self.counts_per_rev as f64).floor() as i64)
    }

    /// Turns the shaft to count `count`, reporting the edges and index
    /// pulses on the way.
    pub fn set_count(&mut self, count: i64) -> EncoderMove {
        let (from, cpr) = (self.count, self.counts_per_rev);
        self.count = count;
        let (index_pulses, first_index) = if count > from {
            // States entered: from+1 ..= count.
            let n = count.div_euclid(cpr) - from.div_euclid(cpr);
            (n, (n > 0).then(|| (from.div_euclid(cpr) + 1) * cpr))
        } else if count < from {
            // States entered: from-1 down to count.
            let n = (from - 1).div_euclid(cpr) - (count - 1).div_euclid(cpr);
            (n, (n > 0).then(|| (from - 1).div_euclid(cpr) * cpr))
        } else {
            (0, None)
        };
        EncoderMove {
            delta: count - from,
            index_pulses: index_pulses as u64,
            first_index,
        }
    }

    /// Line A.
    pub fn a(&self) -> bool {
        matches!(self.count.rem_euclid(4), 1 | 2)
    }

    /// Line B.
    pub fn b(&self) -> bool {
        matches!(self.count.rem_euclid(4), 2 | 3)
    }

    /// Line Z (index).
    pub fn z(&self) -> bool {
        self.count.rem_euclid(self.counts_per_rev) == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_states_in_both_directions() {
        let mut e = QuadEncoder::new(8);
        let mut seen = Vec::new();
        for c in 0..=8 {
            e.set_count(c);
            seen.push((e.a(), e.b()));
        }
        let f = false;
        let t = true;
        assert_eq!(
            seen,
            vec![
                (f, f),
                (t, f),
                (t, t),
                (f, t),
                (f, f),
                (t, f),
                (t, t),
                (f, t),
                (f, f)
            ]
        );
        // Backwards the same states in reverse, through negative counts.
        e.set_count(0);
        let back: Vec<(bool, bool)> = (-4..=0)
            .rev()
            .map(|c| {
                e.set_count(c);
                (e.a(), e.b())
            })
            .collect();
        assert_eq!(back, vec![(f, f), (f, t), (t, t), (t, f), (f, f)]);
    }

    #[test]
    fn counts_follow_the_shaft_both_ways() {
        let mut e = QuadEncoder::new(2000);
        let m = e.set_revs(1.25);
        assert_eq!((m.delta, e.count()), (2500, 2500));
        let m = e.set_revs(-0.5);
        assert_eq!((m.delta, e.count()), (-3500, -1000));
    }

    #[test]
    fn index_once_per_revolution_both_ways() {
        let mut e = QuadEncoder::new(2000);
        assert!(e.z(), "count 0 is an index position");
        e.set_revs(0.5);
        assert!(!e.z());
        let m = e.set_revs(3.5);
        assert_eq!((m.index_pulses, m.first_index), (3, Some(2000)));
        let m = e.set_revs(0.5);
        assert_eq!((m.index_pulses, m.first_index), (3, Some(6000)));
        // Leaving an index state backwards does not count it again, and
        // entering it does.
        e.set_count(0);
        let m = e.set_count(-1);
        assert_eq!(m.index_pulses, 0);
        let m = e.set_count(0);
        assert_eq!((m.index_pulses, m.first_index), (1, Some(0)));
        let m = e.set_count(-2000);
        assert_eq!((m.index_pulses, m.first_index), (1, Some(-2000)));
        assert!(e.z());
        let m = e.set_count(-2000);
        assert_eq!(m, EncoderMove::default());
    }
}
