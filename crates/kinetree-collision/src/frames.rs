//! The narrow phase of the distance queries on world frames in matrix form: one
//! quaternion-to-matrix conversion per shape and placement update instead of quaternion algebra
//! per pair, closed forms for balls against primitives, and [`crate::primitives`] for the other
//! primitive pairs (closed forms where GJK/EPA degenerate, the feature solver of
//! [`crate::cylinders`] for cylinder pairs, the crate's GJK/EPA elsewhere). Pairs it does not handle (meshes, other
//! shapes, GJK that does not settle) go through [`proximity`].

use crate::narrow::{Kind, Posed, Scratch, Witness, proximity};
use glam::{DMat3, DVec3};
use parry3d_f64::math::Pose;
use parry3d_f64::query::Unsupported;
use parry3d_f64::shape::Cylinder;

/// A world frame in matrix form: `p ↦ rot·p + origin`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Frame {
    pub rot: DMat3,
    pub origin: DVec3,
}

impl Frame {
    pub(crate) const IDENTITY: Frame = Frame {
        rot: DMat3::IDENTITY,
        origin: DVec3::ZERO,
    };

    pub(crate) fn of(pose: &Pose) -> Frame {
        Frame {
            rot: DMat3::from_quat(pose.rotation),
            origin: pose.translation,
        }
    }
}

/// The signed distance of two posed shapes with no distance bound, as
/// [`proximity`]`(a, b, f64::INFINITY, …)` computes it; `fa` and `fb` are the frames of
/// `a.pose` and `b.pose`.
pub(crate) fn distance(
    a: Posed<'_>,
    fa: &Frame,
    b: Posed<'_>,
    fb: &Frame,
    scratch: &mut Scratch,
) -> Result<Option<Witness>, Unsupported> {
    let fast = match (a.kind, b.kind) {
        (Kind::Ball(ba), Kind::Ball(bb)) => {
            let d = fb.origin - fa.origin;
            let len = d.length();
            let normal = if len > 0.0 { d / len } else { DVec3::X };
            Some(Witness {
                distance: len - ba.radius - bb.radius,
                point_a: fa.origin + normal * ba.radius,
                point_b: fb.origin - normal * bb.radius,
                normal,
            })
        }
        (Kind::Other, _) | (_, Kind::Other) => None,
        (Kind::Ball(ball), kind) => {
            ball_primitive(fa.origin, ball.radius, kind, &fb.rot, fb.origin).map(|r| Witness {
                distance: r.distance,
                point_a: r.point_b,
                point_b: r.point_a,
                normal: -r.normal,
            })
        }
        (kind, Kind::Ball(ball)) => {
            ball_primitive(fb.origin, ball.radius, kind, &fa.rot, fa.origin)
        }
        (ka, kb) => {
            // Shape b in shape a's frame.
            let rot_t = fa.rot.transpose();
            let rot12 = rot_t * fb.rot;
            let t12 = rot_t * (fb.origin - fa.origin);
            crate::primitives::pair(ka, kb, &rot12, t12, scratch).map(|(p1, p2, n, distance)| {
                Witness {
                    distance,
                    point_a: fa.rot * p1 + fa.origin,
                    point_b: fa.rot * p2 + fa.origin,
                    normal: fa.rot * n,
                }
            })
        }
    };
    match fast {
        Some(w) => Ok(Some(w)),
        None => proximity(a, b, f64::INFINITY, scratch),
    }
}

/// A ball (world centre `center`, radius `radius`) against a box, cylinder or capsule with
/// world rotation `rot` and origin `origin`: `None` when `kind` is none of those, else the signed distance with `point_a` on the
/// primitive, `point_b` on the ball and the normal pointing from the primitive toward the ball
///
/// The closest point of a solid primitive to the centre is exact (clamping); for a centre inside,
/// the nearest face (or side) gives the penetration depth, as in parry's point projection.
pub(crate) fn ball_primitive(
    center: DVec3,
    radius: f64,
    kind: &Kind,
    rot: &DMat3,
    origin: DVec3,
) -> Option<Witness> {
    let c = rot.transpose() * (center - origin);
    // (point on the primitive's surface, outward unit normal there, signed distance centre-surface)
    let (surface, normal, signed) = match kind {
        Kind::Cylinder(cyl) => cylinder_point(c, cyl),
        Kind::Cuboid(b) => {
            let h = b.half_extents;
            let inside = c.abs().cmple(h).all();
            if inside {
                let gap = h - c.abs();
                let axis = if gap.x <= gap.y && gap.x <= gap.z {
                    0
                } else if gap.y <= gap.z {
                    1
                } else {
                    2
                };
                let s = if c[axis] >= 0.0 { 1.0 } else { -1.0 };
                let mut p = c;
                p[axis] = s * h[axis];
                let mut n = DVec3::ZERO;
                n[axis] = s;
                (p, n, -gap[axis])
            } else {
                outside(c, c.clamp(-h, h))
            }
        }
        Kind::Capsule(cap) => {
            let (s0, s1) = (cap.segment.a, cap.segment.b);
            let d = s1 - s0;
            let len2 = d.length_squared();
            let t = if len2 > 0.0 {
                ((c - s0).dot(d) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let on_axis = s0 + d * t;
            let v = c - on_axis;
            let l = v.length();
            let n = if l > 0.0 {
                v / l
            } else {
                d.any_orthonormal_vector()
            };
            (on_axis + n * cap.radius, n, l - cap.radius)
        }
        _ => return None,
    };
    Some(ball_witness(
        center,
        radius,
        rot,
        origin,
        (surface, normal, signed),
    ))
}

/// [`ball_primitive`] for a cylinder.
#[inline(always)]
pub(crate) fn ball_cylinder(
    center: DVec3,
    radius: f64,
    cyl: &Cylinder,
    rot: &DMat3,
    origin: DVec3,
) -> Witness {
    let c = rot.transpose() * (center - origin);
    ball_witness(center, radius, rot, origin, cylinder_point(c, cyl))
}

/// The world witness of a ball (centre `center`) against a primitive at `rot`, `origin`, from
/// the primitive's closest surface point to the centre, its normal and the signed distance of
/// the centre, all in the primitive's frame.
#[inline(always)]
fn ball_witness(
    center: DVec3,
    radius: f64,
    rot: &DMat3,
    origin: DVec3,
    (surface, normal, signed): (DVec3, DVec3, f64),
) -> Witness {
    let n = *rot * normal;
    Witness {
        distance: signed - radius,
        point_a: *rot * surface + origin,
        point_b: center - n * radius,
        normal: n,
    }
}

/// The surface point of a solid cylinder closest to `c` (its frame), the outward normal there
/// and the signed distance of `c` (negative inside).
#[inline(always)]
pub(crate) fn cylinder_point(c: DVec3, cyl: &Cylinder) -> (DVec3, DVec3, f64) {
    let (h, r) = (cyl.half_height, cyl.radius);
    let rho = (c.x * c.x + c.z * c.z).sqrt();
    let u = if rho > 0.0 {
        DVec3::new(c.x / rho, 0.0, c.z / rho)
    } else {
        DVec3::X
    };
    if c.y.abs() <= h && rho <= r {
        let (to_cap, to_side) = (h - c.y.abs(), r - rho);
        if to_side < to_cap {
            (DVec3::new(u.x * r, c.y, u.z * r), u, -to_side)
        } else {
            let s = if c.y >= 0.0 { 1.0 } else { -1.0 };
            (DVec3::new(c.x, s * h, c.z), DVec3::Y * s, -to_cap)
        }
    } else {
        let radial = if rho > r {
            u * r
        } else {
            DVec3::new(c.x, 0.0, c.z)
        };
        let p = DVec3::new(radial.x, c.y.clamp(-h, h), radial.z);
        outside(c, p)
    }
}

/// Surface point `p` of a solid primitive closest to an outside point `c`.
fn outside(c: DVec3, p: DVec3) -> (DVec3, DVec3, f64) {
    let d = c - p;
    let l = d.length();
    (p, if l > 0.0 { d / l } else { DVec3::X }, l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cylinders::{Sides, cylinder_sides};
    use crate::narrow::Scratch;
    use glam::DQuat;
    use parry3d_f64::math::Vector;

    /// The closed form agrees with GJK wherever it applies, and defers elsewhere.
    #[test]
    fn cylinder_sides_match_gjk() {
        let c1 = Cylinder::new(0.2, 0.05);
        let c2 = Cylinder::new(0.1, 0.08);
        let mut scratch = Scratch::default();
        let mut exact = 0;
        for k in 0..400 {
            let f = f64::from(k);
            let pos12 = Pose::from_parts(
                Vector::new(
                    (f * 0.37).sin() * 0.4,
                    (f * 0.11).cos() * 0.3,
                    (f * 0.23).sin() * 0.4,
                ),
                DQuat::from_euler(glam::EulerRot::XYZ, f * 0.7, f * 1.3, f * 0.3),
            );
            let gjk =
                crate::narrow::support(&pos12, &c1, &c2, f64::INFINITY, &mut scratch).unwrap();
            if let Sides::Exact(local) =
                cylinder_sides(pos12.rotation * Vector::Y, pos12.translation, &c1, &c2)
            {
                exact += 1;
                assert!(
                    (local.3 - gjk.3).abs() < 1e-7,
                    "{k}: {} vs {}",
                    local.3,
                    gjk.3
                );
                assert!((local.0 - gjk.0).length() < 1e-3, "{k}");
            }
        }
        assert!(exact > 20, "only {exact} side-to-side cases");
    }

    /// The matrix-form path gives what the pose-form narrow phase gives, for every pair of
    /// primitive kinds, separated and overlapping.
    #[test]
    fn matches_the_pose_path() {
        use parry3d_f64::shape::SharedShape;
        let shapes = [
            SharedShape::ball(0.07),
            SharedShape::cylinder(0.12, 0.09),
            SharedShape::cuboid(0.05, 0.1, 0.08),
            SharedShape::capsule_z(0.1, 0.04),
        ];
        let kinds = shapes.each_ref().map(Kind::of);
        let mut scratch = Scratch::default();
        let mut compared = 0;
        for k in 0..300 {
            let f = f64::from(k);
            let pose = |g: f64| {
                Pose::from_parts(
                    Vector::new((g * 0.37).sin(), (g * 0.11).cos(), (g * 0.23).sin())
                        * (0.05 + 0.3 * (g * 0.05).sin().abs()),
                    DQuat::from_euler(glam::EulerRot::XYZ, g * 0.7, g * 1.3, g * 0.3),
                )
            };
            let (pa, pb) = (pose(f), pose(f * 1.7 + 3.0));
            let (fa, fb) = (Frame::of(&pa), Frame::of(&pb));
            for i in 0..shapes.len() {
                for j in 0..shapes.len() {
                    let a = Posed {
                        kind: &kinds[i],
                        shape: &*shapes[i],
                        pose: &pa,
                    };
                    let b = Posed {
                        kind: &kinds[j],
                        shape: &*shapes[j],
                        pose: &pb,
                    };
                    let ours = distance(a, &fa, b, &fb, &mut scratch).unwrap().unwrap();
                    let theirs = proximity(a, b, f64::INFINITY, &mut scratch)
                        .unwrap()
                        .unwrap();
                    // Both are GJK/EPA results within their relative tolerance (1e-8) when no closed
                    // form applies.
                    let tol = if theirs.distance < 0.0 { 1e-6 } else { 2e-8 };
                    assert!(
                        (ours.distance - theirs.distance).abs() < tol,
                        "{k} {i} {j}: {} vs {}",
                        ours.distance,
                        theirs.distance
                    );
                    assert!(
                        ((ours.point_b - ours.point_a).dot(ours.normal) - ours.distance).abs()
                            < 1e-7
                    );
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, 300 * 16);
    }
}
