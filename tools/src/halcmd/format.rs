//! halcmd's printed output, byte for byte as LinuxCNC prints it.

use hal_core::{ComponentKind, HalType, Instance, PinDir, Value};

use super::cfmt::fmt_g;
use super::session::Options;

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

fn arrow(dir: PinDir) -> &'static str {
    match dir {
        PinDir::In => "<==",
        PinDir::Out => "==>",
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

/// Splits a leading `-tTYPE` / `-t TYPE` off show's patterns.
fn type_filter<'a, 'b>(pats: &'a [&'b str]) -> Result<(Option<HalType>, &'a [&'b str]), String> {
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
        other => HalType::from_name(other).ok_or_else(|| format!("unknown type '{other}'"))?,
    };
    Ok((Some(t), rest))
}

fn show_pins(inst: &Instance, pats: &[&str], only: Option<HalType>) -> Result<String, String> {
    let mut out = format!("Component Pins:\n{HEADER}");
    for p in inst.pins().map_err(|e| e.to_string())? {
        if !matches(pats, &p.name) || only.is_some_and(|t| t != p.hal_type) {
            continue;
        }
        out.push_str(&row(
            p.owner_id,
            p.hal_type,
            p.dir.label(),
            p.value,
            &p.name,
        ));
        if let Some(s) = &p.signal {
            // From the pin's side: an input receives from the signal.
            let a = match p.dir {
                PinDir::In => "<==",
                PinDir::Out => "==>",
                PinDir::Io => "<=>",
            };
            out.push_str(&format!(" {a} {s}"));
        }
        out.push('\n');
    }
    out.push('\n');
    Ok(out)
}

fn show_params(inst: &Instance, pats: &[&str], only: Option<HalType>) -> Result<String, String> {
    let mut out = format!("Parameters:\n{HEADER}");
    for p in inst.params().map_err(|e| e.to_string())? {
        if matches(pats, &p.name) && only.is_none_or(|t| t == p.hal_type) {
            out.push_str(&row(
                p.owner_id,
                p.hal_type,
                p.dir.label(),
                p.value,
                &p.name,
            ));
            out.push('\n');
        }
    }
    out.push('\n');
    Ok(out)
}

fn show_signals(inst: &Instance, pats: &[&str], only: Option<HalType>) -> Result<String, String> {
    let mut out = String::from("Signals:\nType                  Value  Name     (linked to)\n");
    for s in inst.signals().map_err(|e| e.to_string())? {
        if !matches(pats, &s.name) || only.is_some_and(|t| t != s.hal_type) {
            continue;
        }
        out.push_str(&format!(
            "{:<5} {:>21}  {}\n",
            s.hal_type.name(),
            show_value(s.value),
            s.name
        ));
        for (pin, dir) in &s.pins {
            // From the signal's side: an input pin is fed by it.
            let a = match dir {
                PinDir::In => arrow(PinDir::Out),
                PinDir::Out => arrow(PinDir::In),
                PinDir::Io => arrow(PinDir::Io),
            };
            out.push_str(&format!("{:33}{a} {pin}\n", ""));
        }
    }
    out.push('\n');
    Ok(out)
}

fn list(inst: &Instance, kind: &str, pats: &[&str]) -> Result<String, String> {
    let e = |e: hal_core::HalError| e.to_string();
    // `-tTYPE` as first pattern restricts pins, params and signals by type.
    let (type_filter, pats) = match pats.first().and_then(|p| p.strip_prefix("-t")) {
        Some(t) => (
            Some(HalType::from_name(t).ok_or_else(|| format!("unknown type '{t}'"))?),
            &pats[1..],
        ),
        None => (None, pats),
    };
    let keep = |t: HalType| type_filter.is_none_or(|f| f == t);
    let names: Vec<String> = match kind {
        "pin" => inst
            .pins()
            .map_err(e)?
            .into_iter()
            .filter(|p| keep(p.hal_type))
            .map(|p| p.name)
            .collect(),
        "sig" | "signal" => inst
            .signals()
            .map_err(e)?
            .into_iter()
            .filter(|s| keep(s.hal_type))
            .map(|s| s.name)
            .collect(),
        "param" | "parameter" => inst
            .params()
            .map_err(e)?
            .into_iter()
            .filter(|p| keep(p.hal_type))
            .map(|p| p.name)
            .collect(),
        "funct" | "function" => inst
            .functs()
            .map_err(e)?
            .into_iter()
            .map(|f| f.name)
            .collect(),
        "thread" => inst
            .threads()
            .map_err(e)?
            .into_iter()
            .map(|t| t.name)
            .collect(),
        "comp" => {
            // Newest first, as LinuxCNC keeps its component list.
            let mut cs = inst.components().map_err(e)?;
            cs.sort_by_key(|c| std::cmp::Reverse(c.id));
            cs.into_iter().map(|c| c.name).collect()
        }
        other => return Err(format!("Unknown 'list' type '{other}'")),
    };
    let mut out = String::new();
    for n in names.iter().filter(|n| matches(pats, n)) {
        out.push_str(n);
        out.push(' ');
    }
    out.push('\n');
    Ok(out)
}

fn show_comps(inst: &Instance, pats: &[&str]) -> Result<String, String> {
    let mut cs = inst.components().map_err(|e| e.to_string())?;
    cs.sort_by_key(|c| std::cmp::Reverse(c.id));
    let mut out = format!(
        "Loaded HAL Components:\nID      Type  {:<47} PID   State\n",
        "Name"
    );
    for c in cs.iter().filter(|c| matches(pats, &c.name)) {
        let state = if c.ready { "ready" } else { "initializing" };
        let (kind, pid) = match c.kind {
            ComponentKind::User => ("User", c.pid.to_string()),
            _ => ("RT", String::new()),
        };
        out.push_str(&format!(
            " {:>5}  {kind:<4}  {:<47} {pid:>5} {state}\n",
            c.id, c.name
        ));
    }
    out.push('\n');
    Ok(out)
}

fn show_functs(inst: &Instance, pats: &[&str]) -> Result<String, String> {
    let mut out = String::from(
        "Exported Functions:\nOwner   CodeAddr      Arg           FP   Users   Name\n",
    );
    for (i, f) in inst.functs().map_err(|e| e.to_string())?.iter().enumerate() {
        if matches(pats, &f.name) {
            // Code lives in the host, so there is no address to show: the
            // columns hold the function's index and 0.
            out.push_str(&format!(
                " {:05}  {:08x}  {:08x}  {:<3}  {:>5}   {}\n",
                f.owner_id, i, 0, "YES", f.users, f.name
            ));
        }
    }
    out.push('\n');
    Ok(out)
}

fn show_threads(inst: &Instance, pats: &[&str]) -> Result<String, String> {
    let mut out = String::from(
        "Realtime Threads:\n     Period  FP     Name               (     Time, Max-Time )\n",
    );
    for t in inst.threads().map_err(|e| e.to_string())? {
        if !matches(pats, &t.name) {
            continue;
        }
        out.push_str(&format!(
            "{:>11}  {:<3}  {:>20} ( {:>8}, {:>8} )\n",
            t.period, "YES", t.name, t.time_ns, t.tmax_ns
        ));
        for (i, f) in t.functs.iter().enumerate() {
            out.push_str(&format!("{:17}{:>2} {f}\n", "", i + 1));
        }
    }
    out.push('\n');
    Ok(out)
}

fn show_aliases(inst: &Instance, pats: &[&str], pins: bool) -> Result<String, String> {
    let e = |e: hal_core::HalError| e.to_string();
    let (title, pairs): (&str, Vec<(String, String)>) = if pins {
        let v = inst.pins().map_err(e)?;
        (
            "Pin Aliases:",
            v.into_iter()
                .filter_map(|p| Some((p.name, p.orig_name?)))
                .collect(),
        )
    } else {
        let v = inst.params().map_err(e)?;
        (
            "Parameter Aliases:",
            v.into_iter()
                .filter_map(|p| Some((p.name, p.orig_name?)))
                .collect(),
        )
    };
    let mut out = format!("{title}\n {:<47}  {}\n", "Alias", "Original Name");
    for (alias, orig) in pairs.iter().filter(|(a, _)| matches(pats, a)) {
        out.push_str(&format!(" {alias:<47}  {orig}\n"));
    }
    out.push('\n');
    Ok(out)
}

fn status(inst: &Instance) -> String {
    format!(
        "HAL locking status:\n  current lock value 0 (00)\n  HAL_LOCK_NONE - nothing is locked\n\
         HAL memory status\n  used/total shared memory:   {}/{}\n  active components: {}\n\n",
        inst.segment_used(),
        inst.segment_size(),
        inst.components().map(|c| c.len()).unwrap_or(0),
    )
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
    ("lock", "lock [all|tune|none] / unlock [all|tune]: accepted for compatibility"),
    ("debug", "debug [LEVEL]: accepted for compatibility"),
    ("help", "help [COMMAND]: this help"),
];

fn help(cmd: Option<&str>) -> Result<String, String> {
    match cmd {
        None => Ok(HELP
            .iter()
            .map(|(_, h)| format!("  {h}\n"))
            .collect::<String>()),
        Some(c) => HELP
            .iter()
            .find(|(n, _)| *n == c)
            .map(|(_, h)| format!("{h}\n"))
            .ok_or_else(|| format!("No help for unknown command '{c}'")),
    }
}

/// Finds a pin, else a param, by name or original name (halcmd looks
/// pins up first): (value, type, is_param).
pub fn lookup(inst: &Instance, name: &str) -> Result<Option<(Value, HalType, bool)>, String> {
    let e = |e: hal_core::HalError| e.to_string();
    if let Some(p) = inst.pin(name).map_err(e)? {
        return Ok(Some((p.value, p.hal_type, false)));
    }
    Ok(inst
        .param(name)
        .map_err(e)?
        .map(|p| (p.value, p.hal_type, true)))
}

/// Renders the output of `show`, `list`, `getp`, `gets`, `ptype`, `stype`.
pub fn render(inst: &Instance, words: &[&str], opts: &Options) -> Result<String, String> {
    if opts.script && words[0] == "show" {
        if let Some(text) = script::show(inst, &words[1..])? {
            return Ok(text);
        }
    }
    let args = &words[1..];
    let not_found = |n: &str| format!("parameter or pin '{n}': not found");
    match words[0] {
        "show" => {
            let (kind, pats) = match args.split_first() {
                Some((k, rest)) => (*k, rest),
                None => ("all", &[][..]),
            };
            // `-tTYPE` (or `-t TYPE`) first: only items of that type.
            let (type_filter, pats) = type_filter(pats)?;
            match kind {
                "pin" => show_pins(inst, pats, type_filter),
                "param" | "parameter" => show_params(inst, pats, type_filter),
                "sig" | "signal" => show_signals(inst, pats, type_filter),
                "comp" => show_comps(inst, pats),
                "funct" | "function" => show_functs(inst, pats),
                "thread" => show_threads(inst, pats),
                "alias" => Ok(show_aliases(inst, pats, true)? + &show_aliases(inst, pats, false)?),
                "all" => Ok([
                    show_comps(inst, pats)?,
                    show_pins(inst, pats, type_filter)?,
                    show_aliases(inst, pats, true)?,
                    show_signals(inst, pats, type_filter)?,
                    show_params(inst, pats, type_filter)?,
                    show_aliases(inst, pats, false)?,
                    show_functs(inst, pats)?,
                    show_threads(inst, pats)?,
                ]
                .concat()),
                other => Err(format!("Unknown 'show' type '{other}'")),
            }
        }
        "list" => {
            let (kind, pats) = args.split_first().ok_or("list: needs a type")?;
            list(inst, kind, pats)
        }
        "getp" => {
            let n = args.first().ok_or("getp: needs a name")?;
            let (v, _, _) = lookup(inst, n)?.ok_or_else(|| not_found(n))?;
            Ok(format!("{}\n", get_value(v)))
        }
        "ptype" => {
            let n = args.first().ok_or("ptype: needs a name")?;
            let (_, t, _) = lookup(inst, n)?.ok_or_else(|| not_found(n))?;
            Ok(format!("{t}\n"))
        }
        "gets" => {
            let n = args.first().ok_or("gets: needs a signal")?;
            let v = inst
                .signal_value(n)
                .map_err(|_| format!("signal '{n}': not found"))?;
            Ok(format!("{}\n", get_value(v)))
        }
        "stype" => {
            let n = args.first().ok_or("stype: needs a signal")?;
            let t = inst
                .signal_type(n)
                .map_err(|_| format!("signal '{n}': not found"))?;
            Ok(format!("{t}\n"))
        }
        "save" => {
            let text = super::save::save(inst, args.first().copied())?;
            match args.get(1) {
                Some(file) => std::fs::write(file, text)
                    .map(|()| String::new())
                    .map_err(|e| format!("save: {file}: {e}")),
                None => Ok(text),
            }
        }
        "status" => Ok(status(inst)),
        "help" => help(args.first().copied()),
        other => Err(format!("Unknown command '{other}'")),
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

/// `show` in script mode (`-s`): no titles, component names instead of
/// ids, one line per thread and per signal.
mod script {
    use super::{matches, show_value};
    use hal_core::{Instance, PinDir};

    fn e(err: hal_core::HalError) -> String {
        err.to_string()
    }

    /// The script-mode text of `show KIND PATTERNS`, or `None` for kinds
    /// printed the same in both modes.
    pub fn show(inst: &Instance, args: &[&str]) -> Result<Option<String>, String> {
        let (kind, pats) = match args.split_first() {
            Some((k, rest)) => (*k, rest),
            None => return Ok(None),
        };
        let mut out = String::new();
        match kind {
            "pin" => {
                for p in inst
                    .pins()
                    .map_err(e)?
                    .into_iter()
                    .filter(|p| matches(pats, &p.name))
                {
                    out.push_str(&format!(
                        "{} {} {} {} {}",
                        p.owner,
                        p.hal_type.name(),
                        p.dir.label(),
                        show_value(p.value),
                        p.name
                    ));
                    if let Some(s) = p.signal {
                        let a = match p.dir {
                            PinDir::In => "<==",
                            PinDir::Out => "==>",
                            PinDir::Io => "<=>",
                        };
                        out.push_str(&format!(" {a} {s}"));
                    }
                    out.push('\n');
                }
            }
            "param" | "parameter" => {
                for p in inst
                    .params()
                    .map_err(e)?
                    .into_iter()
                    .filter(|p| matches(pats, &p.name))
                {
                    out.push_str(&format!(
                        "{} {} {} {} {}\n",
                        p.owner,
                        p.hal_type.name(),
                        p.dir.label(),
                        show_value(p.value),
                        p.name
                    ));
                }
            }
            "sig" | "signal" => {
                for s in inst
                    .signals()
                    .map_err(e)?
                    .into_iter()
                    .filter(|s| matches(pats, &s.name))
                {
                    out.push_str(&format!(
                        "{} {} {}",
                        s.hal_type.name(),
                        show_value(s.value),
                        s.name
                    ));
                    for (pin, dir) in &s.pins {
                        let a = match dir {
                            PinDir::In => "==>",
                            PinDir::Out => "<==",
                            PinDir::Io => "<=>",
                        };
                        out.push_str(&format!(" {a} {pin}"));
                    }
                    out.push('\n');
                }
            }
            "funct" | "function" => {
                for f in inst
                    .functs()
                    .map_err(e)?
                    .into_iter()
                    .filter(|f| matches(pats, &f.name))
                {
                    let fp = if f.uses_fp { "YES" } else { "NO" };
                    out.push_str(&format!("{} {fp} {} {}\n", f.owner, f.users, f.name));
                }
            }
            "thread" => {
                for t in inst
                    .threads()
                    .map_err(e)?
                    .into_iter()
                    .filter(|t| matches(pats, &t.name))
                {
                    let fp = if t.uses_fp { "YES" } else { "NO" };
                    out.push_str(&format!("{} {fp} {}", t.period, t.name));
                    for f in &t.functs {
                        out.push_str(&format!(" {f}"));
                    }
                    out.push('\n');
                }
            }
            _ => return Ok(None),
        }
        Ok(Some(out))
    }
}
