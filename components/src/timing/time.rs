//! `time`: a cycle timer showing how long `start` has been TRUE (not
//! counting while `pause` is TRUE) in hours, minutes and seconds. A
//! rising edge of `start` restarts it from zero.

use hal_core::Result;

use crate::cmath::f64_to_u32;
use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// The timer's state.
#[derive(Debug, Clone, Default)]
pub struct CycleTimer {
    total_ns: f64,
    old_start: bool,
}

impl CycleTimer {
    /// One call of a thread of `period` ns. Returns (hours, minutes,
    /// seconds) when they are updated.
    pub fn step(&mut self, start: bool, pause: bool, period: i64) -> Option<(u32, u32, u32)> {
        if start && !self.old_start {
            self.total_ns = 0.0;
        }
        self.old_start = start;
        if start && !pause {
            self.total_ns += period as f64;
            let s = f64_to_u32(self.total_ns * 0.000000001);
            Some((s / 3600, (s / 60) % 60, s % 60))
        } else {
            None
        }
    }
}

/// The `time` component.
pub struct Time;
impl HalComp for Time {
    const NAME: &'static str = "time";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let start = inst.pin_in::<bool>("start")?;
        let pause = inst.pin_in::<bool>("pause")?;
        let seconds = inst.pin_out::<u32>("seconds")?;
        let minutes = inst.pin_out::<u32>("minutes")?;
        let hours = inst.pin_out::<u32>("hours")?;
        let mut t = CycleTimer::default();
        inst.funct("_", true, move |ctx| {
            if let Some((h, m, s)) = t.step(start.get(), pause.get(), ctx.period()) {
                seconds.set(s);
                minutes.set(m);
                hours.set(h);
            }
        })
    }
}
halcomp_module!(pub MODULE, Time, "time on in hours, minutes, seconds");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, U32};

    #[test]
    fn counts_running_time_and_restarts_on_an_edge() {
        let mut t = CycleTimer::default();
        let hour = 3_600_000_000_000;
        assert_eq!(t.step(false, false, hour), None);
        assert_eq!(t.step(true, false, hour + 61_000_000_000), Some((1, 1, 1)));
        // Paused: frozen, then counting on.
        assert_eq!(t.step(true, true, hour), None);
        assert_eq!(t.step(true, false, 1_000_000_000), Some((1, 1, 2)));
        // A new start edge restarts.
        t.step(false, false, 1);
        assert_eq!(t.step(true, false, 59_000_000_000), Some((0, 0, 59)));
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("time");
        h.load(&MODULE, &[]).unwrap();
        h.check_pins(
            "time.0",
            &[
                "start bit in 0",
                "pause bit in 0",
                "seconds u32 out 0",
                "minutes u32 out 0",
                "hours u32 out 0",
            ],
        );
        h.thread(&["time.0"]);
        h.expect(&[("time.0.start", Bit(true))], "time.0.hours", U32(0));
    }
}
