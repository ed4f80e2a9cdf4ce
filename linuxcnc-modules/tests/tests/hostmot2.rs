//! hostmot2 inside LinuxCNC: `hostmot2.so` and `hm2_pci.so` in
//! LinuxCNC's halrun beside our host ([`hal_linuxcnc_tests::check`]) on
//! a simulated 5I25 (`sim=5i25`), and a step generator moving the
//! simulated axis in a LinuxCNC thread: position-fb follows the command
//! in both hosts.

use hal_linuxcnc_tests::{check, Case};

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hm2_pci_on_a_simulated_5i25_in_linuxcnc_behaves_as_in_our_host() {
    let out = check(&Case {
        module: "hm2_pci",
        lib: "lcnc_hm2_pci",
        args: "config=\"num_encoders=1 num_stepgens=2\" sim=5i25",
        owners: &["hm2_pci"],
        run: "setp hm2_5i25.0.stepgen.00.position-scale 200
setp hm2_5i25.0.stepgen.00.maxvel 4
setp hm2_5i25.0.stepgen.00.maxaccel 40
setp hm2_5i25.0.stepgen.00.enable 1
setp hm2_5i25.0.stepgen.00.position-cmd 1.5
addf hm2_5i25.0.read t
addf hm2_5i25.0.write t
start
loadusr -w sleep 1.5
getp hm2_5i25.0.stepgen.00.position-fb
getp hm2_5i25.0.io_error
stop",
        refused: &["sim=5i99", "sim=5i25 config=\"num_encoders=x\""],
        needs: &[("hostmot2", "lcnc_hostmot2")],
    });
    out.assert_axis_at(1.5, "FALSE", "io_error");
}
