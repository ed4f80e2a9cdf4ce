//! Read-ahead speed: blocks per second read (and executed into a
//! canon that keeps its world model but prints nothing) on a generated
//! program, and the same program through LinuxCNC's rs274 when
//! `LINUXCNC_RS274` names it (whole process, output to /dev/null).
//!
//! `rs274-bench [LINES]` (default 1000000).

fn main() {
    println!("rs274-bench: see the crate documentation");
}
