//! Inverse kinematics on joints about and along the coordinate axes: the solver's specialised
//! forward pass, Jacobian columns and additive step.

use crate::ik::{errors, params, pose_at};
use glam::DVec3;
use kinetree_kinematics::configuration::{
    is_within_limits, neutral_configuration, random_configuration,
};
use kinetree_kinematics::ik::{IkSolver, IkTarget};
use kinetree_kinematics::model::{JointKind, JointLimits, JointSpec, Link, ModelBuilder};
use kinetree_kinematics::spatial::Se3;
use kinetree_kinematics::{FrameId, KinematicsData};
use rand::SeedableRng;
use rand::rngs::SmallRng;
use std::f64::consts::FRAC_PI_2;

/// Revolute, continuous and prismatic joints about or along x, y and z, placed with no rotation,
/// a rotation about one axis and a general one, ending in a cylindrical joint: random reachable
/// targets from random starts converge within the limits.
#[test]
fn coordinate_axis_joints_with_every_placement_form() {
    let mut b = ModelBuilder::new("axes");
    b.add_link(Link::new("l0"));
    let joints = [
        (JointKind::Revolute, DVec3::Z, [0.0, 0.0, 0.0]),
        (JointKind::Prismatic, DVec3::X, [-FRAC_PI_2, 0.0, 0.0]),
        (JointKind::Revolute, DVec3::Y, [0.0, 0.0, 0.0]),
        (JointKind::Continuous, DVec3::X, [0.0, FRAC_PI_2, 0.0]),
        (JointKind::Prismatic, DVec3::Z, [0.3, 0.2, 0.1]),
        (JointKind::Revolute, DVec3::Z, [FRAC_PI_2, 0.0, 0.0]),
        (JointKind::Revolute, DVec3::X, [0.0, 0.0, 0.4]),
        (JointKind::Cylindrical, DVec3::Y, [0.0, 0.0, 0.0]),
    ];
    for (i, (kind, axis, rpy)) in joints.iter().enumerate() {
        b.add_link(Link::new(format!("l{}", i + 1)));
        b.add_joint(
            JointSpec::new(
                format!("j{}", i + 1),
                *kind,
                format!("l{i}"),
                format!("l{}", i + 1),
            )
            .with_axis(*axis)
            .with_limits(JointLimits::position(-1.5, 2.0))
            .with_placement(Se3::from_xyz_rpy([0.1, 0.25, 0.05 * i as f64], *rpy)),
        );
    }
    let model = b.build().unwrap();
    let tip = FrameId::find(&model, "l8").unwrap();
    let mut solver = IkSolver::new(&model, params());
    let mut data = KinematicsData::new(&model);
    let mut rng = SmallRng::seed_from_u64(4);
    let mut q = neutral_configuration(&model);
    for _ in 0..20 {
        random_configuration(&model, &mut rng, &mut q).unwrap();
        let goal = pose_at(&model, tip, &q);
        random_configuration(&model, &mut rng, &mut q).unwrap();
        let report = solver
            .solve(&model, &mut data, &IkTarget::new(tip, goal), &q)
            .unwrap();
        assert!(report.is_converged(), "{:?}", report.status);
        let (p, o) = errors(&model, tip, report.q, &goal);
        assert!(p < 1e-6 && o < 1e-5, "{p} {o}");
        assert!(is_within_limits(&model, report.q, 0.0).unwrap());
    }
}
