//! `raster`: laser power from a pixel line streamed through a HAL port,
//! as LinuxCNC's component of that name.
//!
//! A program on the `program` port is a header of four fields each ended
//! by `;` (the offset from the start position to the first pixel, the
//! bits per pixel, the pixels per unit, the pixel count) followed by the
//! pixels, each `bpp / 4` hex digits. While `run` is on, the position
//! walks along the line; each pixel is taken from the port as the
//! position reaches it and `output` is the power (0 to 100) interpolated
//! between the last two pixels. A pixel of all ones is "off" (-1): no
//! power across it. Past the last pixel the output is -1 (LinuxCNC's
//! extrapolates there). The position must never go back; `reset` clears
//! a fault and the port.

use std::cell::RefCell;
use std::collections::VecDeque;

use hal_core::{In, Out, Pin, PortIn, Result};

use crate::halcomp::{HalComp, Inst};
use crate::halcomp_module;

/// Why the raster stopped (`fault-code`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum Fault {
    /// No fault.
    None = 0,
    /// The offset field is not a number.
    InvalidOffset = 1,
    /// Bits per pixel not 4 to 32 in steps of 4.
    InvalidBpp = 2,
    /// Pixels per unit not a number above 0.
    InvalidPpu = 3,
    /// Pixel count not a number of at least 2.
    InvalidCount = 4,
    /// A pixel that is not hex digits.
    BadPixelData = 5,
    /// The pixels waiting do not match bpp × count.
    ProgramWrongSize = 6,
    /// The position went back along the line.
    WrongDirection = 7,
}

/// The component's state (`state`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum State {
    /// Waiting for `run`.
    Idle = 0,
    /// Following a program.
    Run = 1,
    /// Stopped on a fault until `reset`.
    Fault = 2,
}

/// Where the program's bytes come from: the `program` port, or a buffer
/// in tests.
pub trait Program {
    /// Bytes waiting.
    fn readable(&self) -> u32;
    /// Copies exactly `out.len()` bytes without taking them.
    fn peek(&self, out: &mut [u8]) -> bool;
    /// Takes `n` bytes.
    fn commit(&self, n: u32) -> bool;
    /// Drops every waiting byte.
    fn clear(&self);
}

impl Program for PortIn {
    fn readable(&self) -> u32 {
        PortIn::readable(self)
    }
    fn peek(&self, out: &mut [u8]) -> bool {
        PortIn::peek(self, out)
    }
    fn commit(&self, n: u32) -> bool {
        self.peek_commit(n)
    }
    fn clear(&self) {
        PortIn::clear(self)
    }
}

/// Takes a header field ended by `;` from the first `limit` bytes and
/// parses it with `parse`; nothing is taken when there is no `;` there or
/// the text does not parse.
fn field<T>(p: &dyn Program, limit: usize, parse: impl Fn(&str) -> Option<T>) -> Option<T> {
    let mut buf = [0u8; 32];
    let n = (p.readable() as usize).min(limit).min(buf.len());
    if !p.peek(&mut buf[..n]) {
        return None;
    }
    let end = buf[..n].iter().position(|&b| b == b';')?;
    let text = std::str::from_utf8(&buf[..end]).ok()?.trim();
    let v = parse(text)?;
    p.commit(end as u32 + 1).then_some(v)
}

fn float_field(p: &dyn Program) -> Option<f64> {
    field(p, 32, |t| t.parse::<f64>().ok().filter(|v| v.is_finite()))
}

fn uint_field(p: &dyn Program) -> Option<u32> {
    field(p, 10, |t| t.parse::<u32>().ok())
}

/// Takes one pixel of `bpp` bits: its power 0 to 100, or -1 for "off"
/// (all ones); None when it is not there or not hex.
fn pixel(p: &dyn Program, bpp: u32) -> Option<f64> {
    let digits = (bpp / 4) as usize;
    let mut buf = [0u8; 8];
    let text = buf.get_mut(..digits)?;
    if !p.peek(text) {
        return None;
    }
    let value = u32::from_str_radix(std::str::from_utf8(text).ok()?, 16).ok()?;
    p.commit(digits as u32);
    let off = u32::MAX >> (32 - bpp);
    Some(if value == off {
        -1.0
    } else {
        100.0 * f64::from(value) / f64::from(off - 1)
    })
}

/// The program's header: what `run` starts with.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Header {
    /// From the start position to the first pixel (its sign: the
    /// direction of travel).
    pub offset: f64,
    /// Bits per pixel.
    pub bpp: u32,
    /// Pixels per unit.
    pub ppu: f64,
    /// Pixels.
    pub count: u32,
}

/// Reads and checks the header, and that the pixels it announces are all
/// there.
fn header(p: &dyn Program) -> std::result::Result<Header, Fault> {
    let offset = float_field(p).ok_or(Fault::InvalidOffset)?;
    let bpp = uint_field(p)
        .filter(|b| (4..=32).contains(b) && b % 4 == 0)
        .ok_or(Fault::InvalidBpp)?;
    let ppu = float_field(p)
        .filter(|v| *v > 0.0)
        .ok_or(Fault::InvalidPpu)?;
    let count = uint_field(p)
        .filter(|c| *c >= 2)
        .ok_or(Fault::InvalidCount)?;
    if u64::from(p.readable()) != u64::from(bpp / 4) * u64::from(count) {
        return Err(Fault::ProgramWrongSize);
    }
    Ok(Header {
        offset,
        bpp,
        ppu,
        count,
    })
}

/// What the component shows, besides its state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outputs {
    /// A program is running.
    pub enabled: bool,
    /// The power command, -1 for none.
    pub output: f64,
    /// The position where `run` started.
    pub program_position: f64,
    /// The program's header.
    pub header: Header,
    /// The position along the line, in pixels.
    pub bitmap_position: f64,
    /// The pixel last taken and the one before (-1: off or none).
    pub current_pixel: f64,
    /// See `current_pixel`.
    pub previous_pixel: f64,
    /// The index of the pixel last taken (-1: none).
    pub current_index: i32,
}

impl Default for Outputs {
    fn default() -> Outputs {
        Outputs {
            enabled: false,
            output: -1.0,
            program_position: 0.0,
            header: Header::default(),
            bitmap_position: 0.0,
            current_pixel: -1.0,
            previous_pixel: -1.0,
            current_index: -1,
        }
    }
}

/// The raster's state machine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Raster {
    /// Idle, running or faulted.
    pub state: State,
    /// The last fault (None after a reset).
    pub fault: Fault,
    /// What the pins show.
    pub out: Outputs,
    previous_bitmap_position: f64,
}

impl Default for Raster {
    fn default() -> Raster {
        Raster {
            state: State::Idle,
            fault: Fault::None,
            out: Outputs::default(),
            previous_bitmap_position: 0.0,
        }
    }
}

impl Raster {
    /// The position along the line, in pixels, at `position`.
    fn along(&self, position: f64) -> f64 {
        let h = &self.out.header;
        let dir = if h.offset < 0.0 { -1.0 } else { 1.0 };
        (position - (self.out.program_position + h.offset)) * h.ppu * dir
    }

    fn trip(&mut self, f: Fault) {
        self.state = State::Fault;
        self.fault = f;
    }

    /// One period.
    pub fn step(&mut self, position: f64, run: bool, reset: bool, p: &dyn Program) {
        self.out.output = -1.0;
        self.out.enabled = false;
        if reset {
            self.state = State::Idle;
            self.fault = Fault::None;
            p.clear();
            return;
        }
        match self.state {
            State::Fault => {}
            State::Idle => self.idle(position, run, p),
            State::Run => self.running(position, run, p),
        }
    }

    fn idle(&mut self, position: f64, run: bool, p: &dyn Program) {
        self.out.bitmap_position = 0.0;
        self.out.current_pixel = -1.0;
        self.out.previous_pixel = -1.0;
        self.out.current_index = -1;
        if !run {
            return;
        }
        match header(p) {
            Err(f) => self.trip(f),
            Ok(h) => {
                self.out.header = h;
                self.out.program_position = position;
                self.state = State::Run;
                self.out.bitmap_position = self.along(position);
                self.previous_bitmap_position = self.out.bitmap_position;
            }
        }
    }

    fn running(&mut self, position: f64, run: bool, p: &dyn Program) {
        let at = self.along(position);
        self.out.bitmap_position = at;
        if !run {
            self.state = State::Idle;
            p.clear();
            return;
        }
        if at < self.previous_bitmap_position {
            self.trip(Fault::WrongDirection);
            return;
        }
        self.previous_bitmap_position = at;
        self.out.enabled = true;
        let count = f64::from(self.out.header.count);
        while at < count && at > f64::from(self.out.current_index) {
            self.out.current_index += 1;
            self.out.previous_pixel = self.out.current_pixel;
            match pixel(p, self.out.header.bpp) {
                Some(v) => self.out.current_pixel = v,
                None => {
                    self.trip(Fault::BadPixelData);
                    return;
                }
            }
        }
        let (cur, prev) = (self.out.current_pixel, self.out.previous_pixel);
        // Past the last pixel the line is done: no power. (LinuxCNC's
        // goes on extrapolating from the last two pixels there, which
        // can command power outside the image.)
        if at < count && (cur > 0.0 || prev > 0.0) {
            let fraction = at - f64::from(self.out.current_index - 1);
            self.out.output = fraction * (cur - prev) + prev;
        }
    }
}

/// The `raster` component.
pub struct RasterComp;

/// The output pins of one instance.
struct RasterPins {
    enabled: Pin<bool, Out>,
    output: Pin<f64, Out>,
    fault: Pin<bool, Out>,
    fault_code: Pin<u32, Out>,
    state: Pin<u32, Out>,
    program_position: Pin<f64, Out>,
    program_offset: Pin<f64, Out>,
    bpp: Pin<u32, Out>,
    ppu: Pin<f64, Out>,
    count: Pin<u32, Out>,
    bitmap_position: Pin<f64, Out>,
    current_pixel_value: Pin<f64, Out>,
    previous_pixel_value: Pin<f64, Out>,
    current_pixel_index: Pin<i32, Out>,
}

impl RasterPins {
    fn new(inst: &mut Inst<'_, '_>) -> Result<RasterPins> {
        Ok(RasterPins {
            enabled: inst.pin_out("enabled")?,
            output: inst.pin_out_init("output", -1.0)?,
            fault: inst.pin_out("fault")?,
            fault_code: inst.pin_out("fault-code")?,
            state: inst.pin_out("state")?,
            program_position: inst.pin_out("program-position")?,
            program_offset: inst.pin_out("program-offset")?,
            bpp: inst.pin_out("bpp")?,
            ppu: inst.pin_out("ppu")?,
            count: inst.pin_out("count")?,
            bitmap_position: inst.pin_out("bitmap-position")?,
            current_pixel_value: inst.pin_out_init("current-pixel-value", -1.0)?,
            previous_pixel_value: inst.pin_out_init("previous-pixel-value", -1.0)?,
            current_pixel_index: inst.pin_out_init("current-pixel-index", -1)?,
        })
    }

    fn show(&self, r: &Raster) {
        let o = &r.out;
        self.enabled.set(o.enabled);
        self.output.set(o.output);
        self.fault.set(r.state == State::Fault);
        self.fault_code.set(r.fault as u32);
        self.state.set(r.state as u32);
        self.program_position.set(o.program_position);
        self.program_offset.set(o.header.offset);
        self.bpp.set(o.header.bpp);
        self.ppu.set(o.header.ppu);
        self.count.set(o.header.count);
        self.bitmap_position.set(o.bitmap_position);
        self.current_pixel_value.set(o.current_pixel);
        self.previous_pixel_value.set(o.previous_pixel);
        self.current_pixel_index.set(o.current_index);
    }
}

impl HalComp for RasterComp {
    const NAME: &'static str = "raster";
    fn build(inst: &mut Inst<'_, '_>) -> Result<()> {
        let position: Pin<f64, In> = inst.pin_in("position")?;
        let reset: Pin<bool, In> = inst.pin_in("reset")?;
        let run: Pin<bool, In> = inst.pin_in("run")?;
        let program = inst.port_in("program")?;
        let pins = RasterPins::new(inst)?;
        let mut raster = Raster::default();
        inst.funct("_", true, move |_| {
            raster.step(position.get(), run.get(), reset.get(), &program);
            pins.show(&raster);
        })
    }
}
halcomp_module!(pub MODULE, RasterComp, "outputs laser power from pixel data streamed through a HAL port");

/// A program held in memory: the fuzz target's and the tests' port.
#[derive(Debug, Default)]
pub(crate) struct Bytes(RefCell<VecDeque<u8>>);

impl Bytes {
    /// A program of the bytes of `data`.
    pub(crate) fn new(data: &[u8]) -> Bytes {
        Bytes(RefCell::new(data.iter().copied().collect()))
    }
}

impl Program for Bytes {
    fn readable(&self) -> u32 {
        self.0.borrow().len().min(u32::MAX as usize) as u32
    }
    fn peek(&self, out: &mut [u8]) -> bool {
        let q = self.0.borrow();
        if out.len() > q.len() {
            return false;
        }
        for (o, b) in out.iter_mut().zip(q.iter()) {
            *o = *b;
        }
        true
    }
    fn commit(&self, n: u32) -> bool {
        let mut q = self.0.borrow_mut();
        if n as usize > q.len() {
            return false;
        }
        q.drain(..n as usize);
        true
    }
    fn clear(&self) {
        self.0.borrow_mut().clear();
    }
}

/// The fuzz target's body: any bytes as a program, followed along a
/// walk of positions drawn from the first bytes, never panic, and the
/// power stays between -1 (off) and 100.
pub fn fuzz_program(data: &[u8]) {
    let (steps, program) = data.split_at(data.len().min(16));
    let p = Bytes::new(program);
    let mut r = Raster::default();
    let mut position = 0.0;
    for (i, s) in steps.iter().enumerate() {
        position += f64::from(*s as i8) / 16.0;
        r.step(position, *s != 0, i == 12, &p);
        let o = r.out.output;
        assert!(
            o.is_nan() || o >= -1.0 - 1e-9 || r.state != State::Run,
            "output {o}"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_is_read_and_power_follows_the_pixels() {
        // Offset 1, 4 bits, 10 pixels per unit, 4 pixels: 0, 7, 14 (full), F (off).
        let p = Bytes::new(b"1;4;10;4;07EF");
        let mut r = Raster::default();
        r.step(0.0, true, false, &p);
        assert_eq!(r.state, State::Run);
        assert_eq!(
            r.out.header,
            Header {
                offset: 1.0,
                bpp: 4,
                ppu: 10.0,
                count: 4
            }
        );
        // Before the first pixel: no power.
        r.step(0.5, true, false, &p);
        assert_eq!(r.out.output, -1.0);
        assert!(r.out.enabled);
        // 0.15 pixels past pixel 1 (7/14 = 50 %) from pixel 0 (0 %).
        r.step(1.115, true, false, &p);
        // 1.15 pixels in: pixels 0 to 2 are taken (one ahead), and the
        // power runs from pixel 1 (50 %) towards pixel 2 (100 %).
        assert_eq!(r.out.current_index, 2);
        assert_eq!((r.out.previous_pixel, r.out.current_pixel), (50.0, 100.0));
        assert!((r.out.output - 57.5).abs() < 1e-9, "{}", r.out.output);
        // At pixel 2 (full power) from pixel 1.
        let mut r2 = Raster::default();
        let p2 = Bytes::new(b"0;4;1;3;0E0");
        r2.step(0.0, true, false, &p2);
        r2.step(1.5, true, false, &p2);
        assert_eq!(r2.out.current_index, 2);
        assert_eq!((r2.out.previous_pixel, r2.out.current_pixel), (100.0, 0.0));
        // 1.5 pixels in: halfway from pixel 1 (100) to pixel 2 (0).
        assert!((r2.out.output - 50.0).abs() < 1e-9, "{}", r2.out.output);
    }

    #[test]
    fn an_off_pixel_gives_no_power() {
        let p = Bytes::new(b"0;8;1;3;FFFFFF");
        let mut r = Raster::default();
        r.step(0.0, true, false, &p);
        r.step(1.5, true, false, &p);
        assert_eq!(r.out.current_pixel, -1.0);
        assert_eq!(r.out.output, -1.0);
    }

    #[test]
    fn every_bad_program_has_its_fault() {
        for (text, fault) in [
            ("x;4;1;2;00", Fault::InvalidOffset),
            ("0;5;1;2;00", Fault::InvalidBpp),
            ("0;36;1;2;00", Fault::InvalidBpp),
            ("0;4;0;2;00", Fault::InvalidPpu),
            ("0;4;-1;2;00", Fault::InvalidPpu),
            ("0;4;1;1;0", Fault::InvalidCount),
            ("0;4;1;3;00", Fault::ProgramWrongSize),
            ("0;4;1", Fault::InvalidPpu),
        ] {
            let p = Bytes::new(text.as_bytes());
            let mut r = Raster::default();
            r.step(0.0, true, false, &p);
            assert_eq!((r.state, r.fault), (State::Fault, fault), "{text}");
            // It stays faulted until reset, which clears the port.
            r.step(0.0, true, false, &p);
            assert_eq!(r.state, State::Fault);
            r.step(0.0, true, true, &p);
            assert_eq!(
                (r.state, r.fault, p.readable()),
                (State::Idle, Fault::None, 0)
            );
        }
        let p = Bytes::new(b"0;4;1;2;0G");
        let mut r = Raster::default();
        r.step(0.0, true, false, &p);
        r.step(1.2, true, false, &p);
        assert_eq!(r.fault, Fault::BadPixelData);
    }

    #[test]
    fn going_back_is_a_fault_and_stopping_clears_the_port() {
        let p = Bytes::new(b"0;4;1;4;1234");
        let mut r = Raster::default();
        r.step(0.0, true, false, &p);
        r.step(1.0, true, false, &p);
        r.step(0.5, true, false, &p);
        assert_eq!((r.state, r.fault), (State::Fault, Fault::WrongDirection));
        let p = Bytes::new(b"0;4;1;4;1234");
        let mut r = Raster::default();
        r.step(0.0, true, false, &p);
        r.step(0.0, false, false, &p);
        assert_eq!((r.state, p.readable()), (State::Idle, 0));
    }

    #[test]
    fn a_negative_offset_runs_the_other_way() {
        let p = Bytes::new(b"-1;4;2;2;E0");
        let mut r = Raster::default();
        r.step(10.0, true, false, &p);
        // Start + offset = 9; moving down 0.25 gives half a pixel.
        r.step(8.75, true, false, &p);
        assert!((r.out.bitmap_position - 0.5).abs() < 1e-9);
        assert_eq!(r.out.current_index, 1);
    }

    /// Through the host: a writer component streams a program into the
    /// port `raster.0.program`, and the thread follows the position.
    #[test]
    fn a_program_through_a_port_drives_the_output() {
        use crate::testing::TestHost;
        use hal_core::{ComponentKind, HalType, Value};
        let mut h = TestHost::new("raster");
        h.load(&MODULE, &["count=1"]).unwrap();
        let inst = h.instance().clone();
        let c = inst.new_component("feeder", ComponentKind::User).unwrap();
        let w = c.port_out("feeder.out").unwrap();
        inst.newsig("pixels", HalType::Port).unwrap();
        inst.set_signal("pixels", Value::Port(64)).unwrap();
        inst.link("feeder.out", "pixels").unwrap();
        inst.link("raster.0.program", "pixels").unwrap();
        assert!(w.write(b"0;8;1;3;00FE80"));
        h.thread(&["raster.0"]);
        h.set("raster.0.run", Value::Bit(true));
        h.run(2);
        assert_eq!(h.get("raster.0.state"), Value::U32(State::Run as u32));
        assert_eq!(h.get("raster.0.count"), Value::U32(3));
        h.set("raster.0.position", Value::Float(1.5));
        h.run(2);
        // Pixel 1 (FE, 100 %) to pixel 2 (80, 50.4 %), half way.
        let want = 0.5 * (100.0 * 128.0 / 254.0 - 100.0) + 100.0;
        match h.get("raster.0.output") {
            Value::Float(v) => assert!((v - want).abs() < 1e-9, "{v}"),
            v => panic!("{v:?}"),
        }
        assert_eq!(h.get("raster.0.enabled"), Value::Bit(true));
        h.set("raster.0.position", Value::Float(1.0));
        h.run(2);
        assert_eq!(
            h.get("raster.0.fault-code"),
            Value::U32(Fault::WrongDirection as u32)
        );
        assert_eq!(h.get("raster.0.fault"), Value::Bit(true));
        assert_eq!(h.get("raster.0.output"), Value::Float(-1.0));
    }
}
