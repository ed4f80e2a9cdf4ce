//! `spindle_monitor`: spindle at-speed and under-speed detection. Once
//! the spindle is on and the feedback comes within `threshold` of the
//! command, `spindle-at-speed` sets; after that, falling more than
//! `threshold` below the command sets `spindle-underspeed` (until the
//! spindle is turned off).

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The pin and param values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MonitorVars {
    /// Pin `spindle-is-on`.
    pub is_on: bool,
    /// Pin `spindle-command`.
    pub command: f64,
    /// Pin `spindle-feedback`.
    pub feedback: f64,
    /// Pin `spindle-at-speed` (read back).
    pub at_speed: bool,
    /// Pin `spindle-underspeed` (read back).
    pub underspeed: bool,
    /// Param `level`: 0 idle, 1 spinning up, 2 monitoring.
    pub level: u32,
    /// Param `threshold`.
    pub threshold: f64,
}

/// One call.
pub fn monitor(v: &mut MonitorVars) {
    match v.level {
        0 => {
            v.at_speed = false;
            v.underspeed = false;
            if v.is_on {
                v.level = 1;
            }
        }
        1 => {
            if !v.is_on {
                v.level = 0;
            } else if (v.command - v.feedback).abs() < v.threshold {
                v.level = 2;
                v.at_speed = true;
            }
        }
        2 => {
            if !v.is_on {
                v.level = 0;
            } else if v.command - v.feedback > v.threshold {
                v.underspeed = true;
            }
        }
        _ => v.level = 0,
    }
}

/// The `spindle_monitor` component.
pub struct SpindleMonitor;
impl HalComp for SpindleMonitor {
    const NAME: &'static str = "spindle_monitor";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let is_on = inst.pin_in::<bool>("spindle-is-on")?;
        let command = inst.pin_in::<f64>("spindle-command")?;
        let feedback = inst.pin_in::<f64>("spindle-feedback")?;
        let at_speed = inst.pin_out::<bool>("spindle-at-speed")?;
        let underspeed = inst.pin_out::<bool>("spindle-underspeed")?;
        let level = inst.param_rw::<u32>("level", 0)?;
        let threshold = inst.param_rw::<f64>("threshold", 0.0)?;
        inst.funct("_", true, move |_| {
            let mut v = MonitorVars {
                is_on: is_on.get(),
                command: command.get(),
                feedback: feedback.get(),
                at_speed: at_speed.get(),
                underspeed: underspeed.get(),
                level: level.get(),
                threshold: threshold.get(),
            };
            monitor(&mut v);
            at_speed.set(v.at_speed);
            underspeed.set(v.underspeed);
            level.set(v.level);
        })
    }
}
halcomp_module!(pub MODULE, SpindleMonitor, "spindle at-speed and underspeed detection");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float, U32};

    #[test]
    fn at_speed_then_underspeed() {
        let mut v = MonitorVars {
            is_on: true,
            command: 1000.0,
            feedback: 0.0,
            threshold: 50.0,
            ..Default::default()
        };
        monitor(&mut v);
        monitor(&mut v);
        assert_eq!((v.level, v.at_speed), (1, false));
        v.feedback = 980.0;
        monitor(&mut v);
        assert_eq!((v.level, v.at_speed), (2, true));
        v.feedback = 900.0;
        monitor(&mut v);
        assert!(v.underspeed && v.at_speed);
        v.is_on = false;
        monitor(&mut v);
        monitor(&mut v);
        assert!(!v.underspeed && !v.at_speed && v.level == 0);
        v.level = 7;
        monitor(&mut v);
        assert_eq!(v.level, 0);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("spindle-monitor");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "spindle-monitor.0",
            &[
                "spindle-is-on bit in 0",
                "spindle-command float in 0",
                "spindle-feedback float in 0",
                "spindle-at-speed bit out 0",
                "spindle-underspeed bit out 0",
            ],
        );
        h.check_params(
            "spindle-monitor.0",
            &["level u32 rw 0", "threshold float rw 0"],
        );
        h.thread(&["spindle-monitor.0"]);
        h.setp("spindle-monitor.0.threshold", Float(1.0));
        h.expect(
            &[("spindle-monitor.0.spindle-is-on", Bit(true))],
            "spindle-monitor.0.spindle-at-speed",
            Bit(true),
        );
        assert_eq!(h.getp("spindle-monitor.0.level"), U32(2));
    }
}
