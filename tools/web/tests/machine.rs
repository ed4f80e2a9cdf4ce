//! The machine panel on the simulated mill (configs/sim/mill run by the
//! suite's `linuxcnc`): the state reads as task's, machine-on and home go
//! through task as task-cmd sends them, a refusal is task's message, and
//! a button pressed from another origin does nothing.
//!
//! `linuxcnc` belongs to another package (hal-tools): the test runs the
//! one cargo built beside hal-web (`cargo test --workspace` and
//! scripts/test-all build every binary first) and fails, saying so, when
//! it is not there.

#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use common::Web;
use hal_launcher::{request, TaskAnswer};

/// A program of the suite from cargo's output directory.
fn suite_bin(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    let path = deps.parent().unwrap().join(name);
    assert!(
        path.exists(),
        "{} is not built: this test runs the suite's machine; build the suite's \
         programs first (cargo build -p hal-tools --bins)",
        path.display()
    );
    path
}

/// A running `linuxcnc mill.ini` in a scratch copy of configs/sim/mill.
struct Mill {
    instance: String,
    dir: PathBuf,
    child: Child,
    stderr: Arc<Mutex<String>>,
}

impl Mill {
    fn start() -> Mill {
        let instance = format!("t-web-mill-{}", std::process::id());
        let dir = std::env::temp_dir().join(format!("hal-web-{instance}"));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/sim/mill");
        for entry in std::fs::read_dir(&src).unwrap().flatten() {
            let name = entry.file_name();
            if !name.to_string_lossy().starts_with("sim.var") {
                std::fs::copy(entry.path(), dir.join(&name)).unwrap();
            }
        }
        let mut child = Command::new(suite_bin("linuxcnc"))
            .arg(dir.join("mill.ini"))
            .env("HAL_INSTANCE", &instance)
            .env("HAL_NO_REALTIME", "1")
            .env("HAL_SHM_SIZE", (16u64 << 20).to_string())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let stderr = Arc::new(Mutex::new(String::new()));
        let mut pipe = child.stderr.take().unwrap();
        let sink = stderr.clone();
        std::thread::spawn(move || {
            let mut buf = [0u8; 4096];
            while let Ok(n) = pipe.read(&mut buf) {
                if n == 0 {
                    break;
                }
                sink.lock()
                    .unwrap()
                    .push_str(&String::from_utf8_lossy(&buf[..n]));
            }
        });
        let mill = Mill {
            instance,
            dir,
            child,
            stderr,
        };
        let end = Instant::now() + Duration::from_secs(90);
        while !matches!(mill.task("status"), Some(TaskAnswer::Done(_))) {
            assert!(
                Instant::now() < end,
                "the mill did not come up:\n{}",
                mill.stderr.lock().unwrap()
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        mill
    }

    fn task(&self, word: &str) -> Option<TaskAnswer> {
        request(&self.instance, &[word.to_string()], Duration::from_secs(10)).ok()
    }
}

impl Drop for Mill {
    fn drop(&mut self) {
        common::stop(&mut self.child, Duration::from_secs(30));
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn machine(web: &Web) -> serde_json::Value {
    let (status, body) = web.request("GET", "/api/machine", &[], None);
    assert_eq!(status, 200, "{body}");
    serde_json::from_str(&body).unwrap()
}

fn press(web: &Web, action: &str) -> (u16, serde_json::Value) {
    let body = serde_json::json!({ "action": action }).to_string();
    let (status, answer) = web.post_same_origin("/api/machine", &body, None);
    (status, serde_json::from_str(&answer).unwrap())
}

/// Waits (up to `secs`) until `done` accepts the panel's state.
fn wait_for(web: &Web, secs: u64, what: &str, done: impl Fn(&serde_json::Value) -> bool) {
    let end = Instant::now() + Duration::from_secs(secs);
    loop {
        let m = machine(web);
        if done(&m) {
            return;
        }
        assert!(Instant::now() < end, "never {what}: {m}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn machine_on_and_home_go_through_task() {
    let mill = Mill::start();
    let web = Web::start(&mill.instance, &[]);
    let m = machine(&web);
    assert_eq!(m["running"], true, "{m}");
    assert_eq!(m["state"]["machine"], "ESTOP", "{m}");

    // In e-stop, task refuses machine-on; the page gets task's words.
    let (status, answer) = press(&web, "machine-on");
    assert_eq!(status, 422, "{answer}");
    let Some(TaskAnswer::Refused(why)) = mill.task("machine-on") else {
        panic!("task accepted machine-on in e-stop");
    };
    assert_eq!(answer["error"], why);

    // A button pressed from another origin does nothing.
    let evil = [("Origin", "http://evil.example")];
    let body = r#"{"action":"estop-reset"}"#;
    let (status, _) = web.request("POST", "/api/machine", &evil, Some(body));
    assert_eq!(status, 403);
    assert_eq!(machine(&web)["state"]["machine"], "ESTOP");

    let (status, answer) = press(&web, "estop-reset");
    assert_eq!(status, 200, "{answer}");
    let (status, answer) = press(&web, "machine-on");
    assert_eq!(status, 200, "{answer}");
    wait_for(&web, 10, "on", |m| m["state"]["machine"] == "ON");

    let (status, answer) = press(&web, "mode-manual");
    assert_eq!(status, 200, "{answer}");
    let (status, answer) = press(&web, "home");
    assert_eq!(status, 200, "{answer}");
    wait_for(&web, 120, "homed", |m| {
        let joints = m["motion"]["joints"].as_object();
        joints.is_some_and(|j| !j.is_empty() && j.values().all(|j| j["homed"] == "TRUE"))
    });
}
