//! The I/O-port path on a real kernel, in the VM rig (run as root there):
//! `ioperm` and `/dev/port` on a port range nothing decodes (base 0x340:
//! 0x340..0x35f and 0x740..0x75f on the rig's q35 machine), where the
//! probe and `loadrt` must say that nothing answers and load nothing,
//! and the search over every jumper choice finds no board. Elsewhere the
//! test is ignored, with the reason (on another machine these ports may
//! hold a real device); run on purpose outside the rig it fails.

use hal_core::{Host, HostConfig};
use hal_driver::bus::{DevPortPorts, IopermPorts, PortBus};
use hal_stg::detect::{self, Model};
use hal_stg::{StgError, MODULE};

const BASE: u16 = 0x340;

#[test]
#[ignore = "probes real I/O ports: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn empty_ports_answer_nothing_through_ioperm_and_dev_port() {
    assert!(
        std::env::var_os("VMRIG_KERNEL").is_some(),
        "not in the VM rig (VMRIG_KERNEL unset); run this binary through \
         ../shared/tools/vmrig to probe real, unused I/O ports"
    );
    let ranges = detect::port_ranges(BASE).unwrap();

    // The bring-up probe through both real backends.
    let ioperm = IopermPorts::open(&ranges).expect("ioperm as root in the VM");
    let e = hal_stg::probe(&ioperm, BASE).unwrap_err();
    assert!(matches!(e, StgError::NothingAnswers { base: BASE }), "{e}");
    assert_eq!(ioperm.inb(BASE + 0x403), 0xFF);
    assert_eq!(
        ioperm.inw(BASE + 0x410),
        0xFFFF,
        "16-bit read of the empty ADC port"
    );
    assert_eq!(ioperm.errors(), 0);
    assert_eq!(
        ioperm.inb(0x80),
        0xFF,
        "outside the declared ranges: refused"
    );
    assert_eq!(ioperm.errors(), 1);
    let devport = DevPortPorts::open(&ranges).expect("/dev/port as root in the VM");
    let e = hal_stg::probe(&devport, BASE).unwrap_err();
    assert_eq!(
        e.to_string(),
        "no board answers at 0x340 (its board test register reads 0xff: nothing decodes the port)"
    );
    assert_eq!(devport.errors(), 0);
    let sig = detect::read_signature(&devport, BASE);
    assert!(sig.empty && Model::from_signature(sig.value).is_none());

    // loadrt over ioperm: a given base, a forced model, the search; none
    // leaves anything loaded.
    let host = Host::create(HostConfig::for_tests("stg-real-ports")).unwrap();
    for args in [&["base=0x340"][..], &["base=0x340", "model=2"]] {
        let e = host.loadrt(&MODULE, args).unwrap_err().to_string();
        assert_eq!(
            e,
            "hal_stg: no board answers at 0x340 (its board test register reads 0xff: nothing \
             decodes the port)",
            "{args:?}"
        );
        assert!(host.loaded_components().is_empty());
    }
    let e = host
        .loadrt(&MODULE, &[] as &[&str])
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("hal_stg: no Servo-To-Go found at any base address"),
        "{e}"
    );
    let e = host
        .loadrt(&MODULE, &["backend=devport", "base=0x340"])
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("hal_stg: backend=devport cannot drive a Servo-To-Go"),
        "{e}"
    );
    assert!(host.loaded_components().is_empty());
    eprintln!("ioperm and /dev/port: nothing at 0x340, no board at any base, nothing loaded");
}
