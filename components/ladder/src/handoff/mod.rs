//! How the `classicladder` loader hands a checked program to
//! `classicladder_rt`: through a named region of the HAL instance
//! ([`REGION`]) that the module allocates at `loadrt`, sized for its
//! [`Sizes`]. The module writes a magic word and its sizes; the loader
//! writes the program's words between two bumps of a sequence word (odd
//! while writing, as a seqlock), and the refresh funct decodes a new
//! sequence into spare storage, checks every number, and swaps it in
//! only when the sequence did not move meanwhile. The region is shared
//! memory any process may write, so decoding trusts nothing and never
//! allocates.
//!
//! Words: 0 magic, 1 sequence, 2 status (written by the module), 3 the
//! sequence the status is about, 4 refusal detail, 5.. the sizes, then
//! from [`BODY`] the sections, rungs, expressions, timers, monostables,
//! counters and IEC timers, each with a fixed number of words.

use std::sync::atomic::{AtomicU64, Ordering::*};

mod decode;

pub use decode::{decode, Intake};

use crate::expr::{CmpOp, ExprForm, Op, MAX_OPS};
use crate::model::{IecMode, Program, SectionRole, Sizes, VarRef, CELLS};

/// The region's name.
pub const REGION: &str = "classicladder.0.program";
/// The magic word, "cladder1".
pub const MAGIC: u64 = u64::from_le_bytes(*b"cladder1");
const SEQ: usize = 1;
const STATUS: usize = 2;
const STATUS_SEQ: usize = 3;
const DETAIL: usize = 4;
const SIZES: usize = 5;
/// Where the program's words start.
pub const BODY: usize = 24;
const _: () = assert!(SIZES + Sizes::COUNT <= BODY, "the sizes overlap the body");
const RUNG_WORDS: usize = 1 + CELLS;
const EXPR_WORDS: usize = 2 + MAX_OPS;

/// What the module says of the last program handed to it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// No program yet.
    Waiting,
    /// Running the program of this sequence.
    Running(u64),
    /// Refused the program of this sequence (part, item).
    Refused(u64, Part, u32),
}

/// The parts of the handed-over words, for a refusal's detail.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// A section.
    Section = 1,
    /// A rung.
    Rung = 2,
    /// An expression.
    Expr = 3,
    /// A timer, monostable, counter or IEC timer setup.
    Setup = 4,
}

impl Part {
    fn from_code(c: u64) -> Part {
        match c {
            1 => Part::Section,
            2 => Part::Rung,
            3 => Part::Expr,
            _ => Part::Setup,
        }
    }
}

impl std::fmt::Display for Part {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Part::Section => "section",
            Part::Rung => "rung",
            Part::Expr => "expression",
            Part::Setup => "block setup",
        })
    }
}

/// A refusal: which part and item.
pub type Refusal = (Part, u32);

/// The words a module of `sizes` needs.
pub fn region_words(s: &Sizes) -> usize {
    BODY + s.sections
        + s.rungs * RUNG_WORDS
        + s.exprs * EXPR_WORDS
        + s.timers
        + s.monostables
        + s.counters
        + s.timers_iec
}

/// Written by the module at `loadrt`.
pub fn init(words: &[AtomicU64], s: &Sizes) {
    for (i, v) in s.to_array().iter().enumerate() {
        if let Some(w) = words.get(SIZES + i) {
            w.store(*v as u64, Relaxed);
        }
    }
    if let Some(w) = words.first() {
        w.store(MAGIC, Release);
    }
}

/// The sizes the module wrote, if the words are the module's.
pub fn read_sizes(words: &[AtomicU64]) -> Option<Sizes> {
    if words.len() < BODY || words[0].load(Acquire) != MAGIC {
        return None;
    }
    let s = Sizes::from_array(std::array::from_fn(|i| {
        words[SIZES + i].load(Relaxed) as usize
    }));
    (region_words(&s) <= words.len()).then_some(s)
}

/// The module's status.
pub fn status(words: &[AtomicU64]) -> Status {
    let get = |i: usize| words.get(i).map_or(0, |w| w.load(Acquire));
    match get(STATUS) {
        1 => Status::Running(get(STATUS_SEQ)),
        2 => {
            let d = get(DETAIL);
            Status::Refused(get(STATUS_SEQ), Part::from_code(d & 0xff), (d >> 32) as u32)
        }
        _ => Status::Waiting,
    }
}

/// Sets the module's status (by the module).
pub fn set_status(words: &[AtomicU64], s: Status) {
    let (code, seq, detail) = match s {
        Status::Waiting => (0, 0, 0),
        Status::Running(q) => (1, q, 0),
        Status::Refused(q, p, i) => (2, q, p as u64 | (i as u64) << 32),
    };
    if words.len() > DETAIL {
        words[DETAIL].store(detail, Relaxed);
        words[STATUS_SEQ].store(seq, Relaxed);
        words[STATUS].store(code, Release);
    }
}

fn var_word(v: VarRef) -> u64 {
    v.kind.code() as u64 | (v.index as u64) << 32
}

fn op_word(op: Op) -> u64 {
    let (tag, var, val): (u64, u64, u32) = match op {
        Op::Const(c) => (1, 0, c as u32),
        Op::Load(v) => (2, v.kind.code() as u64, v.index),
        Op::Not => (3, 0, 0),
        Op::Neg => (4, 0, 0),
        Op::Add => (5, 0, 0),
        Op::Sub => (6, 0, 0),
        Op::Mul => (7, 0, 0),
        Op::Div => (8, 0, 0),
        Op::Rem => (9, 0, 0),
        Op::Pow => (10, 0, 0),
        Op::And => (11, 0, 0),
        Op::Or => (12, 0, 0),
        Op::Abs => (13, 0, 0),
        Op::Min(n) => (14, 0, n as u32),
        Op::Max(n) => (15, 0, n as u32),
        Op::Avg(n) => (16, 0, n as u32),
    };
    tag | var << 8 | (val as u64) << 32
}

fn cmp_code(op: CmpOp) -> u64 {
    match op {
        CmpOp::Eq => 0,
        CmpOp::Ne => 1,
        CmpOp::Lt => 2,
        CmpOp::Le => 3,
        CmpOp::Gt => 4,
        CmpOp::Ge => 5,
    }
}

/// The body words of `p` for a module of `s` (by the loader).
pub fn encode(p: &Program, s: &Sizes) -> Vec<u64> {
    let mut w = Vec::with_capacity(region_words(s) - BODY);
    for sec in p.sections.iter().take(s.sections) {
        let (tag, sub) = match sec.role {
            SectionRole::Unused => (0u64, 0u64),
            SectionRole::Main => (1, 0),
            SectionRole::SubRoutine(n) => (2, n as u64 & 0xff_ffff),
        };
        w.push(
            tag | sub << 8 | (sec.first as u64 & 0xffff) << 32 | (sec.last as u64 & 0xffff) << 48,
        );
    }
    for r in p.rungs.iter().take(s.rungs) {
        w.push(r.used as u64 | ((r.next as u32) as u64) << 32);
        for c in &r.cells {
            let (t, vc, n) = c.element.codes();
            w.push(t as u64 | (c.top as u64) << 8 | (vc as u64) << 16 | (n as u64) << 32);
        }
    }
    for e in p.exprs.iter().take(s.exprs) {
        let (tag, cmp, split, target) = match e.form {
            ExprForm::Empty => (0, 0, 0, 0),
            ExprForm::Compare { op, split } => (1, cmp_code(op), split as u64, 0),
            ExprForm::Assign { target } => (2, 0, 0, var_word(target)),
        };
        w.push(tag | cmp << 8 | split << 16 | (e.len as u64) << 24);
        w.push(target);
        w.extend(e.ops.iter().map(|o| op_word(*o)));
    }
    for t in p.timers.iter().chain(&p.monostables) {
        w.push(t.base_ms as u32 as u64 | (t.preset as u32 as u64) << 32);
    }
    w.extend(p.counters.iter().map(|c| *c as u32 as u64));
    for t in &p.timers_iec {
        let mode = match t.mode {
            IecMode::OnDelay => 0u64,
            IecMode::OffDelay => 1,
            IecMode::Pulse => 2,
        };
        w.push(t.base_ms as u32 as u64 & 0xff_ffff | mode << 24 | (t.preset as u32 as u64) << 32);
    }
    w
}

/// Writes `body` as a new program (by the loader); returns its sequence.
pub fn publish(words: &[AtomicU64], body: &[u64]) -> Option<u64> {
    if words.len() < BODY + body.len() {
        return None;
    }
    let seq = words[SEQ].load(Acquire);
    let writing = (seq | 1).wrapping_add(if seq & 1 == 1 { 2 } else { 0 });
    words[SEQ].store(writing, Relaxed);
    std::sync::atomic::fence(Release);
    for (slot, v) in words[BODY..].iter().zip(body) {
        slot.store(*v, Relaxed);
    }
    let done = writing.wrapping_add(1);
    words[SEQ].store(done, Release);
    Some(done)
}

/// The sequence of the program in the region (odd: being written).
pub fn sequence(words: &[AtomicU64]) -> u64 {
    words.get(SEQ).map_or(0, |w| w.load(Acquire))
}

/// Whether the sequence is still `seq` (after decoding).
pub fn unchanged(words: &[AtomicU64], seq: u64) -> bool {
    std::sync::atomic::fence(Acquire);
    words.get(SEQ).is_some_and(|w| w.load(Relaxed) == seq)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::Expr;
    use crate::model::{Cell, ContactKind, Element, IecSetup, Section};

    fn small() -> Sizes {
        Sizes {
            rungs: 3,
            exprs: 2,
            sections: 2,
            timers: 1,
            monostables: 1,
            counters: 1,
            timers_iec: 1,
            ..Sizes::default()
        }
    }

    fn program(s: &Sizes) -> Program {
        let mut p = Program::empty(s);
        p.rungs[0].used = true;
        p.rungs[0].cells[0] = Cell {
            element: Element::Contact(
                ContactKind::Rising,
                VarRef {
                    kind: crate::model::VarKind::Input,
                    index: 1,
                },
            ),
            top: false,
        };
        p.sections[0] = Section {
            role: SectionRole::Main,
            first: 0,
            last: 0,
        };
        p.exprs[1] = Expr::assign("%W1:=%IW0*3", s).unwrap();
        p.timers_iec[0] = IecSetup {
            base_ms: 100,
            preset: 7,
            mode: IecMode::Pulse,
        };
        p
    }

    fn region(s: &Sizes) -> Vec<AtomicU64> {
        let w: Vec<AtomicU64> = (0..region_words(s)).map(|_| AtomicU64::new(0)).collect();
        init(&w, s);
        w
    }

    #[test]
    fn round_trip_and_sizes() {
        let s = small();
        let w = region(&s);
        assert_eq!(read_sizes(&w), Some(s));
        let p = program(&s);
        let seq = publish(&w, &encode(&p, &s)).unwrap();
        assert_eq!(seq & 1, 0);
        assert_eq!(sequence(&w), seq);
        let mut back = Program::empty(&s);
        decode(&w, &s, &mut back).unwrap();
        assert_eq!(back, p);
        set_status(&w, Status::Refused(seq, Part::Rung, 2));
        assert_eq!(status(&w), Status::Refused(seq, Part::Rung, 2));
        assert!(read_sizes(&w[..3]).is_none());
    }

    #[test]
    fn damaged_words_are_refused_never_a_panic() {
        let s = small();
        let w = region(&s);
        let body = encode(&program(&s), &s);
        let mut back = Program::empty(&s);
        // A section past the rungs, an unknown cell, an unbalanced
        // expression: each refused, naming its part.
        let cases: [(usize, u64, Part); 3] = [
            (0, 1 | 9 << 32, Part::Section),
            (s.sections + 1, 77, Part::Rung),
            (
                s.sections + s.rungs * RUNG_WORDS + EXPR_WORDS + 2,
                5,
                Part::Expr,
            ),
        ];
        for (at, v, part) in cases {
            let mut b = body.clone();
            b[at] = v;
            publish(&w, &b).unwrap();
            assert_eq!(decode(&w, &s, &mut back).unwrap_err().0, part, "word {at}");
        }
        // Every word replaced by a few values: decoded or refused.
        for at in 0..body.len() {
            for v in [0, 1, u64::MAX, 0x8000_0000_0000_0063, 0xffff_0032] {
                let mut b = body.clone();
                b[at] = v;
                publish(&w, &b).unwrap();
                let _ = decode(&w, &s, &mut back);
            }
        }
    }

    #[test]
    fn a_program_is_taken_a_few_words_per_poll() {
        let s = Sizes {
            rungs: 40,
            ..small()
        };
        let w = region(&s);
        let p = program(&s);
        let mut intake = Intake::new();
        let mut spare = Program::empty(&s);
        assert_eq!(intake.poll(&w, &s, &mut spare, 64), None, "nothing yet");
        let seq = publish(&w, &encode(&p, &s)).unwrap();
        let mut polls = 1;
        let verdict = loop {
            if let Some(v) = intake.poll(&w, &s, &mut spare, 64) {
                break v;
            }
            polls += 1;
            assert!(polls < 1000, "never finished");
        };
        assert_eq!(verdict, (seq, Ok(())));
        assert!(polls >= region_words(&s) / 128, "{polls} polls: not spread");
        assert_eq!(spare, p);
        assert_eq!(intake.poll(&w, &s, &mut spare, 64), None, "answered once");
    }

    #[test]
    fn a_program_replaced_while_decoding_is_started_again() {
        let s = Sizes {
            rungs: 40,
            ..small()
        };
        let w = region(&s);
        let mut intake = Intake::new();
        let mut spare = Program::empty(&s);
        publish(&w, &encode(&program(&s), &s)).unwrap();
        assert_eq!(intake.poll(&w, &s, &mut spare, 64), None, "under way");
        // The second program has a bad section: the answer is about it.
        let mut body = encode(&program(&s), &s);
        body[1] = 9;
        let seq = publish(&w, &body).unwrap();
        let verdict = (0..1000).find_map(|_| intake.poll(&w, &s, &mut spare, 64));
        assert_eq!(verdict, Some((seq, Err((Part::Section, 1)))));
    }
}
