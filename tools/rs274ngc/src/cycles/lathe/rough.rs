//! The roughing passes of G71/G72 and their pockets.
//!
//! The profile arrives turned so that Z and X decrease along it (G72's
//! turned a quarter first, so its passes run along X). From the start
//! point the passes step down in X by the increment; each pass feeds
//! along Z until it meets the profile, then backs off by the retract
//! distance and returns in rapid. Where the profile rises again (a
//! pocket), the cut follows it up and the pocket is roughed the same
//! way from its own top. G7x.1 leaves the pockets, G7x.2 cuts only them.

use super::complex::{max, min, C};
use super::profile::Profile;
use super::segment::{Motion, Segment, TOLERANCE};
use crate::error::{InterpError, Result};

/// Which part of the profile a roughing cycle cuts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Pockets {
    /// G71, G72: everything, pockets included.
    All,
    /// G71.1, G72.1: no pockets.
    None,
    /// G71.2, G72.2: only the pockets, after a G7x.1.
    Only,
}

/// The words of a roughing cycle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Rough {
    /// The start point (Z, X).
    pub start: C,
    /// Extra displacement of the profile (W, U).
    pub shift: C,
    /// Material left on the profile (D).
    pub allowance: f64,
    /// Depth of cut per pass (I).
    pub increment: f64,
    /// Retract distance (R).
    pub retract: f64,
    /// The most moves (and steps) the cycle may make
    /// ([`crate::Config::max_cycle_moves`]).
    pub limit: u32,
}

/// A [`Motion`] that only counts, for the dry run that refuses a cycle
/// with too many moves before it moves.
struct Count {
    moves: u64,
    limit: u32,
}

impl Count {
    fn one(&mut self) -> Result<()> {
        self.moves += 1;
        if self.moves > u64::from(self.limit) {
            return Err(InterpError::G7xTooManyPasses { limit: self.limit });
        }
        Ok(())
    }
}

impl Motion for Count {
    fn feed(&mut self, _end: C) -> Result<()> {
        self.one()
    }
    fn rapid(&mut self, _end: C) -> Result<()> {
        self.one()
    }
    fn arc(&mut self, _ccw: bool, _center: C, _end: C) -> Result<()> {
        self.one()
    }
}

/// Rough the profile (`along_x` for G72), writing the moves to `out`.
pub(crate) fn rough(
    mut path: Profile,
    pockets: Pockets,
    along_x: bool,
    w: &Rough,
    out: &mut dyn Motion,
) -> Result<()> {
    let Some(first) = path.segs.first_mut() else {
        return Err(InterpError::G7xProfileVanished);
    };
    first.start = w.start;
    if along_x {
        path.rotate();
    }
    path.swap();
    path.do_finish()?;
    path.monotonic()?;
    let offset = path.add_distance(w.allowance);
    for note in path.notes.drain(..) {
        out.note(&note);
    }
    offset?;
    for s in path.segs.iter_mut() {
        s.shift(w.shift);
    }
    let start = path.segs[0].start;
    let last_end = path.segs[path.segs.len() - 1].end;
    if last_end.im < start.im {
        path.segs
            .push(Segment::line(last_end, C::new(last_end.re, start.im)));
    }
    let run = |out: &mut dyn Motion| {
        out.rapid(start)?;
        let mut pass = Passes {
            segs: &path.segs,
            delta: max(w.increment, 2.0 * TOLERANCE),
            escape: C::new(1.0, 1.0).scale(w.retract),
            pocket_starts: vec![start],
            steps: 0,
            limit: w.limit,
        };
        pass.pocket(pockets, start, out)
    };
    run(&mut Count {
        moves: 0,
        limit: w.limit,
    })?;
    run(&mut path.motion(out))
}

/// The state of the passes over one profile.
struct Passes<'a> {
    segs: &'a [Segment],
    delta: f64,
    escape: C,
    /// The tops of the pockets being cut (the start point first).
    pocket_starts: Vec<C>,
    steps: u64,
    limit: u32,
}

/// What the pass loop does next.
enum Next {
    Done,
    /// A new pocket starts at segment `p`, from `location`.
    Pocket(usize, C),
}

impl Passes<'_> {
    fn count(&mut self) -> Result<()> {
        self.steps += 1;
        if self.steps > u64::from(self.limit) {
            return Err(InterpError::G7xTooManyPasses { limit: self.limit });
        }
        Ok(())
    }

    fn top(&self) -> f64 {
        self.pocket_starts.last().map_or(0.0, |p| p.im)
    }

    /// Cut from `location`, pocket after pocket.
    fn pocket(&mut self, pockets: Pockets, mut location: C, out: &mut dyn Motion) -> Result<()> {
        let mut p = 0;
        if pockets == Pockets::Only {
            // Follow the profile down without cutting the first pocket.
            while p < self.segs.len() {
                self.count()?;
                if self.segs[p].dive(&mut location, -1e9, out, p == 0)? {
                    break;
                }
                p += 1;
            }
        }
        loop {
            match self.passes(pockets, p, location, out)? {
                Next::Done => return Ok(()),
                Next::Pocket(at, from) => {
                    p = at;
                    location = from;
                }
            }
        }
    }

    /// The passes of one pocket, from segment `p`.
    fn passes(
        &mut self,
        pockets: Pockets,
        mut p: usize,
        mut location: C,
        out: &mut dyn Motion,
    ) -> Result<Next> {
        let mut x = self.top();
        while p < self.segs.len() {
            self.count()?;
            while x - TOLERANCE > location.im {
                self.count()?;
                x -= self.delta;
            }
            if self.segs[p].dive(&mut location, x, out, p == 0)? {
                return self.follow_up(pockets, p, location, out);
            }
            if (location.im - x).abs() > TOLERANCE {
                p += 1;
                continue;
            }
            self.one_pass(&mut p, &mut x, location, out)?;
        }
        Ok(Next::Done)
    }

    /// After the dive: follow the rising profile, to the next pocket.
    fn follow_up(
        &mut self,
        pockets: Pockets,
        mut p: usize,
        mut location: C,
        out: &mut dyn Motion,
    ) -> Result<Next> {
        if pockets == Pockets::None {
            for s in &self.segs[p..] {
                s.climb_only(&mut location, out)?;
            }
            return Ok(Next::Done);
        }
        while p < self.segs.len() {
            if self.segs[p].climb(&mut location, out)? {
                if pockets == Pockets::Only {
                    if location.im > self.top() && self.pocket_starts.len() > 1 {
                        self.pocket_starts.pop();
                    }
                    if self.pocket_starts.len() == 1 {
                        self.pocket_starts.push(location);
                    }
                }
                return Ok(Next::Pocket(p, location));
            }
            p += 1;
        }
        Ok(Next::Done)
    }

    /// At height `location.im`: feed along Z to the first segment met,
    /// then retract and come back in rapid for the next pass.
    fn one_pass(
        &mut self,
        p: &mut usize,
        x: &mut f64,
        location: C,
        out: &mut dyn Motion,
    ) -> Result<()> {
        for ip in *p..self.segs.len() {
            let hits = self.segs[ip].hits(location.im);
            if hits.is_empty() {
                continue;
            }
            let destination_z = if ip != *p { hits.front() } else { hits.back() };
            let distance = (destination_z - location.re).abs();
            if destination_z - TOLERANCE > location.re {
                continue;
            }
            if distance < TOLERANCE {
                if *p == ip {
                    continue;
                } else if (location - self.segs[ip].start).abs() < TOLERANCE {
                    *p = ip;
                } else {
                    *x -= self.delta;
                }
                return Ok(());
            }
            let mut dest = location;
            dest.re = destination_z;
            out.feed(dest)?;
            let escape_scale = min(1.0, distance / 2.0 / self.escape.re);
            dest += self.escape.scale(escape_scale);
            out.rapid(dest)?;
            out.rapid(location - self.escape.scale(escape_scale).conj())?;
            if *p == 0 {
                out.rapid(location)?;
            } else {
                out.feed(location)?;
            }
            *x -= self.delta;
            return Ok(());
        }
        Ok(())
    }
}
