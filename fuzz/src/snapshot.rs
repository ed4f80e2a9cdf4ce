//! The shape of an instance, to tell whether an operation changed it:
//! every object's name, type and links, without values or ids (which
//! move on their own).

use std::fmt::Debug;

use hal_core::{Host, Instance};

/// Everything a failed operation must leave as it was.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Snapshot {
    /// Modules the host has loaded, when taken through the host.
    modules: Vec<String>,
    /// Components: name and kind.
    components: Vec<String>,
    /// Pins: name, type, direction, signal.
    pins: Vec<String>,
    /// Params: name, type, direction.
    params: Vec<String>,
    /// Signals: name, type, linked pins.
    signals: Vec<String>,
    /// Functions: name, owner, threads using it.
    functs: Vec<String>,
    /// Threads: name, period, functions.
    threads: Vec<String>,
    /// Named regions: name, owner, size.
    regions: Vec<String>,
}

fn list<T: Debug>(
    items: hal_core::Result<Vec<T>>,
    what: &str,
    f: impl Fn(&T) -> String,
) -> Vec<String> {
    match items {
        Ok(v) => v.iter().map(f).collect(),
        Err(e) => panic!("listing {what} failed: {e}"),
    }
}

impl Snapshot {
    /// The instance's shape. Panics if listing fails: a consistent
    /// instance can always be listed.
    pub fn of(inst: &Instance) -> Snapshot {
        Snapshot {
            modules: Vec::new(),
            components: list(inst.components(), "components", |c| {
                format!("{} {:?}", c.name, c.kind)
            }),
            pins: list(inst.pins(), "pins", |p| {
                format!("{} {} {} {:?}", p.name, p.hal_type, p.dir, p.signal)
            }),
            params: list(inst.params(), "params", |p| {
                format!("{} {} {}", p.name, p.hal_type, p.dir.label())
            }),
            signals: list(inst.signals(), "signals", |s| {
                format!("{} {} {:?}", s.name, s.hal_type, s.pins)
            }),
            functs: list(inst.functs(), "functions", |f| {
                format!("{} {} {}", f.name, f.owner, f.users)
            }),
            threads: list(inst.threads(), "threads", |t| {
                format!("{} {} {:?} {:?}", t.name, t.period, t.functs, t.init_functs)
            }),
            regions: list(inst.regions(), "regions", |r| {
                format!("{} {} {}", r.name, r.owner_id, r.size)
            }),
        }
    }

    /// The shape of a host's instance, with its loaded modules.
    pub fn of_host(host: &Host) -> Snapshot {
        let mut s = Snapshot::of(host.instance());
        s.modules = host
            .loaded_modules()
            .into_iter()
            .map(str::to_string)
            .collect();
        s
    }

    /// What differs from `other`, in words; `None` if nothing.
    pub fn difference(&self, other: &Snapshot) -> Option<String> {
        if self == other {
            return None;
        }
        let mut out = Vec::new();
        let mut compare = |what: &str, a: &[String], b: &[String]| {
            let gone: Vec<&String> = a.iter().filter(|x| !b.contains(x)).collect();
            let new: Vec<&String> = b.iter().filter(|x| !a.contains(x)).collect();
            if !gone.is_empty() || !new.is_empty() {
                out.push(format!("{what}: gone {gone:?}, new {new:?}"));
            } else if a != b {
                out.push(format!("{what}: reordered from {a:?} to {b:?}"));
            }
        };
        compare("modules", &self.modules, &other.modules);
        compare("components", &self.components, &other.components);
        compare("pins", &self.pins, &other.pins);
        compare("params", &self.params, &other.params);
        compare("signals", &self.signals, &other.signals);
        compare("functions", &self.functs, &other.functs);
        compare("threads", &self.threads, &other.threads);
        compare("regions", &self.regions, &other.regions);
        Some(out.join("; "))
    }
}

/// Deletes every thread of `host`: threads stay when the module that
/// made them is unloaded (as in LinuxCNC), so a target that starts each
/// input from an empty instance deletes them itself.
pub fn delete_threads(host: &Host) {
    let threads = host.instance().threads().expect("listing threads");
    for t in threads {
        if let Err(e) = host.delete_thread(&t.name) {
            panic!("deleting thread {}: {e}", t.name);
        }
    }
}
