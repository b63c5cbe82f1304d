//! Lane forms of the symmetric 3x3 matrix and of the articulated-body inertia of `aba.rs`, with
//! the scalar types' arithmetic in the same order (so each lane is the scalar result bit for
//! bit).

use kinetree_kinematics::spatial::lanes::{LForce, LMat3, LMotion, LVec3, Lanes};
use kinetree_kinematics::spatial::real::{Matrix3 as _, Vector3 as _};
use kinetree_kinematics::spatial::{Inertia, Symmetric3};

/// A symmetric 3x3 matrix per lane (the lane form of [`Symmetric3`]).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LSym3<const L: usize> {
    pub(crate) xx: Lanes<L>,
    pub(crate) xy: Lanes<L>,
    pub(crate) xz: Lanes<L>,
    pub(crate) yy: Lanes<L>,
    pub(crate) yz: Lanes<L>,
    pub(crate) zz: Lanes<L>,
}

impl<const L: usize> LSym3<L> {
    /// As [`Symmetric3::mul_vec3`].
    #[inline(always)]
    pub(crate) fn mul_vec(&self, v: &LVec3<L>) -> LVec3<L> {
        LVec3 {
            x: self.xx * v.x + self.xy * v.y + self.xz * v.z,
            y: self.xy * v.x + self.yy * v.y + self.yz * v.z,
            z: self.xz * v.x + self.yz * v.y + self.zz * v.z,
        }
    }

    /// As `Symmetric3 + Symmetric3`.
    #[inline(always)]
    pub(crate) fn add(&self, o: &Self) -> Self {
        Self {
            xx: self.xx + o.xx,
            xy: self.xy + o.xy,
            xz: self.xz + o.xz,
            yy: self.yy + o.yy,
            yz: self.yz + o.yz,
            zz: self.zz + o.zz,
        }
    }

    /// As `Symmetric3 * f64`.
    #[inline(always)]
    pub(crate) fn scale_by(&self, s: f64) -> Self {
        Self {
            xx: self.xx * s,
            xy: self.xy * s,
            xz: self.xz * s,
            yy: self.yy * s,
            yz: self.yz * s,
            zz: self.zz * s,
        }
    }

    /// As [`Symmetric3::skew_square`].
    #[inline(always)]
    pub(crate) fn skew_square(v: &LVec3<L>) -> Self {
        let (x, y, z) = (v.x, v.y, v.z);
        Self {
            xx: y * y + z * z,
            xy: -x * y,
            xz: -x * z,
            yy: x * x + z * z,
            yz: -y * z,
            zz: x * x + y * y,
        }
    }

    /// As [`Symmetric3::rotate`] of a constant `s` by the lanes' rotation `r`.
    #[inline(always)]
    pub(crate) fn rotated(s: &Symmetric3, r: &LMat3<L>) -> Self {
        let m0 = r.mul_const_vec(s.column(0));
        let m1 = r.mul_const_vec(s.column(1));
        let m2 = r.mul_const_vec(s.column(2));
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

    /// As [`Symmetric3::trace`].
    #[inline(always)]
    pub(crate) fn trace(&self) -> Lanes<L> {
        self.xx + self.yy + self.zz
    }
}

/// A rigid-body inertia per lane expressed in the world frame: the constant mass, the lanes'
/// centre of mass and rotational inertia about it (the lane form of [`Inertia`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LRigid<const L: usize> {
    pub(crate) mass: f64,
    pub(crate) com: LVec3<L>,
    pub(crate) rotational: LSym3<L>,
}

impl<const L: usize> LRigid<L> {
    /// As [`Inertia::transformed`] of a constant inertia by the lanes' placement.
    #[inline(always)]
    pub(crate) fn transformed(i: &Inertia, rotation: &LMat3<L>, translation: &LVec3<L>) -> Self {
        Self {
            mass: i.mass,
            com: rotation.mul_const_vec(i.com) + *translation,
            rotational: LSym3::rotated(&i.rotational, rotation),
        }
    }

    /// As [`Inertia::mul_motion`].
    #[inline(always)]
    pub(crate) fn mul_motion(&self, v: &LMotion<L>) -> LForce<L> {
        let lin = (v.linear + v.angular.cross(&self.com)).scale_by(self.mass);
        LForce {
            linear: lin,
            angular: self.com.cross(&lin) + self.rotational.mul_vec(&v.angular),
        }
    }
}

/// The lane form of `ArticulatedInertia`: `f = A·v + B·ω`, `n = Bᵀ·v + C·ω`.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LArticulated<const L: usize> {
    a: LSym3<L>,
    b: LMat3<L>,
    c: LSym3<L>,
}

impl<const L: usize> LArticulated<L> {
    /// As `ArticulatedInertia::from_inertia`.
    #[inline(always)]
    pub(crate) fn from_rigid(i: &LRigid<L>) -> Self {
        let m = Lanes::splat(i.mass);
        let mc = i.com.scale_by(i.mass);
        let zero = Lanes::ZERO;
        Self {
            a: LSym3 {
                xx: m,
                xy: zero,
                xz: zero,
                yy: m,
                yz: zero,
                zz: m,
            },
            b: LMat3 {
                x_axis: LVec3 {
                    x: zero,
                    y: -mc.z,
                    z: mc.y,
                },
                y_axis: LVec3 {
                    x: mc.z,
                    y: zero,
                    z: -mc.x,
                },
                z_axis: LVec3 {
                    x: -mc.y,
                    y: mc.x,
                    z: zero,
                },
            },
            // `rotational_about(0)`: `com - 0` is `com`.
            c: i.rotational
                .add(&LSym3::skew_square(&i.com).scale_by(i.mass)),
        }
    }

    /// As `ArticulatedInertia::mul_motion`.
    #[inline(always)]
    pub(crate) fn mul_motion(&self, m: &LMotion<L>) -> LForce<L> {
        let (v, w) = (&m.linear, &m.angular);
        LForce {
            linear: self.a.mul_vec(v) + self.b.mul_vec(w),
            angular: self.b.transpose_mul_vec(v) + self.c.mul_vec(w),
        }
    }

    /// As `ArticulatedInertia::sub_outer`.
    #[inline(always)]
    pub(crate) fn sub_outer(&mut self, x: &LForce<L>, y: &LForce<L>) {
        let (xl, xa, yl, ya) = (&x.linear, &x.angular, &y.linear, &y.angular);
        self.a.xx -= xl.x * yl.x;
        self.a.xy -= xl.x * yl.y;
        self.a.xz -= xl.x * yl.z;
        self.a.yy -= xl.y * yl.y;
        self.a.yz -= xl.y * yl.z;
        self.a.zz -= xl.z * yl.z;
        self.b.x_axis -= xl.scale(ya.x);
        self.b.y_axis -= xl.scale(ya.y);
        self.b.z_axis -= xl.scale(ya.z);
        self.c.xx -= xa.x * ya.x;
        self.c.xy -= xa.x * ya.y;
        self.c.xz -= xa.x * ya.z;
        self.c.yy -= xa.y * ya.y;
        self.c.yz -= xa.y * ya.z;
        self.c.zz -= xa.z * ya.z;
    }

    /// As `ArticulatedInertia::add_assign`.
    #[inline(always)]
    pub(crate) fn add_assign(&mut self, o: &Self) {
        self.a = self.a.add(&o.a);
        self.b.x_axis += o.b.x_axis;
        self.b.y_axis += o.b.y_axis;
        self.b.z_axis += o.b.z_axis;
        self.c = self.c.add(&o.c);
    }

    /// As `ArticulatedInertia::scale`.
    #[inline(always)]
    pub(crate) fn scale(&self) -> Lanes<L> {
        self.a.trace().map(f64::abs) + self.c.trace().map(f64::abs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aba::ArticulatedInertia;
    use kinetree_kinematics::spatial::glam::DVec3;
    use kinetree_kinematics::spatial::lanes::LSe3;
    use kinetree_kinematics::spatial::{Force, Motion, Se3};

    #[test]
    fn every_lane_is_the_scalar_result_bit_for_bit() {
        let xs = [
            Se3::from_xyz_rpy([0.1, 0.2, 0.3], [0.4, 0.5, 0.6]),
            Se3::from_xyz_rpy([-0.3, 0.0, 0.7], [0.1, -0.2, 0.3]),
            Se3::from_xyz_rpy([1.3, -2.0, 0.1], [3.0, 1.2, -2.3]),
            Se3::from_xyz_rpy([0.0, 0.5, -0.5], [-1.0, 0.0, 2.0]),
        ];
        let body = Inertia::new(
            2.5,
            DVec3::new(0.1, -0.2, 0.3),
            Symmetric3::new(0.4, 0.01, -0.02, 0.5, 0.03, 0.6),
        );
        let mut lx = LSe3::<4>::default();
        let (mut lm, mut lf) = (LMotion::<4>::zero(), LForce::<4>::zero());
        let ms = xs.map(|x| Motion::new(x.translation, x.rotation.y_axis * 1.3));
        let fs = xs.map(|x| Force::new(x.rotation.z_axis, x.translation * -0.7));
        for l in 0..4 {
            lx.set_lane(l, &xs[l]);
            lm.set_lane(l, &ms[l]);
            lf.set_lane(l, &fs[l]);
        }
        let rigid = LRigid::transformed(&body, &lx.rotation, &lx.translation);
        let mut art = LArticulated::from_rigid(&rigid);
        let before = art;
        art.sub_outer(&lf, &rigid.mul_motion(&lm));
        art.add_assign(&before);
        let (m, scale) = (art.mul_motion(&lm), art.scale());
        for l in 0..4 {
            let r = body.transformed(&xs[l]);
            assert_eq!(rigid.mul_motion(&lm).lane(l), r.mul_motion(&ms[l]));
            let mut a = ArticulatedInertia::from_inertia(&r);
            let b = a;
            a.sub_outer(&fs[l], &r.mul_motion(&ms[l]));
            a.add_assign(&b);
            assert_eq!(m.lane(l), a.mul_motion(&ms[l]));
            assert_eq!(scale.0[l], a.scale());
        }
    }
}
