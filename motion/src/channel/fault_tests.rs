//! The fault block of the status snapshot: the last fault outlives later
//! messages that are not faults, and the block appended to format 4
//! leaves the words before it as they were.

use super::*;
use crate::command::Command;
use crate::kins::trivkins::Trivkins;
use crate::kins::KinematicsType;
use crate::test_support::{configure_test_joints, Sim};
use crate::{Event, Fault, MotionConfig, MotionCore};

/// One trivkins joint whose motor is stuck at 0 while it jogs: a
/// following error disables motion.
fn tripped() -> Sim {
    let kins = std::sync::Arc::new(Trivkins::new("X", KinematicsType::Identity).unwrap());
    let mut m = MotionCore::new(
        MotionConfig {
            num_joints: 1,
            ..MotionConfig::default()
        },
        kins,
    );
    configure_test_joints(&mut m);
    let mut s = Sim::new(m);
    s.enable();
    s.stuck[0] = Some(0.0);
    s.cmd(Command::JogCont { joint: 0, vel: 5.0 }).unwrap();
    for _ in 0..1000 {
        if !s.m.is_enabled() {
            return s;
        }
        s.cycle();
    }
    panic!("the stuck motor did not trip a following error");
}

fn snapshot(s: &Sim) -> [u64; STATUS_WORDS] {
    let mut w = [0u64; STATUS_WORDS];
    fill_status(&s.m, LastCommand::default(), 0, &mut w);
    w
}

#[test]
fn the_last_fault_outlives_a_later_harmless_message() {
    let s = tripped();
    let st = decode_status(&snapshot(&s)).unwrap();
    let fault = st.last_fault.unwrap();
    assert_eq!(fault.event, Event::JointFollowingError { joint: 0 });
    assert_eq!((st.faults_reported, fault.number), (1, 1));
    let trip = fault.following.unwrap();
    assert!(trip.error > trip.limit && trip.limit > 0.0, "{trip:?}");
    // A message that is no fault (as homing's abort after a disable)
    // replaces the last message, not the last fault.
    s.m.events().push(Event::JogStopped { immediate: true });
    let st = decode_status(&snapshot(&s)).unwrap();
    assert_eq!(st.last_event, Some(Event::JogStopped { immediate: true }));
    assert_eq!(st.events_reported, 2);
    assert_eq!(st.last_fault, Some(fault));
    let text = st.to_string();
    assert!(
        text.contains("last fault: joint 0 following error (error ")
            && text.contains("(message 1 of 2; faults reported: 1)"),
        "{text}"
    );
}

#[test]
fn the_fault_block_is_appended_to_format_4() {
    // Format 4's snapshot ended where the fault block starts: a reader
    // built before it reads the same words at the same places.
    assert_eq!(FAULT_START, IO_START + 3 + 2 * crate::sizes::MAX_IO);
    assert_eq!(EOFFSET_START, FAULT_START + crate::FAULT_WORDS);
    let s = tripped();
    let w = snapshot(&s);
    // A controller from before the fault block publishes fewer words; the
    // reader's copy has zeros there: no fault, everything else the same.
    let mut old = w;
    old[FAULT_START..EOFFSET_START].fill(0);
    let (new, old) = (decode_status(&w).unwrap(), decode_status(&old).unwrap());
    assert_eq!((old.faults_reported, old.last_fault), (0, None));
    assert!(new.last_fault.is_some());
    assert_eq!(
        MotionStatus {
            faults_reported: 0,
            last_fault: None,
            ..new
        },
        old
    );
}

#[test]
fn a_fault_block_with_a_word_that_is_no_fault_reads_as_none() {
    let s = tripped();
    let mut w = snapshot(&s);
    w[FAULT_START + 1] = u64::MAX;
    let st = decode_status(&w).unwrap();
    assert_eq!((st.faults_reported, st.last_fault), (1, None));
    assert_eq!(Fault::from_words(&[0; crate::FAULT_WORDS]), None);
}
