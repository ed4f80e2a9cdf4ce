//! The veth pair the tests on a real wire share: the shell lines that
//! make it inside a network namespace, and how to tell that
//! `ethercat-sim` answers on its end. tests/soem.rs runs the lines in a
//! script under `unshare`; tests/veth_master.rs in a namespace of its
//! own thread.

/// What `ethercat-sim` prints once its slaves answer on the interface.
pub const SIM_READY: &str = "slave(s)";

/// Shell lines (one command a line, nothing else) that bring up the
/// loopback and a veth pair, `master` and `slave`, both ends up.
pub fn veth_script(master: &str, slave: &str) -> String {
    format!(
        "ip link set lo up\n\
         ip link add name {master} type veth peer name {slave}\n\
         ip link set {master} up\n\
         ip link set {slave} up\n"
    )
}
