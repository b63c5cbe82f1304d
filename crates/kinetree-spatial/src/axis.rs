//! Cross products with a coordinate axis `e_K` (`K` = 0, 1, 2 for x, y, z), written out so that
//! the zero entries cost nothing: the kernels of joints whose axis is a coordinate axis.

use glam::DVec3;

/// `a × (s·e_K)`.
///
/// ```
/// use kinetree_spatial::{axis, DVec3};
/// let a = DVec3::new(1.0, 2.0, 3.0);
/// assert_eq!(axis::cross_unit::<2>(a, 0.5), a.cross(DVec3::Z * 0.5));
/// ```
#[inline(always)]
#[must_use]
pub fn cross_unit<const K: usize>(a: DVec3, s: f64) -> DVec3 {
    match K {
        0 => DVec3::new(0.0, a.z * s, -a.y * s),
        1 => DVec3::new(-a.z * s, 0.0, a.x * s),
        _ => DVec3::new(a.y * s, -a.x * s, 0.0),
    }
}

/// `e_K × a`.
///
/// ```
/// use kinetree_spatial::{axis, DVec3};
/// let a = DVec3::new(1.0, 2.0, 3.0);
/// assert_eq!(axis::unit_cross::<0>(a), DVec3::X.cross(a));
/// ```
#[inline(always)]
#[must_use]
pub fn unit_cross<const K: usize>(a: DVec3) -> DVec3 {
    match K {
        0 => DVec3::new(0.0, -a.z, a.y),
        1 => DVec3::new(a.z, 0.0, -a.x),
        _ => DVec3::new(-a.y, a.x, 0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn match_the_general_cross_product() {
        let a = DVec3::new(0.3, -1.7, 2.9);
        let units = [DVec3::X, DVec3::Y, DVec3::Z];
        let s = -0.4;
        assert_eq!(cross_unit::<0>(a, s), a.cross(units[0] * s));
        assert_eq!(cross_unit::<1>(a, s), a.cross(units[1] * s));
        assert_eq!(cross_unit::<2>(a, s), a.cross(units[2] * s));
        assert_eq!(unit_cross::<0>(a), units[0].cross(a));
        assert_eq!(unit_cross::<1>(a), units[1].cross(a));
        assert_eq!(unit_cross::<2>(a), units[2].cross(a));
    }
}
