//! The SDFormat loader on documents written by hand, one feature per test, with the expected
//! values worked out by hand (the comparison with libsdformat, Pinocchio and Drake is in the
//! dynamics tests).

use kinetree_model::sdf::{SdfOptions, load_sdf_file, load_sdf_str};
use kinetree_model::spatial::Se3;
use kinetree_model::spatial::glam::{DMat3, DVec3};
use kinetree_model::{Geometry, JointKind, Model, ModelError, RootJoint};
use std::f64::consts::FRAC_PI_2;
use std::path::PathBuf;

fn load(sdf: &str) -> Model {
    Model::from_sdf_str(sdf).unwrap_or_else(|e| panic!("{e}"))
}

/// A 1.9 document holding `body` in a model called `m`.
fn model(body: &str) -> String {
    format!("<sdf version=\"1.9\"><model name=\"m\">{body}</model></sdf>")
}

/// The located error of a document that must not load: (line, element, message).
fn sdf_error(sdf: &str) -> (usize, String, String) {
    match Model::from_sdf_str(sdf) {
        Ok(_) => panic!("loaded: {sdf}"),
        Err(ModelError::Sdf {
            line,
            element,
            message,
            ..
        }) => (line, element, message),
        Err(e) => panic!("not an SDFormat error: {e}"),
    }
}

fn close(a: &Se3, b: &Se3) -> bool {
    a.abs_diff_eq(b, 1e-12, 1e-12)
}

fn joint<'m>(m: &'m Model, name: &str) -> &'m kinetree_model::Joint {
    m.joint(
        m.joint_index(name)
            .unwrap_or_else(|| panic!("no joint {name}")),
    )
}

fn temp_dir(what: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kinetree-sdf-{what}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_free_tree_floats_from_where_the_file_puts_it() {
    let sdf = model(
        r#"<pose>1 2 3 0 0 0</pose>
        <link name="base"><pose>0 0 1 0 0 1.5707963267948966</pose></link>
        <link name="arm"/>
        <joint name="shoulder" type="continuous"><parent>base</parent><child>arm</child>
          <axis><xyz>0 0 1</xyz></axis></joint>"#,
    );
    let loaded = load_sdf_str(&sdf, &SdfOptions::default()).unwrap();
    let m = &loaded.model;
    // Names as written, no `m::` prefix; the floating joint is named after the root link.
    assert_eq!((m.nq(), m.nv()), (8, 7));
    assert_eq!(joint(m, "base").kind, JointKind::Floating);
    assert!(close(&joint(m, "base").placement, &Se3::IDENTITY));
    assert_eq!(joint(m, "shoulder").kind, JointKind::Continuous);
    // q0: the base at model pose · link pose = (1, 2, 4), a quarter turn about z.
    let h = 0.5f64.sqrt();
    let q0 = &loaded.q0;
    let at = m.joint_q_range(m.joint_index("base").unwrap()).start;
    let expected = [1.0, 2.0, 4.0, 0.0, 0.0, h, h];
    for k in 0..7 {
        assert!((q0[at + k] - expected[k]).abs() < 1e-15, "{q0:?}");
    }
    // Welding free trees instead (the `--floating` choice): a fixed joint at that pose.
    let options = SdfOptions {
        free_trees: RootJoint::Fixed,
        ..SdfOptions::default()
    };
    let welded = load_sdf_str(&sdf, &options).unwrap().model;
    assert_eq!((welded.nq(), welded.nv()), (1, 1));
    let base = joint(&welded, "base");
    assert_eq!(base.kind, JointKind::Fixed);
    assert!(close(
        &base.placement,
        &Se3::from_xyz_rpy([1.0, 2.0, 4.0], [0.0, 0.0, FRAC_PI_2])
    ));
}

#[test]
fn several_free_trees_get_one_floating_joint_each() {
    let m = load(&model(
        r#"<link name="a"/><link name="b"><pose>0 1 0 0 0 0</pose></link>
        <link name="c"/><joint name="bc" type="fixed"><parent>b</parent><child>c</child></joint>"#,
    ));
    assert_eq!((m.nq(), m.nv()), (14, 12));
    assert_eq!(joint(&m, "a").kind, JointKind::Floating);
    assert_eq!(joint(&m, "b").kind, JointKind::Floating);
    assert!(m.joint_index("c").is_none());
}

#[test]
fn relative_to_composes_poses_through_frames() {
    // f sits 1 m along a's x axis, a is turned a quarter about z: f is at (0, 1, 0) in the
    // model; b is 1 m along f's x axis (f is turned like a): (0, 2, 0), turned by a quarter.
    let m = load(&model(
        r#"<link name="a"><pose>0 0 0 0 0 1.5707963267948966</pose></link>
        <frame name="f" attached_to="a"><pose>1 0 0 0 0 0</pose></frame>
        <link name="b"><pose relative_to="f">1 0 0 0 0 0</pose></link>
        <joint name="ab" type="fixed"><parent>a</parent><child>b</child></joint>"#,
    ));
    // The fixed joint's frame defaults to the child's: b in a's frame is (2, 0, 0).
    assert!(close(
        &joint(&m, "ab").placement,
        &Se3::from_translation(DVec3::new(2.0, 0.0, 0.0))
    ));
    // The <frame> is a named frame of a, 1 m along its x axis.
    let f = &m.frames()[m.frame_index("f").unwrap()];
    assert_eq!(m.link(f.link).name, "a");
    assert!(close(&f.placement, &Se3::from_translation(DVec3::X)));
}

#[test]
fn a_joint_posed_off_its_child_carries_it_through_a_massless_link() {
    // cart_pole's pin: the joint is 0.5 m above the pole's frame (its pose is relative to the
    // child), the pole 0.5 m below the cart.
    let m = load(&model(
        r#"<link name="cart"/>
        <link name="pole"><pose>0 0 -0.5 0 0 0</pose></link>
        <joint name="pin" type="revolute"><pose>0 0 0.5 0 0 0</pose>
          <parent>cart</parent><child>pole</child><axis><xyz>0 -1 0</xyz></axis></joint>"#,
    ));
    let pin = joint(&m, "pin");
    assert!(close(&pin.placement, &Se3::IDENTITY));
    assert_eq!(m.link(pin.child_link).name, "pin:frame");
    assert_eq!(pin.axis, DVec3::new(0.0, -1.0, 0.0));
    let carry = joint(&m, "pin:child");
    assert_eq!(carry.kind, JointKind::Fixed);
    assert!(close(
        &carry.placement,
        &Se3::from_translation(DVec3::new(0.0, 0.0, -0.5))
    ));
    // A child posed at its joint needs no extra link.
    let m = load(&model(
        r#"<link name="a"/>
        <joint name="j" type="prismatic"><pose relative_to="a">0 0 1 0 0 0</pose>
          <parent>a</parent><child>b</child><axis><xyz>1 0 0</xyz></axis></joint>
        <link name="b"><pose relative_to="j"/></link>"#,
    ));
    assert_eq!(m.links().len(), 2);
    assert!(close(
        &joint(&m, "j").placement,
        &Se3::from_translation(DVec3::Z)
    ));
}

#[test]
fn axes_expressed_in_another_frame_are_turned_into_the_joint_frame() {
    // b is turned a quarter about z: the model's x axis is −y in b's frame (the joint frame).
    let sdf = r#"<link name="a"/><link name="b"><pose>0 0 0 0 0 1.5707963267948966</pose></link>
        <joint name="j" type="revolute"><parent>a</parent><child>b</child>
          <axis><xyz expressed_in="__model__">1 0 0</xyz>
            <limit><lower>-1</lower><upper>1</upper></limit></axis></joint>"#;
    let axis = joint(&load(&model(sdf)), "j").axis;
    assert!(
        (axis - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-15,
        "{axis}"
    );
    // SDFormat 1.6: `use_parent_model_frame` says the same.
    let old = format!(
        "<sdf version=\"1.6\"><model name=\"m\">{}</model></sdf>",
        sdf.replace(
            "<xyz expressed_in=\"__model__\">1 0 0</xyz>",
            "<xyz>1 0 0</xyz><use_parent_model_frame>true</use_parent_model_frame>"
        )
    );
    let axis = joint(&load(&old), "j").axis;
    assert!(
        (axis - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-15,
        "{axis}"
    );
    // Without it, the axis is in the joint frame.
    let plain = old.replace("<use_parent_model_frame>true</use_parent_model_frame>", "");
    assert_eq!(joint(&load(&plain), "j").axis, DVec3::X);
}

#[test]
fn limits_and_dynamics_are_read_and_unbounded_revolutes_are_continuous() {
    let m = load(&model(
        r#"<link name="a"/><link name="b"/><link name="c"/><link name="d"/>
        <joint name="r" type="revolute"><parent>a</parent><child>b</child>
          <axis><xyz>0 1 0</xyz><limit><lower>-0.5</lower><upper>2</upper>
            <effort>30</effort><velocity>-1</velocity></limit>
            <dynamics><damping>0.1</damping><friction>0.2</friction></dynamics></axis></joint>
        <joint name="free_spin" type="revolute"><parent>b</parent><child>c</child>
          <axis><xyz>0 0 2</xyz><limit><effort>0</effort></limit></axis></joint>
        <joint name="slide" type="prismatic"><parent>c</parent><child>d</child>
          <axis><xyz>1 0 0</xyz><limit><lower>-0.3</lower><upper>0</upper></limit></axis></joint>
        <joint name="weld" type="fixed"><parent>world</parent><child>a</child></joint>"#,
    ));
    let r = joint(&m, "r");
    assert_eq!(r.kind, JointKind::Revolute);
    assert_eq!((r.limits.lower, r.limits.upper), (-0.5, 2.0));
    assert_eq!((r.limits.effort, r.limits.velocity), (30.0, f64::INFINITY));
    assert_eq!((r.dynamics.damping, r.dynamics.friction), (0.1, 0.2));
    let spin = joint(&m, "free_spin");
    assert_eq!(spin.kind, JointKind::Continuous);
    assert_eq!(spin.axis, DVec3::Z, "the axis is normalised");
    let slide = joint(&m, "slide");
    assert_eq!(slide.kind, JointKind::Prismatic);
    assert_eq!((slide.limits.lower, slide.limits.upper), (-0.3, 0.0));
    // Welded to the world: no floating joint.
    assert_eq!((m.nq(), m.nv()), (3, 3));
    assert_eq!(joint(&m, "weld").parent_link, None);
}

#[test]
fn inertials_have_their_pose_and_links_without_one_weigh_one_kilogram() {
    let m = load(&model(
        r#"<link name="a"><inertial><pose>0.1 0 0 0 0 1.5707963267948966</pose><mass>2</mass>
          <inertia><ixx>1</ixx><iyy>2</iyy><izz>3</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz>
          </inertia></inertial></link>
        <link name="b"/>
        <joint name="j" type="fixed"><parent>a</parent><child>b</child></joint>"#,
    ));
    let a = m.link(m.link_index("a").unwrap()).inertia();
    assert_eq!(a.mass, 2.0);
    assert!((a.com - DVec3::new(0.1, 0.0, 0.0)).length() < 1e-15);
    // The inertial frame is turned a quarter about z: its x and y moments swap in link axes.
    let i = a.rotational.to_mat3();
    assert!((i.x_axis.x - 2.0).abs() < 1e-12 && (i.y_axis.y - 1.0).abs() < 1e-12);
    assert!((i.z_axis.z - 3.0).abs() < 1e-12);
    let b = m.link(m.link_index("b").unwrap()).inertia();
    assert_eq!(b.mass, 1.0);
    assert!(b.rotational.to_mat3().abs_diff_eq(DMat3::IDENTITY, 1e-15));
}

#[test]
fn slightly_impossible_inertias_load_with_a_warning() {
    // 1 + 1 < 2.5: the triangle inequality fails, as in real exported files.
    let m = load(&model(
        r#"<link name="a"><inertial><mass>1</mass><inertia><ixx>1</ixx><iyy>1</iyy>
          <izz>2.5</izz></inertia></inertial></link>"#,
    ));
    assert_eq!(m.warnings().len(), 1, "{:?}", m.warnings());
}

#[test]
fn geometry_of_every_kind() {
    let dir = temp_dir("mesh");
    std::fs::write(dir.join("part.stl"), "solid part\nendsolid part\n").unwrap();
    let sdf = model(
        r#"<link name="a">
          <collision name="box"><pose>0 0 1 0 0 0</pose><geometry><box><size>1 2 3</size></box></geometry></collision>
          <collision name="cyl"><geometry><cylinder><radius>0.1</radius><length>0.5</length></cylinder></geometry></collision>
          <collision name="ball"><geometry><sphere><radius>0.2</radius></sphere></geometry></collision>
          <collision name="pill"><geometry><capsule><radius>0.1</radius><length>0.3</length></capsule></geometry></collision>
          <collision name="egg"><geometry><ellipsoid><radii>1 2 3</radii></ellipsoid></geometry></collision>
          <visual name="mesh"><geometry><mesh><uri>part.stl</uri><scale>1 -1 2</scale></mesh></geometry>
            <material><diffuse>1 0 0 1</diffuse></material></visual>
          <visual name="remote"><geometry><mesh><uri>model://somewhere/else.stl</uri></mesh></geometry></visual>
        </link>"#,
    );
    std::fs::write(dir.join("shapes.sdf"), &sdf).unwrap();
    let m = Model::from_sdf_file(dir.join("shapes.sdf")).unwrap();
    let a = m.link(m.link_index("a").unwrap());
    let shapes: Vec<&Geometry> = a.collisions.iter().map(|c| &c.geometry).collect();
    assert_eq!(
        shapes,
        [
            &Geometry::Box {
                size: [1.0, 2.0, 3.0]
            },
            &Geometry::Cylinder {
                radius: 0.1,
                length: 0.5
            },
            &Geometry::Sphere { radius: 0.2 },
            &Geometry::Capsule {
                radius: 0.1,
                length: 0.3
            },
        ]
    );
    assert!(close(
        &a.collisions[0].origin,
        &Se3::from_translation(DVec3::Z)
    ));
    // A relative mesh path is resolved from the file's folder; an unresolved model:// URI is
    // kept as written, with a note.
    match &a.visuals[0].geometry {
        Geometry::Mesh { filename, scale } => {
            assert_eq!(PathBuf::from(filename), dir.join("part.stl"));
            assert_eq!(*scale, [1.0, -1.0, 2.0]);
        }
        other => panic!("{other:?}"),
    }
    assert!(
        matches!(&a.visuals[1].geometry, Geometry::Mesh { filename, .. } if filename == "model://somewhere/else.stl")
    );
    let ignored = m.ignored().join("; ");
    assert!(ignored.contains("ellipsoid"), "{ignored}");
    assert!(ignored.contains("visual/material"), "{ignored}");
    assert!(ignored.contains("model://somewhere/else.stl"), "{ignored}");
}

#[test]
fn static_models_are_welded_where_the_file_puts_them() {
    let m = load(&model(
        r#"<static>true</static><pose>0 0 1 0 0 0</pose>
        <link name="wall"><pose>2 0 0 0 0 0</pose></link>
        <link name="door"/>
        <joint name="hinge" type="revolute"><parent>wall</parent><child>door</child>
          <axis><xyz>0 0 1</xyz></axis></joint>"#,
    ));
    assert_eq!((m.nq(), m.nv()), (0, 0));
    assert!(close(
        &joint(&m, "wall").placement,
        &Se3::from_translation(DVec3::new(2.0, 0.0, 1.0))
    ));
    assert_eq!(joint(&m, "door").kind, JointKind::Fixed);
    assert!(m.joint_index("hinge").is_none());
}

#[test]
fn a_world_of_several_models_prefixes_their_names() {
    let m = load(
        r#"<sdf version="1.9"><world name="w"><gravity>0 0 -1.62</gravity>
        <model name="r1"><pose>1 0 0 0 0 0</pose><link name="base"/></model>
        <model name="r2"><pose>-1 0 0 0 0 0</pose><link name="base"/><link name="arm"/>
          <joint name="j" type="revolute"><parent>base</parent><child>arm</child>
          <axis><xyz>0 0 1</xyz></axis></joint></model>
        <physics type="ode"/></world></sdf>"#,
    );
    assert_eq!(m.gravity(), DVec3::new(0.0, 0.0, -1.62));
    for name in ["r1::base", "r2::base", "r2::arm"] {
        assert!(m.link_index(name).is_some(), "{name}");
    }
    assert_eq!(joint(&m, "r2::j").kind, JointKind::Continuous);
    assert_eq!(joint(&m, "r1::base").kind, JointKind::Floating);
    assert_eq!((m.nq(), m.nv()), (15, 13));
    assert!(m.ignored().iter().any(|x| x.contains("world/physics")));
}

#[test]
fn nested_models_and_includes_through_the_search_path() {
    let dir = temp_dir("include");
    let lib = dir.join("lib");
    std::fs::create_dir_all(lib.join("gripper")).unwrap();
    std::fs::write(
        lib.join("gripper/model.config"),
        "<model><name>gripper</name><sdf version=\"1.9\">gripper.sdf</sdf></model>",
    )
    .unwrap();
    std::fs::write(
        lib.join("gripper/gripper.sdf"),
        r#"<sdf version="1.9"><model name="gripper"><pose>5 5 5 0 0 0</pose>
        <link name="palm"/><link name="finger"><pose>0 0 0.1 0 0 0</pose></link>
        <joint name="slide" type="prismatic"><parent>palm</parent><child>finger</child>
          <axis><xyz>1 0 0</xyz></axis></joint></model></sdf>"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("arm.sdf"),
        r#"<sdf version="1.9"><model name="arm">
        <link name="base"/>
        <model name="wrist"><pose relative_to="base">0 0 1 0 0 0</pose><link name="flange"/></model>
        <joint name="w" type="fixed"><parent>base</parent><child>wrist::flange</child></joint>
        <include><uri>model://gripper</uri><name>hand</name>
          <pose relative_to="wrist::flange">0 0 0.2 0 0 0</pose></include>
        <joint name="mount" type="fixed"><parent>wrist::flange</parent><child>hand::palm</child></joint>
        </model></sdf>"#,
    )
    .unwrap();
    let options = SdfOptions {
        free_trees: RootJoint::Fixed,
        search_path: vec![lib],
    };
    let m = load_sdf_file(dir.join("arm.sdf"), &options).unwrap().model;
    // Nested items are prefixed by their model; the include's pose replaces the file's.
    assert!(close(
        &joint(&m, "w").placement,
        &Se3::from_translation(DVec3::Z)
    ));
    assert!(close(
        &joint(&m, "mount").placement,
        &Se3::from_translation(DVec3::new(0.0, 0.0, 0.2))
    ));
    assert_eq!(joint(&m, "hand::slide").kind, JointKind::Prismatic);
    assert!(close(
        &joint(&m, "hand::slide").placement,
        &Se3::from_translation(DVec3::new(0.0, 0.0, 0.1))
    ));
    assert_eq!((m.nq(), m.nv()), (1, 1));
}

#[test]
fn include_loops_and_missing_includes_are_refused() {
    let dir = temp_dir("loop");
    std::fs::write(
        dir.join("a.sdf"),
        "<sdf version=\"1.9\"><model name=\"a\"><link name=\"l\"/>\n<include><uri>b.sdf</uri></include></model></sdf>",
    )
    .unwrap();
    std::fs::write(
        dir.join("b.sdf"),
        "<sdf version=\"1.9\"><model name=\"b\"><link name=\"l\"/>\n\n<include><uri>a.sdf</uri></include></model></sdf>",
    )
    .unwrap();
    match Model::from_sdf_file(dir.join("a.sdf")) {
        Err(ModelError::Sdf {
            file,
            line,
            element,
            message,
        }) => {
            assert_eq!(file, Some(dir.join("b.sdf")));
            assert_eq!((line, element.as_str()), (3, "include"));
            assert!(message.contains("include loop"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let (line, element, message) = sdf_error(&model(
        "<link name=\"l\"/>\n<include><uri>model://nowhere</uri></include>",
    ));
    assert_eq!((line, element.as_str()), (2, "include"));
    assert!(message.contains("not found"), "{message}");
}

#[test]
fn universal_joints_are_two_revolutes_about_their_axes() {
    let m = load(&model(
        r#"<link name="a"/><link name="b"/>
        <joint name="u" type="universal"><parent>a</parent><child>b</child>
          <axis><xyz>0 0 1</xyz></axis><axis2><xyz>0 1 0</xyz></axis2></joint>"#,
    ));
    assert_eq!((m.nq(), m.nv()), (9, 8));
    let first = joint(&m, "u.rx");
    let second = joint(&m, "u.ry");
    assert_eq!((first.axis, second.axis), (DVec3::X, DVec3::Y));
    // The composite frame turns x onto the first axis (z) and y onto the second (y).
    let r = first.placement.rotation;
    assert!((r * DVec3::X - DVec3::Z).length() < 1e-15);
    assert!((r * DVec3::Y - DVec3::Y).length() < 1e-15);
    let u = m.user_joint_index("u").unwrap();
    assert_eq!(m.user_joint_q_range(u).len(), 2);
}

#[test]
fn screw_and_gearbox_joints_are_refused_by_name() {
    for kind in ["screw", "gearbox"] {
        let (line, element, message) = sdf_error(&model(&format!(
            "<link name=\"a\"/><link name=\"b\"/>\n<joint name=\"s\" type=\"{kind}\"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>"
        )));
        assert_eq!((line, element.as_str()), (2, "joint"));
        assert!(message.contains("'s'"), "{message}");
    }
}

#[test]
fn bad_documents_give_errors_naming_element_and_line() {
    let cases: [(&str, usize, &str, &str); 9] = [
        (
            "<link name=\"a\">\n<pose relative_to=\"nowhere\">0 0 0 0 0 0</pose></link>",
            2,
            "pose",
            "names no frame",
        ),
        (
            "<frame name=\"f\"><pose relative_to=\"g\"/></frame>\n<frame name=\"g\"><pose relative_to=\"f\"/></frame><link name=\"a\"/>",
            1,
            "pose",
            "cycle",
        ),
        (
            "<link name=\"a\"/><link name=\"b\"/>\n<joint name=\"ab\" type=\"fixed\"><parent>a</parent><child>b</child></joint>\n<joint name=\"ba\" type=\"fixed\"><parent>b</parent><child>a</child></joint>",
            3,
            "joint",
            "loop",
        ),
        (
            "<link name=\"a\"><visual name=\"v\"><geometry><mesh>\n<uri>missing.stl</uri></mesh></geometry></visual></link>",
            2,
            "uri",
            "not found",
        ),
        (
            "<link name=\"a\"><inertial>\n<mass>1e300</mass></inertial></link>",
            2,
            "mass",
            "absurd",
        ),
        (
            "<link name=\"a\"><inertial>\n<mass>-1</mass></inertial></link>",
            2,
            "mass",
            "negative",
        ),
        (
            "<link name=\"a\">\n<pose>0 0 nan 0 0 0</pose></link>",
            2,
            "pose",
            "not a finite number",
        ),
        (
            "<link name=\"a\"><collision name=\"c\"><geometry>\n<torus/></geometry></collision></link>",
            2,
            "torus",
            "unknown geometry",
        ),
        (
            "<link name=\"a\"/>\n<link name=\"a\"/>",
            2,
            "link",
            "already used",
        ),
    ];
    for (body, line, element, message) in cases {
        let (l, e, m) = sdf_error(&model(body));
        assert_eq!((l, e.as_str()), (line, element), "{body}: {m}");
        assert!(m.contains(message), "{body}: {m}");
    }
    let (_, element, message) = sdf_error("<sdf version=\"1.9\"><robot name=\"r\"/></sdf>");
    assert_eq!(element, "robot");
    assert!(message.contains("unknown element"), "{message}");
}

#[test]
fn unknown_elements_in_models_links_and_joints_are_noted() {
    let m = load(&model(
        r#"<plugin name="p" filename="x.so"/><plugin name="q" filename="y.so"/>
        <link name="a"><sensor name="imu" type="imu"/><foo/></link>
        <link name="b"/>
        <joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>1 0 0</xyz></axis>
          <stopKd>1</stopKd><physics><ode><provide_feedback>true</provide_feedback></ode></physics></joint>"#,
    ));
    let ignored = m.ignored().join("; ");
    for what in [
        "model/plugin (×2)",
        "link/sensor",
        "link/foo (unknown element)",
        "joint/stopKd (unknown element)",
        "joint/physics",
    ] {
        assert!(ignored.contains(what), "{what} in {ignored}");
    }
}

#[test]
fn poses_as_quaternions_and_in_degrees() {
    let m = load(&model(
        r#"<link name="a"/>
        <link name="b"><pose rotation_format="quat_xyzw">1 0 0 0 0 0.7071067811865476 0.7071067811865476</pose></link>
        <link name="c"><pose degrees="true">0 0 0 0 0 90</pose></link>
        <joint name="ab" type="fixed"><parent>a</parent><child>b</child></joint>
        <joint name="ac" type="fixed"><parent>a</parent><child>c</child></joint>"#,
    ));
    let quarter = Se3::from_rotation_z(FRAC_PI_2);
    assert!(close(
        &joint(&m, "ab").placement,
        &(Se3::from_translation(DVec3::X) * quarter)
    ));
    assert!(close(&joint(&m, "ac").placement, &quarter));
}

#[test]
fn a_placement_frame_puts_that_frame_at_the_model_pose() {
    // The model's pose places its frame `foot` (0.5 m below the body) at (0, 0, 0): the body
    // ends up 0.5 m up.
    let loaded = load_sdf_str(
        r#"<sdf version="1.9"><model name="m" placement_frame="foot">
        <link name="body"/><frame name="foot" attached_to="body"><pose>0 0 -0.5 0 0 0</pose></frame>
        </model></sdf>"#,
        &SdfOptions::default(),
    )
    .unwrap();
    assert_eq!(&loaded.q0[..3], &[0.0, 0.0, 0.5]);
}

#[test]
fn from_file_recognises_sdformat_by_its_root() {
    let dir = temp_dir("from-file");
    let path = dir.join("robot.xml");
    std::fs::write(&path, model("<link name=\"a\"/>")).unwrap();
    let floating = Model::from_file(&path, None).unwrap();
    assert_eq!(floating.nq(), 7);
    let fixed = Model::from_file(&path, RootJoint::Fixed).unwrap();
    assert_eq!(fixed.nq(), 0);
}

#[test]
fn mimic_joints_follow_their_leader() {
    // SDFormat: q = offset + multiplier · (q_leader − reference) = 2 q_leader + (0.1 − 2·0.3).
    let m = load(&model(
        r#"<link name="a"/><link name="b"/><link name="c"/>
        <joint name="lead" type="prismatic"><parent>a</parent><child>b</child><axis><xyz>1 0 0</xyz></axis></joint>
        <joint name="follow" type="prismatic"><parent>a</parent><child>c</child><axis><xyz>0 1 0</xyz>
          <mimic joint="lead"><multiplier>2</multiplier><offset>0.1</offset><reference>0.3</reference></mimic>
        </axis></joint>"#,
    ));
    let mimic = joint(&m, "follow").mimic.clone().unwrap();
    assert_eq!(mimic.joint, "lead");
    assert_eq!(mimic.multiplier, 2.0);
    assert!((mimic.offset - (0.1 - 0.6)).abs() < 1e-15);
}

#[test]
fn frames_of_merged_links_are_named_frames_of_their_host() {
    // libsdformat ≥ 12.7 keeps a lumped link as `<frame name="J" attached_to="PARENT">` (its
    // fixed joint) and `<frame name="LINK" attached_to="J">`.
    let m = load(&model(
        r#"<link name="arm"/>
        <frame name="tool_joint" attached_to="arm"><pose>0 0 0.1 0 0 1.5707963267948966</pose></frame>
        <frame name="tool" attached_to="tool_joint"/>"#,
    ));
    let tool = &m.frames()[m.frame_index("tool").unwrap()];
    assert_eq!(m.link(tool.link).name, "arm");
    assert!(close(
        &tool.placement,
        &Se3::from_xyz_rpy([0.0, 0.0, 0.1], [0.0, 0.0, FRAC_PI_2])
    ));
}

/// Deterministic mutations of real files (cut, repeated and swapped ranges, numbers replaced by
/// NaN, huge or negative values, names swapped): every outcome is a model with finite numbers
/// or a typed error, never a panic.
#[test]
fn mutated_files_give_models_or_typed_errors() {
    let dir = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/reference/sdf"
    ));
    let sources = [
        "drake/models/examples/multibody/cart_pole/cart_pole.sdf",
        "drake/models/examples/planar_gripper/planar_gripper.sdf",
        "converted/ur5.sdf",
    ];
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let replacements = [
        "nan",
        "1e308",
        "-1",
        "0",
        "world",
        "__model__",
        "base_link",
        "</link>",
        "<pose>",
        "relative_to=\"x\"",
        "::",
    ];
    let (mut loaded, mut refused) = (0, 0);
    for source in sources {
        let text = std::fs::read_to_string(dir.join(source)).unwrap();
        // ASCII text and replacements: every byte offset is a character boundary.
        assert!(text.is_ascii());
        for _ in 0..300 {
            let mut t = text.clone();
            for _ in 0..1 + next(3) {
                let a = next(t.len());
                let b = (a + next(40)).min(t.len());
                match next(3) {
                    0 => t.replace_range(a..b, ""),
                    1 => {
                        let piece = t[a..b].to_string();
                        t.insert_str(b, &piece);
                    }
                    _ => t.replace_range(a..b, replacements[next(replacements.len())]),
                }
            }
            match Model::from_sdf_str(&t) {
                Ok(m) => {
                    loaded += 1;
                    for j in m.joints() {
                        assert!(j.placement.is_finite() && j.axis.is_finite(), "{t}");
                    }
                    for l in m.links() {
                        let i = l.inertia();
                        assert!(i.mass.is_finite() && i.com.is_finite(), "{t}");
                    }
                }
                Err(_) => refused += 1,
            }
        }
    }
    assert!(
        loaded > 0 && refused > 0,
        "{loaded} loaded, {refused} refused"
    );
}
