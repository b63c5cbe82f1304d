//! Mesh loading: the unit cube of tests/data/meshes as ASCII STL, binary STL and OBJ.

use crate::common::{data_dir, urdf};
use kinetree_collision::kinematics::KinematicsData;
use kinetree_collision::mesh::{parse_stl, read_mesh_file};
use kinetree_collision::{
    CollisionData, CollisionError, CollisionModel, CollisionOptions, MeshMode, any_collision,
    compute_distances, compute_self_collisions,
};
use kinetree_test_support::assert_close;

fn robot(mesh: &str, scale: &str) -> kinetree_collision::kinematics::model::Model {
    urdf(&format!(
        r#"<link name="base"/>
           <link name="a"><collision><geometry><mesh filename="{mesh}" scale="{scale}"/></geometry></collision></link>
           <link name="b"><collision><geometry><sphere radius="0.25"/></geometry></collision></link>
           <joint name="ja" type="revolute"><parent link="base"/><child link="a"/>
             <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
           <joint name="jb" type="prismatic"><parent link="base"/><child link="b"/>
             <axis xyz="1 0 0"/><limit lower="-10" upper="10" effort="1" velocity="1"/></joint>"#
    ))
}

#[test]
fn stl_ascii_and_binary_read_the_same_cube() {
    let dir = data_dir().join("meshes");
    let ascii = read_mesh_file(&dir.join("unit_cube_ascii.stl")).unwrap();
    let binary = read_mesh_file(&dir.join("unit_cube_binary.stl")).unwrap();
    let obj = read_mesh_file(&dir.join("unit_cube.obj")).unwrap();
    for m in [&ascii, &binary, &obj] {
        assert_eq!(m.vertices.len(), 8);
        assert_eq!(m.triangles.len(), 12);
    }
    assert_eq!(ascii, binary);
    // The binary file's header starts with "solid": the size decides, not the header.
    let bytes = std::fs::read(dir.join("unit_cube_binary.stl")).unwrap();
    assert!(bytes.starts_with(b"solid"));
    assert_eq!(parse_stl(&bytes).unwrap(), binary);
}

#[test]
fn meshes_load_through_search_paths_and_collide() {
    for (file, mode) in [
        (
            "package://kinetree_test/meshes/unit_cube_binary.stl",
            MeshMode::TriMesh,
        ),
        ("meshes/unit_cube_ascii.stl", MeshMode::ConvexHull),
        (
            "package://kinetree_test/meshes/unit_cube.obj",
            MeshMode::ConvexHull,
        ),
    ] {
        // The cube is scaled to 0.4 x 1 x 1 (half-width 0.2 in x): the sphere (radius 0.25)
        // centred at x collides for x < 0.45.
        let model = robot(file, "0.4 1 1");
        let options = CollisionOptions::default()
            .with_mesh_path(data_dir())
            .with_mesh_mode(mode);
        let cmodel = CollisionModel::from_model(&model, &options).unwrap();
        assert_eq!(cmodel.shapes().len(), 2);
        let mut kinematics = KinematicsData::new(&model);
        let mut data = CollisionData::new(&cmodel);
        for (x, expected) in [(1.0, 0.55), (0.5, 0.05), (0.4, -0.05)] {
            let mut q = vec![0.0; 2];
            q[model.joint_q_range(model.joint_index("jb").unwrap()).start] = x;
            data.compute_placements(&model, &cmodel, &mut kinematics, &q)
                .unwrap();
            let d = compute_distances(&cmodel, &mut data).unwrap()[0].distance;
            assert_close!(d, expected, 1e-6, 0.0, "{file} {mode:?} x = {x}: {d}");
            assert_eq!(
                any_collision(&cmodel, &mut data).unwrap(),
                expected < 0.0,
                "{file} x = {x}"
            );
        }
    }
}

#[test]
fn missing_mesh_is_an_error_naming_the_file_or_skipped() {
    let model = robot("package://nowhere/missing.stl", "1 1 1");
    let options = CollisionOptions::default().with_mesh_path(data_dir());
    match CollisionModel::from_model(&model, &options) {
        Err(e @ CollisionError::MeshNotFound { .. }) => {
            assert!(
                e.to_string().contains("package://nowhere/missing.stl"),
                "{e}"
            );
        }
        other => panic!("expected MeshNotFound, got {other:?}"),
    }
    let cmodel =
        CollisionModel::from_model(&model, &options.clone().skip_missing_meshes()).unwrap();
    assert_eq!(cmodel.shapes().len(), 1);
    assert_eq!(cmodel.skipped_meshes().len(), 1);
    assert_eq!(
        cmodel.skipped_meshes()[0].filename,
        "package://nowhere/missing.stl"
    );
    // An unparsable file is an error naming it.
    let model = robot("reference/README.md", "1 1 1");
    match CollisionModel::from_model(&model, &options) {
        Err(e @ CollisionError::MeshParse { .. }) => assert!(e.to_string().contains("README.md")),
        other => panic!("expected MeshParse, got {other:?}"),
    }
    // Ignoring meshes lists them too.
    let cmodel =
        CollisionModel::from_model(&model, &options.with_mesh_mode(MeshMode::Ignore)).unwrap();
    assert_eq!(cmodel.skipped_meshes().len(), 1);
}

/// The bundled Panda with its collision meshes (triangle meshes, the default). No search path
/// is given: `package://example-robot-data/robots/panda_description/…` resolves to
/// tests/data/robots/panda_description/… through the model file's directory.
fn bundled_panda() -> (kinetree_collision::kinematics::model::Model, CollisionModel) {
    use kinetree_collision::kinematics::model::{Model, RootJoint};
    let urdf = data_dir().join("robots/panda.urdf");
    let model = Model::from_urdf_file(&urdf, RootJoint::Fixed).unwrap();
    let options = CollisionOptions::default().with_model_file(&urdf, &[]);
    let cmodel = CollisionModel::from_model(&model, &options).unwrap();
    (model, cmodel)
}

#[test]
fn the_bundled_panda_finds_its_meshes_next_to_the_urdf() {
    let (model, cmodel) = bundled_panda();
    assert!(cmodel.skipped_meshes().is_empty());
    // 17 collision elements: 9 link meshes (link0..link7, hand) and 4 boxes per finger.
    assert_eq!(cmodel.shapes().len(), 17);
    let srdf = std::fs::read_to_string(data_dir().join("robots/panda_description/srdf/panda.srdf"))
        .unwrap();
    // The bundled SRDF names links of the bundled URDF only.
    let disabled = kinetree_collision::srdf::parse_disabled_pairs(&srdf).unwrap();
    assert!(disabled.len() > 10, "{}", disabled.len());
    for pair in &disabled {
        for link in [&pair.link1, &pair.link2] {
            assert!(model.link_index(link).is_some(), "{link}");
        }
    }
}

/// A box x ∈ [0, 1], y ∈ [0.5, 1.5], z ∈ [0, 1] as an OBJ, triangles counter-clockwise seen
/// from outside; written to a scratch folder.
fn offset_box() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("kinetree-mirror-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("offset_box.obj");
    let mut text = String::new();
    for i in 0..8 {
        let (x, y, z) = (i & 1, (i >> 1) & 1, (i >> 2) & 1);
        text.push_str(&format!("v {x} {} {z}\n", 0.5 + y as f64));
    }
    // Faces as quads (1-based), each counter-clockwise from outside, split in two triangles.
    for [a, b, c, d] in [
        [1, 5, 7, 3], // x = 0
        [2, 4, 8, 6], // x = 1
        [1, 2, 6, 5], // y = 0.5
        [3, 7, 8, 4], // y = 1.5
        [1, 3, 4, 2], // z = 0
        [5, 6, 8, 7], // z = 1
    ] {
        text.push_str(&format!("f {a} {b} {c}\nf {a} {c} {d}\n"));
    }
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn mirroring_keeps_the_mesh_outward_and_its_volume() {
    use glam::DVec3;
    let mesh = read_mesh_file(&offset_box()).unwrap();
    assert_close!(mesh.signed_volume(), 1.0, 1e-12);
    for (scale, volume) in [
        (DVec3::new(1.0, -1.0, 1.0), 1.0),
        (DVec3::new(-1.0, -1.0, 1.0), 1.0),
        (DVec3::new(2.0, -1.0, 3.0), 6.0),
        (DVec3::new(-0.5, -2.0, -1.0), 1.0),
    ] {
        let scaled = mesh.scaled(scale);
        assert!(
            (scaled.signed_volume() - volume).abs() < 1e-12,
            "{scale}: {}",
            scaled.signed_volume()
        );
        assert_eq!(scaled.vertices[2], mesh.vertices[2] * scale);
    }
}

/// `scale="1 -1 1"` mirrors the box to y ∈ [-1.5, -0.5]; a 0.25 m ball on a slider along y,
/// centred at x = 0.5, z = 0.5, is 0.25 m away at y = 0, penetrates by 0.05 m at y = -0.3 and
/// is 1.25 m away at y = 1 (where the unmirrored box would hold it).
#[test]
fn a_mirrored_mesh_collides_where_its_mirror_image_is() {
    let file = offset_box();
    let model = urdf(&format!(
        r#"<link name="base"/>
           <link name="a"><collision><geometry><mesh filename="{}" scale="1 -1 1"/></geometry></collision></link>
           <link name="b"><collision><geometry><sphere radius="0.25"/></geometry></collision></link>
           <joint name="ja" type="revolute"><parent link="base"/><child link="a"/>
             <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
           <joint name="jb" type="prismatic"><parent link="base"/><child link="b"/><origin xyz="0.5 0 0.5"/>
             <axis xyz="0 1 0"/><limit lower="-10" upper="10" effort="1" velocity="1"/></joint>"#,
        file.display()
    ));
    for mode in [MeshMode::ConvexHull, MeshMode::TriMesh] {
        let options = CollisionOptions::default().with_mesh_mode(mode);
        let cmodel = CollisionModel::from_model(&model, &options).unwrap();
        let mut kinematics = KinematicsData::new(&model);
        let mut data = CollisionData::new(&cmodel);
        for (y, expected) in [(0.0, 0.25), (-0.3, -0.05), (1.0, 1.25), (-2.0, 0.25)] {
            let mut q = vec![0.0; 2];
            q[model.joint_q_range(model.joint_index("jb").unwrap()).start] = y;
            data.compute_placements(&model, &cmodel, &mut kinematics, &q)
                .unwrap();
            let d = compute_distances(&cmodel, &mut data).unwrap()[0].distance;
            assert_close!(d, expected, 1e-9, 0.0, "{mode:?} y = {y}: {d}");
        }
    }
    // A zero or non-finite factor stays an error naming the link.
    for scale in ["1 0 1", "1 nan 1", "inf 1 1"] {
        let text = format!(
            r#"<robot name="t"><link name="a"><collision><geometry><mesh filename="{}" scale="{scale}"/></geometry></collision></link></robot>"#,
            file.display()
        );
        let e = kinetree_collision::kinematics::model::Model::from_urdf_str(
            &text,
            kinetree_collision::kinematics::model::RootJoint::Fixed,
        )
        .unwrap_err();
        assert!(e.to_string().contains("'a'"), "{scale}: {e}");
    }
}

/// Two triangle meshes: every distance between the bundled Panda's link meshes equals parry's
/// own (a separate algorithm: its composite-shape distance, triangle against mesh), with the
/// witness points on the two surfaces, as far apart as the distance, along the normal.
#[test]
fn mesh_pair_distances_match_parrys_on_the_bundled_panda() {
    use kinetree_collision::kinematics::configuration;
    use kinetree_collision::parry::query::{self, PointQuery};
    let (model, cmodel) = bundled_panda();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    let mut rng = <rand::rngs::SmallRng as rand::SeedableRng>::seed_from_u64(11);
    let mut q = vec![0.0; model.nq()];
    let (mut separated, mut penetrating) = (0, 0);
    for state in 0..12 {
        configuration::random_configuration(&model, &mut rng, &mut q).unwrap();
        data.compute_placements(&model, &cmodel, &mut kinematics, &q)
            .unwrap();
        let found = compute_distances(&cmodel, &mut data).unwrap().to_vec();
        for p in found {
            let (sa, sb) = (&cmodel.shapes()[p.a], &cmodel.shapes()[p.b]);
            let (Some(ma), Some(mb)) = (sa.shape().as_trimesh(), sb.shape().as_trimesh()) else {
                continue;
            };
            let (pose_a, pose_b) = (
                *data.shape_pose(p.a).unwrap(),
                *data.shape_pose(p.b).unwrap(),
            );
            let theirs = query::distance(&pose_a, ma, &pose_b, mb).unwrap().distance;
            let what = format!("state {state}, {} / {}", sa.name(), sb.name());
            if theirs > 0.0 {
                separated += 1;
                assert_close!(p.distance, theirs, 1e-10, 1e-8, "{what}");
                assert!(
                    ma.distance_to_point(&pose_a, p.point_a, false) < 1e-10,
                    "{what}"
                );
                assert!(
                    mb.distance_to_point(&pose_b, p.point_b, false) < 1e-10,
                    "{what}"
                );
                let gap = p.point_b - p.point_a;
                assert_close!(gap.length(), p.distance, 1e-10, 1e-8, "{what}");
                assert_close!(gap.dot(p.normal), p.distance, 1e-10, 1e-8, "{what}");
            } else {
                penetrating += 1;
                assert!(p.distance <= 0.0, "{what}: {}", p.distance);
            }
        }
    }
    // 9 link meshes (link7 and the hand are one body): 35 pairs on two bodies, minus the 8 of
    // a parent and its child.
    assert_eq!(separated + penetrating, 12 * 27);
    assert!(separated > 300, "{separated}");
}

/// Two boxes as triangle meshes (the unit cube scaled to 0.4 x 1 x 1 and 0.4 x 0.6 x 0.6), side
/// by side along x: the distance is the gap between the faces, or between an edge and a face
/// once the first box turns about z; once they overlap, a collision with a negative distance
/// (no deeper than the overlap: the surfaces cross).
#[test]
fn two_mesh_boxes_are_as_far_apart_as_their_faces() {
    let model = urdf(
        r#"<link name="base"/>
           <link name="a"><collision><geometry><mesh filename="package://kinetree_test/meshes/unit_cube_binary.stl" scale="0.4 1 1"/></geometry></collision></link>
           <link name="b"><collision><geometry><mesh filename="package://kinetree_test/meshes/unit_cube.obj" scale="0.4 0.6 0.6"/></geometry></collision></link>
           <joint name="ja" type="revolute"><parent link="base"/><child link="a"/>
             <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
           <joint name="jb" type="prismatic"><parent link="base"/><child link="b"/>
             <axis xyz="1 0 0"/><limit lower="-10" upper="10" effort="1" velocity="1"/></joint>"#,
    );
    let options = CollisionOptions::default().with_mesh_path(data_dir());
    let cmodel = CollisionModel::from_model(&model, &options).unwrap();
    assert!(
        cmodel
            .shapes()
            .iter()
            .all(|s| s.shape().as_trimesh().is_some())
    );
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    let (ja, jb) = (
        model.joint_q_range(model.joint_index("ja").unwrap()).start,
        model.joint_q_range(model.joint_index("jb").unwrap()).start,
    );
    let quarter = std::f64::consts::FRAC_PI_4;
    // Half extents along x: 0.2 for b; for a, 0.2, 0.5 a quarter turn on, and (0.2 + 0.5)/√2
    // (a vertical edge) an eighth of a turn on.
    for (angle, x, expected) in [
        (0.0, 1.0, 0.6),
        (0.0, 0.45, 0.05),
        (-2.0 * quarter, 1.0, 0.3),
        (quarter, 1.0, 0.8 - 0.7 * quarter.cos()),
        (quarter, -0.9, 0.7 - 0.7 * quarter.cos()),
    ] {
        let mut q = vec![0.0; 2];
        (q[ja], q[jb]) = (angle, x);
        data.compute_placements(&model, &cmodel, &mut kinematics, &q)
            .unwrap();
        let p = compute_distances(&cmodel, &mut data).unwrap()[0];
        assert_close!(p.distance, expected, 1e-9, 0.0, "angle {angle}, x = {x}");
        assert_close!(p.normal.x.abs(), 1.0, 1e-9, 0.0, "angle {angle}, x = {x}");
        assert_close!((p.point_b - p.point_a).x.abs(), expected, 1e-9, 0.0);
        assert!(
            !any_collision(&cmodel, &mut data).unwrap(),
            "angle {angle}, x = {x}"
        );
    }
    for x in [0.35, 0.1, -0.25] {
        let mut q = vec![0.0; 2];
        q[jb] = x;
        data.compute_placements(&model, &cmodel, &mut kinematics, &q)
            .unwrap();
        let d = compute_distances(&cmodel, &mut data).unwrap()[0].distance;
        assert!(d < 0.0 && d >= -(0.4 - x.abs()) - 1e-9, "x = {x}: {d}");
        assert!(any_collision(&cmodel, &mut data).unwrap(), "x = {x}");
        // The contact list finds the same crossing.
        let contacts = compute_self_collisions(&cmodel, &mut data).unwrap();
        assert_eq!(contacts.len(), 1, "x = {x}");
        assert_close!(contacts[0].distance, d, 1e-12, 0.0, "x = {x}");
    }
}
