use std::sync::Arc;

use hal_core::{Host, HostConfig, Value};
use hal_driver::sim::SimBoard;

use super::sim::{SpeakerModel, PORT_B};
use super::{load_on, MODULE, SIM_KEY};

fn board(host: &Host) -> Arc<SimBoard<SpeakerModel>> {
    hal_driver::sim::find(host.instance().name(), SIM_KEY).expect("the simulated speaker")
}

/// Runs `speaker.0.write` once, through a 1 ms thread started for one
/// cycle.
fn cycle(host: &Host) {
    let inst = host.instance();
    let before = inst.threads().unwrap()[0].cycles;
    host.start().unwrap();
    let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
    while inst.threads().unwrap()[0].cycles == before {
        assert!(std::time::Instant::now() < end, "the thread did not run");
        std::thread::sleep(std::time::Duration::from_micros(200));
    }
    host.stop();
}

#[test]
fn linuxcnc_names_and_a_click_per_change() {
    let host = Host::create(HostConfig::for_tests("speaker")).unwrap();
    host.loadrt(&MODULE, &["backend=sim"]).unwrap();
    let inst = host.instance();
    let mut pins: Vec<String> = inst
        .pins()
        .unwrap()
        .into_iter()
        .map(|p| p.name)
        .filter(|n| !n.ends_with(".time"))
        .collect();
    pins.sort();
    let want: Vec<String> = (0..8)
        .map(|i| format!("speaker.0.pin-{i:02}-out"))
        .collect();
    assert_eq!(pins, want);
    let functs: Vec<String> = inst.functs().unwrap().into_iter().map(|f| f.name).collect();
    assert_eq!(functs, ["speaker.0.write"]);
    host.create_thread("t", 10_000_000, true, None).unwrap();
    host.addf("speaker.0.write", "t", -1).unwrap();
    let b = board(&host);
    // Untouched inputs: no click, both low bits off.
    cycle(&host);
    assert_eq!(b.with(|m| (m.clicks(), m.port_b() & 3)), (0, 0));
    // A change clicks once: the bit is set in that run, cleared next.
    inst.set_pin("speaker.0.pin-03-out", Value::Bit(true))
        .unwrap();
    cycle(&host);
    assert_eq!(b.with(|m| (m.clicks(), m.port_b() & 3)), (1, 2));
    cycle(&host);
    assert_eq!(b.with(|m| (m.clicks(), m.port_b() & 3)), (1, 0));
    inst.set_pin("speaker.0.pin-07-out", Value::Bit(true))
        .unwrap();
    cycle(&host);
    cycle(&host);
    assert_eq!(b.with(|m| m.clicks()), 2);
}

#[test]
fn the_other_bits_of_port_b_are_kept_and_safe_state_silences() {
    let host = Host::create(HostConfig::for_tests("speaker-bits")).unwrap();
    let b = Arc::new(SimBoard::new(SpeakerModel::new()));
    // Bit 2 and 3 (parity and channel check enables) set by someone else.
    hal_driver::bus::PortBus::outb(&*b, PORT_B, 0x0c);
    load_on(&host, b.clone()).unwrap();
    host.create_thread("t", 10_000_000, true, None).unwrap();
    host.addf("speaker.0.write", "t", -1).unwrap();
    host.instance()
        .set_pin("speaker.0.pin-00-out", Value::Bit(true))
        .unwrap();
    cycle(&host);
    assert_eq!(b.with(|m| m.port_b()), 0x0e);
    host.unload("hal_speaker").unwrap();
    assert_eq!(b.with(|m| m.port_b()), 0x0c);
}

#[test]
fn a_bad_backend_is_refused_naming_it() {
    let host = Host::create(HostConfig::for_tests("speaker-bad")).unwrap();
    let e = host
        .loadrt(&MODULE, &["backend=pcspkr"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("backend") && e.contains("pcspkr"), "{e}");
    let e = host.loadrt(&MODULE, &["count=2"]).unwrap_err().to_string();
    assert!(e.contains("count"), "{e}");
    assert!(host.instance().component("hal_speaker").unwrap().is_none());
    // auto falls back to the simulator where port I/O cannot be had, and
    // loads either way.
    host.loadrt(&MODULE, &["backend=auto"]).unwrap();
}
