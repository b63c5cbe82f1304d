//! yapCAD's own exports load as they are, and their world poses agree with forward kinematics at
//! the exported joint values.

use kinetree_kinematics::model::{Issue, JointKind, Model};
use kinetree_kinematics::{Chain, FrameId, KinematicsData, forward_kinematics};
use kinetree_test_support::assert_close;

fn data(name: &str) -> String {
    format!(
        "{}/../../tests/data/yapcad/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

fn assert_fk_matches_export(file: &str) -> Model {
    let chain = Model::from_yapcad_file(data(file)).unwrap();
    let model = &chain.model;
    assert!(model.warnings().is_empty(), "{:?}", model.warnings());
    let mut d = KinematicsData::new(model);
    forward_kinematics(model, &mut d, &chain.q).unwrap();
    let mut checked = 0;
    for (l, pose) in chain.world_poses.iter().enumerate() {
        let pose = pose.expect("every part exports its world transform");
        let fk = d.world_from_link()[l];
        let err = (fk.translation - pose.translation).length();
        assert!(err < 1e-12, "{}: {err} m", model.link(l).name);
        let r = (fk.rotation - pose.rotation).to_cols_array();
        assert!(r.iter().all(|x| x.abs() < 1e-12), "{}", model.link(l).name);
        checked += 1;
    }
    assert_eq!(checked, model.links().len());
    chain.model
}

#[test]
fn the_quickstart_export_loads_with_its_joint_value() {
    let model = assert_fk_matches_export("yap_quickstart.yapcad.json");
    assert_eq!((model.nq(), model.links().len()), (1, 2));
    let chain = Model::from_yapcad_file(data("yap_quickstart.yapcad.json")).unwrap();
    assert_close!(chain.q[0], core::f64::consts::FRAC_PI_4, 1e-15);
    let j = model.joint(model.joint_index("joint1").unwrap());
    // yapCAD's default limits: ±180°.
    assert_eq!(
        (j.limits.lower, j.limits.upper),
        (-core::f64::consts::PI, core::f64::consts::PI)
    );
    // The root part is attached to the world datum by its own (fixed) joint.
    let base = model.joint(model.joint_index("base_joint").unwrap());
    assert_eq!(base.parent_link, None);
    // Recognised by shape through the ordinary JSON loader too.
    let same = Model::from_file(data("yap_quickstart.yapcad.json"), None).unwrap();
    assert_eq!(model.first_difference(&same, 0.0), None);
}

#[test]
fn the_arm_export_loads_in_si_with_frames_and_metadata() {
    let model = assert_fk_matches_export("yap_arm.yapcad.json");
    assert_eq!(model.nq(), 5);
    let grip = model.joint(model.joint_index("j_grip").unwrap());
    assert_eq!(grip.kind, JointKind::Prismatic);
    assert_eq!((grip.limits.lower, grip.limits.upper), (0.0, 0.04));
    assert_eq!(grip.parent_frame.as_deref(), Some("TOOL_FLANGE"));
    let upper = model.link(model.link_index("UPPER_ARM").unwrap());
    assert_eq!(upper.metadata.mesh.as_deref(), Some("stl/upper_arm.stl"));
    assert_eq!(upper.metadata.color, Some([0.9, 0.5, 0.1, 1.0]));
    // The TCP, by hand from the file: (238.510, 182.020, -53.928) mm.
    let mut chain = Chain::new(model.clone());
    let cfg = Model::from_yapcad_file(data("yap_arm.yapcad.json"))
        .unwrap()
        .q;
    chain.set_q(&cfg).unwrap();
    let tcp = chain.world_from("TCP").unwrap();
    let expected = [
        0.238_510_222_698_152_66,
        0.182_019_581_326_063_02,
        -0.053_928_336_505_207_085,
    ];
    for (a, b) in tcp.translation.to_array().iter().zip(expected) {
        assert_close!(a, b, 1e-12, 0.0, "{a} vs {b}");
    }
    // Part frames: `part/frame`, and the implicit ORIGIN of every part.
    let mount = chain.world_from("BASE/MOUNT").unwrap();
    assert_close!(mount.translation.z, 0.04, 1e-15);
    let origin = FrameId::find(&model, "FOREARM/ORIGIN").unwrap();
    assert_eq!(origin, FrameId::Link(model.link_index("FOREARM").unwrap()));
}

#[test]
fn a_world_pose_that_disagrees_is_a_warning_naming_the_part_and_the_distance() {
    let text = std::fs::read_to_string(data("yap_arm.yapcad.json")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    // Move the gripper's exported pose 3 mm along x and 4 mm along y: 5 mm off.
    let m = &mut doc["parts"]["GRIPPER"]["world_transform"]["matrix"];
    m[0][3] = (m[0][3].as_f64().unwrap() + 3.0).into();
    m[1][3] = (m[1][3].as_f64().unwrap() + 4.0).into();
    let chain = Model::from_yapcad_str(&doc.to_string()).unwrap();
    let [
        Issue::WorldPoseMismatch {
            part,
            distance,
            angle,
        },
    ] = chain.model.warnings()
    else {
        panic!("expected one mismatch, got {:?}", chain.model.warnings());
    };
    assert_eq!(part, "GRIPPER");
    assert_close!(distance, 0.005, 1e-12, 0.0, "{distance}");
    assert!(*angle < 1e-12);
    let message = chain.model.warnings()[0].to_string();
    assert!(
        message.contains("part 'GRIPPER'") && message.contains("5.000e-3 m"),
        "{message}"
    );
}

#[test]
fn yapcad_cylindrical_joints_rotate_and_missing_parent_frames_fall_back() {
    let text = std::fs::read_to_string(data("yap_quickstart.yapcad.json")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    let link1 = &mut doc["parts"]["LINK1"];
    link1["joint"]["type"] = "cylindrical".into();
    link1["joint"]["limits"] = serde_json::json!([-90, 90]);
    link1["parent_frame"] = "MOUNT".into();
    let chain = Model::from_yapcad_str(&doc.to_string()).unwrap();
    let model = &chain.model;
    let j = model.joint(model.joint_index("joint1").unwrap());
    assert_eq!(j.kind, JointKind::Revolute);
    assert_eq!(j.limits.upper, core::f64::consts::FRAC_PI_2);
    assert_eq!(chain.q, [core::f64::consts::FRAC_PI_4]);
    assert!(model.ignored().iter().any(|i| i.contains("cylindrical")));
    assert!(matches!(
        model.warnings(),
        [Issue::ParentFrameFallback { joint, frame, link }]
            if joint == "joint1" && frame == "MOUNT" && link == "BASE"
    ));
}

#[test]
fn datums_resolve_on_their_own_and_reload_into_a_live_chain() {
    use kinetree_kinematics::model::{ModelError, datum};
    let dir = std::env::temp_dir().join(format!("kinetree-reload-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let servo = dir.join("servo.json");
    let write = |z: f64| {
        std::fs::write(
            &servo,
            format!(r#"{{"units": {{"length": "mm", "angle": "deg"}}, "datums": {{"shaft": {{"xyz": [0, 0, {z}], "rpy": [0, 0, 90]}}}}}}"#),
        )
        .unwrap();
    };
    write(10.0);
    let pose = datum::resolve_datum(&servo, "shaft").unwrap();
    assert_close!(pose.translation.z, 0.01, 1e-15);
    assert_close!(pose.rotation.x_axis.y, 1.0, 1e-15);
    // A model whose horn part hangs from the datum frame.
    let model_json = r#"{"name": "servo_arm", "units": {"length": "mm", "angle": "deg"},
      "links": [{"name": "body"}, {"name": "horn"}],
      "joints": [{"name": "spin", "type": "revolute", "parent": "body", "child": "horn",
                  "parent_frame": "shaft", "origin": {"xyz": [5, 0, 0]}}],
      "frames": [{"name": "shaft", "link": "body", "datum": {"file": "servo.json", "name": "shaft"}}]}"#;
    let path = dir.join("arm.json");
    std::fs::write(&path, model_json).unwrap();
    let mut chain = Chain::new(Model::from_json_file(&path, None).unwrap());
    chain.set_joint_value("spin", 0.3).unwrap();
    let before = chain.world_from("horn").unwrap();
    // shaft at z = 10 mm, turned 90°: the 5 mm offset points along world y.
    assert!((before.translation - glam::DVec3::new(0.0, 0.005, 0.01)).length() < 1e-15);
    write(25.0);
    assert_eq!(chain.reload_datums(Some(&dir)).unwrap(), 1);
    assert_eq!(chain.joint_value("spin").unwrap(), 0.3);
    let after = chain.world_from("horn").unwrap();
    assert!((after.translation - glam::DVec3::new(0.0, 0.005, 0.025)).length() < 1e-15);
    assert!(after.rotation.abs_diff_eq(before.rotation, 1e-15));
    let shaft = chain.world_from("body/shaft").unwrap();
    assert_close!(shaft.translation.z, 0.025, 1e-15);
    // Nothing changed: nothing to do.
    assert_eq!(chain.reload_datums(Some(&dir)).unwrap(), 0);
    // A missing datum names both the file and the datum, and leaves the chain as it was.
    std::fs::write(&servo, r#"{"datums": {"other": {}}}"#).unwrap();
    let e = chain.reload_datums(Some(&dir)).unwrap_err();
    let message = e.to_string();
    assert!(
        message.contains("servo.json") && message.contains("'shaft'"),
        "{message}"
    );
    assert!(matches!(
        e,
        kinetree_kinematics::KinematicsError::Model(ModelError::Datum { .. })
    ));
    assert_close!(
        chain.world_from("horn").unwrap().translation.z,
        0.025,
        1e-15
    );
    std::fs::remove_file(&servo).unwrap();
    let e = datum::resolve_datum(&servo, "shaft").unwrap_err();
    assert!(
        e.to_string().contains("servo.json") && e.to_string().contains("shaft"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_assembly_rooted_on_the_world_converts_to_urdf_through_a_world_link() {
    use kinetree_kinematics::model::RootJoint;
    let chain = Model::from_yapcad_file(data("yap_arm.yapcad.json")).unwrap();
    let model = &chain.model;
    let urdf = model.to_urdf_string().unwrap();
    assert!(urdf.contains("<link name=\"world\"/>"), "{urdf}");
    assert!(urdf.contains("<parent link=\"world\"/>"), "{urdf}");
    let back = Model::from_urdf_str(&urdf, RootJoint::Fixed).unwrap();
    assert_eq!(back.links().len(), model.links().len() + 1);
    assert_eq!(back.nq(), model.nq());
    // The same pose of every part at the exported joint values, joint by joint name.
    let mut q = vec![0.0; back.nq()];
    for (j, joint) in model.joints().iter().enumerate() {
        let r = model.joint_q_range(j);
        if r.is_empty() {
            continue;
        }
        let k = back.joint_index(&joint.name).unwrap();
        q[back.joint_q_range(k)].copy_from_slice(&chain.q[r]);
    }
    let (mut a, mut b) = (KinematicsData::new(model), KinematicsData::new(&back));
    forward_kinematics(model, &mut a, &chain.q).unwrap();
    forward_kinematics(&back, &mut b, &q).unwrap();
    for (l, link) in model.links().iter().enumerate() {
        let there = b.world_from_link()[back.link_index(&link.name).unwrap()];
        let here = a.world_from_link()[l];
        assert!(
            (there.translation - here.translation).length() < 1e-12,
            "{}",
            link.name
        );
        let r = (there.rotation - here.rotation).to_cols_array();
        assert!(r.iter().all(|x| x.abs() < 1e-12), "{}", link.name);
    }
}
