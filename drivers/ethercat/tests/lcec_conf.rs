//! `lcec_conf` checks the configuration before it touches HAL: a bad
//! file is refused with its line and element, a good one with no HAL
//! session to keep it in says so. (configs/sim/ethercat.hal runs the
//! whole `loadusr -W lcec_conf` then `loadrt lcec` path through halrun:
//! tools/cli/tests/ethercat_config.rs.)
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::process::Command;

fn run(file: &std::path::Path, instance: &str) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_lcec_conf"))
        .arg(file)
        .env("HAL_INSTANCE", instance)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn bad_files_and_no_session_are_refused_with_what_and_where() {
    let dir = std::env::temp_dir().join(format!("hal-lcec-conf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.xml");
    std::fs::write(
        &bad,
        "<masters>\n  <master idx=\"0\" appTimePeriod=\"x\" refClockSyncCycles=\"1\"/>\n</masters>\n",
    )
    .unwrap();
    let (code, err) = run(&bad, "lcec-conf-test-none");
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("bad.xml:2") && err.contains("appTimePeriod"),
        "{err}"
    );
    let (code, err) = run(&dir.join("missing.xml"), "lcec-conf-test-none");
    assert_eq!(code, 1);
    assert!(err.contains("missing.xml"), "{err}");
    let good = dir.join("good.xml");
    std::fs::write(
        &good,
        "<masters><master idx=\"0\" appTimePeriod=\"1000000\" refClockSyncCycles=\"1\"/></masters>",
    )
    .unwrap();
    let (code, err) = run(&good, "lcec-conf-test-no-such-instance");
    assert_eq!(code, 1);
    assert!(err.contains("attaching to the HAL instance"), "{err}");
}
