//! The `ini.*` pins LinuxCNC's task creates (component `inihal`): input
//! pins that start at the INI file's values and, when changed, send the
//! matching configuration to the motion controller.

use hal_core::{Component, ComponentKind, In, Instance, Pin};
use hal_lang::ini::Ini;

use crate::config::{axis_letters, joint_count, AxisLimits, JointLimits, TrajSettings};

/// A change of an `ini.*` pin, for the motion controller.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IniChange {
    /// `ini.N.backlash`.
    Backlash {
        /// The joint number.
        joint: usize,
        /// The new value.
        value: f64,
    },
    /// `ini.N.ferror`.
    Ferror {
        /// The joint number.
        joint: usize,
        /// The new value.
        value: f64,
    },
    /// `ini.N.min_ferror`.
    MinFerror {
        /// The joint number.
        joint: usize,
        /// The new value.
        value: f64,
    },
    /// `ini.N.min_limit` / `max_limit`.
    JointLimits {
        /// The joint number.
        joint: usize,
        /// The lower limit.
        min: f64,
        /// The upper limit.
        max: f64,
    },
    /// `ini.N.max_velocity`.
    JointVel {
        /// The joint number.
        joint: usize,
        /// The new value.
        value: f64,
    },
    /// `ini.N.max_acceleration`.
    JointAcc {
        /// The joint number.
        joint: usize,
        /// The new value.
        value: f64,
    },
    /// `ini.N.home`, `home_offset`, `home_sequence`.
    Homing {
        /// The joint number.
        joint: usize,
        /// `HOME`.
        home: f64,
        /// `HOME_OFFSET`.
        offset: f64,
        /// `HOME_SEQUENCE`.
        sequence: i32,
    },
    /// `ini.L.min_limit` / `max_limit` (L as an axis number).
    AxisLimits {
        /// The axis number (X=0 … W=8).
        axis: usize,
        /// The lower limit.
        min: f64,
        /// The upper limit.
        max: f64,
    },
    /// `ini.L.max_velocity`.
    AxisVel {
        /// The axis number (X=0 … W=8).
        axis: usize,
        /// The new value.
        value: f64,
    },
    /// `ini.L.max_acceleration`.
    AxisAcc {
        /// The axis number (X=0 … W=8).
        axis: usize,
        /// The new value.
        value: f64,
    },
    /// `ini.N.max_jerk`.
    JointJerk {
        /// The joint number.
        joint: usize,
        /// The new value.
        value: f64,
    },
    /// `ini.L.max_jerk`.
    AxisJerk {
        /// The axis number (X=0 … W=8).
        axis: usize,
        /// The new value.
        value: f64,
    },
    /// `ini.traj_max_velocity`.
    TrajVel {
        /// The new value.
        value: f64,
    },
    /// `ini.traj_max_acceleration`.
    TrajAcc {
        /// The new value.
        value: f64,
    },
    /// `ini.traj_max_jerk`.
    TrajJerk {
        /// The new value.
        value: f64,
    },
    /// `ini.traj_planner_type`.
    PlannerType {
        /// The new value.
        value: i32,
    },
    /// A pin whose setting the motion controller has no equivalent of.
    NotApplied {
        /// The pin name.
        pin: &'static str,
    },
}

impl IniChange {
    /// The name of the pin that changed.
    pub fn pin(&self) -> String {
        let axis = |a: usize| motion::command::axis_letter(a).to_ascii_lowercase();
        match *self {
            IniChange::Backlash { joint, .. } => format!("ini.{joint}.backlash"),
            IniChange::Ferror { joint, .. } => format!("ini.{joint}.ferror"),
            IniChange::MinFerror { joint, .. } => format!("ini.{joint}.min_ferror"),
            IniChange::JointLimits { joint, .. } => format!("ini.{joint}.min_limit/max_limit"),
            IniChange::JointVel { joint, .. } => format!("ini.{joint}.max_velocity"),
            IniChange::JointAcc { joint, .. } => format!("ini.{joint}.max_acceleration"),
            IniChange::JointJerk { joint, .. } => format!("ini.{joint}.max_jerk"),
            IniChange::Homing { joint, .. } => {
                format!("ini.{joint}.home/home_offset/home_sequence")
            }
            IniChange::AxisLimits { axis: a, .. } => format!("ini.{}.min_limit/max_limit", axis(a)),
            IniChange::AxisVel { axis: a, .. } => format!("ini.{}.max_velocity", axis(a)),
            IniChange::AxisAcc { axis: a, .. } => format!("ini.{}.max_acceleration", axis(a)),
            IniChange::AxisJerk { axis: a, .. } => format!("ini.{}.max_jerk", axis(a)),
            IniChange::TrajVel { .. } => "ini.traj_max_velocity".into(),
            IniChange::TrajAcc { .. } => "ini.traj_max_acceleration".into(),
            IniChange::TrajJerk { .. } => "ini.traj_max_jerk".into(),
            IniChange::PlannerType { .. } => "ini.traj_planner_type".into(),
            IniChange::NotApplied { pin } => pin.into(),
        }
    }
}

struct JointPins {
    backlash: Pin<f64, In>,
    ferror: Pin<f64, In>,
    min_ferror: Pin<f64, In>,
    min_limit: Pin<f64, In>,
    max_limit: Pin<f64, In>,
    max_velocity: Pin<f64, In>,
    max_acceleration: Pin<f64, In>,
    max_jerk: Pin<f64, In>,
    home: Pin<f64, In>,
    home_offset: Pin<f64, In>,
    home_sequence: Pin<i32, In>,
}

struct AxisPins {
    axis: usize,
    min_limit: Pin<f64, In>,
    max_limit: Pin<f64, In>,
    max_velocity: Pin<f64, In>,
    max_acceleration: Pin<f64, In>,
    max_jerk: Pin<f64, In>,
}

/// A traj pin and what it holds.
struct TrajPin {
    name: &'static str,
    pin: TrajValue,
}

enum TrajValue {
    Float(Pin<f64, In>),
    Bit(Pin<bool, In>),
    S32(Pin<i32, In>),
}

impl TrajPin {
    /// What a change of this pin asks of the motion controller.
    fn change(&self) -> IniChange {
        match (self.name, &self.pin) {
            ("ini.traj_max_velocity", TrajValue::Float(p)) => IniChange::TrajVel { value: p.get() },
            ("ini.traj_max_acceleration", TrajValue::Float(p)) => {
                IniChange::TrajAcc { value: p.get() }
            }
            ("ini.traj_max_jerk", TrajValue::Float(p)) => IniChange::TrajJerk { value: p.get() },
            ("ini.traj_planner_type", TrajValue::S32(p)) => {
                IniChange::PlannerType { value: p.get() }
            }
            (name, _) => IniChange::NotApplied { pin: name },
        }
    }
}

impl TrajValue {
    fn bits(&self) -> u64 {
        match self {
            TrajValue::Float(p) => p.get().to_bits(),
            TrajValue::Bit(p) => u64::from(p.get()),
            TrajValue::S32(p) => p.get() as u64,
        }
    }
}

/// The `inihal` component and its pins.
pub struct TaskPins {
    _comp: Component,
    joints: Vec<JointPins>,
    axes: Vec<AxisPins>,
    traj: Vec<TrajPin>,
    /// Values seen last, to tell changes (f64 bits, per pin in order).
    last: Vec<u64>,
}

impl TaskPins {
    /// Creates the pins with the INI file's values (or LinuxCNC's
    /// defaults where a key is missing).
    pub fn create(inst: &Instance, ini: &Ini) -> Result<TaskPins, crate::LaunchError> {
        let c = inst.new_component("inihal", ComponentKind::User)?;
        let f = |name: String, v: f64| c.pin_init::<f64, In>(&name, v);
        let mut joints = Vec::new();
        for j in 0..joint_count(ini)? {
            let l = JointLimits::from_ini(ini, j)?;
            let p = |k: &str| format!("ini.{j}.{k}");
            joints.push(JointPins {
                backlash: f(p("backlash"), l.backlash)?,
                ferror: f(p("ferror"), l.ferror)?,
                min_ferror: f(p("min_ferror"), l.min_ferror)?,
                min_limit: f(p("min_limit"), l.min_limit)?,
                max_limit: f(p("max_limit"), l.max_limit)?,
                max_velocity: f(p("max_velocity"), l.max_velocity)?,
                max_acceleration: f(p("max_acceleration"), l.max_acceleration)?,
                max_jerk: f(p("max_jerk"), l.max_jerk)?,
                home: f(p("home"), l.homing.home)?,
                home_offset: f(p("home_offset"), l.homing.offset)?,
                home_sequence: c.pin_init(&p("home_sequence"), l.homing.sequence)?,
            });
        }
        let mut axes = Vec::new();
        for (axis, letter) in axis_letters(ini) {
            let l = AxisLimits::from_ini(ini, letter)?;
            let p = |k: &str| format!("ini.{letter}.{k}");
            axes.push(AxisPins {
                axis,
                min_limit: f(p("min_limit"), l.min_limit)?,
                max_limit: f(p("max_limit"), l.max_limit)?,
                max_velocity: f(p("max_velocity"), l.max_velocity)?,
                max_acceleration: f(p("max_acceleration"), l.max_acceleration)?,
                max_jerk: f(p("max_jerk"), l.max_jerk)?,
            });
        }
        let t = TrajSettings::from_ini(ini)?;
        let float = |name: &'static str, v: f64| -> hal_core::Result<TrajPin> {
            Ok(TrajPin {
                name,
                pin: TrajValue::Float(c.pin_init(name, v)?),
            })
        };
        let traj = vec![
            TrajPin {
                name: "ini.traj_arc_blend_enable",
                pin: TrajValue::Bit(c.pin_init("ini.traj_arc_blend_enable", t.arc_blend_enable)?),
            },
            TrajPin {
                name: "ini.traj_arc_blend_fallback_enable",
                pin: TrajValue::Bit(c.pin_init(
                    "ini.traj_arc_blend_fallback_enable",
                    t.arc_blend_fallback_enable,
                )?),
            },
            float("ini.traj_arc_blend_gap_cycles", t.arc_blend_gap_cycles)?,
            float(
                "ini.traj_arc_blend_optimization_depth",
                t.arc_blend_optimization_depth,
            )?,
            float("ini.traj_arc_blend_ramp_freq", t.arc_blend_ramp_freq)?,
            float("ini.traj_default_acceleration", t.default_acceleration)?,
            float("ini.traj_default_velocity", t.default_velocity)?,
            float("ini.traj_max_acceleration", t.max_acceleration)?,
            float("ini.traj_max_velocity", t.max_velocity)?,
            float("ini.traj_max_jerk", t.max_jerk)?,
            TrajPin {
                name: "ini.traj_planner_type",
                pin: TrajValue::S32(c.pin_init("ini.traj_planner_type", t.planner_type)?),
            },
        ];
        c.ready()?;
        let mut pins = TaskPins {
            _comp: c,
            joints,
            axes,
            traj,
            last: Vec::new(),
        };
        pins.last = pins.values();
        Ok(pins)
    }

    /// Every pin's value as bits, in a fixed order.
    fn values(&self) -> Vec<u64> {
        let mut v = Vec::new();
        for j in &self.joints {
            v.extend([
                j.backlash.get().to_bits(),
                j.ferror.get().to_bits(),
                j.min_ferror.get().to_bits(),
                j.min_limit.get().to_bits(),
                j.max_limit.get().to_bits(),
                j.max_velocity.get().to_bits(),
                j.max_acceleration.get().to_bits(),
                j.max_jerk.get().to_bits(),
                j.home.get().to_bits(),
                j.home_offset.get().to_bits(),
                j.home_sequence.get() as u64,
            ]);
        }
        for a in &self.axes {
            v.extend([
                a.min_limit.get().to_bits(),
                a.max_limit.get().to_bits(),
                a.max_velocity.get().to_bits(),
                a.max_acceleration.get().to_bits(),
                a.max_jerk.get().to_bits(),
            ]);
        }
        v.extend(self.traj.iter().map(|t| t.pin.bits()));
        v
    }

    /// The pins changed since the last call, as configuration changes.
    pub fn changes(&mut self) -> Vec<IniChange> {
        let now = self.values();
        if now == self.last {
            return Vec::new();
        }
        let old = std::mem::replace(&mut self.last, now);
        let now = &self.last;
        let changed = |i: usize| old.get(i) != now.get(i);
        let mut out = Vec::new();
        let mut i = 0;
        for (joint, j) in self.joints.iter().enumerate() {
            let c: Vec<bool> = (i..i + 11).map(changed).collect();
            if c[0] {
                out.push(IniChange::Backlash {
                    joint,
                    value: j.backlash.get(),
                });
            }
            if c[1] {
                out.push(IniChange::Ferror {
                    joint,
                    value: j.ferror.get(),
                });
            }
            if c[2] {
                out.push(IniChange::MinFerror {
                    joint,
                    value: j.min_ferror.get(),
                });
            }
            if c[3] || c[4] {
                out.push(IniChange::JointLimits {
                    joint,
                    min: j.min_limit.get(),
                    max: j.max_limit.get(),
                });
            }
            if c[5] {
                out.push(IniChange::JointVel {
                    joint,
                    value: j.max_velocity.get(),
                });
            }
            if c[6] {
                out.push(IniChange::JointAcc {
                    joint,
                    value: j.max_acceleration.get(),
                });
            }
            if c[7] {
                out.push(IniChange::JointJerk {
                    joint,
                    value: j.max_jerk.get(),
                });
            }
            if c[8] || c[9] || c[10] {
                out.push(IniChange::Homing {
                    joint,
                    home: j.home.get(),
                    offset: j.home_offset.get(),
                    sequence: j.home_sequence.get(),
                });
            }
            i += 11;
        }
        for a in &self.axes {
            let c: Vec<bool> = (i..i + 5).map(changed).collect();
            if c[0] || c[1] {
                out.push(IniChange::AxisLimits {
                    axis: a.axis,
                    min: a.min_limit.get(),
                    max: a.max_limit.get(),
                });
            }
            if c[2] {
                out.push(IniChange::AxisVel {
                    axis: a.axis,
                    value: a.max_velocity.get(),
                });
            }
            if c[3] {
                out.push(IniChange::AxisAcc {
                    axis: a.axis,
                    value: a.max_acceleration.get(),
                });
            }
            if c[4] {
                out.push(IniChange::AxisJerk {
                    axis: a.axis,
                    value: a.max_jerk.get(),
                });
            }
            i += 5;
        }
        for t in &self.traj {
            if changed(i) {
                out.push(t.change());
            }
            i += 1;
        }
        out
    }
}
