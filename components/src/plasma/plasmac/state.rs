//! The states and stop types of `plasmac`, numbered as LinuxCNC's
//! `state-out` and `stop-type-out` report them (QtPlasmaC reads both).

/// A state of the cut cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(i32)]
pub enum State {
    /// Waiting for a cut, scribe, spot, pulse or test.
    #[default]
    Idle = 0,
    /// Fast move down to the probe start height.
    ProbeHeight = 1,
    /// Slow move down until the float switch or ohmic probe triggers.
    ProbeDown = 2,
    /// Slow move up until the sensor releases.
    ProbeUp = 3,
    /// Takes the probed height as zero.
    ZeroHeight = 4,
    /// Move to the pierce height.
    PierceHeight = 5,
    /// Fires the torch.
    TorchOn = 6,
    /// Waits for Arc OK, retrying the start.
    ArcOk = 7,
    /// Waits the pierce delay.
    PierceDelay = 8,
    /// Holds at the puddle jump height.
    PuddleJump = 9,
    /// Move to the cut height.
    CutHeight = 10,
    /// Cutting with voltage THC (modes 0 and 1).
    CutMode01 = 11,
    /// Cutting with up/down THC (mode 2).
    CutMode2 = 12,
    /// Holds motion at the end of a cut before the torch goes off.
    PauseAtEnd = 13,
    /// Move to the safe height after a cut.
    SafeHeight = 14,
    /// Move to the top of Z after a stop, pause or error.
    MaxHeight = 15,
    /// Ends one cut.
    EndCut = 16,
    /// Takes the Z offset back at the end of a job.
    EndJob = 17,
    /// A torch pulse.
    TorchPulse = 18,
    /// Motion along the path while paused.
    PausedMotion = 19,
    /// Ohmic test: the ohmic sense is on while the test is held.
    OhmicTest = 20,
    /// A probe test holds at the pierce height.
    ProbeTest = 21,
    /// Scribing.
    Scribing = 22,
    /// Moves XY away for a consumable change.
    ConsumableChangeOn = 23,
    /// Moves XY back after a consumable change.
    ConsumableChangeOff = 24,
    /// Moves XY for cut recovery.
    CutRecoveryOn = 25,
    /// Takes the cut recovery XY offset back while cutting.
    CutRecoveryOff = 26,
}

impl State {
    /// The number `state-out` shows.
    pub fn number(self) -> i32 {
        self as i32
    }

    /// States in which the torch is lit or about to be.
    pub fn is_cutting(self) -> bool {
        matches!(
            self,
            State::TorchOn
                | State::ArcOk
                | State::PierceDelay
                | State::PuddleJump
                | State::CutHeight
                | State::CutMode01
                | State::CutMode2
                | State::PauseAtEnd
                | State::CutRecoveryOff
        )
    }

    /// States that probe.
    pub fn is_probing(self) -> bool {
        matches!(
            self,
            State::ProbeHeight | State::ProbeDown | State::ProbeUp | State::ZeroHeight
        )
    }
}

/// Why the program was stopped or paused (`stop-type-out`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(i32)]
pub enum StopType {
    /// Not stopped.
    #[default]
    None = 0,
    /// The program is stopped: the job ends.
    Stop = 1,
    /// Paused by an error of the cut: waits for resume.
    Wait = 2,
    /// Paused by the operator: waits for resume.
    Pause = 3,
}

/// An error of the cut cycle: each is printed once (on stderr, as
/// LinuxCNC's operator errors are) and leaves `state-out`/`stop-type-out`
/// as the doc of each variant says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(usize)]
pub enum Fault {
    /// A sensor was on when a cut started: program stopped.
    SensorBeforeProbe = 0,
    /// Probing reached the Z minimum limit: program stopped.
    ProbeMinLimit = 1,
    /// No Arc OK after `arc-max-starts` attempts: paused (wait).
    NoArc = 2,
    /// Arc OK lost while cutting: paused (wait).
    ArcLost = 3,
    /// The breakaway switch tripped while cutting: paused (wait).
    Breakaway = 4,
    /// The float switch tripped while cutting: paused (wait).
    FloatSwitch = 5,
    /// THC reached the Z minimum limit: program stopped.
    ThcMinLimit = 6,
    /// THC reached the Z maximum limit: program stopped.
    ThcMaxLimit = 7,
    /// A cut began while the machine is not homed: program stopped.
    NotHomed = 8,
}

/// The message of each [`Fault`], indexed by its number.
pub const FAULT_TEXTS: &[&str] = &[
    "plasmac: a float, ohmic or breakaway sensor was on before probing, program stopped\n",
    "plasmac: probing reached the Z axis minimum limit, program stopped\n",
    "plasmac: no arc detected after the maximum number of starts, program paused\n",
    "plasmac: valid arc lost while cutting, program paused\n",
    "plasmac: breakaway switch activated while cutting, program paused\n",
    "plasmac: float switch activated while cutting, program paused\n",
    "plasmac: THC reached the Z axis minimum limit, program stopped\n",
    "plasmac: THC reached the Z axis maximum limit, program stopped\n",
    "plasmac: cut started on a machine that is not homed, program stopped\n",
];

impl Fault {
    /// Its index in [`FAULT_TEXTS`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// The stop type it leaves.
    pub fn stop_type(self) -> StopType {
        match self {
            Fault::NoArc | Fault::ArcLost | Fault::Breakaway | Fault::FloatSwitch => StopType::Wait,
            _ => StopType::Stop,
        }
    }
}

/// What `debug-print` prints on entering each state, by number.
pub(super) const STATE_TEXTS: &[&str] = &[
    "plasmac: IDLE\n",
    "plasmac: PROBE_HEIGHT\n",
    "plasmac: PROBE_DOWN\n",
    "plasmac: PROBE_UP\n",
    "plasmac: ZERO_HEIGHT\n",
    "plasmac: PIERCE_HEIGHT\n",
    "plasmac: TORCH_ON\n",
    "plasmac: ARC_OK\n",
    "plasmac: PIERCE_DELAY\n",
    "plasmac: PUDDLE_JUMP\n",
    "plasmac: CUT_HEIGHT\n",
    "plasmac: CUT_MODE_01\n",
    "plasmac: CUT_MODE_2\n",
    "plasmac: PAUSE_AT_END\n",
    "plasmac: SAFE_HEIGHT\n",
    "plasmac: MAX_HEIGHT\n",
    "plasmac: END_CUT\n",
    "plasmac: END_JOB\n",
    "plasmac: TORCHPULSE\n",
    "plasmac: PAUSED_MOTION\n",
    "plasmac: OHMIC_TEST\n",
    "plasmac: PROBE_TEST\n",
    "plasmac: SCRIBING\n",
    "plasmac: CONSUMABLE_CHANGE_ON\n",
    "plasmac: CONSUMABLE_CHANGE_OFF\n",
    "plasmac: CUT_RECOVERY_ON\n",
    "plasmac: CUT_RECOVERY_OFF\n",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_linuxcncs() {
        assert_eq!(State::Idle.number(), 0);
        assert_eq!(State::CutMode01.number(), 11);
        assert_eq!(State::EndJob.number(), 17);
        assert_eq!(State::CutRecoveryOff.number(), 26);
        assert_eq!(StopType::Pause as i32, 3);
        assert_eq!(FAULT_TEXTS.len(), Fault::NotHomed.index() + 1);
        assert_eq!(
            STATE_TEXTS.len(),
            State::CutRecoveryOff.number() as usize + 1
        );
        assert!(STATE_TEXTS[11].contains("CUT_MODE_01"));
        assert_eq!(Fault::ArcLost.stop_type(), StopType::Wait);
        assert_eq!(Fault::ProbeMinLimit.stop_type(), StopType::Stop);
    }
}
