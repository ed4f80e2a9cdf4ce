//! A joint's homing configuration (the `HOME_*` keys of an INI file's
//! `[JOINT_n]` section) and the rules a usable configuration follows.

use bitflags::bitflags;

use super::coded::coded_enum;

bitflags! {
    /// The homing option bits, numbered as LinuxCNC's
    /// SET_JOINT_HOMING_PARAMS sends them.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
    pub struct HomeFlags: u32 {
        /// HOME_IGNORE_LIMITS: limit switches do not end homing moves
        /// (the home switch is one of the limit switches).
        const IGNORE_LIMITS = 1;
        /// HOME_USE_INDEX: latch on the encoder index after the switch.
        const USE_INDEX = 2;
        /// HOME_IS_SHARED: the switch is shared; refuse to start on it.
        const IS_SHARED = 4;
        /// LOCKING_INDEXER: unlock before homing, lock afterwards.
        const UNLOCK_FIRST = 8;
        /// HOME_ABSOLUTE_ENCODER 1 or 2: the feedback is absolute.
        const ABSOLUTE_ENCODER = 16;
        /// Homing a homed joint again does nothing (absolute encoders).
        const NO_REHOME = 32;
        /// HOME_ABSOLUTE_ENCODER 2: no move to HOME afterwards.
        const NO_FINAL_MOVE = 64;
        /// HOME_INDEX_NO_ENCODER_RESET: the encoder keeps counting at the
        /// index, so motion applies the offset itself.
        const INDEX_NO_ENCODER_RESET = 128;
    }
}

/// Sequence numbers above this magnitude are not part of home-all.
pub const MAX_HOME_ALL_SEQUENCE: i32 = 100;

/// The homing configuration of a joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HomingConfig {
    /// HOME_OFFSET: the joint position given to the latched reference.
    pub offset: f64,
    /// HOME: where the joint goes once the reference is set.
    pub home: f64,
    /// HOME_FINAL_VEL: speed of the move to HOME; ≤ 0 means the joint's
    /// maximum velocity.
    pub final_vel: f64,
    /// HOME_SEARCH_VEL: speed and direction of the switch search; 0 means
    /// there is no switch.
    pub search_vel: f64,
    /// HOME_LATCH_VEL: speed and direction of the latch move.
    pub latch_vel: f64,
    /// The option bits.
    pub flags: HomeFlags,
    /// HOME_SEQUENCE: order in home-all; equal magnitudes home together,
    /// negative ones as one synchronised group.
    pub sequence: i32,
    /// VOLATILE_HOME: unhomed when the machine goes off.
    pub volatile_home: bool,
}

impl Default for HomingConfig {
    /// LinuxCNC's module defaults before any configuration: home in place
    /// at 0, not part of home-all.
    fn default() -> Self {
        HomingConfig {
            offset: 0.0,
            home: 0.0,
            final_vel: -1.0,
            search_vel: 0.0,
            latch_vel: 0.0,
            flags: HomeFlags::empty(),
            sequence: 1000,
            volatile_home: false,
        }
    }
}

coded_enum! {
    /// Why a homing configuration cannot be used.
    pub enum ConfigProblem {
        /// A value that is not a finite number.
        NotFinite = 1 => "a homing value is not a finite number",
        /// Bits no option has.
        UnknownFlags = 2 => "unknown homing option bits",
        /// HOME_SEARCH_VEL without HOME_LATCH_VEL.
        SearchWithoutLatch = 3 => "HOME_SEARCH_VEL is set but HOME_LATCH_VEL is 0",
        /// HOME_LATCH_VEL without a switch search and without HOME_USE_INDEX.
        LatchWithoutSearchOrIndex = 4 => "HOME_LATCH_VEL without HOME_SEARCH_VEL needs HOME_USE_INDEX",
        /// HOME_USE_INDEX without HOME_LATCH_VEL (nothing would move to the
        /// index).
        IndexWithoutLatch = 5 => "HOME_USE_INDEX needs a HOME_LATCH_VEL",
        /// "No final move" without an absolute encoder.
        NoFinalMoveWithoutAbsoluteEncoder = 6 => "'no final move' is only for HOME_ABSOLUTE_ENCODER",
        /// A sequence number whose magnitude does not fit.
        BadSequence = 7 => "HOME_SEQUENCE out of range",
        /// LOCKING_INDEXER on a joint without `unlock` pins (motmod's
        /// `unlock_joints_mask`).
        NoUnlockPins = 8 => "LOCKING_INDEXER needs the joint in motmod's unlock_joints_mask",
        /// An absolute-encoder locking indexer with a final move would move
        /// while locked.
        LockedFinalMove = 9 => "a locking indexer with HOME_ABSOLUTE_ENCODER must use 2 (no final move)",
    }
}

impl HomingConfig {
    /// Checks the configuration. The valid (search, latch, index)
    /// combinations are LinuxCNC's: (0, 0, no) homes in place, (0, ≠0,
    /// yes) on the index only, (≠0, ≠0, no) on the switch, (≠0, ≠0, yes)
    /// on the switch then the index. LinuxCNC finds the other ones only
    /// when homing starts (or, for an index without latch speed, never);
    /// here they are refused when set.
    pub fn check(&self) -> Result<(), ConfigProblem> {
        let values = [
            self.offset,
            self.home,
            self.final_vel,
            self.search_vel,
            self.latch_vel,
        ];
        if values.iter().any(|v| !v.is_finite()) {
            return Err(ConfigProblem::NotFinite);
        }
        if !self.flags.difference(HomeFlags::all()).is_empty() {
            return Err(ConfigProblem::UnknownFlags);
        }
        if self.sequence == i32::MIN {
            return Err(ConfigProblem::BadSequence);
        }
        let f = self.flags;
        if f.contains(HomeFlags::NO_FINAL_MOVE) && !f.contains(HomeFlags::ABSOLUTE_ENCODER) {
            return Err(ConfigProblem::NoFinalMoveWithoutAbsoluteEncoder);
        }
        if f.contains(HomeFlags::ABSOLUTE_ENCODER) {
            if f.contains(HomeFlags::UNLOCK_FIRST) && !f.contains(HomeFlags::NO_FINAL_MOVE) {
                return Err(ConfigProblem::LockedFinalMove);
            }
            // The velocities are not used.
            return Ok(());
        }
        let index = f.contains(HomeFlags::USE_INDEX);
        match (self.search_vel != 0.0, self.latch_vel != 0.0) {
            (true, false) => Err(ConfigProblem::SearchWithoutLatch),
            (false, true) if !index => Err(ConfigProblem::LatchWithoutSearchOrIndex),
            (false, false) if index => Err(ConfigProblem::IndexWithoutLatch),
            _ => Ok(()),
        }
    }

    /// Whether the joint belongs to a synchronised group.
    pub fn is_synchronized(&self) -> bool {
        self.sequence < 0
    }

    /// Whether home-all homes this joint.
    pub fn in_home_all(&self) -> bool {
        self.sequence.unsigned_abs() <= MAX_HOME_ALL_SEQUENCE as u32
    }
}
