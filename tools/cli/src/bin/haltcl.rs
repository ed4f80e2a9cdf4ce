//! haltcl: run a Tcl HAL file (or an interactive Tcl session) on a running
//! HAL instance, as LinuxCNC's `haltcl [-i INI] [file.tcl [args...]]`.

use std::io::IsTerminal;
use std::path::PathBuf;

use hal_core::{instance_from_env, Instance};
use hal_lang::haltcl::{run, TclJob};
use hal_lang::ini::Ini;
use hal_lang::{Options, Session};

fn main() {
    let args = hal_tools::stdio::args_or_exit("haltcl", 1);
    let mut ini = None;
    let mut i = 0;
    while let Some(a) = args.get(i) {
        // haltcl's -i is LinuxCNC's INI file: the instance is long only.
        if let Some(found) = hal_core::userspace::instance_option(&args, i, false) {
            let (name, words) = found.unwrap_or_else(|e| die(&e.to_string()));
            if let Err(e) = hal_core::userspace::select_instance(&name) {
                die(&format!("--instance: {e}"));
            }
            i += words;
            continue;
        }
        match a.as_str() {
            "-i" | "-ini" => {
                let Some(path) = args.get(i + 1) else {
                    die("-i needs an INI file")
                };
                match Ini::load(std::path::Path::new(path)) {
                    Ok(v) => ini = Some(v),
                    Err(e) => die(&e.to_string()),
                }
                i += 2;
            }
            "-h" | "--help" => {
                hal_tools::outln!("{}", hal_tools::usage::HALTCL);
                return;
            }
            "--version" => {
                hal_tools::outln!("{}", hal_core::userspace::version_line("haltcl"));
                return;
            }
            // A script's name never starts with '-' here: the word is an
            // option haltcl does not have.
            other if other.starts_with('-') && other != "-" => {
                die(&format!("unknown option '{other}' (see haltcl --help)"))
            }
            _ => break,
        }
    }
    let job = TclJob {
        script: args.get(i).map(PathBuf::from),
        argv: args
            .get(i + 1..)
            .map(<[String]>::to_vec)
            .unwrap_or_default(),
        prompt: std::io::stdin().is_terminal(),
        twopass: None,
    };
    let inst = match Instance::attach(&instance_from_env()) {
        Ok(inst) => inst,
        Err(e) => die(&e.to_string()),
    };
    let (mut out, mut err) = (hal_tools::stdio::stdout(), std::io::stderr());
    let opts = Options {
        ini: ini.clone(),
        ..Options::default()
    };
    let mut session = Session::new(inst, opts, &mut out, &mut err);
    if let Err(e) = run(&mut session, ini.as_ref(), &job) {
        // A failed script has printed its own error.
        if !matches!(e, hal_lang::haltcl::HaltclError::Failed { .. }) {
            eprintln!("{e}");
        }
        std::process::exit(1);
    }
}

fn die(msg: &str) -> ! {
    eprintln!("haltcl: {msg}");
    std::process::exit(1);
}
