//! End-to-end HAL-file tests from the workspace's tests/ folder.

mod common;

use common::*;

fn case(name: &str) -> std::path::PathBuf {
    root().join("tests").join(name)
}

fn assert_expected(name: &str) {
    let dir = case(name);
    let out = halrun(&dir, &["-f", "test.hal"], name);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{name}: halrun failed: {stderr}");
    let expected = std::fs::read_to_string(dir.join("expected")).unwrap();
    let got = String::from_utf8_lossy(&out.stdout);
    assert_eq!(got, expected, "{name}: stdout differs (stderr: {stderr})");
}

#[test]
fn fast_thread_increments_slow_thread_resets() {
    let out = halrun(&case("threads"), &["-f", "test.hal"], "threads");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let values: Vec<u32> = text
        .lines()
        .map(|l| {
            l.trim()
                .parse()
                .unwrap_or_else(|_| panic!("not a number: {l:?}"))
        })
        .collect();
    assert_eq!(values.len(), 3500, "exactly 3500 samples");
    assert_eq!(values[0], 1);
    let mut resets = 0;
    for w in values.windows(2) {
        if w[1] == 1 {
            resets += 1;
        } else {
            assert_eq!(
                w[1],
                w[0] + 1,
                "a sample is neither the previous + 1 nor a reset"
            );
        }
    }
    assert!(resets >= 100, "only {resets} resets in 3500 fast periods");
}

#[test]
fn streamer_to_sampler_round_trip() {
    assert_expected("stream-roundtrip");
}

#[test]
fn nets_change_while_threads_run() {
    assert_expected("nets");
}

const SHOW: &str =
    "show pin\nshow param\nshow sig\nshow funct\nshow thread\nshow alias\nlist comp\n";

#[test]
fn save_then_reload_gives_the_same_show() {
    let tmp = std::env::temp_dir().join(instance("save-reload"));
    std::fs::create_dir_all(&tmp).unwrap();
    let src = case("save-reload").join("test.hal");
    let first = format!("source {}\nsave allu saved.hal\n{SHOW}", src.display());
    std::fs::write(tmp.join("first.hal"), first).unwrap();
    let a = halrun(&tmp, &["-f", "first.hal"], "save-a");
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    let saved = std::fs::read_to_string(tmp.join("saved.hal")).unwrap();
    assert!(saved.contains("loadrt and2 count=2"), "{saved}");
    assert!(
        saved.contains("alias pin and2.1.in1 spare-input"),
        "{saved}"
    );
    std::fs::write(tmp.join("second.hal"), format!("source saved.hal\n{SHOW}")).unwrap();
    let b = halrun(&tmp, &["-f", "second.hal"], "save-b");
    assert!(b.status.success(), "{}", String::from_utf8_lossy(&b.stderr));
    assert_eq!(
        String::from_utf8_lossy(&a.stdout),
        String::from_utf8_lossy(&b.stdout),
        "reloaded configuration differs; saved file:\n{saved}"
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn killing_halrun_takes_its_host_down() {
    let dir = std::env::temp_dir().join(instance("killed"));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("wait.hal"),
        "loadrt threads\nloadusr -w sleep 30\n",
    )
    .unwrap();
    let name = instance("killed-run");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_halrun"))
        .args(["-f", "wait.hal"])
        .current_dir(&dir)
        .env("HAL_INSTANCE", &name)
        .env("HAL_NO_REALTIME", "1")
        .spawn()
        .unwrap();
    let up = (0..500).any(|_| {
        std::thread::sleep(std::time::Duration::from_millis(10));
        hal_core::Instance::attach(&name).is_ok_and(|i| !i.threads().unwrap_or_default().is_empty())
    });
    assert!(up, "the instance came up");
    child.kill().unwrap();
    child.wait().unwrap();
    let gone = (0..500).any(|_| {
        std::thread::sleep(std::time::Duration::from_millis(10));
        hal_core::Instance::attach(&name).is_err()
    });
    assert!(gone, "the host outlived halrun");
    let _ = std::fs::remove_dir_all(dir);
}
