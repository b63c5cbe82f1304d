//! The batched forward-dynamics derivatives against the one-state `aba_derivatives`, state by
//! state, on every reference robot and the every-joint-kind models, on every lane width, with
//! and without the joint terms; and their errors.

use crate::common::{SIMD, SIZES, all_models, assert_matrices_per_state, stacked_states as states};
use kinetree_dynamics::batch::{DerivativesBatch, aba_derivatives_batch};
use kinetree_dynamics::model::{Model, RootJoint};
use kinetree_dynamics::{DerivativesData, DynamicsError, JointTerms, aba_derivatives};

/// Asserts the batched matrices of the stacked states equal `aba_derivatives`, state by state,
/// bit for bit.
fn assert_one_state(
    model: &Model,
    data: &mut DerivativesData,
    stacked: (&[f64], &[f64], &[f64]),
    got: [&[f64]; 3],
    what: &str,
) {
    let names = ["dddq_dq", "dddq_dv", "dddq_dtau"];
    assert_matrices_per_state(model, stacked, got, names, what, |q, v, x| {
        let one = aba_derivatives(model, data, q, v, x).unwrap();
        [
            one.dddq_dq.to_vec(),
            one.dddq_dv.to_vec(),
            one.dddq_dtau.to_vec(),
        ]
    });
}

#[test]
fn batched_aba_derivatives_equal_the_one_state_ones_bit_for_bit() {
    for (name, model) in all_models() {
        let nv = model.nv();
        let nn = nv * nv;
        for terms in [JointTerms::Ignored, JointTerms::FromModel] {
            let mut data = DerivativesData::with_joint_terms(&model, terms);
            for simd in SIMD {
                let mut batch = DerivativesBatch::with_options(&model, terms, simd);
                for n in SIZES {
                    let (q, v, tau) = states(&model, n, 47 + n as u64);
                    // Garbage in the outputs: every entry must be written.
                    let (mut dq, mut dv, mut minv) = (
                        vec![f64::NAN; n * nn],
                        vec![7.0; n * nn],
                        vec![-1.0; n * nn],
                    );
                    // Twice: the second call finds the first one's values in the buffers.
                    for _ in 0..2 {
                        aba_derivatives_batch(
                            &model, &mut batch, &q, &v, &tau, &mut dq, &mut dv, &mut minv,
                        )
                        .unwrap();
                    }
                    let what = format!("{name} {terms:?} {simd:?} n={n}");
                    let outputs = [&dq[..], &dv[..], &minv[..]];
                    assert_one_state(&model, &mut data, (&q, &v, &tau), outputs, &what);
                }
            }
        }
    }
}

#[test]
fn batched_aba_derivatives_name_a_bad_state_as_one_call_would() {
    let (_, model) = all_models().remove(0);
    let (nq, nv) = (model.nq(), model.nv());
    let nn = nv * nv;
    let n = 9;
    let (q, v, tau) = states(&model, n, 5);
    let (mut dq, mut dv, mut minv) = (vec![0.0; n * nn], vec![0.0; n * nn], vec![0.0; n * nn]);
    let mut data = DerivativesData::new(&model);
    for simd in SIMD {
        let mut batch = DerivativesBatch::with_options(&model, JointTerms::Ignored, simd);
        // An infinite torque in state 6: the one-state error, wrapped with the index.
        let mut bad = tau.clone();
        bad[6 * nv + 1] = f64::INFINITY;
        let err = aba_derivatives_batch(
            &model, &mut batch, &q, &v, &bad, &mut dq, &mut dv, &mut minv,
        )
        .unwrap_err();
        let one = aba_derivatives(
            &model,
            &mut data,
            &q[6 * nq..7 * nq],
            &v[6 * nv..7 * nv],
            &bad[6 * nv..7 * nv],
        )
        .unwrap_err();
        assert!(
            matches!(&err, DynamicsError::InBatchState { index: 6, source } if format!("{source:?}") == format!("{one:?}")),
            "{err:?}"
        );
        assert!(
            matches!(
                one,
                DynamicsError::NonFinite {
                    what: "tau",
                    index: 1
                }
            ),
            "{one:?}"
        );
        // Lengths that are not whole states, and outputs of the wrong size.
        let err = aba_derivatives_batch(
            &model,
            &mut batch,
            &q,
            &v,
            &tau[1..],
            &mut dq,
            &mut dv,
            &mut minv,
        )
        .unwrap_err();
        assert!(
            matches!(err, DynamicsError::DimensionMismatch { what: "tau", .. }),
            "{err:?}"
        );
        let err = aba_derivatives_batch(
            &model,
            &mut batch,
            &q,
            &v,
            &tau,
            &mut dq,
            &mut dv,
            &mut minv[1..],
        )
        .unwrap_err();
        assert!(
            matches!(
                err,
                DynamicsError::DimensionMismatch {
                    what: "dddq_dtau",
                    ..
                }
            ),
            "{err:?}"
        );
    }
    // A batch built for another model.
    let other = all_models().pop().unwrap().1;
    let mut wrong = DerivativesBatch::new(&other);
    let err = aba_derivatives_batch(
        &model, &mut wrong, &q, &v, &tau, &mut dq, &mut dv, &mut minv,
    )
    .unwrap_err();
    assert!(matches!(err, DynamicsError::DataMismatch { .. }), "{err:?}");
}

/// Two links on revolute joints; the second link's mass is `mass2`.
fn two_links(mass2: f64) -> Model {
    let urdf = format!(
        r#"<robot name="arm"><link name="a"/>
          <link name="b"><inertial><origin xyz="0.5 0 0"/><mass value="2"/>
            <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <link name="c"><inertial><origin xyz="0.3 0 0"/><mass value="{mass2}"/>
            <inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
            <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
          <joint name="j2" type="revolute"><parent link="b"/><child link="c"/>
            <origin xyz="1 0 0"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
        </robot>"#
    );
    Model::from_urdf_str(&urdf, RootJoint::Fixed).unwrap()
}

/// A state whose derivatives overflow (finite inputs, a huge velocity) and a model whose mass
/// matrix is singular are named by the state's index with the one-state error, on every lane
/// width and in a partly filled block; the neighbours are fine.
#[test]
fn batched_aba_derivatives_name_an_overflowing_or_singular_state() {
    let n = 11;
    let q: Vec<f64> = (0..2 * n).map(|i| 0.1 * i as f64).collect();
    let tau = vec![0.5; 2 * n];
    let nn = 4;
    let (mut dq, mut dv, mut minv) = (vec![0.0; n * nn], vec![0.0; n * nn], vec![0.0; n * nn]);
    let mut v = vec![0.3; 2 * n];
    // v² overflows.
    v[2 * 9] = 1e200;
    let model = two_links(1.0);
    let mut data = DerivativesData::new(&model);
    let one = aba_derivatives(&model, &mut data, &q[18..20], &v[18..20], &tau[18..20]).unwrap_err();
    assert!(matches!(one, DynamicsError::Overflow { .. }), "{one:?}");
    // A massless last link: M is singular in every state, the first is named.
    let singular = two_links(0.0);
    let mut sdata = DerivativesData::new(&singular);
    let sone = aba_derivatives(&singular, &mut sdata, &q[..2], &v[..2], &tau[..2]).unwrap_err();
    assert!(
        matches!(&sone, DynamicsError::SingularMassMatrix { joints } if joints == &["j2"]),
        "{sone:?}"
    );
    for simd in SIMD {
        let mut batch = DerivativesBatch::with_options(&model, JointTerms::Ignored, simd);
        let err = aba_derivatives_batch(
            &model, &mut batch, &q, &v, &tau, &mut dq, &mut dv, &mut minv,
        )
        .unwrap_err();
        assert!(
            matches!(&err, DynamicsError::InBatchState { index: 9, source } if format!("{source:?}") == format!("{one:?}")),
            "{simd:?}: {err:?}"
        );
        // Without the bad state, every state is accepted.
        aba_derivatives_batch(
            &model,
            &mut batch,
            &q[..18],
            &v[..18],
            &tau[..18],
            &mut dq[..9 * nn],
            &mut dv[..9 * nn],
            &mut minv[..9 * nn],
        )
        .unwrap();
        let mut sbatch = DerivativesBatch::with_options(&singular, JointTerms::Ignored, simd);
        let err = aba_derivatives_batch(
            &singular,
            &mut sbatch,
            &q,
            &v,
            &tau,
            &mut dq,
            &mut dv,
            &mut minv,
        )
        .unwrap_err();
        assert!(
            matches!(&err, DynamicsError::InBatchState { index: 0, source } if format!("{source:?}") == format!("{sone:?}")),
            "{simd:?}: {err:?}"
        );
    }
}

#[test]
fn batched_aba_derivatives_of_a_large_tree_equal_the_one_state_ones() {
    // Above the size whose solves run in lanes (nv > 64), the batch runs one state at a time:
    // a branched tree of every joint kind with a floating base, with the joint terms.
    let model =
        kinetree_dynamics::model::samples::random_tree_with_root(11, 60, RootJoint::Floating);
    let nv = model.nv();
    assert!(nv > 64, "nv = {nv}");
    let nn = nv * nv;
    let mut data = DerivativesData::with_joint_terms(&model, JointTerms::FromModel);
    let mut batch = DerivativesBatch::with_joint_terms(&model, JointTerms::FromModel);
    let n = 3;
    let (q, v, tau) = states(&model, n, 5);
    let (mut dq, mut dv, mut minv) = (
        vec![f64::NAN; n * nn],
        vec![f64::NAN; n * nn],
        vec![f64::NAN; n * nn],
    );
    aba_derivatives_batch(
        &model, &mut batch, &q, &v, &tau, &mut dq, &mut dv, &mut minv,
    )
    .unwrap();
    let outputs = [&dq[..], &dv[..], &minv[..]];
    assert_one_state(&model, &mut data, (&q, &v, &tau), outputs, "large tree");
}
