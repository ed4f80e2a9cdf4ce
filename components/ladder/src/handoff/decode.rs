//! Decoding a handed-over program, all at once ([`decode`]) or a bounded
//! number of words per call ([`Intake`], what the refresh funct uses, so
//! that a new program never costs one period more than a few µs however
//! large the module's sizes are).
//!
//! Every item has a fixed place in the region, so the work is a list of
//! steps (a section, a rung, an expression, a block setup, then each
//! section's rung chain) that can stop after any one of them and go on in
//! the next period.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use super::{region_words, sequence, unchanged, Part, Refusal, BODY, EXPR_WORDS, RUNG_WORDS};
use crate::expr::{CmpOp, Expr, ExprForm, Op, MAX_OPS};
use crate::model::{
    Cell, Element, IecMode, IecSetup, Program, Rung, Section, SectionRole, Sizes, TimerSetup,
    VarRef,
};

/// The kinds of step, in the order they run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Section,
    Rung,
    Expr,
    /// A timer, then the monostables after the timers.
    Timer,
    Counter,
    Iec,
    /// Checks section `index`'s rung chain (after every rung is in).
    Chain,
    Done,
}

impl Kind {
    fn after(self) -> Kind {
        match self {
            Kind::Section => Kind::Rung,
            Kind::Rung => Kind::Expr,
            Kind::Expr => Kind::Timer,
            Kind::Timer => Kind::Counter,
            Kind::Counter => Kind::Iec,
            Kind::Iec => Kind::Chain,
            Kind::Chain | Kind::Done => Kind::Done,
        }
    }

    /// How many items of this kind a module of `s` has.
    fn count(self, s: &Sizes) -> usize {
        match self {
            Kind::Section | Kind::Chain => s.sections,
            Kind::Rung => s.rungs,
            Kind::Expr => s.exprs,
            Kind::Timer => s.timers + s.monostables,
            Kind::Counter => s.counters,
            Kind::Iec => s.timers_iec,
            Kind::Done => 0,
        }
    }

    /// Roughly how many words of work one item is (a chain check walks
    /// up to every rung, a few words' worth each).
    fn weight(self, s: &Sizes) -> usize {
        match self {
            Kind::Chain => 1 + s.rungs / 4,
            k => k.stride(),
        }
    }

    /// The words of one item in the region.
    fn stride(self) -> usize {
        match self {
            Kind::Rung => RUNG_WORDS,
            Kind::Expr => EXPR_WORDS,
            _ => 1,
        }
    }

    /// Where item 0 of this kind starts in the region.
    fn start(self, s: &Sizes) -> usize {
        let rungs = BODY + s.sections;
        let exprs = rungs + s.rungs * RUNG_WORDS;
        let timers = exprs + s.exprs * EXPR_WORDS;
        let counters = timers + s.timers + s.monostables;
        match self {
            Kind::Section | Kind::Chain | Kind::Done => BODY,
            Kind::Rung => rungs,
            Kind::Expr => exprs,
            Kind::Timer => timers,
            Kind::Counter => counters,
            Kind::Iec => counters + s.counters,
        }
    }
}

/// One item to decode or check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Step {
    kind: Kind,
    index: usize,
}

impl Step {
    /// The first step for a module of `s`.
    fn first(s: &Sizes) -> Step {
        Step {
            kind: Kind::Section,
            index: 0,
        }
        .settled(s)
    }

    /// The step after this one.
    fn next(self, s: &Sizes) -> Step {
        Step {
            index: self.index + 1,
            ..self
        }
        .settled(s)
    }

    /// Moves past kinds with no item left.
    fn settled(mut self, s: &Sizes) -> Step {
        while self.kind != Kind::Done && self.index >= self.kind.count(s) {
            self.kind = self.kind.after();
            self.index = 0;
        }
        self
    }

    /// Decodes (or checks) this step's item into `p`.
    fn run(self, words: &[AtomicU64], s: &Sizes, p: &mut Program) -> Result<(), Refusal> {
        let i = self.index;
        let mut r = Reader {
            words,
            pos: self.kind.start(s) + i * self.kind.stride(),
        };
        let item = i as u32;
        match self.kind {
            Kind::Section => {
                p.sections[i] = decode_section(r.next(), s).ok_or((Part::Section, item))?;
            }
            Kind::Rung => {
                decode_rung(&mut r, s, &mut p.rungs[i]).map_err(|_| (Part::Rung, item))?;
            }
            Kind::Expr => {
                decode_expr(&mut r, s, &mut p.exprs[i]).map_err(|_| (Part::Expr, item))?;
            }
            Kind::Timer => {
                let t = decode_timer(r.next()).ok_or((Part::Setup, item))?;
                match p.timers.get_mut(i) {
                    Some(slot) => *slot = t,
                    None => p.monostables[i - s.timers] = t,
                }
            }
            Kind::Counter => {
                p.counters[i] = (r.next() & 0xffff_ffff) as u32 as i32;
            }
            Kind::Iec => {
                p.timers_iec[i] = decode_iec(r.next()).ok_or((Part::Setup, item))?;
            }
            Kind::Chain => {
                let sec = p.sections[i];
                let ok = sec.role == SectionRole::Unused
                    || (p.rungs[sec.first as usize].used
                        && p.rungs[sec.last as usize].used
                        && crate::compile::chain(p, &sec).is_ok());
                if !ok {
                    return Err((Part::Section, item));
                }
            }
            Kind::Done => {}
        }
        Ok(())
    }
}

/// Decodes the region's program into `p` (sized for `s`) without
/// allocating; a refusal names the part and item that is wrong.
pub fn decode(words: &[AtomicU64], s: &Sizes, p: &mut Program) -> Result<(), Refusal> {
    if words.len() < region_words(s) {
        return Err((Part::Setup, 0));
    }
    let mut step = Step::first(s);
    while step.kind != Kind::Done {
        step.run(words, s, p)?;
        step = step.next(s);
    }
    Ok(())
}

/// Watches the region for new programs and decodes each a bounded number
/// of words per [`poll`](Intake::poll), into spare storage. A program
/// whose sequence moves while it is being decoded is started again.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Intake {
    /// The last sequence answered (0: none).
    handled: u64,
    /// The sequence being decoded and the next step.
    work: Option<(u64, Step)>,
}

impl Intake {
    /// Nothing answered, nothing under way.
    pub fn new() -> Intake {
        Intake::default()
    }

    /// Decodes up to about `budget` words (at least one item) of the
    /// newest program into `spare`. Returns the program's sequence and
    /// its verdict once it is wholly decoded or refused, and the sequence
    /// did not move meanwhile; `None` while there is nothing new or the
    /// work goes on.
    pub fn poll(
        &mut self,
        words: &[AtomicU64],
        s: &Sizes,
        spare: &mut Program,
        budget: usize,
    ) -> Option<(u64, Result<(), Refusal>)> {
        let seq = sequence(words);
        let (wanted, mut step) = match self.work {
            Some((w, step)) if w == seq => (w, step),
            _ if seq == self.handled || seq & 1 == 1 => {
                self.work = None;
                return None;
            }
            _ if words.len() < region_words(s) => {
                return self.answer(words, seq, Err((Part::Setup, 0)));
            }
            _ => (seq, Step::first(s)),
        };
        let mut spent = 0;
        while step.kind != Kind::Done && spent < budget.max(1) {
            if let Err(refusal) = step.run(words, s, spare) {
                return self.answer(words, wanted, Err(refusal));
            }
            spent += step.kind.weight(s);
            step = step.next(s);
        }
        if step.kind == Kind::Done {
            self.answer(words, wanted, Ok(()))
        } else {
            self.work = Some((wanted, step));
            None
        }
    }

    /// Ends the work on `seq`: its verdict stands if the words did not
    /// move while it was decoded; otherwise the next poll starts again.
    fn answer(
        &mut self,
        words: &[AtomicU64],
        seq: u64,
        verdict: Result<(), Refusal>,
    ) -> Option<(u64, Result<(), Refusal>)> {
        self.work = None;
        if unchanged(words, seq) {
            self.handled = seq;
            Some((seq, verdict))
        } else {
            None
        }
    }
}

/// Reads words one after the other, 0 past the end.
struct Reader<'a> {
    words: &'a [AtomicU64],
    pos: usize,
}

impl Reader<'_> {
    fn next(&mut self) -> u64 {
        let v = self.words.get(self.pos).map_or(0, |w| w.load(Relaxed));
        self.pos += 1;
        v
    }
}

fn decode_section(w: u64, s: &Sizes) -> Option<Section> {
    let first = (w >> 32 & 0xffff) as u32;
    let last = (w >> 48) as u32;
    let role = match w & 0xff {
        0 => SectionRole::Unused,
        1 => SectionRole::Main,
        2 => SectionRole::SubRoutine((w >> 8 & 0xff_ffff) as u32),
        _ => return None,
    };
    (first < s.rungs as u32 && last < s.rungs as u32).then_some(Section { role, first, last })
}

fn decode_timer(w: u64) -> Option<TimerSetup> {
    let base_ms = (w & 0xffff_ffff) as u32 as i32;
    let preset = (w >> 32) as u32 as i32;
    ([60_000, 1000, 100].contains(&base_ms) && preset >= 0)
        .then_some(TimerSetup { base_ms, preset })
}

fn decode_iec(w: u64) -> Option<IecSetup> {
    let mode = match w >> 24 & 0xff {
        0 => IecMode::OnDelay,
        1 => IecMode::OffDelay,
        2 => IecMode::Pulse,
        _ => return None,
    };
    let base = decode_timer((w & 0xff_ffff) | (w & !0xffff_ffff))?;
    Some(IecSetup {
        base_ms: base.base_ms,
        preset: base.preset,
        mode,
    })
}

fn decode_rung(r: &mut Reader<'_>, s: &Sizes, rung: &mut Rung) -> Result<(), ()> {
    let h = r.next();
    rung.used = h & 1 == 1;
    rung.next = (h >> 32) as u32 as i32;
    if rung.next < -1 || rung.next as i64 >= s.rungs as i64 {
        return Err(());
    }
    for (i, c) in rung.cells.iter_mut().enumerate() {
        let w = r.next();
        let (x, y) = (i / crate::model::RUNG_HEIGHT, i % crate::model::RUNG_HEIGHT);
        let element = Element::from_codes(
            (w & 0xff) as i64,
            (w >> 16 & 0xffff) as i64,
            (w >> 32) as i64,
            x,
            y,
            s,
        )
        .map_err(|_| ())?;
        *c = Cell {
            element,
            top: w >> 8 & 1 == 1,
        };
    }
    Ok(())
}

fn decode_var(w: u64, s: &Sizes) -> Result<VarRef, ()> {
    VarRef::from_codes((w & 0xffff) as i64, (w >> 32) as i64, s).map_err(|_| ())
}

fn decode_expr(r: &mut Reader<'_>, s: &Sizes, e: &mut Expr) -> Result<(), ()> {
    let h = r.next();
    let target = r.next();
    let len = (h >> 24 & 0xff) as usize;
    if len > MAX_OPS {
        return Err(());
    }
    e.form = match h & 0xff {
        0 => ExprForm::Empty,
        1 => {
            let op = match h >> 8 & 0xff {
                0 => CmpOp::Eq,
                1 => CmpOp::Ne,
                2 => CmpOp::Lt,
                3 => CmpOp::Le,
                4 => CmpOp::Gt,
                5 => CmpOp::Ge,
                _ => return Err(()),
            };
            ExprForm::Compare {
                op,
                split: (h >> 16 & 0xff) as u8,
            }
        }
        2 => {
            let t = decode_var(target, s)?;
            if !t.kind.is_writable() {
                return Err(());
            }
            ExprForm::Assign { target: t }
        }
        _ => return Err(()),
    };
    e.len = len as u8;
    for op in e.ops.iter_mut() {
        let w = r.next();
        let val = (w >> 32) as u32;
        let n = u8::try_from(val).map_err(|_| ());
        *op = match w & 0xff {
            1 => Op::Const(val as i32),
            2 => Op::Load(decode_var(w >> 8 & 0xffff | w & !0xffff_ffff, s)?),
            3 => Op::Not,
            4 => Op::Neg,
            5 => Op::Add,
            6 => Op::Sub,
            7 => Op::Mul,
            8 => Op::Div,
            9 => Op::Rem,
            10 => Op::Pow,
            11 => Op::And,
            12 => Op::Or,
            13 => Op::Abs,
            14 => Op::Min(n?),
            15 => Op::Max(n?),
            16 => Op::Avg(n?),
            _ => return Err(()),
        };
    }
    e.check().map_err(|_| ())
}
