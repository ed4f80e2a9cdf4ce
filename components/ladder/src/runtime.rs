//! The ladder scan: each main section's rungs from its first to its last,
//! each rung column by column (left to right) and in a column row by row,
//! as ClassicLadder evaluates them. Power reaches a cell from the cell on
//! its left, or from any cell on the left of a run of vertical wires it
//! belongs to; column 0 is on the left rail. `-(J)-` jumps to another
//! rung, `-(C)-` runs a sub-routine section and comes back after the
//! rung. A scan that runs more rungs than a budget allows (a jump loop)
//! stops there and is counted. Nothing here allocates after
//! [`Engine::new`].

use crate::expr::{eval, ExprForm};
use crate::model::{
    CoilKind, ContactKind, Element, Program, Rung, SectionRole, Sizes, CELLS, RUNG_HEIGHT,
    RUNG_WIDTH,
};
use crate::vars::Vars;

/// Sub-routine calls that may nest.
pub const CALL_DEPTH: usize = 25;

/// The dynamic state of one rung: each cell's output and, for edge
/// contacts, the variable at the previous scan.
#[derive(Debug, Clone, Copy)]
struct RungState {
    out: [bool; CELLS],
    bak: [bool; CELLS],
}

const CLEAR: RungState = RungState {
    out: [false; CELLS],
    bak: [false; CELLS],
};

/// A ladder runtime: the memory and the rungs' dynamic state.
#[derive(Debug, Clone)]
pub struct Engine {
    /// The variables.
    pub vars: Vars,
    rungs: Vec<RungState>,
    /// Scans stopped early by the rung budget (a jump loop).
    pub overruns: u64,
}

/// What one rung asks for after it ran.
#[derive(Debug, Clone, Copy, Default)]
struct Flow {
    jump: Option<u32>,
    call: Option<u32>,
}

fn idx(x: usize, y: usize) -> usize {
    x * RUNG_HEIGHT + y
}

/// Whether power reaches the left of cell (x, y).
fn left(rung: &Rung, out: &[bool; CELLS], x: usize, y: usize) -> bool {
    if x == 0 {
        return true;
    }
    if x >= RUNG_WIDTH || y >= RUNG_HEIGHT {
        return false;
    }
    let o = |yy: usize| out[idx(x - 1, yy)];
    let top = |yy: usize| rung.cells[idx(x, yy)].top;
    if o(y) {
        return true;
    }
    let mut p = y;
    while p > 0 && top(p) {
        p -= 1;
        if o(p) {
            return true;
        }
    }
    let mut p = y + 1;
    while p < RUNG_HEIGHT && top(p) {
        if o(p) {
            return true;
        }
        p += 1;
    }
    false
}

impl Engine {
    /// A runtime for a module of `sizes` (allocates).
    pub fn new(sizes: &Sizes) -> Engine {
        Engine {
            vars: Vars::new(sizes),
            rungs: vec![CLEAR; sizes.rungs],
            overruns: 0,
        }
    }

    /// Starts `prog` afresh: memory cleared, block setups taken, and the
    /// edge contacts primed with their variables as they are now (a
    /// falling-edge contact on a bit that is off does not fire at the
    /// first scan, as in ClassicLadder).
    pub fn install(&mut self, prog: &Program) {
        self.vars.reset(prog);
        self.rungs.fill(CLEAR);
        for (rung, st) in prog.rungs.iter().zip(self.rungs.iter_mut()) {
            for (cell, bak) in rung.cells.iter().zip(st.bak.iter_mut()) {
                if let Element::Contact(kind, v) = cell.element {
                    let on = self.vars.read(v) != 0;
                    *bak = match kind {
                        ContactKind::Falling => !on,
                        _ => on,
                    };
                }
            }
        }
    }

    /// One scan of `prog`, `dt_ms` after the previous.
    pub fn scan(&mut self, prog: &Program, dt_ms: i32) {
        let mut budget = 16 * prog.rungs.len() + 64;
        for s in 0..prog.sections.len() {
            if prog.sections[s].role == SectionRole::Main
                && !self.section(prog, s, dt_ms, &mut budget)
            {
                self.overruns += 1;
                return;
            }
        }
    }

    /// Runs main section `s` (and what it calls); false when the budget
    /// ran out.
    fn section(&mut self, prog: &Program, s: usize, dt_ms: i32, budget: &mut usize) -> bool {
        // Return points: (section, rung to go on with, or None when the
        // caller had finished).
        let mut stack = [(0usize, None::<usize>); CALL_DEPTH];
        let mut depth = 0usize;
        let mut sec = s;
        let mut r = prog.sections[s].first as usize;
        loop {
            if *budget == 0 {
                return false;
            }
            *budget -= 1;
            let Some(rung) = prog.rungs.get(r) else {
                return true;
            };
            let flow = self.rung(prog, r, dt_ms);
            let section = prog.sections[sec];
            let at_last = r == section.last as usize;
            if let Some(sub) = flow.call {
                let target = prog
                    .sections
                    .iter()
                    .position(|x| x.role == SectionRole::SubRoutine(sub));
                if let (Some(t), true) = (target, depth < CALL_DEPTH) {
                    let back = (!at_last)
                        .then_some(rung.next)
                        .and_then(|n| usize::try_from(n).ok());
                    stack[depth] = (sec, back);
                    depth += 1;
                    sec = t;
                    r = prog.sections[t].first as usize;
                    continue;
                }
            } else if let Some(j) = flow.jump {
                r = j as usize;
                continue;
            }
            if !at_last {
                match usize::try_from(rung.next) {
                    Ok(n) => {
                        r = n;
                        continue;
                    }
                    Err(_) => return true,
                }
            }
            // The section's last rung: a main section is done; a
            // sub-routine returns to the first caller with rungs left.
            loop {
                if depth == 0 {
                    return true;
                }
                depth -= 1;
                let (caller, back) = stack[depth];
                if let Some(b) = back {
                    sec = caller;
                    r = b;
                    break;
                }
            }
        }
    }

    /// Runs rung `r` once.
    fn rung(&mut self, prog: &Program, r: usize, dt_ms: i32) -> Flow {
        let mut flow = Flow::default();
        let (Some(rung), Some(st)) = (prog.rungs.get(r), self.rungs.get_mut(r)) else {
            return flow;
        };
        let vars = &mut self.vars;
        for x in 0..RUNG_WIDTH {
            for y in 0..RUNG_HEIGHT {
                let i = idx(x, y);
                match rung.cells[i].element {
                    Element::Free | Element::Unusable => {}
                    Element::Connection => st.out[i] = left(rung, &st.out, x, y),
                    Element::Contact(kind, v) => {
                        let mut on = vars.read(v) != 0;
                        if matches!(kind, ContactKind::Closed | ContactKind::Falling) {
                            on = !on;
                        }
                        let level = on;
                        if matches!(kind, ContactKind::Rising | ContactKind::Falling) && st.bak[i] {
                            on = false;
                        }
                        st.out[i] = on && left(rung, &st.out, x, y);
                        st.bak[i] = level;
                    }
                    Element::Coil(kind, v) => {
                        let p = left(rung, &st.out, x, y);
                        match kind {
                            CoilKind::Normal => vars.write(v, p as i32),
                            CoilKind::Inverted => vars.write(v, !p as i32),
                            CoilKind::Set if p => vars.write(v, 1),
                            CoilKind::Reset if p => vars.write(v, 0),
                            _ => {}
                        }
                    }
                    Element::Jump(n) if left(rung, &st.out, x, y) => flow.jump = Some(n),
                    Element::Call(n) if left(rung, &st.out, x, y) => flow.call = Some(n),
                    Element::Timer(n) if x >= 1 && y + 1 < RUNG_HEIGHT => {
                        let input = left(rung, &st.out, x - 1, y);
                        let (done, running) = vars.timer(n, input, dt_ms);
                        st.out[i] = done;
                        st.out[idx(x, y + 1)] = running;
                    }
                    Element::Monostable(n) if x >= 1 => {
                        let input = left(rung, &st.out, x - 1, y);
                        st.out[i] = vars.monostable(n, input, dt_ms);
                    }
                    Element::Counter(n) if x >= 1 && y + 3 < RUNG_HEIGHT => {
                        let ins = [0, 1, 2, 3].map(|k| left(rung, &st.out, x - 1, y + k));
                        let (empty, done, full) = vars.counter(n, ins);
                        st.out[i] = empty;
                        st.out[idx(x, y + 1)] = done;
                        st.out[idx(x, y + 2)] = full;
                    }
                    Element::TimerIec(n) if x >= 1 => {
                        let input = left(rung, &st.out, x - 1, y);
                        st.out[i] = vars.timer_iec(n, input, dt_ms);
                    }
                    Element::Compare(n) if x >= 2 => {
                        let ok = prog.exprs.get(n as usize).is_some_and(|e| match e.form {
                            ExprForm::Compare { op, split } => {
                                let ops = e.used();
                                let split = (split as usize).min(ops.len());
                                let read = |v| vars.read(v);
                                op.test(eval(&ops[..split], &read), eval(&ops[split..], &read))
                            }
                            _ => false,
                        });
                        st.out[i] = ok && left(rung, &st.out, x - 2, y);
                    }
                    Element::Operate(n) if x >= 2 && left(rung, &st.out, x - 2, y) => {
                        if let Some(e) = prog.exprs.get(n as usize) {
                            if let ExprForm::Assign { target } = e.form {
                                let v = eval(e.used(), &|v| vars.read(v));
                                vars.write(target, v);
                            }
                        }
                    }
                    _ => {}
                }
            }
        }
        flow
    }
}
