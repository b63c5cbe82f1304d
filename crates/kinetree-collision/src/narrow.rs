//! The narrow phase: signed distance with witness points between two posed shapes, without
//! allocating once the scratch buffers exist.
//!
//! Primitive shapes are dispatched on their concrete type ([`Kind`]) so parry's GJK/EPA are
//! monomorphised over them (inlined support functions); other shapes go through parry's
//! `dyn Shape` queries.

use crate::cylinders::{Sides, cylinder_sides, cylinders};
use crate::frames::ball_primitive;
use glam::DVec3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::partitioning::BvhNode;
use parry3d_f64::query::epa::EPA;
use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::query::{
    self, ClosestPoints, PointQuery, PointQueryWithLocation, Unsupported, details,
};
use parry3d_f64::shape::{
    Ball, Capsule, Cuboid, Cylinder, Shape, SharedShape, SupportMap, TriMesh,
};

mod mesh;
use mesh::{ball_mesh, capsule_mesh, mesh_convex, mesh_mesh};

/// The concrete type of a shape, for static dispatch.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Kind {
    Ball(Ball),
    Cylinder(Cylinder),
    Cuboid(Cuboid),
    Capsule(Capsule),
    /// Anything else (meshes, convex hulls, user shapes): parry's dynamic queries.
    Other,
}

impl Kind {
    pub(crate) fn of(shape: &SharedShape) -> Kind {
        if let Some(b) = shape.as_ball() {
            Kind::Ball(*b)
        } else if let Some(c) = shape.as_cylinder() {
            Kind::Cylinder(*c)
        } else if let Some(c) = shape.as_cuboid() {
            Kind::Cuboid(*c)
        } else if let Some(c) = shape.as_capsule() {
            Kind::Capsule(*c)
        } else {
            Kind::Other
        }
    }

    /// The world bounding box of the shape at `pose` (closed forms for primitives).
    pub(crate) fn aabb(&self, shape: &dyn Shape, pose: &Pose) -> Aabb {
        let c = pose.translation;
        let half = match self {
            Kind::Ball(b) => DVec3::splat(b.radius),
            Kind::Cylinder(cyl) => {
                // Axis extent h·|a_i| plus the disk's extent r·sqrt(1 - a_i²).
                let a = pose.rotation * DVec3::Y;
                let disk = (DVec3::ONE - a * a).max(DVec3::ZERO);
                a.abs() * cyl.half_height
                    + DVec3::new(disk.x.sqrt(), disk.y.sqrt(), disk.z.sqrt()) * cyl.radius
            }
            Kind::Cuboid(b) => {
                let m = glam::DMat3::from_quat(pose.rotation);
                let h = b.half_extents;
                m.x_axis.abs() * h.x + m.y_axis.abs() * h.y + m.z_axis.abs() * h.z
            }
            Kind::Capsule(cap) => {
                let (a, b) = (pose * cap.segment.a, pose * cap.segment.b);
                let r = DVec3::splat(cap.radius);
                return Aabb::new(a.min(b) - r, a.max(b) + r);
            }
            Kind::Other => return shape.compute_aabb(pose),
        };
        Aabb::new(c - half, c + half)
    }
}

/// Reusable buffers of the narrow phase: parry's EPA keeps its polytope in vectors, which are
/// reused from one penetration query to the next.
#[derive(Default)]
pub(crate) struct Scratch {
    epa: EPA,
    simplex: VoronoiSimplex,
    pub(crate) polytope: crate::gjk::Polytope,
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

/// A posed shape: its concrete kind, the shape itself and its world pose.
#[derive(Clone, Copy)]
pub(crate) struct Posed<'a> {
    pub kind: &'a Kind,
    pub shape: &'a dyn Shape,
    pub pose: &'a Pose,
}

/// Points and normal in shape `a`'s frame, and the signed distance.
type Local = (Vector, Vector, Vector, f64);

/// The signed distance between `a` and `b`, or `None` when it is larger than `max_dist`.
///
/// Positive: separation, with the closest points. Negative: penetration depth, with the deepest
/// points (each on its shape's surface). `normal` is a unit vector pointing from `a` toward `b`.
pub(crate) fn proximity(
    a: Posed<'_>,
    b: Posed<'_>,
    max_dist: f64,
    scratch: &mut Scratch,
) -> Result<Option<Witness>, Unsupported> {
    if let (Kind::Ball(ba), Kind::Ball(bb)) = (a.kind, b.kind) {
        // Closed form, as coal does for spheres.
        let d = b.pose.translation - a.pose.translation;
        let len = d.length();
        let normal = if len > 0.0 { d / len } else { DVec3::X };
        let distance = len - ba.radius - bb.radius;
        if distance > max_dist {
            return Ok(None);
        }
        return Ok(Some(Witness {
            distance,
            point_a: a.pose.translation + normal * ba.radius,
            point_b: b.pose.translation - normal * bb.radius,
            normal,
        }));
    }
    // A ball against a primitive: exact closed forms in the primitive's frame.
    if let Kind::Ball(ball) = a.kind
        && let Some(r) = ball_primitive_at(a.pose.translation, ball.radius, b.kind, b.pose)
    {
        return Ok((r.distance <= max_dist).then_some(Witness {
            distance: r.distance,
            point_a: r.point_b,
            point_b: r.point_a,
            normal: -r.normal,
        }));
    }
    if let Kind::Ball(ball) = b.kind
        && let Some(r) = ball_primitive_at(b.pose.translation, ball.radius, a.kind, a.pose)
    {
        return Ok((r.distance <= max_dist).then_some(r));
    }
    let pos12 = a.pose.inv_mul(b.pose);
    // Distance queries between primitives: closed forms where GJK/EPA degenerate, then the
    // crate's GJK/EPA (as the pair loops compute them); parry's below when those do not settle.
    if max_dist > 0.0
        && crate::primitives::is_solid(a.kind)
        && crate::primitives::is_solid(b.kind)
        && let Some(local) = crate::primitives::pair(
            a.kind,
            b.kind,
            &glam::DMat3::from_quat(pos12.rotation),
            pos12.translation,
            scratch,
        )
    {
        return Ok((local.3 <= max_dist).then(|| in_world(a.pose, local)));
    }
    let local: Option<Local> = match (a.kind, b.kind) {
        (Kind::Ball(ball), Kind::Cylinder(s)) => ball_convex(&pos12, ball, s, max_dist),
        (Kind::Ball(ball), Kind::Cuboid(s)) => ball_convex(&pos12, ball, s, max_dist),
        (Kind::Ball(ball), Kind::Capsule(s)) => ball_convex(&pos12, ball, s, max_dist),
        (Kind::Cylinder(s), Kind::Ball(ball)) => convex_ball(&pos12, s, ball, max_dist),
        (Kind::Cuboid(s), Kind::Ball(ball)) => convex_ball(&pos12, s, ball, max_dist),
        (Kind::Capsule(s), Kind::Ball(ball)) => convex_ball(&pos12, s, ball, max_dist),
        (Kind::Cylinder(s1), Kind::Cylinder(s2)) => {
            // Distance queries: the feature solver; collision queries (a zero bound): the
            // side-to-side closed form only, then parry's GJK, which counts separations within
            // its tolerance as contact.
            let (axis2, center2) = (pos12.rotation * Vector::Y, pos12.translation);
            let sides = if max_dist > 0.0 {
                cylinders(axis2, center2, s1, s2, scratch.polytope.tol)
            } else {
                cylinder_sides(axis2, center2, s1, s2)
            };
            match sides {
                Sides::Exact(local) => (local.3 <= max_dist).then_some(local),
                Sides::Fallback(start) => {
                    support_from(&pos12, s1, s2, max_dist, start.dir, scratch)
                }
            }
        }
        (Kind::Cylinder(s1), Kind::Cuboid(s2)) => support(&pos12, s1, s2, max_dist, scratch),
        (Kind::Cylinder(s1), Kind::Capsule(s2)) => support(&pos12, s1, s2, max_dist, scratch),
        (Kind::Cuboid(s1), Kind::Cylinder(s2)) => support(&pos12, s1, s2, max_dist, scratch),
        (Kind::Cuboid(s1), Kind::Cuboid(s2)) => support(&pos12, s1, s2, max_dist, scratch),
        (Kind::Cuboid(s1), Kind::Capsule(s2)) => support(&pos12, s1, s2, max_dist, scratch),
        (Kind::Capsule(s1), Kind::Cylinder(s2)) => support(&pos12, s1, s2, max_dist, scratch),
        (Kind::Capsule(s1), Kind::Cuboid(s2)) => support(&pos12, s1, s2, max_dist, scratch),
        (Kind::Capsule(s1), Kind::Capsule(s2)) => support(&pos12, s1, s2, max_dist, scratch),
        _ => {
            if let Some(w) = ball_mesh(a, b, max_dist) {
                // A ball and a triangle mesh: the closest point of the mesh, no EPA.
                return Ok(w);
            }
            if let Some(w) = capsule_mesh(a, b, max_dist, scratch) {
                return Ok(w);
            }
            if let (Some(ball), true) = (a.shape.as_ball(), b.shape.is_convex()) {
                ball_convex(&pos12, ball, b.shape, max_dist)
            } else if let (true, Some(ball)) = (a.shape.is_convex(), b.shape.as_ball()) {
                convex_ball(&pos12, a.shape, ball, max_dist)
            } else if let (Some(s1), Some(s2)) =
                (a.shape.as_support_map(), b.shape.as_support_map())
            {
                support(&pos12, s1, s2, max_dist, scratch)
            } else if let Some(w) = mesh_convex(a, b, max_dist, scratch) {
                // A triangle mesh against a convex shape: the crate's per-triangle queries.
                return Ok(w);
            } else if let Some(w) = mesh_mesh(a, b, max_dist, scratch) {
                // Two triangle meshes: a pruned traversal of both trees.
                return Ok(w);
            } else {
                // Other composite shapes, or two meshes whose traversal found no pair within its
                // bound (GJK's tolerance): parry's generic queries.
                return composite(a, b, max_dist);
            }
        }
    };
    Ok(local.map(|local| in_world(a.pose, local)))
}

/// A result in the first shape's frame (at `pose`), in the world frame.
fn in_world(pose: &Pose, (p1, p2, n, distance): Local) -> Witness {
    Witness {
        distance,
        point_a: pose.transform_point(p1),
        point_b: pose.transform_point(p2),
        normal: pose.rotation * n,
    }
}

/// [`ball_primitive`] for a primitive at a parry pose.
fn ball_primitive_at(center: DVec3, radius: f64, kind: &Kind, pose: &Pose) -> Option<Witness> {
    if matches!(kind, Kind::Ball(_) | Kind::Other) {
        return None;
    }
    ball_primitive(
        center,
        radius,
        kind,
        &glam::DMat3::from_quat(pose.rotation),
        pose.translation,
    )
}

fn ball_convex<S: Shape + ?Sized>(
    pos12: &Pose,
    ball: &Ball,
    s: &S,
    max_dist: f64,
) -> Option<Local> {
    details::contact_ball_convex_polyhedron(pos12, ball, s, max_dist)
        .map(|c| (c.point1, pos12 * c.point2, c.normal1, c.dist))
}

fn convex_ball<S: Shape + ?Sized>(
    pos12: &Pose,
    s: &S,
    ball: &Ball,
    max_dist: f64,
) -> Option<Local> {
    details::contact_convex_polyhedron_ball(pos12, s, ball, max_dist)
        .map(|c| (c.point1, pos12 * c.point2, c.normal1, c.dist))
}

/// GJK for separated shapes, EPA (with the reused buffers) for penetrating ones.
pub(crate) fn support<G1, G2>(
    pos12: &Pose,
    g1: &G1,
    g2: &G2,
    max_dist: f64,
    scratch: &mut Scratch,
) -> Option<Local>
where
    G1: ?Sized + SupportMap,
    G2: ?Sized + SupportMap,
{
    let dir = pos12.translation.try_normalize().unwrap_or(Vector::X);
    support_from(pos12, g1, g2, max_dist, dir, scratch)
}

/// [`support`] with GJK's first search direction given (a unit vector from shape 1 toward
/// shape 2, in shape 1's frame).
fn support_from<G1, G2>(
    pos12: &Pose,
    g1: &G1,
    g2: &G2,
    max_dist: f64,
    dir: Vector,
    scratch: &mut Scratch,
) -> Option<Local>
where
    G1: ?Sized + SupportMap,
    G2: ?Sized + SupportMap,
{
    // Distance queries: the lean GJK/EPA first; parry's GJK/EPA when they do not settle, and
    // for collision queries, where parry's GJK stops at the first separating direction.
    if max_dist > 0.0
        && let Some(local) = crate::gjk::signed_distance(pos12, g1, g2, dir, &mut scratch.polytope)
    {
        return (local.3 <= max_dist).then_some(local);
    }
    scratch
        .simplex
        .reset(CsoPoint::from_shapes(pos12, g1, g2, dir));
    match gjk::closest_points(pos12, g1, g2, max_dist, true, &mut scratch.simplex) {
        GJKResult::ClosestPoints(p1, p2, n) => {
            // Separated: the distance between the witnesses, along them.
            let d = p2 - p1;
            let len = d.length();
            let n = if len > 0.0 { d / len } else { n };
            Some((p1, p2, n, len))
        }
        GJKResult::Intersection => {
            // Collision queries: the crate's EPA first (it starts from the degenerate simplices
            // of coincident and symmetric shapes, where parry's gives up); distance queries
            // already tried it above.
            if max_dist <= 0.0
                && let Some(local) =
                    crate::gjk::signed_distance(pos12, g1, g2, dir, &mut scratch.polytope)
                && local.3 <= 0.0
            {
                return Some(local);
            }
            match scratch.epa.closest_points(pos12, g1, g2, &scratch.simplex) {
                Some((p1, p2, n)) => Some((p1, p2, n, (p2 - p1).dot(n).min(0.0))),
                // Both EPAs failed: a conservative depth rather than "touching".
                None => Some(conservative_depth(pos12, g1, g2)),
            }
        }
        GJKResult::NoIntersection(_) | GJKResult::Proximity(_) => None,
    }
}

/// An upper bound of the penetration depth of two overlapping shapes, for when both EPAs fail:
/// the smallest extent of their difference over 26 directions (the faces, edges and corners of
/// a cube). Moving the second shape that far along the reported normal separates them, so the
/// depth is never understated (the old fallback reported touching).
fn conservative_depth<G1, G2>(pos12: &Pose, g1: &G1, g2: &G2) -> Local
where
    G1: ?Sized + SupportMap,
    G2: ?Sized + SupportMap,
{
    let mut best = (f64::INFINITY, Vector::ZERO, Vector::ZERO, Vector::X);
    for k in 0..27 {
        let i = |m: i32| f64::from((k / m) % 3 - 1);
        let Some(n) = Vector::new(i(1), i(3), i(9)).try_normalize() else {
            continue;
        };
        let p1 = g1.local_support_point(n);
        let p2 = pos12 * g2.local_support_point(pos12.rotation.inverse() * -n);
        let extent = n.dot(p1 - p2);
        if extent < best.0 {
            best = (extent, p1, p2, n);
        }
    }
    let (extent, p1, p2, n) = best;
    (p1, p2, n, -extent.max(0.0))
}

fn composite(a: Posed<'_>, b: Posed<'_>, max_dist: f64) -> Result<Option<Witness>, Unsupported> {
    match query::closest_points(a.pose, a.shape, b.pose, b.shape, max_dist)? {
        ClosestPoints::WithinMargin(p1, p2) => {
            let d = p2 - p1;
            Ok(Some(Witness {
                distance: d.length(),
                point_a: p1,
                point_b: p2,
                normal: d.try_normalize().unwrap_or(DVec3::X),
            }))
        }
        ClosestPoints::Disjoint => Ok(None),
        ClosestPoints::Intersecting => Ok(Some(
            match query::contact(a.pose, a.shape, b.pose, b.shape, 0.0)? {
                Some(c) => Witness {
                    distance: c.dist.min(0.0),
                    point_a: c.point1,
                    point_b: c.point2,
                    normal: c.normal1,
                },
                None => Witness {
                    distance: 0.0,
                    point_a: a.pose.translation,
                    point_b: b.pose.translation,
                    normal: DVec3::X,
                },
            },
        )),
    }
}

/// Whether the two posed shapes overlap or touch (no penetration depth computed).
pub(crate) fn intersects(
    a: Posed<'_>,
    b: Posed<'_>,
    scratch: &mut Scratch,
) -> Result<bool, Unsupported> {
    let pos12 = a.pose.inv_mul(b.pose);
    let hit = match (a.kind, b.kind) {
        (Kind::Ball(ba), Kind::Ball(bb)) => {
            let r = ba.radius + bb.radius;
            pos12.translation.length_squared() <= r * r
        }
        (Kind::Ball(_) | Kind::Capsule(_), Kind::Other)
        | (Kind::Other, Kind::Ball(_) | Kind::Capsule(_))
            if a.shape.as_trimesh().is_some() || b.shape.as_trimesh().is_some() =>
        {
            // Inside a closed mesh counts (see `ball_mesh`, `capsule_mesh`).
            proximity(a, b, 0.0, scratch)?.is_some()
        }
        (Kind::Ball(_), Kind::Other)
        | (Kind::Other, Kind::Ball(_))
        | (Kind::Other, Kind::Other) => {
            query::intersection_test(a.pose, a.shape, b.pose, b.shape)?.intersecting
        }
        (Kind::Ball(_), _) | (_, Kind::Ball(_)) => proximity(a, b, 0.0, scratch)?.is_some(),
        (Kind::Cylinder(s1), Kind::Cylinder(s2)) => overlap(&pos12, s1, s2, scratch),
        (Kind::Cylinder(s1), Kind::Cuboid(s2)) => overlap(&pos12, s1, s2, scratch),
        (Kind::Cylinder(s1), Kind::Capsule(s2)) => overlap(&pos12, s1, s2, scratch),
        (Kind::Cuboid(s1), Kind::Cylinder(s2)) => overlap(&pos12, s1, s2, scratch),
        (Kind::Cuboid(s1), Kind::Cuboid(s2)) => overlap(&pos12, s1, s2, scratch),
        (Kind::Cuboid(s1), Kind::Capsule(s2)) => overlap(&pos12, s1, s2, scratch),
        (Kind::Capsule(s1), Kind::Cylinder(s2)) => overlap(&pos12, s1, s2, scratch),
        (Kind::Capsule(s1), Kind::Cuboid(s2)) => overlap(&pos12, s1, s2, scratch),
        (Kind::Capsule(s1), Kind::Capsule(s2)) => overlap(&pos12, s1, s2, scratch),
        _ => query::intersection_test(a.pose, a.shape, b.pose, b.shape)?.intersecting,
    };
    Ok(hit)
}

/// GJK's boolean form: stops as soon as a separating direction is found.
fn overlap<G1, G2>(pos12: &Pose, g1: &G1, g2: &G2, scratch: &mut Scratch) -> bool
where
    G1: ?Sized + SupportMap,
    G2: ?Sized + SupportMap,
{
    let dir = pos12.translation.try_normalize().unwrap_or(Vector::X);
    scratch
        .simplex
        .reset(CsoPoint::from_shapes(pos12, g1, g2, dir));
    matches!(
        gjk::closest_points(pos12, g1, g2, 0.0, false, &mut scratch.simplex),
        GJKResult::Intersection | GJKResult::Proximity(_)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    /// The ball closed forms agree with parry's point projection, inside and outside.
    #[test]
    fn ball_primitives_match_parry() {
        let shapes = [
            SharedShape::cylinder(0.2, 0.1),
            SharedShape::cuboid(0.1, 0.2, 0.3),
            SharedShape::capsule_z(0.15, 0.05),
        ];
        let mut scratch = Scratch::default();
        for shape in &shapes {
            let kind = Kind::of(shape);
            for k in 0..300 {
                let f = f64::from(k);
                let pose = Pose::from_parts(
                    Vector::new(0.1, -0.2, 0.05),
                    DQuat::from_euler(glam::EulerRot::XYZ, f * 0.7, f * 1.3, f * 0.3),
                );
                let center = Vector::new((f * 0.37).sin(), (f * 0.11).cos(), (f * 0.23).sin())
                    * 0.35
                    + pose.translation;
                let ball = Ball::new(0.04);
                let ours = ball_primitive_at(center, ball.radius, &kind, &pose).unwrap();
                let pos12 = pose.inv_mul(&Pose::from_translation(center));
                let theirs =
                    details::contact_convex_polyhedron_ball(&pos12, &**shape, &ball, f64::MAX)
                        .unwrap();
                assert!(
                    (ours.distance - theirs.dist).abs() < 1e-12,
                    "{k}: {} vs {}",
                    ours.distance,
                    theirs.dist
                );
                assert!(
                    (ours.point_a - pose * theirs.point1).length() < 1e-12,
                    "{k}"
                );
                // Through the dispatcher, both orders.
                let (bk, bp) = (Kind::Ball(ball), Pose::from_translation(center));
                let ab = proximity(
                    Posed {
                        kind: &bk,
                        shape: &ball,
                        pose: &bp,
                    },
                    Posed {
                        kind: &kind,
                        shape: &**shape,
                        pose: &pose,
                    },
                    f64::MAX,
                    &mut scratch,
                )
                .unwrap()
                .unwrap();
                assert!(
                    (ab.distance - theirs.dist).abs() < 1e-12
                        && (ab.point_b - ours.point_a).length() < 1e-12
                );
                assert!((ab.normal + ours.normal).length() < 1e-12);
            }
        }
    }
}
