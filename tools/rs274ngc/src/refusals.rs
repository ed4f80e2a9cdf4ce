//! Every refusal of a whole program, earliest first, found by running
//! it against a canon that moves nothing (for `gcode-run --check`).

use std::path::Path;

use crate::canon::ToolEntry;
use crate::config::Config;
use crate::error::InterpError;
use crate::interp::{Interp, Location, Status};
use crate::print_canon::PrintCanon;

/// Stop after this many refusals (a program of garbage has one per line).
const MAX_REFUSALS: usize = 1000;

/// Blocks [`list_refusals`] runs before giving up on a program that does
/// not end (an endless loop).
pub const MAX_CHECKED_BLOCKS: usize = 5_000_000;

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

/// Every refusal of the program at `path`, run to its end against a canon
/// that moves nothing (parameters are not saved), sorted by file, line
/// and column, each place and text once. `tools` is the tool table.
pub fn list_refusals(path: &Path, config: Config, tools: Vec<ToolEntry>) -> Vec<Refusal> {
    list_refusals_within(path, config, tools, MAX_CHECKED_BLOCKS)
}

/// [`list_refusals`] running at most `max_blocks` blocks; a program still
/// running then gets a last refusal saying so.
pub fn list_refusals_within(
    path: &Path,
    config: Config,
    tools: Vec<ToolEntry>,
    max_blocks: usize,
) -> Vec<Refusal> {
    let mut run = Run {
        path,
        canon: PrintCanon::new(None, tools),
        interp: Interp::new(Config {
            parameter_file: None,
            ..config
        }),
        refusals: Vec::new(),
    };
    run.run_to_end(max_blocks);
    let mut refusals = run.refusals;
    refusals.sort_by(|a, b| {
        let key = |r: &Refusal| (r.location.file.clone(), r.location.line, r.location.column);
        key(a).cmp(&key(b))
    });
    refusals
        .dedup_by(|a, b| a.location == b.location && a.error.to_string() == b.error.to_string());
    refusals
}

struct Run<'a> {
    path: &'a Path,
    canon: PrintCanon,
    interp: Interp,
    refusals: Vec<Refusal>,
}

impl Run<'_> {
    fn push(&mut self, error: InterpError) {
        let mut location = self.interp.error_location();
        if location.file.as_os_str().is_empty() {
            location.file = self.path.to_path_buf();
        }
        self.refusals.push(Refusal { location, error });
    }

    fn run_to_end(&mut self, max_blocks: usize) {
        if let Err(e) = self.interp.init(&mut self.canon) {
            return self.push(e);
        }
        if let Err(e) = self.interp.open(self.path, &mut self.canon) {
            return self.push(e);
        }
        let mut last_line = -1;
        for _ in 0..max_blocks {
            if self.refusals.len() >= MAX_REFUSALS {
                return;
            }
            match self.interp.read(&mut self.canon) {
                Ok(Status::EndFile) => return,
                Ok(_) => {}
                Err(e) => {
                    let line = self.interp.sequence_number();
                    let end = matches!(
                        e,
                        InterpError::NoPercentAtEnd
                            | InterpError::NoPercentOrEnd
                            | InterpError::Io { .. }
                    ) || line == last_line;
                    self.push(e);
                    last_line = line;
                    if end {
                        return;
                    }
                    continue;
                }
            }
            match self.interp.execute(&mut self.canon) {
                Ok(Status::Exit) => return,
                Ok(_) => {}
                Err(e) => self.push(e),
            }
        }
        self.push(InterpError::DoesNotEnd(max_blocks));
    }
}
