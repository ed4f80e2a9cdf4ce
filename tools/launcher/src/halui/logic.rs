//! halui's decisions, apart from its pins: which button edges mean which
//! request, the override counters, and task's `state` answer read back.
//! Buttons act on edges, as LinuxCNC's halui: a rising edge asks once
//! (holding a button does not repeat it); a jog button also stops its
//! jog on the falling edge.

use crate::error::LaunchError;
use crate::task::Mode;
use crate::task_manual::Jogged;

use super::panel_state::{parse_panel, PanelState};
use super::selection::OnSelected;

/// What a button edge asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    /// `halui.machine.on`.
    MachineOn,
    /// `halui.machine.off`.
    MachineOff,
    /// `halui.estop.activate`.
    EstopActivate,
    /// `halui.estop.reset`.
    EstopReset,
    /// `halui.mode.manual`, `.auto`, `.mdi`.
    Mode(Mode),
    /// `halui.program.run`.
    Run,
    /// `halui.program.pause`.
    Pause,
    /// `halui.program.resume`.
    Resume,
    /// `halui.program.step`.
    Step,
    /// `halui.program.stop` and `halui.abort`.
    Abort,
    /// `halui.mist.on`/`.off`.
    Mist(bool),
    /// `halui.flood.on`/`.off`.
    Flood(bool),
    /// `halui.lube.on`/`.off`.
    Lube(bool),
    /// `halui.home-all`.
    HomeAll,
    /// `halui.joint.N.home`.
    Home(i32),
    /// `halui.joint.N.unhome`.
    Unhome(i32),
    /// `halui.joint.N.plus`/`.minus` (or `halui.axis.L.*`) pressed: jog
    /// at the jog speed, in the direction's sign.
    JogStart(Jogged, f64),
    /// `halui.joint.N.plus`/`.minus` (or `halui.axis.L.*`) released.
    JogStop(Jogged),
    /// `halui.joint.N.increment-plus`/`-minus` (or `halui.axis.L.*`): jog
    /// by the increment.
    JogIncrement(Jogged, f64),
    /// A jog by a signed distance (the selected joint's or axis's
    /// increment).
    JogBy(Jogged, f64),
    /// `halui.mode.teleop` (jogs move world axes) or `halui.mode.joint`
    /// (jogs move joints).
    JogMode {
        /// Teleop rather than joint mode.
        teleop: bool,
    },
    /// `halui.program.optional-stop.on`/`.off`.
    OptionalStop(bool),
    /// `halui.program.block-delete.on`/`.off`.
    BlockDelete(bool),
    /// `halui.joint.N.select`.
    SelectJoint(usize),
    /// `halui.axis.L.select` (the world axis number).
    SelectAxis(usize),
    /// A `halui.joint.selected.*` button.
    SelectedJoint(OnSelected),
    /// A `halui.axis.selected.*` button.
    SelectedAxis(OnSelected),
    /// `halui.mdi-command-NN`.
    Mdi(usize),
    /// An override's `increase` (+1) or `decrease` (-1).
    OverrideStep(Override, f64),
    /// An override's `reset`.
    OverrideReset(Override),
}

/// The overrides halui drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Override {
    /// `halui.feed-override.*`.
    Feed,
    /// `halui.rapid-override.*`.
    Rapid,
    /// `halui.max-velocity.*`.
    MaxVelocity,
}

impl Override {
    /// The pin prefix, as LinuxCNC names it.
    pub fn prefix(self) -> &'static str {
        match self {
            Override::Feed => "feed-override",
            Override::Rapid => "rapid-override",
            Override::MaxVelocity => "max-velocity",
        }
    }

    /// `scale` at start, as LinuxCNC's halui has it: 0.1 for the feed
    /// and rapid overrides, 0 for the maximum velocity.
    pub fn default_scale(self) -> f64 {
        match self {
            Override::Feed | Override::Rapid => 0.1,
            Override::MaxVelocity => 0.0,
        }
    }

    /// The task request that sets it.
    pub fn request(self) -> &'static str {
        self.prefix()
    }
}

/// Rising and falling edges of a set of buttons.
#[derive(Debug, Default)]
pub struct Edges {
    last: Vec<bool>,
}

impl Edges {
    /// The buttons that changed since the last call: (index, new value).
    /// The first call sees no edges: a button held at start-up does not
    /// act.
    pub fn changes(&mut self, now: &[bool]) -> Vec<(usize, bool)> {
        if self.last.len() != now.len() {
            self.last = now.to_vec();
            return Vec::new();
        }
        let out = now
            .iter()
            .zip(&self.last)
            .enumerate()
            .filter(|(_, (n, l))| n != l)
            .map(|(i, (n, _))| (i, *n))
            .collect();
        self.last.copy_from_slice(now);
        out
    }
}

/// The input pins of one override.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OverrideInputs {
    /// `count-enable`.
    pub count_enable: bool,
    /// `counts`.
    pub counts: i32,
    /// `scale`.
    pub scale: f64,
    /// `direct-value`.
    pub direct_value: bool,
}

/// One override's counter: the value its pins ask for.
#[derive(Debug, Clone, Copy, Default)]
pub struct OverrideCounter {
    last_counts: Option<i32>,
}

impl OverrideCounter {
    /// The value the counts ask for, given the value in effect; `None`
    /// when they ask for no change. With `direct-value` the value is
    /// counts × scale; otherwise each count moves it by `scale`. The
    /// first reading only sets the starting count.
    pub fn target(&mut self, inp: &OverrideInputs, current: f64) -> Option<f64> {
        let last = self.last_counts.replace(inp.counts);
        if !inp.count_enable {
            return None;
        }
        if inp.direct_value {
            let want = f64::from(inp.counts) * inp.scale;
            return (want != current).then_some(want);
        }
        let delta = inp.counts.wrapping_sub(last?);
        (delta != 0).then(|| current + f64::from(delta) * inp.scale)
    }
}

/// Task's state as its `state` request answers it.
#[derive(Debug, Clone, PartialEq)]
pub struct TaskState {
    /// `ESTOP`, `OFF` or `ON`.
    pub machine: String,
    /// `MANUAL`, `AUTO` or `MDI`.
    pub mode: String,
    /// `IDLE`, `RUNNING` or `PAUSED`.
    pub program: String,
    /// Mist coolant on.
    pub mist: bool,
    /// Flood coolant on.
    pub flood: bool,
    /// Lube on.
    pub lube: bool,
    /// The tool in the spindle.
    pub tool: i32,
    /// The feed override.
    pub feed_override: f64,
    /// The rapid override.
    pub rapid_override: f64,
    /// The tool-tip speed limit.
    pub max_velocity: f64,
    /// Switches, tool offsets and diameter, relative offsets.
    pub panel: PanelState,
}

impl TaskState {
    /// The value an override has now.
    pub fn override_value(&self, which: Override) -> f64 {
        match which {
            Override::Feed => self.feed_override,
            Override::Rapid => self.rapid_override,
            Override::MaxVelocity => self.max_velocity,
        }
    }

    /// Task's mode.
    pub fn task_mode(&self) -> Option<Mode> {
        match self.mode.as_str() {
            "MANUAL" => Some(Mode::Manual),
            "AUTO" => Some(Mode::Auto),
            "MDI" => Some(Mode::Mdi),
            _ => None,
        }
    }
}

/// Reads task's `state` answer: `key=value` lines, every key of
/// [`TaskState`] present; unknown keys are passed over (a newer task may
/// say more).
pub fn parse_state(text: &str) -> Result<TaskState, LaunchError> {
    let bad = |why: String| LaunchError::TaskState { why };
    let mut fields: Vec<(&str, &str)> = Vec::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let (k, v) = line
            .split_once('=')
            .ok_or_else(|| bad(format!("line {line:?} is not key=value")))?;
        fields.push((k.trim(), v.trim()));
    }
    let get = |key: &str| {
        fields
            .iter()
            .find(|(k, _)| *k == key)
            .map(|(_, v)| *v)
            .ok_or_else(|| bad(format!("no {key}")))
    };
    let number = |key: &str| -> Result<f64, LaunchError> {
        let v = get(key)?;
        v.parse::<f64>()
            .ok()
            .filter(|x| !x.is_nan())
            .ok_or_else(|| bad(format!("{key}={v} is not a number")))
    };
    let flag = |key: &str| -> Result<bool, LaunchError> {
        match get(key)? {
            "0" => Ok(false),
            "1" => Ok(true),
            v => Err(bad(format!("{key}={v} is not 0 or 1"))),
        }
    };
    let word = |key: &str, allowed: &[&str]| -> Result<String, LaunchError> {
        let v = get(key)?;
        if allowed.contains(&v) {
            Ok(v.to_string())
        } else {
            Err(bad(format!(
                "{key}={v} is not one of {}",
                allowed.join(", ")
            )))
        }
    };
    let tool = |key: &str| -> Result<i32, LaunchError> {
        let v = get(key)?;
        v.parse()
            .map_err(|_| bad(format!("{key}={v} is not a tool number")))
    };
    Ok(TaskState {
        machine: word("machine", &["ESTOP", "OFF", "ON"])?,
        mode: word("mode", &["MANUAL", "AUTO", "MDI"])?,
        program: word("program", &["IDLE", "RUNNING", "PAUSED"])?,
        mist: flag("mist")?,
        flood: flag("flood")?,
        lube: flag("lube")?,
        tool: tool("tool")?,
        feed_override: number("feed-override")?,
        rapid_override: number("rapid-override")?,
        max_velocity: number("max-velocity")?,
        panel: parse_panel(&fields)?,
    })
}

/// Fuzz body: task `state` answers through [`parse_state`]; a state read
/// has only the words its keys allow.
pub fn fuzz_state(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    if let Ok(s) = parse_state(&text) {
        assert!(["ESTOP", "OFF", "ON"].contains(&s.machine.as_str()));
        assert!(s.task_mode().is_some());
        assert!(!s.feed_override.is_nan());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const STATE: &str = "machine=ON\nmode=AUTO\nprogram=PAUSED\nmist=0\nflood=1\nlube=0\n\
                         tool=3\nfeed-override=1.2\nrapid-override=0.5\nmax-velocity=4\n\
                         optional-stop=0\nblock-delete=1\ntool-offset=0 0 2 0 0 0 0 0 0\n\
                         tool-diameter=0.5\nrelative-offset=1 0 2 0 0 0 0 0 0\n";

    #[test]
    fn edges_act_once_per_press_and_not_at_start() {
        let mut e = Edges::default();
        assert!(e.changes(&[true, false]).is_empty(), "held at start-up");
        assert!(e.changes(&[true, false]).is_empty(), "held: no repeat");
        assert_eq!(e.changes(&[false, true]), [(0, false), (1, true)]);
        assert!(e.changes(&[false, true]).is_empty());
    }

    #[test]
    fn counts_move_the_override_by_scale_and_direct_sets_it() {
        let mut c = OverrideCounter::default();
        let mut inp = OverrideInputs {
            count_enable: true,
            counts: 100,
            scale: 0.01,
            direct_value: false,
        };
        assert_eq!(c.target(&inp, 1.0), None, "the first reading only starts");
        inp.counts = 110;
        let t = c.target(&inp, 1.0).unwrap();
        assert!((t - 1.1).abs() < 1e-12, "{t}");
        assert_eq!(c.target(&inp, 1.1), None);
        inp.count_enable = false;
        inp.counts = 50;
        assert_eq!(c.target(&inp, 1.1), None, "counts disabled");
        inp.count_enable = true;
        inp.direct_value = true;
        inp.counts = 80;
        let t = c.target(&inp, 1.1).unwrap();
        assert!((t - 0.8).abs() < 1e-12, "{t}");
    }

    #[test]
    fn state_reads_back_and_refuses_what_is_not_one() {
        let s = parse_state(STATE).unwrap();
        assert_eq!(
            (s.machine.as_str(), s.task_mode(), s.program.as_str()),
            ("ON", Some(Mode::Auto), "PAUSED")
        );
        assert!(s.flood && !s.mist);
        assert_eq!((s.tool, s.override_value(Override::Feed)), (3, 1.2));
        assert!(s.panel.block_delete && !s.panel.optional_stop);
        assert_eq!(s.panel.relative_offset[0], 1.0);
        let e = parse_state(&STATE.replace("mist=0", "mist=2"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("mist=2 is not 0 or 1"), "{e}");
        let e = parse_state("machine=ON\n").unwrap_err().to_string();
        assert!(e.contains("no mode"), "{e}");
        let e = parse_state("garbage").unwrap_err().to_string();
        assert!(e.contains("is not key=value"), "{e}");
    }
}
