//! hal_ppmc inside LinuxCNC: `hal_ppmc.so` (diverted over LinuxCNC's
//! own) in LinuxCNC's halrun beside our host ([`hal_linuxcnc_tests::check`]),
//! and a step loop on a simulated USC closing in a LinuxCNC thread: each
//! host's own pid drives step generator 0 out of estop, the simulated
//! motor steps, counter 0 counts, and the axis settles at the command.

use hal_linuxcnc_tests::{check, Case};

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hal_ppmc_in_linuxcnc_behaves_as_in_our_host() {
    let out = check(&Case {
        module: "hal_ppmc",
        lib: "lcnc_hal_ppmc",
        args: "sim=usc extradac=0x00",
        owners: &["hal_ppmc"],
        run: "loadrt pid num_chan=1
setp ppmc.0.encoder.00.scale 1000
setp ppmc.0.stepgen.00.scale 1000
setp pid.0.Pgain 50
setp pid.0.deadband 0.0015
setp pid.0.maxoutput 20
net fb ppmc.0.encoder.00.position => pid.0.feedback
net vel pid.0.output => ppmc.0.stepgen.00.velocity
setp ppmc.0.stepgen.00.enable 1
setp ppmc.0.dout.07.out 1
setp pid.0.command -1.5
setp pid.0.enable 1
addf ppmc.0.read t
addf pid.0.do-pid-calcs t
addf ppmc.0.write t
start
loadusr -w sleep 1.5
getp ppmc.0.encoder.00.position
stop
unloadrt pid",
        refused: &[
            "sim=usc extradac=0x00 extradout=0x00",
            "sim=upc:3 timestamp=0x00",
            "sim=bogus",
            "port_addr=0x10000 sim=usc",
        ],
        needs: &[],
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
