//! hm2_pci on a real PCI BAR: the VM rig's ivshmem device (1af4:1110)
//! stands in for a 5i25, its BAR 2 holding the FPGA window, and a
//! host-side peer plays the board's firmware in that memory (the
//! simulator through [`Mirror`]).
//!
//! One binary, two roles, as `.ci/run` runs it (spec `hostmot2 vmrig
//! peer`): in the VM, `hm2_pci_registers_and_runs_on_a_real_bar` finds
//! the device through sysfs, enables it, maps BAR 2, registers the board
//! and runs it; on the host, `host_peer` serves the board in the BAR file
//! (`HAL_PEER_BAR_FILE`). Outside the rig both are ignored, with
//! the reason; run there on purpose they fail.
//!
//! Layout of BAR 2: the board's 64 KiB register window at 0, then
//! `MAGIC` (peer, once serving) at 0x10000, a heartbeat at 0x10004 and
//! `DONE` (guest: the peer may exit) at 0x10010.

use std::time::{Duration, Instant};

use hal_core::module::ModuleArgs;
use hal_core::{Host, HostConfig, Value};
use hal_driver::bus::{MmapWindow, RegWindow};
use hal_driver::vmrig::{self, IVSHMEM, IVSHMEM_SHARED_BAR};
use hostmot2::hal::{self, HM2_PCI_MODULE, HOSTMOT2_MODULE};
use hostmot2::pci::PciBoard;
use hostmot2::sim::machine;
use hostmot2::sim::mirror::Mirror;
use hostmot2::sim::{boards, Hm2Model};

const MAGIC_AT: usize = 0x1_0000;
const HEARTBEAT: usize = 0x1_0004;
const DONE_AT: usize = 0x1_0010;
const MAGIC: u32 = 0x484D_3250; // "HM2P"
const DONE: u32 = 0x600D_D0E5;

/// The ivshmem device dressed as a 5i25 whose FPGA window is BAR 2.
const IVSHMEM_5I25: PciBoard = PciBoard {
    ids: IVSHMEM,
    board: "5i25",
    bar: IVSHMEM_SHARED_BAR,
    connectors: &["P3", "P2"],
    pins_per_connector: 17,
    leds: 2,
    fpga_part: "6slx9tqg144",
};

fn wait(what: &str, secs: u64, mut cond: impl FnMut() -> bool) {
    assert!(
        vmrig::wait_until(Duration::from_secs(secs), &mut cond),
        "timed out after {secs} s waiting for {what}"
    );
}

#[test]
#[ignore = "needs the VM rig's ivshmem device: runs in ../shared/tools/vmrig (scripts/test-all)"]
fn hm2_pci_registers_and_runs_on_a_real_bar() {
    let iv = vmrig::ivshmem().expect(
        "no VM rig ivshmem device (VMRIG_IVSHMEM_BAR unset or missing): \
         run this binary through ../shared/tools/vmrig",
    );
    let host = Host::create(HostConfig::for_tests("hm2-vmrig")).unwrap();
    host.loadrt(&HOSTMOT2_MODULE, &[] as &[&str]).unwrap();
    let args = |a: &[&str]| ModuleArgs::parse("hm2_pci", HM2_PCI_MODULE.params, a).unwrap();
    if std::env::var_os("HAL_PEER_EXPECTED").is_none() {
        // No firmware behind the BAR: the cookie check refuses it.
        let dev = hal_driver::pci::find(&iv.sysfs, &[IVSHMEM])
            .unwrap()
            .remove(0);
        let _on = dev.enable().unwrap();
        let bar = dev.map_bar(IVSHMEM_SHARED_BAR).unwrap();
        bar.write32(0x100, 0);
        let e = hal::load_pci(&host, &args(&[]), &iv.sysfs, &[IVSHMEM_5I25]).unwrap_err();
        assert!(
            e.to_string().contains("invalid cookie, got 0x00000000"),
            "{e}"
        );
        eprintln!("SKIPPED the board exchange: HAL_PEER_EXPECTED unset (no host-side peer)");
        return;
    }
    let dev = hal_driver::pci::find(&iv.sysfs, &[IVSHMEM])
        .unwrap()
        .remove(0);
    let _on = dev.enable().unwrap();
    let bar = dev.map_bar(IVSHMEM_SHARED_BAR).unwrap();
    wait("the peer's magic word", 120, || {
        bar.read32(MAGIC_AT) == MAGIC
    });
    let beat = bar.read32(HEARTBEAT);
    wait("the peer's heartbeat", 60, || bar.read32(HEARTBEAT) != beat);

    // Registration reads the IDROM through the real BAR.
    hal::load_pci(
        &host,
        &args(&["config=num_encoders=0 num_stepgens=2"]),
        &iv.sysfs,
        &[IVSHMEM_5I25],
    )
    .unwrap();
    let inst = host.instance();
    let set = |name: &str, v: Value| {
        let full = format!("hm2_5i25.0.{name}");
        if inst.pin(&full).unwrap().is_some() {
            inst.set_pin(&full, v).unwrap()
        } else {
            inst.set_param(&full, v).unwrap()
        }
    };
    let get = |name: &str| inst.pin_value(&format!("hm2_5i25.0.{name}")).unwrap();
    host.create_thread("servo", 1_000_000, true, None).unwrap();
    host.addf("hm2_5i25.0.read", "servo", -1).unwrap();
    host.addf("hm2_5i25.0.write", "servo", -1).unwrap();
    set("watchdog.timeout_ns", Value::U32(200_000_000)); // TCG is slow
    host.start().unwrap();

    // A GPIO output goes out through the BAR and its level comes back.
    set("gpio.013.is_output", Value::Bit(true));
    set("gpio.013.out", Value::Bit(true));
    wait("gpio.013 to read high", 60, || {
        get("gpio.013.in") == Value::Bit(true)
    });
    set("gpio.013.out", Value::Bit(false));
    wait("gpio.013 to read low", 60, || {
        get("gpio.013.in") == Value::Bit(false)
    });

    // A step generator runs in the peer's firmware; its feedback moves.
    set("stepgen.00.position-scale", Value::Float(100.0));
    set("stepgen.00.maxaccel", Value::Float(0.0));
    for t in ["steplen", "stepspace", "dirsetup", "dirhold"] {
        set(&format!("stepgen.00.{t}"), Value::U32(1000));
    }
    set("stepgen.00.control-type", Value::Bit(true));
    set("stepgen.00.velocity-cmd", Value::Float(10.0));
    set("stepgen.00.enable", Value::Bit(true));
    wait(
        "stepgen 0 to count 200 steps",
        120,
        || matches!(get("stepgen.00.counts"), Value::S32(c) if c >= 200),
    );

    // Writes stop: the peer's watchdog bites and read reports it.
    host.stop();
    std::thread::sleep(Duration::from_millis(1500));
    host.start().unwrap();
    wait("has_bit", 60, || {
        get("watchdog.has_bit") == Value::Bit(true)
    });
    host.stop();
    host.unload("hm2_pci").unwrap();
    bar.write32(DONE_AT, DONE);
}

#[test]
#[ignore = "the host-side peer of a VM rig run: scripts/test-all starts it beside the VM"]
fn host_peer() {
    let file = vmrig::peer_bar_file()
        .expect("not the host-side peer: HAL_PEER_BAR_FILE unset (scripts/test-all sets it)");
    let timeout = std::env::var("HAL_PEER_TIMEOUT_S")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300u64);
    let win = MmapWindow::open(&file).expect("the BAR file");
    let spec = boards::preset("5i25").unwrap();
    let model = Hm2Model::with_world(spec, Box::new(machine::preset("5i25")));
    let mut mirror = Mirror::new(model, 0);
    mirror.publish_all(&win);
    win.write32(DONE_AT, 0);
    win.write32(MAGIC_AT, MAGIC);
    let start = Instant::now();
    let mut last = Instant::now();
    let mut beat = 0u32;
    while win.read32(DONE_AT) != DONE {
        assert!(
            start.elapsed() < Duration::from_secs(timeout),
            "the guest never said DONE"
        );
        let now = Instant::now();
        let dt = now.duration_since(last).as_nanos() as u64;
        last = now;
        mirror.step(&win, dt);
        beat = beat.wrapping_add(1);
        win.write32(HEARTBEAT, beat);
        std::thread::sleep(Duration::from_micros(200));
    }
}
