//! halcmd's printed output, byte for byte as LinuxCNC prints it.

use hal_core::{HalType, Instance, PinDir, Value};

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

fn show_pins(inst: &Instance, pats: &[&str]) -> Result<String, String> {
    let mut out = format!("Component Pins:\n{HEADER}");
    for p in inst.pins().map_err(|e| e.to_string())? {
        if !matches(pats, &p.name) {
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

fn show_params(inst: &Instance, pats: &[&str]) -> Result<String, String> {
    let mut out = format!("Parameters:\n{HEADER}");
    for p in inst.params().map_err(|e| e.to_string())? {
        if matches(pats, &p.name) {
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

fn show_signals(inst: &Instance, pats: &[&str]) -> Result<String, String> {
    let mut out = String::from("Signals:\nType                  Value  Name     (linked to)\n");
    for s in inst.signals().map_err(|e| e.to_string())? {
        if !matches(pats, &s.name) {
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
        "comp" => inst
            .components()
            .map_err(e)?
            .into_iter()
            .map(|c| c.name)
            .collect(),
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

/// Finds a param, else a pin, by name or original name: (value, type,
/// is_param).
pub fn lookup(inst: &Instance, name: &str) -> Result<Option<(Value, HalType, bool)>, String> {
    let e = |e: hal_core::HalError| e.to_string();
    if let Some(p) = inst
        .params()
        .map_err(e)?
        .into_iter()
        .find(|p| p.name == name || p.orig_name.as_deref() == Some(name))
    {
        return Ok(Some((p.value, p.hal_type, true)));
    }
    Ok(inst
        .pins()
        .map_err(e)?
        .into_iter()
        .find(|p| p.name == name || p.orig_name.as_deref() == Some(name))
        .map(|p| (p.value, p.hal_type, false)))
}

/// Renders the output of `show`, `list`, `getp`, `gets`, `ptype`, `stype`.
pub fn render(inst: &Instance, words: &[&str], _opts: &Options) -> Result<String, String> {
    let args = &words[1..];
    let not_found = |n: &str| format!("parameter or pin '{n}': not found");
    match words[0] {
        "show" => {
            let (kind, pats) = match args.split_first() {
                Some((k, rest)) => (*k, rest),
                None => ("all", &[][..]),
            };
            match kind {
                "pin" => show_pins(inst, pats),
                "param" | "parameter" => show_params(inst, pats),
                "sig" | "signal" => show_signals(inst, pats),
                "all" => Ok(format!(
                    "{}{}{}",
                    show_pins(inst, pats)?,
                    show_params(inst, pats)?,
                    show_signals(inst, pats)?
                )),
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
                .map_err(|_| format!("signal '{n}' not found"))?;
            Ok(format!("{}\n", get_value(v)))
        }
        "stype" => {
            let n = args.first().ok_or("stype: needs a signal")?;
            let t = inst
                .signal_type(n)
                .map_err(|_| format!("signal '{n}' not found"))?;
            Ok(format!("{t}\n"))
        }
        other => Err(format!("{other}: not available")),
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
