//! `gcode-run` as a client of task: when a machine started by
//! `linuxcnc` runs on the instance, the program runs through task (mode
//! AUTO, open, run), the operator's keys become task's pause, resume,
//! step and abort, and the outcome is task's. Task then stays the one
//! authority over the machine.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::time::Duration;

use hal_launcher::part_program::run::{Key, Keys};
use hal_launcher::{request, TaskAnswer, TaskClientError};

use crate::ToolsError;

/// How a run through task ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TaskRun {
    /// Task finished the program; its words.
    Done(String),
    /// Aborted (a key, Ctrl-C, or someone else's abort).
    Aborted(String),
    /// Task refused to start it, or the run failed; its words.
    Failed(String),
}

/// Whether a task (a `linuxcnc` launcher) serves `instance`.
pub fn task_runs(instance: &str) -> bool {
    !matches!(
        request(instance, &["status".to_string()], Duration::from_secs(2)),
        Err(TaskClientError::NotRunning { .. })
    )
}

/// Task's answer to `words`: its words when done, its refusal or the
/// client's failure otherwise.
fn ask(instance: &str, words: &[&str]) -> Result<String, ToolsError> {
    let words: Vec<String> = words.iter().map(|w| w.to_string()).collect();
    match request(instance, &words, Duration::from_secs(30))? {
        TaskAnswer::Done(text) => Ok(text),
        TaskAnswer::Refused(why) => Err(ToolsError::TaskRefused(why)),
    }
}

/// The value of `key: value` in task's status.
fn status_value<'a>(status: &'a str, key: &str) -> Option<&'a str> {
    status
        .lines()
        .find_map(|l| l.strip_prefix(key)?.strip_prefix(": "))
}

/// Runs `file` through the task of `instance`; `stop` (Ctrl-C) aborts.
pub fn run_through_task(
    instance: &str,
    file: &Path,
    keys: &Keys,
    stop: &AtomicBool,
    progress: bool,
) -> TaskRun {
    let path = match std::fs::canonicalize(file) {
        Ok(p) => p,
        Err(e) => return TaskRun::Failed(format!("{}: {e}", file.display())),
    };
    let path = path.to_string_lossy().into_owned();
    for words in [&["mode", "auto"][..], &["open", &path], &["run"]] {
        if let Err(why) = ask(instance, words) {
            return TaskRun::Failed(format!("task-cmd {}: {why}", words.join(" ")));
        }
    }
    loop {
        let key = if stop.load(Relaxed) {
            Some(Key::Abort)
        } else {
            keys.next()
        };
        if let Some(k) = key {
            let word = match k {
                Key::Pause => "pause",
                Key::Resume => "resume",
                Key::Step => "step",
                Key::Abort => "abort",
            };
            if let Err(why) = ask(instance, &[word]) {
                eprintln!("\ngcode-run: {word}: {why}");
            }
        }
        let status = match ask(instance, &["status"]) {
            Ok(s) => s,
            Err(why) => return TaskRun::Failed(why.to_string()),
        };
        if status_value(&status, "interp") == Some("IDLE") {
            if progress {
                eprintln!();
            }
            return match ask(instance, &["wait-done"]) {
                Ok(text) => TaskRun::Done(text),
                Err(ToolsError::TaskRefused(why)) if why.ends_with("aborted") => {
                    TaskRun::Aborted(why)
                }
                Err(why) => TaskRun::Failed(why.to_string()),
            };
        }
        if progress {
            eprint!(
                "\rline {:>6}  motion line {:>6}  {}\x1b[K",
                status_value(&status, "current line").unwrap_or("?"),
                status_value(&status, "motion line").unwrap_or("?"),
                status_value(&status, "interp").unwrap_or("?"),
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}
