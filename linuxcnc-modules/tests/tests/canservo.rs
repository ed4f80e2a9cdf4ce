//! canservo inside LinuxCNC: `canservo.so` in LinuxCNC's halrun beside
//! our host ([`hal_linuxcnc_tests::check`]), with two CiA 402 drives on
//! the module's simulated CAN bus (booted, identified and configured by
//! SDO at load), and its functions in a LinuxCNC thread: drive 0 powers
//! up to Operation enabled and follows a position command, and the bus
//! counts no errors.

use hal_linuxcnc_tests::{check, Case};

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn canservo_in_linuxcnc_behaves_as_in_our_host() {
    let out = check(&Case {
        module: "canservo",
        lib: "lcnc_canservo",
        args: "backend=sim nodes=3,5 scale=1000,2000 diag_ms=0",
        owners: &["canservo"],
        run: "addf canservo.read t
addf canservo.write t
setp canservo.0.enable 1
start
loadusr -w sleep 1
getp canservo.0.enabled
getp canservo.0.state
setp canservo.0.position-cmd 0.5
loadusr -w sleep 1
getp canservo.0.position-fb
getp canservo.0.amp-fault
getp canservo.bus-errors
stop",
        refused: &[
            "backend=sim",
            "backend=sim nodes=1,1",
            "backend=sim nodes=1 mode=xyz",
            "iface=nocan7 nodes=1",
        ],
        needs: &[],
    });
    for (host, values) in [("LinuxCNC", &out.theirs), ("ours", &out.ours)] {
        assert_eq!(values.len(), 5, "{host}: {values:?}");
        assert_eq!(values[..2], ["TRUE", "5"], "{host}: {values:?}");
        let pos: f64 = values[2]
            .parse()
            .unwrap_or_else(|_| panic!("{host}: no position in {values:?}"));
        assert!(
            (pos - 0.5).abs() < 0.002,
            "{host}: drive 0 stands at {pos}, not 0.5"
        );
        assert_eq!(values[3..], ["FALSE", "0"], "{host}: {values:?}");
    }
}
