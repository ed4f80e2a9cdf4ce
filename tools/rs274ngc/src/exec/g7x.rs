//! G70, G71 and G72 in the interpreter: the checks LinuxCNC makes, the
//! profile read by calling its subroutine (`Q` names it) and collecting
//! the moves of its blocks instead of executing them, and the moves the
//! geometry in [`crate::cycles::lathe`] produces, made as ordinary G0,
//! G1, G2 and G3 moves.

use crate::block::{Block, OType};
use crate::canon::{Canon, Plane};
use crate::codes::*;
use crate::cycles::lathe::{self, Finish, Motion, Pockets, Profile, Rough, Segment, C};
use crate::error::{InterpError, Result};
use crate::interp::Interp;
use crate::setup::{DistanceMode, Side};

/// The most blocks the profile subroutine may run (loops included).
const MAX_PROFILE_BLOCKS: usize = 100_000;
/// The most segments a profile may have.
const MAX_SEGMENTS: usize = 10_000;
/// Coordinates closer than this are the same point (LinuxCNC's `equal`).
const TOLERANCE_EQUAL: f64 = 0.0001;

/// The distance modes in force when the cycle was programmed (the
/// cycle itself runs in absolute mode).
#[derive(Debug, Clone, Copy)]
struct Modes {
    incremental: bool,
    ijk_incremental: bool,
}

impl Interp {
    /// Execute a G70, G71.x or G72.x block.
    pub(crate) fn convert_g7x(&mut self, block: &mut Block, canon: &mut dyn Canon) -> Result<()> {
        if !block.q_flag {
            return Err(InterpError::G7xNeedsQ);
        }
        let code = block.g_modes[GM_MOTION];
        let (cycle, sub) = (code / 10, code % 10);
        if self.s.cutter_comp_side != Side::Off && cycle != 70 {
            return Err(InterpError::G7xWithComp(cycle, sub));
        }
        if self.s.plane != Plane::Xz {
            return Err(InterpError::G7xPlane(cycle, sub));
        }
        let saved = (self.s.distance_mode, self.s.ijk_distance_mode);
        let modes = Modes {
            incremental: saved.0 == DistanceMode::Incremental,
            ijk_incremental: saved.1 == DistanceMode::Incremental,
        };
        self.s.distance_mode = DistanceMode::Absolute;
        self.s.ijk_distance_mode = DistanceMode::Absolute;
        self.reading_profile = true;
        let result = self.run_g7x(cycle, sub, modes, block, canon);
        self.reading_profile = false;
        self.s.distance_mode = saved.0;
        self.s.ijk_distance_mode = saved.1;
        result
    }

    fn run_g7x(
        &mut self,
        cycle: i32,
        sub: i32,
        modes: Modes,
        block: &mut Block,
        canon: &mut dyn Canon,
    ) -> Result<()> {
        let (start_x, start_z) = (self.s.current.x, self.s.current.z);
        let (mut x, mut z) = (start_x, start_z);
        if modes.incremental {
            x += if block.x_flag { block.x_number } else { 0.0 };
            z += if block.z_flag { block.z_number } else { 0.0 };
        } else {
            x = if block.x_flag { block.x_number } else { x };
            z = if block.z_flag { block.z_number } else { z };
        }
        let words = block.clone();
        // Under cutter compensation (G70 only) this rapid and every move
        // of the passes go through the compensation queue, as in
        // LinuxCNC 2.9: the rapid is the entry move if the comp has not
        // moved yet.
        let compensating = self.s.cutter_comp_side != Side::Off;
        self.convert_straight(G_0, block, canon)?;
        let (path, mut last) = self.read_profile(words.q_number, C::new(z, x), modes, canon)?;
        // The moves belong to the cycle's line (for task's motion line).
        last.line_number = words.line_number;
        if path.segs.len() <= 1 {
            return Ok(());
        }
        let word = |flag: bool, value: f64, default: f64| if flag { value } else { default };
        let increment = word(words.i_flag, words.i_number, 1.0);
        // Reading the profile left the current point at its end. Without
        // compensation the point the cycle started from is put back (no
        // move shows it: each pass starts with an absolute rapid). With
        // it, LinuxCNC 2.9 leaves the profile's end as the tool's
        // position, and the compensation of the first pass's rapids
        // starts from there (the programmed point stays the cycle's
        // start point).
        if !compensating {
            self.s.current.x = start_x;
            self.s.current.z = start_z;
        }
        if increment <= 0.0 {
            return Err(InterpError::G7xIncrement);
        }
        let allowance = word(words.d_flag, words.d_number, 0.0);
        let rough = Rough {
            start: C::new(z, x),
            shift: C::new(
                word(words.w_flag, words.w_number, 0.0),
                word(words.u_flag, words.u_number, 0.0),
            ),
            allowance,
            increment,
            retract: word(words.r_flag, words.r_number, 0.5),
            limit: self.config.max_cycle_moves,
        };
        let pockets = match sub {
            1 => Pockets::None,
            2 => Pockets::Only,
            _ => Pockets::All,
        };
        let mut machine = Machine {
            interp: self,
            canon,
            block: last,
        };
        match cycle {
            70 => {
                let finish = Finish {
                    start: C::new(z, x),
                    first: allowance,
                    last: word(words.e_flag, words.e_number, 0.0),
                    passes: word(words.p_flag, words.p_number, 1.0),
                    limit: rough.limit,
                };
                lathe::finish(path, &finish, &mut machine)
            }
            71 => lathe::rough(path, pockets, false, &rough, &mut machine),
            72 => lathe::rough(path, pockets, true, &rough, &mut machine),
            _ => Ok(()),
        }
    }

    /// Call subroutine `q` and collect its moves from `start`; returns
    /// the profile and the last block read.
    fn read_profile(
        &mut self,
        q: f64,
        start: C,
        modes: Modes,
        canon: &mut dyn Canon,
    ) -> Result<(Profile, Block)> {
        let exit_level = self.flow.call_level;
        let call = format!("O{} CALL", crate::cfmt::f(q, 6));
        self.read_line(Some(call.as_bytes()), canon)?;
        let mut path = Profile::default();
        let mut at = start;
        let mut blocks = 0;
        loop {
            if self.block.o_type != OType::None {
                let mut b = std::mem::take(&mut self.block);
                let result = self.convert_control_functions(&mut b, canon);
                self.block = b;
                result?;
            }
            if self.flow.call_level == exit_level {
                break;
            }
            blocks += 1;
            if blocks > MAX_PROFILE_BLOCKS {
                return Err(InterpError::G7xProfileTooLong(MAX_PROFILE_BLOCKS));
            }
            for (index, value) in std::mem::take(&mut self.pending_numbered) {
                self.params.set(index, value);
            }
            for (name, value) in std::mem::take(&mut self.pending_named) {
                self.store_named_param(&name, value)?;
            }
            self.profile_block(&mut path, &mut at, modes)?;
            self.read_line(None, canon)?;
        }
        Ok((path, self.block.clone()))
    }

    /// Add the move of the block just read (if it moves) to the profile.
    fn profile_block(&mut self, path: &mut Profile, at: &mut C, modes: Modes) -> Result<()> {
        let b = &self.block;
        let start = *at;
        let mut end = if modes.incremental {
            C::default()
        } else {
            start
        };
        if b.u_flag {
            if modes.incremental {
                return Err(InterpError::G7xUIncremental);
            }
            if b.x_flag {
                return Err(InterpError::G7xUAndX);
            }
            let u = if self.s.lathe_diameter_mode {
                b.u_number / 2.0
            } else {
                b.u_number
            };
            end.im += u;
        } else if b.x_flag {
            end.im = b.x_number;
        }
        if b.w_flag {
            if modes.incremental {
                return Err(InterpError::G7xWIncremental);
            }
            if b.z_flag {
                return Err(InterpError::G7xWAndZ);
            }
            end.re += b.w_number;
        } else if b.z_flag {
            end.re = b.z_number;
        }
        if modes.incremental {
            end += start;
        }
        if b.g_modes[GM_MOTION] != -1 {
            self.s.motion_mode = b.g_modes[GM_MOTION];
        }
        if start == end {
            return Ok(());
        }
        let motion = self.s.motion_mode;
        let segment = match motion {
            G_0 | G_1 => Some(Segment::line(start, end)),
            G_2 | G_3 => Some(profile_arc(b, motion, start, end, modes)?),
            _ => None,
        };
        let mut add = |s: Segment| {
            if path.segs.len() >= MAX_SEGMENTS {
                return Err(InterpError::G7xTooManySegments(MAX_SEGMENTS));
            }
            path.segs.push(s);
            Ok(())
        };
        if let Some(segment) = segment {
            add(segment)?;
            if b.a_flag && b.c_flag {
                return Err(InterpError::G7xFilletAndChamfer);
            }
            if b.a_flag {
                add(Segment::fillet(b.a_number, end))?;
            }
            if b.c_flag {
                add(Segment::chamfer(b.c_number, end))?;
            }
        }
        self.s.current.x = end.im;
        self.s.current.z = end.re;
        *at = end;
        Ok(())
    }
}

/// The arc of a profile block, by radius (R) or center (I, K).
fn profile_arc(b: &Block, motion: i32, start: C, end: C, modes: Modes) -> Result<Segment> {
    let mut center = C::new(
        if b.k_flag { b.k_number } else { 0.0 },
        if b.i_flag { b.i_number } else { 0.0 },
    );
    if b.r_flag {
        if b.i_flag || b.k_flag {
            return Err(InterpError::G7xArcRAndIk);
        }
        let r = b.r_number;
        let chord = (end - start).norm();
        center = (start + end).div_real(2.0);
        let d = lathe::complex::I.scale(((r * r - chord / 4.0) / chord).sqrt()) * (end - start);
        center = if motion == G_3 {
            center + d
        } else {
            center - d
        };
    } else {
        if !b.i_flag && !b.k_flag {
            return Err(InterpError::G7xArcNoIk);
        }
        if modes.ijk_incremental {
            center += start;
        }
    }
    Ok(Segment::arc(motion == G_3, start, center, end))
}

/// The interpreter as the output of the cycle geometry: each move is a
/// G0, G1, G2 or G3 of the block last read, with its X, Z (and I, K)
/// replaced.
struct Machine<'a> {
    interp: &'a mut Interp,
    canon: &'a mut dyn Canon,
    block: Block,
}

impl Machine<'_> {
    fn set_end(&mut self, end: C) {
        self.block.x_flag = true;
        self.block.x_number = end.im;
        self.block.z_flag = true;
        self.block.z_number = end.re;
    }
}

impl Motion for Machine<'_> {
    fn feed(&mut self, end: C) -> Result<()> {
        self.set_end(end);
        self.interp.convert_straight(G_1, &self.block, self.canon)
    }

    fn rapid(&mut self, end: C) -> Result<()> {
        self.set_end(end);
        self.interp.convert_straight(G_0, &self.block, self.canon)
    }

    fn arc(&mut self, ccw: bool, center: C, end: C) -> Result<()> {
        self.set_end(end);
        self.block.i_flag = true;
        self.block.i_number = center.im;
        self.block.k_flag = true;
        self.block.k_number = center.re;
        let current = self.interp.s.current;
        if (current.z - end.re).abs() < TOLERANCE_EQUAL
            && (current.x - end.im).abs() < TOLERANCE_EQUAL
        {
            return Ok(());
        }
        let mv = if ccw { G_3 } else { G_2 };
        self.interp.convert_arc(mv, &mut self.block, self.canon)
    }

    fn note(&mut self, text: &str) {
        self.canon.print(text);
    }
}
