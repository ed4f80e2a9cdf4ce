//! Mesa's own tool reads our simulated Ethernet boards: Debian's
//! mesaflash 3.4.6 (unpacked by scripts/mesaflash-peer) runs `--sserial`
//! and `--readhmid` against hm2-eth-sim's 7I76E and 7I96S, served on a
//! loopback address of their own at LBP16's port 27181 (mesaflash knows
//! no other port). Its Smart Serial readout must show the processor's
//! baud rate and each card's globals and modes as it shows a real card's,
//! and its IDROM readout must agree with ours.
//!
//! Without mesaflash unpacked the tests are reported as ignored.
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::io::Read as _;
use std::net::{Ipv4Addr, SocketAddr};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

use hostmot2::eth::EthTransport;
use hostmot2::readhmid;
use hostmot2::sim::boards;
use hostmot2::sim::eth::{EthBoard, EthIdentity};
use hostmot2::sim::eth_server::{self, Faults, Running};
use hostmot2::sim::sserial::SimRemote;
use hostmot2::sim::{machine, Hm2Model};

/// LBP16's UDP port, the only one mesaflash uses.
const LBP16_PORT: u16 = 27181;
/// How long one mesaflash run may take (it has no timeout of its own
/// once it found a board).
const RUN_LIMIT: Duration = Duration::from_secs(120);

/// Loopback addresses handed out by this process.
static NEXT: AtomicU32 = AtomicU32::new(0);

/// The simulated Ethernet board `preset` with `remotes` on its Smart
/// Serial port, served on a loopback address no other test uses.
fn serve(preset: &str, remotes: Vec<hostmot2::sim::sserial::RemoteSpec>) -> Running {
    let mut spec = boards::preset(preset).unwrap();
    spec.remotes = remotes;
    let pid = std::process::id();
    for _ in 0..64 {
        // 127.91.x.y: x, y from the process id and a counter, never 0
        // or 255 in the last place.
        let n = pid
            .wrapping_mul(64)
            .wrapping_add(NEXT.fetch_add(1, Ordering::Relaxed));
        let ip = Ipv4Addr::new(127, 91, (n >> 8) as u8, 1 + (n % 253) as u8);
        let model = Hm2Model::with_world(spec.clone(), Box::new(machine::preset(preset)));
        let board = EthBoard::new(model, EthIdentity::new(boards::eth_name(preset).unwrap()));
        match eth_server::spawn_on(board, Faults::default(), SocketAddr::from((ip, LBP16_PORT))) {
            Ok(running) => return running,
            Err(e) if e.kind() == std::io::ErrorKind::AddrInUse => continue,
            Err(e) => panic!("binding {ip}:{LBP16_PORT}: {e}"),
        }
    }
    panic!("no free loopback address for the simulated board");
}

/// What one mesaflash run printed.
struct Run {
    ok: bool,
    stdout: String,
    stderr: String,
}

/// The mesaflash binary and its library directory, as the build found
/// them (build.rs).
fn peer() -> (&'static str, &'static str) {
    match (option_env!("MESAFLASH_PEER_BIN"), option_env!("MESAFLASH_PEER_LIBS")) {
        (Some(bin), Some(libs)) => (bin, libs),
        _ => panic!("mesaflash was not unpacked when this test was built: run scripts/mesaflash-peer install"),
    }
}

/// Runs mesaflash once with `args`, killed after [`RUN_LIMIT`].
fn mesaflash_once(args: &[&str]) -> Run {
    let (bin, libs) = peer();
    let mut child = Command::new(bin)
        .args(args)
        .env("LD_LIBRARY_PATH", libs)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mesaflash starts");
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        out.read_to_string(&mut s).unwrap();
        s
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = String::new();
        err.read_to_string(&mut s).unwrap();
        s
    });
    let deadline = Instant::now() + RUN_LIMIT;
    let status = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break st;
        }
        if Instant::now() > deadline {
            child.kill().unwrap();
            let _ = child.wait();
            panic!("mesaflash {args:?} ran longer than {RUN_LIMIT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Run {
        ok: status.success(),
        stdout: reader.join().unwrap(),
        stderr: err_reader.join().unwrap(),
    }
}

/// Runs mesaflash against the board at `board`: `--device DEVICE
/// --addr IP` and `command`. Its probe waits only 2 ms for the first
/// reply, so a run that found no board on a busy machine is repeated.
fn mesaflash(device: &str, board: &Running, command: &[&str]) -> Run {
    let ip = board.addr().ip().to_string();
    let mut args = vec!["--device", device, "--addr", &ip];
    args.extend_from_slice(command);
    let mut run = mesaflash_once(&args);
    for _ in 0..4 {
        if !run.stdout.contains("board found") {
            break;
        }
        std::thread::sleep(Duration::from_millis(200));
        run = mesaflash_once(&args);
    }
    run
}

/// Asserts that `run` succeeded and printed no error.
fn assert_clean(run: &Run, what: &str) {
    assert!(
        run.ok,
        "{what}: mesaflash failed\n{}\n{}",
        run.stdout, run.stderr
    );
    assert!(
        !run.stdout.to_lowercase().contains("error") && run.stderr.is_empty(),
        "{what}: mesaflash reported an error\n{}\n{}",
        run.stdout,
        run.stderr
    );
}

/// Changes the card on `port`, `channel` of the served board.
fn card<R>(board: &Running, channel: usize, f: impl FnOnce(&mut SimRemote) -> R) -> R {
    board
        .shared()
        .with(|b| f(b.model().sserial().remote(0, channel).unwrap()))
}

#[test]
#[cfg_attr(
    not(mesaflash_peer),
    ignore = "needs mesaflash unpacked (scripts/mesaflash-peer install)"
)]
fn mesaflash_reads_the_7i76_on_a_7i76e_as_a_real_one() {
    let board = serve("7i76e", vec![boards::seven_i76_on(0, 0)]);
    let run = mesaflash("7i76e", &board, &["--sserial"]);
    assert_clean(&run, "--sserial");
    assert_eq!(
        run.stdout,
        "SSLBP port 0:
  SSLBP Version: 0.43
  SSLBP Channels: 1
  SSLBP Baud Rate: 2500000
  sserial device at channel 0: 7I76 GPIO+SPINDLE (unit 0x10001234)
    SwRevision = 22
    NVUnitNumber = 0x10001234
    NVBaudRate = 2.5Mb
    NVWatchDogTimeout = 50ms
    SOFTWARE MODE io_spin [index 00]
    SOFTWARE MODE io_ana_spin [index 01]
    SOFTWARE MODE io_enc_ana_spin_fv [index 02]
"
    );
    // The values come from where the records say: changed on the card,
    // mesaflash sees them changed.
    card(&board, 0, |c| {
        assert!(c.set_global("NVBaudRate", 10));
        assert!(c.set_global("NVWatchDogTimeout", 300));
    });
    let run = mesaflash("7i76e", &board, &["--sserial", "--verbose"]);
    assert_clean(&run, "--sserial --verbose");
    for line in [
        "  SSLBP Channel Start: 16",
        "  SSLBP Clock: 100 MHz",
        "    NVBaudRate = 5Mb",
        "    NVWatchDogTimeout = 300ms",
    ] {
        assert!(
            run.stdout.lines().any(|l| l == line),
            "{line:?} missing:\n{}",
            run.stdout
        );
    }
    // mesaflash leaves the card in RAM mode, and the driver still reads
    // it afterwards.
    assert_eq!(card(&board, 0, |c| c.global("NVBaudRate")), Some(10));
}

#[test]
#[cfg_attr(
    not(mesaflash_peer),
    ignore = "needs mesaflash unpacked (scripts/mesaflash-peer install)"
)]
fn mesaflash_reads_both_channels_of_a_7i77_on_a_7i96s() {
    let board = serve("7i96s", boards::seven_i77_on(0, 0).to_vec());
    let run = mesaflash("7i96s", &board, &["--sserial"]);
    assert_clean(&run, "--sserial");
    assert_eq!(
        run.stdout,
        "SSLBP port 0:
  SSLBP Version: 0.43
  SSLBP Channels: 2
  SSLBP Baud Rate: 2500000
  sserial device at channel 0: 7I77 GPIO (unit 0x12007700)
    SwRevision = 22
    NVUnitNumber = 0x12007700
    NVBaudRate = 2.5Mb
    NVWatchDogTimeout = 50ms
    SOFTWARE MODE input_output [index 00]
    SOFTWARE MODE io_analog [index 01]
    SOFTWARE MODE io_analog_fieldvoltage [index 02]
    SOFTWARE MODE io_encoder_analog_fieldvoltage [index 03]
  sserial device at channel 1: 7I77 ANALOG (unit 0x11007701)
    SwRevision = 22
    NVUnitNumber = 0x11007701
    NVBaudRate = 2.5Mb
    NVWatchDogTimeout = 50ms
    SOFTWARE MODE analogout_enables [index 00]
"
    );
}

/// The part of a `--readhmid` text before the pin-out, without the
/// blank line mesaflash 3.4.6 puts before the pin-out's title (3.5
/// prints none, as we do).
fn modules_part(text: &str) -> &str {
    text.split("Configuration pin-out:")
        .next()
        .unwrap()
        .trim_end()
}

/// The pin-out's rows from the I/O number on: mesaflash labels the
/// first column with its own breakout-board names on these boards
/// (`TB3-1`), where we print the connector pin.
fn pin_rows(text: &str) -> Vec<&str> {
    let pinout = text.split("Configuration pin-out:").nth(1).unwrap_or("");
    pinout
        .lines()
        .filter(|l| l.len() > 18 && l.is_char_boundary(18))
        .map(|l| &l[18..])
        .filter(|rest| {
            rest.trim_start()
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_digit())
        })
        .collect()
}

#[test]
#[cfg_attr(
    not(mesaflash_peer),
    ignore = "needs mesaflash unpacked (scripts/mesaflash-peer install)"
)]
fn mesaflash_readhmid_agrees_with_ours() {
    for (preset, device, name) in [
        ("7i76e", "7i76e", "MESA7I76"),
        ("7i96s", "7i96s", "MESA7I96"),
    ] {
        let board = serve(preset, vec![boards::seven_i76_on(0, 0)]);
        let run = mesaflash(device, &board, &["--readhmid"]);
        assert_clean(&run, "--readhmid");
        let theirs = &run.stdout;
        assert!(
            theirs.contains(&format!("  BoardName : {name}\n")),
            "{theirs}"
        );
        assert!(theirs.contains("  Module: SSerial\n"), "{theirs}");
        assert!(!theirs.contains("Unknown"), "{theirs}");
        assert!(
            theirs.contains("SSerial          0        RXData0         (In)"),
            "{theirs}"
        );
        let mut t = EthTransport::connect(board.addr()).unwrap();
        let connectors = vec!["??".to_string(); 3];
        let ours = readhmid::read_hmid(&mut t, &connectors).unwrap();
        assert_eq!(modules_part(theirs), modules_part(&ours), "{preset}");
        let rows = pin_rows(theirs);
        assert_eq!(rows.len(), 51, "{preset}: 3 × 17 pins\n{theirs}");
        assert_eq!(rows, pin_rows(&ours), "{preset}");
    }
}

/// The boards `hm2_eth sim=` added for LinuxCNC's 7I93 samples (and the
/// 7I92 and 7I95): mesaflash reads their IDROMs as ours does, connector
/// by connector.
#[test]
#[cfg_attr(
    not(mesaflash_peer),
    ignore = "needs mesaflash unpacked (scripts/mesaflash-peer install)"
)]
fn mesaflash_readhmid_reads_the_7i93_7i92_and_7i95() {
    for (preset, name, connectors, pins) in [
        ("7i93", "MESA7I93", 2, 48),
        ("7i92", "MESA7I92", 2, 34),
        ("7i95", "MESA7I95", 2, 58),
    ] {
        let board = serve(preset, Vec::new());
        let run = mesaflash(preset, &board, &["--readhmid"]);
        assert_clean(&run, "--readhmid");
        let theirs = &run.stdout;
        assert!(
            theirs.contains(&format!("  BoardName : {name}\n")),
            "{theirs}"
        );
        assert!(!theirs.contains("Unknown"), "{theirs}");
        let mut t = EthTransport::connect(board.addr()).unwrap();
        let ours = readhmid::read_hmid(&mut t, &vec!["??".to_string(); connectors]).unwrap();
        assert_eq!(modules_part(theirs), modules_part(&ours), "{preset}");
        let rows = pin_rows(theirs);
        assert_eq!(rows.len(), pins, "{preset}\n{theirs}");
        assert_eq!(rows, pin_rows(&ours), "{preset}");
    }
}
