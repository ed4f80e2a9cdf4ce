//! Build script of every module crate here: links the `<module>.so`
//! with `-z nodelete`. LinuxCNC's rtapi_app dlcloses a module at unload;
//! Rust's standard library in the module (thread-local destructors,
//! helper threads) is not safe to unmap, and keeping the image keeps the
//! module's pool of HAL shared-memory cells for its next load (see
//! hal_driver::linuxcnc).

fn main() {
    println!("cargo:rustc-cdylib-link-arg=-Wl,-z,nodelete");
    println!("cargo:rerun-if-changed=../nodelete.rs");
}
