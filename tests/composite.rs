//! Composite joints (trip_kinematics' `Transformation`): forward kinematics against the product
//! of the factors by hand, the Jacobian against finite differences, dynamics identities, inverse
//! kinematics, configuration-space operations on a ball factor, and a JSON round trip.

use glam::DVec3;
use kinetree::dynamics::{DynamicsData, aba, crba, rnea};
use kinetree::kinematics::ik::{IkParams, IkSolver, IkTarget};
use kinetree::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, configuration,
    forward_kinematics,
};
use kinetree::model::composite::{Axis, CompositeJointSpec, Factor};
use kinetree::model::{JointLimits, JsonOptions, Link, Model, ModelBuilder, RootJoint};
use kinetree::spatial::{Motion, Se3, Symmetric3};
use rand::SeedableRng;
use rand::rngs::SmallRng;

fn body(name: &str) -> Link {
    Link::new(name).with_mass(
        1.5,
        DVec3::new(0.05, 0.1, -0.2),
        Symmetric3::new(0.03, 0.001, 0.0, 0.04, 0.002, 0.02),
    )
}

/// pelvis —hip: tx 0.1, ry, rz, tz -0.05 → thigh —knee: ball, tz 0.3 (constant) → shank.
fn leg() -> Model {
    let mut b = ModelBuilder::new("leg");
    b.add_link(body("pelvis"))
        .add_link(body("thigh"))
        .add_link(body("shank"));
    b.add_composite(
        CompositeJointSpec::new(
            "hip",
            "pelvis",
            "thigh",
            [
                Factor::Translate(Axis::X, Some(0.1)),
                Factor::Rotate(Axis::Y, None),
                Factor::Rotate(Axis::Z, None),
                Factor::Translate(Axis::Z, Some(-0.05)),
            ],
        )
        .with_placement(Se3::from_translation(DVec3::new(0.0, 0.2, 0.0)))
        .with_limits([
            JointLimits::position(-2.0, 2.0),
            JointLimits::position(-1.5, 1.5),
        ]),
    );
    b.add_composite(CompositeJointSpec::new(
        "knee",
        "thigh",
        "shank",
        [
            Factor::Ball,
            Factor::Translate(Axis::Z, Some(0.3)),
            Factor::Translate(Axis::Y, None),
        ],
    ));
    b.root_joint(RootJoint::Fixed);
    b.build().unwrap()
}

/// The shank's pose from the factors, by hand.
fn shank_by_hand(ry: f64, rz: f64, quat: glam::DQuat, ty: f64) -> Se3 {
    Se3::from_translation(DVec3::new(0.0, 0.2, 0.0))
        * Se3::from_translation(DVec3::new(0.1, 0.0, 0.0))
        * Se3::from_rotation_y(ry)
        * Se3::from_rotation_z(rz)
        * Se3::from_translation(DVec3::new(0.0, 0.0, -0.05))
        * Se3::from_quat(quat)
        * Se3::from_translation(DVec3::new(0.0, 0.0, 0.3))
        * Se3::from_translation(DVec3::new(0.0, ty, 0.0))
}

fn random_q(model: &Model, seed: u64) -> Vec<f64> {
    let mut q = vec![0.0; model.nq()];
    configuration::random_configuration(model, &mut SmallRng::seed_from_u64(seed), &mut q).unwrap();
    q
}

#[test]
fn the_state_variables_are_the_joints_coordinates() {
    let m = leg();
    // hip: ry, rz; knee: a quaternion and ty.
    assert_eq!((m.nq(), m.nv()), (2 + 4 + 1, 2 + 3 + 1));
    for name in ["hip.ry", "hip.rz", "knee.ball", "knee.ty"] {
        assert!(m.joint_index(name).is_some(), "no {name}");
    }
    let ry = m.joint(m.joint_index("hip.ry").unwrap());
    assert_eq!((ry.limits.lower, ry.limits.upper), (-2.0, 2.0));
}

#[test]
fn forward_kinematics_is_the_product_of_the_factors() {
    let m = leg();
    let shank = FrameId::find(&m, "shank").unwrap();
    let mut data = KinematicsData::new(&m);
    for seed in 0..20 {
        let q = random_q(&m, seed);
        forward_kinematics(&m, &mut data, &q).unwrap();
        let quat = glam::DQuat::from_xyzw(q[2], q[3], q[4], q[5]).normalize();
        let want = shank_by_hand(q[0], q[1], quat, q[6]);
        let got = data.world_from(shank).unwrap();
        assert!(
            (got.translation - want.translation).length() < 1e-14,
            "{got:?} vs {want:?}"
        );
        assert!(got.rotation.abs_diff_eq(want.rotation, 1e-14));
    }
}

#[test]
fn the_jacobian_matches_finite_differences() {
    let m = leg();
    let shank = FrameId::find(&m, "shank").unwrap();
    let mut data = KinematicsData::new(&m);
    let q = random_q(&m, 7);
    let mut jac = vec![Motion::ZERO; m.nv()];
    compute_frame_jacobian(
        &m,
        &mut data,
        &q,
        shank,
        ReferenceFrame::LocalWorldAligned,
        &mut jac,
    )
    .unwrap();
    let position = |q: &[f64], data: &mut KinematicsData| {
        forward_kinematics(&m, data, q).unwrap();
        data.world_from(shank).unwrap().translation
    };
    let h = 1e-6;
    for (k, column) in jac.iter().enumerate() {
        let mut dv = vec![0.0; m.nv()];
        let (mut qp, mut qm) = (q.clone(), q.clone());
        dv[k] = h;
        configuration::integrate(&m, &q, &dv, &mut qp).unwrap();
        dv[k] = -h;
        configuration::integrate(&m, &q, &dv, &mut qm).unwrap();
        let fd = (position(&qp, &mut data) - position(&qm, &mut data)) / (2.0 * h);
        assert!(
            (fd - column.linear).length() < 1e-8,
            "column {k}: {fd} vs {}",
            column.linear
        );
    }
}

#[test]
fn dynamics_are_consistent() {
    let m = leg();
    let mut data = DynamicsData::new(&m);
    let q = random_q(&m, 3);
    let v: Vec<f64> = (0..m.nv()).map(|i| 0.3 - 0.1 * i as f64).collect();
    let a: Vec<f64> = (0..m.nv()).map(|i| 0.5 * i as f64 - 1.0).collect();
    let tau = rnea(&m, &mut data, &q, &v, &a).unwrap().to_vec();
    let back = aba(&m, &mut data, &q, &v, &tau).unwrap();
    for (x, y) in back.iter().zip(&a) {
        assert!((x - y).abs() < 1e-9, "{back:?} vs {a:?}");
    }
    // The mass matrix is symmetric with a positive diagonal.
    let n = m.nv();
    let mass = crba(&m, &mut data, &q).unwrap();
    for i in 0..n {
        assert!(mass[i * n + i] > 0.0);
        for j in 0..n {
            assert!((mass[i * n + j] - mass[j * n + i]).abs() < 1e-12);
        }
    }
}

#[test]
fn inverse_kinematics_reaches_a_pose_of_the_composite_chain() {
    let m = leg();
    let shank = FrameId::find(&m, "shank").unwrap();
    let goal_q = random_q(&m, 11);
    let mut data = KinematicsData::new(&m);
    forward_kinematics(&m, &mut data, &goal_q).unwrap();
    let goal = *data.world_from(shank).unwrap();
    let mut solver = IkSolver::new(&m, IkParams::default());
    let start = configuration::neutral_configuration(&m);
    let report = solver
        .solve(&m, &mut data, &IkTarget::new(shank, goal), &start)
        .unwrap();
    assert!(report.position_error < 1e-6, "{report:?}");
    assert!(report.orientation_error < 1e-6, "{report:?}");
}

#[test]
fn configuration_operations_and_a_json_round_trip_handle_composite_joints() {
    let m = leg();
    let (q0, q1) = (random_q(&m, 1), random_q(&m, 2));
    let mut v = vec![0.0; m.nv()];
    configuration::difference(&m, &q0, &q1, &mut v).unwrap();
    let mut back = vec![0.0; m.nq()];
    configuration::integrate(&m, &q0, &v, &mut back).unwrap();
    let mut rest = vec![0.0; m.nv()];
    configuration::difference(&m, &q1, &back, &mut rest).unwrap();
    assert!(rest.iter().all(|x| x.abs() < 1e-12), "{rest:?}");
    // Through JSON (written as its elementary joints): the same coordinates, the same poses.
    let json = m.to_json_string(&JsonOptions::default()).unwrap();
    let again = Model::from_json_str(&json, None::<RootJoint>).unwrap();
    assert_eq!(again.nq(), m.nq());
    let shank = FrameId::find(&m, "shank").unwrap();
    let (mut d0, mut d1) = (KinematicsData::new(&m), KinematicsData::new(&again));
    forward_kinematics(&m, &mut d0, &q1).unwrap();
    forward_kinematics(&again, &mut d1, &q1).unwrap();
    let (a, b) = (d0.world_from(shank).unwrap(), d1.world_from(shank).unwrap());
    assert!((a.translation - b.translation).length() < 1e-12);
}

#[test]
fn a_composite_of_constants_only_is_a_fixed_joint() {
    let mut b = ModelBuilder::new("weld");
    b.add_link(Link::new("a")).add_link(body("b"));
    b.add_composite(CompositeJointSpec::new(
        "w",
        "a",
        "b",
        [
            Factor::Rotate(Axis::Z, Some(std::f64::consts::FRAC_PI_2)),
            Factor::Translate(Axis::X, Some(1.0)),
        ],
    ));
    let m = b.build().unwrap();
    assert_eq!(m.nq(), 0);
    let mut data = KinematicsData::new(&m);
    forward_kinematics(&m, &mut data, &[]).unwrap();
    let p = data.world_from(FrameId::find(&m, "b").unwrap()).unwrap();
    assert!((p.translation - DVec3::new(0.0, 1.0, 0.0)).length() < 1e-15);
    // An unknown parent is reported by the builder, naming it.
    let mut bad = ModelBuilder::new("bad");
    bad.add_link(Link::new("b"));
    bad.add_composite(CompositeJointSpec::new(
        "j",
        "nowhere",
        "b",
        [Factor::Rotate(Axis::X, None)],
    ));
    let e = bad.build().unwrap_err().to_string();
    assert!(e.contains("nowhere"), "{e}");
}
