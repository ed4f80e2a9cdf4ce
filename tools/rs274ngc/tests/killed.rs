//! rs274 stopped by a signal while a program loops forever: every line
//! it printed before the loop is already out, none waits in a buffer.

use std::io::Read;
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

#[test]
fn the_lines_before_an_endless_loop_are_out_before_it_is_killed() {
    let dir = std::env::temp_dir().join(format!("rs274-killed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let program = dir.join("forever.ngc");
    // Three moves, then a loop that prints nothing and never ends.
    std::fs::write(
        &program,
        "G21 G90\nG1 X1 F100\nG1 Y2\nG1 Z3\n#1 = 0\no100 while [1]\n#1 = [#1 + 1]\no100 endwhile\nM2\n",
    )
    .unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_rs274"))
        .arg(&program)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let (tx, rx) = mpsc::channel();
    let reader = std::thread::spawn(move || {
        let mut out = Vec::new();
        let mut buf = [0u8; 4096];
        loop {
            match stdout.read(&mut buf) {
                Ok(0) | Err(_) => break,
                Ok(n) => {
                    out.extend_from_slice(&buf[..n]);
                    if String::from_utf8_lossy(&out)
                        .contains("STRAIGHT_FEED(1.0000, 2.0000, 3.0000")
                    {
                        let _ = tx.send(());
                    }
                }
            }
        }
        out
    });
    // The third move's line arrives while the loop runs (a buffered
    // writer would hold it until exit, which never comes).
    let arrived = rx.recv_timeout(Duration::from_secs(30)).is_ok();
    child.kill().unwrap();
    child.wait().unwrap();
    let text = String::from_utf8(reader.join().unwrap()).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        arrived,
        "the moves before the loop were not printed: {text:?}"
    );
    assert!(text.ends_with('\n'), "{text:?}");
}
