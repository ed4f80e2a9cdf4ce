//! The fuzz targets, one module each. A module defines
//! `pub static TARGET: Target`; its line below registers it (a test of
//! the same name, an entry in [`ALL`], a corpus directory of the same
//! name under `fuzz/corpus/`).

crate::register_targets! {
    halcmd_lexer,
    halcmd_dispatch,
    loadrt_params,
    halstreamer_input,
}
