//! `lcec_conf`'s command line (clap), in a file of its own so its man
//! page is built from it too (tools/cli/tests/man_pages.rs includes it).

use clap::Parser;

/// Reads linuxcnc-ethercat's configuration for `loadrt lcec`.
#[derive(Parser, Debug)]
#[command(
    name = "lcec_conf",
    version,
    after_help = "Examples:\n  \
        loadusr -W lcec_conf ethercat-conf.xml\n  \
        loadrt lcec\n\n\
        As in linuxcnc-ethercat: the file is checked (an error names its line and element) \
        and kept in the HAL instance while lcec_conf runs, as the user component lcec_conf; \
        loadrt lcec then takes it from there. `loadrt lcec config=FILE` reads a file \
        without lcec_conf. lcec_conf ends with the HAL session (or on SIGTERM)."
)]
pub struct Args {
    /// linuxcnc-ethercat's configuration file (ethercat-conf.xml).
    pub file: std::path::PathBuf,
}
