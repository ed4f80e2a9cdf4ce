//! The G-code subset the runner executes, turned into motion commands.
//!
//! Known: G0 G1 G2 G3 (I J K or R, P turns), G4 P, G17 G18 G19, G20 G21,
//! G61 G61.1 G64 P Q, G90 G91, G90.1 G91.1, F (units per minute), M0 M1
//! M2 M30, N, comments; axis words X Y Z A B C U V W. Anything else is
//! refused with its file, line and column, never guessed.
//!
//! Semantics as LinuxCNC's interpreter: modal codes persist; arc centres
//! are incremental (G91.1) unless G90.1; an arc's plane sets its normal
//! (+Z, +Y, +X for G17, G18, G19), G3 turns counter-clockwise about it,
//! G2 clockwise, P n adds n − 1 full turns; the end radius may differ
//! from the start radius by a small tolerance (the arc becomes a slight
//! spiral); a radius (R) arc takes the shorter way for R > 0, the longer
//! for R < 0. G64 Q merges successive straight feed moves that stay
//! within Q of one straight line (LinuxCNC's naive-CAM detector). The
//! motion id of each move is its line number in the file.

use motion::command::{Command, LineKind, TermCond};
use motion::kins::Pose;

use super::words::{blocks, Block, Code, Word};
use super::{Loc, ProgramError};

/// Linear units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Units {
    /// Millimetres.
    Mm,
    /// Inches.
    Inch,
}

impl Units {
    /// Millimetres per unit.
    fn mm(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::Inch => 25.4,
        }
    }
}

/// What the runner does, in program order.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// Send this command (a move, a dwell, a termination condition).
    Send(Command, Loc),
    /// M0: wait until the moves before have run, then wait for the
    /// operator to resume.
    Pause(Loc),
    /// M1: like M0 if optional stops are on.
    OptionalPause(Loc),
    /// M2 or M30: the program ends here.
    End(Loc),
}

/// The interpreter's modal state.
#[derive(Debug, Clone)]
struct State {
    /// Current position, machine units.
    pos: [f64; 9],
    motion: Option<u32>,
    plane: u32,
    /// Program units per machine unit (G20 on a millimetre machine:
    /// 1/25.4).
    scale: f64,
    absolute: bool,
    arc_absolute: bool,
    /// Feed, machine units per second.
    feed: Option<f64>,
    /// G64 Q in machine units (0: off).
    naive: f64,
    /// Millimetres per machine unit.
    machine_mm: f64,
}

/// A straight feed move being merged under G64 Q.
#[derive(Debug, Clone)]
struct Pending {
    start: [f64; 9],
    /// Points passed so far (the ends of the merged moves).
    through: Vec<[f64; 9]>,
    end: [f64; 9],
    vel: f64,
    id: i32,
    loc: Loc,
}

const AXES: [char; 9] = ['X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V', 'W'];

/// The modal group of a G code (LinuxCNC's numbering), for "two codes of
/// one group on a line".
fn group(number: u32) -> u32 {
    match number {
        0 | 10 | 20 | 30 | 382..=385 => 1,
        40 => 0,
        170 | 180 | 190 => 2,
        200 | 210 => 6,
        610 | 611 | 640 => 13,
        900 | 910 => 3,
        901 | 911 => 4,
        _ => 99,
    }
}

/// Distance from `p` to the line from `a` to `b` (all nine axes).
fn off_line(p: &[f64; 9], a: &[f64; 9], b: &[f64; 9]) -> f64 {
    let ab: Vec<f64> = (0..9).map(|i| b[i] - a[i]).collect();
    let ap: Vec<f64> = (0..9).map(|i| p[i] - a[i]).collect();
    let l2: f64 = ab.iter().map(|x| x * x).sum();
    let t = if l2 > 0.0 {
        (ap.iter().zip(&ab).map(|(x, y)| x * y).sum::<f64>() / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ap.iter()
        .zip(&ab)
        .map(|(x, y)| (x - t * y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The interpreter.
struct Interp<'a> {
    file: &'a str,
    st: State,
    out: Vec<Step>,
    pending: Option<Pending>,
}

impl Interp<'_> {
    fn err(&self, loc: Loc, message: impl Into<String>) -> ProgramError {
        ProgramError {
            file: self.file.to_string(),
            loc,
            message: message.into(),
        }
    }

    /// A length word in machine units.
    fn len(&self, w: Word) -> f64 {
        w.value / self.st.scale
    }

    fn flush(&mut self) {
        if let Some(p) = self.pending.take() {
            self.out.push(Step::Send(
                Command::Line {
                    end: Pose(p.end),
                    vel: p.vel,
                    ini_maxvel: 0.0,
                    acc: 0.0,
                    kind: LineKind::Feed,
                    id: p.id,
                },
                p.loc,
            ));
        }
    }

    fn send(&mut self, cmd: Command, loc: Loc) {
        self.flush();
        self.out.push(Step::Send(cmd, loc));
    }

    /// The end point of a move from the axis words.
    fn target(&self, b: &Block) -> [f64; 9] {
        let mut end = self.st.pos;
        for (i, &l) in AXES.iter().enumerate() {
            if let Some(w) = b.get(l) {
                // Rotary axes are degrees whatever the units.
                let v = if (3..6).contains(&i) {
                    w.value
                } else {
                    self.len(w)
                };
                end[i] = if self.st.absolute { v } else { end[i] + v };
            }
        }
        end
    }

    fn line(&mut self, b: &Block, rapid: bool, id: i32, loc: Loc) -> Result<(), ProgramError> {
        let end = self.target(b);
        if rapid {
            self.send(
                Command::Line {
                    end: Pose(end),
                    vel: 0.0,
                    ini_maxvel: 0.0,
                    acc: 0.0,
                    kind: LineKind::Traverse,
                    id,
                },
                loc,
            );
        } else {
            let vel = self.st.feed.ok_or_else(|| {
                self.err(
                    loc,
                    "G1 with no feed rate: give an F word (units per minute)",
                )
            })?;
            self.feed_line(end, vel, id, loc);
        }
        self.st.pos = end;
        Ok(())
    }

    /// A feed line, merged with the pending one under G64 Q if every point
    /// passed stays within Q of the merged line.
    fn feed_line(&mut self, end: [f64; 9], vel: f64, id: i32, loc: Loc) {
        if self.st.naive > 0.0 {
            if let Some(p) = &mut self.pending {
                let fits = p.vel == vel
                    && p.through
                        .iter()
                        .chain(std::iter::once(&p.end))
                        .all(|q| off_line(q, &p.start, &end) <= self.st.naive);
                if fits {
                    p.through.push(p.end);
                    p.end = end;
                    p.id = id;
                    p.loc = loc;
                    return;
                }
            }
            self.flush();
            self.pending = Some(Pending {
                start: self.st.pos,
                through: Vec::new(),
                end,
                vel,
                id,
                loc,
            });
            return;
        }
        self.send(
            Command::Line {
                end: Pose(end),
                vel,
                ini_maxvel: 0.0,
                acc: 0.0,
                kind: LineKind::Feed,
                id,
            },
            loc,
        );
    }

    fn arc(&mut self, b: &Block, cw: bool, id: i32, code: Code) -> Result<(), ProgramError> {
        let loc = code.loc;
        let vel = self.st.feed.ok_or_else(|| {
            self.err(
                loc,
                format!("{} with no feed rate: give an F word", code.name()),
            )
        })?;
        // The plane's two axes, its normal, and its offset letters.
        let (a0, a1, normal, letters) = match self.st.plane {
            170 => (0, 1, [0.0, 0.0, 1.0], ['I', 'J', 'K']),
            180 => (2, 0, [0.0, 1.0, 0.0], ['K', 'I', 'J']),
            _ => (1, 2, [1.0, 0.0, 0.0], ['J', 'K', 'I']),
        };
        if let Some(w) = b.get(letters[2]) {
            return Err(self.err(
                w.loc,
                format!(
                    "{} word given for an arc in the G{} plane",
                    letters[2],
                    self.st.plane / 10
                ),
            ));
        }
        let start = self.st.pos;
        let end = self.target(b);
        let turns_p = match b.get('P') {
            None => 1,
            Some(w) if w.value >= 1.0 && w.value.fract() == 0.0 && w.value <= 1e6 => w.value as i32,
            Some(w) => {
                return Err(self.err(w.loc, "P (turns) must be a whole number of at least 1"))
            }
        };
        let (u, v) = (start[a0], start[a1]);
        let (eu, ev) = (end[a0], end[a1]);
        let center2 = if let Some(r) = b.get('R') {
            if b.get(letters[0]).is_some() || b.get(letters[1]).is_some() {
                return Err(self.err(r.loc, "an arc takes R or centre offsets, not both"));
            }
            let radius = self.len(r);
            let (dx, dy) = (eu - u, ev - v);
            let d = (dx * dx + dy * dy).sqrt();
            if d < 1e-9 {
                return Err(self.err(r.loc, "a radius arc cannot end where it starts"));
            }
            let half = d / 2.0;
            let tol = self.tolerance();
            if radius.abs() < half - tol {
                return Err(self.err(
                    r.loc,
                    format!(
                        "radius {:.6} is too small for an arc ending {:.6} away",
                        radius.abs() * self.st.scale,
                        d * self.st.scale
                    ),
                ));
            }
            let h = (radius * radius - half * half).max(0.0).sqrt();
            // Left of the chord for a counter-clockwise short arc.
            let (mx, my) = (u + dx / 2.0, v + dy / 2.0);
            let (px, py) = (-dy / d, dx / d);
            let left = (radius > 0.0) != cw;
            let s = if left { h } else { -h };
            (mx + px * s, my + py * s)
        } else {
            let i = b.get(letters[0]).map(|w| self.len(w));
            let j = b.get(letters[1]).map(|w| self.len(w));
            if i.is_none() && j.is_none() {
                return Err(self.err(
                    loc,
                    format!(
                        "{} needs {} and/or {} (the centre) or R",
                        code.name(),
                        letters[0],
                        letters[1]
                    ),
                ));
            }
            let (i, j) = (i.unwrap_or(0.0), j.unwrap_or(0.0));
            if self.st.arc_absolute {
                (i, j)
            } else {
                (u + i, v + j)
            }
        };
        let r0 = ((u - center2.0).powi(2) + (v - center2.1).powi(2)).sqrt();
        let r1 = ((eu - center2.0).powi(2) + (ev - center2.1).powi(2)).sqrt();
        if r0 < 1e-9 || r1 < 1e-9 {
            return Err(self.err(loc, "the arc's start or end is on its centre"));
        }
        if (r1 - r0).abs() > self.tolerance().max(0.001 * r0) {
            return Err(self.err(
                loc,
                format!(
                    "radius to end of arc ({:.6}) differs from radius to start ({:.6})",
                    r1 * self.st.scale,
                    r0 * self.st.scale
                ),
            ));
        }
        let mut center = [0.0; 3];
        center[a0] = center2.0;
        center[a1] = center2.1;
        let axis = 3 - a0 - a1;
        center[axis] = start[axis];
        let turns = if cw { -turns_p } else { turns_p - 1 };
        self.send(
            Command::Circle {
                end: Pose(end),
                center,
                normal,
                turns,
                vel,
                ini_maxvel: 0.0,
                acc: 0.0,
                id,
            },
            loc,
        );
        self.st.pos = end;
        Ok(())
    }

    /// LinuxCNC's arc radius tolerance: 0.0005 inch, in machine units.
    fn tolerance(&self) -> f64 {
        0.0005 * 25.4 / self.st.machine_mm
    }

    /// One line.
    fn block(&mut self, line: usize, b: &Block, units: Units) -> Result<bool, ProgramError> {
        let id = line as i32;
        let (motion, m_code) = self.check_codes(b)?;
        self.modal_settings(b, units)?;
        let dwell = b.codes.iter().find(|c| c.number == 40);
        let term = b.codes.iter().find(|c| group(c.number) == 13);
        self.check_words(b, motion, dwell, term)?;
        if let Some(d) = dwell {
            self.dwell(b, d, id)?;
        }
        if let Some(t) = term {
            self.term_cond(b, t)?;
        }
        if let Some(m) = motion {
            self.st.motion = Some(m.number);
        }
        self.motion_of_line(b, motion, dwell, id)?;
        if let Some(m) = m_code {
            self.flush();
            match m.number {
                0 => self.out.push(Step::Pause(m.loc)),
                10 => self.out.push(Step::OptionalPause(m.loc)),
                _ => {
                    self.out.push(Step::End(m.loc));
                    return Ok(false);
                }
            }
        }
        Ok(true)
    }

    /// Refuses the line's unknown codes, two codes of one group, more than
    /// one M code and the words the runner does not know; returns its
    /// motion code and its M code.
    fn check_codes(&self, b: &Block) -> Result<(Option<Code>, Option<Code>), ProgramError> {
        let mut seen = Vec::new();
        let mut motion: Option<Code> = None;
        let mut ms = Vec::new();
        for c in &b.codes {
            if c.letter == 'M' {
                if !matches!(c.number, 0 | 10 | 20 | 300) {
                    return Err(self.err(
                        c.loc,
                        format!(
                            "{} is not supported (the runner knows M0 M1 M2 M30)",
                            c.name()
                        ),
                    ));
                }
                ms.push(*c);
                continue;
            }
            let g = group(c.number);
            if g == 99 || (382..=385).contains(&c.number) {
                return Err(self.err(
                    c.loc,
                    format!(
                        "{} is not supported (the runner knows G0 G1 G2 G3 G4 G17 G18 G19 G20 \
                         G21 G61 G61.1 G64 G90 G91 G90.1 G91.1)",
                        c.name()
                    ),
                ));
            }
            if g != 0 && seen.contains(&g) {
                return Err(self.err(
                    c.loc,
                    format!(
                        "{} conflicts with another code of its group on this line",
                        c.name()
                    ),
                ));
            }
            seen.push(g);
            if g == 1 {
                motion = Some(*c);
            }
        }
        if let Some(second) = ms.get(1) {
            return Err(self.err(second.loc, "only one M code per line"));
        }
        for l in ['D', 'E', 'H', 'L', 'O', 'S', 'T'] {
            if let Some(w) = b.get(l) {
                return Err(self.err(w.loc, format!("the {l} word is not supported")));
            }
        }
        Ok((motion, ms.first().copied()))
    }

    /// Units, distance modes and plane first, then the feed.
    fn modal_settings(&mut self, b: &Block, units: Units) -> Result<(), ProgramError> {
        for c in &b.codes {
            match c.number {
                200 => self.st.scale = units.mm() / 25.4,
                210 => self.st.scale = units.mm(),
                900 => self.st.absolute = true,
                910 => self.st.absolute = false,
                901 => self.st.arc_absolute = true,
                911 => self.st.arc_absolute = false,
                170 | 180 | 190 => self.st.plane = c.number,
                _ => {}
            }
        }
        if let Some(f) = b.get('F') {
            if f.value <= 0.0 {
                return Err(self.err(f.loc, "F must be positive"));
            }
            self.st.feed = Some(self.len(f) / 60.0);
        }
        Ok(())
    }

    /// Refuses P, Q, I, J, K and R words that no code of the line (or the
    /// modal arc) takes.
    fn check_words(
        &self,
        b: &Block,
        motion: Option<Code>,
        dwell: Option<&Code>,
        term: Option<&Code>,
    ) -> Result<(), ProgramError> {
        let uses_p = dwell.is_some()
            || term.is_some_and(|c| c.number == 640)
            || motion.is_some_and(|m| m.number == 20 || m.number == 30);
        if let Some(w) = b.get('P') {
            if !uses_p {
                return Err(self.err(w.loc, "P word with no code that takes it (G4, G64, G2, G3)"));
            }
        }
        if let Some(w) = b.get('Q') {
            if term.is_none_or(|c| c.number != 640) {
                return Err(self.err(w.loc, "Q word with no G64"));
            }
        }
        for l in ['I', 'J', 'K', 'R'] {
            if let Some(w) = b.get(l) {
                let arc = motion
                    .map(|m| m.number)
                    .or(self.st.motion)
                    .is_some_and(|m| m == 20 || m == 30);
                if !arc {
                    return Err(self.err(w.loc, format!("{l} word with no arc (G2, G3)")));
                }
            }
        }
        Ok(())
    }

    /// `G4 P<seconds>`.
    fn dwell(&mut self, b: &Block, d: &Code, id: i32) -> Result<(), ProgramError> {
        let p = b
            .get('P')
            .ok_or_else(|| self.err(d.loc, "G4 needs P (seconds)"))?;
        if p.value < 0.0 {
            return Err(self.err(p.loc, "the dwell time must not be negative"));
        }
        self.send(
            Command::Dwell {
                seconds: p.value,
                id,
            },
            d.loc,
        );
        Ok(())
    }

    /// `G61`, `G61.1`, `G64 [P] [Q]`: the path's termination condition.
    fn term_cond(&mut self, b: &Block, t: &Code) -> Result<(), ProgramError> {
        let (cond, tol) = match t.number {
            610 => (TermCond::ExactPath, 0.0),
            611 => (TermCond::Stop, 0.0),
            _ => (TermCond::Blend, b.get('P').map_or(0.0, |w| self.len(w))),
        };
        if tol < 0.0 {
            return Err(self.err(t.loc, "G64 P must not be negative"));
        }
        self.st.naive = if t.number == 640 {
            let q = b.get('Q').map_or(0.0, |w| self.len(w));
            if q < 0.0 {
                return Err(self.err(t.loc, "G64 Q must not be negative"));
            }
            q
        } else {
            0.0
        };
        self.send(
            Command::SetTermCond {
                cond,
                tolerance: tol,
            },
            t.loc,
        );
        Ok(())
    }

    /// The line's move, in the modal motion mode, if it has axis words.
    fn motion_of_line(
        &mut self,
        b: &Block,
        motion: Option<Code>,
        dwell: Option<&Code>,
        id: i32,
    ) -> Result<(), ProgramError> {
        let Some(first_axis) = AXES.iter().find_map(|&l| b.get(l)) else {
            return match motion {
                Some(m) if m.number == 20 || m.number == 30 => {
                    Err(self.err(m.loc, format!("{} with no end point", m.name())))
                }
                _ => Ok(()),
            };
        };
        let Some(mode) = self.st.motion else {
            return Err(self.err(
                first_axis.loc,
                "axis words with no motion mode (G0, G1, G2, G3)",
            ));
        };
        if let Some(d) = dwell {
            return Err(self.err(d.loc, "G4 and a move on one line"));
        }
        let loc = motion.map_or(first_axis.loc, |m| m.loc);
        let code = motion.unwrap_or(Code {
            letter: 'G',
            number: mode,
            loc,
        });
        match mode {
            0 => self.line(b, true, id, loc),
            10 => self.line(b, false, id, loc),
            20 => self.arc(b, true, id, code),
            _ => self.arc(b, false, id, code),
        }
    }
}

/// Turns a program into steps. `start` is where the machine is (machine
/// units); `units` the machine's linear units. Nothing is sent if any
/// line is refused.
pub fn interpret(
    file: &str,
    src: &[u8],
    start: Pose,
    units: Units,
) -> Result<Vec<Step>, ProgramError> {
    let src = std::str::from_utf8(src).map_err(|e| {
        let ok = &src[..e.valid_up_to()];
        let line = ok.iter().filter(|&&b| b == b'\n').count() + 1;
        let col = ok.iter().rev().take_while(|&&b| b != b'\n').count() + 1;
        ProgramError {
            file: file.to_string(),
            loc: Loc { line, column: col },
            message: "not UTF-8 text".into(),
        }
    })?;
    let mut it = Interp {
        file,
        st: State {
            pos: start.0,
            motion: None,
            plane: 170,
            // Programs start in the machine's units.
            scale: 1.0,
            absolute: true,
            arc_absolute: false,
            feed: None,
            naive: 0.0,
            machine_mm: units.mm(),
        },
        out: Vec::new(),
        pending: None,
    };
    for (line, b) in blocks(file, src)? {
        if !it.block(line, &b, units)? {
            break;
        }
    }
    it.flush();
    Ok(it.out)
}
