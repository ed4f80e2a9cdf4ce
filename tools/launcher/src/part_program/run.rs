//! Running a program's steps on a machine: queueing them through the
//! motion command channel as fast as the queue takes them, showing
//! progress, and obeying the operator's keys (pause, resume, step,
//! abort) and M0/M1 stops.

use std::io::{IsTerminal, Read, Write};
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::mpsc::{channel, Receiver};
use std::sync::Arc;
use std::time::{Duration, Instant};

use motion::command::{Command, Reject};
use motion::{MotionClient, MotionStatus};

use super::interp::Step;
use super::Loc;

/// What the operator asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// Slow down and stop along the path.
    Pause,
    /// Carry on.
    Resume,
    /// Run to the end of the current line, then pause.
    Step,
    /// Stop along the path and forget the rest.
    Abort,
}

impl Key {
    /// The key of a typed character (p r s a, or q for abort).
    pub fn from_char(c: char) -> Option<Key> {
        match c.to_ascii_lowercase() {
            'p' | ' ' => Some(Key::Pause),
            'r' | 'c' => Some(Key::Resume),
            's' => Some(Key::Step),
            'a' | 'q' => Some(Key::Abort),
            _ => None,
        }
    }
}

/// How the run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Every step ran.
    Done {
        /// Time from the first move queued to the last one finished.
        seconds: f64,
    },
    /// The operator (or Ctrl-C) aborted at this motion id.
    Aborted {
        /// The motion id executing when it stopped.
        line: i32,
    },
    /// The controller refused a step, or could not be reached.
    Failed(String),
}

/// Options of a run.
#[derive(Debug, Clone, Copy)]
pub struct RunOptions {
    /// M1 stops too.
    pub optional_stop: bool,
    /// Show a progress line (else only the outcome).
    pub progress: bool,
    /// Queue the program (up to the queue's size or the first M0/M1)
    /// while paused, then start it: the motion then does not depend on
    /// how fast the moves arrive (reproducible runs).
    pub preload: bool,
}

/// Reads the operator's keys from standard input in a thread: single
/// keys when it is a terminal (put in non-canonical mode for the run and
/// restored after), else one per line. Ends quietly at end of input.
pub struct Keys {
    rx: Receiver<Key>,
    saved: Option<libc::termios>,
}

impl Keys {
    /// Starts reading.
    pub fn start() -> Keys {
        let stdin = std::io::stdin();
        let saved = if stdin.is_terminal() {
            raw_mode()
        } else {
            None
        };
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let mut byte = [0u8; 1];
            let mut input = std::io::stdin().lock();
            while let Ok(1) = input.read(&mut byte) {
                if let Some(k) = Key::from_char(byte[0] as char) {
                    if tx.send(k).is_err() {
                        return;
                    }
                }
            }
        });
        Keys { rx, saved }
    }

    /// Keys that will never come (for runs without a keyboard).
    pub fn none() -> Keys {
        let (_tx, rx) = channel();
        Keys { rx, saved: None }
    }

    fn next(&self) -> Option<Key> {
        self.rx.try_recv().ok()
    }
}

impl Drop for Keys {
    fn drop(&mut self) {
        if let Some(t) = self.saved {
            // SAFETY: restores the terminal settings read by `raw_mode`
            // on standard input, a valid descriptor for the process's life.
            unsafe {
                libc::tcsetattr(libc::STDIN_FILENO, libc::TCSANOW, &t);
            }
        }
    }
}

/// Puts the terminal on standard input in non-canonical mode without
/// echo (keys arrive one by one); returns the settings to restore.
fn raw_mode() -> Option<libc::termios> {
    // SAFETY: termios is plain data; tcgetattr fills it or fails.
    let mut t: libc::termios = unsafe { std::mem::zeroed() };
    // SAFETY: standard input is a valid descriptor; `t` is writable.
    if unsafe { libc::tcgetattr(libc::STDIN_FILENO, &mut t) } != 0 {
        return None;
    }
    let saved = t;
    t.c_lflag &= !(libc::ICANON | libc::ECHO);
    t.c_cc[libc::VMIN] = 1;
    t.c_cc[libc::VTIME] = 0;
    // SAFETY: as above, with settings derived from the current ones.
    if unsafe { libc::tcsetattr(libc::STDIN_FILENO, libc::TCSANOW, &t) } != 0 {
        return None;
    }
    Some(saved)
}

/// Runs `steps` (from `file`, `lines` lines long) on the machine behind
/// `client`, which must be enabled and in coordinated mode. `stop` (set
/// by Ctrl-C) aborts like the abort key.
pub fn run(
    client: &mut MotionClient,
    file: &str,
    lines: usize,
    steps: &[Step],
    opts: RunOptions,
    keys: &Keys,
    stop: &Arc<AtomicBool>,
) -> Outcome {
    let mut next = 0;
    let mut held: Option<Loc> = None;
    let mut aborting = false;
    let mut started: Option<Instant> = None;
    let mut last_shown = Instant::now() - Duration::from_secs(1);
    let place = |loc: Loc| format!("{file}:{}:{}", loc.line, loc.column);
    let mut preloading = opts.preload;
    if preloading {
        if let Err(r) = client.send(Command::Pause) {
            return Outcome::Failed(format!("pause to preload: {}", r.reason));
        }
    }
    loop {
        // Preloading ends when nothing more can be queued before starting.
        let blocked = match steps.get(next) {
            None | Some(Step::Pause(_)) | Some(Step::End(_)) => true,
            Some(Step::OptionalPause(_)) => opts.optional_stop,
            Some(Step::Send(..)) => false,
        };
        if preloading && blocked {
            preloading = false;
            if let Err(r) = client.send(Command::Resume) {
                return Outcome::Failed(format!("start after preloading: {}", r.reason));
            }
        }
        let status = match client.status() {
            Ok(s) => s,
            Err(e) => return Outcome::Failed(format!("status: {e}")),
        };
        let done = status.traj.depth == 0 && status.in_position;
        if opts.progress && last_shown.elapsed() > Duration::from_millis(100) {
            show(&status, lines, held.is_some());
            last_shown = Instant::now();
        }
        // Keys first: an abort wins over everything.
        let key = if stop.load(Relaxed) {
            Some(Key::Abort)
        } else {
            keys.next()
        };
        if let Some(k) = key {
            let cmd = match k {
                Key::Pause => Some(Command::Pause),
                Key::Resume => {
                    held = None;
                    Some(Command::Resume)
                }
                Key::Step => Some(Command::Step),
                Key::Abort => {
                    aborting = true;
                    Some(Command::Abort)
                }
            };
            if let Some(cmd) = cmd {
                if let Err(r) = client.send(cmd) {
                    eprintln!("\n{}", r.reason);
                }
            }
        }
        if aborting {
            if done {
                finish_line(opts.progress);
                return Outcome::Aborted {
                    line: status.traj.exec_id,
                };
            }
            std::thread::sleep(Duration::from_millis(2));
            continue;
        }
        let mut busy = false;
        if held.is_none() {
            match steps.get(next) {
                Some(Step::Send(cmd, loc)) => match client.send(*cmd) {
                    Ok(_) => {
                        started.get_or_insert_with(Instant::now);
                        next += 1;
                        busy = true;
                    }
                    Err(r) if matches!(r.reason, Reject::QueueFull { .. }) => {
                        if preloading {
                            preloading = false;
                            if let Err(r) = client.send(Command::Resume) {
                                return Outcome::Failed(format!(
                                    "start after preloading: {}",
                                    r.reason
                                ));
                            }
                        }
                    }
                    Err(r) => {
                        let _ = client.send(Command::Abort);
                        finish_line(opts.progress);
                        return Outcome::Failed(format!("{}: {}", place(*loc), r.reason));
                    }
                },
                Some(Step::Pause(loc)) | Some(Step::OptionalPause(loc)) => {
                    let optional = matches!(steps[next], Step::OptionalPause(_));
                    if optional && !opts.optional_stop {
                        next += 1;
                    } else if done {
                        finish_line(opts.progress);
                        eprintln!(
                            "{}: {} pause: press r to resume",
                            place(*loc),
                            if optional { "M1" } else { "M0" }
                        );
                        held = Some(*loc);
                        next += 1;
                    }
                }
                Some(Step::End(_)) => next = steps.len(),
                None => {
                    if done {
                        finish_line(opts.progress);
                        return Outcome::Done {
                            seconds: started.map_or(0.0, |t| t.elapsed().as_secs_f64()),
                        };
                    }
                }
            }
        }
        if !busy {
            std::thread::sleep(Duration::from_millis(2));
        }
    }
}

/// The progress line, redrawn in place.
fn show(s: &MotionStatus, lines: usize, held: bool) {
    let t = &s.traj;
    let pct = if lines > 0 {
        (t.exec_id.max(0) as f64 / lines as f64 * 100.0).min(100.0)
    } else {
        0.0
    };
    let state = if held {
        " M0 pause (r resumes)"
    } else if t.stepping {
        " stepping"
    } else if t.paused {
        " paused (r resumes, s steps)"
    } else if t.aborting {
        " aborting"
    } else {
        ""
    };
    eprint!(
        "\rline {:>5}/{lines} {pct:5.1}%  speed {:9.3}/s  queued {:4}{state}\x1b[K",
        t.exec_id, t.current_vel, t.depth
    );
    let _ = std::io::stderr().flush();
}

fn finish_line(progress: bool) {
    if progress {
        eprintln!();
    }
}
