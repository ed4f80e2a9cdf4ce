//! Reading INI text: lines, sections, continued values, escapes and
//! `#INCLUDE`s expanded in place.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::escape::{unescape, Unescape};
use super::{Entry, Ini, IniError, IniWarning, Origin, Reader, MAX_INCLUDE_DEPTH};

/// A path made absolute (for recursion checks), without touching the disk
/// beyond `canonicalize` when the file exists.
pub(super) fn normalize(p: &Path) -> PathBuf {
    std::fs::canonicalize(p).unwrap_or_else(|_| {
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            std::env::current_dir().unwrap_or_default().join(p)
        }
    })
}

/// One INI text being read into an [`Ini`].
pub(super) struct Parser<'a, 'r> {
    pub(super) ini: &'a mut Ini,
    pub(super) read: &'a mut Reader<'r>,
    /// Files being read, outermost first.
    pub(super) stack: Vec<PathBuf>,
    /// Turn errors into warnings (text without a file).
    pub(super) lenient: bool,
    /// The current section; includes are expanded in place, so a section
    /// begun in an included file goes on after it.
    pub(super) section: String,
}

impl Parser<'_, '_> {
    /// Reads `text` (of `file`, in `dir`, `depth` includes deep).
    pub(super) fn text(
        &mut self,
        text: &str,
        file: Arc<str>,
        dir: &Path,
        depth: usize,
    ) -> Result<(), IniError> {
        let lines: Vec<&str> = text.lines().collect();
        let mut i = 0;
        while i < lines.len() {
            let number = i + 1;
            let raw = lines[i].strip_suffix('\r').unwrap_or(lines[i]);
            i += 1;
            let origin = Origin {
                file: file.clone(),
                line: number,
            };
            if let Some(rest) = raw.strip_prefix("#INCLUDE") {
                if rest.starts_with([' ', '\t']) || rest.is_empty() {
                    let r = self.include(rest.trim(), origin, dir, depth);
                    let r = self.skip_as_linuxcnc_does(r);
                    self.or_warn(r)?;
                    continue;
                }
            }
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') || line.starts_with(';') {
                continue;
            }
            if let Some(inner) = line.strip_prefix('[') {
                match inner.split_once(']') {
                    Some((name, rest)) => {
                        let rest = rest.trim();
                        if !(rest.is_empty() || rest.starts_with('#') || rest.starts_with(';')) {
                            self.warn(
                                origin.clone(),
                                format!("text after section header ignored: {rest:?}"),
                            );
                        }
                        self.section = name.trim().to_string();
                        if !self.ini.sections.contains(&self.section) {
                            self.ini.sections.push(self.section.clone());
                        }
                    }
                    None => self.warn(
                        origin,
                        format!("section header without ']' skipped: {line:?}"),
                    ),
                }
                continue;
            }
            let Some((key, first)) = line.split_once('=') else {
                self.warn(
                    origin,
                    format!("line is not KEY = VALUE, skipped: {line:?}"),
                );
                continue;
            };
            let key = key.trim().to_string();
            if key.is_empty() || key.contains(char::is_whitespace) {
                self.warn(origin, format!("bad key {key:?}, line skipped"));
                continue;
            }
            // Continuation: a value ending in a backslash goes on with the
            // next line, joined as written.
            let mut value = String::new();
            let mut part = first.trim_start().to_string();
            loop {
                let trimmed = part.trim_end();
                if ends_with_continuation(trimmed) && i < lines.len() {
                    value.push_str(&trimmed[..trimmed.len() - 1]);
                    part = lines[i].strip_suffix('\r').unwrap_or(lines[i]).to_string();
                    i += 1;
                } else {
                    value.push_str(trimmed);
                    break;
                }
            }
            let value = match unescape(&value) {
                Ok(v) => v,
                Err(problem) => {
                    let e = match problem {
                        Unescape::Escape(escape) => IniError::BadEscape {
                            origin,
                            section: self.section.clone(),
                            key,
                            escape,
                        },
                        Unescape::Text(problem) => IniError::BadText {
                            origin,
                            section: self.section.clone(),
                            key,
                            problem,
                        },
                    };
                    self.or_warn(Err(e))?;
                    continue;
                }
            };
            self.ini.entries.push(Entry {
                section: self.section.clone(),
                key,
                value,
                origin,
            });
        }
        Ok(())
    }

    fn include(
        &mut self,
        name: &str,
        origin: Origin,
        dir: &Path,
        depth: usize,
    ) -> Result<(), IniError> {
        if name.is_empty() {
            return Err(IniError::IncludeWithoutName { origin });
        }
        if depth + 1 > MAX_INCLUDE_DEPTH {
            return Err(IniError::IncludeTooDeep {
                origin,
                max: MAX_INCLUDE_DEPTH,
            });
        }
        let path = resolve_include(name, dir);
        let key = normalize(&path);
        if self.stack.contains(&key) {
            return Err(IniError::IncludeCycle { origin, path });
        }
        let text = (self.read)(&path).map_err(|source| IniError::Io {
            origin: Some(origin),
            path: path.clone(),
            source,
        })?;
        self.stack.push(key);
        let sub_dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        let file: Arc<str> = Arc::from(path.to_string_lossy().as_ref());
        let r = self.text(&text, file, &sub_dir, depth + 1);
        self.stack.pop();
        r
    }

    /// LinuxCNC's launcher reports an `#INCLUDE` without a file name, or
    /// of a file that does not exist, and goes on without it; so do we,
    /// with a warning naming the line. Other failures (a cycle, too deep,
    /// a file that exists but cannot be read) stay errors.
    fn skip_as_linuxcnc_does(&mut self, r: Result<(), IniError>) -> Result<(), IniError> {
        match r {
            Err(IniError::IncludeWithoutName { origin }) => {
                self.warn(origin, "#INCLUDE without a file name, skipped".into());
                Ok(())
            }
            Err(IniError::Io {
                origin: Some(origin),
                path,
                source,
            }) if source.kind() == std::io::ErrorKind::NotFound => {
                self.warn(
                    origin,
                    format!("#INCLUDE {}: no such file, skipped", path.display()),
                );
                Ok(())
            }
            other => other,
        }
    }

    fn warn(&mut self, origin: Origin, message: String) {
        self.ini.warnings.push(IniWarning { origin, message });
    }

    fn or_warn(&mut self, r: Result<(), IniError>) -> Result<(), IniError> {
        match r {
            Err(e) if self.lenient => {
                let origin = match &e {
                    IniError::IncludeTooDeep { origin, .. }
                    | IniError::IncludeCycle { origin, .. }
                    | IniError::IncludeWithoutName { origin }
                    | IniError::BadEscape { origin, .. }
                    | IniError::BadText { origin, .. } => origin.clone(),
                    IniError::Io {
                        origin: Some(origin),
                        ..
                    } => origin.clone(),
                    _ => Origin {
                        file: Arc::from("<ini>"),
                        line: 0,
                    },
                };
                self.warn(origin, e.to_string());
                Ok(())
            }
            other => other,
        }
    }
}

/// An include path: absolute, `~/`-relative, else next to the including
/// file if it is there, else relative to the working directory.
fn resolve_include(name: &str, dir: &Path) -> PathBuf {
    if let Some(rest) = name.strip_prefix("~/") {
        if let Some(home) = std::env::var_os("HOME") {
            return PathBuf::from(home).join(rest);
        }
    }
    let p = Path::new(name);
    if p.is_absolute() {
        return p.to_path_buf();
    }
    let beside = dir.join(p);
    if beside.exists() || !p.exists() {
        beside
    } else {
        p.to_path_buf()
    }
}

/// Whether a trimmed value ends in a continuation backslash (an escaped
/// backslash `\\` does not continue).
fn ends_with_continuation(s: &str) -> bool {
    let n = s.bytes().rev().take_while(|&b| b == b'\\').count();
    n % 2 == 1
}
