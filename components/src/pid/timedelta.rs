//! `timedelta`: measures the real time between successive runs of its
//! function against the thread's nominal period (a halcompile-style
//! component: `count=`/`names=`, one function `<prefix>` per instance).

use std::sync::atomic::{AtomicI32, Ordering::Relaxed};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Out, Pin, Result};

use crate::halcomp::{self, instance_names};

/// The `timedelta` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "timedelta",
    params: halcomp::PARAMS,
    help: "measures the jitter of the thread its function runs in",
    load,
};

/// The values of an instance's pins that a call reads or writes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimeDeltaIo {
    /// `out`: the last measured interval (ns).
    pub out: i32,
    /// `err`: the running sum of (interval - period) (ns).
    pub err: i32,
    /// `min`: the shortest interval since the last reset.
    pub min: i32,
    /// `max`: the longest interval since the last reset.
    pub max: i32,
    /// `jitter`: the largest deviation of `min` or `max` from the period.
    pub jitter: i32,
    /// `current-jitter`: |interval - period| of the last call.
    pub current_jitter: i32,
    /// `current-error`: interval - period of the last call.
    pub current_error: i32,
    /// `avg-err`: `err` divided by the call counter.
    pub avg_err: f64,
    /// `reset` (in): start measuring afresh.
    pub reset: bool,
}

/// One instance's state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TimeDelta {
    /// Time of the previous call (ns), 0 before the first and after reset.
    pub last: i64,
    /// Whether the next measured interval is the first.
    pub first: bool,
}

impl Default for TimeDelta {
    fn default() -> Self {
        TimeDelta {
            last: 0,
            first: true,
        }
    }
}

impl TimeDelta {
    /// One call at time `now` (ns) in a thread of period `period` (ns).
    /// `counter` is the call counter `avg-err` divides by; LinuxCNC
    /// shares it between all instances of a load (see [`load`]).
    pub fn step(&mut self, io: &mut TimeDeltaIo, now: i64, period: i64, counter: &AtomicI32) {
        if self.last != 0 {
            let d = now.wrapping_sub(self.last);
            io.out = d as i32;
            io.err = (io.err as i64).wrapping_add(d).wrapping_sub(period) as i32;
            if self.first {
                self.first = false;
                io.min = d as i32;
                io.max = d as i32;
                io.jitter = 0;
            } else {
                if d < io.min as i64 {
                    io.min = d as i32;
                }
                if d > io.max as i64 {
                    io.max = d as i32;
                }
                io.jitter = (io.max as i64 - period).max(period - io.min as i64) as i32;
                io.current_jitter = (d - period).max(period - d) as i32;
                io.current_error = (d - period) as i32;
            }
            let k = counter.fetch_add(1, Relaxed).wrapping_add(1);
            io.avg_err = io.err as f64 / k as f64;
        }
        if io.reset {
            self.first = true;
            self.last = 0;
            io.out = 0;
            io.jitter = 0;
            io.max = 0;
        } else {
            self.last = now;
        }
    }
}

/// The pins of one instance.
struct Pins {
    jitter: Pin<i32, Out>,
    current_jitter: Pin<i32, Out>,
    current_error: Pin<i32, Out>,
    min: Pin<i32, Out>,
    max: Pin<i32, Out>,
    reset: Pin<bool, In>,
    out: Pin<i32, Out>,
    err: Pin<i32, Out>,
    avg_err: Pin<f64, Out>,
}

impl Pins {
    fn read(&self) -> TimeDeltaIo {
        TimeDeltaIo {
            out: self.out.get(),
            err: self.err.get(),
            min: self.min.get(),
            max: self.max.get(),
            jitter: self.jitter.get(),
            current_jitter: self.current_jitter.get(),
            current_error: self.current_error.get(),
            avg_err: self.avg_err.get(),
            reset: self.reset.get(),
        }
    }

    fn write(&self, io: &TimeDeltaIo) {
        self.out.set(io.out);
        self.err.set(io.err);
        self.min.set(io.min);
        self.max.set(io.max);
        self.jitter.set(io.jitter);
        self.current_jitter.set(io.current_jitter);
        self.current_error.set(io.current_error);
        self.avg_err.set(io.avg_err);
    }
}

/// Loads the instances. The counter `avg-err` divides by is, as in
/// LinuxCNC, the module's `count` variable: shared by every instance of
/// the load and starting at the instance count (0 with `names=`).
fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let names = instance_names(MODULE.name, args)?;
    let by_names = args.str("names").is_some_and(|n| !n.is_empty());
    let start = if by_names { 0 } else { names.len() as i32 };
    let counter = Arc::new(AtomicI32::new(start));
    let mut b = host.new_rt_component(MODULE.name)?;
    for prefix in &names {
        let c = b.component();
        let p = |item: &str| format!("{prefix}.{item}");
        let pins = Pins {
            jitter: c.pin(&p("jitter"))?,
            current_jitter: c.pin(&p("current-jitter"))?,
            current_error: c.pin(&p("current-error"))?,
            min: c.pin(&p("min"))?,
            max: c.pin(&p("max"))?,
            reset: c.pin(&p("reset"))?,
            out: c.pin(&p("out"))?,
            err: c.pin(&p("err"))?,
            avg_err: c.pin(&p("avg-err"))?,
        };
        let counter = counter.clone();
        let mut state = TimeDelta::default();
        b.funct(prefix, true, move |ctx| {
            let mut io = pins.read();
            // The cycle's wake-up time: no clock call in realtime code.
            let now = ctx.now_ns() as i64;
            state.step(&mut io, now, ctx.period(), &counter);
            pins.write(&io);
        })?;
    }
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::host;

    const P: i64 = 1_000_000;

    #[test]
    fn first_call_only_records_the_time() {
        let mut td = TimeDelta::default();
        let mut io = TimeDeltaIo::default();
        let k = AtomicI32::new(1);
        td.step(&mut io, 5_000, P, &k);
        assert_eq!(io, TimeDeltaIo::default());
        assert_eq!(td.last, 5_000);
        assert!(td.first);
        assert_eq!(k.load(Relaxed), 1);
    }

    #[test]
    fn measures_intervals_jitter_and_error() {
        let mut td = TimeDelta::default();
        let mut io = TimeDeltaIo::default();
        let k = AtomicI32::new(1);
        td.step(&mut io, 10_000_000, P, &k);
        // First interval: min = max = d, jitter 0, current-* untouched.
        td.step(&mut io, 11_000_100, P, &k);
        assert_eq!(
            (io.out, io.err, io.min, io.max, io.jitter),
            (1_000_100, 100, 1_000_100, 1_000_100, 0)
        );
        assert_eq!((io.current_jitter, io.current_error), (0, 0));
        assert_eq!(io.avg_err, 100.0 / 2.0);
        // A short interval: min drops, jitter = period - min.
        td.step(&mut io, 11_999_800, P, &k);
        assert_eq!(
            (io.out, io.err, io.min, io.max),
            (999_700, -200, 999_700, 1_000_100)
        );
        assert_eq!(
            (io.jitter, io.current_jitter, io.current_error),
            (300, 300, -300)
        );
        assert_eq!(io.avg_err, -200.0 / 3.0);
        // A long interval: max rises, jitter = max - period.
        td.step(&mut io, 13_000_300, P, &k);
        assert_eq!(
            (io.out, io.err, io.min, io.max),
            (1_000_500, 300, 999_700, 1_000_500)
        );
        assert_eq!(
            (io.jitter, io.current_jitter, io.current_error),
            (500, 500, 500)
        );
        assert_eq!(io.avg_err, 300.0 / 4.0);
    }

    #[test]
    fn reset_restarts_min_max_but_keeps_err_and_counter() {
        let mut td = TimeDelta::default();
        let mut io = TimeDeltaIo::default();
        let k = AtomicI32::new(0);
        td.step(&mut io, 1_000, P, &k);
        td.step(&mut io, 1_001_000, P, &k);
        td.step(&mut io, 2_000_000, P, &k);
        assert_eq!((io.min, io.max, io.err), (999_000, 1_000_000, -1_000));
        io.reset = true;
        td.step(&mut io, 3_000_500, P, &k);
        // The interval is still measured, then out/jitter/max are cleared.
        assert_eq!((io.out, io.jitter, io.max, io.min), (0, 0, 0, 999_000));
        assert_eq!(io.err, -500);
        assert_eq!((td.last, td.first), (0, true));
        // While reset is held nothing is measured.
        td.step(&mut io, 4_000_000, P, &k);
        assert_eq!((io.out, io.err, k.load(Relaxed)), (0, -500, 3));
        io.reset = false;
        td.step(&mut io, 5_000_000, P, &k);
        td.step(&mut io, 6_000_200, P, &k);
        assert_eq!(
            (io.out, io.min, io.max, io.jitter),
            (1_000_200, 1_000_200, 1_000_200, 0)
        );
        assert_eq!(io.err, -300);
        assert_eq!(io.avg_err, -300.0 / 4.0);
    }

    #[test]
    fn err_and_out_wrap_like_s32() {
        let mut td = TimeDelta::default();
        let mut io = TimeDeltaIo {
            err: i32::MAX,
            ..Default::default()
        };
        let k = AtomicI32::new(i32::MAX);
        td.step(&mut io, 1, P, &k);
        // An interval of 2^32 + 5 ns: out keeps the low 32 bits.
        td.step(&mut io, 1 + (1 << 32) + 5, P, &k);
        assert_eq!(io.out, 5);
        let want = (i32::MAX as i64 + (1 << 32) + 5 - P) as i32;
        assert_eq!(io.err, want);
        // The counter wraps too (C int with -fwrapv).
        assert_eq!(k.load(Relaxed), i32::MIN);
        assert_eq!(io.avg_err, want as f64 / i32::MIN as f64);
    }

    fn load_args(h: &Host, args: &[&str]) -> Result<()> {
        h.loadrt(&MODULE, args)
    }

    #[test]
    fn loads_halcompile_style_instances() {
        let h = host();
        load_args(&h, &["count=2"]).unwrap();
        let inst = h.instance();
        let mut pins: Vec<String> = inst
            .pins()
            .unwrap()
            .into_iter()
            .map(|p| p.name)
            .filter(|n| n.starts_with("timedelta.1."))
            .collect();
        pins.sort();
        assert_eq!(
            pins,
            [
                "timedelta.1.avg-err",
                "timedelta.1.current-error",
                "timedelta.1.current-jitter",
                "timedelta.1.err",
                "timedelta.1.jitter",
                "timedelta.1.max",
                "timedelta.1.min",
                "timedelta.1.out",
                "timedelta.1.reset",
                "timedelta.1.time",
            ]
        );
        let functs: Vec<String> = inst.functs().unwrap().into_iter().map(|f| f.name).collect();
        assert_eq!(functs, ["timedelta.0", "timedelta.1"]);

        let h = host();
        load_args(&h, &["names=td"]).unwrap();
        h.create_thread("t", 1_000_000, true, None).unwrap();
        h.addf("td", "t", -1).unwrap();
        h.start().unwrap();
        let inst = h.instance();
        let s32 = |n: &str| match inst.pin_value(n).unwrap() {
            hal_core::Value::S32(v) => v,
            other => panic!("{other:?}"),
        };
        let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
        while s32("td.max") == 0 || s32("td.out") == 0 {
            assert!(std::time::Instant::now() < end, "timedelta never measured");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        h.stop();
        assert!(s32("td.min") > 0 && s32("td.min") <= s32("td.max"));

        let h = host();
        assert!(load_args(&h, &["count=2", "names=a"]).is_err());
        assert!(h.instance().pins().unwrap().is_empty());
    }
}
