//! Rigid transforms: group laws, agreement with 4x4 and 6x6 matrix forms.

use crate::support::*;
use kinetree_spatial::{DVec3, Se3};
use proptest::prelude::*;

proptest! {
    #![proptest_config(config())]

    #[test]
    fn transform_times_inverse_is_identity(t in se3()) {
        let id = flat_se3(&Se3::IDENTITY);
        prop_assert!(max_diff(&flat_se3(&(t * t.inverse())), &id) < 1e-14);
        prop_assert!(max_diff(&flat_se3(&(t.inverse() * t)), &id) < 1e-14);
        prop_assert!(max_diff(&flat_se3(&t.inv_mul(&t)), &id) < 1e-14);
        prop_assert!(max_diff(&flat_se3(&t.inverse().inverse()), &flat_se3(&t)) < 1e-14);
    }

    #[test]
    fn composition_is_the_homogeneous_matrix_product(a in se3(), b in se3(), c in se3(), p in vec3(3.0)) {
        let ab = a * b;
        let product = a.to_mat4() * b.to_mat4();
        prop_assert!(max_diff(&ab.to_mat4().to_cols_array(), &product.to_cols_array()) < 1e-14);
        // Associative, and inv_mul is inverse-then-compose.
        prop_assert!(max_diff(&flat_se3(&((a * b) * c)), &flat_se3(&(a * (b * c)))) < 1e-13);
        prop_assert!(max_diff(&flat_se3(&a.inv_mul(&b)), &flat_se3(&(a.inverse() * b))) < 1e-14);
        // Points: a_from_c = a_from_b * b_from_c applied right to left.
        let lhs = ab.transform_point(p);
        let rhs = a.transform_point(b.transform_point(p));
        prop_assert!((lhs - rhs).length() < 1e-13);
        prop_assert!((a.inverse_transform_point(a.transform_point(p)) - p).length() < 1e-14);
        prop_assert!((a.inverse_transform_vector(a.transform_vector(p)) - p).length() < 1e-14);
    }

    #[test]
    fn act_motion_and_act_force_are_the_action_matrices(t in se3(), m in motion(), f in force()) {
        let xm = mat6_vec(&t.to_action_matrix(), m.to_array());
        prop_assert!(max_diff(&xm, &t.act_motion(&m).to_array()) < 1e-14);
        let xf = mat6_vec(&t.to_dual_action_matrix(), f.to_array());
        prop_assert!(max_diff(&xf, &t.act_force(&f).to_array()) < 1e-14);
        // The inverse actions are the inverse transform's matrices.
        let inv = t.inverse();
        let xm_inv = mat6_vec(&inv.to_action_matrix(), m.to_array());
        prop_assert!(max_diff(&xm_inv, &t.act_inv_motion(&m).to_array()) < 1e-13);
        let xf_inv = mat6_vec(&inv.to_dual_action_matrix(), f.to_array());
        prop_assert!(max_diff(&xf_inv, &t.act_inv_force(&f).to_array()) < 1e-13);
        prop_assert!(t.act_inv_motion(&t.act_motion(&m)).abs_diff_eq(&m, 1e-13));
        prop_assert!(t.act_inv_force(&t.act_force(&f)).abs_diff_eq(&f, 1e-13));
    }

    #[test]
    fn action_matrices_form_a_representation(a in se3(), b in se3()) {
        // X(a b) = X(a) X(b), and the force transform is the inverse transpose: X*ᵀ X = I.
        let lhs = (a * b).to_action_matrix();
        let rhs = mat6_mul(&a.to_action_matrix(), &b.to_action_matrix());
        prop_assert!(max_diff(&flat6(&lhs), &flat6(&rhs)) < 1e-13);
        let dual_t_x = mat6_mul(&transpose6(&a.to_dual_action_matrix()), &a.to_action_matrix());
        prop_assert!(max_diff(&flat6(&dual_t_x), &flat6(&IDENTITY6)) < 1e-13);
    }

    #[test]
    fn quaternion_round_trip(t in se3()) {
        let q = t.to_quat();
        prop_assert!((q.length() - 1.0).abs() < 1e-14);
        let back = Se3::from_translation_quat(t.translation, q);
        prop_assert!(max_diff(&flat_se3(&back), &flat_se3(&t)) < 1e-14);
        // Stored x, y, z, w: the vector part is sin(θ/2)·axis.
        let (axis, angle) = q.to_axis_angle();
        let expected = axis * (angle / 2.0).sin();
        prop_assert!((DVec3::new(q.x, q.y, q.z) - expected).length() < 1e-12);
        prop_assert!((q.w - (angle / 2.0).cos()).abs() < 1e-12);
    }

    #[test]
    fn row_major_arrays_round_trip(t in se3()) {
        let back = Se3::from_rows(&t.to_rows());
        prop_assert_eq!(back, Some(t));
        prop_assert_eq!(t.to_rows()[3], [0.0, 0.0, 0.0, 1.0]);
    }
}
