//! The narrow phase: signed distance with witness points between two posed parry shapes,
//! without allocating once the scratch buffers exist.

use glam::DVec3;
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::epa::EPA;
use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::query::{self, ClosestPoints, Unsupported, details};
use parry3d_f64::shape::Shape;

/// Reusable buffers of the narrow phase: parry's EPA keeps its polytope in vectors, which are
/// reused from one penetration query to the next.
#[derive(Default)]
pub(crate) struct Scratch {
    epa: EPA,
    simplex: VoronoiSimplex,
}

impl core::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("Scratch { epa, simplex }")
    }
}

impl Clone for Scratch {
    fn clone(&self) -> Self {
        Self::default()
    }
}

/// Signed distance and witness points in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Witness {
    pub distance: f64,
    pub point_a: DVec3,
    pub point_b: DVec3,
    pub normal: DVec3,
}

/// The signed distance between shape `a` at `pos_a` and shape `b` at `pos_b` (both world poses),
/// or `None` when it is larger than `max_dist`.
///
/// Positive: separation, with the closest points. Negative: penetration depth, with the deepest
/// points (each on its shape's surface). `normal` is a unit vector pointing from `a` toward `b`.
pub(crate) fn proximity(
    pos_a: &Pose,
    a: &dyn Shape,
    pos_b: &Pose,
    b: &dyn Shape,
    max_dist: f64,
    scratch: &mut Scratch,
) -> Result<Option<Witness>, Unsupported> {
    if let (Some(ba), Some(bb)) = (a.as_ball(), b.as_ball()) {
        // Closed form, as coal does for spheres.
        let d = pos_b.translation - pos_a.translation;
        let (normal, len) = match d.try_normalize() {
            Some(n) => (n, d.length()),
            None => (DVec3::X, 0.0),
        };
        let distance = len - ba.radius - bb.radius;
        if distance > max_dist {
            return Ok(None);
        }
        return Ok(Some(Witness {
            distance,
            point_a: pos_a.translation + normal * ba.radius,
            point_b: pos_b.translation - normal * bb.radius,
            normal,
        }));
    }
    let pos12 = pos_a.inv_mul(pos_b);
    let local = if let (Some(ba), true) = (a.as_ball(), b.is_convex()) {
        details::contact_ball_convex_polyhedron(&pos12, ba, b, max_dist)
            .map(|c| (c.point1, pos12 * c.point2, c.normal1, c.dist))
    } else if let (true, Some(bb)) = (a.is_convex(), b.as_ball()) {
        details::contact_convex_polyhedron_ball(&pos12, a, bb, max_dist)
            .map(|c| (c.point1, pos12 * c.point2, c.normal1, c.dist))
    } else if let (Some(sa), Some(sb)) = (a.as_support_map(), b.as_support_map()) {
        let dir = pos12.translation.try_normalize().unwrap_or(Vector::X);
        scratch
            .simplex
            .reset(CsoPoint::from_shapes(&pos12, sa, sb, dir));
        match gjk::closest_points(&pos12, sa, sb, max_dist, true, &mut scratch.simplex) {
            GJKResult::ClosestPoints(p1, p2, n) => {
                let d = p2 - p1;
                let len = d.length();
                // Separated: the distance between the witnesses, along them.
                let n = if len > 0.0 { d / len } else { n };
                Some((p1, p2, n, len))
            }
            GJKResult::Intersection => {
                match scratch.epa.closest_points(&pos12, sa, sb, &scratch.simplex) {
                    Some((p1, p2, n)) => Some((p1, p2, n, (p2 - p1).dot(n).min(0.0))),
                    // EPA failed on a degenerate configuration: report touching.
                    None => Some((DVec3::ZERO, DVec3::ZERO, Vector::X, 0.0)),
                }
            }
            GJKResult::NoIntersection(_) | GJKResult::Proximity(_) => None,
        }
    } else {
        // Composite shapes (triangle meshes): parry's generic queries.
        return composite(pos_a, a, pos_b, b, max_dist);
    };
    Ok(local.map(|(p1, p2, n, distance)| Witness {
        distance,
        point_a: pos_a.transform_point(p1),
        point_b: pos_a.transform_point(p2),
        normal: pos_a.rotation * n,
    }))
}

fn composite(
    pos_a: &Pose,
    a: &dyn Shape,
    pos_b: &Pose,
    b: &dyn Shape,
    max_dist: f64,
) -> Result<Option<Witness>, Unsupported> {
    match query::closest_points(pos_a, a, pos_b, b, max_dist)? {
        ClosestPoints::WithinMargin(p1, p2) => {
            let d = p2 - p1;
            let len = d.length();
            Ok(Some(Witness {
                distance: len,
                point_a: p1,
                point_b: p2,
                normal: d.try_normalize().unwrap_or(DVec3::X),
            }))
        }
        ClosestPoints::Disjoint => Ok(None),
        ClosestPoints::Intersecting => Ok(Some(match query::contact(pos_a, a, pos_b, b, 0.0)? {
            Some(c) => Witness {
                distance: c.dist.min(0.0),
                point_a: c.point1,
                point_b: c.point2,
                normal: c.normal1,
            },
            None => Witness {
                distance: 0.0,
                point_a: pos_a.translation,
                point_b: pos_b.translation,
                normal: DVec3::X,
            },
        })),
    }
}

/// Whether the two posed shapes overlap or touch.
pub(crate) fn intersects(
    pos_a: &Pose,
    a: &dyn Shape,
    pos_b: &Pose,
    b: &dyn Shape,
) -> Result<bool, Unsupported> {
    query::intersection_test(pos_a, a, pos_b, b).map(|r| r.intersecting)
}
