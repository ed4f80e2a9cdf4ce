//! The state machine's frame: what it keeps between calls, one call
//! (sense, check the machine, run the state, move the offsets, set the
//! outputs) and the helpers the states share. The states themselves are
//! in `probe`, `torch`, `cut` and `stops`.

use super::moves::{self, Mover};
use super::pins::{Inputs, Outputs};
use super::sense::Senses;
use super::state::{Fault, State, StopType};
use super::stats::Stats;
use super::thc::Thc;

/// What one call knows besides its pins.
#[derive(Debug, Clone, Copy)]
pub struct Ctx<'a> {
    /// The input pins.
    pub i: &'a Inputs,
    /// The period in seconds.
    pub dt: f64,
    /// Units per offset count.
    pub scale: f64,
    /// Z without the external offset (the program's Z).
    pub base_z: f64,
}

impl Ctx<'_> {
    /// Counts per period of a feed rate in units per minute.
    pub fn speed(&self, feed_upm: f64) -> i32 {
        moves::counts_per_period(feed_upm, self.dt, self.scale)
    }

    /// Counts of a distance in units.
    pub fn counts(&self, units: f64) -> i32 {
        moves::to_counts(units, self.scale)
    }

    /// Counts that put Z at machine height `z`.
    pub fn counts_at(&self, z: f64) -> i32 {
        self.counts(z - self.base_z)
    }

    /// Machine units per mm (unset reads as metric).
    pub fn units_per_mm(&self) -> f64 {
        moves::usable_units_per_mm(self.i.units_per_mm)
    }

    /// Counts of the highest Z the component drives to: `max-offset` mm
    /// under the Z maximum limit.
    pub fn top(&self) -> i32 {
        let margin = f64::from(self.i.max_offset.max(0)) * self.units_per_mm();
        self.counts_at(self.i.axis_z_max_limit - margin)
    }

    /// X and Y offset counts for `x`/`y` (counts), held so that the axes
    /// stay within their limits (when the limits are connected).
    pub fn xy_within_limits(&self, x: i32, y: i32) -> (i32, i32) {
        let i = self.i;
        let hold = |want: i32, pos: f64, current: f64, min: f64, max: f64| {
            if max <= min {
                return want;
            }
            let base = pos - current;
            let lo = self.counts(min - base);
            let hi = self.counts(max - base);
            want.clamp(lo.min(hi), hi.max(lo))
        };
        (
            hold(
                x,
                i.axis_x_position,
                i.x_offset_current,
                i.axis_x_min_limit,
                i.axis_x_max_limit,
            ),
            hold(
                y,
                i.axis_y_position,
                i.y_offset_current,
                i.axis_y_min_limit,
                i.axis_y_max_limit,
            ),
        )
    }

    /// Whether a float, ohmic or breakaway sensor is on.
    pub fn sensor(&self) -> bool {
        self.i.float_switch || self.i.ohmic_probe || self.i.breakaway
    }

    /// Whether the cut needs Arc OK.
    pub fn arc_ok_required(&self) -> bool {
        let ignored = self.i.ignore_arc_ok_0
            || self.i.ignore_arc_ok_1
            || (self.i.mesh_enable && self.i.mesh_arc_ok);
        self.i.torch_enable && !ignored
    }
}

/// Flags of the job in progress.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Job {
    /// A cut (or spot) was asked for and not yet started.
    pub start_pending: bool,
    /// A probe test was asked for and not yet started.
    pub probe_test_pending: bool,
    /// A scribe was asked for and not yet started.
    pub scribe_pending: bool,
    /// A torch pulse was asked for and not yet started.
    pub pulse_pending: bool,
    /// The cycle running is a probe test.
    pub probe_test: bool,
    /// The cycle running is a spot.
    pub spotting: bool,
    /// The cut was started without a program running.
    pub manual: bool,
    /// The restart after a pause continues a cut recovery.
    pub recovering: bool,
    /// Waiting at the top for resume, stop or a paused action.
    pub waiting: bool,
    /// Where a torch pulse or ohmic test returns to.
    pub back_to: State,
    /// The probe that triggered was the ohmic probe.
    pub ohmic_hit: bool,
    /// Where the last cut ended (X, Y), for skipping the IHS.
    pub last_end: Option<(f64, f64)>,
    /// Arc starts tried in this pierce.
    pub arc_starts: i32,
    /// Seconds since a spot reached its threshold voltage.
    pub spot_timer: f64,
    /// The program was seen paused since the stop (so running again
    /// means resumed).
    pub paused_seen: bool,
}

/// Input levels of the previous call, for edges.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Last {
    cutting_start: bool,
    spotting_start: bool,
    scribe_start: bool,
    torch_pulse_start: bool,
    probe_test: bool,
}

/// The `plasmac` controller.
#[derive(Debug, Clone, Default)]
pub struct Plasmac {
    /// The state.
    pub state: State,
    /// The stop type.
    pub stop_type: StopType,
    /// The outputs as last set.
    pub o: Outputs,
    /// Arc voltage, Arc OK and ohmic sense.
    pub senses: Senses,
    /// The Z offset.
    pub z: Mover,
    /// The X offset.
    pub x: Mover,
    /// The Y offset.
    pub y: Mover,
    /// Z counts at the probed top of the stock.
    pub zero: i32,
    /// Seconds in the current step of the current state.
    pub timer: f64,
    /// The job's flags.
    pub job: Job,
    /// The height controller.
    pub thc: Thc,
    /// Job statistics.
    pub stats: Stats,
    last: Last,
    fault: Option<Fault>,
}

impl Plasmac {
    /// One call of a `period_ns` thread: returns the fault this call
    /// raised, if any (the caller prints it).
    pub fn step(&mut self, i: &Inputs, period_ns: i64) -> Option<Fault> {
        let dt = period_ns.max(0) as f64 * 1e-9;
        let c = Ctx {
            i,
            dt,
            scale: moves::offset_scale(i.resolution, i.units_per_mm),
            base_z: i.axis_z_position - i.z_offset_current,
        };
        self.senses.update(i, dt);
        self.latch(i);
        self.o.program_run = false;
        if !i.machine_is_on || i.external_estop {
            self.shutdown();
        } else {
            self.acknowledge(i);
            self.run_state(&c);
        }
        self.z.step();
        self.x.step();
        self.y.step();
        self.outputs(&c);
        self.stats.update(&c, &mut self.o, self.state);
        self.fault.take()
    }

    /// Latches the requests that start cycles from their rising edges.
    fn latch(&mut self, i: &Inputs) {
        let l = self.last;
        if (i.cutting_start && !l.cutting_start) || (i.spotting_start && !l.spotting_start) {
            self.job.start_pending = true;
        }
        if !i.cutting_start && !i.spotting_start {
            self.job.start_pending = false;
        }
        self.job.scribe_pending = i.scribe_start && (self.job.scribe_pending || !l.scribe_start);
        self.job.pulse_pending =
            i.torch_pulse_start && (self.job.pulse_pending || !l.torch_pulse_start);
        self.job.probe_test_pending =
            i.probe_test && (self.job.probe_test_pending || !l.probe_test);
        self.last = Last {
            cutting_start: i.cutting_start,
            spotting_start: i.spotting_start,
            scribe_start: i.scribe_start,
            torch_pulse_start: i.torch_pulse_start,
            probe_test: i.probe_test,
        };
    }

    /// Drops the program requests halui has carried out.
    fn acknowledge(&mut self, i: &Inputs) {
        if i.program_is_paused {
            self.o.program_pause = false;
        }
        if i.program_is_idle {
            self.o.program_stop = false;
        }
        if i.program_is_running && !i.program_is_paused {
            self.o.program_resume = false;
        }
        if !i.cutting_start {
            self.o.cutting_stop = false;
        }
    }

    /// Machine off or external E-stop: everything off, offsets dropped,
    /// back to idle.
    fn shutdown(&mut self) {
        self.o.torch_on = false;
        self.o.feed_hold = false;
        self.o.scribe_arm = false;
        self.o.scribe_on = false;
        self.o.program_pause = false;
        self.o.program_resume = false;
        self.o.program_stop = false;
        self.o.cutting_stop = false;
        self.o.paused_motion = false;
        self.o.consumable_changing = false;
        self.o.cut_recovering = false;
        for m in [&mut self.z, &mut self.x, &mut self.y] {
            *m = Mover::default();
        }
        self.thc.reset();
        let keep = self.job.last_end;
        self.job = Job {
            last_end: keep,
            ..Job::default()
        };
        self.stop_type = StopType::None;
        self.enter(State::Idle);
    }

    fn run_state(&mut self, c: &Ctx<'_>) {
        if self.in_cycle() && self.program_left(c) {
            return;
        }
        match self.state {
            State::Idle => self.idle(c),
            State::ProbeHeight => self.probe_height(c),
            State::ProbeDown => self.probe_down(c),
            State::ProbeUp => self.probe_up(c),
            State::ZeroHeight => self.zero_height(c),
            State::PierceHeight => self.pierce_height(c),
            State::TorchOn => self.torch_on(c),
            State::ArcOk => self.arc_ok(c),
            State::PierceDelay => self.pierce_delay(c),
            State::PuddleJump => self.puddle_jump(c),
            State::CutHeight => self.cut_height(c),
            State::CutMode01 | State::CutMode2 => self.cut_mode(c),
            State::PauseAtEnd => self.pause_at_end(c),
            State::SafeHeight => self.safe_height(c),
            State::MaxHeight => self.max_height(c),
            State::EndCut => self.end_cut(c),
            State::EndJob => self.end_job(c),
            State::TorchPulse => self.torch_pulse(c),
            State::PausedMotion => self.paused_motion(c),
            State::OhmicTest => self.ohmic_test(c),
            State::ProbeTest => self.probe_test(c),
            State::Scribing => self.scribing(c),
            State::ConsumableChangeOn => self.consumable_change_on(c),
            State::ConsumableChangeOff => self.consumable_change_off(c),
            State::CutRecoveryOn => self.cut_recovery_on(c),
            State::CutRecoveryOff => self.cut_recovery_off(c),
        }
        self.timer += c.dt;
    }

    /// States of a cycle that a program pause or stop interrupts.
    fn in_cycle(&self) -> bool {
        self.state.is_probing()
            || self.state.is_cutting()
            || matches!(self.state, State::PierceHeight | State::ProbeTest)
    }

    /// Goes to `s` with its timer at zero.
    pub(super) fn enter(&mut self, s: State) {
        self.state = s;
        self.timer = 0.0;
    }

    /// Raises `f`: torch off, the program paused or stopped as `f` asks
    /// (a manual cut is stopped through `cutting-stop`), Z to the top.
    pub(super) fn raise(&mut self, c: &Ctx<'_>, f: Fault) {
        self.fault = Some(f);
        self.o.torch_on = false;
        self.thc.reset();
        let st = f.stop_type();
        if self.job.manual {
            self.o.cutting_stop = true;
        } else if st == StopType::Stop {
            self.o.program_stop = true;
        } else {
            self.o.program_pause = true;
        }
        self.stop_type = st;
        self.go_top(c);
    }

    /// Torch off, Z to the top, then wait there (see `max_height`).
    pub(super) fn go_top(&mut self, c: &Ctx<'_>) {
        self.o.torch_on = false;
        self.o.ohmic_enable = false;
        self.z.go(c.top(), c.speed(c.i.setup_feed_rate));
        self.job.waiting = false;
        self.job.paused_seen = false;
        self.enter(State::MaxHeight);
    }

    /// Starts a Z move to `height` above the probed zero, kept under the
    /// top.
    pub(super) fn z_to_height(&mut self, c: &Ctx<'_>, height: f64) {
        let target = (self.zero.saturating_add(c.counts(height))).min(c.top());
        self.z.go(target, c.speed(c.i.setup_feed_rate));
    }

    /// Whether the Z move is done.
    pub(super) fn z_arrived(&self, c: &Ctx<'_>) -> bool {
        self.z.arrived(c.i.z_offset_current, c.scale)
    }

    /// The outputs every state shares.
    fn outputs(&mut self, c: &Ctx<'_>) {
        let i = c.i;
        let o = &mut self.o;
        o.state_out = self.state.number();
        // The THC's indicators belong to the cut: every other state shows
        // it idle, however the cut was left (its end, a pause, a fault,
        // a stop).
        if !matches!(self.state, State::CutMode01 | State::CutMode2) {
            o.thc_active = false;
            o.led_up = false;
            o.led_down = false;
            o.cornerlock_is_locked = false;
            o.voidlock_is_locked = false;
        }
        o.stop_type_out = self.stop_type as i32;
        o.arc_voltage_out = self.senses.volts;
        o.arc_ok_out = self.senses.arc_ok && o.torch_on;
        o.ohmic_sense_out = self.senses.ohmic_sense;
        o.sensor_active = c.sensor();
        o.offset_scale = c.scale;
        o.z_offset_counts = self.z.counts;
        o.x_offset_counts = self.x.counts;
        o.y_offset_counts = self.y.counts;
        o.z_offset_enable = self.state != State::Idle || self.z.counts != 0;
        o.xy_offset_enable = self.x.counts != 0
            || self.y.counts != 0
            || matches!(
                self.state,
                State::ConsumableChangeOn | State::CutRecoveryOn | State::CutRecoveryOff
            );
        let z_rel = (f64::from(self.z.counts) - f64::from(self.zero)) * c.scale;
        o.z_relative = z_rel;
        o.z_height = if self.state == State::Idle {
            0.0
        } else {
            z_rel
        };
        let ovr = if i.feed_override > 0.0 {
            i.feed_override
        } else {
            1.0
        };
        o.requested_feed_rate = i.feed_upm * ovr;
        o.current_feed_rate = i.current_velocity * 60.0;
        if self.state != State::PausedMotion {
            o.adaptive_feed = if i.feed_reduction > 0.0 && i.feed_reduction < 100.0 {
                i.feed_reduction / 100.0
            } else {
                1.0
            };
        }
        o.thc_enabled = i.thc_enable && !i.thc_disable && !i.mesh_enable;
        o.jog_inhibit = !i.override_jog
            && (c.sensor()
                || !matches!(self.state, State::Idle | State::MaxHeight)
                || (self.state == State::MaxHeight && !self.job.waiting));
    }
}
