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
    CollisionData, CollisionError, CollisionModel, CollisionOptions, compute_distances,
    compute_world_distances,
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

fn turned(geometry: Geometry, xyz: [f64; 3], rpy: [f64; 3]) -> Placed {
    Placed { geometry, xyz, rpy }
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

/// The signed distance of `a` and `b` on two sibling links (the pair query).
fn pair_distance(a: &Placed, b: &Placed) -> Result<f64, CollisionError> {
    let joint = |name: &str, child: &str| {
        format!(
            r#"<joint name="{name}" type="prismatic"><parent link="base"/><child link="{child}"/>
               <axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#
        )
    };
    let model = urdf(&format!(
        r#"<link name="base"/>{}{}{}{}"#,
        link("a", a),
        link("b", b),
        joint("ja", "a"),
        joint("jb", "b")
    ));
    let cmodel = CollisionModel::from_model(&model, &options())?;
    assert_eq!(cmodel.pairs().len(), 1);
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    data.compute_placements(&model, &cmodel, &mut kinematics, &[0.0, 0.0])?;
    Ok(compute_distances(&cmodel, &mut data)?[0].distance)
}

/// The signed distance of `a` on a link and `b` as a world obstacle.
fn world_distance(a: &Placed, b: &Placed) -> Result<f64, CollisionError> {
    let model = urdf(&link("a", a));
    let options = options();
    let cmodel = CollisionModel::from_model(&model, &options)?;
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    data.compute_placements(&model, &cmodel, &mut kinematics, &[])?;
    data.add_obstacle("b", &b.geometry, &Se3::from_xyz_rpy(b.xyz, b.rpy), &options)?;
    Ok(compute_world_distances(&cmodel, &mut data)?[0].distance)
}

/// The four evaluations of a case (pair and world path, both orders).
fn distances(a: &Placed, b: &Placed) -> [f64; 4] {
    let run = |r: Result<f64, CollisionError>| r.unwrap_or_else(|e| panic!("{a:?} {b:?}: {e}"));
    [
        run(pair_distance(a, b)),
        run(pair_distance(b, a)),
        run(world_distance(a, b)),
        run(world_distance(b, a)),
    ]
}

/// Asserts all four evaluations are within [`TOL`] of `expected`; returns the failures as
/// text (so a grid reports every failing case at once).
fn check(what: &str, a: &Placed, b: &Placed, expected: f64) -> Option<String> {
    let d = distances(a, b);
    d.iter()
        .any(|x| (x - expected).abs() > TOL)
        .then(|| format!("{what}: {d:?}, expected {expected}"))
}

fn assert_all(failures: Vec<String>) {
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Item 7: two identical capsules (radius 0.05, length 0.3) at the same place; the capsule
/// against the identical cylinder; two identical cylinders. The shortest separating move is
/// sideways: the sum of the radii, 0.1 (along the axis it is 0.2 + 0.2 for the capsules,
/// 0.2 + 0.15 for capsule and cylinder, 0.15 + 0.15 for the cylinders).
#[test]
fn issue_39_item_7_coincident_capsules_and_cylinders() {
    let o = [0.0; 3];
    assert_all(
        [
            ("capsules", capsule(0.05, 0.3), capsule(0.05, 0.3)),
            ("capsule, cylinder", capsule(0.05, 0.3), cylinder(0.05, 0.3)),
            ("cylinders", cylinder(0.05, 0.3), cylinder(0.05, 0.3)),
        ]
        .into_iter()
        .filter_map(|(what, a, b)| check(what, &at(a, o), &at(b, o), -0.1))
        .collect(),
    );
}

/// Item 8: the mesh cube of side 0.1 against a sphere of radius 0.01 centred on its surface:
/// on a face centre (on the diagonal two triangles share), on edges and on a vertex. The
/// sphere must move out by its radius: -0.01 everywhere.
#[test]
fn issue_39_item_8_sphere_centred_on_a_mesh_surface() {
    let cube = at(mesh_cube(0.1), [0.0; 3]);
    let centres = [
        ("face centre +z", [0.0, 0.0, 0.05]),
        ("face centre -x", [-0.05, 0.0, 0.0]),
        ("face point", [0.01, -0.02, 0.05]),
        ("edge midpoint", [0.05, 0.0, 0.05]),
        ("edge point", [0.05, 0.05, 0.013]),
        ("edge point 2", [-0.02, -0.05, -0.05]),
        ("vertex", [0.05, 0.05, 0.05]),
        ("vertex 2", [-0.05, 0.05, -0.05]),
    ];
    assert_all(
        centres
            .into_iter()
            .filter_map(|(what, c)| check(what, &cube, &at(sphere(0.01), c), -0.01))
            .collect(),
    );
}

/// Item 9: a 0.2 m box inside a long obstacle box (1e5 or 1e6 by 1 by 1, centred at x = 5):
/// the box leaves through a side face, 0.5 + 0.1 = 0.6.
#[test]
fn issue_39_item_9_box_inside_a_huge_box() {
    let small = at(cuboid(0.2, 0.2, 0.2), [0.0; 3]);
    assert_all(
        [1e5, 1e6]
            .into_iter()
            .filter_map(|len| {
                check(
                    &format!("length {len}"),
                    &small,
                    &at(cuboid(len, 1.0, 1.0), [5.0, 0.0, 0.0]),
                    -0.6,
                )
            })
            .collect(),
    );
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

/// URDF roll, pitch, yaw of a rotation (`R = Rz(yaw)·Ry(pitch)·Rx(roll)`).
fn rpy_of(q: glam::DQuat) -> [f64; 3] {
    let (yaw, pitch, roll) = q.to_euler(glam::EulerRot::ZYX);
    [roll, pitch, yaw]
}

const PI: f64 = core::f64::consts::PI;

/// A grid of degenerate placements for every pair of primitives, with the signed distance
/// worked by hand for each (box `B` is 0.2 × 0.4 × 0.6; capsule `C` and cylinder `Y` have
/// radius 0.05 and length 0.3 along z unless said otherwise).
#[test]
fn primitive_pairs_on_degenerate_placements() {
    let o = [0.0; 3];
    let b = || cuboid(0.2, 0.4, 0.6);
    let c = || capsule(0.05, 0.3);
    let y = || cylinder(0.05, 0.3);
    // Along x: pitch a quarter turn. Along (1, 1, 0): then yaw an eighth.
    let along_x = [0.0, PI / 2.0, 0.0];
    let s2 = 2f64.sqrt();
    let s3 = 3f64.sqrt();
    // A box corner (-1, -1, -1) turned onto -x: about (0, 1, -1) by acos(1/√3).
    let corner_out = rpy_of(glam::DQuat::from_axis_angle(
        glam::DVec3::new(0.0, 1.0, -1.0).normalize(),
        (1.0 / s3).acos(),
    ));
    let cases: Vec<(&str, Placed, Placed, f64)> = vec![
        // Spheres.
        (
            "spheres coincident",
            at(sphere(0.1), o),
            at(sphere(0.05), o),
            -0.15,
        ),
        (
            "spheres touching",
            at(sphere(0.1), o),
            at(sphere(0.05), [0.15, 0.0, 0.0]),
            0.0,
        ),
        // Nested off centre: out along x, 0.35 - 0.1.
        (
            "spheres nested",
            at(sphere(0.3), o),
            at(sphere(0.05), [0.1, 0.0, 0.0]),
            -0.25,
        ),
        // Sphere and box: centre inside (nearest face 0.1 away), on a face, edge, vertex.
        ("sphere in box", at(b(), o), at(sphere(0.05), o), -0.15),
        (
            "sphere on box face",
            at(b(), o),
            at(sphere(0.05), [0.1, 0.0, 0.0]),
            -0.05,
        ),
        (
            "sphere on box edge",
            at(b(), o),
            at(sphere(0.05), [0.1, 0.2, 0.0]),
            -0.05,
        ),
        (
            "sphere on box vertex",
            at(b(), o),
            at(sphere(0.05), [0.1, 0.2, 0.3]),
            -0.05,
        ),
        (
            "sphere touching box face",
            at(b(), o),
            at(sphere(0.05), [0.15, 0.0, 0.0]),
            0.0,
        ),
        (
            "sphere touching box vertex",
            at(b(), o),
            at(
                sphere(0.05),
                [0.1 + 0.05 / s3, 0.2 + 0.05 / s3, 0.3 + 0.05 / s3],
            ),
            0.0,
        ),
        // Sphere and capsule: centres together, on the segment's end, on the tip.
        ("sphere in capsule", at(c(), o), at(sphere(0.02), o), -0.07),
        (
            "sphere at capsule end",
            at(c(), o),
            at(sphere(0.02), [0.0, 0.0, 0.15]),
            -0.07,
        ),
        (
            "sphere on capsule tip",
            at(c(), o),
            at(sphere(0.02), [0.0, 0.0, 0.2]),
            -0.02,
        ),
        (
            "sphere touching capsule",
            at(c(), o),
            at(sphere(0.02), [0.07, 0.0, 0.1]),
            0.0,
        ),
        // Sphere and cylinder: centre (nearest the side), rim, cap centre, touching the rim.
        ("sphere in cylinder", at(y(), o), at(sphere(0.02), o), -0.07),
        (
            "sphere on cylinder rim",
            at(y(), o),
            at(sphere(0.02), [0.05, 0.0, 0.15]),
            -0.02,
        ),
        (
            "sphere on cylinder cap",
            at(y(), o),
            at(sphere(0.02), [0.0, 0.0, 0.15]),
            -0.02,
        ),
        (
            "sphere touching cylinder rim",
            at(y(), o),
            at(sphere(0.02), [0.05 + 0.02 / s2, 0.0, 0.15 + 0.02 / s2]),
            0.0,
        ),
        // Boxes: coincident (out along x, 0.1 + 0.1), nested (out through +x, 0.5 - 0.3 +
        // 0.05), face to face touching, an edge and a corner 0.01 into a face.
        ("boxes coincident", at(b(), o), at(b(), o), -0.2),
        (
            "box nested in box",
            at(cuboid(1.0, 1.0, 1.0), o),
            at(cuboid(0.1, 0.1, 0.1), [0.3, 0.0, 0.0]),
            -0.25,
        ),
        (
            "boxes touching faces",
            at(cuboid(0.2, 0.2, 0.2), o),
            at(cuboid(0.2, 0.2, 0.2), [0.2, 0.05, 0.0]),
            0.0,
        ),
        (
            "box edge into a face",
            at(cuboid(0.2, 0.2, 0.2), o),
            turned(
                cuboid(0.2, 0.2, 0.2),
                [0.1 + 0.1 * s2 - 0.01, 0.0, 0.0],
                [0.0, 0.0, PI / 4.0],
            ),
            -0.01,
        ),
        (
            "box corner into a face",
            at(cuboid(0.2, 0.2, 0.2), o),
            turned(
                cuboid(0.2, 0.2, 0.2),
                [0.1 + 0.1 * s3 - 0.01, 0.0, 0.0],
                corner_out,
            ),
            -0.01,
        ),
        // A plate 1e-4 thick through a box's centre: 0.1 + 5e-5 along z.
        (
            "box on a thin plate",
            at(cuboid(1.0, 1.0, 1e-4), o),
            at(cuboid(0.2, 0.2, 0.2), o),
            -0.10005,
        ),
        // Inside a box 1e5 m long (1 × 1 across, centred at x = 5): out sideways, 0.5 plus the
        // half width across.
        (
            "box in a long box",
            at(cuboid(1e5, 1.0, 1.0), [5.0, 0.0, 0.0]),
            at(cuboid(0.2, 0.2, 0.2), o),
            -0.6,
        ),
        (
            "capsule in a long box",
            at(cuboid(1e5, 1.0, 1.0), [5.0, 0.0, 0.0]),
            at(c(), o),
            -0.55,
        ),
        (
            "cylinder in a long box",
            at(cuboid(1e5, 1.0, 1.0), [5.0, 0.0, 0.0]),
            at(y(), o),
            -0.55,
        ),
        (
            "sphere in a long box",
            at(cuboid(1e5, 1.0, 1.0), [5.0, 0.0, 0.0]),
            at(sphere(0.05), o),
            -0.55,
        ),
        // Capsules: coincident and crossed (out sideways, 0.05 + 0.05), side by side and end
        // to end touching, long thin coincident ones.
        (
            "capsules crossed",
            at(c(), o),
            turned(c(), o, along_x),
            -0.1,
        ),
        (
            "capsules side by side",
            at(c(), o),
            at(c(), [0.1, 0.0, 0.05]),
            0.0,
        ),
        (
            "capsules end to end",
            at(c(), o),
            at(c(), [0.0, 0.0, 0.4]),
            0.0,
        ),
        (
            "thin capsules",
            at(capsule(1e-4, 100.0), o),
            at(capsule(1e-4, 100.0), o),
            -2e-4,
        ),
        // Capsule and cylinder: crossed through the centre (out along y, 0.05 + 0.05), lying
        // on the cap, end into the cap by 0.05 (tip at 0.1, cap at 0.15).
        (
            "capsule across a cylinder",
            at(y(), o),
            turned(c(), o, along_x),
            -0.1,
        ),
        (
            "capsule on a cylinder cap",
            at(y(), o),
            turned(c(), [0.0, 0.0, 0.2], along_x),
            0.0,
        ),
        (
            "capsule into a cylinder cap",
            at(y(), o),
            at(c(), [0.0, 0.0, 0.3]),
            -0.05,
        ),
        (
            "capsule beside a cylinder",
            at(y(), o),
            at(c(), [0.08, 0.0, 0.02]),
            -0.02,
        ),
        // Cylinders: stacked touching, crossed (out along y, 0.1), side by side 0.02 deep,
        // long thin coincident ones.
        (
            "cylinders stacked",
            at(y(), o),
            at(y(), [0.0, 0.0, 0.3]),
            0.0,
        ),
        (
            "cylinders crossed",
            at(y(), o),
            turned(y(), o, along_x),
            -0.1,
        ),
        (
            "cylinders side by side",
            at(y(), o),
            at(y(), [0.08, 0.0, 0.0]),
            -0.02,
        ),
        (
            "thin cylinders",
            at(cylinder(1e-4, 100.0), o),
            at(cylinder(1e-4, 100.0), o),
            -2e-4,
        ),
        // Box and capsule: centred (out along x, 0.1 + 0.05), lying on the top face,
        // along a vertical edge (out by the radius).
        ("capsule in a box", at(b(), o), at(c(), o), -0.15),
        (
            "capsule on a box",
            at(b(), o),
            turned(c(), [0.0, 0.0, 0.35], along_x),
            0.0,
        ),
        (
            "capsule on a box edge",
            at(b(), o),
            at(c(), [0.1, 0.2, 0.0]),
            -0.05,
        ),
        // Box and cylinder: centred (out along x, 0.1 + 0.05), standing on the top face, side
        // 0.01 into the +x face.
        ("cylinder in a box", at(b(), o), at(y(), o), -0.15),
        (
            "cylinder on a box",
            at(b(), o),
            at(y(), [0.0, 0.0, 0.45]),
            0.0,
        ),
        (
            "cylinder into a box face",
            at(b(), o),
            at(y(), [0.14, 0.0, 0.0]),
            -0.01,
        ),
    ];
    assert_all(
        cases
            .iter()
            .filter_map(|(what, a, b, expected)| check(what, a, b, *expected))
            .collect(),
    );
}

/// The mesh cube of side 0.1 (closed, so a solid) against a sphere, a box and a capsule on
/// degenerate placements, worked by hand.
#[test]
fn mesh_cube_on_degenerate_placements() {
    let cube = at(mesh_cube(0.1), [0.0; 3]);
    let s3 = 3f64.sqrt();
    let cases: Vec<(&str, Placed, f64)> = vec![
        // Sphere: centre inside, 0.02 below the top face (0.02 + 0.01); touching a face and a
        // vertex.
        ("sphere inside", at(sphere(0.01), [0.0, 0.0, 0.03]), -0.03),
        (
            "sphere touching a face",
            at(sphere(0.01), [0.0, 0.0, 0.06]),
            0.0,
        ),
        (
            "sphere touching a vertex",
            at(
                sphere(0.01),
                [0.05 + 0.01 / s3, 0.05 + 0.01 / s3, 0.05 + 0.01 / s3],
            ),
            0.0,
        ),
        ("sphere apart", at(sphere(0.01), [0.0, 0.2, 0.0]), 0.14),
        // A box of side 0.02 centred on a face, an edge, a vertex: out by its half side.
        (
            "box on a face",
            at(cuboid(0.02, 0.02, 0.02), [0.0, 0.0, 0.05]),
            -0.01,
        ),
        (
            "box on an edge",
            at(cuboid(0.02, 0.02, 0.02), [0.05, 0.0, 0.05]),
            -0.01,
        ),
        (
            "box on a vertex",
            at(cuboid(0.02, 0.02, 0.02), [0.05, 0.05, 0.05]),
            -0.01,
        ),
        (
            "box touching a face",
            at(cuboid(0.02, 0.02, 0.02), [0.0, 0.0, 0.06]),
            0.0,
        ),
        // A capsule (radius 0.01, length 0.04) lying on the top face along the diagonal the
        // two triangles share (out by the radius), standing through it (0.02 of segment
        // inside, plus the radius), and touching it.
        (
            "capsule on the diagonal",
            turned(
                capsule(0.01, 0.04),
                [0.0, 0.0, 0.05],
                [0.0, PI / 2.0, PI / 4.0],
            ),
            -0.01,
        ),
        (
            "capsule through a face",
            at(capsule(0.01, 0.04), [0.0, 0.0, 0.05]),
            -0.03,
        ),
        (
            "capsule touching a face",
            at(capsule(0.01, 0.04), [0.0, 0.0, 0.08]),
            0.0,
        ),
    ];
    assert_all(
        cases
            .iter()
            .filter_map(|(what, b, expected)| check(what, &cube, b, *expected))
            .collect(),
    );
}
