//! From a [`Project`] as written to a [`Program`] the module runs: every
//! cell, variable, block and expression checked against the module's
//! [`Sizes`], the rung chains of the sections followed, and the
//! expressions compiled. An error names the line of the `.clp` file.

use crate::clp::{Project, RawCell};
use crate::error::LadderError;
use crate::expr::{Expr, ExprForm};
use crate::model::{
    base_ms, Cell, Element, IecMode, IecSetup, Program, Section, SectionRole, Sizes, TimerSetup,
    RUNG_HEIGHT,
};

/// A checked program, and notes on what of the project is not run.
#[derive(Debug, Clone)]
pub struct Compiled {
    /// The program.
    pub program: Program,
    /// Parts of the project read but not acted on.
    pub notes: Vec<String>,
}

fn structure(what: String) -> LadderError {
    LadderError::Structure { what }
}

/// Checks `project` against `sizes` and builds its program.
pub fn compile(project: &Project, sizes: &Sizes) -> Result<Compiled, LadderError> {
    let mut prog = Program::empty(sizes);
    let mut notes = project.notes.clone();
    let mut uses: Vec<(usize, usize, bool)> = Vec::new(); // (expr, line, is_compare)
    for r in &project.rungs {
        if r.number >= sizes.rungs {
            return Err(structure(format!(
                "line {}: rung {} is past the {} rungs the module has (raise numRungs)",
                r.line, r.number, sizes.rungs
            )));
        }
        let rung = &mut prog.rungs[r.number];
        rung.used = true;
        rung.next = -1;
        if r.next >= 0 {
            rung.next = i32::try_from(r.next).unwrap_or(i32::MAX);
        }
        for (y, (line, row)) in r.rows.iter().enumerate() {
            for (x, raw) in row.iter().enumerate() {
                let cell =
                    cell(raw, x, y, sizes, &mut notes).map_err(|source| LadderError::Cell {
                        line: *line,
                        rung: r.number,
                        x,
                        y,
                        source,
                    })?;
                match cell.element {
                    Element::Compare(n) => uses.push((n as usize, *line, true)),
                    Element::Operate(n) => uses.push((n as usize, *line, false)),
                    _ => {}
                }
                rung.cells[x * RUNG_HEIGHT + y] = cell;
            }
        }
    }
    check_links(project, &prog)?;
    // A next rung that is not defined ends a chain (checked per section).
    let used: Vec<bool> = prog.rungs.iter().map(|r| r.used).collect();
    for r in prog.rungs.iter_mut() {
        if r.next >= 0 && !used.get(r.next as usize).copied().unwrap_or(false) {
            r.next = -1;
        }
    }
    sections(project, sizes, &mut prog)?;
    check_calls(project, &prog)?;
    expressions(project, sizes, &uses, &mut prog, &mut notes)?;
    setups(project, sizes, &mut prog)?;
    if !project.sequential.is_empty() {
        notes.push(format!(
            "sequential.csv (line {}): the Grafcet steps are not run (no section is sequential)",
            project.sequential[0]
        ));
    }
    Ok(Compiled {
        program: prog,
        notes,
    })
}

fn cell(
    raw: &RawCell,
    x: usize,
    y: usize,
    sizes: &Sizes,
    notes: &mut Vec<String>,
) -> Result<Cell, crate::model::CellError> {
    // Codes 100-103 are the editor's tools (wire to top, pointer, long
    // wire, eraser); an old editor could leave them in a saved rung.
    // They do nothing, as in ClassicLadder.
    if (100..=103).contains(&raw.code) {
        let note = format!(
            "editor tool code {} left in a rung is treated as empty",
            raw.code
        );
        if !notes.contains(&note) {
            notes.push(note);
        }
        return Ok(Cell {
            element: Element::Free,
            top: raw.top,
        });
    }
    Ok(Cell {
        element: Element::from_codes(raw.code, raw.var_code, raw.num, x, y, sizes)?,
        top: raw.top,
    })
}

/// Every jump names a rung the project defines. (A `#NEXTRUNG` only
/// matters inside a section's chain, which [`chain`] follows; the last
/// rung of a section may name anything, as ClassicLadder's saved ones
/// do.)
fn check_links(project: &Project, prog: &Program) -> Result<(), LadderError> {
    for r in &project.rungs {
        let rung = &prog.rungs[r.number];
        for c in &rung.cells {
            if let Element::Jump(n) = c.element {
                if !defined(prog, n as i64) {
                    return Err(structure(format!(
                        "line {}: rung {} jumps to rung {n}, which is not defined",
                        r.line, r.number
                    )));
                }
            }
        }
    }
    Ok(())
}

fn defined(prog: &Program, n: i64) -> bool {
    usize::try_from(n)
        .ok()
        .and_then(|n| prog.rungs.get(n))
        .is_some_and(|r| r.used)
}

fn sections(project: &Project, sizes: &Sizes, prog: &mut Program) -> Result<(), LadderError> {
    if project.sections.is_empty() && project.rungs.iter().any(|r| !r.rows.is_empty()) {
        return Err(structure(
            "the project has rungs but no sections.csv saying which run".into(),
        ));
    }
    for s in &project.sections {
        let at = format!("line {} (section {})", s.line, s.number);
        let idx = usize::try_from(s.number)
            .ok()
            .filter(|&n| n < sizes.sections)
            .ok_or_else(|| {
                structure(format!(
                    "{at}: past the {} sections the module has (raise numSections)",
                    sizes.sections
                ))
            })?;
        match s.language {
            0 => {}
            1 => {
                return Err(structure(format!(
                    "{at}: sequential (Grafcet) sections are not supported"
                )))
            }
            l => {
                return Err(structure(format!(
                    "{at}: language {l} is neither ladder (0) nor sequential (1)"
                )))
            }
        }
        let role = match s.sub {
            -1 => SectionRole::Main,
            // A call can only name a sub-routine below numSections, so a
            // larger number could never run (and would not fit the
            // hand-off's 24-bit field).
            n if (0..sizes.sections as i64).contains(&n) => SectionRole::SubRoutine(n as u32),
            n => {
                return Err(structure(format!(
                    "{at}: sub-routine number {n} is not between 0 and {} (numSections={})",
                    sizes.sections.saturating_sub(1) as i64,
                    sizes.sections
                )))
            }
        };
        for (what, r) in [("first", s.first), ("last", s.last)] {
            if !defined(prog, r) {
                return Err(structure(format!(
                    "{at}: its {what} rung {r} is not defined"
                )));
            }
        }
        let sec = Section {
            role,
            first: s.first as u32,
            last: s.last as u32,
        };
        chain(prog, &sec).map_err(|b| {
            structure(match b {
                ChainBreak::EndsAt(r) => format!(
                    "{at}: rung {r} ends the chain before the last rung {} is reached",
                    s.last
                ),
                ChainBreak::Loops => format!(
                    "{at}: the rungs from {} never reach the last rung {} (a loop)",
                    s.first, s.last
                ),
            })
        })?;
        prog.sections[idx] = sec;
    }
    Ok(())
}

/// Why a section's rungs do not lead from its first to its last.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChainBreak {
    /// The chain ends at this rung (no next rung, or one not defined).
    EndsAt(usize),
    /// The chain loops without reaching the last rung.
    Loops,
}

/// Follows a section's rungs from its first to its last (no allocation:
/// the realtime side checks decoded programs with it too).
pub fn chain(prog: &Program, s: &Section) -> Result<(), ChainBreak> {
    let mut r = s.first as usize;
    for _ in 0..prog.rungs.len() {
        if r == s.last as usize {
            return Ok(());
        }
        let next = prog.rungs.get(r).map_or(-1, |x| x.next);
        if next < 0 || !prog.rungs.get(next as usize).is_some_and(|x| x.used) {
            return Err(ChainBreak::EndsAt(r));
        }
        r = next as usize;
    }
    Err(ChainBreak::Loops)
}

fn check_calls(project: &Project, prog: &Program) -> Result<(), LadderError> {
    for r in &project.rungs {
        for c in &prog.rungs[r.number].cells {
            if let Element::Call(n) = c.element {
                let found = prog
                    .sections
                    .iter()
                    .any(|s| s.role == SectionRole::SubRoutine(n));
                if !found {
                    return Err(structure(format!(
                        "line {}: rung {} calls sub-routine {n}, which no section is",
                        r.line, r.number
                    )));
                }
            }
        }
    }
    Ok(())
}

fn expressions(
    project: &Project,
    sizes: &Sizes,
    uses: &[(usize, usize, bool)],
    prog: &mut Program,
    notes: &mut Vec<String>,
) -> Result<(), LadderError> {
    let mut form: Vec<Option<bool>> = vec![None; sizes.exprs];
    for &(n, line, is_compare) in uses {
        match form[n] {
            Some(f) if f != is_compare => {
                return Err(structure(format!(
                    "line {line}: expression {n} is used by a compare and an operate block"
                )))
            }
            _ => form[n] = Some(is_compare),
        }
    }
    for (n, f) in form.iter().enumerate() {
        let Some(is_compare) = *f else { continue };
        let Some(t) = project.exprs.iter().rev().find(|e| e.number == n) else {
            notes.push(format!(
                "expression {n} is used but not defined; it is empty"
            ));
            continue;
        };
        let parsed = if is_compare {
            Expr::compare(&t.text, sizes)
        } else {
            Expr::assign(&t.text, sizes)
        };
        let e = parsed.map_err(|source| LadderError::Expr {
            line: t.line,
            number: n,
            text: t.text.clone(),
            source,
        })?;
        if e.form == ExprForm::Empty {
            notes.push(format!("expression {n} (line {}) is empty", t.line));
        }
        prog.exprs[n] = e;
    }
    Ok(())
}

fn setups(project: &Project, sizes: &Sizes, prog: &mut Program) -> Result<(), LadderError> {
    let base = |id: i64, line: usize, part: &str| {
        base_ms(id).ok_or_else(|| LadderError::Syntax {
            line,
            part: part.to_string(),
            what: format!("time base {id} is not 0 (minutes), 1 (seconds) or 2 (100 ms)"),
        })
    };
    let preset = |v: i64, line: usize, part: &str| {
        i32::try_from(v)
            .ok()
            .filter(|p| *p >= 0)
            .ok_or_else(|| LadderError::Syntax {
                line,
                part: part.to_string(),
                what: format!("preset {v} is negative or too large"),
            })
    };
    for (i, p) in project.timers.iter().take(sizes.timers).enumerate() {
        prog.timers[i] = TimerSetup {
            base_ms: base(p.values[0], p.line, "timers.csv")?,
            preset: preset(p.values[1], p.line, "timers.csv")?,
        };
    }
    for (i, p) in project
        .monostables
        .iter()
        .take(sizes.monostables)
        .enumerate()
    {
        prog.monostables[i] = TimerSetup {
            base_ms: base(p.values[0], p.line, "monostables.csv")?,
            preset: preset(p.values[1], p.line, "monostables.csv")?,
        };
    }
    for (i, p) in project.counters.iter().take(sizes.counters).enumerate() {
        prog.counters[i] = preset(p.values[0], p.line, "counters.csv")?;
    }
    for (i, p) in project.timers_iec.iter().take(sizes.timers_iec).enumerate() {
        let mode = match p.values[2] {
            0 => IecMode::OnDelay,
            1 => IecMode::OffDelay,
            2 => IecMode::Pulse,
            m => {
                return Err(LadderError::Syntax {
                    line: p.line,
                    part: "timers_iec.csv".into(),
                    what: format!("mode {m} is not 0 (TON), 1 (TOF) or 2 (TP)"),
                })
            }
        };
        prog.timers_iec[i] = IecSetup {
            base_ms: base(p.values[0], p.line, "timers_iec.csv")?,
            preset: preset(p.values[1], p.line, "timers_iec.csv")?,
            mode,
        };
    }
    Ok(())
}
