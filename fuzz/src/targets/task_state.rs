//! Task's `state` answers as halui reads them
//! ([`hal_launcher::fuzz::task_state`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "task_state",
    run: hal_launcher::fuzz::task_state,
    dictionary: &[
        "machine=", "mode=", "program=", "mist=", "flood=", "lube=", "tool=",
        "feed-override=", "rapid-override=", "max-velocity=", "ON", "OFF", "ESTOP",
        "MANUAL", "AUTO", "MDI", "IDLE", "RUNNING", "PAUSED", "\n", "=",
    ],
    generate: None,
};
