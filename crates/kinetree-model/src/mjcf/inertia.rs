//! Masses and inertias as MuJoCo's compiler infers them from geoms: the volume (or surface) of
//! each primitive, its principal moments, and a body's total over its geoms.

use glam::{DMat3, DQuat, DVec3};
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

/// How MuJoCo integrates a mesh's mass (`<mesh inertia=…>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum MeshInertia {
    /// Tetrahedra from the face centroid with their volumes taken positive (MuJoCo's default):
    /// exact for convex meshes, an over-count for others.
    Legacy,
    /// Signed tetrahedra: the exact volume of a closed, consistently oriented mesh.
    Exact,
    /// Mass spread over the surface.
    Shell,
}

/// A mesh's mass properties per unit density: its volume (or area), centre of mass and
/// rotational inertia about that centre, in the mesh's frame (after scaling).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct MeshMass {
    pub(super) measure: f64,
    pub(super) com: DVec3,
    pub(super) inertia: Symmetric3,
}

/// MuJoCo's smallest meaningful value (`mjMINVAL`).
const MINVAL: f64 = 1e-15;

/// A triangle's unit normal (the raw cross product when degenerate), centre and area, as
/// MuJoCo computes them (areas of faces shorter than `mjMINVAL` count as 0).
fn triangle(a: DVec3, b: DVec3, c: DVec3) -> (DVec3, DVec3, f64) {
    let center = (a + b + c) / 3.0;
    let n = (b - a).cross(c - a);
    let len = n.length();
    if len < MINVAL {
        return (n, center, 0.0);
    }
    (n / len, center, 0.5 * len)
}

/// The mass properties of a triangle mesh as MuJoCo's compiler computes them: the centre and
/// volume from pyramids on the area-weighted face centroid, then the inertia from tetrahedra on
/// the centre of mass, with volumes taken positive in [`MeshInertia::Legacy`] mode.
pub(super) fn mesh_mass(
    vertices: &[DVec3],
    triangles: &[[u32; 3]],
    mode: MeshInertia,
) -> Result<MeshMass, &'static str> {
    let corner = |t: &[u32; 3], k: usize| vertices.get(t[k] as usize).copied();
    let mut faces = Vec::with_capacity(triangles.len());
    for t in triangles {
        match (corner(t, 0), corner(t, 1), corner(t, 2)) {
            (Some(a), Some(b), Some(c)) => faces.push([a, b, c]),
            _ => return Err("a face refers to a vertex that does not exist"),
        }
    }
    let (mut facecen, mut total_area) = (DVec3::ZERO, 0.0);
    for [a, b, c] in &faces {
        let (_, center, area) = triangle(*a, *b, *c);
        facecen += area * center;
        total_area += area;
    }
    if total_area < MINVAL {
        return Err("the mesh's surface area is too small");
    }
    facecen /= total_area;
    let mut com = DVec3::ZERO;
    let mut measure = 0.0;
    for [a, b, c] in &faces {
        let (normal, center, area) = triangle(*a, *b, *c);
        let (weight, at) = match mode {
            MeshInertia::Shell => (area, center),
            _ => {
                let v = (center - facecen).dot(normal) * area / 3.0;
                let v = if mode == MeshInertia::Legacy {
                    v.abs()
                } else {
                    v
                };
                (v, center * 3.0 / 4.0 + facecen / 4.0)
            }
        };
        measure += weight;
        com += weight * at;
    }
    if measure < MINVAL {
        return Err(if measure < 0.0 {
            "the mesh's volume is negative (its faces are inside out)"
        } else {
            "the mesh's volume is too small (try inertia=\"shell\")"
        });
    }
    com /= measure;
    // Products of inertia about the centre of mass, by tetrahedra (or triangles for a shell).
    let mut p = [0.0f64; 6];
    let pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    let mut total = 0.0;
    for face in &faces {
        let [d, e, f] = face.map(|v| v - com);
        let (normal, center, area) = triangle(d, e, f);
        let v = match mode {
            MeshInertia::Shell => area,
            _ => center.dot(normal) * area / 3.0,
        };
        let v = if mode == MeshInertia::Legacy {
            v.abs()
        } else {
            v
        };
        total += v;
        let c = if mode == MeshInertia::Shell {
            12.0
        } else {
            20.0
        };
        for (j, &(k, l)) in pairs.iter().enumerate() {
            p[j] += v / c
                * (2.0 * (d[k] * d[l] + e[k] * e[l] + f[k] * f[l])
                    + d[k] * e[l]
                    + d[l] * e[k]
                    + d[k] * f[l]
                    + d[l] * f[k]
                    + e[k] * f[l]
                    + e[l] * f[k]);
        }
    }
    let inertia = Symmetric3::new(p[1] + p[2], -p[3], -p[4], p[0] + p[2], -p[5], p[0] + p[1]);
    // MuJoCo's checks, on its eigenvalues (sorted, the smallest last).
    let (moments, _) = mesh_principal_axes(&inertia);
    if moments[2] <= 0.0 {
        return Err("the mesh's principal moments must be positive");
    }
    let violates = |a: f64, b: f64, c: f64| a + b < c * (1.0 - 1e-6) - 1e-9;
    let [a, b, c] = moments;
    if violates(a, b, c) || violates(a, c, b) || violates(b, c, a) {
        return Err("the mesh's principal moments violate A + B >= C");
    }
    Ok(MeshMass {
        measure: total,
        com,
        inertia,
    })
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
            if moments.iter().any(|m| *m < 1e-14) {
                return Err("the summed inertia of the geoms must have positive eigenvalues");
            }
            Ok(Some(BodyMass {
                mass,
                pos: com,
                rot,
                moments,
            }))
        }
    }
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations, to the last bits:
/// the eigenvalues and a right-handed rotation whose columns are the eigenvectors (as MuJoCo
/// 4.0 diagonalises `fullinertia` and the summed inertia of several geoms).
pub(super) fn principal_axes(s: &Symmetric3) -> ([f64; 3], DMat3) {
    let mut a = s.to_mat3().to_cols_array_2d();
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off == 0.0 {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = if theta == 0.0 {
                1.0
            } else {
                theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
            };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J with the rotation J in the (p, q) plane.
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * rp[k] - s * rq[k];
                a[q][k] = s * rp[k] + c * rq[k];
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
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

/// Principal moments and axes of a mesh's inertia as MuJoCo's compiler finds them
/// (`mjuu_eig3`, which MuJoCo 4.0 uses for meshes): Jacobi rotations on the largest
/// off-diagonal entry, accumulated in a unit quaternion, stopping once that entry is below
/// 1e-12 or the rotation's cosine above 1 − 1e-12, then sorted in decreasing order by quarter
/// turns. The stopping rule leaves off-diagonal residues (up to ~1e-9 relative) that MuJoCo
/// drops; reproducing it is what makes a mesh body's inertia equal MuJoCo's. Returns the
/// moments and the rotation whose columns are the axes.
pub(super) fn mesh_principal_axes(s: &Symmetric3) -> ([f64; 3], DMat3) {
    const EPS: f64 = 1e-12;
    let m = s.to_mat3();
    let mut quat = DQuat::IDENTITY;
    let mut values = [0.0; 3];
    for _ in 0..500 {
        let r = DMat3::from_quat(quat);
        let d = r.transpose() * m * r;
        // d.col(c)[r] is the entry at row r, column c.
        let at = |row: usize, col: usize| d.col(col)[row];
        values = [at(0, 0), at(1, 1), at(2, 2)];
        let (rk, ck, rotk) = if at(0, 1).abs() > at(0, 2).abs() && at(0, 1).abs() > at(1, 2).abs() {
            (0, 1, 2)
        } else if at(0, 2).abs() > at(1, 2).abs() {
            (0, 2, 1)
        } else {
            (1, 2, 0)
        };
        let off = at(rk, ck);
        if off.abs() < EPS {
            break;
        }
        let tau = (at(ck, ck) - at(rk, rk)) / (2.0 * off);
        let t = if tau >= 0.0 {
            1.0 / (tau + (1.0 + tau * tau).sqrt())
        } else {
            -1.0 / (-tau + (1.0 + tau * tau).sqrt())
        };
        let c = 1.0 / (1.0 + t * t).sqrt();
        if c > 1.0 - EPS {
            break;
        }
        let mut half = (0.5 - 0.5 * c).sqrt();
        if tau >= 0.0 {
            half = -half;
        }
        if rotk == 1 {
            half = -half;
        }
        let mut v = [0.0; 3];
        v[rotk] = half;
        let step = DQuat::from_xyzw(v[0], v[1], v[2], (1.0 - half * half).sqrt()).normalize();
        quat = (quat * step).normalize();
    }
    // Decreasing order (swaps 0-1, 1-2, 0-1), each swap a quarter turn about the third axis.
    for j in 0..3 {
        let lead = j % 2;
        if values[lead] + EPS < values[lead + 1] {
            values.swap(lead, lead + 1);
            let h = core::f64::consts::FRAC_1_SQRT_2;
            let mut v = [0.0; 3];
            v[(lead + 2) % 3] = h;
            quat = (quat * DQuat::from_xyzw(v[0], v[1], v[2], h)).normalize();
        }
    }
    (values, DMat3::from_quat(quat))
}

/// A mesh geom's principal moments for mass `mass`, as MuJoCo derives them from the mesh's
/// principal moments per unit density `unit` and volume (or area) `measure`: through the sides
/// of the box with the same inertia.
pub(super) fn mesh_moments(unit: [f64; 3], measure: f64, mass: f64) -> [f64; 3] {
    let side = |a: f64, b: f64, c: f64| 0.5 * (6.0 * (b + c - a) / measure).sqrt();
    let b = [
        side(unit[0], unit[1], unit[2]),
        side(unit[1], unit[0], unit[2]),
        side(unit[2], unit[0], unit[1]),
    ];
    [
        mass * (b[1] * b[1] + b[2] * b[2]) / 3.0,
        mass * (b[0] * b[0] + b[2] * b[2]) / 3.0,
        mass * (b[0] * b[0] + b[1] * b[1]) / 3.0,
    ]
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
    fn mesh_principal_axes_stop_where_mujoco_does() {
        let r =
            kinetree_spatial::rotation::rot_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let s = Symmetric3::from_diagonal(DVec3::new(1.0, 2.0, 3.5)).rotate(&r);
        let (values, rot) = mesh_principal_axes(&s);
        // Decreasing, and back to the matrix to within what MuJoCo's stopping rule leaves.
        assert!(
            values[0] >= values[1] && values[1] >= values[2],
            "{values:?}"
        );
        assert!((values[0] - 3.5).abs() < 1e-6 && (values[2] - 1.0).abs() < 1e-6);
        let back = Symmetric3::from_diagonal(DVec3::from_array(values)).rotate(&rot);
        for (x, y) in back.to_voigt().iter().zip(s.to_voigt()) {
            assert!((x - y).abs() < 1e-5, "{x} {y}");
        }
        assert!((rot.determinant() - 1.0).abs() < 1e-12);
        // A diagonal matrix stays as it is, sorted.
        let (values, rot) =
            mesh_principal_axes(&Symmetric3::from_diagonal(DVec3::new(1.0, 3.0, 2.0)));
        assert_eq!(values, [3.0, 2.0, 1.0]);
        assert!((rot * DVec3::X).abs().abs_diff_eq(DVec3::Y, 1e-15));
        // The accurate decomposition gives the matrix back to the last bits.
        let (values, rot) = principal_axes(&s);
        let back = Symmetric3::from_diagonal(DVec3::from_array(values)).rotate(&rot);
        for (x, y) in back.to_voigt().iter().zip(s.to_voigt()) {
            assert!((x - y).abs() < 1e-14, "{x} {y}");
        }
    }
}
