//! Roll-pitch-yaw and Euler angles, including at and near gimbal lock.

use crate::support::*;
use kinetree_spatial::rotation::{
    from_euler_xyz, from_rpy, is_rotation, rot_x, rot_y, rot_z, to_euler_xyz, to_rpy,
};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

/// A pitch at or within `1e-4` rad of ±π/2 (gimbal lock), with exact ±π/2 drawn often.
fn near_gimbal_lock() -> impl Strategy<Value = f64> {
    let offset = prop_oneof![Just(0.0), 0.0..1e-12, 0.0..1e-8, 0.0..1e-4];
    (any::<bool>(), offset).prop_map(|(up, eps)| {
        if up {
            FRAC_PI_2 - eps
        } else {
            -FRAC_PI_2 + eps
        }
    })
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn rpy_round_trips_away_from_gimbal_lock(
        roll in -PI + 1e-9..PI - 1e-9,
        pitch in -FRAC_PI_2 + 1e-3..FRAC_PI_2 - 1e-3,
        yaw in -PI + 1e-9..PI - 1e-9,
    ) {
        let [r, p, y] = to_rpy(&from_rpy(roll, pitch, yaw));
        prop_assert!((r - roll).abs() < 1e-11 && (p - pitch).abs() < 1e-11 && (y - yaw).abs() < 1e-11,
            "{:?} vs {:?}", [r, p, y], [roll, pitch, yaw]);
        let [a, b, c] = to_euler_xyz(&from_euler_xyz(roll, pitch, yaw));
        prop_assert!((a - roll).abs() < 1e-11 && (b - pitch).abs() < 1e-11 && (c - yaw).abs() < 1e-11);
    }

    #[test]
    fn rpy_reproduces_the_rotation_at_gimbal_lock(roll in -PI..PI, pitch in near_gimbal_lock(), yaw in -PI..PI) {
        // Roll and yaw are not unique there, but the rotation must come back to round-off.
        let r = from_rpy(roll, pitch, yaw);
        let [a, b, c] = to_rpy(&r);
        prop_assert!((-FRAC_PI_2..=FRAC_PI_2).contains(&b));
        prop_assert!(max_diff(&flat3(&from_rpy(a, b, c)), &flat3(&r)) < 4e-15);
        let e = from_euler_xyz(roll, pitch, yaw);
        let [a, b, c] = to_euler_xyz(&e);
        prop_assert!((-FRAC_PI_2..=FRAC_PI_2).contains(&b));
        prop_assert!(max_diff(&flat3(&from_euler_xyz(a, b, c)), &flat3(&e)) < 4e-15);
    }

    #[test]
    fn angles_of_any_rotation_reproduce_it(r in rotation()) {
        let [a, b, c] = to_rpy(&r);
        prop_assert!(max_diff(&flat3(&from_rpy(a, b, c)), &flat3(&r)) < 1e-14);
        let [a, b, c] = to_euler_xyz(&r);
        prop_assert!(max_diff(&flat3(&from_euler_xyz(a, b, c)), &flat3(&r)) < 1e-14);
    }

    #[test]
    fn rpy_is_fixed_axes_and_euler_is_moving_axes(a in -PI..PI, b in -PI..PI, c in -PI..PI) {
        // URDF rpy: about fixed x, then fixed y, then fixed z = Rz·Ry·Rx.
        prop_assert!(max_diff(&flat3(&from_rpy(a, b, c)), &flat3(&(rot_z(c) * rot_y(b) * rot_x(a)))) < 1e-15);
        // Intrinsic XYZ: about x, then the new y, then the newer z = Rx·Ry·Rz.
        prop_assert!(max_diff(&flat3(&from_euler_xyz(a, b, c)), &flat3(&(rot_x(a) * rot_y(b) * rot_z(c)))) < 1e-15);
        prop_assert!(is_rotation(&from_rpy(a, b, c), 1e-14));
    }
}
