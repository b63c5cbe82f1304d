//! A lean GJK distance for two separated convex shapes (van den Bergen's algorithm with the
//! closest-point-on-simplex regions of Ericson's *Real-Time Collision Detection*), used before
//! parry's GJK/EPA: on the panda's cylinder pairs it is several times cheaper than parry's
//! general Voronoi simplex. It reports `None` for overlapping shapes and for the rare cases it
//! does not settle, and the caller then runs parry's GJK and EPA.

use glam::{DMat3, DVec3};
use parry3d_f64::math::Pose;
use parry3d_f64::shape::SupportMap;

/// Relative precision of the distance: iterations stop when the gap between the upper bound
/// `|v|` and the lower bound `v·w / |v|` is below `REL_TOL · |v|` (1e-8 m for shapes a metre
/// apart, a hundredth of the reference tolerance; coal's default GJK tolerance is 1e-6).
const REL_TOL: f64 = 1e-8;
const MAX_ITERATIONS: usize = 64;

#[derive(Clone, Copy)]
struct Vertex {
    /// Point of the Minkowski difference `A - B`.
    w: DVec3,
    /// Support point of `A`.
    a: DVec3,
    /// Support point of `B` (in `A`'s frame).
    b: DVec3,
}

/// Closest points `(point on 1, point on 2, unit normal from 1 to 2, distance)` in shape 1's
/// frame, or `None` (overlap, touching, or no convergence).
pub(crate) fn separated_distance<G1, G2>(
    pos12: &Pose,
    g1: &G1,
    g2: &G2,
    dir: DVec3,
) -> Option<(DVec3, DVec3, DVec3, f64)>
where
    G1: ?Sized + SupportMap,
    G2: ?Sized + SupportMap,
{
    let rot = DMat3::from_quat(pos12.rotation);
    let rot_t = rot.transpose();
    let t12 = pos12.translation;
    // Support point of the difference toward `d`: a(d) - b(-d).
    let support = |d: DVec3| {
        let a = g1.local_support_point(d);
        let b = rot * g2.local_support_point(rot_t * -d) + t12;
        Vertex { w: a - b, a, b }
    };
    let mut simplex = [support(dir); 4];
    let mut n = 1;
    let mut lambda = [1.0, 0.0, 0.0, 0.0];
    let mut v = simplex[0].w;
    for _ in 0..MAX_ITERATIONS {
        let vv = v.length_squared();
        if vv < 1e-24 {
            return None;
        }
        let w = support(-v);
        // Lower bound of the distance: v·w / |v|; stop when it meets the upper bound |v|.
        let gap = vv - v.dot(w.w);
        // A repeated vertex means no progress is possible either.
        if gap <= REL_TOL * vv || simplex[..n].iter().any(|s| s.w == w.w) {
            return finish(&simplex[..n], &lambda[..n]);
        }
        simplex[n] = w;
        let region = closest_region(&simplex, n + 1)?;
        if region.point.length_squared() >= vv {
            // The new point did not bring the simplex closer: round-off in a nearly degenerate
            // simplex. Keep the previous answer if it is nearly converged (its lower bound along
            // `v` is within 1e-8 relative); parry's GJK takes over otherwise.
            return if gap <= 1e-8 * vv {
                finish(&simplex[..n], &lambda[..n])
            } else {
                None
            };
        }
        // Compact in place: with the kept indices sorted, each source is at or after its slot.
        let mut kept = [
            (region.vertices[0], region.weights[0]),
            (region.vertices[1], region.weights[1]),
            (region.vertices[2], region.weights[2]),
        ];
        n = region.count;
        kept[..n].sort_unstable_by_key(|k| k.0);
        for (t, &(k, l)) in kept[..n].iter().enumerate() {
            simplex[t] = simplex[k];
            lambda[t] = l;
        }
        v = region.point;
    }
    None
}

fn finish(simplex: &[Vertex], lambda: &[f64]) -> Option<(DVec3, DVec3, DVec3, f64)> {
    let mut p1 = DVec3::ZERO;
    let mut p2 = DVec3::ZERO;
    for (s, l) in simplex.iter().zip(lambda) {
        p1 += s.a * *l;
        p2 += s.b * *l;
    }
    let d = p2 - p1;
    let len = d.length();
    (len > 0.0).then(|| (p1, p2, d / len, len))
}

/// The smallest sub-simplex whose hull contains the point closest to the origin.
#[derive(Clone, Copy)]
struct Region {
    point: DVec3,
    /// Indices of its vertices into the simplex (the first `count`).
    vertices: [usize; 3],
    count: usize,
    weights: [f64; 3],
}

impl Region {
    fn vertex(i: usize, p: DVec3) -> Self {
        Region {
            point: p,
            vertices: [i, i, i],
            count: 1,
            weights: [1.0, 0.0, 0.0],
        }
    }

    fn edge(i: usize, j: usize, p: DVec3, t: f64) -> Self {
        Region {
            point: p,
            vertices: [i, j, j],
            count: 2,
            weights: [1.0 - t, t, 0.0],
        }
    }
}

/// The closest point of the hull of `s[..n]` to the origin, or `None` when the origin is inside
/// the tetrahedron (the shapes overlap).
fn closest_region(s: &[Vertex; 4], n: usize) -> Option<Region> {
    match n {
        2 => Some(segment(s[0].w, s[1].w, 0, 1)),
        3 => Some(triangle(s, [0, 1, 2])),
        _ => tetrahedron(s),
    }
}

fn segment(a: DVec3, b: DVec3, i: usize, j: usize) -> Region {
    let ab = b - a;
    let t = -a.dot(ab);
    if t <= 0.0 {
        return Region::vertex(i, a);
    }
    let denom = ab.length_squared();
    if t >= denom {
        return Region::vertex(j, b);
    }
    let t = t / denom;
    Region::edge(i, j, a + ab * t, t)
}

/// Ericson's closest point of a triangle to the origin, by Voronoi region.
fn triangle(s: &[Vertex; 4], [i, j, k]: [usize; 3]) -> Region {
    let (a, b, c) = (s[i].w, s[j].w, s[k].w);
    let (ab, ac) = (b - a, c - a);
    let (d1, d2) = (-ab.dot(a), -ac.dot(a));
    if d1 <= 0.0 && d2 <= 0.0 {
        return Region::vertex(i, a);
    }
    let (d3, d4) = (-ab.dot(b), -ac.dot(b));
    if d3 >= 0.0 && d4 <= d3 {
        return Region::vertex(j, b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let t = d1 / (d1 - d3);
        return Region::edge(i, j, a + ab * t, t);
    }
    let (d5, d6) = (-ab.dot(c), -ac.dot(c));
    if d6 >= 0.0 && d5 <= d6 {
        return Region::vertex(k, c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let t = d2 / (d2 - d6);
        return Region::edge(i, k, a + ac * t, t);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return Region::edge(j, k, b + (c - b) * t, t);
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    Region {
        point: a + ab * v + ac * w,
        vertices: [i, j, k],
        count: 3,
        weights: [1.0 - v - w, v, w],
    }
}

/// Ericson's closest point of a tetrahedron: the best of the faces the origin is outside of.
fn tetrahedron(s: &[Vertex; 4]) -> Option<Region> {
    const FACES: [[usize; 4]; 4] = [[0, 1, 2, 3], [0, 2, 3, 1], [0, 3, 1, 2], [1, 3, 2, 0]];
    let mut best: Option<Region> = None;
    for [i, j, k, l] in FACES {
        let (a, b, c, d) = (s[i].w, s[j].w, s[k].w, s[l].w);
        let normal = (b - a).cross(c - a);
        let origin_side = -a.dot(normal);
        let other_side = (d - a).dot(normal);
        // Skip faces with the origin on the inner side; a flat tetrahedron has none.
        if origin_side * other_side > 0.0 && other_side.abs() > 1e-30 {
            continue;
        }
        let r = triangle(s, [i, j, k]);
        if best.is_none_or(|b| r.point.length_squared() < b.point.length_squared()) {
            best = Some(r);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;
    use parry3d_f64::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
    use parry3d_f64::shape::{Cuboid, Cylinder};

    /// Ours against parry's GJK for one pair: `Some(true)` solved, `Some(false)` declined.
    fn check<G2: SupportMap>(pos12: &Pose, g1: &Cylinder, g2: &G2, k: i32) -> bool {
        let dir = pos12.translation.normalize();
        let mut simplex = VoronoiSimplex::new();
        simplex.reset(CsoPoint::from_shapes(pos12, g1, g2, dir));
        let theirs = match gjk::closest_points(pos12, g1, g2, f64::MAX, true, &mut simplex) {
            GJKResult::ClosestPoints(p1, p2, _) => Some((p2 - p1).length()),
            _ => None,
        };
        let Some((p1, p2, n, d)) = separated_distance(pos12, g1, g2, dir) else {
            return false;
        };
        let t = theirs.unwrap_or_else(|| panic!("{k}: ours {d} but parry finds an overlap"));
        // Both are distances between points of the shapes, so upper bounds of the true
        // distance, each within its relative tolerance (parry: 4.7e-8, or a stall).
        assert!(d <= t + 2.0 * REL_TOL * t, "{k}: {d} vs {t}");
        assert!(((p2 - p1).length() - d).abs() < 1e-12);
        // The plane normal to `n` separates the shapes by nearly `d`: a lower bound.
        let a = g1.local_support_point(n);
        let b = pos12 * g2.local_support_point(pos12.rotation.inverse() * -n);
        let lower = n.dot(b - a);
        assert!(
            d - lower < 2.0 * REL_TOL * d + 1e-12 && lower <= d + 1e-12,
            "{k}: {d} vs lower bound {lower}"
        );
        true
    }

    /// Agrees with parry's GJK and certifies its result on separated cylinder and box pairs;
    /// declines overlapping ones.
    #[test]
    fn matches_parry_gjk() {
        let cylinder = Cylinder::new(0.15, 0.09);
        let cuboid = Cuboid::new(DVec3::new(0.05, 0.2, 0.1));
        let (mut solved, mut declined) = (0, 0);
        for k in 0..2000 {
            let f = f64::from(k);
            let pos12 = Pose::from_parts(
                DVec3::new((f * 0.37).sin(), (f * 0.11).cos(), (f * 0.23).sin())
                    * (0.1 + 0.5 * (f * 0.05).sin().abs()),
                DQuat::from_euler(glam::EulerRot::XYZ, f * 0.7, f * 1.3, f * 0.3),
            );
            for ok in [
                check(&pos12, &cylinder, &cylinder, k),
                check(&pos12, &cylinder, &cuboid, k),
            ] {
                if ok {
                    solved += 1;
                } else {
                    declined += 1;
                }
            }
        }
        assert!(
            solved > 2000 && declined > 100,
            "{solved} solved, {declined} declined"
        );
    }
}
