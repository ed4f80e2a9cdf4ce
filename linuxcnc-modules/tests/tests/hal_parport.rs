//! hal_parport inside LinuxCNC: `hal_parport.so` in LinuxCNC's halrun
//! beside our host ([`hal_linuxcnc_tests::check`]), and its functions in
//! a LinuxCNC thread with the simulated port's loopback plug closing the
//! loop: data pin 2 drives status pin 15.

use hal_linuxcnc_tests::{check, Case};

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hal_parport_in_linuxcnc_behaves_as_in_our_host() {
    let out = check(&Case {
        module: "hal_parport",
        lib: "lcnc_hal_parport",
        // Three ports: `out` with the loopback plug, `in` and `x`.
        args: r#"cfg="0 simloop 1 sim in 2 sim x""#,
        owners: &["hal_parport"],
        run: "addf parport.0.write t
addf parport.0.read t
start
setp parport.0.pin-02-out 1
loadusr -w sleep 0.3
getp parport.0.pin-15-in
setp parport.0.pin-02-out 0
loadusr -w sleep 0.3
getp parport.0.pin-15-in
stop",
        refused: &[r#"cfg="0 bogus""#, r#"cfg="0 sim 0 simloop""#],
    });
    assert_eq!(out.theirs, ["TRUE", "FALSE"]);
    assert_eq!(out.ours, ["TRUE", "FALSE"]);
}
