//! Lanes: the spatial types of `L` independent states side by side (structure of arrays), for
//! the batched sweeps that evaluate several states of one model at once.
//!
//! [`Lanes<L>`] is `L` numbers; [`LVec3`], [`LMat3`], [`LSe3`], [`LMotion`] and [`LForce`] are
//! the lane forms of `DVec3`, `DMat3`, [`Se3`], [`Motion`] and [`Force`]. Every operation does
//! the scalar type's arithmetic in the same order, lane by lane, so a lane's result is the
//! scalar result bit for bit; written as fixed-length loops, the compiler turns them into SIMD
//! instructions (4 lanes of AVX2, 8 of AVX-512) inside a function compiled for those features.
//! Model constants (placements, inertias) stay scalar and are broadcast.
//!
//! ```
//! use kinetree_spatial::lanes::{LSe3, LVec3};
//! use kinetree_spatial::real::Vector3;
//! use kinetree_spatial::{DVec3, Se3};
//! let a = Se3::from_xyz_rpy([0.1, 0.2, 0.3], [0.4, 0.5, 0.6]);
//! let b = Se3::from_xyz_rpy([-0.3, 0.0, 0.7], [0.1, -0.2, 0.3]);
//! let mut lanes = LSe3::<4>::splat(&a);
//! lanes.set_lane(2, &b);
//! let product = lanes.compose(&LSe3::splat(&a));
//! assert_eq!(product.lane(2), b * a);
//! assert_eq!(product.lane(0), a * a);
//! let p = LVec3::<4>::splat(DVec3::X);
//! assert_eq!(p.cross(&p).lane(1), DVec3::ZERO);
//! ```

use crate::{Force, Motion, Se3};
#[cfg(test)]
use crate::{Inertia, OriginInertia, Symmetric3};
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, Neg, Sub, SubAssign};
use glam::{DMat3, DVec3};

/// A lane value on a 64-byte boundary (a [`LaneVec`] element). The lane types' sizes at 8 lanes
/// are multiples of 64 bytes, so this adds no padding there.
#[derive(Clone, Copy, Debug)]
#[repr(align(64))]
struct Aligned<T>(T);

/// A fixed-length buffer of lane values, each starting on a cache-line boundary, so that 8-lane
/// (AVX-512) loads and stores never straddle two lines. A `Vec` of them is aligned only as its
/// element type (8 bytes), and a misaligned 64-byte access costs two.
///
/// ```
/// use kinetree_spatial::lanes::{LaneVec, LMotion};
/// let mut v = LaneVec::new(LMotion::<8>::zero(), 3);
/// v[1].linear.x.0[2] = 1.0;
/// assert_eq!(v.len(), 3);
/// assert_eq!(v.iter().map(|m| m.linear.x.0[2]).sum::<f64>(), 1.0);
/// assert_eq!(&v[0] as *const _ as usize % 64, 0);
/// ```
#[derive(Clone, Debug)]
pub struct LaneVec<T>(Vec<Aligned<T>>);

impl<T: Clone> LaneVec<T> {
    /// `n` copies of `x`.
    #[must_use]
    pub fn new(x: T, n: usize) -> Self {
        Self(vec![Aligned(x); n])
    }

    /// Sets every element to `x`.
    pub fn fill(&mut self, x: T) {
        for e in &mut self.0 {
            e.0 = x.clone();
        }
    }
}

impl<T> LaneVec<T> {
    /// The number of elements.
    #[must_use]
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether there are no elements.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The elements in order.
    pub fn iter(&self) -> impl Iterator<Item = &T> {
        self.0.iter().map(|x| &x.0)
    }

    /// The elements in order, mutable.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = &mut T> {
        self.0.iter_mut().map(|x| &mut x.0)
    }
}

impl<T> Default for LaneVec<T> {
    fn default() -> Self {
        Self(Vec::new())
    }
}

impl<T> core::ops::Index<usize> for LaneVec<T> {
    type Output = T;
    #[inline(always)]
    fn index(&self, i: usize) -> &T {
        &self.0[i].0
    }
}

impl<T> core::ops::IndexMut<usize> for LaneVec<T> {
    #[inline(always)]
    fn index_mut(&mut self, i: usize) -> &mut T {
        &mut self.0[i].0
    }
}

/// `L` numbers, one per state.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(transparent)]
pub struct Lanes<const L: usize>(pub [f64; L]);

impl<const L: usize> Default for Lanes<L> {
    #[inline(always)]
    fn default() -> Self {
        Self::ZERO
    }
}

impl<const L: usize> Lanes<L> {
    /// Zero in every lane.
    pub const ZERO: Self = Self([0.0; L]);

    /// `x` in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(x: f64) -> Self {
        Self([x; L])
    }

    /// `f` of every lane.
    #[inline(always)]
    #[must_use]
    pub fn map(self, f: impl Fn(f64) -> f64) -> Self {
        let mut out = self.0;
        for x in &mut out {
            *x = f(*x);
        }
        Self(out)
    }
}

macro_rules! lane_binary {
    ($tr:ident, $f:ident, $tra:ident, $fa:ident, $op:tt) => {
        impl<const L: usize> $tr for Lanes<L> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                let mut out = [0.0; L];
                for l in 0..L {
                    out[l] = self.0[l] $op o.0[l];
                }
                Self(out)
            }
        }
        impl<const L: usize> $tr<f64> for Lanes<L> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: f64) -> Self {
                let mut out = [0.0; L];
                for l in 0..L {
                    out[l] = self.0[l] $op o;
                }
                Self(out)
            }
        }
        impl<const L: usize> $tra for Lanes<L> {
            #[inline(always)]
            fn $fa(&mut self, o: Self) {
                *self = *self $op o;
            }
        }
    };
}

lane_binary!(Add, add, AddAssign, add_assign, +);
lane_binary!(Sub, sub, SubAssign, sub_assign, -);
lane_binary!(Div, div, DivAssign, div_assign, /);

impl<const L: usize> Mul for Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let mut out = [0.0; L];
        for l in 0..L {
            out[l] = self.0[l] * o.0[l];
        }
        Self(out)
    }
}

impl<const L: usize> Mul<f64> for Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: f64) -> Self {
        let mut out = [0.0; L];
        for l in 0..L {
            out[l] = self.0[l] * o;
        }
        Self(out)
    }
}

impl<const L: usize> Neg for Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        let mut out = [0.0; L];
        for l in 0..L {
            out[l] = -self.0[l];
        }
        Self(out)
    }
}

/// A 3-vector per lane (the lane form of `DVec3`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LVec3<const L: usize> {
    /// x of every lane.
    pub x: Lanes<L>,
    /// y of every lane.
    pub y: Lanes<L>,
    /// z of every lane.
    pub z: Lanes<L>,
}

impl<const L: usize> LVec3<L> {
    /// Zero in every lane.
    pub const ZERO: Self = Self {
        x: Lanes::ZERO,
        y: Lanes::ZERO,
        z: Lanes::ZERO,
    };

    /// `v` in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(v: DVec3) -> Self {
        Self {
            x: Lanes::splat(v.x),
            y: Lanes::splat(v.y),
            z: Lanes::splat(v.z),
        }
    }

    /// Lane `l`.
    #[inline(always)]
    #[must_use]
    pub fn lane(&self, l: usize) -> DVec3 {
        DVec3::new(self.x.0[l], self.y.0[l], self.z.0[l])
    }

    /// Sets lane `l` to `v`.
    #[inline(always)]
    pub fn set_lane(&mut self, l: usize, v: DVec3) {
        self.x.0[l] = v.x;
        self.y.0[l] = v.y;
        self.z.0[l] = v.z;
    }
}

impl<const L: usize> Add for LVec3<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl<const L: usize> Sub for LVec3<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl<const L: usize> Neg for LVec3<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self {
            x: -self.x,
            y: -self.y,
            z: -self.z,
        }
    }
}

impl<const L: usize> AddAssign for LVec3<L> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<const L: usize> SubAssign for LVec3<L> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

/// A 3x3 matrix per lane, by columns (the lane form of `DMat3`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LMat3<const L: usize> {
    /// First column.
    pub x_axis: LVec3<L>,
    /// Second column.
    pub y_axis: LVec3<L>,
    /// Third column.
    pub z_axis: LVec3<L>,
}

impl<const L: usize> LMat3<L> {
    /// `m` in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(m: &DMat3) -> Self {
        Self {
            x_axis: LVec3::splat(m.x_axis),
            y_axis: LVec3::splat(m.y_axis),
            z_axis: LVec3::splat(m.z_axis),
        }
    }

    /// Lane `l`.
    #[inline(always)]
    #[must_use]
    pub fn lane(&self, l: usize) -> DMat3 {
        DMat3::from_cols(
            self.x_axis.lane(l),
            self.y_axis.lane(l),
            self.z_axis.lane(l),
        )
    }

    /// Sets lane `l` to `m`.
    #[inline(always)]
    pub fn set_lane(&mut self, l: usize, m: &DMat3) {
        self.x_axis.set_lane(l, m.x_axis);
        self.y_axis.set_lane(l, m.y_axis);
        self.z_axis.set_lane(l, m.z_axis);
    }
}

/// A rigid transform per lane: [`Se3`] over lanes.
pub type LSe3<const L: usize> = Se3<Lanes<L>>;

/// A spatial motion per lane: [`Motion`] over lanes.
pub type LMotion<const L: usize> = Motion<Lanes<L>>;

/// A spatial force per lane: [`Force`] over lanes.
pub type LForce<const L: usize> = Force<Lanes<L>>;

impl<const L: usize> Se3<Lanes<L>> {
    /// `x` in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(x: &Se3) -> Self {
        Self::from_const(x)
    }

    /// Lane `l`.
    #[inline(always)]
    #[must_use]
    pub fn lane(&self, l: usize) -> Se3 {
        Se3::new(self.rotation.lane(l), self.translation.lane(l))
    }

    /// Sets lane `l` to `x`.
    #[inline(always)]
    pub fn set_lane(&mut self, l: usize, x: &Se3) {
        self.rotation.set_lane(l, &x.rotation);
        self.translation.set_lane(l, x.translation);
    }
}

macro_rules! lane_spatial {
    ($s:ident) => {
        impl<const L: usize> $s<Lanes<L>> {
            /// `x` in every lane.
            #[inline(always)]
            #[must_use]
            pub fn splat(x: &$s) -> Self {
                Self {
                    linear: LVec3::splat(x.linear),
                    angular: LVec3::splat(x.angular),
                }
            }

            /// Lane `l`.
            #[inline(always)]
            #[must_use]
            pub fn lane(&self, l: usize) -> $s {
                $s::new(self.linear.lane(l), self.angular.lane(l))
            }

            /// Sets lane `l` to `x`.
            #[inline(always)]
            pub fn set_lane(&mut self, l: usize, x: &$s) {
                self.linear.set_lane(l, x.linear);
                self.angular.set_lane(l, x.angular);
            }
        }
    };
}

lane_spatial!(Motion);
lane_spatial!(Force);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::real::{Matrix3, Vector3};

    fn se3s() -> [Se3; 4] {
        [
            Se3::from_xyz_rpy([0.1, 0.2, 0.3], [0.4, 0.5, 0.6]),
            Se3::from_xyz_rpy([-0.3, 0.0, 0.7], [0.1, -0.2, 0.3]),
            Se3::from_xyz_rpy([1.3, -2.0, 0.1], [3.0, 1.2, -2.3]),
            Se3::from_xyz_rpy([0.0, 0.5, -0.5], [-1.0, 0.0, 2.0]),
        ]
    }

    fn load<T: Copy, U: Default>(xs: &[T; 4], set: impl Fn(&mut U, usize, &T)) -> U {
        let mut out = U::default();
        for (l, x) in xs.iter().enumerate() {
            set(&mut out, l, x);
        }
        out
    }

    #[test]
    fn every_lane_is_the_scalar_result_bit_for_bit() {
        let xs = se3s();
        let ys = [xs[2], xs[0], xs[3], xs[1]];
        let ms = xs.map(|x| Motion::new(x.translation, x.rotation.x_axis * 1.7));
        let fs = ys.map(|x| Force::new(x.rotation.z_axis, x.translation * -0.3));
        let lx: LSe3<4> = load(&xs, |o: &mut LSe3<4>, l, x| o.set_lane(l, x));
        let ly: LSe3<4> = load(&ys, |o: &mut LSe3<4>, l, x| o.set_lane(l, x));
        let lm: LMotion<4> = load(&ms, |o: &mut LMotion<4>, l, x| o.set_lane(l, x));
        let lf: LForce<4> = load(&fs, |o: &mut LForce<4>, l, x| o.set_lane(l, x));
        let rigid = Inertia::new(
            2.5,
            DVec3::new(0.1, -0.2, 0.3),
            Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6),
        );
        let inertia = OriginInertia::from_inertia(&rigid);
        for l in 0..4 {
            assert_eq!(lx.compose(&ly).lane(l), xs[l] * ys[l]);
            assert_eq!(lx.mul_const(&ys[1]).lane(l), xs[l] * ys[1]);
            assert_eq!(lx.act_motion(&lm).lane(l), xs[l].act_motion(&ms[l]));
            assert_eq!(lx.act_inv_motion(&lm).lane(l), xs[l].act_inv_motion(&ms[l]));
            assert_eq!(lx.act_force(&lf).lane(l), xs[l].act_force(&fs[l]));
            assert_eq!(lm.cross_motion(&lm).lane(l), ms[l].cross_motion(&ms[l]));
            assert_eq!(lm.cross_force(&lf).lane(l), ms[l].cross_force(&fs[l]));
            assert_eq!(lm.dot(&lf).0[l], ms[l].dot(&fs[l]));
            assert_eq!(
                OriginInertia::<Lanes<4>>::from_const(&inertia)
                    .mul_motion(&lm)
                    .lane(l),
                inertia.mul_motion(&ms[l])
            );
            assert_eq!(rigid.mul_motion(&lm).lane(l), rigid.mul_motion(&ms[l]));
            let lm2 = LMotion {
                linear: lf.angular,
                angular: lf.linear,
            };
            let m2 = Motion::new(fs[l].angular, fs[l].linear);
            assert_eq!(
                rigid.rnea_force(&lm, &lm2).lane(l),
                rigid.rnea_force(&ms[l], &m2)
            );
            let v = lm.linear;
            let c = DVec3::new(0.3, -0.7, 1.1);
            assert_eq!(v.cross_const(c).lane(l), ms[l].linear.cross(c));
            assert_eq!(LVec3::const_cross(c, &v).lane(l), c.cross(ms[l].linear));
            assert_eq!(
                lx.rotation.transpose_mul_vec(&v).lane(l),
                xs[l].inverse_transform_vector(ms[l].linear)
            );
        }
    }
}
