//! halscope, headless: capture HAL pins to PNG, CSV or VCD (see
//! `hal_scope::scope`).

use std::process::ExitCode;

use clap::Parser;
use hal_core::userspace::ExitSignals;
use hal_core::{instance_from_env, Instance};
use hal_scope::scope::args::Args;
use hal_scope::scope::{capture, title, write_outputs, ScopeError};

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(ScopeError::Usage(m)) => {
            eprintln!("halscope: {m} (see halscope --help)");
            ExitCode::from(2)
        }
        Err(e) => {
            eprintln!("halscope: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), ScopeError> {
    // LinuxCNC's configurations start its GUI bare ('loadusr halscope',
    // beside 'loadrt scope_rt'): say what this one is instead of clap's
    // missing-argument error.
    if std::env::args_os().len() == 1 {
        return Err(ScopeError::Usage(
            "this halscope is headless (no window): name what to capture and where, e.g. \
             'halscope --pins NAME,... --out capture.png'"
                .into(),
        ));
    }
    let args = Args::parse();
    let name = args.instance.clone().unwrap_or_else(instance_from_env);
    let req = args.request()?;
    let signals = ExitSignals::install()?;
    let inst = Instance::attach(&name).map_err(|source| ScopeError::Attach {
        instance: name.clone(),
        source,
    })?;
    let record = capture(&inst, &req, &|| signals.requested())?;
    write_outputs(&record, &req, &title(&record, &req))?;
    for (path, _) in &req.outputs {
        hal_tools::outln!("halscope: wrote {}", path.display());
    }
    Ok(())
}
