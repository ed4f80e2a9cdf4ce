//! One connection's state and its answers: hello, the enable password,
//! the per-connection settings, and `get`/`set` turned into task
//! requests. Replies are LinuxCNC's: `NAME VALUE` for a get, `SET NAME
//! ACK` (verbose) or `SET NAME NAK` for a set, `GET NAME NAK` for what
//! cannot be got.

use std::time::Duration;

use super::parse::{parse, tail_after_sub, Request};
use super::stat::Snapshot;
use super::vocab::{help, Entry, Sub};
use crate::error::ToolsError;

/// The server version `hello` announces (LinuxCNC's).
pub const SERVER_VERSION: &str = "1.1";

/// The longest wait for task when the session's timeout is 0 (forever).
const LONGEST_WAIT: Duration = Duration::from_secs(86_400);

/// What answers the requests a session sends on: task, or a stand-in.
pub trait Machine {
    /// Sends one request of `task-cmd`'s words; task's answer text, or
    /// [`ToolsError::TaskRefused`] with its reason.
    fn ask(&mut self, words: &[String], timeout: Duration) -> Result<String, ToolsError>;
}

/// The server's settings, shared by every session.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The name `hello` answers with (`--name`).
    pub name: String,
    /// The password `hello` needs (`--connectpw`).
    pub connect_pw: String,
    /// The password `set enable` needs (`--enablepw`).
    pub enable_pw: String,
    /// The INI file (`-ini`), for `get inifile`.
    pub ini_file: String,
    /// `[EMC]DEBUG`, for `get debug`.
    pub debug: i64,
    /// `[KINS]KINEMATICS` names identity kinematics (trivkins).
    pub identity_kins: bool,
    /// Where a relative `set open` file is taken from (`--path`).
    pub open_dir: Option<std::path::PathBuf>,
    /// Whether each configured joint is angular (`[JOINT_n]TYPE`).
    pub angular_joints: Vec<bool>,
}

/// What the server does after a line.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum After {
    /// Read the next line.
    Continue,
    /// Close this connection (`quit`).
    Close,
    /// Close it and end the server, and with it the machine (`shutdown`).
    Shutdown,
}

/// One connection.
#[derive(Debug)]
pub struct Session<'s> {
    cfg: &'s Settings,
    hello: bool,
    enabled: bool,
    echo: bool,
    verbose: bool,
    wait_done: bool,
    update_auto: bool,
    timeout: f64,
    comm_prot: String,
    linear_conv: &'static str,
    angular_conv: &'static str,
    debug: i64,
    /// The newest task message number seen.
    seq: u64,
    error: Option<String>,
    operator_text: Option<String>,
    operator_display: Option<String>,
    /// The text of the last value or error message a command produced.
    /// LinuxCNC's server keeps it in one reply buffer per connection and
    /// sends that buffer again, unchanged, for a `get` of `wait`, `probe`
    /// or `probe_clear`, which write nothing into it.
    reply_buffer: String,
}

/// `on` or `off` (any case) as a flag.
fn on_off(word: Option<&&str>) -> Option<bool> {
    match word?.to_ascii_lowercase().as_str() {
        "on" => Some(true),
        "off" => Some(false),
        _ => None,
    }
}

fn yes(b: bool, on: &str, off: &str) -> String {
    if b { on } else { off }.to_string()
}

fn words(w: &[&str]) -> Vec<String> {
    w.iter().map(|s| (*s).to_string()).collect()
}

/// LinuxCNC's name for the reply: the subcommand in capitals.
fn upper(e: &Entry) -> String {
    e.name.to_ascii_uppercase()
}

/// A word a client sent, bounded and in capitals, for a NAK.
fn shown(word: &str) -> String {
    word.chars()
        .take(64)
        .collect::<String>()
        .to_ascii_uppercase()
}

impl<'s> Session<'s> {
    /// A new connection: echo on, verbose off, not enabled, no hello.
    pub fn new(cfg: &'s Settings) -> Session<'s> {
        Session {
            cfg,
            hello: false,
            enabled: false,
            echo: true,
            verbose: false,
            wait_done: false,
            update_auto: true,
            timeout: 0.0,
            comm_prot: SERVER_VERSION.to_string(),
            linear_conv: "AUTO",
            angular_conv: "AUTO",
            debug: cfg.debug,
            seq: 0,
            error: None,
            operator_text: None,
            operator_display: None,
            reply_buffer: String::new(),
        }
    }

    fn wait(&self) -> Duration {
        if self.timeout > 0.0 {
            Duration::try_from_secs_f64(self.timeout).unwrap_or(LONGEST_WAIT)
        } else {
            LONGEST_WAIT
        }
    }

    /// Answers one request line into `out` (lines without their ends).
    pub fn handle(&mut self, line: &str, m: &mut dyn Machine, out: &mut Vec<String>) -> After {
        match parse(line) {
            Request::Empty => {}
            Request::Hello(words) => {
                let ok = words.is_some_and(|[pw, _, _]| pw == self.cfg.connect_pw);
                if let (true, Some([_, _, version])) = (ok, words) {
                    self.hello = true;
                    self.comm_prot = version.chars().take(16).collect();
                    // Only messages from now on are this session's.
                    if let Ok(text) = m.ask(&words_of(&["messages", "0"]), self.wait()) {
                        self.seq = newest(&text);
                    }
                    out.push(format!("HELLO ACK {} {SERVER_VERSION}", self.cfg.name));
                } else {
                    out.push("HELLO NAK".to_string());
                }
            }
            // These write no value: the reply buffer goes out as it is.
            Request::Get(Ok(e), _)
                if self.hello && matches!(e.sub, Sub::Wait | Sub::Probe | Sub::ProbeClear) =>
            {
                out.push(self.reply_buffer.clone());
            }
            Request::Get(sub, args) => match sub {
                Ok(e) if self.hello => match self.get(e, &args, m) {
                    Some(lines) => {
                        if let Some(last) = lines.last() {
                            self.reply_buffer = buffered(last);
                        }
                        out.extend(lines);
                    }
                    None => out.push(format!("GET {} NAK", upper(e))),
                },
                Ok(e) => out.push(format!("GET {} NAK", upper(e))),
                Err(w) => out.push(format!("GET {} NAK", shown(w))),
            },
            Request::Set(sub, args) => match sub {
                Ok(e) if self.hello => {
                    let mdi = tail_after_sub(line);
                    match self.set(e, &args, mdi, m) {
                        Ok(()) if self.verbose => out.push(format!("SET {} ACK", upper(e))),
                        Ok(()) => {}
                        Err(Some(text)) => {
                            self.reply_buffer = buffered(&text);
                            out.push(text);
                        }
                        Err(None) => out.push(format!("SET {} NAK", upper(e))),
                    }
                }
                Ok(e) => out.push(format!("SET {} NAK", upper(e))),
                Err(w) => out.push(format!("SET {} NAK", shown(w))),
            },
            Request::Quit => return After::Close,
            Request::Shutdown => {
                if self.hello && self.enabled {
                    return After::Shutdown;
                }
                out.push("SHUTDOWN NAK".to_string());
            }
            Request::Help(topic) => out.extend(help(topic)),
            Request::Unknown(w) => out.push(format!("{} NAK", shown(w))),
        }
        After::Continue
    }

    /// Reads task's messages that arrived since the last look.
    fn poll_messages(&mut self, m: &mut dyn Machine) {
        let Ok(text) = m.ask(&words_of(&["messages", &self.seq.to_string()]), self.wait()) else {
            return;
        };
        self.seq = newest(&text);
        for l in text.lines().skip(1) {
            let mut it = l.splitn(3, ' ');
            let (_, kind, msg) = (it.next(), it.next(), it.next().unwrap_or(""));
            let slot = match kind {
                Some("1" | "11") => &mut self.error,
                Some("2" | "12") => &mut self.operator_text,
                Some("3" | "13") => &mut self.operator_display,
                _ => continue,
            };
            *slot = Some(msg.to_string());
        }
    }

    fn message(slot: &mut Option<String>) -> String {
        slot.take().unwrap_or_else(|| "OK".to_string())
    }

    /// The reply lines of `get`; `None` for what cannot be got.
    fn get(&mut self, e: &Entry, args: &[&str], m: &mut dyn Machine) -> Option<Vec<String>> {
        let name = match e.sub {
            // LinuxCNC answers both under the one name.
            Sub::ProgramLinearUnits => "PROGRAM_UNITS".to_string(),
            _ => upper(e),
        };
        if let Some(v) = self.get_local(e.sub) {
            return Some(vec![format!("{name} {v}")]);
        }
        match e.sub {
            Sub::Error | Sub::OperatorText | Sub::OperatorDisplay => {
                self.poll_messages(m);
                let slot = match e.sub {
                    Sub::Error => &mut self.error,
                    Sub::OperatorText => &mut self.operator_text,
                    _ => &mut self.operator_display,
                };
                return Some(vec![format!("{name} {}", Self::message(slot))]);
            }
            Sub::Update => {
                return Some(vec![format!(
                    "GET_UPDATE {}",
                    yes(self.update_auto, "AUTO", "NONE")
                )])
            }
            _ => {}
        }
        let s = Snapshot::parse(&m.ask(&words_of(&["stat"]), self.wait()).ok()?);
        if matches!(e.sub, Sub::Spindle | Sub::Brake) {
            return self.get_spindles(e, args, &s);
        }
        let v = super::reply::value(e.sub, args, &s, self)?;
        Some(vec![format!("{name} {v}")])
    }

    /// Whether joint `j` is configured as angular (`None`: not configured).
    pub fn joint_is_angular(&self, j: usize) -> Option<bool> {
        self.cfg.angular_joints.get(j).copied()
    }

    /// The display's linear units conversion (`AUTO`, `INCH`, `MM`, `CM`).
    pub fn linear_conversion(&self) -> &'static str {
        self.linear_conv
    }

    /// The display's angular units conversion.
    pub fn angular_conversion(&self) -> &'static str {
        self.angular_conv
    }

    /// Values this session holds itself.
    fn get_local(&self, sub: Sub) -> Option<String> {
        Some(match sub {
            Sub::Echo => yes(self.echo, "ON", "OFF"),
            Sub::Verbose => yes(self.verbose, "ON", "OFF"),
            Sub::Enable => yes(self.enabled, "ON", "OFF"),
            Sub::SetWait => yes(self.wait_done, "DONE", "RECEIVED"),
            Sub::Timeout | Sub::SetTimeout => format!("{:.6}", self.timeout),
            Sub::CommMode => "ASCII".to_string(),
            Sub::CommProt => self.comm_prot.clone(),
            Sub::Plat => "Linux".to_string(),
            Sub::Inifile => self.cfg.ini_file.clone(),
            Sub::Debug => self.debug.to_string(),
            Sub::LinearUnitConversion => self.linear_conv.to_string(),
            Sub::AngularUnitConversion => self.angular_conv.to_string(),
            Sub::KinematicsType if self.cfg.identity_kins => "1".to_string(),
            Sub::Time => {
                let t = std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0.0, |d| d.as_secs_f64());
                format!("{t:.6}")
            }
            _ => return None,
        })
    }

    /// `get spindle|brake [N]`: one line per spindle asked about.
    fn get_spindles(&mut self, e: &Entry, args: &[&str], s: &Snapshot) -> Option<Vec<String>> {
        let count = s.int("spindles").unwrap_or(1).max(0);
        let which = match args.first() {
            None => -1,
            Some(w) => w.parse::<i64>().ok()?,
        };
        if which < -1 || which >= count {
            return Some(vec![format!(
                "error: invalid spindle: {which} (valid: -1 - {count})"
            )]);
        }
        let range = if which == -1 {
            0..count
        } else {
            which..which + 1
        };
        Some(
            range
                .map(|n| {
                    if e.sub == Sub::Brake {
                        format!(
                            "BRAKE {}",
                            yes(s.flag(&format!("spindle.{n}.brake")), "ON", "OFF")
                        )
                    } else {
                        let dir = match s.int(&format!("spindle.{n}.direction")).unwrap_or(0) {
                            d if d > 0 => "FORWARD",
                            d if d < 0 => "REVERSE",
                            _ => "OFF",
                        };
                        format!("SPINDLE {n} {dir}")
                    }
                })
                .collect(),
        )
    }

    /// Settings this session holds itself; `None` when `sub` is not one.
    fn set_local(&mut self, sub: Sub, args: &[&str]) -> Option<Result<(), Option<String>>> {
        let first = args.first();
        let lower = first.map(|w| w.to_ascii_lowercase());
        let bad = Err(None);
        Some(match (sub, lower.as_deref()) {
            (Sub::Echo, _) => on_off(first).map(|b| self.echo = b).ok_or(None),
            (Sub::Verbose, _) => on_off(first).map(|b| self.verbose = b).ok_or(None),
            (Sub::Enable, Some("off")) => {
                self.enabled = false;
                Ok(())
            }
            (Sub::Enable, Some(_)) if first.is_some_and(|p| *p == self.cfg.enable_pw) => {
                self.enabled = true;
                Ok(())
            }
            (Sub::SetWait, Some("done")) => {
                self.wait_done = true;
                Ok(())
            }
            (Sub::SetWait, Some("received")) => {
                self.wait_done = false;
                Ok(())
            }
            (Sub::Update, Some(w @ ("auto" | "none"))) => {
                self.update_auto = w == "auto";
                Ok(())
            }
            (Sub::Timeout | Sub::SetTimeout, Some(w)) => match w.parse::<f64>() {
                Ok(t) if t.is_finite() => {
                    self.timeout = t.max(0.0);
                    Ok(())
                }
                _ => bad,
            },
            (Sub::CommMode, Some("ascii")) => Ok(()),
            (Sub::CommProt, Some(w)) => match w.parse::<f64>() {
                Ok(v) if v > 0.0 && v <= 1.1 => {
                    self.comm_prot = w.to_string();
                    Ok(())
                }
                _ => bad,
            },
            (Sub::Debug, Some(w)) => w.parse().map(|d| self.debug = d).map_err(|_| None),
            (Sub::LinearUnitConversion, Some(w)) => {
                self.linear_conv = match w {
                    "inch" => "INCH",
                    "mm" => "MM",
                    "cm" => "CM",
                    "auto" => "AUTO",
                    _ => return Some(bad),
                };
                Ok(())
            }
            (Sub::AngularUnitConversion, Some(w)) => {
                self.angular_conv = match w {
                    "deg" => "DEG",
                    "rad" => "RAD",
                    "grad" => "GRAD",
                    "auto" => "AUTO",
                    _ => return Some(bad),
                };
                Ok(())
            }
            (
                Sub::Enable
                | Sub::SetWait
                | Sub::Update
                | Sub::Timeout
                | Sub::SetTimeout
                | Sub::CommMode
                | Sub::CommProt
                | Sub::Debug
                | Sub::LinearUnitConversion
                | Sub::AngularUnitConversion,
                _,
            ) => bad,
            _ => return None,
        })
    }

    /// `set`: Ok, or the reply that replaces the NAK (`None`: the NAK).
    fn set(
        &mut self,
        e: &Entry,
        args: &[&str],
        mdi: &str,
        m: &mut dyn Machine,
    ) -> Result<(), Option<String>> {
        if let Some(r) = self.set_local(e.sub, args) {
            return r;
        }
        if !self.enabled {
            return Err(None);
        }
        if matches!(e.sub, Sub::Spindle | Sub::Brake) {
            return self.set_spindles(e.sub, args, m);
        }
        let joined;
        let open_args: Vec<&str>;
        let args = match (e.sub, args, &self.cfg.open_dir) {
            (Sub::Open, [f], Some(dir)) => {
                joined = dir.join(f).display().to_string();
                open_args = vec![joined.as_str()];
                &open_args[..]
            }
            _ => args,
        };
        if e.sub == Sub::Home && self.home_of_missing_joint(args, m)? {
            return Ok(());
        }
        let requests = super::reply::requests(e.sub, args, mdi, self.wait_done).ok_or(None)?;
        for r in requests {
            // A refusal is the NAK (LinuxCNC's `get error` stays OK after
            // one); what task reports on its error channel is `get error`'s.
            m.ask(&r, self.wait()).map_err(|_| None)?;
        }
        if self.wait_done && e.sub == Sub::Home {
            self.wait_homing(m);
        }
        Ok(())
    }

    /// `set spindle|brake WORD [N]` (N -1 or none: every spindle).
    fn set_spindles(
        &mut self,
        sub: Sub,
        args: &[&str],
        m: &mut dyn Machine,
    ) -> Result<(), Option<String>> {
        let word = args.first().map(|w| w.to_ascii_lowercase()).ok_or(None)?;
        let s = Snapshot::parse(&m.ask(&words_of(&["stat"]), self.wait()).map_err(|_| None)?);
        let count = s.int("spindles").unwrap_or(1).max(0);
        let which = match args.get(1) {
            None => -1,
            Some(w) => w.parse::<i64>().map_err(|_| None)?,
        };
        if which < -1 || which >= count {
            return Err(Some(format!(
                "error: invalid spindle: {which} (valid: -1 - {count})"
            )));
        }
        let action: &[&str] = match (sub, word.as_str()) {
            (Sub::Brake, "on") => &["brake", "on"],
            (Sub::Brake, "off") => &["brake", "off"],
            (Sub::Spindle, w @ ("forward" | "reverse" | "off" | "increase" | "decrease")) => {
                &[match w {
                    "forward" => "forward",
                    "reverse" => "reverse",
                    "off" => "off",
                    "increase" => "increase",
                    _ => "decrease",
                }]
            }
            // Our increase and decrease are one step each: nothing to end.
            (Sub::Spindle, "constant") => return Ok(()),
            _ => return Err(None),
        };
        let range = if which == -1 {
            0..count
        } else {
            which..which + 1
        };
        for n in range {
            let mut w = vec!["spindle".to_string(), n.to_string()];
            w.extend(words(action));
            m.ask(&w, self.wait()).map_err(|_| None)?;
        }
        Ok(())
    }
}

/// The most joints LinuxCNC's motion has room for; `set home` takes a
/// joint number up to this one.
const MAX_JOINTS: i64 = 16;

impl Session<'_> {
    /// Whether `set home N` names a joint the machine does not have but
    /// LinuxCNC's motion has room for (up to [`MAX_JOINTS`]): LinuxCNC
    /// takes that request and homes nothing, so it is acknowledged
    /// without a request to task. A number past that, or not a number,
    /// is the NAK.
    fn home_of_missing_joint(
        &mut self,
        args: &[&str],
        m: &mut dyn Machine,
    ) -> Result<bool, Option<String>> {
        let joint = args
            .first()
            .and_then(|w| w.parse::<i64>().ok())
            .filter(|j| (-1..=MAX_JOINTS).contains(j))
            .ok_or(None)?;
        let s = Snapshot::parse(&m.ask(&words_of(&["stat"]), self.wait()).map_err(|_| None)?);
        Ok(s.int("joints").is_some_and(|n| joint >= n))
    }
}

/// The longest `set home` waits for the homing to end (with set_wait done).
const HOMING_WAIT: Duration = Duration::from_secs(120);

impl Session<'_> {
    /// With set_wait done, a home is done when no joint homes any more
    /// and motion is in position.
    fn wait_homing(&mut self, m: &mut dyn Machine) {
        let end = std::time::Instant::now() + self.wait().min(HOMING_WAIT);
        while std::time::Instant::now() < end {
            let Ok(text) = m.ask(&words_of(&["stat"]), self.wait()) else {
                return;
            };
            let s = Snapshot::parse(&text);
            let joints = s.int("joints").unwrap_or(0);
            let homing = (0..joints).any(|j| s.flag(&format!("joint.{j}.homing")));
            if !homing && s.flag("inpos") {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

/// What a reply line leaves in the reply buffer: a custom error's
/// message without its `error: ` lead, any other line whole.
fn buffered(line: &str) -> String {
    line.strip_prefix(ERROR_LEAD).unwrap_or(line).to_string()
}

/// The lead of a custom error reply (`error: invalid spindle: ...`).
const ERROR_LEAD: &str = "error: ";

fn words_of(w: &[&str]) -> Vec<String> {
    words(w)
}

/// The newest message number in task's `messages` answer.
fn newest(text: &str) -> u64 {
    text.lines()
        .next()
        .and_then(|l| l.trim().parse().ok())
        .unwrap_or(0)
}
