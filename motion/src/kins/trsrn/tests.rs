use super::*;
use crate::kins::twotype::TwoTypeKins;
use crate::kins::{Kinematics, KinsFlags};
use proptest::prelude::*;

/// A machine with every dimension set, so no term drops out.
fn sample(layout: Layout) -> Head {
    Head {
        layout,
        tool: 50.0,
        pivot: 100.0,
        z_pivot: 200.0,
        x_offset: 5.0,
        y_offset: 7.0,
        rot_axis: 300.0,
        z_rot_axis: 400.0,
        pre_rot: 0.3,
        nut_angle: 45.0,
        primary: 20.0,
        secondary: 35.0,
    }
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol)
}

/// The head's sines and cosines as LinuxCNC's sources name them:
/// (Ss, Cs, Sp, Cp, Sv, Cv, r, s, t).
fn head_terms(h: &Head, sec: f64, prim: f64) -> [f64; 9] {
    let (ss, cs) = sec.to_radians().sin_cos();
    let (sp, cp) = prim.to_radians().sin_cos();
    let (sv, cv) = h.nut_angle.to_radians().sin_cos();
    let r = cs + sv * sv * (1.0 - cs);
    let s = cs + cv * cv * (1.0 - cs);
    let t = sv * cv * (1.0 - cs);
    [ss, cs, sp, cp, sv, cv, r, s, t]
}

#[test]
fn xyzacb_tcp_forward_is_linuxcncs() {
    let h = sample(Layout::Acb);
    let (px, py, pz, w, sec, prim) = (10.0f64, 20.0, 30.0, 15.0f64, 25.0, 40.0);
    let [ss, _, sp, cp, sv, cv, r, s, t] = head_terms(&h, sec, prim);
    let (sw, cw) = w.to_radians().sin_cos();
    let (ly, lz, dx, dy, dt) = (h.pivot, h.z_pivot, h.x_offset, h.y_offset, h.tool);
    let dray = h.rot_axis - (dy + ly);
    let draz = h.z_rot_axis - lz;
    let (cvss, svss) = (cv * ss, sv * ss);
    // LinuxCNC's expansion, grouped by the head offset's components.
    let hx = -(cp * svss - sp * t) * (dt + lz) - cp * dx + (cp * cvss + sp * r) * ly + dy * sp;
    let hy = -cp * dy - dx * sp - (sp * svss + cp * t) * (dt + lz) + (cvss * sp - cp * r) * ly;
    let hz = -s * (dt + lz) - t * ly;
    let want = [
        hx + dx + px,
        cw * (hy + py - dray) - sw * (hz + pz - draz) + dray + dy + ly,
        sw * (hy + py - dray) + cw * (hz + pz - draz) + draz + dt + lz,
    ];
    let got = h.tcp_world([px, py, pz], [w, sec, prim]);
    assert!(close(&got, &want, 1e-9), "{got:?} vs {want:?}");
}

#[test]
fn xyzbca_tcp_forward_is_linuxcncs() {
    let h = sample(Layout::Bca);
    let (px, py, pz, sec, w, prim) = (10.0f64, 20.0, 30.0, 25.0, 15.0f64, 40.0);
    let [ss, _, sp, cp, sv, cv, r, s, t] = head_terms(&h, sec, prim);
    let (sw, cw) = w.to_radians().sin_cos();
    let (lx, lz, dx, dy, dt) = (h.pivot, h.z_pivot, h.x_offset, h.y_offset, h.tool);
    let drax = h.rot_axis - lx - dx;
    let draz = h.z_rot_axis - lz;
    let (cvss, svss) = (cv * ss, sv * ss);
    let want_x = -cp * cw * dx + cw * dy * sp
        - cw * (drax - px)
        - (cw * sp * svss + cp * cw * t + sw * s) * (dt + lz)
        + (cvss * cw * sp - cp * cw * r - sw * t) * lx
        - (draz - pz) * sw
        + drax
        + dx
        + lx;
    let want_y =
        (cp * svss - sp * t) * (dt + lz) - cp * dy - (cp * cvss + sp * r) * lx - dx * sp + dy + py;
    let want_z = cp * dx * sw - dy * sp * sw - cw * (draz - pz)
        + (sp * svss * sw + cp * sw * t - cw * s) * (dt + lz)
        - (cvss * sp * sw - cp * sw * r + cw * t) * lx
        + (drax - px) * sw
        + draz
        + dt
        + lz;
    let got = h.tcp_world([px, py, pz], [sec, w, prim]);
    assert!(
        close(&got, &[want_x, want_y, want_z], 1e-9),
        "{got:?} vs {:?}",
        [want_x, want_y, want_z]
    );
}

#[test]
fn tool_forward_is_linuxcncs_for_both_heads() {
    for layout in [Layout::Acb, Layout::Bca] {
        let h = sample(layout);
        let (px, py, pz) = (10.0f64, 20.0, 30.0);
        let [ss, cs, sp, cp, sv, cv, r, s, t] = head_terms(&h, h.secondary, h.primary);
        let (stc, ctc) = h.pre_rot.sin_cos();
        let (l, lz, dx, dy) = (h.pivot, h.z_pivot, h.x_offset, h.y_offset);
        let (cvss, svss) = (cv * ss, sv * ss);
        let want = match layout {
            Layout::Acb => {
                let (k00, k01) = (cs * ctc - cvss * stc, ctc * cvss + stc * r);
                let (k10, k11) = (-(ctc * cvss + cs * stc), -(cvss * stc - ctc * r));
                [
                    (k00 * cp - k01 * sp) * (dx + px) - k00 * dx
                        + (k01 * cp + k00 * sp) * (dy + l + py)
                        - k01 * dy
                        - (ctc * svss - stc * t) * (lz + pz)
                        - l * stc,
                    (k10 * cp - k11 * sp) * (dx + px) - k10 * dx
                        + (k11 * cp + k10 * sp) * (dy + l + py)
                        - k11 * dy
                        - ctc * l
                        + (stc * svss + ctc * t) * (lz + pz),
                    (cp * svss - sp * t) * (dx + px) + (sp * svss + cp * t) * (dy + l + py)
                        - dx * svss
                        + (lz + pz) * s
                        - dy * t
                        - lz,
                ]
            }
            Layout::Bca => {
                let (k00, k01) = (ctc * r - cvss * stc, ctc * cvss + cs * stc);
                let (k10, k11) = (-(ctc * cvss + stc * r), cs * ctc - cvss * stc);
                [
                    (k00 * cp - k01 * sp) * (dx + l + px) - k00 * dx
                        + (k01 * cp + k00 * sp) * (dy + py)
                        - k01 * dy
                        - ctc * l
                        + (stc * svss + ctc * t) * (lz + pz),
                    (k10 * cp - k11 * sp) * (dx + l + px) - k10 * dx
                        + (k11 * cp + k10 * sp) * (dy + py)
                        - k11 * dy
                        + (ctc * svss - stc * t) * (lz + pz)
                        + l * stc,
                    (sp * svss + cp * t) * (dx + l + px) - (cp * svss - sp * t) * (dy + py)
                        + dy * svss
                        + (lz + pz) * s
                        - dx * t
                        - lz,
                ]
            }
        };
        let got = h.tool_world([px, py, pz]);
        assert!(close(&got, &want, 1e-9), "{layout:?}: {got:?} vs {want:?}");
    }
}

#[test]
fn identity_at_startup_and_three_types_to_switch_between() {
    let k = TwoTypeKins::new(sample(Layout::Acb));
    assert_eq!(k.active_type(), 0);
    let j = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    let mut p = Pose::ZERO;
    k.forward(&j, &mut p, &mut KinsFlags::default()).unwrap();
    assert_eq!(p.0[..6], j);
    k.switch_to(2).unwrap();
    assert_eq!(k.active_type(), 2);
    assert_eq!(k.switch_to(3), Err(KinsError::Unsupported));
    assert_eq!(k.active_type(), 2);
}

#[test]
fn short_joint_sets_and_non_numbers_are_refused() {
    let k = TwoTypeKins::new(sample(Layout::Bca));
    k.switch_to(1).unwrap();
    let mut flags = KinsFlags::default();
    let mut p = Pose::ZERO;
    assert_eq!(
        k.forward(&[0.0; 5], &mut p, &mut flags),
        Err(KinsError::Unsupported)
    );
    p.0[4] = f64::NAN;
    let mut j = [2.0; 6];
    assert_eq!(
        k.inverse(&p, &mut j, &mut flags),
        Err(KinsError::NoSolution)
    );
    assert_eq!(j, [2.0; 6]);
    let mut bad = sample(Layout::Bca);
    bad.nut_angle = f64::INFINITY;
    let k = TwoTypeKins::new(bad);
    k.switch_to(2).unwrap();
    let mut out = Pose::ZERO;
    assert_eq!(
        k.forward(&[0.0; 6], &mut out, &mut flags),
        Err(KinsError::NoSolution)
    );
    assert_eq!(out, Pose::ZERO);
}

proptest! {
    #[test]
    fn every_type_round_trips(
        acb in any::<bool>(), kins_type in 0usize..3,
        xyz in prop::array::uniform3(-500.0f64..500.0),
        angles in prop::array::uniform3(-360.0f64..360.0),
        dims in prop::array::uniform7(-300.0f64..300.0),
        nut in -90.0f64..90.0, pre in -3.2f64..3.2,
        tool_angles in prop::array::uniform2(-180.0f64..180.0),
    ) {
        let layout = if acb { Layout::Acb } else { Layout::Bca };
        let head = Head {
            layout,
            tool: dims[0], pivot: dims[1], z_pivot: dims[2], x_offset: dims[3],
            y_offset: dims[4], rot_axis: dims[5], z_rot_axis: dims[6],
            pre_rot: pre, nut_angle: nut, primary: tool_angles[0], secondary: tool_angles[1],
        };
        let k = TwoTypeKins::new(head);
        k.switch_to(i32::try_from(kins_type).unwrap()).unwrap();
        let mut p = Pose::ZERO;
        p.0[..3].copy_from_slice(&xyz);
        p.0[3..6].copy_from_slice(&angles);
        let mut flags = KinsFlags::default();
        let mut j = [0.0; 6];
        k.inverse(&p, &mut j, &mut flags).unwrap();
        let mut back = Pose::ZERO;
        k.forward(&j, &mut back, &mut flags).unwrap();
        prop_assert!(close(&back.0, &p.0, 1e-8), "{:?} vs {:?}", back, p);
    }
}
