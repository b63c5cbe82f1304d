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

/// A ball and a triangle mesh (either order): `None` when the pair is not one. The signed
/// distance is the ball centre's distance to the closest point of the triangles, less the
/// radius, negated (and then less the radius) when the mesh is closed and the centre inside it
/// (parry's pseudo-normal test, [`crate::is_closed_trimesh`]). An open mesh is a surface: a
/// centre on either side is outside.
fn ball_mesh(a: Posed<'_>, b: Posed<'_>, max_dist: f64) -> Option<Option<Witness>> {
    let (ball, ball_pose, mesh, mesh_pose, mesh_first) =
        if let (Some(ball), Some(mesh)) = (a.shape.as_ball(), b.shape.as_trimesh()) {
            (ball, a.pose, mesh, b.pose, false)
        } else if let (Some(mesh), Some(ball)) = (a.shape.as_trimesh(), b.shape.as_ball()) {
            (ball, b.pose, mesh, a.pose, true)
        } else {
            return None;
        };
    let r = ball.radius;
    let c = mesh_pose.inverse_transform_point(ball_pose.translation);
    // Beyond the bound from the mesh's box: no projection needed.
    if max_dist.is_finite() && mesh.local_aabb().distance_to_local_point(c, true) - r > max_dist {
        return Some(None);
    }
    let (distance, on_mesh, n) = sphere_mesh(mesh, c, r);
    Some(
        (distance <= max_dist)
            .then(|| mesh_witness(mesh_pose, mesh_first, distance, on_mesh, c - n * r, n)),
    )
}

/// A ball at `c` (the mesh's frame) of radius `r` against a triangle mesh: the signed
/// distance (see [`ball_mesh`]), the mesh's closest point and its outward normal there.
fn sphere_mesh(mesh: &TriMesh, c: Vector, r: f64) -> (f64, Vector, Vector) {
    let (proj, (id, _)) = mesh.project_local_point_and_get_location(c, false);
    let inside = proj.is_inside && mesh.pseudo_normals_if_oriented().is_some();
    let gap = c - proj.point;
    let len = gap.length();
    // The outward normal: toward the centre when it is outside.
    let n = if len > 0.0 {
        if inside { -gap / len } else { gap / len }
    } else {
        mesh.triangle(id).normal().unwrap_or(Vector::Z)
    };
    (if inside { -len } else { len } - r, proj.point, n)
}

/// The world witness of a mesh (at `mesh_pose`) and another shape from points and the mesh's
/// outward normal in the mesh's frame, in the pair's order.
fn mesh_witness(
    mesh_pose: &Pose,
    mesh_first: bool,
    distance: f64,
    on_mesh: Vector,
    on_other: Vector,
    n: Vector,
) -> Witness {
    let (on_mesh, on_other, n) = (
        mesh_pose.transform_point(on_mesh),
        mesh_pose.transform_point(on_other),
        mesh_pose.rotation * n,
    );
    if mesh_first {
        Witness {
            distance,
            point_a: on_mesh,
            point_b: on_other,
            normal: n,
        }
    } else {
        Witness {
            distance,
            point_a: on_other,
            point_b: on_mesh,
            normal: -n,
        }
    }
}

/// Samples of a capsule's segment for [`capsule_mesh`].
const SEGMENT_SAMPLES: u32 = 16;

/// A capsule and a closed triangle mesh (either order): `None` when the pair is not one. Where
/// the capsule's segment reaches the mesh's inside (or its surface), the signed distance is that
/// of its deepest point, as a ball of the capsule's radius there ([`ball_mesh`]): the
/// segment's signed distance to the solid is sampled along it and refined around the smallest
/// sample by golden-section search. Otherwise (and for an open mesh, a surface) the
/// triangle-by-triangle query of [`mesh_convex`], exact for a segment outside.
fn capsule_mesh(
    a: Posed<'_>,
    b: Posed<'_>,
    max_dist: f64,
    scratch: &mut Scratch,
) -> Option<Option<Witness>> {
    let (capsule, capsule_pose, mesh, mesh_pose, mesh_first) =
        match (a.kind, b.shape.as_trimesh(), a.shape.as_trimesh(), b.kind) {
            (Kind::Capsule(c), Some(mesh), _, _) => (c, a.pose, mesh, b.pose, false),
            (_, _, Some(mesh), Kind::Capsule(c)) => (c, b.pose, mesh, a.pose, true),
            _ => return None,
        };
    let pos = mesh_pose.inv_mul(capsule_pose);
    let (e0, e1) = (pos * capsule.segment.a, pos * capsule.segment.b);
    let r = capsule.radius;
    let capsule_box = Aabb::new(e0.min(e1) - Vector::splat(r), e0.max(e1) + Vector::splat(r));
    if mesh.pseudo_normals_if_oriented().is_none() || !capsule_box.intersects(&mesh.local_aabb()) {
        // Open, or clearly outside: the surface query.
        return mesh_convex(a, b, max_dist, scratch);
    }
    let at = |t: f64| e0 + (e1 - e0) * t;
    let depth = |t: f64| sphere_mesh(mesh, at(t), 0.0).0;
    let (mut best_t, mut best) = (0.0, f64::INFINITY);
    for k in 0..=SEGMENT_SAMPLES {
        let t = f64::from(k) / f64::from(SEGMENT_SAMPLES);
        let d = depth(t);
        if d < best {
            (best_t, best) = (t, d);
        }
    }
    if best > 0.0 {
        // The segment stays outside: the surface query is exact.
        return mesh_convex(a, b, max_dist, scratch);
    }
    // Golden-section search for the deepest point between the neighbouring samples.
    let step = 1.0 / f64::from(SEGMENT_SAMPLES);
    let (mut lo, mut hi) = ((best_t - step).max(0.0), (best_t + step).min(1.0));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (depth(x1), depth(x2));
    for _ in 0..40 {
        if f1 < f2 {
            (hi, x2, f2) = (x2, x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = depth(x1);
        } else {
            (lo, x1, f1) = (x1, x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = depth(x2);
        }
    }
    for (t, d) in [(x1, f1), (x2, f2)] {
        if d < best {
            (best_t, best) = (t, d);
        }
    }
    let c = at(best_t);
    let (distance, on_mesh, n) = sphere_mesh(mesh, c, r);
    Some(
        (distance <= max_dist)
            .then(|| mesh_witness(mesh_pose, mesh_first, distance, on_mesh, c - n * r, n)),
    )
}

/// A triangle mesh against a convex shape (either order), triangle by triangle with the crate's
/// GJK/EPA; `None` when neither or both are meshes, or the other shape has no support map.
///
/// parry's own composite query is not used here: its box–triangle closest points report a
/// vertex-to-vertex distance for face-to-face configurations, and its best-first traversal with
/// a zero margin visits no triangle (so overlaps were missed by the collision lists).
///
/// Penetration: the deepest of the triangles the convex shape overlaps (a triangle mesh is a
/// surface; a shape wholly inside it does not touch it). Separation: the closest triangle.
fn mesh_convex(
    a: Posed<'_>,
    b: Posed<'_>,
    max_dist: f64,
    scratch: &mut Scratch,
) -> Option<Option<Witness>> {
    let (mesh, other, flipped) = match (a.shape.as_trimesh(), b.shape.as_trimesh()) {
        (Some(m), None) => (m, b, false),
        (None, Some(m)) => (m, a, true),
        _ => return None,
    };
    let mesh_pose = if flipped { b.pose } else { a.pose };
    let convex = other.shape.as_support_map()?;
    // The convex shape in the mesh's frame.
    let pos12 = mesh_pose.inv_mul(other.pose);
    let aabb = other.shape.compute_aabb(&pos12);
    let bvh = mesh.bvh();
    // Triangles whose boxes overlap the shape's box: the only ones that can penetrate it.
    let mut best: Option<Local> = None;
    for id in bvh.intersect_aabb(&aabb) {
        let tri = mesh.triangle(id);
        if let Some(local) = support(&pos12, &tri, convex, f64::INFINITY, scratch)
            && local.3 < 0.0
            && best.is_none_or(|b| local.3 < b.3)
        {
            best = Some(local);
        }
    }
    if best.is_none() {
        // Separated (or touching): the closest triangle, best-first through the BVH. The margin
        // is kept positive because the traversal only visits boxes strictly below it.
        let margin = if max_dist > 0.0 { max_dist } else { 1e-12 };
        let msum_shift = -aabb.center();
        let msum_margin = aabb.half_extents();
        let scratch = core::cell::RefCell::new(&mut *scratch);
        best = bvh
            .find_best(
                margin,
                |node: &BvhNode, _| {
                    Aabb {
                        mins: node.mins() + msum_shift - msum_margin,
                        maxs: node.maxs() + msum_shift + msum_margin,
                    }
                    .distance_to_origin()
                },
                |id, _| {
                    let tri = mesh.triangle(id);
                    support(&pos12, &tri, convex, margin, &mut scratch.borrow_mut())
                        .map(|local| (local.3, local))
                },
            )
            .map(|(_, (_, local))| local);
    }
    let (p1, p2, n, distance) = best.filter(|l| l.3 <= max_dist)?;
    // Back to the world frame, from the first shape to the second.
    let (pm, po, n) = (
        mesh_pose.transform_point(p1),
        mesh_pose.transform_point(p2),
        mesh_pose.rotation * n,
    );
    Some(Some(if flipped {
        Witness {
            distance,
            point_a: po,
            point_b: pm,
            normal: -n,
        }
    } else {
        Witness {
            distance,
            point_a: pm,
            point_b: po,
            normal: n,
        }
    }))
}

/// At most this many more projections refine the first pair of surface points of two meshes.
const PROJECTIONS: usize = 8;

/// How far (relative to the coordinates, in metres) a mesh's vertex may lie beyond a
/// separating plane and still count as on it: rounding in the projections, far below the
/// distances' own precision (GJK's 1e-8).
const SLAB_TOLERANCE: f64 = 1e-12;

/// Two triangle meshes, as [`mesh_convex`] treats a mesh (a surface): separated, the closest
/// pair of triangles; touching or overlapping, the deepest of the crossing pairs. `None` when
/// either shape is not a triangle mesh.
///
/// 1. Two surface points, each the projection of the other onto its mesh, settle on a pair of
///    triangles, whose closest points are then solved exactly.
/// 2. When the slab between the planes through those points, normal to the gap, holds no
///    vertex of either mesh, it separates the meshes and that pair is the answer (most pairs of
///    the bundled Panda's links).
/// 3. Otherwise both bounding-volume trees are traversed at once from step 1's distance,
///    skipping the pairs of boxes, and of triangles, farther apart than the best pair so far
///    (by box distance and by their gap along step 1's direction; once two triangles touch,
///    every pair that does not overlap).
///
/// parry's composite query, used before, tests the triangles of one mesh against the whole
/// other mesh with no bound between them: on the bundled Panda's meshes (200–300 triangles
/// each) a pair took ~0.6 ms, a whole `compute_distances` ~30 ms; and with a zero margin (a
/// collision query) it visits no triangle.
fn mesh_mesh(
    a: Posed<'_>,
    b: Posed<'_>,
    max_dist: f64,
    scratch: &mut Scratch,
) -> Option<Option<Witness>> {
    let (ma, mb) = (a.shape.as_trimesh()?, b.shape.as_trimesh()?);
    // Mesh b in mesh a's frame.
    let pos12 = a.pose.inv_mul(b.pose);
    // Projections onto each mesh (in a's frame), with the triangle they land on.
    let on_a = |p: Vector| {
        let (proj, (id, _)) = ma.project_local_point_and_get_location(p, false);
        (proj.point, id)
    };
    let on_b = |p: Vector| {
        let (proj, (id, _)) =
            mb.project_local_point_and_get_location(pos12.inverse_transform_point(p), false);
        (pos12 * proj.point, id)
    };
    // Alternate projections from b's centre: each step can only bring the points closer.
    let (mut pb, mut ib) = on_b(on_a(pos12 * mb.local_aabb().center()).0);
    let (mut pa, mut ia) = on_a(pb);
    for _ in 0..PROJECTIONS {
        let (next, id) = on_b(pa);
        let closer = (pa - next).length() < (pa - pb).length() * (1.0 - 1e-12);
        (pb, ib) = (next, id);
        if !closer {
            break;
        }
        (pa, ia) = on_a(pb);
    }
    // The two triangles the points settled on, solved exactly: when no vertex of a lies
    // beyond the plane through their closest point normal to the gap, nor any vertex of b
    // before the parallel plane through theirs, the slab between the planes separates the
    // meshes, and those triangles are the closest pair.
    let pair = support(
        &pos12,
        &ma.triangle(ia),
        &mb.triangle(ib),
        f64::INFINITY,
        scratch,
    );
    if let Some(local @ (p1, p2, n, distance)) = pair
        && distance > 0.0
    {
        let (n_b, offset) = (pos12.rotation.inverse() * n, pos12.translation.dot(n));
        let beyond_a = ma
            .vertices()
            .iter()
            .map(|v| v.dot(n))
            .fold(f64::MIN, f64::max);
        let before_b = mb
            .vertices()
            .iter()
            .map(|v| v.dot(n_b))
            .fold(f64::MAX, f64::min)
            + offset;
        let slack = SLAB_TOLERANCE * (1.0 + p1.abs().max_element() + p2.abs().max_element());
        if beyond_a <= p1.dot(n) + slack && before_b >= p2.dot(n) - slack {
            return Some((distance <= max_dist).then(|| in_world(a.pose, local)));
        }
    }
    // An upper bound of the distance (the two points', or their triangles'), with a little
    // slack so that the pair of triangles is not pruned; or `max_dist` when that is lower.
    let upper = pair.map_or(f64::INFINITY, |l| l.3).min((pa - pb).length());
    let bound = (upper.max(0.0) * (1.0 + 1e-9) + 1e-12).min(max_dist.max(0.0));
    let limit = core::cell::Cell::new(bound);
    // |R|: a box of b's tree, turned into a's frame, lies in a box of these half extents.
    let rot = glam::DMat3::from_quat(pos12.rotation);
    let abs_rot = glam::DMat3::from_cols(rot.x_axis.abs(), rot.y_axis.abs(), rot.z_axis.abs());
    // The direction from the first surface point to the second, in both frames: the gap
    // between two boxes along it is a second lower bound of their triangles' distance, which
    // prunes the boxes that lie off to the side as the box distance alone does not.
    let axis = (pb - pa).try_normalize().unwrap_or(Vector::ZERO);
    let axis_in_b = rot.transpose() * axis;
    let axis_offset = pos12.translation.dot(axis);
    let (axis_a, axis_b) = (axis.abs(), axis_in_b.abs());
    let apart = |na: &BvhNode, nb: &BvhNode| {
        let (ca, ha) = (na.center(), (na.maxs() - na.mins()) * 0.5);
        let cb = pos12 * nb.center();
        let hb_local = (nb.maxs() - nb.mins()) * 0.5;
        let hb = abs_rot * hb_local;
        let boxes = ((ca - cb).abs() - ha - hb).max(Vector::ZERO).length();
        let slab = (cb - ca).dot(axis) - ha.dot(axis_a) - hb_local.dot(axis_b);
        boxes.max(slab)
    };
    let mut best: Option<Local> = None;
    let pairs = ma
        .bvh()
        .leaf_pairs(mb.bvh(), |na, nb| apart(na, nb) <= limit.get());
    for (ia, ib) in pairs {
        let (ta, tb) = (ma.triangle(ia), mb.triangle(ib));
        // The gap between the two triangles' own vertices along the axis: a tighter lower
        // bound than their boxes', for the price of six dot products.
        let high_a = ta.a.dot(axis).max(ta.b.dot(axis)).max(ta.c.dot(axis));
        let low_b =
            tb.a.dot(axis_in_b)
                .min(tb.b.dot(axis_in_b))
                .min(tb.c.dot(axis_in_b))
                + axis_offset;
        if low_b - high_a > limit.get() {
            continue;
        }
        let Some(local) = support(&pos12, &ta, &tb, limit.get(), scratch) else {
            continue;
        };
        if best.is_none_or(|b| local.3 < b.3) {
            // Once two triangles touch, only overlapping boxes can hold a deeper pair.
            limit.set(local.3.max(0.0).min(limit.get()));
            best = Some(local);
        }
    }
    let Some(local) = best else {
        // Nothing within the bound: farther apart than `max_dist` when that was the bound; a
        // bound from the surface points always holds their triangles, unless GJK's tolerance
        // put them just above it, when parry's query decides.
        return (bound >= max_dist).then_some(None);
    };
    Some((local.3 <= max_dist).then(|| in_world(a.pose, local)))
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
