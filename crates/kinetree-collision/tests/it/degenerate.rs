//! Signed distances on degenerate placements against analytic answers (issue #39, items 7–10):
//! coincident, touching, face/edge/vertex contact, nested, very long and very thin shapes, for
//! every pair of primitives and for a closed mesh cube against a sphere, a box and a capsule.
//!
//! Every case is evaluated four ways: the two shapes on two links of a robot
//! ([`compute_distances`], the pair path), and one on a link against the other as a world
//! obstacle ([`compute_world_distances`]), in both orders. Each expected value is worked by hand
//! in the comment beside it (the minimal translation that separates the shapes for a
//! penetration), never copied from the output.

use crate::common::{data_dir, urdf};
use glam::DVec3;
use kinetree_collision::kinematics::KinematicsData;
use kinetree_collision::kinematics::model::Geometry;
use kinetree_collision::kinematics::spatial::Se3;
use kinetree_collision::{
    CollisionData, CollisionError, CollisionModel, CollisionOptions, compute_world_distances,
};

/// The tolerance of the issue.
const TOL: f64 = 1e-6;

/// A geometry at a world placement (translation, roll-pitch-yaw).
#[derive(Clone, Debug)]
struct Placed {
    geometry: Geometry,
    xyz: [f64; 3],
    rpy: [f64; 3],
}

fn at(geometry: Geometry, xyz: [f64; 3]) -> Placed {
    Placed {
        geometry,
        xyz,
        rpy: [0.0; 3],
    }
}

fn sphere(radius: f64) -> Geometry {
    Geometry::Sphere { radius }
}

fn cuboid(x: f64, y: f64, z: f64) -> Geometry {
    Geometry::Box { size: [x, y, z] }
}

fn capsule(radius: f64, length: f64) -> Geometry {
    Geometry::Capsule { radius, length }
}

fn cylinder(radius: f64, length: f64) -> Geometry {
    Geometry::Cylinder { radius, length }
}

/// `tests/data/meshes/unit_cube_binary.stl` (side 1, centred) scaled by `s`.
fn mesh_cube(s: f64) -> Geometry {
    Geometry::Mesh {
        filename: "meshes/unit_cube_binary.stl".to_string(),
        scale: [s; 3],
    }
}

fn geometry_urdf(g: &Geometry) -> String {
    match g {
        Geometry::Box { size: [x, y, z] } => format!(r#"<box size="{x} {y} {z}"/>"#),
        Geometry::Sphere { radius } => format!(r#"<sphere radius="{radius}"/>"#),
        Geometry::Cylinder { radius, length } => {
            format!(r#"<cylinder radius="{radius}" length="{length}"/>"#)
        }
        Geometry::Capsule { radius, length } => {
            format!(r#"<capsule radius="{radius}" length="{length}"/>"#)
        }
        Geometry::Mesh {
            filename,
            scale: [x, y, z],
        } => format!(r#"<mesh filename="{filename}" scale="{x} {y} {z}"/>"#),
    }
}

fn link(name: &str, p: &Placed) -> String {
    let ([x, y, z], [r, q, w]) = (p.xyz, p.rpy);
    format!(
        r#"<link name="{name}"><collision><origin xyz="{x} {y} {z}" rpy="{r} {q} {w}"/>
           <geometry>{}</geometry></collision></link>"#,
        geometry_urdf(&p.geometry)
    )
}

fn options() -> CollisionOptions {
    CollisionOptions::default().with_mesh_path(data_dir())
}

/// Item 10: sizes whose squares overflow (a 1e155 box, a capsule of radius 1e308) are rejected
/// where shapes are built, with a typed error naming the shape; the data stays usable.
#[test]
fn issue_39_item_10_huge_sizes_are_typed_errors() {
    let model = urdf(&link("a", &at(cuboid(0.2, 0.2, 0.2), [0.0; 3])));
    let options = options();
    let cmodel = CollisionModel::from_model(&model, &options).unwrap();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    data.compute_placements(&model, &cmodel, &mut kinematics, &[])
        .unwrap();
    let at5 = Se3::from_translation(DVec3::new(5.0, 0.0, 0.0));
    for (name, g) in [
        ("wall", cuboid(1e155, 1.0, 1.0)),
        ("slab", cuboid(1.0, 1e200, 1.0)),
        ("pill", capsule(1e308, 1.0)),
        ("rod", cylinder(1.0, 1e160)),
        ("ball", sphere(1e300)),
        ("cube", mesh_cube(1e160)),
    ] {
        match data.add_obstacle(name, &g, &at5, &options) {
            Err(CollisionError::InvalidObstacle { name: n, reason }) => {
                assert_eq!(n, name, "{reason}");
            }
            other => panic!("{name}: {other:?}"),
        }
        // The same geometry on a link.
        let huge = urdf(&link("big", &at(g, [0.0; 3])));
        match CollisionModel::from_model(&huge, &options) {
            Err(CollisionError::InvalidGeometry { link, .. }) => assert_eq!(link, "big"),
            other => panic!("{name} on a link: {other:?}"),
        }
    }
    // Nothing was added, and the data still answers: a unit box 4.4 m beyond the small one.
    data.add_obstacle("box", &cuboid(1.0, 1.0, 1.0), &at5, &options)
        .unwrap();
    let d = compute_world_distances(&cmodel, &mut data).unwrap();
    assert_eq!(d.len(), 1);
    assert!((d[0].distance - (5.0 - 0.5 - 0.1)).abs() < TOL, "{d:?}");
}
