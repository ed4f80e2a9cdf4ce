//! The interpreter's one error type. The text of each variant is the text
//! LinuxCNC's interpreter gives for the same refusal (rs274 prints it),
//! so a program refused by LinuxCNC is refused here with the same words.

use std::io;
use std::path::PathBuf;

/// Every refusal and failure of the interpreter.
#[derive(Debug, thiserror::Error)]
#[allow(missing_docs)] // each variant is documented by its message
pub enum InterpError {
    // ---- reading a line -------------------------------------------------
    #[error("Command too long")]
    CommandTooLong,
    #[error("Nested comment found")]
    NestedComment,
    #[error("Unclosed comment found")]
    UnclosedComment,
    #[error("Bad character '\\{0:03o}' used")]
    BadCharacterCode(u8),
    #[error("Bad character '{0}' used")]
    BadCharacter(char),
    #[error("Multiple {0} words on one line")]
    MultipleWords(char),
    #[error("Multiple U words on one line")]
    MultipleU,
    #[error("Multiple V words on one line")]
    MultipleV,
    #[error("Multiple W words on one line")]
    MultipleW,
    #[error("Multiple spindle choice ($) words on one line")]
    MultipleDollar,
    #[error("Negative f word used")]
    NegativeF,
    #[error("Negative spindle speed used")]
    NegativeS,
    #[error("Negative h word used")]
    NegativeH,
    #[error("Negative l word used")]
    NegativeL,
    #[error("Negative tool id (tool not found)")]
    NegativeTool,
    #[error("Negative g code used")]
    NegativeG,
    #[error("Negative m code used")]
    NegativeM,
    #[error("G-code out of range")]
    GCodeOutOfRange,
    #[error("Unknown g code used")]
    UnknownG,
    #[error("M-code greater than 199: M{0}")]
    MCodeTooBig(i32),
    #[error("Unknown m code used: M{0}")]
    UnknownM(i32),
    #[error("Two g codes used from same modal group")]
    TwoGCodesSameGroup,
    #[error("Two m codes used from same modal group")]
    TwoMCodesSameGroup,
    #[error("Too many m codes on line")]
    TooManyMCodes,
    #[error("Non integer value for integer")]
    NonInteger,
    #[error("Bad format unsigned integer")]
    BadUnsignedInteger,
    #[error("No characters found in reading real value")]
    NoCharactersForValue,
    #[error("bad number format (conversion failed) parsing '{0}'")]
    BadNumber(String),
    #[error("bad number format (trailing characters) parsing '{0}'")]
    BadNumberTrailing(String),
    #[error("Calculation resulted in 'not a number'")]
    NotANumber,
    #[error("Calculation resulted in 'infinity'")]
    Infinity,
    #[error("Unclosed expression")]
    UnclosedExpression,
    #[error("Unknown operation")]
    UnknownOperation,
    #[error("Unknown operation name starting with {0}")]
    UnknownOperationName(char),
    #[error("Unknown word starting with {0}")]
    UnknownWord(char),
    #[error("Unknown word where unary operation could be")]
    UnknownUnary,
    #[error("Left bracket missing after unary operation name")]
    LeftBracketMissingAfterUnary,
    #[error("Slash missing after first atan argument")]
    SlashMissingAfterAtan,
    #[error("Left bracket missing after slash with atan")]
    LeftBracketMissingAfterAtanSlash,
    #[error("Attempt to divide by zero")]
    DivideByZero,
    #[error("Attempt to raise negative to non integer power")]
    NegativeToNonIntegerPower,
    #[error("Argument to acos out of range")]
    AcosRange,
    #[error("Argument to asin out of range")]
    AsinRange,
    #[error("Negative argument to sqrt")]
    NegativeSqrt,
    #[error("Zero or negative argument to ln")]
    LnRange,
    #[error("Parameter number out of range")]
    ParameterOutOfRange,
    #[error("Parameter is readonly")]
    ParameterReadonly,
    #[error("Equal sign missing in parameter setting")]
    EqualSignMissing,
    #[error("Expected # reading parameter")]
    ExpectedHash,
    #[error("Expected ] reading bracketed parameter")]
    ExpectedRightBracket,
    #[error("Named parameter not terminated")]
    NamedParameterNotTerminated,
    #[error("Named parameter #<{0}> not defined")]
    NamedParameterUndefined(String),
    #[error("Cannot assign to read-only parameter #<{0}>")]
    NamedParameterReadonly(String),
    #[error("Cannot read current position with cutter radius compensation on")]
    PositionWithComp,
    #[error("File ended with no percent sign")]
    NoPercentAtEnd,
    #[error("File ended with no percent sign or program end")]
    NoPercentOrEnd,

    // ---- block checks ---------------------------------------------------
    #[error("Cannot use axis values with g80")]
    AxisWithG80,
    #[error("All axes missing with g52 or g92")]
    AxesMissingG52G92,
    #[error("Cannot use two g codes that both use axis values")]
    TwoAxisGCodes,
    #[error("All axes missing with motion code")]
    AxesMissingMotion,
    #[error("Cannot use axis values without a g code that uses them")]
    AxisWithoutGCode,
    #[error("Polar coordinates can only be used for motion")]
    PolarOnlyMotion,
    #[error("Cannot use polar coordinate except in G17 plane")]
    PolarNotG17,
    #[error("Cannot specify both polar coordinate and X word")]
    PolarAndX,
    #[error("Cannot specify both polar coordinate and Y word")]
    PolarAndY,
    #[error("Dwell time missing with g4")]
    DwellMissing,
    #[error("G4 not allowed with G2 or G3 because they both use P")]
    G4WithArc,
    #[error("Must use g0 or g1 with g53")]
    G53NeedsG0G1,
    #[error("Cannot use g53 incremental")]
    G53Incremental,
    #[error("Line with G10 does not have L0, L1, L10, L11, L2, or L20")]
    G10BadL,
    #[error("P value not an integer with G10")]
    G10PNotInteger,
    #[error("P value out of range (0-9) with G10 L{0}")]
    G10PRangeCoord(i32),
    #[error("P value out of range with G10 L{0}")]
    G10PRangeTool(i32),
    #[error("Between G5.2 and G5.3 codes, only additional G5.2 codes are allowed.")]
    NurbsInterrupted,
    #[error("Cannot put an a in canned cycle")]
    AInCycle,
    #[error("Cannot put a b in canned cycle")]
    BInCycle,
    #[error("Cannot put a c in canned cycle")]
    CInCycle,
    #[error("D word with no G41, G41.1, G42, G42.1, G71, G71.1, G71.2 or G96 to use it")]
    DWordUnused,
    #[error("$ (spindle selection) word with no M3, M4, M5, M19, M51, G33, G33.1, G76, G95, G96 or G97 to use it")]
    DollarUnused,
    #[error("E word with no G70, G76, M66, M67 or M68 to use it")]
    EWordUnused,
    #[error("H word with no G43 or G76 to use it")]
    HWordUnused,
    #[error("I word with no G2, G3, G5, G5.1, G10, G33.1, G76, or G87 to use it")]
    IWordUnused,
    #[error("J word with no G2, G3, G5, G5.1, G10, G76 or G87 to use it")]
    JWordUnused,
    #[error("K word with no G2, G3, G33, G33.1, G76, or G87 to use it")]
    KWordUnused,
    #[error("L word with no G10, cutter compensation, canned cycle, digital/analog input, M98 or NURBS code")]
    LWordUnused,
    #[error("P word with no G2 G3 G4 G10 G64 G5 G5.2 G76 G82 G86 G88 G89 or M50 M51 M52 M53 M62 M63 M64 M65 M66 M98 or user M code to use it")]
    PWordUnused,
    #[error("P value not an integer with M19 G2 or G3")]
    PNotIntegerArc,
    #[error("P value must be 0,1,or 2 with M19")]
    M19PRange,
    #[error("P value should be 1 or greater with G2 or G3")]
    ArcPTooSmall,
    #[error("Q word with no G5, G10, G64, G73, G76, G83, M19, M66, M67, M68 or user M code that uses it")]
    QWordUnused,
    #[error("R word with no g code that uses it")]
    RWordUnused,
    #[error("R value must be within 0..360 with M19")]
    M19RRange,
    #[error("S word missing with G96")]
    SMissingG96,
    #[error("K word missing with g33/g33.1")]
    KMissingG33,
    #[error("F word used with a g33/g33.1")]
    FWithG33,
    #[error("P word missing with G76")]
    PMissingG76,
    #[error("I J or K words missing with G76")]
    IjkMissingG76,

    // ---- execution ------------------------------------------------------
    #[error("{0}")]
    Unsupported(&'static str),
    #[error("Cannot do g1 with zero feed rate")]
    G1ZeroFeed,
    #[error("F word missing with inverse time g1 move")]
    FMissingInverseG1,
    #[error("Cannot feed with zero spindle speed in feed per rev mode")]
    ZeroSpeedFeedPerRev,
    #[error("Cannot use g53 with cutter radius comp")]
    G53WithComp,
    #[error("Cannot make arc with zero feed rate")]
    ArcZeroFeed,
    #[error("F word missing with inverse time arc move")]
    FMissingInverseArc,
    #[error("R i j k words all missing for arc")]
    ArcNoRijk,
    #[error("Mixed radius ijk format for arc")]
    ArcMixedFormat,
    #[error("K word given for arc in xy plane")]
    ArcKInXy,
    #[error("I word given for arc in yz plane")]
    ArcIInYz,
    #[error("J word given for arc in xz plane")]
    ArcJInXz,
    #[error("{0} word missing in absolute center arc")]
    ArcAbsoluteCenterMissing(char),
    #[error("X and y words missing for arc in xy plane")]
    ArcXyMissing,
    #[error("Y and z words missing for arc in yz plane")]
    ArcYzMissing,
    #[error("X and z words missing for arc in xz plane")]
    ArcXzMissing,
    #[error("Cannot do an arc in planes G17.1, G18.1, or G19.1")]
    ArcInUvwPlane,
    #[error("The move just after exiting cutter compensation mode must be straight, not an arc")]
    ArcAfterCompOff,
    #[error("Current point same as end point of arc")]
    ArcSameEnds,
    #[error("Arc radius too small to reach end point")]
    ArcRadiusTooSmall,
    #[error("Zero-radius arc: start=({a}{sx:.4},{b}{sy:.4}) center=({a}{cx:.4},{b}{cy:.4}) end=({a}{ex:.4},{b}{ey:.4}) r1={r1:.4} r2={r2:.4}")]
    ArcZeroRadius {
        a: char,
        b: char,
        sx: f64,
        sy: f64,
        cx: f64,
        cy: f64,
        ex: f64,
        ey: f64,
        r1: f64,
        r2: f64,
    },
    /// The text is formatted with C's `%.4g` for the absolute error,
    /// which Rust has no format for, so it is kept ready-made.
    #[error("{0}")]
    ArcRadiusMismatch(String),
    #[error("Tool radius not less than arc radius with comp")]
    ToolRadiusNotLessThanArc,
    #[error("Radius of cutter compensation entry arc is not greater than the tool radius")]
    CompEntryArcTooSmall,
    #[error("Length of cutter compensation entry move is not greater than the tool radius")]
    CompEntryTooShort,
    #[error("Arc move in concave corner cannot be reached by the tool without gouging")]
    CompArcConcave,
    #[error("Arc to arc motion is invalid because the arcs have the same center")]
    CompArcSameCenter,
    #[error("Arc to arc motion makes a corner the compensated tool can't fit in without gouging")]
    CompArcArcGouge,
    #[error(
        "Arc to straight motion makes a corner the compensated tool can't fit in without gouging"
    )]
    CompArcLineGouge,
    #[error("Straight traverse in concave corner cannot be reached by the tool without gouging")]
    CompTraverseConcave,
    #[error("Straight feed in concave corner cannot be reached by the tool without gouging")]
    CompFeedConcave,
    #[error("Zero degree inside corner is invalid for cutter compensation")]
    CompZeroCorner,
    #[error("Bug in tool radius comp")]
    CompBug,
    #[error("Cutter radius compensation allowed only in XY, XZ planes")]
    CompPlane,
    #[error("Cannot turn cutter radius comp on when on")]
    CompAlreadyOn,
    #[error("G{0}.1 with L word, but plane is not G18")]
    CompLathePlaneL(i32),
    #[error("G{0} requires D word to be a whole number")]
    CompDNotWhole(i32),
    #[error("Negative d word tool radius index used")]
    CompNegativeD,
    #[error("G{0} with lathe tool, but plane is not G18")]
    CompLathePlane(i32),
    #[error("G{0}.1 with no D word")]
    CompNoD(i32),
    #[error("Cannot change planes with cutter radius compensation on")]
    PlaneWithComp,
    #[error("Cannot change axis offsets with cutter radius comp")]
    AxisOffsetsWithComp,
    #[error("Cannot change control mode with cutter radius compensation on")]
    ControlModeWithComp,
    #[error("Cannot change coordinate systems with cutter radius compensation on")]
    CoordSystemWithComp,
    #[error("Cannot change the active coordinate system with cutter radius compensation on")]
    ActiveCoordSystemWithComp,
    #[error("Cannot change retract mode with cutter radius compensation on")]
    RetractWithComp,
    #[error("Cannot set reference point with cutter compensation in effect")]
    SaveHomeWithComp,
    #[error("Cannot use g28 or g30 with cutter radius comp")]
    HomeWithComp,
    #[error("Cannot change units with cutter radius comp")]
    UnitsWithComp,
    #[error("Cannot probe with cutter radius comp on")]
    ProbeWithComp,
    #[error("Cannot probe with zero feed rate")]
    ProbeZeroFeed,
    #[error("Cannot probe with feed per rev mode")]
    ProbeFeedPerRev,
    #[error("Start point too close to probe point")]
    ProbeTooClose,
    #[error("I J words not allowed with G10 L2")]
    G10L2Ij,
    #[error("R not allowed in G10 L20")]
    G10L20R,
    #[error("G10 L1 without offsets has no effect")]
    G10L1NoOffsets,
    #[error("Q number in G10 is not an integer")]
    G10QNotInteger,
    #[error("Invalid tool orientation")]
    InvalidOrientation,
    #[error("Requested tool {0} not found in the tool table")]
    ToolNotFound(i32),
    #[error("Need tool prepared -Txx- for toolchange")]
    NoToolPrepared,
    #[error("Cannot change tools with cutter radius compensation on")]
    ToolChangeWithComp,
    #[error("Cannot change tool offset with cutter radius compensation on")]
    ToolOffsetWithComp,
    #[error("G43.2: Can not have both H and axis words")]
    G432HAndAxes,
    #[error("G43.2: No axes specified and H word missing")]
    G432Nothing,
    #[error("Need non-negative Q-word to specify tool number with M61")]
    M61Q,
    #[error("Cannot use G5.3 without G5.2 first")]
    NurbsEndWithoutStart,
    #[error("You must specify a number of control points at least equal to the order L = {0}")]
    NurbsTooFewPoints(u32),
    #[error("You must specify both X and Y coordinates for Control Points")]
    NurbsXy,
    #[error("Can specify P without X and Y only for the first control point")]
    NurbsPOnlyFirst,
    #[error("Must specify positive weight P for every Control Point")]
    NurbsWeight,
    #[error("Cannot make a NURBS with 0 feedrate")]
    NurbsZeroFeed,
    #[error("Cannot convert spline with cutter radius compensation")]
    SplineWithComp,
    #[error("Splines must be in the XY plane")]
    SplinePlane,
    #[error("Splines may not have motion in Z, A, B, or C")]
    SplineAxes,
    #[error("Must specify both I and J with G5.1")]
    SplineIjG51,
    #[error("Must specify both I and J, or neither")]
    SplineIj,
    #[error("Must specify both P and Q with G5")]
    SplinePq,
    #[error("G7x.x  requires a Q word")]
    G7xNeedsQ,
    #[error("G{0}.{1} cannot be used with cutter compensation enabled")]
    G7xWithComp(i32, i32),
    #[error("G{0}.{1} can only be used in XZ plane (G18)")]
    G7xPlane(i32, i32),
    #[error("G7x error: Cannot use U in incremental mode (G91)")]
    G7xUIncremental,
    #[error("G7x error: Cannot use U and X in the same block")]
    G7xUAndX,
    #[error("G7x error: Cannot use W in incremental mode (G91)")]
    G7xWIncremental,
    #[error("G7x error: Cannot use W and Z in the same block")]
    G7xWAndZ,
    #[error("G7X error: both R and I or K flag used for arc")]
    G7xArcRAndIk,
    #[error("G7X error: either I or K must be present for arc")]
    G7xArcNoIk,
    #[error("G7X error: Both A and C parameters on a corner")]
    G7xFilletAndChamfer,
    #[error("G7X error: I must be greater than zero.")]
    G7xIncrement,
    #[error("G7X error: Not monotonic")]
    G7xNotMonotonic,
    #[error("G7X error: Cannot intersect parallel lines")]
    G7xParallelLines,
    #[error("G7X error: How did we get here?")]
    G7xLostPath,
    #[error("G7X error: x too large in straight dive")]
    G7xXTooLarge,
    #[error("G7X error: Corner finish failed at {0}")]
    G7xCornerFinish(String),
    #[error("G7X error: the profile vanished when offset by the finishing allowance")]
    G7xProfileVanished,
    #[error("G7X error: offsetting the profile took more than {0} steps")]
    G7xOffsetSteps(usize),
    #[error(
        "G7X error: the cycle would make more than {limit} moves or passes \
         (a cutting increment I too small, too many G70 passes P, \
         or a profile whose passes never end)"
    )]
    G7xTooManyPasses { limit: u32 },
    #[error("G7X error: the profile subroutine read more than {0} blocks without returning")]
    G7xProfileTooLong(usize),
    #[error("G7X error: the profile has more than {0} segments")]
    G7xTooManySegments(usize),
    #[error("Cannot set motion output with cutter radius compensation on")]
    M62WithComp,
    #[error("Cannot set motion digital output with cutter radius compensation on")]
    M63WithComp,
    #[error("Cannot set auxiliary digital output with cutter radius compensation on")]
    M64WithComp,
    #[error("No valid P word with M{0}")]
    NoPWithM(i32),
    #[error("Invalid to select both a digital and an analog input with M66")]
    M66BothInputs,
    #[error("Zero timeout with wait type != immediate return")]
    M66ZeroTimeout,
    #[error("Can't select analog input with wait type != immediate return")]
    M66AnalogWait,
    #[error("Need to have either a valid P or a valid E word with M66")]
    M66NoInput,
    #[error("Cannot wait for digital input with cutter radius compensation on")]
    M66DigitalWithComp,
    #[error("Cannot wait for analog input with cutter radius compensation on")]
    M66AnalogWithComp,
    #[error("Digital input selected out of bounds")]
    M66DigitalRange,
    #[error("Analog input selected out of bounds")]
    M66AnalogRange,
    #[error("Cannot set motion analog output with cutter radius compensation on")]
    M67WithComp,
    #[error("Cannot set auxiliary analog output with cutter radius compensation on")]
    M68WithComp,
    #[error("Invalid analog index with M{0}")]
    AnalogIndex(i32),
    #[error("Q word with M19 requires a value > 0")]
    M19Q,
    #[error(
        "Spindle ($) number out of range in M{m} Command\nnum_spindles ={count}. $={dollar}\n"
    )]
    SpindleOutOfRange { m: i32, count: usize, dollar: i32 },
    #[error("Spindle ($) number out of range in M19 Command")]
    M19SpindleOutOfRange,
    #[error("Invalid spindle ($) number in {0}")]
    SpindleNumber(&'static str),
    #[error("Spindle not turning in {0}")]
    SpindleNotTurning(&'static str),
    #[error("Chosen spindle ({0}) not turning in G76")]
    G76SpindleNotTurning(i32),
    #[error("Invalid D-number in G76 cycle")]
    G76SpindleNumber,
    #[error("Cannot use G76 threading cycle with cutter radius compensation on")]
    G76WithComp,
    #[error("Cannot move rotary axes with G76")]
    G76Rotary,
    #[error("In G76, I must not be 0")]
    G76IZero,
    #[error("In G76, J must be greater than 0")]
    G76JNotPositive,
    #[error("In G76, K must be greater than J")]
    G76KNotAboveJ,
    #[error("G10 L0 not allowed with loaded tool <{0}>\n")]
    G10L0ToolLoaded(i32),
    #[error("Bug code not g0 or g1")]
    CompMoveNotG0G1,
    #[error("Cannot restore context from invalid stack frame - missing M70/M73?")]
    M72NoContext,
    #[error("Cannot enable overrides with cutter radius compensation on")]
    EnableOverridesWithComp,
    #[error("Cannot disable overrides with cutter radius compensation on")]
    DisableOverridesWithComp,
    #[error("M7x: restore_settings failed executing: '{0}': {1}")]
    RestoreFailed(String, String),

    // ---- canned cycles --------------------------------------------------
    #[error("Cannot feed with zero feed rate")]
    CycleZeroFeed,
    #[error("Cannot use inverse time feed with canned cycles")]
    CycleInverseTime,
    #[error("Cannot use canned cycles with cutter compensation on")]
    CycleWithComp,
    #[error("R clearance plane unspecified in cycle")]
    CycleNoR,
    #[error("Cannot do zero repeats of cycle")]
    CycleZeroRepeats,
    #[error("{0} value unspecified in {1} plane canned cycle")]
    CycleAxisUnspecified(char, &'static str),
    #[error("R less than {0} in cycle in {1} plane")]
    CycleRBelow(&'static str, &'static str),
    #[error("Cannot put {0} in a canned cycle in the {1} plane")]
    CycleAxisInPlane(&'static str, &'static str),
    #[error("Incremental motion with polar coordinates is indeterminate when at the origin")]
    PolarIncrementalAtOrigin,
    #[error("Dwell time p word missing with g{0}")]
    CycleDwellMissing(i32),
    #[error(
        "G{code} would make about {moves:.0} moves in one block, more than the {limit} allowed \
         (check its L repeats and Q peck depth)"
    )]
    CycleTooLong { code: i32, moves: f64, limit: u32 },
    #[error(
        "G76 would make more than {limit} moves \
         (check its J, K, R and H words)"
    )]
    ThreadTooLong { limit: u32 },
    #[error("Negative or zero q value used")]
    CycleQNotPositive,
    #[error("Q word missing with g{0}")]
    CycleQMissing(i32),
    #[error("{0} word missing with g87")]
    G87WordMissing(char),
    #[error("Spindle not turning in g{0}")]
    CycleSpindleNotTurning(i32),
    #[error("Spindle not turning in G{0}")]
    TapSpindleNotTurning(i32),
    #[error("Spindle turning clockwise in G74")]
    G74Clockwise,
    #[error("Spindle turning counterclockwise in G84")]
    G84CounterClockwise,

    // ---- parameters, O-words, files -------------------------------------
    #[error("Parameter file out of order")]
    ParameterFileOrder,
    #[error("Unable to open parameter file: '{0}'")]
    ParameterFileOpen(String),
    #[error("Cannot open variable file")]
    VariableFileOpen,
    #[error("Coordinate system index parameter 5220 out of range")]
    CoordIndexRange,
    #[error("Unable to open file <{0}>")]
    UnableToOpenFile(String),
    #[error("Unable to open file: {0}")]
    UnableToOpen(String),
    #[error("File not open")]
    FileNotOpen,
    #[error("A file is already open")]
    FileAlreadyOpen,
    #[error("File name too long")]
    FileNameTooLong,
    #[error("cannot reopen file {0} - removed or renamed? ({1})")]
    CannotReopen(String, String),
    #[error("Too many subroutine levels")]
    TooManySubLevels,
    #[error("Too many subroutine parameters")]
    TooManySubParams,
    #[error("Nested subroutine definition")]
    NestedSubDefinition,
    #[error("Not in subroutine definition")]
    NotInSubDefinition,
    #[error("Unknown control command in o word")]
    UnknownOControl,
    #[error("Unexpected character after O-word")]
    UnexpectedAfterO,
    #[error("Left bracket missing after '{0}'")]
    LeftBracketMissingAfter(&'static str),
    #[error("Unknown oword number")]
    UnknownOwordNumber,
    #[error("{0}: not in a subroutine definition: '{1}'")]
    StandaloneReturn(i32, String),
    #[error("{0}: undefined O-word label: '{1}'")]
    UndefinedOLabel(i32, String),
    #[error("{0}: no matching 'if' label: '{1}' (found '{2}' in line {3})")]
    NoMatchingIf(i32, String, &'static str, i32),
    #[error("{0}: no matching label: '{1}' (found '{2}' in line {3}): '{4}'")]
    NoMatchingEndif(i32, String, &'static str, i32, String),
    #[error("{0}: no matching while/do label: '{1}' (found '{2}' in line {3})")]
    NoMatchingWhile(i32, String, &'static str, i32),
    #[error("{0}: no matching label: '{1}' (found '{2}' in line {3})")]
    NoMatchingLoop(i32, String, &'static str, i32),
    #[error("{0}: duplicate O-word label: '{1}' - defined in line {2}")]
    DuplicateLoopLabel(i32, String, i32),
    #[error("{0}: duplicate O-word label - already defined in line {1}: '{2}'")]
    DuplicateIfLabel(i32, i32, String),
    #[error("File:{0} line:{1} sub: o|{2}| found in illegal location")]
    SubIllegalLocation(String, i32, String),
    #[error("File:{0} line:{1} redefining sub: o|{2}| already defined in file:{3}")]
    SubRedefined(String, i32, String, String),
    #[error("the program has not ended after {0} blocks (an endless loop?)")]
    DoesNotEnd(usize),
    #[error("Failed to find sub 'O{0}' before EOF")]
    SubNotFoundBeforeEof(String),
    #[error("EOF in file:{0} seeking o-word: o<{1}> from line: {2}")]
    EofSeekingSub(String, String, i32),
    #[error("Fanuc 'O....' subroutine must be called with 'M98'")]
    FanucSubNeedsM98,
    #[error("'O.... sub' subroutine must be called with 'O.... call'")]
    SubNeedsCall,
    #[error("Fanuc 'O....' subroutine definition must end with 'M99'")]
    FanucSubNeedsM99,
    #[error("'O.... endsub' or 'O.... return' must follow 'O.... sub' subroutine definition")]
    SubNeedsEndsub,
    #[error("Found 'm98' code with no P-word")]
    M98NoP,
    #[error("Found 'M99' instead of 'O endsub' after 'O sub'")]
    M99InSub,
    #[error("M99 main program endless loop")]
    M99Endless,
    #[error("DISABLE_FANUC_STYLE_SUB set in INI file, but found m98")]
    FanucDisabledM98,
    #[error("DISABLE_FANUC_STYLE_SUB set in INI file, but found m99")]
    FanucDisabledM99,
    #[error("DISABLE_FANUC_STYLE_SUB disabled in INI file, but found bare O-word")]
    FanucDisabledO,
    #[error("Bug:  Reached convert_stop() from M99 as subprogram return")]
    M99Bug,
    /// A refusal raised by the program itself with `(ABORT, ...)`.
    #[error("{0}")]
    Abort(String),

    // ---- bounded input and outside files ---------------------------------
    /// A file the suite's reader of users' files refused (not a regular
    /// file, too large, unreadable part way).
    #[error(transparent)]
    File(hal_core::files::FileError),
    #[error("{path}: {size} bytes is more than the limit of {limit} bytes")]
    FileTooLarge {
        path: PathBuf,
        size: u64,
        limit: u64,
    },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("{path}:{line}: {what}")]
    BadFileLine {
        path: PathBuf,
        line: usize,
        what: String,
    },
}

/// A shorter name for results of the interpreter.
pub type Result<T, E = InterpError> = std::result::Result<T, E>;

impl InterpError {
    /// The refusal of the suite's file reader, as the interpreter
    /// reports it: a file that cannot be opened stays an [`InterpError::Io`]
    /// (LinuxCNC's "Unable to open file" comes from it).
    pub fn from_file(e: hal_core::files::FileError) -> Self {
        match e.problem {
            hal_core::files::FileProblem::Open(source) => InterpError::Io {
                path: e.path,
                source,
            },
            _ => InterpError::File(e),
        }
    }

    /// An I/O error on the named file.
    pub fn io(path: impl Into<PathBuf>, source: io::Error) -> Self {
        InterpError::Io {
            path: path.into(),
            source,
        }
    }
}
