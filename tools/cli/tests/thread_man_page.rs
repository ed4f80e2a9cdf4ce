//! The `threads(9)` page in packaging/man9 describes every parameter the
//! `threads` module takes, every `setthread` switch and the environment
//! the executor reads, so it cannot fall behind the code unnoticed.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::path::PathBuf;

fn page() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../packaging/man9/threads.9");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_threads_page_names_every_parameter_switch_and_variable() {
    let page = page();
    let threads = hal_components::modules()
        .into_iter()
        .find(|m| m.name == "threads")
        .expect("the threads module is registered");
    let mut bases: Vec<&str> = threads
        .params
        .iter()
        .map(|p| p.name.trim_end_matches(|c: char| c.is_ascii_digit()))
        .collect();
    bases.dedup();
    assert!(bases.len() >= 6, "{bases:?}");
    for base in bases {
        // Each parameter has its own entry: `.BI baseN= ...`.
        assert!(
            page.contains(&format!(".BI {base}N= ")),
            "threads.9 has no entry for {base}N"
        );
    }
    for switch in ["timing=", "cpu=", "missed="] {
        assert!(
            page.contains(&format!(".RB [ {switch}")),
            "the setthread synopsis lacks {switch}"
        );
    }
    for var in [
        "RTAPI_CPU_NUMBER",
        "HAL_NO_REALTIME",
        "HAL_NO_SHORT_SLICE",
        "HAL_NO_CPU_LATENCY",
    ] {
        assert!(
            page.contains(&format!(".B {var}\n")),
            "threads.9 lacks {var}"
        );
    }
}
