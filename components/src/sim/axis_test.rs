//! `steptest` and `axistest`: move one axis back and forth for the
//! configuration wizards (StepConf, PnCConf) to try its speed and
//! acceleration. With `run`, the command alternates between `run-low`
//! and `run-high` around the starting feedback (`dir`: 0 both ways, 1
//! up only, 2 down only), pausing `pause` seconds at each end; when
//! `run` drops it returns to the start. Otherwise `jog-plus`/`jog-minus`
//! lead the feedback (steptest by two periods at `maxvel`, axistest by
//! 10 units).

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The pin and param values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisTestVars {
    /// Pin `jog-minus`.
    pub jog_minus: bool,
    /// Pin `jog-plus`.
    pub jog_plus: bool,
    /// Pin `run`.
    pub run: bool,
    /// Pin `amplitude`.
    pub amplitude: f64,
    /// Pin `dir`.
    pub dir: i32,
    /// Pin `position-cmd` (read back).
    pub position_cmd: f64,
    /// Pin `position-fb`.
    pub position_fb: f64,
    /// Pin `running` (read back).
    pub running: bool,
    /// Pin `run-start` (read back).
    pub run_start: f64,
    /// Pin `run-low` (read back).
    pub run_low: f64,
    /// Pin `run-high` (read back).
    pub run_high: f64,
    /// Pin `pause` (seconds).
    pub pause: i32,
    /// Param `epsilon`.
    pub epsilon: f64,
    /// Param `elapsed`.
    pub elapsed: f64,
}

/// The state between calls.
#[derive(Debug, Clone, Default)]
pub struct AxisTest {
    timer: f64,
    timer_on: bool,
}

impl AxisTest {
    /// One call `fperiod` seconds after the last; `jog` is how far a jog
    /// leads the feedback.
    pub fn step(&mut self, v: &mut AxisTestVars, fperiod: f64, jog: f64) {
        if self.timer_on {
            self.timer += fperiod;
        }
        v.elapsed = self.timer;
        if v.run {
            if !v.running {
                v.running = true;
                v.run_start = v.position_fb;
                v.run_high = if v.dir == 2 {
                    v.run_start
                } else {
                    v.run_start + v.amplitude
                };
                v.run_low = if v.dir == 1 {
                    v.run_start
                } else {
                    v.run_start - v.amplitude
                };
                v.position_cmd = v.run_low;
            }
            let at_end = v.position_cmd == v.run_low || v.position_cmd == v.run_high;
            if (v.position_fb - v.position_cmd).abs() < v.epsilon && at_end {
                if !self.timer_on {
                    self.timer = 0.0;
                    self.timer_on = true;
                } else if self.timer >= f64::from(v.pause) {
                    self.timer_on = false;
                    v.position_cmd = if v.position_cmd == v.run_low {
                        v.run_high
                    } else {
                        v.run_low
                    };
                }
            }
        } else if v.running {
            v.position_cmd = v.run_start;
            if (v.position_fb - v.run_start).abs() < v.epsilon {
                v.running = false;
                self.timer_on = false;
            }
        } else if v.jog_minus {
            v.position_cmd = v.position_fb - jog;
        } else if v.jog_plus {
            v.position_cmd = v.position_fb + jog;
        } else {
            v.position_cmd = v.position_fb;
        }
    }
}

/// Builds an instance; `steptest` adds `maxaccel` and leads by two
/// periods at `maxvel`, `axistest` leads by 10.
fn build(inst: &mut Inst<'_, '_>, steptest: bool) -> Result<()> {
    let jog_minus = inst.pin_in::<bool>("jog-minus")?;
    let jog_plus = inst.pin_in::<bool>("jog-plus")?;
    let run = inst.pin_in::<bool>("run")?;
    let maxvel = inst.pin_in::<f64>("maxvel")?;
    // steptest declares it for the wizard; the motion here never reads it.
    let _maxaccel = if steptest {
        Some(inst.pin_in::<f64>("maxaccel")?)
    } else {
        None
    };
    let amplitude = inst.pin_in::<f64>("amplitude")?;
    let dir = inst.pin_in::<i32>("dir")?;
    let position_cmd = inst.pin_out::<f64>("position-cmd")?;
    let position_fb = inst.pin_in::<f64>("position-fb")?;
    let running = inst.pin_out::<bool>("running")?;
    let _run_target = inst.pin_out::<f64>("run-target")?;
    let run_start = inst.pin_out::<f64>("run-start")?;
    let run_low = inst.pin_out::<f64>("run-low")?;
    let run_high = inst.pin_out::<f64>("run-high")?;
    let pause = inst.pin_in::<i32>("pause")?;
    let epsilon = inst.param_rw::<f64>("epsilon", 0.001)?;
    let elapsed = inst.param_ro::<f64>("elapsed", 0.0)?;
    let mut t = AxisTest::default();
    let name = if steptest { "_" } else { "update" };
    inst.funct(name, true, move |ctx| {
        let mut v = AxisTestVars {
            jog_minus: jog_minus.get(),
            jog_plus: jog_plus.get(),
            run: run.get(),
            amplitude: amplitude.get(),
            dir: dir.get(),
            position_cmd: position_cmd.get(),
            position_fb: position_fb.get(),
            running: running.get(),
            run_start: run_start.get(),
            run_low: run_low.get(),
            run_high: run_high.get(),
            pause: pause.get(),
            epsilon: epsilon.get(),
            elapsed: elapsed.get(),
        };
        let jog = if steptest {
            2.0 * maxvel.get() * ctx.fperiod()
        } else {
            10.0
        };
        t.step(&mut v, ctx.fperiod(), jog);
        elapsed.set(v.elapsed);
        running.set(v.running);
        run_start.set(v.run_start);
        run_high.set(v.run_high);
        run_low.set(v.run_low);
        position_cmd.set(v.position_cmd);
    })
}

/// The `steptest` component.
pub struct Steptest;
impl HalComp for Steptest {
    const NAME: &'static str = "steptest";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        build(inst, true)
    }
}
halcomp_module!(pub STEPTEST, Steptest, "test acceleration and velocity of an axis (StepConf)");

/// The `axistest` component.
pub struct Axistest;
impl HalComp for Axistest {
    const NAME: &'static str = "axistest";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        build(inst, false)
    }
}
halcomp_module!(pub AXISTEST, Axistest, "test an axis (PnCConf)");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn run_alternates_between_the_ends_with_pauses() {
        let mut t = AxisTest::default();
        let mut v = AxisTestVars {
            run: true,
            amplitude: 2.0,
            position_fb: 5.0,
            pause: 1,
            epsilon: 0.001,
            ..Default::default()
        };
        t.step(&mut v, 0.5, 0.0);
        assert!(v.running);
        assert_eq!((v.run_low, v.run_high, v.position_cmd), (3.0, 7.0, 3.0));
        v.position_fb = 3.0;
        t.step(&mut v, 0.5, 0.0); // arrived: the pause starts
        t.step(&mut v, 0.5, 0.0);
        assert_eq!(v.position_cmd, 3.0, "still pausing");
        t.step(&mut v, 0.5, 0.0);
        assert_eq!(v.position_cmd, 7.0, "a second later: the other end");
        // Stop: back to the start, then idle.
        v.run = false;
        t.step(&mut v, 0.5, 0.0);
        assert_eq!(v.position_cmd, 5.0);
        v.position_fb = 5.0;
        t.step(&mut v, 0.5, 0.0);
        assert!(!v.running);
    }

    #[test]
    fn one_sided_runs_and_jogs() {
        let mut t = AxisTest::default();
        let mut v = AxisTestVars {
            run: true,
            amplitude: 1.0,
            dir: 1,
            ..Default::default()
        };
        t.step(&mut v, 0.001, 0.0);
        assert_eq!((v.run_low, v.run_high), (0.0, 1.0));
        let mut v = AxisTestVars {
            jog_plus: true,
            position_fb: 2.0,
            ..Default::default()
        };
        t.step(&mut v, 0.001, 0.5);
        assert_eq!(v.position_cmd, 2.5);
    }

    #[test]
    fn pins_and_functions() {
        let mut h = TestHost::new("axistest");
        h.load(&STEPTEST, &[]).unwrap();
        h.load(&AXISTEST, &[]).unwrap();
        let common = [
            "jog-minus bit in 0",
            "jog-plus bit in 0",
            "run bit in 0",
            "maxvel float in 0",
            "amplitude float in 0",
            "dir s32 in 0",
            "position-cmd float out 0",
            "position-fb float in 0",
            "running bit out 0",
            "run-target float out 0",
            "run-start float out 0",
            "run-low float out 0",
            "run-high float out 0",
            "pause s32 in 0",
        ];
        h.check_pins("axistest.0", &common);
        let mut with_accel = common.to_vec();
        with_accel.push("maxaccel float in 0");
        h.check_pins("steptest.0", &with_accel);
        h.check_params(
            "steptest.0",
            &["epsilon float rw 0.001", "elapsed float ro 0"],
        );
        assert_eq!(h.functs(), ["axistest.0.update", "steptest.0"]);
        h.thread(&["axistest.0.update"]);
        h.set("axistest.0.position-fb", Float(1.0));
        h.expect(
            &[("axistest.0.jog-minus", Bit(true))],
            "axistest.0.position-cmd",
            Float(-9.0),
        );
    }
}
