//! `sim_home_switch`: a home switch for a simulated joint. The switch
//! closes when the position reaches `home-pos` (from either side: a
//! negative `home-pos` puts the switch on the negative side) and opens
//! again only after travelling back by `hysteresis`. It also clears
//! `index-enable` `index-delay-ms` after motion sets it, as an encoder
//! passing its index would.

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::timing::write_changed;

/// The pin values one call reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SimHomeSwitchVars {
    /// Pin `cur-pos`.
    pub cur_pos: f64,
    /// Pin `home-pos`.
    pub home_pos: f64,
    /// Pin `hysteresis`.
    pub hysteresis: f64,
    /// Pin `home-sw` (read back).
    pub home_sw: bool,
    /// Pin `index-enable` (I/O).
    pub index_enable: bool,
    /// Pin `index-delay-ms`.
    pub index_delay_ms: f64,
}

/// Per-instance state.
#[derive(Debug, Clone, Default)]
pub struct SimHomeSwitch {
    /// `index-enable` at the end of the previous call.
    old_index_enable: bool,
    /// Milliseconds left before `index-enable` is cleared (0: idle).
    index_timer_ms: f64,
}

impl SimHomeSwitch {
    /// One call of a thread of `period_ns`.
    pub fn step(&mut self, v: &mut SimHomeSwitchVars, period_ns: i64) {
        v.home_sw = if v.home_pos >= 0.0 {
            if v.cur_pos >= v.home_pos {
                true
            } else if v.cur_pos <= v.home_pos - v.hysteresis {
                false
            } else {
                v.home_sw
            }
        } else if v.cur_pos <= v.home_pos {
            true
        } else if v.cur_pos >= v.home_pos + v.hysteresis {
            false
        } else {
            v.home_sw
        };

        if self.index_timer_ms > 0.0 {
            self.index_timer_ms -= period_ns as f64 * 1e-6;
            if self.index_timer_ms <= 0.0 {
                self.index_timer_ms = 0.0;
                v.index_enable = false;
                // The edge memory is not updated on this call (as in
                // LinuxCNC): it still says TRUE, so index-enable set again
                // before one call has seen it FALSE is not a new edge.
                return;
            }
        }
        if v.index_enable && !self.old_index_enable {
            self.index_timer_ms = v.index_delay_ms;
        }
        self.old_index_enable = v.index_enable;
    }
}

/// The `sim_home_switch` component.
pub struct SimHomeSwitchComp;
impl HalComp for SimHomeSwitchComp {
    const NAME: &'static str = "sim_home_switch";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let cur_pos = inst.pin_in::<f64>("cur-pos")?;
        let home_pos = inst.pin_in_init::<f64>("home-pos", 1.0)?;
        let hysteresis = inst.pin_in_init::<f64>("hysteresis", 0.1)?;
        let home_sw = inst.pin_out::<bool>("home-sw")?;
        let index_enable = inst.pin_io::<bool>("index-enable", false)?;
        let index_delay_ms = inst.pin_in_init::<f64>("index-delay-ms", 10.0)?;
        let mut state = SimHomeSwitch::default();
        inst.funct("_", true, move |ctx| {
            let old = SimHomeSwitchVars {
                cur_pos: cur_pos.get(),
                home_pos: home_pos.get(),
                hysteresis: hysteresis.get(),
                home_sw: home_sw.get(),
                index_enable: index_enable.get(),
                index_delay_ms: index_delay_ms.get(),
            };
            let mut v = old;
            state.step(&mut v, ctx.period());
            write_changed(&home_sw, old.home_sw, v.home_sw);
            write_changed(&index_enable, old.index_enable, v.index_enable);
        })
    }
}
halcomp_module!(pub MODULE, SimHomeSwitchComp, "home switch simulator");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    fn vars(home_pos: f64) -> SimHomeSwitchVars {
        SimHomeSwitchVars {
            home_pos,
            hysteresis: 0.1,
            index_delay_ms: 10.0,
            ..Default::default()
        }
    }

    fn at(s: &mut SimHomeSwitch, v: &mut SimHomeSwitchVars, pos: f64) -> bool {
        v.cur_pos = pos;
        s.step(v, 1_000_000);
        v.home_sw
    }

    #[test]
    fn positive_switch_has_hysteresis() {
        let (mut s, mut v) = (SimHomeSwitch::default(), vars(1.0));
        assert!(!at(&mut s, &mut v, 0.5));
        assert!(at(&mut s, &mut v, 1.0), "closes at home-pos");
        assert!(at(&mut s, &mut v, 0.95), "stays closed inside the band");
        assert!(at(&mut s, &mut v, 0.91));
        assert!(!at(&mut s, &mut v, 0.9), "opens at home-pos - hysteresis");
        assert!(!at(&mut s, &mut v, 0.95), "stays open inside the band");
    }

    #[test]
    fn negative_switch_mirrors() {
        let (mut s, mut v) = (SimHomeSwitch::default(), vars(-2.0));
        assert!(!at(&mut s, &mut v, 0.0));
        assert!(at(&mut s, &mut v, -2.5));
        assert!(at(&mut s, &mut v, -1.95));
        assert!(!at(&mut s, &mut v, -1.9));
        // home-pos 0 counts as the positive side.
        let (mut s, mut v) = (SimHomeSwitch::default(), vars(0.0));
        assert!(at(&mut s, &mut v, 0.0));
    }

    #[test]
    fn index_enable_clears_after_the_delay() {
        let (mut s, mut v) = (SimHomeSwitch::default(), vars(1.0));
        v.index_delay_ms = 2.5;
        v.index_enable = true;
        // Edge: the timer starts at 2.5 ms; 1 ms periods.
        let mut calls = 0;
        while v.index_enable {
            s.step(&mut v, 1_000_000);
            calls += 1;
            assert!(calls < 10);
        }
        // Calls 2 and 3 count down to 0.5 ms, call 4 reaches zero.
        assert_eq!(calls, 4);
        // Set again at once: the edge memory still says TRUE, so this is
        // no edge and the timer stays idle.
        v.index_enable = true;
        s.step(&mut v, 1_000_000);
        assert!(v.index_enable);
        assert_eq!(s.index_timer_ms, 0.0);
        // After one call that sees it FALSE, setting it is an edge again.
        v.index_enable = false;
        s.step(&mut v, 1_000_000);
        v.index_enable = true;
        s.step(&mut v, 1_000_000);
        assert_eq!(s.index_timer_ms, 2.5);
    }

    #[test]
    fn pins_and_a_run() {
        let mut h = TestHost::new("simhome");
        h.load(&MODULE, &["names=sw"]).unwrap();
        h.check_pins(
            "sw",
            &[
                "cur-pos float in 0",
                "home-pos float in 1",
                "hysteresis float in 0.1",
                "home-sw bit out 0",
                "index-enable bit io 0",
                "index-delay-ms float in 10",
            ],
        );
        h.check_params("sw", &[]);
        assert_eq!(h.functs(), ["sw"]);
        h.thread(&["sw"]);
        h.expect(&[("sw.cur-pos", Float(1.5))], "sw.home-sw", Bit(true));
        h.set("sw.index-delay-ms", Float(0.5));
        h.expect(
            &[("sw.index-enable", Bit(true))],
            "sw.index-enable",
            Bit(false),
        );
        h.check_load_fails(&MODULE, &["count=1", "names=x"]);
    }
}
