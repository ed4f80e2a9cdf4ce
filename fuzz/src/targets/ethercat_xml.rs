//! linuxcnc-ethercat's `ethercat-conf.xml` ([`hal_ethercat::fuzzing::xml`]):
//! errors name file, line and element; an accepted configuration has a
//! positive period and PDO entries whose complex parts fit them.

use crate::Target;

/// The target.
pub static TARGET: Target = Target {
    name: "ethercat_xml",
    run: hal_ethercat::fuzzing::xml,
    dictionary: &[
        "<masters>", "</masters>", "<master ", "</master>", "<slave ", "</slave>", "/>",
        "<syncManager ", "<pdo ", "<pdoEntry ", "<complexEntry ", "<dcConf ", "<sdoConfig ",
        "<sdoDataRaw ", "<modParam ", "<watchdog ", "idx=\"", "subIdx=\"", "bitLen=\"",
        "halPin=\"", "halType=\"", "type=\"generic\"", "type=\"EL7041\"", "appTimePeriod=\"",
        "refClockSyncCycles=\"", "vid=\"", "pid=\"", "dir=\"in\"", "dir=\"out\"",
        "sync0Cycle=\"*", "complex", "float-unsigned", "s32", "u32", "bit", "0x", "\"",
    ],
    generate: None,
};
