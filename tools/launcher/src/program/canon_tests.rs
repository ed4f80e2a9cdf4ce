//! Tests of task's canon: units, offsets and rotation on moves, arcs,
//! spindle and output commands, M66, skipped lines, faults.

use super::*;

fn p(x: f64, y: f64, z: f64) -> Pose {
    Pose {
        x,
        y,
        z,
        ..Pose::ZERO
    }
}

fn line_end(op: Option<&Op>) -> [f64; 9] {
    match op {
        Some(Op::Motion(Command::Line { end, .. })) => end.0,
        other => panic!("not a line: {other:?}"),
    }
}

#[test]
fn moves_take_units_offsets_rotation_and_tool_length() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.use_length_units(Units::Inches);
    c.set_g5x_offset(1, &p(1.0, 0.0, -1.0));
    c.use_tool_length_offset(&p(0.0, 0.0, 0.5));
    c.set_xy_rotation(90.0);
    c.straight_traverse(7, &p(1.0, 0.0, 0.0));
    let end = line_end(c.ops.back());
    // X1 rotated by 90 degrees is Y1; plus G54 X1 Z-1 and tool Z0.5.
    let want = [25.4, 25.4, -12.7];
    for (got, want) in end.iter().zip(want) {
        assert!((got - want).abs() < 1e-9, "{end:?}");
    }
    // The position reads back in program units and coordinates.
    let back = c.position();
    assert!((back.x - 1.0).abs() < 1e-9 && back.y.abs() < 1e-9 && back.z.abs() < 1e-9);
}

#[test]
fn inch_moves_on_an_inch_machine_end_on_the_numbers_given() {
    // LinuxCNC's ccomp-early-exit test, run on the 2.9 peer, reads
    // stat.position (0.1, 0.2, 0.3) exactly after G0 X0.1 Y0.2 Z0.3 on an
    // inch machine: program units go to millimetres and then to machine
    // units, two roundings. One factor (25.4 * (1 / 25.4), a bit under 1)
    // gave 0.09999999999999999, 0.19999999999999998, 0.29999999999999993.
    let mut c = TaskCanon::new(1.0 / 25.4, 0b111);
    c.use_length_units(Units::Inches);
    c.straight_traverse(1, &p(0.1, 0.2, 0.3));
    let end = line_end(c.ops.back());
    assert_eq!(end[..3], [0.1, 0.2, 0.3]);
    // X0.9 goes through the same two steps as LinuxCNC's, to the same bits.
    c.straight_traverse(2, &p(0.9, 0.2, 0.3));
    let end = line_end(c.ops.back());
    assert_eq!(end[..3], [0.9 * 25.4 * (1.0 / 25.4), 0.2, 0.3]);
    // Millimetre programs on the inch machine: 2.54, 5.08 and 7.62 mm
    // come out as 0.1, 0.2 and 0.3 inch.
    c.use_length_units(Units::Mm);
    c.straight_traverse(3, &p(2.54, 5.08, 7.62));
    let end = line_end(c.ops.back());
    assert_eq!(end[..3], [0.1, 0.2, 0.3]);
}

#[test]
fn an_xz_arc_turns_about_y_and_feeds_in_units_per_second() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.set_feed_rate(600.0);
    c.select_plane(Plane::Xz);
    c.arc_feed(
        3,
        &Arc {
            first_end: 1.0,
            second_end: 2.0,
            first_axis: 0.0,
            second_axis: 1.0,
            rotation: -1,
            axis_end_point: 5.0,
            rest: Pose::ZERO,
        },
    );
    match c.ops.back() {
        Some(Op::Motion(Command::Circle {
            end,
            center,
            normal,
            turns,
            vel,
            id,
            ..
        })) => {
            assert_eq!(&end.0[..3], &[2.0, 5.0, 1.0]);
            assert_eq!(*center, [1.0, 5.0, 0.0]);
            assert_eq!(*normal, [0.0, 1.0, 0.0]);
            assert_eq!((*turns, *vel, *id), (-1, 10.0, 3));
        }
        other => panic!("not an arc: {other:?}"),
    }
}

/// The spindle commands queued, with their lines (constant surface speed
/// switched off, sent with every start, left out).
fn spindle_commands(c: &TaskCanon) -> Vec<(Command, i32)> {
    c.ops
        .iter()
        .filter_map(|op| match op {
            Op::AfterMoves {
                command: Command::SpindleCss { factor, .. },
                ..
            } if *factor == 0.0 => None,
            Op::AfterMoves { command, line } => Some((*command, *line)),
            _ => None,
        })
        .collect()
}

#[test]
fn spindle_words_become_motion_commands_in_program_order() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.line = 4;
    // S alone while stopped changes nothing in motion.
    c.set_spindle_speed(0, 1200.0);
    assert!(c.ops.is_empty());
    c.start_spindle_counterclockwise(0);
    c.line = 5;
    c.set_spindle_speed(0, 800.0);
    c.line = 6;
    c.stop_spindle_turning(0);
    c.start_spindle_clockwise(1);
    let on = |spindle, speed| Command::SpindleOn {
        spindle,
        speed,
        wait: true,
    };
    assert_eq!(
        spindle_commands(&c),
        [
            (on(0, -1200.0), 4),
            (on(0, -800.0), 5),
            (Command::SpindleOff { spindle: 0 }, 6),
            (on(1, 0.0), 6),
        ]
    );
    c.set_spindle_speed(9, 100.0);
    assert_eq!(c.fault.as_deref(), Some("spindle 9"));
}

#[test]
fn outputs_go_with_the_next_move_or_after_the_moves_before() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.line = 3;
    c.set_motion_output_bit(1);
    c.set_aux_output_value(2, 4.5);
    assert_eq!(
        c.ops.iter().cloned().collect::<Vec<_>>(),
        [
            Op::Motion(Command::SetDout {
                index: 1,
                on: true,
                now: false
            }),
            Op::AfterMoves {
                command: Command::SetAout {
                    index: 2,
                    value: 4.5,
                    now: true
                },
                line: 3
            },
        ]
    );
}

#[test]
fn m66_waits_on_inputs_motion_has_and_reads_them() {
    let mut c = TaskCanon::new(1.0, 0b111);
    let io = motion::channel::IoState {
        din: vec![false, true],
        dout: vec![false, false],
        ain: vec![1.5],
        aout: vec![0.0],
    };
    c.refresh([0.0; 9], vec![ToolEntry::EMPTY], 0, io, (false, [0.0; 9]));
    assert_eq!(c.wait_input(2, InputKind::Digital, 1, 1.0), Err(()));
    assert_eq!(c.wait_input(1, InputKind::Analog, 0, 0.0), Err(()));
    assert_eq!(c.wait_input(1, InputKind::Digital, 3, 2.0), Ok(()));
    assert_eq!(
        c.ops.back(),
        Some(&Op::WaitInput {
            index: 1,
            digital: true,
            mode: 3,
            timeout: 2.0
        })
    );
    assert!(c.digital_input(1, false) && !c.digital_input(0, true));
    assert!(c.digital_input(7, true), "no such input: the default");
    assert_eq!(c.analog_input(0, 0.0), 1.5);
}

#[test]
fn skipped_lines_keep_their_settings_and_move_nothing() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.set_motion_control_mode(MotionMode::ExactStop, 0.0);
    let from = c.ops.len();
    c.straight_feed(2, &p(1.0, 0.0, 0.0));
    c.set_motion_control_mode(MotionMode::Continuous, 0.1);
    c.start_spindle_clockwise(0);
    c.flood_on();
    c.dwell(1.0);
    c.disable_feed_override();
    c.program_end();
    c.drop_actions_from(from);
    let kept: Vec<Op> = c.ops.iter().skip(from).cloned().collect();
    assert_eq!(
        kept,
        [
            Op::Motion(Command::SetTermCond {
                cond: TermCond::Blend,
                tolerance: 0.1
            }),
            Op::Motion(Command::FeedScaleEnable { on: false }),
            Op::End,
        ]
    );
    assert_eq!(c.ops.len(), from + 3, "the ops before are kept");
}

#[test]
fn calls_the_machine_cannot_do_are_a_fault() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.nurbs_feed(1, &[], 3);
    c.straight_feed(2, &p(0.0, 0.0, -1.0));
    assert_eq!(c.fault.as_deref(), Some("NURBS moves (G5.2)"));
}

#[test]
fn a_probe_queues_a_probing_move_and_its_check() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.set_feed_rate(60.0);
    c.straight_probe(4, &p(0.0, 0.0, -2.0), 0);
    match c.ops.front() {
        Some(Op::Motion(Command::Probe {
            end,
            vel,
            probe,
            id,
        })) => {
            assert_eq!(end.0[2], -2.0);
            assert_eq!((*vel, *probe, *id), (1.0, ProbeType::G38_2, 4));
        }
        other => panic!("not a probe: {other:?}"),
    }
    assert!(matches!(c.ops.get(1), Some(Op::ProbeCheck { line: 4, .. })));
    // G38.3 ends without an error: no check.
    c.straight_probe(5, &p(0.0, 0.0, -3.0), 1);
    assert_eq!(c.ops.len(), 3);
    // The result motion reports, in program coordinates.
    c.set_g5x_offset(1, &p(1.0, 0.0, 0.0));
    c.refresh(
        [0.0; 9],
        vec![ToolEntry::EMPTY],
        0,
        motion::channel::IoState::default(),
        (true, [3.0, 0.0, -1.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
    );
    assert!(c.probe_tripped());
    let at = c.probe_position();
    assert!((at.x - 2.0).abs() < 1e-12 && (at.z + 1.5).abs() < 1e-12);
    assert!(c.fault.is_none());
}

#[test]
fn a_synchronised_feed_goes_to_motion_between_spindle_syncs() {
    // An inch program on a millimetre machine: K0.1 is 2.54 mm per turn.
    let mut c = TaskCanon::new(1.0, 0b111);
    c.use_length_units(Units::Inches);
    c.set_feed_rate(0.0);
    c.set_spindle_speed(0, 300.0);
    c.start_spindle_clockwise(0);
    c.set_feed_mode(0, 1);
    c.set_feed_rate(0.01);
    c.ops.clear();
    c.start_speed_feed_synch(0, 0.1, false);
    c.straight_feed(7, &p(0.0, 0.0, -1.0));
    c.stop_speed_feed_synch();
    c.straight_feed(8, &p(0.0, 0.0, -2.0));
    assert!(c.fault.is_none(), "{:?}", c.fault);
    let ops: Vec<_> = c.ops.iter().collect();
    assert!(
        matches!(ops[0], Op::Motion(Command::SpindleSync { spindle: 0, per_rev, velocity_mode: false })
            if (per_rev - 2.54).abs() < 1e-12),
        "{ops:?}"
    );
    // No feed per revolution inside the synchronised move; its speed is
    // the pitch at the programmed spindle speed (motion follows the
    // spindle instead).
    match ops[1] {
        Op::Motion(Command::Line {
            end,
            vel,
            kind: LineKind::Feed,
            id: 7,
            ..
        }) => {
            assert!((end.0[2] + 25.4).abs() < 1e-9);
            assert!((vel - 2.54 * 5.0).abs() < 1e-9, "{vel}");
        }
        other => panic!("not the synchronised line: {other:?}"),
    }
    assert_eq!(
        ops[2],
        &Op::Motion(Command::SpindleSync {
            spindle: 0,
            per_rev: 0.0,
            velocity_mode: false
        })
    );
    // The G95 feed comes back for the next feed move.
    assert!(
        matches!(ops[3], Op::Motion(Command::SetFeedPerRev { spindle: 0, per_rev })
            if (per_rev - 0.254).abs() < 1e-12),
        "{ops:?}"
    );
    assert!(matches!(ops[4], Op::Motion(Command::Line { id: 8, .. })));
    // A spindle motion does not have is refused.
    c.start_speed_feed_synch(9, 1.0, false);
    assert_eq!(c.fault.as_deref(), Some("spindle 9"));
}

#[test]
fn a_rigid_tap_goes_to_motion_and_the_queue_ends_where_it_was() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.set_g5x_offset(1, &p(10.0, 0.0, 0.0));
    c.set_spindle_speed(0, 600.0);
    c.start_spindle_clockwise(0);
    c.straight_traverse(1, &p(1.0, 2.0, 3.0));
    c.ops.clear();
    // Without the synchronisation the interpreter always sends first.
    c.rigid_tap(2, (1.0, 2.0, -4.0), 1.5);
    assert_eq!(
        c.fault.as_deref(),
        Some("rigid tapping (G33.1) without spindle synchronisation")
    );
    let mut c = TaskCanon::new(1.0, 0b111);
    c.set_g5x_offset(1, &p(10.0, 0.0, 0.0));
    c.set_spindle_speed(0, 600.0);
    c.start_spindle_clockwise(0);
    c.straight_traverse(1, &p(1.0, 2.0, 3.0));
    c.ops.clear();
    c.start_speed_feed_synch(0, 1.25, false);
    c.rigid_tap(2, (1.0, 2.0, -4.0), 1.5);
    c.stop_speed_feed_synch();
    assert!(c.fault.is_none(), "{:?}", c.fault);
    match &c.ops[1] {
        Op::Motion(Command::RigidTap {
            end,
            vel,
            scale,
            id: 2,
        }) => {
            assert_eq!((end.0[0], end.0[1], end.0[2]), (11.0, 2.0, -4.0));
            assert_eq!((*vel, *scale), (12.5, 1.5));
        }
        other => panic!("not a rigid tap: {other:?}"),
    }
    // The next move starts from the tap's start.
    c.straight_feed(3, &p(1.0, 3.0, 3.0));
    match c.ops.back() {
        Some(Op::Motion(Command::Line { end, .. })) => assert_eq!(end.0[..3], [11.0, 3.0, 3.0]),
        other => panic!("{other:?}"),
    }
}

#[test]
fn constant_surface_speed_goes_to_motion_before_the_start() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.set_g5x_offset(1, &p(-2.0, 0.0, 0.0));
    c.line = 3;
    // G20 G96 D1500 S300 M3: 300 ft/min is 91440 mm/min.
    c.use_length_units(Units::Inches);
    c.set_spindle_mode(0, 1500.0);
    c.set_spindle_speed(0, 300.0);
    c.start_spindle_clockwise(0);
    let got = spindle_commands(&c);
    match got.as_slice() {
        [(
            Command::SpindleCss {
                spindle: 0,
                factor,
                x_offset,
            },
            3,
        ), (
            Command::SpindleOn {
                spindle: 0,
                speed,
                wait: true,
            },
            3,
        )] => {
            assert!((factor - 91440.0 / std::f64::consts::TAU).abs() < 1e-6);
            assert_eq!((*x_offset, *speed), (-2.0, 1500.0));
        }
        other => panic!("{other:?}"),
    }
    // G97 S800: off, then the speed.
    c.ops.clear();
    c.set_spindle_mode(0, 0.0);
    c.set_spindle_speed(0, 800.0);
    assert!(matches!(
        c.ops.front(),
        Some(Op::AfterMoves {
            command: Command::SpindleCss { factor, .. },
            ..
        }) if *factor == 0.0
    ));
    assert!(matches!(
        c.ops.get(1),
        Some(Op::AfterMoves {
            command: Command::SpindleOn { speed, .. },
            ..
        }) if *speed == 800.0
    ));
}

#[test]
fn feed_per_revolution_goes_to_motion_before_the_feed_moves() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.use_length_units(Units::Inches);
    c.set_feed_mode(0, 1);
    c.set_feed_rate(0.01);
    c.straight_traverse(1, &p(1.0, 0.0, 0.0));
    c.straight_feed(2, &p(2.0, 0.0, 0.0));
    c.straight_feed(3, &p(3.0, 0.0, 0.0));
    c.set_feed_mode(0, 0);
    c.set_feed_rate(10.0);
    c.straight_feed(4, &p(4.0, 0.0, 0.0));
    let per_rev: Vec<f64> = c
        .ops
        .iter()
        .filter_map(|op| match op {
            Op::Motion(Command::SetFeedPerRev {
                spindle: 0,
                per_rev,
            }) => Some(*per_rev),
            _ => None,
        })
        .collect();
    // Once before the first feed move (not the rapid); G94 ends it as
    // LinuxCNC's canon does, by ending the spindle synchronisation.
    assert_eq!(per_rev.len(), 1, "{:?}", c.ops);
    assert!((per_rev[0] - 0.254).abs() < 1e-12);
    assert!(matches!(
        c.ops.get(4),
        Some(Op::Motion(Command::SpindleSync { per_rev, .. })) if *per_rev == 0.0
    ));
    assert!(matches!(
        c.ops.get(1),
        Some(Op::Motion(Command::SetFeedPerRev { .. }))
    ));
    // After an abort motion's planner has forgotten it: sent again.
    c.planner_reset();
    c.ops.clear();
    c.set_feed_mode(0, 1);
    c.straight_feed(5, &p(5.0, 0.0, 0.0));
    assert!(matches!(
        c.ops.front(),
        Some(Op::Motion(Command::SetFeedPerRev { .. }))
    ));
}

#[test]
fn m6_traverses_to_the_tool_change_position_before_the_load() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.rates = AxisRates {
        vel: [4.0; 9],
        acc: [1000.0; 9],
    };
    c.straight_traverse(3, &p(5.0, 6.0, 7.0));
    c.ops.clear();
    // Without a change position the load comes alone.
    c.change_tool(0);
    assert!(matches!(c.ops.pop_front(), Some(Op::Io(IoRequest::Load))));
    assert!(c.ops.is_empty());
    // X Y Z given: a traverse there (machine coordinates, offsets not
    // applied), the other axes where they were, then the load.
    c.tool_change_position = Some([
        Some(0.5),
        Some(-1.0),
        Some(2.0),
        None,
        None,
        None,
        None,
        None,
        None,
    ]);
    c.set_g5x_offset(1, &p(100.0, 100.0, 100.0));
    c.line = 9;
    c.change_tool(0);
    match c.ops.pop_front() {
        Some(Op::Motion(Command::Line {
            end,
            vel,
            ini_maxvel,
            acc: _,
            kind,
            id,
        })) => {
            assert_eq!(&end.0[..3], &[0.5, -1.0, 2.0]);
            assert_eq!((kind, id), (LineKind::Traverse, 9));
            // From (5, 6, 7): Y's 7 units at 4 u/s set the time.
            assert_eq!(vel, ini_maxvel);
            assert!((vel - 94.25f64.sqrt() / 1.75).abs() < 1e-9, "{vel}");
        }
        other => panic!("not a traverse: {other:?}"),
    }
    assert!(matches!(c.ops.pop_front(), Some(Op::Io(IoRequest::Load))));
}

#[test]
fn a_move_that_goes_nowhere_is_not_sent() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.set_feed_rate(600.0);
    c.straight_traverse(1, &p(0.0, 0.0, 0.0));
    c.straight_feed(2, &p(0.0, 0.0, 0.0));
    assert!(c.ops.is_empty(), "{:?}", c.ops);
    c.straight_feed(3, &p(1.0, 0.0, 0.0));
    assert_eq!(line_end(c.ops.back())[0], 1.0);
    c.straight_traverse(4, &p(1.0, 0.0, 0.0));
    assert_eq!(c.ops.len(), 1, "{:?}", c.ops);
}

/// What LinuxCNC's canon sends for each move: the path speed and
/// acceleration the axes' limits allow along it (`ini_maxvel`, `acc`), a
/// rapid at that speed, a feed at its feed rate up to it; no move of no
/// length.
#[test]
fn moves_carry_the_path_limits_of_their_axes_and_empty_moves_are_dropped() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.rates = AxisRates {
        vel: [4.0, 2.0, 4.0, 4.0, 4.0, 4.0, 4.0, 4.0, 4.0],
        acc: [1000.0; 9],
    };
    let rates = |op: Option<Op>| match op {
        Some(Op::Motion(Command::Line {
            vel,
            ini_maxvel,
            acc,
            ..
        })) => (vel, ini_maxvel, acc),
        other => panic!("not a line: {other:?}"),
    };
    c.straight_traverse(1, &p(3.0, 4.0, 0.0));
    // Y's 4 units at 2 u/s take 2 s for a path 5 long.
    assert_eq!(rates(c.ops.pop_front()), (2.5, 2.5, 1250.0));
    c.set_feed_rate(60.0);
    c.straight_feed(2, &p(3.0, 0.0, 0.0));
    assert_eq!(rates(c.ops.pop_front()), (1.0, 2.0, 1000.0));
    c.set_feed_rate(6000.0);
    c.straight_feed(3, &p(6.0, 0.0, 0.0));
    assert_eq!(rates(c.ops.pop_front()), (4.0, 4.0, 1000.0));
    c.straight_traverse(4, &p(6.0, 0.0, 0.0));
    c.straight_feed(5, &p(6.0, 0.0, 0.0));
    assert!(c.ops.is_empty(), "{:?}", c.ops);
}

/// G43 and G49 give motion the tool offset (machine units) once the
/// moves before have ended, as LinuxCNC's task sends SET_OFFSET.
#[test]
fn the_tool_length_offset_goes_to_motion_after_the_moves() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.use_length_units(Units::Inches);
    c.use_tool_length_offset(&p(0.0, 0.0, 0.5));
    match c.ops.pop_back() {
        Some(Op::AfterMoves {
            command: Command::SetToolOffset { offset },
            ..
        }) => assert_eq!(offset.0, [0.0, 0.0, 12.7, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        other => panic!("not a tool offset: {other:?}"),
    }
}

#[test]
fn units_per_minute_ends_the_spindle_synchronisation() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.set_spindle_speed(0, 600.0);
    c.start_speed_feed_synch(0, 0.1, false);
    c.set_feed_mode(0, 0);
    assert!(
        matches!(
            c.ops.back(),
            Some(Op::Motion(Command::SpindleSync {
                per_rev,
                velocity_mode: false,
                ..
            })) if *per_rev == 0.0
        ),
        "{:?}",
        c.ops
    );
    assert!(c.synched.is_none());
}

#[test]
fn a_skipped_rigid_tap_is_dropped_with_the_other_moves() {
    let mut c = TaskCanon::new(1.0, 0b111);
    c.set_spindle_speed(0, 600.0);
    c.start_speed_feed_synch(0, 0.1, false);
    let from = c.ops.len();
    c.rigid_tap(4, (0.0, 0.0, -1.0), 1.0);
    assert!(matches!(
        c.ops.back(),
        Some(Op::Motion(Command::RigidTap { .. }))
    ));
    c.drop_actions_from(from);
    assert_eq!(c.ops.len(), from, "{:?}", c.ops);
}
