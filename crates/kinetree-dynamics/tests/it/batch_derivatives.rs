//! The batched inverse-dynamics derivatives against the one-state `rnea_derivatives`, state by
//! state, on every reference robot and the every-joint-kind models, on every lane width, with
//! and without the joint terms; and their errors.

use crate::common::{SIMD, SIZES, all_models, assert_matrices_per_state, stacked_states as states};
use kinetree_dynamics::batch::{DerivativesBatch, rnea_derivatives_batch};
use kinetree_dynamics::model::{Model, RootJoint};
use kinetree_dynamics::{DerivativesData, DynamicsError, JointTerms, rnea_derivatives};

/// Asserts the batched matrices of the stacked states equal `rnea_derivatives`, state by state,
/// bit for bit.
fn assert_one_state(
    model: &Model,
    data: &mut DerivativesData,
    stacked: (&[f64], &[f64], &[f64]),
    got: [&[f64]; 3],
    what: &str,
) {
    let names = ["dtau_dq", "dtau_dv", "dtau_da"];
    assert_matrices_per_state(model, stacked, got, names, what, |q, v, x| {
        let one = rnea_derivatives(model, data, q, v, x).unwrap();
        [
            one.dtau_dq.to_vec(),
            one.dtau_dv.to_vec(),
            one.dtau_da.to_vec(),
        ]
    });
}

#[test]
fn batched_rnea_derivatives_equal_the_one_state_ones_bit_for_bit() {
    for (name, model) in all_models() {
        let nv = model.nv();
        let nn = nv * nv;
        for terms in [JointTerms::Ignored, JointTerms::FromModel] {
            let mut data = DerivativesData::with_joint_terms(&model, terms);
            for simd in SIMD {
                let mut batch = DerivativesBatch::with_options(&model, terms, simd);
                for n in SIZES {
                    let (q, v, a) = states(&model, n, 31 + n as u64);
                    // Garbage in the outputs: every entry must be written.
                    let (mut dq, mut dv, mut da) = (
                        vec![f64::NAN; n * nn],
                        vec![7.0; n * nn],
                        vec![-1.0; n * nn],
                    );
                    rnea_derivatives_batch(
                        &model, &mut batch, &q, &v, &a, &mut dq, &mut dv, &mut da,
                    )
                    .unwrap();
                    let what = format!("{name} {terms:?} {simd:?} n={n}");
                    let outputs = [&dq[..], &dv[..], &da[..]];
                    assert_one_state(&model, &mut data, (&q, &v, &a), outputs, &what);
                }
            }
        }
    }
}

#[test]
fn batched_rnea_derivatives_name_a_bad_state_as_one_call_would() {
    let (_, model) = all_models().remove(0);
    let (nq, nv) = (model.nq(), model.nv());
    let nn = nv * nv;
    let n = 9;
    let (q, v, a) = states(&model, n, 5);
    let (mut dq, mut dv, mut da) = (vec![0.0; n * nn], vec![0.0; n * nn], vec![0.0; n * nn]);
    let mut data = DerivativesData::new(&model);
    for simd in SIMD {
        let mut batch = DerivativesBatch::with_options(&model, JointTerms::Ignored, simd);
        // A NaN velocity in state 6: the one-state error, wrapped with the index.
        let mut bad = v.clone();
        bad[6 * nv + 1] = f64::NAN;
        let err =
            rnea_derivatives_batch(&model, &mut batch, &q, &bad, &a, &mut dq, &mut dv, &mut da)
                .unwrap_err();
        let one = rnea_derivatives(
            &model,
            &mut data,
            &q[6 * nq..7 * nq],
            &bad[6 * nv..7 * nv],
            &a[6 * nv..7 * nv],
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
                    what: "v",
                    index: 1
                }
            ),
            "{one:?}"
        );
        // Lengths that are not whole states, and outputs of the wrong size.
        let err = rnea_derivatives_batch(
            &model,
            &mut batch,
            &q,
            &v,
            &a[1..],
            &mut dq,
            &mut dv,
            &mut da,
        )
        .unwrap_err();
        assert!(
            matches!(err, DynamicsError::DimensionMismatch { what: "a", .. }),
            "{err:?}"
        );
        let err = rnea_derivatives_batch(
            &model,
            &mut batch,
            &q,
            &v,
            &a,
            &mut dq,
            &mut dv[1..],
            &mut da,
        )
        .unwrap_err();
        assert!(
            matches!(
                err,
                DynamicsError::DimensionMismatch {
                    what: "dtau_dv",
                    ..
                }
            ),
            "{err:?}"
        );
    }
    // A batch built for another model.
    let other = all_models().pop().unwrap().1;
    let mut wrong = DerivativesBatch::new(&other);
    let err = rnea_derivatives_batch(&model, &mut wrong, &q, &v, &a, &mut dq, &mut dv, &mut da)
        .unwrap_err();
    assert!(matches!(err, DynamicsError::DataMismatch { .. }), "{err:?}");
}

/// A state whose derivatives overflow (finite inputs, a huge velocity) is named by its index
/// with the one-state error, on every lane width and in a partly filled block; its neighbours
/// are fine.
#[test]
fn batched_rnea_derivatives_name_an_overflowing_state() {
    let model = Model::from_urdf_str(
        r#"<robot name="arm"><link name="a"/>
          <link name="b"><inertial><origin xyz="0.5 0 0"/><mass value="2"/>
            <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <link name="c"><inertial><origin xyz="0.3 0 0"/><mass value="1"/>
            <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
          <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
            <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
          <joint name="j2" type="revolute"><parent link="b"/><child link="c"/>
            <origin xyz="1 0 0"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
        </robot>"#,
        RootJoint::Fixed,
    )
    .unwrap();
    let n = 11;
    let q: Vec<f64> = (0..2 * n).map(|i| 0.1 * i as f64).collect();
    let a = vec![0.5; 2 * n];
    let mut v = vec![0.3; 2 * n];
    // v² overflows.
    v[2 * 9] = 1e200;
    let mut data = DerivativesData::new(&model);
    let one = rnea_derivatives(&model, &mut data, &q[18..20], &v[18..20], &a[18..20]).unwrap_err();
    assert!(matches!(one, DynamicsError::Overflow { .. }), "{one:?}");
    let nn = 4;
    let (mut dq, mut dv, mut da) = (vec![0.0; n * nn], vec![0.0; n * nn], vec![0.0; n * nn]);
    for simd in SIMD {
        let mut batch = DerivativesBatch::with_options(&model, JointTerms::Ignored, simd);
        let err = rnea_derivatives_batch(&model, &mut batch, &q, &v, &a, &mut dq, &mut dv, &mut da)
            .unwrap_err();
        assert!(
            matches!(&err, DynamicsError::InBatchState { index: 9, source } if format!("{source:?}") == format!("{one:?}")),
            "{simd:?}: {err:?}"
        );
        // Without the bad state, every state is accepted.
        rnea_derivatives_batch(
            &model,
            &mut batch,
            &q[..18],
            &v[..18],
            &a[..18],
            &mut dq[..9 * nn],
            &mut dv[..9 * nn],
            &mut da[..9 * nn],
        )
        .unwrap();
    }
}

#[test]
fn batched_rnea_derivatives_of_a_large_tree_equal_the_one_state_ones() {
    // Above the size whose matrices are assembled in lanes (nv > 64), each entry goes straight
    // to its state's place: a branched tree of every joint kind with a floating base, with the
    // joint terms, on every lane width.
    let model =
        kinetree_dynamics::model::samples::random_tree_with_root(7, 60, RootJoint::Floating);
    let nv = model.nv();
    assert!(nv > 64, "nv = {nv}");
    let nn = nv * nv;
    let mut data = DerivativesData::with_joint_terms(&model, JointTerms::FromModel);
    for simd in SIMD {
        let mut batch = DerivativesBatch::with_options(&model, JointTerms::FromModel, simd);
        let n = 9;
        let (q, v, a) = states(&model, n, 3);
        let (mut dq, mut dv, mut da) = (
            vec![f64::NAN; n * nn],
            vec![f64::NAN; n * nn],
            vec![f64::NAN; n * nn],
        );
        rnea_derivatives_batch(&model, &mut batch, &q, &v, &a, &mut dq, &mut dv, &mut da).unwrap();
        let outputs = [&dq[..], &dv[..], &da[..]];
        let what = format!("{simd:?}");
        assert_one_state(&model, &mut data, (&q, &v, &a), outputs, &what);
    }
}
