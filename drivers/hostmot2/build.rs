//! Tells the tests whether Mesa's mesaflash can run here: cfg
//! `mesaflash_peer`, and its path in `MESAFLASH_PEER_BIN`, when it is
//! unpacked (scripts/mesaflash-peer install; its prefix is
//! $MESAFLASH_PEER_PREFIX, else target/mesaflash-peer). Without it the
//! tests against it (tests/mesaflash.rs) are reported as ignored, with
//! that reason.
//!
//! Likewise cfg `pymodbus_peer` and `PYMODBUS_PYTHON` when the
//! workspace's Python environment (`$HAL_PYTHON_VENV`, else
//! target/python-venv, filled by scripts/install-deps) has pymodbus and
//! pyserial, for hm2_modbus against pymodbus (tests/modbus_pymodbus.rs); see
//! build-support/pymodbus_probe.rs.

use std::path::PathBuf;

include!("../../build-support/pymodbus_probe.rs");

fn main() {
    pymodbus_probe();
    println!("cargo:rustc-check-cfg=cfg(mesaflash_peer)");
    println!("cargo:rerun-if-env-changed=MESAFLASH_PEER_PREFIX");
    let prefix = std::env::var_os("MESAFLASH_PEER_PREFIX")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let here = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
            here.join("../../target/mesaflash-peer")
        });
    let binary = prefix.join("usr/bin/mesaflash");
    println!("cargo:rerun-if-changed={}", binary.display());
    if binary.exists() {
        println!("cargo:rustc-cfg=mesaflash_peer");
        println!("cargo:rustc-env=MESAFLASH_PEER_BIN={}", binary.display());
        let libs = prefix.join("usr/lib/x86_64-linux-gnu");
        println!("cargo:rustc-env=MESAFLASH_PEER_LIBS={}", libs.display());
    }
}
