//! HAL files through halcmd's command dispatcher, against a live host of
//! this process. One halcmd session serves every input; the requests
//! only the host carries out (`loadrt`, `addf`, `delf`, ...) go to the
//! host through `hal_host::InProcess`, which runs them as the host's socket
//! connections do, without the socket: over the socket, an input cost
//! two thread wake-ups per request, and on a busy machine the wake-ups
//! were most of the time.
//!
//! Each input is a HAL file run with `-k` (every line is tried). Lines
//! whose command would reach outside the instance are dropped before it
//! runs: `loadusr` (starts programs), `source` (reads any file, such as
//! `/dev/zero`), `save` to a file, `waitusr` and `unloadusr`, and `start`
//! (running threads make the outcome depend on timing; functions have
//! tests of their own). Checked besides "no panic": the instance can be
//! listed after every input, and `stop`, `unloadrt all`, `delsig all`
//! then succeed and (with the threads deleted, which outlive their
//! module) leave it as empty as it started.

use std::cell::RefCell;
use std::io::Write;
use std::rc::Rc;
use std::sync::Arc;

use hal_core::{Host, Instance};
use hal_lang::lexer::{hal_text, logical_lines, tokenize};
use hal_lang::{Options, Session};
use hal_host::InProcess;

use crate::registry::fuzz_registry;
use crate::snapshot::delete_threads;
use crate::snapshot::Snapshot;
use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "halcmd_dispatch",
    run,
    dictionary: &[
        "loadrt ",
        "unloadrt ",
        "net ",
        "newsig ",
        "delsig ",
        "sets ",
        "gets ",
        "setp ",
        "getp ",
        "ptype ",
        "stype ",
        "linkps ",
        "linksp ",
        "linkpp ",
        "unlinkp ",
        "addf ",
        "delf ",
        "initf ",
        "show ",
        "list ",
        "alias ",
        "unalias ",
        "echo\n",
        "unecho\n",
        "print ",
        "status",
        "help ",
        "save",
        "stop\n",
        "lock",
        "unlock",
        "setexact_for_test_suite_only\n",
        " = ",
        " => ",
        " <= ",
        " <=> ",
        " all",
        " pin",
        " sig",
        " param",
        " funct",
        " thread",
        " comp",
        " alias",
        " -t ",
        "bit",
        "float",
        "s32",
        "u32",
        "s64",
        "u64",
        "loadrt threads name1=t period1=1000000\n",
        "loadrt and2 count=2\n",
        "loadrt hal_parport cfg=\"0 out\"\n",
        "and2.0",
        "and2.0.in0",
        "and2.0.out",
        "t",
        "\n",
    ],
    generate: None,
};

/// Commands that reach outside the instance or depend on timing; their
/// lines are dropped.
const DROPPED: &[&str] = &["loadusr", "source", "waitusr", "unloadusr", "start"];

/// Commands that bring the instance back to empty after an input (which
/// may have locked it).
const RESET: &str = "unlock all\nstop\nunloadrt all\ndelsig all\nunecho\n";

/// halcmd's error stream, kept to explain a failed reset.
#[derive(Clone, Default)]
struct Messages(Rc<RefCell<Vec<u8>>>);

impl Write for Messages {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

struct Fixture {
    host: Arc<Host>,
    messages: Messages,
    session: Session<'static>,
    empty: Snapshot,
}

impl Drop for Fixture {
    fn drop(&mut self) {
        self.host.shutdown();
    }
}

thread_local! {
    static FIXTURE: RefCell<Option<Fixture>> = const { RefCell::new(None) };
}

fn start() -> Fixture {
    let host = Arc::new(
        Host::create(crate::host_config("dispatch", 2 << 20)).expect("fuzz host"),
    );
    let inst = Instance::attach(host.instance().name()).expect("attach fuzz host");
    // Output goes nowhere: the checks look at the instance. The session
    // lives as long as the thread, so its streams are leaked (once).
    let messages = Messages::default();
    let out: &'static mut dyn Write = Box::leak(Box::new(std::io::sink()));
    let err: &'static mut dyn Write = Box::leak(Box::new(messages.clone()));
    let opts = Options {
        keep_going: true,
        ..Options::default()
    };
    let link = InProcess::new(host.clone(), fuzz_registry());
    let session = Session::new(inst, opts, out, err).with_host_link(Box::new(link));
    let empty = Snapshot::of(session.instance());
    Fixture {
        host,
        messages,
        session,
        empty,
    }
}

/// The input with the lines of [`DROPPED`] commands, and `save` to a
/// file, left out.
fn contained(text: &str) -> String {
    let mut out = String::new();
    for line in logical_lines(text) {
        if let Ok(words) = tokenize(&line.text, None) {
            let first = words.first().map(String::as_str).unwrap_or("");
            if DROPPED.contains(&first) || (first == "save" && words.len() > 2) {
                continue;
            }
        }
        out.push_str(&line.text);
        out.push('\n');
    }
    out
}

fn run(input: &[u8]) {
    let text = contained(&hal_text(input));
    // The fixture is taken out for the run and put back only if the run
    // passes: after a finding, the next input (bolero shrinking it) gets
    // a fresh host instead of the state the finding left.
    let mut fixture = FIXTURE.with(|cell| cell.borrow_mut().take());
    let fx = fixture.get_or_insert_with(start);
    fx.session.run_text(Some("fuzz.hal"), &text);
    Snapshot::of(fx.session.instance());
    fx.messages.0.borrow_mut().clear();
    if !fx.session.run_text(Some("reset.hal"), RESET) {
        panic!(
            "reset after {text:?} failed: {}",
            String::from_utf8_lossy(&fx.messages.0.borrow())
        );
    }
    fx.messages.0.borrow_mut().clear();
    // Threads outlive the `threads` module, as in LinuxCNC; halcmd
    // has no command to delete them, the host does.
    delete_threads(&fx.host);
    if let Some(diff) = fx.empty.difference(&Snapshot::of(fx.session.instance())) {
        panic!("reset after {text:?} left: {diff}");
    }
    FIXTURE.with(|cell| *cell.borrow_mut() = fixture);
}
