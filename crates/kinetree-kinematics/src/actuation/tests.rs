//! Unit tests of the actuation groups.

use super::*;
use crate::chain::Chain;
use crate::data::KinematicsData;
use crate::error::{GroupProblem, KinematicsError};
use crate::{FrameId, forward_kinematics, update_frame_placements};
use glam::DVec3;
use kinetree_model::spatial::Se3;
use kinetree_model::{FrameSpec, JointLimits, JointSpec, Link, ModelBuilder};
use kinetree_model::{JointKind, Model};
use std::f64::consts::FRAC_PI_6;

/// A thigh with a knee 1 m up, axis z, limits ±1.2 rad, and a foot frame 0.5 m along the shank.
fn leg() -> Model {
    let mut b = ModelBuilder::new("leg");
    b.add_link(Link::new("thigh"));
    b.add_part(
        Link::new("shank"),
        JointSpec::new("knee", JointKind::Revolute, "thigh", "shank")
            .with_placement(Se3::from_translation(DVec3::new(0.0, 0.0, 1.0)))
            .with_limits(JointLimits::position(-1.2, 1.2)),
    );
    b.add_frame(FrameSpec::new(
        "foot",
        "shank",
        Se3::from_translation(DVec3::new(0.5, 0.0, 0.0)),
    ));
    b.build().unwrap()
}

const PARENT_ANCHOR: DVec3 = DVec3::new(0.0, -0.4, 1.0);
const CHILD_ANCHOR: DVec3 = DVec3::new(0.1, 0.0, 0.0);

fn knee_group(model: &Model) -> ActuationGroup {
    let actuator = LinearActuator::new(model, "knee", PARENT_ANCHOR, CHILD_ANCHOR).unwrap();
    let spec = GroupSpec::new("knee_drive", ["knee_actuator"], ["knee"], [0.42]);
    ActuationGroup::new(model, spec, actuator).unwrap()
}

#[test]
fn linear_actuator_matches_the_law_of_cosines_by_hand() {
    let model = leg();
    let act = LinearActuator::new(&model, "knee", PARENT_ANCHOR, CHILD_ANCHOR).unwrap();
    // In the knee frame the anchors are (0, -0.4, 0) and (0.1, 0, 0): radii 0.4 and 0.1, no
    // axial offset, β = 90°, so s² = 0.17 − 0.08·cos(θ + 90°) = 0.17 + 0.08·sin θ.
    for theta in [-1.2, -0.5, 0.0, FRAC_PI_6, 1.1] {
        let by_hand = (0.17 + 0.08 * f64::sin(theta)).sqrt();
        assert!((act.length(theta) - by_hand).abs() < 1e-15, "θ = {theta}");
        // And back: θ = asin((s² − 0.17) / 0.08).
        assert!((act.angle(by_hand) - theta).abs() < 1e-12, "θ = {theta}");
    }
    let (lo, hi) = act.length_range();
    assert!((lo - 0.3).abs() < 1e-15 && (hi - 0.5).abs() < 1e-15);
    assert!(act.angle(0.29).is_nan() && act.angle(0.51).is_nan());
}

#[test]
fn linear_actuator_round_trips_and_drives_forward_kinematics() {
    let model = leg();
    let mut leg = ActuatedChain::new(Chain::new(model.clone()), vec![knee_group(&model)]).unwrap();
    assert_eq!(leg.actuator_names(), ["knee_actuator"]);
    // The group starts at its probe length.
    assert!((leg.actuated_state()[0] - 0.42).abs() < 1e-15);

    // Round trip actuated → virtual → actuated over the working stroke.
    let group = &leg.groups()[0];
    let mut v = Vec::new();
    let mut back = Vec::new();
    for k in 0..=20 {
        let s = 0.32 + 0.16 * f64::from(k) / 20.0;
        group.map.to_virtual(&[s], &mut v);
        group.map.to_actuated(&v, &mut back);
        assert!((back[0] - s).abs() < 1e-12, "s = {s}");
        v.clear();
        back.clear();
    }

    // 0.21 m² gives 30°: the foot is 0.5 m along a shank turned 30° about z, 1 m up.
    leg.set_actuated("knee_actuator", 0.21f64.sqrt()).unwrap();
    assert!((leg.chain().joint_value("knee").unwrap() - FRAC_PI_6).abs() < 1e-12);
    let foot = leg.world_from("foot").unwrap();
    let by_hand = DVec3::new(0.5 * FRAC_PI_6.cos(), 0.5 * FRAC_PI_6.sin(), 1.0);
    assert!((foot.translation - by_hand).length() < 1e-12);
    assert!(foot.abs_diff_eq(
        &Se3::new(Se3::from_rotation_z(FRAC_PI_6).rotation, by_hand),
        1e-12,
        1e-12
    ));
    // The anchors, placed by forward kinematics, are exactly one stroke apart.
    let shank = leg.world_from("shank").unwrap();
    let gap = shank.transform_point(CHILD_ANCHOR) - PARENT_ANCHOR;
    assert!((gap.length() - 0.21f64.sqrt()).abs() < 1e-12);

    // Setting the joint moves the actuator: at -30°, s² = 0.17 − 0.04.
    leg.set_joint_value("knee", -FRAC_PI_6).unwrap();
    assert!((leg.actuated("knee_actuator").unwrap() - 0.13f64.sqrt()).abs() < 1e-12);

    // A stroke the mechanism cannot reach is an error and changes nothing.
    let err = leg.set_actuated("knee_actuator", 0.6).unwrap_err();
    assert!(matches!(
        err,
        KinematicsError::MappingNonFinite { ref group, direction: MappingDirection::ActuatedToVirtual, index: 0 }
            if group == "knee_drive"
    ));
    assert!((leg.actuated("knee_actuator").unwrap() - 0.13f64.sqrt()).abs() < 1e-12);
    assert!((leg.chain().joint_value("knee").unwrap() + FRAC_PI_6).abs() < 1e-12);
}

#[test]
fn linear_actuator_length_is_the_anchor_distance_in_a_general_geometry() {
    // A tilted joint with an oblique axis and anchors off the pivot plane.
    let mut b = ModelBuilder::new("arm");
    b.add_link(Link::new("base"));
    b.add_part(
        Link::new("arm"),
        JointSpec::new("elbow", JointKind::Revolute, "base", "arm")
            .with_placement(Se3::from_xyz_rpy([0.2, -0.1, 0.5], [0.3, -0.2, 0.7]))
            .with_axis(DVec3::new(0.2, 0.3, 0.9))
            .with_limits(JointLimits::position(-0.8, 0.6)),
    );
    let model = b.build().unwrap();
    let (pa, ca) = (DVec3::new(0.1, 0.3, 0.2), DVec3::new(0.25, -0.05, 0.12));
    let act = LinearActuator::new(&model, "elbow", pa, ca).unwrap();
    let mut data = KinematicsData::new(&model);
    let arm = FrameId::find(&model, "arm").unwrap();
    for k in 0..=10 {
        let theta = -0.8 + 1.4 * f64::from(k) / 10.0;
        forward_kinematics(&model, &mut data, &[theta]).unwrap();
        let distance = (data.world_from(arm).unwrap().transform_point(ca) - pa).length();
        assert!((act.length(theta) - distance).abs() < 1e-12, "θ = {theta}");
        assert!((act.angle(distance) - theta).abs() < 1e-9, "θ = {theta}");
    }
}

#[test]
fn linear_actuator_rejects_bad_geometry() {
    let model = leg();
    assert!(matches!(
        LinearActuator::new(&model, "hip", PARENT_ANCHOR, CHILD_ANCHOR),
        Err(KinematicsError::UnknownJoint { name }) if name == "hip"
    ));
    // The child anchor on the knee axis.
    assert!(matches!(
        LinearActuator::new(&model, "knee", PARENT_ANCHOR, DVec3::new(0.0, 0.0, 0.3)),
        Err(KinematicsError::InvalidJointValue { joint, .. }) if joint == "knee"
    ));
    // In line with the pivot at θ = 0, the middle of the range.
    assert!(matches!(
        LinearActuator::new(&model, "knee", DVec3::new(-0.4, 0.0, 1.0), CHILD_ANCHOR),
        Err(KinematicsError::InvalidJointValue { joint, .. }) if joint == "knee"
    ));
    let mut b = ModelBuilder::new("slider");
    b.add_link(Link::new("a"));
    b.add_part(
        Link::new("b"),
        JointSpec::new("s", JointKind::Prismatic, "a", "b"),
    );
    assert!(matches!(
        LinearActuator::new(&b.build().unwrap(), "s", PARENT_ANCHOR, CHILD_ANCHOR),
        Err(KinematicsError::WrongJointKind {
            kind: JointKind::Prismatic,
            ..
        })
    ));
}

/// A forearm, a pitch joint (y) and a roll joint (x), then a finger on a prismatic joint.
fn wrist() -> Model {
    let mut b = ModelBuilder::new("wrist");
    b.add_link(Link::new("forearm"));
    b.add_part(
        Link::new("yoke"),
        JointSpec::new("pitch", JointKind::Revolute, "forearm", "yoke").with_axis(DVec3::Y),
    );
    b.add_part(
        Link::new("hand"),
        JointSpec::new("roll", JointKind::Revolute, "yoke", "hand")
            .with_axis(DVec3::X)
            .with_placement(Se3::from_translation(DVec3::new(0.05, 0.0, 0.0))),
    );
    b.add_part(
        Link::new("finger"),
        JointSpec::new("grip", JointKind::Prismatic, "hand", "finger").with_axis(DVec3::Y),
    );
    b.build().unwrap()
}

/// Bevel differential with a 2:1 output: pitch = (a + b) / 4, roll = (a − b) / 4.
fn differential() -> impl Actuation {
    FnActuation::new(
        |m: &[f64], j: &mut Vec<f64>| j.extend([(m[0] + m[1]) / 4.0, (m[0] - m[1]) / 4.0]),
        |j: &[f64], m: &mut Vec<f64>| m.extend([2.0 * (j[0] + j[1]), 2.0 * (j[0] - j[1])]),
    )
}

#[test]
fn differential_couples_two_motors_to_pitch_and_roll() {
    let model = wrist();
    let spec = GroupSpec::new(
        "wrist",
        ["motor_a", "motor_b"],
        ["pitch", "roll"],
        [0.0, 0.0],
    );
    let group = ActuationGroup::new(&model, spec, differential()).unwrap();
    let mut robot = ActuatedChain::new(Chain::new(model.clone()), vec![group]).unwrap();
    // The union: the group's motors, then the directly driven grip.
    assert_eq!(robot.actuator_names(), ["motor_a", "motor_b", "grip"]);

    robot.set_actuated_state(&[1.0, 0.2, 0.01]).unwrap();
    let chain = robot.chain();
    assert!((chain.joint_value("pitch").unwrap() - 0.3).abs() < 1e-15);
    assert!((chain.joint_value("roll").unwrap() - 0.2).abs() < 1e-15);
    assert!((chain.joint_value("grip").unwrap() - 0.01).abs() < 1e-15);

    // Equal motor motion pitches only.
    robot.set_actuated("motor_b", 1.0).unwrap();
    assert!((robot.chain().joint_value("pitch").unwrap() - 0.5).abs() < 1e-15);
    assert!(robot.chain().joint_value("roll").unwrap().abs() < 1e-15);

    // Setting a virtual joint keeps the group's other joint and moves both motors.
    robot.set_joint_value("roll", 0.1).unwrap();
    assert!((robot.chain().joint_value("pitch").unwrap() - 0.5).abs() < 1e-15);
    let state = robot.actuated_state();
    assert!((state[0] - 1.2).abs() < 1e-15 && (state[1] - 0.8).abs() < 1e-15);

    // The hand pose equals a full forward kinematics at pitch 0.5, roll 0.1.
    let mut data = KinematicsData::new(&model);
    forward_kinematics(&model, &mut data, &[0.5, 0.1, 0.01]).unwrap();
    update_frame_placements(&model, &mut data).unwrap();
    let hand = robot.world_from("hand").unwrap();
    let full = data
        .world_from(FrameId::find(&model, "hand").unwrap())
        .unwrap();
    assert!(hand.abs_diff_eq(full, 1e-15, 1e-15));
    let by_hand = Se3::from_rotation_y(0.5)
        * Se3::from_translation(DVec3::new(0.05, 0.0, 0.0))
        * Se3::from_rotation_x(0.1);
    assert!(hand.abs_diff_eq(&by_hand, 1e-15, 1e-15));

    // Unknown names and wrong sizes are errors that change nothing.
    assert!(matches!(
        robot.set_actuated("motor_c", 0.0),
        Err(KinematicsError::UnknownActuator { name }) if name == "motor_c"
    ));
    assert!(matches!(
        robot.set_actuated_state(&[0.0, 0.0]),
        Err(KinematicsError::DimensionMismatch {
            expected: 3,
            actual: 2,
            ..
        })
    ));
    assert!((robot.actuated("motor_a").unwrap() - 1.2).abs() < 1e-15);
}

#[test]
fn construction_reports_bad_mappings() {
    let model = wrist();
    let spec = || GroupSpec::new("wrist", ["a", "b"], ["pitch", "roll"], [0.3, -0.1]);

    // actuated → virtual writes one value for two joints.
    let short = FnActuation::new(
        |m: &[f64], j: &mut Vec<f64>| j.push(m[0]),
        |j: &[f64], m: &mut Vec<f64>| m.extend([j[0], j[0]]),
    );
    let err = ActuationGroup::new(&model, spec(), short).unwrap_err();
    assert!(matches!(
        err,
        KinematicsError::MappingSize { ref group, direction: MappingDirection::ActuatedToVirtual, expected: 2, actual: 1 }
            if group == "wrist"
    ));

    // virtual → actuated writes three values for two actuators.
    let long = FnActuation::new(
        |m: &[f64], j: &mut Vec<f64>| j.extend_from_slice(m),
        |j: &[f64], m: &mut Vec<f64>| m.extend([j[0], j[1], 0.0]),
    );
    let err = ActuationGroup::new(&model, spec(), long).unwrap_err();
    assert!(matches!(
        err,
        KinematicsError::MappingSize {
            direction: MappingDirection::VirtualToActuated,
            expected: 2,
            actual: 3,
            ..
        }
    ));

    // The inverse forgets the gear ratio: not a round trip.
    let inconsistent = FnActuation::new(
        |m: &[f64], j: &mut Vec<f64>| j.extend([(m[0] + m[1]) / 4.0, (m[0] - m[1]) / 4.0]),
        |j: &[f64], m: &mut Vec<f64>| m.extend([j[0] + j[1], j[0] - j[1]]),
    );
    let err = ActuationGroup::new(&model, spec(), inconsistent).unwrap_err();
    match err {
        KinematicsError::MappingInconsistent {
            group,
            actuator,
            probe,
            round_trip,
            ..
        } => {
            assert_eq!((group.as_str(), actuator.as_str()), ("wrist", "a"));
            assert!((probe - 0.3).abs() < 1e-15 && (round_trip - 0.15).abs() < 1e-15);
        }
        other => panic!("unexpected {other}"),
    }

    // NaN at the probe.
    let nan = FnActuation::new(
        |m: &[f64], j: &mut Vec<f64>| j.extend([m[0], m[1].ln()]),
        |j: &[f64], m: &mut Vec<f64>| m.extend([j[0], j[1].exp()]),
    );
    assert!(matches!(
        ActuationGroup::new(&model, spec(), nan),
        Err(KinematicsError::MappingNonFinite { index: 1, .. })
    ));

    // Ill-defined groups.
    let ok = || differential();
    let bad_specs = [
        GroupSpec::new("g", Vec::<String>::new(), ["pitch"], Vec::new()),
        GroupSpec::new("g", ["a", "a"], ["pitch", "roll"], [0.0, 0.0]),
        GroupSpec::new("g", ["a", "b"], ["pitch", "pitch"], [0.0, 0.0]),
        spec().with_tolerance(-1.0),
    ];
    for s in bad_specs {
        assert!(matches!(
            ActuationGroup::new(&model, s, ok()),
            Err(KinematicsError::InvalidGroup { .. })
        ));
    }
    assert!(matches!(
        ActuationGroup::new(&model, GroupSpec::new("g", ["a", "b"], ["pitch", "yaw"], [0.0, 0.0]), ok()),
        Err(KinematicsError::UnknownJoint { name }) if name == "yaw"
    ));
    assert!(matches!(
        ActuationGroup::new(
            &model,
            GroupSpec::new("g", ["a", "b"], ["pitch", "roll"], [0.0]),
            ok()
        ),
        Err(KinematicsError::DimensionMismatch { what: "probe", .. })
    ));
}

#[test]
fn groups_must_not_overlap() {
    let model = wrist();
    let make = |name: &str, actuators: [&str; 2]| {
        ActuationGroup::new(
            &model,
            GroupSpec::new(name, actuators, ["pitch", "roll"], [0.0, 0.0]),
            differential(),
        )
        .unwrap()
    };
    let err = ActuatedChain::new(
        Chain::new(model.clone()),
        vec![make("first", ["a", "b"]), make("second", ["c", "d"])],
    )
    .unwrap_err();
    assert!(matches!(
        err,
        KinematicsError::InvalidGroup { ref group, problem: GroupProblem::JointAlreadyDriven { ref joint, ref by } }
            if group == "second" && joint == "pitch" && by == "first"
    ));
    // An actuator named like a directly driven joint.
    let err =
        ActuatedChain::new(Chain::new(model.clone()), vec![make("w", ["grip", "b"])]).unwrap_err();
    assert!(matches!(err, KinematicsError::InvalidGroup { ref group, .. } if group == "w"));
    // A group built for another model.
    let other = leg();
    let err = ActuatedChain::new(Chain::new(other), vec![make("w", ["a", "b"])]).unwrap_err();
    assert!(matches!(
        err,
        KinematicsError::InvalidGroup {
            problem: GroupProblem::OtherModel,
            ..
        }
    ));
}

#[test]
fn chains_and_groups_can_move_between_threads() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Chain>();
    send_sync::<ActuationGroup>();
    send_sync::<ActuatedChain>();
}

#[test]
fn group_state_stays_consistent_both_ways() {
    let model = wrist();
    let spec = GroupSpec::new("wrist", ["a", "b"], ["pitch", "roll"], [0.4, 0.0]);
    let mut group = ActuationGroup::new(&model, spec, differential()).unwrap();
    let close = |a: &[f64], b: &[f64]| {
        assert!(
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-15),
            "{a:?} != {b:?}"
        );
    };
    close(group.virtual_q(), &[0.1, 0.1]);
    group.set_virtual_q(&[0.2, -0.1]).unwrap();
    close(group.actuated(), &[0.2, 0.6]);
    group.set_actuator("b", 0.2).unwrap();
    close(group.virtual_q(), &[0.1, 0.0]);
    group.set_joint_q("roll", &[0.05]).unwrap();
    close(group.actuated(), &[0.3, 0.1]);
    let mut q = vec![9.0; model.nq()];
    group.write_q(&mut q).unwrap();
    close(&q, &[0.1, 0.05, 9.0]);
    assert!(matches!(
        group.set_actuated(&[f64::NAN, 0.0]),
        Err(KinematicsError::NonFinite {
            what: "actuated",
            index: 0
        })
    ));
    assert!(matches!(
        group.write_q(&mut [0.0; 2]),
        Err(KinematicsError::DimensionMismatch { .. })
    ));
}
