//! [`Real`]: the numbers the spatial types and the algorithms are generic over.
//!
//! An algorithm written once over `T: Real` runs on one state with `T = f64` and on a block of
//! states side by side with `T = Lanes<L>` ([`crate::lanes`]). The operations are the field
//! operations plus the few functions the sweeps need ([`Real::sin_cos`], [`Real::sqrt`],
//! [`Real::sign`]); there is no comparison, so a lane never branches on its own value. Model
//! constants (placements, inertias, axes) stay `f64` and enter through the `*_const` operations
//! and `Mul<f64>`, which a lane type broadcasts.
//!
//! [`Real::V3`] and [`Real::M3`] are the 3-vector and 3x3 matrix of the number type: glam's
//! `DVec3` and `DMat3` for `f64` (so the everyday [`Se3`], [`Motion`](crate::Motion)
//! and [`Force`](crate::Force) hold glam values), [`LVec3`] and [`LMat3`] for lanes. Every
//! operation of [`Vector3`] and [`Matrix3`] does glam's arithmetic in glam's order, so a lane's
//! result is the `f64` result bit for bit.
//!
//! ```
//! use kinetree_spatial::real::{Real, Vector3};
//! use kinetree_spatial::lanes::Lanes;
//! // One function, two number types.
//! fn spin<T: Real>(w: T::V3, r: T::V3) -> T::V3 { w.cross(&r) }
//! let v = spin::<f64>(glam::DVec3::Z, glam::DVec3::X);
//! assert_eq!(v, glam::DVec3::Y);
//! let lanes = spin::<Lanes<4>>(Vector3::from_const(glam::DVec3::Z), Vector3::from_const(glam::DVec3::X));
//! assert_eq!(lanes.lane(3), glam::DVec3::Y);
//! ```

use crate::Se3;
use crate::lanes::{LMat3, LVec3, Lanes};
use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};
use glam::{DMat3, DVec3};

/// A number type of the generic algorithms: `f64` for one state, [`Lanes<L>`] for `L` states.
pub trait Real:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + Mul<f64, Output = Self>
    + Add<f64, Output = Self>
{
    /// The 3-vector of this number type.
    type V3: Vector3<Self>;
    /// The 3x3 matrix (by columns) of this number type.
    type M3: Matrix3<Self>;

    /// Zero.
    const ZERO: Self;

    /// How many states a value holds: 1 for `f64`, `L` for `Lanes<L>`.
    const LANES: usize;

    /// The constant `x` (in every lane).
    #[must_use]
    fn splat(x: f64) -> Self;

    /// `(sin x, cos x)` by kinetree's fast kernel ([`sin_cos`]), the same bits in every form.
    #[must_use]
    fn sin_cos(self) -> (Self, Self);

    /// The square root.
    #[must_use]
    fn sqrt(self) -> Self;

    /// `1`, `-1` or `0` for a positive, negative or zero (or NaN) value.
    #[must_use]
    fn sign(self) -> Self;

    /// The absolute value.
    #[must_use]
    fn abs(self) -> Self;

    /// A pivot of a factorization and its check, lane by lane: `(1 / self, 0)` where `self`
    /// exceeds `tolerance`, else `(0, 1)` (a pivot at most `tolerance`, or NaN, is refused).
    /// The one comparison the algorithms make; what a refusal means is decided at their edges.
    #[must_use]
    fn pivot(self, tolerance: Self) -> (Self, Self);

    /// The transform `f` gives for each lane's numbers `x` (at most 8 of them): a
    /// computation left to one-state code, lane by lane, out of line. The rare joint kinds take
    /// this path, so that the kernels stay compact (their one-state code is a call, not an
    /// inlined copy); for `f64` it is `f(x)`, called out of line.
    #[must_use]
    fn each_lane(x: &[Self], f: impl Fn(&[f64]) -> Se3) -> Se3<Self>;
}

/// The 3-vector operations the generic algorithms use (glam's `DVec3` arithmetic).
pub trait Vector3<T: Real>:
    Copy
    + Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
{
    /// The zero vector.
    const ZERO: Self;

    /// From three coordinates.
    #[must_use]
    fn new(x: T, y: T, z: T) -> Self;

    /// The constant `v` (in every lane).
    #[must_use]
    fn from_const(v: DVec3) -> Self;

    /// Coordinate `k` (0, 1, 2 for x, y, z).
    #[must_use]
    fn get(&self, k: usize) -> T;

    /// Coordinate `k` (0, 1, 2 for x, y, z), mutably.
    fn get_mut(&mut self, k: usize) -> &mut T;

    /// Every coordinate times `s`.
    #[must_use]
    fn scale(&self, s: T) -> Self;

    /// Every coordinate times the constant `s`.
    #[must_use]
    fn scale_by(&self, s: f64) -> Self;

    /// The cross product `self × r`.
    #[must_use]
    fn cross(&self, r: &Self) -> Self;

    /// The cross product with a constant, `self × r`.
    #[must_use]
    fn cross_const(&self, r: DVec3) -> Self;

    /// A constant's cross product with a vector, `l × r`.
    #[must_use]
    fn const_cross(l: DVec3, r: &Self) -> Self;

    /// The dot product.
    #[must_use]
    fn dot(&self, r: &Self) -> T;

    /// `*self = *src`, coordinate by coordinate (a whole-struct copy of a wide lane value can
    /// compile to a call of `memcpy`).
    #[inline(always)]
    fn assign(&mut self, src: &Self) {
        *self = *src;
    }
}

/// The 3x3 matrix operations the generic algorithms use (glam's `DMat3` arithmetic).
pub trait Matrix3<T: Real>: Copy + Debug + PartialEq {
    /// The identity.
    const IDENTITY: Self;

    /// From three columns.
    #[must_use]
    fn from_cols(x: T::V3, y: T::V3, z: T::V3) -> Self;

    /// The constant `m` (in every lane).
    #[must_use]
    fn from_const(m: &DMat3) -> Self;

    /// Column `k`.
    #[must_use]
    fn col(&self, k: usize) -> T::V3;

    /// `self · v`.
    #[must_use]
    fn mul_vec(&self, v: &T::V3) -> T::V3;

    /// `self · v` for a constant `v`.
    #[must_use]
    fn mul_const_vec(&self, v: DVec3) -> T::V3;

    /// `selfᵀ · v`, as three dot products with the columns.
    #[must_use]
    fn transpose_mul_vec(&self, v: &T::V3) -> T::V3;

    /// `self · m`.
    #[must_use]
    fn mul_mat(&self, m: &Self) -> Self;

    /// `self · m` for a constant `m`.
    #[must_use]
    fn mul_const_mat(&self, m: &DMat3) -> Self;

    /// The transpose.
    #[must_use]
    fn transpose(&self) -> Self;

    /// `*self = *src`, column by column (see [`Vector3::assign`]).
    #[inline(always)]
    fn assign(&mut self, src: &Self) {
        *self = *src;
    }
}

impl Real for f64 {
    type V3 = DVec3;
    type M3 = DMat3;

    const ZERO: Self = 0.0;

    const LANES: usize = 1;

    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }

    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        sin_cos(self)
    }

    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }

    #[inline(always)]
    fn sign(self) -> Self {
        if self > 0.0 {
            1.0
        } else if self < 0.0 {
            -1.0
        } else {
            0.0
        }
    }

    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }

    #[inline(always)]
    fn pivot(self, tolerance: Self) -> (Self, Self) {
        if self > tolerance {
            (1.0 / self, 0.0)
        } else {
            (0.0, 1.0)
        }
    }

    #[inline(always)]
    fn each_lane(x: &[Self], f: impl Fn(&[f64]) -> Se3) -> Se3 {
        out_of_line(&f, x)
    }
}

/// `f(x)`, as a call: the one-state code of [`Real::each_lane`] stays out of the kernels (one
/// copy per closure type, that is per generic function that hands one over).
#[inline(never)]
fn out_of_line<F: Fn(&[f64]) -> Se3>(f: &F, x: &[f64]) -> Se3 {
    f(x)
}

impl Vector3<f64> for DVec3 {
    const ZERO: Self = DVec3::ZERO;

    #[inline(always)]
    fn new(x: f64, y: f64, z: f64) -> Self {
        DVec3::new(x, y, z)
    }

    #[inline(always)]
    fn from_const(v: DVec3) -> Self {
        v
    }

    #[inline(always)]
    fn get(&self, k: usize) -> f64 {
        self[k]
    }

    #[inline(always)]
    fn get_mut(&mut self, k: usize) -> &mut f64 {
        &mut self[k]
    }

    #[inline(always)]
    fn scale(&self, s: f64) -> Self {
        *self * s
    }

    #[inline(always)]
    fn scale_by(&self, s: f64) -> Self {
        *self * s
    }

    #[inline(always)]
    fn cross(&self, r: &Self) -> Self {
        DVec3::cross(*self, *r)
    }

    #[inline(always)]
    fn cross_const(&self, r: DVec3) -> Self {
        DVec3::cross(*self, r)
    }

    #[inline(always)]
    fn const_cross(l: DVec3, r: &Self) -> Self {
        DVec3::cross(l, *r)
    }

    #[inline(always)]
    fn dot(&self, r: &Self) -> f64 {
        DVec3::dot(*self, *r)
    }
}

impl Matrix3<f64> for DMat3 {
    const IDENTITY: Self = DMat3::IDENTITY;

    #[inline(always)]
    fn from_cols(x: DVec3, y: DVec3, z: DVec3) -> Self {
        DMat3::from_cols(x, y, z)
    }

    #[inline(always)]
    fn from_const(m: &DMat3) -> Self {
        *m
    }

    #[inline(always)]
    fn col(&self, k: usize) -> DVec3 {
        DMat3::col(self, k)
    }

    #[inline(always)]
    fn mul_vec(&self, v: &DVec3) -> DVec3 {
        *self * *v
    }

    #[inline(always)]
    fn mul_const_vec(&self, v: DVec3) -> DVec3 {
        *self * v
    }

    #[inline(always)]
    fn transpose_mul_vec(&self, v: &DVec3) -> DVec3 {
        DVec3::new(
            self.x_axis.dot(*v),
            self.y_axis.dot(*v),
            self.z_axis.dot(*v),
        )
    }

    #[inline(always)]
    fn mul_mat(&self, m: &Self) -> Self {
        *self * *m
    }

    #[inline(always)]
    fn mul_const_mat(&self, m: &DMat3) -> Self {
        *self * *m
    }

    #[inline(always)]
    fn transpose(&self) -> Self {
        DMat3::transpose(self)
    }
}

impl<const L: usize> Real for Lanes<L> {
    type V3 = LVec3<L>;
    type M3 = LMat3<L>;

    const ZERO: Self = Lanes::ZERO;

    const LANES: usize = L;

    #[inline(always)]
    fn splat(x: f64) -> Self {
        Lanes::splat(x)
    }

    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        sin_cos_lanes(self)
    }

    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f64::sqrt)
    }

    #[inline(always)]
    fn sign(self) -> Self {
        self.map(<f64 as Real>::sign)
    }

    #[inline(always)]
    fn abs(self) -> Self {
        self.map(f64::abs)
    }

    #[inline(always)]
    fn pivot(self, tolerance: Self) -> (Self, Self) {
        let (mut inverse, mut refused) = ([0.0; L], [0.0; L]);
        for l in 0..L {
            if self.0[l] > tolerance.0[l] {
                inverse[l] = 1.0 / self.0[l];
            } else {
                refused[l] = 1.0;
            }
        }
        (Lanes(inverse), Lanes(refused))
    }

    #[inline(always)]
    fn each_lane(x: &[Self], f: impl Fn(&[f64]) -> Se3) -> Se3<Self> {
        let n = x.len().min(8);
        let mut out = Se3::<Self>::identity();
        for l in 0..L {
            let mut one = [0.0; 8];
            for (o, xk) in one.iter_mut().zip(&x[..n]) {
                *o = xk.0[l];
            }
            out.set_lane(l, &f(&one[..n]));
        }
        out
    }
}

impl<const L: usize> Vector3<Lanes<L>> for LVec3<L> {
    const ZERO: Self = LVec3::ZERO;

    #[inline(always)]
    fn new(x: Lanes<L>, y: Lanes<L>, z: Lanes<L>) -> Self {
        LVec3 { x, y, z }
    }

    #[inline(always)]
    fn from_const(v: DVec3) -> Self {
        LVec3::splat(v)
    }

    #[inline(always)]
    fn get(&self, k: usize) -> Lanes<L> {
        match k {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }

    #[inline(always)]
    fn get_mut(&mut self, k: usize) -> &mut Lanes<L> {
        match k {
            0 => &mut self.x,
            1 => &mut self.y,
            _ => &mut self.z,
        }
    }

    #[inline(always)]
    fn scale(&self, s: Lanes<L>) -> Self {
        LVec3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    #[inline(always)]
    fn scale_by(&self, s: f64) -> Self {
        LVec3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    /// As `DVec3::cross`.
    #[inline(always)]
    fn cross(&self, r: &Self) -> Self {
        LVec3 {
            x: self.y * r.z - r.y * self.z,
            y: self.z * r.x - r.z * self.x,
            z: self.x * r.y - r.x * self.y,
        }
    }

    #[inline(always)]
    fn cross_const(&self, r: DVec3) -> Self {
        LVec3 {
            x: self.y * r.z - self.z * r.y,
            y: self.z * r.x - self.x * r.z,
            z: self.x * r.y - self.y * r.x,
        }
    }

    #[inline(always)]
    fn const_cross(l: DVec3, r: &Self) -> Self {
        LVec3 {
            x: r.z * l.y - r.y * l.z,
            y: r.x * l.z - r.z * l.x,
            z: r.y * l.x - r.x * l.y,
        }
    }

    /// As `DVec3::dot`.
    #[inline(always)]
    fn dot(&self, r: &Self) -> Lanes<L> {
        (self.x * r.x) + (self.y * r.y) + (self.z * r.z)
    }

    #[inline(always)]
    fn assign(&mut self, src: &Self) {
        self.x = src.x;
        self.y = src.y;
        self.z = src.z;
    }
}

impl<const L: usize> Matrix3<Lanes<L>> for LMat3<L> {
    const IDENTITY: Self = {
        let (o, i) = (Lanes::ZERO, Lanes([1.0; L]));
        LMat3 {
            x_axis: LVec3 { x: i, y: o, z: o },
            y_axis: LVec3 { x: o, y: i, z: o },
            z_axis: LVec3 { x: o, y: o, z: i },
        }
    };

    #[inline(always)]
    fn from_cols(x: LVec3<L>, y: LVec3<L>, z: LVec3<L>) -> Self {
        LMat3 {
            x_axis: x,
            y_axis: y,
            z_axis: z,
        }
    }

    #[inline(always)]
    fn from_const(m: &DMat3) -> Self {
        LMat3::splat(m)
    }

    #[inline(always)]
    fn col(&self, k: usize) -> LVec3<L> {
        match k {
            0 => self.x_axis,
            1 => self.y_axis,
            _ => self.z_axis,
        }
    }

    /// As `DMat3 * DVec3`.
    #[inline(always)]
    fn mul_vec(&self, v: &LVec3<L>) -> LVec3<L> {
        self.x_axis.scale(v.x) + self.y_axis.scale(v.y) + self.z_axis.scale(v.z)
    }

    #[inline(always)]
    fn mul_const_vec(&self, v: DVec3) -> LVec3<L> {
        self.x_axis.scale_by(v.x) + self.y_axis.scale_by(v.y) + self.z_axis.scale_by(v.z)
    }

    /// As `Se3::inverse_transform_vector`: three dot products.
    #[inline(always)]
    fn transpose_mul_vec(&self, v: &LVec3<L>) -> LVec3<L> {
        LVec3 {
            x: self.x_axis.dot(v),
            y: self.y_axis.dot(v),
            z: self.z_axis.dot(v),
        }
    }

    /// As `DMat3 * DMat3`.
    #[inline(always)]
    fn mul_mat(&self, m: &Self) -> Self {
        Self::from_cols(
            self.mul_vec(&m.x_axis),
            self.mul_vec(&m.y_axis),
            self.mul_vec(&m.z_axis),
        )
    }

    #[inline(always)]
    fn mul_const_mat(&self, m: &DMat3) -> Self {
        Self::from_cols(
            self.mul_const_vec(m.x_axis),
            self.mul_const_vec(m.y_axis),
            self.mul_const_vec(m.z_axis),
        )
    }

    #[inline(always)]
    fn transpose(&self) -> Self {
        let (x, y, z) = (&self.x_axis, &self.y_axis, &self.z_axis);
        Self::from_cols(
            LVec3::new(x.x, y.x, z.x),
            LVec3::new(x.y, y.y, z.y),
            LVec3::new(x.z, y.z, z.z),
        )
    }

    #[inline(always)]
    fn assign(&mut self, src: &Self) {
        self.x_axis.assign(&src.x_axis);
        self.y_axis.assign(&src.y_axis);
        self.z_axis.assign(&src.z_axis);
    }
}

/// `(sin x, cos x)` to within an ulp or two, inlined and branch-free for `|x| < 1e5` (every
/// joint angle in practice); larger arguments fall back to [`f64::sin_cos`].
///
/// Cody–Waite reduction by π/2 with a three-part constant, then fdlibm's minimax kernels on
/// `[-π/4, π/4]`. About half the cost of the libm call, which matters because every revolute
/// joint of every sweep needs one. [`Real::sin_cos`] of lanes gives the same bits.
///
/// ```
/// let (s, c) = kinetree_spatial::real::sin_cos(0.5);
/// assert!((s - 0.5f64.sin()).abs() <= f64::EPSILON && (c - 0.5f64.cos()).abs() <= f64::EPSILON);
/// ```
#[inline(always)]
#[must_use]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() >= 1e5 {
        return x.sin_cos();
    }
    let (t, s, c) = reduced_sin_cos(x);
    // Quadrant n = k mod 4: (sin, cos) = (s, c), (c, -s), (-s, -c), (-c, s).
    quadrant(t.to_bits(), s, c)
}

/// The rounded quotient `t` (the integer `k` of `x ≈ k·π/2 + r` in its mantissa) and the
/// kernels' `(sin r, cos r)`: the arithmetic of [`sin_cos`], written once over [`Real`].
#[inline(always)]
#[allow(
    clippy::excessive_precision,
    reason = "fdlibm's constants, digit for digit"
)]
fn reduced_sin_cos<T: Real>(x: T) -> (T, T, T) {
    // π/2 split into parts whose products with |k| < 2^20 are exact (fdlibm's pio2_1, pio2_2).
    const PIO2_1: f64 = 1.570_796_326_734_125_614_17e0;
    const PIO2_2: f64 = 6.077_100_506_303_965_976_6e-11;
    const PIO2_3: f64 = 2.022_266_248_795_950_631_54e-21;
    const ROUND: f64 = 6_755_399_441_055_744.0; // 1.5·2^52: adding it rounds to an integer.
    const S1: f64 = -1.666_666_666_666_663_243_48e-1;
    const S2: f64 = 8.333_333_333_322_489_461_24e-3;
    const S3: f64 = -1.984_126_982_985_794_931_34e-4;
    const S4: f64 = 2.755_731_370_707_006_767_89e-6;
    const S5: f64 = -2.505_076_025_340_686_341_95e-8;
    const S6: f64 = 1.589_690_995_211_550_102_21e-10;
    const C1: f64 = 4.166_666_666_666_660_190_37e-2;
    const C2: f64 = -1.388_888_888_887_410_957_49e-3;
    const C3: f64 = 2.480_158_728_947_672_941_78e-5;
    const C4: f64 = -2.755_731_435_139_066_330_35e-7;
    const C5: f64 = 2.087_572_321_298_174_827_90e-9;
    const C6: f64 = -1.135_964_755_778_819_482_65e-11;
    let c = T::splat;
    let t = x * core::f64::consts::FRAC_2_PI + ROUND;
    let kf = t - c(ROUND);
    let r = ((x - kf * PIO2_1) - kf * PIO2_2) - kf * PIO2_3;
    let z = r * r;
    let s = r + r * z * (c(S1) + z * (c(S2) + z * (c(S3) + z * (c(S4) + z * (c(S5) + z * S6)))));
    let p = z * z * (c(C1) + z * (c(C2) + z * (c(C3) + z * (c(C4) + z * (c(C5) + z * C6)))));
    let hz = z * 0.5;
    let w = c(1.0) - hz;
    (t, s, w + (((c(1.0) - w) - hz) + p))
}

/// `(sin x, cos x)` from the kernels' `(s, c)` and the quadrant in the low bits of `t`'s
/// mantissa: `(s, c)`, `(c, -s)`, `(-s, -c)`, `(-c, s)`, by integer operations (branch-free).
#[inline(always)]
fn quadrant(n: u64, s: f64, c: f64) -> (f64, f64) {
    let odd = 0u64.wrapping_sub(n & 1);
    let (sb, cb) = (s.to_bits(), c.to_bits());
    let sv = (sb & !odd) | (cb & odd);
    let cv = (cb & !odd) | (sb & odd);
    (
        f64::from_bits(sv ^ ((n & 2) << 62)),
        f64::from_bits(cv ^ ((n.wrapping_add(1) & 2) << 62)),
    )
}

/// [`sin_cos`] of every lane, bit for bit, in SIMD: the same reduction and kernels, and the
/// quadrant by whole-array integer operations so that the compiler keeps every step in
/// full-width vectors (lanes with `|x| ≥ 1e5` take the scalar path, as `sin_cos` does).
#[inline(always)]
fn sin_cos_lanes<const L: usize>(x: Lanes<L>) -> (Lanes<L>, Lanes<L>) {
    let (t, s, c) = reduced_sin_cos(x);
    let (mut sin, mut cos) = ([0.0; L], [0.0; L]);
    for l in 0..L {
        (sin[l], cos[l]) = quadrant(t.0[l].to_bits(), s.0[l], c.0[l]);
    }
    let mut large = 0u64;
    for l in 0..L {
        large |= u64::from(x.0[l].abs() >= 1e5);
    }
    if large != 0 {
        for l in 0..L {
            if x.0[l].abs() >= 1e5 {
                (sin[l], cos[l]) = x.0[l].sin_cos();
            }
        }
    }
    (Lanes(sin), Lanes(cos))
}

/// Implements `Clone` (as a plain copy) and `Copy` for types generic over their number type
/// `T: Real`: `copy_by_value!(Motion, Force)`.
///
/// `#[derive(Clone, Copy)]` on a type with a type parameter clones field by field (the derive
/// cannot know the fields are `Copy`), and LLVM then assembles each clone on the stack: filling
/// a slice of `Motion` with zeros cost a store-forwarding stall per element, which made the
/// one-state frame Jacobian 1.2 to 1.5 times slower. A clone that is a copy compiles to plain
/// stores.
#[macro_export]
macro_rules! copy_by_value {
    ($($t:ident),+ $(,)?) => {$(
        impl<T: $crate::Real> ::core::clone::Clone for $t<T> {
            #[inline(always)]
            fn clone(&self) -> Self {
                *self
            }
        }
        impl<T: $crate::Real> ::core::marker::Copy for $t<T> {}
    )+};
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lane_sin_cos_is_the_scalar_one_bit_for_bit() {
        let mut x = -1.2e5 + 0.123;
        let mut checked = 0;
        while x < 1.2e5 {
            let xs = Lanes([x, -x * 0.5, x * 1e-3, x * 1e-9]);
            let (s, c) = xs.sin_cos();
            for l in 0..4 {
                let (s0, c0) = sin_cos(xs.0[l]);
                assert_eq!(
                    (s.0[l].to_bits(), c.0[l].to_bits()),
                    (s0.to_bits(), c0.to_bits()),
                    "{}",
                    xs.0[l]
                );
                checked += 1;
            }
            x += 0.377_123;
        }
        for i in -2000..2000 {
            let x = f64::from(i) * core::f64::consts::FRAC_PI_4;
            let xs = Lanes([x, x * (1.0 + 1e-15), -0.0, 0.0]);
            let (s, c) = xs.sin_cos();
            for l in 0..4 {
                let (s0, c0) = sin_cos(xs.0[l]);
                assert_eq!(
                    (s.0[l].to_bits(), c.0[l].to_bits()),
                    (s0.to_bits(), c0.to_bits()),
                    "{}",
                    xs.0[l]
                );
            }
        }
        assert!(checked > 1_000_000);
    }

    #[test]
    fn sin_cos_is_within_two_ulps_of_libm() {
        let mut x = -1e5 + 0.1;
        while x < 1e5 {
            let (s, c) = sin_cos(x);
            assert!((s - x.sin()).abs() <= 2.0 * f64::EPSILON, "sin {x}");
            assert!((c - x.cos()).abs() <= 2.0 * f64::EPSILON, "cos {x}");
            x += 0.731;
        }
        assert_eq!(sin_cos(2e5), 2e5f64.sin_cos());
    }

    #[test]
    fn lane_transpose_and_identity_are_the_scalar_ones() {
        let m = DMat3::from_cols(
            DVec3::new(0.1, 0.2, 0.3),
            DVec3::new(-0.4, 0.5, 0.6),
            DVec3::new(0.7, -0.8, 0.9),
        );
        let l = <LMat3<4> as Matrix3<Lanes<4>>>::from_const(&m);
        assert_eq!(Matrix3::transpose(&l).lane(2), m.transpose());
        assert_eq!(
            <LMat3<4> as Matrix3<Lanes<4>>>::IDENTITY.lane(1),
            DMat3::IDENTITY
        );
    }
}
