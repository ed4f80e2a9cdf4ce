//! Simulated input devices: a description (name, phys, id, keys, axes,
//! LEDs) and the events they send, from a script timed from the first
//! read, from a file or FIFO of raw `input_event` records (the kernel's
//! bytes, through the same parser), or pushed by a test through a
//! [`SimHandle`]. A device is unplugged by its script, by its handle, or
//! when its events file is removed, as a node leaves `/dev/input`.
//!
//! `hal_input --sim FILE` (or `HAL_INPUT_SIM=FILE`) looks inputspecs up
//! among the devices of FILE, a text of lines:
//!
//! ```text
//! device Sim Jog Pendant        # starts a device: its name
//! node /dev/input/event7        # its node (default /dev/input/eventN, N from 0)
//! phys sim/input0
//! id 0003 1234 5678 0100        # bus vendor product version, hex
//! keys BTN_0 BTN_1 KEY_A        # names as the pins have them, or numbers
//! held BTN_1                    # keys down at start
//! rel REL_WHEEL
//! abs ABS_X -512 511 4 16 0     # min max [fuzz [flat [value]]]
//! leds LED_NUML
//! events jog.fifo               # raw records (relative to FILE's directory)
//! at 100 EV_KEY BTN_0 1         # milliseconds after the first read
//! at 100 EV_SYN 0 0
//! at 900 unplug
//! ```

use std::collections::VecDeque;
use std::fs::File;
use std::io::Read;
use std::os::fd::BorrowedFd;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use crate::device::{human_order, Catalogue, Identity, InputDevice};
use crate::error::{InputError, Result, SimProblem};
use crate::names;
use crate::regs::{self, AbsInfo, Event, InputId, EV_ABS, EV_KEY, EV_LED, EV_REL};

/// The largest description file read.
pub const FILE_MAX: u64 = 1 << 20;
/// The most devices a description holds.
pub const DEVICES_MAX: usize = 64;
/// The most script steps of one device.
pub const STEPS_MAX: usize = 100_000;

/// One step of a device's script.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// Send an event.
    Event(Event),
    /// Go away.
    Unplug,
}

/// What a simulated device is.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SimSpec {
    /// Who it is (its node included).
    pub who: Identity,
    /// Its keys and buttons.
    pub keys: Vec<u16>,
    /// Keys held when it is opened.
    pub held: Vec<u16>,
    /// Its relative axes.
    pub rel: Vec<u16>,
    /// Its absolute axes and their ranges.
    pub abs: Vec<(u16, AbsInfo)>,
    /// Its LEDs.
    pub leds: Vec<u16>,
    /// A file or FIFO of raw records it sends.
    pub events: Option<PathBuf>,
    /// Its script: (time after the first read, step), in time order.
    pub script: Vec<(Duration, Step)>,
}

/// State shared by a device's openings and its handle.
#[derive(Debug, Default)]
struct Shared {
    queue: VecDeque<Event>,
    unplugged: bool,
    written: Vec<Event>,
    grabbed: bool,
}

/// A test's hold on a simulated device: events in, LED writes out.
#[derive(Debug, Clone, Default)]
pub struct SimHandle(Arc<Mutex<Shared>>);

impl SimHandle {
    fn lock(&self) -> MutexGuard<'_, Shared> {
        // A panic while holding the lock leaves plain data: use it.
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Queues events for the next read.
    pub fn push(&self, events: &[Event]) {
        self.lock().queue.extend(events.iter().copied());
    }

    /// Unplugs the device.
    pub fn unplug(&self) {
        self.lock().unplugged = true;
    }

    /// The events written to the device so far (LED states).
    pub fn written(&self) -> Vec<Event> {
        self.lock().written.clone()
    }

    /// Whether the device was taken for exclusive access.
    pub fn grabbed(&self) -> bool {
        self.lock().grabbed
    }
}

/// Simulated devices to look inputspecs up in.
pub struct SimCatalogue {
    devices: Vec<(SimSpec, SimHandle)>,
}

impl SimCatalogue {
    /// A catalogue of these devices.
    pub fn new(specs: Vec<SimSpec>) -> SimCatalogue {
        SimCatalogue {
            devices: specs
                .into_iter()
                .map(|s| (s, SimHandle::default()))
                .collect(),
        }
    }

    /// Reads a description file.
    pub fn load(path: &Path) -> Result<SimCatalogue> {
        let err = |source| InputError::SimFile {
            path: path.to_path_buf(),
            source,
        };
        let mut text = String::new();
        File::open(path)
            .and_then(|f| f.take(FILE_MAX + 1).read_to_string(&mut text))
            .map_err(err)?;
        if text.len() as u64 > FILE_MAX {
            return Err(err(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("larger than {FILE_MAX} bytes"),
            )));
        }
        let base = path.parent().unwrap_or(Path::new("."));
        let specs = parse(&text, &path.display().to_string(), base)?;
        Ok(SimCatalogue::new(specs))
    }

    /// The handle of the device at `index` (description order).
    pub fn handle(&self, index: usize) -> Option<SimHandle> {
        self.devices.get(index).map(|(_, h)| h.clone())
    }
}

impl Catalogue for SimCatalogue {
    fn describe(&self) -> String {
        "the --sim description".into()
    }

    fn exists(&self, path: &Path) -> bool {
        self.devices.iter().any(|(s, _)| s.who.path == path)
    }

    fn nodes(&self) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = self
            .devices
            .iter()
            .map(|(s, _)| s.who.path.clone())
            .collect();
        v.sort_by(|a, b| human_order(a, b));
        v
    }

    fn open(&self, path: &Path) -> Result<Box<dyn InputDevice>> {
        let (spec, handle) = self
            .devices
            .iter()
            .find(|(s, _)| s.who.path == path)
            .ok_or_else(|| InputError::Device {
                op: "opening",
                path: path.to_path_buf(),
                source: std::io::ErrorKind::NotFound.into(),
            })?;
        Ok(Box::new(SimDevice::open(spec.clone(), handle.clone())?))
    }
}

/// An opened simulated device.
pub struct SimDevice {
    spec: SimSpec,
    shared: SimHandle,
    started: Option<Instant>,
    next_step: usize,
    events: Option<File>,
    carry: Vec<u8>,
}

impl SimDevice {
    /// Opens a device (its events file too, if it has one).
    pub fn open(spec: SimSpec, shared: SimHandle) -> Result<SimDevice> {
        let events = match &spec.events {
            Some(p) => Some(
                std::fs::OpenOptions::new()
                    .read(true)
                    .custom_flags(libc::O_NONBLOCK | libc::O_CLOEXEC)
                    .open(p)
                    .map_err(|source| InputError::Device {
                        op: "opening the events file",
                        path: p.clone(),
                        source,
                    })?,
            ),
            None => None,
        };
        Ok(SimDevice {
            spec,
            shared,
            started: None,
            next_step: 0,
            events,
            carry: Vec::new(),
        })
    }

    fn gone(&self) -> InputError {
        InputError::Gone {
            path: self.spec.who.path.clone(),
            name: self.spec.who.name.clone(),
            source: None,
        }
    }

    /// Reads what the events file has: whole records out, a partial one
    /// kept for the next read.
    fn read_file(&mut self, out: &mut Vec<Event>) -> Result<()> {
        let (Some(f), Some(path)) = (self.events.as_mut(), self.spec.events.as_ref()) else {
            return Ok(());
        };
        let mut buf = [0u8; 64 * regs::EVENT_SIZE];
        loop {
            match f.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => self.carry.extend_from_slice(&buf[..n]),
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(source) => {
                    return Err(InputError::Device {
                        op: "reading the events file",
                        path: path.clone(),
                        source,
                    })
                }
            }
        }
        let whole = self.carry.len() - self.carry.len() % regs::EVENT_SIZE;
        let mut decoded = Vec::new();
        regs::parse_events(&self.carry[..whole], &mut decoded)?;
        self.carry.drain(..whole);
        out.append(&mut decoded);
        if !path.exists() {
            self.shared.unplug();
        }
        Ok(())
    }
}

impl InputDevice for SimDevice {
    fn identity(&self) -> &Identity {
        &self.spec.who
    }

    fn codes(&mut self, kind: u16, max: u16) -> Result<Vec<u16>> {
        let mut v: Vec<u16> = match kind {
            EV_KEY => self.spec.keys.clone(),
            EV_REL => self.spec.rel.clone(),
            EV_ABS => self.spec.abs.iter().map(|(c, _)| *c).collect(),
            EV_LED => self.spec.leds.clone(),
            _ => Vec::new(),
        };
        v.retain(|c| *c <= max);
        v.sort_unstable();
        v.dedup();
        Ok(v)
    }

    fn absinfo(&mut self, code: u16) -> Result<AbsInfo> {
        Ok(self
            .spec
            .abs
            .iter()
            .find(|(c, _)| *c == code)
            .map(|(_, a)| *a)
            .unwrap_or_default())
    }

    fn keys_held(&mut self) -> Result<Vec<u16>> {
        Ok(self.spec.held.clone())
    }

    fn grab(&mut self) -> Result<()> {
        self.shared.lock().grabbed = true;
        Ok(())
    }

    fn read_available(&mut self, out: &mut Vec<Event>) -> Result<()> {
        let start = *self.started.get_or_insert_with(Instant::now);
        let now = start.elapsed();
        while let Some((at, step)) = self.spec.script.get(self.next_step) {
            if *at > now {
                break;
            }
            match step {
                Step::Event(e) => out.push(*e),
                Step::Unplug => self.shared.unplug(),
            }
            self.next_step += 1;
        }
        self.read_file(out)?;
        let mut s = self.shared.lock();
        out.extend(s.queue.drain(..));
        if s.unplugged {
            drop(s);
            return Err(self.gone());
        }
        Ok(())
    }

    fn write(&mut self, event: Event) -> Result<()> {
        let mut s = self.shared.lock();
        if s.unplugged {
            drop(s);
            return Err(self.gone());
        }
        s.written.push(event);
        Ok(())
    }

    fn fd(&self) -> Option<BorrowedFd<'_>> {
        None
    }
}

/// A line's words, `#` comments removed.
fn words(line: &str) -> Vec<&str> {
    line.split('#')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect()
}

/// A number: decimal, or hex with `0x`.
fn number<T: TryFrom<i64>>(w: &str) -> Option<T> {
    let (neg, digits) = match w.strip_prefix('-') {
        Some(d) => (true, d),
        None => (false, w),
    };
    let v = match digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
    {
        Some(h) => i64::from_str_radix(h, 16).ok()?,
        None => digits.parse::<i64>().ok()?,
    };
    T::try_from(if neg { -v } else { v }).ok()
}

/// An event type word: `EV_KEY`... or a number up to `EV_MAX`.
fn event_type(w: &str) -> Option<u16> {
    let named = match w.to_ascii_uppercase().as_str() {
        "EV_SYN" => Some(regs::EV_SYN),
        "EV_KEY" => Some(EV_KEY),
        "EV_REL" => Some(EV_REL),
        "EV_ABS" => Some(EV_ABS),
        "EV_MSC" => Some(regs::EV_MSC),
        "EV_LED" => Some(EV_LED),
        "EV_SND" => Some(regs::EV_SND),
        _ => None,
    };
    named.or_else(|| number::<u16>(w).filter(|t| *t <= regs::EV_MAX))
}

/// An event code word for type `kind`: a name of the type or a number.
fn event_code(kind: u16, w: &str) -> Option<u16> {
    names::code_by_name(kind, w).or_else(|| number::<u16>(w))
}

/// Parses a description (`file` names it in errors, `base` is where
/// relative `events` paths start).
pub fn parse(text: &str, file: &str, base: &Path) -> Result<Vec<SimSpec>> {
    let mut specs: Vec<SimSpec> = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let bad = |what: SimProblem| InputError::SimLine {
            file: file.to_string(),
            line: n + 1,
            what,
        };
        let w = words(line);
        let Some(&key) = w.first() else { continue };
        if key == "device" {
            if specs.len() == DEVICES_MAX {
                return Err(bad(SimProblem::TooManyDevices(DEVICES_MAX)));
            }
            let name = line.split('#').next().unwrap_or("").trim()["device".len()..].trim();
            let name = name.trim_matches('"').to_string();
            specs.push(SimSpec {
                who: Identity {
                    path: PathBuf::from(format!("/dev/input/event{}", specs.len())),
                    name,
                    phys: None,
                    id: InputId::default(),
                },
                ..SimSpec::default()
            });
            continue;
        }
        let Some(spec) = specs.last_mut() else {
            return Err(bad(SimProblem::NoDevice(key.to_string())));
        };
        parse_line(spec, &w, base).map_err(bad)?;
    }
    Ok(specs)
}

/// One line of a device.
fn parse_line(spec: &mut SimSpec, w: &[&str], base: &Path) -> std::result::Result<(), SimProblem> {
    let args = &w[1..];
    let codes = |kind: u16| -> std::result::Result<Vec<u16>, SimProblem> {
        args.iter().map(|a| known_code(kind, a)).collect()
    };
    match w[0] {
        "node" => match args {
            [p] => spec.who.path = PathBuf::from(p),
            _ => return Err(SimProblem::Usage("node takes one path")),
        },
        "phys" => spec.who.phys = Some(args.join(" ")),
        "id" => {
            let v: Option<Vec<u16>> = args
                .iter()
                .map(|a| u16::from_str_radix(a, 16).ok())
                .collect();
            match v.as_deref() {
                Some(&[bustype, vendor, product, version]) => {
                    spec.who.id = InputId {
                        bustype,
                        vendor,
                        product,
                        version,
                    }
                }
                _ => {
                    return Err(SimProblem::Usage(
                        "id takes four hex words: bus vendor product version",
                    ))
                }
            }
        }
        "keys" => spec.keys.extend(codes(EV_KEY)?),
        "held" => spec.held.extend(codes(EV_KEY)?),
        "rel" => spec.rel.extend(codes(EV_REL)?),
        "leds" => spec.leds.extend(codes(EV_LED)?),
        "abs" => spec.abs.push(parse_abs(args)?),
        "events" => match args {
            [p] => spec.events = Some(base.join(p)),
            _ => return Err(SimProblem::Usage("events takes one path")),
        },
        "at" => {
            if spec.script.len() == STEPS_MAX {
                return Err(SimProblem::TooManySteps(STEPS_MAX));
            }
            let step = parse_step(args)?;
            if spec.script.last().is_some_and(|(t, _)| *t > step.0) {
                return Err(SimProblem::OutOfOrder);
            }
            spec.script.push(step);
        }
        other => return Err(SimProblem::UnknownWord(other.to_string())),
    }
    Ok(())
}

/// `abs NAME MIN MAX [FUZZ [FLAT [VALUE]]]`.
fn parse_abs(args: &[&str]) -> std::result::Result<(u16, AbsInfo), SimProblem> {
    const USAGE: &str = "abs takes NAME MIN MAX [FUZZ [FLAT [VALUE]]], numbers that fit 32 bits";
    if !(3..=6).contains(&args.len()) {
        return Err(SimProblem::Usage(USAGE));
    }
    let code = known_code(EV_ABS, args[0])?;
    let nums: Option<Vec<i32>> = args[1..].iter().map(|a| number::<i32>(a)).collect();
    let nums = nums.ok_or(SimProblem::Usage(USAGE))?;
    let at = |i: usize| nums.get(i).copied().unwrap_or(0);
    let (minimum, maximum) = (at(0), at(1));
    if minimum > maximum {
        return Err(SimProblem::Range {
            name: args[0].to_string(),
            minimum,
            maximum,
        });
    }
    Ok((
        code,
        AbsInfo {
            minimum,
            maximum,
            fuzz: at(2),
            flat: at(3),
            value: nums.get(4).copied().unwrap_or(centre(minimum, maximum)),
            resolution: 0,
        },
    ))
}

/// The middle of a range, rounded towards zero.
fn centre(minimum: i32, maximum: i32) -> i32 {
    let mid = (i64::from(minimum) + i64::from(maximum)) / 2;
    i32::try_from(mid).unwrap_or(0)
}

/// `at MS TYPE CODE VALUE` or `at MS unplug`.
fn parse_step(args: &[&str]) -> std::result::Result<(Duration, Step), SimProblem> {
    const USAGE: &str = "at takes MS TYPE CODE VALUE, or MS unplug";
    let ms = args
        .first()
        .and_then(|a| a.parse::<u64>().ok())
        .ok_or(SimProblem::Usage(USAGE))?;
    let at = Duration::from_millis(ms);
    match &args[1..] {
        ["unplug"] => Ok((at, Step::Unplug)),
        [t, c, v] => {
            let kind = event_type(t).ok_or_else(|| SimProblem::EventType(t.to_string()))?;
            let code = event_code(kind, c).ok_or_else(|| SimProblem::EventCode {
                code: c.to_string(),
                kind: t.to_string(),
            })?;
            let value = number::<i32>(v).ok_or_else(|| SimProblem::Value(v.to_string()))?;
            Ok((at, Step::Event(Event { kind, code, value })))
        }
        _ => Err(SimProblem::Usage(USAGE)),
    }
}

/// The code `name` of event type `kind`, as hal_input names codes.
fn known_code(kind: u16, name: &str) -> std::result::Result<u16, SimProblem> {
    names::code_by_name(kind, name).ok_or_else(|| SimProblem::UnknownCode {
        name: name.to_string(),
        kind: names::type_name(kind),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const PENDANT: &str = "\
# a jog pendant
device \"Sim Jog Pendant\"
phys sim/input0
id 0003 1234 5678 0100
keys BTN_0 btn_1 KEY_A
held BTN_1
rel REL_WHEEL
abs ABS_X -512 511 4 16
leds LED_NUML
at 5 EV_KEY BTN_0 1
at 5 EV_SYN 0 0
at 10 unplug
device Sim Mouse
node /dev/input/event9
";

    #[test]
    fn a_description_reads_back() {
        let specs = parse(PENDANT, "p.txt", Path::new("/tmp")).unwrap();
        assert_eq!(specs.len(), 2);
        let p = &specs[0];
        assert_eq!(p.who.name, "Sim Jog Pendant");
        assert_eq!(p.who.path, Path::new("/dev/input/event0"));
        assert_eq!(p.who.id.vendor, 0x1234);
        assert_eq!(p.keys, [0x100, 0x101, 30]);
        assert_eq!(p.held, [0x101]);
        assert_eq!(p.abs[0].1.value, 0);
        assert_eq!(p.abs[0].1.flat, 16);
        assert_eq!(p.script.len(), 3);
        assert_eq!(specs[1].who.path, Path::new("/dev/input/event9"));
    }

    #[test]
    fn bad_lines_are_named() {
        for (text, want) in [
            ("keys KEY_A\n", ":1: 'keys' before"),
            ("device x\nkeys KEY_NOPE\n", ":2: 'KEY_NOPE'"),
            ("device x\nabs ABS_X 5 1\n", "minimum 5 above maximum 1"),
            ("device x\nabs ABS_X 1 99999999999\n", "32 bits"),
            ("device x\nat 5 EV_KEY KEY_A 1\nat 1 unplug\n", "time order"),
            ("device x\nat x unplug\n", "at takes"),
            ("device x\nid 3 4\n", "four hex"),
            ("device x\nfrob\n", "unknown word 'frob'"),
        ] {
            let e = parse(text, "f", Path::new(".")).unwrap_err().to_string();
            assert!(e.contains(want), "{text:?}: {e}");
        }
    }

    #[test]
    fn the_script_plays_then_unplugs() {
        let specs = parse(PENDANT, "p.txt", Path::new("/tmp")).unwrap();
        let cat = SimCatalogue::new(specs);
        let mut d = cat.open(Path::new("/dev/input/event0")).unwrap();
        let mut out = Vec::new();
        let end = Instant::now() + Duration::from_secs(10);
        let err = loop {
            match d.read_available(&mut out) {
                Ok(()) => assert!(Instant::now() < end, "never unplugged"),
                Err(e) => break e,
            }
            std::thread::sleep(Duration::from_millis(1));
        };
        assert!(matches!(err, InputError::Gone { .. }), "{err}");
        assert_eq!(out.len(), 2);
        assert_eq!(out[0].code, 0x100);
    }
}
