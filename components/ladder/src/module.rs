//! `loadrt classicladder_rt`: LinuxCNC's ClassicLadder realtime module.
//! Its parameters size the PLC (LinuxCNC's names and defaults; 0 or a
//! negative value keeps the default, as there); it makes the pins
//! `classicladder.0.in-NN`, `out-NN`, `s32in-NN`, `s32out-NN`,
//! `floatin-NN`, `floatout-NN` and `hide_gui`, the parameter
//! `classicladder.ladder-state` (0 until a program is loaded, 2 while it
//! runs) and the funct `classicladder.0.refresh`. The funct takes a new
//! program from the loader's region ([`crate::handoff`]), and, each time
//! at least a millisecond has passed, reads the inputs, scans the rungs
//! with the milliseconds passed, and writes the outputs.

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, In, Out, Param, Pin, Result, Ro};

use crate::handoff::{self, Status};
use crate::model::{Program, Sizes};
use crate::runtime::Engine;

/// The most of any one object a module may be asked for.
pub const MAX_SIZE: i64 = 10_000;

/// The settable sizes, as `loadrt` parameters.
const PARAMS: &[ParamDecl] = &{
    const N: usize = settable();
    let mut out = [ParamDecl {
        name: "",
        kind: ParamKind::Int,
        help: "",
    }; N];
    let (mut i, mut k) = (0, 0);
    while i < Sizes::COUNT {
        if let (Some(name), help) = Sizes::PARAMS[i] {
            out[k] = ParamDecl {
                name,
                kind: ParamKind::Int,
                help,
            };
            k += 1;
        }
        i += 1;
    }
    out
};

/// How many sizes are `loadrt` parameters.
const fn settable() -> usize {
    let (mut i, mut n) = (0, 0);
    while i < Sizes::COUNT {
        if Sizes::PARAMS[i].0.is_some() {
            n += 1;
        }
        i += 1;
    }
    n
}

/// The `classicladder_rt` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "classicladder_rt",
    params: PARAMS,
    help: "ClassicLadder: a ladder-logic PLC; load its program with loadusr classicladder FILE.clp",
    load,
};

/// The sizes `args` ask for.
pub fn sizes(args: &ModuleArgs) -> Result<Sizes> {
    let mut v = Sizes::default().to_array();
    for (slot, (param, _)) in v.iter_mut().zip(Sizes::PARAMS) {
        let Some(name) = param else { continue };
        match args.int(name) {
            Some(n) if n > MAX_SIZE => {
                return Err(HalError::ModuleParam {
                    module: MODULE.name.into(),
                    param: name.into(),
                    reason: format!("{n} is more than {MAX_SIZE}"),
                })
            }
            Some(n) if n > 0 => *slot = n as usize,
            _ => {}
        }
    }
    Ok(Sizes::from_array(v))
}

/// The pins of the module.
struct Pins {
    inputs: Vec<Pin<bool, In>>,
    outputs: Vec<Pin<bool, Out>>,
    s32_in: Vec<Pin<i32, In>>,
    s32_out: Vec<Pin<i32, Out>>,
    float_in: Vec<Pin<f64, In>>,
    float_out: Vec<Pin<f64, Out>>,
    state: Param<i32, Ro>,
}

fn pins(c: &hal_core::Component, s: &Sizes) -> Result<Pins> {
    let n = |kind: &str, i: usize| format!("classicladder.0.{kind}-{i:02}");
    let inputs = (0..s.inputs)
        .map(|i| c.pin(&n("in", i)))
        .collect::<Result<_>>()?;
    let _hide_gui: Pin<bool, In> = c.pin("classicladder.0.hide_gui")?;
    let s32_in = (0..s.s32_in)
        .map(|i| c.pin(&n("s32in", i)))
        .collect::<Result<_>>()?;
    let float_in = (0..s.float_in)
        .map(|i| c.pin(&n("floatin", i)))
        .collect::<Result<_>>()?;
    let outputs = (0..s.outputs)
        .map(|i| c.pin(&n("out", i)))
        .collect::<Result<_>>()?;
    let s32_out = (0..s.s32_out)
        .map(|i| c.pin(&n("s32out", i)))
        .collect::<Result<_>>()?;
    let float_out = (0..s.float_out)
        .map(|i| c.pin(&n("floatout", i)))
        .collect::<Result<_>>()?;
    Ok(Pins {
        inputs,
        outputs,
        s32_in,
        s32_out,
        float_in,
        float_out,
        state: c.param("classicladder.ladder-state", 0)?,
    })
}

/// A float input as ClassicLadder takes it: truncated toward zero,
/// saturated to s32 (NaN reads 0).
fn truncate(v: f64) -> i32 {
    v as i32
}

/// How many words of a new program the refresh funct decodes per
/// period: about 10 µs of work, so a default-sized program (11 000 words)
/// is taken in 6 periods and the largest sizes never stretch one period.
const DECODE_WORDS_PER_PERIOD: usize = 2048;

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let s = sizes(args)?;
    let mut b = host.new_rt_component("classicladder_rt")?;
    let c = b.component();
    let mut pins = pins(c, &s)?;
    let region = c.region(handoff::REGION, handoff::region_words(&s) * 8)?;
    handoff::init(region.words(), &s);
    let mut engine = Engine::new(&s);
    let mut current = Box::new(Program::empty(&s));
    let mut spare = Box::new(Program::empty(&s));
    let mut intake = handoff::Intake::new();
    let mut running = false;
    let mut leftover_ns: i64 = 0;
    b.funct("classicladder.0.refresh", true, move |ctx| {
        let words = region.words();
        if let Some((seq, verdict)) = intake.poll(words, &s, &mut spare, DECODE_WORDS_PER_PERIOD) {
            match verdict {
                Ok(()) => {
                    std::mem::swap(&mut current, &mut spare);
                    engine.install(&current);
                    running = true;
                    handoff::set_status(words, Status::Running(seq));
                }
                Err((part, item)) => handoff::set_status(words, Status::Refused(seq, part, item)),
            }
        }
        leftover_ns = leftover_ns.saturating_add(ctx.period().max(0));
        let ms = leftover_ns / 1_000_000;
        leftover_ns %= 1_000_000;
        pins.state.set(if running { 2 } else { 0 });
        if ms < 1 || !running {
            return;
        }
        let v = &mut engine.vars;
        for (slot, pin) in v.inputs.iter_mut().zip(&pins.inputs) {
            *slot = pin.get();
        }
        for (slot, pin) in v.word_in.iter_mut().zip(&pins.s32_in) {
            *slot = pin.get();
        }
        for (slot, pin) in v.float_in.iter_mut().zip(&pins.float_in) {
            *slot = truncate(pin.get());
        }
        engine.scan(&current, ms.min(i32::MAX as i64) as i32);
        let v = &engine.vars;
        for (pin, val) in pins.outputs.iter_mut().zip(&v.outputs) {
            pin.set(*val);
        }
        for (pin, val) in pins.s32_out.iter_mut().zip(&v.word_out) {
            pin.set(*val);
        }
        for (pin, val) in pins.float_out.iter_mut().zip(&v.float_out) {
            pin.set(*val as f64);
        }
    })?;
    b.ready()
}
