//! `loadrt lcec config=... backend=sim` in a HAL host with a running
//! servo thread: lcec's pins for a coupler, digital I/O, a generic slave
//! and a CiA 402 drive on the simulated segment; the drive enabled and
//! moved in CSP; a lost slave and its fault reset; errors for a bad
//! configuration that leave nothing behind.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::PathBuf;

mod common {
    pub mod pins;
    pub mod wait;
}
use common::pins::{float, pin, set};
use common::wait::wait;

use hal_core::{Host, HostConfig, MsgLevel, Value};
use hal_ethercat::hal::MODULE;
use hal_ethercat::link::SharedSegment;

const CONF: &str = r#"<masters>
  <master idx="0" appTimePeriod="1000000" refClockSyncCycles="1000">
    <slave idx="0" type="EK1100" name="D0"/>
    <slave idx="1" type="EL1008" name="D1"/>
    <slave idx="2" type="EL2008" name="D2"/>
    <slave idx="3" type="basic_cia402" vid="00000e5c" pid="00000402" name="X">
      <modParam name="mode" value="csp"/>
    </slave>
    <slave idx="4" type="generic" vid="00000539" pid="00000010" configPdos="true" name="G">
      <syncManager idx="2" dir="out">
        <pdo idx="1600">
          <pdoEntry idx="7000" subIdx="01" bitLen="16" halPin="out-word" halType="u32"/>
        </pdo>
      </syncManager>
      <syncManager idx="3" dir="in">
        <pdo idx="1a00">
          <pdoEntry idx="6000" subIdx="01" bitLen="16" halPin="in-val" halType="float" scale="0.5" offset="1"/>
        </pdo>
      </syncManager>
    </slave>
  </master>
</masters>
"#;

fn conf_file(tag: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hal-ethercat-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("ethercat-conf.xml");
    std::fs::write(&p, text).unwrap();
    p
}

fn host(tag: &str) -> Host {
    let h = Host::create(HostConfig::for_tests(tag)).unwrap();
    h.rt_log().set_level(MsgLevel::Info);
    h
}

#[test]
fn lcec_pins_io_drive_and_a_lost_slave() {
    let file = conf_file("io", CONF);
    let h = host("lcec-sim-io");
    h.loadrt(
        &MODULE,
        &[&format!("config={}", file.display()), "backend=sim"],
    )
    .unwrap();
    let seg = hal_driver::sim::find::<std::sync::Mutex<hal_ethercat::sim::Segment>>(
        h.instance().name(),
        "lcec.0",
    )
    .expect("published segment");
    let seg: SharedSegment = seg;
    for name in [
        "lcec.all-op",
        "lcec.0.link-up",
        "lcec.0.wkc",
        "lcec.0.D0.slave-state-op",
        "lcec.0.D1.din-3",
        "lcec.0.D1.din-3-not",
        "lcec.0.D2.dout-5",
        "lcec.0.X.srv-enable",
        "lcec.0.X.srv-actual-position",
        "lcec.0.G.out-word",
        "lcec.0.G.in-val",
    ] {
        assert!(h.instance().pin_value(name).is_ok(), "{name}");
    }
    h.create_thread("servo", 1_000_000, true, None).unwrap();
    h.addf("lcec.read-all", "servo", -1).unwrap();
    h.addf("lcec.write-all", "servo", -1).unwrap();
    h.start().unwrap();
    wait("all-op", || pin(&h, "lcec.all-op") == Value::Bit(true));
    assert_eq!(pin(&h, "lcec.0.slaves-responding"), Value::U32(5));
    assert_eq!(pin(&h, "lcec.0.X.slave-oper"), Value::Bit(true));

    // Digital input 3 on, output 5 on.
    seg.lock()
        .unwrap()
        .slave_mut(1)
        .unwrap()
        .device
        .od
        .set(0x6030, 1, 1);
    set(&h, "lcec.0.D2.dout-5", Value::Bit(true));
    wait("din-3", || pin(&h, "lcec.0.D1.din-3") == Value::Bit(true));
    assert_eq!(pin(&h, "lcec.0.D1.din-3-not"), Value::Bit(false));
    wait("dout-5 on the wire", || {
        seg.lock().unwrap().slaves()[2].device.od.get(0x7050, 1) == 1
    });

    // The generic slave loops its output word back: 100 × 0.5 + 1.
    set(&h, "lcec.0.G.out-word", Value::U32(100));
    wait("in-val", || float(&h, "lcec.0.G.in-val") == 51.0);

    // The drive: enable, follow a CSP command.
    set(&h, "lcec.0.X.srv-pos-scale", Value::Float(1000.0));
    set(&h, "lcec.0.X.srv-enable", Value::Bit(true));
    wait("srv-enabled", || {
        pin(&h, "lcec.0.X.srv-enabled") == Value::Bit(true)
    });
    set(&h, "lcec.0.X.srv-target-position", Value::Float(2.5));
    wait("the drive at 2.5", || {
        (float(&h, "lcec.0.X.srv-actual-position") - 2.5).abs() < 1e-3
    });

    // The line cut before the drive: it faults, its outputs go safe.
    seg.lock().unwrap().cut_before(Some(3));
    wait("srv-fault", || {
        pin(&h, "lcec.0.X.srv-fault") == Value::Bit(true)
    });
    assert_eq!(pin(&h, "lcec.all-op"), Value::Bit(false));
    assert_eq!(pin(&h, "lcec.0.X.srv-enabled"), Value::Bit(false));
    // Whole again; the fault reset brings it back, enable again.
    seg.lock().unwrap().cut_before(None);
    set(&h, "lcec.0.X.srv-enable", Value::Bit(false));
    set(&h, "lcec.0.X.srv-fault-reset", Value::Bit(true));
    wait("srv-fault cleared", || {
        pin(&h, "lcec.0.X.srv-fault") == Value::Bit(false)
    });
    set(&h, "lcec.0.X.srv-fault-reset", Value::Bit(false));
    set(&h, "lcec.0.X.srv-enable", Value::Bit(true));
    wait("srv-enabled again", || {
        pin(&h, "lcec.0.X.srv-enabled") == Value::Bit(true)
    });
    h.stop();
    h.unloadrt("lcec").unwrap();
    // The safe state: the output is off after unload.
    assert_eq!(seg.lock().unwrap().slaves()[2].device.od.get(0x7050, 1), 0);
}

#[test]
fn configuration_errors_name_file_line_and_element_and_leave_nothing() {
    let h = host("lcec-sim-errors");
    let e = h.loadrt(&MODULE, &["backend=sim"]).unwrap_err().to_string();
    assert!(e.contains("config"), "{e}");
    let bad = conf_file(
        "bad",
        "<masters>\n<master idx=\"0\" appTimePeriod=\"1000000\" refClockSyncCycles=\"1\">\n<slave idx=\"0\" type=\"EL9999\" name=\"Z\"/>\n</master>\n</masters>\n",
    );
    let e = h
        .loadrt(
            &MODULE,
            &[&format!("config={}", bad.display()), "backend=sim"],
        )
        .unwrap_err();
    let text = format!(
        "{e}: {}",
        std::error::Error::source(&e)
            .map(|s| s.to_string())
            .unwrap_or_default()
    );
    assert!(
        text.contains("ethercat-conf.xml:3") && text.contains("EL9999"),
        "{text}"
    );
    assert!(h.instance().component("lcec").unwrap().is_none());
    let e = h
        .loadrt(&MODULE, &[&format!("config={}", file_missing().display())])
        .unwrap_err();
    assert!(format!("{e:?}").contains("no-such-file"), "{e:?}");
}

fn file_missing() -> PathBuf {
    PathBuf::from("/nonexistent/no-such-file.xml")
}

#[test]
fn analog_terminals_and_the_encoder_scale_their_values() {
    let file = conf_file(
        "analog",
        r#"<masters><master idx="0" appTimePeriod="1000000" refClockSyncCycles="1">
  <slave idx="0" type="EL3102" name="ai"/>
  <slave idx="1" type="EL4102" name="ao"/>
  <slave idx="2" type="EL5101" name="enc"/>
</master></masters>"#,
    );
    let h = host("lcec-sim-analog");
    h.loadrt(
        &MODULE,
        &[&format!("config={}", file.display()), "backend=sim"],
    )
    .unwrap();
    let seg: SharedSegment = hal_driver::sim::find(h.instance().name(), "lcec.0").unwrap();
    h.create_thread("servo", 1_000_000, true, None).unwrap();
    h.addf("lcec.0.read", "servo", -1).unwrap();
    h.addf("lcec.0.write", "servo", -1).unwrap();
    h.start().unwrap();
    wait("all-op", || pin(&h, "lcec.0.all-op") == Value::Bit(true));
    // EL3102 channel 1: raw -16384 with overrange set; val = bias + scale × raw / 32767.
    {
        let mut s = seg.lock().unwrap();
        let od = &mut s.slave_mut(0).unwrap().device.od;
        od.set(0x3102, 2, (-16384i16) as u16 as u64);
        od.set(0x3102, 1, 0b10);
    }
    set(&h, "lcec.0.ai.ain-1-scale", Value::Float(10.0));
    set(&h, "lcec.0.ai.ain-1-bias", Value::Float(1.0));
    wait("ain-1-val", || {
        (float(&h, "lcec.0.ai.ain-1-val") - (1.0 - 10.0 * 16384.0 / 32767.0)).abs() < 1e-9
    });
    assert_eq!(pin(&h, "lcec.0.ai.ain-1-raw"), Value::S32(-16384));
    assert_eq!(pin(&h, "lcec.0.ai.ain-1-overrange"), Value::Bit(true));
    assert_eq!(pin(&h, "lcec.0.ai.ain-1-underrange"), Value::Bit(false));
    // EL4102 channel 0: value 0.25 enabled: raw 0.25 × 32767 on the wire.
    set(&h, "lcec.0.ao.aout-0-value", Value::Float(0.25));
    set(&h, "lcec.0.ao.aout-0-enable", Value::Bit(true));
    wait("aout-0 on the wire", || {
        seg.lock().unwrap().slaves()[1].device.od.get(0x3001, 1) == 8192
    });
    assert_eq!(pin(&h, "lcec.0.ao.aout-0-pos"), Value::Bit(true));
    // EL5101: the shaft turns; the count follows, the position is scaled.
    set(&h, "lcec.0.enc.enc-pos-scale", Value::Float(4.0));
    hal_ethercat::sim::control::Control::parse("shaft 2 40000")
        .unwrap()
        .apply(&mut seg.lock().unwrap())
        .unwrap();
    wait("the encoder counts", || {
        match pin(&h, "lcec.0.enc.enc-count") {
            Value::S32(c) => c > 40_000,
            _ => false,
        }
    });
    let pos = float(&h, "lcec.0.enc.enc-pos");
    assert!(pos > 10_000.0, "{pos}");
    h.stop();
}

#[test]
fn distributed_clocks_pins() {
    let file = conf_file(
        "dc",
        r#"<masters><master idx="0" appTimePeriod="1000000" refClockSyncCycles="1">
  <slave idx="0" type="EK1100" name="D0"/>
  <slave idx="1" type="basic_cia402" vid="00000e5c" pid="00000402" name="X">
    <dcConf assignActivate="300" sync0Cycle="*1" sync0Shift="0"/>
  </slave>
</master></masters>"#,
    );
    let h = host("lcec-sim-dc");
    h.loadrt(
        &MODULE,
        &[&format!("config={}", file.display()), "backend=sim"],
    )
    .unwrap();
    let seg: SharedSegment = hal_driver::sim::find(h.instance().name(), "lcec.0").unwrap();
    // lcec's default threshold: 4 % of the period.
    let param = |n: &str| h.instance().param_value(n).unwrap();
    assert_eq!(param("lcec.0.dc-sync-max"), Value::U32(40_000));
    assert_eq!(param("lcec.0.dc-sync-monitor"), Value::Bit(true));
    let activation = seg.lock().unwrap().slaves()[1].sync_activation().unwrap();
    assert_eq!(
        (activation.flags, activation.sync0_cycle),
        (0x03, 1_000_000)
    );
    h.create_thread("servo", 1_000_000, true, None).unwrap();
    h.addf("lcec.read-all", "servo", -1).unwrap();
    h.addf("lcec.write-all", "servo", -1).unwrap();
    h.start().unwrap();
    // Converged, and the difference under the threshold, read in one
    // cycle's worth: the two pins are read apart, and on a loaded test
    // machine the master's helper (not realtime) can be late with a
    // sample in between (one run under the whole suite read 250 ms
    // right after `converged`).
    wait("dc-sync-converged with a small dc-sync-diff", || {
        pin(&h, "lcec.0.dc-sync-converged") == Value::Bit(true)
            && matches!(pin(&h, "lcec.0.dc-sync-diff"), Value::U32(d) if d < 40_000)
    });
    // The time pair: the application time is the cycle's monotonic time
    // on the time base the slaves' clocks keep (the reference clock
    // follows it).
    let word = |n: &str| match pin(&h, n) {
        Value::U32(v) => u64::from(v),
        v => panic!("{n} is {v:?}"),
    };
    let time =
        |n: &str| word(&format!("lcec.0.{n}-time-hi")) << 32 | word(&format!("lcec.0.{n}-time-lo"));
    wait("the time pins", || word("lcec.0.mono-time-hi") > 0);
    h.stop();
    let (app, mono) = (time("app"), time("mono"));
    assert!(mono > 0 && app > 0);
    let reference = seg.lock().unwrap().slaves()[0].system_time() as u64;
    assert!(
        reference.abs_diff(app) < 1_000_000_000,
        "reference {reference}, app {app}"
    );
    h.start().unwrap();
    // The monitor off: converged says nothing.
    h.instance()
        .set_param("lcec.0.dc-sync-monitor", Value::Bit(false))
        .unwrap();
    wait("converged off", || {
        pin(&h, "lcec.0.dc-sync-converged") == Value::Bit(false)
    });
    h.stop();
}
