//! `lcec_conf`: checks linuxcnc-ethercat's configuration and keeps it in
//! the HAL instance for `loadrt lcec` ([`hal_ethercat::lcec::handoff`]),
//! as a user component that lives until the session ends.

use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, Instance};
use hal_ethercat::lcec::{self, handoff};

mod args;
use args::Args;

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("lcec_conf: {e}");
            ExitCode::from(1)
        }
    }
}

/// What can stop `lcec_conf`.
#[derive(Debug, thiserror::Error)]
enum RunError {
    #[error(transparent)]
    Config(#[from] hal_ethercat::Error),
    #[error("{what}: {source}")]
    Hal {
        what: &'static str,
        #[source]
        source: hal_core::HalError,
    },
}

fn hal(what: &'static str) -> impl FnOnce(hal_core::HalError) -> RunError {
    move |source| RunError::Hal { what, source }
}

fn run(args: &Args) -> Result<(), RunError> {
    let text = lcec::conf::read_text(&args.file)?;
    // Checked here, so an error names the file at `loadusr`.
    lcec::conf::parse(&text, &args.file)?;
    let path = std::path::absolute(&args.file).unwrap_or_else(|_| args.file.clone());
    let exit = ExitSignals::install().map_err(hal("installing signal handlers"))?;
    let inst = Instance::attach(&hal_core::instance_from_env())
        .map_err(hal("attaching to the HAL instance"))?;
    let comp = inst
        .new_component(handoff::REGION, ComponentKind::User)
        .map_err(hal("creating the component lcec_conf"))?;
    handoff::publish(&comp, &path, &text).map_err(hal("keeping the configuration"))?;
    comp.ready().map_err(hal("making lcec_conf ready"))?;
    while !exit.requested() && inst.host_alive() {
        std::thread::sleep(Duration::from_millis(100));
    }
    Ok(())
}
