//! linuxcncrsh as a machine's display: the launcher starts it for
//! `[DISPLAY]DISPLAY = linuxcncrsh ARGS`, a client talks LinuxCNC's text
//! protocol to it on a TCP port, and `shutdown` ends the machine.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod machine;

use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use machine::{mill_copy, Machine, Scratch};

/// A port no one listens on now (the kernel's pick, let go again).
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// The simulated mill whose display is `linuxcncrsh ARGS`.
fn mill_with_rsh(s: &Scratch, args: &str) -> std::path::PathBuf {
    let ini = mill_copy(s);
    let text = std::fs::read_to_string(&ini).unwrap();
    assert!(text.contains("\nDISPLAY = axis\n"));
    let text = text.replace(
        "\nDISPLAY = axis\n",
        &format!("\nDISPLAY = linuxcncrsh {args}\n"),
    );
    std::fs::write(&ini, text).unwrap();
    ini
}

/// One client connection.
struct Client {
    out: TcpStream,
    lines: BufReader<TcpStream>,
}

impl Client {
    /// Connects to `port`, waiting for the server to come up.
    fn connect(port: u16, m: &Machine) -> Client {
        let end = Instant::now() + Duration::from_secs(60);
        loop {
            if let Ok(s) = TcpStream::connect(("127.0.0.1", port)) {
                s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
                return Client {
                    lines: BufReader::new(s.try_clone().unwrap()),
                    out: s,
                };
            }
            assert!(Instant::now() < end, "no server on {port}:\n{}", m.stderr());
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    fn send(&mut self, line: &str) {
        self.out
            .write_all(format!("{line}\r\n").as_bytes())
            .unwrap();
    }

    /// The next reply line, without its `\r\n` (which it must end with).
    fn reply(&mut self) -> String {
        let mut l = String::new();
        self.lines.read_line(&mut l).unwrap();
        assert!(l.ends_with("\r\n"), "reply {l:?} does not end with CR LF");
        l.trim_end_matches("\r\n").to_string()
    }

    /// Sends `line` and returns the one reply line.
    fn ask(&mut self, line: &str) -> String {
        self.send(line);
        self.reply()
    }

    /// Asks `line` until the reply is `want` (a state that takes time).
    fn ask_until(&mut self, line: &str, want: &str) {
        let end = Instant::now() + Duration::from_secs(60);
        loop {
            let got = self.ask(line);
            if got == want {
                return;
            }
            assert!(Instant::now() < end, "{line}: {got}, never {want}");
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

#[test]
fn a_client_drives_the_machine_and_shutdown_ends_it() {
    let s = Scratch::new("rsh-drive");
    let port = free_port();
    let ini = mill_with_rsh(&s, &format!("--port {port} --sessions 2"));
    let m = Machine::spawn(&ini, "rsh-drive", &[]);
    let mut c = Client::connect(port, &m);

    // Nothing but help before hello.
    assert_eq!(c.ask("get estop"), "GET ESTOP NAK");
    assert_eq!(c.ask("hello wrong me 1.0"), "HELLO NAK");
    assert_eq!(c.ask("hello EMC me"), "HELLO NAK");
    assert_eq!(c.ask("HELLO EMC me 1.0"), "HELLO ACK EMCNETSVR 1.1");
    // Without the enable password nothing moves; verbose acknowledges sets.
    assert_eq!(c.ask("set estop off"), "SET ESTOP NAK");
    assert_eq!(c.ask("set enable nope"), "SET ENABLE NAK");
    assert_eq!(c.ask("get enable"), "ENABLE OFF");
    assert_eq!(c.ask("set verbose on"), "SET VERBOSE ACK");
    assert_eq!(c.ask("set enable EMCTOO"), "SET ENABLE ACK");
    assert_eq!(c.ask("get plat"), "PLAT Linux");
    assert_eq!(c.ask("get estop"), "ESTOP ON");
    assert_eq!(c.ask("get machine"), "MACHINE OFF");
    assert_eq!(c.ask("set mode mdi"), "SET MODE NAK");
    // A refusal is the NAK alone (as LinuxCNC's): `get error` stays OK.
    assert_eq!(c.ask("get error"), "ERROR OK");
    assert_eq!(c.ask("set estop off"), "SET ESTOP ACK");
    assert_eq!(c.ask("get estop"), "ESTOP OFF");
    assert_eq!(c.ask("set machine on"), "SET MACHINE ACK");
    assert_eq!(c.ask("get machine"), "MACHINE ON");
    assert_eq!(c.ask("set mode manual"), "SET MODE ACK");
    assert_eq!(c.ask("get mode"), "MODE MANUAL");
    // Pause and resume are taken with nothing running, as LinuxCNC's
    // task takes them in every mode: nothing is held, nothing reported.
    assert_eq!(c.ask("set pause"), "SET PAUSE ACK");
    assert_eq!(c.ask("set resume"), "SET RESUME ACK");
    assert_eq!(c.ask("get error"), "ERROR OK");
    // The probe's tripped flag is cleared in any mode.
    assert_eq!(c.ask("set probe_clear"), "SET PROBE_CLEAR ACK");
    assert_eq!(c.ask("get probe_tripped"), "PROBE_TRIPPED 0");
    assert_eq!(c.ask("set home -1"), "SET HOME ACK");
    c.ask_until(
        "get joint_homed",
        "JOINT_HOMED HOMED HOMED HOMED NOT NOT NOT",
    );
    // A joint the machine lacks but LinuxCNC's motion has room for (16)
    // is taken and homes nothing; past that it is refused.
    assert_eq!(c.ask("set home 5"), "SET HOME ACK");
    assert_eq!(c.ask("get error"), "ERROR OK");
    assert_eq!(c.ask("set home 17"), "SET HOME NAK");
    // Optional stop starts on, as LinuxCNC's interpreter starts it.
    assert_eq!(c.ask("get optional_stop"), "OPTIONAL_STOP 1");
    // LinuxCNC lists six joints at least.
    assert_eq!(c.ask("get joint_fault"), "JOINT_FAULT OK OK OK OK OK OK");
    assert_eq!(c.ask("get comm_prot"), "COMM_PROT 1.0");
    assert_eq!(
        c.ask("get joint_type"),
        "JOINT_TYPE LINEAR LINEAR LINEAR LINEAR LINEAR LINEAR"
    );
    assert_eq!(c.ask("get joint_units 0"), "JOINT_UNITS MM");
    assert_eq!(c.ask("get program_linear_units"), "PROGRAM_UNITS MM");
    assert_eq!(c.ask("get joint_limit 1"), "JOINT_LIMIT OK");

    // MDI, waited for; positions in LinuxCNC's six columns.
    assert_eq!(c.ask("set mode mdi"), "SET MODE ACK");
    assert_eq!(c.ask("set set_wait done"), "SET SET_WAIT ACK");
    // Overriding limits is MANUAL's and a step AUTO's: refused here with
    // LinuxCNC's words on the error channel.
    assert_eq!(c.ask("get override_limits"), "OVERRIDE_LIMITS 0");
    assert_eq!(c.ask("set override_limits off"), "SET OVERRIDE_LIMITS NAK");
    assert_eq!(
        c.ask("get error"),
        "ERROR can't do that (EMC_JOINT_OVERRIDE_LIMITS:129) in MDI mode"
    );
    assert_eq!(c.ask("set step"), "SET STEP NAK");
    assert_eq!(
        c.ask("get error"),
        "ERROR can't do that (EMC_TASK_PLAN_STEP:511) in MDI mode"
    );
    assert_eq!(c.ask("set mdi g0 x1 y2"), "SET MDI ACK");
    assert_eq!(
        c.ask("get abs_cmd_pos"),
        "ABS_CMD_POS 1.000000 2.000000 0.000000 0.000000 0.000000 0.000000"
    );
    c.ask_until("get abs_act_pos y", "ABS_ACT_POS 2.000000");
    assert_eq!(c.ask("set mdi t2 m6"), "SET MDI ACK");
    assert_eq!(c.ask("get tool"), "TOOL 2");
    assert_eq!(c.ask("get program"), "PROGRAM NONE");
    assert_eq!(c.ask("get program_status"), "PROGRAM_STATUS IDLE");
    assert_eq!(c.ask("get feed_override"), "FEED_OVERRIDE 100");
    assert_eq!(c.ask("get error"), "ERROR OK");
    // A line the interpreter refuses: a NAK, then its words on `get error`.
    assert_eq!(c.ask("set mdi g2 x5"), "SET MDI NAK");
    let err = c.ask("get error");
    assert!(err.starts_with("ERROR ") && err != "ERROR OK", "{err}");

    // Coolant and spindle, and LinuxCNC's reply for a spindle that is not.
    assert_eq!(c.ask("get flood"), "FLOOD OFF");
    assert_eq!(c.ask("set flood on"), "SET FLOOD ACK");
    assert_eq!(c.ask("get flood"), "FLOOD ON");
    // A get of probe, probe_clear or wait writes nothing and sends the
    // reply buffer again: the last value line.
    assert_eq!(c.ask("get probe"), "FLOOD ON");
    assert_eq!(c.ask("get wait"), "FLOOD ON");
    assert_eq!(c.ask("get tool_offset"), "TOOL_OFFSET 0.000000");
    // set tool_offset takes a tool, its length and its diameter.
    assert_eq!(c.ask("set tool_offset 1"), "SET TOOL_OFFSET NAK");
    assert_eq!(c.ask("set tool_offset 3 40 5"), "SET TOOL_OFFSET ACK");
    assert_eq!(c.ask("get spindle"), "SPINDLE 0 OFF");
    assert_eq!(
        c.ask("set spindle forward 99"),
        "error: invalid spindle: 99 (valid: -1 - 1)"
    );
    // A custom error's message is left in the buffer without its lead.
    assert_eq!(
        c.ask("get probe_clear"),
        "invalid spindle: 99 (valid: -1 - 1)"
    );
    assert_eq!(c.ask("set spindle forward"), "SET SPINDLE ACK");
    c.ask_until("get spindle 0", "SPINDLE 0 FORWARD");
    assert_eq!(c.ask("set spindle off"), "SET SPINDLE ACK");

    // Words that are no command, and a line past the bound.
    assert_eq!(c.ask("get nosuch"), "GET NOSUCH NAK");
    assert_eq!(c.ask("set plat"), "SET PLAT NAK");
    assert_eq!(c.ask("frobnicate"), "FROBNICATE NAK");
    assert_eq!(
        c.ask(&"x".repeat(10_000)),
        "error: line longer than 4096 bytes"
    );
    c.send("help");
    assert_eq!(c.reply(), "Available commands:");
    for word in ["Hello", "Get", "Set", "Shutdown", "Help"] {
        assert!(c.reply().starts_with(&format!("  {word}")));
    }

    // --sessions 2: a second client is served, a third is turned away.
    let mut second = Client::connect(port, &m);
    assert_eq!(second.ask("get echo"), "GET ECHO NAK");
    let mut third = Client::connect(port, &m);
    assert_eq!(third.reply(), "error: too many sessions");
    // Only an enabled session may shut the machine down.
    assert_eq!(second.ask("hello EMC two 1.0"), "HELLO ACK EMCNETSVR 1.1");
    assert_eq!(second.ask("shutdown"), "SHUTDOWN NAK");
    second.send("quit");

    c.send("shutdown");
    let (status, err) = m.wait_exit();
    assert_eq!(status.code(), Some(0), "{err}");
}
