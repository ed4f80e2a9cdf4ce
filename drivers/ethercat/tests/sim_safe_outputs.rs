//! Safe outputs per slave and per meaning when the link is lost, on the
//! simulated segment in process (`backend=sim`): an EL2008, an EL4102,
//! an EL7041 and a CiA 402 drive, all driven, then the link cut.
//!
//! * While the link is down the output pins that report what goes on
//!   the wire say safe: the drive's `srv-cia-controlword` 0 (disable
//!   voltage), the EL4102's `curr-dc` and `raw` 0, the EL7041's
//!   `srv-curr-dc` and `srv-raw-cmd` 0.
//! * The first frame after the link returns carries the safe values
//!   (each slave's outputs as that frame wrote them: the simulated ESC
//!   keeps them, `Esc::outputs_after_silence`), not those of before.
//! * The EL7041 stays disabled with `srv-enable` still high, until that
//!   falls and rises again.
//! * The drive never enables by itself: with `srv-enable` still high it
//!   gets disable voltage until a fault reset and a new enable, and the
//!   controlwords it acted on from the return on are disable voltage,
//!   then shutdown, switch on, enable operation, each once in that
//!   order: no quick stop, no 0/2 alternation.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::PathBuf;
use std::time::Duration;

mod common {
    pub mod pins;
    pub mod wait;
}
use common::pins::{bit, pin, set};
use common::wait::{wait, wait_within};

use hal_core::{Host, HostConfig, MsgLevel, Value};
use hal_ethercat::hal::MODULE;
use hal_ethercat::link::SharedSegment;
use hal_ethercat::sim::esc::OUTPUT_WATCHDOG_NS;
use hal_ethercat::sim::servo::Servo;

const CONF: &str = r#"<masters>
  <master idx="0" appTimePeriod="1000000" refClockSyncCycles="1000">
    <slave idx="0" type="EK1100" name="D0"/>
    <slave idx="1" type="EL2008" name="do"/>
    <slave idx="2" type="EL4102" name="ao"/>
    <slave idx="3" type="EL7041" name="st"/>
    <slave idx="4" type="basic_cia402" vid="00000e5c" pid="00000402" name="X">
      <modParam name="mode" value="csp"/>
    </slave>
  </master>
</masters>
"#;

/// The drive's position on the segment.
const DRIVE: usize = 4;

fn conf_file() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hal-ethercat-safe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("ethercat-conf.xml");
    std::fs::write(&p, CONF).unwrap();
    p
}

/// Pin `name` as a number, whatever its type.
fn num(h: &Host, name: &str) -> f64 {
    match pin(h, name) {
        Value::Bit(b) => f64::from(u8::from(b)),
        Value::Float(f) => f,
        Value::S32(v) => f64::from(v),
        Value::U32(v) | Value::Port(v) => f64::from(v),
        Value::S64(v) => v as f64,
        Value::U64(v) => v as f64,
    }
}

/// Object `index:sub` of slave `slave` as the simulator holds it.
fn wire(seg: &SharedSegment, slave: usize, index: u16, sub: u8) -> u64 {
    seg.lock().unwrap().slaves()[slave]
        .device
        .od
        .get(index, sub)
}

/// The controlwords the simulated drive acted on, oldest first, since
/// the last call (which are forgotten).
fn applied(seg: &SharedSegment) -> Vec<u16> {
    let mut s = seg.lock().unwrap();
    let app = s.slave_mut(DRIVE).unwrap().device.app.as_any_mut();
    app.downcast_mut::<Servo>()
        .unwrap()
        .applied
        .drain(..)
        .collect()
}

/// Waits until the servo thread has run `n` more cycles.
fn cycles(h: &Host, n: usize) {
    for _ in 0..n {
        let before = pin(h, "lcec.0.mono-time-lo");
        wait("a servo cycle", || pin(h, "lcec.0.mono-time-lo") != before);
    }
}

/// `v` with runs of one value made one.
fn collapsed(v: &[u16]) -> Vec<u16> {
    let mut out: Vec<u16> = Vec::new();
    for &x in v {
        if out.last() != Some(&x) {
            out.push(x);
        }
    }
    out
}

#[test]
fn a_lost_link_puts_each_slave_safe_the_first_frame_back_is_safe_and_the_drive_enables_only_again_from_the_start(
) {
    let file = conf_file();
    let h = Host::create(HostConfig::for_tests("lcec-sim-safe")).unwrap();
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
    wait("all-op", || bit(&h, "lcec.0.all-op"));

    // Everything driven: an output on, an analog output at 0.25, the
    // stepper turning, the drive enabled.
    set(&h, "lcec.0.do.dout-0", Value::Bit(true));
    set(&h, "lcec.0.ao.aout-0-value", Value::Float(0.25));
    set(&h, "lcec.0.ao.aout-0-enable", Value::Bit(true));
    set(&h, "lcec.0.st.srv-cmd", Value::Float(0.1));
    set(&h, "lcec.0.st.srv-enable", Value::Bit(true));
    set(&h, "lcec.0.X.srv-pos-scale", Value::Float(1000.0));
    set(&h, "lcec.0.X.srv-enable", Value::Bit(true));
    wait("the drive enabled", || bit(&h, "lcec.0.X.srv-enabled"));
    wait("everything on the wire", || {
        wire(&seg, 1, 0x7000, 1) == 1
            && wire(&seg, 2, 0x3001, 1) == 8192
            && wire(&seg, 3, 0x7010, 1) == 1
            && wire(&seg, DRIVE, 0x6040, 0) & 0x0f == 0x0f
    });
    assert!(num(&h, "lcec.0.ao.aout-0-curr-dc") > 0.2);
    assert!(num(&h, "lcec.0.st.srv-raw-cmd") > 0.0);

    // The link lost: the pins that report the wire say safe.
    seg.lock().unwrap().set_link_down(true);
    wait("the link down on the pins", || !bit(&h, "lcec.0.link-up"));
    cycles(&h, 3);
    for (name, want) in [
        ("lcec.0.X.srv-cia-controlword", 0.0),
        ("lcec.0.X.srv-enabled", 0.0),
        ("lcec.0.X.srv-fault", 1.0),
        ("lcec.0.ao.aout-0-curr-dc", 0.0),
        ("lcec.0.ao.aout-0-raw", 0.0),
        ("lcec.0.ao.aout-0-pos", 0.0),
        ("lcec.0.st.srv-curr-dc", 0.0),
        ("lcec.0.st.srv-raw-cmd", 0.0),
    ] {
        assert_eq!(num(&h, name), want, "{name} while the link is down");
    }
    // Down for longer than the slaves' watchdog, so that the simulator
    // records what the first frame back carries.
    std::thread::sleep(Duration::from_nanos(3 * OUTPUT_WATCHDOG_NS));
    applied(&seg);
    seg.lock().unwrap().set_link_down(false);
    wait("all-op again", || bit(&h, "lcec.0.all-op"));
    cycles(&h, 20);

    // The first frame back: every slave's outputs safe.
    {
        let s = seg.lock().unwrap();
        for (slave, what) in [(1, "EL2008"), (2, "EL4102"), (3, "EL7041")] {
            let first = s.slaves()[slave].outputs_after_silence().unwrap();
            assert!(
                first.iter().all(|b| *b == 0),
                "{what}: the first frame back carried {first:02x?}"
            );
        }
        let first = s.slaves()[DRIVE].outputs_after_silence().unwrap();
        assert_eq!(
            u16::from_le_bytes([first[0], first[1]]),
            0,
            "the drive's controlword in the first frame back"
        );
    }
    // The drive and the stepper stay off with their enables still high.
    assert_eq!(wire(&seg, 3, 0x7010, 1), 0, "the EL7041 stays disabled");
    assert_eq!(num(&h, "lcec.0.st.srv-curr-dc"), 0.0);
    assert!(!bit(&h, "lcec.0.X.srv-enabled"));
    assert!(bit(&h, "lcec.0.X.srv-enable"));
    assert_eq!(num(&h, "lcec.0.X.srv-cia-controlword"), 0.0);
    let mut since_return = applied(&seg);
    assert!(
        since_return.iter().all(|cw| *cw == 0),
        "before a fault reset the drive got only disable voltage: {since_return:x?}"
    );

    // Fault reset, a new enable: the enable sequence from its start.
    set(&h, "lcec.0.X.srv-enable", Value::Bit(false));
    set(&h, "lcec.0.X.srv-fault-reset", Value::Bit(true));
    cycles(&h, 3);
    wait("the fault cleared", || !bit(&h, "lcec.0.X.srv-fault"));
    set(&h, "lcec.0.X.srv-fault-reset", Value::Bit(false));
    cycles(&h, 3);
    set(&h, "lcec.0.X.srv-enable", Value::Bit(true));
    wait_within("enabled again", Duration::from_secs(30), || {
        bit(&h, "lcec.0.X.srv-enabled")
    });
    cycles(&h, 3);
    since_return.extend(applied(&seg));
    let seq = collapsed(&since_return);
    assert!(
        seq == [0x00, 0x06, 0x07, 0x0f] || seq == [0x00, 0x80, 0x00, 0x06, 0x07, 0x0f],
        "controlwords the drive acted on after the return: {seq:x?} (all: {since_return:x?})"
    );
    // The stepper after a new enable edge.
    set(&h, "lcec.0.st.srv-enable", Value::Bit(false));
    cycles(&h, 3);
    set(&h, "lcec.0.st.srv-enable", Value::Bit(true));
    wait("the EL7041 enabled again", || {
        wire(&seg, 3, 0x7010, 1) == 1 && num(&h, "lcec.0.st.srv-curr-dc") > 0.05
    });
    // And the other slaves follow their pins again.
    wait("the outputs back on the wire", || {
        wire(&seg, 1, 0x7000, 1) == 1 && wire(&seg, 2, 0x3001, 1) == 8192
    });
    h.stop();
    h.unloadrt("lcec").unwrap();
}
