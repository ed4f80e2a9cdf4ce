//! The fuzz body for the server's input (fuzz/ target `linuxcncrsh_line`).

use std::time::Duration;

use super::server::{Line, LineReader};
use super::session::{Machine, Session, Settings};
use crate::error::ToolsError;

/// A machine whose answers come from the input: `stat` a fixed snapshot,
/// other requests done or refused by turns.
struct Scripted {
    turn: usize,
}

impl Machine for Scripted {
    fn ask(&mut self, words: &[String], _: Duration) -> Result<String, ToolsError> {
        self.turn += 1;
        match words.first().map(String::as_str) {
            Some("stat") => Ok("task_state=i:4\ntask_mode=i:3\nestop=i:0\nspindles=i:2\n\
                joints=i:3\nposition=F:1 2 3\nactual_position=F:1 2 3\nhomed=I:1 0 1\n\
                limit=I:0 1 8\nfeedrate=f:1.5\nfile=s:\ninterp_state=i:1\ngcodes=I:0 800 170\n\
                settings=F:0 10 1000\nspindle.0.direction=i:1\nspindle.1.brake=i:1\n\
                linear_units=f:0.03937007874015748\nangular_units=f:1\n"
                .to_string()),
            Some("messages") => Ok("3\n2 11 an error\n3 13 a display\n".to_string()),
            _ if self.turn % 3 == 0 => Err(ToolsError::TaskRefused("refused".to_string())),
            _ => Ok(String::new()),
        }
    }
}

/// Feeds `data` to a session as a connection would and checks each
/// reply is one bounded line.
pub fn lines(data: &[u8]) {
    let cfg = Settings {
        name: "EMCNETSVR".to_string(),
        connect_pw: "EMC".to_string(),
        enable_pw: "EMCTOO".to_string(),
        ini_file: "emc.ini".to_string(),
        debug: 0,
        identity_kins: true,
        open_dir: None,
        angular_joints: vec![false, false, true],
    };
    let mut session = Session::new(&cfg);
    let mut machine = Scripted { turn: 0 };
    let mut reader = LineReader::new(data);
    let mut out = Vec::new();
    loop {
        out.clear();
        match reader.next_line() {
            Line::End => return,
            Line::TooLong | Line::NotText => continue,
            Line::Text(t) => {
                assert!(t.len() <= super::parse::MAX_LINE);
                session.handle(&t, &mut machine, &mut out);
            }
        }
        for r in &out {
            assert!(!r.contains(['\r', '\n']), "a reply holds a line end: {r:?}");
            assert!(r.len() <= 4 * super::parse::MAX_LINE, "reply too long");
        }
    }
}
