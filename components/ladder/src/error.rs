//! The crate's error type: what the `.clp` parser, the loader and the
//! realtime module refuse.

use hal_core::files::FileError;
use hal_core::HalError;

use crate::expr::ExprError;
use crate::model::CellError;

/// Everything this crate refuses.
#[derive(Debug, thiserror::Error)]
pub enum LadderError {
    /// The project file could not be read.
    #[error(transparent)]
    Read(#[from] FileError),
    /// A line of the project file that does not parse.
    #[error("line {line} ({part}): {what}")]
    Syntax {
        /// 1-based line in the .clp file.
        line: usize,
        /// The part of the bundle (`rung_3.csv`, `timers.csv`...).
        part: String,
        /// What is wrong.
        what: String,
    },
    /// A rung cell the module cannot run.
    #[error("line {line} (rung {rung}, column {x}, row {y}): {source}")]
    Cell {
        /// 1-based line in the .clp file.
        line: usize,
        /// The rung.
        rung: usize,
        /// Column (0-based, as ClassicLadder counts).
        x: usize,
        /// Row (0-based).
        y: usize,
        /// Why.
        #[source]
        source: CellError,
    },
    /// An arithmetic expression that does not parse.
    #[error("line {line} (expression {number} '{text}'): {source}")]
    Expr {
        /// 1-based line in the .clp file (0 when the expression is missing).
        line: usize,
        /// The expression's number.
        number: usize,
        /// Its text.
        text: String,
        /// Why.
        #[source]
        source: ExprError,
    },
    /// A program whose sections or rung chain cannot run.
    #[error("{what}")]
    Structure {
        /// What is wrong.
        what: String,
    },
    /// The handed-over program in shared memory is damaged.
    #[error("the program in HAL region '{region}' is damaged: {what}")]
    Handoff {
        /// The region.
        region: String,
        /// What is wrong.
        what: String,
    },
    /// The realtime module is not loaded in the instance.
    #[error("classicladder_rt is not loaded in HAL instance '{instance}' (loadrt classicladder_rt first)")]
    NotLoaded {
        /// The instance.
        instance: String,
        /// Why the region could not be opened.
        #[source]
        source: HalError,
    },
    /// The realtime module did not take the program.
    #[error("classicladder_rt refused the program: {what}")]
    Refused {
        /// Its reason.
        what: String,
    },
    /// A HAL operation failed.
    #[error(transparent)]
    Hal(#[from] HalError),
    /// A bad command line.
    #[error("{0}")]
    Usage(String),
}
