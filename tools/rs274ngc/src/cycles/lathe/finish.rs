//! G70, the finishing cycle: the profile cut along its whole length, in
//! one or more passes whose distance from the final profile goes from D
//! down to E.

use super::complex::C;
use super::profile::Profile;
use super::segment::Motion;
use crate::error::{InterpError, Result};

/// The words of a finishing cycle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Finish {
    /// The start point (Z, X), where each pass starts from.
    pub start: C,
    /// Distance of the first pass from the profile (D).
    pub first: f64,
    /// Distance of the last pass (E).
    pub last: f64,
    /// Number of passes (P).
    pub passes: f64,
    /// The most moves the cycle may make
    /// ([`crate::Config::max_cycle_moves`]).
    pub limit: u32,
}

/// Cut the finishing passes of `path`.
pub(crate) fn finish(mut path: Profile, w: &Finish, out: &mut dyn Motion) -> Result<()> {
    // Each pass: two rapids and the segments, plus an arc per corner.
    let moves = w.passes.floor() * (2.0 * path.segs.len() as f64 + 2.0);
    if moves.is_nan() || moves > f64::from(w.limit) {
        return Err(InterpError::G7xTooManyPasses { limit: w.limit });
    }
    let Some(first) = path.segs.first_mut() else {
        return Err(InterpError::G7xProfileVanished);
    };
    first.start = w.start;
    // Find how the profile must be turned, on a copy without its lead-in.
    let mut probe = path.clone();
    probe.segs.remove(0);
    probe.swap();
    if !probe.segs.iter().all(|s| s.monotonic()) {
        probe.rotate();
        probe.swap();
    }
    probe.monotonic()?;
    if probe.flip_state & 4 != 0 {
        path.rotate();
    }
    path.swap();
    path.do_finish()?;
    path.monotonic()?;
    let mut out = path.motion(out);
    let passes = w.passes as i32;
    for pass in (1..=passes).rev() {
        let distance = f64::from(pass - 1) * (w.first - w.last) / w.passes + w.last;
        let mut cut = path.clone();
        let offset = cut.add_distance(distance);
        for note in cut.notes.drain(..) {
            out.note(&note);
        }
        offset?;
        out.rapid(cut.segs[0].start)?;
        out.rapid(cut.segs[0].end)?;
        for s in &cut.segs[1..] {
            s.draw(&mut out)?;
        }
    }
    Ok(())
}
