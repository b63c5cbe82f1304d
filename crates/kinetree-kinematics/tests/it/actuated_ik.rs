//! trip_kinematics' ways through actuation groups: mappings with runtime arguments, and inverse
//! kinematics answered in actuated coordinates.

use glam::DVec3;
use kinetree_kinematics::ik::{IkParams, IkSolver, IkTarget};
use kinetree_kinematics::model::samples;
use kinetree_kinematics::{
    ActuatedChain, ActuationArgs, ActuationGroup, ArgActuation, Chain, FnActuation, FrameId,
    GroupSpec, KinematicsError,
};

/// A differential: `joint1 = (m1 + m2) / 2`, `joint2 = (m1 - m2) / 2`.
fn differential_arm() -> ActuatedChain {
    let arm = samples::planar_2r(0.3, 0.2);
    let diff = ActuationGroup::new(
        &arm,
        GroupSpec::new("diff", ["m1", "m2"], ["joint1", "joint2"], [0.0, 0.0]),
        FnActuation::new(
            |m: &[f64], q: &mut Vec<f64>| q.extend([(m[0] + m[1]) / 2.0, (m[0] - m[1]) / 2.0]),
            |q: &[f64], m: &mut Vec<f64>| m.extend([q[0] + q[1], q[0] - q[1]]),
        ),
    )
    .unwrap();
    ActuatedChain::new(Chain::new(arm), vec![diff]).unwrap()
}

#[test]
fn inverse_kinematics_answers_in_actuated_coordinates() {
    let mut robot = differential_arm();
    let model = robot.chain().model().clone();
    let tool = FrameId::find(&model, "tool").unwrap();
    // A reachable point, by hand: q = (0.4, 0.9).
    let (q1, q2) = (0.4f64, 0.9f64);
    let goal = DVec3::new(
        0.3 * q1.cos() + 0.2 * (q1 + q2).cos(),
        0.3 * q1.sin() + 0.2 * (q1 + q2).sin(),
        0.0,
    );
    robot.set_actuated_state(&[0.3, 0.1]).unwrap();
    // No time budget: the result must not depend on the machine's load.
    let params = IkParams {
        time_budget: None,
        ..IkParams::default()
    };
    let mut solver = IkSolver::new(&model, params);
    let report = robot
        .solve_ik(&mut solver, &IkTarget::position(tool, goal))
        .unwrap();
    assert!(report.position_error < 1e-6, "{report:?}");
    assert_eq!(report.actuated, robot.actuated_state());
    // The actuated values are the differential's inverse of the joint values reached.
    let q = robot.chain().q().to_vec();
    assert!((report.actuated[0] - (q[0] + q[1])).abs() < 1e-12);
    assert!((report.actuated[1] - (q[0] - q[1])).abs() < 1e-12);
    // Driving a fresh robot with them puts the tool on the goal.
    let mut fresh = differential_arm();
    fresh.set_actuated_state(&report.actuated).unwrap();
    let tip = fresh.world_from("tool").unwrap().translation;
    assert!((tip - goal).length() < 1e-6, "{tip} vs {goal}");
}

#[test]
fn mapping_arguments_change_at_run_time() {
    let arm = samples::planar_2r(0.3, 0.2);
    // A rod of adjustable length pushes joint1: angle = asin(extension / length).
    let rod = ActuationArgs::new([0.1]);
    let group = ActuationGroup::new(
        &arm,
        GroupSpec::new("rod", ["extension"], ["joint1"], [0.05]),
        ArgActuation::new(
            rod.clone(),
            |len: &[f64], e: &[f64], q: &mut Vec<f64>| q.push((e[0] / len[0]).asin()),
            |len: &[f64], q: &[f64], e: &mut Vec<f64>| e.push(q[0].sin() * len[0]),
        ),
    )
    .unwrap();
    let mut robot = ActuatedChain::new(Chain::new(arm), vec![group]).unwrap();
    robot.set_actuated("extension", 0.05).unwrap();
    assert!((robot.chain().q()[0] - (0.5f64).asin()).abs() < 1e-15);
    rod.set(&[0.2]);
    assert_eq!(rod.get(), [0.2]);
    robot.remap().unwrap();
    assert_eq!(robot.actuated("extension").unwrap(), 0.05);
    assert!((robot.chain().q()[0] - (0.25f64).asin()).abs() < 1e-15);
    // An argument that puts the state out of the mapping's domain is an error; nothing moves.
    rod.set(&[0.01]);
    let e = robot.remap().unwrap_err();
    assert!(matches!(e, KinematicsError::MappingNonFinite { .. }), "{e}");
    assert!((robot.chain().q()[0] - (0.25f64).asin()).abs() < 1e-15);
}
