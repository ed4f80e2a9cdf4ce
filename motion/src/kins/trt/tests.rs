use super::*;
use crate::kins::math::norm;
use proptest::prelude::*;

fn kins(table: Table) -> TableKins {
    let letters = match table.tilt {
        Tilt::A => "xyzac",
        Tilt::B => "xyzbc",
    };
    TableKins::new(table, letters).unwrap()
}

fn fwd(k: &TableKins, j: &[f64]) -> Pose {
    let mut p = Pose::ZERO;
    k.forward(j, &mut p, &mut KinsFlags::default()).unwrap();
    p
}

fn inv(k: &TableKins, p: &Pose, n: usize) -> Vec<f64> {
    let mut j = vec![0.0; n];
    k.inverse(p, &mut j, &mut KinsFlags::default()).unwrap();
    j
}

#[test]
fn untilted_table_is_identity() {
    for tilt in [Tilt::A, Tilt::B] {
        let mut t = Table::new(tilt);
        t.rot_point = [10.0, 20.0, 30.0];
        t.z_offset = 5.0;
        let k = kins(t);
        let p = fwd(&k, &[1.0, 2.0, 3.0, 0.0, 0.0]);
        assert!(norm(sub([p.0[0], p.0[1], p.0[2]], [1.0, 2.0, 3.0])) < 1e-12);
    }
}

#[test]
fn the_rotary_turns_the_workpiece_the_linuxcnc_way() {
    // C = 90°, rotary axis through the origin: the table turns so that a
    // point the tool touches at machine X = 10 is, on the workpiece, at
    // Y = −10 by LinuxCNC's default directions and at +10 conventionally.
    let k = kins(Table::new(Tilt::A));
    let p = fwd(&k, &[10.0, 0.0, 0.0, 0.0, 90.0]);
    assert!(
        (p.0[0]).abs() < 1e-12 && (p.0[1] + 10.0).abs() < 1e-12,
        "{p:?}"
    );
    assert_eq!((p.0[3], p.0[5]), (0.0, 90.0));
    let k = kins(Table {
        conventional: true,
        ..Table::new(Tilt::A)
    });
    let p = fwd(&k, &[10.0, 0.0, 0.0, 0.0, 90.0]);
    assert!((p.0[1] - 10.0).abs() < 1e-12, "{p:?}");
}

#[test]
fn tilting_a_turns_y_into_z_and_b_turns_x_into_z() {
    let k = kins(Table::new(Tilt::A));
    let p = fwd(&k, &[0.0, 10.0, 0.0, 90.0, 0.0]);
    // Default directions: Z = −sin A · Y.
    assert!(
        p.0[1].abs() < 1e-12 && (p.0[2] + 10.0).abs() < 1e-12,
        "{p:?}"
    );
    let k = kins(Table::new(Tilt::B));
    let p = fwd(&k, &[10.0, 0.0, 0.0, 90.0, 0.0]);
    // Default directions: Z = sin B · X.
    assert!(
        p.0[0].abs() < 1e-12 && (p.0[2] - 10.0).abs() < 1e-12,
        "{p:?}"
    );
    assert_eq!(p.0[4], 90.0);
}

#[test]
fn offsets_move_the_tilt_axis() {
    // With the tilt axis 5 above the rotary axis' point, a tilt of 90°
    // about it moves the point on the rotary axis at the rot point.
    let mut t = Table::new(Tilt::A);
    t.z_offset = 3.0;
    t.tool_offset = 2.0;
    let k = kins(t);
    let p = fwd(&k, &[0.0, 0.0, 0.0, 90.0, 0.0]);
    // J − d = (0, 0, −5) turned by −90° about X is (0, −5, 0); plus d.
    assert!(
        (p.0[1] + 5.0).abs() < 1e-12 && (p.0[2] - 5.0).abs() < 1e-12,
        "{p:?}"
    );
}

#[test]
fn gantry_and_extra_letters_follow_coordinates() {
    let k = TableKins::new(Table::new(Tilt::B), "xyzbcyw").unwrap();
    let mut p = Pose::ZERO;
    p.0[0] = 1.0;
    p.0[1] = 2.0;
    p.0[8] = 7.0;
    let j = inv(&k, &p, 7);
    assert_eq!(j, [1.0, 2.0, 0.0, 0.0, 0.0, 2.0, 7.0]);
    assert_eq!(k.has_axis(8), Some(true));
    assert_eq!(k.has_axis(0), Some(true));
    assert_eq!(k.has_axis(3), Some(false));
    // The five letters are required.
    assert!(TableKins::new(Table::new(Tilt::B), "xyzc").is_err());
    assert!(TableKins::new(Table::new(Tilt::B), "xyzac").is_err());
}

#[test]
fn non_numbers_are_refused() {
    let k = kins(Table::new(Tilt::A));
    let mut p = Pose::ZERO;
    p.0[5] = f64::NAN;
    let mut j = [0.0; 5];
    assert_eq!(
        k.inverse(&p, &mut j, &mut KinsFlags::default()),
        Err(KinsError::NoSolution)
    );
    let mut back = Pose::ZERO;
    assert_eq!(
        k.forward(
            &[0.0, f64::INFINITY, 0.0, 0.0, 0.0],
            &mut back,
            &mut KinsFlags::default()
        ),
        Err(KinsError::NoSolution)
    );
}

fn table(tilt: Tilt) -> impl Strategy<Value = Table> {
    (
        prop::array::uniform3(-200.0f64..200.0),
        prop::array::uniform4(-100.0f64..100.0),
        any::<bool>(),
    )
        .prop_map(move |(rot_point, [x, y, z, tool], conventional)| Table {
            tilt,
            rot_point,
            x_offset: x,
            y_offset: y,
            z_offset: z,
            tool_offset: tool,
            conventional,
        })
}

fn check(t: Table, xyz: [f64; 3], tilt: f64, c: f64) -> std::result::Result<(), TestCaseError> {
    let k = kins(t);
    let mut p = Pose::ZERO;
    p.0[..3].copy_from_slice(&xyz);
    p.0[t.tilt.axis()] = tilt;
    p.0[5] = c;
    let j = inv(&k, &p, 5);
    let back = fwd(&k, &j);
    for a in 0..6 {
        prop_assert!((back.0[a] - p.0[a]).abs() < 1e-9, "{:?} vs {:?}", back, p);
    }
    let j2 = inv(&k, &back, 5);
    for i in 0..5 {
        prop_assert!((j2[i] - j[i]).abs() < 1e-9);
    }
    Ok(())
}

proptest! {
    #[test]
    fn round_trips_with_default_offsets(
        xyz in prop::array::uniform3(-500.0f64..500.0),
        tilt in -120.0f64..120.0, c in -720.0f64..720.0, b in any::<bool>(),
    ) {
        check(Table::new(if b { Tilt::A } else { Tilt::B }), xyz, tilt, c)?;
    }

    #[test]
    fn round_trips_with_random_offsets(
        ta in table(Tilt::A), tb in table(Tilt::B),
        xyz in prop::array::uniform3(-500.0f64..500.0),
        tilt in -120.0f64..120.0, c in -720.0f64..720.0,
    ) {
        check(ta, xyz, tilt, c)?;
        check(tb, xyz, tilt, c)?;
    }
}
