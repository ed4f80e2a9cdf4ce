//! Slaves that lose their configuration, seen through lcec's pins and
//! log (`backend=sim`, in process): a power-cycled EL2008 comes back to
//! OP without a fault reset (its state pins go through INIT on the way)
//! and its outputs follow the pins again; a different device plugged in
//! its place is refused, stays in INIT, and the log names the slave,
//! the position and both identities; a drive behind a cut line is said
//! not to answer, and is in OP again once the line is whole. The veth test restarts a whole
//! segment over a wire; `sim_master` the master's side in detail.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::PathBuf;

mod common {
    pub mod pins;
    pub mod wait;
}
use common::pins::{bit, set};
use common::wait::wait;

use hal_core::{Host, HostConfig, MsgLevel, Value};
use hal_ethercat::hal::MODULE;
use hal_ethercat::link::SharedSegment;
use hal_ethercat::sim;

const CONF: &str = r#"<masters>
  <master idx="0" appTimePeriod="1000000" refClockSyncCycles="1000">
    <slave idx="0" type="EK1100" name="D0"/>
    <slave idx="1" type="EL2008" name="D1"/>
    <slave idx="2" type="basic_cia402" vid="00000e5c" pid="00000402" name="X"/>
  </master>
</masters>
"#;

fn conf_file() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("hal-ethercat-recovery-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("ethercat-conf.xml");
    std::fs::write(&p, CONF).unwrap();
    p
}

fn dout_on_wire(seg: &SharedSegment) -> u64 {
    seg.lock().unwrap().slaves()[1].device.od.get(0x7000, 1)
}

#[test]
fn a_power_cycled_terminal_comes_back_to_op_and_another_device_in_its_place_is_refused_by_name() {
    let file = conf_file();
    let h = Host::create(HostConfig::for_tests("lcec-sim-recovery")).unwrap();
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
    set(&h, "lcec.0.D1.dout-0", Value::Bit(true));
    wait("dout-0 on the wire", || dout_on_wire(&seg) == 1);

    // Power-cycled: INIT, no address, its output off.
    seg.lock().unwrap().reset_slave(1);
    wait("the terminal seen lost", || {
        !bit(&h, "lcec.0.all-op") && !bit(&h, "lcec.0.D1.slave-state-op")
    });
    wait("all-op again, no fault reset", || {
        bit(&h, "lcec.0.all-op") && bit(&h, "lcec.0.D1.slave-state-op")
    });
    wait("dout-0 on the wire again", || dout_on_wire(&seg) == 1);

    // An EL1008 where the EL2008 was.
    {
        let mut s = seg.lock().unwrap();
        let other = sim::device_by_name("EL1008", 77).unwrap();
        *s.slave_mut(1).unwrap() = sim::esc::Esc::new(other, 1);
    }
    let says = |l: &str| {
        l.contains("lcec.0.D1: position 1 now holds vendor 0x00000002 product 0x03f03052")
            && l.contains("not the device found at start-up (vendor 0x00000002 product 0x07d83052)")
    };
    wait("the refusal in the log", || {
        h.flush_rt_log();
        h.rt_log().history().iter().any(|(_, l)| says(l))
    });
    wait("the other device left in INIT", || {
        bit(&h, "lcec.0.D1.slave-state-init") && !bit(&h, "lcec.0.all-op")
    });
    // Said once, not at every retry.
    std::thread::sleep(std::time::Duration::from_millis(1500));
    h.flush_rt_log();
    let times = h.rt_log().history().iter().filter(|(_, l)| says(l)).count();
    assert_eq!(times, 1, "the refusal is logged once");
    assert!(bit(&h, "lcec.0.D1.slave-state-init"));

    // The line cut before the drive: the master looks for it, says once
    // that nothing answers there; whole again, it is in OP as it was.
    seg.lock().unwrap().cut_before(Some(2));
    let unanswered = |l: &str| {
        l == "lcec.0.X: not back in OP: no answer at its station address nor at its position; the master tries again every 500 ms"
    };
    wait("the drive unanswered in the log", || {
        h.flush_rt_log();
        h.rt_log().history().iter().any(|(_, l)| unanswered(l))
    });
    seg.lock().unwrap().cut_before(None);
    wait("the drive in OP again", || {
        bit(&h, "lcec.0.X.slave-state-op")
    });
    h.stop();
    h.unloadrt("lcec").unwrap();
}
