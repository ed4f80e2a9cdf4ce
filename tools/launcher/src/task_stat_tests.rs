//! Tests of the `stat` snapshot's LinuxCNC layouts.

use super::*;

#[test]
fn values_are_written_with_their_kind() {
    let mut out = String::new();
    push(&mut out, "a", &Value::Int(-3));
    push(&mut out, "b", &Value::Float(0.5));
    push(&mut out, "c", &Value::Text("x\ny".into()));
    push(&mut out, "d", &Value::Ints(vec![1, 2]));
    push(&mut out, "e", &Value::Floats(vec![1.0, -2.5]));
    push(&mut out, "f", &Value::Floats(vec![]));
    assert_eq!(out, "a=i:-3\nb=f:0.5\nc=s:x y\nd=I:1 2\ne=F:1 -2.5\nf=F:\n");
}

#[test]
fn output_requests_parse_and_refuse_bad_words() {
    let p = |w: &str| parse(&w.split(' ').collect::<Vec<_>>());
    assert_eq!(
        p("set-dout 3 on").unwrap().unwrap(),
        TaskRequest::SetDout { index: 3, on: true }
    );
    assert_eq!(
        p("set-aout 1 -2.5").unwrap().unwrap(),
        TaskRequest::SetAout {
            index: 1,
            value: -2.5
        }
    );
    assert_eq!(p("stat").unwrap().unwrap(), TaskRequest::Stat);
    assert!(p("mode auto").is_none());
    let e = p("set-dout 64 on").unwrap().unwrap_err().to_string();
    assert!(e.contains("0..63, not '64'"), "{e}");
    let e = p("set-dout 1 maybe").unwrap().unwrap_err().to_string();
    assert!(e.contains("on or off, not 'maybe'"), "{e}");
    let e = p("set-aout 1 inf").unwrap().unwrap_err().to_string();
    assert!(e.contains("not 'inf'"), "{e}");
}

#[test]
fn codes_go_where_linuxcnc_puts_them() {
    let codes = rs274ngc::ActiveCodes {
        g: vec![
            10, 170, 900, 901, 940, 210, 400, 490, 540, 640, 980, 970, 80,
        ],
        m: vec![3, 9, 8, 48],
        feed: 600.0,
        speed: 1000.0,
        tolerance: 0.05,
        naivecam_tolerance: 0.01,
    };
    let p = ProgramView {
        file: None,
        read_line: 7,
        codes,
        queued_mdi: 0,
        call_level: 0,
        rotation_xy: 0.0,
        interpreter_errcode: 0,
    };
    assert_eq!(
        linuxcnc_gcodes(&p),
        [7, 10, -1, 170, 400, 210, 900, 940, 540, 490, 980, 640, -1, 970, 901, 80, -1]
    );
    assert_eq!(linuxcnc_mcodes(&p), [7, -1, 3, -1, -1, 8, 48, -1, -1, -1]);
    assert_eq!(linuxcnc_settings(&p), [7.0, 600.0, 1000.0, 0.05, 0.01]);
    let mut p = p;
    p.codes.m = vec![5, 9, 9, 49];
    assert_eq!(linuxcnc_mcodes(&p), [7, -1, 5, -1, 9, -1, 49, -1, -1, -1]);
}

#[test]
fn limit_bits_follow_linuxcncs_mask() {
    let j = motion::channel::JointState {
        min_limit: -1.0,
        max_limit: 1.0,
        ..Default::default()
    };
    assert_eq!(limit_mask(&j), 0);
    let on_switch = motion::channel::JointState {
        neg_hard_limit: true,
        ..j
    };
    assert_eq!(limit_mask(&on_switch), 1);
    let both = motion::channel::JointState {
        neg_hard_limit: true,
        pos_hard_limit: true,
        ..j
    };
    assert_eq!(limit_mask(&both), 3);
    // Beyond the soft limits counts only once the joint is homed.
    let beyond = motion::channel::JointState { pos_cmd: -2.0, ..j };
    assert_eq!(limit_mask(&beyond), 0);
    let homed_low = motion::channel::JointState {
        homed: true,
        ..beyond
    };
    assert_eq!(limit_mask(&homed_low), 4);
    let homed_high = motion::channel::JointState {
        homed: true,
        pos_cmd: 2.0,
        ..j
    };
    assert_eq!(limit_mask(&homed_high), 8);
    assert!(above_soft_limit(&homed_high) && !below_soft_limit(&homed_high));
}

#[test]
fn names_are_unique_within_each_table() {
    let mut names: Vec<&str> = FIELDS.iter().map(|f| f.0).collect();
    names.extend(MOTION_FIELDS.iter().map(|f| f.0));
    let n = names.len();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), n, "a stat field is named twice");
}
