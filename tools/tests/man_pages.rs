//! Man pages of the clap tools, generated from their clap definitions
//! (clap_mangen) and kept in packaging/man/ for the Debian package. A
//! page that no longer matches its tool's definition fails here;
//! `HAL_UPDATE_MAN=1 cargo test -p hal-tools --test man_pages` rewrites
//! them.

use std::path::PathBuf;

use clap::CommandFactory;

/// The tools whose man pages are generated: (name, command).
fn pages() -> Vec<(&'static str, clap::Command)> {
    vec![("halscope", hal_tools::scope::args::Args::command())]
}

fn render(cmd: clap::Command) -> Vec<u8> {
    let mut out = Vec::new();
    clap_mangen::Man::new(cmd)
        .render(&mut out)
        .expect("renders");
    out
}

#[test]
fn man_pages_match_the_clap_definitions() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../packaging/man");
    let update = std::env::var_os("HAL_UPDATE_MAN").is_some();
    for (name, cmd) in pages() {
        let page = render(cmd);
        let text = String::from_utf8_lossy(&page);
        // The examples of --help are in the page too.
        assert!(text.contains("Examples:"), "{name}: {text}");
        let path = dir.join(format!("{name}.1"));
        if update {
            std::fs::write(&path, &page).unwrap();
        }
        let committed = std::fs::read(&path).unwrap_or_default();
        assert!(
            committed == page,
            "{}: out of date with {name}'s clap definition; rerun with HAL_UPDATE_MAN=1",
            path.display()
        );
    }
}
