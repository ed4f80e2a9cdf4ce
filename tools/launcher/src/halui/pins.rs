//! halui's HAL component and pins, with LinuxCNC's names: the buttons
//! (each tied to the [`Action`] its edge asks for), the override inputs,
//! the jog speed and increments, and the status outputs.

use hal_core::{Component, ComponentKind, In, Instance, Out, Pin};

use super::analog::AnalogPins;
use super::joint_status::{limits_overridden, JointStatusPins};
use super::logic::{Action, Override, OverrideInputs, TaskState};
use super::panel_pins::PanelPins;
use super::selection::SelectionPins;
use crate::task::Mode;
use crate::task_manual::Jogged;

/// A button: its pin, what its rising edge asks for, and what its
/// falling edge asks for (jog buttons stop their jog).
struct Button {
    pin: Pin<bool, In>,
    rise: Action,
    fall: Option<Action>,
}

/// The pins of one override.
struct OverridePins {
    which: Override,
    count_enable: Pin<bool, In>,
    counts: Pin<i32, In>,
    scale: Pin<f64, In>,
    direct_value: Pin<bool, In>,
    value: Pin<f64, Out>,
}

/// One joint's status pins and jog increment.
struct JointPins {
    status: JointStatusPins,
    increment: Pin<f64, In>,
}

/// One axis's pins.
struct AxisPins {
    /// The world axis (0..=8 for X .. W).
    axis: usize,
    pos_commanded: Pin<f64, Out>,
    increment: Pin<f64, In>,
}

/// What the machine looks like to halui's status pins: task's state and
/// motion's, when each could be read.
pub struct Status<'a> {
    /// Task's `state` answer.
    pub task: Option<&'a TaskState>,
    /// Motion's status snapshot.
    pub motion: Option<&'a motion::MotionStatus>,
}

/// The `halui.*` pins.
pub struct HaluiPins {
    comp: Component,
    buttons: Vec<Button>,
    overrides: Vec<OverridePins>,
    joints: Vec<JointPins>,
    axes: Vec<AxisPins>,
    joint_jog_speed: Pin<f64, In>,
    axis_jog_speed: Pin<f64, In>,
    machine_is_on: Pin<bool, Out>,
    estop_is_activated: Pin<bool, Out>,
    mode_is: [(Mode, Pin<bool, Out>); 3],
    mode_is_teleop: Pin<bool, Out>,
    mode_is_joint: Pin<bool, Out>,
    program_is: [(&'static str, Pin<bool, Out>); 3],
    mist_is_on: Pin<bool, Out>,
    flood_is_on: Pin<bool, Out>,
    lube_is_on: Pin<bool, Out>,
    tool_number: Pin<u32, Out>,
    /// `halui.halui-mdi-is-running`, made when MDI commands are
    /// configured.
    mdi_is_running: Option<Pin<bool, Out>>,
    /// The selected joint and axis.
    pub selection: SelectionPins,
    /// Analog jogging.
    pub analog: AnalogPins,
    panel: PanelPins,
    /// `halui.spindle.N.*` (see `spindle`).
    pub(super) spindles: Vec<super::spindle::SpindlePins>,
}

/// What a machine's halui has pins for.
pub struct Layout<'a> {
    /// `[KINS]JOINTS`.
    pub joints: usize,
    /// The axes of `[TRAJ]COORDINATES`: (axis number, letter).
    pub axes: &'a [(usize, char)],
    /// How many `[HALUI]MDI_COMMAND`s.
    pub mdi_commands: usize,
    /// Machine units per millimetre.
    pub units_per_mm: f64,
    /// `[TRAJ]SPINDLES`.
    pub spindles: usize,
    /// Some `[JOINT_n]HOME_SEQUENCE` is set (`halui.home-all` exists).
    pub home_all: bool,
}

/// The buttons of a machine's halui, each with what its edges ask for.
fn make_buttons(comp: &Component, layout: &Layout<'_>) -> hal_core::Result<Vec<Button>> {
    let mut buttons = Vec::new();
    let mut button = |name: &str, rise: Action, fall: Option<Action>| {
        comp.pin(&format!("halui.{name}"))
            .map(|pin| buttons.push(Button { pin, rise, fall }))
    };
    for (name, action) in [
        ("machine.on", Action::MachineOn),
        ("machine.off", Action::MachineOff),
        ("estop.activate", Action::EstopActivate),
        ("estop.reset", Action::EstopReset),
        ("mode.manual", Action::Mode(Mode::Manual)),
        ("mode.auto", Action::Mode(Mode::Auto)),
        ("mode.mdi", Action::Mode(Mode::Mdi)),
        ("program.run", Action::Run),
        ("program.pause", Action::Pause),
        ("program.resume", Action::Resume),
        ("program.step", Action::Step),
        ("program.stop", Action::Abort),
        ("abort", Action::Abort),
        ("mist.on", Action::Mist(true)),
        ("mist.off", Action::Mist(false)),
        ("flood.on", Action::Flood(true)),
        ("flood.off", Action::Flood(false)),
        ("lube.on", Action::Lube(true)),
        ("lube.off", Action::Lube(false)),
    ] {
        button(name, action, None)?;
    }
    // As in LinuxCNC: only a machine with a home sequence homes all.
    if layout.home_all {
        button("home-all", Action::HomeAll, None)?;
    }
    for o in [Override::Feed, Override::Rapid, Override::MaxVelocity] {
        let pre = o.prefix();
        button(
            &format!("{pre}.increase"),
            Action::OverrideStep(o, 1.0),
            None,
        )?;
        button(
            &format!("{pre}.decrease"),
            Action::OverrideStep(o, -1.0),
            None,
        )?;
        if o != Override::MaxVelocity {
            button(&format!("{pre}.reset"), Action::OverrideReset(o), None)?;
        }
    }
    let mut jog_buttons = |base: String, what: Jogged| {
        let stop = Some(Action::JogStop(what));
        button(&format!("{base}.plus"), Action::JogStart(what, 1.0), stop)?;
        button(&format!("{base}.minus"), Action::JogStart(what, -1.0), stop)?;
        button(
            &format!("{base}.increment-plus"),
            Action::JogIncrement(what, 1.0),
            None,
        )?;
        button(
            &format!("{base}.increment-minus"),
            Action::JogIncrement(what, -1.0),
            None,
        )
    };
    for j in 0..layout.joints {
        jog_buttons(format!("joint.{j}"), Jogged::Joint(j as i32))?;
    }
    for &(axis, letter) in layout.axes {
        jog_buttons(format!("axis.{letter}"), Jogged::Axis(axis as i32))?;
    }
    for j in 0..layout.joints {
        let j32 = j as i32;
        button(&format!("joint.{j}.home"), Action::Home(j32), None)?;
        button(&format!("joint.{j}.unhome"), Action::Unhome(j32), None)?;
    }
    for n in 0..layout.mdi_commands {
        button(&format!("mdi-command-{n:02}"), Action::Mdi(n), None)?;
    }
    let more = super::selection::buttons(layout)
        .into_iter()
        .chain(super::panel_pins::buttons());
    for (name, rise, fall) in more {
        button(&name, rise, fall)?;
    }
    Ok(buttons)
}

/// LinuxCNC's halui makes the input pins of every axis letter, X to W,
/// whatever the machine's axes (its status pins only for the machine's
/// own): a pendant's HAL file that nets `halui.axis.a.plus` loads on a
/// machine without A. On such an axis the pins do nothing.
fn absent_axis_inputs(comp: &Component, layout: &Layout<'_>) -> hal_core::Result<()> {
    let absent = motion::kins::AXIS_LETTERS
        .iter()
        .filter(|l| !layout.axes.iter().any(|(_, letter)| letter == *l));
    for letter in absent {
        for name in [
            "select",
            "plus",
            "minus",
            "increment-plus",
            "increment-minus",
        ] {
            let _: Pin<bool, In> = comp.pin(&format!("halui.axis.{letter}.{name}"))?;
        }
        for name in ["analog", "increment"] {
            let _: Pin<f64, In> = comp.pin(&format!("halui.axis.{letter}.{name}"))?;
        }
    }
    Ok(())
}

impl HaluiPins {
    /// Creates the component `halui` and its pins, and makes it ready.
    pub fn create(inst: &Instance, layout: &Layout<'_>) -> hal_core::Result<HaluiPins> {
        let comp = inst.new_component("halui", ComponentKind::User)?;
        let p = |n: &str| format!("halui.{n}");
        let buttons = make_buttons(&comp, layout)?;
        let mut overrides = Vec::new();
        for which in [Override::Feed, Override::Rapid, Override::MaxVelocity] {
            let pre = which.prefix();
            overrides.push(OverridePins {
                which,
                count_enable: comp.pin_init(&p(&format!("{pre}.count-enable")), true)?,
                counts: comp.pin(&p(&format!("{pre}.counts")))?,
                scale: comp.pin_init(&p(&format!("{pre}.scale")), which.default_scale())?,
                direct_value: comp.pin(&p(&format!("{pre}.direct-value")))?,
                value: comp.pin(&p(&format!("{pre}.value")))?,
            });
        }
        let mut joints = Vec::new();
        for j in 0..layout.joints {
            let name = |n: &str| p(&format!("joint.{j}.{n}"));
            joints.push(JointPins {
                status: JointStatusPins::create(&comp, &p(&format!("joint.{j}")))?,
                increment: comp.pin(&name("increment"))?,
            });
        }
        let mut axes = Vec::new();
        for &(axis, letter) in layout.axes {
            axes.push(AxisPins {
                axis,
                pos_commanded: comp.pin(&p(&format!("axis.{letter}.pos-commanded")))?,
                increment: comp.pin(&p(&format!("axis.{letter}.increment")))?,
            });
        }
        absent_axis_inputs(&comp, layout)?;
        let mut spindles = Vec::with_capacity(layout.spindles);
        for n in 0..layout.spindles {
            spindles.push(super::spindle::SpindlePins::new(&comp, n)?);
        }
        let units: Pin<f64, Out> = comp.pin(&p("machine.units-per-mm"))?;
        units.set(layout.units_per_mm);
        let pins = HaluiPins {
            joint_jog_speed: comp.pin(&p("joint.jog-speed"))?,
            axis_jog_speed: comp.pin(&p("axis.jog-speed"))?,
            machine_is_on: comp.pin(&p("machine.is-on"))?,
            estop_is_activated: comp.pin_init(&p("estop.is-activated"), true)?,
            mode_is: [
                (Mode::Manual, comp.pin(&p("mode.is-manual"))?),
                (Mode::Auto, comp.pin(&p("mode.is-auto"))?),
                (Mode::Mdi, comp.pin(&p("mode.is-mdi"))?),
            ],
            mode_is_teleop: comp.pin(&p("mode.is-teleop"))?,
            mode_is_joint: comp.pin(&p("mode.is-joint"))?,
            program_is: [
                ("IDLE", comp.pin_init(&p("program.is-idle"), true)?),
                ("RUNNING", comp.pin(&p("program.is-running"))?),
                ("PAUSED", comp.pin(&p("program.is-paused"))?),
            ],
            mist_is_on: comp.pin(&p("mist.is-on"))?,
            flood_is_on: comp.pin(&p("flood.is-on"))?,
            lube_is_on: comp.pin(&p("lube.is-on"))?,
            tool_number: comp.pin(&p("tool.number"))?,
            mdi_is_running: if layout.mdi_commands > 0 {
                Some(comp.pin(&p("halui-mdi-is-running"))?)
            } else {
                None
            },
            selection: SelectionPins::create(&comp, layout)?,
            analog: AnalogPins::create(&comp, layout)?,
            panel: PanelPins::create(&comp, layout)?,
            buttons,
            overrides,
            joints,
            axes,
            spindles,
            comp,
        };
        pins.comp.ready()?;
        Ok(pins)
    }

    /// Every button's value, in a fixed order.
    pub fn buttons(&self) -> Vec<bool> {
        self.buttons.iter().map(|b| b.pin.get()).collect()
    }

    /// What the edge of button `index` to `value` asks for.
    pub fn action(&self, index: usize, value: bool) -> Option<Action> {
        let b = self.buttons.get(index)?;
        if value {
            Some(b.rise)
        } else {
            b.fall
        }
    }

    /// Shows whether an `mdi-command-NN` of halui's runs.
    pub fn set_mdi_running(&self, running: bool) {
        if let Some(pin) = &self.mdi_is_running {
            pin.set(running);
        }
    }

    /// Whether a button whose rising edge asks for `rise` is held now.
    pub fn held(&self, rise: Action) -> bool {
        self.buttons.iter().any(|b| b.rise == rise && b.pin.get())
    }

    /// The jogs (`JogStart`) of the plus/minus buttons held now.
    pub fn held_jogs(&self) -> Vec<Action> {
        self.buttons
            .iter()
            .filter(|b| matches!(b.rise, Action::JogStart(..)) && b.pin.get())
            .map(|b| b.rise)
            .collect()
    }

    /// `halui.joint.jog-speed` or `halui.axis.jog-speed`.
    pub fn jog_speed(&self, what: Jogged) -> f64 {
        match what {
            Jogged::Joint(_) => self.joint_jog_speed.get(),
            Jogged::Axis(_) => self.axis_jog_speed.get(),
        }
    }

    /// `halui.joint.N.increment` or `halui.axis.L.increment`.
    pub fn increment(&self, what: Jogged) -> f64 {
        match what {
            Jogged::Joint(j) => usize::try_from(j)
                .ok()
                .and_then(|j| self.joints.get(j))
                .map_or(0.0, |j| j.increment.get()),
            Jogged::Axis(a) => self
                .axes
                .iter()
                .find(|p| i32::try_from(p.axis) == Ok(a))
                .map_or(0.0, |p| p.increment.get()),
        }
    }

    /// The input pins of every override.
    pub fn override_inputs(&self) -> Vec<(Override, OverrideInputs)> {
        self.overrides
            .iter()
            .map(|o| {
                (
                    o.which,
                    OverrideInputs {
                        count_enable: o.count_enable.get(),
                        counts: o.counts.get(),
                        scale: o.scale.get(),
                        direct_value: o.direct_value.get(),
                    },
                )
            })
            .collect()
    }

    /// `scale` of an override.
    pub fn override_scale(&self, which: Override) -> f64 {
        self.overrides
            .iter()
            .find(|o| o.which == which)
            .map_or(0.0, |o| o.scale.get())
    }

    /// Writes the status pins.
    pub fn write(&self, status: &Status<'_>) {
        self.panel.write(status.task, status.motion);
        self.selection.write(status.motion);
        if let Some(t) = status.task {
            self.machine_is_on.set(t.machine == "ON");
            self.estop_is_activated.set(t.machine == "ESTOP");
            for (mode, pin) in &self.mode_is {
                pin.set(t.task_mode() == Some(*mode));
            }
            for (name, pin) in &self.program_is {
                pin.set(t.program == *name);
            }
            self.mist_is_on.set(t.mist);
            self.flood_is_on.set(t.flood);
            self.lube_is_on.set(t.lube);
            self.tool_number.set(u32::try_from(t.tool).unwrap_or(0));
            for o in &self.overrides {
                o.value.set(t.override_value(o.which));
            }
        }
        if let Some(m) = status.motion {
            self.mode_is_teleop.set(m.teleop_mode);
            self.mode_is_joint.set(!m.teleop_mode && !m.coord_mode);
            let overridden = limits_overridden(m.override_mask);
            for (pins, joint) in self.joints.iter().zip(&m.joints) {
                pins.status.write(joint, overridden);
            }
            for p in &self.axes {
                if let Some(a) = m.axes.get(p.axis) {
                    p.pos_commanded.set(a.pos_cmd);
                }
            }
        }
    }
}
