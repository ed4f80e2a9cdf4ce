//! hal_stg inside LinuxCNC: `hal_stg.so` in LinuxCNC's halrun beside our
//! host ([`hal_linuxcnc_tests::check`]), and a servo loop on the
//! simulated Servo-To-Go closing in a LinuxCNC thread: each host's own
//! pid drives DAC 0, the simulated motor turns, counter 0 counts, and the
//! axis settles at the commanded position.

use hal_linuxcnc_tests::{check, Case};

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hal_stg_in_linuxcnc_behaves_as_in_our_host() {
    let out = check(&Case {
        module: "hal_stg",
        lib: "lcnc_hal_stg",
        args: "backend=sim num_chan=4 dio=IOIO",
        owners: &["hal_stg"],
        run: "loadrt pid num_chan=1
setp stg.0.position-scale 800
setp pid.0.Pgain 20
setp pid.0.Dgain 0.1
setp pid.0.maxoutput 10
net fb stg.0.position => pid.0.feedback
net volts pid.0.output => stg.0.dac-value
setp pid.0.command -1.5
setp pid.0.enable 1
addf stg.capture-position t
addf pid.0.do-pid-calcs t
addf stg.write-dacs t
start
loadusr -w sleep 1.5
getp stg.0.position
stop
unloadrt pid",
        refused: &[
            "backend=sim num_chan=9",
            "backend=sim dio=IOX",
            "backend=bogus",
        ],
    });
    for (host, values) in [("LinuxCNC", &out.theirs), ("ours", &out.ours)] {
        let pos: f64 = values
            .first()
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{host}: no position in {values:?}"));
        assert!(
            (pos + 1.5).abs() < 0.01,
            "{host}: the axis stands at {pos}, not -1.5"
        );
    }
}
