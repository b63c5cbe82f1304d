//! The SO(3) and SE(3) exponential and logarithm maps.

use crate::support::*;
use kinetree_spatial::explog::{exp6, log6, so3_left_jacobian, so3_left_jacobian_inverse};
use kinetree_spatial::rotation::{exp3, log3};
use kinetree_spatial::{DMat3, Motion};
use proptest::prelude::*;
use std::f64::consts::PI;

proptest! {
    #![proptest_config(config())]

    #[test]
    fn exp6_of_log6_is_the_transform(t in se3()) {
        // Angles from 0 to π inclusive: log6 picks the angle in [0, π], exp6 maps it back.
        let back = exp6(&log6(&t));
        prop_assert!(
            max_diff(&flat_se3(&back), &flat_se3(&t)) < 1e-12,
            "{:?} vs {:?}", back, t
        );
    }

    #[test]
    fn log6_of_exp6_is_the_twist(axis in unit_vec(), a in 0.0..(PI - 1e-3), v in vec3(2.0)) {
        // Below π the logarithm is unique, so the twist itself comes back.
        let m = Motion::new(v, axis * a);
        let back = log6(&exp6(&m));
        prop_assert!(max_diff(&back.to_array(), &m.to_array()) < 1e-10, "{:?} vs {:?}", back, m);
    }

    #[test]
    fn exp6_is_a_one_parameter_subgroup(m in motion(), s in -1.0..1.0, u in -1.0..1.0) {
        // exp(s m) exp(u m) = exp((s + u) m).
        let lhs = exp6(&(m * s)) * exp6(&(m * u));
        let rhs = exp6(&(m * (s + u)));
        prop_assert!(max_diff(&flat_se3(&lhs), &flat_se3(&rhs)) < 1e-12);
        // And exp(-m) is the inverse of exp(m).
        let id = exp6(&m) * exp6(&-m);
        prop_assert!(max_diff(&flat_se3(&id), &flat_se3(&kinetree_spatial::Se3::IDENTITY)) < 1e-13);
    }

    #[test]
    fn so3_maps_round_trip(r in rotation()) {
        let w = log3(&r);
        prop_assert!(w.length() <= PI + 1e-12);
        prop_assert!(max_diff(&flat3(&exp3(w)), &flat3(&r)) < 1e-13);
        // exp3 agrees with glam's axis-angle rotation.
        if w.length() > 0.0 {
            let glam = DMat3::from_axis_angle(w.normalize(), w.length());
            prop_assert!(max_diff(&flat3(&exp3(w)), &flat3(&glam)) < 1e-14);
        }
    }

    #[test]
    fn left_jacobian_inverse_is_its_inverse(axis in unit_vec(), a in angle()) {
        let w = axis * a;
        let p = so3_left_jacobian(w) * so3_left_jacobian_inverse(w);
        prop_assert!(max_diff(&flat3(&p), &flat3(&DMat3::IDENTITY)) < 1e-12);
    }

    #[test]
    fn interpolation_hits_both_ends(a in se3(), b in se3()) {
        prop_assert!(max_diff(&flat_se3(&a.interpolate(&b, 0.0)), &flat_se3(&a)) < 1e-13);
        prop_assert!(max_diff(&flat_se3(&a.interpolate(&b, 1.0)), &flat_se3(&b)) < 1e-11);
    }
}
