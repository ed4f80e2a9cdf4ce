//! Running a program's steps on a machine: queueing them through the
//! motion command channel as fast as the queue takes them, showing
//! progress, and obeying the operator's keys (pause, resume, step,
//! abort) and M0/M1 stops.

use std::io::{IsTerminal, Read, Write};
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::mpsc::{channel, Receiver};
use std::sync::Arc;
use std::time::{Duration, Instant};

use motion::command::{Command, Reject};
use motion::{MotionClient, MotionStatus};
use nix::sys::termios::{self, LocalFlags, SetArg, SpecialCharacterIndices, Termios};

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
    saved: Option<Termios>,
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

    /// The next key pressed, if any.
    pub fn next(&self) -> Option<Key> {
        self.rx.try_recv().ok()
    }
}

impl Drop for Keys {
    fn drop(&mut self) {
        if let Some(t) = &self.saved {
            let _ = termios::tcsetattr(std::io::stdin(), SetArg::TCSANOW, t);
        }
    }
}

/// Puts the terminal on standard input in non-canonical mode without
/// echo (keys arrive one by one); returns the settings to restore.
fn raw_mode() -> Option<Termios> {
    let stdin = std::io::stdin();
    let saved = termios::tcgetattr(&stdin).ok()?;
    let mut t = saved.clone();
    t.local_flags &= !(LocalFlags::ICANON | LocalFlags::ECHO);
    t.control_chars[SpecialCharacterIndices::VMIN as usize] = 1;
    t.control_chars[SpecialCharacterIndices::VTIME as usize] = 0;
    termios::tcsetattr(&stdin, SetArg::TCSANOW, &t).ok()?;
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
    let mut r = Runner {
        client,
        file,
        steps,
        opts,
        next: 0,
        held: None,
        aborting: false,
        started: None,
        preloading: opts.preload,
    };
    if r.preloading {
        if let Err(rj) = r.client.send(Command::Pause) {
            return Outcome::Failed(format!("pause to preload: {}", rj.reason));
        }
    }
    let mut last_shown = Instant::now() - Duration::from_secs(1);
    loop {
        // Preloading ends when nothing more can be queued before starting.
        if r.blocked() {
            if let Err(outcome) = r.end_preload() {
                return outcome;
            }
        }
        let status = match r.client.status() {
            Ok(s) => s,
            Err(e) => return Outcome::Failed(format!("status: {e}")),
        };
        let done = status.traj.depth == 0 && status.in_position;
        if opts.progress && last_shown.elapsed() > Duration::from_millis(100) {
            show(&status, lines, r.held.is_some());
            last_shown = Instant::now();
        }
        // Keys first: an abort wins over everything.
        let key = if stop.load(Relaxed) {
            Some(Key::Abort)
        } else {
            keys.next()
        };
        if let Some(k) = key {
            r.key(k);
        }
        if r.aborting {
            if done {
                finish_line(opts.progress);
                return Outcome::Aborted {
                    line: status.traj.exec_id,
                };
            }
            std::thread::sleep(Duration::from_millis(2));
            continue;
        }
        match r.advance(done) {
            ControlFlow::Break(outcome) => return outcome,
            ControlFlow::Continue(true) => {}
            ControlFlow::Continue(false) => std::thread::sleep(Duration::from_millis(2)),
        }
    }
}

/// A run's way through its steps.
struct Runner<'a> {
    client: &'a mut MotionClient,
    file: &'a str,
    steps: &'a [Step],
    opts: RunOptions,
    /// The next step to send.
    next: usize,
    /// Where an M0 (or M1) holds the run until resumed.
    held: Option<Loc>,
    aborting: bool,
    /// When the first move was queued.
    started: Option<Instant>,
    /// Queueing while paused (see [`RunOptions::preload`]).
    preloading: bool,
}

impl Runner<'_> {
    /// `file:line:column` of `loc`, for messages.
    fn place(&self, loc: Loc) -> String {
        format!("{}:{}:{}", self.file, loc.line, loc.column)
    }

    /// Whether the next step cannot be queued before the run starts.
    fn blocked(&self) -> bool {
        match self.steps.get(self.next) {
            None | Some(Step::Pause(_)) | Some(Step::End(_)) => true,
            Some(Step::OptionalPause(_)) => self.opts.optional_stop,
            Some(Step::Send(..)) => false,
        }
    }

    /// Starts the preloaded queue, if preloading.
    fn end_preload(&mut self) -> Result<(), Outcome> {
        if !self.preloading {
            return Ok(());
        }
        self.preloading = false;
        self.client
            .send(Command::Resume)
            .map(|_| ())
            .map_err(|r| Outcome::Failed(format!("start after preloading: {}", r.reason)))
    }

    /// An operator's key: pause, resume, step or abort.
    fn key(&mut self, k: Key) {
        let cmd = match k {
            Key::Pause => Command::Pause,
            Key::Resume => {
                self.held = None;
                Command::Resume
            }
            Key::Step => Command::Step,
            Key::Abort => {
                self.aborting = true;
                Command::Abort
            }
        };
        if let Err(r) = self.client.send(cmd) {
            eprintln!("\n{}", r.reason);
        }
    }

    /// Sends the next step if it can go now (`done`: the queue is empty and
    /// the machine in position). Continues with whether something was
    /// sent; breaks with the run's outcome.
    fn advance(&mut self, done: bool) -> ControlFlow<Outcome, bool> {
        if self.held.is_some() {
            return ControlFlow::Continue(false);
        }
        match self.steps.get(self.next) {
            Some(Step::Send(cmd, loc)) => match self.client.send(*cmd) {
                Ok(_) => {
                    self.started.get_or_insert_with(Instant::now);
                    self.next += 1;
                    return ControlFlow::Continue(true);
                }
                Err(r) if matches!(r.reason, Reject::QueueFull { .. }) => {
                    if let Err(outcome) = self.end_preload() {
                        return ControlFlow::Break(outcome);
                    }
                }
                Err(r) => {
                    let _ = self.client.send(Command::Abort);
                    finish_line(self.opts.progress);
                    return ControlFlow::Break(Outcome::Failed(format!(
                        "{}: {}",
                        self.place(*loc),
                        r.reason
                    )));
                }
            },
            Some(Step::Pause(loc)) | Some(Step::OptionalPause(loc)) => {
                let optional = matches!(self.steps[self.next], Step::OptionalPause(_));
                if optional && !self.opts.optional_stop {
                    self.next += 1;
                } else if done {
                    finish_line(self.opts.progress);
                    eprintln!(
                        "{}: {} pause: press r to resume",
                        self.place(*loc),
                        if optional { "M1" } else { "M0" }
                    );
                    self.held = Some(*loc);
                    self.next += 1;
                }
            }
            Some(Step::End(_)) => self.next = self.steps.len(),
            None if done => {
                finish_line(self.opts.progress);
                return ControlFlow::Break(Outcome::Done {
                    seconds: self.started.map_or(0.0, |t| t.elapsed().as_secs_f64()),
                });
            }
            None => {}
        }
        ControlFlow::Continue(false)
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
