//! configs/sim/hal-input.hal, run as halrun runs it (a host serving the
//! instance, a halcmd session reading the file from its directory,
//! `loadusr -W hal_input` starting the real program on the simulated
//! devices beside it): the pendant's button and wheel set a feed
//! override, the joystick a jog speed; `unloadusr` releases them.
//!
//! Alone in its test binary: it changes the working directory, as
//! halrun's user would.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use hal_core::{Instance, Value};
use hal_driver::testing::wait;
use hal_host::testing::InProcessHost;
use std::path::Path;

fn float(inst: &Instance, sig: &str) -> f64 {
    match inst.signal_value(sig).unwrap() {
        Value::Float(v) => v,
        v => panic!("{sig} is {v:?}"),
    }
}

#[test]
fn the_hal_input_config_runs_on_simulated_devices() {
    let host = InProcessHost::start("hal-input-config");
    let inst = host.instance();

    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/sim");
    std::env::set_current_dir(&dir).unwrap();
    std::env::remove_var("HAL_INPUT_SIM");
    let text = std::fs::read_to_string("hal-input.hal").unwrap();
    let (ok, out, err) = host.run("hal-input.hal", &text, false);
    let said = format!("{out}\n{err}");
    assert!(ok, "{said}");
    assert!(said.contains("feed-override"), "{said}");
    let c = inst.component("hal_input").unwrap().unwrap();
    assert!(c.ready);
    wait("the override at 0.8", || {
        (float(&inst, "feed-override") - 0.8).abs() < 1e-9
    });
    assert_eq!(
        inst.signal_value("override-enable").unwrap(),
        Value::Bit(true)
    );
    wait("the stick right", || float(&inst, "stick-x") == 1.0);
    wait("the jog speed full", || float(&inst, "jog-speed") > 0.99);

    // unloadusr: hal_input goes, leaving the button released and the
    // stick centred in their signals.
    let (ok, _, err) = host.run("unload.hal", "unloadusr hal_input\n", false);
    assert!(ok, "{err}");
    assert!(inst.component("hal_input").unwrap().is_none());
    assert_eq!(
        inst.signal_value("override-enable").unwrap(),
        Value::Bit(false)
    );
    assert!(float(&inst, "stick-x").abs() < 0.01);
    wait("the jog speed back to zero", || {
        float(&inst, "jog-speed").abs() < 1e-9
    });
    drop(inst);
    drop(host);
}
