//! `hm2_spi` and `hm2_rpspi` on simulated SPI links: the board found by
//! its IDROM name and named as LinuxCNC names it, its modules running
//! over Mesa's SPI frames, the parameters checked with clear errors, and
//! real devices refused cleanly when absent.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;
use common::{has_pin, with_core};

use hal_core::Value::{Bit, Float};
use hostmot2::sim::spi::SpiBoardModel;
use hostmot2::spi::hal::{HM2_RPSPI_MODULE, HM2_SPI_MODULE};
use hostmot2::spi::{frame::Command, identify, SpiTransport};
use std::sync::Arc;

use hal_driver::sim::SimBoard;

#[test]
fn hm2_spi_finds_a_7i90_and_names_it() {
    let h = with_core("spi-7i90");
    h.loadrt(
        &HM2_SPI_MODULE,
        &[
            "sim=7i90",
            "spidev_path=/dev/spidev0.0",
            "config=num_stepgens=5 num_encoders=2",
        ],
    )
    .unwrap();
    for pin in [
        "hm2_7i90.0.stepgen.04.position-cmd",
        "hm2_7i90.0.encoder.01.position",
        "hm2_7i90.0.pwmgen.00.value",
        "hm2_7i90.0.gpio.071.in",
    ] {
        assert!(has_pin(&h, pin), "{pin}");
    }
    assert!(!has_pin(&h, "hm2_7i90.0.encoder.02.position"));
}

#[test]
fn hm2_rpspi_probes_in_order_and_the_stepgens_move() {
    let h = with_core("spi-rpspi");
    h.loadrt(
        &HM2_RPSPI_MODULE,
        &[
            "spi_probe=5",
            "sim=7c80,7c81",
            "spiclk_rate=12500",
            "spiclk_rate_rd=6250",
            "config=num_stepgens=6,num_stepgens=5",
        ],
    )
    .unwrap();
    assert!(has_pin(&h, "hm2_7c80.0.stepgen.05.position-cmd"));
    assert!(has_pin(&h, "hm2_7c81.0.stepgen.04.position-cmd"));
    assert!(has_pin(&h, "hm2_7c80.0.gpio.053.in"));
    assert!(has_pin(&h, "hm2_7c81.0.gpio.056.in"));
    let inst = h.instance();
    inst.set_param("hm2_7c80.0.stepgen.00.position-scale", Float(100.0))
        .unwrap();
    inst.set_param("hm2_7c80.0.stepgen.00.maxvel", Float(100.0))
        .unwrap();
    inst.set_param("hm2_7c80.0.stepgen.00.maxaccel", Float(1000.0))
        .unwrap();
    inst.set_pin("hm2_7c80.0.stepgen.00.enable", Bit(true))
        .unwrap();
    inst.set_pin("hm2_7c80.0.stepgen.00.position-cmd", Float(0.5))
        .unwrap();
    h.create_thread("servo", 1_000_000, true, None).unwrap();
    h.addf("hm2_7c80.0.read", "servo", -1).unwrap();
    h.addf("hm2_7c80.0.write", "servo", -1).unwrap();
    h.start().unwrap();
    let end = std::time::Instant::now() + std::time::Duration::from_secs(30);
    loop {
        let fb = match inst.pin_value("hm2_7c80.0.stepgen.00.position-fb").unwrap() {
            Float(f) => f,
            v => panic!("{v:?}"),
        };
        if (fb - 0.5).abs() < 0.02 {
            break;
        }
        assert!(std::time::Instant::now() < end, "position-fb stays {fb}");
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    h.stop();
}

#[test]
fn bad_parameters_say_which_and_why() {
    let h = with_core("spi-params");
    for (module, args, want) in [
        (
            &HM2_SPI_MODULE,
            vec!["sim=7i90", "spidev_rate=10"],
            "spidev_rate",
        ),
        (
            &HM2_SPI_MODULE,
            vec!["sim=7i91"],
            "not a simulated SPI board",
        ),
        (
            &HM2_SPI_MODULE,
            vec!["sim=7i90", "spidev_path=spidev0.0"],
            "not a device path",
        ),
        (
            &HM2_RPSPI_MODULE,
            vec!["sim=7c80", "spi_probe=0"],
            "spi_probe",
        ),
        (
            &HM2_RPSPI_MODULE,
            vec!["sim=7c80", "spi_pull_miso=3"],
            "spi_pull_miso",
        ),
        (
            &HM2_RPSPI_MODULE,
            vec!["sim=7c80", "spiclk_rate_rd=5"],
            "spiclk_rate_rd",
        ),
        (
            &HM2_RPSPI_MODULE,
            vec!["sim=7c80,7c81"],
            "2 simulated boards for 1 places",
        ),
    ] {
        let e = h.loadrt(module, &args).unwrap_err().to_string();
        assert!(e.contains(want), "{args:?}: {e}");
        assert!(!has_pin(&h, "hm2_7i90.0.read"));
    }
    // A device that does not exist: the path and the system's words.
    let e = h
        .loadrt(&HM2_SPI_MODULE, &["spidev_path=/nonexistent/spidev9.9"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("/nonexistent/spidev9.9"), "{e}");
}

/// A device that answers zeros: no board.
struct Nothing;

impl hal_driver::bus::SpiBus for Nothing {
    fn transfer(&self, buf: &mut [u32], _speed_hz: u32) {
        buf.fill(0);
    }
    fn errors(&self) -> u64 {
        0
    }
    fn describe(&self) -> String {
        "nothing".into()
    }
}

fn link_to(spec: hostmot2::image::FirmwareSpec) -> Arc<SimBoard<SpiBoardModel>> {
    let (board, _) = hostmot2::sim::board(spec, Box::new(hostmot2::sim::machine::preset("")));
    Arc::new(SimBoard::new(SpiBoardModel::new(board)))
}

#[test]
fn identification_refuses_what_is_not_a_known_board() {
    let link = link_to(hostmot2::sim::spi::preset("7c81").unwrap());
    let mut t = SpiTransport::new(link.clone(), 1_000_000, 1_000_000);
    assert_eq!(identify(&mut t, "/dev/spidev0.0").unwrap().board, "7c81");
    assert_eq!(link.with(|m| m.frame_errors), 0);
    // A HostMot2 board the SPI drivers do not know: named.
    let other = link_to(hostmot2::sim::boards::preset("5i25").unwrap());
    let mut t = SpiTransport::new(other, 1_000_000, 1_000_000);
    let e = identify(&mut t, "/dev/spidev0.1").unwrap_err().to_string();
    assert!(e.contains("MESA5I25") && e.contains("spidev0.1"), "{e}");
    // Nothing answers: not a HostMot2 board.
    let mut t = SpiTransport::new(Arc::new(Nothing), 1_000_000, 1_000_000);
    let e = identify(&mut t, "/dev/spidev1.0").unwrap_err().to_string();
    assert!(e.contains("no HostMot2 board"), "{e}");
    // A junk message is refused by the board, not served.
    let mut junk = [Command::read(0x100, 2).encode() | 0x1, 0, 0];
    hal_driver::bus::SpiBus::transfer(&*link, &mut junk, 1);
    assert_eq!(link.with(|m| m.frame_errors), 1);
    assert_eq!(junk, [0, 0, 0]);
}
