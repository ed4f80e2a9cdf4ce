use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
use std::sync::{Arc, Mutex};

use hal_core::{ComponentKind, Host, HostConfig};

use super::line::{e2, g6, line};
use super::Logger;
use crate::command::{Command, LineKind, TermCond};
use crate::kins::Pose;
use crate::MotionClient;

#[test]
fn numbers_are_written_as_c_writes_percent_6g() {
    let cases = [
        (1.66296, "1.66296"),
        (415.74, "415.74"),
        (4.0, "4"),
        (-0.5, "-0.5"),
        (0.0, "0"),
        (1e-7, "1e-07"),
        (0.0001, "0.0001"),
        (0.00001234, "1.234e-05"),
        (100000.0, "100000"),
        (1234567.0, "1.23457e+06"),
        (999999.5, "1e+06"),
        (2.0 / 3.0, "0.666667"),
    ];
    for (v, want) in cases {
        assert_eq!(g6(v), want, "{v}");
    }
}

#[test]
fn lines_in_linuxcnc_words() {
    let end = Pose([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
    assert_eq!(
        line(&Command::Line {
            end,
            vel: 1.66296,
            ini_maxvel: 1.66296,
            acc: 415.74,
            kind: LineKind::Feed,
            id: 2
        }),
        "SET_LINE x=1, y=2, z=3, a=4, b=5, c=6, u=7, v=8, w=9, id=2, motion_type=2, \
         vel=1.66296, ini_maxvel=1.66296, acc=415.74, turn=-1"
    );
    assert_eq!(line(&Command::Coord), "COORD");
    assert_eq!(line(&Command::Home { joint: -1 }), "JOINT_HOME joint=-1");
    assert_eq!(
        line(&Command::SetJointPositionLimits {
            joint: 0,
            min: -40.0,
            max: 40.0
        }),
        "SET_JOINT_POSITION_LIMITS joint=0, min=-40, max=40"
    );
    assert_eq!(
        line(&Command::SetTermCond {
            cond: TermCond::Blend,
            tolerance: 0.0
        }),
        "SET_TERM_COND termCond=2, tolerance=0"
    );
    assert_eq!(line(&Command::SpindleOff { spindle: 0 }), "SPINDLE_OFF");
    assert_eq!(line(&Command::FeedScale { scale: 1.0 }), "FEED_SCALE");
}

/// The start-up settings LinuxCNC 2.9's task sends before the joints, in
/// its logger's words (its SET_OFFSET has no comma after c).
#[test]
fn start_up_settings_in_linuxcnc_words() {
    assert_eq!(
        line(&Command::SetNumJoints { joints: 9 }),
        "SET_NUM_JOINTS 9"
    );
    assert_eq!(
        line(&Command::SetNumSpindles { spindles: 1 }),
        "SET_NUM_SPINDLES 1"
    );
    assert_eq!(
        line(&Command::SetVel {
            vel: 0.0,
            ini_maxvel: 1.2
        }),
        "SET_VEL vel=0, ini_maxvel=1.2"
    );
    let blends = Command::SetupArcBlends {
        enable: true,
        fallback: false,
        depth: 50,
        gap_cycles: 4,
        ramp_freq: 100.0,
    };
    assert_eq!(line(&blends), "SETUP_ARC_BLENDS");
    assert_eq!(
        line(&Command::SetSpindleParams {
            spindle: 0,
            max_pos: 1e99,
            min_pos: 0.0,
            max_neg: -1e99,
            min_neg: 0.0,
        }),
        "SET_SPINDLE_PARAMS, 1.00e+99, 0.00e+00, -1.00e+99, 0.00e+00"
    );
    assert_eq!(
        line(&Command::SetToolOffset {
            offset: Pose([0.0, 0.0, 1.5, 0.0, 0.0, 0.0, 0.0, 0.0, -0.25])
        }),
        "SET_OFFSET x=0, y=0, z=1.5, a=0, b=0, c=0 u=0, v=0, w=-0.25"
    );
    let arc = Command::Circle {
        end: Pose([1.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        center: [0.0, 0.0, 0.0],
        normal: [0.0, 0.0, 1.0],
        turns: -1,
        vel: 0.5,
        ini_maxvel: 2.0,
        acc: 40.0,
        id: 7,
    };
    assert_eq!(
        line(&arc),
        "SET_CIRCLE:\n    pos: x=1, y=0, z=0.5, a=0, b=0, c=0, u=0, v=0, w=0\n    \
         center: x=0, y=0, z=0\n    normal: x=0, y=0, z=1\n    \
         id=7, motion_type=3, vel=0.5, ini_maxvel=2, acc=40, turn=-1"
    );
    assert_eq!(e2(2.5e-3), "2.50e-03");
    assert_eq!(e2(-1234.5), "-1.23e+03");
}

/// LinuxCNC 2.9's logger writes the amplifier commands bare, one line a
/// joint, as its machine-on and e-stop sequences show.
#[test]
fn amplifier_lines_name_no_joint() {
    assert_eq!(
        line(&Command::EnableAmplifier { joint: 3 }),
        "ENABLE_AMPLIFIER"
    );
    assert_eq!(
        line(&Command::DisableAmplifier { joint: 0 }),
        "DISABLE_AMPLIFIER"
    );
}

#[test]
fn task_talks_to_it_as_to_motmod_and_every_command_is_logged() {
    let host = Host::create(HostConfig::for_tests("motion-logger")).unwrap();
    let inst = host.instance().clone();
    let comp = inst
        .new_component("motion-logger", ComponentKind::User)
        .unwrap();
    let mut logger = Logger::create(&inst, &comp).unwrap();
    comp.ready().unwrap();
    let lines = Arc::new(Mutex::new(Vec::<String>::new()));
    let stop = Arc::new(AtomicBool::new(false));
    let server = {
        let (lines, stop) = (lines.clone(), stop.clone());
        std::thread::spawn(move || {
            while !stop.load(Relaxed) {
                logger.serve(&mut |l| lines.lock().unwrap().push(l.to_string()));
                logger.tick(0.001);
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
        })
    };
    let mut client = MotionClient::open(&inst).unwrap();
    for j in 0..3 {
        client.send(Command::JointActivate { joint: j }).unwrap();
    }
    client.send(Command::Enable).unwrap();
    client.send(Command::Home { joint: -1 }).unwrap();
    client.send(Command::Coord).unwrap();
    client
        .send(Command::Line {
            end: Pose([0.1, 0.2, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
            vel: 1.0,
            ini_maxvel: 0.0,
            acc: 0.0,
            kind: LineKind::Traverse,
            id: 3,
        })
        .unwrap();
    // Constant surface speed, then the spindle: one line, LinuxCNC's.
    client
        .send(Command::SpindleCss {
            spindle: 0,
            factor: 100.0,
            x_offset: 0.5,
        })
        .unwrap();
    client
        .send(Command::SpindleOn {
            spindle: 0,
            speed: 500.0,
            wait: false,
        })
        .unwrap();
    // Refused as motion refuses it, and logged all the same.
    let refused = client.send(Command::Home { joint: 40 }).unwrap_err();
    assert!(
        refused.reason.to_string().contains("40"),
        "{}",
        refused.reason
    );
    let status = client.status().unwrap();
    assert!(
        status.enabled && status.coord_mode && status.all_homed,
        "{status:?}"
    );
    assert!(status.in_position, "{status:?}");
    stop.store(true, Relaxed);
    server.join().unwrap();
    let lines = lines.lock().unwrap().clone();
    assert_eq!(
        lines,
        [
            "JOINT_ACTIVATE joint=0",
            "JOINT_ACTIVATE joint=1",
            "JOINT_ACTIVATE joint=2",
            "ENABLE",
            "JOINT_HOME joint=-1",
            "COORD",
            "SET_LINE x=0.1, y=0.2, z=0.3, a=0, b=0, c=0, u=0, v=0, w=0, id=3, motion_type=1, \
             vel=1, ini_maxvel=0, acc=0, turn=-1",
            "SPINDLE_ON speed=500.000000, css_factor=100.000000, xoffset=0.500000",
            "JOINT_HOME joint=40",
        ]
    );
    drop(comp);
}
