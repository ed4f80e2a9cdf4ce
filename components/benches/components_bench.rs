//! Prints the cost of the motion components' realtime functions in ns per
//! invocation: `stepgen.make-pulses` (3 channels), `encoder.update-counters`
//! (3 channels) and one pid loop's `do-pid-calcs`.
//!
//! Part 1 calls the components' host-free entry points directly
//! (stepgen's host-free [`Stepgen`], the encoder's [`Counter`], pid's
//! [`Pid::step`]),
//! so it measures the per-call logic alone. Part 2 loads the real modules
//! into a [`Host`] and runs them in a thread, reading each function's
//! `.time` pin every cycle: that adds the pin reads and writes of the HAL
//! glue and the executor's own timing reads.
//!
//! `cargo bench -p hal-components` runs both (about 10 s);
//! `cargo bench -p hal-components -- quick` runs part 1 only.

use std::hint::black_box;
use std::time::{Duration, Instant};

use hal_components::encoder::encoder::{Counter, CounterInputs, Link};
use hal_components::encoder::quadrature::QuadMode;
use hal_components::pid::control::{Pid, PidIo};
use hal_components::stepgen::model::Stepgen;
use hal_components::stepgen::pulses::PICKOFF;
use hal_components::stepgen::steptype::StepType;
use hal_components::stepgen::ChannelConfig;
use hal_core::*;

/// Base-thread period the host-free stepgen and encoder passes assume (ns).
const BASE_NS: i64 = 50_000;
/// Servo period the host-free pid calls assume (ns).
const SERVO_NS: i64 = 1_000_000;
/// Timed rounds per figure; the table shows the best and the median.
const ROUNDS: usize = 7;

fn main() -> Result<()> {
    let quick = std::env::args().any(|a| a == "quick");
    println!("components benchmark: ns per invocation");
    println!("\n1. host-free entry points ({ROUNDS} rounds each)");
    println!(
        "  {:<44} {:>10} {:>8} {:>8}",
        "function", "calls", "best", "median"
    );
    row(
        "stepgen.make-pulses, 3 type-0 channels",
        20_000_000,
        stepgen_pass(),
    );
    row(
        "encoder.update-counters, 3 channels",
        20_000_000,
        encoder_pass(),
    );
    row("pid do-pid-calcs, 1 loop", 20_000_000, pid_call());
    if !quick {
        through_host()?;
    }
    Ok(())
}

/// Times `calls` invocations of `f` in each of [`ROUNDS`] rounds (after
/// one untimed warm-up round) and prints the best and median ns per call.
fn row(label: &str, calls: u64, mut f: impl FnMut(u64)) {
    f(calls / 10);
    let mut per_call: Vec<f64> = (0..ROUNDS)
        .map(|_| {
            let t = Instant::now();
            f(calls);
            t.elapsed().as_nanos() as f64 / calls as f64
        })
        .collect();
    per_call.sort_by(f64::total_cmp);
    println!(
        "  {label:<44} {calls:>10} {:>8.2} {:>8.2}",
        per_call[0],
        per_call[ROUNDS / 2]
    );
}

/// A make-pulses pass over three type-0 channels stepping at different
/// rates (one step per 3, 4 and 5 calls), each reversing every 4096 calls
/// so that the ramp, the direction hold and the timers all get exercised.
fn stepgen_pass() -> impl FnMut(u64) {
    let step0 = ChannelConfig {
        step_type: StepType::builtin(0).expect("type 0 exists"),
        velocity_mode: false,
    };
    let mut sg = Stepgen::new(&[step0; 3]);
    for (i, c) in (0..).zip(sg.chans.iter_mut()) {
        c.enable = true;
        c.params.steplen = BASE_NS as u32;
        c.params.hold = BASE_NS as u32;
        c.params.setup = BASE_NS as u32;
        c.dds.target_addval = (1i64 << PICKOFF) / (3 + i);
        c.dds.deltalim = 1 << 22;
    }
    let mut n: u64 = 0;
    move |calls| {
        let mut steps = 0;
        for _ in 0..calls {
            n += 1;
            if n % 4096 == 0 {
                for c in sg.chans.iter_mut() {
                    c.dds.target_addval = -c.dds.target_addval;
                }
            }
            steps += black_box(&mut sg).make_pulses(black_box(BASE_NS));
        }
        black_box(steps);
    }
}

/// An update-counters pass over three channels (x4, x1 and counter mode)
/// fed one quadrature state per call: 32 edges forward, then 32 back, with
/// an index pulse once per sweep; the index is re-armed as
/// capture-position would.
fn encoder_pass() -> impl FnMut(u64) {
    const FORWARD: [(bool, bool); 4] = [(false, false), (true, false), (true, true), (false, true)];
    let sweep: Vec<(bool, bool, bool)> = (0..64)
        .map(|i: usize| {
            let phase = if i < 32 { i % 4 } else { (64 - i) % 4 };
            let (a, b) = FORWARD[phase];
            (a, b, i == 16)
        })
        .collect();
    let inputs = [QuadMode::X4, QuadMode::X1, QuadMode::Counter].map(|mode| CounterInputs {
        mode,
        ..CounterInputs::default()
    });
    let mut counters = [Counter::new(); 3];
    let mut links = [Link::default(); 3];
    let mut raw = [0i32; 3];
    let mut timebase = 0u32;
    let mut k = 0usize;
    move |calls| {
        for _ in 0..calls {
            let (a, b, z) = sweep[k & 63];
            k = k.wrapping_add(1);
            for ch in 0..3 {
                let mut inp = inputs[ch];
                inp.phase_a = a;
                inp.phase_b = b;
                inp.phase_z = z;
                counters[ch].update(
                    black_box(&inp),
                    &mut raw[ch],
                    &mut links[ch],
                    timebase,
                    black_box(BASE_NS),
                );
                if !z {
                    links[ch].index_armed = true;
                }
            }
            timebase = timebase.wrapping_add(BASE_NS as u32);
        }
        black_box((raw, links));
    }
}

/// One pid loop (P, I, D, FF1 and an output limit) closed around an
/// integrator plant, following a command that sweeps a 1024-point sine.
fn pid_call() -> impl FnMut(u64) {
    let wave: Vec<f64> = (0..1024)
        .map(|i| (i as f64 * std::f64::consts::TAU / 1024.0).sin())
        .collect();
    let mut io = PidIo {
        enable: true,
        pgain: 50.0,
        igain: 10.0,
        dgain: 0.01,
        ff1: 1.0,
        maxoutput: 100.0,
        maxerror_i: 1.0,
        ..PidIo::default()
    };
    let mut pid = Pid::new();
    // The derivative pins' own storage, as when they are unconnected.
    let (mut cmd_d, mut fb_d) = (0.0f64, 0.0f64);
    let t = SERVO_NS as f64 * 1e-9;
    let mut k = 0usize;
    move |calls| {
        for _ in 0..calls {
            io.command = wave[k & 1023];
            k = k.wrapping_add(1);
            pid.step(black_box(&mut io), black_box(SERVO_NS), |est| {
                if let Some((c, f)) = est {
                    cmd_d = c;
                    fb_d = f;
                }
                (cmd_d, fb_d)
            });
            io.feedback += io.output * t;
        }
        black_box(&io);
    }
}

/// Part 2: the real functions in a host thread, timed by their `.time`
/// pins.
// Long on purpose: one host, its wiring and the timed run read as one
// scenario; the wiring and the recorder share the host and its names.
fn through_host() -> Result<()> {
    const PERIOD_NS: i64 = 100_000;
    const RUN: Duration = Duration::from_secs(3);
    let name = format!("comp-bench-{}", std::process::id());
    let host = Host::create(HostConfig::new(&name))?;
    let inst = host.instance();
    host.loadrt(&hal_components::stepgen::MODULE, &["step_type=0,0,0"])?;
    host.loadrt(&hal_components::encoder::encoder::MODULE, &["num_chan=3"])?;
    host.loadrt(&hal_components::pid::control::MODULE, &["num_chan=1"])?;

    // A driver that moves the stepgen commands, feeds the encoders a
    // quadrature sweep and closes the pid loop around an integrator, and
    // a recorder that copies the three functions' `.time` pins to a ring.
    const TIMED: [&str; 3] = [
        "stepgen.make-pulses",
        "encoder.update-counters",
        "pid.0.do-pid-calcs",
    ];
    let mut b = host.new_rt_component("bench")?;
    let c = b.component();
    let pos_cmd: Vec<Pin<f64, Out>> = (0..3)
        .map(|i| c.pin(&format!("bench.pos-cmd.{i}")))
        .collect::<Result<_>>()?;
    let phase_a: Pin<bool, Out> = c.pin("bench.phase-A")?;
    let phase_b: Pin<bool, Out> = c.pin("bench.phase-B")?;
    let pid_cmd: Pin<f64, Out> = c.pin("bench.pid-cmd")?;
    let pid_fb: Pin<f64, Out> = c.pin("bench.pid-fb")?;
    let pid_out: Pin<f64, In> = c.pin("bench.pid-out")?;
    let times: Vec<Pin<i32, In>> = (0..TIMED.len())
        .map(|i| c.pin(&format!("bench.time.{i}")))
        .collect::<Result<_>>()?;
    let mut ring = RingWriter::create(c, "bench.times", 1 << 16, TIMED.len())?;
    let mut cycle: u64 = 0;
    b.funct("bench.drive", true, move |ctx| {
        cycle += 1;
        let x = cycle as f64 * ctx.fperiod();
        for (i, p) in pos_cmd.iter().enumerate() {
            p.set((x * (1.0 + i as f64)).sin());
        }
        let phase = (cycle / 3) % 8;
        let q = if phase < 4 { phase } else { 7 - phase };
        phase_a.set(q == 1 || q == 2);
        phase_b.set(q >= 2);
        pid_cmd.set(x.sin());
        pid_fb.set(pid_fb.get() + pid_out.get() * ctx.fperiod());
    })?;
    b.funct("bench.record", false, move |_| {
        let mut rec = [0u64; TIMED.len()];
        for (r, t) in rec.iter_mut().zip(&times) {
            *r = t.get().max(0) as u64;
        }
        ring.push(&rec);
    })?;
    b.ready()?;

    let net = |sig: &str, t: HalType, pins: &[&str]| -> Result<()> {
        inst.newsig(sig, t)?;
        pins.iter().try_for_each(|p| inst.link(p, sig))
    };
    for i in 0..3 {
        net(
            &format!("pos-cmd-{i}"),
            HalType::Float,
            &[
                &format!("bench.pos-cmd.{i}"),
                &format!("stepgen.{i}.position-cmd"),
            ],
        )?;
        inst.set_pin(&format!("stepgen.{i}.enable"), Value::Bit(true))?;
        inst.set_param(&format!("stepgen.{i}.position-scale"), Value::Float(1000.0))?;
        inst.set_param(&format!("stepgen.{i}.maxaccel"), Value::Float(1000.0))?;
    }
    for (sig, pin) in [("phase-A", "phase-A"), ("phase-B", "phase-B")] {
        let pins: Vec<String> = std::iter::once(format!("bench.{pin}"))
            .chain((0..3).map(|i| format!("encoder.{i}.{pin}")))
            .collect();
        net(
            sig,
            HalType::Bit,
            &pins.iter().map(String::as_str).collect::<Vec<_>>(),
        )?;
    }
    inst.set_pin("encoder.1.x4-mode", Value::Bit(false))?;
    inst.set_pin("encoder.2.counter-mode", Value::Bit(true))?;
    net(
        "pid-cmd",
        HalType::Float,
        &["bench.pid-cmd", "pid.0.command"],
    )?;
    net(
        "pid-fb",
        HalType::Float,
        &["bench.pid-fb", "pid.0.feedback"],
    )?;
    net(
        "pid-out",
        HalType::Float,
        &["pid.0.output", "bench.pid-out"],
    )?;
    inst.set_pin("pid.0.enable", Value::Bit(true))?;
    inst.set_pin("pid.0.Pgain", Value::Float(50.0))?;
    inst.set_pin("pid.0.Igain", Value::Float(10.0))?;
    inst.set_pin("pid.0.FF1", Value::Float(1.0))?;
    for (i, f) in TIMED.iter().enumerate() {
        net(
            &format!("time-{i}"),
            HalType::S32,
            &[&format!("{f}.time"), &format!("bench.time.{i}")],
        )?;
    }

    host.create_thread("bench", PERIOD_NS, true, None)?;
    for f in [
        "bench.drive",
        "stepgen.update-freq",
        "stepgen.make-pulses",
        "stepgen.capture-position",
        "encoder.update-counters",
        "encoder.capture-position",
        "pid.0.do-pid-calcs",
        "bench.record",
    ] {
        host.addf(f, "bench", -1)?;
    }
    let mut reader = RingReader::open(inst, "bench.times")?;
    host.set_function_timing(true);
    host.start()?;
    std::thread::sleep(RUN);
    host.stop();

    let mut cols: Vec<Vec<u64>> = vec![Vec::new(); TIMED.len()];
    let mut rec = [0u64; TIMED.len()];
    let mut cycles = 0usize;
    while reader.pop(&mut rec) {
        cycles += 1;
        // The first cycles fault pages in and report 0 (no previous run).
        if cycles > 10 {
            for (c, v) in cols.iter_mut().zip(rec) {
                c.push(v);
            }
        }
    }
    println!(
        "\n2. real functions in a {} us host thread, from their .time pins \
         ({cycles} cycles, realtime: {})",
        PERIOD_NS / 1000,
        host.is_realtime()
    );
    println!(
        "  {:<44} {:>8} {:>8} {:>8}",
        "function", "min", "median", "p99"
    );
    for (f, mut v) in TIMED.iter().zip(cols) {
        if v.is_empty() {
            println!("  {f:<44} no cycles ran");
            continue;
        }
        v.sort_unstable();
        println!(
            "  {f:<44} {:>8} {:>8} {:>8}",
            v[0],
            v[v.len() / 2],
            v[v.len() * 99 / 100]
        );
    }
    println!("  (times include the executor's clock read per function)");
    host.shutdown();
    Ok(())
}
