//! Running HAL files through halrun, each on an instance of its own.
#![allow(dead_code)]

pub mod bins;
pub mod scope;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// An instance name no other test uses.
pub fn instance(tag: &str) -> String {
    hal_core::HostConfig::for_tests(tag).instance
}

/// Runs `halrun ARGS` in `dir` on a fresh instance, without realtime
/// scheduling (tests run side by side).
pub fn halrun(dir: &Path, args: &[&str], tag: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_halrun"))
        .args(args)
        .current_dir(dir)
        .env("HAL_INSTANCE", instance(tag))
        .env("HAL_NO_REALTIME", "1")
        .env("HAL_SHM_SIZE", (8u64 << 20).to_string())
        .output()
        .expect("halrun runs")
}

/// Runs `tests/<name>/test.hal`, checks that it succeeded and that its
/// stdout equals `expected` byte for byte, and returns the stdout.
pub fn run_exact(name: &str) -> String {
    let dir = root().join("tests").join(name);
    let out = halrun(&dir, &["-f", "test.hal"], name);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{name}: halrun failed: {stderr}");
    let got = String::from_utf8_lossy(&out.stdout).into_owned();
    let expected = std::fs::read_to_string(dir.join("expected")).unwrap();
    assert_eq!(got, expected, "{name}: stdout differs (stderr: {stderr})");
    got
}

/// The error lines of LinuxCNC's stderr that describe the user's mistake:
/// without the lines about LinuxCNC's own process machinery.
pub fn meaningful_stderr(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| {
            !["dlopen", "rtapi_app", "insmod", "waitpid"]
                .iter()
                .any(|w| l.contains(w))
        })
        .map(str::to_string)
        .collect()
}

/// Runs one of the tools on `instance`, without realtime scheduling.
pub fn run(bin: &str, args: &[&str], instance: &str) -> Output {
    Command::new(bin)
        .args(args)
        .env("HAL_INSTANCE", instance)
        .env("HAL_NO_REALTIME", "1")
        .output()
        .expect("runs")
}

/// Runs `halcmd ARGS` on `instance`, which must succeed; returns stdout.
pub fn halcmd(args: &[&str], instance: &str) -> String {
    let out = run(env!("CARGO_BIN_EXE_halcmd"), args, instance);
    assert!(
        out.status.success(),
        "halcmd {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs motion-cmd; (exit code, stdout, stderr).
pub fn mcmd(args: &[&str], instance: &str) -> (i32, String, String) {
    let out = run(env!("CARGO_BIN_EXE_motion-cmd"), args, instance);
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Runs motion-cmd, which must have its command accepted.
pub fn accepted(args: &[&str], instance: &str) {
    let (code, out, err) = mcmd(args, instance);
    assert_eq!(code, 0, "motion-cmd {args:?}: {out}{err}");
    assert!(out.starts_with("accepted (serial "), "{out}");
}

/// Polls `motion-cmd status` until `f` accepts it (10 s at most, `what`
/// names the wait in the failure); returns that status.
pub fn wait_status(instance: &str, what: &str, f: impl Fn(&str) -> bool) -> String {
    let end = Instant::now() + Duration::from_secs(10);
    loop {
        let (code, out, err) = mcmd(&["status"], instance);
        assert_eq!(code, 0, "{err}");
        if f(&out) {
            return out;
        }
        assert!(Instant::now() < end, "timed out waiting for {what}:\n{out}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// `realtime start` on `instance`, then motmod with trivkins (x y z) and
/// three joints whose position commands feed back, its functions on the
/// servo thread, and the threads started.
pub fn start_motion_instance(instance: &str) {
    let realtime = env!("CARGO_BIN_EXE_realtime");
    assert!(run(realtime, &["start"], instance).status.success());
    halcmd(&["loadrt", "trivkins", "coordinates=xyz"], instance);
    halcmd(&["loadrt", "motmod", "num_joints=3"], instance);
    for j in 0..3 {
        let sig = format!("j{j}pos");
        halcmd(
            &[
                "net",
                &sig,
                &format!("joint.{j}.motor-pos-cmd"),
                &format!("joint.{j}.motor-pos-fb"),
            ],
            instance,
        );
    }
    halcmd(
        &["addf", "motion-command-handler", "servo-thread"],
        instance,
    );
    halcmd(&["addf", "motion-controller", "servo-thread"], instance);
    halcmd(&["start"], instance);
}
