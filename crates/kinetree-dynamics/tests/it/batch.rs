//! The batched entry points (`kinetree_kinematics::batch`, `kinetree_dynamics::batch`) against
//! the one-state algorithms, state by state, on every reference robot and a model with every
//! joint kind (fixed and floating root) and a placed free joint, for batch sizes that do and do not fill the SIMD lanes.

use crate::common::{SIMD, SIZES, all_models, stacked_states as states};
use kinetree_dynamics::batch::{DynamicsBatch, aba_batch, crba_batch, rnea_batch};
use kinetree_dynamics::kinematics::batch::{
    KinematicsBatch, forward_kinematics_batch, forward_kinematics_matrices_batch,
    frame_jacobian_batch, frame_jacobian_rows_batch,
};
use kinetree_dynamics::kinematics::{
    KinematicsData, KinematicsError, compute_frame_jacobian, forward_kinematics,
    update_frame_placements,
};
use kinetree_dynamics::model::{JointDynamics, JointKind, JointSpec, Link, Model, ModelBuilder};
use kinetree_dynamics::spatial::glam::DVec3;
use kinetree_dynamics::spatial::{Motion, Se3, Symmetric3};
use kinetree_dynamics::{
    DynamicsData, DynamicsError, FrameId, JointTerms, ReferenceFrame, aba, crba, rnea,
};

/// Relative agreement required of every batched result with the one-state one.
const TOL: f64 = 1e-14;

/// Asserts `got` equals `want` to [`TOL`] relative to `want`'s largest entry.
fn assert_rel(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}");
    let scale = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() <= TOL * scale,
            "{what}[{i}]: batched {g:e}, one-state {w:e} (scale {scale:e})"
        );
    }
}

/// Asserts `got` equals `want` exactly (`==`, so a zero's sign may differ): the lane kernels
/// repeat the one-state arithmetic in the same order, and the Python package promises that a
/// stacked call equals one-by-one calls bit for bit.
fn assert_exact(got: &[f64], want: &[f64], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(g == w, "{what}[{i}]: batched {g:e}, one-state {w:e}");
    }
}

fn se3_numbers(xs: &[Se3]) -> Vec<f64> {
    xs.iter()
        .flat_map(|x| {
            let mut v = x.rotation.to_cols_array().to_vec();
            v.extend(x.translation.to_array());
            v
        })
        .collect()
}

fn motion_numbers(xs: &[Motion]) -> Vec<f64> {
    xs.iter().flat_map(Motion::to_array).collect()
}

#[test]
fn batched_kinematics_equals_the_one_state_path() {
    for (name, model) in models() {
        let (nq, nv, nl, nf) = (
            model.nq(),
            model.nv(),
            model.links().len(),
            model.frames().len(),
        );
        for simd in SIMD {
            let mut batch = KinematicsBatch::with_simd(&model, simd);
            let mut data = KinematicsData::new(&model);
            let mut column = vec![Motion::ZERO; nv];
            let targets = [FrameId::Link(nl - 1), FrameId::Link(nl / 2)]
                .into_iter()
                .chain((nf > 0).then(|| FrameId::Frame(nf - 1)));
            let targets: Vec<FrameId> = targets.collect();
            for n in SIZES {
                let (q, _, _) = states(&model, n, 11 + n as u64);
                let mut links = vec![Se3::IDENTITY; n * nl];
                let mut frames = vec![Se3::IDENTITY; n * nf];
                forward_kinematics_batch(&model, &mut batch, &q, &mut links, Some(&mut frames))
                    .unwrap();
                // Every link as 4 x 4 matrices, and a selection (the last link, the root, the
                // last again), from NaN-filled buffers so that a number left unwritten shows.
                let mut all = vec![f64::NAN; n * nl * 16];
                forward_kinematics_matrices_batch(&model, &mut batch, &q, None, &mut all).unwrap();
                let pick = [nl - 1, 0, nl - 1];
                let mut picked = vec![f64::NAN; n * pick.len() * 16];
                forward_kinematics_matrices_batch(&model, &mut batch, &q, Some(&pick), &mut picked)
                    .unwrap();
                for k in 0..n {
                    forward_kinematics(&model, &mut data, &q[k * nq..(k + 1) * nq]).unwrap();
                    update_frame_placements(&model, &mut data).unwrap();
                    let what = format!("{name} {simd:?} n={n} state {k}");
                    assert_exact(
                        &se3_numbers(&links[k * nl..(k + 1) * nl]),
                        &se3_numbers(data.world_from_link()),
                        &format!("{what} links"),
                    );
                    assert_exact(
                        &se3_numbers(&frames[k * nf..(k + 1) * nf]),
                        &se3_numbers(data.world_from_frame()),
                        &format!("{what} frames"),
                    );
                    let homogeneous = |x: &Se3| x.to_mat4().transpose().to_cols_array();
                    let want: Vec<f64> = data
                        .world_from_link()
                        .iter()
                        .flat_map(homogeneous)
                        .collect();
                    assert_exact(
                        &all[k * nl * 16..(k + 1) * nl * 16],
                        &want,
                        &format!("{what} matrices"),
                    );
                    let want: Vec<f64> = pick
                        .iter()
                        .flat_map(|&l| homogeneous(&data.world_from_link()[l]))
                        .collect();
                    assert_exact(
                        &picked[k * 48..(k + 1) * 48],
                        &want,
                        &format!("{what} picked matrices"),
                    );
                }
                for &frame in &targets {
                    for reference in [
                        ReferenceFrame::World,
                        ReferenceFrame::Local,
                        ReferenceFrame::LocalWorldAligned,
                    ] {
                        let mut jac = vec![Motion::ZERO; n * nv];
                        frame_jacobian_batch(&model, &mut batch, &q, frame, reference, &mut jac)
                            .unwrap();
                        // NaN where the rows form would leave a number unwritten.
                        let mut rows = vec![f64::NAN; n * 6 * nv];
                        frame_jacobian_rows_batch(
                            &model, &mut batch, &q, frame, reference, &mut rows,
                        )
                        .unwrap();
                        for k in 0..n {
                            let qk = &q[k * nq..(k + 1) * nq];
                            compute_frame_jacobian(
                                &model,
                                &mut data,
                                qk,
                                frame,
                                reference,
                                &mut column,
                            )
                            .unwrap();
                            assert_exact(
                                &motion_numbers(&jac[k * nv..(k + 1) * nv]),
                                &motion_numbers(&column),
                                &format!(
                                    "{name} {simd:?} n={n} state {k} jacobian {frame:?} {reference:?}"
                                ),
                            );
                            // Row r of the matrix is component r of every column.
                            let transposed: Vec<f64> = (0..6)
                                .flat_map(|r| column.iter().map(move |c| c.to_array()[r]))
                                .collect();
                            assert_exact(
                                &rows[k * 6 * nv..(k + 1) * 6 * nv],
                                &transposed,
                                &format!(
                                    "{name} {simd:?} n={n} state {k} jacobian rows {frame:?} {reference:?}"
                                ),
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn batched_dynamics_equals_the_one_state_path() {
    for (name, model) in models() {
        let (nq, nv) = (model.nq(), model.nv());
        for simd in SIMD {
            let mut batch = DynamicsBatch::with_options(&model, JointTerms::Ignored, simd);
            let mut terms = DynamicsBatch::with_options(&model, JointTerms::FromModel, simd);
            let mut data = DynamicsData::new(&model);
            let mut data_terms = DynamicsData::with_joint_terms(&model, JointTerms::FromModel);
            for n in SIZES {
                let (q, v, a) = states(&model, n, 23 + n as u64);
                let mut tau = vec![0.0; n * nv];
                rnea_batch(&model, &mut batch, &q, &v, &a, &mut tau).unwrap();
                let mut ddq = vec![0.0; n * nv];
                aba_batch(&model, &mut batch, &q, &v, &tau, &mut ddq).unwrap();
                let mut mass = vec![0.0; n * nv * nv];
                crba_batch(&model, &mut batch, &q, &mut mass).unwrap();
                for k in 0..n {
                    let (qk, vk, ak) = (
                        &q[k * nq..(k + 1) * nq],
                        &v[k * nv..(k + 1) * nv],
                        &a[k * nv..(k + 1) * nv],
                    );
                    let what = format!("{name} {simd:?} n={n} state {k}");
                    let t = rnea(&model, &mut data, qk, vk, ak).unwrap().to_vec();
                    assert_rel(&tau[k * nv..(k + 1) * nv], &t, &format!("{what} rnea"));
                    assert_exact(&tau[k * nv..(k + 1) * nv], &t, &format!("{what} rnea"));
                    let d = aba(&model, &mut data, qk, vk, &t).unwrap();
                    assert_rel(&ddq[k * nv..(k + 1) * nv], d, &format!("{what} aba"));
                    assert_exact(&ddq[k * nv..(k + 1) * nv], d, &format!("{what} aba"));
                    // And the round trip closes: ABA of RNEA's torques gives back a.
                    for (x, y) in d.iter().zip(ak) {
                        assert!((x - y).abs() < 1e-6 * (1.0 + y.abs()), "{what} aba∘rnea");
                    }
                    let m = crba(&model, &mut data, qk).unwrap();
                    let nn = nv * nv;
                    assert_rel(&mass[k * nn..(k + 1) * nn], m, &format!("{what} crba"));
                    assert_exact(&mass[k * nn..(k + 1) * nn], m, &format!("{what} crba"));
                }
                // With the joints' armature, damping and friction.
                rnea_batch(&model, &mut terms, &q, &v, &a, &mut tau).unwrap();
                aba_batch(&model, &mut terms, &q, &v, &a, &mut ddq).unwrap();
                crba_batch(&model, &mut terms, &q, &mut mass).unwrap();
                for k in 0..n {
                    let r = k * nv..(k + 1) * nv;
                    let (qk, vk) = (&q[k * nq..(k + 1) * nq], &v[r.clone()]);
                    let what = format!("{name} {simd:?} n={n} state {k} with joint terms");
                    let t = rnea(&model, &mut data_terms, qk, vk, &a[r.clone()]).unwrap();
                    assert_rel(&tau[r.clone()], t, &format!("{what} rnea"));
                    let d = aba(&model, &mut data_terms, qk, vk, &a[r.clone()]).unwrap();
                    assert_exact(&ddq[r], d, &format!("{what} aba"));
                    let nn = nv * nv;
                    let m = crba(&model, &mut data_terms, qk).unwrap();
                    assert_exact(&mass[k * nn..(k + 1) * nn], m, &format!("{what} crba"));
                }
            }
        }
    }
}

/// A hinge carrying a mass, and a massless hinge on it (with armature, which
/// `JointTerms::FromModel` adds to its pivot).
/// Every model of [`all_models`], and one with a free-floating joint whose placement is not the
/// identity (the lane kernel of a free joint applies the placement only then).
fn models() -> Vec<(String, Model)> {
    let mut b = ModelBuilder::new("placed_floating");
    b.add_link(Link::new("base"));
    let inertia = Symmetric3::new(0.01, 0.001, -0.002, 0.02, 0.003, 0.03);
    b.add_part(
        Link::new("arm").with_mass(1.5, DVec3::new(0.3, 0.0, 0.0), inertia),
        JointSpec::new("shoulder", JointKind::Revolute, "base", "arm").with_axis(DVec3::Y),
    );
    b.add_part(
        Link::new("drone").with_mass(0.7, DVec3::new(0.0, 0.1, -0.05), inertia),
        JointSpec::new("free", JointKind::Floating, "arm", "drone")
            .with_placement(Se3::from_xyz_rpy([0.6, -0.1, 0.2], [0.3, -0.4, 0.5])),
    );
    b.add_part(
        Link::new("tip").with_mass(0.2, DVec3::new(0.05, 0.0, 0.0), inertia),
        JointSpec::new("wrist", JointKind::Revolute, "drone", "tip").with_axis(DVec3::X),
    );
    let mut out = all_models();
    out.push(("placed_floating".into(), b.build().unwrap()));
    out
}

#[test]
fn batched_crba_of_a_large_tree_equals_the_one_state_path() {
    // Above the size whose block of matrices is assembled in lanes (nv > 64), each state's
    // matrix is written from the list of entries: a branched tree of every joint kind, with a
    // floating base.
    let model = kinetree_dynamics::model::samples::random_tree_with_root(
        7,
        60,
        kinetree_dynamics::model::RootJoint::Floating,
    );
    let (nq, nv) = (model.nq(), model.nv());
    assert!(nv > 64, "nv = {nv}");
    let mut data = DynamicsData::new(&model);
    for simd in SIMD {
        let mut batch = DynamicsBatch::with_options(&model, JointTerms::Ignored, simd);
        for n in [1, 9] {
            let (q, _, _) = states(&model, n, 31 + n as u64);
            let mut mass = vec![f64::NAN; n * nv * nv];
            crba_batch(&model, &mut batch, &q, &mut mass).unwrap();
            for k in 0..n {
                let m = crba(&model, &mut data, &q[k * nq..(k + 1) * nq]).unwrap();
                let nn = nv * nv;
                let what = format!("{simd:?} n={n} state {k} crba");
                assert_exact(&mass[k * nn..(k + 1) * nn], m, &what);
            }
        }
    }
}

fn massless_leaf() -> Model {
    let mut b = ModelBuilder::new("massless_leaf");
    b.add_link(Link::new("base"));
    let inertia = Symmetric3::new(0.01, 0.0, 0.0, 0.02, 0.0, 0.03);
    b.add_part(
        Link::new("arm").with_mass(1.5, DVec3::new(0.3, 0.0, 0.0), inertia),
        JointSpec::new("shoulder", JointKind::Revolute, "base", "arm").with_axis(DVec3::Y),
    );
    let dynamics = JointDynamics {
        damping: 0.1,
        friction: 0.2,
        armature: 0.05,
    };
    b.add_part(
        Link::new("tip"),
        JointSpec::new("finger", JointKind::Revolute, "arm", "tip")
            .with_axis(DVec3::Z)
            .with_placement(Se3::from_translation(DVec3::new(0.6, 0.0, 0.0)))
            .with_dynamics(dynamics),
    );
    b.build().unwrap()
}

#[test]
fn a_bad_state_is_named_by_its_index_and_bad_lengths_are_errors() {
    let (_, model) = all_models().remove(0);
    let (nq, nv) = (model.nq(), model.nv());
    let n = 9;
    let (mut q, v, a) = states(&model, n, 5);
    q[6 * nq] = f64::NAN;
    let mut links = vec![Se3::IDENTITY; n * model.links().len()];
    let mut batch = KinematicsBatch::new(&model);
    let err = forward_kinematics_batch(&model, &mut batch, &q, &mut links, None).unwrap_err();
    assert!(
        matches!(&err, KinematicsError::InBatchState { index: 6, source } if matches!(**source, KinematicsError::NonFinite { what: "q", index: 0 })),
        "{err:?}"
    );
    // The Jacobian's rows form names the same state, and a buffer of columns' length is refused.
    let mut rows = vec![0.0; n * 6 * nv];
    let last = FrameId::Link(model.links().len() - 1);
    let err = frame_jacobian_rows_batch(
        &model,
        &mut batch,
        &q,
        last,
        ReferenceFrame::World,
        &mut rows,
    )
    .unwrap_err();
    assert!(
        matches!(&err, KinematicsError::InBatchState { index: 6, source } if matches!(**source, KinematicsError::NonFinite { what: "q", index: 0 })),
        "{err:?}"
    );
    let err = frame_jacobian_rows_batch(
        &model,
        &mut batch,
        &q,
        last,
        ReferenceFrame::World,
        &mut rows[..n * nv],
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            KinematicsError::DimensionMismatch {
                what: "jacobian",
                ..
            }
        ),
        "{err:?}"
    );
    // The matrices form names the same state, a link the model does not have, and a buffer of
    // the wrong length.
    let nl = model.links().len();
    let mut matrices = vec![0.0; n * 2 * 16];
    let err =
        forward_kinematics_matrices_batch(&model, &mut batch, &q, Some(&[0, 1]), &mut matrices)
            .unwrap_err();
    assert!(
        matches!(&err, KinematicsError::InBatchState { index: 6, source } if matches!(**source, KinematicsError::NonFinite { what: "q", index: 0 })),
        "{err:?}"
    );
    let err =
        forward_kinematics_matrices_batch(&model, &mut batch, &q, Some(&[0, nl]), &mut matrices)
            .unwrap_err();
    assert!(
        matches!(err, KinematicsError::FrameOutOfRange { what: "link", index, count } if index == nl && count == nl),
        "{err:?}"
    );
    let err =
        forward_kinematics_matrices_batch(&model, &mut batch, &q, None, &mut matrices).unwrap_err();
    assert!(
        matches!(
            err,
            KinematicsError::DimensionMismatch {
                what: "matrices",
                ..
            }
        ),
        "{err:?}"
    );
    let mut dynamics = DynamicsBatch::new(&model);
    let mut tau = vec![0.0; n * nv];
    let err = rnea_batch(&model, &mut dynamics, &q, &v, &a, &mut tau).unwrap_err();
    assert!(
        matches!(&err, DynamicsError::InBatchState { index: 6, .. }),
        "{err:?}"
    );
    // A q that is not a whole number of states, and outputs of the wrong size.
    let err = forward_kinematics_batch(&model, &mut batch, &q[1..], &mut links, None).unwrap_err();
    assert!(
        matches!(err, KinematicsError::DimensionMismatch { what: "q", .. }),
        "{err:?}"
    );
    let err = forward_kinematics_batch(&model, &mut batch, &q, &mut links[1..], None).unwrap_err();
    assert!(
        matches!(
            err,
            KinematicsError::DimensionMismatch {
                what: "world_from_link",
                ..
            }
        ),
        "{err:?}"
    );
    let err = rnea_batch(&model, &mut dynamics, &q, &v, &a[1..], &mut tau).unwrap_err();
    assert!(
        matches!(err, DynamicsError::DimensionMismatch { what: "a", .. }),
        "{err:?}"
    );
    let mut short = vec![0.0; n * nv - 1];
    let err = aba_batch(&model, &mut dynamics, &q, &v, &a, &mut short).unwrap_err();
    assert!(
        matches!(err, DynamicsError::DimensionMismatch { what: "ddq", .. }),
        "{err:?}"
    );
    // A state whose tau is not finite, and ABA of a model with a massless subtree: the
    // one-state function's error, for the first such state.
    let mut bad_tau = a.clone();
    bad_tau[4 * nv + 1] = f64::INFINITY;
    let mut ddq = vec![0.0; n * nv];
    let err = aba_batch(&model, &mut dynamics, &q[..], &v, &bad_tau, &mut ddq).unwrap_err();
    assert!(
        matches!(&err, DynamicsError::InBatchState { index: 4, source } if matches!(**source, DynamicsError::NonFinite { what: "tau", index: 1 })),
        "{err:?}"
    );
    let massless = massless_leaf();
    let mut dynamics = DynamicsBatch::new(&massless);
    let q = [0.1, 0.2, 0.3, -0.4, 0.5, 0.6, 0.7, 0.8, -0.9, 1.0];
    let mut ddq = [0.0; 10];
    for simd in SIMD {
        let mut wide = DynamicsBatch::with_options(&massless, JointTerms::Ignored, simd);
        aba_batch(&massless, &mut wide, &q, &q, &q, &mut ddq).unwrap_err();
    }
    let err = aba_batch(&massless, &mut dynamics, &q, &q, &q, &mut ddq).unwrap_err();
    assert!(
        matches!(&err, DynamicsError::InBatchState { index: 0, source } if matches!(&**source, DynamicsError::SingularMassMatrix { joints } if joints == &["finger"])),
        "{err:?}"
    );
    // With the massless leaf locked by armature, every state is regular.
    let mut terms = DynamicsBatch::with_joint_terms(&massless, JointTerms::FromModel);
    aba_batch(&massless, &mut terms, &q, &q, &q, &mut ddq).unwrap();
    let mut data = DynamicsData::with_joint_terms(&massless, JointTerms::FromModel);
    for k in 0..5 {
        let r = 2 * k..2 * k + 2;
        let d = aba(
            &massless,
            &mut data,
            &q[r.clone()],
            &q[r.clone()],
            &q[r.clone()],
        )
        .unwrap();
        assert_exact(
            &ddq[r],
            d,
            &format!("massless leaf with armature, state {k}"),
        );
    }
    // A batch built for another model.
    let other = all_models().pop().unwrap().1;
    let mut wrong = DynamicsBatch::new(&other);
    let err = rnea_batch(&model, &mut wrong, &q, &v, &a, &mut tau).unwrap_err();
    assert!(matches!(err, DynamicsError::DataMismatch { .. }), "{err:?}");
}

/// The batched CRBA's overflow check (a probe summed in the lanes): a state whose mass matrix
/// overflows is named by its index, on every lane width and in a partly filled block, and
/// finite entries whose sum overflows the probe are still accepted.
#[test]
fn batched_crba_names_an_overflowing_state_and_accepts_finite_huge_entries() {
    // A turn about z carrying a 1e150 kg slider along x: M₀₀ = m·x², which overflows at x = 1e80.
    let slider = Model::from_urdf_str(
        r#"<robot name="slider"><link name="a"/><link name="b"/>
          <link name="c"><inertial><mass value="1e150"/>
            <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <joint name="turn" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
          <joint name="slide" type="prismatic"><parent link="b"/><child link="c"/><axis xyz="1 0 0"/>
            <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
        </robot>"#,
        kinetree_dynamics::model::RootJoint::Fixed,
    )
    .unwrap();
    // Two prismatic branches of 1.5e308 kg each: the diagonal is finite, its sum is not.
    let branches = Model::from_urdf_str(
        r#"<robot name="r"><link name="a"/>
          <link name="b"><inertial><mass value="1.5e308"/>
            <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <link name="c"><inertial><mass value="1.5e308"/>
            <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <joint name="j1" type="prismatic"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/>
            <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
          <joint name="j2" type="prismatic"><parent link="a"/><child link="c"/><axis xyz="0 1 0"/>
            <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
        </robot>"#,
        kinetree_dynamics::model::RootJoint::Fixed,
    )
    .unwrap();
    for simd in SIMD {
        for (n, bad) in [(3, 2), (9, 6), (9, 8)] {
            let mut q: Vec<f64> = (0..n).flat_map(|k| [0.1 * k as f64, 0.5]).collect();
            q[2 * bad + 1] = 1e80;
            let mut batch = DynamicsBatch::with_options(&slider, JointTerms::Ignored, simd);
            let mut mass = vec![0.0; n * 4];
            let err = crba_batch(&slider, &mut batch, &q, &mut mass).unwrap_err();
            assert!(
                matches!(&err, DynamicsError::InBatchState { index, source } if *index == bad && matches!(&**source, DynamicsError::Overflow { joint, .. } if joint == "turn")),
                "{simd:?} n={n}: {err:?}"
            );
            q[2 * bad + 1] = 0.5;
            mass.fill(f64::NAN);
            crba_batch(&slider, &mut batch, &q, &mut mass).unwrap();
            let mut data = DynamicsData::new(&slider);
            for (k, m) in mass.chunks(4).enumerate() {
                assert_eq!(m, crba(&slider, &mut data, &q[2 * k..2 * k + 2]).unwrap());
            }
            assert!(mass[3] == 1e150 && mass[1] == 0.0, "{mass:?}");
        }
        let mut batch = DynamicsBatch::with_options(&branches, JointTerms::Ignored, simd);
        let q = [0.5, -0.5, 0.1, 0.2, -0.3, 0.4];
        let mut mass = [f64::NAN; 12];
        crba_batch(&branches, &mut batch, &q, &mut mass).unwrap();
        assert!(
            mass.chunks(4).all(|m| m == [1.5e308, 0.0, 0.0, 1.5e308]),
            "{mass:?}"
        );
    }
}
