//! Tests of `pid`: the algorithm step by step against values worked out
//! from the formulas of components.md §3.5, closed loops on simulated
//! plants, and the HAL module (naming, module parameters, derivative pins).

use super::*;

/// Thread period of the step-by-step tests: 1 ms.
const P: i64 = 1_000_000;
/// `T = P * 1e-9` for [`P`].
const T: f64 = 0.001;
/// `R = 1.0 / T` for [`P`].
const R: f64 = 1000.0;

/// The `command-deriv` and `feedback-deriv` pins: their own storage, and
/// the signal each reads instead while connected.
#[derive(Default)]
struct DerivPins {
    cmd_own: f64,
    fb_own: f64,
    cmd_signal: Option<f64>,
    fb_signal: Option<f64>,
}

impl DerivPins {
    fn access(&mut self, estimates: Option<(f64, f64)>) -> (f64, f64) {
        if let Some((c, f)) = estimates {
            self.cmd_own = c;
            self.fb_own = f;
        }
        (
            self.cmd_signal.unwrap_or(self.cmd_own),
            self.fb_signal.unwrap_or(self.fb_own),
        )
    }
}

/// One loop with its pins.
#[derive(Default)]
struct Loop {
    pid: Pid,
    io: PidIo,
    d: DerivPins,
}

impl Loop {
    /// An enabled loop with only `Pgain` = 1, error against the current
    /// command unless `previous_target`.
    fn enabled(previous_target: bool) -> Loop {
        let mut l = Loop::default();
        l.io.enable = true;
        l.io.error_previous_target = previous_target;
        l
    }

    fn step(&mut self) {
        let d = &mut self.d;
        self.pid.step(&mut self.io, P, |e| d.access(e));
    }

    fn step_with(&mut self, command: f64, feedback: f64) {
        self.io.command = command;
        self.io.feedback = feedback;
        self.step();
    }
}

#[test]
fn test_period_gives_exact_t_and_r() {
    assert_eq!(P as f64 * 1e-9, T);
    assert_eq!(1.0 / T, R);
}

#[test]
fn pins_start_at_linuxcnc_defaults() {
    let io = PidIo::default();
    assert_eq!(io.pgain, 1.0);
    assert!(io.error_previous_target);
    assert_eq!((io.tune_effort, io.tune_cycles, io.tune_type), (0.5, 50, 0));
    assert!(!io.enable && !io.tune_mode && !io.tune_start);
    assert_eq!(Pid::new().tstate, TuneState::Pid);
}

#[test]
fn disabled_loop_outputs_zero_but_tracks_derivatives() {
    let mut l = Loop::default();
    l.step();
    assert_eq!((l.io.error, l.io.output), (0.0, 0.0));

    // Error uses the previous command (0), so only the feedback counts.
    l.step_with(2.0, 0.5);
    assert_eq!(l.io.error, 0.0 - 0.5);
    assert_eq!(l.io.output, 0.0);
    assert_eq!(l.pid.error_i, 0.0);
    assert_eq!((l.d.cmd_own, l.d.fb_own), (2.0 * R, 0.5 * R));
    assert_eq!(l.pid.error_d, 2000.0 - 500.0);
    assert_eq!(l.pid.command_d, 2000.0);
    assert_eq!(l.pid.command_dd, 2000.0 * R);
    assert_eq!(l.pid.command_ddd, 2.0e6 * R);

    // Same inputs again: the estimates return to 0 and the higher
    // derivatives see the drop.
    l.step_with(2.0, 0.5);
    assert_eq!(l.io.error, 2.0 - 0.5);
    assert_eq!((l.pid.error_d, l.pid.command_d), (0.0, 0.0));
    assert_eq!(l.pid.command_dd, (0.0 - 2000.0) * R);
    assert_eq!(l.pid.command_ddd, (-2.0e6 - 2.0e6) * R);
    assert_eq!(l.io.output, 0.0);
    assert!(!l.io.saturated);
}

#[test]
fn proportional_term_bias_and_previous_target() {
    let mut l = Loop::enabled(true);
    l.io.pgain = 3.0;
    l.io.bias = 0.25;
    l.step_with(1.0, 0.0);
    // First call: previous command 0, so e = 0 and only bias remains.
    assert_eq!((l.io.error, l.io.output), (0.0, 0.25));
    l.step_with(1.0, 0.0);
    assert_eq!((l.io.error, l.io.output), (1.0, 0.25 + 3.0 * 1.0));

    let mut l = Loop::enabled(false);
    l.io.pgain = 3.0;
    l.io.bias = 0.25;
    l.step_with(1.0, 0.0);
    assert_eq!((l.io.error, l.io.output), (1.0, 3.25));
    l.step_with(1.0, 0.75);
    assert_eq!((l.io.error, l.io.output), (0.25, 0.25 + 3.0 * 0.25));
}

#[test]
fn deadband_is_subtracted_and_maxerror_applies_first() {
    let mut l = Loop::enabled(false);
    l.io.deadband = 0.25;
    for (cmd, want) in [
        (0.75, 0.5),
        (-0.75, -0.5),
        (0.25, 0.0),
        (-0.25, 0.0),
        (0.125, 0.0),
        (0.0, 0.0),
    ] {
        l.step_with(cmd, 0.0);
        // `error` shows the raw error; the output uses the reduced one.
        assert_eq!(l.io.error, cmd);
        assert_eq!(l.io.output, want, "command {cmd}");
    }
    l.io.maxerror = 0.5;
    l.step_with(2.0, 0.0);
    assert_eq!((l.io.error, l.io.output), (2.0, 0.5 - 0.25));
    l.step_with(-2.0, 0.0);
    assert_eq!((l.io.error, l.io.output), (-2.0, -0.5 + 0.25));
    l.step_with(0.375, 0.0);
    assert_eq!(l.io.output, 0.375 - 0.25);
}

#[test]
fn integrator_accumulates_is_limited_and_resets_when_disabled() {
    let mut l = Loop::enabled(false);
    l.io.pgain = 0.0;
    l.io.igain = 10.0;
    l.step_with(2.0, 0.0);
    let ei1 = 0.0 + 2.0 * T;
    assert_eq!((l.pid.error_i, l.io.output), (ei1, 10.0 * ei1));
    l.step_with(2.0, 0.0);
    let ei2 = ei1 + 2.0 * T;
    assert_eq!((l.pid.error_i, l.io.output), (ei2, 10.0 * ei2));
    l.io.maxerror_i = 0.005;
    l.step_with(2.0, 0.0);
    assert_eq!((l.pid.error_i, l.io.output), (0.005, 10.0 * 0.005));
    l.step_with(-20.0, 0.0);
    assert_eq!(l.pid.error_i, -0.005);
    l.io.enable = false;
    l.step_with(2.0, 0.0);
    assert_eq!((l.pid.error_i, l.io.output), (0.0, 0.0));
    l.io.enable = true;
    l.step_with(2.0, 0.0);
    assert_eq!(l.pid.error_i, ei1);
}

#[test]
fn saturation_limits_output_freezes_integrator_and_counts() {
    let mut l = Loop::enabled(false);
    l.io.pgain = 10.0;
    l.io.igain = 1.0;
    l.io.maxoutput = 1.0;
    l.step_with(2.0, 0.0);
    let ei = 0.0 + 2.0 * T;
    assert_eq!(l.io.output, 1.0);
    assert_eq!(l.pid.limit_state, 1.0);
    assert_eq!(l.pid.error_i, ei);
    assert!(l.io.saturated);
    assert_eq!((l.io.saturated_s, l.io.saturated_count), (0.0 + T, 1));

    // Saturated in the error's direction: the integrator holds.
    l.step_with(2.0, 0.0);
    assert_eq!(l.pid.error_i, ei);
    assert_eq!((l.io.saturated_s, l.io.saturated_count), (T + T, 2));

    // The error reverses: it integrates, and saturates the other way.
    l.step_with(-2.0, 0.0);
    assert_eq!(l.pid.error_i, ei + -2.0 * T);
    assert_eq!((l.io.output, l.pid.limit_state), (-1.0, -1.0));
    assert_eq!((l.io.saturated_s, l.io.saturated_count), (T + T + T, 3));

    // Back inside the limit: everything about saturation clears.
    l.step_with(0.05, 0.0);
    let ei = ei + -2.0 * T + 0.05 * T;
    assert_eq!(l.pid.error_i, ei);
    assert_eq!(l.io.output, 0.0 + 10.0 * 0.05 + 1.0 * ei);
    assert_eq!(l.pid.limit_state, 0.0);
    assert!(!l.io.saturated);
    assert_eq!((l.io.saturated_s, l.io.saturated_count), (0.0, 0));

    // Saturated, then disabled: output 0 and saturation cleared.
    l.step_with(5.0, 0.0);
    assert!(l.io.saturated);
    l.io.enable = false;
    l.step();
    assert_eq!(
        (l.io.output, l.pid.limit_state, l.pid.error_i),
        (0.0, 0.0, 0.0)
    );
    assert!(!l.io.saturated);
    assert_eq!((l.io.saturated_s, l.io.saturated_count), (0.0, 0));
}

#[test]
fn saturated_count_stops_at_s32_max() {
    let mut l = Loop::enabled(false);
    l.io.maxoutput = 0.5;
    l.io.saturated_count = i32::MAX - 1;
    l.step_with(1.0, 0.0);
    assert_eq!(l.io.saturated_count, i32::MAX);
    l.step_with(1.0, 0.0);
    assert_eq!(l.io.saturated_count, i32::MAX);
}

#[test]
fn derivative_and_feed_forward_terms_sum_in_order() {
    let mut l = Loop::enabled(false);
    l.io.pgain = 2.0;
    l.io.igain = 3.0;
    l.io.dgain = 0.5;
    l.io.bias = 0.125;
    l.io.ff0 = 1.5;
    l.io.ff1 = 0.25;
    l.io.ff2 = 0.001;
    l.io.ff3 = 1e-6;

    // Call 1: command 0.001, feedback 0.0005.
    l.step_with(0.001, 0.0005);
    let e1 = 0.001 - 0.0005;
    let ei1 = 0.0 + e1 * T;
    let (cd1, fd1) = ((0.001 - 0.0) * R, (0.0005 - 0.0) * R);
    let ed1 = cd1 - fd1;
    let cdd1 = (cd1 - 0.0) * R;
    let cddd1 = (cdd1 - 0.0) * R;
    assert_eq!(l.pid.error_i, ei1);
    assert_eq!(
        (
            l.pid.error_d,
            l.pid.command_d,
            l.pid.command_dd,
            l.pid.command_ddd
        ),
        (ed1, cd1, cdd1, cddd1)
    );
    let out1 = 0.125 + 2.0 * e1 + 3.0 * ei1 + 0.5 * ed1;
    let out1 = out1 + (0.001 * 1.5 + cd1 * 0.25 + cdd1 * 0.001 + cddd1 * 1e-6);
    assert_eq!(l.io.output, out1);

    // Call 2: command 0.003, feedback 0.001.
    l.step_with(0.003, 0.001);
    let e2 = 0.003 - 0.001;
    let ei2 = ei1 + e2 * T;
    let (cd2, fd2) = ((0.003 - 0.001) * R, (0.001 - 0.0005) * R);
    let ed2 = cd2 - fd2;
    let cdd2 = (cd2 - cd1) * R;
    let cddd2 = (cdd2 - cdd1) * R;
    assert_eq!(
        (
            l.pid.error_d,
            l.pid.command_d,
            l.pid.command_dd,
            l.pid.command_ddd
        ),
        (ed2, cd2, cdd2, cddd2)
    );
    let out2 = 0.125 + 2.0 * e2 + 3.0 * ei2 + 0.5 * ed2;
    let out2 = out2 + (0.003 * 1.5 + cd2 * 0.25 + cdd2 * 0.001 + cddd2 * 1e-6);
    assert_eq!(l.io.output, out2);
}

#[test]
fn derivative_limits_clamp_each_term() {
    let mut l = Loop::enabled(false);
    l.io.pgain = 0.0;
    l.io.maxerror_d = 50.0;
    l.io.maxcmd_d = 10.0;
    l.io.maxcmd_dd = 500.0;
    l.io.maxcmd_ddd = 2.0e4;
    l.step_with(1.0, 0.0);
    assert_eq!(l.d.cmd_own, 1000.0);
    assert_eq!(l.pid.error_d, 50.0);
    assert_eq!(l.pid.command_d, 10.0);
    assert_eq!(l.pid.command_dd, 500.0);
    assert_eq!(l.pid.command_ddd, 2.0e4);
    l.step_with(0.0, 0.0);
    assert_eq!(l.pid.error_d, -50.0);
    assert_eq!(l.pid.command_d, -10.0);
    assert_eq!(l.pid.command_dd, -500.0);
    assert_eq!(l.pid.command_ddd, -2.0e4);
    // The command stops: commandD returns to 0, the rise of 10 * R in
    // commandD is limited again.
    l.step_with(0.0, 0.0);
    assert_eq!((l.pid.command_d, (0.0 - -10.0) * R), (0.0, 1.0e4));
    assert_eq!(l.pid.command_dd, 500.0);
    assert_eq!(l.pid.command_ddd, 2.0e4);
    // Steady: commandDD = (0 - 0) * R, commandDDD = (0 - 500) * R, limited.
    l.step_with(0.0, 0.0);
    assert_eq!(
        (l.pid.error_d, l.pid.command_dd, l.pid.command_ddd),
        (0.0, 0.0, -2.0e4)
    );
    l.step_with(0.0, 0.0);
    assert_eq!(l.pid.command_ddd, 0.0);
}

#[test]
fn connected_derivative_pins_replace_the_estimates() {
    let mut l = Loop::enabled(false);
    l.io.pgain = 0.0;
    l.io.dgain = 2.0;
    l.io.ff1 = 1.0;
    l.d.cmd_signal = Some(4.0);
    l.d.fb_signal = Some(1.0);
    l.step_with(0.5, 0.25);
    // The estimates still go to the pins' own storage...
    assert_eq!((l.d.cmd_own, l.d.fb_own), (0.5 * R, 0.25 * R));
    // ...but the connected pins read their signals.
    assert_eq!((l.pid.error_d, l.pid.command_d), (3.0, 4.0));
    assert_eq!(
        l.io.output,
        0.0 + 0.0 * 0.25 + 0.0 + 2.0 * 3.0 + (0.0 + 4.0 * 1.0)
    );
    // Only the feedback derivative connected.
    l.d.cmd_signal = None;
    l.step_with(0.75, 0.25);
    assert_eq!(l.d.cmd_own, (0.75 - 0.5) * R);
    assert_eq!(l.pid.error_d, 250.0 - 1.0);
    assert_eq!(l.pid.command_d, 250.0);
}

#[test]
fn index_enable_falling_edge_uses_current_command_and_keeps_estimates() {
    let mut l = Loop::enabled(true);
    l.io.index_enable = true;
    l.step_with(1.0, 0.0);
    l.step_with(1.0, 0.25);
    assert_eq!(l.io.error, 1.0 - 0.25);
    assert_eq!((l.d.cmd_own, l.d.fb_own), (0.0, 0.25 * R));

    // The encoder found the index: index-enable falls and the feedback
    // jumps; the command moves in the same call.
    l.io.index_enable = false;
    l.step_with(1.25, -3.0);
    assert_eq!(l.io.error, 1.25 - -3.0);
    assert_eq!(l.io.output, 1.0 * (1.25 - -3.0));
    assert_eq!((l.d.cmd_own, l.d.fb_own), (0.0, 0.25 * R));
    assert_eq!(l.pid.error_d, 0.0 - 0.25 * R);
    assert_eq!(
        (l.pid.prev_cmd, l.pid.prev_fb, l.pid.prev_ie),
        (1.25, -3.0, false)
    );

    // The next call is normal again, from the new previous values.
    l.step_with(1.25, -3.0);
    assert_eq!(l.io.error, 1.25 - -3.0);
    assert_eq!((l.d.cmd_own, l.d.fb_own), (0.0, 0.0));

    // A rising edge changes nothing.
    l.io.index_enable = true;
    l.step_with(1.5, -3.0);
    assert_eq!(l.io.error, 1.25 - -3.0);
    assert_eq!(l.d.cmd_own, (1.5 - 1.25) * R);
}

#[test]
fn tune_mode_resets_the_loop_and_waits() {
    let mut l = Loop::enabled(true);
    l.io.igain = 1.0;
    l.step_with(1.0, 0.0);
    l.step_with(2.0, 0.0);
    assert!(l.pid.error_i != 0.0 && l.pid.command_ddd != 0.0);
    let ddd = l.pid.command_ddd;
    let own = (l.d.cmd_own, l.d.fb_own);
    l.io.tune_mode = true;
    l.step_with(3.0, 0.5);
    assert_eq!(l.io.error, 2.0 - 0.5);
    assert_eq!(l.io.output, 0.0);
    assert_eq!(l.pid.tstate, TuneState::Idle);
    assert_eq!(
        (
            l.pid.error_i,
            l.pid.error_d,
            l.pid.prev_cmd,
            l.pid.limit_state
        ),
        (0.0, 0.0, 0.0, 0.0)
    );
    assert_eq!((l.pid.command_d, l.pid.command_dd), (0.0, 0.0));
    // Not reset by LinuxCNC either:
    assert_eq!(l.pid.command_ddd, ddd);
    assert_eq!((l.d.cmd_own, l.d.fb_own), own);
}

/// Runs the relay example of the auto-tune tests up to the end of tuning
/// and returns the loop and the `(Ku, Tu)` worked out by hand.
fn tune_by_hand(tune_type: u32) -> (Loop, f64, f64) {
    let mut l = Loop::enabled(true);
    l.io.tune_cycles = 2;
    l.io.tune_effort = -0.5; // its absolute value is used
    l.io.tune_type = tune_type;
    l.io.bias = 0.125;
    l.io.ff0 = 1.0;
    l.io.ff1 = 7.0;
    l.io.ff2 = 1.0;
    l.io.tune_mode = true;
    // PID state: the tune-mode call resets and goes idle.
    l.step_with(0.0, 0.0);
    assert_eq!((l.pid.tstate, l.io.output), (TuneState::Idle, 0.0));
    // Idle without tune-start: only the error is updated.
    l.step_with(0.0, 0.25);
    assert_eq!(
        (l.pid.tstate, l.io.error, l.io.output),
        (TuneState::Idle, -0.25, 0.0)
    );
    l.io.tune_start = true;
    l.step();
    assert_eq!(l.pid.tstate, TuneState::Start);
    assert_eq!(l.io.output, 0.0);
    l.pid.ultimate_gain = 9.0;
    l.step();
    assert_eq!(l.pid.tstate, TuneState::Pos);
    assert_eq!(l.io.output, 0.125 + 0.5);
    assert_eq!((l.pid.ultimate_gain, l.pid.cycle_count), (0.0, 0));
    assert!(l.io.tune_start);

    // e = 0.25: stays positive.
    l.step_with(0.0, -0.25);
    assert_eq!(
        (l.pid.cycle_period, l.pid.cycle_amplitude),
        (P as u32, 0.25)
    );
    assert_eq!(l.io.output, 0.625);
    // e = -0.5: the first half cycle ends (its peak now 0.5).
    l.step_with(0.0, 0.5);
    assert_eq!(l.pid.tstate, TuneState::Neg);
    assert_eq!(l.pid.cycle_count, 1);
    let avg = 0.0 + 0.5 / 2.0;
    let total = 0.0 + 2_000_000.0 * 0.000000001;
    assert_eq!((l.pid.avg_amplitude, l.pid.total_time), (avg, total));
    assert_eq!((l.pid.cycle_amplitude, l.pid.cycle_period), (0.0, 0));
    assert_eq!(l.io.output, 0.125 - 0.5);
    // e = -0.75, then e = 1.0 ends the second half cycle. Its peak
    // includes the sample that ended it (LinuxCNC's order).
    l.step_with(0.0, 0.75);
    assert_eq!((l.pid.cycle_amplitude, l.io.output), (0.75, -0.375));
    l.step_with(0.0, -1.0);
    let avg = avg + 1.0 / 2.0;
    let total = total + 2_000_000.0 * 0.000000001;
    assert_eq!(l.pid.cycle_count, 2);
    assert_eq!((l.pid.avg_amplitude, l.pid.total_time), (avg, total));
    let ku = (4.0 * 0.5) / (PI_TRUNCATED * avg);
    let tu = 2.0 * total / 2.0;
    assert_eq!((l.pid.ultimate_gain, l.pid.ultimate_period), (ku, tu));
    // Tuning done: output back to bias, tune-start cleared, idle.
    assert_eq!(l.io.output, 0.125);
    assert!(!l.io.tune_start);
    assert_eq!(l.pid.tstate, TuneState::Idle);
    assert_eq!((l.io.ff0, l.io.ff2), (0.0, 0.0));
    (l, ku, tu)
}

#[test]
fn autotune_ziegler_nichols_pid_gains() {
    let (l, ku, tu) = tune_by_hand(0);
    assert_eq!(l.io.pgain, 0.6 * ku);
    assert_eq!(l.io.igain, 1.2 * ku / tu);
    assert_eq!(l.io.dgain, (3.0 / 40.0) * ku * tu);
    assert_eq!(l.io.ff1, 0.0);
}

#[test]
fn autotune_ziegler_nichols_pi_ff1_gains() {
    let (mut l, ku, tu) = tune_by_hand(1);
    assert_eq!(l.io.pgain, 0.45 * ku);
    assert_eq!(l.io.igain, 0.54 * ku / tu);
    assert_eq!((l.io.dgain, l.io.ff1), (0.0, 1.0));
    // Leaving tune mode: one more abort call, then normal control.
    l.io.tune_mode = false;
    l.step_with(1.0, 0.0);
    assert_eq!(
        (l.pid.tstate, l.io.output, l.io.error),
        (TuneState::Pid, 0.125, 1.0)
    );
    l.step_with(1.0, 0.0);
    assert_eq!(l.pid.tstate, TuneState::Pid);
    assert_eq!(l.io.error, 0.0 - 0.0);
}

#[test]
fn autotune_aborts_when_disabled_or_tune_mode_drops() {
    let mut l = Loop::enabled(true);
    l.io.bias = -0.25;
    l.io.tune_mode = true;
    l.step();
    l.io.tune_start = true;
    l.step();
    l.step();
    assert_eq!(l.pid.tstate, TuneState::Pos);
    l.io.enable = false;
    l.step_with(0.0, 1.0);
    assert_eq!((l.io.output, l.io.error), (-0.25, -1.0));
    assert!(!l.io.tune_start);
    assert_eq!(l.pid.tstate, TuneState::Idle);
    // Disabled in tune mode: every call aborts again, output = bias.
    l.io.output = 3.0;
    l.io.tune_start = true;
    l.step();
    assert_eq!(
        (l.io.output, l.io.tune_start, l.pid.tstate),
        (-0.25, false, TuneState::Idle)
    );
    l.io.tune_mode = false;
    l.step();
    assert_eq!(l.pid.tstate, TuneState::Pid);
}

#[test]
fn autotune_with_zero_cycles_finishes_at_once() {
    let mut l = Loop::enabled(true);
    l.io.tune_cycles = 0;
    l.io.tune_mode = true;
    l.step();
    l.io.tune_start = true;
    l.step();
    l.step();
    l.step_with(0.0, -1.0);
    assert_eq!(l.pid.tstate, TuneState::Idle);
    assert_eq!(l.pid.ultimate_gain, f64::INFINITY);
    assert!(l.pid.ultimate_period.is_nan());
    assert_eq!(l.pid.cycle_period, P as u32);
}

#[test]
fn relay_period_counter_wraps_like_u32() {
    let mut pid = Pid::new();
    pid.tstate = TuneState::Pos;
    pid.cycle_period = u32::MAX;
    let mut io = PidIo {
        enable: true,
        tune_mode: true,
        ..PidIo::default()
    };
    pid.step(&mut io, 5, |_| unreachable!("no derivative while tuning"));
    assert_eq!(pid.cycle_period, 4);
}

#[test]
fn negative_limit_values_follow_the_c_comparisons() {
    // maxerror = -1: `e > -1` holds for e = 0.5, so e becomes -1.
    assert_eq!(limit(0.5, -1.0), -1.0);
    // ...and for e = -3 the second test `e < 1` gives 1.
    assert_eq!(limit(-3.0, -1.0), 1.0);
    assert_eq!(limit(3.0, 0.0), 3.0);
    assert!(limit(f64::NAN, 1.0).is_nan());
}

// ---- closed loops ------------------------------------------------------

/// Position loop on an ideal velocity actuator (x' = output): P control
/// settles exactly on a constant command and, with FF1 = 1, on a ramp.
#[test]
fn closed_loop_integrator_plant_settles_on_command() {
    let mut l = Loop::enabled(true);
    l.io.pgain = 50.0;
    l.io.command = 1.0;
    let mut x = 0.0;
    for _ in 0..2000 {
        l.io.feedback = x;
        l.step();
        x += l.io.output * T;
    }
    assert!((x - 1.0).abs() < 1e-9, "x = {x}");
    assert!(l.io.error.abs() < 1e-9);

    // A ramp of 0.5 units/s with velocity feed-forward: no lag remains.
    l.io.ff1 = 1.0;
    for k in 0..3000 {
        l.io.command = 1.0 + 0.5 * (k as f64 * T);
        l.io.feedback = x;
        l.step();
        x += l.io.output * T;
    }
    // `error` compares with the previous command, which x has reached.
    assert!(l.io.error.abs() < 1e-9, "error = {}", l.io.error);
}

/// Velocity loop on a first-order lag with a constant load: P alone
/// leaves an offset, the integrator removes it.
#[test]
fn closed_loop_lag_plant_needs_the_integrator() {
    fn run(igain: f64) -> f64 {
        let (tau, load) = (0.05, 0.3);
        let mut l = Loop::enabled(false);
        l.io.pgain = 2.0;
        l.io.igain = igain;
        l.io.command = 1.0;
        let mut y = 0.0;
        for _ in 0..10_000 {
            l.io.feedback = y;
            l.step();
            y += (l.io.output - load - y) * (T / tau);
        }
        y
    }
    let p_only = run(0.0);
    assert!((p_only - (2.0 - 0.3) / 3.0).abs() < 1e-9, "y = {p_only}");
    let pi = run(20.0);
    assert!((pi - 1.0).abs() < 1e-9, "y = {pi}");
}

/// Motor position plant: velocity lags the output, position integrates
/// it, and the feedback arrives `delay` calls late.
struct Motor {
    v: f64,
    x: f64,
    tau: f64,
    pipe: std::collections::VecDeque<f64>,
}

impl Motor {
    fn new(tau: f64, delay: usize) -> Motor {
        Motor {
            v: 0.0,
            x: 0.0,
            tau,
            pipe: std::iter::repeat_n(0.0, delay).collect(),
        }
    }

    fn feedback(&self) -> f64 {
        *self.pipe.front().unwrap()
    }

    fn advance(&mut self, u: f64) {
        self.v += (u - self.v) * (T / self.tau);
        self.x += self.v * T;
        self.pipe.pop_front();
        self.pipe.push_back(self.x);
    }
}

/// The relay test finds the plant's ultimate gain and period, and the
/// Ziegler-Nichols gains it sets then hold the motor on its command.
#[test]
fn closed_loop_autotune_then_control() {
    let mut m = Motor::new(0.05, 10);
    let mut l = Loop::enabled(true);
    l.io.tune_mode = true;
    l.io.tune_effort = 1.0;
    l.io.tune_cycles = 20;
    l.io.tune_start = true;
    let mut calls = 0;
    while l.io.tune_start || l.pid.tstate != TuneState::Idle {
        l.io.feedback = m.feedback();
        l.step();
        m.advance(l.io.output);
        calls += 1;
        assert!(calls < 100_000, "tuning never finished");
    }
    let (ku, tu) = (l.pid.ultimate_gain, l.pid.ultimate_period);
    // For e^{-0.01 s} / (s (0.05 s + 1)) the phase reaches -180 degrees
    // near 43 rad/s: Tu about 0.145 s, |G| about 1/100 there.
    assert!((0.1..0.2).contains(&tu), "Tu = {tu}");
    assert!((50.0..200.0).contains(&ku), "Ku = {ku}");
    assert_eq!(l.io.pgain, 0.6 * ku);

    // Normal control with the tuned gains.
    l.io.tune_mode = false;
    l.io.command = 0.5;
    for _ in 0..20_000 {
        l.io.feedback = m.feedback();
        l.step();
        m.advance(l.io.output);
    }
    assert_eq!(l.pid.tstate, TuneState::Pid);
    assert!((m.x - 0.5).abs() < 1e-6, "x = {}", m.x);
    assert!(m.v.abs() < 1e-6);
}

// ---- the HAL module ----------------------------------------------------

mod hal {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::{PinDir, Value};

    fn host() -> TestHost {
        TestHost::new("pid")
    }

    fn load(host: &Host, args: &[&str]) -> Result<()> {
        host.loadrt(&MODULE, args)
    }

    const ITEMS: &[&str] = &[
        "Dgain",
        "FF0",
        "FF1",
        "FF2",
        "FF3",
        "Igain",
        "Pgain",
        "bias",
        "command",
        "command-deriv",
        "deadband",
        "enable",
        "error",
        "error-previous-target",
        "feedback",
        "feedback-deriv",
        "index-enable",
        "maxcmdD",
        "maxcmdDD",
        "maxcmdDDD",
        "maxerror",
        "maxerrorD",
        "maxerrorI",
        "maxoutput",
        "output",
        "saturated",
        "saturated-count",
        "saturated-s",
        "tune-cycles",
        "tune-effort",
        "tune-mode",
        "tune-start",
        "tune-type",
    ];
    const DEBUG_ITEMS: &[&str] = &[
        "commandD",
        "commandDD",
        "commandDDD",
        "errorD",
        "errorI",
        "ultimate-gain",
        "ultimate-period",
    ];

    fn expected_pins(prefixes: &[&str], debug: bool) -> Vec<String> {
        let mut v: Vec<String> = prefixes
            .iter()
            .flat_map(|p| {
                let extra = if debug { DEBUG_ITEMS } else { &[] };
                ITEMS.iter().chain(extra).map(move |i| format!("{p}.{i}"))
            })
            .collect();
        v.sort();
        v
    }

    #[test]
    fn default_load_makes_three_loops_with_every_pin() {
        let h = host();
        load(&h, &[]).unwrap();
        assert_eq!(h.pins(), expected_pins(&["pid.0", "pid.1", "pid.2"], false));
        assert_eq!(
            h.functs(),
            [
                "pid.0.do-pid-calcs",
                "pid.1.do-pid-calcs",
                "pid.2.do-pid-calcs"
            ]
        );
        let inst = h.instance();
        let v = |n: &str| inst.pin_value(n).unwrap();
        assert_eq!(v("pid.1.Pgain"), Value::Float(1.0));
        assert_eq!(v("pid.1.error-previous-target"), Value::Bit(true));
        assert_eq!(v("pid.1.tune-effort"), Value::Float(0.5));
        assert_eq!(v("pid.1.tune-cycles"), Value::U32(50));
        assert_eq!(v("pid.1.tune-type"), Value::U32(0));
        assert_eq!(v("pid.1.saturated-count"), Value::S32(0));
        let pins = inst.pins().unwrap();
        let dir = |n: &str| pins.iter().find(|p| p.name == n).unwrap().dir;
        assert_eq!(dir("pid.0.tune-start"), PinDir::Io);
        assert_eq!(dir("pid.0.tune-effort"), PinDir::Io);
        assert_eq!(dir("pid.0.tune-mode"), PinDir::In);
        assert_eq!(dir("pid.0.command-deriv"), PinDir::In);
        assert_eq!(dir("pid.0.saturated-s"), PinDir::Out);
        assert!(inst
            .params()
            .unwrap()
            .iter()
            .all(|p| p.name.ends_with("tmax") || p.name.ends_with("tmax-increased")));
    }

    #[test]
    fn num_chan_names_and_debug() {
        let h = host();
        load(&h, &["num_chan=16", "debug=1"]).unwrap();
        let names: Vec<String> = (0..16).map(|i| format!("pid.{i}")).collect();
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        assert_eq!(h.pins(), expected_pins(&refs, true));

        let h = host();
        load(&h, &["names=x.pos,spindle,", "debug=0"]).unwrap();
        assert_eq!(h.pins(), expected_pins(&["spindle", "x.pos"], false));
        assert_eq!(h.functs(), ["spindle.do-pid-calcs", "x.pos.do-pid-calcs"]);

        // num_chan=0 with empty names is the default.
        let h = host();
        load(&h, &["num_chan=0", "names="]).unwrap();
        assert_eq!(h.functs().len(), 3);
    }

    #[test]
    fn bad_module_parameters_fail_and_leave_nothing() {
        let cases: &[(&[&str], &str)] = &[
            (&["num_chan=17"], "num_chan"),
            (&["num_chan=-1"], "num_chan"),
            (&["num_chan=2", "names=a"], "mutually exclusive"),
            (
                &["names=a,b,c,d,e,f,g,h,i,j,k,l,m,n,o,p,q"],
                "can only take 16",
            ),
            (&["num_chan=x"], "num_chan"),
            (&["bogus=1"], "bogus"),
            // As for encoder, a name after an empty one is refused rather
            // than silently dropped.
            (&["names=a,,b"], "empty channel name"),
            (&["names=,x"], "empty channel name"),
        ];
        for (args, why) in cases {
            let h = host();
            let err = load(&h, args).unwrap_err().to_string();
            assert!(err.contains(why), "{args:?}: {err}");
            assert!(h.pins().is_empty(), "{args:?}");
            assert!(h.loaded_components().is_empty());
        }
        // A duplicate name fails on the duplicate pin.
        let h = host();
        assert!(load(&h, &["names=a,a"]).is_err());
        assert!(h.pins().is_empty());
    }

    /// Runs the loaded functions in a 1 ms thread until `done` holds.
    fn run_until(h: &Host, mut done: impl FnMut() -> bool) {
        h.start().unwrap();
        let end = std::time::Instant::now() + std::time::Duration::from_secs(10);
        while !done() {
            assert!(std::time::Instant::now() < end, "condition never held");
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        h.stop();
    }

    #[test]
    fn derivative_pins_estimate_unless_connected() {
        let h = host();
        load(&h, &["num_chan=1", "debug=1"]).unwrap();
        h.create_thread("t", 1_000_000, true, None).unwrap();
        h.addf("pid.0.do-pid-calcs", "t", -1).unwrap();
        let inst = h.instance();
        let f = |v| Value::Float(v);
        let get = |n: &str| match inst.pin_value(n).unwrap() {
            Value::Float(x) => x,
            other => panic!("{other:?}"),
        };
        inst.set_pin("pid.0.enable", Value::Bit(true)).unwrap();
        inst.set_pin("pid.0.Pgain", f(0.0)).unwrap();
        inst.set_pin("pid.0.FF1", f(1.0)).unwrap();
        inst.set_pin("pid.0.Dgain", f(1.0)).unwrap();

        // Unconnected, constant command: the estimates settle to 0 and
        // the pins show them.
        inst.set_pin("pid.0.command", f(2.0)).unwrap();
        run_until(&h, || {
            get("pid.0.commandDDD") == 0.0 && get("pid.0.error") == 2.0
        });
        assert_eq!(get("pid.0.command-deriv"), 0.0);
        assert_eq!(get("pid.0.output"), 0.0);

        // Connected to signals: the signals' values are used.
        inst.newsig("cv", hal_core::HalType::Float).unwrap();
        inst.newsig("fv", hal_core::HalType::Float).unwrap();
        inst.link("pid.0.command-deriv", "cv").unwrap();
        inst.link("pid.0.feedback-deriv", "fv").unwrap();
        inst.set_signal("cv", f(7.0)).unwrap();
        inst.set_signal("fv", f(2.5)).unwrap();
        run_until(&h, || get("pid.0.commandD") == 7.0);
        assert_eq!(get("pid.0.errorD"), 7.0 - 2.5);
        assert_eq!(get("pid.0.output"), 4.5 + 7.0);
        assert_eq!(inst.signal_value("cv").unwrap(), f(7.0));

        // Unlinked again: the estimate takes over from the kept value.
        inst.unlink("pid.0.command-deriv").unwrap();
        inst.unlink("pid.0.feedback-deriv").unwrap();
        run_until(&h, || get("pid.0.commandD") == 0.0);
        assert_eq!(get("pid.0.command-deriv"), 0.0);
        assert_eq!(get("pid.0.output"), 0.0);
    }

    #[test]
    fn autotune_writes_gains_through_connected_pins() {
        let h = host();
        load(&h, &["num_chan=1"]).unwrap();
        h.create_thread("t", 1_000_000, true, None).unwrap();
        h.addf("pid.0.do-pid-calcs", "t", -1).unwrap();
        let inst = h.instance();
        inst.newsig("pg", hal_core::HalType::Float).unwrap();
        inst.link("pid.0.Pgain", "pg").unwrap();
        for (pin, v) in [
            ("pid.0.enable", Value::Bit(true)),
            ("pid.0.tune-mode", Value::Bit(true)),
            ("pid.0.tune-cycles", Value::U32(1)),
            ("pid.0.tune-effort", Value::Float(0.25)),
            ("pid.0.feedback", Value::Float(-1.0)),
        ] {
            inst.set_pin(pin, v).unwrap();
        }
        inst.set_pin("pid.0.tune-start", Value::Bit(true)).unwrap();
        // e = 1 from the start: the first half cycle never ends by itself.
        run_until(&h, || {
            inst.pin_value("pid.0.output").unwrap() == Value::Float(0.25)
        });
        inst.set_pin("pid.0.feedback", Value::Float(2.0)).unwrap();
        run_until(&h, || {
            inst.pin_value("pid.0.tune-start").unwrap() == Value::Bit(false)
        });
        // One half cycle whose peak, 2, is the sample that ended it.
        let ku = (4.0 * 0.25) / (PI_TRUNCATED * (0.0 + 2.0 / 1.0));
        assert_eq!(inst.signal_value("pg").unwrap(), Value::Float(0.6 * ku));
        assert_eq!(inst.pin_value("pid.0.output").unwrap(), Value::Float(0.0));
    }
}
