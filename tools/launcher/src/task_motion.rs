//! Task watching motion every cycle: motion's enable flag against the
//! machine state, and the fault that disabled motion.

use motion::MotionStatus;

use crate::error::LaunchError;
use crate::task::{MachineState, Task};

/// What task has seen of motion's messages.
#[derive(Debug, Default)]
pub(crate) struct MotionMessages {
    /// Faults motion had reported when task last saw it enabled with the
    /// machine on: a fault after it is why motion disabled itself.
    faults_while_on: u64,
}

impl MotionMessages {
    /// Why motion disabled itself: its last fault, if it reported one
    /// since task last saw it enabled with the machine on.
    fn why_disabled(&self, status: &MotionStatus) -> String {
        match status.last_fault {
            Some(f) if status.faults_reported > self.faults_while_on => {
                format!(" (last fault: {f})")
            }
            _ => " (motion reported no fault)".to_string(),
        }
    }
}

impl Task {
    /// Task is the one authority over the machine state: every cycle it
    /// compares motion's enable flag with its own state. Motion that disabled itself turns the machine off,
    /// naming the fault; motion enabled while task is not on (an enable
    /// answered too late, after a stalled servo thread) is disabled again.
    pub(crate) fn watch_motion(&mut self) {
        let Some(m) = &mut self.motion else { return };
        let Some(status) = m.status() else { return };
        if status.heartbeat < self.settle_until {
            return;
        }
        match (self.state == MachineState::On, status.enabled) {
            (true, true) => self.motion_messages.faults_while_on = status.faults_reported,
            (true, false) => {
                let why = self.motion_messages.why_disabled(&status);
                eprintln!("task: the motion controller disabled itself{why}: machine off");
                self.state = MachineState::Off;
                self.stop_program();
            }
            (false, true) => {
                eprintln!(
                    "task: the motion controller is enabled while the machine is {}: \
                     disabling it",
                    self.state.name()
                );
                if let Err(source) = m.disable() {
                    eprintln!("task: {}", LaunchError::Disabling { source });
                }
                self.settle();
            }
            (false, false) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use motion::{Event, Fault, FollowingErrorTrip};

    fn status(messages: u64, last: Event, faults: u64, fault: Option<Fault>) -> MotionStatus {
        MotionStatus {
            events_reported: messages,
            last_event: Some(last),
            faults_reported: faults,
            last_fault: fault,
            ..MotionStatus::default()
        }
    }

    fn ferror(number: u64) -> Fault {
        Fault {
            event: Event::JointFollowingError { joint: 2 },
            number,
            following: Some(FollowingErrorTrip {
                error: 0.25,
                limit: 0.125,
            }),
        }
    }

    #[test]
    fn the_fault_is_named_not_a_later_homing_message() {
        let seen = MotionMessages::default();
        let abort = Event::HomingAborted {
            joint: 2,
            fault: motion::homing::HomeFault::Disabled,
            state: motion::homing::HomeState::Idle,
        };
        let s = status(2, abort, 1, Some(ferror(1)));
        assert_eq!(
            seen.why_disabled(&s),
            " (last fault: joint 2 following error (error 0.250000, limit 0.125000))"
        );
    }

    #[test]
    fn a_fault_from_before_the_machine_was_on_is_not_named() {
        let mut seen = MotionMessages::default();
        let fe = Event::JointFollowingError { joint: 2 };
        let s = status(1, fe, 1, Some(ferror(1)));
        seen.faults_while_on = 1;
        assert_eq!(seen.why_disabled(&s), " (motion reported no fault)");
    }
}
