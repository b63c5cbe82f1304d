//! Bad input: every kind of error is a typed `Err` whose message names the offending item.

use glam::DVec3;
use kinetree_model::{
    Issue, ItemKind, JointKind, JointSpec, Link, Model, ModelBuilder, ModelError, RootJoint,
};
use kinetree_spatial::{InertiaDefect, Se3};
use std::path::PathBuf;

fn urdf_err(urdf: &str) -> ModelError {
    Model::from_urdf_str(urdf, RootJoint::Fixed).expect_err("the URDF must be rejected")
}

fn json_err(json: &str) -> ModelError {
    Model::from_json_str(json, None).expect_err("the JSON must be rejected")
}

/// A two-link URDF whose joint has the given inner XML.
fn joint_urdf(joint_type: &str, inner: &str) -> String {
    format!(
        r#"<robot name="r">
  <link name="base"/>
  <link name="arm"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="elbow" type="{joint_type}"><parent link="base"/><child link="arm"/>{inner}</joint>
</robot>"#
    )
}

#[test]
fn malformed_xml_gives_line_and_column() {
    let urdf = "<robot name=\"r\">\n  <link name=\"a\">\n  </joint>\n</robot>\n";
    let e = urdf_err(urdf);
    let ModelError::Xml { line, column, .. } = &e else {
        panic!("expected ModelError::Xml, got {e:?}");
    };
    assert_eq!((*line, *column), (3, 3), "{e}");
    assert!(e.to_string().contains("at line 3, column 3"), "{e}");
    assert!(e.to_string().contains("joint"), "{e}");
    // From a file, the file is named too.
    let path = std::env::temp_dir().join(format!("kinetree-bad-{}.urdf", std::process::id()));
    std::fs::write(&path, urdf).unwrap();
    let e = Model::from_urdf_file(&path, RootJoint::Fixed).unwrap_err();
    assert!(
        matches!(&e, ModelError::Xml { file: Some(f), line: 3, .. } if *f == path),
        "{e}"
    );
    assert!(e.to_string().contains(&path.display().to_string()), "{e}");
    let _ = std::fs::remove_file(&path);
}

#[test]
fn a_missing_file_is_an_io_error_naming_it() {
    let path = PathBuf::from("/nonexistent/kinetree/robot.urdf");
    let e = Model::from_urdf_file(&path, RootJoint::Fixed).unwrap_err();
    assert!(
        matches!(&e, ModelError::Io { path: p, .. } if *p == path),
        "{e}"
    );
    assert!(
        e.to_string().contains("/nonexistent/kinetree/robot.urdf"),
        "{e}"
    );
    let e = Model::from_json_file(path.with_extension("json"), None).unwrap_err();
    assert!(matches!(e, ModelError::Io { .. }), "{e}");
}

#[test]
fn two_roots() {
    let e = urdf_err(r#"<robot name="r"><link name="left"/><link name="right"/></robot>"#);
    assert_eq!(
        e.issues(),
        [Issue::MultipleRoots {
            links: vec!["left".into(), "right".into()]
        }]
    );
    assert!(e.to_string().contains("left, right"), "{e}");
}

#[test]
fn a_cycle() {
    let e = urdf_err(
        r#"<robot name="loop">
  <link name="root"/><link name="a"/><link name="b"/>
  <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
  <joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint>
</robot>"#,
    );
    let [Issue::Cycle { link }] = e.issues() else {
        panic!("expected one cycle, got {e}");
    };
    assert!(link == "a" || link == "b", "{e}");
    assert!(
        e.to_string()
            .contains(&format!("cycle through link '{link}'")),
        "{e}"
    );
}

#[test]
fn an_unknown_mimic_target_in_the_builder() {
    let mut b = ModelBuilder::new("m");
    b.add_link(Link::new("base")).add_link(Link::new("finger"));
    b.add_joint(
        JointSpec::new("knuckle", JointKind::Revolute, "base", "finger")
            .with_mimic("thumb", 2.0, 0.0),
    );
    let e = b.build().unwrap_err();
    assert!(
        matches!(e.issues(), [Issue::UnknownMimicTarget { joint, target }] if joint == "knuckle" && target == "thumb")
    );
    assert!(
        e.to_string()
            .contains("joint 'knuckle' mimics unknown joint 'thumb'"),
        "{e}"
    );
}

#[test]
fn a_negative_mass() {
    let e = urdf_err(
        r#"<robot name="r"><link name="lead"><inertial><mass value="-2"/>
           <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>"#,
    );
    assert!(
        matches!(e.issues(), [Issue::InvalidInertia { link, mass, defect: InertiaDefect::NegativeMass { mass: m } }] if link == "lead" && *mass == -2.0 && *m == -2.0),
        "{e}"
    );
    // Said as it is (it was "not positive semi-definite (principal moment -2e0)").
    assert!(
        e.to_string().contains("link 'lead'")
            && e.to_string().contains("the mass -2 kg is negative"),
        "{e}"
    );
    // JSON goes through the same checks.
    let e = json_err(
        r#"{"links": [{"name": "lead", "inertial": {"mass": -2, "inertia": {"ixx": 1, "iyy": 1, "izz": 1}}}]}"#,
    );
    assert!(
        e.to_string().contains("link 'lead'") && e.to_string().contains("mass -2"),
        "{e}"
    );
}

#[test]
fn a_nan_in_an_origin() {
    let e = urdf_err(&joint_urdf("fixed", r#"<origin xyz="0 NaN 0"/>"#));
    assert_eq!(
        e.issues(),
        [Issue::NonFinite {
            kind: ItemKind::Joint,
            name: "elbow".into(),
            what: "origin"
        }]
    );
    assert!(
        e.to_string()
            .contains("joint 'elbow' has a non-finite origin"),
        "{e}"
    );
    // The builder checks links' inertial origins as well.
    let mut b = ModelBuilder::new("m");
    b.add_link(Link::new("a").with_mass(
        1.0,
        DVec3::new(f64::NAN, 0.0, 0.0),
        kinetree_spatial::Symmetric3::IDENTITY,
    ));
    let e = b.build().unwrap_err();
    assert!(
        e.to_string()
            .contains("link 'a' has a non-finite inertial origin"),
        "{e}"
    );
}

#[test]
fn a_zero_axis() {
    let e = urdf_err(&joint_urdf(
        "revolute",
        r#"<axis xyz="0 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>"#,
    ));
    assert_eq!(
        e.issues(),
        [Issue::InvalidAxis {
            joint: "elbow".into(),
            axis: [0.0; 3]
        }]
    );
    assert!(
        e.to_string()
            .contains("joint 'elbow' has a zero or non-finite axis"),
        "{e}"
    );
}

#[test]
fn lower_above_upper() {
    let e = urdf_err(&joint_urdf(
        "prismatic",
        r#"<axis xyz="1 0 0"/><limit lower="0.5" upper="-0.5" effort="1" velocity="1"/>"#,
    ));
    assert_eq!(
        e.issues(),
        [Issue::InvalidLimits {
            joint: "elbow".into(),
            lower: 0.5,
            upper: -0.5
        }]
    );
    assert!(
        e.to_string()
            .contains("joint 'elbow' has lower limit 0.5 > upper limit -0.5"),
        "{e}"
    );
}

#[test]
fn duplicate_names() {
    let e = urdf_err(
        r#"<robot name="r"><link name="base"/><link name="arm"/><link name="arm"/>
           <joint name="j" type="fixed"><parent link="base"/><child link="arm"/></joint></robot>"#,
    );
    assert!(
        e.issues().contains(&Issue::DuplicateName {
            kind: ItemKind::Link,
            name: "arm".into()
        }),
        "{e}"
    );
    assert!(e.to_string().contains("duplicate link name 'arm'"), "{e}");
    let e = json_err(
        r#"{"links": [{"name": "a"}], "frames": [{"name": "tcp", "link": "a"}, {"name": "tcp", "link": "a"}]}"#,
    );
    assert!(
        e.to_string().contains("duplicate frame name 'a/tcp'"),
        "{e}"
    );
}

#[test]
fn an_unknown_parent_frame() {
    let e = json_err(
        r#"{"links": [{"name": "base"}, {"name": "arm"}],
            "frames": [{"name": "mount", "link": "arm"}],
            "joints": [{"name": "j", "type": "fixed", "parent": "base", "child": "arm", "parent_frame": "mount"}]}"#,
    );
    assert_eq!(
        e.issues(),
        [Issue::UnknownParentFrame {
            joint: "j".into(),
            frame: "mount".into(),
            link: "base".into()
        }]
    );
    assert!(
        e.to_string()
            .contains("joint 'j' attaches to unknown frame 'mount' of link 'base'"),
        "{e}"
    );
}

#[test]
fn an_unknown_unit_name() {
    let e = json_err(r#"{"units": {"length": "inch"}, "links": []}"#);
    assert!(
        matches!(&e, ModelError::UnknownUnit { quantity: "length", unit, .. } if unit == "inch"),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "unknown length unit 'inch' (known: m, cm, mm)"
    );
    let e = json_err(r#"{"units": {"angle": "grad"}}"#);
    assert!(
        e.to_string().contains("'grad'") && e.to_string().contains("rad, deg"),
        "{e}"
    );
}

#[test]
fn wrong_length_arrays() {
    let json = "{\n  \"links\": [{\"name\": \"a\"}],\n  \"frames\": [{\"name\": \"f\", \"link\": \"a\",\n    \"origin\": {\"xyz\": [1, 2]}}]\n}";
    let e = json_err(json);
    let ModelError::Json { line, column, .. } = &e else {
        panic!("expected ModelError::Json, got {e:?}");
    };
    assert_eq!((*line, *column), (4, 29), "{e}");
    assert_eq!(
        e.to_string(),
        "invalid JSON at line 4, column 29: `xyz` must have 3 numbers, found 2"
    );
    for (field, json) in [
        (
            "rpy",
            r#"{"links": [{"name": "a", "inertial": {"mass": 1, "origin": {"rpy": [1, 2, 3, 4]}}}]}"#,
        ),
        (
            "quat",
            r#"{"links": [{"name": "a", "visuals": [{"origin": {"quat": [0, 0, 1]}, "geometry": {"type": "sphere", "radius": 1}}]}]}"#,
        ),
        (
            "size",
            r#"{"links": [{"name": "a", "collisions": [{"geometry": {"type": "box", "size": [1, 2]}}]}]}"#,
        ),
        ("gravity", r#"{"gravity": [0, -9.81]}"#),
        (
            "axis",
            r#"{"links": [{"name": "a"}, {"name": "b"}], "joints": [{"name": "j", "type": "revolute", "parent": "a", "child": "b", "axis": [0, 1]}]}"#,
        ),
    ] {
        let e = json_err(json);
        assert!(
            matches!(
                e,
                ModelError::Json {
                    line: 1,
                    column: 1..,
                    ..
                }
            ),
            "{e}"
        );
        assert!(
            e.to_string().contains(&format!("`{field}` must have")),
            "{e}"
        );
    }
}

#[test]
fn an_unknown_json_field() {
    let e = json_err("{\n  \"name\": \"x\",\n  \"links\": [{\"name\": \"a\", \"mas\": 1}]\n}");
    let ModelError::Json {
        line,
        column,
        message,
        ..
    } = &e
    else {
        panic!("expected ModelError::Json, got {e:?}");
    };
    assert_eq!((*line, *column), (3, 31), "{e}");
    assert!(message.starts_with("unknown field `mas`"), "{message}");
    // A misspelt top-level key, an unknown joint type and a missing required field.
    let e = json_err(r#"{"link": []}"#);
    assert!(e.to_string().contains("unknown field `link`"), "{e}");
    let e = json_err(
        r#"{"links": [{"name": "a"}, {"name": "b"}], "joints": [{"name": "j", "type": "hinge", "parent": "a", "child": "b"}]}"#,
    );
    assert!(e.to_string().contains("unknown variant `hinge`"), "{e}");
    let e = json_err(r#"{"links": [{"inertial": {"mass": 1}}]}"#);
    assert!(e.to_string().contains("missing field `name`"), "{e}");
}

fn datum_model(dir: &std::path::Path, datum_file: &str, datum: &str) -> PathBuf {
    let path = dir.join("model.json");
    std::fs::write(
        &path,
        format!(
            r#"{{"links": [{{"name": "bracket"}}],
                "frames": [{{"name": "horn", "link": "bracket", "datum": {{"file": "{datum_file}", "name": "{datum}"}}}}]}}"#
        ),
    )
    .unwrap();
    path
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kinetree-errors-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_missing_datum_file() {
    let dir = temp_dir("no-datum-file");
    let path = datum_model(&dir, "servo.json", "output_shaft");
    let e = Model::from_json_file(&path, None).unwrap_err();
    let ModelError::Datum {
        frame,
        file,
        datum,
        message,
    } = &e
    else {
        panic!("expected ModelError::Datum, got {e:?}");
    };
    assert_eq!((frame.as_str(), datum.as_str()), ("horn", "output_shaft"));
    assert_eq!(*file, dir.join("servo.json"));
    assert!(
        message.starts_with("cannot read the datum file"),
        "{message}"
    );
    let text = e.to_string();
    assert!(
        text.contains("frame 'horn'")
            && text.contains("'output_shaft'")
            && text.contains("servo.json"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_missing_datum_in_an_existing_file() {
    let dir = temp_dir("no-datum");
    std::fs::write(
        dir.join("servo.json"),
        r#"{"datums": {"mount_face": {"xyz": [0, 0, 0.01]}, "body_center": {}}}"#,
    )
    .unwrap();
    let path = datum_model(&dir, "servo.json", "output_shaft");
    let e = Model::from_json_file(&path, None).unwrap_err();
    assert!(
        matches!(&e, ModelError::Datum { frame, datum, .. } if frame == "horn" && datum == "output_shaft"),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        format!(
            "frame 'horn': datum 'output_shaft' in {}: the file has no datum of that name (it has: body_center, mount_face)",
            dir.join("servo.json").display()
        )
    );
    // A malformed datum file is a datum error too, with the position in that file.
    std::fs::write(
        dir.join("servo.json"),
        "{\"datums\": {\"output_shaft\": {\"xyz\": [0, 0]}}}",
    )
    .unwrap();
    let e = Model::from_json_file(&path, None).unwrap_err();
    assert!(matches!(e, ModelError::Datum { .. }), "{e:?}");
    assert!(
        e.to_string().contains("malformed datum file at line 1"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_cylindrical_joint_cannot_be_written_to_urdf() {
    let mut b = ModelBuilder::new("m");
    b.add_link(Link::new("base"))
        .add_link(Link::new("nut").with_mass(
            1.0,
            DVec3::ZERO,
            kinetree_spatial::Symmetric3::IDENTITY,
        ));
    b.add_joint(JointSpec::new(
        "screw",
        JointKind::Cylindrical,
        "base",
        "nut",
    ));
    let m = b.build().unwrap();
    let e = m.to_urdf_string().unwrap_err();
    assert!(
        matches!(&e, ModelError::UnsupportedJoint { joint, kind: JointKind::Cylindrical, .. } if joint == "screw"),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "joint 'screw' is cylindrical, which URDF cannot express"
    );
}

#[test]
fn several_problems_are_reported_together() {
    let mut b = ModelBuilder::new("many");
    b.add_link(Link::new("base")).add_link(Link::new("a"));
    b.add_joint(
        JointSpec::new("j", JointKind::Prismatic, "base", "a")
            .with_axis(DVec3::ZERO)
            .with_placement(Se3::from_translation(DVec3::new(0.0, f64::INFINITY, 0.0))),
    );
    b.add_joint(JointSpec::new("k", JointKind::Fixed, "nowhere", "a"));
    let e = b.build().unwrap_err();
    let text = e.to_string();
    for part in [
        "joint 'k' has unknown parent link 'nowhere'",
        "joint 'j' has a non-finite origin",
        "joint 'j' has a zero or non-finite axis",
        "link 'a' is the child of several joints: j, k",
    ] {
        assert!(text.contains(part), "missing '{part}' in {text}");
    }
    assert!(!matches!(
        e.issues()[0],
        Issue::InvalidInertia {
            defect: InertiaDefect::NonFinite,
            ..
        }
    ));
}

#[test]
fn a_huge_axis_is_normalized_without_overflow() {
    // |axis|² overflows to inf: the axis used to normalize to [0, 0, 0] (a joint that moves
    // nothing) and pass the zero-axis check.
    let model = Model::from_urdf_str(
        &joint_urdf(
            "revolute",
            r#"<axis xyz="1e308 1e308 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>"#,
        ),
        RootJoint::Fixed,
    )
    .unwrap();
    let axis = model.bodies()[1].axis;
    let h = std::f64::consts::FRAC_1_SQRT_2;
    assert!((axis - DVec3::new(h, h, 0.0)).length() < 1e-15, "{axis}");
    // Tiny but non-zero axes are normalized too; zero and subnormal ones are refused.
    let model = Model::from_urdf_str(
        &joint_urdf(
            "prismatic",
            r#"<axis xyz="0 0 -1e-9"/><limit lower="-1" upper="1" effort="1" velocity="1"/>"#,
        ),
        RootJoint::Fixed,
    )
    .unwrap();
    assert_eq!(model.bodies()[1].axis, DVec3::new(0.0, 0.0, -1.0));
    let e = urdf_err(&joint_urdf(
        "revolute",
        r#"<axis xyz="0 5e-324 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>"#,
    ));
    assert!(matches!(e.issues(), [Issue::InvalidAxis { .. }]), "{e}");
}

#[test]
fn negative_damping_or_friction_is_refused() {
    // A negative damping feeds energy into the motion (a simulation diverged to 1e82 J).
    for (attrs, what) in [
        (r#"damping="-0.5" friction="0""#, "damping"),
        (r#"damping="0" friction="-2""#, "friction"),
    ] {
        let e = urdf_err(&joint_urdf(
            "revolute",
            &format!(
                r#"<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/><dynamics {attrs}/>"#
            ),
        ));
        match e.issues() {
            [Issue::InvalidJointDynamics { joint, what: w, .. }] => {
                assert_eq!(joint, "elbow");
                assert_eq!(*w, what);
            }
            other => panic!("expected InvalidJointDynamics, got {other:?}"),
        }
        assert!(
            e.to_string()
                .contains(&format!("joint 'elbow' has a negative {what}")),
            "{e}"
        );
    }
    // Zero and positive values load.
    Model::from_urdf_str(
        &joint_urdf(
            "revolute",
            r#"<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/><dynamics damping="0.1" friction="0.2"/>"#,
        ),
        RootJoint::Fixed,
    )
    .unwrap();
}

/// Three revolute joints in a chain; `mimics` gives each joint's `<mimic>` leader, if any.
fn mimic_urdf(mimics: [Option<&str>; 3]) -> String {
    let mut s = String::from(r#"<robot name="m"><link name="l0"/>"#);
    for (i, leader) in mimics.iter().enumerate() {
        let mimic = leader
            .map(|l| format!(r#"<mimic joint="{l}"/>"#))
            .unwrap_or_default();
        s += &format!(
            r#"<link name="l{n}"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{n}"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" effort="1" velocity="1"/>{mimic}</joint>"#,
            n = i + 1
        );
    }
    s + "</robot>"
}

#[test]
fn a_mimic_cycle_is_refused_in_every_mode() {
    use kinetree_model::{LoadOptions, MimicMode};
    let urdf = mimic_urdf([Some("j2"), None, Some("j0")]);
    for mode in [MimicMode::Coupled, MimicMode::default()] {
        let options = LoadOptions {
            mimic: mode,
            ..LoadOptions::from(RootJoint::Fixed)
        };
        let e = Model::from_urdf_str_with(&urdf, &options).unwrap_err();
        let cycle = e.issues().iter().filter(|i| {
            matches!(i, Issue::InvalidMimic { joint, reason }
                if joint == "j0" && reason.contains("mimic cycle j0 -> j2 -> j0"))
        });
        assert_eq!(cycle.count(), 1, "{mode:?}: {e}");
    }
    // A chain that ends at a leader is no cycle (and loads uncoupled).
    let chain = mimic_urdf([None, Some("j0"), Some("j1")]);
    assert!(Model::from_urdf_str(&chain, RootJoint::Fixed).is_ok());
}

#[test]
fn a_massless_link_with_rotational_inertia_is_a_warning() {
    let urdf = r#"<robot name="r"><link name="base"/>
  <link name="ghost"><inertial><mass value="0"/><inertia ixx="0.5" ixy="0" ixz="0" iyy="0.5" iyz="0" izz="0.25"/></inertial></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="ghost"/><axis xyz="0 0 1"/>
  <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#;
    let m = Model::from_urdf_str(urdf, RootJoint::Fixed).unwrap();
    assert_eq!(
        m.warnings(),
        [Issue::MasslessInertia {
            link: "ghost".into(),
            largest: 0.5
        }]
    );
    assert!(
        m.warnings()[0]
            .to_string()
            .contains("link 'ghost' has mass 0")
    );
    // Mass 0 and no inertia is simply massless: no warning.
    let clean = urdf
        .replace(r#"ixx="0.5""#, r#"ixx="0""#)
        .replace(r#"iyy="0.5""#, r#"iyy="0""#)
        .replace(r#"izz="0.25""#, r#"izz="0""#);
    assert!(
        Model::from_urdf_str(&clean, RootJoint::Fixed)
            .unwrap()
            .warnings()
            .is_empty()
    );
}
