//! The part-program runner's library: the G-code subset it executes
//! ([`interp`], with [`words`] reading the lines) and running the result
//! on a machine ([`run`]).

pub mod interp;
pub mod run;
pub mod words;

/// A place in the program: line and column, from 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Loc {
    /// Line, from 1.
    pub line: usize,
    /// Column (characters), from 1.
    pub column: usize,
}

/// A line of the program that cannot run, and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{}:{}: {message}", loc.line, loc.column)]
pub struct ProgramError {
    /// The file.
    pub file: String,
    /// Where.
    pub loc: Loc,
    /// What.
    pub message: String,
}

/// The fuzz target's body: any bytes as a program, never a panic; every
/// refusal names a place inside the input.
pub fn fuzz_program(data: &[u8]) {
    match interp::interpret("fuzz", data, motion::kins::Pose::ZERO, interp::Units::Mm) {
        Ok(steps) => {
            for s in steps {
                // Whatever is sent is finite where it must be.
                if let interp::Step::Send(motion::command::Command::Line { end, .. }, _) = s {
                    assert!(end.0.iter().all(|v| v.is_finite()));
                }
            }
        }
        Err(e) => {
            let lines = data.split(|&b| b == b'\n').count();
            assert!(e.loc.line >= 1 && e.loc.line <= lines.max(1), "{e}");
            assert!(e.loc.column >= 1);
        }
    }
}

#[cfg(test)]
mod tests;
