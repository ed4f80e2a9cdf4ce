//! `[HAL]TWOPASS` as LinuxCNC's twopass.tcl does it: in pass 0 every
//! HALFILE is read and only its `loadrt` lines are gathered, per module,
//! so one module may be loaded from several files; at the end of pass 0
//! each module is loaded once, with `count=` and `num_chan=` summed,
//! `names=` and `personality=` joined with commas, `debug=` OR-ed, and any
//! other parameter kept in order. `loadusr` runs in pass 0. In pass 1 the
//! files are read again and every other command runs in file order;
//! `loadrt` of a module loaded in pass 0 is skipped and `loadusr` too.

use crate::error::LaunchError;

/// The loadrt lines of one module gathered in pass 0.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
struct Gathered {
    module: String,
    /// `count`, `num_chan` or `names`: the form the first line used.
    form: Option<&'static str>,
    count: i64,
    num_chan: i64,
    names: Vec<String>,
    personality: Vec<String>,
    debug: Option<i64>,
    other: Vec<String>,
}

/// Modules gathered in pass 0, in order of first appearance.
#[derive(Debug, Clone, Default)]
pub struct TwoPass {
    modules: Vec<Gathered>,
    loaded: Vec<String>,
}

/// A `count=`/`num_chan=` value: LinuxCNC adds them with Tcl's `incr`.
fn whole(module: &str, item: &str, value: &str) -> Result<i64, LaunchError> {
    hal_lang::ini::parse_int(value).ok_or_else(|| LaunchError::TwoPass {
        module: module.to_string(),
        reason: format!("{item}={value} is not a whole number"),
    })
}

/// `so_far` plus the whole number `value` of `item`, refused when the sum
/// leaves the i64 range (found by the fuzz target: two huge counts).
fn sum(module: &str, item: &str, so_far: i64, value: &str) -> Result<i64, LaunchError> {
    so_far
        .checked_add(whole(module, item, value)?)
        .ok_or_else(|| LaunchError::TwoPass {
            module: module.to_string(),
            reason: format!("{item}= values add up past {}", i64::MAX),
        })
}

impl TwoPass {
    /// Nothing gathered yet.
    pub fn new() -> TwoPass {
        TwoPass::default()
    }

    /// Gathers one `loadrt MODULE ARGS...` (the words after `loadrt`).
    pub fn gather(&mut self, words: &[String]) -> Result<(), LaunchError> {
        let Some((module, args)) = words.split_first() else {
            return Err(LaunchError::TwoPassNoModule);
        };
        if self.loaded.contains(module) {
            return Err(LaunchError::TwoPass {
                module: module.clone(),
                reason: "already loaded".into(),
            });
        }
        let at = match self.modules.iter().position(|g| &g.module == module) {
            Some(i) => i,
            None => {
                self.modules.push(Gathered {
                    module: module.clone(),
                    ..Gathered::default()
                });
                self.modules.len() - 1
            }
        };
        let g = &mut self.modules[at];
        for pair in args {
            let (item, value) = pair.split_once('=').unwrap_or((pair.as_str(), ""));
            let form = match item {
                "count" => Some("count"),
                "num_chan" => Some("num_chan"),
                "names" => Some("names"),
                _ => None,
            };
            if let Some(form) = form {
                match g.form {
                    None => g.form = Some(form),
                    Some(first) if first != form => {
                        return Err(LaunchError::TwoPass {
                            module: module.clone(),
                            reason: format!(
                                "cannot mix count=, num_chan= and names= forms \
                                 (first used form: {first}=)"
                            ),
                        })
                    }
                    Some(_) => {}
                }
            }
            match item {
                "count" => g.count = sum(module, item, g.count, value)?,
                "num_chan" => g.num_chan = sum(module, item, g.num_chan, value)?,
                "names" => g.names.push(value.to_string()),
                "personality" => g.personality.push(value.to_string()),
                "debug" => {
                    let v = whole(module, item, value)?;
                    g.debug = Some(g.debug.unwrap_or(0) | v);
                }
                _ => g.other.push(pair.clone()),
            }
        }
        Ok(())
    }

    /// The merged `loadrt` commands, one per module, in order.
    pub fn load_commands(&self) -> Vec<Vec<String>> {
        self.modules
            .iter()
            .map(|g| {
                let mut v = vec!["loadrt".to_string(), g.module.clone()];
                match g.form {
                    Some("count") => v.push(format!("count={}", g.count)),
                    Some("num_chan") => v.push(format!("num_chan={}", g.num_chan)),
                    Some(_) => v.push(format!("names={}", g.names.join(","))),
                    None => {}
                }
                if !g.personality.is_empty() {
                    v.push(format!("personality={}", g.personality.join(",")));
                }
                if let Some(d) = g.debug {
                    v.push(format!("debug={d}"));
                }
                v.extend(g.other.iter().cloned());
                v
            })
            .collect()
    }

    /// Marks the gathered modules loaded (end of pass 0).
    pub fn finish_pass0(&mut self) {
        for g in self.modules.drain(..) {
            self.loaded.push(g.module);
        }
    }

    /// Whether pass 1 skips `loadrt module` (it was loaded in pass 0).
    pub fn loaded_in_pass0(&self, module: &str) -> bool {
        self.loaded.iter().any(|m| m == module)
    }
}

/// Whether a .hal file opts out of TWOPASS: a line that, without spaces
/// and in lower case, starts with `#notwopass`.
pub fn is_notwopass(text: &str) -> bool {
    text.lines().any(|l| {
        l.chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_lowercase()
            .starts_with("#notwopass")
    })
}

/// The fuzz target's body: gathers every line of `data` that starts with
/// `loadrt` and builds the merged commands. Never panics.
pub fn fuzz_gather(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let mut tp = TwoPass::new();
    for line in text.lines() {
        let words: Vec<String> = line.split_whitespace().map(str::to_string).collect();
        if words.first().map(String::as_str) == Some("loadrt") {
            let _ = tp.gather(&words[1..]);
        }
    }
    let _ = tp.load_commands();
    let _ = is_notwopass(&text);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_string).collect()
    }

    #[test]
    fn counts_add_and_names_join_across_files() {
        let mut tp = TwoPass::new();
        tp.gather(&w("and2 count=2")).unwrap();
        tp.gather(&w("pid names=x_pid,y_pid debug=0")).unwrap();
        tp.gather(&w("and2 count=1")).unwrap();
        tp.gather(&w("pid names=z_pid debug=1")).unwrap();
        tp.gather(&w("mux_generic config=bb8,fu4")).unwrap();
        tp.gather(&w("bitslice names=b1 personality=8")).unwrap();
        tp.gather(&w("bitslice names=b2 personality=16")).unwrap();
        let cmds: Vec<String> = tp.load_commands().iter().map(|c| c.join(" ")).collect();
        assert_eq!(
            cmds,
            [
                "loadrt and2 count=3",
                "loadrt pid names=x_pid,y_pid,z_pid debug=1",
                "loadrt mux_generic config=bb8,fu4",
                "loadrt bitslice names=b1,b2 personality=8,16",
            ]
        );
        tp.finish_pass0();
        assert!(tp.loaded_in_pass0("pid"));
        assert!(!tp.loaded_in_pass0("or2"));
        assert!(tp.gather(&w("pid count=1")).is_err());
    }

    #[test]
    fn counts_that_add_up_past_the_range_are_refused() {
        let mut tp = TwoPass::new();
        let w = |s: &str| s.split_whitespace().map(str::to_string).collect::<Vec<_>>();
        tp.gather(&w("and2 count=1")).unwrap();
        let e = tp
            .gather(&w("and2 count=9223372036854775807"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("count= values add up past"), "{e}");
    }

    #[test]
    fn forms_may_not_mix() {
        let mut tp = TwoPass::new();
        tp.gather(&w("and2 count=1")).unwrap();
        let e = tp.gather(&w("and2 names=a")).unwrap_err().to_string();
        assert!(e.contains("cannot mix"), "{e}");
        assert!(tp.gather(&w("or2 count=x")).is_err());
    }

    #[test]
    fn notwopass_is_found_in_any_case_and_spacing() {
        assert!(is_notwopass("loadrt x\n# NoTwoPass here\n"));
        assert!(!is_notwopass("loadrt x # notwopass\n"));
        fuzz_gather(b"loadrt a count=1\nloadrt a names=b\nloadrt\n");
    }
}
