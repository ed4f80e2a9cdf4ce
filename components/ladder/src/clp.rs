//! The `.clp` project bundle ClassicLadder saves: one text file holding
//! the files of a project directory, each between `_FILE-name` and
//! `_/FILE-name` lines, the whole between `_FILES_CLASSICLADDER` and
//! `_/FILES_CLASSICLADDER`. This module reads the bundle into a
//! [`Project`] of raw numbers, each remembering its line; the checks
//! against a module's sizes are [`crate::compile`]'s.
//!
//! Parts read: `rung_N.csv` (`#NEXTRUNG=`, then rows of
//! `type-top-vartype/varnum` cells), `sections.csv`, `timers.csv`,
//! `monostables.csv`, `counters.csv`, `timers_iec.csv`,
//! `arithmetic_expressions.csv`, `symbols.csv`, `sequential.csv`,
//! `general.txt`. `ioconf.csv`, `modbusioconf.csv` and `com_params.txt`
//! configure I/O this runtime does not have; their content is noted.
//! Lines starting with `;` are comments everywhere.

use crate::error::LadderError;
use crate::model::{RUNG_HEIGHT, RUNG_WIDTH};

/// The most rungs, sections or parameter lines a bundle may hold.
pub const MAX_ITEMS: usize = 10_000;

/// One cell as written: `type-top-vartype/varnum`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RawCell {
    /// Element type code.
    pub code: i64,
    /// The vertical wire to the row above.
    pub top: bool,
    /// Variable type code.
    pub var_code: i64,
    /// Variable (or timer, rung, expression...) number.
    pub num: i64,
}

/// One rung as written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RungText {
    /// Its number (from `rung_N.csv`).
    pub number: usize,
    /// `#NEXTRUNG=`.
    pub next: i64,
    /// `#LABEL=`.
    pub label: String,
    /// `#COMMENT=`.
    pub comment: String,
    /// Its rows: the line each came from, and the cells.
    pub rows: Vec<(usize, [RawCell; RUNG_WIDTH])>,
    /// The line of `_FILE-rung_N.csv`.
    pub line: usize,
}

/// One line of `sections.csv`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SectionText {
    /// Line.
    pub line: usize,
    /// Section number.
    pub number: i64,
    /// 0 ladder, 1 sequential.
    pub language: i64,
    /// -1 for a main section, else the sub-routine number.
    pub sub: i64,
    /// First rung.
    pub first: i64,
    /// Last rung.
    pub last: i64,
}

/// A numbered line of parameters (`timers.csv` and the like).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Params {
    /// Line.
    pub line: usize,
    /// The numbers on it.
    pub values: Vec<i64>,
}

/// One line of `arithmetic_expressions.csv`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExprText {
    /// Line.
    pub line: usize,
    /// Expression number.
    pub number: usize,
    /// The text.
    pub text: String,
}

/// One line of `symbols.csv`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Symbol {
    /// Line.
    pub line: usize,
    /// The variable (`%I0`).
    pub var: String,
    /// Its symbol.
    pub name: String,
    /// Its comment.
    pub comment: String,
}

/// A whole bundle, as written.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Project {
    /// The rungs, in file order.
    pub rungs: Vec<RungText>,
    /// The sections.
    pub sections: Vec<SectionText>,
    /// The arithmetic expressions.
    pub exprs: Vec<ExprText>,
    /// `timers.csv`: base id, preset.
    pub timers: Vec<Params>,
    /// `monostables.csv`: base id, preset.
    pub monostables: Vec<Params>,
    /// `counters.csv`: preset.
    pub counters: Vec<Params>,
    /// `timers_iec.csv`: base id, preset, mode.
    pub timers_iec: Vec<Params>,
    /// The symbols.
    pub symbols: Vec<Symbol>,
    /// Lines of `sequential.csv` that hold steps or transitions.
    pub sequential: Vec<usize>,
    /// `PERIODIC_REFRESH` of `general.txt`, if given.
    pub periodic_refresh_ms: Option<i64>,
    /// Parts read but not acted on, said once each.
    pub notes: Vec<String>,
}

fn syntax(line: usize, part: &str, what: impl Into<String>) -> LadderError {
    LadderError::Syntax {
        line,
        part: part.to_string(),
        what: what.into(),
    }
}

fn int(text: &str, line: usize, part: &str, what: &str) -> Result<i64, LadderError> {
    let t = text.trim();
    t.parse::<i64>()
        .map_err(|_| syntax(line, part, format!("{what} '{t}' is not an integer")))
}

/// Parses a bundle.
pub fn parse(text: &str) -> Result<Project, LadderError> {
    let mut p = Project::default();
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')));
    let mut seen_header = false;
    while let Some((n, line)) = lines.next() {
        let t = line.trim();
        if t.is_empty() {
            continue;
        }
        if t == "_FILES_CLASSICLADDER" {
            seen_header = true;
            continue;
        }
        if t == "_/FILES_CLASSICLADDER" {
            return if seen_header {
                Ok(p)
            } else {
                Err(syntax(
                    n,
                    "bundle",
                    "end of bundle without _FILES_CLASSICLADDER",
                ))
            };
        }
        let Some(name) = t.strip_prefix("_FILE-") else {
            return Err(syntax(
                n,
                "bundle",
                format!("'{t}' is outside any _FILE- part (is this a ClassicLadder .clp file?)"),
            ));
        };
        if !seen_header {
            return Err(syntax(n, "bundle", "_FILE- before _FILES_CLASSICLADDER"));
        }
        let end = format!("_/FILE-{name}");
        let mut body = Vec::new();
        let mut closed = false;
        for (m, l) in lines.by_ref() {
            if l.trim() == end {
                closed = true;
                break;
            }
            if l.starts_with("_FILE-") || l.starts_with("_/FILE") {
                return Err(syntax(m, name, format!("'{}' before {end}", l.trim())));
            }
            body.push((m, l));
        }
        if !closed {
            return Err(syntax(n, name, format!("{end} is missing")));
        }
        part(&mut p, n, name, &body)?;
        if p.rungs.len() > MAX_ITEMS || p.exprs.len() > MAX_ITEMS {
            return Err(syntax(
                n,
                name,
                format!("more than {MAX_ITEMS} rungs or expressions"),
            ));
        }
    }
    Err(syntax(
        text.lines().count(),
        "bundle",
        "_/FILES_CLASSICLADDER is missing (file truncated?)",
    ))
}

/// The data lines of a part: not blank, not `;` comments.
fn data<'a>(body: &'a [(usize, &'a str)]) -> impl Iterator<Item = (usize, &'a str)> + 'a {
    body.iter()
        .map(|&(n, l)| (n, l))
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with(';'))
}

fn part(p: &mut Project, n: usize, name: &str, body: &[(usize, &str)]) -> Result<(), LadderError> {
    if let Some(num) = name
        .strip_prefix("rung_")
        .and_then(|r| r.strip_suffix(".csv"))
    {
        let number = int(num, n, name, "rung number")?;
        if !(0..MAX_ITEMS as i64).contains(&number) {
            return Err(syntax(
                n,
                name,
                format!("rung number {number} is out of range"),
            ));
        }
        if p.rungs.iter().any(|r| r.number == number as usize) {
            return Err(syntax(n, name, format!("rung {number} is given twice")));
        }
        p.rungs.push(rung(n, name, number as usize, body)?);
        return Ok(());
    }
    match name {
        "sections.csv" => {
            for (m, l) in data(body).filter(|(_, l)| !l.starts_with('#')) {
                let v = numbers(l, m, name, 6)?;
                p.sections.push(SectionText {
                    line: m,
                    number: v[0],
                    language: v[1],
                    sub: v[2],
                    first: v[3],
                    last: v[4],
                });
            }
        }
        "timers.csv" => p.timers = param_lines(body, name, 2)?,
        "monostables.csv" => p.monostables = param_lines(body, name, 2)?,
        "counters.csv" => p.counters = param_lines(body, name, 1)?,
        "timers_iec.csv" => p.timers_iec = param_lines(body, name, 3)?,
        "arithmetic_expressions.csv" => p.exprs = exprs(body, name)?,
        "symbols.csv" => {
            for (m, l) in data(body).filter(|(_, l)| !l.starts_with('#')) {
                let mut f = l.splitn(3, ',');
                p.symbols.push(Symbol {
                    line: m,
                    var: f.next().unwrap_or("").trim().to_string(),
                    name: f.next().unwrap_or("").trim().to_string(),
                    comment: f.next().unwrap_or("").trim().to_string(),
                });
            }
        }
        "sequential.csv" => {
            p.sequential = data(body)
                .filter(|(_, l)| !l.starts_with('#'))
                .map(|(m, _)| m)
                .collect();
        }
        "general.txt" => {
            for (m, l) in data(body) {
                if let Some(v) = l.trim().strip_prefix("PERIODIC_REFRESH=") {
                    p.periodic_refresh_ms = Some(int(v, m, name, "PERIODIC_REFRESH")?);
                }
            }
        }
        "ioconf.csv" | "modbusioconf.csv" => {
            if data(body).any(|(_, l)| !l.starts_with('#')) {
                p.notes.push(format!(
                    "{name}: its I/O (direct ports, comedi, Modbus) is not run here; \
                     connect the %I/%Q pins in HAL instead"
                ));
            }
        }
        "com_params.txt" => {}
        _ => p.notes.push(format!(
            "part '{name}' (line {n}) is not known and was skipped"
        )),
    }
    Ok(())
}

fn numbers(l: &str, m: usize, part: &str, want: usize) -> Result<Vec<i64>, LadderError> {
    let fields: Vec<&str> = l.split(',').collect();
    if fields.len() != want {
        return Err(syntax(
            m,
            part,
            format!(
                "{} numbers where {want} were expected: '{}'",
                fields.len(),
                l.trim()
            ),
        ));
    }
    fields.iter().map(|f| int(f, m, part, "value")).collect()
}

fn param_lines(
    body: &[(usize, &str)],
    part: &str,
    want: usize,
) -> Result<Vec<Params>, LadderError> {
    let mut v = Vec::new();
    for (m, l) in data(body).filter(|(_, l)| !l.starts_with('#')) {
        if v.len() >= MAX_ITEMS {
            return Err(syntax(m, part, format!("more than {MAX_ITEMS} lines")));
        }
        v.push(Params {
            line: m,
            values: numbers(l, m, part, want)?,
        });
    }
    Ok(v)
}

fn exprs(body: &[(usize, &str)], part: &str) -> Result<Vec<ExprText>, LadderError> {
    let v2 = body.iter().any(|(_, l)| l.trim().starts_with("#VER=2"));
    let mut out = Vec::new();
    let mut next = 0usize;
    for &(m, l) in body {
        let t = l.trim_end();
        if t.trim_start().starts_with(';') || t.starts_with("#VER=") {
            continue;
        }
        if v2 {
            if t.trim().is_empty() {
                continue;
            }
            let (num, text) = t
                .split_once(',')
                .ok_or_else(|| syntax(m, part, "expected NUMBER,EXPRESSION"))?;
            let number = int(num, m, part, "expression number")?;
            if !(0..MAX_ITEMS as i64).contains(&number) {
                return Err(syntax(
                    m,
                    part,
                    format!("expression number {number} is out of range"),
                ));
            }
            out.push(ExprText {
                line: m,
                number: number as usize,
                text: text.to_string(),
            });
        } else {
            // The first format: one expression per line, by position.
            if !t.trim().is_empty() {
                out.push(ExprText {
                    line: m,
                    number: next,
                    text: t.trim().to_string(),
                });
            }
            next += 1;
            if next > MAX_ITEMS {
                return Err(syntax(m, part, format!("more than {MAX_ITEMS} lines")));
            }
        }
    }
    Ok(out)
}

fn rung(
    n: usize,
    part: &str,
    number: usize,
    body: &[(usize, &str)],
) -> Result<RungText, LadderError> {
    let mut r = RungText {
        number,
        next: -1,
        label: String::new(),
        comment: String::new(),
        rows: Vec::new(),
        line: n,
    };
    for (m, l) in data(body) {
        if let Some(h) = l.strip_prefix('#') {
            if let Some(v) = h.strip_prefix("VER=") {
                let major = v.split('.').next().unwrap_or("");
                if int(major, m, part, "version")? > 2 {
                    return Err(syntax(
                        m,
                        part,
                        format!("rung format version {v} is newer than 2"),
                    ));
                }
            } else if let Some(v) = h.strip_prefix("NEXTRUNG=") {
                r.next = int(v, m, part, "NEXTRUNG")?;
            } else if let Some(v) = h.strip_prefix("LABEL=") {
                r.label = v.to_string();
            } else if let Some(v) = h.strip_prefix("COMMENT=") {
                r.comment = v.to_string();
            }
            continue;
        }
        if r.rows.len() == RUNG_HEIGHT {
            return Err(syntax(
                m,
                part,
                format!("more than {RUNG_HEIGHT} rows of cells"),
            ));
        }
        let fields: Vec<&str> = l.split(',').collect();
        if fields.len() != RUNG_WIDTH {
            return Err(syntax(
                m,
                part,
                format!(
                    "{} cells in a row; a rung is {RUNG_WIDTH} wide",
                    fields.len()
                ),
            ));
        }
        let mut row = [RawCell::default(); RUNG_WIDTH];
        for (x, f) in fields.iter().enumerate() {
            row[x] = cell(f, m, part, x)?;
        }
        r.rows.push((m, row));
    }
    Ok(r)
}

fn cell(f: &str, m: usize, part: &str, x: usize) -> Result<RawCell, LadderError> {
    let f = f.trim();
    let bad = || {
        syntax(
            m,
            part,
            format!("cell {x} '{f}' is not type-top-vartype/varnum"),
        )
    };
    let (head, num) = f.split_once('/').ok_or_else(bad)?;
    let mut it = head.splitn(3, '-');
    let (Some(code), Some(top), Some(var_code)) = (it.next(), it.next(), it.next()) else {
        return Err(bad());
    };
    let what = format!("cell {x}");
    let top = int(top, m, part, &what)?;
    if !(0..=1).contains(&top) {
        return Err(syntax(
            m,
            part,
            format!("cell {x}: the wire-to-top flag is {top}, not 0 or 1"),
        ));
    }
    Ok(RawCell {
        code: int(code, m, part, &what)?,
        top: top == 1,
        var_code: int(var_code, m, part, &what)?,
        num: int(num, m, part, &what)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "_FILES_CLASSICLADDER\n_FILE-rung_0.csv\n#VER=2.0\n#NEXTRUNG=-1\n\
        1-0-50/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 9-0-0/0 , 50-0-60/0\n\
        _/FILE-rung_0.csv\n_FILE-sections.csv\n#VER=1.0\n#NAME000=Prog1\n000,0,-1,0,0,0\n_/FILE-sections.csv\n\
        _/FILES_CLASSICLADDER\n";

    #[test]
    fn reads_a_small_bundle() {
        let p = parse(SMALL).unwrap();
        assert_eq!(p.rungs.len(), 1);
        assert_eq!(p.rungs[0].rows.len(), 1);
        assert_eq!(
            p.rungs[0].rows[0].1[9],
            RawCell {
                code: 50,
                top: false,
                var_code: 60,
                num: 0
            }
        );
        assert_eq!(p.sections[0].first, 0);
    }

    #[test]
    fn errors_name_the_line() {
        let bad = SMALL.replace("9-0-0/0 , 50-0-60/0", "9-0-0 , 50-0-60/0");
        let e = parse(&bad).unwrap_err().to_string();
        assert!(e.starts_with("line 5 (rung_0.csv): cell 8"), "{e}");
        let cut = &SMALL[..SMALL.len() - 22];
        assert!(parse(cut).unwrap_err().to_string().contains("missing"));
        let e = parse("hello\n").unwrap_err().to_string();
        assert!(e.contains("line 1") && e.contains("outside"), "{e}");
        let top = SMALL.replace("1-0-50/0", "1-2-50/0");
        assert!(parse(&top).unwrap_err().to_string().contains("not 0 or 1"));
        let wide = SMALL.replace("50-0-60/0\n", "50-0-60/0 , 0-0-0/0\n");
        assert!(parse(&wide).unwrap_err().to_string().contains("11 cells"));
    }
}
