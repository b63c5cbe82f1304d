//! Signed distances of two primitives other than balls (cylinders, boxes, capsules) for the
//! distance queries, in the first shape's frame: closed forms where GJK and EPA degenerate or
//! lose precision, the crate's GJK/EPA elsewhere.
//!
//! - Two capsules: the distance of their segments less both radii, exact for every placement
//!   (coincident and crossing capsules included: a capsule is its segment grown by its radius,
//!   so the support function, and with it the depth, grows by the radius too).
//! - A capsule and a box or a cylinder: the same reduction to the segment. A segment against a
//!   box overlaps exactly when no separating axis exists among the box's three face normals
//!   and the segment's direction crossed with the box's edges, and the smallest overlap along
//!   those axes is then the exact depth (the faces of the two shapes' Minkowski difference are
//!   normal to those axes). A segment parallel to a cylinder's axis: their difference is a
//!   cylinder, so the distance is a point's to a cylinder. Otherwise the crate's GJK/EPA on the
//!   segment.
//! - Two boxes: the same separating-axis test on the 15 axes when their bounding spheres meet;
//!   overlapping boxes get the exact depth, relative to nothing (a box 1e6 m long keeps the
//!   precision of a small one). Separated boxes: GJK.
//! - Two cylinders: [`crate::cylinders`] (closed forms by feature pair, and parallel
//!   overlapping cylinders), then GJK/EPA.
//!
//! Bounding spheres that do not meet skip the separating-axis tests, so shapes clearly apart
//! cost what GJK costs.

use crate::cylinders::{Sides, cylinders};
use crate::frames::cylinder_point;
use crate::gjk::{Local, signed_distance_mat};
use crate::narrow::{Kind, Scratch};
use glam::{DMat3, DVec3};
use parry3d_f64::shape::{Capsule, Cuboid, Cylinder, SupportMap};

/// Whether `kind` is handled here (a cylinder, box or capsule).
pub(crate) fn is_solid(kind: &Kind) -> bool {
    matches!(kind, Kind::Cylinder(_) | Kind::Cuboid(_) | Kind::Capsule(_))
}

/// The signed distance of two primitives, shape 2 at rotation `rot12` and translation `t12` in
/// shape 1's frame; `None` for other kinds, or when GJK/EPA do not settle (the caller then runs
/// parry's).
pub(crate) fn pair(
    ka: &Kind,
    kb: &Kind,
    rot12: &DMat3,
    t12: DVec3,
    scratch: &mut Scratch,
) -> Option<Local> {
    match (ka, kb) {
        (Kind::Cylinder(s1), Kind::Cylinder(s2)) => {
            match cylinders(rot12.y_axis, t12, s1, s2, scratch.polytope.tol) {
                Sides::Exact(local) => Some(local),
                Sides::Fallback(start) => {
                    signed_distance_mat(rot12, t12, s1, s2, start.dir, &mut scratch.polytope)
                }
            }
        }
        (Kind::Capsule(c1), Kind::Capsule(c2)) => Some(capsules(c1, c2, rot12, t12)),
        (Kind::Cuboid(b1), Kind::Cuboid(b2)) => {
            boxes(b1, b2, rot12, t12).or_else(|| gjk(rot12, t12, b1, b2, scratch))
        }
        (Kind::Capsule(c), Kind::Cuboid(b)) => capsule_box(c, b, rot12, t12, scratch),
        (Kind::Cuboid(b), Kind::Capsule(c)) => {
            flipped(rot12, t12, |r, t| capsule_box(c, b, r, t, scratch))
        }
        (Kind::Cylinder(y), Kind::Capsule(c)) => cylinder_capsule(y, c, rot12, t12, scratch),
        (Kind::Capsule(c), Kind::Cylinder(y)) => {
            flipped(rot12, t12, |r, t| cylinder_capsule(y, c, r, t, scratch))
        }
        (Kind::Cylinder(s1), Kind::Cuboid(s2)) => gjk(rot12, t12, s1, s2, scratch),
        (Kind::Cuboid(s1), Kind::Cylinder(s2)) => gjk(rot12, t12, s1, s2, scratch),
        _ => None,
    }
}

/// The crate's GJK/EPA from the direction between the shapes' origins.
fn gjk<G1, G2>(rot12: &DMat3, t12: DVec3, g1: &G1, g2: &G2, scratch: &mut Scratch) -> Option<Local>
where
    G1: ?Sized + SupportMap,
    G2: ?Sized + SupportMap,
{
    let dir = t12.try_normalize().unwrap_or(DVec3::X);
    signed_distance_mat(rot12, t12, g1, g2, dir, &mut scratch.polytope)
}

/// A result of `f` solved with the shapes swapped (shape 1 at the rotation and translation
/// it is given, in shape 2's frame), turned back into shape 1's frame and order.
fn flipped(
    rot12: &DMat3,
    t12: DVec3,
    f: impl FnOnce(&DMat3, DVec3) -> Option<Local>,
) -> Option<Local> {
    let rot21 = rot12.transpose();
    let (q2, q1, m, d) = f(&rot21, -(rot21 * t12))?;
    Some((*rot12 * q1 + t12, *rot12 * q2 + t12, -(*rot12 * m), d))
}

/// `local` with shape 1 grown by `r1` and shape 2 by `r2` (capsules around their segments).
fn inflate((p1, p2, n, d): Local, r1: f64, r2: f64) -> Local {
    (p1 + n * r1, p2 - n * r2, n, d - r1 - r2)
}

/// Two capsules: their segments' closest points, less the radii.
fn capsules(c1: &Capsule, c2: &Capsule, rot12: &DMat3, t12: DVec3) -> Local {
    let (a1, b1) = (c1.segment.a, c1.segment.b);
    let (a2, b2) = (*rot12 * c2.segment.a + t12, *rot12 * c2.segment.b + t12);
    let (x1, x2) = segments(a1, b1, a2, b2);
    let gap = x2 - x1;
    let len = gap.length();
    let scale = (b1 - a1).length().max((b2 - a2).length()).max(1.0);
    let n = if len > 1e-12 * scale {
        gap / len
    } else {
        // The segments meet: normal to both (any normal to parallel ones), toward the second.
        let (d1, d2) = (b1 - a1, b2 - a2);
        let n = d1
            .cross(d2)
            .try_normalize()
            .or_else(|| d1.try_normalize().map(DVec3::any_orthonormal_vector))
            .or_else(|| d2.try_normalize().map(DVec3::any_orthonormal_vector))
            .unwrap_or(DVec3::X);
        if n.dot((a2 + b2) - (a1 + b1)) < 0.0 {
            -n
        } else {
            n
        }
    };
    inflate((x1, x2, n, len), c1.radius, c2.radius)
}

/// The closest points of the segments `[a1, b1]` and `[a2, b2]` (Ericson, *Real-Time
/// Collision Detection* 5.1.9).
fn segments(a1: DVec3, b1: DVec3, a2: DVec3, b2: DVec3) -> (DVec3, DVec3) {
    let (d1, d2, r) = (b1 - a1, b2 - a2, a1 - a2);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let (s, t) = if a <= f64::MIN_POSITIVE && e <= f64::MIN_POSITIVE {
        (0.0, 0.0)
    } else if a <= f64::MIN_POSITIVE {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e <= f64::MIN_POSITIVE {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            // Parallel segments (to round-off): any s; start from the first's end.
            let s = if denom > 1e-14 * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t = (b * s + f) / e;
            if t < 0.0 {
                ((-c / a).clamp(0.0, 1.0), 0.0)
            } else if t > 1.0 {
                (((b - c) / a).clamp(0.0, 1.0), 1.0)
            } else {
                (s, t)
            }
        }
    };
    (a1 + d1 * s, a2 + d2 * t)
}

/// A box or a segment for the separating-axis test: centre, unit axes and half extents along
/// them (one axis for a segment).
struct Polytope {
    center: DVec3,
    axes: [DVec3; 3],
    half: [f64; 3],
    /// 3 for a box, 1 for a segment.
    count: usize,
}

impl Polytope {
    fn cuboid(rot: &DMat3, center: DVec3, h: DVec3) -> Self {
        Self {
            center,
            axes: [rot.x_axis, rot.y_axis, rot.z_axis],
            half: [h.x, h.y, h.z],
            count: 3,
        }
    }

    fn segment(a: DVec3, b: DVec3) -> Self {
        let half = (b - a) * 0.5;
        let len = half.length();
        Self {
            center: (a + b) * 0.5,
            axes: [
                half.try_normalize().unwrap_or(DVec3::Z),
                DVec3::ZERO,
                DVec3::ZERO,
            ],
            half: [len, 0.0, 0.0],
            count: 1,
        }
    }

    /// A bound of the distance from the centre to any point.
    fn reach(&self) -> f64 {
        self.half[..self.count].iter().sum()
    }

    /// Half the width along the unit `l`.
    fn radius(&self, l: DVec3) -> f64 {
        (0..self.count)
            .map(|i| self.half[i] * l.dot(self.axes[i]).abs())
            .sum()
    }

    /// The point furthest along `l`: the middle of a face or an edge when `l` is normal to it.
    fn support(&self, l: DVec3) -> DVec3 {
        let mut p = self.center;
        for i in 0..self.count {
            let along = l.dot(self.axes[i]);
            if along.abs() > 1e-12 {
                p += self.axes[i] * (self.half[i] * along.signum());
            }
        }
        p
    }
}

/// The separating-axis test of two boxes, or a segment (first) and a box: `None` when an axis
/// separates them, else the exact signed distance (the smallest overlap, negated) with the
/// deepest points along its axis.
fn separating_axes(a: &Polytope, b: &Polytope) -> Option<Local> {
    let t = b.center - a.center;
    let mut best = (f64::INFINITY, DVec3::X);
    let mut overlaps = |l: DVec3| {
        let s = l.dot(t);
        let o = a.radius(l) + b.radius(l) - s.abs();
        if o < best.0 {
            best = (o, if s < 0.0 { -l } else { l });
        }
        o >= 0.0
    };
    for p in [a, b] {
        if p.count == 3 && !p.axes.iter().all(|&l| overlaps(l)) {
            return None;
        }
    }
    for &u in &a.axes[..a.count] {
        for &v in &b.axes[..b.count] {
            let c = u.cross(v);
            // Parallel edges: the face axes already cover their plane.
            if c.length_squared() > 1e-20 && !overlaps(c.normalize()) {
                return None;
            }
        }
    }
    let (depth, n) = best;
    Some((a.support(n), b.support(-n), n, -depth))
}

/// Two boxes whose bounding spheres meet, when they overlap (or touch): the exact depth.
fn boxes(b1: &Cuboid, b2: &Cuboid, rot12: &DMat3, t12: DVec3) -> Option<Local> {
    let a = Polytope::cuboid(&DMat3::IDENTITY, DVec3::ZERO, b1.half_extents);
    let b = Polytope::cuboid(rot12, t12, b2.half_extents);
    let reach = b1.half_extents.length() + b2.half_extents.length();
    if t12.length_squared() > reach * reach {
        return None;
    }
    separating_axes(&a, &b)
}

/// A capsule (first) and a box: the segment's overlap with the box in closed form, else its
/// distance by GJK; less the radius.
fn capsule_box(
    c: &Capsule,
    b: &Cuboid,
    rot12: &DMat3,
    t12: DVec3,
    scratch: &mut Scratch,
) -> Option<Local> {
    let seg = Polytope::segment(c.segment.a, c.segment.b);
    let cuboid = Polytope::cuboid(rot12, t12, b.half_extents);
    let reach = seg.reach() + b.half_extents.length();
    if (t12 - seg.center).length_squared() <= reach * reach
        && let Some(local) = separating_axes(&seg, &cuboid)
    {
        return Some(inflate(local, c.radius, 0.0));
    }
    // The segment is clear of the box (GJK separates it); the capsule itself if GJK does not
    // settle on the segment.
    gjk(rot12, t12, &c.segment, b, scratch)
        .filter(|l| l.3 > 0.0)
        .map(|l| inflate(l, c.radius, 0.0))
        .or_else(|| gjk(rot12, t12, c, b, scratch))
}

/// A cylinder (first) and a capsule: parallel, a point against a cylinder in closed form; else
/// the segment by GJK/EPA, less the radius.
fn cylinder_capsule(
    y: &Cylinder,
    c: &Capsule,
    rot12: &DMat3,
    t12: DVec3,
    scratch: &mut Scratch,
) -> Option<Local> {
    let (e0, e1) = (*rot12 * c.segment.a + t12, *rot12 * c.segment.b + t12);
    let half = (e1 - e0) * 0.5;
    let center = (e0 + e1) * 0.5;
    let hs = half.length();
    if half.x * half.x + half.z * half.z <= 1e-24 * hs * hs {
        // Parallel to the axis (y): the differences of the segment's and the cylinder's points
        // form a cylinder of radius `r` and half height `h + hs` around `center`; its surface
        // point nearest the origin splits into a cylinder point and a segment point.
        let (h, r) = (y.half_height, y.radius);
        let big = h + hs;
        let (s, outward, signed) = cylinder_point(-center, &Cylinder::new(big, r));
        let (radial, up) = (DVec3::new(s.x, 0.0, s.z), s.y);
        let share = |part: f64| if big > 0.0 { part / big } else { 0.5 };
        let p_cyl = -(radial + DVec3::Y * (up * share(h)));
        let p_seg = center + DVec3::Y * (up * share(hs));
        let n = -outward;
        return Some(inflate((p_cyl, p_seg, n, signed), 0.0, c.radius));
    }
    gjk(rot12, t12, y, &c.segment, scratch)
        .map(|l| inflate(l, 0.0, c.radius))
        .or_else(|| gjk(rot12, t12, y, c, scratch))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    /// Hand-worked capsule pairs: crossing, coincident, parallel apart, end to end.
    #[test]
    fn capsule_pairs() {
        let c = Capsule::new_z(0.2, 0.05);
        let id = DMat3::IDENTITY;
        // Coincident: out sideways by both radii.
        let (p1, p2, n, d) = capsules(&c, &c, &id, DVec3::ZERO);
        assert!(close(d, -0.1) && close((p2 - p1).dot(n), d));
        // Crossing at right angles through both centres: the same.
        let turn = DMat3::from_quat(DQuat::from_rotation_x(core::f64::consts::FRAC_PI_2));
        let (_, _, n, d) = capsules(&c, &c, &turn, DVec3::ZERO);
        assert!(close(d, -0.1) && close(n.x.abs(), 1.0));
        // Side by side 0.3 apart.
        let (p1, p2, n, d) = capsules(&c, &c, &id, DVec3::new(0.3, 0.0, 0.1));
        assert!(close(d, 0.2) && close(n.x, 1.0) && close(p1.x, 0.05) && close(p2.x, 0.25));
        // End to end along z, caps 0.02 apart: segments 0.12 apart.
        let (_, _, n, d) = capsules(&c, &c, &id, DVec3::new(0.0, 0.0, 0.52));
        assert!(close(d, 0.02) && close(n.z, 1.0));
    }

    /// Boxes: nested, crossed and touching, against hand-worked depths.
    #[test]
    fn box_pairs() {
        let small = Cuboid::new(DVec3::splat(0.1));
        let long = Cuboid::new(DVec3::new(5e5, 0.5, 0.5));
        let id = DMat3::IDENTITY;
        // A small box inside a long one, off centre by 0.2 in z: out through the top, 0.5 - 0.2
        // + 0.1.
        let (p1, p2, n, d) = boxes(&small, &long, &id, DVec3::new(-5.0, 0.0, -0.2)).unwrap();
        assert!(close(d, -0.4), "{d}");
        assert!(close(n.z, -1.0) && close((p2 - p1).dot(n), d));
        // Turned 45° about z, centred: corners reach 0.1·√2 along x and y, so the way out is
        // along z, 0.1 + 0.1.
        let turn = DMat3::from_quat(DQuat::from_rotation_z(core::f64::consts::FRAC_PI_4));
        let (_, _, n, d) = boxes(&small, &small, &turn, DVec3::ZERO).unwrap();
        assert!(close(d, -0.2) && close(n.z.abs(), 1.0), "{d}");
        // Face to face, touching.
        let (_, _, _, d) = boxes(&small, &small, &id, DVec3::new(0.2, 0.05, 0.0)).unwrap();
        assert!(close(d, 0.0), "{d}");
        // Apart: left to GJK.
        assert!(boxes(&small, &small, &id, DVec3::new(0.21, 0.0, 0.0)).is_none());
    }
}
