//! Tests of `plasmac`: a bench that closes the loop (motion follows the
//! offsets, the float switch trips on the stock, the arc voltage follows
//! the torch height), the full cut cycle, every error path, and a load
//! through the host.

mod actions;
mod cycle;
mod faults;
mod host;

use super::machine::Plasmac;
use super::pins::Inputs;
use super::state::{Fault, State};

/// Thread period of the bench (1 ms).
const PERIOD: i64 = 1_000_000;

/// The controller on a simulated table.
struct Bench {
    p: Plasmac,
    i: Inputs,
    /// X and Y without the offsets.
    base_x: f64,
    base_y: f64,
    /// Machine Z of the top of the stock.
    surface: f64,
    /// Torch travel before the float switch trips.
    travel: f64,
    /// Added to the arc voltage (a disturbance).
    volts_error: f64,
    /// The arc will not start or has gone out.
    arc_dead: bool,
    /// Every state entered, in order.
    states: Vec<State>,
    /// Every fault raised.
    faults: Vec<Fault>,
}

impl Bench {
    /// A metric table: Z at 0 between -100 and 10, stock top at -50.
    fn new() -> Bench {
        let i = Inputs {
            machine_is_on: true,
            homed: true,
            torch_enable: true,
            mode: 1,
            units_per_mm: 1.0,
            arc_voltage_scale: 1.0,
            axis_z_min_limit: -100.0,
            axis_z_max_limit: 10.0,
            probe_start_height: 60.0,
            setup_feed_rate: 6000.0,
            probe_feed_rate: 600.0,
            probe_final_speed: 10,
            float_switch_travel: 0.5,
            pierce_height: 3.8,
            cut_height: 1.5,
            pierce_delay: 0.01,
            cut_volts: 100.0,
            arc_fail_delay: 0.05,
            arc_max_starts: 3,
            restart_delay: 0.01,
            arc_lost_delay: 0.005,
            thc_enable: true,
            thc_delay: 0.01,
            thc_threshold: 1.0,
            pid_p_gain: 10.0,
            height_per_volt: 0.1,
            thc_feed_rate: 600.0,
            feed_upm: 1000.0,
            safe_height: 20.0,
            program_is_running: true,
            ..Inputs::default()
        };
        Bench {
            p: Plasmac::default(),
            i,
            base_x: 0.0,
            base_y: 0.0,
            surface: -50.0,
            travel: 0.5,
            volts_error: 0.0,
            arc_dead: false,
            states: vec![State::Idle],
            faults: Vec::new(),
        }
    }

    /// Torch Z now.
    fn z(&self) -> f64 {
        self.i.axis_z_position
    }

    /// One period: the table answers the last outputs, then the
    /// controller runs.
    fn tick(&mut self) {
        let scale = self.p.o.offset_scale;
        self.i.z_offset_current = f64::from(self.p.o.z_offset_counts) * scale;
        self.i.x_offset_current = f64::from(self.p.o.x_offset_counts) * scale;
        self.i.y_offset_current = f64::from(self.p.o.y_offset_counts) * scale;
        self.i.axis_z_position = self.i.z_offset_current;
        self.i.axis_x_position = self.base_x + self.i.x_offset_current;
        self.i.axis_y_position = self.base_y + self.i.y_offset_current;
        self.i.float_switch = self.z() <= self.surface - self.travel;
        let lit = self.p.o.torch_on && !self.arc_dead;
        self.i.arc_ok_in = lit;
        let height = self.z() - self.surface;
        self.i.arc_voltage_in = if lit {
            100.0 + (height - 1.5) * 10.0 + self.volts_error
        } else {
            0.0
        };
        let moving = !self.p.o.feed_hold && self.i.program_is_running && !self.i.program_is_paused;
        self.i.current_velocity = if moving { self.i.feed_upm / 60.0 } else { 0.0 };
        if let Some(f) = self.p.step(&self.i, PERIOD) {
            self.faults.push(f);
        }
        if self.states.last() != Some(&self.p.state) {
            self.states.push(self.p.state);
        }
    }

    /// Runs until `done` holds (panics after `max` periods).
    fn until(&mut self, max: usize, what: &str, done: impl Fn(&Bench) -> bool) {
        for _ in 0..max {
            self.tick();
            if done(self) {
                return;
            }
        }
        panic!(
            "{what}: not reached in {max} periods; state {:?}, states {:?}, faults {:?}",
            self.p.state, self.states, self.faults
        );
    }

    /// Runs until the state is `s`.
    fn until_state(&mut self, max: usize, s: State) {
        self.until(max, &format!("{s:?}"), |b| b.p.state == s);
    }

    /// Runs `n` periods.
    fn run(&mut self, n: usize) {
        for _ in 0..n {
            self.tick();
        }
    }

    /// Starts a cut and runs it to `CUT_MODE_01`.
    fn cut(&mut self) {
        self.i.cutting_start = true;
        self.until_state(20_000, State::CutMode01);
    }

    /// Whether `seq` appears in the states entered, in order.
    fn visited_in_order(&self, seq: &[State]) -> bool {
        let mut it = self.states.iter();
        seq.iter().all(|s| it.any(|v| v == s))
    }
}
