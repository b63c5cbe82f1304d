//! Inverse kinematics: the reference targets of the three arms, limits on every iterate, the
//! position-only / orientation-only / per-axis modes, several targets on floating-base robots,
//! every joint kind, the posture objective, determinism, typed errors, the analytic two-link arm,
//! and no allocation per solve.

use crate::common::reference_dir;
use glam::{DMat3, DVec3};
use kinetree_kinematics::configuration::{
    self, Space, is_within_limits, neutral_configuration, random_configuration, set_joint_q,
    set_named,
};
use kinetree_kinematics::ik::{
    IkParams, IkReport, IkSolver, IkStatus, IkTarget, PlanarTwoLink, TwoLinkSeeder,
};
use kinetree_kinematics::model::{
    JointKind, JointLimits, JointSpec, Link, Model, ModelBuilder, RootJoint, samples,
};
use kinetree_kinematics::spatial::Se3;
use kinetree_kinematics::spatial::rotation::log3;
use kinetree_kinematics::{
    FrameId, KinematicsData, KinematicsError, forward_kinematics, update_frame_placements,
};
use rand::SeedableRng;
use rand::rngs::SmallRng;
use serde_json::Value;
use std::sync::{Arc, Mutex};

/// Deterministic parameters: no time budget (the budget is for the release report).
pub(crate) fn params() -> IkParams {
    IkParams {
        time_budget: None,
        ..IkParams::default()
    }
}

fn load(robot: &str) -> (Model, Value) {
    let v: Value = serde_json::from_str(
        &std::fs::read_to_string(reference_dir().join(format!("{robot}.json"))).unwrap(),
    )
    .unwrap();
    let root = if v["root_joint"] == "fixed" {
        RootJoint::Fixed
    } else {
        RootJoint::Floating
    };
    let model =
        Model::from_urdf_file(reference_dir().join(v["urdf"].as_str().unwrap()), root).unwrap();
    (model, v)
}

fn pose_of(target: &Value) -> Se3 {
    let r = |i: usize, j: usize| target["rotation"][i][j].as_f64().unwrap();
    let t = |i: usize| target["translation"][i].as_f64().unwrap();
    Se3::new(
        DMat3::from_cols(
            DVec3::new(r(0, 0), r(1, 0), r(2, 0)),
            DVec3::new(r(0, 1), r(1, 1), r(2, 1)),
            DVec3::new(r(0, 2), r(1, 2), r(2, 2)),
        ),
        DVec3::new(t(0), t(1), t(2)),
    )
}

/// Position and orientation errors of `frame` at `q` against `goal`, by a fresh forward
/// kinematics (not the solver's own numbers).
pub(crate) fn errors(model: &Model, frame: FrameId, q: &[f64], goal: &Se3) -> (f64, f64) {
    let mut data = KinematicsData::new(model);
    forward_kinematics(model, &mut data, q).unwrap();
    update_frame_placements(model, &mut data).unwrap();
    let x = data.world_from(frame).unwrap();
    (
        (x.translation - goal.translation).length(),
        log3(&(goal.rotation.transpose() * x.rotation)).length(),
    )
}

pub(crate) fn pose_at(model: &Model, frame: FrameId, q: &[f64]) -> Se3 {
    let mut data = KinematicsData::new(model);
    forward_kinematics(model, &mut data, q).unwrap();
    update_frame_placements(model, &mut data).unwrap();
    *data.world_from(frame).unwrap()
}

#[test]
fn reference_targets_converge_on_every_arm() {
    for robot in ["panda", "ur5", "kinova"] {
        let (model, v) = load(robot);
        let ik = &v["ik_targets"];
        let ee = FrameId::find(&model, ik["ee_link"].as_str().unwrap()).unwrap();
        let mut solver = IkSolver::new(&model, params());
        let mut data = KinematicsData::new(&model);
        let mut rng = SmallRng::seed_from_u64(3);
        let neutral = neutral_configuration(&model);
        let mut random = neutral.clone();
        for (i, t) in ik["targets"].as_array().unwrap().iter().enumerate() {
            let goal = pose_of(t);
            // The solution given in the file reproduces the target with our forward kinematics.
            let mut q_ref = neutral.clone();
            let named = t["q_by_joint"].as_object().unwrap();
            let values = named.iter().map(|(n, x)| (n, [x.as_f64().unwrap()]));
            set_named(&model, Space::Configuration, &mut q_ref, values).unwrap();
            let (p, o) = errors(&model, ee, &q_ref, &goal);
            assert!(
                p < 1e-9 && o < 1e-9,
                "{robot} target {i}: reference q gives {p}, {o}"
            );
            random_configuration(&model, &mut rng, &mut random).unwrap();
            for q0 in [&neutral, &random] {
                let report = solver
                    .solve(&model, &mut data, &IkTarget::new(ee, goal), q0)
                    .unwrap();
                assert_eq!(report.status, IkStatus::Converged, "{robot} target {i}");
                let (p, o) = errors(&model, ee, report.q, &goal);
                assert!(p < 1e-6 && o < 1e-5, "{robot} target {i}: {p} m, {o} rad");
                assert!((p - report.position_error).abs() < 1e-12);
                assert!(is_within_limits(&model, report.q, 0.0).unwrap());
                // Joints off the path (panda's fingers) keep their start value.
                if robot == "panda" {
                    assert_eq!(&report.q[7..], &q0[7..]);
                }
                // `data` holds the solution's forward kinematics.
                let x = data.world_from(ee).unwrap();
                assert!((x.translation - goal.translation).length() < 1e-6);
            }
        }
    }
}

#[test]
fn every_iterate_respects_the_limits() {
    for robot in ["panda", "kinova"] {
        let (model, v) = load(robot);
        let ee = FrameId::find(&model, v["ik_targets"]["ee_link"].as_str().unwrap()).unwrap();
        let iterates = Arc::new(Mutex::new(Vec::<Vec<f64>>::new()));
        let mut solver = IkSolver::new(&model, params());
        let sink = Arc::clone(&iterates);
        solver.set_observer(move |it| sink.lock().unwrap().push(it.q.to_vec()));
        let mut data = KinematicsData::new(&model);
        let mut rng = SmallRng::seed_from_u64(11);
        let mut q = neutral_configuration(&model);
        let mut converged = 0;
        for _ in 0..40 {
            random_configuration(&model, &mut rng, &mut q).unwrap();
            let goal = pose_at(&model, ee, &q);
            random_configuration(&model, &mut rng, &mut q).unwrap();
            let report = solver
                .solve(&model, &mut data, &IkTarget::new(ee, goal), &q)
                .unwrap();
            converged += usize::from(report.is_converged());
        }
        assert_eq!(converged, 40, "{robot}");
        let iterates = iterates.lock().unwrap();
        assert!(
            iterates.len() > 400,
            "{robot}: only {} iterates",
            iterates.len()
        );
        for q in iterates.iter() {
            assert!(is_within_limits(&model, q, 0.0).unwrap(), "{robot}: {q:?}");
        }
    }
}

#[test]
fn a_start_outside_the_limits_is_clamped() {
    let (model, _) = load("panda");
    let ee = FrameId::find(&model, "panda_hand_tcp").unwrap();
    let goal = pose_at(&model, ee, &[0.1, 0.2, -0.3, -1.5, 0.4, 1.2, 0.3, 0.0, 0.0]);
    let mut q0 = neutral_configuration(&model);
    q0[1] = 5.0; // panda_joint2 is limited to ±1.7628
    q0[3] = 0.5; // panda_joint4 to [-3.0718, -0.0698]
    let mut solver = IkSolver::new(&model, params());
    let iterates = Arc::new(Mutex::new(Vec::<Vec<f64>>::new()));
    let sink = Arc::clone(&iterates);
    solver.set_observer(move |it| sink.lock().unwrap().push(it.q.to_vec()));
    let mut data = KinematicsData::new(&model);
    let report = solver
        .solve(&model, &mut data, &IkTarget::new(ee, goal), &q0)
        .unwrap();
    assert!(report.is_converged());
    let iterates = iterates.lock().unwrap();
    assert!((iterates[0][1] - 1.7628).abs() < 1e-12);
    assert!(
        iterates
            .iter()
            .all(|q| is_within_limits(&model, q, 0.0).unwrap())
    );
}

#[test]
fn position_only_orientation_only_and_axis_weights() {
    let (model, _) = load("ur5");
    let ee = FrameId::find(&model, "tool0").unwrap();
    let mut solver = IkSolver::new(&model, params());
    let mut data = KinematicsData::new(&model);
    let mut rng = SmallRng::seed_from_u64(5);
    let mut q = neutral_configuration(&model);
    for _ in 0..10 {
        random_configuration(&model, &mut rng, &mut q).unwrap();
        let goal = pose_at(&model, ee, &q);
        let q0 = neutral_configuration(&model);

        let report = solver
            .solve(
                &model,
                &mut data,
                &IkTarget::position(ee, goal.translation),
                &q0,
            )
            .unwrap();
        assert!(report.is_converged());
        assert_eq!(report.orientation_error, 0.0);
        let x = pose_at(&model, ee, report.q);
        assert!((x.translation - goal.translation).length() < 1e-6);

        let report = solver
            .solve(
                &model,
                &mut data,
                &IkTarget::orientation(ee, goal.rotation),
                &q0,
            )
            .unwrap();
        assert!(report.is_converged());
        assert_eq!(report.position_error, 0.0);
        let (_, o) = errors(&model, ee, report.q, &goal);
        assert!(o < 1e-5);

        // The tool may spin about the target's z axis: position and the z axis are reached.
        let spin = IkTarget::new(ee, goal).with_axis_weights([1.0, 1.0, 1.0, 1.0, 1.0, 0.0]);
        let report = solver.solve(&model, &mut data, &spin, &q0).unwrap();
        assert!(report.is_converged());
        let x = pose_at(&model, ee, report.q);
        assert!((x.translation - goal.translation).length() < 1e-6);
        assert!((x.rotation.z_axis - goal.rotation.z_axis).length() < 1e-5);
    }
}

#[test]
fn two_feet_and_a_hand_on_talos_and_two_feet_on_solo12() {
    // Talos: both soles (full pose) and the left gripper (position, half weight), floating base.
    let (model, _) = load("talos_reduced");
    let frames = [
        "left_sole_link",
        "right_sole_link",
        "gripper_left_base_link",
    ]
    .map(|n| FrameId::find(&model, n).unwrap());
    let mut rng = SmallRng::seed_from_u64(21);
    let mut solver = IkSolver::new(&model, params());
    let mut data = KinematicsData::new(&model);
    for _ in 0..5 {
        let mut q_goal = neutral_configuration(&model);
        random_configuration(&model, &mut rng, &mut q_goal).unwrap();
        let goals = frames.map(|f| pose_at(&model, f, &q_goal));
        let targets = [
            IkTarget::new(frames[0], goals[0]),
            IkTarget::new(frames[1], goals[1]),
            IkTarget::position(frames[2], goals[2].translation).with_weight(0.5),
        ];
        let q0 = neutral_configuration(&model);
        let report = solver
            .solve_targets(&model, &mut data, &targets, &q0)
            .unwrap();
        assert!(report.is_converged(), "{:?}", report.status);
        for (k, f) in frames.iter().enumerate() {
            let (p, o) = errors(&model, *f, report.q, &goals[k]);
            assert!(p < 1e-6, "frame {k}: {p}");
            if k < 2 {
                assert!(o < 1e-5, "frame {k}: {o}");
            }
        }
        let quat = &report.q[3..7];
        assert!((quat.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12);
        assert!(is_within_limits(&model, report.q, 0.0).unwrap());
    }

    // Solo12: two feet at their positions; the base moves, the other legs stay.
    let (model, _) = load("solo12");
    let feet = ["FL_FOOT", "HR_FOOT"].map(|n| FrameId::find(&model, n).unwrap());
    let mut solver = IkSolver::new(&model, params());
    let mut data = KinematicsData::new(&model);
    let mut q_goal = neutral_configuration(&model);
    random_configuration(&model, &mut rng, &mut q_goal).unwrap();
    let goals = feet.map(|f| pose_at(&model, f, &q_goal));
    let targets = feet.map(|f| IkTarget::position(f, pose_at(&model, f, &q_goal).translation));
    let q0 = neutral_configuration(&model);
    let report = solver
        .solve_targets(&model, &mut data, &targets, &q0)
        .unwrap();
    assert!(report.is_converged());
    for (f, g) in feet.iter().zip(&goals) {
        assert!((pose_at(&model, *f, report.q).translation - g.translation).length() < 1e-6);
    }
    let fr = model.joint_q_range(model.joint_index("FR_HAA").unwrap());
    assert_eq!(report.q[fr.clone()], q0[fr]);
}

/// A chain with every joint kind (and a floating joint in the middle).
fn every_kind(with_floating: bool) -> Model {
    let mut b = ModelBuilder::new("kinds");
    b.add_link(Link::new("l0"));
    let mut kinds = vec![
        JointKind::Planar,
        JointKind::Revolute,
        JointKind::Continuous,
        JointKind::Prismatic,
        JointKind::Cylindrical,
        JointKind::Spherical,
    ];
    if with_floating {
        kinds.insert(3, JointKind::Floating);
    }
    for (i, k) in kinds.iter().enumerate() {
        b.add_link(Link::new(format!("l{}", i + 1)));
        b.add_joint(
            JointSpec::new(
                format!("j{}", i + 1),
                *k,
                format!("l{i}"),
                format!("l{}", i + 1),
            )
            .with_axis(DVec3::new(0.3, -0.5, 0.8))
            .with_limits(JointLimits::position(-2.0, 2.5))
            .with_placement(Se3::from_xyz_rpy([0.3, 0.2, 0.1], [0.3, 0.2, 0.1])),
        );
    }
    b.build().unwrap()
}

#[test]
fn every_joint_kind_and_a_floating_joint_mid_chain() {
    for with_floating in [false, true] {
        let model = every_kind(with_floating);
        let tip = FrameId::find(&model, if with_floating { "l7" } else { "l6" }).unwrap();
        let mut solver = IkSolver::new(&model, params());
        let mut data = KinematicsData::new(&model);
        let mut rng = SmallRng::seed_from_u64(9);
        let mut q = neutral_configuration(&model);
        for _ in 0..10 {
            random_configuration(&model, &mut rng, &mut q).unwrap();
            let goal = pose_at(&model, tip, &q);
            random_configuration(&model, &mut rng, &mut q).unwrap();
            let report = solver
                .solve(&model, &mut data, &IkTarget::new(tip, goal), &q)
                .unwrap();
            assert!(report.is_converged(), "{:?}", report.status);
            let (p, o) = errors(&model, tip, report.q, &goal);
            assert!(p < 1e-6 && o < 1e-5);
            assert!(is_within_limits(&model, report.q, 0.0).unwrap());
            // Quaternions stay unit: normalising changes nothing.
            let mut n = report.q.to_vec();
            configuration::normalize(&model, &mut n).unwrap();
            assert!(n.iter().zip(report.q).all(|(a, b)| (a - b).abs() < 1e-12));
        }
    }
}

#[test]
fn posture_picks_a_nearby_solution_and_moving_joints_can_be_chosen() {
    let (model, _) = load("panda");
    let ee = FrameId::find(&model, "panda_hand_tcp").unwrap();
    let mut data = KinematicsData::new(&model);
    let mut rng = SmallRng::seed_from_u64(17);
    let posture = [0.0, -0.3, 0.0, -2.0, 0.0, 1.8, 0.8, 0.0, 0.0];
    let mut plain = IkSolver::new(&model, params());
    let mut with_posture = IkSolver::new(&model, params());
    with_posture.set_posture(&model, &posture, 0.2).unwrap();
    let (mut d_plain, mut d_posture) = (0.0, 0.0);
    let mut q = neutral_configuration(&model);
    for _ in 0..20 {
        random_configuration(&model, &mut rng, &mut q).unwrap();
        let goal = pose_at(&model, ee, &q);
        let target = IkTarget::new(ee, goal);
        let a = plain.solve(&model, &mut data, &target, &posture).unwrap();
        assert!(a.is_converged());
        d_plain += configuration::distance(&model, a.q, &posture).unwrap();
        let b = with_posture
            .solve(&model, &mut data, &target, &posture)
            .unwrap();
        assert!(b.is_converged());
        d_posture += configuration::distance(&model, b.q, &posture).unwrap();
    }
    assert!(d_posture < d_plain, "{d_posture} vs {d_plain}");

    // Only joints 1..6 move: joint 7 keeps its start value; a position target is still met.
    let mut solver = IkSolver::new(&model, params());
    let names: Vec<String> = (1..=6).map(|i| format!("panda_joint{i}")).collect();
    solver.set_moving_joints(&model, &names).unwrap();
    let goal = pose_at(&model, ee, &[0.3, 0.1, -0.2, -1.8, 0.2, 1.5, 0.4, 0.0, 0.0]);
    let q0 = neutral_configuration(&model);
    let report = solver
        .solve(
            &model,
            &mut data,
            &IkTarget::position(ee, goal.translation),
            &q0,
        )
        .unwrap();
    assert!(report.is_converged());
    assert_eq!(report.q[6], q0[6]);
    assert!(matches!(
        solver.set_moving_joints(&model, &["nope"]),
        Err(KinematicsError::UnknownJoint { .. })
    ));
    solver.move_all_joints();
}

#[test]
fn solves_are_deterministic_and_budgets_are_reported() {
    let (model, _) = load("ur5");
    let ee = FrameId::find(&model, "tool0").unwrap();
    let goal = pose_at(&model, ee, &[0.4, -1.2, 1.6, -0.3, 1.1, 0.2]);
    let q0 = neutral_configuration(&model);
    let mut data = KinematicsData::new(&model);
    let mut a = IkSolver::new(&model, params());
    let mut b = IkSolver::new(&model, params());
    let ra = a
        .solve(&model, &mut data, &IkTarget::new(ee, goal), &q0)
        .unwrap();
    let (qa, ia) = (ra.q.to_vec(), ra.iterations);
    let rb = b
        .solve(&model, &mut data, &IkTarget::new(ee, goal), &q0)
        .unwrap();
    assert_eq!((rb.q.to_vec(), rb.iterations), (qa.clone(), ia));
    // Solving again with the same solver gives the same answer (the generator is reseeded).
    let rc = a
        .solve(&model, &mut data, &IkTarget::new(ee, goal), &q0)
        .unwrap();
    assert_eq!(rc.q, &qa[..]);

    // An unreachable target: best effort, within limits, with its residual.
    let far = Se3::from_translation(DVec3::new(3.0, 0.0, 0.5));
    let mut solver = IkSolver::new(
        &model,
        IkParams {
            max_iterations: 300,
            ..params()
        },
    );
    let report = solver
        .solve(
            &model,
            &mut data,
            &IkTarget::position(ee, far.translation),
            &q0,
        )
        .unwrap();
    assert_eq!(report.iterations, 300);
    assert!(report.restarts > 0);
    match report.status {
        IkStatus::BestEffort { residual } => {
            assert!(residual > 1.0 && (residual - report.position_error).abs() < 1e-12);
        }
        other => panic!("expected best effort, got {other:?}"),
    }
    assert!(is_within_limits(&model, report.q, 0.0).unwrap());

    // No budget at all: failed, and q is the start.
    let mut none = IkSolver::new(
        &model,
        IkParams {
            max_iterations: 0,
            ..params()
        },
    );
    let report = none
        .solve(&model, &mut data, &IkTarget::new(ee, goal), &q0)
        .unwrap();
    assert_eq!(report.status, IkStatus::Failed);
    assert_eq!(report.q, &q0[..]);
}

#[test]
fn bad_inputs_are_typed_errors() {
    let (model, _) = load("ur5");
    let ee = FrameId::find(&model, "tool0").unwrap();
    let mut solver = IkSolver::new(&model, params());
    let mut data = KinematicsData::new(&model);
    let q0 = neutral_configuration(&model);
    let good = IkTarget::new(ee, Se3::from_translation(DVec3::new(0.3, 0.2, 0.4)));

    assert!(matches!(
        FrameId::find(&model, "no_such_link"),
        Err(KinematicsError::UnknownFrame { .. })
    ));
    let unknown = IkTarget::new(FrameId::Link(10_000), good.pose);
    assert!(matches!(
        solver.solve(&model, &mut data, &unknown, &q0),
        Err(KinematicsError::FrameOutOfRange { index: 10_000, .. })
    ));
    let nan = IkTarget::position(ee, DVec3::new(f64::NAN, 0.0, 0.0));
    assert!(matches!(
        solver.solve(&model, &mut data, &nan, &q0),
        Err(KinematicsError::NonFinite { .. })
    ));
    assert!(matches!(
        solver.solve(&model, &mut data, &good, &q0[..5]),
        Err(KinematicsError::DimensionMismatch { what: "q0", .. })
    ));
    let mut q_nan = q0.clone();
    q_nan[2] = f64::NAN;
    assert!(matches!(
        solver.solve(&model, &mut data, &good, &q_nan),
        Err(KinematicsError::NonFinite { what: "q0", .. })
    ));
    let skewed = IkTarget::new(
        ee,
        Se3::new(DMat3::from_diagonal(DVec3::new(1.0, 2.0, 1.0)), DVec3::ZERO),
    );
    assert!(matches!(
        solver.solve(&model, &mut data, &skewed, &q0),
        Err(KinematicsError::InvalidTarget { .. })
    ));
    for weights in [[0.0; 6], [1.0, 1.0, 1.0, -1.0, 1.0, 1.0]] {
        assert!(matches!(
            solver.solve(&model, &mut data, &good.with_axis_weights(weights), &q0),
            Err(KinematicsError::InvalidTarget { .. })
        ));
    }
    assert!(matches!(
        solver.solve_targets(&model, &mut data, &[], &q0),
        Err(KinematicsError::InvalidTarget { .. })
    ));
    // Finite but absurd: squared residuals would overflow and the report's errors be inf or
    // NaN (the viewer's fuzzing found a position-only target at (1e308, -1e308, 0)).
    for far in [
        IkTarget::position(ee, DVec3::new(1e308, -1e308, 5e-324)),
        IkTarget::position(ee, DVec3::new(0.0, 0.0, 1e51)),
        good.with_axis_weights([1e60, 1.0, 1.0, 1.0, 1.0, 1.0]),
    ] {
        let e = solver.solve(&model, &mut data, &far, &q0).unwrap_err();
        assert!(
            matches!(e, KinematicsError::InvalidTarget { index: 0, .. }),
            "{e:?}"
        );
        assert!(e.to_string().contains("1e50"), "{e}");
    }
    // Large but workable: a finite report.
    let report = solver
        .solve(
            &model,
            &mut data,
            &IkTarget::position(ee, DVec3::splat(1e40)),
            &q0,
        )
        .unwrap();
    assert!(report.position_error.is_finite() && report.orientation_error.is_finite());
    assert!(matches!(
        solver.solve_targets(&model, &mut data, &[good; 5], &q0),
        Err(KinematicsError::DimensionMismatch { .. })
    ));
    // Another model's data, and another model.
    let other = samples::planar_2r(1.0, 1.0);
    let mut other_data = KinematicsData::new(&other);
    assert!(matches!(
        solver.solve(&model, &mut other_data, &good, &q0),
        Err(KinematicsError::DataMismatch { .. })
    ));
    assert!(matches!(
        solver.solve(&other, &mut other_data, &good, &[0.0, 0.0]),
        Err(KinematicsError::DataMismatch { .. })
    ));
    assert!(matches!(
        solver.set_posture(&model, &q0[..2], 0.1),
        Err(KinematicsError::DimensionMismatch { .. })
    ));
    // Fewer target slots after set_params.
    solver.set_params(IkParams {
        max_targets: 1,
        ..params()
    });
    assert_eq!(solver.params().max_targets, 1);
    assert!(matches!(
        solver.solve_targets(&model, &mut data, &[good; 2], &q0),
        Err(KinematicsError::DimensionMismatch { .. })
    ));
    assert!(solver.solve(&model, &mut data, &good, &q0).is_ok());
    // An absurd number of slots is capped (10⁹ aborted on the allocation), and still solves.
    solver.set_params(IkParams {
        max_targets: 1_000_000_000,
        ..params()
    });
    assert_eq!(
        solver.params().max_targets,
        kinetree_kinematics::ik::MAX_TARGETS
    );
    let mut capped = IkSolver::new(
        &model,
        IkParams {
            max_targets: usize::MAX,
            ..params()
        },
    );
    assert_eq!(
        capped.params().max_targets,
        kinetree_kinematics::ik::MAX_TARGETS
    );
    assert!(capped.solve(&model, &mut data, &good, &q0).is_ok());
}

#[test]
fn analytic_two_link_arm_and_seeding() {
    let (l1, l2) = (1.0, 0.8);
    let model = samples::planar_2r(l1, l2);
    let tool = FrameId::find(&model, "tool").unwrap();
    let arm = PlanarTwoLink::new(l1, l2).unwrap();
    for (x, y) in [(1.2, 0.5), (-0.4, 1.1), (0.3, -0.2), (-1.79, 0.0)] {
        let s = arm.solve(x, y).unwrap();
        assert!(s.elbow_up[1] >= 0.0 && s.elbow_down[1] <= 0.0);
        for q in [s.elbow_up, s.elbow_down] {
            let p = pose_at(&model, tool, &q).translation;
            assert!(
                (p - DVec3::new(x, y, 0.0)).length() < 1e-12,
                "({x}, {y}): {p}"
            );
        }
    }
    // Unreachable: outside the outer radius, inside the inner one.
    assert!(!arm.is_reachable(1.81, 0.0) && arm.solve(1.81, 0.0).is_none());
    assert!(!arm.is_reachable(0.1, 0.1) && arm.solve(0.1, 0.1).is_none());
    assert_eq!(arm.reach().1, l1 + l2);

    // The analytic solution seeds the numeric solver: converged at the seed, no step needed.
    let mut solver = IkSolver::new(&model, params());
    let seeder: TwoLinkSeeder = arm
        .seeder(&model, "joint1", "joint2", Se3::IDENTITY)
        .unwrap();
    solver.set_seeder(seeder);
    let mut data = KinematicsData::new(&model);
    let target = IkTarget::position(tool, DVec3::new(1.2, 0.5, 0.0));
    let report = solver
        .solve(&model, &mut data, &target, &[0.0, 0.0])
        .unwrap();
    assert!(report.is_converged());
    assert_eq!((report.iterations, report.restarts), (0, 0));
    let s = arm.solve(1.2, 0.5).unwrap();
    assert!((report.q[0] - s.elbow_up[0]).abs() < 1e-12);
    // An unreachable target: the seeder offers nothing, the numeric solver reports best effort
    // with the tip stretched towards it.
    let far = IkTarget::position(tool, DVec3::new(2.5, 0.0, 0.0));
    let mut budgeted = IkSolver::new(
        &model,
        IkParams {
            max_iterations: 200,
            ..params()
        },
    );
    let report = budgeted
        .solve(&model, &mut data, &far, &[0.3, 0.3])
        .unwrap();
    assert!(matches!(report.status, IkStatus::BestEffort { .. }));
    // The best iterate met, not necessarily the exact optimum (the arm stretched straight out).
    assert!(report.position_error > 0.7 && report.position_error < 0.7 + 1e-3);
    assert!(matches!(
        arm.seeder(&model, "joint1", "nope", Se3::IDENTITY),
        Err(KinematicsError::UnknownJoint { .. })
    ));
}

#[test]
fn a_solve_allocates_nothing() {
    for (robot, frames) in [
        ("panda", &["panda_hand_tcp"][..]),
        ("kinova", &["j2s6s200_end_effector"][..]),
        (
            "talos_reduced",
            &["left_sole_link", "right_sole_link", "arm_right_7_link"][..],
        ),
    ] {
        let (model, _) = load(robot);
        let frames: Vec<FrameId> = frames
            .iter()
            .map(|n| FrameId::find(&model, n).unwrap())
            .collect();
        let mut rng = SmallRng::seed_from_u64(1);
        let mut solver = IkSolver::new(&model, IkParams::default());
        solver
            .set_posture(&model, &neutral_configuration(&model), 0.05)
            .unwrap();
        let mut data = KinematicsData::new(&model);
        let mut cases = Vec::new();
        for _ in 0..20 {
            let mut q = neutral_configuration(&model);
            random_configuration(&model, &mut rng, &mut q).unwrap();
            let targets: Vec<IkTarget> = frames
                .iter()
                .map(|f| IkTarget::new(*f, pose_at(&model, *f, &q)))
                .collect();
            random_configuration(&model, &mut rng, &mut q).unwrap();
            cases.push((targets, q));
        }
        // Far targets too, so that budgets, restarts and best effort are exercised.
        let far = vec![IkTarget::position(frames[0], DVec3::new(5.0, 0.0, 0.0))];
        cases.push((far, neutral_configuration(&model)));
        let mut restarts = 0;
        let count = kinetree_test_support::allocations_during(|| {
            for (targets, q0) in &cases {
                let report = solver
                    .solve_targets(&model, &mut data, targets, q0)
                    .unwrap();
                restarts += report.restarts;
            }
        });
        assert_eq!(count, 0, "{robot}: a solve allocated");
        assert!(restarts > 0, "{robot}: no restart exercised");
    }
}

#[test]
fn coupled_mimic_followers_move_with_their_leader() {
    use kinetree_kinematics::model::{LoadOptions, MimicMode};
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/robots/panda.urdf"
    );
    let options = LoadOptions {
        mimic: MimicMode::Coupled,
        ..LoadOptions::from(RootJoint::Fixed)
    };
    let model = Model::from_urdf_file_with(path, &options).unwrap();
    // panda_finger_joint2 follows panda_finger_joint1: the right finger is moved by a coordinate
    // that is not on its own path.
    let right = FrameId::find(&model, "panda_rightfinger").unwrap();
    let mut q_goal = neutral_configuration(&model);
    q_goal[..7].copy_from_slice(&[0.2, -0.4, 0.1, -2.0, 0.3, 1.7, 0.6]);
    set_joint_q(&model, &mut q_goal, "panda_finger_joint1", &[0.03]).unwrap();
    let goal = pose_at(&model, right, &q_goal);
    // Only the leader may move: the solver must find it through the follower's column.
    let mut solver = IkSolver::new(&model, params());
    solver
        .set_moving_joints(&model, &["panda_finger_joint1"])
        .unwrap();
    let mut q0 = q_goal.clone();
    set_joint_q(&model, &mut q0, "panda_finger_joint1", &[0.0]).unwrap();
    let mut data = KinematicsData::new(&model);
    let report = solver
        .solve(
            &model,
            &mut data,
            &IkTarget::position(right, goal.translation),
            &q0,
        )
        .unwrap();
    assert!(report.is_converged(), "{:?}", report.status);
    let finger = model.joint_q_range(model.joint_index("panda_finger_joint1").unwrap());
    assert!((report.q[finger.start] - 0.03).abs() < 1e-6);
    // Every joint free: the full pose of the right finger from neutral.
    solver.move_all_joints();
    let report = solver
        .solve(
            &model,
            &mut data,
            &IkTarget::new(right, goal),
            &neutral_configuration(&model),
        )
        .unwrap();
    assert!(report.is_converged());
    assert!(is_within_limits(&model, report.q, 0.0).unwrap());
}

#[test]
fn the_solver_can_move_to_another_thread() {
    fn assert_send<T: Send>() {}
    assert_send::<IkSolver>();
    assert_send::<IkReport<'static>>();
}
