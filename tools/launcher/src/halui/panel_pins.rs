//! halui's switch, jog-mode, tool and position pins, with LinuxCNC's
//! names: `halui.mode.teleop`/`.joint` (MANUAL mode's jogs by world axis
//! or by joint), `halui.program.optional-stop.*` and
//! `halui.program.block-delete.*`, `halui.tool.length_offset.L` and
//! `halui.tool.diameter`, and each axis's `pos-feedback` and
//! `pos-relative`.

use hal_core::{Component, Out, Pin};

use super::logic::{Action, TaskState};
use super::pins::Layout;

/// Every world axis's letter, in motion's order: LinuxCNC makes a tool
/// length offset pin for each, whatever the machine's coordinates.
const ALL_AXES: [char; 9] = ['x', 'y', 'z', 'a', 'b', 'c', 'u', 'v', 'w'];

/// One axis's position pins.
struct AxisPositionPins {
    /// The world axis (0..=8 for X .. W).
    axis: usize,
    pos_feedback: Pin<f64, Out>,
    pos_relative: Pin<f64, Out>,
}

/// The switch, tool and position status pins.
pub struct PanelPins {
    optional_stop_is_on: Pin<bool, Out>,
    block_delete_is_on: Pin<bool, Out>,
    tool_length_offset: Vec<Pin<f64, Out>>,
    tool_diameter: Pin<f64, Out>,
    axes: Vec<AxisPositionPins>,
}

/// The jog-mode and switch buttons: (pin name after `halui.`, rising-edge
/// action, falling-edge action).
pub fn buttons() -> Vec<(String, Action, Option<Action>)> {
    [
        ("mode.teleop", Action::JogMode { teleop: true }),
        ("mode.joint", Action::JogMode { teleop: false }),
        ("program.optional-stop.on", Action::OptionalStop(true)),
        ("program.optional-stop.off", Action::OptionalStop(false)),
        ("program.block-delete.on", Action::BlockDelete(true)),
        ("program.block-delete.off", Action::BlockDelete(false)),
    ]
    .into_iter()
    .map(|(name, action)| (name.to_string(), action, None))
    .collect()
}

impl PanelPins {
    /// Creates the pins.
    pub fn create(comp: &Component, layout: &Layout<'_>) -> hal_core::Result<PanelPins> {
        let p = |n: &str| format!("halui.{n}");
        let mut tool_length_offset = Vec::new();
        for letter in ALL_AXES {
            tool_length_offset.push(comp.pin(&p(&format!("tool.length_offset.{letter}")))?);
        }
        let mut axes = Vec::new();
        for &(axis, letter) in layout.axes {
            axes.push(AxisPositionPins {
                axis,
                pos_feedback: comp.pin(&p(&format!("axis.{letter}.pos-feedback")))?,
                pos_relative: comp.pin(&p(&format!("axis.{letter}.pos-relative")))?,
            });
        }
        Ok(PanelPins {
            optional_stop_is_on: comp.pin(&p("program.optional-stop.is-on"))?,
            block_delete_is_on: comp.pin(&p("program.block-delete.is-on"))?,
            tool_length_offset,
            tool_diameter: comp.pin(&p("tool.diameter"))?,
            axes,
        })
    }

    /// Writes the pins from task's state and motion's status, each when
    /// it could be read. The relative position is the commanded one less
    /// the G5x, G92 and tool offsets, as LinuxCNC's halui computes it.
    pub fn write(&self, task: Option<&TaskState>, motion: Option<&motion::MotionStatus>) {
        if let Some(t) = task {
            let panel = &t.panel;
            self.optional_stop_is_on.set(panel.optional_stop);
            self.block_delete_is_on.set(panel.block_delete);
            for (pin, offset) in self.tool_length_offset.iter().zip(panel.tool_offset) {
                pin.set(offset);
            }
            self.tool_diameter.set(panel.tool_diameter);
        }
        let Some(m) = motion else { return };
        for p in &self.axes {
            if let Some(fb) = m.traj.pos_fb.get(p.axis) {
                p.pos_feedback.set(*fb);
            }
            if let (Some(a), Some(t)) = (m.axes.get(p.axis), task) {
                let offset = t.panel.relative_offset.get(p.axis).copied().unwrap_or(0.0);
                p.pos_relative.set(a.pos_cmd - offset);
            }
        }
    }
}
