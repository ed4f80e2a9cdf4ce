//! The ladder's memory: bits, words, the physical I/O images, and the
//! state of timers, monostables, counters and IEC timers, with the one
//! read and write of a variable the rungs and expressions use. Sized at
//! construction; nothing here allocates afterwards.

use crate::model::{IecMode, Program, Sizes, VarKind, VarRef, COUNTER_MAX};

/// An old-style timer (%T).
#[derive(Debug, Clone, Copy, Default)]
pub struct TimerState {
    /// Time base, ms.
    pub base_ms: i32,
    /// Preset, base units.
    pub preset: i32,
    /// Time left, ms.
    pub left_ms: i32,
    /// Done output.
    pub done: bool,
    /// Running output.
    pub running: bool,
}

/// A monostable (%M).
#[derive(Debug, Clone, Copy, Default)]
pub struct MonoState {
    /// Time base, ms.
    pub base_ms: i32,
    /// Preset, base units.
    pub preset: i32,
    /// Time left, ms.
    pub left_ms: i32,
    /// Running output.
    pub running: bool,
    /// Input at the previous scan.
    pub input_bak: bool,
}

/// A counter (%C).
#[derive(Debug, Clone, Copy, Default)]
pub struct CounterState {
    /// Preset.
    pub preset: i32,
    /// Value (0-9999).
    pub value: i32,
    /// Value before the last change.
    pub value_bak: i32,
    /// Count-up input at the previous scan.
    pub up_bak: bool,
    /// Count-down input at the previous scan.
    pub down_bak: bool,
    /// Done output (value = preset).
    pub done: bool,
    /// Empty output (wrapped below 0).
    pub empty: bool,
    /// Full output (wrapped past 9999).
    pub full: bool,
}

/// An IEC timer (%TM).
#[derive(Debug, Clone, Copy)]
pub struct IecState {
    /// Time base, ms.
    pub base_ms: i32,
    /// Preset, base units.
    pub preset: i32,
    /// Mode.
    pub mode: IecMode,
    /// Time counted, ms.
    pub elapsed_ms: i32,
    /// Whether it is timing.
    pub started: bool,
    /// Q output.
    pub q: bool,
    /// Input at the previous scan.
    pub input_bak: bool,
}

/// All variables and block states.
#[derive(Debug, Clone)]
pub struct Vars {
    /// %B.
    pub bits: Vec<bool>,
    /// %I.
    pub inputs: Vec<bool>,
    /// %Q.
    pub outputs: Vec<bool>,
    /// %E.
    pub errors: Vec<bool>,
    /// %W.
    pub words: Vec<i32>,
    /// %IW.
    pub word_in: Vec<i32>,
    /// %QW.
    pub word_out: Vec<i32>,
    /// %IF (truncated to integers).
    pub float_in: Vec<i32>,
    /// %QF.
    pub float_out: Vec<i32>,
    /// %T.
    pub timers: Vec<TimerState>,
    /// %M.
    pub monos: Vec<MonoState>,
    /// %C.
    pub counters: Vec<CounterState>,
    /// %TM.
    pub iec: Vec<IecState>,
}

fn ms(preset: i32, base: i32) -> i32 {
    preset.saturating_mul(base)
}

impl Vars {
    /// Zeroed memory for a module of `sizes` (allocates).
    pub fn new(s: &Sizes) -> Vars {
        Vars {
            bits: vec![false; s.bits],
            inputs: vec![false; s.inputs],
            outputs: vec![false; s.outputs],
            errors: vec![false; s.error_bits],
            words: vec![0; s.words],
            word_in: vec![0; s.s32_in],
            word_out: vec![0; s.s32_out],
            float_in: vec![0; s.float_in],
            float_out: vec![0; s.float_out],
            timers: vec![TimerState::default(); s.timers],
            monos: vec![MonoState::default(); s.monostables],
            counters: vec![CounterState::default(); s.counters],
            iec: vec![
                IecState {
                    base_ms: 1000,
                    preset: 0,
                    mode: IecMode::OnDelay,
                    elapsed_ms: 0,
                    started: false,
                    q: false,
                    input_bak: false
                };
                s.timers_iec
            ],
        }
    }

    /// Clears everything and takes the block setups of `prog`, as a
    /// freshly loaded program starts.
    pub fn reset(&mut self, prog: &Program) {
        for v in [&mut self.bits, &mut self.outputs, &mut self.errors] {
            v.fill(false);
        }
        for v in [&mut self.words, &mut self.word_out, &mut self.float_out] {
            v.fill(0);
        }
        for (t, s) in self.timers.iter_mut().zip(&prog.timers) {
            *t = TimerState {
                base_ms: s.base_ms,
                preset: s.preset,
                left_ms: ms(s.preset, s.base_ms),
                ..TimerState::default()
            };
        }
        for (m, s) in self.monos.iter_mut().zip(&prog.monostables) {
            *m = MonoState {
                base_ms: s.base_ms,
                preset: s.preset,
                ..MonoState::default()
            };
        }
        for (c, p) in self.counters.iter_mut().zip(&prog.counters) {
            *c = CounterState {
                preset: *p,
                ..CounterState::default()
            };
        }
        for (t, s) in self.iec.iter_mut().zip(&prog.timers_iec) {
            *t = IecState {
                base_ms: s.base_ms,
                preset: s.preset,
                mode: s.mode,
                elapsed_ms: 0,
                started: false,
                q: false,
                input_bak: false,
            };
        }
    }

    /// A variable's value (a bit is 0 or 1; a missing one 0).
    pub fn read(&self, v: VarRef) -> i32 {
        use VarKind::*;
        let i = v.index as usize;
        let b = |x: Option<&bool>| x.copied().unwrap_or(false) as i32;
        let w = |x: Option<&i32>| x.copied().unwrap_or(0);
        let t = self.timers.get(i);
        let m = self.monos.get(i);
        let c = self.counters.get(i);
        let e = self.iec.get(i);
        match v.kind {
            Bit => b(self.bits.get(i)),
            Input => b(self.inputs.get(i)),
            Output => b(self.outputs.get(i)),
            ErrorBit => b(self.errors.get(i)),
            Word => w(self.words.get(i)),
            WordInput => w(self.word_in.get(i)),
            WordOutput => w(self.word_out.get(i)),
            FloatInput => w(self.float_in.get(i)),
            FloatOutput => w(self.float_out.get(i)),
            TimerDone => t.is_some_and(|t| t.done) as i32,
            TimerRunning => t.is_some_and(|t| t.running) as i32,
            TimerPreset => t.map_or(0, |t| t.preset),
            TimerValue => t.map_or(0, |t| t.left_ms.max(0) / t.base_ms.max(1)),
            MonostableRunning => m.is_some_and(|m| m.running) as i32,
            MonostablePreset => m.map_or(0, |m| m.preset),
            MonostableValue => m.map_or(0, |m| m.left_ms.max(0) / m.base_ms.max(1)),
            CounterDone => c.is_some_and(|c| c.done) as i32,
            CounterEmpty => c.is_some_and(|c| c.empty) as i32,
            CounterFull => c.is_some_and(|c| c.full) as i32,
            CounterPreset => c.map_or(0, |c| c.preset),
            CounterValue => c.map_or(0, |c| c.value),
            TimerIecDone => e.is_some_and(|e| e.q) as i32,
            TimerIecPreset => e.map_or(0, |e| e.preset),
            TimerIecValue => e.map_or(0, |e| e.elapsed_ms / e.base_ms.max(1)),
        }
    }

    /// Writes a variable (a bit takes `value != 0`); read-only kinds and
    /// missing variables are left alone.
    pub fn write(&mut self, v: VarRef, value: i32) {
        use VarKind::*;
        let i = v.index as usize;
        fn set<T>(slot: Option<&mut T>, v: T) {
            if let Some(s) = slot {
                *s = v;
            }
        }
        match v.kind {
            Bit => set(self.bits.get_mut(i), value != 0),
            Output => set(self.outputs.get_mut(i), value != 0),
            ErrorBit => set(self.errors.get_mut(i), value != 0),
            Word => set(self.words.get_mut(i), value),
            WordOutput => set(self.word_out.get_mut(i), value),
            FloatOutput => set(self.float_out.get_mut(i), value),
            TimerPreset => set(self.timers.get_mut(i).map(|t| &mut t.preset), value),
            MonostablePreset => set(self.monos.get_mut(i).map(|m| &mut m.preset), value),
            CounterPreset => set(self.counters.get_mut(i).map(|c| &mut c.preset), value),
            CounterValue => set(self.counters.get_mut(i).map(|c| &mut c.value), value),
            TimerIecPreset => set(self.iec.get_mut(i).map(|t| &mut t.preset), value),
            _ => {}
        }
    }

    /// Old timer `n` for one scan of `dt_ms` with its input; returns
    /// (done, running).
    pub fn timer(&mut self, n: u32, input: bool, dt_ms: i32) -> (bool, bool) {
        let Some(t) = self.timers.get_mut(n as usize) else {
            return (false, false);
        };
        if !input {
            t.running = false;
            t.done = false;
            t.left_ms = ms(t.preset, t.base_ms);
        } else if t.left_ms > 0 {
            t.left_ms -= dt_ms;
            t.running = true;
            t.done = false;
        } else {
            t.running = false;
            t.done = true;
        }
        (t.done, t.running)
    }

    /// Monostable `n` for one scan; returns running. Not retriggerable.
    /// The time left stops at 0 (ClassicLadder's can go below 0 when the
    /// scan does not divide the preset, and then never triggers again).
    pub fn monostable(&mut self, n: u32, input: bool, dt_ms: i32) -> bool {
        let Some(m) = self.monos.get_mut(n as usize) else {
            return false;
        };
        if input && !m.input_bak && m.left_ms == 0 {
            m.running = true;
            m.left_ms = ms(m.preset, m.base_ms);
        }
        if m.left_ms > 0 {
            m.left_ms = (m.left_ms - dt_ms).max(0);
        } else {
            m.running = false;
        }
        m.input_bak = input;
        m.running
    }

    /// Counter `n` with its inputs (reset, preset, up, down); returns
    /// (empty, done, full).
    pub fn counter(&mut self, n: u32, inputs: [bool; 4]) -> (bool, bool, bool) {
        let Some(c) = self.counters.get_mut(n as usize) else {
            return (false, false, false);
        };
        let [reset, preset, up, down] = inputs;
        if up && !c.up_bak {
            c.value_bak = c.value;
            c.value = if c.value >= COUNTER_MAX {
                0
            } else {
                c.value + 1
            };
        }
        if down && !c.down_bak {
            c.value_bak = c.value;
            c.value = if c.value <= 0 {
                COUNTER_MAX
            } else {
                c.value - 1
            };
        }
        if preset {
            c.value_bak = c.value;
            c.value = c.preset;
        }
        if reset {
            c.value_bak = c.value;
            c.value = 0;
        }
        c.up_bak = up;
        c.down_bak = down;
        c.done = c.value == c.preset;
        c.empty = c.value == COUNTER_MAX && c.value_bak == 0;
        c.full = c.value == 0 && c.value_bak == COUNTER_MAX;
        (c.empty, c.done, c.full)
    }

    /// IEC timer `n` for one scan; returns Q.
    pub fn timer_iec(&mut self, n: u32, input: bool, dt_ms: i32) -> bool {
        let Some(t) = self.iec.get_mut(n as usize) else {
            return false;
        };
        let preset_ms = ms(t.preset, t.base_ms);
        let tick = |t: &mut IecState| {
            if t.started {
                t.elapsed_ms = t.elapsed_ms.saturating_add(dt_ms).min(preset_ms);
            } else {
                t.started = true;
                t.elapsed_ms = 0;
            }
        };
        match t.mode {
            IecMode::OnDelay => {
                if input {
                    tick(t);
                    t.q = t.elapsed_ms >= preset_ms;
                } else {
                    t.started = false;
                    t.elapsed_ms = 0;
                    t.q = false;
                }
            }
            IecMode::OffDelay => {
                if input {
                    t.q = true;
                    t.started = false;
                    t.elapsed_ms = 0;
                } else if t.q {
                    tick(t);
                    if t.elapsed_ms >= preset_ms {
                        t.q = false;
                        t.started = false;
                    }
                }
            }
            IecMode::Pulse => {
                if input && !t.input_bak && !t.q {
                    t.started = false;
                    tick(t);
                    t.q = true;
                } else if t.q {
                    tick(t);
                }
                if t.q && t.elapsed_ms >= preset_ms {
                    t.q = false;
                    t.started = false;
                }
            }
        }
        t.input_bak = input;
        t.q
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::IecSetup;

    fn with_iec(mode: IecMode, preset: i32) -> Vars {
        let s = Sizes::default();
        let mut p = Program::empty(&s);
        p.timers_iec[0] = IecSetup {
            base_ms: 100,
            preset,
            mode,
        };
        let mut v = Vars::new(&s);
        v.reset(&p);
        v
    }

    /// Q over `inputs`, one 100 ms scan each.
    fn run(v: &mut Vars, inputs: &str) -> String {
        inputs
            .chars()
            .map(|c| {
                if v.timer_iec(0, c == '1', 100) {
                    '1'
                } else {
                    '0'
                }
            })
            .collect()
    }

    #[test]
    fn iec_timers_over_many_scans() {
        // Preset 3 x 100 ms.
        let mut ton = with_iec(IecMode::OnDelay, 3);
        assert_eq!(run(&mut ton, "0111110110000"), "0000110000000");
        let mut tof = with_iec(IecMode::OffDelay, 3);
        assert_eq!(run(&mut tof, "0110000011000"), "0111110011111");
        let mut tp = with_iec(IecMode::Pulse, 3);
        assert_eq!(run(&mut tp, "01000011111100"), "01110011100000");
        assert_eq!(
            tp.read(VarRef {
                kind: VarKind::TimerIecValue,
                index: 0
            }),
            3
        );
        let mut zero = with_iec(IecMode::OnDelay, 0);
        assert_eq!(run(&mut zero, "0110"), "0110");
    }

    #[test]
    fn counter_wraps_both_ways() {
        let s = Sizes::default();
        let mut p = Program::empty(&s);
        p.counters[0] = 2;
        let mut v = Vars::new(&s);
        v.reset(&p);
        let up = |v: &mut Vars, on: bool| v.counter(0, [false, false, on, false]);
        assert_eq!(up(&mut v, true), (false, false, false));
        up(&mut v, false);
        assert_eq!(up(&mut v, true), (false, true, false), "2 = preset: done");
        let down = |v: &mut Vars, on: bool| v.counter(0, [false, false, false, on]);
        down(&mut v, true);
        down(&mut v, false);
        down(&mut v, true);
        down(&mut v, false);
        assert_eq!(down(&mut v, true), (true, false, false), "0 -> 9999: empty");
        assert_eq!(
            v.read(VarRef {
                kind: VarKind::CounterValue,
                index: 0
            }),
            COUNTER_MAX
        );
        down(&mut v, false);
        assert_eq!(up(&mut v, true), (false, false, true), "9999 -> 0: full");
        assert_eq!(
            v.counter(0, [false, true, false, false]),
            (false, true, false),
            "preset"
        );
        assert!(!v.counter(0, [true, true, false, false]).1, "reset wins");
    }
}
