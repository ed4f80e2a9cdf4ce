//! LinuxCNC's INI files: sections of `KEY = value` lines, `#`/`;` comment
//! lines, values continued over several lines with a trailing backslash,
//! escapes in values, and `#INCLUDE` of other files (at most 16 deep,
//! recursion refused). Every entry remembers the file and line it came
//! from, so a bad value is reported where it is.
//!
//! A key may appear several times: [`Ini::get`] returns the first value
//! (as LinuxCNC's `Find`), [`Ini::all`] every one in order (as
//! `[HAL]HALFILE`).

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use parser::{normalize, Parser};

mod escape;
mod parser;

/// How deep `#INCLUDE`s may nest (LinuxCNC's limit).
pub const MAX_INCLUDE_DEPTH: usize = 16;

/// Where an entry (or a problem) is: a file as it was named and a line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Origin {
    /// The file, as it was named (the INI path, or an `#INCLUDE` argument
    /// resolved to a path).
    pub file: Arc<str>,
    /// The 1-based line number (of the first line of a continued value).
    pub line: usize,
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file, self.line)
    }
}

/// One `KEY = value` line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entry {
    /// The section it is in (empty before the first section header).
    pub section: String,
    /// The key.
    pub key: String,
    /// The value, trimmed, continuation lines joined, escapes resolved.
    pub value: String,
    /// Where it was written.
    pub origin: Origin,
}

/// Why an INI file could not be read, or a value not used.
#[derive(Debug, thiserror::Error)]
pub enum IniError {
    /// The file (or an included one) could not be read.
    #[error("{}cannot read INI file {}: {source}", at(.origin), .path.display())]
    Io {
        /// The `#INCLUDE` line, for an included file.
        origin: Option<Origin>,
        /// The file.
        path: PathBuf,
        /// What went wrong.
        #[source]
        source: std::io::Error,
    },
    /// `#INCLUDE`s nest deeper than [`MAX_INCLUDE_DEPTH`].
    #[error("{origin}: #INCLUDE nested more than {max} levels deep")]
    IncludeTooDeep {
        /// The `#INCLUDE` line.
        origin: Origin,
        /// The limit.
        max: usize,
    },
    /// A file includes itself, directly or through others.
    #[error("{origin}: recursive #INCLUDE of {}", .path.display())]
    IncludeCycle {
        /// The `#INCLUDE` line.
        origin: Origin,
        /// The file already being read.
        path: PathBuf,
    },
    /// `#INCLUDE` without a file name.
    #[error("{origin}: #INCLUDE needs a file name")]
    IncludeWithoutName {
        /// The line.
        origin: Origin,
    },
    /// An escape in a value that does not make a character.
    #[error("{origin}: [{section}]{key}: bad escape {escape:?} in the value")]
    BadEscape {
        /// The line.
        origin: Origin,
        /// The section.
        section: String,
        /// The key.
        key: String,
        /// The escape as written.
        escape: String,
    },
    /// A value that is not valid UTF-8 after its escapes are resolved, or
    /// contains a NUL.
    #[error("{origin}: [{section}]{key}: the value {problem}")]
    BadText {
        /// The line.
        origin: Origin,
        /// The section.
        section: String,
        /// The key.
        key: String,
        /// What is wrong with it.
        problem: &'static str,
    },
    /// A value that does not have the type its user needs.
    #[error("{origin}: [{section}]{key} = {value:?} is not {expected}")]
    BadValue {
        /// Where the value is.
        origin: Origin,
        /// The section.
        section: String,
        /// The key.
        key: String,
        /// The value.
        value: String,
        /// What was expected ("a number", "a boolean", ...).
        expected: &'static str,
    },
    /// A value that must be there is not.
    #[error("{file}: [{section}]{key} is missing")]
    Missing {
        /// The INI file.
        file: String,
        /// The section.
        section: String,
        /// The key.
        key: String,
    },
}

fn at(origin: &Option<Origin>) -> String {
    origin
        .as_ref()
        .map(|o| format!("{o}: "))
        .unwrap_or_default()
}

/// A note about a line that was not understood and was skipped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IniWarning {
    /// The line.
    pub origin: Origin,
    /// What was wrong.
    pub message: String,
}

impl fmt::Display for IniWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.origin, self.message)
    }
}

/// A parsed INI file with its includes expanded.
#[derive(Debug, Clone, Default)]
pub struct Ini {
    entries: Vec<Entry>,
    sections: Vec<String>,
    warnings: Vec<IniWarning>,
    path: Option<PathBuf>,
}

/// Reads the file an `#INCLUDE` names (the real file system, or a map in
/// tests and fuzzing).
pub type Reader<'a> = dyn FnMut(&Path) -> std::io::Result<String> + 'a;

impl Ini {
    /// Parses INI text that stands alone (an `#INCLUDE` is reported as a
    /// warning). Problems with values become warnings too; for errors use
    /// [`Ini::load`] or [`Ini::parse_with`].
    pub fn parse(text: &str) -> Ini {
        let mut ini = Ini::default();
        let mut refuse = |p: &Path| -> std::io::Result<String> {
            Err(std::io::Error::new(
                std::io::ErrorKind::Unsupported,
                format!("#INCLUDE {} in text without a file", p.display()),
            ))
        };
        let mut parser = Parser {
            ini: &mut ini,
            read: &mut refuse,
            stack: Vec::new(),
            lenient: true,
            section: String::new(),
        };
        // Lenient parsing never fails.
        let _ = parser.text(text, Arc::from("<ini>"), Path::new("."), 0);
        ini
    }

    /// Reads the INI file at `path` and everything it includes.
    pub fn load(path: &Path) -> Result<Ini, IniError> {
        // Bytes that are not UTF-8 (a Latin-1 comment) read as U+FFFD,
        // as in HAL files, instead of failing the whole file. Only
        // regular files of a bounded size are read (`#INCLUDE /dev/zero`
        // is refused with the reason).
        use hal_core::files::{limits, read_user_text};
        let mut read = |p: &Path| Ok(read_user_text(p, limits::INI, "INI file")?);
        let mut ini = Ini::parse_with(path, &mut read)?;
        ini.path = Some(path.to_path_buf());
        Ok(ini)
    }

    /// Reads the INI file at `path` through `read` (which also serves the
    /// included files).
    pub fn parse_with(path: &Path, read: &mut Reader<'_>) -> Result<Ini, IniError> {
        let text = read(path).map_err(|source| IniError::Io {
            origin: None,
            path: path.to_path_buf(),
            source,
        })?;
        let mut ini = Ini {
            path: Some(path.to_path_buf()),
            ..Ini::default()
        };
        let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        let mut parser = Parser {
            ini: &mut ini,
            read,
            stack: vec![normalize(path)],
            lenient: false,
            section: String::new(),
        };
        let name: Arc<str> = Arc::from(path.to_string_lossy().as_ref());
        parser.text(&text, name, &dir, 0)?;
        Ok(ini)
    }

    /// The same file with `entries` in place of its own: a configuration
    /// read in an older format and converted in memory (the launcher's
    /// update of pre-2.8 INI files). The file name and the warnings stay;
    /// the sections are those of the new entries, in order, plus the
    /// sections the file had without any entry.
    pub fn with_entries(&self, entries: Vec<Entry>) -> Ini {
        let mut sections: Vec<String> = Vec::new();
        let empty = self
            .sections
            .iter()
            .filter(|s| !self.entries.iter().any(|e| &e.section == *s));
        for s in entries.iter().map(|e| &e.section).chain(empty) {
            if !sections.contains(s) {
                sections.push(s.clone());
            }
        }
        Ini {
            entries,
            sections,
            warnings: self.warnings.clone(),
            path: self.path.clone(),
        }
    }

    /// The file this INI was read from.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// The directory of the INI file (`.` for text without a file).
    pub fn dir(&self) -> PathBuf {
        match self.path.as_deref().and_then(Path::parent) {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        }
    }

    /// A short name for messages: the file name as given, or `INI`.
    pub fn name(&self) -> String {
        self.path
            .as_deref()
            .map(|p| p.to_string_lossy().into_owned())
            .unwrap_or_else(|| "INI".to_string())
    }

    /// Every entry, in file order (includes expanded in place).
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// Section names in order of first appearance.
    pub fn sections(&self) -> &[String] {
        &self.sections
    }

    /// Lines that were skipped, with the reason.
    pub fn warnings(&self) -> &[IniWarning] {
        &self.warnings
    }

    /// The first entry of `key` in `section`.
    pub fn entry(&self, section: &str, key: &str) -> Option<&Entry> {
        self.entries
            .iter()
            .find(|e| e.section == section && e.key == key)
    }

    /// The first value of `key` in `section`.
    pub fn get(&self, section: &str, key: &str) -> Option<&str> {
        self.entry(section, key).map(|e| e.value.as_str())
    }

    /// The first value of `key` in any section (halcmd's `[]KEY`).
    pub fn get_in_any(&self, key: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|e| e.key == key)
            .map(|e| e.value.as_str())
    }

    /// Every entry of `key` in `section`, in order.
    pub fn all<'a>(&'a self, section: &'a str, key: &'a str) -> impl Iterator<Item = &'a Entry> {
        self.entries
            .iter()
            .filter(move |e| e.section == section && e.key == key)
    }

    /// Whether the section exists (even empty).
    pub fn has_section(&self, section: &str) -> bool {
        self.sections.iter().any(|s| s == section)
    }

    /// A number (its first word, as LinuxCNC ignores a second one).
    pub fn real(&self, section: &str, key: &str) -> Result<Option<f64>, IniError> {
        self.typed(section, key, "a number", |w| {
            w.parse::<f64>().ok().filter(|v| !v.is_nan())
        })
    }

    /// A whole number: decimal, or with `0x`, `0o`, `0b` prefixes; a sign.
    pub fn int(&self, section: &str, key: &str) -> Result<Option<i64>, IniError> {
        self.typed(section, key, "a whole number", parse_int)
    }

    /// A boolean: TRUE/YES/ON/1 or FALSE/NO/OFF/0, in any case.
    pub fn boolean(&self, section: &str, key: &str) -> Result<Option<bool>, IniError> {
        self.typed(
            section,
            key,
            "a boolean (YES/NO, TRUE/FALSE, ON/OFF, 1/0)",
            parse_bool,
        )
    }

    /// A value that must be present.
    pub fn required(&self, section: &str, key: &str) -> Result<&Entry, IniError> {
        self.entry(section, key).ok_or_else(|| IniError::Missing {
            file: self.name(),
            section: section.to_string(),
            key: key.to_string(),
        })
    }

    fn typed<T>(
        &self,
        section: &str,
        key: &str,
        expected: &'static str,
        parse: impl Fn(&str) -> Option<T>,
    ) -> Result<Option<T>, IniError> {
        let Some(e) = self.entry(section, key) else {
            return Ok(None);
        };
        let first = e.value.split_whitespace().next().unwrap_or("");
        parse(first).map(Some).ok_or_else(|| IniError::BadValue {
            origin: e.origin.clone(),
            section: section.to_string(),
            key: key.to_string(),
            value: e.value.clone(),
            expected,
        })
    }
}

/// An INI boolean word.
pub fn parse_bool(word: &str) -> Option<bool> {
    match word.to_ascii_uppercase().as_str() {
        "TRUE" | "YES" | "ON" | "1" => Some(true),
        "FALSE" | "NO" | "OFF" | "0" => Some(false),
        _ => None,
    }
}

/// An INI whole number: optional sign, then decimal or `0x`/`0o`/`0b`.
pub fn parse_int(word: &str) -> Option<i64> {
    let (neg, body) = match word.as_bytes().first() {
        Some(b'-') => (true, &word[1..]),
        Some(b'+') => (false, &word[1..]),
        _ => (false, word),
    };
    let lower = body.to_ascii_lowercase();
    let (radix, digits) = if let Some(d) = lower.strip_prefix("0x") {
        (16, d)
    } else if let Some(d) = lower.strip_prefix("0o") {
        (8, d)
    } else if let Some(d) = lower.strip_prefix("0b") {
        (2, d)
    } else {
        (10, lower.as_str())
    };
    if digits.is_empty() || digits.starts_with(['+', '-']) {
        return None;
    }
    let v = i128::from_str_radix(digits, radix).ok()?;
    i64::try_from(if neg { -v } else { v }).ok()
}

/// The fuzz target's body: parses `data` as an INI file whose includes are
/// served from the same bytes (every include name resolves to them), so
/// include recursion and depth limits are exercised too. Never panics.
pub fn fuzz_parse(data: &[u8]) {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut read = |p: &Path| -> std::io::Result<String> {
        if p.as_os_str().len() % 3 == 0 {
            Err(std::io::Error::from(std::io::ErrorKind::NotFound))
        } else {
            Ok(text.clone())
        }
    };
    if let Ok(ini) = Ini::parse_with(Path::new("fuzz.ini"), &mut read) {
        for e in ini.entries() {
            let _ = ini.real(&e.section, &e.key);
            let _ = ini.int(&e.section, &e.key);
            let _ = ini.boolean(&e.section, &e.key);
        }
    }
    let _ = Ini::parse(&String::from_utf8_lossy(data));
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn files(map: &[(&str, &str)]) -> impl FnMut(&Path) -> std::io::Result<String> {
        let map: HashMap<PathBuf, String> = map
            .iter()
            .map(|(k, v)| (PathBuf::from(k), v.to_string()))
            .collect();
        move |p: &Path| {
            map.get(p)
                .cloned()
                .ok_or_else(|| std::io::Error::from(std::io::ErrorKind::NotFound))
        }
    }

    #[test]
    fn first_value_wins_and_comments_are_skipped() {
        let ini = Ini::parse("# c\n[A]\nX = 1\n; c\nX = 2\n[B]\nX=3\n");
        assert_eq!(ini.get("A", "X"), Some("1"));
        assert_eq!(ini.get("B", "X"), Some("3"));
        assert_eq!(ini.get("C", "X"), None);
        let all: Vec<&str> = ini.all("A", "X").map(|e| e.value.as_str()).collect();
        assert_eq!(all, ["1", "2"]);
        assert_eq!(ini.sections(), ["A", "B"]);
    }

    #[test]
    fn values_keep_inner_text_and_continue_over_lines() {
        let ini = Ini::parse(
            "[K]\nKINEMATICS = trivkins coordinates=xyz\nV = a # not a comment\n\
             APP = sim_pin \\\nini.0.a \\\n  ini.1.b\nS = Hello\\\n \\\nWorld\\\n!\nLAST = 1\n",
        );
        assert_eq!(ini.get("K", "KINEMATICS"), Some("trivkins coordinates=xyz"));
        assert_eq!(ini.get("K", "V"), Some("a # not a comment"));
        assert_eq!(ini.get("K", "APP"), Some("sim_pin ini.0.a   ini.1.b"));
        assert_eq!(ini.get("K", "S"), Some("Hello World!"));
        assert_eq!(ini.entry("K", "LAST").unwrap().origin.line, 11);
    }

    #[test]
    fn escapes_make_characters() {
        let ini = Ini::parse(
            "[E]\nA = \\360\\237\\230\\200\nB = \\xf0\\x9f\\x98\\x80\nC = \\ud83d\\ude00\nD = \\U0001f600\n\
             T = a\\tb\nSP = \\x20x\\x20\nKEEP = c:\\dir\n",
        );
        for k in ["A", "B", "C", "D"] {
            assert_eq!(
                ini.get("E", k),
                Some("\u{1f600}"),
                "{k} {:?}",
                ini.warnings()
            );
        }
        assert_eq!(ini.get("E", "T"), Some("a\tb"));
        assert_eq!(ini.get("E", "SP"), Some(" x "));
        assert_eq!(ini.get("E", "KEEP"), Some("c:\\dir"));
        let bad = Ini::parse("[E]\nN = a\\0b\nH = \\xZZ\n");
        assert_eq!(bad.get("E", "N"), None);
        assert_eq!(bad.warnings().len(), 2, "{:?}", bad.warnings());
    }

    #[test]
    fn includes_expand_in_place_with_their_origin() {
        let mut read = files(&[
            ("cfg/m.ini", "[A]\nX = 1\n#INCLUDE j.inc\n[C]\nZ = 3\n"),
            ("cfg/j.inc", "[B]\nY = 2\n#INCLUDE sub/k.inc\n"),
            ("cfg/sub/k.inc", "W = 4\n"),
        ]);
        let ini = Ini::parse_with(Path::new("cfg/m.ini"), &mut read).unwrap();
        let keys: Vec<(&str, &str)> = ini
            .entries()
            .iter()
            .map(|e| (e.section.as_str(), e.key.as_str()))
            .collect();
        assert_eq!(keys, [("A", "X"), ("B", "Y"), ("B", "W"), ("C", "Z")]);
        let w = ini.entry("B", "W").unwrap();
        assert_eq!(w.origin.to_string(), "cfg/sub/k.inc:1");
    }

    #[test]
    fn include_errors_name_the_line() {
        let mut read = files(&[("m.ini", "[A]\n#INCLUDE m.ini\n")]);
        let e = Ini::parse_with(Path::new("m.ini"), &mut read).unwrap_err();
        assert!(
            e.to_string().starts_with("m.ini:2: recursive #INCLUDE"),
            "{e}"
        );
        // A missing file or name is skipped with a warning, as LinuxCNC's
        // launcher does (its includes_demo.ini shows both).
        let mut read = files(&[("m.ini", "[A]\nX = 1\n#INCLUDE gone.inc\n#INCLUDE\nY = 2\n")]);
        let ini = Ini::parse_with(Path::new("m.ini"), &mut read).unwrap();
        assert_eq!(ini.get("A", "Y"), Some("2"));
        let shown: Vec<String> = ini.warnings().iter().map(|w| w.to_string()).collect();
        assert_eq!(shown.len(), 2, "{shown:?}");
        assert!(
            shown[0].contains("m.ini:3") && shown[0].contains("gone.inc: no such file, skipped"),
            "{shown:?}"
        );
        assert!(
            shown[1].contains("m.ini:4") && shown[1].contains("without a file name"),
            "{shown:?}"
        );
        // A chain of 17 includes is one too many.
        let names: Vec<String> = (0..=17).map(|i| format!("f{i}.inc")).collect();
        let texts: Vec<String> = (0..=17)
            .map(|i| format!("#INCLUDE f{}.inc\n", i + 1))
            .collect();
        let pairs: Vec<(&str, &str)> = names
            .iter()
            .zip(&texts)
            .map(|(n, t)| (n.as_str(), t.as_str()))
            .collect();
        let mut read = files(&pairs);
        let e = Ini::parse_with(Path::new("f0.inc"), &mut read).unwrap_err();
        assert!(matches!(e, IniError::IncludeTooDeep { .. }), "{e}");
        // Lower case or indented is a comment, not an include.
        let ini = Ini::parse("#include x\n  #INCLUDE y\n[A]\nX=1\n");
        assert!(ini.warnings().is_empty());
    }

    #[test]
    fn typed_values_report_where_they_are() {
        let ini = Ini::parse("[J]\nV = 1.5 2\nB = yes\nI = 0x10\nBAD = 1.2;c\n");
        assert_eq!(ini.real("J", "V").unwrap(), Some(1.5));
        assert_eq!(ini.boolean("J", "B").unwrap(), Some(true));
        assert_eq!(ini.int("J", "I").unwrap(), Some(16));
        assert_eq!(ini.real("J", "NONE").unwrap(), None);
        let e = ini.real("J", "BAD").unwrap_err();
        assert_eq!(e.to_string(), "<ini>:5: [J]BAD = \"1.2;c\" is not a number");
        assert_eq!(parse_int("-0b101"), Some(-5));
        assert_eq!(parse_int("0o17"), Some(15));
        assert_eq!(parse_int("x"), None);
    }
}
