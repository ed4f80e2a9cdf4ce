//! The binaries of the workspace, listed by `cargo metadata`, so that a
//! binary another branch adds is covered without touching the tests.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A binary of the workspace.
pub struct Bin {
    /// Its package.
    pub package: String,
    /// Its name.
    pub name: String,
}

/// Every binary target of every workspace package.
pub fn workspace_bins() -> Vec<Bin> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .args([
            "metadata",
            "--no-deps",
            "--format-version",
            "1",
            "--offline",
        ])
        .current_dir(super::root())
        .output()
        .expect("cargo metadata runs");
    assert!(
        out.status.success(),
        "cargo metadata: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).expect("metadata is JSON");
    let mut bins = Vec::new();
    for p in meta["packages"].as_array().expect("packages") {
        for t in p["targets"].as_array().expect("targets") {
            let is_bin = t["kind"]
                .as_array()
                .is_some_and(|k| k.iter().any(|k| k == "bin"));
            if is_bin {
                bins.push(Bin {
                    package: p["name"].as_str().unwrap_or_default().to_string(),
                    name: t["name"].as_str().unwrap_or_default().to_string(),
                });
            }
        }
    }
    bins
}

/// The directory cargo put this package's binaries in.
pub fn bin_dir() -> PathBuf {
    Path::new(env!("CARGO_BIN_EXE_halcmd"))
        .parent()
        .expect("binary directory")
        .to_path_buf()
}

/// The workspace's binaries that exist; the missing ones are reported (a
/// failure under `HAL_REQUIRE_ALL_BINS=1`: `.ci/run` builds every binary
/// first; `cargo test` alone builds only those of packages with
/// integration tests).
pub fn present_bins() -> Vec<(String, PathBuf)> {
    let dir = bin_dir();
    let strict = std::env::var_os("HAL_REQUIRE_ALL_BINS").is_some_and(|v| v == "1");
    let mut present = Vec::new();
    let mut missing = Vec::new();
    for b in workspace_bins() {
        let exe = dir.join(&b.name);
        if exe.is_file() {
            present.push((b.name, exe));
        } else {
            missing.push(format!("{} (package {})", b.name, b.package));
        }
    }
    if !missing.is_empty() {
        let note = format!(
            "binaries not built, not tested: {} (cargo build --workspace --bins builds them)",
            missing.join(", ")
        );
        assert!(!strict, "{note}");
        eprintln!("note: {note}");
    }
    assert!(
        present.iter().any(|(n, _)| n == "halcmd"),
        "the binary list lacks halcmd"
    );
    present
}
