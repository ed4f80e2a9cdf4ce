//! A generic slave with `configPdos="true"` gets the PDO layout of its
//! `<syncManager>`s: the master writes the assignment and mapping
//! objects in PRE-OP (the simulated slave starts with one PDO per
//! entry and no gap), the process image follows the XML (a gap
//! included), and the pins exchange data through it. Without
//! `configPdos` the slave keeps its own layout.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::Path;

mod common {
    pub mod pins;
    pub mod wait;
}
use common::pins::pin;
use common::wait::wait;

use hal_core::{Host, HostConfig, MsgLevel, Value};
use hal_ethercat::hal::MODULE;
use hal_ethercat::link::SharedSegment;

fn conf(config_pdos: bool) -> String {
    format!(
        r#"<masters><master idx="0" appTimePeriod="1000000" refClockSyncCycles="1">
  <slave idx="0" type="generic" vid="00000539" pid="00000020" configPdos="{config_pdos}" name="G">
    <syncManager idx="2" dir="out">
      <pdo idx="1600">
        <pdoEntry idx="7000" subIdx="01" bitLen="16" halPin="a" halType="u32"/>
        <pdoEntry idx="0000" subIdx="00" bitLen="8"/>
        <pdoEntry idx="7000" subIdx="02" bitLen="8" halPin="b" halType="u32"/>
      </pdo>
    </syncManager>
    <syncManager idx="3" dir="in">
      <pdo idx="1a00">
        <pdoEntry idx="6000" subIdx="01" bitLen="16" halPin="ra" halType="u32"/>
        <pdoEntry idx="6000" subIdx="02" bitLen="8" halPin="rb" halType="u32"/>
      </pdo>
    </syncManager>
  </slave>
</master></masters>"#
    )
}

fn load(tag: &str, text: &str) -> (Host, SharedSegment) {
    let dir = std::env::temp_dir().join(format!("hal-ethercat-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("ethercat-conf.xml");
    std::fs::write(&file, text).unwrap();
    let h = Host::create(HostConfig::for_tests(tag)).unwrap();
    h.rt_log().set_level(MsgLevel::Info);
    h.loadrt(
        &MODULE,
        &[
            &format!("config={}", Path::new(&file).display()),
            "backend=sim",
        ],
    )
    .unwrap();
    let seg: SharedSegment = hal_driver::sim::find(h.instance().name(), "lcec.0").unwrap();
    (h, seg)
}

#[test]
fn the_xml_layout_is_written_to_the_slave_and_used() {
    let (h, seg) = load("lcec-generic-pdos", &conf(true));
    {
        let s = seg.lock().unwrap();
        let d = &s.slaves()[0].device;
        // One PDO assigned, mapping three entries, the gap included.
        assert_eq!(d.od.get(0x1C12, 0), 1);
        assert_eq!(d.od.get(0x1C12, 1), 0x1600);
        assert_eq!(d.od.get(0x1600, 0), 3);
        assert_eq!(d.od.get(0x1600, 1), 0x7000_0110);
        assert_eq!(d.od.get(0x1600, 2), 0x0000_0008);
        assert_eq!(d.od.get(0x1600, 3), 0x7000_0208);
        assert_eq!(d.od.get(0x1C13, 0), 1);
        assert_eq!(d.od.get(0x1A00, 0), 2);
        assert_eq!(d.image_bytes(), (4, 3));
    }
    h.create_thread("servo", 1_000_000, true, None).unwrap();
    h.addf("lcec.read-all", "servo", -1).unwrap();
    h.addf("lcec.write-all", "servo", -1).unwrap();
    h.start().unwrap();
    h.instance()
        .set_pin("lcec.0.G.a", Value::U32(1234))
        .unwrap();
    h.instance().set_pin("lcec.0.G.b", Value::U32(56)).unwrap();
    wait("the loop-back", || {
        pin(&h, "lcec.0.G.ra") == Value::U32(1234) && pin(&h, "lcec.0.G.rb") == Value::U32(56)
    });
    h.stop();
}

#[test]
fn without_config_pdos_the_slave_keeps_its_layout() {
    let (_h, seg) = load("lcec-generic-own", &conf(false));
    let s = seg.lock().unwrap();
    let d = &s.slaves()[0].device;
    assert_eq!(d.od.get(0x1C12, 0), 2, "its own: a PDO per entry");
    assert_eq!(d.image_bytes(), (3, 3));
}
