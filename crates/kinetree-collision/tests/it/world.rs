//! World obstacles: added, moved and removed at run time.

use crate::common::{panda, q_of};
use glam::DVec3;
use kinetree_collision::kinematics::KinematicsData;
use kinetree_collision::kinematics::model::Geometry;
use kinetree_collision::kinematics::spatial::Se3;
use kinetree_collision::parry::math::Pose;
use kinetree_collision::parry::shape::SharedShape;
use kinetree_collision::{
    CollisionData, CollisionError, CollisionModel, CollisionOptions, ObstacleId, any_collision,
    compute_world_collisions, compute_world_distances,
};

#[test]
fn obstacles_collide_and_measure() {
    let (reference, model) = panda();
    let options = CollisionOptions::default();
    let cmodel = CollisionModel::from_model(&model, &options).unwrap();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    let q = q_of(&model, &reference["samples"][0]);
    data.compute_placements(&model, &cmodel, &mut kinematics, &q)
        .unwrap();
    let self_colliding = any_collision(&cmodel, &mut data).unwrap();

    // A capsule along world z far away: no contact, distances from every shape.
    let capsule = data
        .add_obstacle(
            "post",
            &Geometry::Capsule {
                radius: 0.1,
                length: 1.0,
            },
            &Se3::from_translation(DVec3::new(3.0, 0.0, 0.5)),
            &options,
        )
        .unwrap();
    assert!(
        compute_world_collisions(&cmodel, &mut data)
            .unwrap()
            .is_empty()
    );
    let distances = compute_world_distances(&cmodel, &mut data).unwrap();
    assert_eq!(distances.len(), cmodel.shapes().len());
    // The base sphere panda_link0_1 (radius 0.09 at (-0.06, 0, 0.06)) is level with the
    // capsule's segment: distance = 3.06 - 0.09 - 0.1.
    let base = cmodel.shape_index("panda_link0_1").unwrap();
    let d = distances.iter().find(|p| p.a == base).unwrap();
    assert!((d.distance - (3.06 - 0.19)).abs() < 1e-9, "{d:?}");
    assert_eq!(d.b, capsule.0);

    // A ball moved onto the base sphere: a world contact of depth 0.05.
    let ball = data
        .add_obstacle_shape(
            "ball",
            SharedShape::ball(0.1),
            &Pose::translation(5.0, 5.0, 5.0),
        )
        .unwrap();
    data.set_obstacle_pose(ball, &Pose::translation(-0.06, 0.0, 0.06 + 0.14))
        .unwrap();
    assert!(any_collision(&cmodel, &mut data).unwrap());
    let contacts = compute_world_collisions(&cmodel, &mut data).unwrap();
    let c = contacts
        .iter()
        .find(|c| c.a == base && c.b == ball.0)
        .unwrap();
    assert!((c.distance + 0.05).abs() < 1e-12, "{c:?}");
    assert!((c.normal - DVec3::Z).length() < 1e-12);

    // Removing it restores the previous state; ids of the others stay valid.
    data.remove_obstacle(ball).unwrap();
    assert_eq!(any_collision(&cmodel, &mut data).unwrap(), self_colliding);
    assert!(data.obstacle(capsule).is_ok());
    assert!(matches!(
        data.set_obstacle_pose(ball, &Pose::IDENTITY),
        Err(CollisionError::UnknownObstacle { .. })
    ));
    assert!(matches!(
        data.obstacle(ObstacleId(99)),
        Err(CollisionError::UnknownObstacle { id: 99 })
    ));
    let nan = Pose::translation(f64::NAN, 0.0, 0.0);
    assert!(matches!(
        data.set_obstacle_pose(capsule, &nan),
        Err(CollisionError::NonFinite { .. })
    ));
    assert!(matches!(
        data.add_obstacle(
            "bad",
            &Geometry::Sphere { radius: -1.0 },
            &Se3::IDENTITY,
            &options
        ),
        Err(CollisionError::InvalidObstacle { name, reason })
            if name == "bad" && reason.contains("radius = -1")
    ));
    let far = Se3::from_translation(DVec3::new(f64::INFINITY, 0.0, 0.0));
    let err = data
        .add_obstacle("far", &Geometry::Sphere { radius: 1.0 }, &far, &options)
        .unwrap_err();
    assert_eq!(err.to_string(), "obstacle 'far': the pose is not finite");
    data.clear_obstacles();
    assert_eq!(data.obstacles().count(), 0);
    // A shape index past the model's shapes is an error; the last one is the last pose.
    let count = cmodel.shapes().len();
    assert_eq!(data.shape_pose(count - 1).ok(), data.shape_poses().last());
    assert!(matches!(
        data.shape_pose(count),
        Err(CollisionError::ShapeOutOfRange { index, count: c }) if index == count && c == count
    ));
}

#[test]
fn mismatched_data_and_bad_q_are_errors() {
    let (_, model) = panda();
    let cmodel = CollisionModel::from_model(&model, &CollisionOptions::default()).unwrap();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    assert!(matches!(
        data.compute_placements(&model, &cmodel, &mut kinematics, &[0.0; 3]),
        Err(CollisionError::Kinematics(_))
    ));
    let mut fewer = cmodel.clone();
    fewer
        .disable_link_pair(&model, "panda_link0", "panda_hand")
        .unwrap();
    assert!(matches!(
        any_collision(&fewer, &mut data),
        Err(CollisionError::DataMismatch { .. })
    ));
}

/// A scene file gives the same obstacles as adding them by hand: the capsule of
/// `obstacles_collide_and_measure` read from JSON is 3.06 - 0.19 m from the base sphere.
#[test]
fn a_scene_file_adds_its_obstacles() {
    use kinetree_collision::{ObstacleScene, SceneObstacle};
    let scene = ObstacleScene::from_json_str(
        r#"{"obstacles": [
            {"name": "post", "geometry": {"type": "capsule", "radius": 0.1, "length": 1.0},
             "xyz": [3.0, 0.0, 0.5]},
            {"name": "shelf", "geometry": {"type": "box", "size": [0.2, 0.2, 0.2]},
             "xyz": [0.0, 3.0, 0.5], "rpy": [0.0, 0.0, 0.5]}
        ]}"#,
    )
    .unwrap();
    assert_eq!(
        scene.obstacles[0],
        SceneObstacle {
            name: "post".into(),
            geometry: Geometry::Capsule {
                radius: 0.1,
                length: 1.0
            },
            xyz: [3.0, 0.0, 0.5],
            rpy: [0.0; 3],
        }
    );
    let yaw = scene.obstacles[1].placement().rotation * DVec3::X;
    assert!((yaw - DVec3::new(0.5f64.cos(), 0.5f64.sin(), 0.0)).length() < 1e-15);
    assert_eq!(
        ObstacleScene::from_json_str(&scene.to_json_string()).unwrap(),
        scene
    );

    let (reference, model) = panda();
    let options = CollisionOptions::default();
    let cmodel = CollisionModel::from_model(&model, &options).unwrap();
    let mut kinematics = KinematicsData::new(&model);
    let mut data = CollisionData::new(&cmodel);
    let q = q_of(&model, &reference["samples"][0]);
    data.compute_placements(&model, &cmodel, &mut kinematics, &q)
        .unwrap();
    let ids = scene.add_to(&mut data, &options).unwrap();
    assert_eq!(ids.len(), 2);
    assert_eq!(data.obstacle(ids[1]).unwrap().name(), "shelf");
    let base = cmodel.shape_index("panda_link0_1").unwrap();
    let distances = compute_world_distances(&cmodel, &mut data).unwrap();
    let d = distances
        .iter()
        .find(|p| p.a == base && p.b == ids[0].0)
        .unwrap();
    assert!((d.distance - (3.06 - 0.19)).abs() < 1e-9, "{d:?}");

    for (text, line) in [
        (
            r#"{"obstacles": [{"name": "a", "geometry": {"type": "sphere", "radius": 1}, "colour": 1}]}"#,
            1,
        ),
        (
            "{\"obstacles\": [\n{\"geometry\": {\"type\": \"sphere\", \"radius\": 1}}]}",
            2,
        ),
        ("{\"obstacles\": [", 1),
    ] {
        match ObstacleScene::from_json_str(text) {
            Err(CollisionError::InvalidScene {
                line: l, message, ..
            }) => {
                assert_eq!(l, line, "{message}");
                assert!(message.contains(&format!("line {line}")), "{message}");
            }
            other => panic!("{text}: expected InvalidScene, got {other:?}"),
        }
    }
}
