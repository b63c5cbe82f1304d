//! Several root parts, frames that belong to parts, and validation without building (the
//! yapCAD seed's tree rules).

use glam::DVec3;
use kinetree_model::{
    FrameSpec, Issue, JointKind, JointSpec, JsonOptions, Link, Model, ModelBuilder, ModelError,
    RootJoint,
};
use kinetree_spatial::{Se3, Symmetric3};

fn massive(name: &str) -> Link {
    Link::new(name).with_mass(
        1.0,
        DVec3::new(0.1, 0.0, 0.0),
        Symmetric3::from_diagonal(DVec3::splat(0.01)),
    )
}

/// Two robots on one table: `left` welded at x = -1 by a fixed world joint, `right` on a rail
/// (prismatic world joint along y), each with a revolute arm, and a pallet welded at x = 2.
fn two_robots() -> ModelBuilder {
    let mut b = ModelBuilder::new("cell");
    for side in ["left", "right"] {
        b.add_link(massive(&format!("{side}_base")));
        b.add_link(massive(&format!("{side}_arm")));
        b.add_joint(
            JointSpec::new(
                format!("{side}_shoulder"),
                JointKind::Revolute,
                format!("{side}_base"),
                format!("{side}_arm"),
            )
            .with_placement(Se3::from_translation(DVec3::Z)),
        );
        b.add_frame(FrameSpec::new(
            "MOUNT",
            format!("{side}_arm"),
            Se3::from_translation(DVec3::new(0.5, 0.0, 0.0)),
        ));
    }
    b.add_joint(
        JointSpec::new("left_weld", JointKind::Fixed, "GLOBAL_DATUM", "left_base")
            .with_placement(Se3::from_translation(DVec3::new(-1.0, 0.0, 0.0))),
    );
    b.add_joint(
        JointSpec::new("right_rail", JointKind::Prismatic, "world", "right_base")
            .with_axis(DVec3::Y)
            .with_placement(Se3::from_translation(DVec3::new(1.0, 0.0, 0.0))),
    );
    b.add_part(
        Link::new("pallet"),
        JointSpec::new("pallet_weld", JointKind::Fixed, "world", "pallet")
            .with_placement(Se3::from_translation(DVec3::new(2.0, 0.0, 0.0))),
    );
    b
}

#[test]
fn several_roots_each_attached_to_the_world_by_its_own_joint() {
    let m = two_robots().build().unwrap();
    assert_eq!((m.nq(), m.nv()), (3, 3));
    let roots: Vec<&str> = m
        .root_links()
        .into_iter()
        .map(|l| m.link(l).name.as_str())
        .collect();
    assert_eq!(roots, ["left_base", "right_base", "pallet"]);
    let l = |n: &str| m.link_index(n).unwrap();
    // The welded roots sit on the world body at their joint's placement.
    assert_eq!(m.link_body(l("left_base")).0, 0);
    assert_eq!(
        m.link_body(l("pallet")).1.translation.to_array(),
        [2.0, 0.0, 0.0]
    );
    // The rail drives a body whose parent is the world.
    let rail = m.joint_body(m.joint_index("right_rail").unwrap()).unwrap();
    assert_eq!(m.bodies()[rail].parent, 0);
    assert_eq!(m.common_ancestor(l("left_arm"), l("right_arm")), None);
    assert_eq!(
        m.common_ancestor(l("right_arm"), l("right_base")),
        Some(l("right_base"))
    );
    // Depth-first storage: parents precede children.
    for (i, _) in m.links().iter().enumerate() {
        if let Some(p) = m.parent_link(i) {
            assert!(p < i);
        }
    }
}

#[test]
fn several_roots_survive_a_json_round_trip_but_not_urdf() {
    let m = two_robots().build().unwrap();
    let json = m.to_json_string(&JsonOptions::default()).unwrap();
    assert!(json.contains("\"parent\": \"world\""), "{json}");
    let back = Model::from_json_str(&json, None).unwrap();
    assert_eq!(m.first_difference(&back, 1e-12), None);
    let e = m.to_urdf_string().unwrap_err();
    assert!(
        matches!(&e, ModelError::Unsupported { format: "URDF", .. }),
        "{e}"
    );
    assert!(e.to_string().contains("left_weld"), "{e}");
    // A URDF joint whose parent is an undeclared `world` stays an unknown parent.
    let urdf = r#"<robot name="r"><link name="a"/>
        <joint name="j" type="fixed"><parent link="world"/><child link="a"/></joint></robot>"#;
    let e = Model::from_urdf_str(urdf, RootJoint::Fixed).unwrap_err();
    assert!(
        e.issues()
            .iter()
            .any(|i| matches!(i, Issue::UnknownParent { link, .. } if link == "world")),
        "{e}"
    );
}

#[test]
fn a_floating_root_attaches_only_the_parentless_link() {
    let mut b = two_robots();
    b.add_link(Link::new("drone"));
    b.root_joint(RootJoint::Floating);
    let m = b.build().unwrap();
    assert_eq!(m.nq(), 3 + 7);
    let root = m.joint(0);
    assert_eq!(m.link(root.child_link).name, "drone");
    // Its quaternion is the last four of its seven coordinates.
    let drone = m.link_body(root.child_link).0;
    let start = m.bodies()[drone].idx_q + 3;
    assert_eq!(m.quaternion_blocks(), &[(drone, start)]);
    // Without a parentless link, there is nothing to float.
    let mut b = two_robots();
    b.root_joint(RootJoint::Floating);
    assert_eq!(b.build().unwrap().nq(), 3);
}

#[test]
fn frames_belong_to_parts() {
    let m = two_robots().build().unwrap();
    // Both arms have a MOUNT: the bare name is ambiguous, `part/frame` is not.
    assert_eq!(m.frame_index("MOUNT"), None);
    let left = m.frame_index("left_arm/MOUNT").unwrap();
    let right = m.frame_index("right_arm/MOUNT").unwrap();
    assert_ne!(left, right);
    assert_eq!(m.link(m.frames()[right].link).name, "right_arm");
    // A name unique in the model still works alone.
    let mut b = two_robots();
    b.add_frame(FrameSpec::new("tcp", "left_arm", Se3::IDENTITY));
    let m = b.build().unwrap();
    assert_eq!(m.frame_index("tcp"), m.frame_index("left_arm/tcp"));
    // The same name twice on one part is an error naming both.
    let mut b = two_robots();
    b.add_frame(FrameSpec::new("MOUNT", "left_arm", Se3::IDENTITY));
    let e = b.build().unwrap_err();
    assert!(
        e.to_string()
            .contains("duplicate frame name 'left_arm/MOUNT'"),
        "{e}"
    );
}

#[test]
fn parent_frames_resolve_on_the_parent_part_and_origin_is_implicit() {
    let mut b = two_robots();
    b.add_part(
        massive("left_tool"),
        JointSpec::new("left_flange", JointKind::Fixed, "left_arm", "left_tool")
            .at_frame("MOUNT")
            .with_placement(Se3::from_translation(DVec3::Z * 0.1)),
    );
    b.add_part(
        massive("right_tool"),
        JointSpec::new("right_flange", JointKind::Fixed, "right_arm", "right_tool")
            .at_frame("ORIGIN"),
    );
    let m = b.build().unwrap();
    let j = m.joint(m.joint_index("left_flange").unwrap());
    assert_eq!(j.placement.translation.to_array(), [0.5, 0.0, 0.1]);
    assert_eq!(j.parent_frame.as_deref(), Some("MOUNT"));
    let j = m.joint(m.joint_index("right_flange").unwrap());
    assert_eq!(j.placement, Se3::IDENTITY);
    // The JSON export keeps the attachment as declared: frame name plus origin in that frame.
    let json = m.to_json_string(&JsonOptions::default()).unwrap();
    assert!(json.contains("\"parent_frame\": \"MOUNT\""), "{json}");
    assert!(json.contains("\"xyz\": [0.0, 0.0, 0.1]"), "{json}");
    let back = Model::from_json_str(&json, None).unwrap();
    assert_eq!(m.first_difference(&back, 1e-12), None);
    let j = back.joint(back.joint_index("left_flange").unwrap());
    assert_eq!(j.parent_frame.as_deref(), Some("MOUNT"));
    // A frame of another part is not a parent frame.
    let mut b = two_robots();
    b.add_part(
        Link::new("x"),
        JointSpec::new("jx", JointKind::Fixed, "left_base", "x").at_frame("MOUNT"),
    );
    assert!(matches!(
        &b.validate()[..],
        [Issue::UnknownParentFrame { frame, link, .. }] if frame == "MOUNT" && link == "left_base"
    ));
}

#[test]
fn validation_tells_an_orphan_from_a_cycle_without_building() {
    // An orphan: `arm`'s joint names a parent that does not exist; `hand` hangs below it.
    let mut b = ModelBuilder::new("m");
    b.add_link(Link::new("base"))
        .add_link(Link::new("arm"))
        .add_link(Link::new("hand"));
    b.add_joint(JointSpec::new("j1", JointKind::Revolute, "bsae", "arm"));
    b.add_joint(JointSpec::new("j2", JointKind::Revolute, "arm", "hand"));
    let issues = b.validate();
    assert_eq!(
        issues,
        [Issue::UnknownParent {
            joint: "j1".into(),
            link: "bsae".into()
        }]
    );
    assert_eq!(b.build().unwrap_err().issues(), issues);
    // A cycle below a good root: reported once, as a cycle.
    let mut b = ModelBuilder::new("m");
    b.add_link(Link::new("base"))
        .add_link(Link::new("a"))
        .add_link(Link::new("b"));
    b.add_joint(JointSpec::new("ab", JointKind::Fixed, "a", "b"));
    b.add_joint(JointSpec::new("ba", JointKind::Fixed, "b", "a"));
    assert!(matches!(&b.validate()[..], [Issue::Cycle { .. }]));
    // Every link with a parent and one of them unknown: an orphan, neither "no root" nor a cycle.
    let mut b = ModelBuilder::new("m");
    b.add_link(Link::new("a")).add_link(Link::new("b"));
    b.add_joint(JointSpec::new("ja", JointKind::Fixed, "nowhere", "a"));
    b.add_joint(JointSpec::new("jb", JointKind::Fixed, "a", "b"));
    assert!(matches!(&b.validate()[..], [Issue::UnknownParent { link, .. }] if link == "nowhere"));
    // A valid builder validates clean.
    assert!(two_robots().validate().is_empty());
}

#[test]
fn joint_values_survive_export_and_import_with_per_coordinate_units() {
    use kinetree_model::{Units, state};
    let mut b = ModelBuilder::new("m");
    b.add_link(Link::new("base"));
    b.add_part(
        massive("slider"),
        JointSpec::new("cyl", JointKind::Cylindrical, "base", "slider"),
    );
    b.add_part(
        massive("ball"),
        JointSpec::new("ball", JointKind::Spherical, "slider", "ball"),
    );
    let m = b.build().unwrap();
    // The ball's quaternion follows the cylindrical joint's two coordinates.
    let ball = m.link_body(m.link_index("ball").unwrap()).0;
    assert_eq!(m.quaternion_blocks(), &[(ball, 2)]);
    let s = 0.5f64.sqrt();
    let q = [0.25, 0.5, 0.0, 0.0, s, s];
    let json = m
        .to_json_string(&JsonOptions {
            units: Units::MM_DEG,
            positions: Some(&q),
            ..JsonOptions::default()
        })
        .unwrap();
    // The cylindrical joint's position is a length and an angle: mm and degrees.
    assert!(
        json.contains("\"position\": [250.0, 28.64788975654116]"),
        "{json}"
    );
    let back = Model::from_json_str(&json, None).unwrap();
    let read = state::positions_from_json(&back, &json).unwrap();
    for (a, b) in read.iter().zip(q) {
        assert!((a - b).abs() < 1e-15, "{read:?}");
    }
    // Coordinate-wise conversion both ways.
    let mut x = q;
    m.convert_q(&mut x, Units::MM_DEG, false).unwrap();
    assert_eq!(x[0], 250.0);
    assert!((x[1] - 0.5f64.to_degrees()).abs() < 1e-12);
    assert_eq!(x[2..], q[2..]);
    let mut v = [0.001, 0.1, 0.2, 0.3, 0.4];
    m.convert_v(&mut v, Units::MM_DEG, false).unwrap();
    assert!((v[0] - 1.0).abs() < 1e-12 && (v[4] - 0.4f64.to_degrees()).abs() < 1e-12);
    assert!(m.convert_q(&mut [0.0; 2], Units::SI, true).is_err());
    // A position with the wrong number of values names the joint.
    let bad = json.replace("[250.0, 28.64788975654116]", "[250.0]");
    let e = state::positions_from_json(&back, &bad).unwrap_err();
    assert!(e.to_string().contains("joint 'cyl'"), "{e}");
}
