//! Hand-computed cases: two spheres, sphere–box, a cylinder's rim.

use crate::common::urdf;
use glam::DVec3;
use kinetree_collision::kinematics::KinematicsData;
use kinetree_collision::kinematics::model::Model;
use kinetree_collision::{
    CollisionData, CollisionModel, CollisionOptions, Proximity, any_collision, compute_distances,
    compute_self_collisions,
};
use kinetree_test_support::assert_close;

/// Two links `a` and `b` on prismatic joints along world x from a common base (sibling bodies,
/// so they are a candidate pair), with the given collision elements.
fn two_links(a: &str, b: &str) -> Model {
    let joint = |name: &str, child: &str| {
        format!(
            r#"<joint name="{name}" type="prismatic"><parent link="base"/><child link="{child}"/>
               <axis xyz="1 0 0"/><limit lower="-10" upper="10" effort="1" velocity="1"/></joint>"#
        )
    };
    urdf(&format!(
        r#"<link name="base"/><link name="a">{a}</link><link name="b">{b}</link>{}{}"#,
        joint("ja", "a"),
        joint("jb", "b")
    ))
}

fn collision(origin: &str, geometry: &str) -> String {
    format!("<collision><origin {origin}/><geometry>{geometry}</geometry></collision>")
}

/// The single pair's proximity with link `a` at x = `qa` and `b` at x = `qb`.
fn measure(model: &Model, qa: f64, qb: f64) -> (Proximity, bool) {
    let cmodel = CollisionModel::from_model(model, &CollisionOptions::default()).unwrap();
    assert_eq!(cmodel.pairs().len(), 1);
    let mut kinematics = KinematicsData::new(model);
    let mut data = CollisionData::new(&cmodel);
    // Our q order follows the model's joints; set by name to be safe.
    let mut q = vec![0.0; model.nq()];
    for (name, value) in [("ja", qa), ("jb", qb)] {
        let j = model.joint_index(name).unwrap();
        q[model.joint_q_range(j).start] = value;
    }
    data.compute_placements(model, &cmodel, &mut kinematics, &q)
        .unwrap();
    let p = compute_distances(&cmodel, &mut data).unwrap()[0];
    let hit = any_collision(&cmodel, &mut data).unwrap();
    let contacts = compute_self_collisions(&cmodel, &mut data).unwrap();
    assert_eq!(contacts.len(), usize::from(hit));
    if hit {
        assert_close!(contacts[0].distance, p.distance, 1e-9);
    }
    (p, hit)
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn two_spheres() {
    let model = two_links(
        &collision(r#"xyz="0 0 0""#, r#"<sphere radius="0.1"/>"#),
        &collision(r#"xyz="0 0 0""#, r#"<sphere radius="0.2"/>"#),
    );
    let (p, hit) = measure(&model, 0.0, 1.0);
    assert_close!(p.distance, 0.7, 1e-12);
    assert!(!hit);
    assert!(close(p.point_a, DVec3::new(0.1, 0.0, 0.0)));
    assert!(close(p.point_b, DVec3::new(0.8, 0.0, 0.0)));
    assert!(close(p.normal, DVec3::X));
    // Overlapping by 0.1: signed distance -0.1, deepest points on each surface.
    let (p, hit) = measure(&model, 0.5, 0.7);
    assert_close!(p.distance, -0.1, 1e-12);
    assert!(hit);
    assert!(close(p.point_a, DVec3::new(0.6, 0.0, 0.0)));
    assert!(close(p.point_b, DVec3::new(0.5, 0.0, 0.0)));
}

#[test]
fn sphere_and_box() {
    // Box 0.2 x 0.4 x 0.6 on a; sphere of radius 0.1 on b, offset by (0, 0.5, 0.5) in its link.
    let model = two_links(
        &collision(r#"xyz="0 0 0""#, r#"<box size="0.2 0.4 0.6"/>"#),
        &collision(r#"xyz="0 0.5 0.5""#, r#"<sphere radius="0.1"/>"#),
    );
    // Facing the corner region: closest box point (0.1, 0.2, 0.3), centre (0.5, 0.5, 0.5).
    let (p, _) = measure(&model, 0.0, 0.5);
    assert_close!(p.distance, (0.29_f64.sqrt() - 0.1), 1e-9, 0.0, "{p:?}");
    assert!(close(p.point_a, DVec3::new(0.1, 0.2, 0.3)));
    // Facing the edge y = 0.2, z = 0.3: closest box point (0, 0.2, 0.3).
    let (p, hit) = measure(&model, 0.0, 0.0);
    assert_close!(p.distance, (0.13_f64.sqrt() - 0.1), 1e-9, 0.0, "{p:?}");
    assert!(close(p.point_a, DVec3::new(0.0, 0.2, 0.3)));
    assert!(!hit);
    // Facing the +y face: sphere centre (0, 0.5, 0) is 0.3 from it.
    let model_face = two_links(
        &collision(r#"xyz="0 0 0""#, r#"<box size="0.2 0.4 0.6"/>"#),
        &collision(r#"xyz="0 0.5 0""#, r#"<sphere radius="0.1"/>"#),
    );
    let (p, _) = measure(&model_face, 0.05, 0.0);
    assert_close!(p.distance, 0.2, 1e-9, 0.0, "{p:?}");
    assert!(close(p.normal, DVec3::Y));
    // Box moved so the sphere centre (0, 0.5, 0.5) is inside it, 0.05 below the top face
    // (box 0.2 x 0.4 x 0.6 centred at (0, 0.5, 0.5) via a second model): depth = 0.05 + 0.1.
    let model = two_links(
        &collision(r#"xyz="0 0.5 0.25""#, r#"<box size="0.2 0.4 0.6"/>"#),
        &collision(r#"xyz="0 0.5 0.5""#, r#"<sphere radius="0.1"/>"#),
    );
    let (p, hit) = measure(&model, 0.0, 0.0);
    assert!(hit);
    assert_close!(p.distance, -0.15, 1e-9, 0.0, "{p:?}");
    assert!(close(p.normal, DVec3::Z), "{p:?}");
}

#[test]
fn cylinder_rim() {
    // URDF cylinder: radius 0.1, full length 0.4 along its z axis, centred at the origin.
    let cylinder = collision(r#"xyz="0 0 0""#, r#"<cylinder radius="0.1" length="0.4"/>"#);
    // A sphere of radius 0.05 beyond the top rim: closest rim point (0.1, 0, 0.2).
    let model = two_links(
        &cylinder,
        &collision(r#"xyz="0 0 0.3""#, r#"<sphere radius="0.05"/>"#),
    );
    let (p, _) = measure(&model, 0.0, 0.2);
    assert!(
        (p.distance - (0.02_f64.sqrt() - 0.05)).abs() < 1e-9,
        "{p:?}"
    );
    assert!(close(p.point_a, DVec3::new(0.1, 0.0, 0.2)), "{p:?}");
    // Two cylinders rim to rim: top disk of a (z = 0.2, radius 0.1) and bottom disk of b
    // (z = 0.3, centre x = 0.3): 0.1 apart in x and in z.
    let model = two_links(
        &cylinder,
        &collision(
            r#"xyz="0 0 0.5""#,
            r#"<cylinder radius="0.1" length="0.4"/>"#,
        ),
    );
    let (p, hit) = measure(&model, 0.0, 0.3);
    assert_close!(p.distance, 0.02_f64.sqrt(), 1e-8, 0.0, "{p:?}");
    assert!(!hit);
    // Overlapping side by side (axes 0.15 apart): penetration depth 0.05 across the sides.
    let model = two_links(&cylinder, &cylinder);
    let (p, hit) = measure(&model, 0.0, 0.15);
    assert!(hit);
    assert_close!(p.distance, -0.05, 1e-6, 0.0, "{p:?}");
    // A cylinder turned by the element's origin (axis along world y): a sphere on the y axis
    // at 0.3 is 0.3 - 0.2 - 0.05 away.
    let model = two_links(
        &collision(
            r#"xyz="0 0 0" rpy="1.5707963267948966 0 0""#,
            r#"<cylinder radius="0.1" length="0.4"/>"#,
        ),
        &collision(r#"xyz="0 0.3 0""#, r#"<sphere radius="0.05"/>"#),
    );
    let (p, _) = measure(&model, 0.0, 0.0);
    assert_close!(p.distance, 0.05, 1e-9, 0.0, "{p:?}");
}
