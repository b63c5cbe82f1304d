//! Masses and inertias as MuJoCo's compiler infers them from geoms: the volume (or surface) of
//! each primitive, its principal moments, and a body's total over its geoms.

use glam::{DMat3, DVec3};
use kinetree_spatial::Symmetric3;

/// A geom's shape as far as inertia is concerned, with MuJoCo's `size` semantics (half sizes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Solid {
    /// Radius.
    Sphere(f64),
    /// Radius and half-length of the cylindrical part.
    Capsule(f64, f64),
    /// Radius and half-length.
    Cylinder(f64, f64),
    /// Semi-axes.
    Ellipsoid([f64; 3]),
    /// Half sides.
    Box([f64; 3]),
    /// A shape with no volume (plane) or one whose mass properties come from elsewhere.
    Empty,
}

/// Whether mass is spread through the volume (MuJoCo's default) or over the surface
/// (`shellinertia="true"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Spread {
    Volume,
    Shell,
}

impl Solid {
    /// The volume (or, for [`Spread::Shell`], the area) whose product with the density is the mass.
    pub(super) fn measure(self, spread: Spread) -> f64 {
        use core::f64::consts::PI;
        match (self, spread) {
            (Solid::Sphere(r), Spread::Volume) => 4.0 * PI * r * r * r / 3.0,
            (Solid::Sphere(r), Spread::Shell) => 4.0 * PI * r * r,
            (Solid::Capsule(r, h), Spread::Volume) => {
                PI * (r * r * (2.0 * h) + 4.0 * r * r * r / 3.0)
            }
            (Solid::Capsule(r, h), Spread::Shell) => 4.0 * PI * r * r + 2.0 * PI * r * (2.0 * h),
            (Solid::Cylinder(r, h), Spread::Volume) => PI * r * r * (2.0 * h),
            (Solid::Cylinder(r, h), Spread::Shell) => 2.0 * PI * r * r + 2.0 * PI * r * (2.0 * h),
            (Solid::Ellipsoid([a, b, c]), Spread::Volume) => 4.0 * PI * a * b * c / 3.0,
            (Solid::Ellipsoid([a, b, c]), Spread::Shell) => {
                // Thomsen's approximation of the surface, as MuJoCo.
                let p = 1.6075;
                let t = (a * b).powf(p) + (b * c).powf(p) + (c * a).powf(p);
                4.0 * PI * (t / 3.0).powf(1.0 / p)
            }
            (Solid::Box([a, b, c]), Spread::Volume) => 8.0 * a * b * c,
            (Solid::Box([a, b, c]), Spread::Shell) => 8.0 * (a * b + b * c + c * a),
            (Solid::Empty, _) => 0.0,
        }
    }

    /// Principal moments about the centre of mass, in the geom frame, for mass `m`.
    pub(super) fn moments(self, m: f64, spread: Spread) -> [f64; 3] {
        use core::f64::consts::PI;
        match (self, spread) {
            (Solid::Sphere(r), Spread::Volume) => [2.0 * m * r * r / 5.0; 3],
            (Solid::Sphere(r), Spread::Shell) => [2.0 * m * r * r / 3.0; 3],
            (Solid::Capsule(r, hh), Spread::Volume) => {
                let h = 2.0 * hh;
                let m_sphere = m * 4.0 * r / (4.0 * r + 3.0 * h);
                let m_cyl = m - m_sphere;
                let i_sphere = 2.0 * m_sphere * r * r / 5.0;
                let side = m_cyl * (3.0 * r * r + h * h) / 12.0
                    + i_sphere
                    + m_sphere * h * (3.0 * r + 2.0 * h) / 8.0;
                [side, side, m_cyl * r * r / 2.0 + i_sphere]
            }
            (Solid::Capsule(r, hh), Spread::Shell) => {
                let h = 2.0 * hh;
                let a_sphere = 4.0 * PI * r * r;
                let a_cyl = 2.0 * PI * r * h;
                let m_sphere = m * a_sphere / (a_sphere + a_cyl);
                let m_cyl = m - m_sphere;
                let i_sphere = 2.0 * m_sphere * r * r / 3.0;
                let com = r / 2.0;
                let at = hh + com;
                let side = m_cyl * (6.0 * r * r + h * h) / 12.0
                    + i_sphere
                    + m_sphere * (at * at - com * com);
                [side, side, m_cyl * r * r + i_sphere]
            }
            (Solid::Cylinder(r, hh), Spread::Volume) => {
                let h = 2.0 * hh;
                let side = m * (3.0 * r * r + h * h) / 12.0;
                [side, side, m * r * r / 2.0]
            }
            (Solid::Cylinder(r, hh), Spread::Shell) => {
                let h = 2.0 * hh;
                let a_disk = PI * r * r;
                let a_cyl = 2.0 * PI * r * h;
                let m_disk = m * a_disk / (2.0 * a_disk + a_cyl);
                let m_cyl = m - 2.0 * m_disk;
                let disk_x = m_disk * r * r / 4.0 + m_disk * hh * hh;
                let disk_z = m_disk * r * r / 2.0;
                let side = m_cyl * (6.0 * r * r + h * h) / 12.0 + 2.0 * disk_x;
                [side, side, m_cyl * r * r + 2.0 * disk_z]
            }
            (Solid::Ellipsoid([a, b, c]), Spread::Volume) => [
                m * (b * b + c * c) / 5.0,
                m * (a * a + c * c) / 5.0,
                m * (a * a + b * b) / 5.0,
            ],
            (Solid::Ellipsoid([a, b, c]), Spread::Shell) => {
                // The difference of two solid ellipsoids 1e-6 apart, as MuJoCo.
                let eps = 1e-6;
                let va = 4.0 * PI * a * b * c / 3.0;
                let (ae, be, ce) = (a + eps, b + eps, c + eps);
                let vb = 4.0 * PI * ae * be * ce / 3.0;
                let density = m / (vb - va);
                let (ma, mb) = (va * density, vb * density);
                [
                    mb * (be * be + ce * ce) / 5.0 - ma * (b * b + c * c) / 5.0,
                    mb * (ae * ae + ce * ce) / 5.0 - ma * (a * a + c * c) / 5.0,
                    mb * (ae * ae + be * be) / 5.0 - ma * (a * a + b * b) / 5.0,
                ]
            }
            (Solid::Box([a, b, c]), Spread::Volume) => [
                m * (b * b + c * c) / 3.0,
                m * (a * a + c * c) / 3.0,
                m * (a * a + b * b) / 3.0,
            ],
            (Solid::Box([a, b, c]), Spread::Shell) => {
                let (lx, ly, lz) = (2.0 * a, 2.0 * b, 2.0 * c);
                let (a0, a1, a2) = (lx * ly, ly * lz, lz * lx);
                let total = 2.0 * (a0 + a1 + a2);
                let (m0, m1, m2) = (m * a0 / total, m * a1 / total, m * a2 / total);
                let ix =
                    m0 * ly * ly / 12.0 + m1 * (ly * ly + lz * lz) / 12.0 + m2 * lz * lz / 12.0;
                let iy =
                    m0 * lx * lx / 12.0 + m1 * lz * lz / 12.0 + m2 * (lx * lx + lz * lz) / 12.0;
                let iz =
                    m0 * (lx * lx + ly * ly) / 12.0 + m1 * ly * ly / 12.0 + m2 * lx * lx / 12.0;
                [
                    2.0 * (m0 * c * c + m2 * b * b + ix),
                    2.0 * (m0 * c * c + m1 * a * a + iy),
                    2.0 * (m1 * a * a + m2 * b * b + iz),
                ]
            }
            (Solid::Empty, _) => [0.0; 3],
        }
    }
}

/// A point mass's share of a body's rotational inertia: `m (|d|² I − d dᵀ)`.
fn off_center(m: f64, d: DVec3) -> Symmetric3 {
    Symmetric3::skew_square(d) * m
}

/// The mass properties of one geom: mass, its centre (the geom's origin) and principal frame
/// (the geom's axes) in the body frame, and its principal moments.
#[derive(Clone, Copy, Debug)]
pub(super) struct GeomMass {
    pub(super) mass: f64,
    pub(super) pos: DVec3,
    pub(super) rot: DMat3,
    pub(super) moments: [f64; 3],
}

/// A body's inertial frame and principal moments, as MuJoCo stores it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct BodyMass {
    pub(super) mass: f64,
    pub(super) pos: DVec3,
    pub(super) rot: DMat3,
    pub(super) moments: [f64; 3],
}

/// The total of a body's geoms, as MuJoCo's `InertiaFromGeom`: geoms of mass ≤ 1e-14 are left
/// out; one geom gives its own frame; several give their common centre of mass and the
/// principal axes of their summed inertia. `None` when no geom has mass.
pub(super) fn from_geoms(geoms: &[GeomMass]) -> Result<Option<BodyMass>, &'static str> {
    let selected: Vec<&GeomMass> = geoms.iter().filter(|g| g.mass > 1e-14).collect();
    match selected.as_slice() {
        [] => Ok(None),
        [one] => Ok(Some(BodyMass {
            mass: one.mass,
            pos: one.pos,
            rot: one.rot,
            moments: one.moments,
        })),
        many => {
            let mass: f64 = many.iter().map(|g| g.mass).sum();
            if mass < 1e-14 {
                return Err("body mass is too small, cannot compute center of mass");
            }
            let com = many.iter().fold(DVec3::ZERO, |c, g| c + g.pos * g.mass) / mass;
            let mut total = Symmetric3::ZERO;
            for g in many {
                let own = Symmetric3::from_diagonal(DVec3::from_array(g.moments)).rotate(&g.rot);
                total = total + own + off_center(g.mass, g.pos - com);
            }
            let (moments, rot) = principal_axes(&total);
            Ok(Some(BodyMass {
                mass,
                pos: com,
                rot,
                moments,
            }))
        }
    }
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations: the eigenvalues
/// and a right-handed rotation whose columns are the eigenvectors.
pub(super) fn principal_axes(s: &Symmetric3) -> ([f64; 3], DMat3) {
    let mut a = s.to_mat3().to_cols_array_2d();
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let scale = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= f64::EPSILON * scale * 1e-3 || off == 0.0 {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J with the rotation J in the (p, q) plane.
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // `a` is column-major from glam, but symmetric; `v`'s columns (v[row][col]) are eigenvectors.
    let values = [a[0][0], a[1][1], a[2][2]];
    let mut rot = DMat3::from_cols(
        DVec3::new(v[0][0], v[1][0], v[2][0]),
        DVec3::new(v[0][1], v[1][1], v[2][1]),
        DVec3::new(v[0][2], v[1][2], v[2][2]),
    );
    if rot.determinant() < 0.0 {
        rot.z_axis = -rot.z_axis;
    }
    (values, rot)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn primitive_volumes_and_moments_by_hand() {
        use core::f64::consts::PI;
        // A 2 × 4 × 6 box: volume 48, I_x = m (b² + c²)/3 on half sides.
        let b = Solid::Box([1.0, 2.0, 3.0]);
        assert!(close(b.measure(Spread::Volume), 48.0));
        let [ix, iy, iz] = b.moments(12.0, Spread::Volume);
        assert!(close(ix, 12.0 * (16.0 + 36.0) / 12.0) && close(iy, 12.0 * 40.0 / 12.0));
        assert!(close(iz, 12.0 * 20.0 / 12.0));
        // A capsule is a cylinder plus a sphere: volumes add, and the axial moment too.
        let (r, hh) = (0.3, 0.5);
        let cap = Solid::Capsule(r, hh);
        let v_cyl = Solid::Cylinder(r, hh).measure(Spread::Volume);
        let v_sph = Solid::Sphere(r).measure(Spread::Volume);
        assert!(close(cap.measure(Spread::Volume), v_cyl + v_sph));
        let density = 1000.0;
        let m = density * (v_cyl + v_sph);
        let axial = Solid::Cylinder(r, hh).moments(density * v_cyl, Spread::Volume)[2]
            + Solid::Sphere(r).moments(density * v_sph, Spread::Volume)[2];
        assert!(close(cap.moments(m, Spread::Volume)[2], axial));
        // About a diameter: the cylinder, plus the two hemispheres displaced along z (each
        // hemisphere's centre of mass is 3r/8 beyond the cylinder's end).
        let m_h = density * v_sph / 2.0;
        let i_hemi_com = 2.0 * m_h * r * r / 5.0 - m_h * (3.0 * r / 8.0).powi(2);
        let d = hh + 3.0 * r / 8.0;
        let side = Solid::Cylinder(r, hh).moments(density * v_cyl, Spread::Volume)[0]
            + 2.0 * (i_hemi_com + m_h * d * d);
        assert!(close(cap.moments(m, Spread::Volume)[0], side));
        // A thin spherical shell: 2/3 m r².
        assert!(close(
            Solid::Sphere(2.0).moments(3.0, Spread::Shell)[0],
            8.0
        ));
        assert!(close(Solid::Sphere(1.0).measure(Spread::Shell), 4.0 * PI));
        assert_eq!(Solid::Empty.measure(Spread::Volume), 0.0);
    }

    #[test]
    fn two_spheres_sum_about_their_common_centre() {
        let g = |x: f64| GeomMass {
            mass: 2.0,
            pos: DVec3::new(x, 0.0, 0.0),
            rot: DMat3::IDENTITY,
            moments: [0.1; 3],
        };
        let body = from_geoms(&[g(1.0), g(-1.0)]).unwrap().unwrap();
        assert!(close(body.mass, 4.0) && body.pos.length() < 1e-15);
        let mut m = body.moments;
        m.sort_by(f64::total_cmp);
        // About x: 0.2; about y and z: 0.2 + 2 · 2 · 1².
        assert!(close(m[0], 0.2) && close(m[1], 4.2) && close(m[2], 4.2));
        assert!(from_geoms(&[]).unwrap().is_none());
    }

    #[test]
    fn principal_axes_diagonalise() {
        let r =
            kinetree_spatial::rotation::rot_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let s = Symmetric3::from_diagonal(DVec3::new(1.0, 2.0, 3.5)).rotate(&r);
        let (values, rot) = principal_axes(&s);
        let back = Symmetric3::from_diagonal(DVec3::from_array(values)).rotate(&rot);
        for (x, y) in back.to_voigt().iter().zip(s.to_voigt()) {
            assert!(close(*x, y), "{x} {y}");
        }
        assert!((rot.determinant() - 1.0).abs() < 1e-12);
    }
}
