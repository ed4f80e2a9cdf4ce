//! Closed-loop control and loop diagnostics.
//!
//! * `control`: `pid`, the PID controller with feed-forward terms and
//!   relay auto-tuning (a C-style module: `num_chan=`, `names=`, `debug=`).
//! * `timedelta`: measures the real time between runs of its function.
//! * `at_pid`: the older PID with relay auto-tuning.

pub mod at_pid;
pub mod control;
pub mod timedelta;

/// Every module of this family.
pub fn modules() -> Vec<&'static hal_core::ModuleDef> {
    vec![&control::MODULE, &timedelta::MODULE, &at_pid::MODULE]
}
