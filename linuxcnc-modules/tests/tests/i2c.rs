//! The I2C chip modules inside LinuxCNC: `pca9685.so`, `mcp23017.so` and
//! `ads1115.so` in LinuxCNC's halrun beside our host
//! ([`hal_linuxcnc_tests::check`]), each with its chips on a simulated
//! bus served by the module's helper thread, and its functions running
//! in a LinuxCNC thread: the chips answer (no fault, no error), and the
//! MCP23017's input pins read their pull-ups.

use hal_linuxcnc_tests::{check, Case};

/// `getp`s of a chip's fault and error count, for `run`.
fn status(chip: &str) -> String {
    format!("getp {chip}.fault\ngetp {chip}.errors\n")
}

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn pca9685_in_linuxcnc_behaves_as_in_our_host() {
    let run = format!(
        "addf pca9685.0.read t\naddf pca9685.0.write t\naddf pca9685.1.read t\naddf pca9685.1.write t\n\
         setp pca9685.0.pwmgen.03.enable 1\nsetp pca9685.0.pwmgen.03.value 0.25\nstart\n\
         loadusr -w sleep 0.3\n{}{}stop",
        status("pca9685.0"),
        status("pca9685.1")
    );
    let out = check(&Case {
        module: "pca9685",
        lib: "lcnc_pca9685",
        args: "backend=sim address=0x40,0x41 bus=1,2 freq=50,1000 invert=0,1",
        owners: &["pca9685"],
        run: &run,
        refused: &[
            "backend=sim freq=5",
            "backend=sim address=0x40,0x40",
            "backend=sim address=0x10",
        ],
    });
    assert_eq!(out.theirs, ["FALSE", "0", "FALSE", "0"]);
    assert_eq!(out.ours, out.theirs);
}

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn mcp23017_in_linuxcnc_behaves_as_in_our_host() {
    let run = format!(
        "addf mcp23017.0.read t\naddf mcp23017.0.write t\nsetp mcp23017.0.digout.15.out 1\nstart\n\
         loadusr -w sleep 0.3\ngetp mcp23017.0.digin.00.in\ngetp mcp23017.0.digin.03.in\n\
         getp mcp23017.0.digin.04.in\n{}stop",
        status("mcp23017.0")
    );
    let out = check(&Case {
        module: "mcp23017",
        lib: "lcnc_mcp23017",
        args: "backend=sim dir=0x00ff pullup=0x000f",
        owners: &["mcp23017"],
        run: &run,
        refused: &[
            "backend=sim dir=0x00ff pullup=0x0100",
            "backend=sim dir=0x10000",
        ],
    });
    // Pins 0..3 have their pull-ups on, pin 4 floats.
    assert_eq!(out.theirs, ["TRUE", "TRUE", "FALSE", "FALSE", "0"]);
    assert_eq!(out.ours, out.theirs);
}

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn ads1115_in_linuxcnc_behaves_as_in_our_host() {
    let run = format!(
        "addf ads1115.0.read t\nstart\nloadusr -w sleep 0.3\ngetp ads1115.0.adcin.0.value\n{}stop",
        status("ads1115.0")
    );
    let out = check(&Case {
        module: "ads1115",
        lib: "lcnc_ads1115",
        args: "backend=sim range=2048 rate=475 channels=3",
        owners: &["ads1115"],
        run: &run,
        refused: &["backend=sim range=5000", "backend=sim diff=1 channels=3"],
    });
    assert_eq!(out.theirs, ["0", "FALSE", "0"]);
    assert_eq!(out.ours, out.theirs);
}
