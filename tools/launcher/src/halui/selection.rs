//! The selected joint and axis, as LinuxCNC's halui has them: a rising
//! edge on `halui.joint.N.select` (`halui.axis.L.select`) selects it;
//! `halui.joint.selected` (`halui.axis.selected`) says which, the
//! `is-selected` pins show it; the `halui.joint.selected.*` and
//! `halui.axis.selected.*` buttons home and jog whichever is selected
//! when they are pressed, and `halui.joint.selected.*` status pins follow
//! the selected joint.

use hal_core::{Component, In, Out, Pin};

use super::joint_status::{limits_overridden, JointStatusPins};
use super::logic::Action;
use super::pins::Layout;
use crate::task_manual::Jogged;

/// What a `selected` button asks of the selected joint or axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OnSelected {
    /// `home` (joints only).
    Home,
    /// `unhome` (joints only).
    Unhome,
    /// `plus`/`minus` pressed: jog in the direction's sign.
    JogStart(f64),
    /// `plus`/`minus` released.
    JogStop,
    /// `increment-plus`/`-minus`: jog by the selected increment.
    JogIncrement(f64),
}

/// The selection pins and which joint and axis are selected.
pub struct SelectionPins {
    joint_selected: Pin<u32, Out>,
    joint_is_selected: Vec<Pin<bool, Out>>,
    joint_increment: Pin<f64, In>,
    joint_status: JointStatusPins,
    axis_selected: Pin<u32, Out>,
    /// (world axis number, its `is-selected` pin).
    axis_is_selected: Vec<(usize, Pin<bool, Out>)>,
    axis_increment: Pin<f64, In>,
    joint: usize,
    axis: usize,
}

/// The selection's buttons: (pin name after `halui.`, rising-edge
/// action, falling-edge action).
pub fn buttons(layout: &Layout<'_>) -> Vec<(String, Action, Option<Action>)> {
    let mut out = Vec::new();
    for j in 0..layout.joints {
        out.push((format!("joint.{j}.select"), Action::SelectJoint(j), None));
    }
    for &(axis, letter) in layout.axes {
        out.push((
            format!("axis.{letter}.select"),
            Action::SelectAxis(axis),
            None,
        ));
    }
    let jogs = |of: fn(OnSelected) -> Action, base: &str| {
        let stop = Some(of(OnSelected::JogStop));
        vec![
            (format!("{base}.plus"), of(OnSelected::JogStart(1.0)), stop),
            (
                format!("{base}.minus"),
                of(OnSelected::JogStart(-1.0)),
                stop,
            ),
            (
                format!("{base}.increment-plus"),
                of(OnSelected::JogIncrement(1.0)),
                None,
            ),
            (
                format!("{base}.increment-minus"),
                of(OnSelected::JogIncrement(-1.0)),
                None,
            ),
        ]
    };
    out.extend(jogs(Action::SelectedJoint, "joint.selected"));
    out.extend(jogs(Action::SelectedAxis, "axis.selected"));
    out.push((
        "joint.selected.home".into(),
        Action::SelectedJoint(OnSelected::Home),
        None,
    ));
    out.push((
        "joint.selected.unhome".into(),
        Action::SelectedJoint(OnSelected::Unhome),
        None,
    ));
    out
}

impl SelectionPins {
    /// Creates the selection's pins (not its buttons); joint 0 and axis
    /// 0 (X) start selected, as in LinuxCNC.
    pub fn create(comp: &Component, layout: &Layout<'_>) -> hal_core::Result<SelectionPins> {
        let p = |n: &str| format!("halui.{n}");
        let mut joint_is_selected = Vec::new();
        for j in 0..layout.joints {
            joint_is_selected.push(comp.pin_init(&p(&format!("joint.{j}.is-selected")), j == 0)?);
        }
        let mut axis_is_selected = Vec::new();
        for &(axis, letter) in layout.axes {
            let pin = comp.pin_init(&p(&format!("axis.{letter}.is-selected")), axis == 0)?;
            axis_is_selected.push((axis, pin));
        }
        Ok(SelectionPins {
            joint_selected: comp.pin(&p("joint.selected"))?,
            joint_is_selected,
            joint_increment: comp.pin(&p("joint.selected.increment"))?,
            joint_status: JointStatusPins::create(comp, &p("joint.selected"))?,
            axis_selected: comp.pin(&p("axis.selected"))?,
            axis_is_selected,
            axis_increment: comp.pin(&p("axis.selected.increment"))?,
            joint: 0,
            axis: 0,
        })
    }

    /// The selected joint.
    pub fn joint(&self) -> usize {
        self.joint
    }

    /// The selected world axis.
    pub fn axis(&self) -> usize {
        self.axis
    }

    /// Selects joint `j`.
    pub fn select_joint(&mut self, j: usize) {
        self.joint = j;
    }

    /// Selects world axis `axis` (0..=8 for X .. W).
    pub fn select_axis(&mut self, axis: usize) {
        self.axis = axis;
    }

    /// The action a `selected` button asks for, on the joint or axis
    /// selected now; `None` for what an axis cannot do (home).
    pub fn resolve(&self, action: Action) -> Option<Action> {
        let (what, op, increment) = match action {
            Action::SelectedJoint(op) => (
                Jogged::Joint(i32::try_from(self.joint).ok()?),
                op,
                self.joint_increment.get(),
            ),
            Action::SelectedAxis(op) => (
                Jogged::Axis(i32::try_from(self.axis).ok()?),
                op,
                self.axis_increment.get(),
            ),
            other => return Some(other),
        };
        match (op, what) {
            (OnSelected::Home, Jogged::Joint(j)) => Some(Action::Home(j)),
            (OnSelected::Unhome, Jogged::Joint(j)) => Some(Action::Unhome(j)),
            (OnSelected::Home | OnSelected::Unhome, Jogged::Axis(_)) => None,
            (OnSelected::JogStart(dir), _) => Some(Action::JogStart(what, dir)),
            (OnSelected::JogStop, _) => Some(Action::JogStop(what)),
            (OnSelected::JogIncrement(dir), _) => Some(Action::JogBy(what, dir * increment)),
        }
    }

    /// Writes the selection pins and the selected joint's status.
    pub fn write(&self, motion: Option<&motion::MotionStatus>) {
        self.joint_selected
            .set(u32::try_from(self.joint).unwrap_or(u32::MAX));
        self.axis_selected
            .set(u32::try_from(self.axis).unwrap_or(u32::MAX));
        for (j, pin) in self.joint_is_selected.iter().enumerate() {
            pin.set(j == self.joint);
        }
        for (axis, pin) in &self.axis_is_selected {
            pin.set(*axis == self.axis);
        }
        if let Some(m) = motion {
            if let Some(joint) = m.joints.get(self.joint) {
                let overridden = limits_overridden(m.override_mask);
                self.joint_status.write(joint, overridden);
            }
        }
    }
}
