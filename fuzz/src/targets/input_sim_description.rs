//! hal_input's simulated devices' description (`--sim FILE`,
//! [`hal_input::fuzzing::sim_description`]): parsed, or refused naming
//! its line; what parses keeps its script in time order and its codes
//! within hal_input's tables.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "input_sim_description",
    run: hal_input::fuzzing::sim_description,
    dictionary: &[
        "device ", "node ", "phys ", "id 0003 046d c21d 0111", "keys ", "held ", "rel ", "abs ",
        "leds ", "events ", "at ", "unplug", "EV_KEY", "EV_ABS", "EV_REL", "EV_SYN", "BTN_A",
        "ABS_X", "REL_WHEEL", "LED_NUML", "0x", "-", "\n", "#",
    ],
    generate: None,
};
