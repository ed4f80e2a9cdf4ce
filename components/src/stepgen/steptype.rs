//! The sixteen output waveforms of stepgen: step/dir (type 0), up/down
//! (type 1) and the phase tables of types 2..15.

use crate::error::CompError;

/// Longest phase table: type 15 takes up to 18 user patterns.
pub const MAX_CYCLE: usize = 18;

/// Most phases a table drives (phase-A .. phase-E).
pub const MAX_PHASES: usize = 5;

/// Built-in phase tables of types 2..14, indexed by `type - 2`: the number
/// of phases and the patterns (bit 0 = phase-A) for states 0, 1, 2, ...
const BUILTIN: [(u8, &[u8]); 13] = [
    (2, &[1, 3, 2, 0]),
    (3, &[1, 2, 4]),
    (3, &[1, 3, 2, 6, 4, 5]),
    (4, &[1, 2, 4, 8]),
    (4, &[3, 6, 12, 9]),
    (4, &[1, 7, 14, 8]),
    (4, &[5, 6, 10, 9]),
    (4, &[1, 3, 2, 6, 4, 12, 8, 9]),
    (4, &[1, 5, 7, 6, 14, 10, 8, 9]),
    (5, &[1, 2, 4, 8, 16]),
    (5, &[3, 6, 12, 24, 17]),
    (5, &[1, 3, 2, 6, 4, 12, 8, 24, 16, 17]),
    (5, &[3, 7, 6, 14, 12, 28, 24, 25, 17, 19]),
];

/// One channel's step type: its number and, for types 2..15, its phase
/// table. Plain data (`Copy`), so the realtime code holds it inline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepType {
    kind: u8,
    phases: u8,
    len: u8,
    table: [u8; MAX_CYCLE],
}

impl StepType {
    /// A built-in type, 0..=14; `None` for anything else (type 15 needs its
    /// patterns, see [`StepType::user`]).
    pub fn builtin(kind: u8) -> Option<StepType> {
        let mut t = StepType {
            kind,
            phases: 0,
            len: 0,
            table: [0; MAX_CYCLE],
        };
        match kind {
            0 | 1 => {}
            2..=14 => {
                let (phases, pats) = BUILTIN[usize::from(kind - 2)];
                t.phases = phases;
                t.len = pats.len() as u8;
                t.table[..pats.len()].copy_from_slice(pats);
            }
            _ => return None,
        }
        Some(t)
    }

    /// Type 15 with the given patterns (the `user_step_type=` values up to
    /// the first -1). Each must fit in 5 bits, and there must be 1..=18 of
    /// them. The phase count is the position of the highest bit any pattern
    /// uses (0 when all are 0: no phase pins).
    pub fn user(patterns: &[i64]) -> Result<StepType, CompError> {
        if patterns.is_empty() {
            return Err(CompError::NoUserPatterns);
        }
        if patterns.len() > MAX_CYCLE {
            return Err(CompError::TooManyPatterns { max: MAX_CYCLE });
        }
        let mut t = StepType {
            kind: 15,
            phases: 0,
            len: patterns.len() as u8,
            table: [0; MAX_CYCLE],
        };
        let mut used = 0u8;
        for (i, &p) in patterns.iter().enumerate() {
            if !(0..1 << MAX_PHASES).contains(&p) {
                return Err(CompError::PatternTooWide {
                    index: i,
                    pattern: p,
                    max_phases: MAX_PHASES,
                });
            }
            t.table[i] = p as u8;
            used |= p as u8;
        }
        t.phases = (8 - used.leading_zeros()) as u8;
        Ok(t)
    }

    /// The step type number, 0..=15.
    pub fn kind(&self) -> u8 {
        self.kind
    }

    /// Number of phase pins (0 for types 0 and 1).
    pub fn phases(&self) -> usize {
        usize::from(self.phases)
    }

    /// Number of states in the phase cycle (0 for types 0 and 1).
    pub fn cycle_len(&self) -> usize {
        usize::from(self.len)
    }

    /// The phase pattern of `state` (bit 0 = phase-A); 0 outside the table.
    #[inline(always)]
    pub fn pattern(&self, state: i32) -> u8 {
        usize::try_from(state)
            .ok()
            .and_then(|s| self.table[..usize::from(self.len)].get(s))
            .copied()
            .unwrap_or(0)
    }

    /// Whether the type has a separate `dirsetup` time (type 0 only).
    pub fn has_setup(&self) -> bool {
        self.kind == 0
    }

    /// Whether the type has a `stepspace` time (types 0 and 1).
    pub fn has_stepspace(&self) -> bool {
        self.kind < 2
    }
}

/// The name of phase pin `p` (0 = `phase-A`).
pub fn phase_name(p: usize) -> &'static str {
    ["phase-A", "phase-B", "phase-C", "phase-D", "phase-E"][p]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_tables_have_the_documented_shape() {
        let expect: [(u8, usize, usize); 13] = [
            (2, 2, 4),
            (3, 3, 3),
            (4, 3, 6),
            (5, 4, 4),
            (6, 4, 4),
            (7, 4, 4),
            (8, 4, 4),
            (9, 4, 8),
            (10, 4, 8),
            (11, 5, 5),
            (12, 5, 5),
            (13, 5, 10),
            (14, 5, 10),
        ];
        for (kind, phases, len) in expect {
            let t = StepType::builtin(kind).unwrap();
            assert_eq!((t.kind(), t.phases(), t.cycle_len()), (kind, phases, len));
            // Every pattern only drives the type's own phases.
            for s in 0..len as i32 {
                assert!(u32::from(t.pattern(s)) < 1 << phases, "type {kind}");
            }
        }
        assert_eq!(StepType::builtin(2).unwrap().pattern(0), 1);
        assert_eq!(StepType::builtin(14).unwrap().pattern(9), 19);
        assert_eq!(StepType::builtin(0).unwrap().phases(), 0);
        assert_eq!(StepType::builtin(1).unwrap().cycle_len(), 0);
        assert!(StepType::builtin(15).is_none());
        assert!(StepType::builtin(16).is_none());
    }

    #[test]
    fn quadrature_changes_one_phase_per_step() {
        for kind in [2u8, 4, 9, 10, 13] {
            let t = StepType::builtin(kind).unwrap();
            let n = t.cycle_len() as i32;
            for s in 0..n {
                let d = t.pattern(s) ^ t.pattern((s + 1) % n);
                assert_eq!(d.count_ones(), 1, "type {kind} state {s}");
            }
        }
    }

    #[test]
    fn user_type_counts_phases_from_the_highest_bit() {
        let t = StepType::user(&[1, 2, 4]).unwrap();
        assert_eq!((t.kind(), t.phases(), t.cycle_len()), (15, 3, 3));
        assert_eq!(StepType::user(&[16, 0]).unwrap().phases(), 5);
        assert_eq!(StepType::user(&[0, 0]).unwrap().phases(), 0);
        assert_eq!(StepType::user(&[31; 18]).unwrap().cycle_len(), 18);
        assert!(StepType::user(&[]).is_err());
        assert!(StepType::user(&[32])
            .unwrap_err()
            .to_string()
            .contains("5 bits"));
        assert!(StepType::user(&[-2]).is_err());
        assert!(StepType::user(&[1; 19]).is_err());
    }

    #[test]
    fn pattern_outside_the_table_is_zero() {
        let t = StepType::builtin(3).unwrap();
        assert_eq!(t.pattern(-1), 0);
        assert_eq!(t.pattern(3), 0);
        assert_eq!(phase_name(4), "phase-E");
    }
}
