//! Cross products with a coordinate axis `e_K` (`K` = 0, 1, 2 for x, y, z), written out so that
//! the zero entries cost nothing: the kernels of joints whose axis is a coordinate axis. Generic
//! over the number type ([`Real`]).

use crate::real::{Real, Vector3};

/// `a × (s·e_K)`.
///
/// ```
/// use kinetree_spatial::{axis, DVec3};
/// let a = DVec3::new(1.0, 2.0, 3.0);
/// assert_eq!(axis::cross_unit::<f64, 2>(&a, 0.5), a.cross(DVec3::Z * 0.5));
/// ```
#[inline(always)]
#[must_use]
pub fn cross_unit<T: Real, const K: usize>(a: &T::V3, s: T) -> T::V3 {
    let (x, y, z, o) = (a.get(0), a.get(1), a.get(2), T::ZERO);
    match K {
        0 => T::V3::new(o, z * s, -y * s),
        1 => T::V3::new(-z * s, o, x * s),
        _ => T::V3::new(y * s, -x * s, o),
    }
}

/// `e_K × a`.
///
/// ```
/// use kinetree_spatial::{axis, DVec3};
/// let a = DVec3::new(1.0, 2.0, 3.0);
/// assert_eq!(axis::unit_cross::<f64, 0>(&a), DVec3::X.cross(a));
/// ```
#[inline(always)]
#[must_use]
pub fn unit_cross<T: Real, const K: usize>(a: &T::V3) -> T::V3 {
    let (x, y, z, o) = (a.get(0), a.get(1), a.get(2), T::ZERO);
    match K {
        0 => T::V3::new(o, -z, y),
        1 => T::V3::new(z, o, -x),
        _ => T::V3::new(-y, x, o),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn match_the_general_cross_product() {
        let a = DVec3::new(0.3, -1.7, 2.9);
        let units = [DVec3::X, DVec3::Y, DVec3::Z];
        let s = -0.4;
        assert_eq!(cross_unit::<f64, 0>(&a, s), a.cross(units[0] * s));
        assert_eq!(cross_unit::<f64, 1>(&a, s), a.cross(units[1] * s));
        assert_eq!(cross_unit::<f64, 2>(&a, s), a.cross(units[2] * s));
        assert_eq!(unit_cross::<f64, 0>(&a), units[0].cross(a));
        assert_eq!(unit_cross::<f64, 1>(&a), units[1].cross(a));
        assert_eq!(unit_cross::<f64, 2>(&a), units[2].cross(a));
    }
}
