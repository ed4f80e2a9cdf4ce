//! A small simulated machine on the HAL core alone: a 50 us base thread
//! turns a commanded velocity into step pulses, a 1 ms servo thread ramps a
//! position command and follows it, and a motor model counts steps back
//! into positions. Runs for two seconds and prints what happened.
//!
//! This stands in for `configs/sim/` until halrun and the parport driver
//! exist; the README runs it.

use hal_core::*;

const SCALE: f64 = 200.0; // steps per unit
const TARGETS: [f64; 3] = [10.0, -4.0, 2.5];

// Long on purpose: the example reads top to bottom as a tutorial (servo,
// stepgen, motor, wiring, run), each part using the pins the last made.
fn main() -> Result<()> {
    let instance = format!("sim-demo-{}", std::process::id());
    let host = Host::create(HostConfig::new(&instance))?;
    let inst = host.instance().clone();

    // Servo side: per axis, a ramp toward the target, velocity command out.
    let mut servo = host.new_rt_component("servo")?;
    let mut base = host.new_rt_component("stepgen")?;
    let mut motor = host.new_rt_component("motor")?;
    for (axis, target) in TARGETS.iter().enumerate() {
        let c = servo.component();
        let tgt: Pin<f64, In> = c.pin_init(&format!("servo.{axis}.target"), *target)?;
        let fb: Pin<f64, In> = c.pin(&format!("servo.{axis}.position-fb"))?;
        let vel: Pin<f64, Out> = c.pin(&format!("servo.{axis}.velocity-cmd"))?;
        let gain: Param<f64, Rw> = c.param(&format!("servo.{axis}.p-gain"), 20.0)?;
        let maxvel: Param<f64, Rw> = c.param(&format!("servo.{axis}.max-vel"), 15.0)?;
        servo.funct(&format!("servo.{axis}.update"), true, move |_| {
            let v = (gain.get() * (tgt.get() - fb.get())).clamp(-maxvel.get(), maxvel.get());
            vel.set(v);
        })?;

        let c = base.component();
        let vcmd: Pin<f64, In> = c.pin(&format!("stepgen.{axis}.velocity-cmd"))?;
        let step: Pin<bool, Out> = c.pin(&format!("stepgen.{axis}.step"))?;
        let dir: Pin<bool, Out> = c.pin(&format!("stepgen.{axis}.dir"))?;
        let mut accum = 0.0f64;
        base.funct(&format!("stepgen.{axis}.make-pulses"), true, move |ctx| {
            if step.get() {
                step.set(false); // pulses last one base period
                return;
            }
            accum += vcmd.get() * SCALE * ctx.fperiod();
            if accum.abs() >= 1.0 {
                dir.set(accum < 0.0);
                step.set(true);
                accum -= accum.signum();
            }
        })?;

        let c = motor.component();
        let step_in: Pin<bool, In> = c.pin(&format!("motor.{axis}.step"))?;
        let dir_in: Pin<bool, In> = c.pin(&format!("motor.{axis}.dir"))?;
        let counts: Pin<i64, Out> = c.pin(&format!("motor.{axis}.counts"))?;
        let pos: Pin<f64, Out> = c.pin(&format!("motor.{axis}.position"))?;
        let mut last = false;
        motor.funct(&format!("motor.{axis}.update"), true, move |_| {
            let s = step_in.get();
            if s && !last {
                counts.set(counts.get() + if dir_in.get() { -1 } else { 1 });
                pos.set(counts.get() as f64 / SCALE);
            }
            last = s;
        })?;
    }
    servo.ready()?;
    base.ready()?;
    motor.ready()?;

    for axis in 0..TARGETS.len() {
        let net = |sig: &str, t: HalType, pins: &[String]| -> Result<()> {
            inst.newsig(sig, t)?;
            pins.iter().try_for_each(|p| inst.link(p, sig))
        };
        net(
            &format!("vel-{axis}"),
            HalType::Float,
            &[
                format!("servo.{axis}.velocity-cmd"),
                format!("stepgen.{axis}.velocity-cmd"),
            ],
        )?;
        net(
            &format!("step-{axis}"),
            HalType::Bit,
            &[format!("stepgen.{axis}.step"), format!("motor.{axis}.step")],
        )?;
        net(
            &format!("dir-{axis}"),
            HalType::Bit,
            &[format!("stepgen.{axis}.dir"), format!("motor.{axis}.dir")],
        )?;
        net(
            &format!("pos-fb-{axis}"),
            HalType::Float,
            &[
                format!("motor.{axis}.position"),
                format!("servo.{axis}.position-fb"),
            ],
        )?;
    }

    host.create_thread("base-thread", 50_000, true, None)?;
    host.create_thread("servo-thread", 1_000_000, true, None)?;
    for axis in 0..TARGETS.len() {
        host.addf(&format!("stepgen.{axis}.make-pulses"), "base-thread", -1)?;
        host.addf(&format!("motor.{axis}.update"), "base-thread", -1)?;
        host.addf(&format!("servo.{axis}.update"), "servo-thread", -1)?;
    }
    println!(
        "instance '{instance}': 3 axes, base thread 50 us, servo thread 1 ms, realtime: {}",
        host.is_realtime()
    );
    host.start()?;
    std::thread::sleep(std::time::Duration::from_secs(2));
    host.stop();

    println!("\naxis   target   reached    steps");
    for (axis, target) in TARGETS.iter().enumerate() {
        let pos = inst.pin_value(&format!("motor.{axis}.position"))?;
        let counts = inst.pin_value(&format!("motor.{axis}.counts"))?;
        if let (Value::Float(p), Value::S64(c)) = (pos, counts) {
            println!("{axis:>4} {target:>8.3} {p:>9.3} {c:>8}");
        }
    }
    println!(
        "\nthread           period   cycles  overruns  time(ns)  tmax(ns)  latency min/max (us)"
    );
    for t in inst.threads()? {
        println!(
            "{:<14} {:>8} {:>8} {:>9} {:>9} {:>9}  {:.1}/{:.1}",
            t.name,
            t.period,
            t.cycles,
            t.overruns,
            t.time_ns,
            t.tmax_ns,
            t.latency_min_ns.unwrap_or(0) as f64 / 1000.0,
            t.latency_max_ns.unwrap_or(0) as f64 / 1000.0
        );
    }
    Ok(())
}
