//! The crate's error type: what a component's own parsers of `loadrt`
//! strings refuse (personalities, format strings, step patterns), and
//! the broken invariants the `loadrt` fuzz body reports. A refused
//! parameter reaches the user as [`hal_core::HalError::ModuleParam`]
//! naming the module and parameter, with this error's text as its reason.

use hal_core::HalError;

/// Everything a component's parsers refuse, and the broken `loadrt`
/// invariants the fuzz body (`loadrt_is_all_or_nothing`) finds.
#[derive(Debug, thiserror::Error)]
pub enum CompError {
    /// stepgen type 15 without `user_step_type` patterns.
    #[error("step type 15 needs at least one user_step_type pattern")]
    NoUserPatterns,
    /// More `user_step_type` patterns than a cycle holds.
    #[error("at most {max} patterns are allowed")]
    TooManyPatterns {
        /// The most a cycle holds.
        max: usize,
    },
    /// A `user_step_type` pattern uses more bits than there are phases.
    #[error("pattern {index}: {pattern} uses more than {max_phases} bits (phases A-E)")]
    PatternTooWide {
        /// Its position in the list.
        index: usize,
        /// The pattern.
        pattern: i64,
        /// The number of phases.
        max_phases: usize,
    },
    /// A logic personality asks for more inputs than there are.
    #[error("{personality:#x} asks for {inputs} inputs (at most {max})")]
    TooManyInputs {
        /// The personality.
        personality: i64,
        /// The inputs it asks for.
        inputs: usize,
        /// The most there can be.
        max: usize,
    },
    /// An empty bldc `cfg` entry.
    #[error("an empty entry; use 'n' for a motor without feedback")]
    EmptyBldcEntry,
    /// A bldc `cfg` letter that means nothing.
    #[error("'{letter}' in '{entry}' is not one of n h a q i f B 6 H F T")]
    BadBldcLetter {
        /// The letter.
        letter: char,
        /// The entry holding it.
        entry: String,
    },
    /// An `enums` entry without its E; or D; mode.
    #[error("'{spec}' must start with E; (encode) or D; (decode)")]
    EnumMode {
        /// The entry.
        spec: String,
    },
    /// An `enums` entry ending in ';'.
    #[error("'{spec}' ends with ';': a value name is missing")]
    EnumTrailingSemicolon {
        /// The entry.
        spec: String,
    },
    /// A mux_generic format with three type letters.
    #[error("'{format}' has more than two type letters")]
    MuxTypes {
        /// The format string.
        format: String,
    },
    /// A mux_generic format with a character that is not a digit or type.
    #[error("'{format}': '{letter}' is neither a digit nor a type letter (b, f, s, u)")]
    MuxLetter {
        /// The format string.
        format: String,
        /// The character.
        letter: char,
    },
    /// A mux_generic format without a type letter.
    #[error("'{format}' has no type letter (b, f, s, u)")]
    MuxNoType {
        /// The format string.
        format: String,
    },
    /// A mux_generic format with fewer than two inputs.
    #[error("'{format}' asks for {size} inputs (at least 2)")]
    MuxTooSmall {
        /// The format string.
        format: String,
        /// The inputs it asks for.
        size: u32,
    },
    /// A matrix_kb size that is not RxC.
    #[error("'{config}': the size must be RxC, e.g. 4x3")]
    KbSize {
        /// The config string.
        config: String,
    },
    /// A matrix_kb with too many columns.
    #[error("'{config}': at most {max} columns")]
    KbColumns {
        /// The config string.
        config: String,
        /// The most columns.
        max: u32,
    },
    /// A matrix_kb with too many rows.
    #[error("'{config}': at most {max} rows")]
    KbRows {
        /// The config string.
        config: String,
        /// The most rows.
        max: u32,
    },
    /// Reading what the instance holds failed.
    #[error(transparent)]
    Hal(Box<HalError>),
    /// A failed load left objects behind.
    #[error("loadrt {module} failed ({cause}) but left {after} (before: {before})")]
    LeftBehind {
        /// The module.
        module: String,
        /// Why the load failed.
        #[source]
        cause: Box<HalError>,
        /// What the instance held after the load, by kind.
        after: String,
        /// What it held before.
        before: String,
    },
    /// A loaded module would not unload.
    #[error("unloadrt {module}: {source}")]
    Unload {
        /// The module.
        module: String,
        /// Why.
        #[source]
        source: Box<HalError>,
    },
    /// A thread the load made would not go.
    #[error("delete thread {thread}: {source}")]
    DeleteThread {
        /// The thread.
        thread: String,
        /// Why.
        #[source]
        source: Box<HalError>,
    },
    /// A successful load followed by an unload did not restore the instance.
    #[error("unloadrt {module} left {after}")]
    NotRestored {
        /// The module.
        module: String,
        /// What the instance held afterwards, by kind.
        after: String,
    },
    /// A word of scope_rt's shared region that does not hold what the
    /// layout allows (a region of another version, or garbage).
    #[error("scope_rt's shared region: {field} is {value}, {expected}")]
    ScopeShm {
        /// The word's name in the layout.
        field: &'static str,
        /// What it holds.
        value: u64,
        /// What it should hold.
        expected: String,
    },
    /// A capture setting scope_rt cannot take.
    #[error("scope_rt: {setting} {value}: {reason}")]
    ScopeSetting {
        /// The setting.
        setting: &'static str,
        /// Its value.
        value: u64,
        /// Why it is refused.
        reason: String,
    },
}

impl From<HalError> for CompError {
    fn from(e: HalError) -> CompError {
        CompError::Hal(Box::new(e))
    }
}
