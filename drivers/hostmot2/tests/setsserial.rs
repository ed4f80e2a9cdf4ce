//! `setsserial` on the simulated 5i25 with a 7I77 on Smart Serial: a
//! parameter written into the remote's EEPROM, a firmware file written
//! into its flash in setup mode (`sserial_baudrate=115200`), and every
//! way either can fail, each with its own error.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::Path;
use std::sync::Arc;

use hal_core::{Host, HostConfig};
use hostmot2::hal::{HM2_PCI_MODULE, HOSTMOT2_MODULE};
use hostmot2::sim::SimHm2;
use hostmot2::sserial::local;
use hostmot2::SETSSERIAL_MODULE;

const IO: &str = "hm2_5i25.0.7i77.0.0";

/// A host with hostmot2 (`core` its arguments) and the simulated 5i25
/// with its 7I77.
fn board(tag: &str, core: &[&str]) -> (Host, Arc<SimHm2>) {
    let h = Host::create(HostConfig::for_tests(tag)).unwrap();
    h.loadrt(&HOSTMOT2_MODULE, core).unwrap();
    h.loadrt(
        &HM2_PCI_MODULE,
        &["sim=5i25-7i77", "config=sserial_port_0=00"],
    )
    .unwrap();
    let sim = hal_driver::sim::find::<SimHm2>(h.instance().name(), "hm2_5i25.0").unwrap();
    (h, sim)
}

/// Why `loadrt setsserial` failed: the host's error, shown with every
/// cause below it (the step and the board's reason) on one line.
#[derive(Debug, thiserror::Error)]
#[error("{}", whole_text(.0))]
struct Refused(#[source] hal_core::HalError);

impl Refused {
    /// Whether the whole text says `what`.
    fn contains(&self, what: &str) -> bool {
        self.to_string().contains(what)
    }
}

/// `e` and its causes, joined by " / ".
fn whole_text(e: &hal_core::HalError) -> String {
    let mut text = e.to_string();
    let mut src = std::error::Error::source(e);
    while let Some(s) = src {
        text.push_str(" / ");
        text.push_str(&s.to_string());
        src = s.source();
    }
    text
}

/// `loadrt setsserial` with `args`, unloaded again when it loaded.
fn setsserial(h: &Host, args: &[&str]) -> Result<(), Refused> {
    h.loadrt(&SETSSERIAL_MODULE, args).map_err(Refused)?;
    h.unloadrt("setsserial").unwrap();
    Ok(())
}

fn global(sim: &SimHm2, chan: usize, name: &str) -> Option<u32> {
    sim.with(|m| m.sserial().remote(0, chan).unwrap().global(name))
}

#[test]
fn set_writes_the_remotes_eeprom_by_either_name() {
    let (h, sim) = board("setss-set", &[]);
    let comps = h.loaded_components();
    setsserial(&h, &[&format!("cmd=set {IO}.nvwatchdogtimeout 0x14")]).unwrap();
    assert_eq!(global(&sim, 0, "NVWatchDogTimeout"), Some(20));
    assert!(sim.with(|m| m.sserial().remote(0, 0).unwrap().eeprom_writes) > 0);
    assert_eq!(h.loaded_components(), comps, "nothing of setsserial stays");
    // By unit number, as use_serial_numbers names it; the other channel.
    setsserial(&h, &["cmd=set hm2_7i77.7701.NVWatchDogTimeout 33"]).unwrap();
    assert_eq!(global(&sim, 1, "NVWatchDogTimeout"), Some(33));
    assert_eq!(global(&sim, 0, "NVWatchDogTimeout"), Some(20));
}

#[test]
fn set_refuses_what_it_cannot_do() {
    let (h, sim) = board("setss-set-bad", &[]);
    for (cmd, says) in [
        (
            "set hm2_5i25.0.7i77.0.5.nvbaudrate 3",
            "no Smart Serial remote hm2_5i25.0.7i77.0.5",
        ),
        (
            "set hm2_5i25.0.7i77.0.0.nvmaxcurrent 3",
            "has no parameter nvmaxcurrent (it has: swrevision, nvunitnumber",
        ),
        (
            "set hm2_5i25.0.7i77.0.0.nvbaudrate 70000",
            "outside 0..=65535",
        ),
        ("set hm2_5i25.0.7i77.0.0.nvbaudrate -1", "outside 0..=65535"),
        (
            "set hm2_5i25.0.7i77.0.0.nvbaudrate 12abc",
            "not a decimal or 0x hex integer",
        ),
        ("set hm2_5i25.0.7i77.0.0.swrevision 3", "only reports"),
        ("set hm2_5i25.0.7i77.0.0.nvbaudrate", "2 words, 3 expected"),
        (
            "get hm2_5i25.0.7i77.0.0.nvbaudrate 3",
            "unknown command \"get\"",
        ),
    ] {
        let e = setsserial(&h, &[&format!("cmd={cmd}")]).unwrap_err();
        assert!(e.contains(says), "{cmd}: {e}");
    }
    assert_eq!(global(&sim, 0, "NVBaudRate"), Some(9), "unchanged");
    // A processor that never finishes a command: a bounded wait.
    sim.with(|m| m.sserial().ports[0].stuck = true);
    let t0 = std::time::Instant::now();
    let e = setsserial(&h, &[&format!("cmd=set {IO}.nvbaudrate 4")]).unwrap_err();
    assert!(
        e.contains("setup start") && e.contains("not done after 1000 ms"),
        "{e}"
    );
    assert!(t0.elapsed() < std::time::Duration::from_secs(10));
    sim.with(|m| m.sserial().ports[0].stuck = false);
    // A remote that does not answer.
    sim.with(|m| m.sserial().remote(0, 0).unwrap().connected = false);
    let e = setsserial(&h, &[&format!("cmd=set {IO}.nvbaudrate 4")]).unwrap_err();
    assert!(e.contains("did not start in setup mode"), "{e}");
    // Without a board loaded.
    let alone = Host::create(HostConfig::for_tests("setss-alone")).unwrap();
    alone.loadrt(&HOSTMOT2_MODULE, &[] as &[&str]).unwrap();
    let e = setsserial(&alone, &[&format!("cmd=set {IO}.nvbaudrate 4")]).unwrap_err();
    assert!(e.contains("(remotes: none)"), "{e}");
}

/// A firmware image of 3 erase blocks and 100 bytes: block 0 (never
/// written), block 1 full, block 2 all zero, block 3 short.
fn image() -> Vec<u8> {
    let mut v = vec![0u8; 3 * 1024 + 100];
    for (i, b) in v.iter_mut().enumerate() {
        if !(2048..3072).contains(&i) {
            *b = (i % 251) as u8 | 1;
        }
    }
    v
}

fn firmware_dir(bytes: &[u8]) -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(d.path().join("hm2/7i77")).unwrap();
    std::fs::write(d.path().join("hm2/7i77/7I77.BIN"), bytes).unwrap();
    d
}

fn flash_args(dir: &Path, remote: &str, file: &str) -> Vec<String> {
    vec![
        format!("cmd=flash {remote} {file}"),
        format!("firmware_dir={}", dir.display()),
    ]
}

fn flash(h: &Host, dir: &Path, remote: &str, file: &str) -> Result<(), Refused> {
    let args = flash_args(dir, remote, file);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    setsserial(h, &args)
}

#[test]
fn setup_mode_names_the_remotes_and_flash_writes_the_file() {
    let (h, sim) = board("setss-flash", &["sserial_baudrate=115200"]);
    let inst = h.instance();
    assert!(
        inst.pin(&format!("{IO}.output-00")).unwrap().is_none(),
        "no pins"
    );
    assert!(inst.pin("hm2_5i25.0.sserial.port-0.run").unwrap().is_none());
    let img = image();
    let dir = firmware_dir(&img);
    flash(&h, dir.path(), IO, "hm2/7i77/7I77.BIN").unwrap();
    let (flash, erases, writes) = sim.with(|m| {
        let f = &m.sserial().remote(0, 0).unwrap().flash;
        (f.bytes.clone(), f.erases, f.writes)
    });
    assert!(
        flash[..1024].iter().all(|&b| b == 0xFF),
        "block 0 untouched"
    );
    assert_eq!(flash[1024..2048], img[1024..2048]);
    assert!(
        flash[2048..3072].iter().all(|&b| b == 0xFF),
        "empty block skipped"
    );
    assert_eq!(flash[3072..3172], img[3072..3172]);
    assert!(
        flash[3172..3200].iter().all(|&b| b == 0),
        "last chunk padded"
    );
    assert!(
        flash[3200..].iter().all(|&b| b == 0xFF),
        "nothing past the file"
    );
    assert_eq!((erases, writes), (2, 16 + 2));
    // The other channel is untouched.
    let other = sim.with(|m| m.sserial().remote(0, 1).unwrap().flash.writes);
    assert_eq!(other, 0);
}

#[test]
fn flash_refuses_what_it_cannot_do() {
    let img = image();
    let dir = firmware_dir(&img);
    // Not in setup mode.
    let (h, _) = board("setss-flash-baud", &[]);
    let e = flash(&h, dir.path(), IO, "hm2/7i77/7I77.BIN").unwrap_err();
    assert!(
        e.contains("sserial_baudrate=115200 (it was not given)"),
        "{e}"
    );
    let (h, _) = board("setss-flash-baud2", &["sserial_baudrate=2500000"]);
    let e = flash(&h, dir.path(), IO, "hm2/7i77/7I77.BIN").unwrap_err();
    assert!(e.contains("(it was 2500000)"), "{e}");

    let (h, sim) = board("setss-flash-bad", &["sserial_baudrate=115200"]);
    let e = flash(&h, dir.path(), IO, "hm2/7i77/7I77.BIT").unwrap_err();
    assert!(e.contains("not a .BIN file"), "{e}");
    let e = flash(&h, dir.path(), IO, "hm2/7i77/NONE.BIN").unwrap_err();
    assert!(e.contains("NONE.BIN") && e.contains("No such file"), "{e}");
    let e = flash(&h, dir.path(), IO, "../x.BIN").unwrap_err();
    assert!(e.contains("'..'"), "{e}");
    let e = flash(&h, dir.path(), "hm2_5i25.0.7i77.0.7", "hm2/7i77/7I77.BIN").unwrap_err();
    assert!(e.contains("no Smart Serial remote"), "{e}");
    // Too large: refused before anything is read past the limit.
    let big = dir.path().join("hm2/7i77/BIG.BIN");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(hostmot2::setsserial::MAX_BIN_BYTES + 1)
        .unwrap();
    let e = flash(&h, dir.path(), IO, "hm2/7i77/BIG.BIN").unwrap_err();
    assert!(e.contains("larger than 1048576 bytes"), "{e}");
    std::fs::create_dir(dir.path().join("hm2/D.BIN")).unwrap();
    let e = flash(&h, dir.path(), IO, "hm2/D.BIN").unwrap_err();
    assert!(e.contains("not a regular file"), "{e}");

    // An FPGA whose Smart Serial firmware is too old.
    sim.with(|m| m.sserial().ports[0].set_local(local::MINOR_REV, 33));
    let e = flash(&h, dir.path(), IO, "hm2/7i77/7I77.BIN").unwrap_err();
    assert!(
        e.contains("needs Smart Serial firmware version 34") && e.contains("runs version 33"),
        "{e}"
    );
    sim.with(|m| m.sserial().ports[0].set_local(local::MINOR_REV, 43));

    // A remote out of step: its cookie is wrong after the erase.
    sim.with(|m| m.sserial().remote(0, 0).unwrap().flash.cookie = 0x11);
    let e = flash(&h, dir.path(), IO, "hm2/7i77/7I77.BIN").unwrap_err();
    assert!(
        e.contains("erase (block 1)") && e.contains("sync failed") && e.contains("0x11"),
        "{e}"
    );
    sim.with(|m| m.sserial().remote(0, 0).unwrap().flash.cookie = 0x5A);

    // A processor that hangs mid-way: a bounded wait, then the error.
    sim.with(|m| m.sserial().ports[0].stuck = true);
    let e = flash(&h, dir.path(), IO, "hm2/7i77/7I77.BIN").unwrap_err();
    assert!(e.contains("not done after 1000 ms"), "{e}");
}

/// A Smithy 5i20 with its 8I20, hostmot2 loaded with `core`.
fn smithy(tag: &str, core: &[&str]) -> (Host, Arc<SimHm2>) {
    let h = Host::create(HostConfig::for_tests(tag)).unwrap();
    h.loadrt(&HOSTMOT2_MODULE, core).unwrap();
    h.loadrt(
        &HM2_PCI_MODULE,
        &[
            "config=firmware=hm2/5i20/sssvst2_2_4_v31.bit num_encoders=1 num_pwmgens=0 num_stepgens=4 sserial_port_0=0xxxxxxx",
            "sim=5i20",
        ],
    )
    .unwrap();
    let sim = hal_driver::sim::find::<SimHm2>(h.instance().name(), "hm2_5i20.0").unwrap();
    (h, sim)
}

#[test]
fn the_8i20s_maximum_current_and_its_flash() {
    let (h, sim) = smithy("setss-8i20", &[]);
    setsserial(&h, &["cmd=set hm2_8i20.0820.nvmaxcurrent 750"]).unwrap();
    assert_eq!(global(&sim, 0, "nvmaxcurrent"), Some(750));

    // Flashing an 8I20 needs SSLBP 37; a 7I77 would do with 34.
    let (h, sim) = smithy("setss-8i20-flash", &["sserial_baudrate=115200"]);
    let img = image();
    let dir = firmware_dir(&img);
    sim.with(|m| m.sserial().ports[0].set_local(local::MINOR_REV, 36));
    let e = flash(&h, dir.path(), "hm2_5i20.0.8i20.0.0", "hm2/7i77/7I77.BIN").unwrap_err();
    assert!(
        e.contains("version 37 or later") && e.contains("runs version 36"),
        "{e}"
    );
    sim.with(|m| m.sserial().ports[0].set_local(local::MINOR_REV, 37));
    flash(&h, dir.path(), "hm2_5i20.0.8i20.0.0", "hm2/7i77/7I77.BIN").unwrap();
    let block1 = sim.with(|m| m.sserial().remote(0, 0).unwrap().flash.bytes[1024..2048].to_vec());
    assert_eq!(block1, img[1024..2048]);
}

#[test]
fn a_running_port_starts_again_after_set() {
    let (h, sim) = board("setss-running", &[]);
    h.create_thread("servo", 1_000_000, false, None).unwrap();
    h.addf("hm2_5i25.0.read", "servo", -1).unwrap();
    h.addf("hm2_5i25.0.write", "servo", -1).unwrap();
    h.start().unwrap();
    let inst = h.instance();
    let state = || {
        inst.pin_value("hm2_5i25.0.sserial.port-0.port_state")
            .unwrap()
    };
    let wait_running = || {
        let end = std::time::Instant::now() + std::time::Duration::from_secs(20);
        while state() != hal_core::Value::U32(3) {
            assert!(
                std::time::Instant::now() < end,
                "port never ran: {:?}",
                state()
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
    };
    wait_running();
    setsserial(&h, &[&format!("cmd=set {IO}.nvwatchdogtimeout 40")]).unwrap();
    assert_eq!(global(&sim, 0, "NVWatchDogTimeout"), Some(40));
    wait_running();
    assert_eq!(
        inst.pin_value("hm2_5i25.0.sserial.port-0.fault-count")
            .unwrap(),
        hal_core::Value::U32(0)
    );
    h.stop();
}
