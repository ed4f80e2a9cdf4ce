//! One command-line convention for every binary of the workspace (listed
//! by `cargo metadata`, so a new binary is covered at once):
//!
//! * `-h` and `--help` print the help on standard output and exit 0; the
//!   help names `--help` and `--version`;
//! * `--version` prints `NAME X.Y.Z` and exits 0;
//! * an option the tool does not have fails, naming that option, with
//!   nothing on standard output;
//! * a tool that uses a HAL instance takes it as `--instance NAME` (and as
//!   `-i NAME` where `-i` is not LinuxCNC's INI file), says so in its help,
//!   and names the instance when it is not running.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};

use common::bins::present_bins;

/// A tool that uses a HAL instance.
struct InstanceTool {
    bin: &'static str,
    /// `-i NAME` names the instance too (false where `-i` is LinuxCNC's
    /// INI file).
    short: bool,
    /// Arguments after the instance option that make it use the instance
    /// at once; `None` for a tool that would start one (only a bad name is
    /// tried on it).
    attach: Option<&'static [&'static str]>,
}

const INSTANCE_TOOLS: &[InstanceTool] = &[
    InstanceTool {
        bin: "halcmd",
        short: false,
        attach: Some(&["show"]),
    },
    InstanceTool {
        bin: "halrun",
        short: false,
        attach: Some(&["-U"]),
    },
    InstanceTool {
        bin: "haltcl",
        short: false,
        attach: Some(&[]),
    },
    InstanceTool {
        bin: "hal-web",
        short: true,
        attach: Some(&["-p", "0"]),
    },
    InstanceTool {
        bin: "halmeter",
        short: true,
        attach: Some(&["pin", "x"]),
    },
    InstanceTool {
        bin: "halsampler",
        short: true,
        attach: Some(&["-n", "1"]),
    },
    InstanceTool {
        bin: "halstreamer",
        short: true,
        attach: Some(&[]),
    },
    InstanceTool {
        bin: "halscope",
        short: true,
        attach: Some(&["--pins", "x", "--thread", "t", "--out", "x.csv"]),
    },
    InstanceTool {
        bin: "realtime",
        short: true,
        attach: Some(&["status"]),
    },
    InstanceTool {
        bin: "task-cmd",
        short: true,
        attach: Some(&["status"]),
    },
    InstanceTool {
        bin: "motion-cmd",
        short: true,
        attach: Some(&["status"]),
    },
    InstanceTool {
        bin: "gcode-run",
        short: true,
        attach: Some(&["line.ngc"]),
    },
    InstanceTool {
        bin: "hy_vfd",
        short: false,
        attach: Some(&["-d", "sim"]),
    },
    InstanceTool {
        bin: "hy_gt_vfd",
        short: false,
        attach: Some(&["-d", "sim", "-S", "24000", "-F", "400", "-f", "20"]),
    },
    // mb2hal reads its INI file before it attaches (a bad file is
    // refused first), and the conventions' scratch directory has none:
    // only the bad instance name is tried.
    InstanceTool {
        bin: "mb2hal",
        short: false,
        attach: None,
    },
    // Without -x the pendant's driver makes its pins at once.
    InstanceTool {
        bin: "xhc-hb04",
        short: true,
        attach: Some(&["-H"]),
    },
    // hal_input opens its devices before it attaches, and the
    // conventions' scratch directory has no simulated ones: only the bad
    // instance name is tried.
    InstanceTool {
        bin: "hal_input",
        short: false,
        attach: None,
    },
    InstanceTool {
        bin: "hal-host",
        short: true,
        attach: None,
    },
    InstanceTool {
        bin: "linuxcnc",
        short: true,
        attach: None,
    },
    InstanceTool {
        bin: "halui",
        short: false,
        attach: None,
    },
    // The loader attaches before it reads the project file.
    InstanceTool {
        bin: "classicladder",
        short: false,
        attach: Some(&["--nogui", "x.clp"]),
    },
    InstanceTool {
        bin: "z_level_compensation",
        short: false,
        attach: Some(&[]),
    },
    InstanceTool {
        bin: "motion-logger",
        short: false,
        attach: Some(&[]),
    },
    InstanceTool {
        bin: "sim-torch",
        short: false,
        attach: Some(&[]),
    },
    InstanceTool {
        bin: "panelui",
        short: false,
        attach: Some(&[]),
    },
];

/// Runs `exe args` in a scratch directory, with no standard input and an
/// instance nobody runs in the environment.
fn run(exe: &Path, args: &[&str]) -> Output {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("conventions");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("line.ngc"), "G0 X1\nM2\n").unwrap();
    Command::new(exe)
        .args(args)
        .current_dir(&dir)
        .env("HAL_INSTANCE", common::instance("conv-env"))
        .env("HAL_NO_REALTIME", "1")
        .stdin(Stdio::null())
        .output()
        .expect("the binary starts")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// What is wrong with `name`'s help, version and unknown-option handling.
fn check_common(name: &str, exe: &Path) -> Vec<String> {
    let mut faults = Vec::new();
    for flag in ["-h", "--help"] {
        let out = run(exe, &[flag]);
        let help = text(&out.stdout);
        if !out.status.success() || !help.to_lowercase().contains("usage") {
            faults.push(format!(
                "{name} {flag}: status {:?}, no usage on stdout (stderr: {})",
                out.status.code(),
                text(&out.stderr)
            ));
        }
        for want in ["--help", "--version"] {
            if flag == "--help" && !help.contains(want) {
                faults.push(format!("{name} --help does not mention {want}"));
            }
        }
    }
    let out = run(exe, &["--version"]);
    let version = text(&out.stdout);
    let mut words = version.trim_end().split(' ');
    let shaped = words.next() == Some(name)
        && words.next().is_some_and(|v| {
            v.split('.').count() == 3 && v.split('.').all(|n| n.parse::<u32>().is_ok())
        })
        && words.next().is_none()
        && version.ends_with('\n');
    if !out.status.success() || !shaped {
        faults.push(format!(
            "{name} --version: status {:?}, printed {version:?} (want '{name} X.Y.Z')",
            out.status.code()
        ));
    }
    let out = run(exe, &["--no-such-option"]);
    let err = text(&out.stderr);
    if out.status.success()
        || out.status.code() == Some(101)
        || !out.stdout.is_empty()
        || !err.contains("'--no-such-option'")
    {
        faults.push(format!(
            "{name} --no-such-option: status {:?}, stdout {:?}, stderr {err:?} (want a failure naming the option)",
            out.status.code(),
            text(&out.stdout)
        ));
    }
    faults
}

/// What is wrong with how `tool` takes its instance.
fn check_instance(tool: &InstanceTool, exe: &Path, help: &str) -> Vec<String> {
    let name = tool.bin;
    let mut faults = Vec::new();
    if !help.contains("--instance") {
        faults.push(format!("{name} --help does not mention --instance"));
    }
    let mut spellings = vec![vec!["--instance".to_string()]];
    if tool.short {
        spellings.push(vec!["-i".to_string()]);
    }
    for spelling in &spellings {
        // A bad name is refused, named, before anything starts.
        let mut args: Vec<&str> = spelling.iter().map(String::as_str).collect();
        args.push("bad/name");
        args.extend(tool.attach.unwrap_or(&[]));
        let out = run(exe, &args);
        let said = format!("{}{}", text(&out.stdout), text(&out.stderr));
        if out.status.success() || !said.contains("bad/name") {
            faults.push(format!(
                "{name} {args:?}: bad name not refused by name: {said}"
            ));
        }
        // An instance nobody runs is named (not $HAL_INSTANCE's); `halrun
        // -U` on it succeeds, as LinuxCNC's.
        if let Some(attach) = tool.attach {
            let absent = common::instance(&format!("conv-absent-{name}"));
            let mut args: Vec<&str> = spelling.iter().map(String::as_str).collect();
            args.push(&absent);
            args.extend(attach);
            let out = run(exe, &args);
            let said = format!("{}{}", text(&out.stdout), text(&out.stderr));
            if !said.contains(&format!("'{absent}'")) {
                faults.push(format!(
                    "{name} {args:?}: does not say that instance '{absent}' is not running: {said}"
                ));
            }
        }
    }
    faults
}

#[test]
fn every_binary_keeps_the_command_line_conventions() {
    let mut faults = Vec::new();
    let bins = present_bins();
    for (name, exe) in &bins {
        faults.extend(check_common(name, exe));
        let help = text(&run(exe, &["--help"]).stdout);
        match INSTANCE_TOOLS.iter().find(|t| t.bin == name) {
            Some(tool) => faults.extend(check_instance(tool, exe, &help)),
            None if help.contains("--instance") => faults.push(format!(
                "{name} takes --instance but is not in INSTANCE_TOOLS: add it"
            )),
            None => {}
        }
    }
    for tool in INSTANCE_TOOLS {
        assert!(
            common::bins::workspace_bins()
                .iter()
                .any(|b| b.name == tool.bin),
            "INSTANCE_TOOLS names {}, which is no binary of the workspace",
            tool.bin
        );
    }
    assert!(
        faults.is_empty(),
        "{} convention fault(s) among {} binaries:\n{}",
        faults.len(),
        bins.len(),
        faults.join("\n")
    );
}
