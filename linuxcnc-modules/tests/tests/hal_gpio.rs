//! hal_gpio inside LinuxCNC: `hal_gpio.so` in LinuxCNC's halrun beside
//! our host ([`hal_linuxcnc_tests::check`]), and its functions in a
//! LinuxCNC thread on the simulated chip whose n-th output is wired to
//! its n-th input.

use hal_linuxcnc_tests::{check, Case};

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hal_gpio_in_linuxcnc_behaves_as_in_our_host() {
    let out = check(&Case {
        module: "hal_gpio",
        lib: "lcnc_hal_gpio",
        args: "backend=simloop inputs=I0,I1 outputs=O0,O1 invert=O0 reset=O1",
        owners: &["hal_gpio"],
        run: "addf hal_gpio.write t
addf hal_gpio.read t
start
setp hal_gpio.O1-out 1
loadusr -w sleep 0.3
getp hal_gpio.I0-in
getp hal_gpio.I1-in
stop",
        refused: &[
            "backend=bogus inputs=A",
            "backend=sim inputs=A invert=A",
            "backend=sim inputs=A outputs=A",
        ],
    });
    // O0 is inverted (high while its pin is FALSE); O1 was set.
    assert_eq!(out.theirs, ["TRUE", "TRUE"]);
    assert_eq!(out.ours, ["TRUE", "TRUE"]);
}
