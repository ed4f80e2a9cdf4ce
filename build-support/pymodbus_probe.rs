// Included by the build scripts of the crates whose tests run against
// PyPI's pymodbus (mb2hal in drivers/serial, hm2_modbus in
// drivers/hostmot2).

/// Sets cfg `pymodbus_peer`, and `PYMODBUS_PYTHON` to the Python that has
/// it, when the workspace's Python environment (`$HAL_PYTHON_VENV`, else
/// target/python-venv, which scripts/install-deps fills) imports
/// pymodbus and pyserial; without them the tests against pymodbus are
/// reported as ignored, with that reason. The crate being built is two
/// directories below the workspace root.
fn pymodbus_probe() {
    use std::path::PathBuf;
    println!("cargo:rustc-check-cfg=cfg(pymodbus_peer)");
    println!("cargo:rerun-if-env-changed=HAL_PYTHON_VENV");
    let venv = std::env::var_os("HAL_PYTHON_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let here = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
            here.join("../../target/python-venv")
        });
    // install-deps touches this marker after installing pymodbus, so the
    // probe runs again then.
    println!(
        "cargo:rerun-if-changed={}",
        venv.join(".pymodbus-installed").display()
    );
    let python = venv.join("bin/python");
    let found = std::process::Command::new(&python)
        .args(["-c", "import pymodbus, serial"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if found {
        println!("cargo:rustc-cfg=pymodbus_peer");
        println!("cargo:rustc-env=PYMODBUS_PYTHON={}", python.display());
    }
}
