//! linuxcncrsh: LinuxCNC's remote-control text server on this suite's
//! task (see `--help` and hal_tools::rsh).

use std::net::TcpListener;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use hal_launcher::{request, TaskAnswer};
use hal_tools::rsh::server;
use hal_tools::rsh::session::{Machine, Settings};
use hal_tools::tool_args::linuxcncrsh::{normalise, Args};
use hal_tools::ToolsError;

/// Task of the HAL instance this server runs on.
struct Task {
    instance: String,
}

impl Machine for Task {
    fn ask(&mut self, words: &[String], timeout: Duration) -> Result<String, ToolsError> {
        match request(&self.instance, words, timeout)? {
            TaskAnswer::Done(text) => Ok(text),
            TaskAnswer::Refused(text) => Err(ToolsError::TaskRefused(text)),
        }
    }
}

/// An integer as LinuxCNC's INI reader takes it (decimal or 0x hex).
fn ini_int(text: &str) -> Option<i64> {
    let t = text.trim();
    match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(hex) => i64::from_str_radix(hex, 16).ok(),
        None => t.parse().ok(),
    }
}

/// `[JOINT_n]TYPE = ANGULAR` for each of the `[KINS]JOINTS` joints.
fn joint_kinds(ini: Option<&hal_lang::ini::Ini>) -> Vec<bool> {
    let Some(ini) = ini else { return Vec::new() };
    let joints = ini
        .get("KINS", "JOINTS")
        .and_then(|j| j.trim().parse::<usize>().ok())
        .unwrap_or(0)
        .min(16);
    (0..joints)
        .map(|j| {
            ini.get(&format!("JOINT_{j}"), "TYPE")
                .is_some_and(|t| t.trim().eq_ignore_ascii_case("ANGULAR"))
        })
        .collect()
}

fn settings(args: &Args) -> Result<Settings, ToolsError> {
    let ini_file = args
        .ini
        .clone()
        .or_else(|| std::env::var_os("INI_FILE_NAME").map(Into::into));
    let ini = match &ini_file {
        Some(p) => Some(hal_lang::ini::Ini::load(p)?),
        None => None,
    };
    let get = |s: &str, k: &str| ini.as_ref().and_then(|i| i.get(s, k));
    let open_dir = args
        .path
        .clone()
        .or_else(|| ini.as_ref().map(hal_lang::ini::Ini::dir));
    Ok(Settings {
        name: args.name.clone(),
        connect_pw: args.connectpw.clone(),
        enable_pw: args.enablepw.clone(),
        ini_file: ini_file.map_or_else(|| "emc.ini".to_string(), |p| p.display().to_string()),
        debug: get("EMC", "DEBUG").and_then(ini_int).unwrap_or(0),
        identity_kins: get("KINS", "KINEMATICS")
            .is_some_and(|k| k.split_whitespace().next() == Some("trivkins")),
        open_dir,
        angular_joints: joint_kinds(ini.as_ref()),
    })
}

fn main() -> ExitCode {
    let args = match Args::try_parse_from(normalise(std::env::args_os())) {
        Ok(a) => a,
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 1 } else { 0 });
        }
    };
    let cfg = match settings(&args) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("linuxcncrsh: {e}");
            return ExitCode::from(1);
        }
    };
    let listener = match TcpListener::bind(("0.0.0.0", args.port)) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("linuxcncrsh: can't listen on port {}: {e}", args.port);
            return ExitCode::from(1);
        }
    };
    let instance = hal_core::instance_from_env();
    server::run(listener, cfg, args.sessions, move || Task {
        instance: instance.clone(),
    });
    ExitCode::SUCCESS
}
