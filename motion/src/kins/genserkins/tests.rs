use super::*;
use crate::kins::math::angle_diff;
use crate::kins::pumakins::Puma;
use proptest::prelude::*;

fn fwd(k: &Genser, j: [f64; 6]) -> Pose {
    let mut p = Pose::ZERO;
    k.forward(&j, &mut p, &mut KinsFlags::default()).unwrap();
    p
}

fn inv(k: &Genser, p: &Pose, start: [f64; 6]) -> (std::result::Result<[f64; 6], KinsError>, u32) {
    let mut j = start;
    let (r, n) = k.inverse_counted(p, &mut j);
    (r.map(|()| j), n)
}

fn same_pose(a: &Pose, b: &Pose, tol: f64) -> bool {
    (0..3).all(|i| (a.0[i] - b.0[i]).abs() < tol)
        && (3..6).all(|i| angle_diff(rad(a.0[i]), rad(b.0[i])).abs() < rad(tol))
}

#[test]
fn default_links_are_the_puma_of_pumakins() {
    // LinuxCNC's genserkins defaults describe the PUMA 560 that pumakins
    // models (without pumakins' tool offset D6).
    let g = Genser::default();
    let puma = Puma {
        d6: 0.0,
        ..Puma::default()
    };
    for j in [[0.0; 6], [10.0, -20.0, 30.0, 40.0, -50.0, 60.0]] {
        let a = fwd(&g, j);
        let mut b = Pose::ZERO;
        puma.forward(&j, &mut b, &mut KinsFlags::default()).unwrap();
        assert!(same_pose(&a, &b, 1e-9), "{a:?} vs {b:?}");
    }
}

#[test]
fn inverse_converges_from_nearby_and_counts_iterations() {
    let g = Genser::default();
    let j = [10.0, -20.0, 30.0, 40.0, -50.0, 60.0];
    let p = fwd(&g, j);
    let (sol, n) = inv(&g, &p, [12.0, -18.0, 27.0, 44.0, -47.0, 57.0]);
    let sol = sol.unwrap();
    assert!(
        sol.iter().zip(j).all(|(a, b)| (a - b).abs() < 1e-7),
        "{sol:?}"
    );
    assert!((2..20).contains(&n), "{n} iterations");
    // Already there: no iteration needed.
    let (_, n) = inv(&g, &p, j);
    assert_eq!(n, 0);
}

#[test]
fn singular_and_unreachable_poses_are_refused() {
    let g = Genser::default();
    // Far out of reach: the arm stretches straight and the Jacobian turns
    // singular, or the iterations run out.
    let far = Pose([3000.0, 0.0, 0.0, 180.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let (r, _) = inv(&g, &far, [0.0, 0.0, 0.0, 0.0, 30.0, 0.0]);
    assert!(
        matches!(r, Err(KinsError::NoSolution | KinsError::NotConverged)),
        "{r:?}"
    );
    // Starting on a singularity (joint 5 at 0: wrist axes 4 and 6 in
    // line) the Jacobian cannot be inverted.
    let j = [10.0, -20.0, 30.0, 40.0, 20.0, 60.0];
    let p = fwd(&g, j);
    let (r, n) = inv(&g, &p, [0.0; 6]);
    assert_eq!((r, n), (Err(KinsError::NoSolution), 1));
    // No iterations allowed.
    let none = Genser {
        max_iterations: 0,
        ..Genser::default()
    };
    assert_eq!(
        inv(&none, &p, [12.0, -18.0, 27.0, 44.0, 25.0, 57.0]).0,
        Err(KinsError::NotConverged)
    );
    let nan = Pose([f64::NAN; 9]);
    assert_eq!(inv(&g, &nan, j).0, Err(KinsError::NoSolution));
}

#[test]
fn unrotate_measures_a_joint_from_the_previous_one() {
    let plain = Genser::default();
    let mut unrotate = [0; 6];
    unrotate[2] = 1;
    let coupled = Genser {
        unrotate,
        ..Genser::default()
    };
    // Joint 2's motor reads the sum of both angles.
    let a = fwd(&plain, [0.0, 20.0, 30.0, 0.0, 40.0, 0.0]);
    let b = fwd(&coupled, [0.0, 20.0, 50.0, 0.0, 40.0, 0.0]);
    assert!(same_pose(&a, &b, 1e-9));
    let (sol, _) = inv(&coupled, &a, [0.0, 22.0, 48.0, 2.0, 38.0, 1.0]);
    let sol = sol.unwrap();
    assert!((sol[2] - 50.0).abs() < 1e-7, "{sol:?}");
}

fn geometry() -> impl Strategy<Value = Genser> {
    let link = (0.0f64..500.0, -1.6f64..1.6, -300.0f64..300.0);
    prop::array::uniform6(link).prop_map(|l| Genser {
        links: l.map(|(a, alpha, d)| DhLink { a, alpha, d }),
        ..Genser::default()
    })
}

fn check(g: Genser, j: [f64; 6], nudge: [f64; 6]) -> std::result::Result<(), TestCaseError> {
    let (_, frames) = chain(&g.links, &g.angles(&j));
    let tool = chain(&g.links, &g.angles(&j)).0;
    let jac = jacobian(&frames, tool.pos);
    // Away from singularities: every small move of the tool (a unit of
    // the arm's size, or a radian) needs only moderate joint speeds.
    let scale = 1.0 + g.links.iter().map(|l| l.a.abs() + l.d.abs()).sum::<f64>();
    for k in 0..6 {
        let mut e = [0.0; 6];
        e[k] = if k < 3 { scale } else { 1.0 };
        if !solve6(jac, e).is_some_and(|x| x.iter().all(|v| v.abs() < 20.0)) {
            return Ok(());
        }
    }
    let p = fwd(&g, j);
    let start = [0, 1, 2, 3, 4, 5].map(|i| j[i] + nudge[i]);
    let (sol, _) = inv(&g, &p, start);
    let sol = sol.map_err(|e| TestCaseError::fail(format!("{e:?} from {start:?} to {j:?}")))?;
    let p2 = fwd(&g, sol);
    prop_assert!(
        same_pose(&p2, &p, 1e-6 * scale.max(1.0)),
        "{:?} vs {:?}",
        p2,
        p
    );
    // Started nearby, the same solution comes back.
    prop_assert!(
        sol.iter()
            .zip(j)
            .all(|(a, b)| angle_diff(rad(*a), rad(b)).abs() < 1e-6),
        "{:?} vs {:?}",
        sol,
        j
    );
    Ok(())
}

proptest! {
    #[test]
    fn round_trips_with_the_default_links(
        j in prop::array::uniform6(-170.0f64..170.0),
        nudge in prop::array::uniform6(-2.0f64..2.0),
    ) {
        check(Genser::default(), j, nudge)?;
    }

    #[test]
    fn round_trips_with_random_links(
        g in geometry(),
        j in prop::array::uniform6(-170.0f64..170.0),
        nudge in prop::array::uniform6(-2.0f64..2.0),
    ) {
        check(g, j, nudge)?;
    }
}
