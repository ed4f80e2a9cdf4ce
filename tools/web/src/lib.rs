//! hal-web: a running HAL instance, and the machine on it, in a browser.
//!
//! * [`args`]: the command line and its help.
//! * [`run`]: attach, make the token if one is needed, listen, register
//!   the `hal-web` component as ready (`loadusr -W hal-web`), serve.
//! * The API (`/api/...`, behind [`guard`]): `show` (the whole tree),
//!   `stream` (live values of what the page watches, and its meters),
//!   `hal` (setp, sets, net, unlinkp through halcmd's command layer),
//!   `machine` (task's state and buttons, as task-cmd sends them),
//!   `scope` and `scope.csv` (captures by the headless halscope's sampler
//!   and trigger; `record` is how a record is sent),
//!   `threads` (timing and latency histograms, as latency-test reads them).
//! * The page: plain HTML and JavaScript built into the binary.

#![forbid(unsafe_code)]

pub mod args;
mod change;
mod error;
#[cfg(any(test, feature = "fuzzing"))]
pub mod fuzzing;
pub mod guard;
mod machine;
mod meters;
mod page;
mod record;
mod scope;
mod server;
mod snapshot;
mod state;
mod stream;
mod threads;
pub mod token;
mod watch;

pub use args::{parse, Command, Options, USAGE};
pub use change::{run_halcmd, Outcome};
pub use error::WebError;

use std::io::{IsTerminal, Write};

use hal_core::userspace::ExitSignals;
use hal_core::{ComponentKind, Instance};

/// The component hal-web registers, that `loadusr -W hal-web` waits for.
pub const COMPONENT: &str = "hal-web";

/// Serves the instance named by `HAL_INSTANCE` (or `default`) as
/// `options` say, until SIGTERM/SIGINT or the instance ends.
pub fn run(options: &Options) -> Result<(), WebError> {
    let exit = ExitSignals::install()?;
    let inst = Instance::attach(&hal_core::instance_from_env())?;
    let token = if options.token {
        let t = token::Token::generate()?;
        let path = token::path(inst.name())?;
        token::store(&t, &path)?;
        Some((t, path))
    } else {
        None
    };
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_io()
        .enable_time()
        // The blocking work (HAL reads, halcmd, task requests) on at most
        // four threads: hal-web's CPU stays bounded whatever the browsers
        // do, and a button waiting on task (up to 20 s) leaves threads
        // for the live values.
        .max_blocking_threads(4)
        .build()
        .map_err(WebError::Runtime)?;
    let policy = guard::Policy {
        token: token.as_ref().map(|(t, _)| t.clone()),
        read_only: options.read_only,
    };
    let result = runtime.block_on(async {
        let listener = server::bind(options.addr).await?;
        let addr = listener.local_addr().map_err(|source| WebError::Bind {
            addr: options.addr.to_string(),
            source,
        })?;
        announce(inst.name(), addr, token.as_ref(), options.read_only);
        let comp = inst.new_component(COMPONENT, ComponentKind::User)?;
        comp.ready()?;
        let served = server::serve(listener, inst.clone(), policy, exit).await;
        drop(comp);
        served.map_err(WebError::Serve)
    });
    if let Some((_, path)) = &token {
        token::remove(path);
    }
    result
}

/// Says where hal-web listens (and, on a terminal, the token, once).
fn announce(
    instance: &str,
    addr: std::net::SocketAddr,
    token: Option<&(token::Token, std::path::PathBuf)>,
    read_only: bool,
) {
    let mut out = std::io::stdout();
    let mode = if read_only { " (read-only)" } else { "" };
    let _ = writeln!(
        out,
        "hal-web: serving instance '{instance}' on http://{addr}/{mode}"
    );
    if let Some((t, path)) = token {
        if out.is_terminal() {
            let _ = writeln!(out, "hal-web: access token: {}", t.secret());
        }
        let _ = writeln!(
            out,
            "hal-web: the access token is in {} (readable by its owner only)",
            path.display()
        );
    }
    let _ = out.flush();
}
