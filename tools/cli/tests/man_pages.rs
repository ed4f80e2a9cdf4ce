//! Section 1 man pages of every program the Debian package installs,
//! kept in packaging/man/: the clap tools' pages are generated from their
//! clap definitions (clap_mangen), the others' from their `--help` texts
//! (`man/help2roff.rs`). A page that no longer matches its program fails
//! here; `HAL_UPDATE_MAN=1 cargo test -p hal-tools --test man_pages`
//! rewrites them.

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
#[path = "man/help2roff.rs"]
mod help2roff;
#[path = "../../../drivers/ethercat/src/bin/lcec_conf/args.rs"]
mod lcec_conf_args;
/// rs274's page: its --help prints LinuxCNC's usage text word for word,
/// which does not lay options out as the suite's pages do, so the page
/// says the same in the suite's layout.
const RS274_HELP: &str = "\
usage: rs274 [-p interp.so] [-t tool.tbl] [-v var-file.var] [-n 0|1|2]
             [-b] [-s] [-g] [-i INI] [-T] [-l LEVEL] [input file [output file]]

Reads an RS274NGC program (LinuxCNC's dialect) from the input file, or
line by line from standard input, and prints the canonical machining
calls the interpreter makes, numbered, as LinuxCNC's standalone rs274
does, to the output file or standard output.

options:
  -p FILE      the pluggable interpreter (accepted; this rs274 has one)
  -t FILE      the tool table
  -v FILE      the parameter file
  -n 0|1|2     after an error: 0 continue, 1 enter MDI, 2 stop (default)
  -b           toggle block delete (default off)
  -s           toggle printing the stack on errors (default off)
  -g           toggle batch mode (default off)
  -i FILE      the INI file ([RS274NGC] settings)
  -T           call task_init
  -l LEVEL     the log level (default -1)
  -h, --help   print this help and exit
  --version    print the version and exit";

/// Where a page comes from.
enum Source {
    /// A clap definition.
    Clap(Box<clap::Command>),
    /// A help text, with the NAME line's description and the pages to
    /// see also.
    Help {
        summary: &'static str,
        text: String,
        see_also: &'static [&'static str],
    },
}

fn help(
    summary: &'static str,
    text: impl Into<String>,
    see_also: &'static [&'static str],
) -> Source {
    Source::Help {
        summary,
        text: text.into(),
        see_also,
    }
}

/// Every program's page source: (name, source).
fn pages() -> Vec<(&'static str, Source)> {
    use hal_tools::{tool_args, usage};
    use Source::Clap;
    vec![
        (
            "halscope",
            Clap(Box::new(hal_scope::scope::args::Args::command())),
        ),
        (
            "gcode-run",
            Clap(Box::new(tool_args::gcode_run::Args::command())),
        ),
        (
            "linuxcncrsh",
            Clap(Box::new(tool_args::linuxcncrsh::Args::command())),
        ),
        (
            "motion-plot",
            Clap(Box::new(tool_args::motion_plot::Args::command())),
        ),
        (
            "hal-board",
            Clap(Box::new(hostmot2::board_args::Cli::command())),
        ),
        (
            "canservo-tool",
            Clap(Box::new(hal_canservo::tool_args::Cli::command())),
        ),
        (
            "hm2-eth-sim",
            Clap(Box::new(hostmot2::eth_sim_args::Cli::command())),
        ),
        (
            "mesambccc",
            Clap(Box::new(hostmot2::mesambccc_args::Cli::command())),
        ),
        (
            "canservo-sim",
            Clap(Box::new(canservo_sim_args::Args::command())),
        ),
        (
            "parport-tool",
            Clap(Box::new(hal_parport::tool_args::Cli::command())),
        ),
        (
            "motion-cmd",
            Clap(Box::new(tool_args::motion_cmd::Cli::command())),
        ),
        (
            "halcmd",
            help(
                "manipulate a running HAL instance",
                hal_tools::cli::halcmd_usage(),
                &[
                    "halrun(1)",
                    "realtime(1)",
                    "halmeter(1)",
                    "haltcl(1)",
                    "threads(9)",
                ],
            ),
        ),
        (
            "halrun",
            help(
                "start a HAL instance, run a HAL file on it, and stop it",
                usage::HALRUN,
                &["halcmd(1)", "haltcl(1)", "linuxcnc(1)", "realtime(1)"],
            ),
        ),
        (
            "haltcl",
            help(
                "run Tcl HAL files on a running HAL instance",
                usage::HALTCL,
                &["halcmd(1)", "halrun(1)"],
            ),
        ),
        (
            "hal-web",
            help(
                "a running HAL instance and its machine in a browser",
                hal_web::USAGE,
                &["halcmd(1)", "halmeter(1)", "task-cmd(1)", "linuxcnc(1)"],
            ),
        ),
        (
            "halmeter",
            help(
                "watch one pin, signal or parameter of a HAL instance",
                usage::HALMETER,
                &["halcmd(1)", "halscope(1)"],
            ),
        ),
        (
            "halsampler",
            help(
                "print the samples a sampler channel collects",
                usage::HALSAMPLER,
                &["sampler(9)", "halstreamer(1)", "halscope(1)"],
            ),
        ),
        (
            "inivar",
            help(
                "print one value of an INI file",
                usage::INIVAR,
                &["linuxcnc(1)", "halcmd(1)"],
            ),
        ),
        (
            "halstreamer",
            help(
                "feed lines of values into a streamer channel",
                usage::HALSTREAMER,
                &["streamer(9)", "halsampler(1)"],
            ),
        ),
        (
            "realtime",
            help(
                "start and stop the HAL host of an instance",
                usage::REALTIME,
                &["halcmd(1)", "halrun(1)", "hal-host(1)"],
            ),
        ),
        (
            "hal-host",
            help(
                "the HAL host process of an instance",
                usage::HAL_HOST,
                &["realtime(1)", "halrun(1)"],
            ),
        ),
        (
            "task-cmd",
            help(
                "send task requests to a machine that linuxcnc runs",
                usage::task_cmd(),
                &["linuxcnc(1)", "motion-cmd(1)"],
            ),
        ),
        (
            "linuxcnc",
            help(
                "run a LinuxCNC machine configuration headless",
                hal_launcher::USAGE,
                &["task-cmd(1)", "motion-cmd(1)", "halrun(1)", "motion(9)"],
            ),
        ),
        (
            "halui",
            help(
                "LinuxCNC's HAL user interface: halui pins as task requests",
                hal_launcher::halui::USAGE,
                &["linuxcnc(1)", "task-cmd(1)"],
            ),
        ),
        (
            "classicladder",
            help(
                "load a ClassicLadder project into classicladder_rt",
                hal_ladder::user::USAGE,
                &["halrun(1)", "halcmd(1)"],
            ),
        ),
        (
            "motion-logger",
            help(
                "stand in for the motion controller and log every command",
                motion::logger::USAGE,
                &["linuxcnc(1)", "motion-cmd(1)"],
            ),
        ),
        (
            "z_level_compensation",
            help(
                "Z offset from a probed surface map through external offsets",
                hal_launcher::zlevel::USAGE,
                &["linuxcnc(1)", "halui(1)"],
            ),
        ),
        (
            "sim-torch",
            help(
                "the simulated plasma torch of QtPlasmaC's sim configurations",
                hal_launcher::sim_torch::USAGE,
                &["linuxcnc(1)", "plasmac(9)"],
            ),
        ),
        (
            "panelui",
            help(
                "an operator panel: key matrix codes into button pins and task commands",
                hal_launcher::panelui::USAGE,
                &["linuxcnc(1)", "sampler(9)", "sim_matrix_kb(9)", "halui(1)"],
            ),
        ),
        (
            "latency-test",
            help(
                "measure how late HAL threads wake up",
                hal_scope::latency::args::HELP,
                &["threads(9)", "halscope(1)"],
            ),
        ),
        (
            "hy_vfd",
            help(
                "a Huanyang HY-series spindle VFD as a HAL component",
                hal_serial::vfd::hy::USAGE,
                &["hy_gt_vfd(1)", "halcmd(1)"],
            ),
        ),
        (
            "hy_gt_vfd",
            help(
                "a Huanyang GT-series spindle VFD over Modbus RTU as a HAL component",
                hal_serial::vfd::gt::USAGE,
                &["hy_vfd(1)", "halcmd(1)"],
            ),
        ),
        (
            "mb2hal",
            help(
                "LinuxCNC's INI-driven Modbus master (TCP and RTU) as a HAL component",
                hal_serial::mb2hal::USAGE,
                &["hy_gt_vfd(1)", "halcmd(1)"],
            ),
        ),
        (
            "xhc-hb04",
            help(
                "the XHC-HB04 wireless MPG pendant as a HAL component",
                hal_usb::xhc::USAGE,
                &["halui(1)", "halcmd(1)"],
            ),
        ),
        (
            "hal_input",
            help(
                "Linux input devices (keyboards, joysticks, jog wheels, gamepads) as HAL pins",
                hal_input::run::USAGE,
                &["xhc-hb04(1)", "halcmd(1)"],
            ),
        ),
        (
            "ethercat-tool",
            Clap(Box::new(hal_ethercat::tool::args::Cli::command())),
        ),
        (
            "ethercat-sim",
            Clap(Box::new(ethercat_sim_args::Args::command())),
        ),
        ("lcec_conf", Clap(Box::new(lcec_conf_args::Args::command()))),
        (
            "rs274",
            help(
                "run an RS274NGC program through the interpreter and print its canonical calls",
                RS274_HELP,
                &["gcode-run(1)", "linuxcnc(1)"],
            ),
        ),
    ]
}

fn render(name: &str, source: Source) -> Vec<u8> {
    match source {
        Source::Clap(cmd) => {
            let mut out = Vec::new();
            clap_mangen::Man::new(*cmd)
                .render(&mut out)
                .expect("renders");
            let text = String::from_utf8_lossy(&out);
            // The examples of --help are in the page too.
            assert!(text.contains("Examples:"), "{name}: {text}");
            out
        }
        Source::Help {
            summary,
            text,
            see_also,
        } => {
            let page = help2roff::man_page(name, summary, &text, see_also);
            for want in [".TP\n\\fB\\-", "\\-\\-help", "\\-\\-version"] {
                assert!(page.contains(want), "{name}: no {want} in\n{page}");
            }
            page.into_bytes()
        }
    }
}

/// The programs the Debian package puts in /usr/bin.
fn packaged_programs() -> Vec<String> {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml");
    let table: toml::Table = std::fs::read_to_string(manifest).unwrap().parse().unwrap();
    table["package"]["metadata"]["deb"]["assets"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|a| {
            let src = a.as_array()?.first()?.as_str()?;
            let dest = a.as_array()?.get(1)?.as_str()?;
            let bin = src.strip_prefix("target/release/")?;
            (dest == "usr/bin/").then(|| bin.to_string())
        })
        .collect()
}

#[test]
fn every_packaged_program_has_a_current_man_page() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../packaging/man");
    let update = std::env::var_os("HAL_UPDATE_MAN").is_some();
    let pages = pages();
    let names: Vec<&str> = pages.iter().map(|(n, _)| *n).collect();
    for program in packaged_programs() {
        assert!(
            names.contains(&program.as_str()),
            "{program} is packaged but has no man page: add it to pages()"
        );
    }
    // Every page in the package is one of these (none left behind by a
    // renamed or removed tool).
    for entry in std::fs::read_dir(&dir).unwrap() {
        let file = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(
            names.iter().any(|n| format!("{n}.1") == file),
            "packaging/man/{file} is made by no program's definition"
        );
    }
    let mut stale = Vec::new();
    for (name, source) in pages {
        let page = render(name, source);
        let path = dir.join(format!("{name}.1"));
        if update {
            std::fs::write(&path, &page).unwrap();
        }
        if std::fs::read(&path).unwrap_or_default() != page {
            stale.push(path.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "out of date with their programs (rerun with HAL_UPDATE_MAN=1): {}",
        stale.join(", ")
    );
}
