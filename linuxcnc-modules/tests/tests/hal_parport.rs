//! hal_parport inside LinuxCNC: `hal_parport.so` loaded by LinuxCNC's
//! halrun lists what our host lists for the same `loadrt`, its functions
//! run in a LinuxCNC thread with the simulated port's loopback plug
//! closing the loop, wrong parameters get our host's refusals and leave
//! nothing behind, and 100 loads and unloads take no HAL shared memory
//! beyond what LinuxCNC's halcmd keeps of each `loadrt` line itself.
//!
//! One LinuxCNC session and one of our host for all of it.

use hal_linuxcnc_tests::{getp_values, halcmd_args_record, linuxcnc, listing, ours, shm_used};

/// Three ports: `out` with the loopback plug, `in` and `x`.
const ARGS: &str = r#"cfg="0 simloop 1 sim in 2 sim x""#;
const CYCLES: usize = 100;

/// Splits script-mode output at the lines `gets mark` prints.
fn sections(stdout: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    for l in stdout.lines() {
        if matches!(l.trim(), "101" | "102") {
            out.push(String::new());
        } else {
            let last = out.len() - 1;
            out[last].push_str(l);
            out[last].push('\n');
        }
    }
    out
}

/// What both hosts run: the listing, a thread with the loopback, then
/// refused loads.
fn session() -> String {
    format!(
        "loadrt threads name1=t period1=1000000
newsig mark s32
loadrt hal_parport {ARGS}
show pin
show param
show funct
sets mark 101
gets mark
addf parport.0.write t
addf parport.0.read t
start
setp parport.0.pin-02-out 1
loadusr -w sleep 0.3
getp parport.0.pin-15-in
setp parport.0.pin-02-out 0
loadusr -w sleep 0.3
getp parport.0.pin-15-in
stop
unloadrt hal_parport
loadrt hal_parport cfg=\"0 bogus\"
loadrt hal_parport cfg=\"0 sim 0 simloop\"
show pin
show funct
sets mark 102
gets mark
"
    )
}

/// LinuxCNC only: load and unload again and again, with `status` after
/// a first round and after the rest.
fn cycles() -> String {
    let mut s = format!("loadrt hal_parport {ARGS}\nunloadrt hal_parport\nstatus\n");
    for _ in 0..CYCLES {
        s.push_str(&format!(
            "loadrt hal_parport {ARGS}\nunloadrt hal_parport\n"
        ));
    }
    s.push_str("status\n");
    s
}

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hal_parport_in_linuxcnc_behaves_as_in_our_host() {
    let modules = hal_linuxcnc_tests::Modules::stage(&[("hal_parport", "lcnc_hal_parport")]);
    let theirs = linuxcnc(&modules, &(session() + &cycles()));
    let mine = ours("lcnc-parport", &session());
    let (t, m) = (sections(&theirs.stdout), sections(&mine.stdout));
    assert!(
        t.len() == 3 && m.len() == 3,
        "marks missing:\n{}\n---\n{}",
        theirs.stdout,
        theirs.stderr
    );

    // The same pins, parameters and functions.
    let (lt, lm) = (listing(&t[0], "hal_parport"), listing(&m[0], "hal_parport"));
    assert!(lm.len() > 100, "our listing: {lm:?}");
    assert_eq!(lt, lm, "LinuxCNC's listing differs from ours");

    // The loopback plug closes the loop in a LinuxCNC thread.
    assert_eq!(getp_values(&t[1]), ["TRUE", "FALSE"], "{}", theirs.stderr);
    assert_eq!(getp_values(&m[1]), ["TRUE", "FALSE"]);

    // Refused loads: the same messages, and nothing of them stays.
    assert!(listing(&t[1], "hal_parport").is_empty(), "{}", t[1]);
    let refusals: Vec<&str> = mine
        .stderr
        .lines()
        .filter_map(|l| l.find("hal_parport: ").map(|i| &l[i..]))
        .collect();
    assert_eq!(refusals.len(), 2, "our host: {}", mine.stderr);
    for r in refusals {
        assert!(
            theirs.stderr.contains(r),
            "LinuxCNC did not say {r:?}:\n{}",
            theirs.stderr
        );
    }

    // 100 loads and unloads: only halcmd's own record of each line.
    let used = shm_used(&t[2]);
    assert_eq!(used.len(), 2, "{}", t[2]);
    assert_eq!(
        used[1] - used[0],
        CYCLES as u64 * halcmd_args_record(&[ARGS]),
        "HAL shared memory grew by more than halcmd's records of the loadrt lines"
    );
}
