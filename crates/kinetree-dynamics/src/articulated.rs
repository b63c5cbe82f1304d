//! The spatial inertias of the articulated-body algorithm, for one state and for lanes: a rigid
//! body's inertia moved to the world frame ([`RigidInertia`]) and the symmetric 6x6 inertia in
//! 3x3 blocks that ABA accumulates ([`ArticulatedInertia`]).

use kinetree_kinematics::spatial::real::{Matrix3, Real, Vector3};
use kinetree_kinematics::spatial::{Force, Inertia, Motion, Se3, Symmetric3};

/// A rigid body's inertia expressed in another frame: its (constant) mass, centre of mass and
/// rotational inertia about the centre of mass in that frame's axes. The number-generic form of
/// [`Inertia::transformed`] and [`Inertia::mul_motion`], with their operations in their order.
#[derive(Debug)]
pub(crate) struct RigidInertia<T: Real> {
    mass: f64,
    com: T::V3,
    rotational: Symmetric3<T>,
}

kinetree_kinematics::spatial::copy_by_value!(RigidInertia, ArticulatedInertia);

impl<T: Real> RigidInertia<T> {
    /// `i` (given in frame `b`) in frame `a`, for `a_from_b = x`.
    #[inline(always)]
    pub(crate) fn transformed(i: &Inertia, x: &Se3<T>) -> Self {
        Self {
            mass: i.mass,
            com: x.rotation.mul_const_vec(i.com) + x.translation,
            rotational: Symmetric3::from_const(&i.rotational).rotate(&x.rotation),
        }
    }

    /// The momentum `I·v`.
    #[inline(always)]
    pub(crate) fn mul_motion(&self, v: &Motion<T>) -> Force<T> {
        let lin = (v.linear + v.angular.cross(&self.com)).scale_by(self.mass);
        Force {
            linear: lin,
            angular: self.com.cross(&lin) + self.rotational.mul_vec(&v.angular),
        }
    }
}

/// A symmetric 6x6 spatial inertia (rigid or articulated) in 3x3 blocks, acting on
/// `[linear; angular]` motions: `f = A·v + B·ω`, `n = Bᵀ·v + C·ω`. Generic over the number type
/// as the spatial types (`ArticulatedInertia` is the one-state form).
#[derive(Debug, PartialEq)]
pub(crate) struct ArticulatedInertia<T: Real = f64> {
    a: Symmetric3<T>,
    b: T::M3,
    c: Symmetric3<T>,
}

impl<T: Real> Default for ArticulatedInertia<T> {
    #[inline(always)]
    fn default() -> Self {
        let zero = Symmetric3::from_const(&Symmetric3::ZERO);
        Self {
            a: zero,
            b: T::M3::from_cols(T::V3::ZERO, T::V3::ZERO, T::V3::ZERO),
            c: zero,
        }
    }
}

impl<T: Real> ArticulatedInertia<T> {
    /// The 6x6 form of a rigid-body inertia.
    #[inline(always)]
    pub(crate) fn from_rigid(i: &RigidInertia<T>) -> Self {
        let m = T::splat(i.mass);
        let mc = i.com.scale_by(i.mass);
        let (x, y, z, o) = (mc.get(0), mc.get(1), mc.get(2), T::ZERO);
        Self {
            a: Symmetric3 {
                xx: m,
                xy: o,
                xz: o,
                yy: m,
                yz: o,
                zz: m,
            },
            // -m·[c]×
            b: T::M3::from_cols(
                T::V3::new(o, -z, y),
                T::V3::new(z, o, -x),
                T::V3::new(-y, x, o),
            ),
            // `rotational_about(0)`: `com - 0` is `com`.
            c: i.rotational.add_parallel_axis(&i.com, i.mass),
        }
    }

    /// `I·m`.
    #[inline(always)]
    pub(crate) fn mul_motion(&self, m: &Motion<T>) -> Force<T> {
        let (v, w) = (&m.linear, &m.angular);
        Force {
            linear: self.a.mul_vec(v) + self.b.mul_vec(w),
            angular: self.b.transpose_mul_vec(v) + self.c.mul_vec(w),
        }
    }

    /// `self -= x·yᵀ` for two force-like 6-vectors, where the result is known to be symmetric
    /// (ABA's `Iᵃ - U·D⁻¹·Uᵀ`): only the upper triangles of the diagonal blocks are updated.
    #[inline(always)]
    pub(crate) fn sub_outer(&mut self, x: &Force<T>, y: &Force<T>) {
        let (xl, xa, yl, ya) = (&x.linear, &x.angular, &y.linear, &y.angular);
        sub_outer_sym::<T>(&mut self.a, xl, yl);
        // B (linear rows, angular columns) gets x_lin·y_angᵀ.
        let b = &self.b;
        self.b = T::M3::from_cols(
            b.col(0) - xl.scale(ya.get(0)),
            b.col(1) - xl.scale(ya.get(1)),
            b.col(2) - xl.scale(ya.get(2)),
        );
        sub_outer_sym::<T>(&mut self.c, xa, ya);
    }

    /// `self += o`.
    #[inline(always)]
    pub(crate) fn add_assign(&mut self, o: &Self) {
        self.a += o.a;
        let b = &self.b;
        self.b = T::M3::from_cols(
            b.col(0) + o.b.col(0),
            b.col(1) + o.b.col(1),
            b.col(2) + o.b.col(2),
        );
        self.c += o.c;
    }

    /// A magnitude for pivot tolerances: the traces of the diagonal blocks.
    #[inline(always)]
    pub(crate) fn scale(&self) -> T {
        self.a.trace().abs() + self.c.trace().abs()
    }
}

/// The upper triangle of `s -= x·yᵀ`.
#[inline(always)]
fn sub_outer_sym<T: Real>(s: &mut Symmetric3<T>, x: &T::V3, y: &T::V3) {
    let (x0, x1, x2) = (x.get(0), x.get(1), x.get(2));
    let (y0, y1, y2) = (y.get(0), y.get(1), y.get(2));
    s.xx -= x0 * y0;
    s.xy -= x0 * y1;
    s.xz -= x0 * y2;
    s.yy -= x1 * y1;
    s.yz -= x1 * y2;
    s.zz -= x2 * y2;
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetree_kinematics::spatial::glam::DVec3;
    use kinetree_kinematics::spatial::lanes::{LForce, LMotion, LSe3, Lanes};

    #[test]
    fn the_one_state_forms_are_the_inertia_products_and_every_lane_is_one_state() {
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
        let rigid = RigidInertia::<Lanes<4>>::transformed(&body, &lx);
        let mut art = ArticulatedInertia::from_rigid(&rigid);
        let before = art;
        art.sub_outer(&lf, &rigid.mul_motion(&lm));
        art.add_assign(&before);
        let (m, scale) = (art.mul_motion(&lm), art.scale());
        for l in 0..4 {
            // One state: the products of `Inertia`, bit for bit.
            let r = body.transformed(&xs[l]);
            let one = RigidInertia::<f64>::transformed(&body, &xs[l]);
            assert_eq!(one.mul_motion(&ms[l]), r.mul_motion(&ms[l]));
            let mut a = ArticulatedInertia::from_rigid(&one);
            // The 6x6 matrix of the articulated form is the rigid body's.
            let matrix = r.to_matrix();
            for k in 0..6 {
                let mut e = [0.0; 6];
                e[k] = 1.0;
                let col = a.mul_motion(&Motion::from_array(e)).to_array();
                for (row, c) in col.iter().enumerate() {
                    assert!((c - matrix[row][k]).abs() < 1e-14, "({row}, {k})");
                }
            }
            let b = a;
            a.sub_outer(&fs[l], &one.mul_motion(&ms[l]));
            a.add_assign(&b);
            // Every lane is the one-state result.
            assert_eq!(rigid.mul_motion(&lm).lane(l), r.mul_motion(&ms[l]));
            assert_eq!(m.lane(l), a.mul_motion(&ms[l]));
            assert_eq!(scale.0[l], a.scale());
        }
    }
}
