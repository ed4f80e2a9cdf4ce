//! hal_motenc on a real PCI BAR: the VM rig's ivshmem device (1af4:1110)
//! stands in for a MOTENC-Lite whose registers are BAR 2, and a peer
//! plays the board in that memory.
//!
//! One binary, two roles, as `.ci/run` runs it (spec `hal-motenc vmrig
//! peer`): in the VM, `motenc_loads_and_runs_on_a_real_bar` finds the
//! device through sysfs, enables it, maps BAR 2 and runs the driver; on
//! the host, `host_peer` plays the board in the BAR file
//! (`HAL_PEER_BAR_FILE`). Without a host-side peer (`HAL_PEER_EXPECTED`
//! unset) the VM test plays the board itself from a thread over its own
//! mapping of the BAR. Outside the rig both are ignored, with
//! the reason; run there on purpose they fail.
//!
//! The BAR holds the board's registers at 0 (boardVersion, statusControl,
//! counts and inputs written by the peer; DACs, outputs and commands by
//! the driver) and a mailbox at 0x1000: `MAGIC` (peer, once serving),
//! the peer's and the guest's step numbers, the peer's failure code and
//! `DONE` (guest: the peer may exit).

use std::sync::Arc;
use std::time::Duration;

use hal_core::module::ModuleArgs;
use hal_core::{Host, HostConfig, Value};
use hal_driver::bus::{MmapWindow, RegWindow, ALL_ONES};
use hal_driver::pci::PciMatch;
use hal_driver::vmrig::{self, IVSHMEM, IVSHMEM_SHARED_BAR};
use hal_motenc::hal::{load_from, NAME, PARAMS};
use hal_motenc::regs;

const MAGIC_AT: usize = 0x1000;
const PEER_STEP: usize = 0x1004;
const GUEST_STEP: usize = 0x1008;
const PEER_FAIL: usize = 0x100C;
const DONE_AT: usize = 0x1010;
const MAGIC: u32 = 0x4D4F_5445; // "MOTE"
const DONE: u32 = 0x600D_D0E5;

/// The ivshmem device under the MOTENC's name: its BAR 2 is the board's.
const TABLE: &[PciMatch] = &[PciMatch::new(
    IVSHMEM.vendor,
    IVSHMEM.device,
    "MOTENC (ivshmem)",
)];

/// Why the played board stopped before the end.
#[derive(Debug, thiserror::Error)]
enum PeerError {
    /// The guest did not reach a step in time.
    #[error("timed out after {secs} s waiting for {what}")]
    Timeout {
        /// The step waited for.
        what: &'static str,
        /// How long.
        secs: u64,
    },
    /// The driver wrote something else than it should have.
    #[error("step {step}: {found}")]
    Check {
        /// The step (also written to `PEER_FAIL`).
        step: u32,
        /// What the BAR held.
        found: String,
    },
}

fn wait_for(
    what: &'static str,
    secs: u64,
    mut cond: impl FnMut() -> bool,
) -> Result<(), PeerError> {
    if vmrig::wait_until(Duration::from_secs(secs), &mut cond) {
        Ok(())
    } else {
        Err(PeerError::Timeout { what, secs })
    }
}

/// Plays a MOTENC-Lite with ID jumpers 3 in `bar`, step by step with the
/// guest; checks what the driver writes. On a failed check it writes its
/// code to `PEER_FAIL` and returns the reason.
fn play_board(bar: &dyn RegWindow, secs: u64) -> Result<(), PeerError> {
    let fail = |step: u32, found: String| {
        bar.write32(PEER_FAIL, step);
        Err(PeerError::Check { step, found })
    };
    bar.write_burst(0, &[0; regs::SIM_WINDOW_LEN / 4]);
    bar.write_burst(MAGIC_AT, &[0; 5]);
    bar.write32(regs::BOARD_VERSION, regs::VERSION_LITE);
    bar.write32(regs::status_control(0), 3 << regs::STATUS_ID_SHIFT | 0xFFFF);
    bar.write32(regs::digital_io(0), 0xFFFF_FFFF);
    bar.write32(MAGIC_AT, MAGIC);
    bar.write32(PEER_STEP, 1);

    // 1: the driver loaded: LinuxCNC's initialisation is in the BAR.
    wait_for("the guest to load the driver", secs, || {
        bar.read32(GUEST_STEP) >= 1
    })?;
    let want = [
        (regs::digital_io(0), 0x0000_FFFF, "outputs off"),
        (
            regs::status_control(0),
            regs::RESET_ALL_COUNTERS,
            "counters reset",
        ),
        (regs::encoder_count(0, 2), 0, "index disarmed"),
        (regs::TIMER_IRQ_DISABLE, 1, "timer interrupt off"),
        (regs::WATCHDOG_CONTROL, 0, "watchdog off"),
        (regs::dac(5), regs::DAC_ZERO, "DACs at 0 V"),
    ];
    for (off, v, what) in want {
        if bar.read32(off) != v {
            return fail(
                1,
                format!("init: {what}: {off:#x} holds {:#x}", bar.read32(off)),
            );
        }
    }
    // Counts, inputs (in-00 and in-16 on) and the E-stop.
    bar.write32(regs::encoder_count(0, 0), 12345);
    bar.write32(regs::encoder_count(0, 2), (-7i32) as u32);
    bar.write32(
        regs::status_control(0),
        3 << regs::STATUS_ID_SHIFT | regs::STATUS_ESTOP | 0xFFFE,
    );
    bar.write32(regs::digital_io(0), 0xFFFE_FFFF);
    bar.write32(PEER_STEP, 2);

    // 2: the guest read them and set DAC 1 to -5 V; then the board goes.
    wait_for("the guest to read the board", secs, || {
        bar.read32(GUEST_STEP) >= 2
    })?;
    if bar.read32(regs::dac(1)) != regs::dac_code(-5.0) {
        return fail(2, format!("DAC 1 holds {:#x}", bar.read32(regs::dac(1))));
    }
    bar.write32(regs::BOARD_VERSION, ALL_ONES);
    bar.write32(regs::status_control(0), ALL_ONES);
    bar.write32(PEER_STEP, 3);

    // 3: the driver found the board gone and wrote its safe state.
    wait_for("the guest to see the fault", secs, || {
        bar.read32(GUEST_STEP) >= 3
    })?;
    if bar.read32(regs::dac(1)) != regs::DAC_ZERO {
        return fail(
            3,
            format!("safe state: DAC 1 holds {:#x}", bar.read32(regs::dac(1))),
        );
    }
    bar.write32(PEER_STEP, 4);
    wait_for("DONE", secs, || bar.read32(DONE_AT) == DONE)
}

#[test]
#[ignore = "needs the VM rig's ivshmem device: runs in ../shared/tools/vmrig (scripts/test-all)"]
fn motenc_loads_and_runs_on_a_real_bar() {
    let iv = vmrig::ivshmem().expect(
        "no VM rig ivshmem device (VMRIG_IVSHMEM_BAR unset or missing): \
         run this binary through ../shared/tools/vmrig",
    );
    let dev = hal_driver::pci::find(&iv.sysfs, &[IVSHMEM])
        .unwrap()
        .remove(0);
    let enable_count = || -> u32 {
        let text = std::fs::read_to_string(dev.path.join("enable")).unwrap();
        text.trim().parse().unwrap()
    };
    let enables = enable_count();
    let _on = dev.enable().unwrap();
    let bar = dev.map_bar(IVSHMEM_SHARED_BAR).unwrap();
    let local_peer = std::env::var_os("HAL_PEER_EXPECTED").is_none().then(|| {
        eprintln!("no host-side peer (HAL_PEER_EXPECTED unset): the board is played from a thread");
        let own = Arc::new(MmapWindow::open(&iv.bar_path).unwrap());
        own.write32(MAGIC_AT, 0);
        std::thread::spawn(move || play_board(&*own, 120))
    });
    let step = |n: u32| bar.write32(GUEST_STEP, n);
    let peer_at = |n: u32| {
        let ok = vmrig::wait_until(Duration::from_secs(120), || {
            bar.read32(PEER_STEP) >= n || bar.read32(PEER_FAIL) != 0
        });
        assert!(ok, "the peer never reached step {n}");
        assert_eq!(
            bar.read32(PEER_FAIL),
            0,
            "the peer failed a check before step {n}"
        );
    };
    assert!(
        vmrig::wait_until(Duration::from_secs(120), || bar.read32(MAGIC_AT) == MAGIC),
        "the peer never showed its magic word"
    );
    peer_at(1);

    // Discovery, enable, BAR 2, identification: through the real kernel.
    let host = Host::create(HostConfig::for_tests("motenc-vmrig")).unwrap();
    let args = ModuleArgs::parse(NAME, PARAMS, &[] as &[&str]).unwrap();
    load_from(&host, &args, &iv.sysfs, TABLE).unwrap();
    assert_eq!(
        enable_count(),
        enables + 2,
        "the driver holds its own enable"
    );
    let inst = host.instance();
    inst.pin_value("motenc.3.enc-03-count").unwrap();
    assert!(inst.pin_value("motenc.3.enc-04-count").is_err(), "a Lite");
    step(1);
    peer_at(2);

    let get = |n: &str| inst.pin_value(&format!("motenc.3.{n}")).unwrap();
    host.create_thread("servo", 1_000_000, true, None).unwrap();
    for f in [
        "encoder-read",
        "digital-in-read",
        "misc-update",
        "dac-write",
    ] {
        host.addf(&format!("motenc.3.{f}"), "servo", -1).unwrap();
    }
    inst.set_pin("motenc.3.dac-01-value", Value::Float(-5.0))
        .unwrap();
    host.start().unwrap();
    let seen = vmrig::wait_until(Duration::from_secs(60), || {
        get("enc-00-count") == Value::S32(12345)
            && get("enc-02-count") == Value::S32(-7)
            && get("in-00") == Value::Bit(true)
            && get("in-16") == Value::Bit(true)
            && get("estop-in") == Value::Bit(true)
    });
    assert!(seen, "counts and inputs from the BAR");
    assert_eq!(get("in-01"), Value::Bit(false));
    assert!(vmrig::wait_until(Duration::from_secs(60), || {
        bar.read32(regs::dac(1)) == regs::dac_code(-5.0)
    }));
    step(2);
    peer_at(3);
    assert!(
        vmrig::wait_until(Duration::from_secs(60), || get("fault") == Value::Bit(true)),
        "the driver noticed the board is gone"
    );
    assert_eq!(get("fault-code"), Value::U32(1));
    // The latch shows the fault just before the safe state is written.
    assert!(vmrig::wait_until(Duration::from_secs(60), || {
        bar.read32(regs::dac(1)) == regs::DAC_ZERO
    }));
    step(3);
    peer_at(4);
    host.stop();
    host.shutdown();
    assert_eq!(
        enable_count(),
        enables + 1,
        "unloading gave its enable back"
    );
    bar.write32(DONE_AT, DONE);
    if let Some(t) = local_peer {
        t.join().unwrap().unwrap();
    }
}

#[test]
#[ignore = "the host-side peer of a VM rig run: scripts/test-all starts it beside the VM"]
fn host_peer() {
    let file = vmrig::peer_bar_file()
        .expect("not the host-side peer: HAL_PEER_BAR_FILE unset (scripts/test-all sets it)");
    let secs = std::env::var("HAL_PEER_TIMEOUT_S")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let bar = MmapWindow::open(&file).expect("the BAR file");
    play_board(&bar, secs).unwrap();
}
