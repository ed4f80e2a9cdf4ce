//! `plasmac`: LinuxCNC 2.9's plasma cutting controller, the realtime half
//! of QtPlasmaC. A singleton (`loadrt plasmac` makes `plasmac` and its
//! function `plasmac`) that runs the cut cycle as a state machine:
//! probe the stock (float switch or ohmic probe), pierce (with arc start
//! retries), cut with torch height control (arc voltage PID in modes 0
//! and 1, up/down inputs in mode 2, corner lock and void lock), end the
//! cut at the safe height, and on a pause, stop or error leave the torch
//! off at the top, where paused motion, consumable change, cut recovery,
//! torch pulse and ohmic test may run. It moves Z (and X/Y for a
//! consumable change or cut recovery) through motion's external offsets
//! (`axis.N.eoffset-counts`, `-scale`, `-enable`) and asks halui to
//! pause, resume or stop the program.
//!
//! Its pins are LinuxCNC's, with their types, directions and defaults.
//! `debug-print` prints each state change. These inputs are read by
//! nothing here, as they are only carried for a GUI or kept for
//! compatibility: `kerf-width`, `requested-velocity`, `multi-tool`,
//! `gcode-scale`, `offset-set-probe`, `offset-set-scribe`,
//! `offset-probe-delay`, `offset-probe-x`, `offset-probe-y`,
//! `laser-recovery-start`, `laser-x-offset`, `laser-y-offset`,
//! `offsets-active` and `ohmic-max-attempts` (the ohmic probe is tried
//! once; the float switch is always the fallback). `program-run` and
//! `laser-recovery-state` stay at zero.
//! Errors are printed once on stderr, and `state-out` and
//! `stop-type-out` carry LinuxCNC's numbers.

mod cut;
mod machine;
mod moves;
mod pins;
mod probe;
mod sense;
mod state;
mod stats;
mod stops;
mod thc;
mod torch;

#[cfg(test)]
mod tests;

use hal_core::Result;

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;
use crate::notice::Notice;
use machine::Plasmac;
use pins::{InPins, Inputs, OutPins};
use state::{FAULT_TEXTS, STATE_TEXTS};

/// The `plasmac` component.
pub struct PlasmacComp;
impl HalComp for PlasmacComp {
    const NAME: &'static str = "plasmac";
    const SINGLETON: bool = true;
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let inp = InPins::new(inst)?;
        let out = OutPins::new(inst)?;
        let faults = Notice::new(FAULT_TEXTS);
        let states = Notice::new(STATE_TEXTS);
        let mut p = Plasmac::default();
        let mut i = Inputs::default();
        inst.funct("_", true, move |ctx| {
            inp.read(&mut i);
            let before = p.state;
            let fault = p.step(&i, ctx.period());
            out.write(&p.o);
            if let Some(f) = fault {
                faults.post(f.index());
            }
            if i.debug_print && p.state != before {
                states.post(p.state.number() as usize);
            }
        })
    }
}
halcomp_module!(pub MODULE, PlasmacComp, "plasma cutter controller");
