//! Tests of [`Chain`](super::Chain).

use super::*;
use crate::{forward_kinematics, update_frame_placements};
use kinetree_model::{FrameSpec, JointSpec, Link, ModelBuilder, RootJoint};
use rand::SeedableRng;

fn panda() -> Model {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/robots/panda.urdf"
    );
    Model::from_urdf_file(path, RootJoint::Fixed).unwrap()
}

/// Every link and frame pose of `chain` equals a full forward kinematics at its `q`.
fn assert_matches_full_fk(chain: &mut Chain) {
    let model = chain.model().clone();
    let mut data = KinematicsData::new(&model);
    forward_kinematics(&model, &mut data, chain.q()).unwrap();
    update_frame_placements(&model, &mut data).unwrap();
    for (l, link) in model.links().iter().enumerate() {
        let cached = chain.world_from(&link.name).unwrap();
        let full = data.world_from(FrameId::Link(l)).unwrap();
        assert!(cached.abs_diff_eq(full, 1e-14, 1e-14), "link {}", link.name);
    }
    for (f, frame) in model.frames().iter().enumerate() {
        let cached = chain.world_from_id(FrameId::Frame(f)).unwrap();
        let full = data.world_from(FrameId::Frame(f)).unwrap();
        assert!(
            cached.abs_diff_eq(full, 1e-14, 1e-14),
            "frame {}",
            frame.name
        );
    }
    let all = chain.data();
    for (a, b) in all.world_from_body().iter().zip(data.world_from_body()) {
        assert!(a.abs_diff_eq(b, 1e-14, 1e-14));
    }
}

#[test]
fn changing_the_wrist_recomputes_only_the_bodies_below_it() {
    let model = panda();
    let wrist_body = model
        .joint_body(model.joint_index("panda_joint7").unwrap())
        .unwrap();
    let below = model.bodies()[wrist_body].subtree_end - wrist_body;
    // Joint 7 carries the hand and both fingers: 3 of the 9 moving bodies.
    assert_eq!((model.nbodies(), below), (10, 3));
    let mut chain = Chain::new(model);

    // The first full query computes every moving body once.
    chain.update();
    assert_eq!(chain.stats().body_updates, 9);
    assert_eq!(chain.stats().joint_updates, 9);
    // Nothing is stale: queries are free.
    let before = chain.stats();
    let _ = chain.world_from("panda_hand_tcp").unwrap();
    chain.update();
    assert_eq!(chain.stats(), before);

    // Moving the wrist recomputes exactly its subtree, and its joint transform only.
    chain.set_joint_value("panda_joint7", 0.4).unwrap();
    chain.update();
    let after = chain.stats();
    assert_eq!(after.body_updates - before.body_updates, below as u64);
    assert_eq!(after.joint_updates - before.joint_updates, 1);
    assert_matches_full_fk(&mut chain);

    // A single query is lazier still: the hand needs only the wrist body, not the fingers.
    let before = chain.stats();
    chain.set_joint_value("panda_joint7", -0.3).unwrap();
    let _ = chain.world_from("panda_hand").unwrap();
    assert_eq!(chain.stats().body_updates - before.body_updates, 1);
    // The fingers follow when asked for.
    let _ = chain.world_from("panda_leftfinger").unwrap();
    assert_eq!(chain.stats().body_updates - before.body_updates, 2);
    assert_matches_full_fk(&mut chain);

    // Setting a joint to the value it already has invalidates nothing.
    let before = chain.stats();
    chain.set_joint_value("panda_joint7", -0.3).unwrap();
    chain.update();
    assert_eq!(chain.stats(), before);

    // The shoulder moves everything.
    chain.set_joint_value("panda_joint1", 1.0).unwrap();
    chain.update();
    assert_eq!(chain.stats().body_updates - before.body_updates, 9);
}

#[test]
fn cached_poses_always_equal_full_forward_kinematics() {
    let model = panda();
    let mut chain = Chain::new(model.clone());
    let mut rng = rand::rngs::SmallRng::seed_from_u64(3);
    let mut q = vec![0.0; model.nq()];
    let names: Vec<String> = model
        .moving_joints()
        .map(|j| model.joint(j).name.clone())
        .collect();
    for step in 0..40 {
        // Alternate single-joint changes, whole-configuration changes and interleaved queries.
        if step % 5 == 0 {
            crate::configuration::random_configuration(&model, &mut rng, &mut q).unwrap();
            chain.set_q(&q).unwrap();
        } else {
            let name = &names[step % names.len()];
            let v = chain.joint_value(name).unwrap() + 0.1 * step as f64 / 40.0;
            chain.set_joint_value(name, v).unwrap();
            let other = &names[(step * 7) % names.len()];
            let _ = chain.world_from(&model.link(step % 11).name).unwrap();
            chain.set_joint_value(other, -v).unwrap();
        }
        assert_matches_full_fk(&mut chain);
    }
}

#[test]
fn set_q_invalidates_only_changed_blocks() {
    let mut chain = Chain::new(panda());
    chain.update();
    let mut q = chain.q().to_vec();
    q[6] = 0.5; // panda_joint7
    let before = chain.stats();
    chain.set_q(&q).unwrap();
    chain.update();
    assert_eq!(chain.stats().body_updates - before.body_updates, 3);
    assert!(matches!(
        chain.set_q(&q[1..]),
        Err(KinematicsError::DimensionMismatch { .. })
    ));
    q[0] = f64::NAN;
    assert!(matches!(
        chain.set_q(&q),
        Err(KinematicsError::NonFinite { index: 0, .. })
    ));
    assert!((chain.q()[6] - 0.5).abs() < 1e-15);
}

fn small() -> Model {
    let mut b = ModelBuilder::new("small");
    b.add_link(Link::new("base"));
    b.add_part(
        Link::new("upper"),
        JointSpec::new("shoulder", JointKind::Revolute, "base", "upper")
            .with_limits(kinetree_model::JointLimits::position(-1.0, 1.0)),
    );
    b.add_part(
        Link::new("carriage"),
        JointSpec::new("slide", JointKind::Prismatic, "upper", "carriage")
            .with_axis(glam::DVec3::X),
    );
    b.add_part(
        Link::new("head"),
        JointSpec::new("neck", JointKind::Spherical, "upper", "head"),
    );
    b.add_part(
        Link::new("plate"),
        JointSpec::new("weld", JointKind::Fixed, "carriage", "plate"),
    );
    b.add_frame(FrameSpec::new("tool", "plate", Se3::IDENTITY));
    b.build().unwrap()
}

#[test]
fn joint_setters_convert_units_and_reject_wrong_kinds() {
    let mut chain = Chain::new(small());
    chain.set_joint_value_deg("shoulder", 30.0).unwrap();
    assert!((chain.joint_value("shoulder").unwrap() - 30f64.to_radians()).abs() < 1e-15);
    assert!((chain.joint_value_deg("shoulder").unwrap() - 30.0).abs() < 1e-12);
    chain.set_joint_value_mm("slide", 12.5).unwrap();
    assert!((chain.joint_value("slide").unwrap() - 0.0125).abs() < 1e-15);
    assert!((chain.joint_value_mm("slide").unwrap() - 12.5).abs() < 1e-12);
    assert!((chain.set_joint_value_clamped("shoulder", 3.0).unwrap() - 1.0).abs() < 1e-15);
    assert!((chain.joint_value("shoulder").unwrap() - 1.0).abs() < 1e-15);

    let kind_of = |e: KinematicsError| match e {
        KinematicsError::WrongJointKind { joint, kind, .. } => (joint, kind),
        other => panic!("unexpected {other}"),
    };
    let e = chain.set_joint_value_deg("slide", 1.0).unwrap_err();
    assert_eq!(kind_of(e), ("slide".into(), JointKind::Prismatic));
    let e = chain.set_joint_value_mm("shoulder", 1.0).unwrap_err();
    assert_eq!(kind_of(e), ("shoulder".into(), JointKind::Revolute));
    let e = chain.set_joint_value("neck", 1.0).unwrap_err();
    assert_eq!(kind_of(e), ("neck".into(), JointKind::Spherical));
    let e = chain.joint_value("weld").unwrap_err();
    assert_eq!(kind_of(e), ("weld".into(), JointKind::Fixed));
    assert!(matches!(
        chain.set_joint_value("elbow", 1.0),
        Err(KinematicsError::UnknownJoint { name }) if name == "elbow"
    ));
    assert!(matches!(
        chain.set_joint_value("slide", f64::INFINITY),
        Err(KinematicsError::InvalidJointValue { joint, .. }) if joint == "slide"
    ));
    // Multi-DoF joints go through the block setters.
    let half = core::f64::consts::FRAC_1_SQRT_2;
    chain.set_joint_q("neck", &[0.0, 0.0, half, half]).unwrap();
    let neck = chain.joint_q("neck").unwrap();
    assert!(
        neck.iter()
            .zip([0.0, 0.0, half, half])
            .all(|(a, b)| (a - b).abs() < 1e-15)
    );
    assert!(matches!(
        chain.set_joint_q("neck", &[1.0]),
        Err(KinematicsError::InvalidJointValue { .. })
    ));
    assert_matches_full_fk(&mut chain);
}

#[test]
fn random_trees_stay_equal_to_full_forward_kinematics() {
    use kinetree_model::samples;
    let models = [
        samples::random_tree(11, 12),
        samples::random_tree_with_root(5, 9, RootJoint::Floating),
        samples::humanoid_like(),
    ];
    for model in models {
        let mut chain = Chain::new(model.clone());
        chain.update();
        let mut rng = rand::rngs::SmallRng::seed_from_u64(17);
        let mut q = vec![0.0; model.nq()];
        for step in 0..30 {
            crate::configuration::random_configuration(&model, &mut rng, &mut q).unwrap();
            // Change one joint's block at a time and query a link somewhere in the tree.
            let joints: Vec<usize> = model.moving_joints().collect();
            let j = joints[step % joints.len()];
            let name = &model.joint(j).name;
            chain.set_joint_q(name, &q[model.joint_q_range(j)]).unwrap();
            let body = model.joint_body(j).unwrap();
            let before = chain.stats().body_updates;
            chain.update();
            let recomputed = chain.stats().body_updates - before;
            // Exactly the subtree below the changed joint (a random block always differs).
            assert_eq!(recomputed, (model.bodies()[body].subtree_end - body) as u64);
            assert_matches_full_fk(&mut chain);
        }
    }
}

#[test]
fn json_export_carries_world_poses_and_positions() {
    use kinetree_model::Units;
    let mut chain = Chain::new(panda());
    chain.set_joint_value("panda_joint2", -0.7).unwrap();
    chain.set_joint_value("panda_joint4", -2.0).unwrap();
    chain
        .set_joint_value_mm("panda_finger_joint1", 20.0)
        .unwrap();
    let units = [(Units::SI, 1.0, 1.0), (Units::MM_DEG, 1000.0, DEG_PER_RAD)];
    for (units, length, angle) in units {
        let json = chain
            .to_json_string(&JsonOptions {
                units,
                ..JsonOptions::default()
            })
            .unwrap();
        let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
        let triple = |v: &serde_json::Value, scale: f64| -> [f64; 3] {
            let mut out = [0.0; 3];
            if let Some(a) = v.as_array() {
                for (o, x) in out.iter_mut().zip(a) {
                    *o = x.as_f64().unwrap() / scale;
                }
            }
            out
        };
        for link in doc["links"].as_array().unwrap() {
            let name = link["name"].as_str().unwrap();
            let pose = &link["world_pose"];
            let written =
                Se3::from_xyz_rpy(triple(&pose["xyz"], length), triple(&pose["rpy"], angle));
            let expected = chain.world_from(name).unwrap();
            assert!(written.abs_diff_eq(&expected, 1e-9, 1e-12), "{name}");
        }
        for joint in doc["joints"].as_array().unwrap() {
            let name = joint["name"].as_str().unwrap();
            if let Ok(value) = chain.joint_value(name) {
                let scale = if name.contains("finger") {
                    length
                } else {
                    angle
                };
                let written = joint["position"].as_f64().unwrap() / scale;
                assert!((written - value).abs() < 1e-12, "{name}");
            }
        }
        // The file loads back into the same model.
        let back = Model::from_json_str(&json, None).unwrap();
        assert_eq!(back.links().len(), chain.model().links().len());
        assert_eq!(back.nq(), chain.model().nq());
    }
}

#[test]
fn tree_queries_by_name() {
    let chain = Chain::new(small());
    assert_eq!(chain.children("upper").unwrap(), ["carriage", "head"]);
    assert_eq!(
        chain.descendants("upper").unwrap(),
        ["carriage", "plate", "head"]
    );
    assert_eq!(
        chain.path_to_root("plate").unwrap(),
        ["plate", "carriage", "upper", "base"]
    );
    assert_eq!(
        chain.common_ancestor("plate", "head").unwrap(),
        Some("upper")
    );
    assert_eq!(chain.parent("base").unwrap(), None);
    assert_eq!(chain.parent("plate").unwrap(), Some("carriage"));
    assert_eq!(chain.parent_joint("plate").unwrap(), Some("weld"));
    assert_eq!(chain.parent_joint("base").unwrap(), None);
    assert!(matches!(
        chain.children("tool"),
        Err(KinematicsError::UnknownLink { name }) if name == "tool"
    ));
}

#[test]
fn world_and_relative_placements() {
    let mut chain = Chain::new(small());
    chain.set_joint_value("shoulder", 0.5).unwrap();
    chain.set_joint_value("slide", 0.2).unwrap();
    let tool = chain.world_from("tool").unwrap();
    let expected = Se3::from_rotation_z(0.5) * Se3::from_translation(glam::DVec3::X * 0.2);
    assert!(tool.abs_diff_eq(&expected, 1e-15, 1e-15));
    let rel = chain.relative_transform("upper", "tool").unwrap();
    assert!(rel.abs_diff_eq(&Se3::from_translation(glam::DVec3::X * 0.2), 1e-15, 1e-15));
    let all: Vec<(&str, Se3)> = chain.world_from_all().map(|(n, p)| (n, *p)).collect();
    assert_eq!(all.len(), 6);
    assert_eq!(all[5].0, "tool");
    assert!(all[5].1.abs_diff_eq(&expected, 1e-15, 1e-15));
    assert!(matches!(
        chain.relative_transform("upper", "nowhere"),
        Err(KinematicsError::UnknownFrame { name }) if name == "nowhere"
    ));
    assert!(matches!(
        chain.world_from_id(FrameId::Link(99)),
        Err(KinematicsError::FrameOutOfRange { index: 99, .. })
    ));
}
