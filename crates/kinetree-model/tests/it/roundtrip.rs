//! Round trips through URDF and JSON export: every reference robot and the samples come back as
//! the same model (`cargo xtask corpus` does the same for the example-robot-data corpus).

use kinetree_model::{
    Geometry, JointKind, JsonOptions, Model, ModelError, RootJoint, Units, samples,
};
use std::path::PathBuf;

fn reference_urdfs() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/reference/urdf");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "urdf"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 7, "reference URDFs missing");
    files
}

/// URDF → URDF, URDF → JSON (SI and mm/deg), JSON → JSON: each reload equals the original.
fn check_round_trips(model: &Model, what: &str) {
    let root = model.root_joint();
    let urdf = model
        .to_urdf_string()
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    let back = Model::from_urdf_str(&urdf, root).unwrap_or_else(|e| panic!("{what}: {e}\n{urdf}"));
    // URDF has no named frames: those are the only thing allowed to go missing.
    let frames_lost = format!("{} frames vs 0", model.frames().len());
    match model.first_difference(&back, 1e-12) {
        None => {}
        Some(d) if d == frames_lost => {}
        Some(d) => panic!("{what}: URDF round trip differs: {d}"),
    }
    let json = model.to_json_string(&JsonOptions::default()).unwrap();
    let from_json = Model::from_json_str(&json, None).unwrap_or_else(|e| panic!("{what}: {e}"));
    if let Some(d) = model.first_difference(&from_json, 1e-12) {
        panic!("{what}: JSON round trip differs: {d}");
    }
    // And once more: a model read from JSON survives another trip.
    let json2 = from_json.to_json_string(&JsonOptions::default()).unwrap();
    let again = Model::from_json_str(&json2, None).unwrap();
    assert_eq!(from_json.first_difference(&again, 1e-12), None, "{what}");
    let mm = JsonOptions {
        units: Units::MM_DEG,
        ..JsonOptions::default()
    };
    match model.to_json_string(&mm) {
        Ok(json_mm) => {
            let from_mm = Model::from_json_str(&json_mm, None).unwrap();
            if let Some(d) = model.first_difference(&from_mm, 1e-9) {
                panic!("{what}: mm/deg JSON round trip differs: {d}");
            }
        }
        // Only mixed-unit joints with finite limits may refuse millimetres and degrees.
        Err(e) => assert!(
            e.to_string().contains("mix lengths and angles"),
            "{what}: {e}"
        ),
    }
}

#[test]
fn reference_urdfs_survive_urdf_and_json_round_trips() {
    for path in reference_urdfs() {
        for root in [RootJoint::Fixed, RootJoint::Floating] {
            let model = Model::from_urdf_file(&path, root).unwrap();
            check_round_trips(&model, &path.display().to_string());
            // Mesh names, `package://` ones included, are written exactly as they were read.
            let urdf = model.to_urdf_string().unwrap();
            let json = model.to_json_string(&JsonOptions::default()).unwrap();
            let mut meshes = 0;
            for link in model.links() {
                let shapes = link.visuals.iter().map(|v| &v.geometry);
                for g in shapes.chain(link.collisions.iter().map(|c| &c.geometry)) {
                    if let Geometry::Mesh { filename, .. } = g {
                        assert!(
                            urdf.contains(&format!("filename=\"{filename}\"")),
                            "{filename}"
                        );
                        assert!(
                            json.contains(&format!("\"filename\": \"{filename}\"")),
                            "{filename}"
                        );
                        meshes += 1;
                    }
                }
            }
            let name = path.file_name().unwrap().to_string_lossy();
            if name == "panda.urdf" {
                assert_eq!(meshes, 20, "panda's visual and collision meshes");
                assert!(urdf.contains("package://example-robot-data/robots/panda_description/"));
            }
        }
    }
}

#[test]
fn samples_survive_round_trips() {
    for model in [
        samples::pendulum(),
        samples::double_pendulum(),
        samples::planar_2r(0.4, 0.25),
        samples::six_axis(),
        samples::humanoid_like(),
    ] {
        check_round_trips(&model, model.name());
    }
}

#[test]
fn random_trees_with_every_joint_kind_survive_round_trips() {
    let (mut with_urdf, mut cylindrical) = (0, 0);
    for seed in 0..40 {
        for root in [RootJoint::Fixed, RootJoint::Floating] {
            let model = samples::random_tree_with_root(seed, 25, root);
            let what = format!("random tree {seed} ({root:?})");
            let json = model.to_json_string(&JsonOptions::default()).unwrap();
            let back = Model::from_json_str(&json, None).unwrap();
            assert_eq!(model.first_difference(&back, 1e-12), None, "{what}");
            let has_cylindrical = model
                .joints()
                .iter()
                .any(|j| j.kind == JointKind::Cylindrical);
            match model.to_urdf_string() {
                Ok(urdf) => {
                    assert!(!has_cylindrical, "{what}");
                    let back = Model::from_urdf_str(&urdf, root).unwrap();
                    // Named frames are the only thing URDF cannot carry.
                    let frames_lost = format!("{} frames vs 0", model.frames().len());
                    match model.first_difference(&back, 1e-12) {
                        None => {}
                        Some(d) => assert_eq!(d, frames_lost, "{what}"),
                    }
                    with_urdf += 1;
                }
                Err(e) => {
                    assert!(has_cylindrical, "{what}: {e}");
                    assert!(matches!(
                        e,
                        ModelError::UnsupportedJoint {
                            kind: JointKind::Cylindrical,
                            ..
                        }
                    ));
                    cylindrical += 1;
                }
            }
        }
    }
    // Both paths were exercised.
    assert!(
        with_urdf > 0 && cylindrical > 0,
        "{with_urdf} {cylindrical}"
    );
}
