use super::*;
use crate::kins::math::{angle_diff, solve6};
use proptest::prelude::*;

fn same_pose(a: &[f64; 6], b: &[f64; 6], tol: f64) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() < tol)
        && (3..6).all(|i| angle_diff(rad(a[i]), rad(b[i])).abs() < rad(tol))
}

#[test]
fn level_platform_struts() {
    let h = Hexapod::default();
    let p = [0.0, 0.0, 20.0, 0.0, 0.0, 0.0];
    let (l, corr) = h.struts(&p).unwrap();
    assert_eq!(corr, [0.0; 6]);
    for i in 0..STRUTS {
        let d = sub(add(DEFAULT_PLATFORM[i], [0.0, 0.0, 20.0]), DEFAULT_BASE[i]);
        assert!((l[i] - norm(d)).abs() < 1e-12);
    }
    // Lifting the tool point lifts every strut end: same lengths.
    let lifted = Hexapod {
        tool_offset: 5.0,
        spindle_offset: -2.0,
        ..h
    };
    assert_eq!(lifted.struts(&p).unwrap().0, l);
}

#[test]
fn forward_converges_from_a_nearby_guess() {
    let h = Hexapod::default();
    let p = [1.0, -2.0, 22.0, 5.0, -4.0, 3.0];
    let (l, _) = h.struts(&p).unwrap();
    let s = h.solve(&l, &[0.0, 0.0, 20.0, 0.0, 0.0, 0.0]).unwrap();
    assert!(same_pose(&s.pose, &p, 1e-7), "{s:?}");
    assert!(
        (2..10).contains(&s.iterations),
        "{} iterations",
        s.iterations
    );
    // From the answer itself: one look, no step.
    assert_eq!(h.solve(&l, &p).unwrap().iterations, 1);
}

#[test]
fn forward_failures_are_errors() {
    let h = Hexapod::default();
    let p = [0.0, 0.0, 20.0, 0.0, 0.0, 0.0];
    let (l, _) = h.struts(&p).unwrap();
    // A strut of no length.
    let mut zero = l;
    zero[3] = 0.0;
    assert_eq!(h.solve(&zero, &p), Err(KinsError::NoSolution));
    // The platform guessed in the base's plane: the struts' Jacobian is
    // singular there.
    assert_eq!(
        h.solve(&l, &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        Err(KinsError::NoSolution)
    );
    // Too few iterations allowed, or too little error tolerated.
    let hurried = Hexapod {
        limit_iterations: 1,
        ..h
    };
    let guess = [0.0, 0.0, 18.0, 0.0, 0.0, 0.0];
    assert_eq!(hurried.solve(&l, &guess), Err(KinsError::NotConverged));
    let strict = Hexapod {
        max_error: 0.1,
        ..h
    };
    assert_eq!(strict.solve(&l, &guess), Err(KinsError::NotConverged));
    // Struts no platform can have.
    let impossible = [1.0, 1.0, 1.0, 1.0, 1.0, 50.0];
    assert!(h.solve(&impossible, &p).is_err());
    assert_eq!(h.struts(&[f64::NAN; 6]), Err(KinsError::NoSolution));
}

#[test]
fn screw_lead_corrects_twisted_struts() {
    let h = Hexapod {
        screw_lead: 5.0,
        ..Hexapod::default()
    };
    let p = [2.0, 1.0, 22.0, 6.0, -3.0, 8.0];
    let (l, corr) = h.struts(&p).unwrap();
    let (plain, _) = Hexapod::default().struts(&p).unwrap();
    for i in 0..STRUTS {
        assert!((l[i] - plain[i] - corr[i]).abs() < 1e-12);
        assert!(corr[i].abs() < 5.0 / 4.0, "{corr:?}");
    }
    assert!(corr.iter().any(|c| c.abs() > 1e-6), "{corr:?}");
    // The forward kinematics include the correction too.
    let s = h.solve(&l, &[0.0, 0.0, 20.0, 0.0, 0.0, 0.0]).unwrap();
    assert!(same_pose(&s.pose, &p, 1e-7), "{s:?}");
}

fn geometry() -> impl Strategy<Value = Hexapod> {
    // Base points on a circle of 20 to 40, platform points on one of 8 to
    // 15, in pairs 120° apart (the classic 6-6 layout), with some wobble.
    (
        20.0f64..40.0,
        8.0f64..15.0,
        5.0f64..25.0,
        prop::array::uniform6(-2.0f64..2.0),
        0.0f64..5.0,
    )
        .prop_map(|(rb, rp, spread, wobble, lead)| {
            let mut base = [[0.0; 3]; STRUTS];
            let mut platform = [[0.0; 3]; STRUTS];
            for i in 0..STRUTS {
                let pair = (i / 2) as f64 * 120.0;
                let side = if i % 2 == 0 { -1.0 } else { 1.0 };
                let b = rad(pair + side * spread + wobble[i]);
                let p = rad(pair + 60.0 * side - side * spread);
                base[i] = [rb * b.cos(), rb * b.sin(), 0.0];
                platform[i] = [rp * p.cos(), rp * p.sin(), 0.0];
            }
            Hexapod {
                base,
                platform,
                screw_lead: lead,
                ..Hexapod::default()
            }
        })
}

fn check(h: Hexapod, p: [f64; 6], nudge: [f64; 6]) -> std::result::Result<(), TestCaseError> {
    let (l, _) = h.struts(&p).unwrap();
    // Away from singular platform positions (where several solutions
    // crowd together): small strut changes move the platform little.
    let angles = [rad(p[3]), rad(p[4]), rad(p[5])];
    let (jac, _) = h.linearise(&l, [p[0], p[1], p[2]], angles).unwrap();
    for k in 0..6 {
        let mut e = [0.0; 6];
        e[k] = 1.0;
        // At most 10 units or half a radian per unit of strut.
        let ok = solve6(jac, e).is_some_and(|x| {
            x[..3].iter().all(|v| v.abs() < 10.0) && x[3..].iter().all(|v| v.abs() < 0.5)
        });
        if !ok {
            return Ok(());
        }
    }
    let guess = [0, 1, 2, 3, 4, 5].map(|i| p[i] + nudge[i]);
    let s = h
        .solve(&l, &guess)
        .map_err(|e| TestCaseError::fail(format!("{e:?} at {p:?}")))?;
    prop_assert!(same_pose(&s.pose, &p, 1e-6), "{:?} vs {:?}", s.pose, p);
    let (l2, _) = h.struts(&s.pose).unwrap();
    for i in 0..STRUTS {
        prop_assert!((l2[i] - l[i]).abs() < 1e-8);
    }
    Ok(())
}

proptest! {
    #[test]
    fn round_trips_with_the_default_geometry(
        xy in prop::array::uniform2(-5.0f64..5.0), z in 15.0f64..30.0,
        abc in prop::array::uniform3(-15.0f64..15.0),
        nudge in prop::array::uniform6(-0.5f64..0.5),
    ) {
        check(Hexapod::default(), [xy[0], xy[1], z, abc[0], abc[1], abc[2]], nudge)?;
    }

    #[test]
    fn round_trips_with_random_geometries(
        h in geometry(),
        xy in prop::array::uniform2(-3.0f64..3.0), z in 15.0f64..30.0,
        abc in prop::array::uniform3(-10.0f64..10.0),
        nudge in prop::array::uniform6(-0.5f64..0.5),
    ) {
        check(h, [xy[0], xy[1], z, abc[0], abc[1], abc[2]], nudge)?;
    }
}
