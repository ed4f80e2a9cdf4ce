// Included by the build scripts of the crates whose tests run the golden
// corpus (LinuxCNC's recorded outputs): whether it is there is decided
// when the tests are built, so that a test that cannot run is reported
// as ignored (`#[cfg_attr(hal_no_golden, ignore = "...")]`), never as
// passed.
//
// The corpus is `$HAL_GOLDEN_DIR`, else `../shared/golden` beside the
// workspace. Its directory reaches the tests as the compile-time
// variable `HAL_GOLDEN_CORPUS`; when it holds no case (no `*/test.hal`
// or `*/expected`), the cfg `hal_no_golden` is set.

/// Finds the corpus for the crate being built, `depth` directories below
/// the workspace root, and tells cargo and the tests.
fn golden_corpus(depth: usize) {
    use std::path::PathBuf;
    println!("cargo::rustc-check-cfg=cfg(hal_no_golden)");
    println!("cargo::rerun-if-env-changed=HAL_GOLDEN_DIR");
    let mut workspace = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    for _ in 0..depth {
        workspace.pop();
    }
    let given = std::env::var_os("HAL_GOLDEN_DIR").map(PathBuf::from);
    let shared = workspace.join("../shared");
    let dir = given.clone().unwrap_or_else(|| shared.join("golden"));
    let has_case = std::fs::read_dir(&dir).is_ok_and(|entries| {
        entries.flatten().any(|e| {
            let case = e.path();
            case.join("test.hal").is_file() || case.join("expected").is_file()
        })
    });
    // Looked at again when the corpus changes, or when it appears in a
    // `../shared` that exists (a missing path would rerun this script,
    // and rebuild the crate, on every build).
    if dir.exists() {
        println!("cargo::rerun-if-changed={}", dir.display());
    } else if given.is_none() && shared.is_dir() {
        println!("cargo::rerun-if-changed={}", shared.display());
    }
    println!("cargo::rustc-env=HAL_GOLDEN_CORPUS={}", dir.display());
    if !has_case {
        println!("cargo::rustc-cfg=hal_no_golden");
    }
}
