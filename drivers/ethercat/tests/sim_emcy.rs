//! Emergencies of a CiA 402 drive over CoE during cycles: the master's
//! helper reads them from the drive's mailbox without holding the cycle
//! up, and the drive trips as canservo's do on a CANopen EMCY (the
//! shared CiA 402 layer): `srv-fault`, `srv-fault-code` 6, the EMCY's
//! code in `srv-error-code`, and a message naming the drive and the
//! code; a fault reset brings it back.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common {
    pub mod pins;
    pub mod wait;
}
use common::pins::{pin, set};
use common::wait::wait;

use hal_core::{Host, HostConfig, MsgLevel, Value};
use hal_ethercat::hal::MODULE;
use hal_ethercat::link::SharedSegment;
use hal_ethercat::sim::servo::Servo;

const CONF: &str = r#"<masters><master idx="0" appTimePeriod="1000000" refClockSyncCycles="1">
  <slave idx="0" type="EK1100" name="D0"/>
  <slave idx="1" type="basic_cia402" vid="00000e5c" pid="00000402" name="X"/>
</master></masters>"#;

#[test]
fn an_emergency_in_the_mailbox_trips_the_drive_with_its_code() {
    let dir = std::env::temp_dir().join(format!("hal-ethercat-emcy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("ethercat-conf.xml");
    std::fs::write(&file, CONF).unwrap();
    let h = Host::create(HostConfig::for_tests("lcec-emcy")).unwrap();
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
    set(&h, "lcec.0.X.srv-enable", Value::Bit(true));
    wait("srv-enabled", || {
        pin(&h, "lcec.0.X.srv-enabled") == Value::Bit(true)
    });
    // The drive reports an excess temperature by EMCY only: its state
    // machine still says Operation enabled.
    {
        let mut s = seg.lock().unwrap();
        let app = &mut s.slave_mut(1).unwrap().device.app;
        let servo = app.as_any_mut().downcast_mut::<Servo>().unwrap();
        servo.send_emergency(0x4210);
    }
    wait("srv-fault", || {
        pin(&h, "lcec.0.X.srv-fault") == Value::Bit(true)
    });
    assert_eq!(pin(&h, "lcec.0.X.srv-fault-code"), Value::U32(6));
    assert_eq!(pin(&h, "lcec.0.X.srv-error-code"), Value::U32(0x4210));
    assert_eq!(pin(&h, "lcec.0.X.srv-enabled"), Value::Bit(false));
    wait("the message", || {
        h.rt_log().history().iter().any(|(_, l)| {
            l.contains("lcec.0.X.srv (slave 1)")
                && l.contains("EMCY received")
                && l.contains("0x4210")
        })
    });
    // A fault reset clears it; enabled again.
    set(&h, "lcec.0.X.srv-enable", Value::Bit(false));
    set(&h, "lcec.0.X.srv-fault-reset", Value::Bit(true));
    wait("cleared", || {
        pin(&h, "lcec.0.X.srv-fault") == Value::Bit(false)
    });
    set(&h, "lcec.0.X.srv-fault-reset", Value::Bit(false));
    set(&h, "lcec.0.X.srv-enable", Value::Bit(true));
    wait("enabled again", || {
        pin(&h, "lcec.0.X.srv-enabled") == Value::Bit(true)
    });
    h.stop();
}
