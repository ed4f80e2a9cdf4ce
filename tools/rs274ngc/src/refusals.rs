//! Every refusal of a whole program, earliest first, found by running
//! it against a canon that moves nothing (for `gcode-run --check`).

use std::path::Path;

use crate::config::Config;
use crate::error::InterpError;
use crate::interp::{Interp, Location, Status};
use crate::print_canon::PrintCanon;

/// Stop after this many refusals (a program of garbage has one per line).
const MAX_REFUSALS: usize = 1000;

/// One refusal: where, and why.
#[derive(Debug)]
pub struct Refusal {
    /// File, line, column and the word refused.
    pub location: Location,
    /// LinuxCNC's text for the refusal.
    pub error: InterpError,
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.location, self.error)
    }
}

/// Interpret the program at `path` without output and list every
/// refusal, earliest first; interpretation continues after each (the
/// refused line is skipped, as rs274 -n 0 does).
pub fn list_refusals(path: &Path, config: Config, tools: Vec<crate::canon::ToolEntry>) -> Vec<Refusal> {
    let mut canon = PrintCanon::new(None, tools);
    let mut interp = Interp::new(Config {
        parameter_file: None,
        ..config
    });
    let mut refusals = Vec::new();
    let push = |refusals: &mut Vec<Refusal>, interp: &Interp, error: InterpError| {
        let mut location = interp.error_location();
        if location.file.as_os_str().is_empty() {
            location.file = path.to_path_buf();
        }
        refusals.push(Refusal { location, error });
    };
    if let Err(e) = interp.init(&mut canon) {
        push(&mut refusals, &interp, e);
        return refusals;
    }
    if let Err(e) = interp.open(path, &mut canon) {
        push(&mut refusals, &interp, e);
        return refusals;
    }
    let mut last_line = -1;
    while refusals.len() < MAX_REFUSALS {
        match interp.read(&mut canon) {
            Ok(Status::EndFile) => break,
            Ok(_) => {}
            Err(e) => {
                let line = interp.sequence_number();
                let end = matches!(e, InterpError::NoPercentAtEnd | InterpError::NoPercentOrEnd)
                    || matches!(e, InterpError::Io { .. })
                    || line == last_line;
                push(&mut refusals, &interp, e);
                last_line = line;
                if end {
                    break;
                }
                continue;
            }
        }
        match interp.execute(&mut canon) {
            Ok(Status::Exit) => break,
            Ok(_) => {}
            Err(e) => push(&mut refusals, &interp, e),
        }
    }
    refusals
}
