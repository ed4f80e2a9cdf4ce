//! hal_motenc inside LinuxCNC: `hal_motenc.so` in LinuxCNC's halrun
//! beside our host ([`hal_linuxcnc_tests::check`]), and a servo loop on
//! the simulated MOTENC-100 closing in a LinuxCNC thread: each host's own
//! pid drives DAC 0, the simulated motor turns, encoder 0 counts, and the
//! axis settles at the commanded position.

use hal_linuxcnc_tests::{check, Case};

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hal_motenc_in_linuxcnc_behaves_as_in_our_host() {
    let out = check(&Case {
        module: "hal_motenc",
        lib: "lcnc_hal_motenc",
        args: "backend=sim sim_boards=100,lite",
        owners: &["hal_motenc"],
        run: "loadrt pid num_chan=1
setp motenc.0.enc-00-scale 800
setp pid.0.Pgain 20
setp pid.0.Dgain 0.1
setp pid.0.maxoutput 10
net fb motenc.0.enc-00-position => pid.0.feedback
net volts pid.0.output => motenc.0.dac-00-value
setp pid.0.command 2.5
setp pid.0.enable 1
addf motenc.0.encoder-read t
addf pid.0.do-pid-calcs t
addf motenc.0.dac-write t
start
loadusr -w sleep 1.5
getp motenc.0.enc-00-position
stop
unloadrt pid",
        refused: &[
            "backend=sim sim_ids=7",
            "backend=sim sim_boards=200",
            "backend=pci sim_ids=1",
        ],
    });
    for (host, values) in [("LinuxCNC", &out.theirs), ("ours", &out.ours)] {
        let pos: f64 = values
            .first()
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{host}: no position in {values:?}"));
        assert!(
            (pos - 2.5).abs() < 0.01,
            "{host}: the axis stands at {pos}, not 2.5"
        );
    }
}
