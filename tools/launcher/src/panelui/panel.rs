//! The buttons' states, as LinuxCNC's panelui keeps them: a toggle button
//! flips on each press; a momentary button is true while held; a radio
//! button's press makes it the one true button of its group (the others
//! turn false, each running its `FALSE_COMMAND`) and sets the group's
//! output to its `GROUP_OUTPUT`. A command button runs its
//! `TRUE_COMMAND` or `FALSE_COMMAND` whenever its state is set.

use super::commands::Command;
use super::config::{Kind, OutValue, Output, PanelConfig, PinKind};

/// A command a button ran.
#[derive(Debug, Clone, PartialEq)]
pub struct Fired {
    /// The button's name.
    pub button: String,
    /// The command.
    pub command: Command,
}

/// The panel: its configuration and its buttons' states.
#[derive(Debug, Clone)]
pub struct Panel {
    cfg: PanelConfig,
    state: Vec<bool>,
    /// Each group's output (its selected button's `GROUP_OUTPUT`).
    group_value: Vec<f64>,
    by_key: [[Option<usize>; 8]; 8],
}

impl Panel {
    /// The panel at start, and the commands that start runs: each radio
    /// group's default button is set true (its `TRUE_COMMAND`), the other
    /// buttons of the group false (their `FALSE_COMMAND`s).
    pub fn new(cfg: PanelConfig) -> (Panel, Vec<Fired>) {
        let mut by_key = [[None; 8]; 8];
        for (i, b) in cfg.buttons.iter().enumerate() {
            if let Some((r, c)) = b.key {
                by_key[usize::from(r)][usize::from(c)] = Some(i);
            }
        }
        let state = cfg.buttons.iter().map(|b| b.default).collect();
        let group_value = vec![0.0; cfg.groups.len()];
        let mut panel = Panel {
            cfg,
            state,
            group_value,
            by_key,
        };
        let mut fired = Vec::new();
        for g in 0..panel.cfg.groups.len() {
            let d = panel.cfg.groups[g].default;
            panel.set(d, true, &mut fired);
            panel.select(g, d, &mut fired);
        }
        (panel, fired)
    }

    /// The configuration.
    pub fn config(&self) -> &PanelConfig {
        &self.cfg
    }

    /// Button `i`'s state.
    pub fn state(&self, i: usize) -> bool {
        self.state[i]
    }

    /// The button on key (row, column), if any.
    pub fn button_at(&self, row: usize, col: usize) -> Option<usize> {
        self.by_key.get(row)?.get(col).copied().flatten()
    }

    /// A key pressed or released: the commands it ran, `None` when no
    /// button has that key.
    pub fn key(&mut self, row: usize, col: usize, pressed: bool) -> Option<Vec<Fired>> {
        let i = self.button_at(row, col)?;
        let mut fired = Vec::new();
        match self.cfg.buttons[i].kind {
            Kind::Toggle => {
                if pressed {
                    let s = !self.state[i];
                    self.set(i, s, &mut fired);
                }
            }
            Kind::Momentary => self.set(i, pressed, &mut fired),
            Kind::Radio(g) => {
                if pressed && !self.state[i] {
                    self.set(i, true, &mut fired);
                    self.select(g, i, &mut fired);
                }
            }
        }
        Some(fired)
    }

    /// Sets button `i`'s state and runs the command for it.
    fn set(&mut self, i: usize, on: bool, fired: &mut Vec<Fired>) {
        self.state[i] = on;
        let b = &self.cfg.buttons[i];
        if let Output::Command { on: t, off: f } = &b.output {
            if let Some(c) = if on { t } else { f } {
                fired.push(Fired {
                    button: b.name.clone(),
                    command: c.clone(),
                });
            }
        }
    }

    /// Makes `chosen` group `g`'s selected button: the others false.
    fn select(&mut self, g: usize, chosen: usize, fired: &mut Vec<Fired>) {
        let members = self.cfg.groups[g].members.clone();
        for m in members.into_iter().filter(|&m| m != chosen) {
            self.set(m, false, fired);
        }
        self.group_value[g] = self.cfg.buttons[chosen].group_output;
    }

    /// Button `i`'s pin values (`NAME`, `NAME-not`), if it has pins.
    pub fn button_pins(&self, i: usize) -> Option<(OutValue, OutValue)> {
        match self.cfg.buttons[i].output {
            Output::Pin { on, off, .. } => Some(if self.state[i] { (on, off) } else { (off, on) }),
            _ => None,
        }
    }

    /// Group `g`'s pin values (`GROUP`, `GROUP-not`: the value negated;
    /// a U32 group's `-not` is 0, as a U32 cannot be negative).
    pub fn group_pins(&self, g: usize) -> Option<(OutValue, OutValue)> {
        let x = self.group_value[g];
        Some(match self.cfg.groups[g].kind? {
            PinKind::S32 => {
                let n = x.trunc() as i32;
                (OutValue::S32(n), OutValue::S32(n.wrapping_neg()))
            }
            PinKind::U32 => (OutValue::U32(x.trunc() as u32), OutValue::U32(0)),
            PinKind::Float => (OutValue::Float(x), OutValue::Float(-x)),
            PinKind::Bit => (OutValue::Bit(x != 0.0), OutValue::Bit(x == 0.0)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panelui::config::read;

    const FILE: &str = "\
[RADIO_BUTTONS]
  [[scale]]
    OUTPUT = FLOAT
    DEFAULT = small
    [[[small]]]
      KEY = R6C2
      GROUP = scale
      GROUP_OUTPUT = .0001
      OUTPUT = COMMAND
      STATUS_PIN = True
      TRUE_COMMAND = set_linear_jog_velocity, 1
      FALSE_COMMAND = NONE, NONE
    [[[large]]]
      KEY = R0C3
      GROUP = scale
      GROUP_OUTPUT = .01
      OUTPUT = S32
      TRUE_STATE = 20
      FALSE_STATE = -3
      FALSE_COMMAND = NONE
[TOGGLE_BUTTONS]
  [[flood]]
    KEY = R0C4
    OUTPUT = COMMAND
    TRUE_COMMAND = flood_on, NONE
    FALSE_COMMAND = flood_off, NONE
  [[lamp]]
    KEY = R2C5
    OUTPUT = BIT
    DEFAULT = TRUE
[MOMENTARY_BUTTONS]
  [[jog]]
    KEY = R0C2
    OUTPUT = COMMAND
    TRUE_COMMAND = continuous_jog, 0, 1
    FALSE_COMMAND = continuous_jog, 0, 0
";

    fn panel() -> (Panel, Vec<Fired>) {
        Panel::new(read(FILE, &[]).unwrap())
    }

    fn names(f: &[Fired]) -> Vec<(&str, &Command)> {
        f.iter().map(|f| (f.button.as_str(), &f.command)).collect()
    }

    #[test]
    fn start_sets_each_group_default_and_runs_its_command() {
        let (p, fired) = panel();
        assert_eq!(names(&fired), [("small", &Command::LinearJogVelocity(1.0))]);
        assert_eq!(
            p.group_pins(0),
            Some((OutValue::Float(0.0001), OutValue::Float(-0.0001)))
        );
        let large = p.button_at(0, 3).unwrap();
        assert_eq!(
            p.button_pins(large),
            Some((OutValue::S32(-3), OutValue::S32(20)))
        );
        let lamp = p.button_at(2, 5).unwrap();
        assert!(p.state(lamp), "DEFAULT = TRUE");
        assert_eq!(
            p.button_pins(lamp),
            Some((OutValue::Bit(true), OutValue::Bit(false)))
        );
    }

    #[test]
    fn a_radio_press_selects_it_and_releases_the_others() {
        let (mut p, _) = panel();
        let small = p.button_at(6, 2).unwrap();
        let large = p.button_at(0, 3).unwrap();
        assert!(
            p.key(0, 3, true).unwrap().is_empty(),
            "large has no command"
        );
        assert!(p.state(large) && !p.state(small));
        assert_eq!(p.group_pins(0).unwrap().0, OutValue::Float(0.01));
        assert_eq!(
            p.button_pins(large),
            Some((OutValue::S32(20), OutValue::S32(-3)))
        );
        assert!(
            p.key(0, 3, false).unwrap().is_empty(),
            "a release does nothing"
        );
        assert!(
            p.key(0, 3, true).unwrap().is_empty(),
            "pressing the selected one"
        );
        assert!(p.state(large));
        let f = p.key(6, 2, true).unwrap();
        assert_eq!(names(&f), [("small", &Command::LinearJogVelocity(1.0))]);
        assert!(!p.state(large));
    }

    #[test]
    fn toggles_flip_on_press_and_momentaries_follow_the_key() {
        let (mut p, _) = panel();
        assert_eq!(
            names(&p.key(0, 4, true).unwrap()),
            [("flood", &Command::Flood(true))]
        );
        assert!(p.key(0, 4, false).unwrap().is_empty());
        assert_eq!(
            names(&p.key(0, 4, true).unwrap()),
            [("flood", &Command::Flood(false))]
        );
        let jog = |d| Command::ContinuousJog {
            axis: 0,
            direction: d,
        };
        assert_eq!(names(&p.key(0, 2, true).unwrap()), [("jog", &jog(1))]);
        assert_eq!(names(&p.key(0, 2, false).unwrap()), [("jog", &jog(0))]);
        assert!(p.key(7, 7, true).is_none(), "no button there");
    }
}
