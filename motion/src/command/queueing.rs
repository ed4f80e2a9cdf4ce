//! The arguments of the queueing commands: what kind of straight move, the
//! probe's sense, the termination condition for the moves queued next.

/// What a straight move is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineKind {
    /// A rapid (G0): as fast as the axes allow, scaled by the rapid
    /// override; the programmed velocity is ignored.
    Traverse,
    /// A feed move (G1) at the programmed velocity.
    Feed,
}

impl LineKind {
    /// The code on the wire.
    pub fn code(self) -> u64 {
        match self {
            LineKind::Traverse => 0,
            LineKind::Feed => 1,
        }
    }

    /// The kind with wire code `code`.
    pub fn from_code(code: u64) -> Option<LineKind> {
        match code {
            0 => Some(LineKind::Traverse),
            1 => Some(LineKind::Feed),
            _ => None,
        }
    }
}

/// What a probing move (G38.2 to G38.5) looks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ProbeType {
    /// Ending without the sought change is not an error (G38.3, G38.5).
    pub no_error: bool,
    /// Trip when the input goes false (G38.4, G38.5) instead of true.
    pub trip_on_clear: bool,
}

impl ProbeType {
    /// G38.2: towards the workpiece, an error without contact.
    pub const G38_2: ProbeType = ProbeType {
        no_error: false,
        trip_on_clear: false,
    };
    /// G38.3: towards the workpiece, no error without contact.
    pub const G38_3: ProbeType = ProbeType {
        no_error: true,
        trip_on_clear: false,
    };
    /// G38.4: away from the workpiece, an error without loss of contact.
    pub const G38_4: ProbeType = ProbeType {
        no_error: false,
        trip_on_clear: true,
    };
    /// G38.5: away from the workpiece, no error without loss of contact.
    pub const G38_5: ProbeType = ProbeType {
        no_error: true,
        trip_on_clear: true,
    };

    /// LinuxCNC's `probe_type` bits: bit 0 no error, bit 1 trip on clear.
    pub fn bits(self) -> u64 {
        u64::from(self.no_error) | (u64::from(self.trip_on_clear) << 1)
    }

    /// The type of LinuxCNC's `probe_type` bits (0..=3).
    pub fn from_bits(bits: u64) -> Option<ProbeType> {
        (bits <= 3).then_some(ProbeType {
            no_error: bits & 1 != 0,
            trip_on_clear: bits & 2 != 0,
        })
    }

    /// The G-code of this type ("G38.2" ...).
    pub fn gcode(self) -> &'static str {
        match (self.no_error, self.trip_on_clear) {
            (false, false) => "G38.2",
            (true, false) => "G38.3",
            (false, true) => "G38.4",
            (true, true) => "G38.5",
        }
    }
}

/// How the moves queued from now on end (SET_TERM_COND).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TermCond {
    /// Exact stop (G61.1): every move ends at rest.
    Stop,
    /// Exact path (G61): no deviation from the programmed path; corners
    /// the axes can take at speed (nearly tangent ones) are not stopped
    /// at.
    ExactPath,
    /// Blending (G64 P): corners are rounded within the tolerance given
    /// with it (0: as fast as possible, a quarter of the shorter move).
    Blend,
}

impl TermCond {
    /// LinuxCNC's number (0 stop, 1 exact path, 2 blend).
    pub fn code(self) -> u64 {
        match self {
            TermCond::Stop => 0,
            TermCond::ExactPath => 1,
            TermCond::Blend => 2,
        }
    }

    /// The condition with LinuxCNC's number `code`.
    pub fn from_code(code: u64) -> Option<TermCond> {
        match code {
            0 => Some(TermCond::Stop),
            1 => Some(TermCond::ExactPath),
            2 => Some(TermCond::Blend),
            _ => None,
        }
    }
}
