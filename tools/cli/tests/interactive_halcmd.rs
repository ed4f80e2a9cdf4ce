//! Interactive halcmd on a terminal (a pseudo-terminal here): the up
//! arrow recalls earlier commands, within a session and from the one
//! before (history kept in the user's config directory), and Tab
//! completes a pin name from the live instance.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::{AsRawFd, OwnedFd};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use nix::fcntl::{fcntl, FcntlArg, OFlag};
use nix::pty::{openpty, Winsize};

/// The cursor-position query rustyline sends, and the answer a terminal
/// at column 1 gives.
const CURSOR_QUERY: &str = "\x1b[6n";
const CURSOR_AT_COLUMN_1: &[u8] = b"\x1b[1;1R";
const UP: &str = "\x1b[A";

/// halcmd running on a pseudo-terminal.
struct Terminal {
    master: File,
    child: Child,
    /// Everything halcmd wrote.
    seen: String,
    /// How far `expect` has read.
    pos: usize,
    /// Cursor queries answered.
    answered: usize,
    /// A line was entered: its newline comes before the next prompt.
    entered: bool,
}

impl Terminal {
    fn start(instance: &str, config_home: &Path, args: &[&str]) -> Terminal {
        let size = Winsize {
            ws_row: 40,
            ws_col: 200,
            ws_xpixel: 0,
            ws_ypixel: 0,
        };
        let pty = openpty(&size, None).unwrap();
        let slave: OwnedFd = pty.slave;
        let child = Command::new(env!("CARGO_BIN_EXE_halcmd"))
            .args(args)
            .env("HAL_INSTANCE", instance)
            .env("HAL_NO_REALTIME", "1")
            .env("XDG_CONFIG_HOME", config_home)
            .env("TERM", "xterm")
            .stdin(Stdio::from(slave.try_clone().unwrap()))
            .stdout(Stdio::from(slave.try_clone().unwrap()))
            .stderr(Stdio::from(slave))
            .spawn()
            .unwrap();
        let master = File::from(pty.master);
        let flags = fcntl(&master, FcntlArg::F_GETFL).unwrap();
        fcntl(
            &master,
            FcntlArg::F_SETFL(OFlag::from_bits_truncate(flags) | OFlag::O_NONBLOCK),
        )
        .unwrap();
        Terminal {
            master,
            child,
            seen: String::new(),
            pos: 0,
            answered: 0,
            entered: false,
        }
    }

    /// Reads what halcmd wrote, answering its cursor queries.
    fn pump(&mut self) {
        let mut buf = [0u8; 4096];
        loop {
            match self.master.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => self.seen.push_str(&String::from_utf8_lossy(&buf[..n])),
                // EIO: halcmd has exited and closed the terminal.
                Err(_) => break,
            }
        }
        let queries = self.seen.matches(CURSOR_QUERY).count();
        while self.answered < queries {
            self.master.write_all(CURSOR_AT_COLUMN_1).unwrap();
            self.answered += 1;
        }
    }

    /// Waits until `needle` appears after what was already expected.
    fn expect(&mut self, needle: &str) {
        let end = Instant::now() + Duration::from_secs(20);
        loop {
            self.pump();
            if let Some(at) = self.seen[self.pos..].find(needle) {
                self.pos += at + needle.len();
                return;
            }
            assert!(
                Instant::now() < end,
                "no {needle:?} from halcmd (fd {}); it wrote:\n{:?}",
                self.master.as_raw_fd(),
                &self.seen[self.pos..]
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Types `keys` once halcmd prompts for a new line. The editor
    /// redraws the prompt within a line (after Tab, or the up arrow), so
    /// a new prompt is the first one after the newline of the line
    /// entered before; keys typed earlier could be taken for the answer
    /// to its cursor query.
    fn type_line(&mut self, keys: &str) {
        if self.entered {
            self.expect("\n");
        }
        self.expect("halcmd: ");
        self.master.write_all(keys.as_bytes()).unwrap();
        self.entered = keys.ends_with('\r');
    }

    /// Ends the session with Ctrl-D and waits for halcmd to exit.
    fn finish(mut self) -> String {
        self.type_line("\x04");
        let end = Instant::now() + Duration::from_secs(20);
        loop {
            self.pump();
            if let Some(status) = self.child.try_wait().unwrap() {
                assert!(
                    status.success(),
                    "halcmd ended with {status}: {}",
                    self.seen
                );
                return self.seen;
            }
            assert!(Instant::now() < end, "halcmd did not end: {}", self.seen);
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

#[test]
fn history_recall_and_completion_of_live_names() {
    let inst = common::instance("interactive");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    assert!(common::run(realtime, &["start"], &inst).status.success());
    common::halcmd(&["loadrt", "scale"], &inst);
    let home = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("interactive-{inst}"));
    let _ = std::fs::remove_dir_all(&home);
    std::fs::create_dir_all(&home).unwrap();

    // halrun -I runs halcmd -kf, as LinuxCNC's.
    let mut t = Terminal::start(&inst, &home, &["-kf"]);
    t.type_line("setp scale.0.gain 2.5\r");
    t.type_line("getp scale.0.gain\r");
    t.expect("2.5");
    t.type_line("setp scale.0.gain 7.25\r");
    // Up twice: the getp before the last setp.
    t.type_line(&format!("{UP}{UP}\r"));
    t.expect("getp scale.0.gain");
    t.expect("7.25");
    // Tab completes the pin's name from the instance.
    t.type_line("setp scale.0.ga\t 1.5\r");
    t.expect("setp scale.0.gain");
    t.type_line("getp scale.0.gain\r");
    t.expect("1.5");
    let first = t.finish();
    assert!(!first.contains("Unknown command"), "{first}");

    let history = std::fs::read_to_string(home.join("hal/halcmd_history")).unwrap();
    for line in [
        "setp scale.0.gain 2.5",
        "setp scale.0.gain 1.5",
        "getp scale.0.gain",
    ] {
        assert!(
            history.contains(line),
            "no '{line}' in the history:\n{history}"
        );
    }

    // The next session recalls the last command of this one.
    let mut t = Terminal::start(&inst, &home, &[]);
    common::halcmd(&["setp", "scale.0.gain", "-3.5"], &inst);
    t.type_line(&format!("{UP}\r"));
    t.expect("getp scale.0.gain");
    t.expect("-3.5");
    t.finish();

    assert!(common::run(realtime, &["stop"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
    let _ = std::fs::remove_dir_all(&home);
}

#[test]
fn commands_from_a_pipe_are_read_plainly() {
    // No terminal: no prompt, no escape sequences, errors stop the file
    // without -k, as before.
    let inst = common::instance("interactive-pipe");
    let realtime = env!("CARGO_BIN_EXE_realtime");
    assert!(common::run(realtime, &["start"], &inst).status.success());
    let mut child = Command::new(env!("CARGO_BIN_EXE_halcmd"))
        .arg("-f")
        .env("HAL_INSTANCE", &inst)
        .env("HAL_NO_REALTIME", "1")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(
            b"loadrt scale\nsetp scale.0.gain 4\ngetp scale.0.gain\nbogus\ngetp scale.0.offset\n",
        )
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(!out.status.success());
    assert_eq!(String::from_utf8_lossy(&out.stdout), "4\n");
    assert!(String::from_utf8_lossy(&out.stderr).contains("bogus"));
    assert!(common::run(realtime, &["stop"], &inst).status.success());
    let _ = std::fs::remove_file(hal_lang::host_process::log_path(&inst).unwrap());
}
