//! What Tab completes in interactive halcmd: the command, then each
//! argument by what the command takes there (a pin, a signal, a function,
//! a thread, a module for `loadrt` and its parameters, ...), with names
//! read from the live instance at the moment Tab is pressed.

/// The names completion draws from.
pub trait Names {
    /// Names of one kind: `pin`, `param`, `sig`, `funct`, `thread`,
    /// `comp`, `module` (what `loadrt` can load) or `alias`.
    fn names(&self, kind: Kind) -> Vec<String>;
    /// The parameters (`key`) a module takes.
    fn module_params(&self, module: &str) -> Vec<String>;
}

/// A kind of name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Pins.
    Pin,
    /// Parameters.
    Param,
    /// Signals.
    Signal,
    /// Functions.
    Funct,
    /// Threads.
    Thread,
    /// Loaded components.
    Comp,
    /// Modules `loadrt` can load.
    Module,
}

/// What one argument position of a command takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Slot {
    /// Names of these kinds.
    Names(&'static [Kind]),
    /// Names of these kinds, or one of these words.
    NamesOr(&'static [Kind], &'static [&'static str]),
    /// One of these words.
    Words(&'static [&'static str]),
    /// The names of the kind the previous word names (`show pin ...`).
    KindOfPrevious,
    /// `key=` of the module named first (`loadrt MODULE key=...`).
    ModuleParam,
    /// A command name.
    Command,
    /// Nothing to complete.
    Free,
}

use Kind::*;

const PINS: &[Kind] = &[Pin];
const PINS_PARAMS: &[Kind] = &[Pin, Param];
const SIGNALS: &[Kind] = &[Signal];
const FUNCTS: &[Kind] = &[Funct];
const THREADS: &[Kind] = &[Thread];
const COMPS: &[Kind] = &[Comp];
const LOCKS: &[&str] = &["all", "none", "tune", "load", "config", "params", "run"];
const SHOW_KINDS: &[&str] = &[
    "comp", "pin", "sig", "param", "funct", "thread", "alias", "all",
];
const LIST_KINDS: &[&str] = &["comp", "pin", "sig", "param", "funct", "thread"];
const SAVE_KINDS: &[&str] = &[
    "comp",
    "alias",
    "sig",
    "sigu",
    "link",
    "linka",
    "net",
    "neta",
    "netl",
    "netla",
    "param",
    "thread",
    "unconnectedinpins",
    "all",
    "allu",
];
const THREAD_SWITCHES: &[&str] = &["timing=", "cpu=", "missed="];

/// What argument `index` (0 = the first after the command) of `command`
/// takes; the last slot repeats.
fn slots(command: &str) -> &'static [Slot] {
    use Slot::*;
    match command {
        "loadrt" => &[Names(&[Module]), ModuleParam],
        "unloadrt" | "unload" | "unloadusr" => &[NamesOr(COMPS, &["all"]), Free],
        "waitusr" => &[Names(COMPS), Free],
        "setp" | "getp" | "ptype" => &[Names(PINS_PARAMS), Free],
        "sets" | "gets" | "stype" => &[Names(SIGNALS), Free],
        "delsig" => &[NamesOr(SIGNALS, &["all"]), Free],
        "newsig" => &[
            Free,
            Words(&["bit", "float", "s32", "u32", "s64", "u64"]),
            Free,
        ],
        "net" => &[Names(SIGNALS), Names(PINS)],
        "linkps" => &[Names(PINS), Names(SIGNALS), Free],
        "linksp" => &[Names(SIGNALS), Names(PINS), Free],
        "linkpp" => &[Names(PINS), Names(PINS), Free],
        "unlinkp" => &[Names(PINS), Free],
        "addf" | "delf" | "initf" => &[Names(FUNCTS), Names(THREADS), Free],
        "setthread" => &[Names(THREADS), Words(THREAD_SWITCHES)],
        "show" => &[Words(SHOW_KINDS), KindOfPrevious],
        "list" => &[Words(LIST_KINDS), KindOfPrevious],
        "save" => &[Words(SAVE_KINDS), Free],
        "alias" => &[Words(&["pin", "param"]), KindOfPrevious, Free],
        "unalias" => &[Words(&["pin", "param"]), Free],
        "lock" | "unlock" => &[Words(LOCKS), Free],
        "status" => &[Words(&["lock", "mem", "all"]), Free],
        "help" => &[Command, Free],
        _ => &[Free],
    }
}

/// The kinds a word of `show`, `list` or `alias` names.
fn kinds_named(word: &str) -> &'static [Kind] {
    match word {
        "pin" => PINS,
        "param" | "parameter" => &[Param],
        "sig" | "signal" => SIGNALS,
        "funct" | "function" => FUNCTS,
        "thread" => THREADS,
        "comp" => COMPS,
        _ => &[],
    }
}

/// Words halcmd drops as arrows (`=>`, `<=`, `<=>`).
fn is_arrow(word: &str) -> bool {
    word.starts_with('<') || word.starts_with('=')
}

/// Completes the word that ends at the cursor of `before` (the line up
/// to the cursor): where that word starts, and the candidates, sorted.
pub fn complete(before: &str, commands: &[String], names: &dyn Names) -> (usize, Vec<String>) {
    let start = before.rfind(char::is_whitespace).map_or(0, |i| {
        i + before[i..].chars().next().map_or(1, char::len_utf8)
    });
    let partial = &before[start..];
    let done: Vec<&str> = before[..start].split_whitespace().collect();
    let pool: Vec<String> = match done.split_first() {
        None => commands.to_vec(),
        Some((command, args)) => {
            let args: Vec<&str> = args.iter().copied().filter(|w| !is_arrow(w)).collect();
            let table = slots(command);
            let slot = table
                .get(args.len())
                .or(table.last())
                .copied()
                .unwrap_or(Slot::Free);
            candidates(slot, command, &args, commands, names)
        }
    };
    let mut found: Vec<String> = pool
        .into_iter()
        .filter(|c| c.starts_with(partial))
        .collect();
    found.sort();
    found.dedup();
    (start, found)
}

fn candidates(
    slot: Slot,
    command: &str,
    args: &[&str],
    commands: &[String],
    names: &dyn Names,
) -> Vec<String> {
    let of =
        |kinds: &[Kind]| -> Vec<String> { kinds.iter().flat_map(|k| names.names(*k)).collect() };
    let words = |w: &[&str]| -> Vec<String> { w.iter().map(|s| s.to_string()).collect() };
    match slot {
        Slot::Names(kinds) => of(kinds),
        Slot::NamesOr(kinds, extra) => {
            let mut v = of(kinds);
            v.extend(words(extra));
            v
        }
        Slot::Words(w) => words(w),
        Slot::KindOfPrevious => match args.first() {
            Some(kind) if command == "show" && *kind == "all" => Vec::new(),
            Some(kind) => of(kinds_named(kind)),
            None => Vec::new(),
        },
        Slot::ModuleParam => match args.first() {
            Some(module) => names
                .module_params(module)
                .into_iter()
                .map(|p| format!("{p}="))
                .collect(),
            None => Vec::new(),
        },
        Slot::Command => commands.to_vec(),
        Slot::Free => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Fake;

    impl Names for Fake {
        fn names(&self, kind: Kind) -> Vec<String> {
            let v: &[&str] = match kind {
                Pin => &["and2.0.in0", "and2.0.in1", "and2.0.out", "pid.0.output"],
                Param => &["pid.0.maxerror"],
                Signal => &["x-pos", "x-vel"],
                Funct => &["and2.0", "pid.0.do-pid-calcs"],
                Thread => &["servo-thread", "base-thread"],
                Comp => &["and2", "pid"],
                Module => &["and2", "abs", "pid", "pwmgen"],
            };
            v.iter().map(|s| s.to_string()).collect()
        }

        fn module_params(&self, module: &str) -> Vec<String> {
            match module {
                "pid" => vec!["count".into(), "names".into(), "debug".into()],
                _ => vec![],
            }
        }
    }

    fn commands() -> Vec<String> {
        ["loadrt", "loadusr", "net", "setp", "show", "sets"]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn c(line: &str) -> (usize, Vec<String>) {
        complete(line, &commands(), &Fake)
    }

    #[test]
    fn commands_complete_first() {
        assert_eq!(c("lo"), (0, vec!["loadrt".into(), "loadusr".into()]));
        assert_eq!(c("se").1, ["setp", "sets"]);
        assert_eq!(c("").1.len(), commands().len());
    }

    #[test]
    fn arguments_complete_by_what_the_command_takes() {
        assert_eq!(c("setp and2.0.o"), (5, vec!["and2.0.out".into()]));
        assert_eq!(c("setp pid.0.m").1, ["pid.0.maxerror"]);
        assert_eq!(c("loadrt p").1, ["pid", "pwmgen"]);
        assert_eq!(c("loadrt pid c").1, ["count="]);
        assert_eq!(c("loadrt pid count=2 n").1, ["names="]);
        assert_eq!(c("net x-").1, ["x-pos", "x-vel"]);
        assert_eq!(
            c("net x-pos and2.0.out => and2.0.i").1,
            ["and2.0.in0", "and2.0.in1"]
        );
        assert_eq!(c("addf pid").1, ["pid.0.do-pid-calcs"]);
        assert_eq!(c("addf pid.0.do-pid-calcs s").1, ["servo-thread"]);
        assert_eq!(c("addf and2.0 servo-thread ").1, Vec::<String>::new());
        assert_eq!(c("show p").1, ["param", "pin"]);
        assert_eq!(c("show sig x-v").1, ["x-vel"]);
        assert_eq!(c("unloadrt a").1, ["all", "and2"]);
        assert_eq!(c("frobnicate x").1, Vec::<String>::new());
    }

    #[test]
    fn the_word_starts_after_the_last_space() {
        assert_eq!(c("setp  and").0, 6);
        assert_eq!(c("setp ").0, 5);
        assert_eq!(c("setp ").1.len(), 5);
    }
}
