//! hm2_eth inside LinuxCNC: `hostmot2.so` and `hm2_eth.so` in LinuxCNC's
//! halrun beside our host ([`hal_linuxcnc_tests::check`]), both talking
//! LBP16 over UDP to one `hm2-eth-sim` process (a simulated 7I96S) on a
//! port of its own, and a step generator moving the simulated axis in a
//! LinuxCNC thread; and `sim=7i93`, a simulated board inside each HAL
//! process.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::io::BufRead;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

use hal_linuxcnc_tests::{check, Case};

/// `hm2-eth-sim` as cargo built it, beside this test binary's directory
/// (`target/<profile>/hm2-eth-sim`).
fn sim_program() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let program = exe
        .parent()
        .and_then(|deps| deps.parent())
        .unwrap()
        .join("hm2-eth-sim");
    assert!(
        program.exists(),
        "{} is missing: build it first (cargo build -p hostmot2 --bin hm2-eth-sim)",
        program.display()
    );
    program
}

/// The simulated board, on a port the system picked; killed when dropped.
struct Board {
    child: Child,
    addr: String,
}

impl Board {
    fn start() -> Board {
        let mut child = Command::new(sim_program())
            .args(["--board", "7i96s", "--listen", "127.0.0.1:0"])
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let mut line = String::new();
        std::io::BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let addr = line.trim().rsplit(' ').next().unwrap().to_string();
        assert!(addr.starts_with("127.0.0.1:"), "hm2-eth-sim said {line:?}");
        Board { child, addr }
    }
}

impl Drop for Board {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hm2_eth_on_a_simulated_7i96s_in_linuxcnc_behaves_as_in_our_host() {
    let board = Board::start();
    // `check` runs LinuxCNC's session first: the board keeps its step
    // count between the sessions, so the move from 0 to 1.5 is
    // LinuxCNC's, and our host then finds the axis where the command
    // asks (its own moves are in hostmot2's tests).
    let args = format!("board_ip={}", board.addr);
    let out = check(&Case {
        module: "hm2_eth",
        lib: "lcnc_hm2_eth",
        args: &args,
        owners: &["hm2_eth"],
        // A late reply counts toward the packet-error limit, and on a
        // loaded machine a 1 ms thread outside realtime gets many: the
        // limit is raised so that the move is checked, not the machine's
        // load (hostmot2's own tests check the error handling). The
        // simulated board advances its time per read request, so fewer
        // cycles only take longer.
        run: "setp hm2_7i96s.0.packet-error-limit 1000000
setp hm2_7i96s.0.stepgen.00.position-scale 200
setp hm2_7i96s.0.stepgen.00.maxvel 4
setp hm2_7i96s.0.stepgen.00.maxaccel 40
setp hm2_7i96s.0.stepgen.00.enable 1
setp hm2_7i96s.0.stepgen.00.position-cmd 1.5
addf hm2_7i96s.0.read t
addf hm2_7i96s.0.write t
start
loadusr -w sleep 3
getp hm2_7i96s.0.stepgen.00.position-fb
getp hm2_7i96s.0.io_error
stop",
        refused: &["board_ip=192.168.1", "board_ip=300.1.1.1"],
        needs: &[("hostmot2", "lcnc_hostmot2")],
    });
    out.assert_axis_at(1.5, "FALSE", "io_error");
}

#[test]
#[cfg_attr(
    not(linuxcnc_peer),
    ignore = "needs LinuxCNC unpacked (scripts/linuxcnc-peer install) and root for its mount namespace"
)]
fn hm2_eth_sim_in_linuxcnc_runs_a_simulated_7i93_in_process() {
    // Each session has its own simulated board inside its HAL process:
    // no hm2-eth-sim, no socket; board_ip only names the board.
    let out = check(&Case {
        module: "hm2_eth",
        lib: "lcnc_hm2_eth",
        args:
            "board_ip=10.10.10.10 sim=7i93 config=\"num_encoders=4 num_pwmgens=4 num_stepgens=3\"",
        owners: &["hm2_eth"],
        run: "setp hm2_7i93.0.stepgen.00.position-scale 200
setp hm2_7i93.0.stepgen.00.maxvel 4
setp hm2_7i93.0.stepgen.00.maxaccel 40
setp hm2_7i93.0.stepgen.00.enable 1
setp hm2_7i93.0.stepgen.00.position-cmd 1.5
addf hm2_7i93.0.read-request t
addf hm2_7i93.0.read t
addf hm2_7i93.0.write t
start
loadusr -w sleep 3
getp hm2_7i93.0.stepgen.00.position-fb
getp hm2_7i93.0.packet-error-total
stop",
        refused: &["sim=7i99", "sim=7i93,7i93 board_ip=10.10.10.10"],
        needs: &[("hostmot2", "lcnc_hostmot2")],
    });
    out.assert_axis_at(1.5, "0", "no packet error in process");
}
