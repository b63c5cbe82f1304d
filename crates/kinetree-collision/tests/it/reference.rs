//! Per-link-pair signed distances against Pinocchio 4.1 + coal 3.0.3 on panda_collision.

use crate::common::{panda, q_of};
use kinetree_collision::kinematics::KinematicsData;
use kinetree_collision::{
    CollisionData, CollisionModel, CollisionOptions, any_collision, compute_distances,
    compute_link_pair_distances, compute_self_collisions,
};
use std::collections::BTreeMap;

fn key(a: &str, b: &str) -> (String, String) {
    if a < b {
        (a.to_string(), b.to_string())
    } else {
        (b.to_string(), a.to_string())
    }
}

#[test]
fn geometry_and_pairs_match_the_reference() {
    let (reference, model) = panda();
    let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let info = &reference["collision_info"];
    assert_eq!(
        cmodel.shapes().len() as u64,
        info["n_geometries"].as_u64().unwrap()
    );
    assert_eq!(
        cmodel.pairs().len() as u64,
        info["n_candidate_geometry_pairs"].as_u64().unwrap()
    );
    // Every reference geometry exists under the same name, on the same link, with the same
    // placement in its link.
    for g in reference["collision_geometry"].as_array().unwrap() {
        let k = cmodel.shape_index(g["name"].as_str().unwrap()).unwrap();
        let s = &cmodel.shapes()[k];
        assert_eq!(model.link(s.link()).name, g["link"].as_str().unwrap());
        let t = &g["origin_in_link"]["translation"];
        for i in 0..3 {
            assert!((s.origin().translation[i] - t[i].as_f64().unwrap()).abs() < 1e-12);
        }
    }
}

#[test]
fn link_pair_distances_match_coal() {
    let (reference, model) = panda();
    let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    let mut worst = (0.0_f64, String::new());
    let mut worst_positive = 0.0_f64;
    for (s, sample) in reference["samples"].as_array().unwrap().iter().enumerate() {
        let q = q_of(&model, sample);
        let ours: BTreeMap<_, _> =
            compute_link_pair_distances(&model, &cmodel, &mut kinematics, &mut data, &q)
                .unwrap()
                .into_iter()
                .map(|(a, b, d)| (key(a, b), d))
                .collect();
        let theirs: BTreeMap<_, _> = sample["collision"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| {
                (
                    key(e["link_a"].as_str().unwrap(), e["link_b"].as_str().unwrap()),
                    e["distance"].as_f64().unwrap(),
                )
            })
            .collect();
        assert_eq!(
            ours.keys().collect::<Vec<_>>(),
            theirs.keys().collect::<Vec<_>>(),
            "sample {s}: link pair sets differ"
        );
        for (k, d) in &theirs {
            let err = (ours[k] - d).abs();
            if d.is_sign_positive() {
                worst_positive = worst_positive.max(err);
            }
            if err > worst.0 {
                worst = (err, format!("sample {s} {k:?}: ours {} coal {d}", ours[k]));
            }
        }
        // The collision queries agree with the signed distances.
        let colliding = ours.values().any(|d| *d < 0.0);
        assert_eq!(
            any_collision(&cmodel, &mut data).unwrap(),
            colliding,
            "sample {s}"
        );
        let contacts = compute_self_collisions(&cmodel, &mut data)
            .unwrap()
            .to_vec();
        let distances = compute_distances(&cmodel, &mut data).unwrap();
        let negative: Vec<_> = distances
            .iter()
            .filter(|p| p.distance < 0.0)
            .map(|p| (p.a, p.b))
            .collect();
        assert_eq!(
            contacts.iter().map(|c| (c.a, c.b)).collect::<Vec<_>>(),
            negative,
            "sample {s}"
        );
        for c in &contacts {
            let d = distances[cmodel.pair_index(c.a, c.b).unwrap()].distance;
            assert!((c.distance - d).abs() < 1e-9, "sample {s}: contact depth");
        }
    }
    println!(
        "worst |ours - coal| = {:.3e} ({}); positive distances: {worst_positive:.3e}",
        worst.0, worst.1
    );
    assert!(worst.0 < 1e-6, "worst error {:.3e}: {}", worst.0, worst.1);
}

#[test]
fn witness_points_realise_the_distance() {
    let (reference, model) = panda();
    let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    let q = q_of(&model, &reference["samples"][3]);
    data.compute_placements(&model, &cmodel, &mut kinematics, &q)
        .unwrap();
    for p in compute_distances(&cmodel, &mut data).unwrap() {
        let gap = p.point_b - p.point_a;
        // The witnesses are `distance` apart along the normal, whatever the sign.
        assert!((gap.length() - p.distance.abs()).abs() < 1e-7, "{p:?}");
        assert!((gap.dot(p.normal) - p.distance).abs() < 1e-7, "{p:?}");
        assert!((p.normal.length() - 1.0).abs() < 1e-12);
    }
}
