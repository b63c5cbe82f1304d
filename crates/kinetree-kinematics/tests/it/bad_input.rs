//! Configurations that enter the algorithms: quaternions are normalized within
//! [`QUATERNION_NORM_TOLERANCE`] and refused beyond it, naming the joint and the norm.

use kinetree_kinematics::configuration::{check_configuration, integrate};
use kinetree_kinematics::model::{Model, RootJoint};
use kinetree_kinematics::{
    FrameId, KinematicsData, KinematicsError, QUATERNION_NORM_TOLERANCE, forward_kinematics,
};

/// A floating base with a ball joint to an arm of length 1 along x.
fn floating_ball() -> Model {
    Model::from_urdf_str(
        r#"<robot name="r"><link name="base"/><link name="arm"/><link name="hand"/>
           <joint name="ball" type="floating"><parent link="base"/><child link="arm"/></joint>
           <joint name="wrist" type="fixed"><parent link="arm"/><child link="hand"/>
             <origin xyz="1 0 0"/></joint></robot>"#,
        RootJoint::Floating,
    )
    .unwrap()
}

fn hand(model: &Model, q: &[f64]) -> Result<[f64; 3], KinematicsError> {
    let mut data = KinematicsData::new(model);
    forward_kinematics(model, &mut data, q)?;
    Ok(data
        .world_from(FrameId::find(model, "hand").unwrap())?
        .translation
        .to_array())
}

#[test]
fn quaternions_beyond_the_tolerance_are_refused_naming_the_joint_and_norm() {
    let model = floating_ball();
    assert_eq!(model.nq(), 14);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    // The root turned 90° about z (unit): the hand at (0, 1, 0).
    let mut q = vec![
        0.0, 0.0, 0.0, 0.0, 0.0, s, s, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let at = hand(&model, &q).unwrap();
    assert!(
        (at[0]).abs() < 1e-15 && (at[1] - 1.0).abs() < 1e-15,
        "{at:?}"
    );
    // (1, 0, 0, 1) has norm √2: refused, naming the root joint.
    let root = model.joint(model.bodies()[1].joint.unwrap()).name.clone();
    q[3..7].copy_from_slice(&[1.0, 0.0, 0.0, 1.0]);
    match hand(&model, &q) {
        Err(KinematicsError::NonUnitQuaternion { joint, norm }) => {
            assert_eq!(joint, root);
            assert!((norm - 2f64.sqrt()).abs() < 1e-15, "{norm}");
        }
        other => panic!("expected NonUnitQuaternion, got {other:?}"),
    }
    // The zero quaternion is not the identity.
    q[3..7].copy_from_slice(&[0.0; 4]);
    assert!(matches!(
        hand(&model, &q),
        Err(KinematicsError::NonUnitQuaternion { norm: 0.0, .. })
    ));
    // Huge components: the norm is computed without overflow and reported.
    q[3..7].copy_from_slice(&[1e300, 0.0, 0.0, 1e300]);
    match check_configuration(&model, &q) {
        Err(e @ KinematicsError::NonUnitQuaternion { norm, .. }) => {
            assert!((norm / 1e300 - 2f64.sqrt()).abs() < 1e-12, "{norm}");
            assert!(e.to_string().contains(&root), "{e}");
        }
        other => panic!("expected NonUnitQuaternion, got {other:?}"),
    }
    // The ball joint's quaternion is checked too, and named.
    q[3..7].copy_from_slice(&[0.0, 0.0, s, s]);
    q[10..14].copy_from_slice(&[0.0, 0.0, 0.0, 0.5]);
    match hand(&model, &q) {
        Err(e @ KinematicsError::NonUnitQuaternion { .. }) => {
            assert!(e.to_string().contains("'ball'"), "{e}");
            assert!(e.to_string().contains("0.5"), "{e}");
        }
        other => panic!("expected NonUnitQuaternion, got {other:?}"),
    }
    // Integrate refuses it as well.
    let mut out = vec![0.0; 14];
    assert!(matches!(
        integrate(&model, &q, &[0.0; 12], &mut out),
        Err(KinematicsError::NonUnitQuaternion { .. })
    ));
}

#[test]
fn quaternions_within_the_tolerance_are_normalized() {
    let model = floating_ball();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let unit = [
        0.0, 0.0, 0.0, 0.0, 0.0, s, s, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let exact = hand(&model, &unit).unwrap();
    // Scaled by 1 + 0.9·tol: accepted and normalized, so the hand does not move (a rotation
    // built from the raw quaternion would scale the arm by (1 + 0.9·tol)²).
    let mut q = unit;
    let k = 1.0 + 0.9 * QUATERNION_NORM_TOLERANCE;
    for x in &mut q[3..7] {
        *x *= k;
    }
    let at = hand(&model, &q).unwrap();
    for i in 0..3 {
        assert!((at[i] - exact[i]).abs() < 1e-15, "{at:?} vs {exact:?}");
    }
    // Scaled by 1 + 1.1·tol: refused.
    let mut q = unit;
    for x in &mut q[3..7] {
        *x *= 1.0 + 1.1 * QUATERNION_NORM_TOLERANCE;
    }
    assert!(matches!(
        hand(&model, &q),
        Err(KinematicsError::NonUnitQuaternion { .. })
    ));
}

#[test]
fn an_overflowing_placement_is_an_error_naming_the_body() {
    // Two prismatic joints along x: 1e308 + 1e308 overflows to inf.
    let model = Model::from_urdf_str(
        r#"<robot name="r"><link name="base"/><link name="a"/><link name="b"/>
           <joint name="s1" type="prismatic"><parent link="base"/><child link="a"/>
             <axis xyz="1 0 0"/><limit lower="-1e308" upper="1e308" effort="1" velocity="1"/></joint>
           <joint name="s2" type="prismatic"><parent link="a"/><child link="b"/>
             <axis xyz="1 0 0"/><limit lower="-1e308" upper="1e308" effort="1" velocity="1"/></joint>
           </robot>"#,
        RootJoint::Fixed,
    )
    .unwrap();
    let mut data = KinematicsData::new(&model);
    match forward_kinematics(&model, &mut data, &[1e308, 1e308]) {
        Err(e @ KinematicsError::Overflow { .. }) => {
            assert!(e.to_string().contains("'b'"), "{e}");
        }
        other => panic!("expected Overflow, got {other:?}"),
    }
    let mut jac = vec![kinetree_kinematics::spatial::Motion::ZERO; 2];
    assert!(matches!(
        kinetree_kinematics::compute_frame_jacobian(
            &model,
            &mut data,
            &[1e308, 1e308],
            FrameId::find(&model, "b").unwrap(),
            kinetree_kinematics::ReferenceFrame::World,
            &mut jac,
        ),
        Err(KinematicsError::Overflow { .. })
    ));
    // Large but representable values are fine.
    forward_kinematics(&model, &mut data, &[1e300, 1e300]).unwrap();
}

/// A base with two prismatic branches along x: `a` (s1) and `b` (s2, placed at x = 1e308, so
/// `q_s2 = 1e308` overflows b's placement); the model and the two links' frames.
fn two_prismatic_branches() -> (Model, FrameId, FrameId) {
    let model = Model::from_urdf_str(
        r#"<robot name="r"><link name="base"/><link name="a"/><link name="b"/>
           <joint name="s1" type="prismatic"><parent link="base"/><child link="a"/>
             <axis xyz="1 0 0"/><limit lower="-1e308" upper="1e308" effort="1" velocity="1"/></joint>
           <joint name="s2" type="prismatic"><parent link="base"/><child link="b"/>
             <origin xyz="1e308 0 0"/>
             <axis xyz="1 0 0"/><limit lower="-1e308" upper="1e308" effort="1" velocity="1"/></joint>
           </robot>"#,
        RootJoint::Fixed,
    )
    .unwrap();
    let (a, b) = (
        FrameId::find(&model, "a").unwrap(),
        FrameId::find(&model, "b").unwrap(),
    );
    (model, a, b)
}

/// `compute_frame_jacobian` places only the frame's body and its ancestors: an overflow on another
/// branch is not its concern, an overflow on the path is, and neither leaves stale state behind.
#[test]
fn frame_jacobian_overflow_only_on_the_frames_path() {
    use kinetree_kinematics::spatial::Motion;
    use kinetree_kinematics::{ReferenceFrame, compute_frame_jacobian};
    let (model, a, b) = two_prismatic_branches();
    let mut data = KinematicsData::new(&model);
    let mut jac = vec![Motion::ZERO; 2];
    // b at 1e308 + 1e308 overflows; a's Jacobian does not depend on it.
    let q = [0.5, 1e308];
    compute_frame_jacobian(&model, &mut data, &q, a, ReferenceFrame::World, &mut jac).unwrap();
    assert_eq!(jac[0].linear.to_array(), [1.0, 0.0, 0.0]);
    assert_eq!(jac[1], Motion::ZERO);
    assert_eq!(data.world_from(a).unwrap().translation.x, 0.5);
    match compute_frame_jacobian(&model, &mut data, &q, b, ReferenceFrame::World, &mut jac) {
        Err(e @ KinematicsError::Overflow { .. }) => assert!(e.to_string().contains("'b'"), "{e}"),
        other => panic!("expected Overflow naming b, got {other:?}"),
    }
    // The overflowed placement of b, left in the data, does not fail a later call for a.
    compute_frame_jacobian(&model, &mut data, &q, a, ReferenceFrame::World, &mut jac).unwrap();
    assert_eq!(jac[0].linear.to_array(), [1.0, 0.0, 0.0]);
}

/// The batched FK and Jacobian report the first state whose placements overflow with the
/// one-state error, on every instruction set, and keep `compute_frame_jacobian`'s rule that only
/// the frame's path matters.
#[test]
fn a_batch_names_the_first_state_that_overflows() {
    use kinetree_kinematics::batch::{
        KinematicsBatch, Simd, forward_kinematics_batch, frame_jacobian_batch,
    };
    use kinetree_kinematics::spatial::{Motion, Se3};
    use kinetree_kinematics::{ReferenceFrame, compute_frame_jacobian};
    let (model, a, b) = two_prismatic_branches();
    let n = 19;
    let mut q: Vec<f64> = (0..2 * n).map(|i| 0.1 * i as f64).collect();
    // States 10 and 13 put b at 1e308 + 1e308.
    q[2 * 10 + 1] = 1e308;
    q[2 * 13 + 1] = 1e308;
    let mut data = KinematicsData::new(&model);
    let mut one = vec![Motion::ZERO; 2];
    for simd in [Simd::Portable, Simd::Avx2, Simd::Avx512] {
        let mut batch = KinematicsBatch::with_simd(&model, simd);
        let mut links = vec![Se3::IDENTITY; n * model.links().len()];
        match forward_kinematics_batch(&model, &mut batch, &q, &mut links, None) {
            Err(KinematicsError::InBatchState { index: 10, source }) => {
                assert!(
                    matches!(*source, KinematicsError::Overflow { .. }),
                    "{simd:?}: {source:?}"
                );
                assert!(source.to_string().contains("'b'"), "{simd:?}: {source}");
            }
            other => panic!("{simd:?}: expected state 10 to overflow, got {other:?}"),
        }
        let mut jac = vec![Motion::ZERO; 2 * n];
        // b's columns are its axis, finite; its placement is not, which the one-state call
        // reports.
        match frame_jacobian_batch(&model, &mut batch, &q, b, ReferenceFrame::World, &mut jac) {
            Err(KinematicsError::InBatchState { index: 10, source }) => {
                assert!(source.to_string().contains("'b'"), "{simd:?}: {source}");
            }
            other => panic!("{simd:?}: expected state 10 to overflow, got {other:?}"),
        }
        // a's Jacobian does not depend on b: every state is fine and equals the one-state call.
        frame_jacobian_batch(&model, &mut batch, &q, a, ReferenceFrame::World, &mut jac).unwrap();
        for k in 0..n {
            let qk = &q[2 * k..2 * k + 2];
            compute_frame_jacobian(&model, &mut data, qk, a, ReferenceFrame::World, &mut one)
                .unwrap();
            assert_eq!(&jac[2 * k..2 * k + 2], &one[..], "{simd:?} state {k}");
        }
    }
}

/// The batched FK and Jacobian accept and refuse a quaternion near the tolerance exactly as the
/// one-state functions do, on every instruction set.
#[test]
fn a_batch_checks_quaternions_as_the_one_state_call() {
    use kinetree_kinematics::batch::{
        KinematicsBatch, Simd, forward_kinematics_batch, frame_jacobian_batch,
    };
    use kinetree_kinematics::spatial::{Motion, Se3};
    use kinetree_kinematics::{ReferenceFrame, compute_frame_jacobian};
    let model = floating_ball();
    let (nq, nl, nv) = (model.nq(), model.links().len(), model.nv());
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let unit = [
        0.1, 0.2, 0.3, 0.0, 0.0, s, s, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    // Scaled by 1 + f·tol: the norm is 1 + f·tol, accepted for f < 1 and refused beyond.
    let scaled = |root: f64, ball: f64| {
        let mut q = unit;
        for x in &mut q[3..7] {
            *x *= 1.0 + root * QUATERNION_NORM_TOLERANCE;
        }
        for x in &mut q[10..14] {
            *x *= 1.0 + ball * QUATERNION_NORM_TOLERANCE;
        }
        q
    };
    let hand = FrameId::find(&model, "hand").unwrap();
    let mut data = KinematicsData::new(&model);
    let mut one = vec![Motion::ZERO; nv];
    for simd in [Simd::Portable, Simd::Avx2, Simd::Avx512] {
        let mut batch = KinematicsBatch::with_simd(&model, simd);
        // Accepted: norms inside the tolerance, on either side of the fast test's 0.95·tol.
        let fine = [scaled(0.0, 0.0), scaled(0.9, -0.99), scaled(-0.99, 0.97)].concat();
        let n = 3;
        let mut links = vec![Se3::IDENTITY; n * nl];
        forward_kinematics_batch(&model, &mut batch, &fine, &mut links, None).unwrap();
        let mut jac = vec![Motion::ZERO; n * nv];
        frame_jacobian_batch(
            &model,
            &mut batch,
            &fine,
            hand,
            ReferenceFrame::World,
            &mut jac,
        )
        .unwrap();
        for k in 0..n {
            let qk = &fine[k * nq..(k + 1) * nq];
            forward_kinematics(&model, &mut data, qk).unwrap();
            assert_eq!(
                &links[k * nl..(k + 1) * nl],
                data.world_from_link(),
                "{simd:?} {k}"
            );
            compute_frame_jacobian(&model, &mut data, qk, hand, ReferenceFrame::World, &mut one)
                .unwrap();
            assert_eq!(&jac[k * nv..(k + 1) * nv], &one[..], "{simd:?} {k}");
        }
        // Refused: the ball joint of state 2 just beyond the tolerance (state 1 is fine).
        let bad = [scaled(0.0, 0.0), scaled(0.5, 0.5), scaled(0.0, 1.01)].concat();
        for result in [
            forward_kinematics_batch(&model, &mut batch, &bad, &mut links, None),
            frame_jacobian_batch(
                &model,
                &mut batch,
                &bad,
                hand,
                ReferenceFrame::World,
                &mut jac,
            ),
        ] {
            match result {
                Err(KinematicsError::InBatchState { index: 2, source }) => match *source {
                    KinematicsError::NonUnitQuaternion { joint, norm } => {
                        assert_eq!(joint, "ball", "{simd:?}");
                        assert!((norm - 1.0 - 1.01 * QUATERNION_NORM_TOLERANCE).abs() < 1e-12);
                    }
                    other => panic!("{simd:?}: expected NonUnitQuaternion, got {other:?}"),
                },
                other => panic!("{simd:?}: expected state 2 to be refused, got {other:?}"),
            }
        }
    }
}

#[test]
fn integrate_and_interpolate_refuse_results_too_large_for_f64() {
    use kinetree_kinematics::configuration::interpolate;
    let model = floating_ball();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let q0 = [
        0.0, 0.0, 0.0, 0.0, 0.0, s, s, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let mut out = vec![0.0; 14];
    // 1e154 on the free root: its exponential map squares the velocity (NaN before).
    let mut v = [0.0; 12];
    v[..6].fill(1e154);
    match integrate(&model, &q0, &v, &mut out) {
        Err(KinematicsError::Overflow {
            what: "configuration",
            body,
        }) => assert_eq!(body, "base"),
        other => panic!("expected Overflow, got {other:?}"),
    }
    // The ball joint's own block is named by its body.
    v[..6].fill(0.0);
    v[6..].fill(1e154);
    match integrate(&model, &q0, &v, &mut out) {
        Err(KinematicsError::Overflow { body, .. }) => assert_eq!(body, "arm"),
        other => panic!("expected Overflow, got {other:?}"),
    }
    // A large but representable step is integrated: a pure translation of 1e150 along x.
    let mut v = [0.0; 12];
    v[0] = 1e150;
    integrate(&model, &q0, &v, &mut out).unwrap();
    assert!(out.iter().all(|x| x.is_finite()), "{out:?}");
    // Interpolation: a fraction too large for the distance overflows; NaN is refused up front.
    let mut q1 = q0;
    q1[0] = 1e10;
    match interpolate(&model, &q0, &q1, 1e300, &mut out) {
        Err(KinematicsError::Overflow {
            what: "configuration",
            body,
        }) => assert_eq!(body, "base"),
        other => panic!("expected Overflow, got {other:?}"),
    }
    assert!(matches!(
        interpolate(&model, &q0, &q1, f64::NAN, &mut out),
        Err(KinematicsError::NonFinite { what: "t", .. })
    ));
    interpolate(&model, &q0, &q1, 0.5, &mut out).unwrap();
    assert!((out[0] - 5e9).abs() < 1e-3, "{}", out[0]);
}
