//! Step sizes: the sequences `-s N` picks and the stepping through them
//! that `stepsize-up` and `stepsize-down` drive.

/// The sequences `-s 1` to `-s 5` name, in thousandths.
pub const SEQUENCES: [&[i32]; 5] = [
    &[1, 10, 100, 1000],
    &[1, 5, 10, 20],
    &[1, 10, 100],
    &[1, 5, 10, 20, 50, 100],
    &[1, 10, 50, 100, 1000],
];

/// The sequence for `-s n`, if n is 1..=5.
pub fn sequence(n: usize) -> Option<&'static [i32]> {
    n.checked_sub(1).and_then(|i| SEQUENCES.get(i)).copied()
}

/// Which way the step inputs ask to move.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Request {
    None,
    Up,
    Down,
}

/// Steps through a sequence on the rising edges of up and down (both
/// held at once is no request); the step size is read as the sequence
/// entry, times 0.001 for the jog scale.
#[derive(Debug, Clone)]
pub struct Stepper {
    seq: &'static [i32],
    index: usize,
    last: Option<Request>,
}

impl Stepper {
    /// At the first entry of `seq` (which must not be empty).
    pub fn new(seq: &'static [i32]) -> Stepper {
        Stepper {
            seq,
            index: 0,
            last: None,
        }
    }

    /// One look at the inputs; returns the step size.
    pub fn update(&mut self, up: bool, down: bool) -> i32 {
        let req = match (up, down) {
            (true, false) => Request::Up,
            (false, true) => Request::Down,
            _ => Request::None,
        };
        if self.last != Some(req) {
            match req {
                Request::Up => self.index = (self.index + 1) % self.seq.len(),
                Request::Down => {
                    self.index = self.index.checked_sub(1).unwrap_or(self.seq.len() - 1)
                }
                Request::None => {}
            }
        }
        self.last = Some(req);
        self.stepsize()
    }

    /// The current step size.
    pub fn stepsize(&self) -> i32 {
        self.seq[self.index]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_on_edges_and_wraps() {
        let mut s = Stepper::new(sequence(2).unwrap());
        assert_eq!(s.update(false, false), 1);
        assert_eq!(s.update(true, false), 5);
        assert_eq!(s.update(true, false), 5, "held: no step");
        assert_eq!(s.update(false, false), 5);
        for want in [10, 20, 1] {
            s.update(true, false);
            assert_eq!(s.update(false, false), want);
        }
        assert_eq!(s.update(false, true), 20, "down wraps to the last");
        assert_eq!(s.update(true, true), 20, "both: nothing");
    }

    #[test]
    fn five_sequences() {
        assert!(sequence(0).is_none() && sequence(6).is_none());
        assert_eq!(sequence(1).unwrap(), &[1, 10, 100, 1000]);
        assert_eq!(sequence(5).unwrap().len(), 5);
    }
}
