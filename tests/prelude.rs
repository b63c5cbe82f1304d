//! The facade's prelude reaches every layer: one hand-worked check per layer, through
//! `use kinetree::prelude::*` only.

use kinetree::model::samples;
use kinetree::prelude::*;
use std::f64::consts::FRAC_PI_2;

#[test]
fn every_layer_through_the_prelude() -> Result<(), Error> {
    // Kinematics: the planar 2R arm's tool at q = (π/2, -π/2) is at (l2, l1, 0).
    let arm = samples::planar_2r(1.0, 0.5);
    let mut data = KinematicsData::new(&arm);
    let tool = FrameId::find(&arm, "tool")?;
    forward_kinematics(&arm, &mut data, &[FRAC_PI_2, -FRAC_PI_2])?;
    update_frame_placements(&arm, &mut data)?;
    let p = data.world_from(tool)?.translation;
    assert!((p - DVec3::new(0.5, 1.0, 0.0)).length() < 1e-12, "{p}");
    let mut jacobian = vec![Motion::ZERO; arm.nv()];
    compute_frame_jacobian(
        &arm,
        &mut data,
        &configuration::neutral_configuration(&arm),
        tool,
        ReferenceFrame::LocalWorldAligned,
        &mut jacobian,
    )?;
    // Stretched along x: the first joint moves the tool along y at 1.5 m/s per rad/s.
    assert!((jacobian[0].linear - DVec3::new(0.0, 1.5, 0.0)).length() < 1e-12);

    // Dynamics: the pendulum held horizontal needs m·g·l = 9.81 N·m, and ABA inverts it.
    let pendulum = samples::pendulum();
    let mut dynamics = DynamicsData::new(&pendulum);
    let tau = rnea(&pendulum, &mut dynamics, &[FRAC_PI_2], &[0.0], &[0.0])?.to_vec();
    assert!((tau[0] - 9.81).abs() < 1e-12, "{tau:?}");
    let a = aba(&pendulum, &mut dynamics, &[FRAC_PI_2], &[0.0], &tau)?;
    assert!(a[0].abs() < 1e-12, "{a:?}");

    // Collision: the bob (radius 0.05 m at z = -1) and a 0.1 m ball at z = -2 are 0.85 m apart.
    let options = CollisionOptions::default();
    let cmodel = CollisionModel::from_model(&pendulum, &options)?;
    let mut cdata = CollisionData::new(&cmodel);
    let scene = ObstacleScene::from_json_str(
        r#"{"obstacles": [{"name": "ball", "geometry": {"type": "sphere", "radius": 0.1},
                           "xyz": [0, 0, -2]}]}"#,
    )?;
    scene.add_to(&mut cdata, &options)?;
    let mut kinematics = KinematicsData::new(&pendulum);
    cdata.compute_placements(&pendulum, &cmodel, &mut kinematics, &[0.0])?;
    let d = compute_world_distances(&cmodel, &mut cdata)?[0].distance;
    assert!((d - 0.85).abs() < 1e-9, "{d}");

    // Workspace: the arm reaches 1.5 m from its base.
    let set = sample_reachable(&arm, tool, &ReachableParams::grid(41))?;
    assert!((set.max_reach(DVec3::ZERO)? - 1.5).abs() < 1e-9);
    Ok(())
}
