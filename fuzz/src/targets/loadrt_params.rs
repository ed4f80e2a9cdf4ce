//! `loadrt` of every registry module with fuzzed module parameters,
//! straight into an in-process host (no socket, no halcmd).
//!
//! An input is up to eight lines `MODULE key=value ...` loaded in order
//! (so `motmod` can find the `trivkins` loaded before it); a first word
//! that names no module picks one by its bytes, so every input loads
//! something. Checked besides "no panic": a failing `loadrt` leaves the
//! instance and the host exactly as before it (components, pins, params,
//! signals, functions, threads, regions, loaded modules) and says what
//! failed; after the input, `unloadrt all` (and deleting the threads,
//! which outlive their module as in LinuxCNC) brings the instance back
//! to empty. Driver modules come from [`crate::registry`], so only their
//! simulated backends are ever loaded.
//!
//! The stable engine adds inputs of its own: a random module with keys
//! from its parameter table and values of its kinds.

use std::cell::RefCell;

use fastrand::Rng;
use hal_core::module::{ModuleDef, ParamKind};
use hal_core::{Host, Registry};
use hal_lang::lexer::tokenize;

use crate::mutate::NUMBERS;
use crate::registry::fuzz_registry;
use crate::snapshot::{delete_threads, Snapshot};
use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "loadrt_params",
    run,
    dictionary: &[
        "count=",
        "names=",
        "personality=",
        "cfg=",
        "depth=",
        "name1=",
        "period1=",
        "fp1=",
        "num_chan=",
        "step_type=",
        "ctrl_type=",
        "coordinates=",
        "kinstype=",
        "num_joints=",
        "servo_period_nsec=",
        "base_period_nsec=",
        "backend=",
        "sim=",
        "sim_boards=",
        "sim_ids=",
        "config=",
        "test_pattern=",
        "base=",
        "dio=",
        "address=",
        "bus=",
        "inputs=",
        "outputs=",
        "\n",
        ",",
        "\"",
        "=",
    ],
    generate: Some(generate),
};

/// Lines of one input that are loaded; the rest are ignored.
const MAX_LINES: usize = 8;

struct Fixture {
    host: Host,
    registry: Registry,
    names: Vec<&'static str>,
    empty: Snapshot,
}

thread_local! {
    static FIXTURE: RefCell<Option<Fixture>> = const { RefCell::new(None) };
}

fn fixture<R>(f: impl FnOnce(&Fixture) -> R) -> R {
    FIXTURE.with(|cell| {
        let mut cell = cell.borrow_mut();
        let fx = cell.get_or_insert_with(|| {
            let host = Host::create(crate::host_config("loadrt", 2 << 20)).expect("test host");
            let registry = fuzz_registry();
            let names = registry.names();
            let empty = Snapshot::of_host(&host);
            Fixture {
                host,
                registry,
                names,
                empty,
            }
        });
        f(fx)
    })
}

/// The module a line's first word names, or one picked by its bytes.
fn module(fx: &Fixture, word: &str) -> &'static ModuleDef {
    fx.registry.find(word).unwrap_or_else(|| {
        let pick = word.bytes().fold(0usize, |a, b| a.wrapping_mul(31) ^ b as usize);
        fx.registry
            .find(fx.names[pick % fx.names.len()])
            .expect("a listed name")
    })
}

fn run(input: &[u8]) {
    let text = String::from_utf8_lossy(input);
    fixture(|fx| {
        let host = &fx.host;
        // A finding (a panic below) may have left modules loaded.
        if !host.loaded_modules().is_empty() {
            let _ = host.unloadrt("all");
            delete_threads(host);
        }
        for line in text.lines().take(MAX_LINES) {
            // Words as halcmd splits them: a quoted value keeps its spaces.
            let Ok(words) = tokenize(line, None) else {
                continue;
            };
            let Some((first, args)) = words.split_first() else {
                continue;
            };
            let def = module(fx, first);
            let before = Snapshot::of_host(host);
            if let Err(e) = host.loadrt(def, args) {
                let message = e.to_string();
                assert!(!message.is_empty(), "loadrt {} {args:?}: empty error", def.name);
                let after = Snapshot::of_host(host);
                if let Some(diff) = before.difference(&after) {
                    panic!(
                        "failed `loadrt {} {}` ({message}) left the instance changed: {diff}",
                        def.name,
                        args.join(" ")
                    );
                }
            }
        }
        if let Err(e) = host.unloadrt("all") {
            panic!("unloadrt all after {text:?}: {e}");
        }
        delete_threads(host);
        if let Some(diff) = fx.empty.difference(&Snapshot::of_host(host)) {
            panic!("unloadrt all after {text:?} left: {diff}");
        }
    });
}

/// A random value for a parameter of `kind`.
fn value(rng: &mut Rng, kind: ParamKind) -> String {
    let number = |rng: &mut Rng| match rng.u8(..3) {
        0 => NUMBERS[rng.usize(..NUMBERS.len())].to_string(),
        _ => rng.u32(0..6).to_string(),
    };
    let word = |rng: &mut Rng| {
        const WORDS: &[&str] = &[
            "a",
            "x",
            "XYZ",
            "xyz",
            "XYZABCUVW",
            "both",
            "BOTH",
            "inverse",
            "ffb",
            "bsuSUlk",
            "0x378",
            "0 in",
            "0x378 out sim",
            "1 x simloop",
            "0 epp",
            "378_in",
            "bad=name",
            "sp ace",
            "#",
            "\u{e9}",
            "sim",
            "simloop",
            "5i25",
            "7i92",
            "lite",
            "IIOO",
            "0x40",
            "num_encoders=2 num_stepgens=-1",
        ];
        match rng.u8(..8) {
            0 => "n".repeat(rng.usize(40..300)),
            1 => NUMBERS[rng.usize(..NUMBERS.len())].to_string(),
            _ => WORDS[rng.usize(..WORDS.len())].to_string(),
        }
    };
    let list = |rng: &mut Rng, n: usize, item: &dyn Fn(&mut Rng) -> String| {
        (0..rng.usize(0..=n + 1))
            .map(|_| item(rng))
            .collect::<Vec<_>>()
            .join(",")
    };
    match kind {
        ParamKind::Int | ParamKind::Long => number(rng),
        ParamKind::Str => word(rng),
        ParamKind::IntArray(n) | ParamKind::LongArray(n) => list(rng, n.min(16), &number),
        ParamKind::StrArray(n) => list(rng, n.min(16), &word),
    }
}

/// One to three `loadrt` lines for random modules of the registry, with
/// keys from their tables (now and then an unknown one) and values of
/// the declared kinds.
fn generate(rng: &mut Rng) -> Vec<u8> {
    let mut out = String::new();
    fixture(|fx| {
        for _ in 0..rng.usize(1..=3) {
            let def = fx
                .registry
                .find(fx.names[rng.usize(..fx.names.len())])
                .expect("a listed name");
            out.push_str(def.name);
            for _ in 0..rng.usize(0..=4) {
                out.push(' ');
                match def.params.get(rng.usize(..def.params.len() + 1)) {
                    Some(p) => {
                        let v = value(rng, p.kind);
                        if v.contains(char::is_whitespace) {
                            out.push_str(&format!("{}=\"{v}\"", p.name));
                        } else {
                            out.push_str(&format!("{}={v}", p.name));
                        }
                    }
                    None => out.push_str("bogus=1"),
                }
            }
            out.push('\n');
        }
    });
    out.into_bytes()
}
