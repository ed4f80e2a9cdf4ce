//! A joint's leadscrew-error compensation table (LinuxCNC's `comp`): at
//! each nominal position, what to add to the command while moving in the
//! positive direction and while moving in the negative one, interpolated
//! linearly in between and held constant beyond both ends.
//!
//! The table is filled once (entry by entry, nominals increasing, at most
//! [`MAX_COMP_ENTRIES`]) and looked up every servo cycle: a cursor walks
//! to the interval of the commanded position, so continuous motion costs
//! a step or two, and nothing allocates.

/// Most entries a table holds (LinuxCNC's limit).
pub const MAX_COMP_ENTRIES: usize = 256;

/// One point of a compensation table.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CompEntry {
    /// The commanded (nominal) position.
    pub nominal: f64,
    /// Added to the command while moving in the positive direction.
    pub forward: f64,
    /// Added to the command while moving in the negative direction.
    pub reverse: f64,
}

/// Why an entry was not added.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CompPushError {
    /// Its nominal is not above the last entry's.
    NotIncreasing {
        /// The last entry's nominal.
        previous: f64,
    },
    /// The table is full.
    Full,
    /// A value is not a finite number.
    NotFinite,
}

/// A joint's compensation table.
#[derive(Debug, Clone, PartialEq)]
pub struct CompTable {
    entries: [CompEntry; MAX_COMP_ENTRIES],
    len: usize,
    /// The interval of the last lookup: entries `cursor` and `cursor + 1`.
    cursor: usize,
}

impl Default for CompTable {
    fn default() -> Self {
        CompTable {
            entries: [CompEntry::default(); MAX_COMP_ENTRIES],
            len: 0,
            cursor: 0,
        }
    }
}

impl CompTable {
    /// Whether the table has no entry (BACKLASH applies then).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.len
    }

    /// The entries, in order.
    pub fn entries(&self) -> &[CompEntry] {
        &self.entries[..self.len]
    }

    /// Empties the table.
    pub fn clear(&mut self) {
        self.len = 0;
        self.cursor = 0;
    }

    /// Appends an entry; nominals must increase.
    pub fn push(&mut self, e: CompEntry) -> Result<(), CompPushError> {
        if !(e.nominal.is_finite() && e.forward.is_finite() && e.reverse.is_finite()) {
            return Err(CompPushError::NotFinite);
        }
        if self.len == MAX_COMP_ENTRIES {
            return Err(CompPushError::Full);
        }
        if let Some(last) = self.entries[..self.len].last() {
            if e.nominal <= last.nominal {
                return Err(CompPushError::NotIncreasing {
                    previous: last.nominal,
                });
            }
        }
        self.entries[self.len] = e;
        self.len += 1;
        Ok(())
    }

    /// The trim at `pos` for motion in the positive direction (`forward`
    /// true) or the negative one. 0 for an empty table.
    pub fn trim(&mut self, pos: f64, forward: bool) -> f64 {
        let pick = |e: &CompEntry| if forward { e.forward } else { e.reverse };
        let n = self.len;
        if n == 0 {
            return 0.0;
        }
        let first = &self.entries[0];
        if n == 1 || pos <= first.nominal || pos.is_nan() {
            return pick(first);
        }
        let last = &self.entries[n - 1];
        if pos >= last.nominal {
            return pick(last);
        }
        // Walk the cursor to the interval holding pos.
        let mut c = self.cursor.min(n - 2);
        while c > 0 && pos < self.entries[c].nominal {
            c -= 1;
        }
        while c + 2 < n && pos >= self.entries[c + 1].nominal {
            c += 1;
        }
        self.cursor = c;
        let (a, b) = (&self.entries[c], &self.entries[c + 1]);
        let f = (pos - a.nominal) / (b.nominal - a.nominal);
        pick(a) + (pick(b) - pick(a)) * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(rows: &[(f64, f64, f64)]) -> CompTable {
        let mut t = CompTable::default();
        for &(nominal, forward, reverse) in rows {
            t.push(CompEntry {
                nominal,
                forward,
                reverse,
            })
            .unwrap();
        }
        t
    }

    #[test]
    fn hand_computed_interpolation_and_constant_ends() {
        // LinuxCNC's type-1 example.
        let mut t = table(&[
            (-1.0, 0.005, -0.005),
            (0.0, 0.002, -0.003),
            (1.0, 0.003, -0.004),
        ]);
        let cases = [
            // (position, forward trim, reverse trim), by hand.
            (-5.0, 0.005, -0.005),
            (-1.0, 0.005, -0.005),
            (-0.5, 0.0035, -0.004),
            (-0.25, 0.00275, -0.0035),
            (0.0, 0.002, -0.003),
            (0.25, 0.00225, -0.00325),
            (0.75, 0.00275, -0.00375),
            (1.0, 0.003, -0.004),
            (9.0, 0.003, -0.004),
        ];
        // Forwards, backwards and jumping about: the cursor must follow.
        for order in [
            (0..cases.len()).collect::<Vec<_>>(),
            (0..cases.len()).rev().collect(),
            vec![4, 0, 8, 2, 6, 1, 7, 3, 5],
        ] {
            for i in order {
                let (p, f, r) = cases[i];
                assert!((t.trim(p, true) - f).abs() < 1e-15, "fwd at {p}");
                assert!((t.trim(p, false) - r).abs() < 1e-15, "rev at {p}");
            }
        }
    }

    #[test]
    fn entries_must_increase_and_fit() {
        let mut t = table(&[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0)]);
        let e = |nominal| CompEntry {
            nominal,
            forward: 0.0,
            reverse: 0.0,
        };
        assert_eq!(
            t.push(e(1.0)),
            Err(CompPushError::NotIncreasing { previous: 1.0 })
        );
        assert_eq!(
            t.push(e(0.5)),
            Err(CompPushError::NotIncreasing { previous: 1.0 })
        );
        assert_eq!(
            t.push(CompEntry {
                nominal: 2.0,
                forward: f64::NAN,
                reverse: 0.0
            }),
            Err(CompPushError::NotFinite)
        );
        for k in 2..MAX_COMP_ENTRIES {
            t.push(e(k as f64)).unwrap();
        }
        assert_eq!(t.push(e(1e6)), Err(CompPushError::Full));
        t.clear();
        assert!(t.is_empty());
        assert_eq!(t.trim(3.0, true), 0.0);
    }

    #[test]
    fn one_entry_with_half_backlash_each_way_is_backlash() {
        let mut t = table(&[(0.0, 0.05, -0.05)]);
        for p in [-10.0, 0.0, 3.0] {
            assert_eq!(t.trim(p, true), 0.05);
            assert_eq!(t.trim(p, false), -0.05);
        }
    }
}
