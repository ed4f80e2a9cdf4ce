//! One piece of a lathe profile, a straight line or a circular arc, in
//! the (Z, X) plane held as complex numbers, and what the roughing
//! passes ask of it: where a line of constant X crosses it, how to cut
//! down along it (dive), up along it (climb), and how to move it sideways
//! by a distance (offset).
//!
//! By the time the passes run, the profile has been turned so that Z
//! and X both decrease along it; "diving" is a piece that lowers X,
//! "climbing" one that raises it (the bottom of a pocket and its far
//! wall).

use super::complex::{min, C, I};
use crate::error::{InterpError, Result};

/// How close two coordinates must be to count as the same.
pub(crate) const TOLERANCE: f64 = 1e-6;

/// Where the output of a cycle goes: a feed move, a rapid, an arc.
pub(crate) trait Motion {
    /// A straight feed move to `end`.
    fn feed(&mut self, end: C) -> Result<()>;
    /// A rapid move to `end`.
    fn rapid(&mut self, end: C) -> Result<()>;
    /// An arc about `center` to `end`, counterclockwise if `ccw`.
    fn arc(&mut self, ccw: bool, center: C, end: C) -> Result<()>;
    /// A diagnostic line LinuxCNC prints on standard output.
    fn note(&mut self, _text: &str) {}
}

/// The geometry of a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Shape {
    /// A straight line.
    Line,
    /// An arc about `center`.
    Arc { ccw: bool, center: C },
}

/// A corner finish asked for with `A` (fillet) or `C` (chamfer) on a
/// profile move: a placeholder until the neighbours are known.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Corner {
    None,
    Fillet,
    Chamfer,
}

/// Where a line of constant X meets a segment: at most two Z values.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Hits {
    z: [f64; 2],
    n: usize,
}

impl Hits {
    fn push(&mut self, z: f64) {
        if self.n < 2 {
            self.z[self.n] = z;
            self.n += 1;
        }
    }
    pub(crate) fn is_empty(&self) -> bool {
        self.n == 0
    }
    pub(crate) fn front(&self) -> f64 {
        self.z[0]
    }
    pub(crate) fn back(&self) -> f64 {
        self.z[self.n.saturating_sub(1)]
    }
}

/// A segment of the profile.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Segment {
    pub start: C,
    pub end: C,
    pub shape: Shape,
    /// The corner size while this is a corner placeholder, else 0.
    pub finish: f64,
    pub corner: Corner,
}

impl Segment {
    /// A straight line from `start` to `end`.
    pub(crate) fn line(start: C, end: C) -> Segment {
        Segment {
            start,
            end,
            shape: Shape::Line,
            finish: 0.0,
            corner: Corner::None,
        }
    }

    /// An arc from `start` to `end` about `center`.
    pub(crate) fn arc(ccw: bool, start: C, center: C, end: C) -> Segment {
        Segment {
            start,
            end,
            shape: Shape::Arc { ccw, center },
            finish: 0.0,
            corner: Corner::None,
        }
    }

    /// A fillet of radius `size` to be fitted at the corner `at`.
    pub(crate) fn fillet(size: f64, at: C) -> Segment {
        Segment {
            finish: size,
            corner: Corner::Fillet,
            ..Segment::arc(false, at, at, at)
        }
    }

    /// A chamfer of size `size` to be fitted at the corner `at`.
    pub(crate) fn chamfer(size: f64, at: C) -> Segment {
        Segment {
            finish: size,
            corner: Corner::Chamfer,
            ..Segment::line(at, at)
        }
    }

    /// Z and X both non-increasing along the segment.
    pub(crate) fn monotonic(&self) -> bool {
        match self.shape {
            Shape::Line => (self.end - self.start).re <= 1e-3,
            Shape::Arc { ccw, center } => {
                if self.finish != 0.0 {
                    return true;
                }
                let entry = (self.start - center).im;
                let exit = (self.end - center).im;
                let dz = (self.end - self.start).re;
                if ccw {
                    entry >= -1e-3 && exit >= -1e-3 && dz <= -1e-3
                } else {
                    entry <= 1e-3 && exit <= 1e-3 && dz <= -1e-3
                }
            }
        }
    }

    /// The size that limits how far the segment may be offset in a step.
    pub(crate) fn radius(&self) -> f64 {
        match self.shape {
            Shape::Line => (self.start - self.end).abs(),
            Shape::Arc { center, .. } => {
                min((self.start - self.end).abs(), (self.start - center).abs())
            }
        }
    }

    /// Mirror in the Z axis (X negated).
    pub(crate) fn flip_imag(&mut self) {
        self.start = self.start.conj();
        self.end = self.end.conj();
        if let Shape::Arc { ccw, center } = self.shape {
            self.shape = Shape::Arc {
                ccw: !ccw,
                center: center.conj(),
            };
        }
    }

    /// Mirror in the X axis (Z negated).
    pub(crate) fn flip_real(&mut self) {
        self.start = -self.start.conj();
        self.end = -self.end.conj();
        if let Shape::Arc { ccw, center } = self.shape {
            self.shape = Shape::Arc {
                ccw: !ccw,
                center: -center.conj(),
            };
        }
    }

    /// Turn a quarter turn clockwise.
    pub(crate) fn rotate(&mut self) {
        self.start = -self.start * I;
        self.end = -self.end * I;
        if let Shape::Arc { ccw, center } = self.shape {
            self.shape = Shape::Arc {
                ccw,
                center: -center * I,
            };
        }
    }

    /// Move by `d`.
    pub(crate) fn shift(&mut self, d: C) {
        self.start += d;
        if let Shape::Arc { ccw, center } = self.shape {
            self.shape = Shape::Arc {
                ccw,
                center: center + d,
            };
        }
        self.end += d;
    }

    /// Move sideways by `distance` (to the left of the direction of
    /// travel for a line; outwards for a counterclockwise arc).
    pub(crate) fn offset(&mut self, distance: f64) {
        match self.shape {
            Shape::Line => {
                let d = (I.scale(distance) * (self.start - self.end))
                    .div_real((self.start - self.end).abs());
                self.start += d;
                self.end += d;
            }
            Shape::Arc { ccw, center } => {
                let r = (self.start - center).abs();
                let sign = if ccw { 1.0 } else { -1.0 };
                let factor = (r + sign * distance) / r;
                self.start = (self.start - center).scale(factor) + center;
                self.end = (self.end - center).scale(factor) + center;
            }
        }
    }

    fn on_arc(&self, ccw: bool, center: C, p: C) -> bool {
        let from_start = ((self.start - center).conj() * (p - center)).im;
        let from_end = ((self.end - center).conj() * (p - center)).im;
        if ccw {
            from_start >= -TOLERANCE && from_end <= TOLERANCE
        } else {
            from_start <= TOLERANCE && from_end >= -TOLERANCE
        }
    }

    /// Add the Z values where the line X = `x` meets the segment.
    pub(crate) fn intersection_z(&self, x: f64, hits: &mut Hits) {
        let (s, e) = (self.start, self.end);
        match self.shape {
            Shape::Line => {
                if min(s.im, e.im) > x + TOLERANCE
                    || super::complex::max(s.im, e.im) < x - TOLERANCE
                {
                    return;
                }
                if (s - e).im.abs() < TOLERANCE {
                    hits.push(s.re);
                    hits.push(e.re);
                } else {
                    hits.push((x - s.im) / (e.im - s.im) * (e.re - s.re) + s.re);
                }
            }
            Shape::Arc { ccw, center } => {
                let r = (s - center).abs();
                let mut q = -(x - r - center.im) * (x + r - center.im);
                if q < -TOLERANCE {
                    return;
                }
                if q < 0.0 {
                    q = 0.0;
                }
                let q = q.sqrt();
                let p1 = C::new(center.add_real(q).re, x);
                if self.on_arc(ccw, center, p1) {
                    hits.push(p1.re);
                }
                let p2 = C::new(center.add_real(-q).re, x);
                if self.on_arc(ccw, center, p2) {
                    hits.push(p2.re);
                }
            }
        }
    }

    /// The hits of the line X = `x`.
    pub(crate) fn hits(&self, x: f64) -> Hits {
        let mut hits = Hits::default();
        self.intersection_z(x, &mut hits);
        hits
    }

    /// Draw the segment from its start (G70).
    pub(crate) fn draw(&self, out: &mut dyn Motion) -> Result<()> {
        match self.shape {
            Shape::Line => out.feed(self.end),
            Shape::Arc { ccw, center } => out.arc(ccw, center, self.end),
        }
    }

    /// The top of a counterclockwise arc if its end lies past it.
    fn arc_climb_end(&self, center: C) -> C {
        let mut ep = self.end;
        if self.end.re < center.re {
            ep = C::new(center.re, center.im + (self.start - center).abs());
        }
        ep
    }

    /// Follow a rising segment from `location` (at its start); true if
    /// the segment does not rise (a new pocket starts here).
    pub(crate) fn climb(&self, location: &mut C, out: &mut dyn Motion) -> Result<bool> {
        match self.shape {
            Shape::Line => {
                if self.end.im + TOLERANCE < self.start.im {
                    return Ok(true);
                }
                if (*location - self.start).abs() > TOLERANCE {
                    return Err(InterpError::G7xLostPath);
                }
                out.feed(self.end)?;
                *location = self.end;
                Ok(false)
            }
            Shape::Arc { ccw: false, center } => {
                if location.re > center.re {
                    return Ok(true);
                }
                if (*location - self.end).abs() > 1e-3 {
                    out.arc(false, center, self.end)?;
                }
                *location = self.end;
                Ok(false)
            }
            Shape::Arc { ccw: true, center } => {
                if location.re < center.re {
                    return Ok(true);
                }
                let ep = self.arc_climb_end(center);
                if (*location - ep).abs() > 1e-3 {
                    out.arc(true, center, ep)?;
                }
                *location = ep;
                Ok(true)
            }
        }
    }

    /// After the last pass of G7x.1: follow the rising parts of the
    /// profile from the height of `location`.
    pub(crate) fn climb_only(&self, location: &mut C, out: &mut dyn Motion) -> Result<()> {
        if let Shape::Line = self.shape {
            if self.end.im < self.start.im {
                return Ok(());
            }
        }
        let hits = self.hits(location.im);
        if hits.is_empty() {
            return Ok(());
        }
        match self.shape {
            Shape::Line => {
                location.re = hits.front();
                out.feed(*location)?;
                out.feed(self.end)?;
                *location = self.end;
            }
            Shape::Arc { ccw: false, center } => {
                if hits.back() > center.re {
                    return Ok(());
                }
                location.re = hits.back();
                out.feed(*location)?;
                if (*location - self.end).abs() > 1e-3 {
                    out.arc(false, center, self.end)?;
                }
                *location = self.end;
            }
            Shape::Arc { ccw: true, center } => {
                if hits.front() < center.re {
                    return Ok(());
                }
                location.re = hits.front();
                out.feed(*location)?;
                let ep = self.arc_climb_end(center);
                if (*location - ep).abs() > 1e-3 {
                    out.arc(true, center, ep)?;
                }
                *location = ep;
            }
        }
        Ok(())
    }

    /// Cut down along a falling segment from `location` to the height
    /// `x` (or its end); true if the segment does not fall.
    pub(crate) fn dive(
        &self,
        location: &mut C,
        x: f64,
        out: &mut dyn Motion,
        fast: bool,
    ) -> Result<bool> {
        match self.shape {
            Shape::Line => self.dive_line(location, x, out, fast),
            Shape::Arc { ccw, center } => self.dive_arc(ccw, center, location, x, out),
        }
    }

    fn dive_line(
        &self,
        location: &mut C,
        x: f64,
        out: &mut dyn Motion,
        fast: bool,
    ) -> Result<bool> {
        let go = |out: &mut dyn Motion, to: C| if fast { out.rapid(to) } else { out.feed(to) };
        if self.start.im <= self.end.im + TOLERANCE {
            return Ok(true);
        }
        if x < self.end.im {
            go(out, self.end)?;
            *location = self.end;
            return Ok(false);
        }
        let hits = self.hits(x);
        if hits.is_empty() {
            return Err(InterpError::G7xXTooLarge);
        }
        let ep = C::new(hits.front(), x);
        go(out, ep)?;
        *location = ep;
        Ok(false)
    }

    fn dive_arc(
        &self,
        ccw: bool,
        center: C,
        location: &mut C,
        x: f64,
        out: &mut dyn Motion,
    ) -> Result<bool> {
        if (*location - self.end).abs() < TOLERANCE || (*location - self.end).re <= TOLERANCE {
            *location = self.end;
            return Ok(false);
        }
        let mut hits = self.hits(x);
        if hits.is_empty() {
            self.intersection_z(x - TOLERANCE, &mut hits);
        }
        if ccw {
            if location.re - TOLERANCE > center.re {
                return Ok(true);
            }
            if hits.is_empty() || hits.back() > center.re {
                out.arc(true, center, self.end)?;
                *location = self.end;
            } else {
                let ep = C::new(hits.back(), x);
                out.arc(true, center, ep)?;
                *location = ep;
            }
            return Ok(false);
        }
        if location.re <= center.re {
            return Ok(true);
        }
        if hits.is_empty() {
            out.arc(false, center, self.end)?;
            *location = self.end;
        } else if hits.front() >= center.re {
            let ep = C::new(hits.front(), x);
            out.arc(false, center, ep)?;
            *location = ep;
        }
        Ok(false)
    }
}

/// Make the end of `p` and the start of `n` (which follows it) the same
/// point: where the two meet, or the nearer meeting of a line and arc.
pub(crate) fn intersect(p: &mut Segment, n: &mut Segment) -> Result<()> {
    match (p.shape, n.shape) {
        (Shape::Line, Shape::Line) => {
            let rot = (n.start - n.end).conj().div_real((n.start - n.end).abs());
            let ps = (p.start - n.end) * rot;
            let pe = (p.end - n.end) * rot;
            if (ps - pe).im == 0.0 {
                return Err(InterpError::G7xParallelLines);
            }
            let f = ps.im / (ps - pe).im;
            let is = (ps + (pe - ps).scale(f)) / rot + n.end;
            n.start = is;
            p.end = is;
        }
        (Shape::Arc { center, .. }, Shape::Line) => {
            if (n.start - p.end).abs() < TOLERANCE {
                return Ok(());
            }
            let rot = (n.start - n.end).conj().div_real((n.start - n.end).abs());
            let pe = (p.end - n.end) * rot;
            let pc = (center - n.end) * rot;
            let is = nearer_meeting(n.start, pc, pe, rot, n.end);
            n.start = is;
            p.end = is;
        }
        (Shape::Line, Shape::Arc { center, .. }) => {
            if (n.start - p.end).abs() < TOLERANCE {
                return Ok(());
            }
            let rot = (p.start - p.end).conj().div_real((p.start - p.end).abs());
            let pe = (n.end - p.end) * rot;
            let pc = (center - p.end) * rot;
            let is = nearer_meeting(n.start, pc, pe, rot, p.end);
            n.start = is;
            p.end = is;
        }
        (
            Shape::Arc {
                center: pcenter, ..
            },
            Shape::Arc { center, .. },
        ) => {
            let a = (n.start - center).abs();
            let b = (p.start - pcenter).abs();
            let c = (center - pcenter).abs();
            let cos_b = (c * c + a * a - b * b) / 2.0 / a / c;
            let mut cos_b2 = cos_b * cos_b;
            if cos_b2 > 1.0 {
                cos_b2 = 1.0;
            }
            let rot = C::new(cos_b, (1.0 - cos_b2).sqrt());
            let is = (rot * (pcenter - center)).div_real(c).scale(a) + center;
            p.end = is;
            n.start = is;
        }
    }
    Ok(())
}

/// Of the two points where a circle (center `pc`, through `pe`, both in
/// the line's rotated frame) meets the line, the one nearer `near`.
fn nearer_meeting(near: C, pc: C, pe: C, rot: C, origin: C) -> C {
    let mut b = (pc - pe).norm() - pc.im * pc.im;
    if b < 0.0 {
        b = 0.0;
    } else {
        b = b.sqrt();
    }
    let s1 = C::new(pc.re + b, 0.0) / rot + origin;
    let s2 = C::new(pc.re - b, 0.0) / rot + origin;
    if (near - s1).abs() < (near - s2).abs() {
        s1
    } else {
        s2
    }
}
