//! Lane forms of the composite inertia about a frame origin (`OriginInertia`) and of the
//! rotation forms that move it (`RotationForm`), with the scalar arithmetic in the same order
//! (so each lane is the scalar result bit for bit).

use super::articulated::LSym3;
use kinetree_kinematics::spatial::lanes::{LForce, LMat3, LMotion, LVec3, Lanes};
use kinetree_kinematics::spatial::real::{Matrix3 as _, Vector3 as _};
use kinetree_kinematics::spatial::{OriginInertia, RotationForm, Symmetric3};

impl<const L: usize> LSym3<L> {
    /// `s` in every lane.
    #[inline(always)]
    pub(crate) fn splat(s: &Symmetric3) -> Self {
        Self {
            xx: Lanes::splat(s.xx),
            xy: Lanes::splat(s.xy),
            xz: Lanes::splat(s.xz),
            yy: Lanes::splat(s.yy),
            yz: Lanes::splat(s.yz),
            zz: Lanes::splat(s.zz),
        }
    }

    /// Entry `(i, j)` (as [`Symmetric3::get`]).
    #[inline(always)]
    fn get(&self, i: usize, j: usize) -> Lanes<L> {
        match (i.min(j), i.max(j)) {
            (0, 0) => self.xx,
            (0, 1) => self.xy,
            (0, _) => self.xz,
            (1, 1) => self.yy,
            (1, _) => self.yz,
            _ => self.zz,
        }
    }

    /// Sets entry `(i, j)` (as [`Symmetric3::set`]).
    #[inline(always)]
    fn set(&mut self, i: usize, j: usize, x: Lanes<L>) {
        match (i.min(j), i.max(j)) {
            (0, 0) => self.xx = x,
            (0, 1) => self.xy = x,
            (0, _) => self.xz = x,
            (1, 1) => self.yy = x,
            (1, _) => self.yz = x,
            _ => self.zz = x,
        }
    }

    /// Column `k` (as [`Symmetric3::column`]).
    #[inline(always)]
    fn column(&self, k: usize) -> LVec3<L> {
        match k {
            0 => LVec3 {
                x: self.xx,
                y: self.xy,
                z: self.xz,
            },
            1 => LVec3 {
                x: self.xy,
                y: self.yy,
                z: self.yz,
            },
            _ => LVec3 {
                x: self.xz,
                y: self.yz,
                z: self.zz,
            },
        }
    }

    /// As [`Symmetric3::rotate`] by the lanes' rotation `r`.
    #[inline(always)]
    fn rotate(&self, r: &LMat3<L>) -> Self {
        let m0 = r.mul_vec(&self.column(0));
        let m1 = r.mul_vec(&self.column(1));
        let m2 = r.mul_vec(&self.column(2));
        let entry = |i: usize, j: usize| {
            m0.get(i) * r.x_axis.get(j) + m1.get(i) * r.y_axis.get(j) + m2.get(i) * r.z_axis.get(j)
        };
        Self {
            xx: entry(0, 0),
            xy: entry(0, 1),
            xz: entry(0, 2),
            yy: entry(1, 1),
            yz: entry(1, 2),
            zz: entry(2, 2),
        }
    }
}

/// A rotation in the form the kernels apply it in, per lane (the lane form of
/// [`RotationForm`]).
#[derive(Clone, Copy, Debug)]
pub(crate) enum LRotation<const L: usize> {
    /// No rotation.
    Identity,
    /// About coordinate axis `k` by the lanes' angles.
    Axis { k: usize, s: Lanes<L>, c: Lanes<L> },
    /// A general rotation per lane.
    General(LMat3<L>),
}

/// The indices `(i, j, k)` of a rotation about axis `k` (as `per_axis!` of `rotation_form.rs`).
#[inline(always)]
fn axis_indices(k: usize) -> (usize, usize, usize) {
    match k {
        0 => (1, 2, 0),
        1 => (2, 0, 1),
        _ => (0, 1, 2),
    }
}

impl<const L: usize> LRotation<L> {
    /// A constant form in every lane.
    #[inline(always)]
    pub(crate) fn splat(r: &RotationForm) -> Self {
        match *r {
            RotationForm::Identity => Self::Identity,
            RotationForm::Axis { k, s, c } => Self::Axis {
                k,
                s: Lanes::splat(s),
                c: Lanes::splat(c),
            },
            RotationForm::General(m) => Self::General(LMat3::splat(&m)),
        }
    }

    /// As [`RotationForm::apply`].
    #[inline(always)]
    fn apply(&self, v: &LVec3<L>) -> LVec3<L> {
        match *self {
            Self::Identity => *v,
            Self::Axis { k: 0, s, c } => axis_apply::<L, 0>(s, c, v),
            Self::Axis { k: 1, s, c } => axis_apply::<L, 1>(s, c, v),
            Self::Axis { s, c, .. } => axis_apply::<L, 2>(s, c, v),
            Self::General(r) => r.mul_vec(v),
        }
    }

    /// As [`RotationForm::apply_sym`].
    #[inline(always)]
    fn apply_sym(&self, m: &LSym3<L>) -> LSym3<L> {
        match *self {
            Self::Identity => *m,
            Self::Axis { k: 0, s, c } => axis_apply_sym::<L, 0>(s, c, m),
            Self::Axis { k: 1, s, c } => axis_apply_sym::<L, 1>(s, c, m),
            Self::Axis { s, c, .. } => axis_apply_sym::<L, 2>(s, c, m),
            Self::General(r) => m.rotate(&r),
        }
    }
}

/// A rotation about coordinate axis `K` (sines `s`, cosines `c`) applied to `v`, as
/// [`RotationForm::apply`]. The axis is a constant, so that the entries stay in registers: with
/// the axis known only at run time they were read and written through memory.
#[inline(always)]
fn axis_apply<const L: usize, const K: usize>(s: Lanes<L>, c: Lanes<L>, v: &LVec3<L>) -> LVec3<L> {
    let (i, j, _) = axis_indices(K);
    let (vi, vj) = (v.get(i), v.get(j));
    let mut out = *v;
    *out.get_mut(i) = c * vi - s * vj;
    *out.get_mut(j) = s * vi + c * vj;
    out
}

/// A rotation about coordinate axis `K` applied to a symmetric matrix, as
/// [`RotationForm::apply_sym`] (see [`axis_apply`]).
#[inline(always)]
fn axis_apply_sym<const L: usize, const K: usize>(
    s: Lanes<L>,
    c: Lanes<L>,
    m: &LSym3<L>,
) -> LSym3<L> {
    let (i, j, kk) = axis_indices(K);
    let (a, b, d) = (m.get(i, i), m.get(i, j), m.get(j, j));
    let (ik, jk) = (m.get(i, kk), m.get(j, kk));
    let (cc, ss, cs) = (c * c, s * s, c * s);
    let mut out = *m;
    out.set(i, i, cc * a - cs * 2.0 * b + ss * d);
    out.set(j, j, ss * a + cs * 2.0 * b + cc * d);
    out.set(i, j, cs * (a - d) + (cc - ss) * b);
    out.set(i, kk, c * ik - s * jk);
    out.set(j, kk, s * ik + c * jk);
    out
}

/// A spatial inertia about the frame origin per lane (the lane form of [`OriginInertia`]).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LOrigin<const L: usize> {
    pub(crate) m: Lanes<L>,
    pub(crate) h: LVec3<L>,
    pub(crate) i: LSym3<L>,
}

impl<const L: usize> LOrigin<L> {
    /// `y` in every lane.
    #[inline(always)]
    pub(crate) fn splat(y: &OriginInertia) -> Self {
        Self {
            m: Lanes::splat(y.m),
            h: LVec3::splat(y.h),
            i: LSym3::splat(&y.i),
        }
    }

    /// As [`OriginInertia::add_assign`].
    #[inline(always)]
    pub(crate) fn add_assign(&mut self, o: &Self) {
        self.m += o.m;
        self.h += o.h;
        self.i = self.i.add(&o.i);
    }

    /// As [`OriginInertia::mul_motion`].
    #[inline(always)]
    pub(crate) fn mul_motion(&self, s: &LMotion<L>) -> LForce<L> {
        LForce {
            linear: s.linear.scale(self.m) + s.angular.cross(&self.h),
            angular: self.h.cross(&s.linear) + self.i.mul_vec(&s.angular),
        }
    }

    /// As [`OriginInertia::translated`].
    #[inline(always)]
    pub(crate) fn translated(&self, t: &LVec3<L>) -> Self {
        let u = self.h + t.scale(self.m * 0.5);
        let d = u.dot(t) * 2.0;
        let ir = &self.i;
        Self {
            m: self.m,
            h: self.h + t.scale(self.m),
            i: LSym3 {
                xx: ir.xx - t.x * 2.0 * u.x + d,
                xy: ir.xy - (t.x * u.y + u.x * t.y),
                xz: ir.xz - (t.x * u.z + u.x * t.z),
                yy: ir.yy - t.y * 2.0 * u.y + d,
                yz: ir.yz - (t.y * u.z + u.y * t.z),
                zz: ir.zz - t.z * 2.0 * u.z + d,
            },
        }
    }

    /// As [`OriginInertia::rotated`].
    #[inline(always)]
    pub(crate) fn rotated(&self, r: &LRotation<L>) -> Self {
        Self {
            m: self.m,
            h: r.apply(&self.h),
            i: r.apply_sym(&self.i),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetree_kinematics::spatial::glam::DVec3;
    use kinetree_kinematics::spatial::{Inertia, Motion, Se3};

    #[test]
    fn every_lane_is_the_scalar_result_bit_for_bit() {
        let xs = [
            Se3::from_xyz_rpy([0.1, 0.2, 0.3], [0.4, 0.5, 0.6]),
            Se3::from_xyz_rpy([-0.3, 0.0, 0.7], [0.1, -0.2, 0.3]),
            Se3::from_xyz_rpy([1.3, -2.0, 0.1], [3.0, 1.2, -2.3]),
            Se3::from_xyz_rpy([0.0, 0.5, -0.5], [-1.0, 0.0, 2.0]),
        ];
        let y = OriginInertia::from_inertia(&Inertia::new(
            2.5,
            DVec3::new(0.1, -0.2, 0.3),
            Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6),
        ));
        let angles: [f64; 4] = [0.3, -1.2, 2.9, 0.0];
        let mut rot = LMat3::<4>::default();
        let mut t = LVec3::<4>::ZERO;
        let (mut s, mut c) = (Lanes::<4>::ZERO, Lanes::<4>::ZERO);
        let mut m = LMotion::<4>::zero();
        for l in 0..4 {
            rot.set_lane(l, &xs[l].rotation);
            t.set_lane(l, xs[l].translation);
            (s.0[l], c.0[l]) = angles[l].sin_cos();
            m.set_lane(l, &Motion::new(xs[l].translation, xs[l].rotation.x_axis));
        }
        let constant = RotationForm::classify(&xs[1].rotation);
        for k in 0..3 {
            let lanes = LOrigin::splat(&y)
                .rotated(&LRotation::Axis { k, s, c })
                .rotated(&LRotation::splat(&constant))
                .rotated(&LRotation::General(rot))
                .translated(&t);
            let mut sum = lanes;
            sum.add_assign(&lanes);
            let f = sum.mul_motion(&m);
            for l in 0..4 {
                let (sl, cl) = (s.0[l], c.0[l]);
                let one = y
                    .rotated(&RotationForm::Axis { k, s: sl, c: cl })
                    .rotated(&constant)
                    .rotated(&RotationForm::General(xs[l].rotation))
                    .translated(xs[l].translation);
                let mut two = one;
                two.add_assign(&one);
                assert_eq!(f.lane(l), two.mul_motion(&m.lane(l)));
                assert_eq!(lanes.h.lane(l), one.h);
                let i = &lanes.i;
                let got = [i.xx, i.xy, i.xz, i.yy, i.yz, i.zz].map(|x| x.0[l]);
                assert_eq!(got, one.i.to_urdf_array());
            }
        }
    }
}
