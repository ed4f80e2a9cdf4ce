//! `eoffset_per_angle`: an external offset computed from an angle (a
//! rotary axis or the spindle), for turning polygons or waves: inside
//! polygon (`fnum` 0), outside polygon (1), sinusoid (2) or square wave
//! (3), with `fmult` sides or periods per turn and an amplitude of
//! `rfraction` times `radius-ref`. The offset goes out as counts
//! (`kcounts`, scale `kreciprocal`) to a motion axis's eoffset pins, and
//! is enabled and wound down through a small state machine.

use hal_core::Result;

use crate::cmath::f64_to_i32;
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::notice::Notice;

/// What eoffset_per_angle writes to stderr.
pub static TEXTS: &[&str] = &[
    "eoffset_per_angle: active enable-in not honored at start\n",
    "eoffset_per_angle stopping: polygon function needs fmult > 2\n",
];

/// The state machine's states (the `state-dbg` values).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum State {
    /// Machine off, or waiting for `enable-in` to be low once.
    #[default]
    Off = 0,
    /// Waiting for `enable-in`.
    Ready = 1,
    /// Computing offsets.
    Running = 2,
    /// Waiting for motion to bring the offset back to zero.
    Stopping = 3,
    /// Done stopping.
    Finish = 4,
}

/// The offset function's inputs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Shape {
    /// Pin `fnum`.
    pub fnum: i32,
    /// Pin `angle` (degrees).
    pub angle: f64,
    /// Pin `start-angle` (degrees).
    pub start_angle: f64,
    /// Pin `radius-ref`.
    pub radius_ref: f64,
    /// Pin `rfraction`.
    pub rfraction: f64,
    /// Pin `fmult`.
    pub fmult: f64,
}

/// Degrees to radians the way LinuxCNC's macro expands: `x * PI / 180`.
fn rad(x: f64) -> f64 {
    x * std::f64::consts::PI / 180.0
}

/// The offset for `s`, or `None` when the function cannot be computed
/// (a polygon with fewer than three sides). An unknown `fnum` uses
/// function 0.
pub fn offset(s: &Shape) -> Option<f64> {
    match s.fnum {
        2 | 3 => {
            let uangle = s.fmult * (s.angle - s.start_angle) + -90.0;
            let wave = if s.fnum == 2 {
                rad(uangle).sin()
            } else if rad(uangle).sin() >= 0.0 {
                1.0
            } else {
                -1.0
            };
            Some((0.5 * s.rfraction * s.radius_ref) * (1.0 + wave))
        }
        f => {
            if s.fmult <= 2.0 {
                return None;
            }
            let divisor = 360.0 / s.fmult;
            let uangle = s.angle + divisor / 2.0 - s.start_angle;
            let edge = rad(divisor / 2.0 - uangle % divisor).cos();
            Some(if f == 1 {
                (1.0 + s.rfraction) * s.radius_ref * (std::f64::consts::PI / s.fmult).cos() / edge
                    - s.radius_ref
            } else {
                (1.0 + s.rfraction) * s.radius_ref / edge - s.radius_ref
            })
        }
    }
}

/// The pin values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EoffsetVars {
    /// Pin `active` (motion's eoffset-active).
    pub active: bool,
    /// Pin `is-on` (machine on).
    pub is_on: bool,
    /// Pin `enable-in`.
    pub enable_in: bool,
    /// Pin `k` (0 means 10000).
    pub k: u32,
    /// The shape pins.
    pub shape: Shape,
    /// Pin `is-off`.
    pub is_off: bool,
    /// Pin `enable-out`.
    pub enable_out: bool,
    /// Pin `clear`.
    pub clear: bool,
    /// Pin `kcounts`.
    pub kcounts: i32,
    /// Pin `kreciprocal`.
    pub kreciprocal: f64,
    /// Pin `eoffset-dbg`.
    pub eoffset_dbg: f64,
    /// Pin `state-dbg`.
    pub state_dbg: u32,
}

/// Per-instance state.
#[derive(Debug, Clone, Default)]
pub struct EoffsetPerAngle {
    state: State,
    run_ct: i64,
    delay_ct: i64,
    messaged: bool,
    err_stop: bool,
}

impl EoffsetPerAngle {
    /// One call; returns a message index to print, if any.
    pub fn step(&mut self, v: &mut EoffsetVars) -> Option<usize> {
        self.run_ct += 1;
        v.state_dbg = self.state as u32;
        let kfactor = if v.k == 0 { 10000 } else { v.k as i32 };
        v.kreciprocal = f64::from(1.0f32 / kfactor as f32);
        v.is_off = !v.is_on;
        if v.is_off {
            self.err_stop = false;
            v.enable_out = false;
            v.kcounts = 0;
            v.eoffset_dbg = 0.0;
            self.messaged = false;
            self.state = State::Off;
            return None;
        }
        match self.state {
            State::Off => {
                if v.enable_in {
                    if !self.messaged {
                        self.messaged = true;
                        return Some(0);
                    }
                    return None;
                }
                self.err_stop = false;
                self.messaged = true;
                v.kcounts = 0;
                self.state = State::Ready;
                return None;
            }
            State::Ready => {
                if v.enable_in {
                    v.kcounts = 0;
                    v.eoffset_dbg = 0.0;
                    v.enable_out = false;
                    self.delay_ct = 0;
                    self.state = State::Running;
                }
                return None;
            }
            State::Running => {
                if v.enable_in {
                    v.enable_out = true;
                } else {
                    v.clear = true;
                    v.kcounts = 0;
                    v.eoffset_dbg = 0.0;
                    self.state = State::Stopping;
                    self.delay_ct = self.run_ct;
                    return None;
                }
            }
            State::Stopping => {
                if !v.active {
                    self.delay_ct = self.run_ct;
                    self.state = State::Finish;
                }
                return None;
            }
            State::Finish => {
                if self.run_ct >= self.delay_ct {
                    v.enable_out = false;
                    self.state = if self.err_stop {
                        State::Off
                    } else {
                        State::Ready
                    };
                }
                v.clear = false;
                return None;
            }
        }
        match offset(&v.shape) {
            Some(o) => {
                v.kcounts = f64_to_i32(f64::from(kfactor) * o);
                v.eoffset_dbg = f64::from(v.kcounts) * v.kreciprocal;
                None
            }
            None => {
                self.err_stop = true;
                v.kcounts = 0;
                v.eoffset_dbg = 0.0;
                self.state = State::Stopping;
                Some(1)
            }
        }
    }
}

/// The `eoffset_per_angle` component.
pub struct EoffsetPerAngleComp;
impl HalComp for EoffsetPerAngleComp {
    const NAME: &'static str = "eoffset_per_angle";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let active = inst.pin_in::<bool>("active")?;
        let is_on = inst.pin_in::<bool>("is-on")?;
        let enable_in = inst.pin_in::<bool>("enable-in")?;
        let radius_ref = inst.pin_in_init::<f64>("radius-ref", 1.0)?;
        let angle = inst.pin_in::<f64>("angle")?;
        let start_angle = inst.pin_in::<f64>("start-angle")?;
        let fnum = inst.pin_in::<i32>("fnum")?;
        let rfraction = inst.pin_in_init::<f64>("rfraction", 0.1)?;
        let fmult = inst.pin_in_init::<f64>("fmult", 6.0)?;
        let k = inst.pin_in_init::<u32>("k", 10000)?;
        let is_off = inst.pin_out::<bool>("is-off")?;
        let enable_out = inst.pin_out::<bool>("enable-out")?;
        let clear = inst.pin_out::<bool>("clear")?;
        let kcounts = inst.pin_out::<i32>("kcounts")?;
        let kreciprocal = inst.pin_out::<f64>("kreciprocal")?;
        let eoffset_dbg = inst.pin_out::<f64>("eoffset-dbg")?;
        let state_dbg = inst.pin_out::<u32>("state-dbg")?;
        let notice = Notice::new(TEXTS);
        let mut e = EoffsetPerAngle::default();
        inst.funct("_", true, move |_| {
            let mut v = EoffsetVars {
                active: active.get(),
                is_on: is_on.get(),
                enable_in: enable_in.get(),
                k: k.get(),
                shape: Shape {
                    fnum: fnum.get(),
                    angle: angle.get(),
                    start_angle: start_angle.get(),
                    radius_ref: radius_ref.get(),
                    rfraction: rfraction.get(),
                    fmult: fmult.get(),
                },
                is_off: is_off.get(),
                enable_out: enable_out.get(),
                clear: clear.get(),
                kcounts: kcounts.get(),
                kreciprocal: kreciprocal.get(),
                eoffset_dbg: eoffset_dbg.get(),
                state_dbg: state_dbg.get(),
            };
            if let Some(m) = e.step(&mut v) {
                notice.post(m);
            }
            state_dbg.set(v.state_dbg);
            kreciprocal.set(v.kreciprocal);
            is_off.set(v.is_off);
            enable_out.set(v.enable_out);
            clear.set(v.clear);
            kcounts.set(v.kcounts);
            eoffset_dbg.set(v.eoffset_dbg);
        })
    }
}
halcomp_module!(pub MODULE, EoffsetPerAngleComp, "compute external offset per angle");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, S32, U32};

    #[test]
    fn offset_functions() {
        let s = Shape {
            radius_ref: 10.0,
            rfraction: 0.1,
            fmult: 4.0,
            ..Default::default()
        };
        // Inside square: the start angle is the middle of a flat (offset
        // rfraction * radius), 45 degrees on is a corner.
        let flat = offset(&s).unwrap();
        let corner = offset(&Shape { angle: 45.0, ..s }).unwrap();
        assert!((flat - 1.0).abs() < 1e-12, "{flat}");
        assert!(corner > flat);
        // Sinusoid: zero at the start, full amplitude half a period on.
        let w = Shape { fnum: 2, ..s };
        assert!(offset(&w).unwrap().abs() < 1e-12);
        assert!((offset(&Shape { angle: 45.0, ..w }).unwrap() - 1.0).abs() < 1e-12);
        let sq = Shape { fnum: 3, ..s };
        assert_eq!(offset(&Shape { angle: 30.0, ..sq }).unwrap(), 1.0);
        assert_eq!(offset(&Shape { angle: 10.0, ..sq }).unwrap(), 0.0);
        assert_eq!(offset(&Shape { fmult: 2.0, ..s }), None);
        assert_eq!(
            offset(&Shape {
                fnum: 9,
                fmult: 2.0,
                ..s
            }),
            None,
            "unknown is 0"
        );
    }

    #[test]
    fn state_machine_runs_stops_and_needs_a_low_enable_first() {
        let mut e = EoffsetPerAngle::default();
        let mut v = EoffsetVars {
            is_on: true,
            enable_in: true,
            k: 0,
            shape: Shape {
                fnum: 2,
                radius_ref: 1.0,
                rfraction: 0.1,
                fmult: 1.0,
                angle: 180.0,
                ..Default::default()
            },
            ..Default::default()
        };
        assert_eq!(e.step(&mut v), Some(0), "enabled at start: refused");
        assert_eq!(e.step(&mut v), None);
        assert_eq!(e.state, State::Off);
        v.enable_in = false;
        e.step(&mut v);
        assert_eq!(e.state, State::Ready);
        v.enable_in = true;
        e.step(&mut v);
        e.step(&mut v);
        assert!(v.enable_out);
        // 0.1 amplitude at 180 degrees, 10000 counts per unit.
        assert_eq!(v.kcounts, 1000);
        assert_eq!(v.kreciprocal, f64::from(1.0f32 / 10000.0));
        v.enable_in = false;
        e.step(&mut v);
        assert!(v.clear && v.kcounts == 0 && e.state == State::Stopping);
        v.active = true;
        e.step(&mut v);
        v.active = false;
        e.step(&mut v);
        e.step(&mut v);
        assert_eq!(e.state, State::Ready);
        assert!(!v.clear && !v.enable_out);
        v.is_on = false;
        e.step(&mut v);
        assert!(v.is_off && e.state == State::Off);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("eoffset-angle");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "eoffset-per-angle.0",
            &[
                "active bit in 0",
                "is-on bit in 0",
                "enable-in bit in 0",
                "radius-ref float in 1",
                "angle float in 0",
                "start-angle float in 0",
                "fnum s32 in 0",
                "rfraction float in 0.1",
                "fmult float in 6",
                "k u32 in 10000",
                "is-off bit out 0",
                "enable-out bit out 0",
                "clear bit out 0",
                "kcounts s32 out 0",
                "kreciprocal float out 0",
                "eoffset-dbg float out 0",
                "state-dbg u32 out 0",
            ],
        );
        h.thread(&["eoffset-per-angle.0"]);
        h.expect(&[], "eoffset-per-angle.0.is-off", Bit(true));
        h.set("eoffset-per-angle.0.is-on", Bit(true));
        h.run(2);
        h.set("eoffset-per-angle.0.fnum", S32(3));
        h.set("eoffset-per-angle.0.angle", Float(30.0));
        h.expect(
            &[("eoffset-per-angle.0.enable-in", Bit(true))],
            "eoffset-per-angle.0.enable-out",
            Bit(true),
        );
        assert_eq!(h.get("eoffset-per-angle.0.kcounts"), S32(1000));
        assert_eq!(h.get("eoffset-per-angle.0.state-dbg"), U32(2));
    }
}
