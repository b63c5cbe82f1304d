//! Triangle meshes against balls, capsules, convex shapes and other meshes.

use super::*;

/// A ball and a triangle mesh (either order): `None` when the pair is not one. The signed
/// distance is the ball centre's distance to the closest point of the triangles, less the
/// radius, negated (and then less the radius) when the mesh is closed and the centre inside it
/// (parry's pseudo-normal test, [`crate::is_closed_trimesh`]). An open mesh is a surface: a
/// centre on either side is outside.
pub(super) fn ball_mesh(a: Posed<'_>, b: Posed<'_>, max_dist: f64) -> Option<Option<Witness>> {
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
pub(super) fn sphere_mesh(mesh: &TriMesh, c: Vector, r: f64) -> (f64, Vector, Vector) {
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
pub(super) fn mesh_witness(
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
pub(super) const SEGMENT_SAMPLES: u32 = 16;

/// A capsule and a closed triangle mesh (either order): `None` when the pair is not one. Where
/// the capsule's segment reaches the mesh's inside (or its surface), the signed distance is that
/// of its deepest point, as a ball of the capsule's radius there ([`ball_mesh`]): the
/// segment's signed distance to the solid is sampled along it and refined around the smallest
/// sample by golden-section search. Otherwise (and for an open mesh, a surface) the
/// triangle-by-triangle query of [`mesh_convex`], exact for a segment outside.
pub(super) fn capsule_mesh(
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
pub(super) fn mesh_convex(
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
pub(super) const PROJECTIONS: usize = 8;

/// How far (relative to the coordinates, in metres) a mesh's vertex may lie beyond a
/// separating plane and still count as on it: rounding in the projections, far below the
/// distances' own precision (GJK's 1e-8).
pub(super) const SLAB_TOLERANCE: f64 = 1e-12;

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
pub(super) fn mesh_mesh(
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
