//! Two cylinders by the features their closest points lie on: both sides in closed form
//! ([`cylinder_sides`]), and a rim against a rim, a side or a cap face solved on that feature
//! pair ([`cylinder_features`]), each answer certified by the support functions before it is
//! returned. GJK is the fallback.
//!
//! Parry's cylinders lie along their local y axis. Everything here is in the first cylinder's
//! frame: the second one's axis is `axis2` and its centre `center2`.
//!
//! **Certificate.** For any unit `n`, the gap of the two shapes along `n`,
//! `n·center2 - h1·|n·y| - r1·|n × y| - h2·|n·axis2| - r2·|n × axis2|` (the support functions of
//! the cylinders in closed form), is a lower bound of their distance, and the distance between
//! any two of their points an upper bound. A candidate pair of points `p1`, `p2` is accepted
//! when the gap along `(p2 - p1) / |p2 - p1|` is within `tol · |p2 - p1|` of `|p2 - p1|`: the
//! stopping rule of the crate's GJK, so the answer carries the same guarantee,
//! `d - tol · d <= d* <= d`.

use crate::gjk::Local;
use glam::DVec3;
use parry3d_f64::shape::Cylinder;

/// Newton steps allowed on one feature pair.
const NEWTON_STEPS: usize = 10;
/// A Newton step (radians) below which the candidate is tested against the certificate.
const SETTLED: f64 = 1e-4;

/// Outcome of [`cylinder_sides`].
pub(crate) enum Sides {
    /// The exact result.
    Exact(Local),
    /// Not a side-to-side configuration: where to go from here.
    Fallback(Start),
}

/// Where the closest points of the axis segments are: GJK's first direction and the features
/// [`cylinder_features`] tries first.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Start {
    /// Unit vector from the first axis segment's closest point toward the second's.
    pub dir: DVec3,
    /// Height of the closest point on the first axis, clamped to the cylinder.
    s: f64,
    /// Height of the closest point on the second axis, clamped to the cylinder.
    t: f64,
    /// Whether the axes are too close to parallel for the side-to-side closed form.
    parallel: bool,
}

/// Two separated cylinders whose closest points lie on both side surfaces, in closed form.
///
/// Let the axes' common perpendicular meet them at heights `s` and `t`. When both are strictly
/// within the cylinders' half heights and the axes are more than `r1 + r2` apart, the points at
/// `r1` and `r2` along the perpendicular are on the side surfaces and realise the lower bound
/// `|axis distance| - r1 - r2` (every point of a cylinder is within its radius of its axis), so
/// they are the closest points. Otherwise the closest points of the clamped axis segments give
/// GJK a good first direction.
pub(crate) fn cylinder_sides(axis2: DVec3, center2: DVec3, c1: &Cylinder, c2: &Cylinder) -> Sides {
    let cos = axis2.y;
    let denom = 1.0 - cos * cos;
    // Axis segments P(s) = s·y, s ∈ [-h1, h1], and Q(t) = center2 + t·axis2, t ∈ [-h2, h2].
    let (d1, d2) = (-center2.y, -axis2.dot(center2));
    let (h1, h2) = (c1.half_height, c2.half_height);
    let fallback = |s: f64, parallel: bool| {
        // The closest points of the axis segments (Ericson, *Real-Time Collision Detection*
        // 5.1.9): clamp `s`, take the best `t` for it, clamp `t` and redo `s` if needed.
        let mut s = s.clamp(-h1, h1);
        let mut t = cos * s + d2;
        if t.abs() > h2 {
            t = t.clamp(-h2, h2);
            s = (cos * t - d1).clamp(-h1, h1);
        }
        let d = center2 + axis2 * t - DVec3::Y * s;
        Sides::Fallback(Start {
            dir: d
                .try_normalize()
                .or_else(|| center2.try_normalize())
                .unwrap_or(DVec3::X),
            s,
            t,
            parallel,
        })
    };
    if denom < 1e-8 {
        // Parallel axes (to round-off, from the cross product: `denom` itself has only the
        // precision of `cos²`) that overlap or touch: the closed form. Apart, the feature
        // solver's side-to-side case.
        if axis2.x * axis2.x + axis2.z * axis2.z < 1e-24 {
            let local = parallel(center2, c1, c2);
            if local.3 <= 0.0 {
                return Sides::Exact(local);
            }
        }
        // Near-parallel axes: the perpendicular is not unique.
        return fallback(0.0, true);
    }
    let s = (cos * d2 - d1) / denom;
    let t = (d2 - cos * d1) / denom;
    if s.abs() >= h1 || t.abs() >= h2 {
        return fallback(s, false);
    }
    let p = DVec3::Y * s;
    let q = center2 + axis2 * t;
    let d = q - p;
    let len = d.length();
    if len <= c1.radius + c2.radius {
        return fallback(s, false);
    }
    let n = d / len;
    Sides::Exact((
        p + n * c1.radius,
        q - n * c2.radius,
        n,
        len - c1.radius - c2.radius,
    ))
}

/// Two cylinders with parallel axes (the second's centre at `center2`), in closed form: the
/// differences of their points form a cylinder of radius `r1 + r2` and half height `h1 + h2`
/// around `center2`, so the signed distance is the origin's to that cylinder (negative inside),
/// and its surface point nearest the origin splits into a point of each cylinder. Exact for
/// coincident and nested cylinders, where GJK's simplex degenerates.
pub(crate) fn parallel(center2: DVec3, c1: &Cylinder, c2: &Cylinder) -> Local {
    let (r, h) = (c1.radius + c2.radius, c1.half_height + c2.half_height);
    let (s, outward, signed) = crate::frames::cylinder_point(-center2, &Cylinder::new(h, r));
    let (radial, up) = (DVec3::new(s.x, 0.0, s.z), s.y);
    let share = |part: f64, whole: f64| if whole > 0.0 { part / whole } else { 0.5 };
    let p1 = -(radial * share(c1.radius, r) + DVec3::Y * (up * share(c1.half_height, h)));
    let p2 = center2 + radial * share(c2.radius, r) + DVec3::Y * (up * share(c2.half_height, h));
    (p1, p2, -outward, signed)
}

/// Two cylinders: [`cylinder_sides`], then [`cylinder_features`] (for distance queries).
#[inline(always)]
pub(crate) fn cylinders(
    axis2: DVec3,
    center2: DVec3,
    c1: &Cylinder,
    c2: &Cylinder,
    tol: f64,
) -> Sides {
    match cylinder_sides(axis2, center2, c1, c2) {
        Sides::Fallback(start) => cylinder_features(axis2, center2, c1, c2, start, tol),
        exact => exact,
    }
}

/// The two cylinders in the first one's frame, and the certificate's tolerance.
#[derive(Clone, Copy)]
struct Pair {
    axis2: DVec3,
    center2: DVec3,
    h1: f64,
    r1: f64,
    h2: f64,
    r2: f64,
    tol: f64,
}

impl Pair {
    /// The gap of the cylinders along the unit vector `n` (first toward second): a lower bound
    /// of their distance.
    #[inline(always)]
    fn gap(&self, n: DVec3) -> f64 {
        let (a, b) = (n.y, n.dot(self.axis2));
        // |n × y| and |n × axis2| from the components, not sqrt(1 - a²), which loses half the
        // digits near the axes.
        let across1 = (n.x * n.x + n.z * n.z).sqrt();
        let across2 = n.cross(self.axis2).length();
        n.dot(self.center2)
            - self.h1 * a.abs()
            - self.r1 * across1
            - self.h2 * b.abs()
            - self.r2 * across2
    }

    /// The second cylinder's rim point furthest along `-a.axis` against the first one's cap
    /// face on rim `a`, when it lies over that face.
    fn cap_rim(&self, a: Rim) -> Option<(Local, Case)> {
        let m = -a.axis;
        let p2 = self.center2
            + self.axis2 * (self.h2 * m.dot(self.axis2).signum())
            + across(m, self.axis2) * self.r2;
        let height = (p2 - a.center).dot(a.axis);
        let p1 = p2 - a.axis * height;
        if height > 0.0 && p1.x * p1.x + p1.z * p1.z <= self.r1 * self.r1 {
            return self.certify(p1, p2).map(|l| (l, Case::CapRim));
        }
        None
    }

    /// The first cylinder's rim point furthest along `-b.axis` against the second one's cap
    /// face on rim `b`, when it lies over that face.
    fn rim_cap(&self, b: Rim) -> Option<(Local, Case)> {
        let m = -b.axis;
        let p1 = DVec3::Y * (self.h1 * m.y.signum()) + across(m, DVec3::Y) * self.r1;
        let height = (p1 - b.center).dot(b.axis);
        let p2 = p1 - b.axis * height;
        if height > 0.0 && (p2 - b.center).length_squared() <= self.r2 * self.r2 {
            return self.certify(p1, p2).map(|l| (l, Case::RimCap));
        }
        None
    }

    /// `p1` on the first cylinder and `p2` on the second as the answer, if the certificate
    /// accepts them.
    #[inline(always)]
    fn certify(&self, p1: DVec3, p2: DVec3) -> Option<Local> {
        let d = p2 - p1;
        let len = d.length();
        if len.is_nan() || len <= 0.0 {
            return None;
        }
        let n = d / len;
        (len - self.gap(n) <= self.tol * len).then_some((p1, p2, n, len))
    }
}

/// A rim: `center + r·u` for unit `u` orthogonal to the unit `axis`.
#[derive(Clone, Copy)]
struct Rim {
    center: DVec3,
    axis: DVec3,
    r: f64,
}

/// The unit part of `v` orthogonal to the unit `axis` (any unit orthogonal vector when `v` is
/// along `axis`).
#[inline(always)]
fn across(v: DVec3, axis: DVec3) -> DVec3 {
    let v = v - axis * v.dot(axis);
    // Twice: when `v` is nearly along `axis`, one pass leaves round-off along it that the
    // normalisation would magnify.
    (v - axis * v.dot(axis))
        .try_normalize()
        .unwrap_or_else(|| axis.any_orthonormal_vector())
}

/// Which feature pair answered (for the tests' statistics).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Case {
    Parallel,
    RimRim,
    RimSide,
    SideRim,
    CapRim,
    RimCap,
}

/// Two cylinders whose axis segments' closest points are `start` (see [`cylinder_sides`]),
/// solved on the feature pair their closest points lie on: `Exact` when a certified answer is
/// found (the shapes are then separated), else `Fallback` with GJK's first direction (the best
/// direction found, or `start`'s).
pub(crate) fn cylinder_features(
    axis2: DVec3,
    center2: DVec3,
    c1: &Cylinder,
    c2: &Cylinder,
    start: Start,
    tol: f64,
) -> Sides {
    match features(axis2, center2, c1, c2, start, tol) {
        Ok((local, _)) => Sides::Exact(local),
        Err(dir) => Sides::Fallback(Start { dir, ..start }),
    }
}

/// [`cylinder_features`], with the feature pair that answered.
pub(crate) fn features(
    axis2: DVec3,
    center2: DVec3,
    c1: &Cylinder,
    c2: &Cylinder,
    start: Start,
    tol: f64,
) -> Result<(Local, Case), DVec3> {
    let pair = Pair {
        axis2,
        center2,
        h1: c1.half_height,
        r1: c1.radius,
        h2: c2.half_height,
        r2: c2.radius,
        tol,
    };
    let n0 = start.dir;
    // The rims facing the other cylinder: at the clamped end of an axis segment, else on the
    // side of the other cylinder; their points nearest to it as a start.
    let on_side1 = start.s.abs() < pair.h1;
    let on_side2 = start.t.abs() < pair.h2;
    let mut s1 = if on_side1 { n0.y } else { start.s }.signum();
    let mut s2 = if on_side2 { -n0.dot(axis2) } else { start.t }.signum();
    let mut u1 = across(n0, DVec3::Y);
    let mut u2 = across(-n0, axis2);
    let rim1 = |s1: f64| Rim {
        center: DVec3::Y * (s1 * pair.h1),
        axis: DVec3::Y * s1,
        r: pair.r1,
    };
    let rim2 = |s2: f64| Rim {
        center: center2 + axis2 * (s2 * pair.h2),
        axis: axis2 * s2,
        r: pair.r2,
    };
    let side1 = Side {
        center: DVec3::ZERO,
        axis: DVec3::Y,
        h: pair.h1,
        r: pair.r1,
    };
    let side2 = Side {
        center: center2,
        axis: axis2,
        h: pair.h2,
        r: pair.r2,
    };
    if start.parallel {
        // Side by side along the overlap of the axes' heights, if they overlap.
        let reach = pair.h2 * axis2.y.abs();
        let (lo, hi) = (
            (-pair.h1).max(center2.y - reach),
            pair.h1.min(center2.y + reach),
        );
        if lo <= hi {
            let s = 0.5 * (lo + hi);
            let t = (DVec3::Y * s - center2).dot(axis2).clamp(-pair.h2, pair.h2);
            let q = center2 + axis2 * t;
            let n = across(q, DVec3::Y);
            if let Some(local) =
                pair.certify(DVec3::Y * s + n * pair.r1, q - across(n, axis2) * pair.r2)
            {
                return Ok((local, Case::Parallel));
            }
        }
    }
    // A rim point beside the other cylinder's side: that side first.
    if on_side2 && !on_side1 {
        match rim_side(rim1(s1), u1, &side2) {
            Beside(p1, p2) => {
                if let Some(local) = pair.certify(p1, p2) {
                    return Ok((local, Case::RimSide));
                }
            }
            Beyond(s) => s2 = s,
            Failed => {}
        }
    } else if on_side1 && !on_side2 {
        match rim_side(rim2(s2), u2, &side1) {
            Beside(p2, p1) => {
                if let Some(local) = pair.certify(p1, p2) {
                    return Ok((local, Case::SideRim));
                }
            }
            Beyond(s) => s1 = s,
            Failed => {}
        }
    }
    for _ in 0..3 {
        let (a, b) = (rim1(s1), rim2(s2));
        let Some((p1, p2, v1, v2)) = rim_rim(a, u1, b, u2) else {
            // Newton does not settle when a rim's closest point is on the other's cap face.
            return pair.cap_rim(a).or_else(|| pair.rim_cap(b)).ok_or(n0);
        };
        if let Some(local) = pair.certify(p1, p2) {
            return Ok((local, Case::RimRim));
        }
        (u1, u2) = (v1, v2);
        // Which feature each point would rather be on: the direction between the points must
        // lie in the normal cone of the rim (spanned by the rim's axis and radial vector) on
        // both shapes.
        let n = (p2 - p1).normalize_or(n0);
        let off_rim1 = n.dot(a.axis) < 0.0;
        let off_rim2 = n.dot(b.axis) > 0.0;
        let cap1 = n.dot(u1) < 0.0;
        let cap2 = n.dot(u2) > 0.0;
        if cap1 != cap2 {
            let r = if cap1 {
                pair.cap_rim(a)
            } else {
                pair.rim_cap(b)
            };
            return r.ok_or(n);
        }
        if cap1 || off_rim1 == off_rim2 {
            return Err(n);
        }
        if off_rim2 {
            match rim_side(a, u1, &side2) {
                Beside(p1, p2) => {
                    return pair.certify(p1, p2).map(|l| (l, Case::RimSide)).ok_or(n);
                }
                Beyond(s) if s != s2 => s2 = s,
                _ => return Err(n),
            }
        } else {
            match rim_side(b, u2, &side1) {
                Beside(p2, p1) => {
                    return pair.certify(p1, p2).map(|l| (l, Case::SideRim)).ok_or(n);
                }
                Beyond(s) if s != s1 => s1 = s,
                _ => return Err(n),
            }
        }
    }
    Err(n0)
}

/// A cylinder's side: centre, unit axis, half height and radius.
struct Side {
    center: DVec3,
    axis: DVec3,
    h: f64,
    r: f64,
}

/// Outcome of [`rim_side`].
enum RimSide {
    /// The rim point and the side point nearest to it.
    Beside(DVec3, DVec3),
    /// The rim point nearest to the side's axis is beyond the side's end on this side (±1).
    Beyond(f64),
    /// Newton did not head for a minimum, or the rim point is inside the cylinder.
    Failed,
}
use RimSide::{Beside, Beyond, Failed};

/// The closest points of two rims by Newton's method on their angles, from the radial vectors
/// `u1`, `u2`: `(p1, p2, u1, u2)` at the last step, `None` when the distance is not convex
/// there (Newton would not head for a minimum) or the steps do not settle.
#[inline(always)]
fn rim_rim(a: Rim, mut u1: DVec3, b: Rim, mut u2: DVec3) -> Option<(DVec3, DVec3, DVec3, DVec3)> {
    let (r1, r2) = (a.r, b.r);
    for _ in 0..NEWTON_STEPS {
        let (w1, w2) = (a.axis.cross(u1), b.axis.cross(u2));
        let d = (b.center + u2 * r2) - (a.center + u1 * r1);
        // Half the squared distance as a function of the angles: gradient and Hessian.
        let (g1, g2) = (-r1 * d.dot(w1), r2 * d.dot(w2));
        let h11 = r1 * (r1 + d.dot(u1));
        let h22 = r2 * (r2 - d.dot(u2));
        let h12 = -r1 * r2 * w1.dot(w2);
        let mut det = h11 * h22 - h12 * h12;
        let (mut h11, mut h22) = (h11, h22);
        if !(h11 > 0.0 && det > 0.0) {
            // Not convex here (far from the minimum): a Gauss-Newton step, the Hessian without
            // the curvature terms, which heads downhill.
            (h11, h22) = (r1 * r1, r2 * r2);
            det = h11 * h22 - h12 * h12;
            if det.is_nan() || det <= 1e-6 * h11 * h22 {
                return None;
            }
        }
        let inv = 1.0 / det;
        let t1 = (h12 * g2 - h22 * g1) * inv;
        let t2 = (h12 * g1 - h11 * g2) * inv;
        // Turn each radial vector by atan(t) (a retraction of the step onto the circle).
        u1 = (u1 + w1 * t1).normalize();
        u2 = (u2 + w2 * t2).normalize();
        if t1.abs() + t2.abs() < SETTLED {
            return Some((a.center + u1 * r1, b.center + u2 * r2, u1, u2));
        }
    }
    None
}

/// The point of a rim closest to the axis of a cylinder's side by Newton's method on the rim's
/// angle from `u`, and the point of that side nearest to it.
#[inline(always)]
fn rim_side(rim: Rim, mut u: DVec3, side: &Side) -> RimSide {
    let (rr, axis) = (rim.r, side.axis);
    for _ in 0..NEWTON_STEPS {
        let w = rim.axis.cross(u);
        let e = rim.center + u * rr - side.center;
        let e_across = e - axis * e.dot(axis);
        // Half the squared distance to the axis as a function of the angle.
        let g = rr * e_across.dot(w);
        let wa = w.dot(axis);
        let hess = rr * (rr * (1.0 - wa * wa) - e_across.dot(u));
        if hess.is_nan() || hess <= 0.0 {
            return Failed;
        }
        let t = -g / hess;
        u = (u + w * t).normalize();
        if t.abs() < SETTLED {
            let p = rim.center + u * rr;
            let e = p - side.center;
            let along = e.dot(axis);
            if along.abs() > side.h {
                return Beyond(along.signum());
            }
            let e_across = e - axis * along;
            let rho = e_across.length();
            if rho <= side.r {
                return Failed;
            }
            return Beside(p, side.center + axis * along + e_across * (side.r / rho));
        }
    }
    Failed
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gjk::{Polytope, signed_distance};
    use glam::DQuat;
    use parry3d_f64::math::Pose;
    use parry3d_f64::shape::SupportMap;

    /// The pair solved through [`cylinders`] and [`features`] (which must agree), with the
    /// feature pair that answered (`None`: the side-to-side closed form).
    fn solve(
        axis2: DVec3,
        center2: DVec3,
        c1: &Cylinder,
        c2: &Cylinder,
    ) -> Option<(Local, Option<Case>)> {
        let tol = 1e-8;
        match cylinder_sides(axis2, center2, c1, c2) {
            Sides::Exact(local) => Some((local, None)),
            Sides::Fallback(start) => {
                let r = features(axis2, center2, c1, c2, start, tol).ok();
                let r = r.map(|(local, case)| (local, Some(case)));
                let via = match cylinders(axis2, center2, c1, c2, tol) {
                    Sides::Exact(local) => Some(local),
                    Sides::Fallback(_) => None,
                };
                assert_eq!(r.map(|r| r.0), via);
                r
            }
        }
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-12
    }

    /// Hand-worked poses, one per feature pair. With the second axis along x or z and its centre
    /// in the plane z = 0, both shapes are symmetric about that plane, so a closest pair lies in
    /// it (the midpoints of a closest pair and its mirror image), where the cylinders' sections
    /// are rectangles.
    #[test]
    fn hand_worked_features() {
        let c1 = Cylinder::new(0.1, 0.05);
        let c2 = Cylinder::new(0.08, 0.03);
        // Rim to rim: the second axis along x, the rectangles' nearest corners.
        let ((p1, p2, n, d), case) = solve(DVec3::X, DVec3::new(0.3, 0.25, 0.0), &c1, &c2).unwrap();
        assert_eq!(case, Some(Case::RimRim));
        assert!((d - 0.17f64.hypot(0.12)).abs() < 1e-15, "{d}");
        assert!(close(p1, DVec3::new(0.05, 0.1, 0.0)) && close(p2, DVec3::new(0.22, 0.22, 0.0)));
        assert!(close(n, DVec3::new(0.17, 0.12, 0.0) / 0.17f64.hypot(0.12)));
        // Rim to side: the second axis along z; its side passes the first's top rim.
        let center2 = DVec3::new(0.3, 0.25, 0.0);
        let ((p1, p2, _, d), case) = solve(DVec3::Z, center2, &c1, &c2).unwrap();
        assert_eq!(case, Some(Case::RimSide));
        let to_axis = DVec3::new(0.25, 0.15, 0.0);
        assert!((d - (to_axis.length() - 0.03)).abs() < 1e-15, "{d}");
        assert!(close(p1, DVec3::new(0.05, 0.1, 0.0)));
        assert!(close(p2, center2 - to_axis.normalize() * 0.03));
        // The same pose seen from the second cylinder: its side against the rim.
        // (Its frame turns y onto z: a quarter turn about x.)
        let back = DQuat::from_rotation_x(-core::f64::consts::FRAC_PI_2);
        let ((q1, q2, _, e), case) = solve(back * DVec3::Y, back * -center2, &c2, &c1).unwrap();
        assert_eq!(case, Some(Case::SideRim));
        assert!((e - d).abs() < 1e-15 && close(q1, back * (p2 - center2)));
        assert!(close(q2, back * (p1 - center2)));
        // Cap face to rim: the second cylinder above the first, tilted by `a` about z; its
        // lowest point (on the rim) over the first one's top face.
        let a = 0.3f64;
        let (axis2, center2) = (
            DVec3::new(-a.sin(), a.cos(), 0.0),
            DVec3::new(0.01, 0.4, 0.0),
        );
        let low = center2 - axis2 * 0.08 - DVec3::new(a.cos(), a.sin(), 0.0) * 0.03;
        let ((p1, p2, n, d), case) = solve(axis2, center2, &c1, &c2).unwrap();
        assert_eq!(case, Some(Case::CapRim));
        assert!((d - (low.y - 0.1)).abs() < 1e-15, "{d} vs {}", low.y - 0.1);
        assert!(close(p2, low) && close(p1, DVec3::new(low.x, 0.1, 0.0)) && close(n, DVec3::Y));
        // Rim to cap face: the same pose from the second cylinder's frame.
        let back = DQuat::from_rotation_z(-a);
        let (axis1, center1) = (back * DVec3::Y, back * -center2);
        let ((q1, q2, _, e), case) = solve(axis1, center1, &c2, &c1).unwrap();
        assert_eq!(case, Some(Case::RimCap));
        assert!((e - d).abs() < 1e-15 && close(q1, back * (low - center2)));
        assert!(close(q2, back * (p1 - center2)));
        // Parallel sides: the axes 0.2 apart, overlapping in height.
        let ((p1, p2, _, d), case) = solve(DVec3::Y, DVec3::new(0.2, 0.05, 0.0), &c1, &c2).unwrap();
        assert_eq!(case, Some(Case::Parallel));
        assert!((d - 0.12).abs() < 1e-15 && (p1.x - 0.05).abs() < 1e-15);
        assert!((p1.y - 0.035).abs() < 1e-15 && (p2.y - 0.035).abs() < 1e-15);
        // Overlapping: never answered here.
        let overlap = solve(DVec3::X, DVec3::new(0.1, 0.11, 0.0), &c1, &c2);
        assert!(overlap.is_none());
    }

    /// On many poses and sizes: every answer agrees with the crate's GJK run to a much finer
    /// tolerance, its points lie on the shapes, and parry's support points along its normal
    /// bound the distance from below within the tolerance. Almost every separated pair is
    /// answered, and every feature pair occurs.
    #[test]
    fn answers_are_certified() {
        let sizes = [
            Cylinder::new(0.05, 0.09),
            Cylinder::new(0.14, 0.045),
            Cylinder::new(0.2, 0.02),
            Cylinder::new(0.01, 0.1),
        ];
        let mut fine = Polytope::default();
        fine.tol = 1e-13;
        let mut counts = std::collections::BTreeMap::new();
        let (mut separated, mut answered) = (0, 0);
        for k in 0..6000 {
            let f = f64::from(k);
            let (c1, c2) = (&sizes[k as usize % 4], &sizes[(k as usize / 4) % 4]);
            let pos12 = Pose::from_parts(
                DVec3::new((f * 0.37).sin(), (f * 0.11).cos(), (f * 0.23).sin())
                    * (0.1 + 0.4 * (f * 0.05).sin().abs()),
                DQuat::from_euler(glam::EulerRot::XYZ, f * 0.7, f * 1.3, f * 0.3),
            );
            let (axis2, center2) = (pos12.rotation * DVec3::Y, pos12.translation);
            let dir = center2.normalize();
            let Some(reference) = signed_distance(&pos12, c1, c2, dir, &mut fine) else {
                continue;
            };
            if reference.3 > 0.0 {
                separated += 1;
            }
            let Some(((p1, p2, n, d), case)) = solve(axis2, center2, c1, c2) else {
                continue;
            };
            let r = reference.3;
            if d <= 0.0 {
                // Parallel cylinders overlapping or touching: the closed form.
                assert!(case.is_none() && axis2.x.hypot(axis2.z) < 1e-12, "{k}: {d}");
                assert!((d - r).abs() <= 1e-8 * r.abs().max(1e-3), "{k}: {d} vs {r}");
                continue;
            }
            answered += 1;
            *counts.entry(case).or_insert(0) += 1;
            assert!(r > 0.0, "{k}: {d} but the reference is {r}");
            assert!(
                (d - r).abs() <= 1e-8 * r + 1e-15,
                "{k} {case:?}: {d} vs {r}"
            );
            assert!(((p2 - p1).length() - d).abs() < 1e-15 && ((p2 - p1).dot(n) - d).abs() < 1e-15);
            let q2 = pos12.inverse_transform_point(p2);
            for (p, c) in [(p1, c1), (q2, c2)] {
                let rho = (p.x * p.x + p.z * p.z).sqrt();
                assert!(
                    rho <= c.radius + 1e-15 && p.y.abs() <= c.half_height + 1e-15,
                    "{k} {case:?}: {} {}",
                    rho - c.radius,
                    p.y.abs() - c.half_height
                );
            }
            let a = c1.local_support_point(n);
            let b = pos12 * c2.local_support_point(pos12.rotation.inverse() * -n);
            let lower = n.dot(b - a);
            assert!(
                lower <= d + 1e-15 && d - lower <= 1e-8 * d + 1e-15,
                "{k}: {d} vs {lower}"
            );
        }
        assert_eq!(answered, counts.values().sum::<usize>());
        assert!(
            answered as f64 > 0.97 * separated as f64,
            "{answered} of {separated} {counts:?}"
        );
        let cases = [
            Case::RimRim,
            Case::RimSide,
            Case::SideRim,
            Case::CapRim,
            Case::RimCap,
        ];
        for case in cases.map(Some).into_iter().chain([None]) {
            assert!(counts.get(&case).is_some_and(|&c| c > 20), "{counts:?}");
        }
    }
}
