//! Bad input gives typed errors, never panics or NaN.

use crate::common::{every_kind, q_of, robots, v_of};
use kinetree_dynamics::model::spatial::Symmetric3;
use kinetree_dynamics::model::spatial::glam::DVec3;
use kinetree_dynamics::model::{JointKind, JointSpec, Link, Model, ModelBuilder, RootJoint};
use kinetree_dynamics::spatial::Force;
use kinetree_dynamics::{
    DynamicsData, DynamicsError, ExternalForces, FrameId, Integrator, ReferenceFrame, aba,
    center_of_mass, compute_all_terms, crba, factorize_mass_matrix, generalized_gravity,
    mass_matrix_inverse, nonlinear_effects, rnea, rnea_with_external_forces, solve_mass_matrix,
    step,
};

/// base -> heavy (revolute) -> light (massless revolute leaf), and heavy -> a -> b, a massless
/// two-joint subtree.
fn with_massless_subtrees() -> Model {
    let mut b = ModelBuilder::new("massless");
    b.add_link(Link::new("base"));
    let inertia = Symmetric3::new(0.01, 0.0, 0.0, 0.01, 0.0, 0.01);
    b.add_part(
        Link::new("heavy").with_mass(1.0, DVec3::new(0.2, 0.0, 0.0), inertia),
        JointSpec::new("shoulder", JointKind::Revolute, "base", "heavy").with_axis(DVec3::Y),
    );
    b.add_part(
        Link::new("light"),
        JointSpec::new("finger", JointKind::Revolute, "heavy", "light").with_axis(DVec3::Z),
    );
    b.add_part(
        Link::new("a"),
        JointSpec::new("knuckle_a", JointKind::Prismatic, "heavy", "a").with_axis(DVec3::X),
    );
    b.add_part(
        Link::new("b"),
        JointSpec::new("knuckle_b", JointKind::Spherical, "a", "b"),
    );
    b.build().unwrap()
}

fn singular_joints(e: DynamicsError) -> Vec<String> {
    match e {
        DynamicsError::SingularMassMatrix { joints } => joints,
        other => panic!("expected a singular mass matrix, got {other:?}"),
    }
}

#[test]
fn massless_subtrees_are_named() {
    let model = with_massless_subtrees();
    let mut data = DynamicsData::new(&model);
    let q = vec![0.1, 0.2, 0.3, 0.0, 0.0, 0.0, 1.0];
    let v = vec![0.5; model.nv()];
    let tau = vec![1.0; model.nv()];
    let expected = ["finger", "knuckle_a", "knuckle_b"];
    let e = aba(&model, &mut data, &q, &v, &tau).unwrap_err();
    assert_eq!(singular_joints(e), expected);
    let e = factorize_mass_matrix(&model, &mut data, &q).unwrap_err();
    let message = e.to_string();
    assert_eq!(singular_joints(e), expected);
    assert!(
        message.contains("finger, knuckle_a, knuckle_b"),
        "{message}"
    );
    let e = mass_matrix_inverse(&model, &mut data, &q).unwrap_err();
    assert_eq!(singular_joints(e), expected);
    let mut b = vec![1.0; model.nv()];
    assert!(matches!(
        solve_mass_matrix(&model, &mut data, &mut b),
        Err(DynamicsError::NotFactorized)
    ));
    let (mut qs, mut vs) = (q.clone(), v.clone());
    let e = step(
        &model,
        &mut data,
        Integrator::RungeKutta4,
        &mut qs,
        &mut vs,
        &tau,
        1e-3,
    )
    .unwrap_err();
    assert_eq!(singular_joints(e), expected);
    // Inverse dynamics and the mass matrix are still fine.
    assert!(
        rnea(&model, &mut data, &q, &v, &v)
            .unwrap()
            .iter()
            .all(|x| x.is_finite())
    );
    let m = crba(&model, &mut data, &q).unwrap();
    assert!(m.iter().all(|x| x.is_finite()));
    // All terms: aba is reported as undefined, the rest is computed.
    let all = compute_all_terms(&model, &mut data, &q, &v, &v, &tau).unwrap();
    assert!(matches!(
        all.aba,
        Err(DynamicsError::SingularMassMatrix { .. })
    ));
    assert!(all.com.is_ok() && all.kinetic_energy > 0.0);
}

#[test]
fn bad_inputs_are_errors() {
    let model = every_kind(RootJoint::Floating);
    let mut data = DynamicsData::new(&model);
    let (nq, nv) = (model.nq(), model.nv());
    let q = kinetree_dynamics::kinematics::configuration::neutral_configuration(&model);
    let v = vec![0.0; nv];
    let short = vec![0.0; nv - 1];
    assert!(matches!(
        rnea(&model, &mut data, &q[..nq - 1], &v, &v),
        Err(DynamicsError::DimensionMismatch { what: "q", .. })
    ));
    assert!(matches!(
        rnea(&model, &mut data, &q, &short, &v),
        Err(DynamicsError::DimensionMismatch { what: "v", .. })
    ));
    assert!(matches!(
        rnea(&model, &mut data, &q, &v, &short),
        Err(DynamicsError::DimensionMismatch { what: "a", .. })
    ));
    assert!(matches!(
        aba(&model, &mut data, &q, &v, &short),
        Err(DynamicsError::DimensionMismatch { what: "tau", .. })
    ));
    let mut nan = v.clone();
    nan[3] = f64::NAN;
    assert!(matches!(
        nonlinear_effects(&model, &mut data, &q, &nan),
        Err(DynamicsError::NonFinite {
            what: "v",
            index: 3
        })
    ));
    let mut qnan = q.clone();
    qnan[0] = f64::INFINITY;
    assert!(matches!(
        generalized_gravity(&model, &mut data, &qnan),
        Err(DynamicsError::NonFinite {
            what: "q",
            index: 0
        })
    ));
    assert!(matches!(
        aba(&model, &mut data, &q, &v, &nan),
        Err(DynamicsError::NonFinite {
            what: "tau",
            index: 3
        })
    ));
    // Data and external forces of another model.
    let other = with_massless_subtrees();
    let mut other_data = DynamicsData::new(&other);
    assert!(matches!(
        crba(&model, &mut other_data, &q),
        Err(DynamicsError::DataMismatch { .. })
    ));
    let other_fext = ExternalForces::new(&other);
    assert!(matches!(
        rnea_with_external_forces(&model, &mut data, &q, &v, &v, &other_fext),
        Err(DynamicsError::DataMismatch { .. })
    ));
    // Unknown links, bad indices, NaN wrenches.
    let mut fext = ExternalForces::new(&model);
    let f = Force::new(DVec3::X, DVec3::ZERO);
    assert!(matches!(
        fext.add_by_name(&model, "no_such_link", ReferenceFrame::World, f),
        Err(DynamicsError::UnknownLink { name }) if name == "no_such_link"
    ));
    assert!(matches!(
        fext.add(&model, FrameId::Link(999), ReferenceFrame::Local, f),
        Err(DynamicsError::IndexOutOfRange {
            what: "link",
            index: 999,
            ..
        })
    ));
    assert!(matches!(
        fext.add(&model, FrameId::Frame(0), ReferenceFrame::Local, f),
        Err(DynamicsError::IndexOutOfRange { what: "frame", .. })
    ));
    assert!(matches!(
        fext.add(
            &model,
            FrameId::Link(0),
            ReferenceFrame::Local,
            Force::new(DVec3::NAN, DVec3::ZERO)
        ),
        Err(DynamicsError::NonFinite { .. })
    ));
    assert!(fext.is_empty());
    // Several right-hand sides must be whole vectors.
    factorize_mass_matrix(&model, &mut data, &q).unwrap();
    let mut rhs = vec![1.0; nv + 1];
    assert!(matches!(
        solve_mass_matrix(&model, &mut data, &mut rhs),
        Err(DynamicsError::DimensionMismatch { what: "rhs", .. })
    ));
}

#[test]
fn massless_model_has_no_com() {
    let mut b = ModelBuilder::new("ghost");
    b.add_link(Link::new("base"));
    b.add_part(
        Link::new("tip"),
        JointSpec::new("j", JointKind::Continuous, "base", "tip"),
    );
    let model = b.build().unwrap();
    let mut data = DynamicsData::new(&model);
    assert!(matches!(
        center_of_mass(&model, &mut data, &[0.0]),
        Err(DynamicsError::ZeroMass)
    ));
}

/// Reference robots load with their URDF `<dynamics>`: the default data leaves them out (the
/// rigid-body quantities, as Pinocchio's), `FromModel` uses them.
#[test]
fn joint_terms_are_opt_in() {
    assert_eq!(
        kinetree_dynamics::JointTerms::default(),
        kinetree_dynamics::JointTerms::Ignored
    );
    for (robot, reference, model) in robots() {
        let has_terms = model
            .joints()
            .iter()
            .any(|j| j.dynamics.damping != 0.0 || j.dynamics.friction != 0.0);
        let sample = &reference["samples"][0];
        let (q, v, a) = (
            q_of(&model, sample),
            v_of(&model, sample, "v"),
            v_of(&model, sample, "a"),
        );
        let mut default = DynamicsData::new(&model);
        assert_eq!(
            default.joint_terms(),
            kinetree_dynamics::JointTerms::Ignored
        );
        let mut with =
            DynamicsData::with_joint_terms(&model, kinetree_dynamics::JointTerms::FromModel);
        let t1 = rnea(&model, &mut with, &q, &v, &a).unwrap().to_vec();
        let t2 = rnea(&model, &mut default, &q, &v, &a).unwrap().to_vec();
        assert_eq!(t1 != t2, has_terms, "{robot}");
        with.set_joint_terms(&model, kinetree_dynamics::JointTerms::Ignored)
            .unwrap();
        let t3 = rnea(&model, &mut with, &q, &v, &a).unwrap();
        assert_eq!(t3, &t2[..], "{robot}");
    }
}

/// A model without moving joints: every algorithm returns empty results, nothing panics.
#[test]
fn models_without_moving_joints_work() {
    let mut b = ModelBuilder::new("statue");
    b.add_link(Link::new("base").with_mass(1.0, DVec3::ZERO, Symmetric3::IDENTITY));
    b.add_part(
        Link::new("head").with_mass(1.0, DVec3::ZERO, Symmetric3::IDENTITY),
        JointSpec::new("neck", JointKind::Fixed, "base", "head"),
    );
    let model = b.build().unwrap();
    assert_eq!(model.nv(), 0);
    let mut data = DynamicsData::new(&model);
    assert!(rnea(&model, &mut data, &[], &[], &[]).unwrap().is_empty());
    assert!(crba(&model, &mut data, &[]).unwrap().is_empty());
    assert!(aba(&model, &mut data, &[], &[], &[]).unwrap().is_empty());
    assert!(
        mass_matrix_inverse(&model, &mut data, &[])
            .unwrap()
            .is_empty()
    );
    solve_mass_matrix(&model, &mut data, &mut []).unwrap();
    // Everything is welded to the world: no moving mass.
    assert!(matches!(
        center_of_mass(&model, &mut data, &[]),
        Err(DynamicsError::ZeroMass)
    ));
    let (mut q, mut v) = (vec![], vec![]);
    step(
        &model,
        &mut data,
        Integrator::RungeKutta4,
        &mut q,
        &mut v,
        &[],
        1e-3,
    )
    .unwrap();
}

#[test]
fn coupled_mimic_models_are_rejected_not_miscomputed() {
    use kinetree_dynamics::model::{LoadOptions, MimicMode};
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/robots/panda.urdf"
    );
    let options = LoadOptions {
        mimic: MimicMode::Coupled,
        ..LoadOptions::from(RootJoint::Fixed)
    };
    let panda = Model::from_urdf_file_with(path, &options).unwrap();
    let mut data = DynamicsData::new(&panda);
    let (q, v) = (vec![0.0; panda.nq()], vec![0.0; panda.nv()]);
    for result in [
        rnea(&panda, &mut data, &q, &v, &v).map(|_| ()),
        crba(&panda, &mut data, &q).map(|_| ()),
        aba(&panda, &mut data, &q, &v, &v).map(|_| ()),
    ] {
        assert!(
            matches!(&result, Err(DynamicsError::CoupledMimic { joint }) if joint == "panda_finger_joint2"),
            "{result:?}"
        );
    }
}

/// A floating base's quaternion of norm √2 (x = 1, w = 1) used to double the torques: it is
/// refused naming the joint; within the tolerance the torques equal the normalized ones.
#[test]
fn non_unit_quaternions_are_refused_or_normalized() {
    use kinetree_dynamics::kinematics::{KinematicsError, QUATERNION_NORM_TOLERANCE};
    let model = every_kind(RootJoint::Floating);
    let mut data = DynamicsData::new(&model);
    let mut q = kinetree_dynamics::kinematics::configuration::neutral_configuration(&model);
    let (v, a) = (vec![0.1; model.nv()], vec![0.2; model.nv()]);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    q[3..7].copy_from_slice(&[s, 0.0, 0.0, s]);
    let unit = rnea(&model, &mut data, &q, &v, &a).unwrap().to_vec();
    q[3..7].copy_from_slice(&[1.0, 0.0, 0.0, 1.0]);
    for result in [
        rnea(&model, &mut data, &q, &v, &a).map(<[f64]>::to_vec),
        crba(&model, &mut data, &q).map(|_| Vec::new()),
        aba(&model, &mut data, &q, &v, &a).map(<[f64]>::to_vec),
        generalized_gravity(&model, &mut data, &q).map(<[f64]>::to_vec),
    ] {
        match result {
            Err(DynamicsError::Kinematics(KinematicsError::NonUnitQuaternion { joint, norm })) => {
                assert_eq!(joint, model.joint(model.bodies()[1].joint.unwrap()).name);
                assert!((norm - 2f64.sqrt()).abs() < 1e-15);
            }
            other => panic!("expected NonUnitQuaternion, got {other:?}"),
        }
    }
    let k = 1.0 + 0.5 * QUATERNION_NORM_TOLERANCE;
    q[3..7].copy_from_slice(&[s * k, 0.0, 0.0, s * k]);
    let near = rnea(&model, &mut data, &q, &v, &a).unwrap();
    for (x, y) in near.iter().zip(&unit) {
        assert!((x - y).abs() < 1e-12 * (1.0 + y.abs()), "{x} vs {y}");
    }
}

/// Finite but huge inputs used to give NaN and -inf torques in an `Ok`, and a "massless
/// subtree" error from ABA: each result is now checked and an overflow names what overflowed.
#[test]
fn overflow_is_a_typed_error_never_nan_in_ok() {
    let model = every_kind(RootJoint::Fixed);
    let mut data = DynamicsData::new(&model);
    let q = kinetree_dynamics::kinematics::configuration::neutral_configuration(&model);
    let nv = model.nv();
    let mut v = vec![0.0; nv];
    v[0] = 1e308;
    let (a, tau) = (vec![0.0; nv], vec![0.0; nv]);
    let is_overflow = |r: Result<Vec<f64>, DynamicsError>, what: &str| match r {
        Err(e @ DynamicsError::Overflow { .. }) => {
            let text = e.to_string();
            assert!(text.contains("overflowed"), "{what}: {text}");
            assert!(!text.contains("massless"), "{what}: {text}");
        }
        other => panic!("{what}: expected Overflow, got {other:?}"),
    };
    is_overflow(
        rnea(&model, &mut data, &q, &v, &a).map(<[f64]>::to_vec),
        "rnea",
    );
    is_overflow(
        nonlinear_effects(&model, &mut data, &q, &v).map(<[f64]>::to_vec),
        "nle",
    );
    is_overflow(
        aba(&model, &mut data, &q, &v, &tau).map(<[f64]>::to_vec),
        "aba",
    );
    is_overflow(
        kinetree_dynamics::kinetic_energy(&model, &mut data, &q, &v).map(|e| vec![e]),
        "kinetic energy",
    );
    let (mut qs, mut vs) = (q.clone(), v.clone());
    is_overflow(
        step(
            &model,
            &mut data,
            Integrator::RungeKutta4,
            &mut qs,
            &mut vs,
            &tau,
            1e-3,
        )
        .map(|()| Vec::new()),
        "step",
    );
    // The joint is named when a torque overflows.
    match rnea(&model, &mut data, &q, &v, &a) {
        Err(DynamicsError::Overflow { joint, .. }) => assert!(!joint.is_empty()),
        other => panic!("expected Overflow, got {other:?}"),
    }
    // A moderate velocity is fine, and a step from it stays finite.
    v[0] = 1.0;
    let ok = rnea(&model, &mut data, &q, &v, &a).unwrap();
    assert!(ok.iter().all(|x| x.is_finite()));
}

/// base -> l1 (revolute about y, 1 kg at 0.5 m) -> l2 (revolute about y, 1 m out along x) with
/// `mass` at `com` and rotational inertia `inertia`·I, or -> a prismatic finger along x (10 g).
fn two_links(mass: f64, com: DVec3, inertia: f64, prismatic: bool) -> Model {
    let mut b = ModelBuilder::new("two");
    b.add_link(Link::new("base"));
    let unit = Symmetric3::new(0.1, 0.0, 0.0, 0.1, 0.0, 0.1);
    b.add_part(
        Link::new("l1").with_mass(1.0, DVec3::new(0.5, 0.0, 0.0), unit),
        JointSpec::new("j1", JointKind::Revolute, "base", "l1").with_axis(DVec3::Y),
    );
    let (kind, axis) = if prismatic {
        (JointKind::Prismatic, DVec3::X)
    } else {
        (JointKind::Revolute, DVec3::Y)
    };
    b.add_part(
        Link::new("l2").with_mass(
            mass,
            com,
            Symmetric3::new(inertia, 0.0, 0.0, inertia, 0.0, inertia),
        ),
        JointSpec::new("j2", kind, "l1", "l2")
            .with_axis(axis)
            .with_placement(kinetree_dynamics::spatial::Se3::from_translation(DVec3::X)),
    );
    b.build().unwrap()
}

/// Every path that reports a singular mass matrix (ABA, the factorization and inverse, a
/// simulation step) says what happened: an overflow, a loss of precision (links absurdly far
/// out, masses absurdly different) or a massless subtree, never "massless" for the first two.
#[test]
fn overflow_and_lost_precision_are_never_called_a_massless_subtree() {
    fn every_path(model: &Model, q: &[f64]) -> Vec<DynamicsError> {
        let mut data = DynamicsData::new(model);
        let (v, tau) = (vec![0.0; model.nv()], vec![0.0; model.nv()]);
        let (mut qs, mut vs) = (q.to_vec(), v.clone());
        vec![
            aba(model, &mut data, q, &v, &tau).unwrap_err(),
            factorize_mass_matrix(model, &mut data, q).unwrap_err(),
            mass_matrix_inverse(model, &mut data, q).unwrap_err(),
            step(
                model,
                &mut data,
                Integrator::RungeKutta4,
                &mut qs,
                &mut vs,
                &tau,
                1e-3,
            )
            .unwrap_err(),
        ]
    }
    // Mass, inertia or centre of mass at the edge of f64: an overflow, or a loss of precision
    // that names the masses.
    for model in [
        two_links(1e308, DVec3::ZERO, 0.1, false),
        two_links(1.0, DVec3::ZERO, 1e308, false),
        two_links(1.0, DVec3::new(1e308, 0.0, 0.0), 0.1, false),
    ] {
        for e in every_path(&model, &[0.1, 0.2]) {
            let message = e.to_string();
            match e {
                DynamicsError::Overflow { .. } => {}
                DynamicsError::IllConditionedMassMatrix { masses, .. } => {
                    assert_eq!(masses[1], 1e308, "{message}");
                }
                other => panic!("expected an overflow or a loss of precision, got {other:?}"),
            }
            assert!(!message.contains("massless"), "{message}");
        }
    }
    // 1e300 kg on the axis of j2 (which moves only its 0.1 kg·m²) beside a 1 kg link.
    let model = two_links(1e300, DVec3::ZERO, 0.1, false);
    for e in every_path(&model, &[0.1, 0.2]) {
        let message = e.to_string();
        match e {
            DynamicsError::IllConditionedMassMatrix { joints, masses, .. } => {
                assert_eq!(joints, ["j2"]);
                assert_eq!(masses[1], 1e300);
            }
            other => panic!("expected a loss of precision, got {other:?}"),
        }
        assert!(message.contains("to 1.0e300 (kg, kg·m²)"), "{message}");
        assert!(!message.contains("massless"), "{message}");
    }
    // A 10 g finger slid out to 1e9 m, as in a simulation that has run away.
    let model = two_links(0.01, DVec3::ZERO, 1e-6, true);
    for e in every_path(&model, &[0.1, 1e9]) {
        let message = e.to_string();
        match e {
            DynamicsError::IllConditionedMassMatrix { joints, reach, .. } => {
                assert_eq!(joints, ["j2"]);
                // The finger's joint is 1 m out along x, then 1e9 m along it.
                assert!((reach - (1e9 + 1.0)).abs() < 1e-6, "{reach}");
            }
            other => panic!("expected a loss of precision, got {other:?}"),
        }
        assert!(message.contains("1.0e9 m from the origin"), "{message}");
    }
    // A zero or 1e300 quaternion is refused at the entry, naming the joint and the norm.
    let floating = every_kind(RootJoint::Floating);
    let mut data = DynamicsData::new(&floating);
    let v = vec![0.0; floating.nv()];
    for (w, norm) in [(0.0, "norm 0,"), (1e300, "norm 1e300,")] {
        let mut q = kinetree_dynamics::kinematics::configuration::neutral_configuration(&floating);
        q[6] = w;
        let e = aba(&floating, &mut data, &q, &v, &v).unwrap_err();
        assert!(e.to_string().contains(norm), "{e}");
        let e = factorize_mass_matrix(&floating, &mut data, &q).unwrap_err();
        assert!(e.to_string().contains(norm), "{e}");
    }
}

/// The derivatives report an overflow (finite inputs too large for f64 arithmetic) as an error,
/// never NaN in an `Ok` (the Python catalogue of hostile inputs found NaN for ±1e308 states of
/// the Panda, whose fingers slide out to 1e308 m).
#[test]
fn derivatives_of_overflowing_states_are_errors_not_nan() {
    use kinetree_dynamics::{
        DerivativesData, aba_derivatives, generalized_gravity_derivatives, rnea_derivatives,
    };
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/robots/panda.urdf"
    );
    let model = Model::from_urdf_file(path, RootJoint::Fixed).unwrap();
    let mut data = DerivativesData::new(&model);
    let nv = model.nv();
    let zero_q = kinetree_dynamics::kinematics::configuration::neutral_configuration(&model);
    let zero = vec![0.0; nv];
    let mut overflows = 0;
    for huge in [1e308, -1e308] {
        let (big_q, big) = (vec![huge; model.nq()], vec![huge; nv]);
        let mut check = |r: Result<Vec<&[f64]>, DynamicsError>| match r {
            Ok(outputs) => assert!(outputs.iter().all(|x| x.iter().all(|y| y.is_finite()))),
            Err(DynamicsError::Overflow { .. }) => overflows += 1,
            Err(e) => panic!("expected an overflow, got {e:?}"),
        };
        for (q, v, a) in [
            (&big_q, &zero, &zero),
            (&zero_q, &big, &zero),
            (&zero_q, &zero, &big),
        ] {
            check(
                rnea_derivatives(&model, &mut data, q, v, a)
                    .map(|d| vec![d.tau, d.dtau_dq, d.dtau_dv, d.dtau_da]),
            );
            check(
                aba_derivatives(&model, &mut data, q, v, a)
                    .map(|d| vec![d.ddq, d.dddq_dq, d.dddq_dv, d.dddq_dtau]),
            );
        }
        check(generalized_gravity_derivatives(&model, &mut data, &big_q).map(|d| vec![d]));
    }
    // The cases Python found (q, v and a at ±1e308 for RNEA, q for gravity, v and τ for ABA).
    assert!(overflows >= 12, "{overflows} overflows");
    // Finite results beyond the bound the sweep proves finiteness with (|entry| ≤ 1e300) are
    // scanned and returned, not refused: at |v| = 1e152 the Coriolis terms pass 1e300.
    for big in [1e152, -1e152] {
        let v = vec![big; nv];
        let d = rnea_derivatives(&model, &mut data, &zero_q, &v, &zero).unwrap();
        let largest = [d.tau, d.dtau_dq, d.dtau_dv, d.dtau_da]
            .iter()
            .flat_map(|x| x.iter())
            .fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(largest > 1e300 && largest.is_finite(), "{largest}");
    }
    // After the errors, the same data gives the results of a fresh one, bit for bit (the
    // entries that are always zero are never written).
    let q = vec![0.3; model.nq()];
    let (v, a) = (vec![0.5; nv], vec![-0.7; nv]);
    let mut fresh = DerivativesData::new(&model);
    let want = rnea_derivatives(&model, &mut fresh, &q, &v, &a).unwrap();
    let want = [want.tau, want.dtau_dq, want.dtau_dv, want.dtau_da].map(<[f64]>::to_vec);
    let got = rnea_derivatives(&model, &mut data, &q, &v, &a).unwrap();
    assert_eq!(
        [got.tau, got.dtau_dq, got.dtau_dv, got.dtau_da].map(<[f64]>::to_vec),
        want
    );
}
