//! Man pages of the clap tools, generated from their clap definitions
//! (clap_mangen) and kept in packaging/man/ for the Debian package. A
//! page that no longer matches its tool's definition fails here;
//! `HAL_UPDATE_MAN=1 cargo test -p hal-tools --test man_pages` rewrites
//! them.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::path::PathBuf;

use clap::CommandFactory;

// canservo-sim's command line lives in its binary, not in the driver's
// library API.
#[path = "../../../drivers/canservo/src/bin/canservo-sim/args.rs"]
mod canservo_sim_args;
#[path = "../../../drivers/ethercat/src/bin/ethercat-sim/args.rs"]
mod ethercat_sim_args;

/// The tools whose man pages are generated: (name, command).
fn pages() -> Vec<(&'static str, clap::Command)> {
    use hal_tools::tool_args;
    vec![
        ("halscope", hal_scope::scope::args::Args::command()),
        ("gcode-run", tool_args::gcode_run::Args::command()),
        ("motion-plot", tool_args::motion_plot::Args::command()),
        ("hal-board", hostmot2::board_args::Cli::command()),
        ("canservo-tool", hal_canservo::tool_args::Cli::command()),
        ("hm2-eth-sim", hostmot2::eth_sim_args::Cli::command()),
        ("canservo-sim", canservo_sim_args::Args::command()),
        ("parport-tool", hal_parport::tool_args::Cli::command()),
        ("motion-cmd", tool_args::motion_cmd::Cli::command()),
        ("ethercat-tool", hal_ethercat::tool::args::Cli::command()),
        ("ethercat-sim", ethercat_sim_args::Args::command()),
    ]
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
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../packaging/man");
    let update = std::env::var_os("HAL_UPDATE_MAN").is_some();
    let pages = pages();
    // Every page in the package is one of these (none left behind by a
    // renamed or removed tool).
    let generated: Vec<String> = pages.iter().map(|(n, _)| format!("{n}.1")).collect();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let file = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            generated.contains(&file),
            "packaging/man/{file} is not generated from a clap definition"
        );
    }
    for (name, cmd) in pages {
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
