//! Tests of the digital and analog outputs through the core: at once
//! (M64, M65, M68) and with the next queued move (M62, M63, M67).

use super::coord_tests::{line, xyz};
use crate::command::{Command, Reject};

#[test]
fn immediate_outputs_change_at_once_and_bad_numbers_are_refused() {
    let mut s = xyz();
    s.cmd(Command::SetDout {
        index: 3,
        on: true,
        now: true,
    })
    .unwrap();
    s.cmd(Command::SetAout {
        index: 1,
        value: 2.5,
        now: true,
    })
    .unwrap();
    assert!(s.m.io_outputs().dout[3]);
    assert_eq!(s.m.io_outputs().aout[1], 2.5);
    assert_eq!(
        s.cmd(Command::SetDout {
            index: 4,
            on: true,
            now: true
        }),
        Err(Reject::NoSuchOutput { index: 4, count: 4 })
    );
    assert!(s
        .cmd(Command::SetAout {
            index: 0,
            value: f64::INFINITY,
            now: true
        })
        .is_err());
}

#[test]
fn synchronised_outputs_change_when_the_next_move_starts() {
    let mut s = xyz();
    s.coord();
    s.cmd(line(2.0, 0.0, 5.0, 1)).unwrap();
    s.cmd(Command::SetDout {
        index: 0,
        on: true,
        now: false,
    })
    .unwrap();
    s.cmd(Command::SetAout {
        index: 2,
        value: -1.0,
        now: false,
    })
    .unwrap();
    s.cmd(line(2.0, 1.0, 5.0, 2)).unwrap();
    let mut changed_at = None;
    for n in 0..5000 {
        s.cycle();
        if s.m.io_outputs().dout[0] {
            changed_at = Some((n, s.j(0).pos_cmd, s.j(1).pos_cmd));
            break;
        }
    }
    let (_, x, y) = changed_at.expect("the output changed");
    // Not before the first move ended: X at 2, Y only just starting.
    assert!((x - 2.0).abs() < 1e-9 && y < 0.01, "{x} {y}");
    assert_eq!(s.m.io_outputs().aout[2], -1.0);
    // A set with no move after it waits; an abort forgets it.
    s.settle(5000);
    s.cmd(Command::SetDout {
        index: 1,
        on: true,
        now: false,
    })
    .unwrap();
    s.run(50);
    assert!(!s.m.io_outputs().dout[1]);
    s.cmd(Command::Abort).unwrap();
    s.run(5);
    s.cmd(line(3.0, 1.0, 5.0, 3)).unwrap();
    s.settle(5000);
    assert!(!s.m.io_outputs().dout[1], "forgotten by the abort");
}
