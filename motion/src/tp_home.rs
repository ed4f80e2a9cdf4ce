//! `tpmod` and `homemod`: LinuxCNC loads its trajectory planner and its
//! homing code as modules of their own before the motion controller. Here
//! both are built into `motmod`, so these modules only mark that the
//! default planner and homing were asked for; loading them creates
//! nothing. A user-built replacement (`[TRAJ]TPMOD`, `[EMCMOT]HOMEMOD`)
//! is a module this suite does not have, and fails to load by its name.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::Host;

fn nothing_to_create(_: &Host, _: &ModuleArgs) -> hal_core::Result<()> {
    Ok(())
}

/// `loadrt tpmod`.
pub static TPMOD: ModuleDef = ModuleDef {
    name: "tpmod",
    params: &[],
    help: "the coordinated trajectory planner (built into motmod here)",
    load: nothing_to_create,
};

/// `loadrt homemod`.
pub static HOMEMOD: ModuleDef = ModuleDef {
    name: "homemod",
    params: &[],
    help: "the homing module (built into motmod here)",
    load: nothing_to_create,
};

/// Both modules, for the registry.
pub fn modules() -> [&'static ModuleDef; 2] {
    [&TPMOD, &HOMEMOD]
}
