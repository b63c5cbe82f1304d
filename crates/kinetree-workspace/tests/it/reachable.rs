//! Reachable-workspace sampling against closed forms: the planar 2R arm's annulus and
//! manipulability, UR5's reach from its shoulder, determinism across thread counts, exports and
//! input errors.

use crate::reference_dir;
use kinetree_test_support::assert_close;
use kinetree_workspace::kinematics::model::{Model, RootJoint, samples};
use kinetree_workspace::kinematics::spatial::{DQuat, DVec3};
use kinetree_workspace::kinematics::{FrameId, KinematicsError};
use kinetree_workspace::{
    CHUNK_SIZE, ReachableError, ReachableParams, ReachableSet, Sampling, TaskSpace,
    sample_reachable, sample_reachable_with_progress,
};
use std::f64::consts::PI;
use std::sync::Mutex;

const L1: f64 = 1.0;
const L2: f64 = 0.6;

fn planar(params: &ReachableParams) -> ReachableSet {
    let model = samples::planar_2r(L1, L2);
    let tool = FrameId::find(&model, "tool").unwrap();
    sample_reachable(&model, tool, params).unwrap()
}

fn radius(p: DVec3) -> f64 {
    p.truncate().length()
}

#[test]
fn planar_2r_samples_fill_its_annulus() {
    let (inner, outer) = ((L1 - L2).abs(), L1 + L2);
    for params in [
        ReachableParams::grid(181),
        ReachableParams::random(50_000, 3),
    ] {
        let set = planar(&params);
        let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
        for &p in set.positions() {
            let r = radius(p);
            assert!(r >= inner - 1e-12 && r <= outer + 1e-12, "r = {r}");
            assert!(p.z.abs() < 1e-12);
            lo = lo.min(r);
            hi = hi.max(r);
        }
        // The grid holds q2 = ±π and 0 exactly; random samples come close.
        let tol = match params.sampling {
            Sampling::Grid { .. } => 1e-9,
            Sampling::Random { .. } => 2e-3,
        };
        assert!(lo - inner < tol, "{params:?}: min radius {lo}");
        assert!(outer - hi < tol, "{params:?}: max radius {hi}");
        assert_close!(set.max_reach(DVec3::ZERO).unwrap(), hi, 1e-15);
        let b = set.bounds();
        assert!((b.max.x - outer).abs() < tol && (b.min.y + outer).abs() < tol);
    }
}

#[test]
fn planar_2r_voxels_answer_from_the_annulus_not_the_box() {
    let set = planar(&ReachableParams::grid(301));
    let voxels = set.voxelize(0.05).unwrap();
    // Every sample's own voxel was hit.
    assert!(set.positions().iter().all(|&p| voxels.is_reachable(p)));
    for k in 0..72 {
        let a = f64::from(k) * PI / 36.0;
        let dir = DVec3::new(a.cos(), a.sin(), 0.0);
        // Well inside the annulus (a voxel's diagonal from its edges): reached.
        for r in [0.55, 0.8, 1.0, 1.25, 1.5] {
            assert!(voxels.is_reachable(r * dir), "r = {r}, angle {a}");
        }
        // The hole in the middle and the outside, though inside the bounding box: not reached.
        for r in [0.0, 0.1, 0.25, 0.3] {
            assert!(!voxels.is_reachable(r * dir), "r = {r}, angle {a}");
            assert!(set.bounds().contains(r * dir));
        }
        for r in [1.7, 2.0, 3.0] {
            assert!(!voxels.is_reachable(r * dir), "r = {r}, angle {a}");
        }
    }
    assert!(
        !voxels.is_reachable(DVec3::new(1.0, 0.0, 0.2)),
        "off the plane"
    );
    assert!(!voxels.is_reachable(DVec3::NAN));
    // The voxel area approaches the annulus area π(r_o² - r_i²) from above (boundary voxels).
    let area = voxels.len() as f64 * 0.05 * 0.05;
    let annulus = PI * ((L1 + L2).powi(2) - (L1 - L2).powi(2));
    assert!(
        area > annulus && area < 1.25 * annulus,
        "{area} vs {annulus}"
    );
    let stats = voxels.stats_at(DVec3::new(1.0, 0.0, 0.0)).unwrap();
    assert!(stats.count > 0 && stats.max_manipulability >= stats.mean_manipulability);
}

#[test]
fn planar_2r_manipulability_is_l1_l2_sin_q2() {
    // Position task: sqrt(det(Jᵀ·J)) of the 3 x 2 Jacobian equals |det| of the planar 2 x 2 one.
    let k = 61;
    let set = planar(&ReachableParams::grid(k));
    let q = |d: usize| -PI + 2.0 * PI * d as f64 / (k - 1) as f64;
    for (i, &w) in set.manipulability().iter().enumerate() {
        let (q1, q2) = (q(i / k), q(i % k));
        let expected = L1 * L2 * q2.sin().abs();
        assert!(
            (w - expected).abs() < 1e-12,
            "sample {i}: {w} vs {expected}"
        );
        // The grid order is row-major, the first joint slowest.
        let p = set.positions()[i];
        let fk = DVec3::new(
            L1 * q1.cos() + L2 * (q1 + q2).cos(),
            L1 * q1.sin() + L2 * (q1 + q2).sin(),
            0.0,
        );
        assert!(p.distance(fk) < 1e-12);
    }
    // Random samples: the same law, through cos q2 = (r² - l1² - l2²) / (2 l1 l2).
    let set = planar(&ReachableParams::random(10_000, 11));
    for (&p, &w) in set.positions().iter().zip(set.manipulability()) {
        let c = ((p.length_squared() - L1 * L1 - L2 * L2) / (2.0 * L1 * L2)).clamp(-1.0, 1.0);
        let expected = L1 * L2 * (1.0 - c * c).sqrt();
        assert_close!(w, expected, 1e-6, 0.0, "{w} vs {expected}");
    }
}

#[test]
fn planar_2r_pose_task_keeps_orientations_and_uses_six_rows() {
    let k = 13;
    let set = planar(&ReachableParams::grid(k).with_task(TaskSpace::Pose));
    let orientations = set.orientations().unwrap();
    assert_eq!(orientations.len(), set.len());
    let q = |d: usize| -PI + 2.0 * PI * d as f64 / (k - 1) as f64;
    for i in 0..set.len() {
        let (q1, q2) = (q(i / k), q(i % k));
        let expected = DQuat::from_rotation_z(q1 + q2);
        assert!(orientations[i].dot(expected).abs() > 1.0 - 1e-12);
        // Columns [linear; angular]: (-y, x, 0; 0, 0, 1) and (-(y - l1 s1), x - l1 c1, 0; 0, 0, 1).
        let p = set.positions()[i];
        let e = DVec3::new(L1 * q1.cos(), L1 * q1.sin(), 0.0);
        let (c1, c2) = (
            DVec3::new(-p.y, p.x, 0.0),
            DVec3::new(-(p.y - e.y), p.x - e.x, 0.0),
        );
        let (a, b, c) = (c1.dot(c1) + 1.0, c1.dot(c2) + 1.0, c2.dot(c2) + 1.0);
        let expected = (a * c - b * b).max(0.0).sqrt();
        let w = set.manipulability()[i];
        assert_close!(w, expected, 1e-9, 0.0, "{w} vs {expected}");
    }
    assert!(planar(&ReachableParams::grid(3)).orientations().is_none());
}

fn ur5() -> Model {
    Model::from_urdf_file(reference_dir().join("urdf/ur5.urdf"), RootJoint::Fixed).unwrap()
}

fn joint_offset(model: &Model, name: &str) -> DVec3 {
    model
        .joint(model.joint_index(name).unwrap())
        .placement
        .translation
}

#[test]
fn ur5_tool0_reach_from_the_shoulder_matches_its_link_lengths() {
    let model = ur5();
    // Link lengths from the URDF (UR's DH names): d1 shoulder height, a2 upper arm, a3 forearm,
    // d4 the sum of the lateral offsets, d5 and d6 the wrist offsets.
    let d1 = joint_offset(&model, "shoulder_pan_joint").z;
    let (lift, elbow) = (
        joint_offset(&model, "shoulder_lift_joint"),
        joint_offset(&model, "elbow_joint"),
    );
    let a2 = elbow.z;
    let a3 = joint_offset(&model, "wrist_1_joint").z;
    let d4 = lift.y + elbow.y + joint_offset(&model, "wrist_2_joint").y;
    let d5 = joint_offset(&model, "wrist_3_joint").z;
    let d6 = joint_offset(&model, "wrist_3_link-tool0_fixed_joint").y;
    assert!((a2 - 0.425).abs() < 1e-9 && (a3 - 0.39225).abs() < 1e-9);
    // The lift, elbow and wrist-1 axes are parallel: tool0 is d4 + d6·cos θ5 across the arm's
    // plane and at most a2 + a3 + |(d5, d6·sin θ5)| within it, from the point of the base axis at
    // shoulder height. Maximise over θ5.
    let analytic = (0..=100_000)
        .map(|i| {
            let t = PI * f64::from(i) / 100_000.0;
            let across = d4 + d6 * t.cos();
            let within = a2 + a3 + (d5 * d5 + (d6 * t.sin()).powi(2)).sqrt();
            across.hypot(within)
        })
        .fold(0.0, f64::max);
    assert_close!(analytic, 0.949, 1e-3, 0.0, "{analytic}");
    let shoulder = DVec3::new(0.0, 0.0, d1);
    let tool0 = FrameId::find(&model, "tool0").unwrap();
    let set = sample_reachable(&model, tool0, &ReachableParams::random(200_000, 1)).unwrap();
    let reach = set.max_reach(shoulder).unwrap();
    assert!(reach <= analytic + 1e-9, "{reach} > {analytic}");
    assert!(reach > 0.98 * analytic, "{reach} vs {analytic}");
    assert_eq!(set.joints().len(), 6);
}

fn bits(set: &ReachableSet) -> Vec<u64> {
    set.positions()
        .iter()
        .flat_map(|p| p.to_array())
        .chain(set.manipulability().iter().copied())
        .map(f64::to_bits)
        .collect()
}

fn on_threads(threads: usize, f: impl FnOnce() -> ReachableSet + Send) -> ReachableSet {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let model = samples::six_axis();
    let tool = FrameId::find(&model, "tool").unwrap();
    for params in [
        ReachableParams::random(3 * CHUNK_SIZE + 17, 42).with_task(TaskSpace::Pose),
        ReachableParams::grid(5),
    ] {
        let run = || sample_reachable(&model, tool, &params).unwrap();
        let one = on_threads(1, run);
        let two = on_threads(2, run);
        assert_eq!(bits(&one), bits(&two), "{params:?}");
        assert_eq!(one.orientations(), two.orientations());
        assert_eq!(one.bounds(), two.bounds());
    }
    let a = sample_reachable(&model, tool, &ReachableParams::random(100, 1)).unwrap();
    let b = sample_reachable(&model, tool, &ReachableParams::random(100, 2)).unwrap();
    assert_ne!(bits(&a), bits(&b), "another seed gives other samples");
}

#[test]
fn progress_reaches_the_total() {
    let model = samples::six_axis();
    let tool = FrameId::find(&model, "tool").unwrap();
    let n = 2 * CHUNK_SIZE + 5;
    let calls = Mutex::new(Vec::new());
    let report = |done: usize, total: usize| calls.lock().unwrap().push((done, total));
    let set = sample_reachable_with_progress(&model, tool, &ReachableParams::random(n, 0), &report)
        .unwrap();
    let mut calls = calls.into_inner().unwrap();
    calls.sort_unstable();
    assert_eq!(calls.len(), 3);
    assert!(calls.iter().all(|&(_, total)| total == n));
    assert_eq!(calls.last().unwrap().0, set.len());
}

#[test]
fn a_floating_base_is_held_at_q0() {
    let path = reference_dir().join("../robots/panda.urdf");
    let fixed = Model::from_urdf_file(&path, RootJoint::Fixed).unwrap();
    let floating = Model::from_urdf_file(&path, RootJoint::Floating).unwrap();
    // A grid: random draws also advance the generator over held joints, so they differ.
    let params = ReachableParams::grid(3);
    let run = |m: &Model| {
        sample_reachable(m, FrameId::find(m, "panda_hand_tcp").unwrap(), &params).unwrap()
    };
    let (a, b) = (run(&fixed), run(&floating));
    assert_eq!(a.joints(), b.joints());
    assert_eq!(a.joints().len(), 7, "{:?}", a.joints());
    assert!(a.bounds().min.distance(b.bounds().min) < 1e-12);
    assert!(a.bounds().max.distance(b.bounds().max) < 1e-12);
    // Raising the base raises the cloud.
    let mut q0 = kinetree_workspace::kinematics::configuration::neutral_configuration(&floating);
    q0[2] = 1.0;
    let lifted = sample_reachable(
        &floating,
        FrameId::find(&floating, "panda_hand_tcp").unwrap(),
        &params.clone().with_q0(q0),
    )
    .unwrap();
    assert!((lifted.bounds().max.z - b.bounds().max.z - 1.0).abs() < 1e-12);
}

#[test]
fn exports_hold_every_sample() {
    let set = planar(&ReachableParams::random(100, 9));
    let mut csv = Vec::new();
    set.write_csv(&mut csv).unwrap();
    let csv = String::from_utf8(csv).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("x,y,z,manipulability"));
    let first: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_close!(first[0], set.positions()[0].x, 1e-15);
    assert_close!(first[3], set.manipulability()[0], 1e-15);
    assert_eq!(csv.lines().count(), 101);

    let mut ply = Vec::new();
    set.write_ply(&mut ply).unwrap();
    let ply = String::from_utf8(ply).unwrap();
    assert!(ply.starts_with("ply\nformat ascii 1.0\n"));
    assert!(ply.contains("element vertex 100\n"));
    assert!(ply.contains("property double manipulability\n"));
    let body = ply.split("end_header\n").nth(1).unwrap();
    assert_eq!(body.lines().count(), 100);
    assert!(body.lines().all(|l| l.split(' ').count() == 4));

    let mut json = Vec::new();
    set.write_json(&mut json).unwrap();
    let v: serde_json::Value = serde_json::from_slice(&json).unwrap();
    assert_eq!(v["frame"], "tool");
    assert_eq!(v["task"], "position");
    assert_eq!(v["count"], 100);
    assert_eq!(v["sampling"]["seed"], 9);
    assert_eq!(v["joints"], serde_json::json!(["joint1", "joint2"]));
    let samples = v["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 100);
    let y = samples[7][1].as_f64().unwrap();
    assert_close!(y, set.positions()[7].y, 1e-15);
    let max_x = v["bounds"]["max"][0].as_f64().unwrap();
    assert_close!(max_x, set.bounds().max.x, 1e-15);

    let pose = planar(&ReachableParams::random(10, 9).with_task(TaskSpace::Pose));
    let mut json = Vec::new();
    pose.write_json(&mut json).unwrap();
    let v: serde_json::Value = serde_json::from_slice(&json).unwrap();
    assert_eq!(v["samples"][0].as_array().unwrap().len(), 8);

    let voxels = set.voxelize(0.1).unwrap();
    let mut csv = Vec::new();
    voxels.write_csv(&mut csv).unwrap();
    assert_eq!(
        String::from_utf8(csv).unwrap().lines().count(),
        voxels.len() + 1
    );
}

#[test]
fn bad_inputs_are_typed_errors() {
    let model = samples::planar_2r(L1, L2);
    let tool = FrameId::find(&model, "tool").unwrap();
    let err = |params: ReachableParams| sample_reachable(&model, tool, &params).unwrap_err();
    assert!(matches!(
        err(ReachableParams::random(0, 0)),
        ReachableError::NoSamples { what: "samples" }
    ));
    assert!(matches!(
        err(ReachableParams::grid(0)),
        ReachableError::NoSamples { .. }
    ));
    assert!(matches!(
        err(ReachableParams::grid(1 << 20)),
        ReachableError::TooManySamples { .. }
    ));
    assert!(matches!(
        err(ReachableParams::random(10, 0).with_q0(vec![0.0; 3])),
        ReachableError::Kinematics(KinematicsError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        err(ReachableParams::grid(3).with_q0(vec![0.0, f64::NAN])),
        ReachableError::Kinematics(KinematicsError::NonFinite { .. })
    ));
    assert!(matches!(
        sample_reachable(&model, FrameId::Link(99), &ReachableParams::grid(3)),
        Err(ReachableError::Kinematics(
            KinematicsError::FrameOutOfRange {
                what: "link",
                index: 99,
                ..
            }
        ))
    ));
    assert!(matches!(
        FrameId::find(&model, "nope"),
        Err(KinematicsError::UnknownFrame { .. })
    ));
    let set = planar(&ReachableParams::grid(3));
    for size in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            set.voxelize(size),
            Err(ReachableError::InvalidVoxelSize { .. })
        ));
    }
    assert!(matches!(
        set.voxelize(1e-300),
        Err(ReachableError::VoxelSizeOutOfRange { .. })
    ));
    assert!(matches!(
        set.voxelize(1e-90),
        Err(ReachableError::VoxelTooSmall { .. })
    ));
    // A size whose volume overflows (`inf m³` before), and the largest that does not.
    for size in [1e308, 1e103] {
        assert!(matches!(
            set.voxelize(size),
            Err(ReachableError::VoxelSizeOutOfRange { .. })
        ));
    }
    let huge = set.voxelize(1e100).unwrap();
    assert!(huge.volume().is_finite() && huge.volume() > 0.0);
    assert!(matches!(
        set.max_reach(DVec3::new(f64::NAN, 0.0, 0.0)),
        Err(ReachableError::NonFinite { what: "base" })
    ));
}

#[test]
fn a_coupled_mimic_follower_is_moved_by_its_leader() {
    use kinetree_workspace::kinematics::model::{LoadOptions, MimicMode};
    let path = reference_dir().join("../robots/panda.urdf");
    let options = LoadOptions {
        mimic: MimicMode::Coupled,
        ..LoadOptions::from(RootJoint::Fixed)
    };
    let panda = Model::from_urdf_file_with(&path, &options).unwrap();
    let independent = Model::from_urdf_file(&path, RootJoint::Fixed).unwrap();
    let params = ReachableParams::grid(2);
    // The right finger follows the left one: sampling it samples panda_finger_joint1.
    let run = |m: &Model| {
        sample_reachable(m, FrameId::find(m, "panda_rightfinger").unwrap(), &params).unwrap()
    };
    let (coupled, free) = (run(&panda), run(&independent));
    assert_eq!(coupled.joints().len(), 8, "{:?}", coupled.joints());
    assert_eq!(coupled.joints()[7], "panda_finger_joint1");
    assert_eq!(free.joints()[7], "panda_finger_joint2");
    // Same multiplier 1 and offset 0: the same clouds (the fingers' ranges are equal).
    assert!(coupled.bounds().min.distance(free.bounds().min) < 1e-12);
    assert!(coupled.bounds().max.distance(free.bounds().max) < 1e-12);
    let (a, b) = (coupled.manipulability(), free.manipulability());
    assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12));
}
