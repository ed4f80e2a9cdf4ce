//! hm2_test inside LinuxCNC: `hostmot2.so` and `hm2_test.so` in
//! LinuxCNC's halrun beside our host. Every test pattern (0 to 14) is a
//! board whose registration must fail at one check: in both hosts each
//! load is refused with the same message, LinuxCNC's log holds the line
//! LinuxCNC's own hm2_test test looks for, an unknown pattern is refused
//! alike, and nothing of hm2_test is left.

use hal_linuxcnc_tests::{linuxcnc, listing, ours, Modules};

/// Test patterns 0 to 14, and one that does not exist.
const PATTERNS: std::ops::RangeInclusive<u32> = 0..=15;

/// The session both hosts run: every pattern, then what is left.
fn session() -> String {
    let mut s = String::from("loadrt hostmot2\n");
    for n in PATTERNS {
        s.push_str(&format!("loadrt hm2_test test_pattern={n}\n"));
    }
    s.push_str("show pin\nshow param\nshow funct\n");
    s
}

/// Our host's refusals of the loads, as LinuxCNC's rtapi_app prints
/// them too (without our halcmd's `HAL: ERROR: ` in front).
fn refusals(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter_map(|l| l.strip_prefix("HAL: ERROR: "))
        .filter(|l| l.starts_with("hm2_test: "))
        .collect()
}

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hm2_test_patterns_in_linuxcnc_are_refused_as_in_our_host() {
    let modules = Modules::stage(&[("hostmot2", "lcnc_hostmot2"), ("hm2_test", "lcnc_hm2_test")]);
    let theirs = linuxcnc(&modules, &session());
    let mine = ours("lcnc-hm2-test", &session());

    let refused = refusals(&mine.stderr);
    assert_eq!(refused.len(), 16, "{}", mine.stderr);
    assert!(
        refused[15].ends_with("unknown test pattern 15"),
        "{}",
        mine.stderr
    );
    for line in refused {
        assert!(
            theirs.stderr.contains(line),
            "LinuxCNC did not say {line:?}:\n{}",
            theirs.stderr
        );
    }
    // The line LinuxCNC's own hm2_test test looks for, per pattern: in
    // LinuxCNC's log (our host logs it to the realtime log, not halcmd).
    for n in 0..=14 {
        let message = hostmot2::test_patterns::expected_message(n).expect("a pattern's message");
        assert!(
            theirs
                .stderr
                .contains(&format!("hm2/hm2_test.0: {message}")),
            "LinuxCNC did not log {message:?} for pattern {n}:\n{}",
            theirs.stderr
        );
    }
    for (host, out) in [("LinuxCNC", &theirs.stdout), ("ours", &mine.stdout)] {
        assert!(
            listing(out, "hm2_test").is_empty(),
            "{host} kept something of hm2_test:\n{out}"
        );
        assert!(
            !out.contains("hm2_test."),
            "{host} kept something of hm2_test:\n{out}"
        );
    }
}
