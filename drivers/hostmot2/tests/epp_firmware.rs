//! Loading a 7I43's FPGA through its CPLD over EPP, as LinuxCNC's
//! hm2_7i43 does with `firmware=`: the CPLD's registers on the simulated
//! port (the release key, the /PROGRAM pulse, the size bit, the stream),
//! and `loadrt hm2_7i43 config="firmware=..."` end to end, with the
//! simulator's own bitfiles and with a test's firmware directory.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

mod common;
use common::{has_pin, with_core};

use std::sync::Arc;

use hal_driver::sim::SimBoard;
use hostmot2::epp::cpld::{PART_200K, PART_400K};
use hostmot2::epp::hal::{sim_port, PortPlace, HM2_7I43_MODULE, HM2_7I90_MODULE};
use hostmot2::epp::EppTransport;
use hostmot2::fpga::{FpgaError, ProgramStep};
use hostmot2::sim::epp::EppPortModel;
use hostmot2::sim::xilinx;
use hostmot2::transport::Transport;

const BASE: u16 = 0x378;
const PLACE: PortPlace = PortPlace {
    base: BASE,
    base_hi: Some(BASE + 0x400),
    wide: true,
};
const COOKIE_ADDR: u32 = 0x100;
const COOKIE: u32 = 0x55AA_CAFE;

/// A simulated 7I43 (`7i43` or `7i43-2`) running its preset design, as
/// if loaded from its EEPROM, and a transport set up on its port.
fn rig(name: &str) -> (Arc<SimBoard<EppPortModel>>, EppTransport) {
    let (port, _) = sim_port(name, PLACE).unwrap();
    let mut t = EppTransport::new(port.clone(), BASE, PLACE.base_hi, true);
    t.set_up().unwrap();
    (port, t)
}

fn cookie(t: &mut EppTransport) -> u32 {
    let mut w = [0u32; 1];
    t.read(COOKIE_ADDR, &mut w).unwrap();
    w[0]
}

fn step_of(e: FpgaError) -> (ProgramStep, String) {
    match e {
        FpgaError::Program { step, reason } => (step, reason),
        e => panic!("not a programming error: {e}"),
    }
}

#[test]
fn the_cpld_takes_the_port_reports_the_part_and_loads_a_design() {
    for (name, part) in [("7i43", PART_400K), ("7i43-2", PART_200K)] {
        let (port, mut t) = rig(name);
        assert_eq!(cookie(&mut t), COOKIE, "{name}: the EEPROM's design runs");
        let cpld = t.cpld();
        cpld.reset().unwrap();
        assert_eq!(cpld.fpga_part().unwrap(), part, "{name}");
        assert!(port.with(|m| m.board().is_none()), "the design stopped");
        cpld.program(&xilinx::bitstream("SV8", part)).unwrap();
        assert_eq!(
            port.with(|m| m.loaded_design()).as_deref(),
            Some("SV8"),
            "{name}"
        );
        // A second load starts from a cleared FPGA.
        let cpld = t.cpld();
        cpld.reset().unwrap();
        assert_eq!(port.with(|m| m.loaded_design()), None);
        cpld.program(&xilinx::bitstream("SVST4_4", part)).unwrap();
        assert_eq!(port.with(|m| m.loaded_design()).as_deref(), Some("SVST4_4"));
    }
}

#[test]
fn a_stream_for_the_other_part_leaves_the_cpld_answering() {
    let (port, t) = rig("7i43-2");
    let cpld = t.cpld();
    cpld.reset().unwrap();
    cpld.program(&xilinx::bitstream("SV8", PART_400K)).unwrap();
    assert_eq!(port.with(|m| m.loaded_design()), None);
    // DONE stayed low: the CPLD still answers, with DONE low.
    cpld.reset().unwrap();
}

#[test]
fn a_pulled_cable_fails_the_reset_with_an_epp_timeout() {
    let (port, t) = rig("7i43");
    port.with(|m| m.connected = false);
    let (step, why) = step_of(t.cpld().reset().unwrap_err());
    assert_eq!(step, ProgramStep::Reset);
    assert!(
        why.contains("EPP timeout") && why.contains("0x378"),
        "{why}"
    );
}

#[test]
fn hm2_7i43_runs_the_firmware_its_config_names() {
    let h = with_core("epp-fw");
    h.rt_log().set_level(hal_core::MsgLevel::All);
    h.loadrt(
        &HM2_7I43_MODULE,
        &[
            "sim=7i43",
            "config=firmware=hm2/7i43-4/SV8.BIT num_encoders=8 num_pwmgens=8",
        ],
    )
    .unwrap();
    for pin in [
        "hm2_7i43.0.encoder.07.position",
        "hm2_7i43.0.pwmgen.07.value",
    ] {
        assert!(has_pin(&h, pin), "{pin}");
    }
    assert!(!has_pin(&h, "hm2_7i43.0.stepgen.00.position-fb"));
    h.flush_rt_log();
    let said: Vec<String> = h.rt_log().history().into_iter().map(|(_, t)| t).collect();
    assert!(
        said.iter().any(|l| l.contains(
            "firmware hm2/7i43-4/SV8.BIT: design 'sv8.ncd;UserID=0xFFFFFFFF', part '3s400tq144'"
        )),
        "{said:?}"
    );
}

/// Loads hm2_7i43 with `args`, expecting a refusal containing every `want`.
fn refused(tag: &str, args: &[&str], want: &[&str]) {
    let h = with_core(tag);
    let e = h.loadrt(&HM2_7I43_MODULE, args).unwrap_err().to_string();
    for w in want {
        assert!(e.contains(w), "{args:?}: {e}");
    }
    assert_eq!(h.loaded_components(), ["hostmot2"], "{args:?}");
}

#[test]
fn bad_firmware_is_refused_at_its_step() {
    let d = tempfile::tempdir().unwrap();
    let fw = d.path().join("hm2/7i43-2");
    std::fs::create_dir_all(&fw).unwrap();
    std::fs::write(fw.join("SV8.BIT"), xilinx::bitfile("SV8", PART_200K)).unwrap();
    std::fs::write(fw.join("BIG.BIT"), xilinx::bitfile("SV8", PART_400K)).unwrap();
    let dir = format!("firmware_dir={}", d.path().display());
    let h = with_core("epp-fw-dir");
    h.loadrt(
        &HM2_7I43_MODULE,
        &[
            "sim=7i43-2",
            "config=firmware=hm2/7i43-2/SV8.BIT",
            dir.as_str(),
        ],
    )
    .unwrap();
    assert!(has_pin(&h, "hm2_7i43.0.encoder.07.position"));
    refused(
        "epp-fw-part",
        &["sim=7i43-2", "config=firmware=hm2/7i43-2/BIG.BIT", &dir],
        &["bitfile is for the FPGA part '3s400tq144', but this board has a '3s200tq144'"],
    );
    refused(
        "epp-fw-missing",
        &["sim=7i43", "config=firmware=hm2/7i43-4/NONE.BIT", &dir],
        &["cannot read the bitfile", "NONE.BIT"],
    );
    refused(
        "epp-fw-unknown",
        &["sim=7i43", "config=firmware=hm2/7i43-4/7I77X2.BIT"],
        &["does not know the firmware '7I77X2'"],
    );
    refused(
        "epp-fw-toobig",
        &["sim=7i43", "config=firmware=hm2/7i43-4/SV12.BIT"],
        &["12 servo channels need 3 connectors"],
    );
}

#[test]
fn the_7i90_loads_from_flash_and_ignores_firmware() {
    let h = with_core("epp-7i90-fw");
    h.rt_log().set_level(hal_core::MsgLevel::All);
    h.loadrt(
        &HM2_7I90_MODULE,
        &["sim=7i90", "config=firmware=hm2/7i90/SV8.BIT"],
    )
    .unwrap();
    assert!(has_pin(&h, "hm2_7i90.0.stepgen.04.position-fb"));
    h.flush_rt_log();
    let said: Vec<String> = h.rt_log().history().into_iter().map(|(_, t)| t).collect();
    assert!(
        said.iter().any(|l| l.contains(
            "firmware=hm2/7i90/SV8.BIT ignored: this board loads its FPGA from its own flash"
        )),
        "{said:?}"
    );
}
