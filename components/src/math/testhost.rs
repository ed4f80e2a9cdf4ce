//! Test support for the gates, choosers and math families: a private HAL
//! host to load a module into, read and write its pins, and run its
//! functions in a thread until an output settles.

use std::time::{Duration, Instant};

use hal_core::{Host, HostConfig, ModuleDef, Value};

/// A host on an instance no other test uses.
pub struct TestHost {
    /// The host itself.
    pub host: Host,
    threads: usize,
}

impl TestHost {
    /// A fresh host without realtime scheduling.
    pub fn new(tag: &str) -> TestHost {
        TestHost {
            host: Host::create(HostConfig::for_tests(tag)).expect("host starts"),
            threads: 0,
        }
    }

    /// `loadrt def args...`.
    pub fn load(&self, def: &'static ModuleDef, args: &[&str]) -> hal_core::Result<()> {
        self.host.loadrt(def, args)
    }

    /// Sorted names of every pin.
    pub fn pins(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .host
            .instance()
            .pins()
            .unwrap()
            .into_iter()
            .map(|p| p.name)
            .filter(|n| !n.ends_with(".time"))
            .collect();
        v.sort();
        v
    }

    /// Sorted names of every param, without the function timing ones.
    pub fn params(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .host
            .instance()
            .params()
            .unwrap()
            .into_iter()
            .map(|p| p.name)
            .filter(|n| !n.ends_with(".tmax") && !n.ends_with(".tmax-increased"))
            .collect();
        v.sort();
        v
    }

    /// Sorted names of every function.
    pub fn functs(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .host
            .instance()
            .functs()
            .unwrap()
            .into_iter()
            .map(|f| f.name)
            .collect();
        v.sort();
        v
    }

    /// Writes an unconnected pin.
    pub fn set(&self, pin: &str, v: Value) {
        self.host.instance().set_pin(pin, v).unwrap();
    }

    /// Reads a pin.
    pub fn get(&self, pin: &str) -> Value {
        self.host.instance().pin_value(pin).unwrap()
    }

    /// Writes a param.
    pub fn setp(&self, param: &str, v: Value) {
        self.host.instance().set_param(param, v).unwrap();
    }

    /// Reads a param.
    pub fn getp(&self, param: &str) -> Value {
        self.host.instance().param_value(param).unwrap()
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
    /// then stops them.
    pub fn run(&self, n: u64) {
        let target = self.cycles() + n;
        self.host.start().unwrap();
        let end = Instant::now() + Duration::from_secs(10);
        while self.cycles() < target {
            assert!(Instant::now() < end, "threads did not run");
            std::thread::sleep(Duration::from_millis(1));
        }
        self.host.stop();
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
