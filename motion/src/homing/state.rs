//! The states of a joint's homing state machine, numbered as LinuxCNC
//! publishes them on `joint.N.home-state`, and why homing can fail.

/// A joint's homing state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[repr(i32)]
pub enum HomeState {
    /// Not homing.
    #[default]
    Idle = 0,
    /// Homing was requested: checks, then the first real state.
    Start = 1,
    /// Asking a locking indexer to unlock.
    Unlock = 2,
    /// Waiting for the indexer to report it is unlocked.
    UnlockWait = 3,
    /// Starting to move off a switch that was closed at the start.
    InitialBackoffStart = 4,
    /// Moving off the switch.
    InitialBackoffWait = 5,
    /// Starting the coarse search for the switch.
    InitialSearchStart = 6,
    /// Searching for the switch at HOME_SEARCH_VEL.
    InitialSearchWait = 7,
    /// The switch was found: a rough position is set.
    SetCoarsePosition = 8,
    /// Starting to back off the switch before the latch move.
    FinalBackoffStart = 9,
    /// Backing off the switch.
    FinalBackoffWait = 10,
    /// Starting the latch move towards the switch.
    RiseSearchStart = 11,
    /// Latch move: waiting for the switch to close.
    RiseSearchWait = 12,
    /// Starting the latch move off the switch.
    FallSearchStart = 13,
    /// Latch move: waiting for the switch to open.
    FallSearchWait = 14,
    /// The switch (or absolute encoder) sets the position.
    SetSwitchPosition = 15,
    /// Index-only homing: arm the index and move.
    IndexOnlyStart = 16,
    /// Arm the index while still moving.
    IndexSearchStart = 17,
    /// Waiting for the encoder to see the index.
    IndexSearchWait = 18,
    /// The index sets the position.
    SetIndexPosition = 19,
    /// Starting the move to HOME.
    FinalMoveStart = 20,
    /// Moving to HOME.
    FinalMoveWait = 21,
    /// Asking a locking indexer to lock.
    Lock = 22,
    /// Waiting for the indexer to lock.
    LockWait = 23,
    /// Homed.
    Finished = 24,
    /// Homing failed or was cancelled.
    Abort = 25,
}

impl HomeState {
    /// The number published on `joint.N.home-state`.
    pub fn number(self) -> i32 {
        self as i32
    }

    /// The state with that number.
    pub fn from_number(n: i32) -> Option<HomeState> {
        use HomeState::*;
        const ALL: [HomeState; 26] = [
            Idle,
            Start,
            Unlock,
            UnlockWait,
            InitialBackoffStart,
            InitialBackoffWait,
            InitialSearchStart,
            InitialSearchWait,
            SetCoarsePosition,
            FinalBackoffStart,
            FinalBackoffWait,
            RiseSearchStart,
            RiseSearchWait,
            FallSearchStart,
            FallSearchWait,
            SetSwitchPosition,
            IndexOnlyStart,
            IndexSearchStart,
            IndexSearchWait,
            SetIndexPosition,
            FinalMoveStart,
            FinalMoveWait,
            Lock,
            LockWait,
            Finished,
            Abort,
        ];
        usize::try_from(n).ok().and_then(|i| ALL.get(i)).copied()
    }

    /// LinuxCNC's name of the state, for messages.
    pub fn name(self) -> &'static str {
        use HomeState::*;
        match self {
            Idle => "IDLE",
            Start => "START",
            Unlock => "UNLOCK",
            UnlockWait => "UNLOCK_WAIT",
            InitialBackoffStart => "INITIAL_BACKOFF_START",
            InitialBackoffWait => "INITIAL_BACKOFF_WAIT",
            InitialSearchStart => "INITIAL_SEARCH_START",
            InitialSearchWait => "INITIAL_SEARCH_WAIT",
            SetCoarsePosition => "SET_COARSE_POSITION",
            FinalBackoffStart => "FINAL_BACKOFF_START",
            FinalBackoffWait => "FINAL_BACKOFF_WAIT",
            RiseSearchStart => "RISE_SEARCH_START",
            RiseSearchWait => "RISE_SEARCH_WAIT",
            FallSearchStart => "FALL_SEARCH_START",
            FallSearchWait => "FALL_SEARCH_WAIT",
            SetSwitchPosition => "SET_SWITCH_POSITION",
            IndexOnlyStart => "INDEX_ONLY_START",
            IndexSearchStart => "INDEX_SEARCH_START",
            IndexSearchWait => "INDEX_SEARCH_WAIT",
            SetIndexPosition => "SET_INDEX_POSITION",
            FinalMoveStart => "FINAL_MOVE_START",
            FinalMoveWait => "FINAL_MOVE_WAIT",
            Lock => "LOCK",
            LockWait => "LOCK_WAIT",
            Finished => "FINISHED",
            Abort => "ABORT",
        }
    }
}

impl std::fmt::Display for HomeState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Why homing of a joint stopped before it finished.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HomeFault {
    /// A limit switch tripped during a homing move (and the joint does not
    /// ignore its limits while homing).
    HitLimit,
    /// A search move ran its whole length without the expected event.
    EndOfMove,
    /// A shared home switch was already closed when homing started.
    SharedSwitchClosed,
    /// The switch opened before the backoff that needs it closed.
    SwitchInactiveBeforeBackoff,
    /// The switch was still closed when the latch move towards it began.
    SwitchActiveBeforeLatch,
    /// The switch was open when the latch move off it began.
    SwitchInactiveBeforeLatch,
    /// The probe input tripped during a homing move.
    ProbeTripped,
    /// Motion was disabled (by a command or a fault) while homing.
    Disabled,
}

impl HomeFault {
    /// Code on the wire (event encoding).
    pub fn code(self) -> u64 {
        match self {
            HomeFault::HitLimit => 1,
            HomeFault::EndOfMove => 2,
            HomeFault::SharedSwitchClosed => 3,
            HomeFault::SwitchInactiveBeforeBackoff => 4,
            HomeFault::SwitchActiveBeforeLatch => 5,
            HomeFault::SwitchInactiveBeforeLatch => 6,
            HomeFault::ProbeTripped => 7,
            HomeFault::Disabled => 8,
        }
    }

    /// The fault with wire code `code`.
    pub fn from_code(code: u64) -> Option<HomeFault> {
        Some(match code {
            1 => HomeFault::HitLimit,
            2 => HomeFault::EndOfMove,
            3 => HomeFault::SharedSwitchClosed,
            4 => HomeFault::SwitchInactiveBeforeBackoff,
            5 => HomeFault::SwitchActiveBeforeLatch,
            6 => HomeFault::SwitchInactiveBeforeLatch,
            7 => HomeFault::ProbeTripped,
            8 => HomeFault::Disabled,
            _ => return None,
        })
    }
}

impl std::fmt::Display for HomeFault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            HomeFault::HitLimit => "hit a limit switch",
            HomeFault::EndOfMove => {
                "reached the end of the move without the expected switch or index"
            }
            HomeFault::SharedSwitchClosed => "cannot home while the shared home switch is closed",
            HomeFault::SwitchInactiveBeforeBackoff => {
                "home switch inactive before the start of the backoff move"
            }
            HomeFault::SwitchActiveBeforeLatch => {
                "home switch active before the start of the latch move"
            }
            HomeFault::SwitchInactiveBeforeLatch => {
                "home switch inactive before the start of the latch move"
            }
            HomeFault::ProbeTripped => "the probe tripped during the homing motion",
            HomeFault::Disabled => "motion was disabled",
        })
    }
}
