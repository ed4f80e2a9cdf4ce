//! lcec's EL5101 and EL7041 index latches and the EL7041's velocity
//! mode on the simulated segment, through `loadrt lcec backend=sim` in
//! a HAL host: the latch C enable is cleared once the terminal latched
//! at an index pulse and the count restarts there (as an index-enable
//! pin works); the stepper's command becomes the duty
//! cycle and the 16-bit velocity on the wire, its error is `srv-fault`
//! and a fault reset (or an enable edge) clears it.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::PathBuf;

mod common {
    pub mod pins;
    pub mod wait;
}
use common::pins::{float, pin, s32, set};
use common::wait::wait;

use hal_core::{Host, HostConfig, MsgLevel, Value};
use hal_ethercat::hal::MODULE;
use hal_ethercat::link::SharedSegment;
use hal_ethercat::sim::catalog::Stepper;
use hal_ethercat::sim::control::Control;

const CONF: &str = r#"<masters><master idx="0" appTimePeriod="1000000" refClockSyncCycles="1">
  <slave idx="0" type="EL5101" name="enc"/>
  <slave idx="1" type="EL7041" name="x"/>
</master></masters>"#;

fn started(tag: &str) -> (Host, SharedSegment) {
    let dir = std::env::temp_dir().join(format!("hal-ethercat-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file: PathBuf = dir.join("ethercat-conf.xml");
    std::fs::write(&file, CONF).unwrap();
    let h = Host::create(HostConfig::for_tests(tag)).unwrap();
    h.rt_log().set_level(MsgLevel::Info);
    h.loadrt(
        &MODULE,
        &[&format!("config={}", file.display()), "backend=sim"],
    )
    .unwrap();
    let seg: SharedSegment = hal_driver::sim::find(h.instance().name(), "lcec.0").unwrap();
    h.create_thread("servo", 1_000_000, true, None).unwrap();
    h.addf("lcec.read-all", "servo", -1).unwrap();
    h.addf("lcec.write-all", "servo", -1).unwrap();
    h.start().unwrap();
    wait("all-op", || pin(&h, "lcec.all-op") == Value::Bit(true));
    (h, seg)
}

#[test]
fn el5101_latches_at_the_index_and_counts_from_it() {
    let (h, seg) = started("lcec-enc-latch");
    // An index pulse every 4000 counts; the shaft turns 4000 counts/s.
    Control::parse("shaft 0 4000")
        .unwrap()
        .apply(&mut seg.lock().unwrap())
        .unwrap();
    wait("counting", || s32(&h, "lcec.0.enc.enc-count") > 100);
    assert_eq!(pin(&h, "lcec.0.enc.enc-latch-c-valid"), Value::Bit(false));
    set(&h, "lcec.0.enc.enc-index-c-enable", Value::Bit(true));
    // lcec clears the enable once the terminal latched.
    wait("the latch", || {
        pin(&h, "lcec.0.enc.enc-index-c-enable") == Value::Bit(false)
    });
    h.stop();
    let latch = s32(&h, "lcec.0.enc.enc-raw-latch");
    assert!(latch > 0 && latch % 4000 == 0, "latched at {latch}");
    let od_latch = seg.lock().unwrap().slaves()[0].device.od.get(0x6000, 3);
    assert_eq!(od_latch, latch as u64);
    // The count runs from the index: raw count minus the latched one.
    let raw = s32(&h, "lcec.0.enc.enc-raw-count") as i16;
    let count = s32(&h, "lcec.0.enc.enc-count");
    assert_eq!(count, i32::from(raw.wrapping_sub(latch as i16)));
    assert!(float(&h, "lcec.0.enc.enc-frequency-scale") == 0.05);
}

fn stepper(seg: &SharedSegment, f: impl FnOnce(&mut Stepper)) {
    let mut s = seg.lock().unwrap();
    let app = &mut s.slave_mut(1).unwrap().device.app;
    f(app.as_any_mut().downcast_mut::<Stepper>().unwrap());
}

fn velocity_on_wire(seg: &SharedSegment) -> i16 {
    seg.lock().unwrap().slaves()[1].device.od.get(0x7010, 0x21) as u16 as i16
}

#[test]
fn el7041_latches_at_the_encoder_index_and_counts_from_it() {
    let (h, seg) = started("lcec-stepper-latch");
    let x = |p: &str| format!("lcec.0.x.{p}");
    // 0.1 of full speed: 2000 steps/s, an index pulse every 1000.
    set(&h, &x("srv-cmd"), Value::Float(0.1));
    set(&h, &x("srv-enable"), Value::Bit(true));
    wait("counting", || s32(&h, &x("enc-count")) > 100);
    assert_eq!(pin(&h, &x("enc-latch-c-valid")), Value::Bit(false));
    set(&h, &x("enc-latch-c-enable"), Value::Bit(true));
    wait("latch C enabled on the wire", || {
        seg.lock().unwrap().slaves()[1].device.od.get(0x7000, 1) == 1
    });
    // The driver clears the enable once the terminal latched; the
    // terminal then drops its latch.
    wait("the latch", || {
        pin(&h, &x("enc-latch-c-enable")) == Value::Bit(false)
    });
    let latch = s32(&h, &x("enc-raw-latch"));
    assert!(latch > 0 && latch % 1000 == 0, "latched at {latch}");
    wait("latch C valid dropped", || {
        pin(&h, &x("enc-latch-c-valid")) == Value::Bit(false)
    });
    h.stop();
    let od_latch = seg.lock().unwrap().slaves()[1].device.od.get(0x6000, 0x12);
    assert_eq!(od_latch, u64::from(latch as u16));
    // The count runs from the index: raw count minus the latched one.
    let raw = s32(&h, &x("enc-raw-count")) as i16;
    let count = s32(&h, &x("enc-count"));
    assert_eq!(count, i32::from(raw.wrapping_sub(latch as i16)));
    assert!(count > 0, "the motor went on past the index: {count}");
}

#[test]
fn el7041_velocity_mode_and_its_faults() {
    let (h, seg) = started("lcec-stepper");
    let x = |p: &str| format!("lcec.0.x.{p}");
    // Half the command range: duty 0.5, velocity 16383 on the wire.
    set(&h, &x("srv-cmd"), Value::Float(0.5));
    set(&h, &x("srv-enable"), Value::Bit(true));
    wait("velocity on the wire", || velocity_on_wire(&seg) == 16383);
    assert_eq!(s32(&h, &x("srv-raw-cmd")), 16383);
    assert_eq!(float(&h, &x("srv-curr-dc")), 0.5);
    wait("moving", || pin(&h, &x("srv-move-pos")) == Value::Bit(true));
    wait("the encoder counts the steps", || {
        s32(&h, &x("enc-count")) > 100
    });
    // Scaled, offset and limited: (-3 / 2 + 0.25) limited to -0.75.
    set(&h, &x("srv-scale"), Value::Float(2.0));
    set(&h, &x("srv-offset"), Value::Float(0.25));
    set(&h, &x("srv-min-dc"), Value::Float(-0.75));
    set(&h, &x("srv-cmd"), Value::Float(-3.0));
    wait("limited", || velocity_on_wire(&seg) == -24575);
    // Absolute mode: |-3| / 2 + 0.25 = 1.75, limited to 1.
    set(&h, &x("srv-absmode"), Value::Bit(true));
    wait("absolute", || velocity_on_wire(&seg) == 32767);
    // A max-dc past 1 is brought back to 1.
    set(&h, &x("srv-max-dc"), Value::Float(2.0));
    wait("max-dc corrected", || float(&h, &x("srv-max-dc")) == 1.0);
    // Disabled: nothing on the wire.
    set(&h, &x("srv-enable"), Value::Bit(false));
    wait("stopped", || velocity_on_wire(&seg) == 0);
    assert_eq!(float(&h, &x("srv-curr-dc")), 0.0);

    // The terminal's error is srv-fault; srv-fault-reset clears it.
    stepper(&seg, |s| s.error = true);
    wait("srv-fault", || pin(&h, &x("srv-fault")) == Value::Bit(true));
    set(&h, &x("srv-fault-reset"), Value::Bit(true));
    wait("reset", || pin(&h, &x("srv-fault")) == Value::Bit(false));
    set(&h, &x("srv-fault-reset"), Value::Bit(false));
    wait("the reset bit off", || {
        seg.lock().unwrap().slaves()[1].device.od.get(0x7010, 2) == 0
    });
    // An enable edge while in error resets it once by itself.
    stepper(&seg, |s| s.error = true);
    wait("srv-fault again", || {
        pin(&h, &x("srv-fault")) == Value::Bit(true)
    });
    set(&h, &x("srv-enable"), Value::Bit(true));
    wait("the automatic reset", || {
        pin(&h, &x("srv-error")) == Value::Bit(false)
            && pin(&h, &x("srv-fault")) == Value::Bit(false)
    });
    wait("velocity again", || velocity_on_wire(&seg) != 0);
    h.stop();
}
