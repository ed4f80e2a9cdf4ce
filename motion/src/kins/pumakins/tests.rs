use super::*;
use crate::kins::math::{angle_diff, norm, rad};
use proptest::prelude::*;

fn fwd(k: &Puma, j: [f64; 6]) -> (Pose, KinsFlags) {
    let mut p = Pose::ZERO;
    let mut f = KinsFlags::default();
    k.forward(&j, &mut p, &mut f).unwrap();
    (p, f)
}

fn inv(
    k: &Puma,
    p: &Pose,
    iflags: u64,
    current: [f64; 6],
) -> std::result::Result<([f64; 6], u64), KinsError> {
    let mut j = current;
    let mut f = KinsFlags {
        forward: 0,
        inverse: iflags,
    };
    k.inverse(p, &mut j, &mut f).map(|()| (j, f.forward))
}

fn same_angles(a: &[f64; 6], b: &[f64; 6], tol: f64) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| angle_diff(rad(*x), rad(*y)).abs() < rad(tol))
}

fn same_pose(a: &Pose, b: &Pose, tol: f64) -> bool {
    (0..3).all(|i| (a.0[i] - b.0[i]).abs() < tol)
        && (3..6).all(|i| angle_diff(rad(a.0[i]), rad(b.0[i])).abs() < rad(tol))
}

#[test]
fn zero_position_of_a_puma_560() {
    let k = Puma::default();
    let (p, f) = fwd(&k, [0.0; 6]);
    // Upper arm and elbow offset along X, shoulder offset along Y,
    // forearm and tool down, the tool pointing down (a half roll).
    let want = [350.0, 70.0, -470.0];
    for (got, want) in p.0.iter().zip(want) {
        assert!((got - want).abs() < 1e-9, "{p:?}");
    }
    assert!((p.0[3].abs() - 180.0).abs() < 1e-9 && p.0[4].abs() < 1e-9 && p.0[5].abs() < 1e-9);
    // Joint 5 at 0° is a wrist singularity.
    assert_eq!(f.inverse & SINGULAR, SINGULAR);
    // The inverse keeps joint 4 where it is and says so.
    let (j, fflags) = inv(&k, &p, f.inverse, [0.0, 0.0, 0.0, 25.0, 0.0, 0.0]).unwrap();
    assert_eq!(fflags, REACH);
    assert!((j[3] - 25.0).abs() < 1e-9);
    let (back, _) = fwd(&k, j);
    assert!(same_pose(&back, &p, 1e-6), "{back:?}");
}

#[test]
fn every_branch_comes_back_through_the_flags() {
    let k = Puma::default();
    let j = [20.0, -30.0, 40.0, 50.0, 60.0, 70.0];
    let (p, _) = fwd(&k, j);
    let mut seen = Vec::new();
    for flags in 0..8 {
        let (sol, _) = inv(&k, &p, flags, j).unwrap();
        let (back, f) = fwd(&k, sol);
        assert!(
            same_pose(&back, &p, 1e-6),
            "flags {flags}: {back:?} vs {p:?}"
        );
        assert_eq!(f.inverse, flags, "flags {flags}: {sol:?}");
        assert!(!seen.iter().any(|s| same_angles(s, &sol, 1e-3)), "distinct");
        seen.push(sol);
    }
}

#[test]
fn unreachable_poses_are_refused() {
    let k = Puma::default();
    let far = Pose([2000.0, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(inv(&k, &far, 0, [0.0; 6]), Err(KinsError::NoSolution));
    // The wrist centre on the waist axis: closer than the shoulder
    // offset D3 can be.
    let axis = Pose([0.0, 0.0, -170.0, 180.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(inv(&k, &axis, 0, [0.0; 6]), Err(KinsError::NoSolution));
    let nan = Pose([f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(inv(&k, &nan, 0, [0.0; 6]), Err(KinsError::NoSolution));
    // Five joints are not a PUMA.
    let mut j5 = [0.0; 5];
    assert_eq!(
        k.inverse(&far, &mut j5, &mut KinsFlags::default()),
        Err(KinsError::Unsupported)
    );
}

fn geometry() -> impl Strategy<Value = Puma> {
    (
        100.0f64..600.0,
        0.0f64..100.0,
        0.0f64..150.0,
        100.0f64..600.0,
        0.0f64..150.0,
    )
        .prop_map(|(a2, a3, d3, d4, d6)| Puma { a2, a3, d3, d4, d6 })
}

/// Joints away from the arm's singularities: the elbow not straight,
/// joint 5 not at 0 or 180, the wrist off the waist axis.
fn regular(k: &Puma, j: &[f64; 6]) -> bool {
    let q = j.map(rad);
    let w = k.arm6().wrist(&q);
    let planar = (w.pos[0].powi(2) + w.pos[1].powi(2) - k.d3 * k.d3)
        .max(0.0)
        .sqrt();
    let forearm = k.a3.hypot(k.d4);
    let reach = norm([planar, 0.0, w.pos[2]]);
    q[4].sin().abs() > 0.05
        && planar > 0.05 * k.a2
        && reach < (k.a2 + forearm) * 0.999
        && reach > (k.a2 - forearm).abs() * 1.001 + 1e-3
}

fn check(k: Puma, j: [f64; 6]) -> std::result::Result<(), TestCaseError> {
    prop_assume!(regular(&k, &j));
    let (p, f) = fwd(&k, j);
    // inverse(forward(j)) = j, on the branch the flags describe.
    let (back, _) = inv(&k, &p, f.inverse, j).unwrap();
    prop_assert!(same_angles(&back, &j, 1e-6), "{:?} vs {:?}", back, j);
    // forward(inverse(p)) = p on every branch that exists.
    for flags in 0..8 {
        if let Ok((sol, _)) = inv(&k, &p, flags, j) {
            let (p2, _) = fwd(&k, sol);
            prop_assert!(
                same_pose(&p2, &p, 1e-6),
                "flags {}: {:?} vs {:?}",
                flags,
                p2,
                p
            );
        }
    }
    Ok(())
}

proptest! {
    #[test]
    fn round_trips_with_default_dimensions(j in prop::array::uniform6(-170.0f64..170.0)) {
        check(Puma::default(), j)?;
    }

    #[test]
    fn round_trips_with_random_dimensions(
        k in geometry(), j in prop::array::uniform6(-170.0f64..170.0),
    ) {
        check(k, j)?;
    }
}
