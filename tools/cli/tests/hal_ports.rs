//! HAL port signals through halcmd: `newsig NAME port`, `sets` making the
//! buffer once, `show` and `save`, with LinuxCNC 2.9's messages (its
//! `halrun` on the same lines printed these).

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use hal_host::testing::InProcessHost;

#[test]
fn port_signals_are_sized_once_and_shown_by_size() {
    let host = InProcessHost::start("halports");
    let script = "newsig p port\nsets p 100\nsets p 200\nsets p abc\nnewsig q port\nsets q 0\nsave sig\nshow sig\n";
    let (ok, out, err) = host.run("ports.hal", script, true);
    assert!(!ok, "the refused sets fail the run");
    assert_eq!(
        err,
        "ports.hal:3: port is already allocated with 100 bytes.\n\
         ports.hal:3: sets failed\n\
         ports.hal:4: value 'abc' invalid for PORT\n\
         ports.hal:4: sets failed\n"
    );
    // `save` names the type padded to five, as LinuxCNC does ("port ").
    assert!(
        out.contains("# signals\nnewsig p port \nnewsig q port \n"),
        "{out}"
    );
    let shown: Vec<Vec<&str>> = out
        .lines()
        .filter(|l| l.starts_with("port "))
        .map(|l| l.split_whitespace().collect())
        .collect();
    assert_eq!(shown, [["port", "100", "p"], ["port", "0", "q"]], "{out}");
    assert_eq!(
        host.instance().signal_value("p").unwrap(),
        hal_core::Value::Port(100)
    );
}
