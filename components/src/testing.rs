//! Test support shared by every family: a private HAL host to load
//! modules into, list what they created, read and write pins and params,
//! and run their functions in a thread.
//!
//! The free functions work on a plain [`Host`]; [`TestHost`] wraps one
//! with the item accessors and a thread runner, and dereferences to it.

use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, ModuleDef, Result, Value};

/// A host on an instance no other test uses, without realtime.
pub fn host() -> Host {
    Host::create(HostConfig::for_tests("comp")).expect("host starts")
}

/// Loads `def` with `args` into `host`.
pub fn load(host: &Host, def: &'static ModuleDef, args: &[&str]) -> Result<()> {
    host.loadrt(def, args)
}

/// `names` sorted.
fn sorted(names: impl Iterator<Item = String>) -> Vec<String> {
    let mut v: Vec<String> = names.collect();
    v.sort();
    v
}

/// Names of every pin, sorted.
pub fn pin_names(host: &Host) -> Vec<String> {
    sorted(host.instance().pins().unwrap().into_iter().map(|p| p.name))
}

/// Names of every param, sorted.
pub fn param_names(host: &Host) -> Vec<String> {
    sorted(
        host.instance()
            .params()
            .unwrap()
            .into_iter()
            .map(|p| p.name),
    )
}

/// Names of every function, sorted.
pub fn funct_names(host: &Host) -> Vec<String> {
    sorted(
        host.instance()
            .functs()
            .unwrap()
            .into_iter()
            .map(|f| f.name),
    )
}

/// A float value, or a panic naming what it was.
pub fn float(v: Value) -> f64 {
    match v {
        Value::Float(f) => f,
        v => panic!("not a float: {v:?}"),
    }
}

/// A host on an instance no other test uses, with accessors by item name
/// and the threads the test has created.
pub struct TestHost {
    /// The host itself.
    pub host: Host,
    threads: usize,
}

impl std::ops::Deref for TestHost {
    type Target = Host;

    fn deref(&self) -> &Host {
        &self.host
    }
}

impl TestHost {
    /// A fresh host without realtime scheduling; `tag` goes into the
    /// instance name.
    pub fn new(tag: &str) -> TestHost {
        TestHost {
            host: Host::create(HostConfig::for_tests(tag)).expect("host starts"),
            threads: 0,
        }
    }

    /// `loadrt def args...`.
    pub fn load(&self, def: &'static ModuleDef, args: &[&str]) -> Result<()> {
        self.host.loadrt(def, args)
    }

    /// Sorted names of every pin, without the function timing ones
    /// (`<funct>.time`).
    pub fn pins(&self) -> Vec<String> {
        let mut v = pin_names(&self.host);
        v.retain(|n| !n.ends_with(".time"));
        v
    }

    /// Sorted names of every param, without the function timing ones
    /// (`<funct>.tmax`, `<funct>.tmax-increased`).
    pub fn params(&self) -> Vec<String> {
        let mut v = param_names(&self.host);
        v.retain(|n| !n.ends_with(".tmax") && !n.ends_with(".tmax-increased"));
        v
    }

    /// Sorted names of every function.
    pub fn functs(&self) -> Vec<String> {
        funct_names(&self.host)
    }

    /// Sorted names of every pin and param starting with `prefix`, the
    /// function timing ones included.
    pub fn items(&self, prefix: &str) -> Vec<String> {
        let inst = self.host.instance();
        sorted(
            inst.pins()
                .unwrap()
                .into_iter()
                .map(|p| p.name)
                .chain(inst.params().unwrap().into_iter().map(|p| p.name))
                .filter(|n| n.starts_with(prefix)),
        )
    }

    /// Writes an unconnected pin.
    pub fn set(&self, pin: &str, v: Value) {
        self.host.instance().set_pin(pin, v).expect(pin);
    }

    /// Reads a pin (panics naming it if it does not exist).
    pub fn get(&self, pin: &str) -> Value {
        self.host.instance().pin_value(pin).expect(pin)
    }

    /// Writes a param.
    pub fn setp(&self, param: &str, v: Value) {
        self.host.instance().set_param(param, v).expect(param);
    }

    /// Reads a param (panics naming it if it does not exist).
    pub fn getp(&self, param: &str) -> Value {
        self.host.instance().param_value(param).expect(param)
    }

    /// Puts `functs` in a new 1 ms thread (not started yet).
    pub fn thread(&mut self, functs: &[&str]) {
        let name = format!("t{}", self.threads);
        self.threads += 1;
        self.host
            .create_thread(&name, 1_000_000, true, None)
            .unwrap();
        for f in functs {
            self.host.addf(f, &name, -1).unwrap();
        }
    }

    /// Cycles run so far by the first thread.
    fn cycles(&self) -> u64 {
        self.host.instance().threads().unwrap()[0].cycles
    }

    /// Runs the threads for at least `n` more cycles (panics after 10 s),
    /// stops them and returns how many cycles the first thread has run in
    /// all: with one thread started once, exactly how many times each of
    /// its functions ran.
    pub fn run(&self, n: u64) -> u64 {
        let target = self.cycles() + n;
        self.host.start().unwrap();
        let end = Instant::now() + Duration::from_secs(10);
        while self.cycles() < target {
            assert!(Instant::now() < end, "threads did not run");
            std::thread::sleep(Duration::from_millis(1));
        }
        self.host.stop();
        self.cycles()
    }

    /// Sets the inputs, runs a few cycles and checks that `pin` reads
    /// `want`.
    pub fn expect(&self, inputs: &[(&str, Value)], pin: &str, want: Value) {
        for (p, v) in inputs {
            self.set(p, *v);
        }
        self.run(2);
        assert_eq!(self.get(pin), want, "{pin} after {inputs:?}");
    }
}

/// Parses a test's spelling of a value of type `t`: `0`/`1` for bits,
/// decimal for the rest.
fn parse_value(t: hal_core::HalType, s: &str) -> Value {
    use hal_core::HalType as T;
    fn num<N: std::str::FromStr>(t: hal_core::HalType, s: &str) -> N {
        s.parse()
            .unwrap_or_else(|_| panic!("bad {t:?} value '{s}' in a test table"))
    }
    match t {
        T::Bit => Value::Bit(num::<u8>(t, s) != 0),
        T::Float => Value::Float(num(t, s)),
        T::S32 => Value::S32(num(t, s)),
        T::U32 => Value::U32(num(t, s)),
        T::S64 => Value::S64(num(t, s)),
        T::U64 => Value::U64(num(t, s)),
        T::Port => Value::Port(num(t, s)),
    }
}

fn parse_type(s: &str) -> hal_core::HalType {
    use hal_core::HalType as T;
    match s {
        "bit" => T::Bit,
        "float" => T::Float,
        "s32" => T::S32,
        "u32" => T::U32,
        "s64" => T::S64,
        "u64" => T::U64,
        _ => panic!("bad type '{s}' in a test table"),
    }
}

impl TestHost {
    /// Checks that the pins under `<prefix>.` (function `.time` pins
    /// aside) are exactly `want`, each written `"<item> <type> <dir>
    /// <value>"` (`"out float out 0"`, `"enable bit in 1"`): names, types,
    /// directions and current values.
    pub fn check_pins(&self, prefix: &str, want: &[&str]) {
        let got = self
            .host
            .instance()
            .pins()
            .unwrap()
            .into_iter()
            .filter(|p| !p.name.ends_with(".time"))
            .map(|p| (p.name, p.hal_type, p.dir.label().to_lowercase(), p.value));
        check_items("pins", prefix, got, want, |d| match d {
            "in" => "in",
            "out" => "out",
            "io" => "i/o",
            _ => panic!("bad pin direction '{d}'"),
        });
    }

    /// Checks the params under `<prefix>.` (function timing params aside)
    /// as [`TestHost::check_pins`] does pins; the direction is `ro` or
    /// `rw`.
    pub fn check_params(&self, prefix: &str, want: &[&str]) {
        let got = self
            .host
            .instance()
            .params()
            .unwrap()
            .into_iter()
            .filter(|p| !p.name.ends_with(".tmax") && !p.name.ends_with(".tmax-increased"))
            .map(|p| (p.name, p.hal_type, p.dir.label().to_lowercase(), p.value));
        check_items("params", prefix, got, want, |d| match d {
            "ro" | "rw" => d,
            _ => panic!("bad param access '{d}'"),
        });
    }

    /// Checks that loading `def` with `args` fails and leaves nothing of
    /// it behind: no component, pin, param or function.
    pub fn check_load_fails(&self, def: &'static ModuleDef, args: &[&str]) {
        let before = (self.pins(), self.params(), self.functs());
        let comps = self.host.loaded_components();
        assert!(
            self.host.loadrt(def, args).is_err(),
            "{} {args:?} loaded",
            def.name
        );
        assert_eq!(
            self.host.loaded_components(),
            comps,
            "{} {args:?}",
            def.name
        );
        assert_eq!(
            (self.pins(), self.params(), self.functs()),
            before,
            "{} {args:?} left items behind",
            def.name
        );
    }
}

/// Compares the items (name, type, direction label, value) under
/// `<prefix>.` with the `want` lines; `dir` maps a line's direction word
/// to the label HAL listings use.
fn check_items(
    what: &str,
    prefix: &str,
    got: impl Iterator<Item = (String, hal_core::HalType, String, Value)>,
    want: &[&str],
    dir: impl Fn(&str) -> &str,
) {
    let start = format!("{prefix}.");
    let mut got: Vec<_> = got.filter(|(n, ..)| n.starts_with(&start)).collect();
    got.sort_by(|a, b| a.0.cmp(&b.0));
    let mut want: Vec<_> = want
        .iter()
        .map(|line| {
            let f: Vec<&str> = line.split_whitespace().collect();
            assert_eq!(f.len(), 4, "bad line '{line}'");
            let t = parse_type(f[1]);
            (
                format!("{start}{}", f[0]),
                t,
                dir(f[2]).to_string(),
                parse_value(t, f[3]),
            )
        })
        .collect();
    want.sort_by(|a, b| a.0.cmp(&b.0));
    assert_eq!(got, want, "{what} of {prefix}");
}
