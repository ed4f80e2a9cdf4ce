//! A module's section 9 page: its declaration (name, description, module
//! parameters) and what its example load exports, in roff.

use std::collections::BTreeSet;

use hal_core::{FunctInfo, Instance, ParamInfo, ParamKind, PinInfo, ThreadInfo};

use super::examples::Example;

/// What one load added to an instance.
pub struct Listing {
    functs: Vec<FunctInfo>,
    pins: Vec<PinInfo>,
    params: Vec<ParamInfo>,
    threads: Vec<ThreadInfo>,
}

impl Listing {
    /// The objects of `inst` named in `added` (`"pin NAME"`, ...).
    pub fn of(inst: &Instance, added: &BTreeSet<String>) -> hal_core::Result<Listing> {
        let has = |kind: &str, name: &str| added.contains(&format!("{kind} {name}"));
        Ok(Listing {
            functs: inst
                .functs()?
                .into_iter()
                .filter(|f| has("funct", &f.name))
                .collect(),
            pins: inst
                .pins()?
                .into_iter()
                .filter(|p| has("pin", &p.name))
                .collect(),
            params: inst
                .params()?
                .into_iter()
                .filter(|p| has("param", &p.name))
                .collect(),
            threads: inst
                .threads()?
                .into_iter()
                .filter(|t| has("thread", &t.name))
                .collect(),
        })
    }
}

/// One module's page.
pub struct ModulePage<'a> {
    /// The module's declaration.
    pub module: &'static hal_core::ModuleDef,
    /// How it was loaded.
    pub example: Example,
    /// What the load exported.
    pub listing: &'a Listing,
}

/// Escapes text for roff (backslashes, a leading `.` or `'`, hyphens kept
/// searchable).
fn esc(text: &str) -> String {
    let t = text.replace('\\', "\\e").replace('-', "\\-");
    if t.starts_with('.') || t.starts_with('\'') {
        format!("\\&{t}")
    } else {
        t
    }
}

/// A module parameter's type as the page names it.
fn kind(k: ParamKind) -> String {
    match k {
        ParamKind::Int => "int".into(),
        ParamKind::Long => "long".into(),
        ParamKind::Str => "string".into(),
        ParamKind::IntArray(n) => format!("up to {n} ints, comma separated"),
        ParamKind::LongArray(n) => format!("up to {n} longs, comma separated"),
        ParamKind::StrArray(n) => format!("up to {n} strings, comma separated"),
    }
}

impl ModulePage<'_> {
    /// The page in roff.
    pub fn render(&self) -> String {
        let m = self.module;
        let mut out = format!(
            ".TH {} 9 \"\" \"hal-suite {}\" \"HAL suite: loadrt modules\"\n.SH NAME\n{} \\- {}\n",
            m.name.to_uppercase(),
            env!("CARGO_PKG_VERSION"),
            esc(m.name),
            esc(m.help.trim_end_matches('.'))
        );
        out.push_str(&format!(".SH SYNOPSIS\n\\fBloadrt {}\\fR", esc(m.name)));
        for p in m.params {
            out.push_str(&format!(" [\\fB{}\\fR=\\fIVALUE\\fR]", esc(p.name)));
        }
        out.push('\n');
        self.parameters(&mut out);
        self.exports(&mut out);
        out.push_str(
            ".SH \"SEE ALSO\"\nhalcmd(1), halrun(1); \\fBhalcmd show\\fR lists what a \
             configuration's own load exports.\n",
        );
        out
    }

    fn parameters(&self, out: &mut String) {
        out.push_str(".SH \"MODULE PARAMETERS\"\n");
        if self.module.params.is_empty() {
            out.push_str("None.\n");
        }
        for p in self.module.params {
            out.push_str(&format!(
                ".TP\n\\fB{}\\fR ({})\n",
                esc(p.name),
                kind(p.kind)
            ));
            let help = if p.help.is_empty() {
                "(undocumented)"
            } else {
                p.help
            };
            out.push_str(&esc(help));
            out.push('\n');
        }
    }

    fn exports(&self, out: &mut String) {
        let l = self.listing;
        let ex = &self.example;
        out.push_str(".SH EXPORTS\n");
        let mut line = format!("loadrt {} {}", self.module.name, ex.args);
        if ex.eth_board.is_some() {
            line.push_str(" board_ip=ADDRESS");
        }
        out.push_str(&format!(
            "What \\fB{}\\fR exports{}, as \\fBhalcmd show\\fR lists it \
             (types, directions and the values right after the load).\n",
            esc(line.trim_end()),
            if ex.before.is_empty() {
                String::new()
            } else {
                format!(
                    " after \\fB{}\\fR",
                    esc(&ex.before.trim().lines().collect::<Vec<_>>().join("; "))
                )
            }
        ));
        if !ex.note.is_empty() {
            out.push_str(&format!(".PP\n{}\n", esc(ex.note)));
        }
        if l.functs.is_empty() && l.pins.is_empty() && l.params.is_empty() && l.threads.is_empty() {
            out.push_str(".PP\nNothing.\n");
        }
        if !l.functs.is_empty() {
            out.push_str(".SS Functions\n.nf\n");
            for f in &l.functs {
                let fp = if f.uses_fp {
                    "uses floating point"
                } else {
                    "no floating point"
                };
                out.push_str(&format!("{}  ({fp})\n", esc(&f.name)));
            }
            out.push_str(".fi\n");
        }
        table(
            out,
            "Pins",
            l.pins
                .iter()
                .map(|p| (p.hal_type.to_string(), p.dir.label(), &p.name, p.value)),
        );
        table(
            out,
            "Parameters",
            l.params
                .iter()
                .map(|p| (p.hal_type.to_string(), p.dir.label(), &p.name, p.value)),
        );
        if !l.threads.is_empty() {
            out.push_str(".SS Threads\n.nf\n");
            for t in &l.threads {
                out.push_str(&format!("{}  (period {} ns)\n", esc(&t.name), t.period));
            }
            out.push_str(".fi\n");
        }
    }
}

/// A section of `TYPE DIR NAME = VALUE` rows.
fn table<'n>(
    out: &mut String,
    title: &str,
    rows: impl Iterator<Item = (String, &'static str, &'n String, hal_core::Value)>,
) {
    let rows: Vec<_> = rows.collect();
    if rows.is_empty() {
        return;
    }
    out.push_str(&format!(".SS {title}\n.nf\n"));
    for (t, dir, name, value) in rows {
        out.push_str(&format!(
            "{t:<5} {dir:<3} {} = {}\n",
            esc(name),
            esc(&hal_lang::format::get_value(value))
        ));
    }
    out.push_str(".fi\n");
}
