//! `syncToRefClock` on the simulated segment: the reference clock (the
//! EK1100) is made to run 400 ppm fast against the host, and the
//! master's application time follows it through lcec's PLL: `pll-err`
//! stays small where the drift alone would reach a period in 2.5 s,
//! `pll-out` is ±`pll-step`, and the application time gains on the
//! host's clock what the reference clock gains. A jump of the reference
//! clock past `pll-max-err` is taken out at once and counted in
//! `pll-reset-count`.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::PathBuf;
use std::time::{Duration, Instant};

mod common {
    pub mod wait;
}
use common::wait::wait;

use hal_core::{Host, HostConfig, MsgLevel, Value};
use hal_ethercat::hal::MODULE;
use hal_ethercat::link::SharedSegment;
use hal_ethercat::sim::control::Control;

const CONF: &str = r#"<masters>
  <master idx="0" appTimePeriod="4000000" refClockSyncCycles="1000" syncToRefClock="true">
    <slave idx="0" type="EK1100" name="coupler"/>
    <slave idx="1" type="EL1008" name="din"/>
  </master>
</masters>
"#;

const PPM: i64 = 400;
/// The servo period (ns): 4 ms, so that a loaded test machine's
/// scheduling (the master's helper thread is not realtime) stays well
/// inside `pll-max-err`.
const PERIOD: u64 = 4_000_000;

fn conf_file(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hal-ethercat-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("ethercat-conf.xml");
    std::fs::write(&p, CONF).unwrap();
    p
}

fn int(host: &Host, name: &str) -> i64 {
    match host.instance().pin_value(name).unwrap() {
        Value::S32(v) => i64::from(v),
        Value::U32(v) => i64::from(v),
        Value::Bit(b) => i64::from(b),
        v => panic!("{name} is {v:?}"),
    }
}

/// The cycle's (application time, CLOCK_MONOTONIC time) from the four
/// u32 pins, read until two reads agree (the servo thread writes them
/// once a period).
fn times(host: &Host) -> (i64, i64) {
    let read = || {
        let w = |n: &str| int(host, &format!("lcec.0.{n}"));
        (
            w("app-time-hi") << 32 | w("app-time-lo"),
            w("mono-time-hi") << 32 | w("mono-time-lo"),
        )
    };
    loop {
        let (a, b) = (read(), read());
        if a == b {
            return a;
        }
    }
}

/// `pll-err` (absolute, sorted) sampled about every 2 ms for `span`,
/// and how many of the samples had `pll-out` at ±`pll-step` (the others
/// must be 0: a cycle whose frame came late is not compared).
fn errors(host: &Host, span: Duration) -> (Vec<i64>, usize) {
    let end = Instant::now() + span;
    let mut v = Vec::new();
    let mut stepped = 0;
    while Instant::now() < end {
        v.push(int(host, "lcec.0.pll-err").abs());
        match int(host, "lcec.0.pll-out") {
            4000 | -4000 => stepped += 1,
            0 => {}
            out => panic!("pll-out {out}: neither ±pll-step nor 0"),
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    v.sort_unstable();
    (v, stepped)
}

fn control(seg: &SharedSegment, c: Control) {
    c.apply(&mut seg.lock().unwrap()).unwrap();
}

#[test]
fn the_application_time_follows_a_drifting_reference_clock() {
    let conf = conf_file("pll");
    let host = Host::create(HostConfig::for_tests("lcec-pll")).unwrap();
    host.rt_log().set_level(MsgLevel::Err);
    host.loadrt(
        &MODULE,
        &[&format!("config={}", conf.display()), "backend=sim"],
    )
    .unwrap();
    let param = |n: &str| host.instance().param_value(n).unwrap();
    assert_eq!(
        param("lcec.0.pll-step"),
        Value::U32(4000),
        "0.1 % of the period"
    );
    assert_eq!(
        param("lcec.0.pll-max-err"),
        Value::U32(4_000_000),
        "one period"
    );
    let seg: SharedSegment = hal_driver::sim::find(host.instance().name(), "lcec.0").unwrap();
    host.create_thread("servo", PERIOD as i64, true, None)
        .unwrap();
    host.addf("lcec.0.read", "servo", -1).unwrap();
    host.addf("lcec.0.write", "servo", -1).unwrap();
    host.start().unwrap();
    wait("all slaves in OP", || int(&host, "lcec.0.all-op") == 1);
    wait("the PLL comparing", || int(&host, "lcec.0.pll-out") != 0);

    // The reference clock runs 400 ppm fast: 1.6 µs a period, 1 ms in
    // 2.5 s if nothing followed it.
    control(&seg, Control::Drift(0, PPM));
    std::thread::sleep(Duration::from_millis(500));
    let resets0 = int(&host, "lcec.0.pll-reset-count");
    let (app0, mono0) = times(&host);
    let (errs, stepped) = errors(&host, Duration::from_secs(3));
    let (app1, mono1) = times(&host);
    let resets1 = int(&host, "lcec.0.pll-reset-count");
    let median = errs[errs.len() / 2];
    let worst = errs.last().copied().unwrap_or(0);
    let gained = (app1 - app0) - (mono1 - mono0);
    let expected = (mono1 - mono0) * PPM / 1_000_000;
    eprintln!(
        "pll: |pll-err| median {median} ns, worst {worst} ns over {} samples; \
         application time gained {gained} ns on the host in {} ms (the reference: {expected} ns); \
         resets {resets0} -> {resets1}; pll-out ±step in {stepped} samples",
        errs.len(),
        (mono1 - mono0) / 1_000_000
    );
    assert!(
        median <= 100_000,
        "pll-err median {median} ns: the application time does not follow"
    );
    assert!(
        (gained - expected).abs() <= 300_000,
        "the application time gained {gained} ns on the host, the reference clock {expected} ns"
    );
    assert!(
        resets1 - resets0 <= 2,
        "{} resets while following a 400 ppm drift",
        resets1 - resets0
    );
    assert!(
        stepped * 2 >= errs.len(),
        "pll-out at ±pll-step in only {stepped} of {} samples",
        errs.len()
    );

    // A jump of 5 periods is past pll-max-err: taken out at once and
    // counted, and the error is small again after.
    control(&seg, Control::ClockStep(0, 5 * PERIOD as i64));
    wait("the reset counted", || {
        int(&host, "lcec.0.pll-reset-count") > resets1
    });
    // Converged again within a few seconds: on a loaded machine the
    // helper thread (not realtime) can take its sample of the reference
    // late around the jump, and the controller then walks the rest out
    // at pll-step a period (4 µs in 4 ms: 1 ms a second).
    let deadline = Instant::now() + Duration::from_secs(5);
    let median = loop {
        let (errs, _) = errors(&host, Duration::from_millis(250));
        let median = errs[errs.len() / 2];
        if median <= 100_000 || Instant::now() > deadline {
            break median;
        }
    };
    assert!(median <= 100_000, "after the reset: median {median} ns");

    host.stop();
    host.unloadrt("lcec").unwrap();
    let _ = std::fs::remove_dir_all(conf.parent().unwrap());
}
