//! A man page made from a program's `--help` text, for the programs that
//! read their command line by hand (the clap ones get theirs from
//! clap_mangen). The help texts share one shape (`hal_tools::usage`):
//!
//! ```text
//! usage: NAME ...          (or "Usage:" and indented lines)
//!        NAME ...          (more forms)
//!
//! Description, one or more paragraphs.
//!
//! options:                 (a heading: a short line ending in ':')
//!   -x, --long VALUE   what it does
//!                      more of it
//!
//! examples:
//!   NAME -x 1              (other sections are kept as laid out)
//! ```

/// Escapes text for roff: backslashes, and a leading `.` or `'` that
/// would read as a request.
fn escape(text: &str) -> String {
    let t = text.replace('\\', "\\e");
    if t.starts_with('.') || t.starts_with('\'') {
        format!("\\&{t}")
    } else {
        t
    }
}

/// Option words keep their hyphens (`\-`), so they can be searched for.
fn escape_option(text: &str) -> String {
    escape(text).replace('-', "\\-")
}

/// Whether `line` is a section heading: at the left edge, short, ending
/// in `:`, not a sentence.
fn is_heading(line: &str) -> bool {
    !line.starts_with(' ')
        && line.ends_with(':')
        && line.len() <= 30
        && line.split_whitespace().count() <= 3
        && !line[..line.len() - 1].contains([':', '.'])
}

/// The usage lines at the top of `lines`, and how many lines they took.
fn synopsis(name: &str, lines: &[&str]) -> (Vec<String>, usize) {
    let mut forms = Vec::new();
    let mut used = 0;
    for (i, line) in lines.iter().enumerate() {
        let t = line.trim();
        let lower = t.to_lowercase();
        let form = if i == 0 && lower == "usage:" {
            None
        } else if i == 0 && lower.starts_with("usage:") {
            Some(t[6..].trim())
        } else if i > 0 && line.starts_with(' ') && t.starts_with(name) {
            Some(t)
        } else {
            break;
        };
        forms.extend(form.map(str::to_string));
        used = i + 1;
    }
    (forms, used)
}

/// One section: its title and lines.
struct Section<'t> {
    title: String,
    lines: Vec<&'t str>,
}

/// Splits the text after the synopsis into the description and the
/// headed sections.
fn sections<'t>(lines: &[&'t str]) -> Vec<Section<'t>> {
    let mut out = vec![Section {
        title: "DESCRIPTION".into(),
        lines: Vec::new(),
    }];
    for line in lines {
        if is_heading(line) {
            out.push(Section {
                title: line.trim_end_matches(':').to_uppercase(),
                lines: Vec::new(),
            });
        } else if let Some(last) = out.last_mut() {
            last.lines.push(line);
        }
    }
    for s in &mut out {
        while s.lines.first().is_some_and(|l| l.trim().is_empty()) {
            s.lines.remove(0);
        }
        while s.lines.last().is_some_and(|l| l.trim().is_empty()) {
            s.lines.pop();
        }
    }
    out.retain(|s| !s.lines.is_empty());
    out
}

/// Whether `line` starts an option's entry: an option word a little
/// indented (`  -x`, or `      --long` lined up under short ones);
/// descriptions go on further right.
fn is_option_entry(line: &str) -> bool {
    let indent = line.len() - line.trim_start().len();
    (1..8).contains(&indent) && line.trim_start().starts_with('-')
}

/// Whether a section lists options: its first entry is one.
fn lists_options(lines: &[&str]) -> bool {
    lines
        .iter()
        .find(|l| !l.trim().is_empty())
        .is_some_and(|l| is_option_entry(l))
}

/// Paragraphs at the left edge are filled; indented lines kept as laid
/// out.
fn render_text(lines: &[&str], out: &mut String) {
    let mut literal = false;
    let mut gap = false;
    for line in lines {
        if line.trim().is_empty() {
            if literal {
                out.push('\n');
            } else {
                gap = true;
            }
            continue;
        }
        let indented = line.starts_with(' ');
        if indented && !literal {
            out.push_str(".PP\n.RS 4\n.nf\n");
            literal = true;
            gap = false;
        } else if !indented && literal {
            out.push_str(".fi\n.RE\n");
            literal = false;
            gap = true;
        }
        if gap {
            out.push_str(".PP\n");
            gap = false;
        }
        let text = if literal {
            line.get(2..).unwrap_or(line)
        } else {
            line
        };
        out.push_str(&escape(text));
        out.push('\n');
    }
    if literal {
        out.push_str(".fi\n.RE\n");
    }
}

/// Option entries as tagged paragraphs: the option words in bold, the
/// description (after a gap of two spaces, or on the lines below) as the
/// paragraph.
fn render_options(lines: &[&str], out: &mut String) {
    for line in lines {
        let t = line.trim();
        if t.is_empty() {
            continue;
        }
        if is_option_entry(line) {
            let (term, text) = match t.find("  ") {
                Some(at) => (&t[..at], t[at..].trim()),
                None => (t, ""),
            };
            out.push_str(".TP\n\\fB");
            out.push_str(&escape_option(term));
            out.push_str("\\fR\n");
            if !text.is_empty() {
                out.push_str(&escape(text));
                out.push('\n');
            }
        } else {
            out.push_str(&escape(t));
            out.push('\n');
        }
    }
}

/// The man page of `name` (section 1) from its help text; `summary` is
/// the NAME line's description.
pub fn man_page(name: &str, summary: &str, help: &str, see_also: &[&str]) -> String {
    let lines: Vec<&str> = help.lines().collect();
    let (forms, used) = synopsis(name, &lines);
    let mut out = format!(
        ".TH {} 1 \"\" \"hal-suite {}\" \"HAL suite\"\n.SH NAME\n{} \\- {}\n.SH SYNOPSIS\n",
        name.to_uppercase(),
        env!("CARGO_PKG_VERSION"),
        escape_option(name),
        escape(summary)
    );
    for (i, form) in forms.iter().enumerate() {
        if i > 0 {
            out.push_str(".br\n");
        }
        let rest = form.strip_prefix(name).unwrap_or(form).trim();
        out.push_str(&format!(
            "\\fB{}\\fR {}\n",
            escape_option(name),
            escape_option(rest)
        ));
    }
    for section in sections(&lines[used..]) {
        out.push_str(&format!(".SH {}\n", section.title));
        if lists_options(&section.lines) {
            render_options(&section.lines, &mut out);
        } else {
            render_text(&section.lines, &mut out);
        }
    }
    if !see_also.is_empty() {
        out.push_str(".SH \"SEE ALSO\"\n");
        let refs: Vec<String> = see_also.iter().map(|r| escape_option(r)).collect();
        out.push_str(&refs.join(", "));
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_help_text_becomes_a_page() {
        let help = "usage: tool [-x N] FILE\n       tool -U\n\nDoes things.\nTwo lines.\n\n  tool a   indented\n\noptions:\n  -x N        the n\n              more\n  --long\n              on the next line\n\nexamples:\n  tool -x 1 f\n";
        let page = man_page("tool", "does things", help, &["halcmd(1)"]);
        for want in [
            ".TH TOOL 1",
            "tool \\- does things",
            "\\fBtool\\fR [\\-x N] FILE\n.br\n\\fBtool\\fR \\-U",
            ".SH DESCRIPTION\nDoes things.\nTwo lines.\n.PP\n.RS 4\n.nf\ntool a   indented\n.fi\n.RE\n",
            ".SH OPTIONS\n.TP\n\\fB\\-x N\\fR\nthe n\nmore\n.TP\n\\fB\\-\\-long\\fR\non the next line\n",
            ".SH EXAMPLES\n.PP\n.RS 4\n.nf\ntool -x 1 f\n",
            ".SH \"SEE ALSO\"\nhalcmd(1)\n",
        ] {
            assert!(page.contains(want), "no {want:?} in\n{page}");
        }
    }

    #[test]
    fn headings_are_short_lines_ending_in_a_colon() {
        assert!(is_heading("options:"));
        assert!(is_heading("Required:"));
        assert!(!is_heading("  options:"));
        assert!(!is_heading(
            "Options whose values come from a list take any unique beginning:"
        ));
        assert!(!is_heading("e.g.:"));
    }
}
