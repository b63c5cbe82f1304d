//! The worked examples of the kinematics-fundamentals chapter (seed 002), recomputed with `Se3`:
//! a chain of homogeneous transforms, the closed-form inverse, the ZYX rotation matrix, the
//! Denavit–Hartenberg matrix and the 2-link planar arm (L1 = 1 m, L2 = 0.8 m), forward and
//! inverse.

use crate::support::*;
use kinetree_spatial::{DVec3, Se3};
use proptest::prelude::*;
use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2, FRAC_PI_3, FRAC_PI_4, PI};

/// The chapter's DH transform `Rz(θ) · Tz(d) · Tx(a) · Rx(α)`, composed from elementary `Se3`s.
fn dh(a: f64, alpha: f64, d: f64, theta: f64) -> Se3 {
    Se3::from_rotation_z(theta)
        * Se3::from_translation(DVec3::new(0.0, 0.0, d))
        * Se3::from_translation(DVec3::new(a, 0.0, 0.0))
        * Se3::from_rotation_x(alpha)
}

/// The chapter's `DHParameter.to_matrix`, entry by entry (row-major).
fn dh_matrix(a: f64, alpha: f64, d: f64, theta: f64) -> [[f64; 4]; 4] {
    let (st, ct) = theta.sin_cos();
    let (sa, ca) = alpha.sin_cos();
    [
        [ct, -st * ca, st * sa, a * ct],
        [st, ct * ca, -ct * sa, a * st],
        [0.0, sa, ca, d],
        [0.0, 0.0, 0.0, 1.0],
    ]
}

/// The chapter's `Orientation.to_rotation_matrix` (ZYX: yaw, pitch, roll), row-major.
fn zyx_matrix(roll: f64, pitch: f64, yaw: f64) -> [[f64; 3]; 3] {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sy, cy) = yaw.sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// Forward kinematics of the planar arm: base_from_end for joint angles `q`.
fn planar_arm(q: [f64; 2]) -> Se3 {
    dh(1.0, 0.0, 0.0, q[0]) * dh(0.8, 0.0, 0.0, q[1])
}

/// The chapter's analytic IK for the planar 2-link arm (elbow-up), `None` when unreachable.
fn planar_ik(x: f64, y: f64, l1: f64, l2: f64) -> Option<[f64; 2]> {
    let distance = x.hypot(y);
    if distance > l1 + l2 || distance < (l1 - l2).abs() {
        return None;
    }
    let cos_t2 = ((x * x + y * y - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)).clamp(-1.0, 1.0);
    let t2 = cos_t2.acos();
    let t1 = y.atan2(x) - (l2 * t2.sin()).atan2(l1 + l2 * t2.cos());
    Some([t1, t2])
}

#[test]
fn chain_of_transformations() {
    // T_base_to_end = Rz(π/4) · T(0.5, 0, 0) · Rz(π/4).
    let base_from_link1 = Se3::from_rotation_z(FRAC_PI_4);
    let link1_from_link2 = Se3::from_translation(DVec3::new(0.5, 0.0, 0.0));
    let link2_from_end = Se3::from_rotation_z(FRAC_PI_4);
    let base_from_end = base_from_link1 * link1_from_link2 * link2_from_end;
    // The 0.5 m offset turned by 45°, and a 90° turn in all: x_end = y_base.
    let a = 0.5 * FRAC_1_SQRT_2; // 0.35355339…
    assert!((base_from_end.translation - DVec3::new(a, a, 0.0)).length() < 1e-15);
    assert!((base_from_end.translation.x - 0.353_553_390_593_273_7).abs() < 1e-15);
    assert!(
        max_diff(
            &flat_se3(&base_from_end),
            &flat_se3(&Se3::new(
                Se3::from_rotation_z(FRAC_PI_2).rotation,
                DVec3::new(a, a, 0.0)
            ))
        ) < 1e-15
    );
    // The closed-form inverse [Rᵀ, -Rᵀ t]: here Rz(-90°) and (-a, a, 0).
    let end_from_base = base_from_end.inverse();
    assert!((end_from_base.translation - DVec3::new(-a, a, 0.0)).length() < 1e-15);
    let rows = end_from_base.to_rows();
    let r = base_from_end.to_rows();
    for i in 0..3 {
        for j in 0..3 {
            assert_eq!(rows[i][j], r[j][i]);
        }
    }
}

#[test]
fn zyx_orientation_matrix_is_urdf_rpy() {
    // A pose of the chapter's `Pose` class: position (1, 2, 3), roll 0.1, pitch 0.2, yaw 0.3.
    let pose = Se3::from_xyz_rpy([1.0, 2.0, 3.0], [0.1, 0.2, 0.3]);
    let expected = zyx_matrix(0.1, 0.2, 0.3);
    assert!(max_diff(&pose.rotation_rows().concat(), &expected.concat()) < 1e-16);
    // Hand values: R[2][0] = -sin(pitch), R[0][0] = cos(yaw) cos(pitch).
    assert!((pose.rotation_rows()[2][0] + 0.2f64.sin()).abs() < 1e-16);
    assert!(
        (pose.rotation_rows()[0][0] - 0.955_336_489_125_606 * 0.980_066_577_841_241_6).abs()
            < 1e-15
    );
    assert_eq!(pose.to_rows()[0][3], 1.0);
    assert_eq!(pose.to_rows()[2][3], 3.0);
    assert!(max_diff(&pose.to_rpy(), &[0.1, 0.2, 0.3]) < 1e-15);
}

#[test]
fn planar_arm_forward_kinematics() {
    // θ = (45°, 60°): the end effector at (cos 45° + 0.8 cos 105°, sin 45° + 0.8 sin 105°, 0).
    let q = [FRAC_PI_4, FRAC_PI_3];
    let base_from_end = planar_arm(q);
    let p = base_from_end.translation;
    assert!((p.x - 0.500_051_545_104_531_1).abs() < 1e-15, "{p}");
    assert!((p.y - 1.479_847_442_217_802_3).abs() < 1e-15, "{p}");
    assert_eq!(p.z, 0.0);
    // The end frame is turned by θ1 + θ2 = 105° about z.
    assert!(
        max_diff(
            &flat_se3(&base_from_end),
            &flat_se3(&Se3::new(Se3::from_rotation_z(7.0 * PI / 12.0).rotation, p))
        ) < 1e-15
    );
    // Joint positions (`get_joint_positions`): base, elbow at (cos 45°, sin 45°), end.
    let elbow = dh(1.0, 0.0, 0.0, q[0]).translation;
    assert!((elbow - DVec3::new(FRAC_1_SQRT_2, FRAC_1_SQRT_2, 0.0)).length() < 1e-15);
    // The product of the chapter's DH matrices is the same transform.
    let m1 = dh_matrix(1.0, 0.0, 0.0, q[0]);
    let m2 = dh_matrix(0.8, 0.0, 0.0, q[1]);
    let mut product = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            product[i][j] = (0..4).map(|k| m1[i][k] * m2[k][j]).sum();
        }
    }
    assert!(max_diff(&product.concat(), &flat_se3(&base_from_end)) < 1e-15);
}

#[test]
fn planar_arm_inverse_kinematics() {
    // Target (1.2, 0.5): cos θ2 = (1.44 + 0.25 - 1 - 0.64) / 1.6 = 0.03125.
    let [t1, t2] = planar_ik(1.2, 0.5, 1.0, 0.8).unwrap();
    assert!((t2.cos() - 0.03125).abs() < 1e-15);
    // The chapter prints θ1 = -15.3°, θ2 = 88.2°.
    assert!((t1.to_degrees() - -15.338_163_632_640_97).abs() < 1e-10);
    assert!((t2.to_degrees() - 88.209_215_340_671_05).abs() < 1e-10);
    assert_eq!(
        format!("{:.1} {:.1}", t1.to_degrees(), t2.to_degrees()),
        "-15.3 88.2"
    );
    // Forward kinematics through Se3 lands on the target.
    let p = planar_arm([t1, t2]).translation;
    assert!((p - DVec3::new(1.2, 0.5, 0.0)).length() < 1e-15, "{p}");
    // Beyond L1 + L2 = 1.8 m, or inside |L1 - L2| = 0.2 m, there is no solution.
    assert_eq!(planar_ik(1.5, 1.1, 1.0, 0.8), None);
    assert_eq!(planar_ik(0.1, 0.1, 1.0, 0.8), None);
    // At full stretch the elbow is straight.
    let [s1, s2] = planar_ik(0.0, 1.8, 1.0, 0.8).unwrap();
    assert!((s1 - FRAC_PI_2).abs() < 1e-7 && s2.abs() < 1e-7);
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn dh_matrix_is_the_composition_of_elementary_transforms(
        a in -2.0..2.0, alpha in -PI..PI, d in -2.0..2.0, theta in -PI..PI,
    ) {
        let composed = dh(a, alpha, d, theta);
        prop_assert!(max_diff(&flat_se3(&composed), &dh_matrix(a, alpha, d, theta).concat()) < 1e-15);
    }

    #[test]
    fn zyx_matrix_is_from_rpy(roll in -PI..PI, pitch in -PI..PI, yaw in -PI..PI) {
        let r = Se3::from_rpy(roll, pitch, yaw).rotation_rows();
        prop_assert!(max_diff(&r.concat(), &zyx_matrix(roll, pitch, yaw).concat()) < 1e-15);
    }

    #[test]
    fn planar_ik_inverts_planar_fk(t1 in -PI..PI, t2 in 0.05..(PI - 0.05)) {
        // Elbow-up configurations (θ2 in (0, π)) come back exactly.
        let p = planar_arm([t1, t2]).translation;
        let [s1, s2] = planar_ik(p.x, p.y, 1.0, 0.8).unwrap();
        let back = planar_arm([s1, s2]).translation;
        prop_assert!((back - p).length() < 1e-12);
        prop_assert!((s2 - t2).abs() < 1e-9);
    }
}
