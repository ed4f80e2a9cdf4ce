//! `encoder`: software quadrature / pulse counter with index reset, latch,
//! missing-tooth index synthesis and velocity estimation
//! (components.md §3.2).
//!
//! Two functions share each channel: `encoder.update-counters` (integer
//! only, meant for a fast thread) decodes the inputs and records events;
//! `encoder.capture-position` (floating point) turns the recorded events
//! into counts, position and velocity. Their logic is in [`Counter`] and
//! [`Capture`]; the state both touch is a [`Link`].
//!
//! Hand-over between the functions: LinuxCNC double-buffers a record of
//! "events since the last capture" (flags plus values). Here update-counters
//! publishes the latest event of each kind in a [`Mailbox`], each in one
//! 64-bit word (so a reader never sees half an event), and capture-position
//! detects new events by comparing with the mailbox it saw last. For the
//! index and latch events a sequence number makes every event distinct; a
//! counted edge is identified by its (rawcounts, timestamp) pair, which can
//! only repeat if capture-position does not run for 2^32 ns (4.3 s) while
//! update-counters does. Within one thread this is exactly "everything
//! update-counters recorded since the last capture-position".

use std::sync::atomic::{
    AtomicBool, AtomicI32, AtomicU32, AtomicU64,
    Ordering::{Acquire, Relaxed, Release},
};
use std::sync::Arc;

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Component, Host, In, Io, Out, Pin, Result};

use super::quadrature::{QuadDecoder, QuadMode, Step};
use super::{CHANNEL_PARAMS, MAX_CHAN};
use crate::cmath::{f64_to_i32, ScaleCache};
use crate::halcomp::channel_names;

/// The `encoder` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "encoder",
    params: CHANNEL_PARAMS,
    help: "software quadrature / pulse counter (num_chan=1-8, default 3, or names=)",
    load,
};

/// Channels created when neither `num_chan` nor `names` is given.
pub const DEFAULT_CHANNELS: usize = 3;

/// The latest counted edge: `rawcounts` right after it and the global
/// timebase when it was seen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeStamp {
    /// `rawcounts` after the edge.
    pub raw_count: i32,
    /// Timebase (ns, wrapping) of the update-counters call that saw it.
    pub timestamp: u32,
}

impl EdgeStamp {
    fn pack(self) -> u64 {
        ((self.raw_count as u32 as u64) << 32) | self.timestamp as u64
    }
    fn unpack(w: u64) -> EdgeStamp {
        EdgeStamp {
            raw_count: (w >> 32) as u32 as i32,
            timestamp: w as u32,
        }
    }
}

/// The latest index or latch event: the `rawcounts` value it captured and
/// a sequence number that changes with every event.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Tagged {
    /// `rawcounts` when the event happened.
    pub count: i32,
    /// Incremented (wrapping) by every event.
    pub seq: u32,
}

impl Tagged {
    fn pack(self) -> u64 {
        ((self.count as u32 as u64) << 32) | self.seq as u64
    }
    fn unpack(w: u64) -> Tagged {
        Tagged {
            count: (w >> 32) as u32 as i32,
            seq: w as u32,
        }
    }
    fn next(self, count: i32) -> Tagged {
        Tagged {
            count,
            seq: self.seq.wrapping_add(1),
        }
    }
}

/// Events update-counters publishes for capture-position.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Mailbox {
    /// The latest counted edge.
    pub count: EdgeStamp,
    /// The latest index event.
    pub index: Tagged,
    /// The latest latch event.
    pub latch: Tagged,
}

/// State both functions of a channel read and write.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Link {
    /// LinuxCNC's `Zmask`: an index edge resets the count (set by
    /// capture-position from `index-enable`, cleared when the index fires).
    pub index_armed: bool,
    /// Tooth gaps seen since the last capture (missing-teeth mode).
    pub gaps: i32,
    /// Interval (ns) above which a tooth-to-tooth time is taken as a gap.
    pub limit_dt: i32,
    /// Published events.
    pub mailbox: Mailbox,
}

/// The pin values update-counters reads for one channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CounterInputs {
    /// `phase-A`.
    pub phase_a: bool,
    /// `phase-B`.
    pub phase_b: bool,
    /// `phase-Z`.
    pub phase_z: bool,
    /// `latch-input`.
    pub latch_input: bool,
    /// `latch-rising`.
    pub latch_rising: bool,
    /// `latch-falling`.
    pub latch_falling: bool,
    /// From `x4-mode` and `counter-mode`.
    pub mode: QuadMode,
    /// `missing-teeth`.
    pub missing_teeth: i32,
}

impl Default for CounterInputs {
    /// The pins' load-time defaults.
    fn default() -> Self {
        CounterInputs {
            phase_a: false,
            phase_b: false,
            phase_z: false,
            latch_input: false,
            latch_rising: true,
            latch_falling: true,
            mode: QuadMode::X4,
            missing_teeth: 0,
        }
    }
}

/// The update-counters half of a channel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counter {
    decoder: QuadDecoder,
    /// The last two index input samples (bit 0 newest).
    old_z: u8,
    old_latch: bool,
    /// Time since the last up count (ns, wrapping), for tooth gaps.
    dt: i32,
}

impl Counter {
    /// A channel as loaded.
    pub fn new() -> Counter {
        Counter::default()
    }

    /// One update-counters call for this channel. `rawcounts` is the pin
    /// (read and written), `timebase` the global time before this call's
    /// advance, `period` the thread period.
    #[inline]
    pub fn update(
        &mut self,
        inp: &CounterInputs,
        rawcounts: &mut i32,
        link: &mut Link,
        timebase: u32,
        period: i64,
    ) {
        self.dt = (self.dt as i64).wrapping_add(period) as i32;
        match self.decoder.step(inp.phase_a, inp.phase_b, inp.mode) {
            Step::Up => {
                if inp.missing_teeth != 0 && self.dt > link.limit_dt {
                    link.gaps = link.gaps.wrapping_add(1);
                }
                *rawcounts = rawcounts.wrapping_add(1);
                link.mailbox.count = EdgeStamp {
                    raw_count: *rawcounts,
                    timestamp: timebase,
                };
                self.dt = 0;
            }
            Step::Down => {
                *rawcounts = rawcounts.wrapping_sub(1);
                link.mailbox.count = EdgeStamp {
                    raw_count: *rawcounts,
                    timestamp: timebase,
                };
            }
            Step::None => {}
        }
        // Index: a rising edge of (phase-Z or a tooth gap), only when armed.
        let z = inp.phase_z || link.gaps != 0;
        self.old_z = ((self.old_z << 1) | z as u8) & 3;
        if link.index_armed && self.old_z == 0b01 {
            link.mailbox.index = link.mailbox.index.next(*rawcounts);
            link.index_armed = false;
        }
        let l = inp.latch_input;
        if (l && !self.old_latch && inp.latch_rising) || (!l && self.old_latch && inp.latch_falling)
        {
            link.mailbox.latch = link.mailbox.latch.next(*rawcounts);
        }
        self.old_latch = l;
    }
}

/// Pin values capture-position reads, some of which it corrects or
/// writes back (`index-enable`, `position-scale`, `min-speed-estimate`,
/// `rawcounts`, `velocity`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaptureIo {
    /// `index-enable` (cleared when the index fired).
    pub index_enable: bool,
    /// `reset`.
    pub reset: bool,
    /// `position-scale` (a near-zero scale is replaced by 1.0).
    pub position_scale: f64,
    /// `min-speed-estimate` (0 is replaced by 1.0).
    pub min_speed_estimate: f64,
    /// `missing-teeth`.
    pub missing_teeth: i32,
    /// `rawcounts` (missing teeth are added to it).
    pub rawcounts: i32,
    /// `velocity`, read back and updated.
    pub velocity: f64,
}

impl Default for CaptureIo {
    /// The pins' load-time defaults.
    fn default() -> Self {
        CaptureIo {
            index_enable: false,
            reset: false,
            position_scale: 1.0,
            min_speed_estimate: 1.0,
            missing_teeth: 0,
            rawcounts: 0,
            velocity: 0.0,
        }
    }
}

/// The output pins capture-position writes besides `velocity`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CaptureOutputs {
    /// `counts`.
    pub counts: i32,
    /// `counts-latched`.
    pub counts_latched: i32,
    /// `position`.
    pub position: f64,
    /// `position-latched`.
    pub position_latched: f64,
    /// `position-interpolated`.
    pub position_interpolated: f64,
    /// `velocity-rpm`.
    pub velocity_rpm: f64,
}

/// The capture-position half of a channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capture {
    /// The mailbox as seen by the previous call.
    seen: Mailbox,
    raw_count: i32,
    timestamp: u32,
    index_count: i32,
    latch_count: i32,
    /// 1 / position-scale, starting from LinuxCNC's old scale 1.0 and
    /// reciprocal 1.0.
    scale: ScaleCache,
    counts_since_timeout: i32,
}

impl Default for Capture {
    fn default() -> Self {
        Capture {
            seen: Mailbox::default(),
            raw_count: 0,
            timestamp: 0,
            index_count: 0,
            latch_count: 0,
            scale: ScaleCache::new(1.0, 1.0),
            counts_since_timeout: 0,
        }
    }
}

impl Capture {
    /// A channel as loaded.
    pub fn new() -> Capture {
        Capture::default()
    }

    /// One capture-position call for this channel; `timebase` is the
    /// global time as update-counters left it.
    pub fn capture(
        &mut self,
        io: &mut CaptureIo,
        link: &mut Link,
        timebase: u32,
    ) -> CaptureOutputs {
        let mb = link.mailbox;
        if mb.index != self.seen.index {
            self.index_count = mb.index.count;
            io.index_enable = false;
        }
        if mb.latch != self.seen.latch {
            self.latch_count = mb.latch.count;
        }
        let count_detected = mb.count != self.seen.count;
        self.seen = mb;
        link.index_armed = io.index_enable;
        let scale = self.scale.check(&mut io.position_scale, 1.0);
        if io.min_speed_estimate == 0.0 {
            io.min_speed_estimate = 1.0;
        }
        if io.reset {
            // rawcounts itself is never reset; counts become 0.
            self.raw_count = io.rawcounts;
            self.index_count = self.raw_count;
        }
        if count_detected {
            let dtime = mb.count.timestamp.wrapping_sub(self.timestamp);
            let mut dcount = mb.count.raw_count.wrapping_sub(self.raw_count);
            if dcount != 0 {
                // Running estimate of the tooth-gap threshold.
                let l = f64_to_i32(link.limit_dt as f64 * 0.9);
                let q = dtime / (dcount as u32);
                link.limit_dt =
                    f64_to_i32(l as f64 + 0.1 * ((io.missing_teeth as f64 + 0.5) * q as f64));
            }
            let extra = io.missing_teeth.wrapping_mul(link.gaps);
            io.rawcounts = io.rawcounts.wrapping_add(extra);
            self.raw_count = mb.count.raw_count.wrapping_add(extra);
            dcount = dcount.wrapping_add(extra);
            link.gaps = 0;
            self.timestamp = mb.count.timestamp;
            if self.counts_since_timeout < 2 {
                self.counts_since_timeout += 1;
            } else {
                io.velocity = (dcount as f64 * scale) / (dtime as f64 * 1e-9);
            }
        } else if self.counts_since_timeout != 0 {
            let dtime = timebase.wrapping_sub(self.timestamp);
            if io.missing_teeth != 0 && dtime as f64 > 1.5 * link.limit_dt as f64 {
                // Inside a tooth gap: keep the velocity.
            } else if (dtime as f64) < 1e9 / (io.min_speed_estimate * scale) {
                // No new edge: the speed is at most one count per dtime.
                let v = (scale / (dtime as f64 * 1e-9)).abs();
                if v < io.velocity {
                    io.velocity = v;
                }
                if -v > io.velocity {
                    io.velocity = -v;
                }
            } else {
                self.counts_since_timeout = 0;
                io.velocity = 0.0;
            }
        } else {
            io.velocity = 0.0;
        }
        let counts = self.raw_count.wrapping_sub(self.index_count);
        let counts_latched = self.latch_count.wrapping_sub(self.index_count);
        let position = counts as f64 * scale;
        let dtime = timebase.wrapping_sub(self.timestamp);
        CaptureOutputs {
            counts,
            counts_latched,
            position,
            position_latched: counts_latched as f64 * scale,
            position_interpolated: position + io.velocity * (dtime as f64 * 1e-9),
            velocity_rpm: io.velocity * 60.0,
        }
    }
}

/// [`Link`] in atomics, for functions that may run in different threads.
#[derive(Default)]
struct SharedLink {
    index_armed: AtomicBool,
    gaps: AtomicI32,
    limit_dt: AtomicI32,
    count: AtomicU64,
    index: AtomicU64,
    latch: AtomicU64,
}

impl SharedLink {
    fn load(&self) -> Link {
        // The events first (acquire): the writer publishes them last, so
        // the gaps and limits read after them are at least as new.
        let mailbox = Mailbox {
            count: EdgeStamp::unpack(self.count.load(Acquire)),
            index: Tagged::unpack(self.index.load(Acquire)),
            latch: Tagged::unpack(self.latch.load(Acquire)),
        };
        Link {
            index_armed: self.index_armed.load(Relaxed),
            gaps: self.gaps.load(Relaxed),
            limit_dt: self.limit_dt.load(Relaxed),
            mailbox,
        }
    }

    /// Writes back what one function changed relative to `before`. `gaps`
    /// is applied as a difference so that an increment and a clear from
    /// the other function are both kept.
    fn store_changes(&self, before: &Link, after: &Link) {
        if after.index_armed != before.index_armed {
            self.index_armed.store(after.index_armed, Relaxed);
        }
        if after.gaps != before.gaps {
            self.gaps
                .fetch_add(after.gaps.wrapping_sub(before.gaps), Relaxed);
        }
        if after.limit_dt != before.limit_dt {
            self.limit_dt.store(after.limit_dt, Relaxed);
        }
        let (b, a) = (&before.mailbox, &after.mailbox);
        // Events are published last, with release ordering, so that a
        // reader that sees an event also sees the gaps counted with it.
        if a.count != b.count {
            self.count.store(a.count.pack(), Release);
        }
        if a.index != b.index {
            self.index.store(a.index.pack(), Release);
        }
        if a.latch != b.latch {
            self.latch.store(a.latch.pack(), Release);
        }
    }
}

/// update-counters' view of a channel.
struct UpdateChan {
    phase_a: Pin<bool, In>,
    phase_b: Pin<bool, In>,
    phase_z: Pin<bool, In>,
    latch_input: Pin<bool, In>,
    latch_rising: Pin<bool, In>,
    latch_falling: Pin<bool, In>,
    x4_mode: Pin<bool, Io>,
    counter_mode: Pin<bool, Io>,
    missing_teeth: Pin<i32, In>,
    rawcounts: Pin<i32, Out>,
    counter: Counter,
    link: Arc<SharedLink>,
}

/// capture-position's view of a channel.
struct CaptureChan {
    index_enable: Pin<bool, Io>,
    reset: Pin<bool, In>,
    position_scale: Pin<f64, Io>,
    min_speed_estimate: Pin<f64, In>,
    missing_teeth: Pin<i32, In>,
    rawcounts: Pin<i32, Out>,
    counts: Pin<i32, Out>,
    counts_latched: Pin<i32, Out>,
    position: Pin<f64, Out>,
    position_interpolated: Pin<f64, Out>,
    position_latched: Pin<f64, Out>,
    velocity: Pin<f64, Out>,
    velocity_rpm: Pin<f64, Out>,
    capture: Capture,
    link: Arc<SharedLink>,
}

/// Exports channel `name`'s pins: the counting half and the capture half.
fn export_channel(c: &Component, name: &str) -> Result<(UpdateChan, CaptureChan)> {
    let p = |item: &str| format!("{name}.{item}");
    let link = Arc::new(SharedLink::default());
    let phase_a = c.pin(&p("phase-A"))?;
    let phase_b = c.pin(&p("phase-B"))?;
    let phase_z = c.pin(&p("phase-Z"))?;
    let index_enable = c.pin(&p("index-enable"))?;
    let reset = c.pin(&p("reset"))?;
    let latch_input = c.pin(&p("latch-input"))?;
    let latch_rising = c.pin_init(&p("latch-rising"), true)?;
    let latch_falling = c.pin_init(&p("latch-falling"), true)?;
    let rawcounts: Pin<i32, Out> = c.pin(&p("rawcounts"))?;
    let counts = c.pin(&p("counts"))?;
    let counts_latched = c.pin(&p("counts-latched"))?;
    let min_speed_estimate = c.pin_init(&p("min-speed-estimate"), 1.0)?;
    let position = c.pin(&p("position"))?;
    let position_interpolated = c.pin(&p("position-interpolated"))?;
    let position_latched = c.pin(&p("position-latched"))?;
    let velocity = c.pin(&p("velocity"))?;
    let velocity_rpm = c.pin(&p("velocity-rpm"))?;
    let position_scale = c.pin_init(&p("position-scale"), 1.0)?;
    let x4_mode = c.pin_init(&p("x4-mode"), true)?;
    let counter_mode = c.pin(&p("counter-mode"))?;
    let missing_teeth: Pin<i32, In> = c.pin(&p("missing-teeth"))?;
    let update = UpdateChan {
        phase_a,
        phase_b,
        phase_z,
        latch_input,
        latch_rising,
        latch_falling,
        x4_mode,
        counter_mode,
        missing_teeth: missing_teeth.clone(),
        rawcounts: rawcounts.clone(),
        counter: Counter::new(),
        link: link.clone(),
    };
    let capture = CaptureChan {
        index_enable,
        reset,
        position_scale,
        min_speed_estimate,
        missing_teeth,
        rawcounts,
        counts,
        counts_latched,
        position,
        position_interpolated,
        position_latched,
        velocity,
        velocity_rpm,
        capture: Capture::new(),
        link,
    };
    Ok((update, capture))
}

impl UpdateChan {
    /// One update-counters call for this channel at time base `now`.
    fn update(&mut self, now: u32, period: i64) {
        let inp = CounterInputs {
            phase_a: self.phase_a.get(),
            phase_b: self.phase_b.get(),
            phase_z: self.phase_z.get(),
            latch_input: self.latch_input.get(),
            latch_rising: self.latch_rising.get(),
            latch_falling: self.latch_falling.get(),
            mode: QuadMode::from_pins(self.x4_mode.get(), self.counter_mode.get()),
            missing_teeth: self.missing_teeth.get(),
        };
        let before = self.link.load();
        let mut link = before;
        let raw0 = self.rawcounts.get();
        let mut raw = raw0;
        self.counter.update(&inp, &mut raw, &mut link, now, period);
        if raw != raw0 {
            self.rawcounts.set(raw);
        }
        self.link.store_changes(&before, &link);
    }
}

impl CaptureChan {
    /// One capture-position call for this channel at time base `now`.
    fn capture_position(&mut self, now: u32) {
        let before = self.link.load();
        let mut link = before;
        let io0 = CaptureIo {
            index_enable: self.index_enable.get(),
            reset: self.reset.get(),
            position_scale: self.position_scale.get(),
            min_speed_estimate: self.min_speed_estimate.get(),
            missing_teeth: self.missing_teeth.get(),
            rawcounts: self.rawcounts.get(),
            velocity: self.velocity.get(),
        };
        let mut io = io0;
        let out = self.capture.capture(&mut io, &mut link, now);
        self.link.store_changes(&before, &link);
        // Write back only what the function changed, so that inputs
        // driven by others are left alone.
        if io.index_enable != io0.index_enable {
            self.index_enable.set(io.index_enable);
        }
        if io.position_scale.to_bits() != io0.position_scale.to_bits() {
            self.position_scale.set(io.position_scale);
        }
        if io.min_speed_estimate.to_bits() != io0.min_speed_estimate.to_bits() {
            self.min_speed_estimate.overwrite(io.min_speed_estimate);
        }
        if io.rawcounts != io0.rawcounts {
            // Added as a difference: update-counters may have counted
            // meanwhile if it runs in another thread.
            let extra = io.rawcounts.wrapping_sub(io0.rawcounts);
            self.rawcounts.set(self.rawcounts.get().wrapping_add(extra));
        }
        self.velocity.set(io.velocity);
        self.velocity_rpm.set(out.velocity_rpm);
        self.counts.set(out.counts);
        self.counts_latched.set(out.counts_latched);
        self.position.set(out.position);
        self.position_latched.set(out.position_latched);
        self.position_interpolated.set(out.position_interpolated);
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let names = channel_names("encoder", "encoder", DEFAULT_CHANNELS, MAX_CHAN, args)?;
    let mut b = host.new_rt_component("encoder")?;
    let mut update = Vec::with_capacity(names.len());
    let mut capture = Vec::with_capacity(names.len());
    for name in &names {
        let (u, c) = export_channel(b.component(), name)?;
        update.push(u);
        capture.push(c);
    }
    // The module-wide time base, advanced by update-counters.
    let timebase = Arc::new(AtomicU32::new(0));
    let tb = timebase.clone();
    b.funct("encoder.update-counters", false, move |ctx| {
        let period = ctx.period();
        let now = tb.load(Relaxed);
        for ch in update.iter_mut() {
            ch.update(now, period);
        }
        tb.store(now.wrapping_add(period as u32), Relaxed);
    })?;
    b.funct("encoder.capture-position", true, move |_| {
        let now = timebase.load(Relaxed);
        for ch in capture.iter_mut() {
            ch.capture_position(now);
        }
    })?;
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: i64 = 50_000;

    /// One channel driven without a host, in one thread: update-counters
    /// then capture-position each cycle, as a HAL thread would run them.
    struct Sim {
        counter: Counter,
        capture: Capture,
        link: Link,
        timebase: u32,
        inp: CounterInputs,
        io: CaptureIo,
        out: CaptureOutputs,
    }

    impl Sim {
        fn new() -> Sim {
            Sim {
                counter: Counter::new(),
                capture: Capture::new(),
                link: Link::default(),
                timebase: 0,
                inp: CounterInputs::default(),
                io: CaptureIo::default(),
                out: CaptureOutputs::default(),
            }
        }

        fn update(&mut self) {
            self.counter.update(
                &self.inp,
                &mut self.io.rawcounts,
                &mut self.link,
                self.timebase,
                P,
            );
            self.timebase = self.timebase.wrapping_add(P as u32);
        }

        fn capture(&mut self) {
            self.out = self
                .capture
                .capture(&mut self.io, &mut self.link, self.timebase);
        }

        /// Both functions read the `missing-teeth` pin.
        fn set_missing_teeth(&mut self, n: i32) {
            self.inp.missing_teeth = n;
            self.io.missing_teeth = n;
        }

        fn cycle(&mut self, a: bool, b: bool) {
            self.inp.phase_a = a;
            self.inp.phase_b = b;
            self.update();
            self.capture();
        }

        /// `n` forward x4 edges, one per cycle, with `hold` extra cycles
        /// of no change after each edge.
        fn forward(&mut self, n: usize, hold: usize) {
            for _ in 0..n {
                let (a, b) = (self.inp.phase_a, self.inp.phase_b);
                // Next state along 00 -> 10 -> 11 -> 01 -> 00.
                let (a, b) = match (a, b) {
                    (false, false) => (true, false),
                    (true, false) => (true, true),
                    (true, true) => (false, true),
                    (false, true) => (false, false),
                };
                self.cycle(a, b);
                for _ in 0..hold {
                    self.cycle(a, b);
                }
            }
        }

        fn reverse(&mut self, n: usize, hold: usize) {
            for _ in 0..n {
                let (a, b) = match (self.inp.phase_a, self.inp.phase_b) {
                    (false, false) => (false, true),
                    (false, true) => (true, true),
                    (true, true) => (true, false),
                    (true, false) => (false, false),
                };
                self.cycle(a, b);
                for _ in 0..hold {
                    self.cycle(a, b);
                }
            }
        }
    }

    #[test]
    fn counts_and_position_follow_rawcounts() {
        let mut s = Sim::new();
        s.io.position_scale = 4.0;
        s.forward(10, 0);
        assert_eq!(s.io.rawcounts, 10);
        assert_eq!(s.out.counts, 10);
        assert_eq!(s.out.position, 2.5);
        s.reverse(3, 0);
        assert_eq!(s.out.counts, 7);
        assert_eq!(s.out.position, 1.75);
    }

    #[test]
    fn counts_change_only_in_capture() {
        let mut s = Sim::new();
        s.inp.phase_a = true;
        s.update();
        assert_eq!(s.io.rawcounts, 1);
        assert_eq!(s.out.counts, 0);
        s.capture();
        assert_eq!(s.out.counts, 1);
    }

    #[test]
    fn rawcounts_wrap_around() {
        let mut s = Sim::new();
        s.io.rawcounts = i32::MAX;
        s.forward(1, 0);
        assert_eq!(s.io.rawcounts, i32::MIN);
        // counts = raw_count - index_count wraps the same way.
        assert_eq!(s.out.counts, i32::MIN);
    }

    #[test]
    fn reset_zeroes_counts_but_not_rawcounts() {
        let mut s = Sim::new();
        s.forward(5, 0);
        s.io.reset = true;
        s.forward(3, 0);
        assert_eq!(s.io.rawcounts, 8);
        assert_eq!(s.out.counts, 0);
        assert_eq!(s.out.position, 0.0);
        s.io.reset = false;
        s.forward(2, 0);
        assert_eq!(s.out.counts, 2);
    }

    #[test]
    fn index_resets_once_when_armed() {
        let mut s = Sim::new();
        s.forward(5, 0);
        // An index pulse while not armed does nothing.
        s.inp.phase_z = true;
        s.forward(1, 0);
        s.inp.phase_z = false;
        s.forward(1, 0);
        assert_eq!(s.out.counts, 7);
        // Arming takes effect at the next capture.
        s.io.index_enable = true;
        s.capture();
        assert!(s.link.index_armed);
        s.forward(2, 0);
        s.inp.phase_z = true;
        s.forward(1, 0); // index seen with rawcounts 10
        assert!(!s.io.index_enable);
        assert_eq!(s.out.counts, 0);
        s.inp.phase_z = false;
        s.forward(4, 0);
        assert_eq!(s.out.counts, 4);
        // A second pulse without re-arming does not reset again.
        s.inp.phase_z = true;
        s.forward(1, 0);
        assert_eq!(s.out.counts, 5);
    }

    #[test]
    fn index_needs_a_rising_edge() {
        let mut s = Sim::new();
        s.inp.phase_z = true;
        s.forward(3, 0);
        s.io.index_enable = true;
        s.capture();
        // Z stays high: no edge, no reset.
        s.forward(3, 0);
        assert_eq!(s.out.counts, 6);
        assert!(s.io.index_enable);
        s.inp.phase_z = false;
        s.forward(1, 0);
        s.inp.phase_z = true;
        s.forward(1, 0);
        assert_eq!(s.out.counts, 0);
        assert_eq!(s.out.position, 0.0);
    }

    #[test]
    fn latch_on_selected_edges() {
        let mut s = Sim::new();
        s.io.position_scale = 2.0;
        s.forward(4, 0);
        s.inp.latch_input = true;
        s.forward(1, 0);
        assert_eq!(s.out.counts_latched, 5);
        assert_eq!(s.out.position_latched, 2.5);
        s.forward(2, 0);
        s.inp.latch_input = false;
        s.forward(1, 0);
        assert_eq!(s.out.counts_latched, 8);
        // Rising only.
        s.inp.latch_falling = false;
        s.inp.latch_input = true;
        s.forward(1, 0);
        assert_eq!(s.out.counts_latched, 9);
        s.inp.latch_input = false;
        s.forward(1, 0);
        assert_eq!(s.out.counts_latched, 9);
        // Latched counts are relative to the index reference too.
        s.io.reset = true;
        s.capture();
        assert_eq!(s.out.counts_latched, 9 - 10);
    }

    #[test]
    fn tiny_scale_becomes_one_and_zero_min_speed_one() {
        let mut s = Sim::new();
        s.io.position_scale = 1e-21;
        s.io.min_speed_estimate = 0.0;
        s.forward(3, 0);
        assert_eq!(s.io.position_scale, 1.0);
        assert_eq!(s.io.min_speed_estimate, 1.0);
        assert_eq!(s.out.position, 3.0);
        s.io.position_scale = -2.0;
        s.capture();
        assert_eq!(s.out.position, -1.5);
    }

    #[test]
    fn velocity_starts_on_the_third_counting_capture() {
        let mut s = Sim::new();
        // One edge every 4 cycles (200 us): 5000 counts/s.
        s.forward(1, 3);
        s.forward(1, 3);
        assert_eq!(s.io.velocity, 0.0);
        s.forward(1, 0);
        let expect = (1.0 * 1.0) / (4.0 * P as f64 * 1e-9);
        assert_eq!(s.io.velocity, expect);
        assert_eq!(s.out.velocity_rpm, expect * 60.0);
        // position-interpolated is position at the capture itself here
        // (the last edge was in this cycle; timebase is one period on).
        assert_eq!(
            s.out.position_interpolated,
            3.0 + expect * (P as f64 * 1e-9)
        );
        s.reverse(1, 3);
        assert!(s.io.velocity < 0.0);
    }

    #[test]
    fn velocity_decays_then_times_out() {
        let mut s = Sim::new();
        s.io.min_speed_estimate = 1000.0;
        // Threshold: 1e9 / (1000 * 1) = 1 ms = 20 periods.
        s.forward(5, 0);
        let fast = s.io.velocity;
        assert_eq!(fast, 1.0 / (P as f64 * 1e-9));
        // No new edge: the magnitude falls to 1 count / time since edge.
        s.cycle(s.inp.phase_a, s.inp.phase_b);
        assert_eq!(s.io.velocity, (1.0f64 / (2.0 * P as f64 * 1e-9)).abs());
        for _ in 0..17 {
            s.cycle(s.inp.phase_a, s.inp.phase_b);
        }
        // dtime now 19 periods: still estimating.
        assert_eq!(s.io.velocity, 1.0 / (19.0 * P as f64 * 1e-9));
        s.cycle(s.inp.phase_a, s.inp.phase_b);
        assert_eq!(s.io.velocity, 0.0);
        // Disarmed: the next two counting captures give no velocity.
        s.forward(2, 0);
        assert_eq!(s.io.velocity, 0.0);
        s.forward(1, 0);
        assert!(s.io.velocity > 0.0);
    }

    #[test]
    fn decay_keeps_the_sign() {
        let mut s = Sim::new();
        s.reverse(5, 0);
        assert!(s.io.velocity < 0.0);
        s.cycle(s.inp.phase_a, s.inp.phase_b);
        assert_eq!(s.io.velocity, -(1.0 / (2.0 * P as f64 * 1e-9)));
    }

    #[test]
    fn negative_scale_zeroes_velocity_without_counts() {
        // Quirk: the timeout threshold is negative, so every capture
        // without a new count disarms the estimator.
        let mut s = Sim::new();
        s.io.position_scale = -1.0;
        s.forward(5, 0);
        assert!(s.io.velocity < 0.0);
        s.cycle(s.inp.phase_a, s.inp.phase_b);
        assert_eq!(s.io.velocity, 0.0);
    }

    #[test]
    fn x1_and_counter_modes() {
        let mut s = Sim::new();
        s.inp.mode = QuadMode::X1;
        s.forward(12, 0);
        assert_eq!(s.out.counts, 3);
        let mut s = Sim::new();
        s.inp.mode = QuadMode::Counter;
        s.reverse(12, 0);
        // Counter mode counts rising edges of A whatever the direction.
        assert_eq!(s.out.counts, 3);
    }

    #[test]
    fn missing_teeth_synthesises_index_and_fills_counts() {
        let mut s = Sim::new();
        s.inp.mode = QuadMode::Counter;
        s.set_missing_teeth(1);
        // A tooth every 4 cycles (rising A on the first).
        let tooth = |s: &mut Sim, n: usize| {
            for _ in 0..n {
                s.cycle(true, false);
                s.cycle(true, false);
                s.cycle(false, false);
                s.cycle(false, false);
            }
        };
        // limit_dt starts at 0, so the first edge counts as a gap; the
        // capture adds missing_teeth * gaps to rawcounts.
        tooth(&mut s, 1);
        assert_eq!(s.io.rawcounts, 2);
        assert_eq!(s.link.gaps, 0);
        tooth(&mut s, 30);
        let raw = s.io.rawcounts;
        let limit = s.link.limit_dt;
        // The threshold settles near (0.5 + missing) * tooth time, well
        // above one tooth (200 us) and below two.
        assert!(limit > 200_000 && limit < 400_000, "{limit}");
        // Skip one tooth: 8 cycles between rising edges.
        for _ in 0..4 {
            s.cycle(false, false);
        }
        s.io.index_enable = true;
        s.capture();
        tooth(&mut s, 1);
        assert_eq!(s.io.rawcounts, raw + 2, "the missing tooth is added");
        assert!(!s.io.index_enable, "the gap fired the index");
        assert_eq!(s.out.counts, 1);
    }

    #[test]
    fn missing_teeth_keeps_velocity_in_the_gap() {
        let mut s = Sim::new();
        s.inp.mode = QuadMode::Counter;
        s.set_missing_teeth(1);
        for _ in 0..30 {
            s.cycle(true, false);
            s.cycle(false, false);
            s.cycle(false, false);
            s.cycle(false, false);
        }
        let v = s.io.velocity;
        assert!(v > 0.0);
        // Four cycles after the last edge the decay formula applies...
        // ...but beyond 1.5 * limit_dt the velocity is frozen.
        let limit = s.link.limit_dt as f64;
        let mut held = None;
        for _ in 0..12 {
            s.cycle(false, false);
            let dtime = s.timebase.wrapping_sub(s.capture.timestamp) as f64;
            if dtime > 1.5 * limit {
                let h = *held.get_or_insert(s.io.velocity);
                assert_eq!(s.io.velocity, h);
            }
        }
        assert!(held.is_some());
    }

    #[test]
    fn limit_dt_formula_uses_c_conversions() {
        // limit_dt = (int)((int)(limit_dt * 0.9) + 0.1 * ((mt + 0.5) * q))
        let mut s = Sim::new();
        s.io.missing_teeth = 2;
        s.link.limit_dt = 1001;
        s.link.mailbox.count = EdgeStamp {
            raw_count: 3,
            timestamp: 700_001,
        };
        s.capture.counts_since_timeout = 2;
        s.capture();
        let q = (700_001u32 / 3) as f64;
        let expect = f64_to_i32(900.0 + 0.1 * (2.5 * q));
        assert_eq!(s.link.limit_dt, expect);
        // Negative dcount divides by a huge unsigned value: q = 0.
        s.link.mailbox.count = EdgeStamp {
            raw_count: 1,
            timestamp: 800_000,
        };
        s.capture();
        assert_eq!(s.link.limit_dt, f64_to_i32(expect as f64 * 0.9));
    }

    #[test]
    fn timebase_wraps() {
        let mut s = Sim::new();
        s.timebase = u32::MAX - 60_000;
        s.forward(5, 1);
        // Edges straddle the wrap; velocity stays a sane positive value.
        assert_eq!(s.io.velocity, 1.0 / (2.0 * P as f64 * 1e-9));
    }

    #[test]
    fn shared_link_round_trips_and_merges_gaps() {
        let sh = SharedLink::default();
        let before = sh.load();
        let mut a = before;
        a.gaps = 2;
        a.index_armed = true;
        a.mailbox.count = EdgeStamp {
            raw_count: -5,
            timestamp: 0xFFFF_FFF0,
        };
        a.mailbox.latch = Tagged { count: -1, seq: 7 };
        sh.store_changes(&before, &a);
        assert_eq!(sh.load(), a);
        // The capture side clears gaps it saw (2) while update added one.
        let seen = sh.load();
        let mut cleared = seen;
        cleared.gaps = 0;
        sh.gaps.fetch_add(1, Relaxed);
        sh.store_changes(&seen, &cleared);
        assert_eq!(sh.load().gaps, 1);
    }

    mod hosted {
        use super::super::*;
        use crate::testing::{host, load, pin_names as pins};
        use hal_core::Value;

        #[test]
        fn load_creates_channels_pins_and_functions() {
            let h = host();
            load(&h, &MODULE, &[]).unwrap();
            let p = pins(&h);
            assert_eq!(p.iter().filter(|n| n.ends_with(".phase-A")).count(), 3);
            let inst = h.instance();
            assert_eq!(
                inst.pin_value("encoder.2.x4-mode").unwrap(),
                Value::Bit(true)
            );
            assert_eq!(
                inst.pin_value("encoder.0.position-scale").unwrap(),
                Value::Float(1.0)
            );
            assert_eq!(
                inst.pin_value("encoder.1.min-speed-estimate").unwrap(),
                Value::Float(1.0)
            );
            assert_eq!(
                inst.pin_value("encoder.1.latch-falling").unwrap(),
                Value::Bit(true)
            );
            let f: Vec<String> = inst.functs().unwrap().into_iter().map(|f| f.name).collect();
            assert!(f.contains(&"encoder.update-counters".to_string()));
            assert!(f.contains(&"encoder.capture-position".to_string()));
        }

        #[test]
        fn names_load_and_bad_params_leave_nothing() {
            let h = host();
            load(&h, &MODULE, &["names=spindle,x.enc"]).unwrap();
            let p = pins(&h);
            assert!(p.contains(&"spindle.velocity-rpm".to_string()));
            assert!(p.contains(&"x.enc.counts".to_string()));
            let h = host();
            for bad in [
                &["num_chan=9"][..],
                &["num_chan=2", "names=a"],
                &["names=a,b,c,d,e,f,g,h,i"],
                &["bogus=1"],
            ] {
                assert!(load(&h, &MODULE, bad).is_err(), "{bad:?}");
                assert!(pins(&h).is_empty(), "{bad:?}");
            }
            load(&h, &MODULE, &["num_chan=8"]).unwrap();
            assert_eq!(pins(&h).iter().filter(|n| n.ends_with(".reset")).count(), 8);
        }
    }
}
