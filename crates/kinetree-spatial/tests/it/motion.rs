//! Spatial cross products and the power pairing of motions and forces.

use crate::support::*;
use kinetree_spatial::Motion;
use proptest::prelude::*;

proptest! {
    #![proptest_config(config())]

    #[test]
    fn crf_is_minus_crm_transposed(v in motion()) {
        let crm = v.to_cross_motion_matrix();
        let crf = v.to_cross_force_matrix();
        let minus_crm_t: Vec<f64> = flat6(&transpose6(&crm)).iter().map(|x| -x).collect();
        prop_assert_eq!(flat6(&crf), minus_crm_t);
    }

    #[test]
    fn cross_products_are_their_matrices(v in motion(), m in motion(), f in force()) {
        let crm_m = mat6_vec(&v.to_cross_motion_matrix(), m.to_array());
        prop_assert!(max_diff(&crm_m, &v.cross_motion(&m).to_array()) < 1e-14);
        let crf_f = mat6_vec(&v.to_cross_force_matrix(), f.to_array());
        prop_assert!(max_diff(&crf_f, &v.cross_force(&f).to_array()) < 1e-14);
        // v ×ₘ v = 0, and the pairing identity (v ×ₘ m)·f = -m·(v ×* f).
        prop_assert!(v.cross_motion(&v).abs_diff_eq(&Motion::ZERO, 1e-14));
        prop_assert!((v.cross_motion(&m).dot(&f) + m.dot(&v.cross_force(&f))).abs() < 1e-13);
    }

    #[test]
    fn power_is_invariant_under_transforms(t in se3(), m in motion(), f in force()) {
        // Both vectors expressed in another frame deliver the same power.
        let before = m.dot(&f);
        let after = t.act_motion(&m).dot(&t.act_force(&f));
        prop_assert!((before - after).abs() < 1e-12, "{} vs {}", before, after);
        prop_assert!((f.dot(&m) - before).abs() == 0.0);
    }

    #[test]
    fn cross_products_commute_with_transforms(t in se3(), v in motion(), m in motion(), f in force()) {
        // X(v ×ₘ m) = (X v) ×ₘ (X m) and X*(v ×* f) = (X v) ×* (X* f).
        let lhs = t.act_motion(&v.cross_motion(&m));
        let rhs = t.act_motion(&v).cross_motion(&t.act_motion(&m));
        prop_assert!(lhs.abs_diff_eq(&rhs, 1e-12));
        let lhs = t.act_force(&v.cross_force(&f));
        let rhs = t.act_motion(&v).cross_force(&t.act_force(&f));
        prop_assert!(lhs.abs_diff_eq(&rhs, 1e-12));
    }

    #[test]
    fn featherstone_order_swaps_the_halves(m in motion(), f in force()) {
        let a = m.to_array();
        prop_assert_eq!(m.to_featherstone(), [a[3], a[4], a[5], a[0], a[1], a[2]]);
        prop_assert_eq!(Motion::from_featherstone(m.to_featherstone()), m);
        prop_assert_eq!(kinetree_spatial::Force::from_featherstone(f.to_featherstone()), f);
    }
}
