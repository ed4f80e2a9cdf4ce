//! lcec on the simulated segment: three CiA 402 drives in CSP and six
//! terminals (EL1008, EL2008, EL3102, EL4102, EL5101, EL7041) behind an
//! EK1100, `lcec.0.read` and `lcec.0.write` in a 1 ms servo thread of a
//! HAL host. Prints the time of each function and of the servo thread
//! (the executor's own `.time` pins, ns: the servo thread's cost per
//! period; the frames themselves travel in the master's helper thread,
//! which the realtime functions only hand data to), and the frames the
//! master sends per period.
//!
//! The `.time` pins are wall time, so they also count what preempts or
//! interrupts the thread and its cache misses on a loaded machine; the
//! CPU the servo thread used (the kernel's schedstat of `hal-servo`,
//! its wake-ups and the executor included) is printed per period too,
//! with that of a thread of the same period and no function. The two
//! wake at the same deadlines, and the first to run pays the switch
//! into this process from whatever ran before (on a virtual machine a
//! large part of the servo thread's figure), so their difference is
//! not what `read` and `write` cost: the `.time` pins say that.
//!
//! `cargo bench -p hal-ethercat --bench lcec_bench`. The pins are read
//! from this thread about once per period, so the figures are a sample
//! of the periods, not every one. Realtime scheduling is used where the
//! process may; the output says which, with the load average.
#![allow(
    clippy::unwrap_used,
    reason = "benchmark code: a failed unwrap stops the run"
)]

use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, MsgLevel, RealtimeMode, Value};
use hal_ethercat::hal::MODULE;
use hal_ethercat::link::SharedSegment;

const SAMPLES: usize = 5000;

const CONF: &str = r#"<masters>
  <master idx="0" appTimePeriod="1000000" refClockSyncCycles="1000">
    <slave idx="0" type="EK1100" name="coupler"/>
    <slave idx="1" type="EL1008" name="din"/>
    <slave idx="2" type="EL2008" name="dout"/>
    <slave idx="3" type="EL3102" name="ain"/>
    <slave idx="4" type="EL4102" name="aout"/>
    <slave idx="5" type="EL5101" name="enc"/>
    <slave idx="6" type="EL7041" name="stepper"/>
    <slave idx="7" type="basic_cia402" vid="00000e5c" pid="00000402" name="x">
      <modParam name="mode" value="csp"/>
    </slave>
    <slave idx="8" type="basic_cia402" vid="00000e5c" pid="00000402" name="y">
      <modParam name="mode" value="csp"/>
    </slave>
    <slave idx="9" type="basic_cia402" vid="00000e5c" pid="00000402" name="z">
      <modParam name="mode" value="csp"/>
    </slave>
  </master>
</masters>
"#;

fn int(host: &Host, name: &str) -> i64 {
    match host.instance().pin_value(name).unwrap() {
        Value::S32(v) => i64::from(v),
        Value::U32(v) => i64::from(v),
        Value::S64(v) => v,
        Value::U64(v) => v as i64,
        Value::Bit(b) => i64::from(b),
        v => panic!("{name} is {v:?}"),
    }
}

fn wait(what: &str, mut cond: impl FnMut() -> bool) {
    let end = Instant::now() + Duration::from_secs(60);
    while !cond() {
        assert!(Instant::now() < end, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// CPU time (ns) the thread named `comm` of this process has run, from
/// /proc/self/task/*/schedstat; None where the kernel gives none.
fn thread_cpu_ns(comm: &str) -> Option<u64> {
    for task in std::fs::read_dir("/proc/self/task").ok()?.flatten() {
        let p = task.path();
        if std::fs::read_to_string(p.join("comm")).ok()?.trim() == comm {
            let stat = std::fs::read_to_string(p.join("schedstat")).ok()?;
            return stat.split_whitespace().next()?.parse().ok();
        }
    }
    None
}

fn percentile(sorted: &[i64], p: f64) -> i64 {
    let i = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

fn main() {
    let dir = std::env::temp_dir().join(format!("lcec-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let conf = dir.join("ethercat-conf.xml");
    std::fs::write(&conf, CONF).unwrap();

    // SCHED_FIFO where the process may (the helper thread and the
    // simulator are ordinary threads and cannot preempt the servo thread).
    let mut config = HostConfig::for_tests("lcec-bench");
    config.realtime = RealtimeMode::Auto;
    let host = Host::create(config).unwrap();
    host.rt_log().set_level(MsgLevel::Err);
    host.loadrt(
        &MODULE,
        &[&format!("config={}", conf.display()), "backend=sim"],
    )
    .unwrap();
    let seg: SharedSegment = hal_driver::sim::find(host.instance().name(), "lcec.0").unwrap();
    host.create_thread("servo", 1_000_000, true, None).unwrap();
    // A thread with no function: what waking every period costs alone.
    host.create_thread("empty", 1_000_000, true, None).unwrap();
    host.addf("lcec.0.read", "servo", -1).unwrap();
    host.addf("lcec.0.write", "servo", -1).unwrap();
    host.start().unwrap();
    wait("all slaves in OP", || int(&host, "lcec.0.all-op") == 1);
    let inst = host.instance();
    for axis in ["x", "y", "z"] {
        inst.set_pin(&format!("lcec.0.{axis}.srv-enable"), Value::Bit(true))
            .unwrap();
    }
    for axis in ["x", "y", "z"] {
        wait("the drives enabled", || {
            int(&host, &format!("lcec.0.{axis}.srv-enabled")) == 1
        });
    }
    inst.set_pin("lcec.0.aout.aout-0-enable", Value::Bit(true))
        .unwrap();
    inst.set_pin("lcec.0.aout.aout-0-value", Value::Float(0.5))
        .unwrap();
    std::thread::sleep(Duration::from_millis(500));

    let (frames0, _) = seg.lock().unwrap().counters();
    let beat0 = int(&host, "servo.threadbeat");
    let cpu0 = thread_cpu_ns("hal-servo");
    let empty0 = thread_cpu_ns("hal-empty");
    let (mut read, mut write, mut thread) = (
        Vec::with_capacity(SAMPLES),
        Vec::with_capacity(SAMPLES),
        Vec::with_capacity(SAMPLES),
    );
    for _ in 0..SAMPLES {
        read.push(int(&host, "lcec.0.read.time"));
        write.push(int(&host, "lcec.0.write.time"));
        thread.push(int(&host, "servo.time"));
        std::thread::sleep(Duration::from_micros(1000));
    }
    let (frames1, dropped) = seg.lock().unwrap().counters();
    let beat1 = int(&host, "servo.threadbeat");
    let cpu1 = thread_cpu_ns("hal-servo");
    let empty1 = thread_cpu_ns("hal-empty");
    let wkc = int(&host, "lcec.0.wkc");
    host.stop();

    let periods = (beat1 - beat0).max(1);
    println!(
        "lcec on the simulated segment: 3 CiA 402 drives (CSP, enabled), 6 terminals and a \
         coupler; 1 ms servo thread, {SAMPLES} samples over {periods} periods"
    );
    println!(
        "  realtime: {}; load average {}",
        if host.is_realtime() {
            "SCHED_FIFO"
        } else {
            "no (ordinary threads)"
        },
        std::fs::read_to_string("/proc/loadavg")
            .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
            .unwrap_or_default()
    );
    println!("  servo-thread time per period (ns)     median      p99      max");
    for (what, v) in [
        ("lcec.0.read", &mut read),
        ("lcec.0.write", &mut write),
        ("the thread (read + write)", &mut thread),
    ] {
        v.sort_unstable();
        println!(
            "  {what:<32} {:>9} {:>8} {:>8}",
            percentile(v, 0.5),
            percentile(v, 0.99),
            v.last().copied().unwrap_or(0)
        );
    }
    match (cpu0, cpu1, empty0, empty1) {
        (Some(a), Some(b), Some(c), Some(d)) => {
            let (servo, empty) = ((b - a) / periods as u64, (d - c) / periods as u64);
            println!(
                "  CPU per period (schedstat): servo thread {servo} ns, a thread with no function {empty} ns"
            );
        }
        _ => println!("  CPU per period: the kernel gives no schedstat"),
    }
    println!(
        "  frames per period {:.2} ({} frames, {} dropped); working counter {wkc}",
        (frames1 - frames0) as f64 / periods as f64,
        frames1 - frames0,
        dropped
    );
    let _ = std::fs::remove_dir_all(&dir);
}
