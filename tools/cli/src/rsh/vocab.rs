//! The words linuxcncrsh understands: one table, from which the parser
//! and `help` both come.

/// What a subcommand of `get` and `set` is.
/// (The variants are the subcommands of the table below, by name.)
#[allow(missing_docs)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sub {
    Echo,
    Verbose,
    Enable,
    Config,
    CommMode,
    CommProt,
    Inifile,
    Plat,
    Ini,
    Debug,
    SetWait,
    Wait,
    SetTimeout,
    Timeout,
    Update,
    Error,
    OperatorDisplay,
    OperatorText,
    Time,
    Estop,
    Machine,
    Mode,
    Mist,
    Flood,
    Lube,
    LubeLevel,
    Spindle,
    Brake,
    Tool,
    ToolOffset,
    LoadToolTable,
    Home,
    JogStop,
    Jog,
    JogIncr,
    FeedOverride,
    SpindleOverride,
    AbsCmdPos,
    AbsActPos,
    RelCmdPos,
    RelActPos,
    JointPos,
    PosOffset,
    JointLimit,
    JointFault,
    JointHomed,
    Mdi,
    TaskPlanInit,
    Open,
    Run,
    Pause,
    Resume,
    Abort,
    Step,
    Program,
    ProgramLine,
    ProgramStatus,
    ProgramCodes,
    JointType,
    JointUnits,
    ProgramUnits,
    ProgramLinearUnits,
    ProgramAngularUnits,
    UserLinearUnits,
    UserAngularUnits,
    DisplayLinearUnits,
    DisplayAngularUnits,
    LinearUnitConversion,
    AngularUnitConversion,
    ProbeClear,
    ProbeTripped,
    ProbeValue,
    Probe,
    TeleopEnable,
    KinematicsType,
    OverrideLimits,
    OptionalStop,
}

/// One subcommand: its name (matched without regard to case) and the
/// parameters `help` shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Entry {
    /// The name as LinuxCNC's help spells it.
    pub name: &'static str,
    /// Which subcommand it is.
    pub sub: Sub,
    /// Its parameters, for `help`.
    pub params: &'static str,
}

const fn e(name: &'static str, sub: Sub, params: &'static str) -> Entry {
    Entry { name, sub, params }
}

/// Every subcommand of `get` and `set`, in the order `help` lists them.
pub const SUBCOMMANDS: &[Entry] = &[
    e("Abort", Sub::Abort, ""),
    e("Abs_act_pos", Sub::AbsActPos, "[<joint>]"),
    e("Abs_cmd_pos", Sub::AbsCmdPos, "[<joint>]"),
    e(
        "Angular_unit_conversion",
        Sub::AngularUnitConversion,
        "{Deg|Rad|Grad|Auto}",
    ),
    e("Brake", Sub::Brake, "{On|Off} [<spindle>]"),
    e("Comm_mode", Sub::CommMode, "{ASCII|Binary}"),
    e("Comm_prot", Sub::CommProt, "<version>"),
    e("Config", Sub::Config, ""),
    e("Debug", Sub::Debug, "<value>"),
    e("Display_angular_units", Sub::DisplayAngularUnits, ""),
    e("Display_linear_units", Sub::DisplayLinearUnits, ""),
    e("Echo", Sub::Echo, "{On|Off}"),
    e("Enable", Sub::Enable, "{<password>|Off}"),
    e("Error", Sub::Error, ""),
    e("Estop", Sub::Estop, "{On|Off}"),
    e("Feed_override", Sub::FeedOverride, "<percent>"),
    e("Flood", Sub::Flood, "{On|Off}"),
    e("Home", Sub::Home, "{<joint>|-1}"),
    e("Ini", Sub::Ini, "<var> <section>"),
    e("Inifile", Sub::Inifile, ""),
    e("Jog", Sub::Jog, "<joint|axis> <speed>"),
    e("Jog_incr", Sub::JogIncr, "<joint|axis> <speed> <increment>"),
    e("Jog_stop", Sub::JogStop, "<joint|axis>"),
    e("Joint_fault", Sub::JointFault, "[<joint>]"),
    e("Joint_homed", Sub::JointHomed, "[<joint>]"),
    e("Joint_limit", Sub::JointLimit, "[<joint>]"),
    e("Joint_pos", Sub::JointPos, "[<joint>]"),
    e("Joint_type", Sub::JointType, "[<joint>]"),
    e("Joint_units", Sub::JointUnits, "[<joint>]"),
    e("Kinematics_type", Sub::KinematicsType, ""),
    e(
        "Linear_unit_conversion",
        Sub::LinearUnitConversion,
        "{Inch|MM|CM|Auto}",
    ),
    e("Load_tool_table", Sub::LoadToolTable, "<file>"),
    e("Lube", Sub::Lube, "{On|Off}"),
    e("Lube_level", Sub::LubeLevel, ""),
    e("Machine", Sub::Machine, "{On|Off}"),
    e("MDI", Sub::Mdi, "<g-code>"),
    e("Mist", Sub::Mist, "{On|Off}"),
    e("Mode", Sub::Mode, "{Manual|Auto|MDI}"),
    e("Open", Sub::Open, "<file>"),
    e("Operator_display", Sub::OperatorDisplay, ""),
    e("Operator_text", Sub::OperatorText, ""),
    e("Optional_stop", Sub::OptionalStop, "{0|1}"),
    e("Override_limits", Sub::OverrideLimits, "{On|Off}"),
    e("Pause", Sub::Pause, ""),
    e("Plat", Sub::Plat, ""),
    e("Pos_offset", Sub::PosOffset, "[{X|Y|Z|A|B|C}]"),
    e("Probe", Sub::Probe, "<x> <y> <z>"),
    e("Probe_clear", Sub::ProbeClear, ""),
    e("Probe_tripped", Sub::ProbeTripped, ""),
    e("Probe_value", Sub::ProbeValue, ""),
    e("Program", Sub::Program, ""),
    e("Program_angular_units", Sub::ProgramAngularUnits, ""),
    e("Program_codes", Sub::ProgramCodes, ""),
    e("Program_line", Sub::ProgramLine, ""),
    e("Program_linear_units", Sub::ProgramLinearUnits, ""),
    e("Program_status", Sub::ProgramStatus, ""),
    e("Program_units", Sub::ProgramUnits, ""),
    e("Rel_act_pos", Sub::RelActPos, "[<joint>]"),
    e("Rel_cmd_pos", Sub::RelCmdPos, "[<joint>]"),
    e("Resume", Sub::Resume, ""),
    e("Run", Sub::Run, "[<start line>]"),
    e("Set_timeout", Sub::SetTimeout, "<seconds>"),
    e("Set_wait", Sub::SetWait, "{Received|Done}"),
    e(
        "Spindle",
        Sub::Spindle,
        "{Forward|Reverse|Increase|Decrease|Constant|Off} [<spindle>]",
    ),
    e("Spindle_override", Sub::SpindleOverride, "<percent>"),
    e("Step", Sub::Step, ""),
    e("Task_plan_init", Sub::TaskPlanInit, ""),
    e("Teleop_enable", Sub::TeleopEnable, "{On|Off}"),
    e("Time", Sub::Time, ""),
    e("Timeout", Sub::Timeout, "<seconds>"),
    e("Tool", Sub::Tool, ""),
    e(
        "Tool_offset",
        Sub::ToolOffset,
        "[<tool> <length> <diameter>]",
    ),
    e("Update", Sub::Update, "{None|Auto}"),
    e("User_angular_units", Sub::UserAngularUnits, ""),
    e("User_linear_units", Sub::UserLinearUnits, ""),
    e("Verbose", Sub::Verbose, "{On|Off}"),
    e("Wait", Sub::Wait, "{Received|Done}"),
];

/// The subcommand named `word` (any case).
pub fn lookup(word: &str) -> Option<&'static Entry> {
    SUBCOMMANDS
        .iter()
        .find(|e| e.name.eq_ignore_ascii_case(word))
}

/// The top-level commands, for `help` with no argument.
pub const COMMANDS: &[(&str, &str)] = &[
    ("Hello", "<password> <client name> <protocol version>"),
    ("Get", "<emc command>"),
    ("Set", "<emc command>"),
    ("Shutdown", ""),
    ("Help", "<command>"),
];

/// The lines `help` answers for `topic` (none: the command list).
pub fn help(topic: Option<&str>) -> Vec<String> {
    let line = |name: &str, params: &str| {
        if params.is_empty() {
            name.to_string()
        } else {
            format!("{name} {params}")
        }
    };
    let Some(topic) = topic else {
        let mut out = vec!["Available commands:".to_string()];
        out.extend(COMMANDS.iter().map(|(n, p)| format!("  {}", line(n, p))));
        return out;
    };
    let upper = topic.to_ascii_lowercase();
    match upper.as_str() {
        "get" | "set" => {
            let verb = if upper == "get" { "Get" } else { "Set" };
            let mut out = vec![
                format!("Usage: {verb} <emc command>"),
                format!("  {verb} commands require that a hello has been successfully negotiated."),
                "  Emc command may be one of:".to_string(),
            ];
            out.extend(
                SUBCOMMANDS
                    .iter()
                    .map(|e| format!("    {}", line(e.name, e.params))),
            );
            out
        }
        "hello" => vec![
            "Usage: Hello <password> <client name> <protocol version>".to_string(),
            "  The three words may not contain blanks.".to_string(),
        ],
        "shutdown" => vec![
            "Usage: Shutdown".to_string(),
            "  Ends linuxcncrsh and with it the machine; needs a hello and set enable.".to_string(),
        ],
        "help" => vec!["Usage: Help [<command>]".to_string()],
        "quit" => vec![
            "Usage: Quit".to_string(),
            "  Closes this connection.".to_string(),
        ],
        _ => match lookup(topic) {
            Some(e) => vec![format!("Usage: Get|Set {}", line(e.name, e.params))],
            None => vec![format!("{topic} is not a valid command.")],
        },
    }
}
