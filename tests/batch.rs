//! The facade's batch evaluator through its typed request and response: hand-worked values on a
//! planar two-link arm, and typed per-sample errors.

use kinetree::batch::{BatchOptions, JointValue, NamedValues, SampleInput, evaluate};
use kinetree::kinematics::KinematicsError;
use kinetree::model::samples;
use std::f64::consts::FRAC_PI_2;

const L1: f64 = 0.3;
const L2: f64 = 0.2;

fn named(values: &[(&str, f64)]) -> NamedValues {
    values
        .iter()
        .map(|(n, x)| ((*n).to_string(), JointValue::Scalar(*x)))
        .collect()
}

#[test]
fn poses_jacobians_and_dynamics_of_a_planar_arm() {
    let model = samples::planar_2r(L1, L2);
    let sample = SampleInput {
        q: Some(named(&[("joint1", FRAC_PI_2), ("joint2", 0.0)])),
        v: Some(named(&[("joint1", 1.0), ("joint2", 0.0)])),
        ..SampleInput::default()
    };
    let options = BatchOptions {
        jacobians: vec!["tool".into()],
        ..BatchOptions::default()
    };
    let out = evaluate(&model, &[sample], &options).unwrap();
    assert_eq!(
        (out.model.nq, out.model.nv, out.model.joints.len()),
        (2, 2, 2)
    );
    assert_eq!(out.model.joints[1].name, "joint2");
    assert_eq!(out.model.joints[1].kind, "revolute");
    let s = &out.samples[0];
    // Turned 90° about z: link2's origin sits at (0, l1, 0) and its x axis along world y.
    let link2 = s.link_poses["link2"];
    for (got, want) in link2.translation.iter().zip([0.0, L1, 0.0]) {
        assert!((got - want).abs() < 1e-15, "{link2:?}");
    }
    assert!((link2.rotation[1][0] - 1.0).abs() < 1e-15);
    // The tool at p = (0, l1 + l2, 0): column k is [z × (p - o_k); z], rows [linear; angular].
    let j = &s.jacobians["tool"];
    let expected = [
        [-(L1 + L2), -L2],
        [0.0, 0.0],
        [0.0, 0.0],
        [0.0, 0.0],
        [0.0, 0.0],
        [1.0, 1.0],
    ];
    for (row, want) in j.iter().zip(expected) {
        for (got, want) in row.iter().zip(want) {
            assert!((got - want).abs() < 1e-15, "{j:?}");
        }
    }
    // Two 1 kg rods turning about the vertical: no gravity torque; v given, so nle and energy,
    // but no a or tau, so no rnea or aba.
    let d = s.dynamics.as_ref().unwrap();
    assert_eq!(d.moving_mass, 2.0);
    assert!(d.gravity_torque.iter().all(|g| g.abs() < 1e-12));
    assert!(d.nle.is_some() && d.kinetic_energy.unwrap() > 0.0);
    assert!(d.rnea.is_none() && d.aba.is_none());
    assert_eq!(
        d.by_joint.keys().copied().collect::<Vec<_>>(),
        ["gravity_torque", "nle"]
    );
    assert!(d.errors.is_empty());
}

#[test]
fn sample_errors_name_the_sample_and_keep_the_layer_error() {
    let model = samples::planar_2r(L1, L2);
    let good = SampleInput::default();
    let partial = SampleInput {
        q: Some(named(&[("joint1", 0.1)])),
        ..SampleInput::default()
    };
    // By default a joint left out is neutral: both samples evaluate.
    let out = evaluate(
        &model,
        &[good.clone(), partial.clone()],
        &BatchOptions::default(),
    );
    assert_eq!(out.unwrap().samples.len(), 2);
    // Strict: the second sample lacks joint2.
    let strict = BatchOptions {
        strict: true,
        ..BatchOptions::default()
    };
    let full = SampleInput {
        q: Some(named(&[("joint1", 0.1), ("joint2", 0.2)])),
        ..SampleInput::default()
    };
    match evaluate(&model, &[full, partial], &strict) {
        Err(kinetree::Error::Sample { index: 1, source }) => assert!(matches!(
            *source,
            kinetree::Error::Kinematics(KinematicsError::MissingJointValue { ref joint, space: "q" })
                if joint == "joint2"
        )),
        other => panic!("expected a sample error, got {:?}", other.err()),
    }
    let unknown = SampleInput {
        v: Some(named(&[("elbow", 0.1)])),
        ..SampleInput::default()
    };
    match evaluate(&model, &[good, unknown], &BatchOptions::default()) {
        Err(kinetree::Error::Sample { index: 1, source }) => assert!(matches!(
            *source,
            kinetree::Error::Kinematics(KinematicsError::UnknownJoint { ref name }) if name == "elbow"
        )),
        other => panic!("expected a sample error, got {:?}", other.err()),
    }
}

#[test]
fn named_frames_poses_are_reported_when_asked_for() {
    use kinetree::batch::FrameSelection;
    let model = samples::planar_2r(L1, L2);
    let sample = SampleInput {
        q: Some(named(&[("joint1", FRAC_PI_2), ("joint2", -FRAC_PI_2)])),
        ..SampleInput::default()
    };
    // By default, links only.
    let out = evaluate(
        &model,
        std::slice::from_ref(&sample),
        &BatchOptions::default(),
    )
    .unwrap();
    assert!(out.samples[0].frame_poses.is_empty());
    // Every named frame: the tool at (l2, l1, 0), its x axis back along world x.
    for frames in [
        FrameSelection::All,
        FrameSelection::Named(vec!["tool".into()]),
    ] {
        let options = BatchOptions {
            frames,
            ..BatchOptions::default()
        };
        let out = evaluate(&model, std::slice::from_ref(&sample), &options).unwrap();
        let poses = &out.samples[0].frame_poses;
        assert_eq!(poses.keys().collect::<Vec<_>>(), ["tool"]);
        let tool = poses["tool"];
        for (got, want) in tool.translation.iter().zip([L2, L1, 0.0]) {
            assert!((got - want).abs() < 1e-15, "{tool:?}");
        }
        assert!((tool.rotation[0][0] - 1.0).abs() < 1e-15, "{tool:?}");
    }
    // An unknown frame is an error naming it.
    let options = BatchOptions {
        frames: FrameSelection::Named(vec!["nope".into()]),
        ..BatchOptions::default()
    };
    let e = evaluate(&model, &[sample], &options).unwrap_err();
    assert!(e.to_string().contains("nope"), "{e}");
}
