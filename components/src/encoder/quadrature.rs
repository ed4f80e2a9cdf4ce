//! The quadrature / pulse decoder shared by `encoder` and `encoder_ratio`.
//!
//! The decoder keeps a 4-bit history nibble: bit 3 and bit 2 hold the
//! previous B and A inputs. Each step forms a lookup index from that history
//! and the current inputs (`history | B << 1 | A`) and reads the action and
//! the next history from a 16-entry table per mode. The tables are built at
//! compile time from the rules in components.md §3.2, so the decoder costs
//! one table lookup per step.

/// How the decoder interprets its inputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum QuadMode {
    /// Count every edge of A and B: four counts per quadrature cycle.
    #[default]
    X4,
    /// One count per quadrature cycle: up when A rises while B is low,
    /// down when A falls while B is low.
    X1,
    /// Pulse counter: count rising edges of A, up only; B is ignored.
    Counter,
}

impl QuadMode {
    /// The mode the `x4-mode` / `counter-mode` pins select; counter mode
    /// has priority.
    pub fn from_pins(x4_mode: bool, counter_mode: bool) -> QuadMode {
        if counter_mode {
            QuadMode::Counter
        } else if x4_mode {
            QuadMode::X4
        } else {
            QuadMode::X1
        }
    }
}

/// What one decoder step did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// No count.
    None,
    /// One count forward.
    Up,
    /// One count backward.
    Down,
}

/// One table entry: the action and the next history nibble.
type Entry = (Step, u8);

/// Position of an (A, B) pair along the forward cycle
/// (0,0) -> (1,0) -> (1,1) -> (0,1).
const fn cycle_pos(a: u8, b: u8) -> u8 {
    match (a, b) {
        (0, 0) => 0,
        (1, 0) => 1,
        (1, 1) => 2,
        _ => 3,
    }
}

/// The x4 or x1 table: history is always the current inputs.
const fn quad_table(x4: bool) -> [Entry; 16] {
    let mut t = [(Step::None, 0u8); 16];
    let mut idx = 0;
    while idx < 16 {
        let (pa, pb) = (((idx >> 2) & 1) as u8, ((idx >> 3) & 1) as u8);
        let (a, b) = ((idx & 1) as u8, ((idx >> 1) & 1) as u8);
        let step = if x4 {
            // One position forward is up, one back is down; no change or
            // a jump of two (both inputs changed at once) is no count.
            match (cycle_pos(a, b) + 4 - cycle_pos(pa, pb)) % 4 {
                1 => Step::Up,
                3 => Step::Down,
                _ => Step::None,
            }
        } else if pb == 0 && b == 0 && pa == 0 && a == 1 {
            Step::Up
        } else if pb == 0 && b == 0 && pa == 1 && a == 0 {
            Step::Down
        } else {
            Step::None
        };
        t[idx] = (step, (b << 3) | (a << 2));
        idx += 1;
    }
    t
}

/// The counter-mode table. B is masked out of the index before lookup
/// and bit 3 of the history holds the previous A; an index with bit 2 set
/// can only come from a stale x4/x1 history and resets it.
const fn counter_table() -> [Entry; 16] {
    let mut t = [(Step::None, 0u8); 16];
    t[0b0001] = (Step::Up, 0b1000);
    t[0b1001] = (Step::None, 0b1000);
    t
}

static X4_TABLE: [Entry; 16] = quad_table(true);
static X1_TABLE: [Entry; 16] = quad_table(false);
static COUNTER_TABLE: [Entry; 16] = counter_table();

/// A quadrature decoder: the history of one A/B input pair.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QuadDecoder {
    history: u8,
}

impl QuadDecoder {
    /// A decoder whose history is "both inputs low".
    pub const fn new() -> QuadDecoder {
        QuadDecoder { history: 0 }
    }

    /// The history nibble (bits 3..2; see the module docs).
    pub fn history(&self) -> u8 {
        self.history
    }

    /// Feeds the current inputs and returns the count they cause. Changing
    /// `mode` between calls reinterprets the stored history as LinuxCNC
    /// does.
    #[inline]
    pub fn step(&mut self, a: bool, b: bool, mode: QuadMode) -> Step {
        let (table, b) = match mode {
            QuadMode::X4 => (&X4_TABLE, b),
            QuadMode::X1 => (&X1_TABLE, b),
            QuadMode::Counter => (&COUNTER_TABLE, false),
        };
        let idx = (self.history & 0x0C) | ((b as u8) << 1) | a as u8;
        let (step, next) = table[idx as usize];
        self.history = next;
        step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs a sequence of (A, B) pairs and returns the net count.
    fn run(dec: &mut QuadDecoder, seq: &[(u8, u8)], mode: QuadMode) -> i32 {
        seq.iter()
            .map(|&(a, b)| match dec.step(a != 0, b != 0, mode) {
                Step::Up => 1,
                Step::Down => -1,
                Step::None => 0,
            })
            .sum()
    }

    const FORWARD: [(u8, u8); 4] = [(1, 0), (1, 1), (0, 1), (0, 0)];
    const REVERSE: [(u8, u8); 4] = [(0, 1), (1, 1), (1, 0), (0, 0)];

    #[test]
    fn x4_counts_every_edge_both_ways() {
        let mut d = QuadDecoder::new();
        assert_eq!(run(&mut d, &FORWARD, QuadMode::X4), 4);
        assert_eq!(run(&mut d, &REVERSE, QuadMode::X4), -4);
        let mut d = QuadDecoder::new();
        for &(a, b) in &FORWARD {
            assert_eq!(d.step(a != 0, b != 0, QuadMode::X4), Step::Up);
        }
        for &(a, b) in &REVERSE {
            assert_eq!(d.step(a != 0, b != 0, QuadMode::X4), Step::Down);
        }
    }

    #[test]
    fn x4_ignores_no_change_and_double_change() {
        let mut d = QuadDecoder::new();
        assert_eq!(d.step(false, false, QuadMode::X4), Step::None);
        // 00 -> 11 and 11 -> 00: both inputs changed at once.
        assert_eq!(d.step(true, true, QuadMode::X4), Step::None);
        assert_eq!(d.step(true, true, QuadMode::X4), Step::None);
        assert_eq!(d.step(false, false, QuadMode::X4), Step::None);
        d.step(true, false, QuadMode::X4);
        assert_eq!(d.step(false, true, QuadMode::X4), Step::None);
    }

    #[test]
    fn x1_counts_once_per_cycle() {
        let mut d = QuadDecoder::new();
        let mut seq = Vec::new();
        for _ in 0..5 {
            seq.extend_from_slice(&FORWARD);
        }
        assert_eq!(run(&mut d, &seq, QuadMode::X1), 5);
        let mut seq = Vec::new();
        for _ in 0..3 {
            seq.extend_from_slice(&REVERSE);
        }
        assert_eq!(run(&mut d, &seq, QuadMode::X1), -3);
        // Only A rising / falling with B low counts.
        let mut d = QuadDecoder::new();
        assert_eq!(d.step(true, false, QuadMode::X1), Step::Up);
        assert_eq!(d.step(false, false, QuadMode::X1), Step::Down);
        d.step(false, true, QuadMode::X1);
        assert_eq!(d.step(true, true, QuadMode::X1), Step::None);
    }

    #[test]
    fn counter_mode_counts_rising_a_only() {
        let mut d = QuadDecoder::new();
        // B is ignored entirely.
        let seq = [(1, 0), (1, 1), (0, 1), (0, 0), (1, 1), (0, 0), (0, 1)];
        assert_eq!(run(&mut d, &seq, QuadMode::Counter), 2);
        assert_eq!(d.step(true, false, QuadMode::Counter), Step::Up);
        assert_eq!(d.history(), 0b1000);
        assert_eq!(d.step(true, true, QuadMode::Counter), Step::None);
        assert_eq!(d.step(false, false, QuadMode::Counter), Step::None);
        assert_eq!(d.history(), 0);
    }

    #[test]
    fn mode_switch_reinterprets_history() {
        // x4 history with previous A set (bit 2) resets in counter mode
        // without counting, even if A is high.
        let mut d = QuadDecoder::new();
        d.step(true, false, QuadMode::X4);
        assert_eq!(d.history(), 0b0100);
        assert_eq!(d.step(true, false, QuadMode::Counter), Step::None);
        assert_eq!(d.history(), 0);
        // From the cleared history, A high is a fresh rising edge.
        assert_eq!(d.step(true, false, QuadMode::Counter), Step::Up);
        // Now A is 1 in bit 3 of a counter history...
        assert_eq!(d.history(), 0b1000);
        // ...which x4 reads as previous (A, B) = (0, 1): 01 -> 00 is up.
        assert_eq!(d.step(false, false, QuadMode::X4), Step::Up);
        // x4 history "B high, A low" reads as "previous A high" in counter
        // mode: A staying high does not count.
        let mut d = QuadDecoder::new();
        d.step(false, true, QuadMode::X4);
        assert_eq!(d.step(true, true, QuadMode::Counter), Step::None);
    }

    #[test]
    fn from_pins_gives_counter_priority() {
        assert_eq!(QuadMode::from_pins(true, true), QuadMode::Counter);
        assert_eq!(QuadMode::from_pins(false, true), QuadMode::Counter);
        assert_eq!(QuadMode::from_pins(true, false), QuadMode::X4);
        assert_eq!(QuadMode::from_pins(false, false), QuadMode::X1);
    }
}
