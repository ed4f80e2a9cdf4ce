//! hal_input on the kernel's evdev interface, against devices this test
//! makes through `/dev/uinput`: the capabilities, names and axis ranges
//! hal_input reads with its ioctls, events written to the uinput device
//! arriving as `input_event` records, LED events hal_input writes coming
//! back to the uinput device, EVIOCGRAB, the keys held at start, and an
//! unplug (UI_DEV_DESTROY) ending the program with everything released;
//! and LinuxCNC's own hal_input (the peer, `scripts/linuxcnc-peer`) on
//! the same device making the same pins, params and values.
//!
//! Needs root and the uinput module: the VM rig (`../shared/tools/vmrig`)
//! has both (this test loads uinput and evdev if they are missing).
//! Elsewhere the tests are ignored, with the reason; run on purpose
//! without uinput they fail.
//!
//! ```text
//! vmrig run -- target/debug/deps/uinput-<hash> --include-ignored --test-threads=1
//! ```
#![allow(
    clippy::unwrap_used,
    reason = "test code: a failed unwrap fails the test"
)]

use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::AsRawFd;
use std::os::unix::fs::OpenOptionsExt;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use hal_core::{ComponentKind, HalType, Host, HostConfig, Value};
use hal_driver::testing::wait;
use hal_input::evdev::Nodes;
use hal_input::regs::{Event, EVENT_SIZE, EV_ABS, EV_KEY, EV_LED, EV_REL, EV_SYN};
use hal_input::run::{open, Bound};
use hal_input::spec::Parts;
use hal_input::InputError;

const UINPUT: &str = "/dev/uinput";
const BTN_A: u16 = 0x130;
const BTN_B: u16 = 0x131;
const KEY_A: u16 = 30;
const REL_WHEEL: u16 = 8;
const ABS_X: u16 = 0;
const LED_NUML: u16 = 0;

/// `_IOC` for the uinput requests ('U').
const fn ioc(dir: u64, nr: u64, size: u64) -> u64 {
    (dir << 30) | (size << 16) | ((b'U' as u64) << 8) | nr
}
const UI_DEV_CREATE: u64 = ioc(0, 1, 0);
const UI_DEV_DESTROY: u64 = ioc(0, 2, 0);
/// `struct uinput_setup`: input_id (8), name[80], ff_effects_max (4).
const SETUP_SIZE: usize = 92;
const UI_DEV_SETUP: u64 = ioc(1, 3, SETUP_SIZE as u64);
/// `struct uinput_abs_setup`: code (2), padding (2), input_absinfo (24).
const ABS_SETUP_SIZE: usize = 28;
const UI_ABS_SETUP: u64 = ioc(1, 4, ABS_SETUP_SIZE as u64);
const UI_SET_EVBIT: u64 = ioc(1, 100, 4);
const UI_SET_KEYBIT: u64 = ioc(1, 101, 4);
const UI_SET_RELBIT: u64 = ioc(1, 102, 4);
const UI_SET_ABSBIT: u64 = ioc(1, 103, 4);
const UI_SET_LEDBIT: u64 = ioc(1, 105, 4);

/// A device made through uinput; destroyed when dropped.
struct Uinput {
    file: File,
    name: String,
    alive: bool,
}

/// Loads uinput, and evdev (the event nodes' handler; a kernel with
/// no event node at all may not have it loaded), unless already there.
fn require_uinput() {
    if !Path::new(UINPUT).exists() {
        let _ = Command::new("modprobe").arg("uinput").status();
    }
    if !Path::new("/sys/class/input").read_dir().is_ok_and(|mut d| {
        d.any(|e| e.is_ok_and(|e| e.file_name().to_string_lossy().starts_with("event")))
    }) {
        let _ = Command::new("modprobe").arg("evdev").status();
    }
    assert!(
        Path::new(UINPUT).exists(),
        "no {UINPUT} (needs root and the uinput module); run this binary through the VM rig"
    );
}

impl Uinput {
    /// A pad with BTN_A, BTN_B, KEY_A, REL_WHEEL, ABS_X (-100..100, fuzz
    /// 0, flat 4, at 10) and LED_NUML.
    fn pad(tag: &str) -> Uinput {
        Uinput::make(tag, &[], &[])
    }

    /// The pad with more codes (`(UI_SET_*BIT, code)`) and more absolute
    /// axes (`(code, [value, min, max, fuzz, flat, resolution])`).
    fn make(tag: &str, extra: &[(u64, u16)], extra_abs: &[(u16, [i32; 6])]) -> Uinput {
        require_uinput();
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .custom_flags(libc::O_NONBLOCK)
            .open(UINPUT)
            .unwrap();
        let name = format!("hal uinput {tag} {}", std::process::id());
        let u = Uinput {
            file,
            name,
            alive: false,
        };
        for (req, bit) in [
            (UI_SET_EVBIT, EV_KEY),
            (UI_SET_EVBIT, EV_REL),
            (UI_SET_EVBIT, EV_ABS),
            (UI_SET_EVBIT, EV_LED),
            (UI_SET_KEYBIT, BTN_A),
            (UI_SET_KEYBIT, BTN_B),
            (UI_SET_KEYBIT, KEY_A),
            (UI_SET_RELBIT, REL_WHEEL),
            (UI_SET_ABSBIT, ABS_X),
            (UI_SET_LEDBIT, LED_NUML),
        ]
        .iter()
        .chain(extra)
        {
            u.ioctl_int(*req, i32::from(*bit));
        }
        for (code, info) in [(ABS_X, [10i32, -100, 100, 0, 4, 0])]
            .iter()
            .chain(extra_abs)
        {
            let mut abs = [0u8; ABS_SETUP_SIZE];
            abs[0..2].copy_from_slice(&code.to_ne_bytes());
            for (i, v) in info.iter().enumerate() {
                abs[4 + 4 * i..8 + 4 * i].copy_from_slice(&v.to_ne_bytes());
            }
            u.ioctl_buf(UI_ABS_SETUP, &mut abs);
        }
        let mut setup = [0u8; SETUP_SIZE];
        for (i, v) in [3u16, 0x1d6b, 0x0104, 1].iter().enumerate() {
            setup[2 * i..2 * i + 2].copy_from_slice(&v.to_ne_bytes());
        }
        setup[8..8 + u.name.len()].copy_from_slice(u.name.as_bytes());
        u.ioctl_buf(UI_DEV_SETUP, &mut setup);
        let mut u = u;
        u.ioctl_int(UI_DEV_CREATE, 0);
        u.alive = true;
        // The node appears when the kernel has made it (devtmpfs).
        wait("the event node", || Nodes.nodes_named(&u.name));
        u
    }

    fn ioctl_int(&self, req: u64, arg: i32) {
        // SAFETY: the uinput requests used with this take an int by
        // value (or nothing, for create and destroy).
        let r = unsafe { libc::ioctl(self.file.as_raw_fd(), req as _, arg) };
        assert!(
            r >= 0,
            "uinput ioctl {req:#x}: {}",
            std::io::Error::last_os_error()
        );
    }

    fn ioctl_buf(&self, req: u64, buf: &mut [u8]) {
        assert_eq!(((req >> 16) & 0x3fff) as usize, buf.len());
        // SAFETY: the request's size field is buf's length (checked
        // above): the kernel reads that many bytes from buf.
        let r = unsafe { libc::ioctl(self.file.as_raw_fd(), req as _, buf.as_mut_ptr()) };
        assert!(
            r >= 0,
            "uinput ioctl {req:#x}: {}",
            std::io::Error::last_os_error()
        );
    }

    /// Sends events, then a SYN_REPORT.
    fn send(&mut self, events: &[(u16, u16, i32)]) {
        let mut bytes = Vec::new();
        for &(kind, code, value) in events.iter().chain([(EV_SYN, 0, 0)].iter()) {
            bytes.extend_from_slice(&Event { kind, code, value }.to_record());
        }
        self.file.write_all(&bytes).unwrap();
    }

    /// The LED events hal_input wrote to the device so far.
    fn leds(&mut self) -> Vec<(u16, i32)> {
        let mut out = Vec::new();
        let mut rec = [0u8; EVENT_SIZE];
        while let Ok(n) = self.file.read(&mut rec) {
            if n != EVENT_SIZE {
                break;
            }
            let e = Event::from_record(&rec);
            if e.kind == EV_LED {
                out.push((e.code, e.value));
            }
        }
        out
    }

    fn destroy(&mut self) {
        if self.alive {
            self.ioctl_int(UI_DEV_DESTROY, 0);
            self.alive = false;
        }
    }
}

impl Drop for Uinput {
    fn drop(&mut self) {
        if self.alive {
            // SAFETY: UI_DEV_DESTROY takes no argument.
            unsafe { libc::ioctl(self.file.as_raw_fd(), UI_DEV_DESTROY as _, 0) };
        }
    }
}

/// Whether an event node of that name exists.
trait NamedNodes {
    fn nodes_named(&self, name: &str) -> bool;
}

impl NamedNodes for Nodes {
    fn nodes_named(&self, name: &str) -> bool {
        use hal_input::device::Catalogue;
        self.nodes()
            .iter()
            .any(|n| self.open(n).is_ok_and(|d| d.identity().name == name))
    }
}

#[test]
#[ignore = "needs root and /dev/uinput: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn a_uinput_pad_drives_the_pins_through_the_kernel() {
    let mut u = Uinput::pad("pins");
    // Held before hal_input opens the device: EVIOCGKEY shows it held.
    u.send(&[(EV_KEY, BTN_B, 1)]);
    let host = Host::create(HostConfig::for_tests("hi-uinput")).unwrap();
    let inst = host.instance().clone();
    let comp = inst
        .new_component("hal_input", ComponentKind::User)
        .unwrap();
    let dev = open(&Nodes, &format!("+{}", u.name)).unwrap();
    assert!(dev.identity().path.starts_with("/dev/input"));
    assert_eq!(dev.identity().id.vendor, 0x1d6b);
    let mut b = Bound::new(&comp, 0, dev, Parts::ALL).unwrap();
    let get = |pin: &str| inst.pin_value(&format!("input.0.{pin}")).unwrap();
    // What the ioctls read: the axis range and value, the pins made.
    assert_eq!(get("abs-x-counts"), Value::S32(10));
    assert_eq!(get("abs-x-flat"), Value::S32(4));
    assert_eq!(
        inst.param_value("input.0.abs-x-min").unwrap(),
        Value::S32(-100)
    );
    assert_eq!(get("abs-x-scale"), Value::Float(100.0));
    assert_eq!(get("btn-b"), Value::Bit(true), "held at start");
    assert_eq!(get("btn-b-not"), Value::Bit(false));
    for pin in [
        "btn-a",
        "btn-b-not",
        "key-a",
        "rel-wheel-counts",
        "led-numl",
    ] {
        get(pin);
    }
    assert!(inst.pin("input.0.btn-c").unwrap().is_none());
    u.send(&[
        (EV_KEY, BTN_A, 1),
        (EV_REL, REL_WHEEL, -2),
        (EV_ABS, ABS_X, 50),
    ]);
    let end = Instant::now() + Duration::from_secs(20);
    while get("abs-x-position") != Value::Float(0.5) {
        assert!(Instant::now() < end, "the events never arrived");
        b.step().unwrap();
        std::thread::sleep(Duration::from_millis(5));
    }
    assert_eq!(get("btn-a"), Value::Bit(true));
    assert_eq!(get("btn-a-not"), Value::Bit(false));
    assert_eq!(get("rel-wheel-counts"), Value::S32(-2));
    // LEDs: off at start, then the pin's state reaches the device.
    inst.set_pin("input.0.led-numl", Value::Bit(true)).unwrap();
    b.step().unwrap();
    let mut leds = Vec::new();
    let end = Instant::now() + Duration::from_secs(20);
    while !leds.contains(&(LED_NUML, 1)) {
        assert!(Instant::now() < end, "LED writes seen: {leds:?}");
        leds.extend(u.leds());
        std::thread::sleep(Duration::from_millis(5));
    }
    assert_eq!(leds.first(), Some(&(LED_NUML, 0)), "{leds:?}");
    // Unplugged: the next read says so, by name.
    u.destroy();
    let end = Instant::now() + Duration::from_secs(20);
    let e = loop {
        match b.step() {
            Ok(_) => assert!(Instant::now() < end, "the unplug was never seen"),
            Err(e) => break e,
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    assert!(matches!(e, InputError::Gone { .. }), "{e}");
    assert!(e.to_string().contains(&u.name), "{e}");
}

#[test]
#[ignore = "needs root and /dev/uinput: runs in the VM rig (../shared/tools/vmrig, scripts/test-all)"]
fn the_program_on_a_uinput_pad_releases_everything_when_it_is_unplugged() {
    let mut u = Uinput::pad("proc");
    let host = Host::create(HostConfig::for_tests("hi-uinput-proc")).unwrap();
    let inst = host.instance().clone();
    let mut child = Command::new(env!("CARGO_BIN_EXE_hal_input"))
        .args(["-KA", &u.name])
        .env("HAL_INSTANCE", inst.name())
        .env("HAL_NO_REALTIME", "1")
        .env_remove("HAL_INPUT_SIM")
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait("hal_input ready", || {
        inst.component("hal_input")
            .unwrap()
            .is_some_and(|c| c.ready)
    });
    assert!(
        inst.pin("input.0.rel-wheel-counts").unwrap().is_none(),
        "-KA"
    );
    inst.newsig("jog", HalType::Bit).unwrap();
    inst.link("input.0.key-a", "jog").unwrap();
    u.send(&[(EV_KEY, KEY_A, 1), (EV_ABS, ABS_X, -100)]);
    wait("KEY_A held", || {
        inst.signal_value("jog").unwrap() == Value::Bit(true)
    });
    wait("the axis at -1", || {
        inst.pin_value("input.0.abs-x-is-neg").unwrap() == Value::Bit(true)
    });
    u.destroy();
    let end = Instant::now() + Duration::from_secs(30);
    let status = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break st;
        }
        assert!(Instant::now() < end, "hal_input did not exit on the unplug");
        std::thread::sleep(Duration::from_millis(10));
    };
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(err.contains("the device went away"), "{err}");
    assert_eq!(inst.signal_value("jog").unwrap(), Value::Bit(false));
}

/// The rows of `show pin` and `show param` (script mode) for names under
/// `input.`: type, direction, value and name (the owner's id differs
/// between the two HALs).
fn input_rows(stdout: &str) -> Vec<String> {
    let mut rows: Vec<String> = stdout
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|f| f.len() >= 5 && f[4].starts_with("input."))
        .map(|f| f[1..5].join(" "))
        .collect();
    rows.sort();
    rows
}

#[test]
#[ignore = "needs root, /dev/uinput and LinuxCNC unpacked (scripts/linuxcnc-peer install): runs in the VM rig"]
fn linuxcncs_own_hal_input_makes_the_same_pins_on_the_same_device() {
    let script = peer_script();
    let u = rich_pad("peer");
    let node = open(&Nodes, &u.name).unwrap().identity().path.clone();
    // LinuxCNC runs as nobody: let it open the node.
    std::fs::set_permissions(&node, std::os::unix::fs::PermissionsExt::from_mode(0o666)).unwrap();
    // The node three times: every feature, LEDs only, keys and
    // absolute axes only. A second after ready, both have run their
    // cycle (is-pos, is-neg).
    let text = format!(
        "loadusr -W hal_input {0} -L {0} -KA {0}\nloadusr -w sleep 1\nshow pin\nshow param\n",
        node.display()
    );
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let file = dir.join(format!("peer-hal-input-{}.hal", std::process::id()));
    std::fs::write(&file, &text).unwrap();
    let out = Command::new(&script)
        .args(["run", "halrun", "-s", "-k", "-f"])
        .arg(&file)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let theirs = String::from_utf8_lossy(&out.stdout).into_owned();
    let their_err = String::from_utf8_lossy(&out.stderr).into_owned();
    let theirs = input_rows(&theirs);
    assert!(!theirs.is_empty(), "LinuxCNC made no pins:\n{their_err}");
    let has = |name: &str| {
        theirs
            .iter()
            .any(|r| r.ends_with(&format!(" input.0.{name}")))
    };
    for name in [
        "btn-0",
        "btn-trigger",
        "btn-trigger-happy40",
        "rel-11-counts",
        "abs-60-flat",
        "abs-60-max",
        "abs-hat0x-is-neg",
        "led-11-invert",
        "led-capsl",
    ] {
        assert!(has(name), "LinuxCNC has no {name}: {theirs:#?}");
    }
    assert!(!theirs.iter().any(|r| r.contains("key-744")), "{theirs:#?}");
    for (name, made) in [
        ("input.1.led-capsl", true),
        ("input.1.btn-a", false),
        ("input.2.btn-a", true),
        ("input.2.abs-x-counts", true),
        ("input.2.rel-wheel-counts", false),
        ("input.2.led-numl", false),
    ] {
        let found = theirs.iter().any(|r| r.ends_with(&format!(" {name}")));
        assert_eq!(found, made, "LinuxCNC's {name}: {theirs:#?}");
    }

    let host = Host::create(HostConfig::for_tests("hi-peer")).unwrap();
    let inst = host.instance().clone();
    let (mut so, mut se) = (Vec::new(), Vec::new());
    let opts = hal_lang::Options {
        keep_going: true,
        script: true,
        ..Default::default()
    };
    let ok = hal_lang::Session::new(inst.clone(), opts, &mut so, &mut se)
        .run_text(Some("peer.hal"), &text);
    assert!(ok, "{}", String::from_utf8_lossy(&se));
    let ours = input_rows(&String::from_utf8_lossy(&so));
    let _ = hal_lang::Session::new(inst, hal_lang::Options::default(), &mut so, &mut se)
        .run_text(Some("unload.hal"), "unloadusr hal_input\n");
    let only_theirs: Vec<&String> = theirs.iter().filter(|r| !ours.contains(r)).collect();
    let only_ours: Vec<&String> = ours.iter().filter(|r| !theirs.contains(r)).collect();
    assert!(
        only_theirs.is_empty() && only_ours.is_empty(),
        "LinuxCNC only: {only_theirs:#?}\nours only: {only_ours:#?}"
    );
    std::fs::remove_file(&file).unwrap();
}

/// A pad with more than [`Uinput::pad`]'s codes: key aliases
/// (BTN_TRIGGER, BTN_0), the last key LinuxCNC asks for and one past it,
/// codes its tables do not name (REL_WHEEL_HI_RES, ABS_MT_TOOL_X, LED
/// 11), a hat.
fn rich_pad(tag: &str) -> Uinput {
    Uinput::make(
        tag,
        &[
            (UI_SET_KEYBIT, 0x100),
            (UI_SET_KEYBIT, 0x120),
            (UI_SET_KEYBIT, 0x2e7),
            (UI_SET_KEYBIT, 0x2e8),
            (UI_SET_RELBIT, 11),
            (UI_SET_RELBIT, 0),
            (UI_SET_ABSBIT, 0x10),
            (UI_SET_ABSBIT, 0x3c),
            (UI_SET_LEDBIT, 1),
            (UI_SET_LEDBIT, 11),
        ],
        &[(0x10, [0, -1, 1, 0, 0, 0]), (0x3c, [300, 0, 1023, 3, 0, 0])],
    )
}

/// Fails the test unless LinuxCNC is unpacked; the peer script.
fn peer_script() -> std::path::PathBuf {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/linuxcnc-peer");
    let peer = Command::new(&script).arg("prefix").output().unwrap();
    assert!(
        peer.status.success(),
        "LinuxCNC is not unpacked: run scripts/linuxcnc-peer install"
    );
    script
}

#[test]
#[ignore = "needs root, /dev/uinput and LinuxCNC unpacked (scripts/linuxcnc-peer install): runs in the VM rig"]
fn linuxcncs_own_hal_input_and_ours_agree_on_the_same_events() {
    let script = peer_script();
    let mut u = rich_pad("events");
    let node = open(&Nodes, &u.name).unwrap().identity().path.clone();
    std::fs::set_permissions(&node, std::os::unix::fs::PermissionsExt::from_mode(0o666)).unwrap();
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("peer-events-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::set_permissions(&dir, std::os::unix::fs::PermissionsExt::from_mode(0o777)).unwrap();
    // Each session: ready, then it waits for the events, then shows.
    std::fs::write(
        dir.join("wait-go.sh"),
        format!(
            "until [ -e {0}/go ]; do sleep 0.05; done\nsleep 1\n",
            dir.display()
        ),
    )
    .unwrap();
    let text = |tag: &str| {
        format!(
            "loadusr -W hal_input {node}\nloadusr -w touch {d}/ready-{tag}\n\
             loadusr -w sh {d}/wait-go.sh\nshow pin\nshow param\n",
            node = node.display(),
            d = dir.display()
        )
    };
    let file = dir.join("theirs.hal");
    std::fs::write(&file, text("theirs")).unwrap();
    let theirs = std::thread::spawn(move || {
        Command::new(&script)
            .args(["run", "halrun", "-s", "-k", "-f"])
            .arg(&file)
            .stdin(Stdio::null())
            .output()
            .unwrap()
    });
    let host = Host::create(HostConfig::for_tests("hi-peer-ev")).unwrap();
    let inst = host.instance().clone();
    let ours_text = text("ours");
    let ours_inst = inst.clone();
    let ours = std::thread::spawn(move || {
        let (mut so, mut se) = (Vec::new(), Vec::new());
        let opts = hal_lang::Options {
            keep_going: true,
            script: true,
            ..Default::default()
        };
        let ok = hal_lang::Session::new(ours_inst, opts, &mut so, &mut se)
            .run_text(Some("ours.hal"), &ours_text);
        (ok, so, se)
    });
    let end = Instant::now() + Duration::from_secs(180);
    while !(dir.join("ready-theirs").exists() && dir.join("ready-ours").exists()) {
        assert!(
            Instant::now() < end,
            "the two hal_inputs never both became ready"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    u.send(&[
        (EV_KEY, 0x100, 1),
        (EV_KEY, KEY_A, 1),
        (EV_REL, REL_WHEEL, 3),
        (EV_REL, 11, 120),
        (EV_REL, 0, -7),
        (EV_ABS, 0x3c, 1000),
        (EV_ABS, 0x10, -1),
    ]);
    u.send(&[
        (EV_KEY, KEY_A, 0),
        (EV_REL, REL_WHEEL, -1),
        (EV_ABS, ABS_X, 2),
    ]);
    std::fs::write(dir.join("go"), "").unwrap();
    let out = theirs.join().unwrap();
    let (ok, so, se) = ours.join().unwrap();
    assert!(ok, "{}", String::from_utf8_lossy(&se));
    let theirs = input_rows(&String::from_utf8_lossy(&out.stdout));
    assert!(
        theirs
            .iter()
            .any(|r| r == "s32 OUT 2 input.0.rel-wheel-counts"),
        "LinuxCNC did not see the events: {theirs:#?}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let ours = input_rows(&String::from_utf8_lossy(&so));
    let _ = hal_lang::Session::new(
        inst,
        hal_lang::Options::default(),
        &mut Vec::new(),
        &mut Vec::new(),
    )
    .run_text(Some("unload.hal"), "unloadusr hal_input\n");
    let only_theirs: Vec<&String> = theirs.iter().filter(|r| !ours.contains(r)).collect();
    let only_ours: Vec<&String> = ours.iter().filter(|r| !theirs.contains(r)).collect();
    assert!(
        only_theirs.is_empty() && only_ours.is_empty(),
        "LinuxCNC only: {only_theirs:#?}\nours only: {only_ours:#?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
