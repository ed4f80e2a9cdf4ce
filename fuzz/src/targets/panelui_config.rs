//! panelui's panel files, `_panelui.ini`
//! ([`hal_launcher::fuzz::panelui_config`]).

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "panelui_config",
    run: hal_launcher::fuzz::panelui_config,
    dictionary: &[
        "[HAL_PREFIX]\n", "[RADIO_BUTTONS]\n", "[TOGGLE_BUTTONS]\n", "[MOMENTARY_BUTTONS]\n",
        "[[", "]]", "[[[", "]]]", "\n", " = ", ",", "#", "\"", "'", "KEY", "R0C1", "R7C7",
        "OUTPUT", "BIT", "S32", "U32", "FLOAT", "COMMAND", "NONE", "STATUS_PIN", "TRUE",
        "FALSE", "TRUE_STATE", "FALSE_STATE", "TRUE_COMMAND", "FALSE_COMMAND", "DEFAULT",
        "GROUP", "GROUP_OUTPUT", "NAME", "mdi", "continuous_jog", "flood_on", "user_cmd",
        "0", "-1", "2.5", "g",
    ],
    generate: None,
};
