//! The pin model against the simulated terminals: every entry a pin of a
//! typed slave reads or writes is mapped by that slave's default PDO
//! assignment with the same size, in the direction the pin's kind says
//! (inputs of the slave for HAL_OUT pins, outputs for HAL_IN ones).
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::path::Path;

use hal_ethercat::lcec::{conf, slave_pins, Kind};
use hal_ethercat::sim::od::AssignedPdo;
use hal_ethercat::sim::{self, device::ASSIGN_INPUTS, device::ASSIGN_OUTPUTS};

fn typed_slave(kind: &str) -> conf::Slave {
    let vidpid = if kind == "basic_cia402" {
        r#" vid="0x539" pid="0x2200001""#
    } else {
        ""
    };
    let text = format!(
        r#"<masters><master idx="0" appTimePeriod="1000000" refClockSyncCycles="1"><slave idx="0" type="{kind}" name="s"{vidpid}/></master></masters>"#
    );
    conf::parse(&text, Path::new("t.xml")).unwrap().masters[0].slaves[0].clone()
}

#[test]
fn every_pin_entry_is_mapped_by_the_simulated_terminal() {
    for (kind, device) in [
        ("EL1008", "EL1008"),
        ("EL1018", "EL1018"),
        ("EL2008", "EL2008"),
        ("EL2088", "EL2088"),
        ("EL3102", "EL3102"),
        ("EL4102", "EL4102"),
        ("EL5101", "EL5101"),
        ("EL7041", "EL7041"),
        ("basic_cia402", "servo"),
    ] {
        let dev = sim::device_by_name(device, 1).unwrap();
        let inputs = dev.od.assigned(ASSIGN_INPUTS);
        let outputs = dev.od.assigned(ASSIGN_OUTPUTS);
        let mapped = |pdos: &[AssignedPdo], e: (u16, u8, u8)| {
            pdos.iter().flat_map(|(_, es)| es).any(|x| *x == e)
        };
        let pins = slave_pins(&typed_slave(kind), Path::new("t.xml")).unwrap();
        assert!(!pins.is_empty(), "{kind}");
        for p in pins {
            let Some(e) = p.entry else { continue };
            let key = (e.index, e.sub, e.bits);
            let (in_inputs, in_outputs) = (mapped(&inputs, key), mapped(&outputs, key));
            match p.kind {
                Kind::Out => assert!(in_inputs || in_outputs, "{kind} {}: {key:x?}", p.name),
                Kind::In | Kind::Io => {
                    assert!(in_outputs, "{kind} {}: {key:x?} not an output", p.name)
                }
                Kind::Param => assert!(in_inputs || in_outputs || p.name == "srv-opmode"),
            }
        }
    }
}
