//! Every public reference URDF loads and its moving joints agree with Pinocchio's joint table.

use kinetree_model::{JointKind, Model, RootJoint};
use serde_json::Value;
use std::path::PathBuf;

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/reference")
}

pub(crate) fn reference_robots() -> Vec<(String, Value)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(data_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
            out.push((path.file_stem().unwrap().to_string_lossy().into_owned(), v));
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(out.len() >= 7, "reference data missing");
    out
}

pub(crate) fn load(reference: &Value) -> Model {
    let root = match reference["root_joint"].as_str().unwrap() {
        "fixed" => RootJoint::Fixed,
        _ => RootJoint::Floating,
    };
    let urdf = data_dir().join(reference["urdf"].as_str().unwrap());
    Model::from_urdf_file(&urdf, root).unwrap_or_else(|e| panic!("{}: {e}", urdf.display()))
}

fn opt(v: &Value) -> Option<f64> {
    v.as_f64()
}

#[test]
fn reference_urdfs_match_the_joint_tables() {
    for (robot, reference) in reference_robots() {
        let model = load(&reference);
        let joints = reference["joints"].as_array().unwrap();
        let moving: Vec<usize> = model.moving_joints().collect();
        assert_eq!(
            moving.len(),
            joints.len(),
            "{robot}: number of moving joints"
        );
        // Pinocchio's nv equals ours; its nq counts continuous joints twice.
        assert_eq!(
            model.nv() as u64,
            reference["nv"].as_u64().unwrap(),
            "{robot}: nv"
        );
        for rj in joints {
            let name = rj["name"].as_str().unwrap();
            let ji = model
                .joint_index(name)
                .unwrap_or_else(|| panic!("{robot}: joint {name} missing"));
            let j = model.joint(ji);
            let ty = rj["type"].as_str().unwrap();
            let expected = match ty {
                "free_flyer" | "floating" => JointKind::Floating,
                other => JointKind::from_name(other).unwrap_or_else(|| panic!("type {other}")),
            };
            assert_eq!(j.kind, expected, "{robot}/{name}: type");
            if name == "root_joint" {
                continue;
            }
            assert_eq!(
                model.link(j.parent_link.unwrap()).name,
                rj["parent_link"].as_str().unwrap(),
                "{robot}/{name}: parent link"
            );
            assert_eq!(
                model.link(j.child_link).name,
                rj["child_link"].as_str().unwrap(),
                "{robot}/{name}: child"
            );
            let axis: Vec<f64> = rj["axis"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            for k in 0..3 {
                assert!(
                    (j.axis[k] - axis[k]).abs() < 1e-12,
                    "{robot}/{name}: axis {:?} vs {axis:?}",
                    j.axis
                );
            }
            match (opt(&rj["lower"]), opt(&rj["upper"])) {
                (Some(lo), Some(hi)) => {
                    assert!((j.limits.lower - lo).abs() < 1e-12, "{robot}/{name}: lower");
                    assert!((j.limits.upper - hi).abs() < 1e-12, "{robot}/{name}: upper");
                }
                _ => assert!(
                    j.limits.lower.is_infinite() && j.limits.upper.is_infinite(),
                    "{robot}/{name}"
                ),
            }
            if let Some(vel) = opt(&rj["velocity"]) {
                assert!(
                    (j.limits.velocity - vel).abs() < 1e-12,
                    "{robot}/{name}: velocity"
                );
            }
            if let Some(eff) = opt(&rj["effort"]) {
                assert!(
                    (j.limits.effort - eff).abs() < 1e-12,
                    "{robot}/{name}: effort"
                );
            }
            let mimic = &rj["mimic"];
            assert_eq!(j.mimic.is_some(), !mimic.is_null(), "{robot}/{name}: mimic");
        }
        // Every URDF link is in the model.
        for l in reference["links"].as_array().unwrap() {
            assert!(
                model.link_index(l["name"].as_str().unwrap()).is_some(),
                "{robot}: link {l}"
            );
        }
        let urdf_mass = reference["urdf_total_mass"].as_f64().unwrap();
        assert!(
            (model.total_mass() - urdf_mass).abs() < 1e-9,
            "{robot}: total mass"
        );
    }
}
