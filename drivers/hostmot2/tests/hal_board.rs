//! hal-board on a fake sysfs PCI tree (a 5i25 whose BAR file holds the
//! simulated firmware's image) and on the simulated boards: list,
//! idrom, read, write, watch, and its refusals.

// Test code: a failed unwrap is a failed test, with its message.
#![cfg_attr(test, allow(clippy::unwrap_used))]

use std::process::{Command, Output};

use hal_driver::pci::fake::{FakeBar, FakeSysfs};
use hal_driver::pci::PciIds;
use hostmot2::sim::boards;

fn board_tool(sysfs: &FakeSysfs, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hal-board"))
        .arg("--sysfs")
        .arg(sysfs.dir())
        .args(args)
        .output()
        .expect("hal-board runs")
}

fn stdout(o: &Output) -> String {
    assert!(
        o.status.success(),
        "hal-board failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    assert!(!o.status.success(), "hal-board should have failed");
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fake tree with a 5i25 at 0000:02:00.0 holding the simulated
/// firmware's registers, and an empty 5i24 at 0000:03:00.0.
fn tree(tag: &str) -> FakeSysfs {
    let fake = FakeSysfs::new(tag).unwrap();
    let add = |address, id: u16| {
        let ids = PciIds {
            vendor: 0x2718,
            device: id,
            subvendor: 0x2718,
            subdevice: id,
        };
        let bar = FakeBar::Mem {
            start: 0xfe00_0000,
            len: 0x1_0000,
        };
        fake.add_device(address, ids, &[bar]).unwrap()
    };
    let dir = add("0000:02:00.0", 0x5125);
    let image = boards::preset("5i25").unwrap().image();
    let bytes: Vec<u8> = image.iter().flat_map(|w| w.to_le_bytes()).collect();
    std::fs::write(dir.join("resource0"), bytes).unwrap();
    add("0000:03:00.0", 0x5124);
    fake
}

#[test]
fn lists_pci_and_simulated_boards() {
    let fake = tree("hal-board-list");
    let out = stdout(&board_tool(&fake, &["list"]));
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[0],
        "0000:02:00.0  2718:5125 (subsystem 2718:5125)  5i25  hm2_pci: \
         MESA5I25 (HostMot2, IDROM type 3, 2 × 17 I/O)"
    );
    assert!(
        lines[1].starts_with("0000:03:00.0  2718:5124 (subsystem 2718:5124)  5i24  hm2_pci: (not readable: invalid cookie, got 0x00000000"),
        "{}",
        lines[1]
    );
    assert_eq!(
        lines[2],
        "Ethernet boards are not scanned: give a board's address (hal-board idrom 192.168.1.121)"
    );
    assert_eq!(lines[3], "simulated boards (hm2_pci sim=NAME):");
    assert!(out.contains("sim:7i96s  MESA7I96 (HostMot2, IDROM type 3, 3 × 17 I/O)\n"));
    assert!(out.contains("sim:6i25  MESA6I25 (HostMot2, IDROM type 3, 2 × 17 I/O)\n"));
    let empty = FakeSysfs::new("hal-board-empty").unwrap();
    let out = stdout(&board_tool(&empty, &["list"]));
    assert!(out.starts_with("no board any driver knows under "), "{out}");
}

#[test]
fn idrom_is_printed_as_mesaflash_does() {
    let fake = tree("hal-board-idrom");
    let out = stdout(&board_tool(&fake, &["idrom", "0000:02:00.0"]));
    assert!(out.starts_with("Configuration Name: HOSTMOT2\n\nGeneral configuration information:\n\n  BoardName : MESA5I25\n"));
    assert!(out.contains("\n  Module: StepGen\n  There are 10 of StepGen in configuration\n"));
    assert!(out.contains("\nIO Connections for P3\nDB25 pin#"));
    assert!(out.contains(
        "\n 1                      0   IOPort       StepGen          0        Step/Table1     (Out)\n"
    ));
    // The alias and a simulated board give the same listing.
    let sim = stdout(&board_tool(&fake, &["readhmid", "sim:5i25"]));
    assert_eq!(sim, out);
    let e = stderr(&board_tool(&fake, &["idrom", "0000:03:00.0"]));
    assert!(e.contains("invalid cookie, got 0x00000000"), "{e}");
}

#[test]
fn single_registers_read_and_write() {
    let fake = tree("hal-board-rw");
    assert_eq!(
        stdout(&board_tool(&fake, &["read", "0000:02:00.0", "0x100"])),
        "55AACAFE\n"
    );
    assert_eq!(
        stdout(&board_tool(&fake, &["read", "pci:0000:02:00.0", "256"])),
        "55AACAFE\n"
    );
    stdout(&board_tool(
        &fake,
        &["write", "0000:02:00.0", "0x200", "0xC0000000"],
    ));
    assert_eq!(
        stdout(&board_tool(&fake, &["read", "0000:02:00.0", "0x200"])),
        "C0000000\n"
    );
    let enable = std::fs::read_to_string(fake.dir().join("0000:02:00.0/enable")).unwrap();
    assert_eq!(enable.trim(), "0", "enabled only while the tool runs");
    for (args, want) in [
        (
            &["read", "0000:02:00.0", "0x102"][..],
            "registers are 4-aligned",
        ),
        (
            &["read", "0000:02:00.0", "0x10000"][..],
            "address '0x10000'",
        ),
        (&["read", "0000:02:00.0", "cafe"][..], "address 'cafe'"),
        (
            &["write", "0000:02:00.0", "0x200", "0x100000000"][..],
            "value '0x100000000'",
        ),
        (
            &["read", "0000:09:00.0", "0x100"][..],
            "no HostMot2 board at '0000:09:00.0'",
        ),
        (
            &["read", "sim:7i99", "0x100"][..],
            "'7i99' is not a simulated board",
        ),
    ] {
        let e = stderr(&board_tool(&fake, args));
        assert!(
            e.starts_with("hal-board: ") && e.contains(want),
            "{args:?}: {e}"
        );
    }
}

#[test]
fn a_modules_registers_are_watched() {
    let fake = tree("hal-board-watch");
    let out = stdout(&board_tool(
        &fake,
        &["watch", "0000:02:00.0", "stepgen", "-n", "2", "-i", "1"],
    ));
    let frames: Vec<&str> = out.split("\n\n").filter(|f| !f.trim().is_empty()).collect();
    assert_eq!(frames.len(), 2, "{out}");
    let lines: Vec<&str> = frames[0].lines().collect();
    assert_eq!(
        lines[0],
        "5i25 at 0000:02:00.0 StepGen at 0x2000: 10 instance(s), version 2"
    );
    assert!(lines[1].starts_with("register         addr         0        1"));
    assert_eq!(lines.len(), 2 + 10, "ten registers");
    assert!(lines[2].starts_with("Rate             2000  00000000"));
    assert!(lines[11].starts_with("MasterDDS        2900  00000000"));
    // A simulated board's time moves between snapshots.
    let out = stdout(&board_tool(
        &fake,
        &["watch", "sim:6i25", "qcount", "-n", "2", "-i", "5"],
    ));
    let ts: Vec<&str> = out.lines().filter(|l| l.starts_with("TSCount")).collect();
    assert_eq!(ts.len(), 2);
    assert_ne!(ts[0], ts[1]);
    let e = stderr(&board_tool(
        &fake,
        &["watch", "sim:6i25", "stepgen", "-n", "1"],
    ));
    assert!(e.contains("the firmware has no module 'stepgen'"), "{e}");
}

#[test]
fn lists_motenc_boards_with_their_version_and_board_id() {
    let fake = FakeSysfs::new("hal-board-motenc").unwrap();
    let ids = PciIds {
        vendor: 0x10B5,
        device: 0x3001,
        subvendor: 0x10B5,
        subdevice: 0x9030,
    };
    let bars = [
        FakeBar::Unused,
        FakeBar::Unused,
        FakeBar::Mem {
            start: 0xfd00_0000,
            len: 0x200,
        },
    ];
    let lite = fake.add_device("0000:05:00.0", ids, &bars).unwrap();
    let mut regs = vec![0u8; 0x200];
    regs[0x14..0x18].copy_from_slice(&(2u32 << 16 | 0xFFFF).to_le_bytes()); // ID jumpers 2
    regs[0x1C..0x20].copy_from_slice(&1u32.to_le_bytes()); // MOTENC-Lite
    std::fs::write(lite.join("resource2"), &regs).unwrap();
    let odd = fake.add_device("0000:06:00.0", ids, &bars).unwrap();
    regs[0x1C..0x20].copy_from_slice(&9u32.to_le_bytes());
    std::fs::write(odd.join("resource2"), &regs).unwrap();
    let out = stdout(&board_tool(&fake, &["list"]));
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[0],
        "0000:05:00.0  10b5:3001 (subsystem 10b5:9030)  MOTENC  hal_motenc: MOTENC-Lite \
         (boardVersion 1, board ID jumpers 2)"
    );
    assert!(
        lines[1].starts_with(
            "0000:06:00.0  10b5:3001 (subsystem 10b5:9030)  MOTENC  hal_motenc: (not readable: "
        ) && lines[1].contains("boardVersion is 0x9, expected 0 (MOTENC-100) or 1 (MOTENC-Lite)"),
        "{}",
        lines[1]
    );
    assert!(out.ends_with(
        "simulated MOTENC boards (hal_motenc backend=sim sim_boards=100|lite): MOTENC-100 \
         (boardVersion 0, board ID jumpers 0), MOTENC-Lite (boardVersion 1, board ID jumpers 0)\n"
    ));
    // Listing leaves the devices disabled again.
    let enabled = std::fs::read_to_string(lite.join("enable")).unwrap();
    assert_eq!(enabled.trim(), "0");
}

#[test]
fn probe_reports_the_servo_to_go_model_or_that_nothing_answers() {
    let none = FakeSysfs::new("hal-board-probe").unwrap();
    let out = stdout(&board_tool(&none, &["probe", "0x300", "--via", "sim"]));
    assert_eq!(
        out,
        "0x300: Servo-To-Go Model II (signature 0x74): loadrt hal_stg base=0x300 model=2\n"
    );
    let out = stdout(&board_tool(&none, &["probe", "--via", "sim1"]));
    assert_eq!(
        out,
        "0x300: Servo-To-Go Model I (signature 0x75): loadrt hal_stg base=0x300 model=1\n"
    );
    let err = stderr(&board_tool(&none, &["probe", "0x3e0", "--via", "sim"]));
    assert_eq!(
        err,
        "hal-board: no board answers at 0x3e0 (its board test register reads 0xff: nothing \
         decodes the port)\n"
    );
    let err = stderr(&board_tool(&none, &["probe", "0x378", "--via", "sim"]));
    assert_eq!(
        err,
        "hal-board: 0x378 is not a Servo-To-Go base address (0x200, 0x220, ... 0x3e0)\n"
    );
    let err = stderr(&board_tool(&none, &["probe", "--via", "isa"]));
    assert!(err.contains("'isa' is not a way to the ports"), "{err}");
}

/// hm2-eth-sim on a port of its own, stopped when dropped.
struct EthSim {
    child: std::process::Child,
    addr: String,
}

impl EthSim {
    fn start(args: &[&str]) -> EthSim {
        use std::io::BufRead;
        let mut child = Command::new(env!("CARGO_BIN_EXE_hm2-eth-sim"))
            .args(["--listen", "127.0.0.1:0"])
            .args(args)
            .stdout(std::process::Stdio::piped())
            .spawn()
            .expect("hm2-eth-sim runs");
        let mut line = String::new();
        std::io::BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let addr = line
            .trim()
            .rsplit(' ')
            .next()
            .expect("the address it answers on")
            .to_string();
        EthSim { child, addr }
    }
}

impl Drop for EthSim {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn ethernet_boards_by_address_with_their_smart_serial_cards() {
    let sim = EthSim::start(&["--board", "7i96s", "--remote", "7i77"]);
    let fake = FakeSysfs::new("hal-board-eth").unwrap();
    let out = stdout(&board_tool(&fake, &["idrom", &sim.addr]));
    assert!(out.starts_with("Configuration Name: HOSTMOT2\n"), "{out}");
    assert!(out.contains("  BoardName : MESA7I96\n"), "{out}");
    assert!(out.contains("IO Connections for TB1"), "{out}");
    assert!(out.contains("SSerial"), "{out}");
    assert!(out.contains("TXData0"), "{out}");
    assert_eq!(
        stdout(&board_tool(&fake, &["read", &sim.addr, "0x100"])),
        "55AACAFE\n"
    );
    let out = stdout(&board_tool(
        &fake,
        &["sserial", &sim.addr, "--config", "sserial_port_0=30"],
    ));
    assert!(
        out.starts_with("Smart Serial port 0: firmware version 43, 2 channel(s), 2 card(s)\n"),
        "{out}"
    );
    assert!(
        out.contains("  channel 0: 7I77, unit 0x12007700, mode 3 (io_encoder_analog_fieldvoltage)"),
        "{out}"
    );
    assert!(
        out.contains("HAL names under hm2_7i96s.0.7i77.0.1.:"),
        "{out}"
    );
    assert!(out.contains("AnalogOut5"), "{out}");
    assert!(out.contains("analogout5\n"), "{out}");
    assert!(out.contains("input-00 .. input-31"), "{out}");
    assert!(out.contains("mpg1.count"), "{out}");
    assert!(out.contains("nvwatchdogtimeout   = 50 (0x32) ms"), "{out}");
    assert!(
        out.contains("swrevision          = 22 (0x16), read only"),
        "{out}"
    );
    // A board that never answers: the error names it.
    let silent = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    let addr = silent.local_addr().unwrap().to_string();
    let err = stderr(&board_tool(&fake, &["idrom", &addr]));
    assert!(err.contains(&format!("no reply from {addr}")), "{err}");
}
