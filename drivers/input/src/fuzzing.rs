//! Fuzz-target bodies (for `fuzz/`): each takes arbitrary bytes and
//! checks what the code under test promises.

use std::path::Path;

use crate::regs::{parse_events, Event, EVENT_SIZE};

/// What a read of an event node returned: refused unless a whole number
/// of records, else decoded to one event per record, each of which
/// encodes back to its record (time stamp aside).
pub fn event_records(data: &[u8]) {
    let mut out = Vec::new();
    match parse_events(data, &mut out) {
        Ok(()) => {
            assert_eq!(data.len() % EVENT_SIZE, 0);
            assert_eq!(out.len(), data.len() / EVENT_SIZE);
            for (e, rec) in out.iter().zip(data.chunks_exact(EVENT_SIZE)) {
                let back = e.to_record();
                let at = EVENT_SIZE - 8;
                assert_eq!(&back[at..], &rec[at..]);
                let mut whole = [0u8; EVENT_SIZE];
                whole.copy_from_slice(rec);
                assert_eq!(Event::from_record(&whole), *e);
            }
        }
        Err(_) => {
            assert_ne!(data.len() % EVENT_SIZE, 0);
            assert!(out.is_empty());
        }
    }
}

/// A simulated devices' description: parsed or refused with its line;
/// what parses has every device named by a node, its script in time
/// order, and the codes of its features within hal_input's tables.
pub fn sim_description(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    match crate::sim::parse(&text, "fuzz.txt", Path::new("/nonexistent")) {
        Ok(specs) => {
            assert!(specs.len() <= crate::sim::DEVICES_MAX);
            for s in &specs {
                assert!(s.who.path.is_absolute() || !s.who.path.as_os_str().is_empty());
                assert!(s.script.windows(2).all(|w| w[0].0 <= w[1].0));
                let last = crate::names::last_code(crate::regs::EV_KEY).unwrap_or(0);
                assert!(s.keys.iter().all(|c| *c <= last));
                assert!(s.abs.iter().all(|(_, a)| a.minimum <= a.maximum));
            }
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.starts_with("fuzz.txt:"), "{msg}");
        }
    }
}

/// A command line, arguments separated by NUL bytes (a line naming
/// `--instance` is skipped: that option sets the process's environment):
/// parsed into at least one non-empty inputspec, help, version, or a
/// refusal with a message. Each word is also a shell pattern: one
/// without `*`, `?` or `[` matches itself, and matching never panics.
pub fn command_line(data: &[u8]) {
    use crate::spec::{glob_match, parse_args, Command};
    let text = String::from_utf8_lossy(data);
    let args: Vec<String> = text.split('\0').map(str::to_string).collect();
    if args.iter().any(|a| a.starts_with("--instance")) {
        return;
    }
    match parse_args(&args) {
        Ok(Command::Run(o)) => {
            assert!(!o.devices.is_empty());
            assert!(o
                .devices
                .iter()
                .all(|d| !d.spec.is_empty() && d.spec != "+"));
        }
        Ok(Command::Help | Command::Version) => {}
        Err(e) => assert!(!e.to_string().is_empty()),
    }
    for w in &args {
        if !w.contains(['*', '?', '[']) {
            assert!(glob_match(w, w), "{w:?}");
        }
        assert!(glob_match("*", w));
        if let Some(other) = args.first() {
            let _ = glob_match(w, other);
        }
    }
}
