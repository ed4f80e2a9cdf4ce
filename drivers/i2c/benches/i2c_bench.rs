//! The realtime cost of the I2C hand-offs per cycle: what each chip's
//! `read` and `write` functions do (publish or take one value through a
//! triple buffer, and move it to or from the pins), while the helper
//! thread runs beside them on a simulated bus, as under `loadrt`.
//!
//! `cargo bench -p hal-i2c`. The realtime functions are the closures
//! `loadrt` exports; this binary runs the same steps on the same types
//! (the hand-off ends, canonical pins), plus the bare triple-buffer
//! operations for comparison.
#![allow(
    clippy::unwrap_used,
    reason = "benchmark code: a failed unwrap stops the run"
)]

use std::hint::black_box;
use std::sync::Arc;

use canonical::{AdcIn, ChannelNames, DigIn, DigOut, Pwm};
use hal_core::{Host, HostConfig, Value};
use hal_driver::bench::per_call;
use hal_driver::sim::SimClock;
use hal_i2c::chips::{
    AdcSample, AdcSettings, Ads1115Chip, Chip, DioCmd, Mcp23017Chip, Pca9685Chip, PwmCmd,
};
use hal_i2c::hal::StatusPins;
use hal_i2c::handoff::Handoff;
use hal_i2c::sim::{Ads1115, Mcp23017, Pca9685, SimBus};
use hal_i2c::worker::{ChipRunner, Task};

const N: u64 = 1_000_000;

// Long on purpose: a benchmark script, one figure after another on the
// same host and simulated bus.
fn main() {
    let host = Host::create(HostConfig::for_tests("i2c-bench")).expect("host");
    let b = host.new_rt_component("bench").expect("component");
    let c = b.component();

    println!("triple buffer alone ({N} calls each)");
    let mut h = Handoff::<PwmCmd, u16>::new();
    per_call("publish a 16-channel PWM command", N, |i| {
        let mut cmd = PwmCmd::default();
        cmd.counts[0] = i as u16;
        h.cmd_port.publish(black_box(cmd));
    });
    per_call("take the newest status", N, |_| {
        black_box(h.status_port.latest());
    });

    // A simulated bus with one chip of each kind and a helper thread
    // servicing them every millisecond, as under loadrt.
    let bus = Arc::new(SimBus::new(
        "bench bus",
        Arc::new(SimClock::following_thread()),
    ));
    bus.add_chip(0x40, Box::new(Pca9685::new()));
    bus.add_chip(0x20, Box::new(Mcp23017::new()));
    bus.add_chip(0x48, Box::new(Ads1115::new()));
    let mut pca = Pca9685Chip::new(0x40, 3, false, false);
    pca.init(&*bus, &PwmCmd::default()).expect("pca");
    let mut mcp = Mcp23017Chip::new(0x20, 0x7F00, 0);
    mcp.init(&*bus, &DioCmd::default()).expect("mcp");
    let settings = AdcSettings {
        channels: 4,
        differential: false,
        pga: 1,
        dr: 7,
    };
    let mut ads = Ads1115Chip::new(0x48, settings);
    ads.init(&*bus, &()).expect("ads");
    let (pca_run, mut pca_rt) = ChipRunner::new("pca9685.0", pca, host.rt_log());
    let (mcp_run, mut mcp_rt) = ChipRunner::new("mcp23017.0", mcp, host.rt_log());
    let (ads_run, mut ads_rt) = ChipRunner::new("ads1115.0", ads, host.rt_log());
    let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let helper = {
        let (bus, stop) = (bus.clone(), stop.clone());
        let tasks: Vec<Arc<dyn Task>> = vec![pca_run, mcp_run, ads_run];
        std::thread::spawn(move || {
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                let now = hal_core::clock::monotonic_ns();
                hal_i2c::bus::I2cBus::tick(&*bus, now);
                for t in &tasks {
                    t.service(&*bus, now);
                }
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
        })
    };

    let pwm_names = ChannelNames::canonical::<Pwm>("pca9685", 0, 16);
    let pwm: Vec<Pwm> = (0..16)
        .map(|ch| Pwm::export(c, &pwm_names, ch).unwrap())
        .collect();
    let pca_status = StatusPins::export(c, "pca9685.0").unwrap();
    for ch in 0..16 {
        host.instance()
            .set_pin(&pwm_names.item(ch, "enable"), Value::Bit(true))
            .unwrap();
    }
    let din = ChannelNames::canonical::<DigIn>("mcp23017", 0, 16);
    let dout = ChannelNames::canonical::<DigOut>("mcp23017", 0, 16);
    let inputs: Vec<(usize, DigIn)> = (8..15)
        .map(|p| (p, DigIn::export(c, &din, p).unwrap()))
        .collect();
    let outputs: Vec<(usize, DigOut)> = (0..8)
        .chain(15..16)
        .map(|p| (p, DigOut::export(c, &dout, p).unwrap()))
        .collect();
    let mcp_status = StatusPins::export(c, "mcp23017.0").unwrap();
    let adc_names = ChannelNames::canonical::<AdcIn>("ads1115", 0, 4);
    let adcs: Vec<AdcIn> = (0..4)
        .map(|ch| AdcIn::export(c, &adc_names, ch, settings.lsb_volts(), 0.0).unwrap())
        .collect();
    let ads_status = StatusPins::export(c, "ads1115.0").unwrap();

    println!("realtime function bodies, helper thread running ({N} calls each)");
    per_call("pca9685.N.write (16 PWM channels)", N, |_| {
        let mut out = PwmCmd::default();
        for (k, ch) in pwm.iter().enumerate() {
            out.counts[k] = PwmCmd::counts_for(ch.duty().unwrap_or(0.0));
        }
        pca_rt.cmd.publish(out);
    });
    per_call("pca9685.N.read (status pins)", N, |_| {
        black_box(pca_status.update(&mut pca_rt.status));
    });
    per_call("mcp23017.N.write (9 outputs)", N, |_| {
        let mut out = DioCmd::default();
        for (pin, d) in &outputs {
            out.out |= (d.level() as u16) << pin;
            out.safe |= (d.safe_level() as u16) << pin;
        }
        mcp_rt.cmd.publish(out);
    });
    per_call("mcp23017.N.read (7 inputs + status)", N, |_| {
        let bits = mcp_status.update(&mut mcp_rt.status).sample;
        for (pin, d) in &inputs {
            d.update(bits & (1 << pin) != 0);
        }
    });
    per_call("ads1115.N.read (4 channels + status)", N, |_| {
        let s: AdcSample = ads_status.update(&mut ads_rt.status).sample;
        for (ch, a) in adcs.iter().enumerate() {
            a.update_counts(s.counts[ch] as i64);
        }
    });
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    helper.join().unwrap();
    let st = ads_rt.status.latest();
    println!(
        "  (the helper thread completed {} ADS1115 cycles, {} conversions of channel 0, {} errors)",
        st.cycles, st.sample.conversions[0], st.errors
    );
}
