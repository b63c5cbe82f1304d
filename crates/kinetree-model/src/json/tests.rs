//! Unit tests of JSON import and export.

use super::*;
use crate::error::ModelError;
use crate::joint::JointLimits;
use crate::link::Geometry;
use crate::model::{Model, RootJoint};
use crate::samples;
use core::f64::consts::FRAC_PI_2;
use glam::DVec3;
use kinetree_spatial::{Se3, rotation};
use std::path::PathBuf;

/// The same model in metres and radians ...
const SI: &str = r#"{
  "name": "units",
  "links": [
    { "name": "base" },
    { "name": "arm",
      "inertial": { "origin": { "xyz": [0.1, 0, 0.02], "rpy": [0, 1.5707963267948966, 0] },
                    "mass": 2.0,
                    "inertia": { "ixx": 0.001, "ixy": 0.0002, "iyy": 0.003, "izz": 0.0035 } },
      "visuals": [ { "origin": { "xyz": [0.2, 0, 0] },
                     "geometry": { "type": "cylinder", "radius": 0.02, "length": 0.4 } } ],
      "collisions": [ { "geometry": { "type": "box", "size": [0.4, 0.05, 0.06] } },
                      { "geometry": { "type": "mesh", "filename": "package://x/arm.stl",
                                      "scale": [0.001, 0.001, 0.001] } } ] },
    { "name": "slide", "inertial": { "mass": 0.5 },
      "collisions": [ { "geometry": { "type": "capsule", "radius": 0.01, "length": 0.1 } },
                      { "geometry": { "type": "sphere", "radius": 0.03 } } ] },
    { "name": "ball", "inertial": { "mass": 0.1 } }
  ],
  "joints": [
    { "name": "shoulder", "type": "revolute", "parent": "base", "child": "arm",
      "origin": { "xyz": [0, 0, 0.1], "rpy": [0, 0, 0.7853981633974483] },
      "limits": { "lower": -1.5707963267948966, "upper": 1.0471975511965976,
                  "velocity": 3.141592653589793, "effort": 12 } },
    { "name": "slider", "type": "prismatic", "parent": "arm", "child": "slide",
      "origin": { "xyz": [0.4, 0, 0] }, "axis": [1, 0, 0],
      "limits": { "lower": -0.05, "upper": 0.25, "velocity": 0.5, "effort": 100 } },
    { "name": "wrist", "type": "spherical", "parent": "slide", "child": "ball",
      "origin": { "xyz": [0.1, 0, 0], "quat": [0, 0, 0.7071067811865476, 0.7071067811865476] },
      "limits": { "velocity": 6.283185307179586 } }
  ],
  "frames": [ { "name": "tip", "link": "ball",
                "origin": { "xyz": [0.05, 0, 0], "rpy": [3.141592653589793, 0, 0] } } ]
}"#;

/// ... and in millimetres and degrees (inertia in kg·mm²).
const MM_DEG: &str = r#"{
  "name": "units",
  "units": { "length": "mm", "angle": "deg" },
  "links": [
    { "name": "base" },
    { "name": "arm",
      "inertial": { "origin": { "xyz": [100, 0, 20], "rpy": [0, 90, 0] },
                    "mass": 2.0,
                    "inertia": { "ixx": 1000, "ixy": 200, "iyy": 3000, "izz": 3500 } },
      "visuals": [ { "origin": { "xyz": [200, 0, 0] },
                     "geometry": { "type": "cylinder", "radius": 20, "length": 400 } } ],
      "collisions": [ { "geometry": { "type": "box", "size": [400, 50, 60] } },
                      { "geometry": { "type": "mesh", "filename": "package://x/arm.stl",
                                      "scale": [0.001, 0.001, 0.001] } } ] },
    { "name": "slide", "inertial": { "mass": 0.5 },
      "collisions": [ { "geometry": { "type": "capsule", "radius": 10, "length": 100 } },
                      { "geometry": { "type": "sphere", "radius": 30 } } ] },
    { "name": "ball", "inertial": { "mass": 0.1 } }
  ],
  "joints": [
    { "name": "shoulder", "type": "revolute", "parent": "base", "child": "arm",
      "origin": { "xyz": [0, 0, 100], "rpy": [0, 0, 45] },
      "limits": { "lower": -90, "upper": 60, "velocity": 180, "effort": 12 },
      "position": 30 },
    { "name": "slider", "type": "prismatic", "parent": "arm", "child": "slide",
      "origin": { "xyz": [400, 0, 0] }, "axis": [1, 0, 0],
      "limits": { "lower": -50, "upper": 250, "velocity": 500, "effort": 100 },
      "position": 12.5 },
    { "name": "wrist", "type": "spherical", "parent": "slide", "child": "ball",
      "origin": { "xyz": [100, 0, 0], "quat": [0, 0, 0.7071067811865476, 0.7071067811865476] },
      "limits": { "velocity": 360 }, "position": [0, 0, 0, 1] }
  ],
  "frames": [ { "name": "tip", "link": "ball",
                "origin": { "xyz": [50, 0, 0], "rpy": [180, 0, 0] } } ]
}"#;

#[test]
fn a_mm_deg_file_equals_the_same_model_in_m_rad() {
    let si = Model::from_json_str(SI, None).unwrap();
    let mm = Model::from_json_str(MM_DEG, None).unwrap();
    assert_eq!(si.first_difference(&mm, 1e-12), None);
    // Spot checks of the conversion, in SI.
    let slider = mm.joint(mm.joint_index("slider").unwrap());
    assert!((slider.limits.upper - 0.25).abs() < 1e-15);
    assert!((slider.limits.velocity - 0.5).abs() < 1e-15);
    assert_eq!(slider.limits.effort, 100.0);
    let shoulder = mm.joint(mm.joint_index("shoulder").unwrap());
    assert!((shoulder.limits.lower + FRAC_PI_2).abs() < 1e-15);
    let arm = mm.link(mm.link_index("arm").unwrap());
    let i = arm.inertial.unwrap();
    assert!((i.inertia.xx - 0.001).abs() < 1e-18 && (i.inertia.xy - 0.0002).abs() < 1e-18);
    assert_eq!(
        arm.collisions[0].geometry,
        Geometry::Box {
            size: [0.4, 0.05, 0.06]
        }
    );
    // Mesh scales are unitless.
    assert!(
        matches!(&arm.collisions[1].geometry, Geometry::Mesh { scale, .. } if *scale == [0.001; 3])
    );
    // The quaternion origin turns the ball 90° about z.
    let wrist = mm.joint(mm.joint_index("wrist").unwrap());
    assert!(wrist.placement.rotation.x_axis.abs_diff_eq(DVec3::Y, 1e-15));
    assert!((wrist.limits.velocity - core::f64::consts::TAU).abs() < 1e-15);
}

#[test]
fn export_in_mm_deg_reads_back_and_writes_file_units() {
    let si = Model::from_json_str(SI, None).unwrap();
    let json = si
        .to_json_string(&JsonOptions {
            units: Units::MM_DEG,
            ..JsonOptions::default()
        })
        .unwrap();
    assert!(json.contains("\"upper\": 250.0"), "{json}");
    assert!(json.contains("\"rpy\": [0.0, 0.0, 45.0]"), "{json}");
    assert!(json.contains("\"ixx\": 1000.0"), "{json}");
    let back = Model::from_json_str(&json, None).unwrap();
    assert_eq!(si.first_difference(&back, 1e-12), None);
    // SI → JSON → SI is exact apart from the rpy conversion of origins.
    let json = si.to_json_string(&JsonOptions::default()).unwrap();
    let again = Model::from_json_str(&json, None).unwrap();
    assert_eq!(si.first_difference(&again, 1e-15), None);
}

#[test]
fn origin_forms_agree() {
    let pose = |origin: &str| {
        let json = format!(
            r#"{{ "links": [{{"name": "a"}}], "frames": [{{"name": "f", "link": "a", "origin": {origin}}}] }}"#
        );
        Model::from_json_str(&json, None).unwrap().frames()[0].placement
    };
    let rpy = pose(r#"{"xyz": [1, 2, 3], "rpy": [0, 0, 1.5707963267948966]}"#);
    let quat =
        pose(r#"{"xyz": [1, 2, 3], "quat": [0, 0, 0.7071067811865476, 0.7071067811865476]}"#);
    let matrix = pose(r#"{"matrix": [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]}"#);
    // Rounded as CAD tools print it: re-orthonormalized.
    let rounded = pose(
        r#"{"matrix": [[0.707107, -0.707107, 0, 0], [0.707107, 0.707107, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}"#,
    );
    assert!(rpy.abs_diff_eq(&quat, 1e-15, 1e-15));
    assert!(rpy.abs_diff_eq(&matrix, 1e-15, 1e-15));
    assert!(rounded.abs_diff_eq(
        &Se3::from_rotation_z(core::f64::consts::FRAC_PI_4),
        1e-6,
        0.0
    ));
    assert!(rotation::is_rotation(&rounded.rotation, 1e-12));
    assert_eq!(pose("{}"), Se3::IDENTITY);
}

#[test]
fn invalid_origins_name_the_item() {
    let load = |origin: &str| {
        let json = format!(
            r#"{{ "links": [{{"name": "a"}}, {{"name": "b"}}],
                "joints": [{{"name": "j", "type": "fixed", "parent": "a", "child": "b", "origin": {origin}}}] }}"#
        );
        Model::from_json_str(&json, None).unwrap_err().to_string()
    };
    let e = load(r#"{"rpy": [0, 0, 1], "quat": [0, 0, 0, 1]}"#);
    assert!(
        e.contains("joint 'j'") && e.contains("both `rpy` and `quat`"),
        "{e}"
    );
    let e = load(r#"{"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]}"#);
    assert!(e.contains("joint 'j'") && e.contains("last row"), "{e}");
    let e = load(r#"{"matrix": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}"#);
    assert!(
        e.contains("joint 'j'") && e.contains("not a rotation"),
        "{e}"
    );
    let e = load(r#"{"quat": [0, 0, 0, 0]}"#);
    assert!(e.contains("joint 'j'") && e.contains("quat"), "{e}");
    let e = load(r#"{"matrix": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}"#);
    assert!(
        e.contains("`matrix` must be 4 rows of 4 numbers") && e.contains("line 2"),
        "{e}"
    );
}

#[test]
fn the_root_joint_comes_from_the_file_unless_overridden() {
    let json = r#"{ "root_joint": "floating", "links": [{"name": "a", "inertial": {"mass": 1}}] }"#;
    assert_eq!(Model::from_json_str(json, None).unwrap().nq(), 7);
    let fixed = Model::from_json_str(json, RootJoint::Fixed).unwrap();
    assert_eq!((fixed.nq(), fixed.root_joint()), (0, RootJoint::Fixed));
    let plain = r#"{ "links": [{"name": "a"}] }"#;
    assert_eq!(
        Model::from_json_str(plain, None).unwrap().root_joint(),
        RootJoint::Fixed
    );
    let floating = Model::from_json_str(plain, Some(RootJoint::Floating)).unwrap();
    assert_eq!(floating.root_joint(), RootJoint::Floating);
    // Export writes the root joint as the option, not as a joint named root_joint.
    let out = floating.to_json_string(&JsonOptions::default()).unwrap();
    assert!(
        out.contains("\"root_joint\": \"floating\"") && !out.contains("\"name\": \"root_joint\"")
    );
}

#[test]
fn world_poses_and_positions_are_written_in_file_units() {
    let arm = samples::planar_2r(0.5, 0.3);
    let q = [FRAC_PI_2, -0.5];
    let poses = [
        Se3::IDENTITY,
        Se3::from_rotation_z(q[0]),
        Se3::from_rotation_z(q[0])
            * Se3::from_translation(DVec3::X * 0.5)
            * Se3::from_rotation_z(q[1]),
    ];
    let json = arm
        .to_json_string(&JsonOptions {
            units: Units::MM_DEG,
            world_poses: Some(&poses),
            positions: Some(&q),
            ..JsonOptions::default()
        })
        .unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["joints"][0]["position"], 90.0);
    assert!((v["joints"][1]["position"].as_f64().unwrap() - (-0.5f64).to_degrees()).abs() < 1e-12);
    let link2 = &v["links"][2]["world_pose"];
    let xyz: Vec<f64> = link2["xyz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!(
        (xyz[0] - 0.0).abs() < 1e-12 && (xyz[1] - 500.0).abs() < 1e-12,
        "{xyz:?}"
    );
    assert!((link2["rpy"][2].as_f64().unwrap() - (FRAC_PI_2 - 0.5).to_degrees()).abs() < 1e-12);
    assert_eq!(
        v["links"][0]["world_pose"]["xyz"],
        serde_json::json!([0.0, 0.0, 0.0])
    );
    // Positions are informational: the file still loads, to the same model.
    assert_eq!(
        arm.first_difference(&Model::from_json_str(&json, None).unwrap(), 1e-12),
        None
    );
    // Wrong lengths are typed errors.
    let e = arm
        .to_json_string(&JsonOptions {
            positions: Some(&[0.0]),
            ..JsonOptions::default()
        })
        .unwrap_err();
    assert!(
        matches!(
            e,
            ModelError::Length {
                expected: 2,
                actual: 1,
                ..
            }
        ),
        "{e}"
    );
    let e = arm
        .to_json_string(&JsonOptions {
            world_poses: Some(&poses[..2]),
            ..JsonOptions::default()
        })
        .unwrap_err();
    assert!(
        matches!(
            e,
            ModelError::Length {
                expected: 3,
                actual: 2,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn mixed_unit_limits_refuse_non_si_units() {
    let json = r#"{ "links": [{"name": "a"}, {"name": "b", "inertial": {"mass": 1}}],
        "joints": [{"name": "screw", "type": "cylindrical", "parent": "a", "child": "b",
                    "limits": {"lower": -1, "upper": 1}}] }"#;
    let m = Model::from_json_str(json, None).unwrap();
    let e = m
        .to_json_string(&JsonOptions {
            units: Units::MM_DEG,
            ..JsonOptions::default()
        })
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("joint 'screw'") && e.contains("mix lengths and angles"),
        "{e}"
    );
    let mm = json.replace("\"links\"", "\"units\": {\"length\": \"mm\"}, \"links\"");
    let e = Model::from_json_str(&mm, None).unwrap_err().to_string();
    assert!(e.contains("joint 'screw'"), "{e}");
    // Unlimited cylindrical joints convert fine.
    let free = json.replace(
        r#""limits": {"lower": -1, "upper": 1}"#,
        r#""axis": [0, 0, 1]"#,
    );
    let free = free.replace("\"links\"", "\"units\": {\"length\": \"mm\"}, \"links\"");
    assert_eq!(Model::from_json_str(&free, None).unwrap().nq(), 2);
}

#[test]
fn colours_take_three_or_four_numbers() {
    let json = r#"{ "links": [{"name": "a", "metadata": {"color": [1, 0.5, 0], "printable": true,
                                                       "mesh": "a.stl", "material": "PLA", "description": "a part"}}] }"#;
    let m = Model::from_json_str(json, None).unwrap();
    let md = &m.link(0).metadata;
    assert_eq!(md.color, Some([1.0, 0.5, 0.0, 1.0]));
    assert!(md.printable);
    assert_eq!(
        (md.mesh.as_deref(), md.material.as_deref()),
        (Some("a.stl"), Some("PLA"))
    );
    let bad = json.replace("[1, 0.5, 0]", "[1, 0.5]");
    let e = Model::from_json_str(&bad, None).unwrap_err();
    assert!(matches!(e, ModelError::Json { line: 1, .. }), "{e}");
    assert!(
        e.to_string()
            .contains("`color` must have 3 (RGB) or 4 (RGBA) numbers, found 2"),
        "{e}"
    );
}

/// A fresh directory under the system's temporary directory.
fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kinetree-model-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const WITH_DATUM: &str = r#"{ "name": "servo_mount",
  "links": [{"name": "bracket"}],
  "frames": [{"name": "horn", "link": "bracket", "description": "servo output",
              "datum": {"file": "cots/servo.json", "name": "output_shaft"}}] }"#;

#[test]
fn datum_frames_resolve_relative_to_the_model_file() {
    let dir = temp_dir("datum");
    std::fs::create_dir_all(dir.join("cots")).unwrap();
    std::fs::write(
        dir.join("cots/servo.json"),
        r#"{ "name": "servo", "units": {"length": "mm", "angle": "deg"},
             "datums": { "output_shaft": {"xyz": [0, 10, 25], "rpy": [0, 0, 90]},
                         "mount_face": {} } }"#,
    )
    .unwrap();
    let path = dir.join("model.json");
    std::fs::write(&path, WITH_DATUM).unwrap();
    let m = Model::from_json_file(&path, None).unwrap();
    let horn = &m.frames()[0];
    let expected =
        Se3::from_translation(DVec3::new(0.0, 0.01, 0.025)) * Se3::from_rotation_z(FRAC_PI_2);
    assert!(
        horn.placement.abs_diff_eq(&expected, 1e-15, 1e-15),
        "{:?}",
        horn.placement
    );
    assert_eq!(
        horn.datum,
        Some(("cots/servo.json".into(), "output_shaft".into()))
    );
    assert_eq!(horn.description.as_deref(), Some("servo output"));
    // By default the reference is written back; inline export writes the pose instead.
    let out = m.to_json_string(&JsonOptions::default()).unwrap();
    assert!(
        out.contains("\"file\": \"cots/servo.json\"") && !out.contains("\"origin\""),
        "{out}"
    );
    std::fs::write(dir.join("again.json"), &out).unwrap();
    assert_eq!(
        Model::from_json_file(dir.join("again.json"), None).unwrap(),
        m
    );
    let inline = m
        .to_json_string(&JsonOptions {
            datums: DatumExport::Inline,
            ..JsonOptions::default()
        })
        .unwrap();
    assert!(
        !inline.contains("datum") && inline.contains("\"origin\""),
        "{inline}"
    );
    let standalone = Model::from_json_str(&inline, None).unwrap();
    assert!(
        standalone.frames()[0]
            .placement
            .abs_diff_eq(&expected, 1e-15, 1e-15)
    );
    assert_eq!(standalone.frames()[0].datum, None);
    // From a string, the datum path is relative to the current directory: not found here.
    let e = Model::from_json_str(WITH_DATUM, None).unwrap_err();
    assert!(matches!(e, ModelError::Datum { .. }), "{e}");
    // `from_file` dispatches on the extension, or sniffs the content.
    assert_eq!(Model::from_file(&path, None).unwrap(), m);
    std::fs::write(dir.join("model.kt"), WITH_DATUM).unwrap();
    assert_eq!(Model::from_file(dir.join("model.kt"), None).unwrap(), m);
    std::fs::write(dir.join("model.txt"), "robot").unwrap();
    let e = Model::from_file(dir.join("model.txt"), None).unwrap_err();
    assert!(matches!(e, ModelError::UnknownFormat { .. }), "{e}");
    std::fs::write(
        dir.join("robot.model"),
        "<robot name=\"r\"><link name=\"a\"/></robot>",
    )
    .unwrap();
    assert_eq!(
        Model::from_file(dir.join("robot.model"), RootJoint::Floating)
            .unwrap()
            .nq(),
        7
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_frame_with_both_origin_and_datum_is_rejected() {
    let json = WITH_DATUM.replace("\"description\"", "\"origin\": {}, \"description\"");
    let e = Model::from_json_str(&json, None).unwrap_err().to_string();
    assert!(
        e.contains("frame 'horn'") && e.contains("both `origin` and `datum`"),
        "{e}"
    );
}

#[test]
fn parent_frames_place_joints() {
    let json = r#"{ "links": [{"name": "base"}, {"name": "arm", "inertial": {"mass": 1}}],
        "frames": [{"name": "mount", "link": "base", "origin": {"xyz": [0, 0, 0.5], "rpy": [0, 0, 1.5707963267948966]}}],
        "joints": [{"name": "j", "type": "revolute", "parent": "base", "child": "arm",
                    "parent_frame": "mount", "origin": {"xyz": [0.1, 0, 0]}}] }"#;
    let m = Model::from_json_str(json, None).unwrap();
    let j = m.joint(0);
    // The mount turns x into y: 0.1 along the mount's x is 0.1 along the base's y.
    assert!(
        j.placement
            .translation
            .abs_diff_eq(DVec3::new(0.0, 0.1, 0.5), 1e-15)
    );
    assert_eq!(j.axis, DVec3::Z);
    assert_eq!(j.limits, JointLimits::UNLIMITED);
}

#[test]
fn positions_are_numbers_or_arrays() {
    let json = |position: &str| {
        format!(
            r#"{{ "links": [{{"name": "a"}}, {{"name": "b"}}],
                "joints": [{{"name": "j", "type": "revolute", "parent": "a", "child": "b", "position": {position}}}] }}"#
        )
    };
    for ok in ["1", "-2.5", "[0.1, 0.2]", "[]"] {
        assert!(Model::from_json_str(&json(ok), None).is_ok(), "{ok}");
    }
    let e = Model::from_json_str(&json("\"up\""), None).unwrap_err();
    assert!(
        e.to_string()
            .contains("expected a number or an array of numbers for `position`"),
        "{e}"
    );
}

#[test]
fn parts_is_another_name_for_links() {
    let m = Model::from_json_str(
        r#"{"name": "kit", "parts": [{"name": "BASE"}, {"name": "LINK1"}],
            "joints": [{"name": "j1", "type": "revolute", "parent": "BASE", "child": "LINK1"}]}"#,
        None,
    )
    .unwrap();
    assert_eq!((m.name(), m.links().len(), m.nq()), ("kit", 2, 1));
    assert_eq!(m.link(1).name, "LINK1");
}

#[test]
fn unsupported_versions_are_rejected() {
    let e = Model::from_json_str(r#"{"version": 2, "links": []}"#, None).unwrap_err();
    assert!(
        e.to_string().contains("unsupported schema version 2"),
        "{e}"
    );
    assert_eq!(
        Model::from_json_str(r#"{"version": 1}"#, None)
            .unwrap()
            .nq(),
        0
    );
}

#[test]
fn the_model_name_is_optional_in_every_loader_as_documented() {
    // The schema docs once said every name was required while the loader defaulted the model's
    // name; the three loaders and the docs now agree: links, joints and frames need a name, the
    // model does not.
    let json = Model::from_json_str(r#"{ "links": [ { "name": "base" } ] }"#, None).unwrap();
    let urdf =
        Model::from_urdf_str(r#"<robot><link name="base"/></robot>"#, RootJoint::Fixed).unwrap();
    let dh = crate::dh::DhTable::from_json_str(r#"{ "dh": [ { "a": 1 } ] }"#).unwrap();
    assert_eq!((json.name(), urdf.name(), dh.name.as_str()), ("", "", ""));
    // A link without a name is still refused.
    let err = Model::from_json_str(r#"{ "links": [ {} ] }"#, None).unwrap_err();
    assert!(err.to_string().contains("missing field `name`"), "{err}");
}
