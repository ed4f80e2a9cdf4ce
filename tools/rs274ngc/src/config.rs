//! Interpreter options that come from the machine's configuration
//! (LinuxCNC's [RS274NGC] INI section and a few others). The library
//! takes them as plain values; reading an INI file is the caller's job.

use std::collections::BTreeMap;
use std::path::PathBuf;

/// Optional interpreter features: `[RS274NGC]` `RETAIN_G43`,
/// `OWORD_NARGS`, `INI_VARS`, `HAL_PIN_VARS` and `NO_DOWNCASE_OWORD` since
/// LinuxCNC 2.8 (before, bits of `FEATURES`, which 2.9 ignores).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Features {
    /// RETAIN_G43: keep G43 in effect across tool changes.
    pub retain_g43: bool,
    /// OWORD_NARGS: subroutines see the number of arguments as `#<n_args>`.
    pub oword_n_args: bool,
    /// INI_VARS: `#<_ini[section]name>` reads the INI file.
    pub ini_vars: bool,
    /// HAL_PIN_VARS: `#<_hal[name]>` reads HAL items.
    pub hal_pin_vars: bool,
    /// NO_DOWNCASE_OWORD: O-word names keep their case.
    pub no_downcase_oword: bool,
}

impl Features {
    /// The features as LinuxCNC 2.9 reads them from `[RS274NGC]`: `get`
    /// answers a key's value. `INI_VARS` and `HAL_PIN_VARS` are on unless
    /// set to 0; the others are off unless set to a non-zero integer.
    pub fn from_ini_keys<'a>(get: impl Fn(&str) -> Option<&'a str>) -> Features {
        let on = |key: &str, default: bool| {
            get(key)
                .and_then(|v| v.trim().parse::<i64>().ok())
                .map_or(default, |v| v != 0)
        };
        Features {
            retain_g43: on("RETAIN_G43", false),
            oword_n_args: on("OWORD_NARGS", false),
            ini_vars: on("INI_VARS", true),
            hal_pin_vars: on("HAL_PIN_VARS", true),
            no_downcase_oword: on("NO_DOWNCASE_OWORD", false),
        }
    }
}

/// Everything configurable about the interpreter.
#[derive(Debug, Clone)]
pub struct Config {
    /// The parameter (.var) file read at start and written at exit; none
    /// means parameters are not kept.
    pub parameter_file: Option<PathBuf>,
    /// Directories searched for `name.ngc` when `O<name> call` names a
    /// subroutine not defined in the program.
    pub subroutine_path: Vec<PathBuf>,
    /// Directories searched for user M-code programs (M100-M199).
    pub user_m_path: Vec<PathBuf>,
    /// Searched first for subroutine files (`[DISPLAY]PROGRAM_PREFIX`);
    /// the current directory when None, as in standalone rs274.
    pub program_prefix: Option<PathBuf>,
    /// Optional features.
    pub features: Features,
    /// Arc end radius tolerance, inch programs.
    pub center_arc_radius_tolerance_inch: f64,
    /// Arc end radius tolerance, mm programs.
    pub center_arc_radius_tolerance_mm: f64,
    /// Clear G52/G92 offsets at program end and start.
    pub disable_g92_persistence: bool,
    /// Refuse Fanuc-style M98/M99 subprograms.
    pub disable_fanuc_style_sub: bool,
    /// Random tool changer: tools swap pockets on change.
    pub random_toolchanger: bool,
    /// M6 moves to the G30 position first.
    pub tool_change_at_g30: bool,
    /// M6 raises Z to machine zero first.
    pub tool_change_quill_up: bool,
    /// M6 leaves the spindle turning.
    pub tool_change_with_spindle_on: bool,
    /// Added to M19 orientations, degrees.
    pub orient_offset: f64,
    /// Closing a program does not reset the interpreter (LinuxCNC turns
    /// this on whenever it has an INI file); the reset comes at exit.
    pub lazy_close: bool,
    /// M99 in the main program starts it over (task); when false it ends
    /// the program as M2 does (standalone rs274).
    pub loop_on_main_m99: bool,
    /// The INI file's entries, `(section, key) -> value` as written, for
    /// `#<_ini[section]key>` (FEATURES bit 2). The first of repeated
    /// keys is kept.
    pub ini_values: BTreeMap<(String, String), String>,
    /// Most moves one canned-cycle block may make (its holes times each
    /// hole's traverses and pecks). A block that would make more, or pecks
    /// too small to deepen the hole at its size, is refused before it
    /// drills: an L or Q typo must not queue millions of moves.
    pub max_cycle_moves: u32,
    /// How many spindles the machine has (`[TRAJ]SPINDLES`), selected by
    /// the `$` word; 1 to [`MAX_SPINDLES`].
    pub spindles: u32,
}

/// The most spindles LinuxCNC's motion controller has.
pub const MAX_SPINDLES: u32 = 8;

impl Config {
    /// [`Config::spindles`] within 1 to [`MAX_SPINDLES`].
    pub fn spindle_count(&self) -> usize {
        self.spindles.clamp(1, MAX_SPINDLES) as usize
    }
}

/// The default of [`Config::max_cycle_moves`]: far beyond any drilling
/// pattern a CAM post-processor writes, and a few seconds of work.
pub const DEFAULT_MAX_CYCLE_MOVES: u32 = 1_000_000;

impl Default for Config {
    fn default() -> Self {
        Config {
            parameter_file: None,
            subroutine_path: Vec::new(),
            user_m_path: Vec::new(),
            program_prefix: None,
            features: Features::default(),
            center_arc_radius_tolerance_inch: 2.0 * 0.001 * std::f64::consts::SQRT_2,
            center_arc_radius_tolerance_mm: 2.0 * 0.01 * std::f64::consts::SQRT_2,
            disable_g92_persistence: false,
            disable_fanuc_style_sub: false,
            random_toolchanger: false,
            tool_change_at_g30: false,
            tool_change_quill_up: false,
            tool_change_with_spindle_on: false,
            orient_offset: 0.0,
            lazy_close: false,
            loop_on_main_m99: false,
            ini_values: BTreeMap::new(),
            max_cycle_moves: DEFAULT_MAX_CYCLE_MOVES,
            spindles: 1,
        }
    }
}
