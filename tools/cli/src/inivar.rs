//! inivar: print one value of an INI file, as LinuxCNC's `inivar` does for
//! shell scripts and test programs (`inivar -var SERVO_PERIOD -sec EMCMOT
//! -ini machine.ini`).
//!
//! The words and messages are LinuxCNC's: `-var` names the key, `-sec` the
//! section (without it every section is searched, in file order), `-ini`
//! the file (default `emc.ini`), `-num` which occurrence (from 1) and
//! `-tildeexpand` turns a leading `~` into `$HOME`. The value is printed as
//! the file has it (an inline comment stays part of it). Exit status 0
//! when found, 1 on a usage error or a value that is not there, 255 when
//! the file cannot be read.

use std::path::Path;

use hal_lang::ini::Ini;

/// LinuxCNC's usage line, printed on a word it does not know.
pub const USAGE: &str =
    "inivar: -var <variable> {-tildeexpand} {-sec <section>} {-ini <INI file>} [-num <nth item>]";

/// What one run asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Query {
    /// The key (`-var`).
    pub var: String,
    /// The section (`-sec`); `None` searches every section.
    pub section: Option<String>,
    /// The INI file (`-ini`).
    pub ini: String,
    /// Which occurrence, from 1 (`-num`).
    pub num: usize,
    /// Whether a leading `~` becomes `$HOME` (`-tildeexpand`).
    pub tilde_expand: bool,
}

/// What a run prints and its exit status.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Outcome {
    /// Standard output (the value and a newline, when found).
    pub stdout: String,
    /// Standard error (why not).
    pub stderr: String,
    /// The exit status.
    pub status: i32,
}

impl Outcome {
    fn fail(status: i32, message: String) -> Outcome {
        Outcome {
            stdout: String::new(),
            stderr: message + "\n",
            status,
        }
    }
}

/// Reads the command line (without the program name). `Err` is the
/// outcome of a bad one.
pub fn parse_args(args: &[String]) -> Result<Query, Outcome> {
    let usage = || Outcome::fail(1, USAGE.to_string());
    let mut var = None;
    let mut section = None;
    let mut ini = "emc.ini".to_string();
    let mut num = 1usize;
    let mut tilde_expand = false;
    let mut words = args.iter();
    while let Some(word) = words.next() {
        match word.as_str() {
            "-var" => var = Some(words.next().ok_or_else(usage)?.clone()),
            "-sec" => section = Some(words.next().ok_or_else(usage)?.clone()),
            "-ini" => ini = words.next().ok_or_else(usage)?.clone(),
            "-num" => {
                let n = words.next().ok_or_else(usage)?;
                num = n
                    .trim()
                    .parse()
                    .ok()
                    .filter(|&n| n >= 1)
                    .ok_or_else(usage)?;
            }
            "-tildeexpand" => tilde_expand = true,
            other => {
                return Err(Outcome::fail(
                    1,
                    format!("inivar: unknown option '{other}'\n{USAGE}"),
                ))
            }
        }
    }
    let var = var.ok_or_else(|| Outcome::fail(1, "inivar: no variable supplied".to_string()))?;
    Ok(Query {
        var,
        section,
        ini,
        num,
        tilde_expand,
    })
}

/// Answers `query` from the file it names; `home` is `$HOME` for
/// `-tildeexpand`.
pub fn answer(query: &Query, home: Option<&str>) -> Outcome {
    let ini = match Ini::load(Path::new(&query.ini)) {
        Ok(ini) => ini,
        Err(_) => return Outcome::fail(255, format!("inivar: can't open {}", query.ini)),
    };
    lookup(&ini, query, home)
}

/// Answers `query` from an INI already read.
pub fn lookup(ini: &Ini, query: &Query, home: Option<&str>) -> Outcome {
    let found = ini
        .entries()
        .iter()
        .filter(|e| e.key == query.var)
        .filter(|e| query.section.as_deref().is_none_or(|s| e.section == s))
        .nth(query.num - 1);
    match found {
        Some(entry) => {
            let value = match (query.tilde_expand, home, entry.value.strip_prefix('~')) {
                (true, Some(home), Some(rest)) if rest.is_empty() || rest.starts_with('/') => {
                    format!("{home}{rest}")
                }
                _ => entry.value.clone(),
            };
            Outcome {
                stdout: value + "\n",
                stderr: String::new(),
                status: 0,
            }
        }
        None => Outcome::fail(
            1,
            format!(
                "Can not find -sec {} -var {} -num {} ",
                query.section.as_deref().unwrap_or("(null)"),
                query.var,
                query.num
            ),
        ),
    }
}

#[cfg(test)]
mod tests {
    // Test code: a failed unwrap is a failed test, with its message.
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn words(line: &str) -> Vec<String> {
        line.split_whitespace().map(str::to_string).collect()
    }

    const TEXT: &str = "[A]\nP = ~/x\nV = 1 ; kept\n[B]\nV = 2\nV = 3\n";

    fn ask(line: &str) -> Outcome {
        let q = parse_args(&words(line)).unwrap();
        lookup(&Ini::parse(TEXT), &q, Some("/home/u"))
    }

    #[test]
    fn finds_first_in_any_section_and_nth_in_one() {
        assert_eq!(ask("-var V").stdout, "1 ; kept\n");
        assert_eq!(ask("-var V -sec B").stdout, "2\n");
        assert_eq!(ask("-var V -sec B -num 2").stdout, "3\n");
        assert_eq!(ask("-var V -num 3").stdout, "3\n");
    }

    #[test]
    fn missing_value_says_what_was_asked() {
        let o = ask("-var V -sec B -num 3");
        assert_eq!((o.status, o.stdout.as_str()), (1, ""));
        assert_eq!(o.stderr, "Can not find -sec B -var V -num 3 \n");
        assert_eq!(
            ask("-var W").stderr,
            "Can not find -sec (null) -var W -num 1 \n"
        );
    }

    #[test]
    fn tilde_is_expanded_only_when_asked() {
        assert_eq!(ask("-var P").stdout, "~/x\n");
        assert_eq!(ask("-var P -tildeexpand").stdout, "/home/u/x\n");
    }

    #[test]
    fn bad_command_lines() {
        let e = parse_args(&words("-sec A")).unwrap_err();
        assert_eq!(
            (e.status, e.stderr.as_str()),
            (1, "inivar: no variable supplied\n")
        );
        for bad in ["-var", "-var V -num 0", "-var V -num x"] {
            let e = parse_args(&words(bad)).unwrap_err();
            assert_eq!((e.status, e.stderr.trim_end()), (1, USAGE), "{bad}");
        }
        let e = parse_args(&words("-var V -x")).unwrap_err();
        assert_eq!(e.stderr, format!("inivar: unknown option '-x'\n{USAGE}\n"));
        let q = parse_args(&words("-var V")).unwrap();
        assert_eq!(q.ini, "emc.ini");
    }

    #[test]
    fn unreadable_file_is_status_255() {
        let mut q = parse_args(&words("-var V")).unwrap();
        q.ini = "/nonexistent/dir/x.ini".to_string();
        let o = answer(&q, None);
        assert_eq!(o.status, 255);
        assert_eq!(o.stderr, "inivar: can't open /nonexistent/dir/x.ini\n");
    }
}
