//! Simulated GPIO chips: what the kernel's `gpio-sim` module does, in
//! process, behind the same [`ChipSet`]/[`LineRequest`] traits as the
//! character device.
//!
//! Each line has an outside level (`gpio-sim`'s `pull`: what the world
//! drives an input with), and, when requested, a setting and a driven
//! value. The electrical level of a line is:
//!
//! * an input, or a line nobody requested: its outside level (or, for a
//!   line wired to another with [`SimChip::wire`], that line's level);
//! * a push-pull output: the driven value, inverted when active-low;
//! * open drain: low when driving low, else the outside level;
//! * open source: high when driving high, else the outside level.
//!
//! A requested bias sets the outside level as `gpio-sim` does (pull-up
//! 1, pull-down 0) until the plant API sets it again. Reads and writes
//! are logical (active-low inverts), bulk, and counted; every change of
//! a line's electrical level is logged with its time, like a logic
//! analyser on the pins ([`SimChip::events`]). A chip can be removed
//! ([`SimChip::remove`]): every access then fails with ENODEV, as the
//! character device does when its chip goes away.
//!
//! The model sits behind a `Mutex` (the simulator only: uncontended, a
//! few instructions per access; the driver layer's `SimBoard` does the
//! same).

use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::{Arc, Mutex, MutexGuard};

use hal_driver::sim::Clock;

use crate::cfg::{Bias, Config, Direction, Drive};
use crate::chip::{ChipInfo, ChipSet, LineError, LineRequest, LineSetting};
use crate::error::GpioError;
use crate::regs::flags;

/// How many level changes a chip's log keeps (the newest).
pub const EVENT_LOG: usize = 8192;

/// A change of a line's electrical level.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineEvent {
    /// When, on the chip's clock, in ns.
    pub time_ns: u64,
    /// The line's offset.
    pub offset: u32,
    /// Its new electrical level.
    pub level: bool,
}

#[derive(Debug, Clone, Default)]
struct SimLine {
    /// The outside level (`gpio-sim`'s pull).
    outside: bool,
    /// The request's setting and consumer, while requested.
    setting: Option<LineSetting>,
    consumer: String,
    /// The logical value the request drives (outputs).
    driven: bool,
    /// Another line whose level this one's outside level follows.
    wired_from: Option<u32>,
}

#[derive(Debug)]
struct ChipState {
    lines: Vec<SimLine>,
    removed: bool,
    events: VecDeque<LineEvent>,
    sets: u64,
    gets: u64,
}

impl ChipState {
    fn outside(&self, offset: u32) -> bool {
        let l = &self.lines[offset as usize];
        match l.wired_from {
            // A wire from an output reads its driven level; from
            // anything else its outside level (no chains of wires).
            Some(from) => self.own_level(from),
            None => l.outside,
        }
    }

    /// The level of a line, not following a wire into it.
    fn own_level(&self, offset: u32) -> bool {
        let l = &self.lines[offset as usize];
        match l.setting {
            Some(s) if s.direction == Direction::Output => {
                let high = l.driven != s.active_low;
                match s.drive {
                    Drive::PushPull => high,
                    Drive::OpenDrain => high && l.outside,
                    Drive::OpenSource => high || l.outside,
                }
            }
            _ => l.outside,
        }
    }

    fn level(&self, offset: u32) -> bool {
        let l = &self.lines[offset as usize];
        match l.setting {
            Some(s) if s.direction == Direction::Output => self.own_level(offset),
            _ => self.outside(offset),
        }
    }

    fn logical(&self, offset: u32) -> bool {
        let active_low = self.lines[offset as usize]
            .setting
            .is_some_and(|s| s.active_low);
        self.level(offset) != active_low
    }

    fn log(&mut self, time_ns: u64, offset: u32, level: bool) {
        if self.events.len() == EVENT_LOG {
            self.events.pop_front();
        }
        self.events.push_back(LineEvent {
            time_ns,
            offset,
            level,
        });
    }
}

/// One simulated chip.
pub struct SimChip {
    info: ChipInfo,
    state: Mutex<ChipState>,
    clock: Arc<dyn Clock>,
}

impl std::fmt::Debug for SimChip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SimChip").field("info", &self.info).finish()
    }
}

impl SimChip {
    /// A chip `name` labelled `label` with lines named `line_names` (""
    /// for unnamed), all inputs at outside level 0, stamping its log with
    /// `clock`.
    pub fn new(name: &str, label: &str, line_names: &[&str], clock: Arc<dyn Clock>) -> SimChip {
        SimChip {
            info: ChipInfo {
                path: format!("sim:{name}"),
                name: name.into(),
                label: label.into(),
                line_names: line_names.iter().map(|s| s.to_string()).collect(),
            },
            state: Mutex::new(ChipState {
                lines: vec![SimLine::default(); line_names.len()],
                removed: false,
                events: VecDeque::with_capacity(EVENT_LOG),
                sets: 0,
                gets: 0,
            }),
            clock,
        }
    }

    fn lock(&self) -> MutexGuard<'_, ChipState> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// What discovery reports.
    pub fn info(&self) -> &ChipInfo {
        &self.info
    }

    /// The offset of the line called `name`.
    pub fn offset(&self, name: &str) -> Option<u32> {
        self.info
            .line_names
            .iter()
            .position(|n| n == name)
            .map(|o| o as u32)
    }

    /// Sets the outside level of line `offset` (writing `gpio-sim`'s
    /// `pull`): what an input reads, what a released open-drain output
    /// floats to. Ignored for offsets the chip does not have.
    pub fn set_outside(&self, offset: u32, level: bool) {
        let mut s = self.lock();
        if let Some(l) = s.lines.get_mut(offset as usize) {
            l.outside = level;
        }
    }

    /// The electrical level of line `offset` (`gpio-sim`'s `value`);
    /// false for offsets the chip does not have.
    pub fn level(&self, offset: u32) -> bool {
        let s = self.lock();
        (offset as usize) < s.lines.len() && s.level(offset)
    }

    /// The requested line's uAPI flags with [`flags::USED`], as line info
    /// reports them; None while the line is free.
    pub fn line_flags(&self, offset: u32) -> Option<u64> {
        let s = self.lock();
        s.lines
            .get(offset as usize)
            .and_then(|l| l.setting)
            .map(|set| set.flags() | flags::USED)
    }

    /// Who holds line `offset` ("" while it is free).
    pub fn consumer(&self, offset: u32) -> String {
        self.lock()
            .lines
            .get(offset as usize)
            .map(|l| l.consumer.clone())
            .unwrap_or_default()
    }

    /// Makes line `to` see line `from`'s level as its outside level (a
    /// wire between two header pins).
    pub fn wire(&self, from: u32, to: u32) {
        let mut s = self.lock();
        let n = s.lines.len() as u32;
        if from < n && to < n && from != to {
            s.lines[to as usize].wired_from = Some(from);
        }
    }

    /// The logged level changes, oldest first.
    pub fn events(&self) -> Vec<LineEvent> {
        self.lock().events.iter().copied().collect()
    }

    /// The logged level changes of line `offset`.
    pub fn events_of(&self, offset: u32) -> Vec<LineEvent> {
        self.lock()
            .events
            .iter()
            .filter(|e| e.offset == offset)
            .copied()
            .collect()
    }

    /// Forgets the logged changes.
    pub fn clear_events(&self) {
        self.lock().events.clear();
    }

    /// Bulk writes so far.
    pub fn sets(&self) -> u64 {
        self.lock().sets
    }

    /// Bulk reads so far.
    pub fn gets(&self) -> u64 {
        self.lock().gets
    }

    /// Takes the chip away: every access fails with ENODEV from now on.
    pub fn remove(&self) {
        self.lock().removed = true;
    }

    /// Requests `lines` for `consumer`, as the kernel would.
    pub fn request(
        self: &Arc<Self>,
        lines: &[LineSetting],
        consumer: &str,
    ) -> Result<SimRequest, GpioError> {
        let mut s = self.lock();
        if s.removed {
            return Err(GpioError::Refused {
                errno: LineError(libc::ENODEV),
                detail: None,
            });
        }
        for l in lines {
            let Some(line) = s.lines.get(l.offset as usize) else {
                return Err(GpioError::NoSuchLine { offset: l.offset });
            };
            if line.setting.is_some() {
                return Err(GpioError::Refused {
                    errno: LineError(libc::EBUSY),
                    detail: Some(format!(
                        "line {} is in use by \"{}\"",
                        l.offset, line.consumer
                    )),
                });
            }
            if l.direction == Direction::Input && l.drive != Drive::PushPull {
                return Err(GpioError::Refused {
                    errno: LineError(libc::EINVAL),
                    detail: Some(format!(
                        "line {}: a drive setting needs an output",
                        l.offset
                    )),
                });
            }
        }
        let now = self.clock.now_ns();
        for l in lines {
            let before = s.level(l.offset);
            let line = &mut s.lines[l.offset as usize];
            line.setting = Some(*l);
            line.consumer = consumer.to_string();
            line.driven = false;
            match l.bias {
                Bias::PullUp => line.outside = true,
                Bias::PullDown => line.outside = false,
                Bias::AsIs | Bias::Disabled => {}
            }
            let after = s.level(l.offset);
            if after != before {
                s.log(now, l.offset, after);
            }
        }
        Ok(SimRequest {
            chip: self.clone(),
            offsets: lines.iter().map(|l| l.offset).collect(),
            errors: AtomicU64::new(0),
        })
    }
}

/// Lines requested on a [`SimChip`]; released when dropped.
#[derive(Debug)]
pub struct SimRequest {
    chip: Arc<SimChip>,
    offsets: Vec<u32>,
    errors: AtomicU64,
}

impl SimRequest {
    fn fail(&self, errno: i32) -> LineError {
        self.errors.fetch_add(1, Relaxed);
        LineError(errno)
    }
}

impl LineRequest for SimRequest {
    fn get(&self, mask: u64) -> Result<u64, LineError> {
        let mut s = self.chip.lock();
        if s.removed {
            return Err(self.fail(libc::ENODEV));
        }
        s.gets += 1;
        let mut bits = 0;
        for (k, &o) in self.offsets.iter().enumerate() {
            if mask & (1 << k) != 0 && s.logical(o) {
                bits |= 1 << k;
            }
        }
        Ok(bits)
    }

    fn set(&self, bits: u64, mask: u64) -> Result<(), LineError> {
        let mut s = self.chip.lock();
        if s.removed {
            return Err(self.fail(libc::ENODEV));
        }
        let is_output = |s: &ChipState, o: u32| {
            s.lines[o as usize]
                .setting
                .is_some_and(|l| l.direction == Direction::Output)
        };
        let selected = || {
            self.offsets
                .iter()
                .enumerate()
                .filter(|(k, _)| mask & (1 << k) != 0)
        };
        if selected().any(|(_, &o)| !is_output(&s, o)) {
            return Err(self.fail(libc::EPERM));
        }
        if mask & crate::regs::low_bits(self.offsets.len()) == 0 {
            return Err(self.fail(libc::EINVAL));
        }
        s.sets += 1;
        let now = self.chip.clock.now_ns();
        for (k, &o) in selected() {
            let before = s.level(o);
            s.lines[o as usize].driven = bits & (1 << k) != 0;
            let after = s.level(o);
            if after != before {
                s.log(now, o, after);
            }
        }
        Ok(())
    }

    fn errors(&self) -> u64 {
        self.errors.load(Relaxed)
    }

    fn describe(&self) -> String {
        format!("simulated {} lines {:?}", self.chip.info, self.offsets)
    }
}

impl Drop for SimRequest {
    /// Releases the lines: they read their outside level again.
    fn drop(&mut self) {
        let mut s = self.chip.lock();
        let now = self.chip.clock.now_ns();
        for &o in &self.offsets {
            let before = s.level(o);
            let line = &mut s.lines[o as usize];
            line.setting = None;
            line.consumer.clear();
            let after = s.level(o);
            if after != before {
                s.log(now, o, after);
            }
        }
    }
}

/// A set of simulated chips, the [`ChipSet`] of the `sim` backends.
#[derive(Debug, Default)]
pub struct SimChips {
    chips: Vec<Arc<SimChip>>,
}

impl SimChips {
    /// The chips `chips`, discovered in this order.
    pub fn new(chips: Vec<Arc<SimChip>>) -> SimChips {
        SimChips { chips }
    }

    /// What `backend=sim` gives: one chip `gpiochip0` labelled
    /// `hal_gpio sim` with one line per name in `cfg`, in its order
    /// (inputs first). With `loopback`, the n-th output is wired to the
    /// n-th input.
    pub fn for_config(cfg: &Config, loopback: bool, clock: Arc<dyn Clock>) -> SimChips {
        let names: Vec<&str> = cfg.lines.iter().map(|l| l.name.as_str()).collect();
        let chip = Arc::new(SimChip::new("gpiochip0", "hal_gpio sim", &names, clock));
        if loopback {
            let offsets = |d| {
                cfg.lines
                    .iter()
                    .enumerate()
                    .filter(move |(_, l)| l.direction == d)
                    .map(|(o, _)| o as u32)
            };
            for (from, to) in offsets(Direction::Output).zip(offsets(Direction::Input)) {
                chip.wire(from, to);
            }
        }
        SimChips::new(vec![chip])
    }

    /// The chips.
    pub fn chips(&self) -> &[Arc<SimChip>] {
        &self.chips
    }

    /// The chip and offset of the line called `name` (the first, should
    /// several have it).
    pub fn line(&self, name: &str) -> Option<(&Arc<SimChip>, u32)> {
        self.chips
            .iter()
            .find_map(|c| c.offset(name).map(|o| (c, o)))
    }

    /// Sets the outside level of line `name` (see
    /// [`SimChip::set_outside`]); false if no chip has it.
    pub fn set_outside(&self, name: &str, level: bool) -> bool {
        self.line(name)
            .map(|(c, o)| c.set_outside(o, level))
            .is_some()
    }

    /// The electrical level of line `name`.
    pub fn level(&self, name: &str) -> Option<bool> {
        self.line(name).map(|(c, o)| c.level(o))
    }

    /// The level changes of line `name`.
    pub fn events(&self, name: &str) -> Vec<LineEvent> {
        self.line(name)
            .map(|(c, o)| c.events_of(o))
            .unwrap_or_default()
    }
}

impl ChipSet for SimChips {
    fn chips(&self) -> Result<Vec<ChipInfo>, GpioError> {
        Ok(self.chips.iter().map(|c| c.info.clone()).collect())
    }

    fn request(
        &self,
        chip: &ChipInfo,
        lines: &[LineSetting],
    ) -> Result<Box<dyn LineRequest>, GpioError> {
        let names = |c: &ChipInfo| {
            lines
                .iter()
                .map(|l| {
                    c.line_names
                        .get(l.offset as usize)
                        .cloned()
                        .unwrap_or_else(|| format!("line {}", l.offset))
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        let sim = self
            .chips
            .iter()
            .find(|c| c.info.path == chip.path)
            .ok_or_else(|| GpioError::Request {
                chip: chip.to_string(),
                lines: names(chip),
                reason: "no such simulated chip".into(),
            })?;
        let req = sim
            .request(lines, crate::regs::CONSUMER)
            .map_err(|e| GpioError::Request {
                chip: chip.to_string(),
                lines: names(chip),
                reason: e.to_string(),
            })?;
        Ok(Box::new(req))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hal_driver::sim::SimClock;

    fn setting(offset: u32, direction: Direction) -> LineSetting {
        LineSetting {
            offset,
            direction,
            active_low: false,
            drive: Drive::PushPull,
            bias: Bias::AsIs,
        }
    }

    fn chip() -> (Arc<SimChip>, Arc<SimClock>) {
        let clock = Arc::new(SimClock::new(100, 0));
        let c = Arc::new(SimChip::new(
            "gpiochip0",
            "test",
            &["A", "B", "C", "D"],
            clock.clone(),
        ));
        (c, clock)
    }

    #[test]
    fn inputs_read_the_outside_and_bias_sets_it() {
        let (c, _) = chip();
        let r = c
            .request(
                &[
                    setting(0, Direction::Input),
                    LineSetting {
                        bias: Bias::PullUp,
                        ..setting(1, Direction::Input)
                    },
                    LineSetting {
                        active_low: true,
                        ..setting(2, Direction::Input)
                    },
                ],
                "t",
            )
            .unwrap();
        assert_eq!(
            r.get(0b111).unwrap(),
            0b110,
            "pull-up high, active-low low reads 1"
        );
        c.set_outside(0, true);
        c.set_outside(1, false);
        c.set_outside(2, true);
        assert_eq!(r.get(0b111).unwrap(), 0b001);
        assert_eq!(r.get(0b100).unwrap(), 0, "only the masked lines");
        assert_eq!(c.gets(), 3);
        assert_eq!(
            c.line_flags(1),
            Some(flags::USED | flags::INPUT | flags::BIAS_PULL_UP)
        );
        assert_eq!(c.consumer(2), "t");
        assert_eq!(c.line_flags(3), None);
    }

    #[test]
    fn outputs_drive_by_mode_and_log_changes() {
        let (c, clock) = chip();
        let r = c
            .request(
                &[
                    setting(0, Direction::Output),
                    LineSetting {
                        active_low: true,
                        ..setting(1, Direction::Output)
                    },
                    LineSetting {
                        drive: Drive::OpenDrain,
                        ..setting(2, Direction::Output)
                    },
                    LineSetting {
                        drive: Drive::OpenSource,
                        ..setting(3, Direction::Output)
                    },
                ],
                "t",
            )
            .unwrap();
        // Requested at logical 0: the active-low line went high then.
        assert_eq!(
            c.events(),
            vec![LineEvent {
                time_ns: 100,
                offset: 1,
                level: true
            }]
        );
        assert_eq!(
            (0..4).map(|o| c.level(o)).collect::<Vec<_>>(),
            [false, true, false, false]
        );
        clock.advance(50);
        r.set(0b1111, 0b1111).unwrap();
        assert_eq!(
            (0..4).map(|o| c.level(o)).collect::<Vec<_>>(),
            [true, false, false, true],
            "open drain high floats to the outside level (0)"
        );
        c.set_outside(2, true);
        assert!(c.level(2));
        r.set(0, 0b0100).unwrap();
        assert!(!c.level(2), "open drain low pulls down");
        assert_eq!(r.get(0b0001).unwrap(), 1, "outputs read back");
        let ev: Vec<_> = c.events_of(0);
        assert_eq!(
            ev,
            vec![LineEvent {
                time_ns: 150,
                offset: 0,
                level: true
            }]
        );
        assert_eq!(c.sets(), 2);
        drop(r);
        assert_eq!(c.line_flags(0), None);
        assert!(!c.level(0), "released: the outside level again");
    }

    #[test]
    fn the_kernel_refusals() {
        let (c, _) = chip();
        let r = c.request(&[setting(0, Direction::Input)], "first").unwrap();
        let e = c
            .request(&[setting(0, Direction::Output)], "second")
            .unwrap_err()
            .to_string();
        assert!(e.contains("in use by \"first\""), "{e}");
        let e = c
            .request(
                &[LineSetting {
                    drive: Drive::OpenDrain,
                    ..setting(1, Direction::Input)
                }],
                "x",
            )
            .unwrap_err()
            .to_string();
        assert!(e.contains("needs an output"), "{e}");
        assert_eq!(r.set(1, 1), Err(LineError(libc::EPERM)));
        assert_eq!(r.errors(), 1);
        c.remove();
        assert_eq!(r.get(1), Err(LineError(libc::ENODEV)));
        assert_eq!(r.errors(), 2);
        assert!(c.request(&[setting(2, Direction::Input)], "x").is_err());
    }

    #[test]
    fn wires_carry_an_output_to_an_input() {
        let (c, _) = chip();
        c.wire(3, 0);
        let o = c.request(&[setting(3, Direction::Output)], "o").unwrap();
        let i = c.request(&[setting(0, Direction::Input)], "i").unwrap();
        assert_eq!(i.get(1).unwrap(), 0);
        o.set(1, 1).unwrap();
        assert_eq!(i.get(1).unwrap(), 1);
    }
}
