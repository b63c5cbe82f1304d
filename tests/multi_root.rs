//! A model with several root parts (each attached to the world datum by its own joint) against
//! the same mechanism hung from one massless root link welded to the world: forward kinematics,
//! Jacobians and dynamics must agree link for link; collision checks the two robots' bases
//! against each other, which are not adjacent once the world is their only common parent.

use glam::DVec3;
use kinetree::collision::{CollisionData, CollisionModel, CollisionOptions, compute_distances};
use kinetree::dynamics::{DynamicsData, aba, crba, rnea};
use kinetree::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, configuration,
    forward_kinematics,
};
use kinetree::model::{Collision, Geometry, JointKind, JointSpec, Link, Model, ModelBuilder};
use kinetree::spatial::{Motion, Se3, Symmetric3};
use rand::SeedableRng;
use rand::rngs::SmallRng;

fn part(name: &str, mass: f64) -> Link {
    let mut l = Link::new(name).with_mass(
        mass,
        DVec3::new(0.1, 0.02, 0.05),
        Symmetric3::new(0.02, 0.001, 0.0, 0.03, 0.002, 0.025),
    );
    l.collisions.push(Collision {
        name: None,
        origin: Se3::IDENTITY,
        geometry: Geometry::Sphere { radius: 0.1 },
    });
    l
}

/// Two arms: `left` welded at x = -1, `right` on a rail along y at x = +1. `root` is the parent
/// name of the two root joints: `"world"` (several roots) or a massless `table` link.
fn cell(root: &str) -> Model {
    let mut b = ModelBuilder::new("cell");
    if root != "world" {
        b.add_link(Link::new(root));
    }
    for (side, x, kind, axis) in [
        ("left", -1.0, JointKind::Fixed, DVec3::Z),
        ("right", 1.0, JointKind::Prismatic, DVec3::Y),
    ] {
        b.add_part(
            part(&format!("{side}_base"), 3.0),
            JointSpec::new(format!("{side}_mount"), kind, root, format!("{side}_base"))
                .with_axis(axis)
                .with_placement(Se3::from_xyz_rpy([x, 0.0, 0.0], [0.1, 0.0, 0.3])),
        );
        b.add_part(
            part(&format!("{side}_upper"), 2.0),
            JointSpec::new(
                format!("{side}_shoulder"),
                JointKind::Revolute,
                format!("{side}_base"),
                format!("{side}_upper"),
            )
            .with_axis(DVec3::new(0.0, 1.0, 1.0))
            .with_placement(Se3::from_translation(DVec3::new(0.0, 0.0, 0.3))),
        );
        b.add_part(
            part(&format!("{side}_fore"), 1.0),
            JointSpec::new(
                format!("{side}_elbow"),
                JointKind::Revolute,
                format!("{side}_upper"),
                format!("{side}_fore"),
            )
            .with_axis(DVec3::X)
            .with_placement(Se3::from_translation(DVec3::new(0.4, 0.0, 0.0))),
        );
    }
    b.build().unwrap()
}

fn close(a: &[f64], b: &[f64], tol: f64, what: &str) {
    kinetree_test_support::assert_close!(a, b, tol, 0.0, "{what}");
}

#[test]
fn several_roots_match_one_massless_root() {
    let multi = cell("world");
    let single = cell("table");
    assert_eq!(multi.root_links().len(), 2);
    assert_eq!(single.root_links().len(), 1);
    assert_eq!((multi.nq(), multi.nv()), (single.nq(), single.nv()));
    let (mut km, mut ks) = (KinematicsData::new(&multi), KinematicsData::new(&single));
    let (mut dm, mut ds) = (DynamicsData::new(&multi), DynamicsData::new(&single));
    let mut rng = SmallRng::seed_from_u64(10);
    let n = multi.nv();
    let mut q = vec![0.0; multi.nq()];
    let (mut jm, mut js) = (vec![Motion::ZERO; n], vec![Motion::ZERO; n]);
    for _ in 0..20 {
        configuration::random_configuration(&multi, &mut rng, &mut q).unwrap();
        let v: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let a: Vec<f64> = (0..n).map(|i| (i as f64 * 1.3).cos()).collect();
        forward_kinematics(&multi, &mut km, &q).unwrap();
        forward_kinematics(&single, &mut ks, &q).unwrap();
        for (l, link) in multi.links().iter().enumerate() {
            let s = single.link_index(&link.name).unwrap();
            let (pm, ps) = (km.world_from_link()[l], ks.world_from_link()[s]);
            close(
                &pm.to_rows().concat(),
                &ps.to_rows().concat(),
                1e-12,
                &link.name,
            );
            let (fm, fs) = (
                FrameId::find(&multi, &link.name).unwrap(),
                FrameId::find(&single, &link.name).unwrap(),
            );
            compute_frame_jacobian(
                &multi,
                &mut km,
                &q,
                fm,
                ReferenceFrame::LocalWorldAligned,
                &mut jm,
            )
            .unwrap();
            compute_frame_jacobian(
                &single,
                &mut ks,
                &q,
                fs,
                ReferenceFrame::LocalWorldAligned,
                &mut js,
            )
            .unwrap();
            for k in 0..n {
                close(&jm[k].to_array(), &js[k].to_array(), 1e-12, "jacobian");
            }
        }
        let tm = rnea(&multi, &mut dm, &q, &v, &a).unwrap().to_vec();
        let ts = rnea(&single, &mut ds, &q, &v, &a).unwrap().to_vec();
        close(&tm, &ts, 1e-10, "rnea");
        let mm = crba(&multi, &mut dm, &q).unwrap().to_vec();
        let ms = crba(&single, &mut ds, &q).unwrap().to_vec();
        close(&mm, &ms, 1e-10, "crba");
        let am = aba(&multi, &mut dm, &q, &v, &tm).unwrap().to_vec();
        close(&am, &a, 1e-9, "aba inverts rnea");
    }
}

#[test]
fn collision_checks_parts_of_different_roots_against_each_other() {
    let model = cell("world");
    let options = CollisionOptions::default();
    let cmodel = CollisionModel::from_model(&model, &options).unwrap();
    let mut kin = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    let mut q = configuration::neutral_configuration(&model);
    let rail = model.joint_q_range(model.joint_index("right_mount").unwrap());
    // The rail's axis is y in its joint frame, which is yawed by 0.3 and rolled by 0.1.
    q[rail.start] = 0.5;
    data.compute_placements(&model, &cmodel, &mut kin, &q)
        .unwrap();
    let shapes = cmodel.shapes();
    let name = |i: usize| shapes[i].name().to_string();
    let proximities = compute_distances(&cmodel, &mut data).unwrap();
    let bases = proximities
        .iter()
        .find(|p| {
            let mut pair = [name(p.a), name(p.b)];
            pair.sort();
            pair == ["left_base_0", "right_base_0"]
        })
        .expect("the two bases are a candidate pair");
    // By hand: the left base sits at (-1, 0, 0); the right one at (1, 0, 0) + 0.5 · R·y.
    let r = Se3::from_rpy(0.1, 0.0, 0.3);
    let right = DVec3::new(1.0, 0.0, 0.0) + r.transform_vector(DVec3::Y) * 0.5;
    let expected = (right - DVec3::new(-1.0, 0.0, 0.0)).length() - 0.2;
    assert!(
        (bases.distance - expected).abs() < 1e-9,
        "{} vs {expected}",
        bases.distance
    );
}
