//! Running the headless halscope in tests and reading its CSV.

use std::path::PathBuf;
use std::process::Command;

/// A scratch directory named after an instance no other test uses.
pub fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(super::instance(tag));
    std::fs::create_dir_all(&d).expect("scratch directory");
    d
}

/// Runs `halscope ARGS` on `instance`: whether it succeeded, and its
/// standard output and error together.
pub fn halscope(instance: &str, args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_halscope"))
        .args(args)
        .env("HAL_INSTANCE", instance)
        .output()
        .expect("halscope runs");
    (
        out.status.success(),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    )
}

/// CSV rows as (sample tag, time, values as text).
pub fn csv_rows(text: &str) -> Vec<(u32, f64, Vec<String>)> {
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[0].parse().expect("sample tag"),
                f[1].parse().expect("time"),
                f[2..].iter().map(|s| s.to_string()).collect(),
            )
        })
        .collect()
}
