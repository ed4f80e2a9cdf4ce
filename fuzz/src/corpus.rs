//! The stored corpus: `fuzz/corpus/<target>/`, one input per file.
//!
//! It holds the seeds (lines and files of the golden HAL cases, the
//! shipped configs, LinuxCNC-style inputs written for it; `hal-fuzz-seed`
//! regenerates them) and every input a fuzzer ever found a bug with
//! (`regression-*` files). `cargo test` runs all of them before the
//! generated cases, and libFuzzer starts from them.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use crate::Target;

/// The corpus directory of the target named `name`.
pub fn dir(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("corpus")
        .join(name)
}

/// Every stored input of the target named `name`, with its file name,
/// sorted by name. A missing directory is an empty corpus.
pub fn load(name: &str) -> Vec<(String, Vec<u8>)> {
    let Ok(entries) = std::fs::read_dir(dir(name)) else {
        return Vec::new();
    };
    let mut files: Vec<(String, Vec<u8>)> = entries
        .filter_map(Result::ok)
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let bytes = std::fs::read(e.path()).ok()?;
            Some((name, bytes))
        })
        .collect();
    files.sort();
    files
}

/// Runs `target` on every stored input; a failing one is named in the
/// panic. Returns the inputs, for the mutator to start from.
pub fn replay(target: &Target) -> Vec<Vec<u8>> {
    let files = load(target.name);
    for (name, bytes) in &files {
        if catch_unwind(AssertUnwindSafe(|| (target.run)(bytes))).is_err() {
            panic!(
                "{}: stored input {} fails (the panic above says how)",
                target.name,
                dir(target.name).join(name).display()
            );
        }
    }
    files.into_iter().map(|(_, bytes)| bytes).collect()
}
