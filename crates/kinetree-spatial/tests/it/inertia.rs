//! Spatial inertias: frame changes, momentum, energy and the 6x6 matrix form.

use crate::support::*;
use kinetree_spatial::Inertia;
use proptest::prelude::*;

proptest! {
    #![proptest_config(config())]

    #[test]
    fn transforming_an_inertia_commutes_with_momentum(i in inertia(), t in se3(), v in motion()) {
        // h_a = I_a v_a with v_a = X v_b must equal X* (I_b v_b).
        let lhs = i.transformed(&t).mul_motion(&t.act_motion(&v));
        let rhs = t.act_force(&i.mul_motion(&v));
        prop_assert!(lhs.abs_diff_eq(&rhs, 1e-11), "{:?} vs {:?}", lhs, rhs);
        // The same in matrix form: I_a = X* I_b X⁻¹.
        let ia = i.transformed(&t).to_matrix();
        let x_inv = t.inverse().to_action_matrix();
        let expected = mat6_mul(&mat6_mul(&t.to_dual_action_matrix(), &i.to_matrix()), &x_inv);
        prop_assert!(max_diff(&flat6(&ia), &flat6(&expected)) < 1e-11);
    }

    #[test]
    fn kinetic_energy_is_frame_independent_and_non_negative(i in inertia(), t in se3(), v in motion()) {
        let e = i.kinetic_energy(&v);
        prop_assert!(e >= 0.0);
        let e_a = i.transformed(&t).kinetic_energy(&t.act_motion(&v));
        prop_assert!((e - e_a).abs() < 1e-11 * (1.0 + e));
        // ½ vᵀ M v from the matrix.
        let mv = mat6_vec(&i.to_matrix(), v.to_array());
        let e_m: f64 = 0.5 * mv.iter().zip(v.to_array()).map(|(a, b)| a * b).sum::<f64>();
        prop_assert!((e - e_m).abs() < 1e-12 * (1.0 + e));
    }

    #[test]
    fn matrix_form_round_trips_and_is_symmetric(i in inertia()) {
        let m = i.to_matrix();
        prop_assert!(max_diff(&flat6(&m), &flat6(&transpose6(&m))) == 0.0);
        let back = Inertia::from_matrix(&m);
        prop_assert!((back.mass - i.mass).abs() < 1e-13);
        prop_assert!((back.com - i.com).length() < 1e-13);
        prop_assert!(max_diff(&back.rotational.to_urdf_array(), &i.rotational.to_urdf_array()) < 1e-13);
    }

    #[test]
    fn sums_and_frame_changes_commute(a in inertia(), b in inertia(), t in se3()) {
        let lhs = (a + b).transformed(&t).to_matrix();
        let rhs = (a.transformed(&t) + b.transformed(&t)).to_matrix();
        prop_assert!(max_diff(&flat6(&lhs), &flat6(&rhs)) < 1e-11);
        // The sum of two bodies is the sum of their matrices.
        let sum = (a + b).to_matrix();
        let (ma, mb) = (a.to_matrix(), b.to_matrix());
        let added: Vec<f64> = flat6(&ma).iter().zip(flat6(&mb)).map(|(x, y)| x + y).collect();
        prop_assert!(max_diff(&flat6(&sum), &added) < 1e-12);
        // transformed_inv undoes transformed.
        let back = a.transformed(&t).transformed_inv(&t);
        prop_assert!(max_diff(&flat6(&back.to_matrix()), &flat6(&a.to_matrix())) < 1e-12);
    }

    #[test]
    fn generated_inertias_are_physically_valid(i in inertia(), t in se3()) {
        prop_assert!(i.check(1e-9).is_ok());
        prop_assert!(i.transformed(&t).check(1e-9).is_ok());
    }
}

/// The `urdf` library's `InertiaTensor` examples: moments and products, the six entries, a 3x3
/// matrix and Voigt order all describe the same tensor, and read back the same.
#[test]
fn inertia_tensor_from_moments_products_matrix_and_voigt() {
    use kinetree_spatial::{DMat3, DVec3, InertiaTensor};
    let t = InertiaTensor::from_moments_products([0.05, 0.06, 0.03], [0.001, -0.002, 0.0]);
    assert_eq!(t.moments(), [0.05, 0.06, 0.03]);
    assert_eq!(t.products(), [0.001, -0.002, 0.0]);
    let m = DMat3::from_cols(
        DVec3::new(0.05, 0.001, -0.002),
        DVec3::new(0.001, 0.06, 0.0),
        DVec3::new(-0.002, 0.0, 0.03),
    );
    assert_eq!(t.to_mat3(), m);
    assert_eq!(InertiaTensor::from_mat3_checked(&m, 0.0).unwrap(), t);
    assert_eq!(
        InertiaTensor::from_entries(0.05, 0.001, -0.002, 0.06, 0.0, 0.03),
        t
    );
    // Voigt order [ixx, iyy, izz, iyz, ixz, ixy].
    assert_eq!(t.to_voigt(), [0.05, 0.06, 0.03, 0.0, -0.002, 0.001]);
    let v = InertiaTensor::from_voigt([0.05, 0.05, 0.08, 0.0, 0.0, 0.01]);
    assert_eq!(
        (v.moments(), v.products()),
        ([0.05, 0.05, 0.08], [0.01, 0.0, 0.0])
    );
    assert_eq!(
        InertiaTensor::from_moments_products(v.moments(), v.products()),
        v
    );
}
