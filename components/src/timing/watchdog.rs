//! `watchdog`: watches up to 32 heartbeat inputs. Each must change state
//! within its `timeout-N` (seconds); if one does not, `ok-out` drops and
//! stays FALSE until `enable-in` rises again. `watchdog.set-timeouts`
//! (slow thread) takes the timeouts and handles `enable-in`;
//! `watchdog.process` (fast thread) watches the inputs.
//!
//! `loadrt watchdog num_inputs=N` (required, 1 to 32) makes one
//! instance named `watchdog`.

use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Param, Pin, Result, Rw};

use crate::shared::Exclusive;

/// Most inputs.
pub const MAX_INPUTS: i64 = 32;

/// The timers of one input, in whole seconds and nanoseconds as LinuxCNC
/// keeps them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Timer {
    old_timeout: f64,
    count_secs: i32,
    count_nsecs: i32,
    timeout_secs: i32,
    timeout_nsecs: i32,
    last: bool,
}

/// The watchdog's state, shared by its two functions.
#[derive(Debug, Clone)]
pub struct Watchdog {
    timers: Vec<Timer>,
    old_enable: bool,
}

impl Watchdog {
    /// A watchdog of `n` inputs, all FALSE so far.
    pub fn new(n: usize) -> Watchdog {
        Watchdog {
            timers: vec![
                Timer {
                    old_timeout: -1.0,
                    ..Timer::default()
                };
                n
            ],
            old_enable: false,
        }
    }

    /// `process`: `inputs` now, `ok` the current output, after `period`
    /// ns. Returns FALSE when an input timed out (the output must drop).
    pub fn process(&mut self, inputs: &[bool], enable: bool, ok: bool, period: i64) -> bool {
        if !enable || !ok {
            return ok;
        }
        let mut fault = false;
        for (t, &input) in self.timers.iter_mut().zip(inputs) {
            if input != t.last {
                t.count_secs = t.timeout_secs;
                t.count_nsecs = t.timeout_nsecs;
            } else {
                t.count_nsecs = (i64::from(t.count_nsecs) - period) as i32;
                if t.count_nsecs < 0 {
                    t.count_nsecs = t.count_nsecs.wrapping_add(1_000_000_000);
                    if t.count_secs > 0 {
                        t.count_secs -= 1;
                    } else {
                        fault = true;
                        t.count_secs = 0;
                        t.count_nsecs = 0;
                    }
                }
            }
            t.last = input;
        }
        !fault
    }

    /// `set-timeouts`: takes new timeouts; restarts the watchdog on a
    /// rising edge of `enable` while faulted. Returns the new output.
    pub fn set_timeouts(&mut self, timeouts: &[f64], enable: bool, ok: bool) -> bool {
        for (t, &timeout) in self.timers.iter_mut().zip(timeouts) {
            let timeout = if timeout < 0.0 { 0.0 } else { timeout };
            if timeout != t.old_timeout {
                t.old_timeout = timeout;
                t.timeout_secs = crate::cmath::f64_to_i32(timeout);
                t.timeout_nsecs =
                    crate::cmath::f64_to_i32(1e9 * (timeout - f64::from(t.timeout_secs)));
            }
        }
        let mut out = ok;
        if !ok && enable && !self.old_enable {
            for t in &mut self.timers {
                t.count_secs = t.timeout_secs;
                t.count_nsecs = t.timeout_nsecs;
            }
            out = true;
        }
        self.old_enable = enable;
        out
    }
}

/// The module parameters.
pub const PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "num_inputs",
    kind: ParamKind::Int,
    help: "number of inputs (1 to 32)",
}];

/// The `watchdog` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "watchdog",
    params: PARAMS,
    help: "monitor one to thirty-two inputs for a heartbeat",
    load,
};

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let n = match args.int("num_inputs") {
        Some(n) if (1..=MAX_INPUTS).contains(&n) => n as usize,
        other => {
            return Err(HalError::ModuleParam {
                module: "watchdog".into(),
                param: "num_inputs".into(),
                reason: match other {
                    None => "required: the number of inputs, 1 to 32".into(),
                    Some(n) => format!("{n} is out of range 1-{MAX_INPUTS}"),
                },
            })
        }
    };
    let mut b = host.new_rt_component("watchdog")?;
    let c = b.component();
    let mut inputs: Vec<Pin<bool, In>> = Vec::with_capacity(n);
    let mut timeouts: Vec<Param<f64, Rw>> = Vec::with_capacity(n);
    for i in 0..n {
        inputs.push(c.pin(&format!("watchdog.input-{i}"))?);
        timeouts.push(c.param(&format!("watchdog.timeout-{i}"), 0.0)?);
    }
    let ok_out = Arc::new(c.pin::<bool, hal_core::Out>("watchdog.ok-out")?);
    let enable = Arc::new(c.pin::<bool, In>("watchdog.enable-in")?);
    let state = Arc::new(Exclusive::new(Watchdog::new(n)));

    let (ok, en, st) = (ok_out.clone(), enable.clone(), state.clone());
    let mut now = vec![false; n];
    b.funct("watchdog.process", false, move |ctx| {
        for (v, p) in now.iter_mut().zip(&inputs) {
            *v = p.get();
        }
        let cur = ok.get();
        if let Some(out) = st.try_with(|w| w.process(&now, en.get(), cur, ctx.period())) {
            if out != cur {
                ok.set(out);
            }
        }
    })?;
    let mut values = vec![0.0; n];
    b.funct("watchdog.set-timeouts", false, move |_| {
        for (v, p) in values.iter_mut().zip(&timeouts) {
            *v = p.get();
        }
        let cur = ok_out.get();
        if let Some(out) = state.try_with(|w| w.set_timeouts(&values, enable.get(), cur)) {
            if out != cur {
                ok_out.set(out);
            }
        }
    })?;
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn a_stopped_heartbeat_trips_after_its_timeout() {
        let mut w = Watchdog::new(2);
        // 1.5 s and 0.25 s timeouts; enable rising arms it.
        let mut ok = w.set_timeouts(&[1.5, 0.25], true, false);
        assert!(ok);
        let mut beat = false;
        // Input 1 toggles every call (100 ms), input 0 stands still.
        let mut calls = 0;
        while ok {
            beat = !beat;
            ok = w.process(&[false, beat], true, ok, 100_000_000);
            calls += 1;
            assert!(calls < 100);
        }
        // 1.5 s counts down in 15 calls; the 16th finds it below zero.
        assert_eq!(calls, 16);
        // Stays tripped until enable rises again.
        assert!(!w.set_timeouts(&[1.5, 0.25], true, false));
        assert!(!w.set_timeouts(&[1.5, 0.25], false, false));
        assert!(w.set_timeouts(&[1.5, 0.25], true, false));
    }

    #[test]
    fn nothing_happens_while_disabled_or_tripped() {
        let mut w = Watchdog::new(1);
        assert!(w.process(&[false], false, true, 2_000_000_000));
        assert!(!w.process(&[false], true, false, 2_000_000_000));
    }

    #[test]
    fn pins_params_and_functions() {
        let mut h = TestHost::new("watchdog");
        h.check_load_fails(&MODULE, &[]);
        h.check_load_fails(&MODULE, &["num_inputs=33"]);
        h.check_load_fails(&MODULE, &["num_inputs=0"]);
        h.load(&MODULE, &["num_inputs=2"]).unwrap();
        h.check_pins(
            "watchdog",
            &[
                "input-0 bit in 0",
                "input-1 bit in 0",
                "ok-out bit out 0",
                "enable-in bit in 0",
            ],
        );
        h.check_params(
            "watchdog",
            &["timeout-0 float rw 0", "timeout-1 float rw 0"],
        );
        assert_eq!(h.functs(), ["watchdog.process", "watchdog.set-timeouts"]);
        h.thread(&["watchdog.set-timeouts", "watchdog.process"]);
        h.setp("watchdog.timeout-0", Float(10.0));
        h.setp("watchdog.timeout-1", Float(10.0));
        h.expect(
            &[("watchdog.enable-in", Bit(true))],
            "watchdog.ok-out",
            Bit(true),
        );
    }
}
