//! What z_level_compensation needs of task: whether the machine is on,
//! and the active G5x offset of X and Y (from task's `state` answer).

use std::time::Duration;

use crate::task_socket::{request, TaskAnswer, TaskClientError};

/// How long a `state` request may take.
const WAIT: Duration = Duration::from_secs(2);

/// The machine as compensation sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MachineView {
    /// Task's machine state is ON.
    pub on: bool,
    /// The G5x offset of X and Y.
    pub g5x: (f64, f64),
}

/// Reads a `state` answer's `machine=` and `g5x-offset=` lines (an
/// answer without `g5x-offset` has a zero offset).
pub fn parse(text: &str) -> Option<MachineView> {
    let mut on = None;
    let mut g5x = (0.0, 0.0);
    for line in text.lines() {
        let Some((key, value)) = line.split_once('=') else {
            continue;
        };
        match key.trim() {
            "machine" => on = Some(value.trim() == "ON"),
            "g5x-offset" => {
                let mut w = value.split_whitespace().map(str::parse::<f64>);
                if let (Some(Ok(x)), Some(Ok(y))) = (w.next(), w.next()) {
                    g5x = (x, y);
                }
            }
            _ => {}
        }
    }
    on.map(|on| MachineView { on, g5x })
}

/// Asks task for its state each cycle; a failure is said once until task
/// answers again.
pub struct TaskWatch {
    instance: String,
    said: bool,
}

impl TaskWatch {
    /// Watches the task of `instance`.
    pub fn new(instance: String) -> TaskWatch {
        TaskWatch {
            instance,
            said: false,
        }
    }

    /// The machine now, or `None` while task does not answer.
    pub fn read(&mut self) -> Option<MachineView> {
        let words = ["state".to_string()];
        let why = match request(&self.instance, &words, WAIT) {
            Ok(TaskAnswer::Done(text)) => match parse(&text) {
                Some(m) => {
                    self.said = false;
                    return Some(m);
                }
                None => "task's state answer has no machine line".to_string(),
            },
            Ok(TaskAnswer::Refused(why)) => why,
            Err(TaskClientError::NotRunning { .. }) => "task is not running".to_string(),
            Err(e) => e.to_string(),
        };
        if !self.said {
            eprintln!("z_level_compensation: machine state: {why}; counts stay 0");
            self.said = true;
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_machine_and_g5x() {
        let m = parse("machine=ON\nmode=MANUAL\ng5x-offset=1.5 -2 0 0 0 0 0 0 0\n").unwrap();
        assert_eq!(
            m,
            MachineView {
                on: true,
                g5x: (1.5, -2.0)
            }
        );
        let m = parse("machine=OFF\n").unwrap();
        assert!(!m.on);
        assert_eq!(parse("mode=MDI\n"), None);
    }
}
