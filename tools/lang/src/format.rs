//! halcmd's printed output, byte for byte as LinuxCNC prints it.

use hal_core::{
    ComponentInfo, ComponentKind, FunctInfo, HalType, Instance, ParamInfo, PinDir, PinInfo,
    SignalInfo, ThreadInfo, Value,
};

use crate::error::{LangError, Result};
use hal_core::cfmt::fmt_g;

/// Whether `name` matches one of `patterns` the way halcmd matches: a
/// pattern matches a name it is a prefix of, or that it matches as a shell
/// glob. No patterns match everything.
pub fn matches(patterns: &[&str], name: &str) -> bool {
    patterns.is_empty()
        || patterns
            .iter()
            .any(|p| name.starts_with(p) || glob(p.as_bytes(), name.as_bytes()))
}

/// fnmatch(3) without flags: `*`, `?` and `[...]` (with `!`/`^` and ranges).
fn glob(p: &[u8], s: &[u8]) -> bool {
    match p.first() {
        None => s.is_empty(),
        Some(b'*') => (0..=s.len()).any(|i| glob(&p[1..], &s[i..])),
        Some(b'?') => !s.is_empty() && glob(&p[1..], &s[1..]),
        Some(b'[') => {
            let Some(close) = p.iter().skip(2).position(|&c| c == b']').map(|i| i + 2) else {
                return s.first() == Some(&b'[') && glob(&p[1..], &s[1..]);
            };
            let Some(&c) = s.first() else { return false };
            let set = &p[1..close];
            let (neg, set) = match set.first() {
                Some(b'!') | Some(b'^') => (true, &set[1..]),
                _ => (false, set),
            };
            let mut hit = false;
            let mut i = 0;
            while i < set.len() {
                if i + 2 < set.len() && set[i + 1] == b'-' {
                    hit |= set[i] <= c && c <= set[i + 2];
                    i += 3;
                } else {
                    hit |= set[i] == c;
                    i += 1;
                }
            }
            hit != neg && glob(&p[close + 1..], &s[1..])
        }
        Some(&c) => s.first() == Some(&c) && glob(&p[1..], &s[1..]),
    }
}

/// A value as `show` prints it: bits TRUE/FALSE, floats `%.7g`, unsigned
/// in hex.
pub fn show_value(v: Value) -> String {
    match v {
        Value::Bit(b) => if b { "TRUE" } else { "FALSE" }.to_string(),
        Value::Float(f) => fmt_g(f, 7),
        Value::S32(x) => x.to_string(),
        Value::S64(x) => x.to_string(),
        Value::U32(x) => format!("0x{x:08X}"),
        Value::U64(x) => format!("0x{x:016X}"),
        // The size of the port's buffer, in bytes.
        Value::Port(x) => x.to_string(),
    }
}

/// A value as `getp` and `gets` print it: unsigned in decimal.
pub fn get_value(v: Value) -> String {
    match v {
        Value::U32(x) => x.to_string(),
        Value::U64(x) => x.to_string(),
        other => show_value(other),
    }
}

/// The arrow `show` and `save` print from a pin's side: an input pin
/// receives from its signal.
pub fn pin_arrow(dir: PinDir) -> &'static str {
    match dir {
        PinDir::In => "<==",
        PinDir::Out => "==>",
        PinDir::Io => "<=>",
    }
}

/// The arrow `show` and `save` print from a signal's side: the signal
/// feeds an input pin.
pub fn sig_arrow(dir: PinDir) -> &'static str {
    match dir {
        PinDir::In => "==>",
        PinDir::Out => "<==",
        PinDir::Io => "<=>",
    }
}

fn row(owner: i32, t: HalType, dir: &str, value: Value, name: &str) -> String {
    format!(
        " {owner:>5}  {:<5} {dir:<3}  {:>20}  {name}",
        t.name(),
        show_value(value)
    )
}

const HEADER: &str = "Owner   Type  Dir                 Value  Name\n";

/// Splits a leading `-tTYPE` / `-t TYPE` off the patterns of `show` and
/// `list`.
fn type_filter<'a, 'b>(pats: &'a [&'b str]) -> Result<(Option<HalType>, &'a [&'b str])> {
    let (name, rest) = match pats {
        ["-t", t, rest @ ..] => (*t, rest),
        [first, rest @ ..] if first.starts_with("-t") => (&first[2..], rest),
        _ => return Ok((None, pats)),
    };
    let t = match name {
        "bool" => HalType::Bit,
        "real" => HalType::Float,
        "signed" => HalType::S32,
        "unsigned" => HalType::U32,
        other => HalType::from_name(other).ok_or_else(|| LangError::UnknownType {
            name: other.to_string(),
        })?,
    };
    Ok((Some(t), rest))
}

/// How `show` prints: the patterns names must match, the `-t` type filter
/// (pins, params and signals), and script mode (`-s`), which leaves out
/// titles and blank lines and prints each object on one line.
struct Show<'a> {
    pats: &'a [&'a str],
    only: Option<HalType>,
    script: bool,
}

impl Show<'_> {
    /// Whether an object named `name` (of type `t`, if typed) is shown.
    fn keeps(&self, name: &str, t: Option<HalType>) -> bool {
        matches(self.pats, name) && t.zip(self.only).is_none_or(|(t, only)| t == only)
    }

    /// A section: its title lines, its rows, a blank line; script mode
    /// prints the rows alone.
    fn section(&self, title: &str, rows: String) -> String {
        if self.script {
            rows
        } else {
            format!("{title}{rows}\n")
        }
    }

    fn comps(&self, comps: &[ComponentInfo]) -> String {
        let mut cs: Vec<&ComponentInfo> =
            comps.iter().filter(|c| self.keeps(&c.name, None)).collect();
        cs.sort_by_key(|c| std::cmp::Reverse(c.id));
        let mut rows = String::new();
        for c in cs {
            let state = if c.ready { "ready" } else { "initializing" };
            let (kind, pid) = match c.kind {
                ComponentKind::User => ("User", c.pid.to_string()),
                _ => ("RT", String::new()),
            };
            rows.push_str(&format!(
                " {:>5}  {kind:<4}  {:<47} {pid:>5} {state}\n",
                c.id, c.name
            ));
        }
        let title = format!(
            "Loaded HAL Components:\nID      Type  {:<47} PID   State\n",
            "Name"
        );
        self.section(&title, rows)
    }

    fn pins(&self, pins: &[PinInfo]) -> String {
        let mut rows = String::new();
        for p in pins
            .iter()
            .filter(|p| self.keeps(&p.name, Some(p.hal_type)))
        {
            if self.script {
                rows.push_str(&format!(
                    "{} {} {} {} {}",
                    p.owner,
                    p.hal_type.name(),
                    p.dir.label(),
                    show_value(p.value),
                    p.name
                ));
            } else {
                rows.push_str(&row(
                    p.owner_id,
                    p.hal_type,
                    p.dir.label(),
                    p.value,
                    &p.name,
                ));
            }
            if let Some(s) = &p.signal {
                rows.push_str(&format!(" {} {s}", pin_arrow(p.dir)));
            }
            rows.push('\n');
        }
        self.section(&format!("Component Pins:\n{HEADER}"), rows)
    }

    fn params(&self, params: &[ParamInfo]) -> String {
        let mut rows = String::new();
        for p in params
            .iter()
            .filter(|p| self.keeps(&p.name, Some(p.hal_type)))
        {
            if self.script {
                rows.push_str(&format!(
                    "{} {} {} {} {}\n",
                    p.owner,
                    p.hal_type.name(),
                    p.dir.label(),
                    show_value(p.value),
                    p.name
                ));
            } else {
                rows.push_str(&row(
                    p.owner_id,
                    p.hal_type,
                    p.dir.label(),
                    p.value,
                    &p.name,
                ));
                rows.push('\n');
            }
        }
        self.section(&format!("Parameters:\n{HEADER}"), rows)
    }

    fn signals(&self, sigs: &[SignalInfo]) -> String {
        let mut rows = String::new();
        for s in sigs
            .iter()
            .filter(|s| self.keeps(&s.name, Some(s.hal_type)))
        {
            if self.script {
                rows.push_str(&format!(
                    "{} {} {}",
                    s.hal_type.name(),
                    show_value(s.value),
                    s.name
                ));
                for (pin, dir) in &s.pins {
                    rows.push_str(&format!(" {} {pin}", sig_arrow(*dir)));
                }
                rows.push('\n');
            } else {
                rows.push_str(&format!(
                    "{:<5} {:>21}  {}\n",
                    s.hal_type.name(),
                    show_value(s.value),
                    s.name
                ));
                for (pin, dir) in &s.pins {
                    rows.push_str(&format!("{:33}{} {pin}\n", "", sig_arrow(*dir)));
                }
            }
        }
        self.section(
            "Signals:\nType                  Value  Name     (linked to)\n",
            rows,
        )
    }

    fn functs(&self, functs: &[FunctInfo]) -> String {
        let mut rows = String::new();
        for (i, f) in functs.iter().enumerate() {
            if !self.keeps(&f.name, None) {
                continue;
            }
            if self.script {
                let fp = if f.uses_fp { "YES" } else { "NO" };
                rows.push_str(&format!("{} {fp} {} {}\n", f.owner, f.users, f.name));
            } else {
                // Code lives in the host, so there is no address to show:
                // the columns hold the function's index and 0.
                rows.push_str(&format!(
                    " {:05}  {:08x}  {:08x}  {:<3}  {:>5}   {}\n",
                    f.owner_id, i, 0, "YES", f.users, f.name
                ));
            }
        }
        self.section(
            "Exported Functions:\nOwner   CodeAddr      Arg           FP   Users   Name\n",
            rows,
        )
    }

    fn threads(&self, threads: &[ThreadInfo]) -> String {
        let mut rows = String::new();
        for t in threads.iter().filter(|t| self.keeps(&t.name, None)) {
            if self.script {
                let fp = if t.uses_fp { "YES" } else { "NO" };
                rows.push_str(&format!("{} {fp} {}", t.period, t.name));
                for f in &t.functs {
                    rows.push_str(&format!(" {f}"));
                }
                rows.push('\n');
            } else {
                rows.push_str(&format!(
                    "{:>11}  {:<3}  {:>20} ( {:>8}, {:>8} )\n",
                    t.period, "YES", t.name, t.time_ns, t.tmax_ns
                ));
                // Only switches away from the defaults: a thread without
                // any shows exactly as in LinuxCNC.
                let switches = thread_switches(t);
                if !switches.is_empty() {
                    rows.push_str(&format!("{:17}   switches: {switches}\n", ""));
                }
                for (i, f) in t.functs.iter().enumerate() {
                    rows.push_str(&format!("{:17}{:>2} {f}\n", "", i + 1));
                }
            }
        }
        self.section(
            "Realtime Threads:\n     Period  FP     Name               (     Time, Max-Time )\n",
            rows,
        )
    }

    /// The aliases among `(name, name before aliasing)` pairs, under
    /// `title` (`Pin Aliases:` or `Parameter Aliases:`).
    fn aliases<'n>(
        &self,
        title: &str,
        pairs: impl Iterator<Item = (&'n str, Option<&'n str>)>,
    ) -> String {
        let mut rows = String::new();
        for (alias, orig) in pairs.filter_map(|(a, o)| Some((a, o?))) {
            if !self.keeps(alias, None) {
                continue;
            }
            if self.script {
                rows.push_str(&format!(" {alias}  {orig}\n"));
            } else {
                rows.push_str(&format!(" {alias:<47}  {orig}\n"));
            }
        }
        self.section(
            &format!("{title}\n {:<47}  {}\n", "Alias", "Original Name"),
            rows,
        )
    }

    fn pin_aliases(&self, pins: &[PinInfo]) -> String {
        let pairs = pins
            .iter()
            .map(|p| (p.name.as_str(), p.orig_name.as_deref()));
        self.aliases("Pin Aliases:", pairs)
    }

    fn param_aliases(&self, params: &[ParamInfo]) -> String {
        let pairs = params
            .iter()
            .map(|p| (p.name.as_str(), p.orig_name.as_deref()));
        self.aliases("Parameter Aliases:", pairs)
    }
}

/// `show [KIND] [-tTYPE] [PATTERN...]`.
fn show(inst: &Instance, args: &[&str], script: bool) -> Result<String> {
    let (kind, pats) = match args.split_first() {
        Some((k, rest)) => (*k, rest),
        None => ("all", &[][..]),
    };
    let (only, pats) = type_filter(pats)?;
    let show = Show { pats, only, script };
    Ok(match kind {
        "pin" => show.pins(&inst.pins()?),
        "param" | "parameter" => show.params(&inst.params()?),
        "sig" | "signal" => show.signals(&inst.signals()?),
        "comp" => show.comps(&inst.components()?),
        "funct" | "function" => show.functs(&inst.functs()?),
        "thread" => show.threads(&inst.threads()?),
        "alias" => show.pin_aliases(&inst.pins()?) + &show.param_aliases(&inst.params()?),
        "all" => {
            // One snapshot of pins and params serves their tables and
            // their aliases.
            let pins = inst.pins()?;
            let params = inst.params()?;
            [
                show.comps(&inst.components()?),
                show.pins(&pins),
                show.pin_aliases(&pins),
                show.signals(&inst.signals()?),
                show.params(&params),
                show.param_aliases(&params),
                show.functs(&inst.functs()?),
                show.threads(&inst.threads()?),
            ]
            .concat()
        }
        other => {
            return Err(LangError::UnknownKind {
                command: "show",
                kind: other.to_string(),
            })
        }
    })
}

/// `list KIND [-tTYPE] [PATTERN...]`: names only, on one line.
fn list(inst: &Instance, kind: &str, pats: &[&str]) -> Result<String> {
    // `-tTYPE` restricts pins, params and signals by type.
    let (only, pats) = type_filter(pats)?;
    let keep = |t: HalType| only.is_none_or(|o| o == t);
    let names: Vec<String> = match kind {
        "pin" => inst
            .pins()?
            .into_iter()
            .filter(|p| keep(p.hal_type))
            .map(|p| p.name)
            .collect(),
        "sig" | "signal" => inst
            .signals()?
            .into_iter()
            .filter(|s| keep(s.hal_type))
            .map(|s| s.name)
            .collect(),
        "param" | "parameter" => inst
            .params()?
            .into_iter()
            .filter(|p| keep(p.hal_type))
            .map(|p| p.name)
            .collect(),
        "funct" | "function" => inst.functs()?.into_iter().map(|f| f.name).collect(),
        "thread" => inst.threads()?.into_iter().map(|t| t.name).collect(),
        "comp" => {
            // Newest first, as LinuxCNC keeps its component list.
            let mut cs = inst.components()?;
            cs.sort_by_key(|c| std::cmp::Reverse(c.id));
            cs.into_iter().map(|c| c.name).collect()
        }
        other => {
            return Err(LangError::UnknownKind {
                command: "list",
                kind: other.to_string(),
            })
        }
    };
    let mut out = String::new();
    for n in names.iter().filter(|n| matches(pats, n)) {
        out.push_str(n);
        out.push(' ');
    }
    out.push('\n');
    Ok(out)
}

/// A thread's switches that differ from the defaults, as `setthread`
/// takes them (`timing=0 cpu=1 missed=catch-up`); empty for none.
pub fn thread_switches(t: &ThreadInfo) -> String {
    let mut words = Vec::new();
    if !t.functs_timed {
        words.push("timing=0".to_string());
    }
    if let Some(cpu) = t.cpu {
        words.push(format!("cpu={cpu}"));
    }
    if t.missed != hal_core::MissedDeadline::Skip {
        words.push(format!("missed={}", t.missed.name()));
    }
    words.join(" ")
}

/// The commands `help` lists, with a line each.
pub const HELP: &[(&str, &str)] = &[
    ("loadrt", "loadrt MODULE [ARGS...]: load a realtime module"),
    ("unloadrt", "unloadrt MODULE|all: unload realtime modules"),
    ("loadusr", "loadusr [-W|-w|-i|-n NAME] PROGRAM [ARGS...]: start a user-space program"),
    ("waitusr", "waitusr NAME: wait for a user-space component to exit"),
    ("unloadusr", "unloadusr NAME|all: stop user-space components"),
    ("unload", "unload NAME|all: unload a component of either kind"),
    ("net", "net SIGNAL PIN [=>|<=|<=>] PIN...: connect pins, creating the signal"),
    ("newsig", "newsig SIGNAL TYPE: create a signal"),
    ("delsig", "delsig SIGNAL|all: delete signals"),
    ("linkps", "linkps PIN [ARROW] SIGNAL: link a pin to a signal"),
    ("linksp", "linksp SIGNAL [ARROW] PIN: link a signal to a pin"),
    ("unlinkp", "unlinkp PIN: unlink a pin"),
    ("setp", "setp NAME VALUE (or NAME = VALUE): set a pin or parameter"),
    ("getp", "getp NAME: print a pin or parameter"),
    ("ptype", "ptype NAME: print the type of a pin or parameter"),
    ("sets", "sets SIGNAL VALUE: set a signal without a writer"),
    ("gets", "gets SIGNAL: print a signal"),
    ("stype", "stype SIGNAL: print the type of a signal"),
    ("addf", "addf FUNCT THREAD [POSITION]: add a function to a thread"),
    ("initf", "initf FUNCT THREAD: run a function once, on the thread's first cycle"),
    ("linkpp", "linkpp PIN1 PIN2: connect two pins with a signal named after the first (obsolete)"),
    ("delf", "delf FUNCT [THREAD]: remove a function from a thread"),
    ("setthread", "setthread THREAD [timing=0|1] [cpu=N|default] [missed=skip|catch-up]: change a thread's switches"),
    ("start", "start: start the realtime threads"),
    ("stop", "stop: stop the realtime threads (not a safe state)"),
    ("show", "show [comp|pin|sig|param|funct|thread|alias|all] [PATTERN...]"),
    ("list", "list comp|pin|sig|param|funct|thread [PATTERN...]: print names"),
    ("save", "save [comp|alias|sig|sigu|link|linka|net|neta|netl|netla|param|thread|unconnectedinpins|all|allu] [FILE]"),
    ("alias", "alias pin|param NAME ALIAS: give a second name"),
    ("unalias", "unalias pin|param ALIAS: remove an alias"),
    ("source", "source FILE: run the commands in FILE"),
    ("echo", "echo / unecho: print each command before it runs"),
    ("print", "print [MESSAGE]: print the file, line and message"),
    ("status", "status [lock|mem|all]: print HAL status"),
    ("lock", "lock [all|none|tune|load|config|params|run]: lock HAL against changes"),
    ("unlock", "unlock [all|none|tune|load|config|params|run]: unlock HAL"),
    ("debug", "debug [LEVEL]: accepted for compatibility"),
    ("help", "help [COMMAND]: this help"),
    ("quit", "quit / exit: stop reading commands (the file ends successfully)"),
];

/// The text of `help` (every command) or `help COMMAND`.
pub fn help(cmd: Option<&str>) -> Result<String> {
    match cmd {
        None => Ok(HELP
            .iter()
            .map(|(_, h)| format!("  {h}\n"))
            .collect::<String>()),
        Some(c) => HELP
            .iter()
            .find(|(n, _)| *n == c)
            .map(|(_, h)| format!("{h}\n"))
            .ok_or_else(|| LangError::NoHelp {
                command: c.to_string(),
            }),
    }
}

/// Finds a param, else a pin, by name or original name: when both exist,
/// halcmd acts on the parameter. Returns (value, type, is_param).
pub fn lookup(inst: &Instance, name: &str) -> Result<Option<(Value, HalType, bool)>> {
    if let Some(p) = inst.param(name)? {
        return Ok(Some((p.value, p.hal_type, true)));
    }
    Ok(inst.pin(name)?.map(|p| (p.value, p.hal_type, false)))
}

/// Renders the output of `show`, `list`, `save`, `getp`, `gets`, `ptype`,
/// `stype`, `status` and `help`. The arguments have been counted against
/// the command table already; `script` is `-s`.
pub fn render(inst: &Instance, cmd: &str, args: &[&str], script: bool) -> Result<String> {
    let not_found = |n: &str| LangError::NoPinOrParam {
        name: n.to_string(),
    };
    let no_signal = |n: &str| LangError::NoSignal {
        name: n.to_string(),
    };
    match cmd {
        "show" => show(inst, args, script),
        "list" => list(inst, args[0], &args[1..]),
        "getp" => {
            let (v, _, _) = lookup(inst, args[0])?.ok_or_else(|| not_found(args[0]))?;
            Ok(format!("{}\n", get_value(v)))
        }
        "ptype" => {
            let (_, t, _) = lookup(inst, args[0])?.ok_or_else(|| not_found(args[0]))?;
            Ok(format!("{t}\n"))
        }
        "gets" => {
            let n = args[0];
            let v = inst.signal_value(n).map_err(|_| no_signal(n))?;
            Ok(format!("{}\n", get_value(v)))
        }
        "stype" => {
            let n = args[0];
            let t = inst.signal_type(n).map_err(|_| no_signal(n))?;
            Ok(format!("{t}\n"))
        }
        "save" => {
            let text = crate::save::save(inst, args.first().copied())?;
            match args.get(1) {
                Some(file) => {
                    std::fs::write(file, text)
                        .map(|()| String::new())
                        .map_err(|source| LangError::File {
                            command: "save:",
                            file: file.to_string(),
                            source,
                        })
                }
                None => Ok(text),
            }
        }
        "status" => crate::lock::status(inst, args.first().copied()),
        "help" => help(args.first().copied()),
        other => Err(LangError::UnknownCommand {
            name: other.to_string(),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_match_prefixes_and_globs() {
        assert!(matches(&[], "x"));
        assert!(matches(&["and2"], "and2.0.in0"));
        assert!(matches(&["*.in"], "conv.0.in"));
        assert!(!matches(&["*.in"], "conv.0.in0.x"));
        assert!(matches(&["conv-s*"], "conv-s32-u32.0.in"));
        assert!(matches(&["a[0-2].?"], "a1.x"));
        assert!(!matches(&["a[!0-2]"], "a1"));
        assert!(!matches(&["nomatch"], "and2.0.in0"));
    }

    #[test]
    fn rows_line_up_with_the_header() {
        let r = row(6, HalType::Bit, "IN", Value::Bit(false), "and2.0.in0");
        assert_eq!(r, "     6  bit   IN                  FALSE  and2.0.in0");
        let r = row(12, HalType::U64, "OUT", Value::U64(u64::MAX), "x");
        assert_eq!(r, "    12  u64   OUT    0xFFFFFFFFFFFFFFFF  x");
    }
}
