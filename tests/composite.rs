//! Composite joints (trip_kinematics' `Transformation`): forward kinematics against the product
//! of the factors by hand, the Jacobian against finite differences, dynamics identities, inverse
//! kinematics, configuration-space operations on a ball factor, and a JSON round trip.

use glam::DVec3;
use kinetree::dynamics::{DynamicsData, aba, crba, rnea};
use kinetree::kinematics::configuration::{Space, from_named};
use kinetree::kinematics::ik::{IkParams, IkSolver, IkTarget};
use kinetree::kinematics::{
    FrameId, KinematicsData, ReferenceFrame, compute_frame_jacobian, configuration,
    forward_kinematics,
};
use kinetree::model::composite::{Axis, CompositeJointSpec, Factor};
use kinetree::model::{
    FrameSpec, Issue, ItemKind, JointKind, JointLimits, JointSpec, JsonOptions, Link, Model,
    ModelBuilder, RootJoint, Units,
};
use kinetree::spatial::{Motion, Se3, Symmetric3};
use rand::SeedableRng;
use rand::rngs::SmallRng;

fn body(name: &str) -> Link {
    Link::new(name).with_mass(
        1.5,
        DVec3::new(0.05, 0.1, -0.2),
        Symmetric3::new(0.03, 0.001, 0.0, 0.04, 0.002, 0.02),
    )
}

/// pelvis —hip: tx 0.1, ry, rz, tz -0.05 → thigh —knee: ball, tz 0.3 (constant) → shank.
fn leg() -> Model {
    let mut b = ModelBuilder::new("leg");
    b.add_link(body("pelvis"))
        .add_link(body("thigh"))
        .add_link(body("shank"));
    b.add_composite(
        CompositeJointSpec::new(
            "hip",
            "pelvis",
            "thigh",
            [
                Factor::Translate(Axis::X, Some(0.1)),
                Factor::Rotate(Axis::Y, None),
                Factor::Rotate(Axis::Z, None),
                Factor::Translate(Axis::Z, Some(-0.05)),
            ],
        )
        .with_placement(Se3::from_translation(DVec3::new(0.0, 0.2, 0.0)))
        .with_limits([
            JointLimits::position(-2.0, 2.0),
            JointLimits::position(-1.5, 1.5),
        ]),
    );
    b.add_composite(CompositeJointSpec::new(
        "knee",
        "thigh",
        "shank",
        [
            Factor::Ball,
            Factor::Translate(Axis::Z, Some(0.3)),
            Factor::Translate(Axis::Y, None),
        ],
    ));
    b.root_joint(RootJoint::Fixed);
    b.build().unwrap()
}

/// The shank's pose from the factors, by hand.
fn shank_by_hand(ry: f64, rz: f64, quat: glam::DQuat, ty: f64) -> Se3 {
    Se3::from_translation(DVec3::new(0.0, 0.2, 0.0))
        * Se3::from_translation(DVec3::new(0.1, 0.0, 0.0))
        * Se3::from_rotation_y(ry)
        * Se3::from_rotation_z(rz)
        * Se3::from_translation(DVec3::new(0.0, 0.0, -0.05))
        * Se3::from_quat(quat)
        * Se3::from_translation(DVec3::new(0.0, 0.0, 0.3))
        * Se3::from_translation(DVec3::new(0.0, ty, 0.0))
}

fn random_q(model: &Model, seed: u64) -> Vec<f64> {
    let mut q = vec![0.0; model.nq()];
    configuration::random_configuration(model, &mut SmallRng::seed_from_u64(seed), &mut q).unwrap();
    q
}

#[test]
fn the_state_variables_are_the_joints_coordinates() {
    let m = leg();
    // hip: ry, rz; knee: a quaternion and ty.
    assert_eq!((m.nq(), m.nv()), (2 + 4 + 1, 2 + 3 + 1));
    for name in ["hip.ry", "hip.rz", "knee.quat", "knee.ty"] {
        assert!(m.joint_index(name).is_some(), "no {name}");
    }
    let ry = m.joint(m.joint_index("hip.ry").unwrap());
    assert_eq!((ry.limits.lower, ry.limits.upper), (-2.0, 2.0));
}

#[test]
fn forward_kinematics_is_the_product_of_the_factors() {
    let m = leg();
    let shank = FrameId::find(&m, "shank").unwrap();
    let mut data = KinematicsData::new(&m);
    for seed in 0..20 {
        let q = random_q(&m, seed);
        forward_kinematics(&m, &mut data, &q).unwrap();
        let quat = glam::DQuat::from_xyzw(q[2], q[3], q[4], q[5]).normalize();
        let want = shank_by_hand(q[0], q[1], quat, q[6]);
        let got = data.world_from(shank).unwrap();
        assert!(
            (got.translation - want.translation).length() < 1e-14,
            "{got:?} vs {want:?}"
        );
        assert!(got.rotation.abs_diff_eq(want.rotation, 1e-14));
    }
}

#[test]
fn the_jacobian_matches_finite_differences() {
    let m = leg();
    let shank = FrameId::find(&m, "shank").unwrap();
    let mut data = KinematicsData::new(&m);
    let q = random_q(&m, 7);
    let mut jac = vec![Motion::ZERO; m.nv()];
    compute_frame_jacobian(
        &m,
        &mut data,
        &q,
        shank,
        ReferenceFrame::LocalWorldAligned,
        &mut jac,
    )
    .unwrap();
    let position = |q: &[f64], data: &mut KinematicsData| {
        forward_kinematics(&m, data, q).unwrap();
        data.world_from(shank).unwrap().translation
    };
    let h = 1e-6;
    for (k, column) in jac.iter().enumerate() {
        let mut dv = vec![0.0; m.nv()];
        let (mut qp, mut qm) = (q.clone(), q.clone());
        dv[k] = h;
        configuration::integrate(&m, &q, &dv, &mut qp).unwrap();
        dv[k] = -h;
        configuration::integrate(&m, &q, &dv, &mut qm).unwrap();
        let fd = (position(&qp, &mut data) - position(&qm, &mut data)) / (2.0 * h);
        assert!(
            (fd - column.linear).length() < 1e-8,
            "column {k}: {fd} vs {}",
            column.linear
        );
    }
}

#[test]
fn dynamics_are_consistent() {
    let m = leg();
    let mut data = DynamicsData::new(&m);
    let q = random_q(&m, 3);
    let v: Vec<f64> = (0..m.nv()).map(|i| 0.3 - 0.1 * i as f64).collect();
    let a: Vec<f64> = (0..m.nv()).map(|i| 0.5 * i as f64 - 1.0).collect();
    let tau = rnea(&m, &mut data, &q, &v, &a).unwrap().to_vec();
    let back = aba(&m, &mut data, &q, &v, &tau).unwrap();
    for (x, y) in back.iter().zip(&a) {
        assert!((x - y).abs() < 1e-9, "{back:?} vs {a:?}");
    }
    // The mass matrix is symmetric with a positive diagonal.
    let n = m.nv();
    let mass = crba(&m, &mut data, &q).unwrap();
    for i in 0..n {
        assert!(mass[i * n + i] > 0.0);
        for j in 0..n {
            assert!((mass[i * n + j] - mass[j * n + i]).abs() < 1e-12);
        }
    }
}

#[test]
fn inverse_kinematics_reaches_a_pose_of_the_composite_chain() {
    let m = leg();
    let shank = FrameId::find(&m, "shank").unwrap();
    let goal_q = random_q(&m, 11);
    let mut data = KinematicsData::new(&m);
    forward_kinematics(&m, &mut data, &goal_q).unwrap();
    let goal = *data.world_from(shank).unwrap();
    // An iteration budget, not a time budget, so the result cannot depend on the machine's load
    // (the 5 ms default ran out once in an unoptimised build on a loaded machine); the solve
    // takes 8 steps.
    let params = IkParams {
        time_budget: None,
        max_iterations: 1_000,
        ..IkParams::default()
    };
    let mut solver = IkSolver::new(&m, params);
    let start = configuration::neutral_configuration(&m);
    let report = solver
        .solve(&m, &mut data, &IkTarget::new(shank, goal), &start)
        .unwrap();
    assert!(report.is_converged(), "{report:?}");
    assert!(report.position_error < 1e-6, "{report:?}");
    assert!(report.orientation_error < 1e-6, "{report:?}");
}

#[test]
fn configuration_operations_and_a_json_round_trip_handle_composite_joints() {
    let m = leg();
    let (q0, q1) = (random_q(&m, 1), random_q(&m, 2));
    let mut v = vec![0.0; m.nv()];
    configuration::difference(&m, &q0, &q1, &mut v).unwrap();
    let mut back = vec![0.0; m.nq()];
    configuration::integrate(&m, &q0, &v, &mut back).unwrap();
    let mut rest = vec![0.0; m.nv()];
    configuration::difference(&m, &q1, &back, &mut rest).unwrap();
    assert!(rest.iter().all(|x| x.abs() < 1e-12), "{rest:?}");
    // Through JSON (written as its elementary joints): the same coordinates, the same poses.
    let json = m.to_json_string(&JsonOptions::default()).unwrap();
    let again = Model::from_json_str(&json, None::<RootJoint>).unwrap();
    assert_eq!(again.nq(), m.nq());
    let shank = FrameId::find(&m, "shank").unwrap();
    let (mut d0, mut d1) = (KinematicsData::new(&m), KinematicsData::new(&again));
    forward_kinematics(&m, &mut d0, &q1).unwrap();
    forward_kinematics(&again, &mut d1, &q1).unwrap();
    let (a, b) = (d0.world_from(shank).unwrap(), d1.world_from(shank).unwrap());
    assert!((a.translation - b.translation).length() < 1e-12);
}

#[test]
fn a_composite_of_constants_only_is_a_fixed_joint() {
    let mut b = ModelBuilder::new("weld");
    b.add_link(Link::new("a")).add_link(body("b"));
    b.add_composite(CompositeJointSpec::new(
        "w",
        "a",
        "b",
        [
            Factor::Rotate(Axis::Z, Some(std::f64::consts::FRAC_PI_2)),
            Factor::Translate(Axis::X, Some(1.0)),
        ],
    ));
    let m = b.build().unwrap();
    assert_eq!(m.nq(), 0);
    let mut data = KinematicsData::new(&m);
    forward_kinematics(&m, &mut data, &[]).unwrap();
    let p = data.world_from(FrameId::find(&m, "b").unwrap()).unwrap();
    assert!((p.translation - DVec3::new(0.0, 1.0, 0.0)).length() < 1e-15);
    // An unknown parent is reported by the builder, naming it.
    let mut bad = ModelBuilder::new("bad");
    bad.add_link(Link::new("b"));
    bad.add_composite(CompositeJointSpec::new(
        "j",
        "nowhere",
        "b",
        [Factor::Rotate(Axis::X, None)],
    ));
    let e = bad.build().unwrap_err().to_string();
    assert!(e.contains("nowhere"), "{e}");
}

/// The leg of [`leg`] as a model file, in `units` ("m"/"rad" or "mm"/"deg").
fn leg_json(mm_deg: bool) -> String {
    let (l, a) = if mm_deg {
        (1000.0, 180.0 / std::f64::consts::PI)
    } else {
        (1.0, 1.0)
    };
    let body = |name: &str| {
        format!(
            r#"{{"name": "{name}", "inertial": {{"origin": {{"xyz": [{}, {}, {}]}}, "mass": 1.5,
                "inertia": {{"ixx": {}, "ixy": {}, "iyy": {}, "iyz": {}, "izz": {}}}}}}}"#,
            0.05 * l,
            0.1 * l,
            -0.2 * l,
            0.03 * l * l,
            0.001 * l * l,
            0.04 * l * l,
            0.002 * l * l,
            0.02 * l * l
        )
    };
    format!(
        r#"{{"name": "leg", "units": {{"length": "{}", "angle": "{}"}},
  "links": [{}, {}, {}],
  "joints": [
    {{"name": "hip", "type": "composite", "parent": "pelvis", "child": "thigh",
      "origin": {{"xyz": [0, {}, 0]}},
      "factors": [{{"param": "tx", "value": {}}},
                  {{"param": "ry", "limits": {{"lower": {}, "upper": {}}}}},
                  {{"param": "rz", "limits": {{"lower": {}, "upper": {}}}}},
                  {{"param": "tz", "value": {}}}]}},
    {{"name": "knee", "type": "composite", "parent": "thigh", "child": "shank",
      "factors": [{{"param": "quat"}}, {{"param": "tz", "value": {}}}, {{"param": "ty"}}]}}
  ]}}"#,
        if mm_deg { "mm" } else { "m" },
        if mm_deg { "deg" } else { "rad" },
        body("pelvis"),
        body("thigh"),
        body("shank"),
        0.2 * l,
        0.1 * l,
        -2.0 * a,
        2.0 * a,
        -1.5 * a,
        1.5 * a,
        -0.05 * l,
        0.3 * l,
    )
}

/// The same leg chained by hand from elementary joints and dummy links (what a user had to
/// write before composite joints).
fn leg_by_hand() -> Model {
    let mut b = ModelBuilder::new("leg");
    for name in ["pelvis", "thigh", "shank"] {
        b.add_link(body(name));
    }
    for name in ["d1", "d2", "d3"] {
        b.add_link(Link::new(name));
    }
    let t = |x: f64, y: f64, z: f64| Se3::from_translation(DVec3::new(x, y, z));
    b.add_joint(
        JointSpec::new("a", JointKind::Revolute, "pelvis", "d1")
            .with_placement(t(0.0, 0.2, 0.0) * t(0.1, 0.0, 0.0))
            .with_axis(DVec3::Y)
            .with_limits(JointLimits::position(-2.0, 2.0)),
    );
    b.add_joint(
        JointSpec::new("b", JointKind::Revolute, "d1", "d2")
            .with_axis(DVec3::Z)
            .with_limits(JointLimits::position(-1.5, 1.5)),
    );
    b.add_joint(
        JointSpec::new("c", JointKind::Fixed, "d2", "thigh").with_placement(t(0.0, 0.0, -0.05)),
    );
    b.add_joint(JointSpec::new("d", JointKind::Spherical, "thigh", "d3"));
    b.add_joint(
        JointSpec::new("e", JointKind::Prismatic, "d3", "shank")
            .with_placement(t(0.0, 0.0, 0.3))
            .with_axis(DVec3::Y),
    );
    b.build().unwrap()
}

#[test]
fn a_json_composite_joint_is_one_joint_named_as_written() {
    let m = Model::from_json_str(&leg_json(false), None::<RootJoint>).unwrap();
    let names: Vec<(&str, &str, usize, usize)> = m
        .moving_user_joints()
        .map(|u| {
            let q = m.user_joint_q_range(u);
            let v = m.user_joint_v_range(u);
            (
                m.user_joints()[u].name.as_str(),
                m.user_joint_type(u),
                q.len(),
                v.len(),
            )
        })
        .collect();
    assert_eq!(
        names,
        [("hip", "composite", 2, 2), ("knee", "composite", 5, 4)]
    );
    assert_eq!(
        m.user_joint_q_range(m.user_joint_index("knee").unwrap()),
        2..7
    );
    // The pieces are not user joints; their links are virtual.
    assert!(m.user_joint_index("hip.ry").is_none());
    let virtual_links: Vec<&str> = (0..m.links().len())
        .filter(|&l| m.is_virtual_link(l))
        .map(|l| m.link(l).name.as_str())
        .collect();
    assert_eq!(virtual_links, ["hip#1", "hip#2", "knee#1"]);
    // The printed tree shows the composite joints, not their pieces.
    let tree = m.to_string();
    assert!(
        tree.contains("thigh <- hip (composite: tx=0.1 ry rz tz=-0.05)"),
        "{tree}"
    );
    assert!(!tree.contains("hip#1"), "{tree}");
    // A named state addresses it by its name, with its whole block.
    let q = from_named(
        &m,
        Space::Configuration,
        [
            ("hip", vec![0.3, -0.2]),
            ("knee", vec![0.0, 0.0, 0.0, 1.0, 0.25]),
        ],
        true,
    )
    .unwrap();
    assert_eq!(q, [0.3, -0.2, 0.0, 0.0, 0.0, 1.0, 0.25]);
    let e = from_named(&m, Space::Configuration, [("hip", vec![0.3])], false).unwrap_err();
    assert!(
        e.to_string().contains("'hip'") && e.to_string().contains("composite joint takes 2"),
        "{e}"
    );
    let e = from_named(&m, Space::Configuration, [("hip", vec![0.3, 0.1])], true).unwrap_err();
    assert!(e.to_string().contains("'knee'"), "{e}");
    // The limits of its variables, in SI.
    let spec = &m.composites()[0].spec;
    assert_eq!(
        spec.limits,
        [
            JointLimits::position(-2.0, 2.0),
            JointLimits::position(-1.5, 1.5)
        ]
    );
    // The same file in millimetres and degrees is the same model.
    let mm = Model::from_json_str(&leg_json(true), None::<RootJoint>).unwrap();
    assert_eq!(m.first_difference(&mm, 1e-12), None);
}

#[test]
fn a_composite_joint_moves_as_the_elementary_chain_by_hand() {
    let m = Model::from_json_str(&leg_json(false), None::<RootJoint>).unwrap();
    let hand = leg_by_hand();
    assert_eq!((m.nq(), m.nv()), (hand.nq(), hand.nv()));
    let (mut dm, mut dh) = (DynamicsData::new(&m), DynamicsData::new(&hand));
    let (mut km, mut kh) = (KinematicsData::new(&m), KinematicsData::new(&hand));
    let (mut jm, mut jh) = (vec![Motion::ZERO; m.nv()], vec![Motion::ZERO; m.nv()]);
    for seed in 0..10 {
        let q = random_q(&hand, seed);
        let v: Vec<f64> = (0..m.nv())
            .map(|i| 0.3 - 0.17 * i as f64 + 0.01 * seed as f64)
            .collect();
        let a: Vec<f64> = (0..m.nv()).map(|i| 0.5 * i as f64 - 1.0).collect();
        for link in ["pelvis", "thigh", "shank"] {
            let (fm, fh) = (
                FrameId::find(&m, link).unwrap(),
                FrameId::find(&hand, link).unwrap(),
            );
            forward_kinematics(&m, &mut km, &q).unwrap();
            forward_kinematics(&hand, &mut kh, &q).unwrap();
            let (pm, ph) = (*km.world_from(fm).unwrap(), *kh.world_from(fh).unwrap());
            assert!((pm.translation - ph.translation).length() < 1e-14, "{link}");
            assert!(pm.rotation.abs_diff_eq(ph.rotation, 1e-14), "{link}");
            for rf in [ReferenceFrame::World, ReferenceFrame::Local] {
                compute_frame_jacobian(&m, &mut km, &q, fm, rf, &mut jm).unwrap();
                compute_frame_jacobian(&hand, &mut kh, &q, fh, rf, &mut jh).unwrap();
                for (x, y) in jm.iter().zip(&jh) {
                    assert!((x.linear - y.linear).length() < 1e-13, "{link} {rf:?}");
                    assert!((x.angular - y.angular).length() < 1e-13, "{link} {rf:?}");
                }
            }
        }
        let tm = rnea(&m, &mut dm, &q, &v, &a).unwrap().to_vec();
        let th = rnea(&hand, &mut dh, &q, &v, &a).unwrap().to_vec();
        for (x, y) in tm.iter().zip(&th) {
            assert!((x - y).abs() < 1e-12 * (1.0 + y.abs()), "{tm:?} vs {th:?}");
        }
    }
}

#[test]
fn a_composite_joint_round_trips_through_json_as_one_joint() {
    let m = Model::from_json_str(&leg_json(false), None::<RootJoint>).unwrap();
    let q = [0.3, -0.2, 0.0, 0.6, 0.0, 0.8, 0.25];
    for units in [Units::SI, Units::MM_DEG] {
        let opts = JsonOptions {
            units,
            positions: Some(&q),
            ..JsonOptions::default()
        };
        let json = m.to_json_string(&opts).unwrap();
        let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
        let joints = doc["joints"].as_array().unwrap();
        assert_eq!(joints.len(), 2, "{json}");
        assert_eq!(joints[0]["name"], "hip");
        assert_eq!(joints[0]["type"], "composite");
        assert_eq!(joints[0]["factors"][1]["param"], "ry");
        let links: Vec<&str> = doc["links"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l["name"].as_str().unwrap())
            .collect();
        assert_eq!(links, ["pelvis", "thigh", "shank"]);
        let again = Model::from_json_str(&json, None::<RootJoint>).unwrap();
        assert_eq!(m.first_difference(&again, 1e-12), None, "{json}");
        let back = kinetree::model::state::positions_from_json(&again, &json).unwrap();
        for (x, y) in back.iter().zip(&q) {
            assert!((x - y).abs() < 1e-12, "{back:?}");
        }
    }
    // A constant quaternion and a parent frame survive too.
    let mut b = ModelBuilder::new("w");
    b.add_link(Link::new("a")).add_link(body("b"));
    b.add_frame(FrameSpec::new(
        "mount",
        "a",
        Se3::from_translation(DVec3::X),
    ));
    let mut spec = CompositeJointSpec::new(
        "w",
        "a",
        "b",
        [
            Factor::Rotation(glam::DQuat::from_xyzw(0.0, 0.0, 2.0, 2.0)),
            Factor::Translate(Axis::Z, None),
        ],
    );
    spec.parent_frame = Some("mount".into());
    b.add_composite(spec);
    let w = b.build().unwrap();
    let json = w.to_json_string(&JsonOptions::default()).unwrap();
    let again = Model::from_json_str(&json, None::<RootJoint>).unwrap();
    assert_eq!(w.first_difference(&again, 1e-12), None, "{json}");
    let mut data = KinematicsData::new(&again);
    forward_kinematics(&again, &mut data, &[0.5]).unwrap();
    let p = data
        .world_from(FrameId::find(&again, "b").unwrap())
        .unwrap();
    assert!(
        (p.translation - DVec3::new(1.0, 0.0, 0.5)).length() < 1e-15,
        "{p:?}"
    );
    assert!((p.rotation * DVec3::X - DVec3::Y).length() < 1e-15);
}

#[test]
fn bad_composite_specs_are_errors_naming_the_joint() {
    let cases = [
        (r#"{"param": "rw"}"#, "unknown parameter"),
        (
            r#"{"param": "ry"}, {"param": "tx"}, {"param": "ry"}"#,
            "'ry' is given twice",
        ),
        (
            r#"{"param": "quat"}, {"param": "quat"}"#,
            "'quat' is given twice",
        ),
        (
            r#"{"param": "quat", "value": [0, 0, 0, 0]}"#,
            "zero or not finite",
        ),
        (r#"{"param": "quat", "value": [0, 0, 1]}"#, "[x, y, z, w]"),
        (r#"{"param": "tx", "value": [1, 2]}"#, "is a number"),
        (
            r#"{"param": "quat", "limits": {"lower": 0}}"#,
            "has `limits`",
        ),
    ];
    for (factors, want) in cases {
        let text = format!(
            r#"{{"links": [{{"name": "a"}}, {{"name": "b"}}], "joints": [{{"name": "hip",
                "type": "composite", "parent": "a", "child": "b", "factors": [{factors}]}}]}}"#
        );
        let e = Model::from_json_str(&text, None::<RootJoint>)
            .unwrap_err()
            .to_string();
        assert!(e.contains("'hip'") && e.contains(want), "{factors}: {e}");
    }
    // A composite without factors, an elementary joint with factors, a composite with an axis.
    for (joint, want) in [
        (r#""type": "composite""#, "needs `factors`"),
        (
            r#""type": "revolute", "factors": []"#,
            "only a composite joint has `factors`",
        ),
        (
            r#""type": "composite", "axis": [1, 0, 0], "factors": []"#,
            "no `axis`",
        ),
        (r#""type": "hinge""#, "expected one of"),
    ] {
        let text = format!(
            r#"{{"links": [{{"name": "a"}}, {{"name": "b"}}], "joints": [{{"name": "hip",
                {joint}, "parent": "a", "child": "b"}}]}}"#
        );
        let e = Model::from_json_str(&text, None::<RootJoint>)
            .unwrap_err()
            .to_string();
        assert!(e.contains(want), "{joint}: {e}");
    }
    // A joint hung inside a composite, and a name used twice.
    let mut b = ModelBuilder::new("m");
    b.add_link(Link::new("a"))
        .add_link(Link::new("b"))
        .add_link(Link::new("c"));
    b.add_composite(CompositeJointSpec::new(
        "hip",
        "a",
        "b",
        [Factor::Rotate(Axis::X, None), Factor::Rotate(Axis::Y, None)],
    ));
    b.add_joint(JointSpec::new("hip", JointKind::Revolute, "hip#1", "c"));
    let issues = b.validate();
    let text: Vec<String> = issues.iter().map(ToString::to_string).collect();
    assert!(
        text.iter()
            .any(|t| t.contains("'hip'") && t.contains("virtual link")),
        "{text:?}"
    );
    assert!(
        issues.contains(&Issue::DuplicateName {
            kind: ItemKind::Joint,
            name: "hip".into()
        }),
        "{text:?}"
    );
}

#[test]
fn urdf_export_writes_the_expansion_with_the_same_motion() {
    let m = Model::from_json_str(&leg_json(false), None::<RootJoint>).unwrap();
    let urdf = m.to_urdf_string().unwrap();
    assert!(urdf.contains("hip#1") && urdf.contains("hip.ry"), "{urdf}");
    let back = Model::from_urdf_str(&urdf, RootJoint::Fixed).unwrap();
    assert_eq!((back.nq(), back.nv()), (m.nq(), m.nv()));
    let q = random_q(&m, 5);
    let (mut d0, mut d1) = (KinematicsData::new(&m), KinematicsData::new(&back));
    forward_kinematics(&m, &mut d0, &q).unwrap();
    forward_kinematics(&back, &mut d1, &q).unwrap();
    let (a, b) = (
        d0.world_from(FrameId::find(&m, "shank").unwrap()).unwrap(),
        d1.world_from(FrameId::find(&back, "shank").unwrap())
            .unwrap(),
    );
    assert!((a.translation - b.translation).length() < 1e-12);
    assert!(a.rotation.abs_diff_eq(b.rotation, 1e-12));
}
