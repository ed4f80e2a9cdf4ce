//! A whole profile: the list of segments from the cycle's start point
//! along the subroutine's moves, and the transformations the cycles
//! apply to it: turning and mirroring it so that Z and X decrease along
//! it (remembering how, to turn the output back), fitting the corner
//! fillets and chamfers, and offsetting it by the finishing allowance.

use super::complex::{display, min, C, I};
use super::segment::{intersect, Corner, Motion, Segment, Shape};
use crate::error::{InterpError, Result};

/// The most offset steps one offset may take (each step is at most half
/// the smallest segment; a profile needing more is refused).
const MAX_OFFSET_STEPS: usize = 10_000;

/// A profile and how it has been turned and mirrored.
#[derive(Debug, Clone, Default)]
pub(crate) struct Profile {
    pub segs: Vec<Segment>,
    /// Bit 0: Z mirrored; bit 1: X mirrored; bit 2: turned a quarter.
    pub flip_state: u8,
    /// Diagnostics of the last offset, for [`Motion::note`]: LinuxCNC
    /// prints "Oops" and the segment's extent when an offset turns a
    /// segment backwards and it is dropped.
    pub notes: Vec<String>,
}

impl Profile {
    /// Turn the profile a quarter turn (G72 cuts along X as G71 along Z).
    pub(crate) fn rotate(&mut self) {
        self.segs.iter_mut().for_each(Segment::rotate);
        self.flip_state ^= 4;
    }

    /// Mirror so that, from its first end point to its last, Z and X
    /// decrease.
    pub(crate) fn swap(&mut self) {
        let (Some(first), Some(last)) = (self.segs.first(), self.segs.last()) else {
            return;
        };
        let dir = first.end - last.end;
        if dir.im > 0.0 {
            self.segs.iter_mut().for_each(Segment::flip_imag);
            self.flip_state ^= 2;
        }
        if dir.re < 0.0 {
            self.segs.iter_mut().for_each(Segment::flip_real);
            self.flip_state ^= 1;
        }
    }

    /// Refuse a profile whose Z does not keep decreasing (the lead-in's
    /// start is first moved level with its end if it lies beyond it).
    pub(crate) fn monotonic(&mut self) -> Result<()> {
        if let Some(first) = self.segs.first_mut() {
            if (first.end - first.start).re > 0.0 {
                first.start.re = first.end.re;
            }
        }
        if self.segs.iter().all(Segment::monotonic) {
            Ok(())
        } else {
            Err(InterpError::G7xNotMonotonic)
        }
    }

    /// Fit the fillets and chamfers to their neighbours and drop what is
    /// left too small.
    pub(crate) fn do_finish(&mut self) -> Result<()> {
        let len = self.segs.len();
        for h in 1..len.saturating_sub(1) {
            if self.segs[h].corner == Corner::None {
                continue;
            }
            let (mut prev, mut corner, mut next) =
                (self.segs[h - 1], self.segs[h], self.segs[h + 1]);
            corner_finish(&mut corner, &mut prev, &mut next)?;
            self.segs[h - 1] = prev;
            self.segs[h] = corner;
            self.segs[h + 1] = next;
        }
        self.segs.retain(|s| s.radius() >= 1e-3);
        Ok(())
    }

    /// The output, turned and mirrored back to the machine's axes.
    pub(crate) fn motion<'a>(&self, out: &'a mut dyn Motion) -> Flipped<'a> {
        Flipped {
            out,
            state: self.flip_state,
        }
    }

    /// Offset the profile (all but its lead-in) by `distance` away from
    /// the material, in steps no larger than half the smallest segment,
    /// joining the pieces with arcs and dropping those that vanish.
    pub(crate) fn add_distance(&mut self, distance: f64) -> Result<()> {
        if self.segs.len() < 2 {
            return Err(InterpError::G7xProfileVanished);
        }
        let first = self.segs[0];
        let last = self.segs[self.segs.len() - 1];
        let angle = (first.end - first.start) / (last.start - first.start);
        let distance = if angle.im < 0.0 { -distance } else { distance };
        let lead_in = self.segs.remove(0);
        let mut current = 0.0;
        let mut steps = 0;
        while current != distance {
            steps += 1;
            if steps > MAX_OFFSET_STEPS || self.segs.is_empty() {
                return Err(InterpError::G7xOffsetSteps(MAX_OFFSET_STEPS));
            }
            let step = self.offset_step(distance, current)?;
            current += step;
        }
        for p in 0..self.segs.len().saturating_sub(1) {
            let mid = (self.segs[p].end + self.segs[p + 1].start).div_real(2.0);
            self.segs[p].end = mid;
            self.segs[p + 1].start = mid;
        }
        let Some(front) = self.segs.first() else {
            return Err(InterpError::G7xProfileVanished);
        };
        let mut lead_in = lead_in;
        lead_in.end = front.start;
        self.segs.insert(0, lead_in);
        Ok(())
    }

    /// One step of [`Profile::add_distance`]; returns the distance moved.
    fn offset_step(&mut self, distance: f64, current: f64) -> Result<f64> {
        let mut step = 1e9;
        for s in &self.segs {
            step = min(step, s.radius() / 2.0);
        }
        step = min(step, (distance - current).abs());
        if distance < 0.0 {
            step = -step;
        }
        let mut p = 0;
        while p < self.segs.len() {
            self.segs[p].offset(step);
            if self.segs[p].radius() < 1e-3 {
                self.segs.remove(p);
            } else {
                p += 1;
            }
        }
        self.connect_gaps(step, distance);
        self.repair_and_join()?;
        Ok(step)
    }

    /// Where an offset opened a gap between two pieces (an outside
    /// corner), bridge it with an arc about the old corner.
    fn connect_gaps(&mut self, step: f64, distance: f64) {
        let mut p = 0;
        while p + 1 < self.segs.len() {
            let n = p + 1;
            if (self.segs[p].end - self.segs[n].start).re > 1e-2 {
                let mut s = self.segs[p];
                let mut e = self.segs[n];
                s.offset(-step);
                e.offset(-step);
                let center = (s.end + e.start).div_real(2.0);
                let bridge =
                    Segment::arc(distance > 0.0, self.segs[p].end, center, self.segs[n].start);
                self.segs.insert(n, bridge);
                p += 1;
            }
            p += 1;
        }
    }

    /// Drop pieces an offset turned backwards or shrank to nothing, and
    /// make each piece end where the next starts.
    fn repair_and_join(&mut self) -> Result<()> {
        let mut p = 0;
        let mut guard = 0usize;
        while p + 1 < self.segs.len() {
            guard += 1;
            if guard > MAX_OFFSET_STEPS * 10 {
                return Err(InterpError::G7xOffsetSteps(MAX_OFFSET_STEPS));
            }
            if !self.segs[p].monotonic() {
                let extent = self.segs[p].start - self.segs[p].end;
                self.notes.push(format!("Oops {}", display(extent)));
                if p == 0 {
                    return Err(InterpError::G7xNotMonotonic);
                }
                if self.segs[p].radius() < self.segs[p - 1].radius() {
                    self.segs.remove(p);
                } else {
                    self.segs.remove(p - 1);
                }
                p = 0;
                if p + 1 >= self.segs.len() {
                    break;
                }
            }
            if self.segs[p].radius() < 1e-3 {
                self.segs.remove(p);
                p = 1;
                continue;
            }
            let (head, tail) = self.segs.split_at_mut(p + 1);
            intersect(&mut head[p], &mut tail[0])?;
            p += 1;
        }
        Ok(())
    }
}

/// Fit the corner placeholder `corner` between `prev` and `next`: offset
/// both by the corner's size (to the side where they meet), intersect,
/// and put the corner's ends back on the two pieces.
fn corner_finish(corner: &mut Segment, prev: &mut Segment, next: &mut Segment) -> Result<()> {
    let (mut p, mut n) = (*prev, *next);
    p.offset(corner.finish);
    n.offset(corner.finish);
    if (p.end - n.start).re > 1e-2 {
        corner.finish = -corner.finish;
        p = *prev;
        n = *next;
        p.offset(corner.finish);
        n.offset(corner.finish);
    }
    if (p.end - n.start).re > 1e-2 {
        return Err(InterpError::G7xCornerFinish(display(prev.end)));
    }
    intersect(&mut p, &mut n)?;
    let center = (p.end + n.start).div_real(2.0);
    p.offset(-corner.finish);
    n.offset(-corner.finish);
    corner.start = p.end;
    prev.end = p.end;
    corner.end = n.start;
    next.start = n.start;
    if corner.corner == Corner::Fillet {
        let ccw = (corner.start - center).im > 0.0 || (corner.end - center).im > 0.0;
        corner.shape = Shape::Arc { ccw, center };
        corner.finish = 0.0;
    }
    Ok(())
}

/// A [`Motion`] that turns and mirrors points back before passing them on.
pub(crate) struct Flipped<'a> {
    out: &'a mut dyn Motion,
    state: u8,
}

impl Flipped<'_> {
    fn point(&self, p: C) -> C {
        match self.state {
            0 => p,
            1 => -p.conj(),
            2 => p.conj(),
            3 => -p,
            4 => I * p,
            5 => (I * p).conj(),
            6 => -(I * p).conj(),
            _ => -I * p,
        }
    }

    fn mirrored(&self) -> bool {
        matches!(self.state, 1 | 2 | 5 | 6)
    }
}

impl Motion for Flipped<'_> {
    fn feed(&mut self, end: C) -> Result<()> {
        let end = self.point(end);
        self.out.feed(end)
    }

    fn rapid(&mut self, end: C) -> Result<()> {
        let end = self.point(end);
        self.out.rapid(end)
    }

    fn arc(&mut self, ccw: bool, center: C, end: C) -> Result<()> {
        let (center, end) = (self.point(center), self.point(end));
        let ccw = ccw != self.mirrored();
        self.out.arc(ccw, center, end)
    }

    fn note(&mut self, text: &str) {
        self.out.note(text);
    }
}
