//! Finding the files `[HAL]HALFILE` (and `POSTGUI_HALFILE`, `SHUTDOWN`)
//! name, as LinuxCNC does: an absolute or `~/` path as given; `LIB:NAME`
//! in the library of standard HAL files only; any other name in the `-H`
//! directories, then the INI file's directory, then the library.

use std::path::{Path, PathBuf};

use hal_lang::ini::{Entry, Origin};

use crate::LaunchError;

/// The library of standard HAL files this suite ships (`lib/hallib`):
/// `$HALLIB_DIR` if set, else `lib/hallib` beside or above the running
/// program, else the one in the source tree it was built from.
pub fn hallib_dir() -> Option<PathBuf> {
    if let Some(d) = std::env::var_os("HALLIB_DIR").filter(|d| !d.is_empty()) {
        return Some(PathBuf::from(d));
    }
    let exe_dir = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(Path::to_path_buf));
    let mut candidates = Vec::new();
    if let Some(dir) = exe_dir {
        // target/<profile>/ (and deps/ for tests), or an installed bin/.
        for up in ["..", "../..", "../../.."] {
            candidates.push(dir.join(up).join("lib/hallib"));
        }
        candidates.push(dir.join("../share/hal/hallib"));
    }
    candidates.push(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../lib/hallib"));
    candidates
        .into_iter()
        .find(|c| c.is_dir())
        .map(|c| std::fs::canonicalize(&c).unwrap_or(c))
}

/// A HAL file named in the INI file, found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HalFile {
    /// The value as written (`LIB:basic_sim.tcl -no_sim_spindle`).
    pub spec: String,
    /// The file found.
    pub path: PathBuf,
    /// The words after the file name (a Tcl file's `::argv`).
    pub args: Vec<String>,
    /// Where the INI file names it.
    pub origin: Origin,
}

impl HalFile {
    /// The file's extension (`hal`, `tcl`, `py`, ...), lower case.
    pub fn kind(&self) -> String {
        self.path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default()
    }

    /// The name LinuxCNC's twopass reports the file by (`twopass:found
    /// NAME`): `./NAME` for a bare name found beside the INI file, else
    /// the whole path found.
    pub fn twopass_name(&self, ini_dir: &Path) -> String {
        let name = self.spec.split_whitespace().next().unwrap_or("");
        let bare =
            !name.starts_with("LIB:") && !name.starts_with("~/") && !Path::new(name).is_absolute();
        if bare && self.path == ini_dir.join(name) {
            format!("./{name}")
        } else {
            self.path.display().to_string()
        }
    }

    /// The name messages use: the path relative to the working directory
    /// when below it, else the whole path.
    pub fn display_name(&self) -> String {
        std::env::current_dir()
            .ok()
            .and_then(|cwd| self.path.strip_prefix(cwd).ok().map(Path::to_path_buf))
            .unwrap_or_else(|| self.path.clone())
            .display()
            .to_string()
    }
}

/// Where to look.
#[derive(Debug, Clone, Default)]
pub struct SearchPath {
    /// `-H` directories, in order.
    pub extra: Vec<PathBuf>,
    /// The INI file's directory.
    pub ini_dir: PathBuf,
    /// The library of standard HAL files.
    pub lib: Option<PathBuf>,
}

impl SearchPath {
    /// Whether `path` is in the library of standard HAL files (which are
    /// in the current format, whatever the machine's INI file says).
    pub fn in_library(&self, path: &Path) -> bool {
        self.lib.as_ref().is_some_and(|lib| path.starts_with(lib))
    }

    /// Finds the file an INI entry names.
    pub fn resolve(&self, entry: &Entry) -> Result<HalFile, LaunchError> {
        let mut words = entry.value.split_whitespace();
        let name = words.next().unwrap_or("");
        let args: Vec<String> = words.map(str::to_string).collect();
        let fail = |reason: String| LaunchError::HalFile {
            origin: entry.origin.clone(),
            key: format!("[{}]{}", entry.section, entry.key),
            spec: entry.value.clone(),
            reason,
        };
        if name.is_empty() {
            return Err(fail("no file named".into()));
        }
        let mut tried = Vec::new();
        let path = if let Some(lib_name) = name.strip_prefix("LIB:") {
            let lib = self.lib.as_ref().ok_or_else(|| {
                fail(
                    "the library of standard HAL files (lib/hallib) was not found; set HALLIB_DIR"
                        .into(),
                )
            })?;
            tried.push(lib.join(lib_name));
            lib.join(lib_name)
        } else if let Some(rest) = name.strip_prefix("~/") {
            let home = std::env::var_os("HOME")
                .map(PathBuf::from)
                .unwrap_or_default();
            tried.push(home.join(rest));
            home.join(rest)
        } else if Path::new(name).is_absolute() {
            tried.push(PathBuf::from(name));
            PathBuf::from(name)
        } else {
            let dirs = self
                .extra
                .iter()
                .chain(std::iter::once(&self.ini_dir))
                .chain(self.lib.iter());
            let mut found = None;
            for d in dirs {
                let cand = d.join(name);
                tried.push(cand.clone());
                if cand.is_file() {
                    found = Some(cand);
                    break;
                }
            }
            found.unwrap_or_else(|| tried[0].clone())
        };
        if path.exists() && !path.is_file() {
            if let Err(e) = hal_core::files::open_regular(&path, "HAL file") {
                return Err(fail(e.problem.to_string()));
            }
        }
        if !path.is_file() {
            let list: Vec<String> = tried.iter().map(|p| p.display().to_string()).collect();
            return Err(fail(format!(
                "file not found (looked for {})",
                list.join(", ")
            )));
        }
        Ok(HalFile {
            spec: entry.value.clone(),
            path,
            args,
            origin: entry.origin.clone(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn entry(value: &str) -> Entry {
        Entry {
            section: "HAL".into(),
            key: "HALFILE".into(),
            value: value.into(),
            origin: Origin {
                file: Arc::from("m.ini"),
                line: 7,
            },
        }
    }

    #[test]
    fn lib_names_and_search_order() {
        let root = std::env::temp_dir().join(format!("halfiles-{}", std::process::id()));
        let (ini, lib, extra) = (root.join("cfg"), root.join("lib"), root.join("h"));
        for d in [&ini, &lib, &extra] {
            std::fs::create_dir_all(d).unwrap();
        }
        std::fs::write(ini.join("core_sim.hal"), "").unwrap();
        std::fs::write(lib.join("core_sim.hal"), "").unwrap();
        std::fs::write(lib.join("basic_sim.tcl"), "").unwrap();
        std::fs::write(extra.join("mine.hal"), "").unwrap();
        let sp = SearchPath {
            extra: vec![extra.clone()],
            ini_dir: ini.clone(),
            lib: Some(lib.clone()),
        };
        assert_eq!(
            sp.resolve(&entry("core_sim.hal")).unwrap().path,
            ini.join("core_sim.hal")
        );
        assert_eq!(
            sp.resolve(&entry("LIB:core_sim.hal")).unwrap().path,
            lib.join("core_sim.hal")
        );
        // As LinuxCNC's twopass names them: ./NAME beside the INI file.
        let name = |spec: &str| sp.resolve(&entry(spec)).unwrap().twopass_name(&ini);
        assert_eq!(name("core_sim.hal"), "./core_sim.hal");
        assert_eq!(
            name("LIB:core_sim.hal"),
            lib.join("core_sim.hal").display().to_string()
        );
        assert_eq!(
            name("mine.hal"),
            extra.join("mine.hal").display().to_string()
        );
        let tcl = sp
            .resolve(&entry("LIB:basic_sim.tcl -no_sim_spindle"))
            .unwrap();
        assert_eq!(
            (tcl.kind(), tcl.args),
            ("tcl".to_string(), vec!["-no_sim_spindle".to_string()])
        );
        assert_eq!(
            sp.resolve(&entry("basic_sim.tcl")).unwrap().path,
            lib.join("basic_sim.tcl")
        );
        assert_eq!(
            sp.resolve(&entry("mine.hal")).unwrap().path,
            extra.join("mine.hal")
        );
        let e = sp.resolve(&entry("LIB:mine.hal")).unwrap_err().to_string();
        assert!(
            e.starts_with("m.ini:7: [HAL]HALFILE = LIB:mine.hal: file not found"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(root);
    }
}
