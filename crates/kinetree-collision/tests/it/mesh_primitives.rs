//! Every primitive against a mesh (triangle mesh and convex hull), separated and penetrating,
//! against hand-computed distances; the collision lists agree with the signed distances.
//!
//! The mesh is `tests/data/meshes/unit_cube.obj` (side 1, centred at the origin); each primitive
//! is 0.2 wide and slides along z above it (or along the diagonal), so every distance is a
//! face–face, edge or corner distance that can be worked by hand.

use crate::common::{data_dir, urdf};
use glam::DVec3;
use kinetree_collision::kinematics::KinematicsData;
use kinetree_collision::kinematics::model::{Geometry, Model};
use kinetree_collision::kinematics::spatial::Se3;
use kinetree_collision::{
    CollisionData, CollisionModel, CollisionOptions, MeshMode, any_collision, compute_distances,
    compute_self_collisions, compute_world_collisions, compute_world_distances,
};

/// The primitives, each as URDF geometry text, its extent above its centre along +z (the
/// distance from the centre to the face facing the cube along z), and its distance to the cube's
/// corner (0.5, 0.5, 0.5) when centred at (0.8, 0.8, 0.8).
const PRIMITIVES: [(&str, f64, f64); 4] = [
    // Corner (0.7, 0.7, 0.7) to corner: 0.2·√3.
    (r#"<box size="0.2 0.2 0.2"/>"#, 0.1, 0.346_410_161_513_775_4),
    // Centre to corner 0.3·√3, less the radius.
    (r#"<sphere radius="0.1"/>"#, 0.1, 0.419_615_242_270_663_2),
    // The bottom rim's point nearest the corner: (0.8 - 0.1/√2, 0.8 - 0.1/√2, 0.7), so
    // √(2·(0.3 - 0.1/√2)² + 0.2²).
    (
        r#"<cylinder radius="0.1" length="0.2"/>"#,
        0.1,
        0.380_981_871_297_853_6,
    ),
    // The segment's end (0.8, 0.8, 0.7): √0.22 less the radius.
    (
        r#"<capsule radius="0.1" length="0.2"/>"#,
        0.2,
        0.369_041_575_982_342_96,
    ),
];

const MODES: [MeshMode; 2] = [MeshMode::TriMesh, MeshMode::ConvexHull];

/// The primitive on link `p` (free to move in x, y, z through three prismatic joints) and the
/// unit cube on link `m` at the origin.
fn robot(primitive: &str) -> Model {
    urdf(&format!(
        r#"<link name="base"/><link name="px"/><link name="py"/>
           <link name="p"><collision><geometry>{primitive}</geometry></collision></link>
           <link name="m"><collision><geometry><mesh filename="meshes/unit_cube.obj"/></geometry></collision></link>
           <joint name="jx" type="prismatic"><parent link="base"/><child link="px"/>
             <axis xyz="1 0 0"/><limit lower="-10" upper="10" effort="1" velocity="1"/></joint>
           <joint name="jy" type="prismatic"><parent link="px"/><child link="py"/>
             <axis xyz="0 1 0"/><limit lower="-10" upper="10" effort="1" velocity="1"/></joint>
           <joint name="jz" type="prismatic"><parent link="py"/><child link="p"/>
             <axis xyz="0 0 1"/><limit lower="-10" upper="10" effort="1" velocity="1"/></joint>
           <joint name="jm" type="fixed"><parent link="base"/><child link="m"/></joint>"#
    ))
}

/// Placements of the primitive's centre and the hand-worked signed distance to the cube, for a
/// primitive whose extent along z above its centre is `e` (0.1 laterally for all of them).
fn cases(e: f64, corner: f64) -> Vec<(DVec3, f64)> {
    vec![
        // Corner to corner (or rim, or cap) along the diagonal.
        (DVec3::splat(0.8), corner),
        // Face to face, far, on axis and off axis (not vertex to vertex).
        (DVec3::new(0.0, 0.0, 2.0), 2.0 - 0.5 - e),
        (DVec3::new(0.3, -0.2, 1.0), 1.0 - 0.5 - e),
        // Beside the cube, facing its +x face.
        (DVec3::new(1.0, 0.1, 0.0), 1.0 - 0.5 - 0.1),
        // Penetrating the top face by 0.05.
        (DVec3::new(0.1, 0.1, 0.5 + e - 0.05), -0.05),
        (DVec3::new(0.0, 0.0, 0.5 + e - 0.02), -0.02),
    ]
}

fn options(mode: MeshMode) -> CollisionOptions {
    CollisionOptions::default()
        .with_mesh_path(data_dir())
        .with_mesh_mode(mode)
}

#[test]
fn every_primitive_against_a_mesh_link_pair() {
    for (primitive, e, corner) in PRIMITIVES {
        let model = robot(primitive);
        for mode in MODES {
            let cmodel = CollisionModel::from_model(&model, &options(mode)).unwrap();
            assert_eq!(cmodel.pairs().len(), 1, "{primitive}");
            let mut kinematics = KinematicsData::new(&model);
            let mut data = CollisionData::new(&cmodel);
            for (at, expected) in cases(e, corner) {
                let q = [at.x, at.y, at.z];
                data.compute_placements(&model, &cmodel, &mut kinematics, &q)
                    .unwrap();
                let d = compute_distances(&cmodel, &mut data).unwrap()[0].distance;
                assert!(
                    (d - expected).abs() < 1e-6,
                    "{primitive} {mode:?} at {at}: {d}, expected {expected}"
                );
                let listed = compute_self_collisions(&cmodel, &mut data)
                    .unwrap()
                    .to_vec();
                assert_eq!(
                    listed.len(),
                    usize::from(expected < 0.0),
                    "{primitive} {mode:?} at {at}: contacts {listed:?}"
                );
                if let Some(c) = listed.first() {
                    assert!(
                        (c.distance - expected).abs() < 1e-6,
                        "{primitive} {mode:?} at {at}: contact {c:?}"
                    );
                }
                assert_eq!(
                    any_collision(&cmodel, &mut data).unwrap(),
                    expected < 0.0,
                    "{primitive} {mode:?} at {at}"
                );
            }
        }
    }
}

/// The primitive as a world obstacle against the cube on a link, and the cube as an obstacle
/// against the primitive on a link.
#[test]
fn every_primitive_against_a_mesh_obstacle_and_back() {
    for (primitive, e, corner) in PRIMITIVES {
        let geometry = primitive_geometry(primitive);
        for mode in MODES {
            let opts = options(mode);
            // The cube on the link, the primitive as the obstacle.
            let model = robot(primitive);
            let cmodel = CollisionModel::from_model(&model, &opts).unwrap();
            let mesh_shape = cmodel.shape_index("m_0").unwrap();
            let prim_shape = cmodel.shape_index("p_0").unwrap();
            let mut kinematics = KinematicsData::new(&model);
            let cube = Geometry::Mesh {
                filename: "meshes/unit_cube.obj".to_string(),
                scale: [1.0; 3],
            };
            for (at, expected) in cases(e, corner) {
                // Primitive obstacle against the linked cube (the linked primitive far away).
                let mut data = CollisionData::new(&cmodel);
                data.compute_placements(&model, &cmodel, &mut kinematics, &[9.0, 9.0, 9.0])
                    .unwrap();
                let id = data
                    .add_obstacle("prim", &geometry, &Se3::from_translation(at), &opts)
                    .unwrap();
                check_world(
                    &cmodel, &mut data, mesh_shape, id.0, expected, primitive, mode,
                );
                // Cube obstacle against the linked primitive: the cube placed so that the
                // primitive (at (9, 9, 9)) sits at `at` relative to it.
                let mut data = CollisionData::new(&cmodel);
                data.compute_placements(&model, &cmodel, &mut kinematics, &[9.0, 9.0, 9.0])
                    .unwrap();
                let id = data
                    .add_obstacle(
                        "cube",
                        &cube,
                        &Se3::from_translation(DVec3::splat(9.0) - at),
                        &opts,
                    )
                    .unwrap();
                check_world(
                    &cmodel, &mut data, prim_shape, id.0, expected, primitive, mode,
                );
            }
        }
    }
}

fn check_world(
    cmodel: &CollisionModel,
    data: &mut CollisionData,
    shape: usize,
    obstacle: usize,
    expected: f64,
    primitive: &str,
    mode: MeshMode,
) {
    let d = compute_world_distances(cmodel, data)
        .unwrap()
        .iter()
        .find(|p| p.a == shape && p.b == obstacle)
        .unwrap()
        .distance;
    assert!(
        (d - expected).abs() < 1e-6,
        "world {primitive} {mode:?}: {d}, expected {expected}"
    );
    let listed: Vec<_> = compute_world_collisions(cmodel, data)
        .unwrap()
        .iter()
        .filter(|p| p.a == shape && p.b == obstacle)
        .copied()
        .collect();
    assert_eq!(
        listed.len(),
        usize::from(expected < 0.0),
        "world {primitive} {mode:?}: {listed:?} expected {expected}"
    );
    if let Some(c) = listed.first() {
        assert!(
            (c.distance - expected).abs() < 1e-6,
            "world {primitive} {mode:?}: contact {c:?}"
        );
    }
}

fn primitive_geometry(text: &str) -> Geometry {
    if text.starts_with("<box") {
        Geometry::Box { size: [0.2; 3] }
    } else if text.starts_with("<sphere") {
        Geometry::Sphere { radius: 0.1 }
    } else if text.starts_with("<cylinder") {
        Geometry::Cylinder {
            radius: 0.1,
            length: 0.2,
        }
    } else {
        Geometry::Capsule {
            radius: 0.1,
            length: 0.2,
        }
    }
}
