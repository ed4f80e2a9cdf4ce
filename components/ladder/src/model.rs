//! The ladder program as the runtime executes it: the module's sizes, the
//! variables, the cells of a rung, sections, and the setups of timers,
//! monostables and counters. Everything here is `Copy` and fixed in size,
//! so a program can be decoded into storage allocated once, at `loadrt`.
//!
//! The numeric codes are those of ClassicLadder's project files (element
//! type, variable type); [`Element::from_codes`] is the one place that
//! turns such a triple into a checked element, for the file parser and
//! for the realtime side decoding what the loader handed it.

use crate::expr::Expr;

/// Columns of a rung (the last is the coil column).
pub const RUNG_WIDTH: usize = 10;
/// Rows of a rung.
pub const RUNG_HEIGHT: usize = 6;
/// Cells of a rung.
pub const CELLS: usize = RUNG_WIDTH * RUNG_HEIGHT;
/// Counters count from 0 to this and wrap.
pub const COUNTER_MAX: i32 = 9999;

/// Defines [`Sizes`] from one list: each field with its `loadrt`
/// parameter (`None` for a size LinuxCNC does not let one set), LinuxCNC's
/// default and what it counts. The struct, its default, the module's
/// parameter table and the hand-off's word order all come from it.
macro_rules! sizes {
    ($($field:ident: $param:expr, $default:literal, $what:literal;)*) => {
        /// How many of each object the module holds (its `loadrt`
        /// parameters).
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub struct Sizes {
            $(
                #[doc = $what]
                pub $field: usize,
            )*
        }

        impl Default for Sizes {
            /// LinuxCNC's defaults.
            fn default() -> Self {
                Sizes { $($field: $default,)* }
            }
        }

        impl Sizes {
            /// How many sizes there are.
            pub const COUNT: usize = [$($default),*].len();

            /// Each size's `loadrt` parameter (`None`: not settable) and
            /// its help text, in the order of [`Sizes::to_array`].
            pub const PARAMS: [(Option<&'static str>, &'static str); Self::COUNT] = [
                $(($param, concat!($what, " (default ", $default, ")")),)*
            ];

            /// The sizes in a fixed order (the hand-off's).
            pub fn to_array(&self) -> [usize; Self::COUNT] {
                [$(self.$field),*]
            }

            /// The sizes from [`Sizes::to_array`]'s order.
            pub fn from_array(v: [usize; Self::COUNT]) -> Sizes {
                let mut it = v.into_iter();
                Sizes { $($field: it.next().unwrap_or($default),)* }
            }
        }
    };
}

sizes! {
    rungs: Some("numRungs"), 100, "rungs";
    bits: Some("numBits"), 500, "memory bits %B";
    words: Some("numWords"), 100, "memory words %W";
    timers: Some("numTimers"), 10, "old timers %T";
    monostables: Some("numMonostables"), 10, "monostables %M";
    counters: Some("numCounters"), 10, "counters %C";
    timers_iec: Some("numTimersIec"), 10, "IEC timers %TM";
    inputs: Some("numPhysInputs"), 15, "bit inputs %I, pins in-NN";
    outputs: Some("numPhysOutputs"), 15, "bit outputs %Q, pins out-NN";
    exprs: Some("numArithmExpr"), 100, "arithmetic expressions";
    sections: Some("numSections"), 10, "sections";
    symbols: Some("numSymbols"), 100, "symbols";
    s32_in: Some("numS32in"), 10, "s32 inputs %IW, pins s32in-NN";
    s32_out: Some("numS32out"), 10, "s32 outputs %QW, pins s32out-NN";
    float_in: Some("numFloatIn"), 10, "float inputs %IF, pins floatin-NN";
    float_out: Some("numFloatOut"), 10, "float outputs %QF, pins floatout-NN";
    error_bits: None, 10, "error bits %E (not a parameter in LinuxCNC)";
}

/// The kinds of variables, with ClassicLadder's type codes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VarKind {
    /// %B: memory bit (0).
    Bit,
    /// %Tn.D: old timer done (10).
    TimerDone,
    /// %Tn.R: old timer running (11).
    TimerRunning,
    /// %TMn.Q: IEC timer output (15).
    TimerIecDone,
    /// %Mn.R: monostable running (20).
    MonostableRunning,
    /// %Cn.D: counter done (25).
    CounterDone,
    /// %Cn.E: counter empty (26).
    CounterEmpty,
    /// %Cn.F: counter full (27).
    CounterFull,
    /// %In: physical input (50).
    Input,
    /// %Qn: physical output (60).
    Output,
    /// %En: error bit (70).
    ErrorBit,
    /// %Wn: memory word (200).
    Word,
    /// %Tn.P: old timer preset (230).
    TimerPreset,
    /// %Tn.V: old timer value (231).
    TimerValue,
    /// %Mn.P: monostable preset (240).
    MonostablePreset,
    /// %Mn.V: monostable value (241).
    MonostableValue,
    /// %Cn.P: counter preset (250).
    CounterPreset,
    /// %Cn.V: counter value (251).
    CounterValue,
    /// %TMn.P: IEC timer preset (260).
    TimerIecPreset,
    /// %TMn.V: IEC timer value (261).
    TimerIecValue,
    /// %IWn: s32 input pin (270).
    WordInput,
    /// %QWn: s32 output pin (280).
    WordOutput,
    /// %IFn: float input pin, truncated (300).
    FloatInput,
    /// %QFn: float output pin (310).
    FloatOutput,
}

impl VarKind {
    /// The kind with ClassicLadder's code `code`.
    pub fn from_code(code: i64) -> Option<VarKind> {
        use VarKind::*;
        Some(match code {
            0 => Bit,
            10 => TimerDone,
            11 => TimerRunning,
            15 => TimerIecDone,
            20 => MonostableRunning,
            25 => CounterDone,
            26 => CounterEmpty,
            27 => CounterFull,
            50 => Input,
            60 => Output,
            70 => ErrorBit,
            200 => Word,
            230 => TimerPreset,
            231 => TimerValue,
            240 => MonostablePreset,
            241 => MonostableValue,
            250 => CounterPreset,
            251 => CounterValue,
            260 => TimerIecPreset,
            261 => TimerIecValue,
            270 => WordInput,
            280 => WordOutput,
            300 => FloatInput,
            310 => FloatOutput,
            _ => return None,
        })
    }

    /// ClassicLadder's code of the kind.
    pub fn code(self) -> u16 {
        use VarKind::*;
        match self {
            Bit => 0,
            TimerDone => 10,
            TimerRunning => 11,
            TimerIecDone => 15,
            MonostableRunning => 20,
            CounterDone => 25,
            CounterEmpty => 26,
            CounterFull => 27,
            Input => 50,
            Output => 60,
            ErrorBit => 70,
            Word => 200,
            TimerPreset => 230,
            TimerValue => 231,
            MonostablePreset => 240,
            MonostableValue => 241,
            CounterPreset => 250,
            CounterValue => 251,
            TimerIecPreset => 260,
            TimerIecValue => 261,
            WordInput => 270,
            WordOutput => 280,
            FloatInput => 300,
            FloatOutput => 310,
        }
    }

    /// Whether the variable is a bit (below ClassicLadder's code 199).
    pub fn is_bit(self) -> bool {
        self.code() < 199
    }

    /// Whether a coil or an operate block may write it.
    pub fn is_writable(self) -> bool {
        use VarKind::*;
        matches!(
            self,
            Bit | Output
                | ErrorBit
                | Word
                | TimerPreset
                | MonostablePreset
                | CounterPreset
                | CounterValue
                | TimerIecPreset
                | WordOutput
                | FloatOutput
        )
    }

    /// How many variables of this kind the module holds.
    pub fn count(self, s: &Sizes) -> usize {
        use VarKind::*;
        match self {
            Bit => s.bits,
            TimerDone | TimerRunning | TimerPreset | TimerValue => s.timers,
            TimerIecDone | TimerIecPreset | TimerIecValue => s.timers_iec,
            MonostableRunning | MonostablePreset | MonostableValue => s.monostables,
            CounterDone | CounterEmpty | CounterFull | CounterPreset | CounterValue => s.counters,
            Input => s.inputs,
            Output => s.outputs,
            ErrorBit => s.error_bits,
            Word => s.words,
            WordInput => s.s32_in,
            WordOutput => s.s32_out,
            FloatInput => s.float_in,
            FloatOutput => s.float_out,
        }
    }

    /// The module parameter that sizes this kind (for error messages).
    pub fn size_param(self) -> &'static str {
        use VarKind::*;
        match self {
            Bit => "numBits",
            TimerDone | TimerRunning | TimerPreset | TimerValue => "numTimers",
            TimerIecDone | TimerIecPreset | TimerIecValue => "numTimersIec",
            MonostableRunning | MonostablePreset | MonostableValue => "numMonostables",
            CounterDone | CounterEmpty | CounterFull | CounterPreset | CounterValue => {
                "numCounters"
            }
            Input => "numPhysInputs",
            Output => "numPhysOutputs",
            ErrorBit => "the 10 error bits",
            Word => "numWords",
            WordInput => "numS32in",
            WordOutput => "numS32out",
            FloatInput => "numFloatIn",
            FloatOutput => "numFloatOut",
        }
    }

    /// ClassicLadder's name of variable `index` of this kind (`%I3`,
    /// `%TM0.Q`).
    pub fn name(self, index: u32) -> String {
        use VarKind::*;
        let (prefix, suffix) = match self {
            Bit => ("B", ""),
            TimerDone => ("T", ".D"),
            TimerRunning => ("T", ".R"),
            TimerIecDone => ("TM", ".Q"),
            MonostableRunning => ("M", ".R"),
            CounterDone => ("C", ".D"),
            CounterEmpty => ("C", ".E"),
            CounterFull => ("C", ".F"),
            Input => ("I", ""),
            Output => ("Q", ""),
            ErrorBit => ("E", ""),
            Word => ("W", ""),
            TimerPreset => ("T", ".P"),
            TimerValue => ("T", ".V"),
            MonostablePreset => ("M", ".P"),
            MonostableValue => ("M", ".V"),
            CounterPreset => ("C", ".P"),
            CounterValue => ("C", ".V"),
            TimerIecPreset => ("TM", ".P"),
            TimerIecValue => ("TM", ".V"),
            WordInput => ("IW", ""),
            WordOutput => ("QW", ""),
            FloatInput => ("IF", ""),
            FloatOutput => ("QF", ""),
        };
        format!("%{prefix}{index}{suffix}")
    }
}

/// One variable: its kind and number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VarRef {
    /// The kind.
    pub kind: VarKind,
    /// The number within the kind.
    pub index: u32,
}

impl VarRef {
    /// The variable with ClassicLadder codes `code`/`index`, checked
    /// against `sizes`.
    pub fn from_codes(code: i64, index: i64, sizes: &Sizes) -> Result<VarRef, CellError> {
        if code == 30 || code == 220 {
            return Err(CellError::Sequential);
        }
        let kind = VarKind::from_code(code).ok_or(CellError::UnknownVarType { code })?;
        let count = kind.count(sizes);
        if index < 0 || index as u64 >= count as u64 {
            return Err(CellError::VarOutOfRange { kind, index, count });
        }
        Ok(VarRef {
            kind,
            index: index as u32,
        })
    }
}

impl std::fmt::Display for VarRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.kind.name(self.index))
    }
}

/// What a contact passes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactKind {
    /// -| |-: the variable is on.
    Open,
    /// -|/|-: the variable is off.
    Closed,
    /// -|P|-: the variable went on since the last scan.
    Rising,
    /// -|N|-: the variable went off since the last scan.
    Falling,
}

/// What a coil does with its variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CoilKind {
    /// -( )-: follows its input.
    Normal,
    /// -(/)-: the inverse of its input.
    Inverted,
    /// -(S)-: set while its input is on.
    Set,
    /// -(R)-: reset while its input is on.
    Reset,
}

/// One element of a rung, with what it acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Element {
    /// An empty cell.
    Free,
    /// Covered by a block whose live cell is elsewhere.
    Unusable,
    /// A horizontal wire.
    Connection,
    /// A contact on a bit.
    Contact(ContactKind, VarRef),
    /// A coil on a bit.
    Coil(CoilKind, VarRef),
    /// -(J)-: jump to rung N.
    Jump(u32),
    /// -(C)-: call sub-routine N.
    Call(u32),
    /// Old timer N (2x2 block).
    Timer(u32),
    /// Monostable N (2x2 block).
    Monostable(u32),
    /// Counter N (2x4 block).
    Counter(u32),
    /// IEC timer N (2x2 block).
    TimerIec(u32),
    /// Compare block on expression N (3 cells wide).
    Compare(u32),
    /// Operate block on expression N (3 cells wide).
    Operate(u32),
}

/// Why a cell or variable is refused; small and `Copy`, so the realtime
/// decoder can report it without allocating.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum CellError {
    /// An element type ClassicLadder does not have.
    #[error("element type {code} is not a ClassicLadder element")]
    UnknownElement {
        /// The code.
        code: i64,
    },
    /// A variable type ClassicLadder does not have.
    #[error("variable type {code} is not a ClassicLadder variable type")]
    UnknownVarType {
        /// The code.
        code: i64,
    },
    /// A variable past the module's size.
    #[error("{} is past the {count} the module has (raise {})", kind.name(*index as u32), kind.size_param())]
    VarOutOfRange {
        /// The kind.
        kind: VarKind,
        /// The number given.
        index: i64,
        /// How many there are.
        count: usize,
    },
    /// A contact or coil on a word.
    #[error("{} is a word; a contact or coil needs a bit", kind.name(*index))]
    NotABit {
        /// The kind.
        kind: VarKind,
        /// The number.
        index: u32,
    },
    /// A coil on a variable the ladder cannot write.
    #[error("{} cannot be written by a coil", kind.name(*index))]
    ReadOnly {
        /// The kind.
        kind: VarKind,
        /// The number.
        index: u32,
    },
    /// A block number past the module's size.
    #[error("{what} {index} is past the {count} the module has (raise {param})")]
    BlockOutOfRange {
        /// timer, counter, expression, rung...
        what: &'static str,
        /// The number given.
        index: i64,
        /// How many there are.
        count: usize,
        /// The module parameter.
        param: &'static str,
    },
    /// A block too close to an edge of the rung for its size.
    #[error("a {what} needs {need}; it does not fit at column {x}, row {y}")]
    DoesNotFit {
        /// The block.
        what: &'static str,
        /// Its footprint.
        need: &'static str,
        /// Column.
        x: usize,
        /// Row.
        y: usize,
    },
    /// A sequential (Grafcet) step variable (%X), which this runtime
    /// does not have.
    #[error("sequential (Grafcet) step variables (%X) are not supported")]
    Sequential,
}

fn block(
    what: &'static str,
    index: i64,
    count: usize,
    param: &'static str,
) -> Result<u32, CellError> {
    if index < 0 || index as u64 >= count as u64 {
        return Err(CellError::BlockOutOfRange {
            what,
            index,
            count,
            param,
        });
    }
    Ok(index as u32)
}

fn bit_var(code: i64, index: i64, sizes: &Sizes, coil: bool) -> Result<VarRef, CellError> {
    let v = VarRef::from_codes(code, index, sizes)?;
    if !v.kind.is_bit() {
        return Err(CellError::NotABit {
            kind: v.kind,
            index: v.index,
        });
    }
    if coil && !v.kind.is_writable() {
        return Err(CellError::ReadOnly {
            kind: v.kind,
            index: v.index,
        });
    }
    Ok(v)
}

impl Element {
    /// The element a project file's `type-top-vartype/varnum` describes
    /// at column `x`, row `y`, checked against `sizes`.
    pub fn from_codes(
        code: i64,
        var_code: i64,
        num: i64,
        x: usize,
        y: usize,
        sizes: &Sizes,
    ) -> Result<Element, CellError> {
        let fits = |what: &'static str, need: &'static str, w: usize, h: usize| {
            if x + 1 < w || y + h > RUNG_HEIGHT {
                Err(CellError::DoesNotFit { what, need, x, y })
            } else {
                Ok(())
            }
        };
        Ok(match code {
            0 => Element::Free,
            99 => Element::Unusable,
            9 => Element::Connection,
            1..=4 => {
                let kind = match code {
                    1 => ContactKind::Open,
                    2 => ContactKind::Closed,
                    3 => ContactKind::Rising,
                    _ => ContactKind::Falling,
                };
                Element::Contact(kind, bit_var(var_code, num, sizes, false)?)
            }
            50..=53 => {
                let kind = match code {
                    50 => CoilKind::Normal,
                    51 => CoilKind::Inverted,
                    52 => CoilKind::Set,
                    _ => CoilKind::Reset,
                };
                Element::Coil(kind, bit_var(var_code, num, sizes, true)?)
            }
            54 => Element::Jump(block("rung", num, sizes.rungs, "numRungs")?),
            55 => Element::Call(block("sub-routine", num, sizes.sections, "numSections")?),
            10 => {
                fits("timer", "2 columns and 2 rows", 2, 2)?;
                Element::Timer(block("timer", num, sizes.timers, "numTimers")?)
            }
            11 => {
                fits("monostable", "2 columns and 2 rows", 2, 2)?;
                Element::Monostable(block(
                    "monostable",
                    num,
                    sizes.monostables,
                    "numMonostables",
                )?)
            }
            12 => {
                fits("counter", "2 columns and 4 rows", 2, 4)?;
                Element::Counter(block("counter", num, sizes.counters, "numCounters")?)
            }
            13 => {
                fits("IEC timer", "2 columns and 2 rows", 2, 2)?;
                Element::TimerIec(block("IEC timer", num, sizes.timers_iec, "numTimersIec")?)
            }
            20 => {
                fits("compare block", "3 columns", 3, 1)?;
                Element::Compare(block("expression", num, sizes.exprs, "numArithmExpr")?)
            }
            60 => {
                fits("operate block", "3 columns", 3, 1)?;
                Element::Operate(block("expression", num, sizes.exprs, "numArithmExpr")?)
            }
            _ => return Err(CellError::UnknownElement { code }),
        })
    }

    /// The project file's `(type, vartype, varnum)` of the element.
    pub fn codes(self) -> (u8, u16, u32) {
        match self {
            Element::Free => (0, 0, 0),
            Element::Unusable => (99, 0, 0),
            Element::Connection => (9, 0, 0),
            Element::Contact(k, v) => {
                let code = match k {
                    ContactKind::Open => 1,
                    ContactKind::Closed => 2,
                    ContactKind::Rising => 3,
                    ContactKind::Falling => 4,
                };
                (code, v.kind.code(), v.index)
            }
            Element::Coil(k, v) => {
                let code = match k {
                    CoilKind::Normal => 50,
                    CoilKind::Inverted => 51,
                    CoilKind::Set => 52,
                    CoilKind::Reset => 53,
                };
                (code, v.kind.code(), v.index)
            }
            Element::Jump(n) => (54, 0, n),
            Element::Call(n) => (55, 0, n),
            Element::Timer(n) => (10, 0, n),
            Element::Monostable(n) => (11, 0, n),
            Element::Counter(n) => (12, 0, n),
            Element::TimerIec(n) => (13, 0, n),
            Element::Compare(n) => (20, 0, n),
            Element::Operate(n) => (60, 0, n),
        }
    }
}

/// One cell: its element and whether a vertical wire joins it (on its
/// left edge) to the cell above.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cell {
    /// The element.
    pub element: Element,
    /// The vertical wire to the row above.
    pub top: bool,
}

impl Cell {
    /// An empty cell.
    pub const FREE: Cell = Cell {
        element: Element::Free,
        top: false,
    };
}

/// One rung: 10 columns by 6 rows, stored column after column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rung {
    /// Whether the project defines it.
    pub used: bool,
    /// The rung that follows it in its section (-1: none).
    pub next: i32,
    /// The cells, index `x * RUNG_HEIGHT + y`.
    pub cells: [Cell; CELLS],
}

impl Rung {
    /// An unused, empty rung.
    pub const EMPTY: Rung = Rung {
        used: false,
        next: -1,
        cells: [Cell::FREE; CELLS],
    };

    /// The cell at column `x`, row `y`.
    pub fn at(&self, x: usize, y: usize) -> Cell {
        self.cells[x * RUNG_HEIGHT + y]
    }
}

/// How a section runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SectionRole {
    /// Not defined.
    Unused,
    /// A main section, run every scan in order.
    Main,
    /// Sub-routine N, run when a -(C)- coil calls it.
    SubRoutine(u32),
}

/// One section of ladder rungs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Section {
    /// What it is.
    pub role: SectionRole,
    /// Its first rung.
    pub first: u32,
    /// Its last rung.
    pub last: u32,
}

impl Section {
    /// An undefined section.
    pub const UNUSED: Section = Section {
        role: SectionRole::Unused,
        first: 0,
        last: 0,
    };
}

/// The preset of an old timer or a monostable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimerSetup {
    /// The time base in milliseconds (60000, 1000 or 100).
    pub base_ms: i32,
    /// The preset in base units.
    pub preset: i32,
}

impl TimerSetup {
    /// ClassicLadder's blank timer: one second base, preset 0.
    pub const DEFAULT: TimerSetup = TimerSetup {
        base_ms: 1000,
        preset: 0,
    };
}

/// The mode of an IEC timer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IecMode {
    /// TON: on after the input has been on for the preset.
    OnDelay,
    /// TOF: off after the input has been off for the preset.
    OffDelay,
    /// TP: a pulse of the preset's length on the input's rising edge.
    Pulse,
}

/// The setup of an IEC timer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IecSetup {
    /// The time base in milliseconds.
    pub base_ms: i32,
    /// The preset in base units.
    pub preset: i32,
    /// The mode.
    pub mode: IecMode,
}

impl IecSetup {
    /// ClassicLadder's blank IEC timer.
    pub const DEFAULT: IecSetup = IecSetup {
        base_ms: 1000,
        preset: 0,
        mode: IecMode::OnDelay,
    };
}

/// A time base id of a project file (0 minutes, 1 seconds, 2 100 ms) in
/// milliseconds.
pub fn base_ms(id: i64) -> Option<i32> {
    match id {
        0 => Some(60_000),
        1 => Some(1000),
        2 => Some(100),
        _ => None,
    }
}

/// A whole program, sized by [`Sizes`]: every vector has exactly the
/// length its size says, so decoding into it never allocates.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// The rungs, by number.
    pub rungs: Vec<Rung>,
    /// The sections, by number.
    pub sections: Vec<Section>,
    /// The arithmetic expressions, by number.
    pub exprs: Vec<Expr>,
    /// The old timers.
    pub timers: Vec<TimerSetup>,
    /// The monostables.
    pub monostables: Vec<TimerSetup>,
    /// The counters' presets.
    pub counters: Vec<i32>,
    /// The IEC timers.
    pub timers_iec: Vec<IecSetup>,
}

impl Program {
    /// An empty program for a module of `sizes` (allocates).
    pub fn empty(sizes: &Sizes) -> Program {
        Program {
            rungs: vec![Rung::EMPTY; sizes.rungs],
            sections: vec![Section::UNUSED; sizes.sections],
            exprs: vec![Expr::EMPTY; sizes.exprs],
            timers: vec![TimerSetup::DEFAULT; sizes.timers],
            monostables: vec![TimerSetup::DEFAULT; sizes.monostables],
            counters: vec![0; sizes.counters],
            timers_iec: vec![IecSetup::DEFAULT; sizes.timers_iec],
        }
    }
}
