//! halrun: start a HAL instance, run a file (or an interactive session) on
//! it, then tear it down, as LinuxCNC's halrun:
//!
//! * `halrun [-I] [halcmd options] [FILE.hal]` runs the file with halcmd
//!   (then, with `-I`, an interactive halcmd; without a file, only that);
//! * `halrun [-T] [-i INI] FILE.tcl` runs the file with haltcl (with
//!   `-T`, an interactive haltcl follows);
//! * `halrun [-I|-T] MACHINE.ini` runs only the `[HAL]TWOPASS` processing
//!   of the machine's `[HAL]HALFILE`s, as LinuxCNC's halrun does (an INI
//!   file without TWOPASS is refused, in LinuxCNC's words);
//! * `halrun -U` stops the instance's realtime environment.
//!
//! The file may also be given as `-f FILE`.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Duration;

use hal_core::{instance_from_env, Instance};
use hal_lang::haltcl::{self, TclJob};
use hal_lang::host_process::{start_host, stop_host};
use hal_lang::Session;
use hal_launcher as launcher;
use hal_tools::cli::{parse_halcmd_args, run_halcmd};
use hal_tools::ToolsError;

/// What the command line asked for.
#[derive(Default)]
struct Request {
    interactive_halcmd: bool,
    interactive_tcl: bool,
    /// halcmd's options, as words.
    halcmd_opts: Vec<String>,
    ini: Option<String>,
    file: Option<String>,
}

fn parse(args: &[String]) -> Result<Request, ToolsError> {
    let mut r = Request::default();
    let mut positional = Vec::new();
    let mut i = 0;
    while let Some(a) = args.get(i) {
        i += 1;
        let Some(flags) = a.strip_prefix('-').filter(|f| !f.is_empty()) else {
            positional.push(a.clone());
            continue;
        };
        for (at, c) in flags.char_indices() {
            // -f and -i take the rest of the word or the next word.
            let mut value = || -> Result<String, ToolsError> {
                let rest = &flags[at + c.len_utf8()..];
                if !rest.is_empty() {
                    return Ok(rest.to_string());
                }
                i += 1;
                args.get(i - 1)
                    .cloned()
                    .ok_or_else(|| ToolsError::usage(format!("option -{c} needs a value")))
            };
            match c {
                'I' => r.interactive_halcmd = true,
                'T' => r.interactive_tcl = true,
                'f' => {
                    r.file = Some(value()?);
                    break;
                }
                'i' => {
                    r.ini = Some(value()?);
                    break;
                }
                'e' | 'k' | 'q' | 's' | 'v' | 'R' | 'Q' | 'V' => {
                    r.halcmd_opts.push(format!("-{c}"))
                }
                // Alone they are handled before parsing; in a group of
                // flags they make no sense.
                'U' => return Err(ToolsError::usage("-U must be the only argument")),
                'h' => return Err(ToolsError::usage("-h must be given alone")),
                other => {
                    return Err(ToolsError::usage(format!(
                        "unknown option '-{other}' (see halrun --help)"
                    )))
                }
            }
        }
    }
    if positional.len() > 1 {
        return Err(ToolsError::usage(format!(
            "too many arguments <{}>",
            positional.join(" ")
        )));
    }
    if let Some(p) = positional.pop() {
        if let Some(f) = &r.file {
            return Err(ToolsError::usage(format!(
                "Specified '-f {f}' and also <{p}>"
            )));
        }
        r.file = Some(p);
    }
    Ok(r)
}

/// Takes the suite's long options (`--help`, `--version`,
/// `--instance NAME`) out of `args`; halrun's own are LinuxCNC's single
/// letters. Any other word starting with `--` is an unknown option.
fn take_long_options(args: Vec<String>) -> Vec<String> {
    let mut rest = Vec::new();
    let mut i = 0;
    while i < args.len() {
        if let Some(found) = hal_core::userspace::instance_option(&args, i, false) {
            let (name, words) = found.unwrap_or_else(|e| die(e.to_string()));
            if let Err(e) = hal_core::userspace::select_instance(&name) {
                die(format!("--instance: {e}"));
            }
            i += words;
            continue;
        }
        match args[i].as_str() {
            "--help" => {
                hal_tools::outln!("{}", hal_tools::usage::HALRUN);
                std::process::exit(0);
            }
            "--version" => {
                hal_tools::outln!("{}", hal_core::userspace::version_line("halrun"));
                std::process::exit(0);
            }
            long if long.starts_with("--") => {
                die(format!("unknown option '{long}' (see halrun --help)"))
            }
            _ => rest.push(args[i].clone()),
        }
        i += 1;
    }
    rest
}

fn main() {
    let args = take_long_options(hal_tools::stdio::args_or_exit("halrun", 1));
    let instance = instance_from_env();
    if args.first().map(String::as_str) == Some("-U") {
        if args.len() > 1 {
            die("-U must be the only argument");
        }
        std::process::exit(unload(&instance));
    }
    if args.iter().any(|a| a == "-h") {
        hal_tools::outln!("{}", hal_tools::usage::HALRUN);
        return;
    }
    let req = match parse(&args) {
        Ok(r) => r,
        Err(e) => die(e),
    };
    let kind = req
        .file
        .as_deref()
        .map(|f| {
            Path::new(f)
                .extension()
                .map(|e| e.to_string_lossy().to_string())
        })
        .map(Option::unwrap_or_default);
    if let Some(k) = &kind {
        if !matches!(k.as_str(), "hal" | "tcl" | "ini") {
            die(format!(
                "Unknown file extension for filename=<{}>",
                req.file.as_deref().unwrap_or_default()
            ));
        }
    }
    if Instance::attach(&instance).is_ok() {
        die("Realtime already running.  Use 'halrun -U' to stop existing realtime session.");
    }
    let mut host = match start_host(&instance, false) {
        Ok(c) => c,
        Err(e) => die(e),
    };
    let status = match Instance::attach(&instance) {
        Ok(inst) => run(inst, &req, kind.as_deref()),
        Err(e) => {
            eprintln!("halrun: {e}");
            1
        }
    };
    if let Err(e) = stop_host(&instance, Duration::from_secs(10)) {
        eprintln!("halrun: stopping realtime: {e}");
        let _ = host.kill();
    }
    let _ = host.wait();
    std::process::exit(status);
}

/// Runs the file and the interactive session asked for. Returns the exit
/// status.
fn run(inst: Instance, req: &Request, kind: Option<&str>) -> i32 {
    let mut words = req.halcmd_opts.clone();
    if let Some(ini) = &req.ini {
        words.extend(["-i".to_string(), ini.clone()]);
    }
    match kind {
        None | Some("hal") => {
            if let Some(f) = &req.file {
                words.extend(["-f".to_string(), f.clone()]);
            } else {
                // No file: an interactive halcmd that keeps going.
                words.push("-k".to_string());
            }
            let parsed = match parse_halcmd_args(&words) {
                Ok(p) => p,
                Err(e) => die(e),
            };
            if req.interactive_tcl && req.file.is_some() {
                let status = run_halcmd(inst.clone(), parsed, false);
                return status.max(interactive_tcl(inst, req.ini.as_deref()));
            }
            if req.file.is_none() && req.interactive_tcl {
                return interactive_tcl(inst, req.ini.as_deref());
            }
            run_halcmd(inst, parsed, req.interactive_halcmd)
        }
        Some("tcl") => {
            let ini = req.ini.as_deref().map(load_ini_or_die);
            let job = TclJob {
                script: req.file.as_ref().map(PathBuf::from),
                ..TclJob::default()
            };
            let mut status = with_session(inst.clone(), ini.clone(), |s| {
                tcl_status(haltcl::run(s, ini.as_ref(), &job))
            });
            if req.interactive_tcl {
                status = status.max(interactive_tcl(inst.clone(), req.ini.as_deref()));
            }
            if req.interactive_halcmd {
                status = status.max(with_session(inst, None, |s| {
                    i32::from(!hal_tools::cli::interactive(s, true))
                }));
            }
            status
        }
        _ => run_ini(inst, req),
    }
}

/// A `.ini` file, as LinuxCNC's halrun takes one: only the `[HAL]TWOPASS`
/// processing of its HALFILEs (its `twopass:` lines on stdout), then the
/// sessions asked for. Without TWOPASS nothing of the file runs.
fn run_ini(inst: Instance, req: &Request) -> i32 {
    let path = req.file.clone().unwrap_or_default();
    let ini = match launcher::load_ini(Path::new(&path)) {
        Ok(i) => i,
        Err(e) => die(e),
    };
    let mut status = 0;
    let opts = launcher::Options {
        ini_path: PathBuf::from(&path),
        keep_going: req.halcmd_opts.iter().any(|o| o == "-k"),
        verbose: req.halcmd_opts.iter().any(|o| o == "-v" || o == "-V"),
        ..launcher::Options::default()
    };
    let (mut out, mut err) = (hal_tools::stdio::stdout(), std::io::stderr());
    let hopts = hal_lang::Options {
        keep_going: opts.keep_going,
        verbose: opts.verbose,
        ini: Some(ini.clone()),
        ..Default::default()
    };
    let mut session = Session::new(inst.clone(), hopts, &mut out, &mut err);
    if launcher::asks_for_twopass(&ini) {
        if let Err(e) = launcher::run_twopass(&mut session, &ini, &opts) {
            eprintln!("halrun: {e}");
            status = 1;
        }
    } else {
        session.say("halrun: An INI file may only be used if it specifies [HAL]TWOPASS");
        status = 1;
    }
    if req.interactive_halcmd {
        let stdin = std::io::stdin();
        let prompt = stdin.is_terminal();
        if !hal_tools::cli::interactive(&mut session, prompt) {
            status = 1;
        }
    }
    if req.interactive_tcl {
        let job = TclJob {
            prompt: std::io::stdin().is_terminal(),
            twopass: None,
            ..TclJob::default()
        };
        status = status.max(tcl_status(haltcl::run(&mut session, Some(&ini), &job)));
    }
    status
}

fn load_ini_or_die(path: &str) -> hal_lang::ini::Ini {
    hal_lang::ini::Ini::load(Path::new(path)).unwrap_or_else(|e| die(e))
}

/// Runs `f` on a session writing to stdout and stderr.
fn with_session<R>(
    inst: Instance,
    ini: Option<hal_lang::ini::Ini>,
    f: impl FnOnce(&mut Session<'_>) -> R,
) -> R {
    let (mut out, mut err) = (hal_tools::stdio::stdout(), std::io::stderr());
    let opts = hal_lang::Options {
        ini,
        ..Default::default()
    };
    let mut session = Session::new(inst, opts, &mut out, &mut err);
    f(&mut session)
}

fn interactive_tcl(inst: Instance, ini: Option<&str>) -> i32 {
    let ini = ini.map(load_ini_or_die);
    let job = TclJob {
        prompt: std::io::stdin().is_terminal(),
        twopass: None,
        ..TclJob::default()
    };
    with_session(inst, ini.clone(), |s| {
        tcl_status(haltcl::run(s, ini.as_ref(), &job))
    })
}

fn tcl_status(r: Result<(), haltcl::HaltclError>) -> i32 {
    match r {
        Ok(()) => 0,
        Err(haltcl::HaltclError::Failed { .. }) => 1,
        Err(e) => {
            eprintln!("{e}");
            1
        }
    }
}

/// `halrun -U`: asks the host to stop everything and exit.
fn unload(instance: &str) -> i32 {
    match stop_host(instance, Duration::from_secs(10)) {
        Ok(()) => 0,
        Err(hal_lang::protocol::ClientError::NotRunning { .. }) => {
            eprintln!("halrun: realtime is not running for instance '{instance}'");
            0
        }
        Err(e) => {
            eprintln!("halrun -U: {e}");
            1
        }
    }
}

fn die(msg: impl std::fmt::Display) -> ! {
    eprintln!("halrun: {msg}");
    std::process::exit(1);
}
