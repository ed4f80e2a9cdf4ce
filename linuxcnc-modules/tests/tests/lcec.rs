//! lcec inside LinuxCNC: `lcec.so` in LinuxCNC's halrun beside our host
//! ([`hal_linuxcnc_tests::check`]), with the simulated segment of the
//! sim configuration (configs/sim/ethercat-conf.xml: a coupler, an
//! EL1008, an EL2008 and three CiA 402 drives), and its functions in a
//! LinuxCNC thread: every slave answers and reaches OP, and drive `x`
//! powers up and follows a position command.

use std::path::PathBuf;

use hal_linuxcnc_tests::{check, Case};

/// The sim configuration; LinuxCNC's rtapi_app (user nobody) reads it
/// where it is in the checkout.
fn conf() -> String {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../configs/sim/ethercat-conf.xml");
    path.canonicalize()
        .expect("configs/sim/ethercat-conf.xml")
        .display()
        .to_string()
}

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn lcec_in_linuxcnc_behaves_as_in_our_host() {
    let conf = conf();
    let args = format!("backend=sim config={conf}");
    let missing = format!("backend=sim config={conf}.missing");
    let unknown_backend = format!("backend=ring config={conf}");
    let out = check(&Case {
        module: "lcec",
        lib: "lcnc_lcec",
        args: &args,
        owners: &["lcec"],
        run: "addf lcec.read-all t
addf lcec.write-all t
setp lcec.0.x.srv-pos-scale 1000
setp lcec.0.x.srv-enable 1
start
loadusr -w sleep 1
getp lcec.all-op
getp lcec.0.slaves-responding
getp lcec.0.x.srv-enabled
setp lcec.0.x.srv-target-position 0.25
loadusr -w sleep 1
getp lcec.0.x.srv-actual-position
getp lcec.0.x.srv-fault
stop",
        refused: &[&missing, &unknown_backend],
        needs: &[],
    });
    for (host, values) in [("LinuxCNC", &out.theirs), ("ours", &out.ours)] {
        assert_eq!(values.len(), 5, "{host}: {values:?}");
        assert_eq!(values[..3], ["TRUE", "6", "TRUE"], "{host}: {values:?}");
        let pos: f64 = values[3]
            .parse()
            .unwrap_or_else(|_| panic!("{host}: no position in {values:?}"));
        assert!(
            (pos - 0.25).abs() < 0.002,
            "{host}: drive x stands at {pos}, not 0.25"
        );
        assert_eq!(values[4], "FALSE", "{host}: {values:?}");
    }
}
