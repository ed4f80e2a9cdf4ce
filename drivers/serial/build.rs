//! Tells the tests whether pymodbus can run here (cfg `pymodbus_peer`,
//! see build-support/pymodbus_probe.rs): without it the tests of mb2hal
//! against pymodbus (tests/mb2hal_pymodbus.rs) are reported as ignored,
//! with that reason.

include!("../../build-support/pymodbus_probe.rs");

fn main() {
    pymodbus_probe();
}
