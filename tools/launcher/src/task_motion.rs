//! Task watching motion every cycle: the messages motion reports
//! (faults, limits, homing and probe messages), printed once each as
//! task sees them, and motion's enable flag against the machine state.

use motion::MotionStatus;

use crate::error::LaunchError;
use crate::task::{MachineState, Task};

/// One thing motion reported: the line task prints, and the text its
/// error channel gets (motion's own words, as LinuxCNC's channel carries
/// them: `joint 0 on limit switch error`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct MotionNews {
    /// Printed on task's standard error.
    pub printed: String,
    /// Put on the error channel.
    pub channel: String,
}

impl MotionNews {
    fn new(printed: String, channel: String) -> MotionNews {
        MotionNews { printed, channel }
    }
}

/// What task has seen of motion's messages.
#[derive(Debug, Default)]
pub(crate) struct MotionMessages {
    /// Messages motion had reported at the last look.
    messages: u64,
    /// Faults motion had reported at the last look.
    faults: u64,
    /// Faults motion had reported when task last saw it enabled with the
    /// machine on: a fault after it is why motion disabled itself.
    faults_while_on: u64,
}

impl MotionMessages {
    /// The lines to print for what motion reported since the last look,
    /// oldest first: its last fault and its last message (once, when
    /// they are the same message), and how many it reported between two
    /// looks that task could not see (the snapshot carries the last
    /// message and the last fault only).
    pub(crate) fn news(&mut self, status: &MotionStatus) -> Vec<MotionNews> {
        let mut lines = Vec::new();
        let new_messages = status.events_reported.saturating_sub(self.messages);
        if new_messages == 0 {
            return lines;
        }
        let mut shown = 0;
        let fault = status
            .last_fault
            .filter(|_| status.faults_reported > self.faults);
        if let Some(f) = &fault {
            lines.push(MotionNews::new(
                format!("task: motion error: {f}"),
                f.event.to_string(),
            ));
            shown += 1;
        }
        let last_is_fault = fault.is_some_and(|f| f.number == status.events_reported);
        if let Some(e) = status.last_event.filter(|_| !last_is_fault) {
            lines.push(MotionNews::new(format!("task: motion: {e}"), e.to_string()));
            shown += 1;
        }
        if new_messages > shown {
            let unseen = new_messages - shown;
            let s = if unseen == 1 { "" } else { "s" };
            let text = format!(
                "motion reported {unseen} more message{s} between two of task's \
                 cycles (not shown: only the last message and the last fault are kept)"
            );
            lines.insert(0, MotionNews::new(format!("task: {text}"), text));
        }
        self.messages = status.events_reported;
        self.faults = status.faults_reported;
        lines
    }

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
    /// prints what motion reported and compares motion's enable flag with
    /// its own state. Motion that disabled itself turns the machine off,
    /// naming the fault; motion enabled while task is not on (an enable
    /// answered too late, after a stalled servo thread) is disabled again.
    pub(crate) fn watch_motion(&mut self) {
        let Some(m) = &mut self.motion else { return };
        let Some(status) = m.status() else { return };
        for news in self.motion_messages.news(&status) {
            eprintln!("{}", news.printed);
            self.messages
                .push(crate::task_messages::OPERATOR_ERROR, &news.channel);
        }
        if status.heartbeat < self.settle_until {
            return;
        }
        match (self.state == MachineState::On, status.enabled) {
            (true, true) => self.motion_messages.faults_while_on = status.faults_reported,
            (true, false) => {
                let why = self.motion_messages.why_disabled(&status);
                eprintln!("task: the motion controller disabled itself{why}: machine off");
                self.messages.push(
                    crate::task_messages::OPERATOR_ERROR,
                    &format!("the motion controller disabled itself{why}: machine off"),
                );
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
    fn a_fault_then_a_homing_message_print_once_each() {
        let mut seen = MotionMessages::default();
        let fe = Event::JointFollowingError { joint: 2 };
        let news = seen.news(&status(1, fe, 1, Some(ferror(1))));
        let lines: Vec<&str> = news.iter().map(|n| n.printed.as_str()).collect();
        assert_eq!(
            lines,
            ["task: motion error: joint 2 following error (error 0.250000, limit 0.125000)"]
        );
        // The error channel gets motion's words alone, as LinuxCNC's.
        assert_eq!(news[0].channel, "joint 2 following error");
        let s = status(1, fe, 1, Some(ferror(1)));
        assert!(seen.news(&s).is_empty(), "printed once");
        let abort = Event::HomingAborted {
            joint: 2,
            fault: motion::homing::HomeFault::Disabled,
            state: motion::homing::HomeState::Idle,
        };
        let s = status(2, abort, 1, Some(ferror(1)));
        let news = seen.news(&s);
        assert_eq!(news.len(), 1, "{news:?}");
        assert!(news[0]
            .printed
            .starts_with("task: motion: homing of joint 2 aborted"));
        assert!(news[0].channel.starts_with("homing of joint 2 aborted"));
        // Motion disabled itself: the fault is named, not the homing
        // message that came after it.
        assert_eq!(
            seen.why_disabled(&s),
            " (last fault: joint 2 following error (error 0.250000, limit 0.125000))"
        );
    }

    #[test]
    fn messages_between_two_looks_are_counted() {
        let mut seen = MotionMessages::default();
        let abort = Event::JogStopped { immediate: false };
        // Fault (message 2) and a jog message (3) since the last look,
        // and one message before them that task never saw.
        let news = seen.news(&status(3, abort, 1, Some(ferror(2))));
        let lines: Vec<&str> = news.iter().map(|n| n.printed.as_str()).collect();
        assert_eq!(lines.len(), 3, "{lines:?}");
        assert!(lines[0].contains("1 more message between"), "{lines:?}");
        assert!(news[0]
            .channel
            .starts_with("motion reported 1 more message"));
        assert!(lines[1].starts_with("task: motion error: joint 2 following error"));
        assert_eq!(lines[2], "task: motion: Jog aborted by jog-stop");
        assert_eq!(news[2].channel, "Jog aborted by jog-stop");
    }

    #[test]
    fn a_fault_from_before_the_machine_was_on_is_not_named() {
        let mut seen = MotionMessages::default();
        let fe = Event::JointFollowingError { joint: 2 };
        let s = status(1, fe, 1, Some(ferror(1)));
        seen.news(&s);
        seen.faults_while_on = 1;
        assert_eq!(seen.why_disabled(&s), " (motion reported no fault)");
    }
}
