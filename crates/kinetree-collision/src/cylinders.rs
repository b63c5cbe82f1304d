//! The distance between two separated cylinders by maximising the lower bound of their
//! support functions, with a certificate; GJK runs when the certificate fails.
//!
//! A cylinder of axis `a`, centre `c`, half height `h` and radius `r` has the support function
//! `h(n) = n·c + h·|n·a| + r·|n - (n·a)·a|`. For a unit `n` from cylinder 1 toward cylinder 2,
//! `L(n) = min over 2 of n·x - max over 1 of n·x = -h₂(-n) - h₁(n)` is the width of the slab
//! between the two along `n`: a lower bound of their distance for every `n`, and the distance at
//! its maximum. `L` is concave and positively homogeneous, so a local maximum on the sphere with
//! `L > 0` is the distance; its gradient is `w(n) = s₂(-n) - s₁(n)` (support points) and its
//! Hessian off the kinks is `-(r₁/ρ₁)·k₁k₁ᵀ - (r₂/ρ₂)·k₂k₂ᵀ` (`ρ = |n - (n·a)·a|`, `k` the unit
//! vector normal to the axis and to `n`'s radial part).
//!
//! The maximum is found by Newton's method on the sphere (rim against rim, where `L` is smooth),
//! on the great circle normal to either axis (a rim against a side, where `L` has a ridge), or
//! is one of the kink directions (an axis: a flat end; the axes' common normal: side against
//! side). Witness points come from the support points and the closed-form projections onto the
//! solid cylinders. The answer is returned only when the witnesses' distance (an upper bound)
//! is within the relative tolerance of GJK (`gjk::REL_TOL`) of the best lower bound, the same
//! guarantee as GJK's own stopping test.

use crate::gjk::{Local, REL_TOL};
use glam::DVec3;
use parry3d_f64::shape::Cylinder;

/// Newton iterations per search.
const MAX_NEWTON: usize = 12;
/// Newton stops after a step below this (radians): the next would be below its square.
const STOP_STEP: f64 = 1e-6;
/// Newton stops when its step would raise `L` by less than this fraction of it (a thousandth of
/// the certificate's tolerance).
const DECREMENT: f64 = 1e-3 * REL_TOL;
/// Largest Newton step (radians), so an early step cannot jump across the sphere.
const MAX_STEP: f64 = 0.5;

/// Two cylinders in the first one's frame: cylinder 1 along y at the origin, cylinder 2 along
/// `axis` at `center`.
struct Pair {
    h1: f64,
    r1: f64,
    h2: f64,
    r2: f64,
    axis: DVec3,
    center: DVec3,
}

/// `L` at a direction `n`: its value, the support points (`s₂(-n) - s₁(n)` is the gradient) and
/// the Hessian `-c₁·k₁k₁ᵀ - c₂·k₂k₂ᵀ` (meaningful when `smooth`, away from the axes).
struct Eval {
    lower: f64,
    s1: DVec3,
    s2: DVec3,
    k1: DVec3,
    c1: f64,
    k2: DVec3,
    c2: f64,
    smooth: bool,
}

impl Eval {
    fn w(&self) -> DVec3 {
        self.s2 - self.s1
    }
}

/// The outcome of [`Pair::newton_sphere`].
enum Search {
    Converged(DVec3),
    /// The iterate crossed the plane normal to this axis, at this direction.
    Ridge(DVec3, DVec3),
    Failed,
}

/// The best bounds found so far.
struct Bounds {
    lower: f64,
    upper: f64,
    witness: (DVec3, DVec3),
}

impl Pair {
    /// `L(n)` (from the support functions, exact for any unit `n`), the support points and
    /// the Hessian's terms.
    fn eval(&self, n: DVec3) -> Eval {
        let radial1 = DVec3::new(n.x, 0.0, n.z);
        let rho1 = radial1.length();
        let s = n.dot(self.axis);
        let radial2 = n - self.axis * s;
        let rho2 = radial2.length();
        let lower = n.dot(self.center)
            - self.h2 * s.abs()
            - self.r2 * rho2
            - self.h1 * n.y.abs()
            - self.r1 * rho1;
        // Along an axis (up to round-off) every rim point is a support point: the centre of the
        // end is one too, and the round-off residue has no meaningful direction.
        let inv1 = if rho1 > 1e-12 { 1.0 / rho1 } else { 0.0 };
        let inv2 = if rho2 > 1e-12 { 1.0 / rho2 } else { 0.0 };
        let (m1, m2) = (radial1 * inv1, radial2 * inv2);
        Eval {
            lower,
            s1: m1 * self.r1 + DVec3::Y * self.h1.copysign(n.y),
            s2: self.center - self.axis * self.h2.copysign(s) - m2 * self.r2,
            k1: DVec3::Y.cross(m1),
            c1: self.r1 * inv1,
            k2: self.axis.cross(m2),
            c2: self.r2 * inv2,
            smooth: rho1 > 1e-9 && rho2 > 1e-9,
        }
    }

    /// The point of solid cylinder 1 closest to `x` (outside it).
    fn closest1(&self, x: DVec3) -> DVec3 {
        let rho = (x.x * x.x + x.z * x.z).sqrt();
        let scale = if rho > self.r1 { self.r1 / rho } else { 1.0 };
        DVec3::new(x.x * scale, x.y.clamp(-self.h1, self.h1), x.z * scale)
    }

    /// The point of solid cylinder 2 closest to `x` (outside it).
    fn closest2(&self, x: DVec3) -> DVec3 {
        let d = x - self.center;
        let s = d.dot(self.axis);
        let radial = d - self.axis * s;
        let rho = radial.length();
        let radial = if rho > self.r2 {
            radial * (self.r2 / rho)
        } else {
            radial
        };
        self.center + self.axis * s.clamp(-self.h2, self.h2) + radial
    }

    /// Records the lower bound at `n` and the witnesses built from its support points: the
    /// other shape's closest point to one, then the first shape's closest point to that (from
    /// the second shape's support point only when the first pair does not certify).
    fn try_direction(&self, n: DVec3, bounds: &mut Bounds) {
        let e = self.eval(n);
        bounds.lower = bounds.lower.max(e.lower);
        let q = self.closest2(e.s1);
        let p = self.closest1(q);
        self.witness(p, q, bounds);
        if !Pair::certified(bounds) {
            let p = self.closest1(e.s2);
            let q = self.closest2(p);
            self.witness(p, q, bounds);
        }
    }

    fn witness(&self, p: DVec3, q: DVec3, bounds: &mut Bounds) {
        let d = (q - p).length();
        if d < bounds.upper {
            bounds.upper = d;
            bounds.witness = (p, q);
        }
    }

    /// Newton's method for the maximum of `L` on the sphere, from `n`, with step halving so
    /// `L` never decreases. A step that would lower `L` across the plane normal to an axis
    /// means the maximum is on that ridge (a side): the search stops there.
    fn newton_sphere(&self, mut n: DVec3) -> Search {
        let side = |n: DVec3| (n.y >= 0.0, n.dot(self.axis) >= 0.0);
        let mut e = self.eval(n);
        for _ in 0..MAX_NEWTON {
            if e.lower <= 0.0 {
                // Far from the maximum the Hessian may be indefinite: step to the gradient.
                let Some(next) = e.w().try_normalize() else {
                    return Search::Failed;
                };
                n = next;
                e = self.eval(n);
                continue;
            }
            if !e.smooth {
                return Search::Failed;
            }
            let (l, w, k1, c1, k2, c2) = (e.lower, e.w(), e.k1, e.c1, e.k2, e.c2);
            let (e1, e2) = n.any_orthonormal_pair();
            let (g1, g2) = (e1.dot(w), e2.dot(w));
            let (a1, a2, b1, b2) = (k1.dot(e1), k1.dot(e2), k2.dot(e1), k2.dot(e2));
            // The Riemannian Hessian in the tangent basis: negative definite since l > 0.
            let m11 = -c1 * a1 * a1 - c2 * b1 * b1 - l;
            let m22 = -c1 * a2 * a2 - c2 * b2 * b2 - l;
            let m12 = -c1 * a1 * a2 - c2 * b1 * b2;
            let det = m11 * m22 - m12 * m12;
            if det <= 0.0 {
                return Search::Failed;
            }
            let d1 = -(m22 * g1 - m12 * g2) / det;
            let d2 = -(m11 * g2 - m12 * g1) / det;
            if 0.5 * (g1 * d1 + g2 * d2) <= DECREMENT * l {
                // The Newton step would gain less than this: converged.
                return Search::Converged(n);
            }
            let mut step = (d1 * d1 + d2 * d2).sqrt();
            let mut delta = e1 * d1 + e2 * d2;
            if step > MAX_STEP {
                delta *= MAX_STEP / step;
                step = MAX_STEP;
            }
            let here = side(n);
            let mut halvings = 0;
            loop {
                let next = (n + delta).normalize();
                let en = self.eval(next);
                if en.lower >= l {
                    (n, e) = (next, en);
                    break;
                }
                let there = side(next);
                if there.0 != here.0 {
                    return Search::Ridge(DVec3::Y, n);
                }
                if there.1 != here.1 {
                    return Search::Ridge(self.axis, n);
                }
                halvings += 1;
                if halvings > 4 {
                    return Search::Converged(n);
                }
                delta *= 0.5;
                step *= 0.5;
            }
            if step < STOP_STEP {
                return Search::Converged(n);
            }
        }
        Search::Converged(n)
    }

    /// Newton's method for the maximum of `L` on the great circle normal to `axis`, from the
    /// projection of `n` on it.
    fn newton_circle(&self, axis: DVec3, n: DVec3) -> Option<DVec3> {
        let mut n = (n - axis * n.dot(axis)).try_normalize()?;
        for _ in 0..MAX_NEWTON {
            let e = self.eval(n);
            let (l, w, k1, c1, k2, c2) = (e.lower, e.w(), e.k1, e.c1, e.k2, e.c2);
            if l > 0.0 && !e.smooth {
                return None;
            }
            if l <= 0.0 {
                n = (w - axis * w.dot(axis)).try_normalize()?;
                continue;
            }
            let t = axis.cross(n);
            let g = t.dot(w);
            let (a, b) = (k1.dot(t), k2.dot(t));
            let m = -c1 * a * a - c2 * b * b - l;
            let mut s = -g / m;
            if 0.5 * g * s <= DECREMENT * l {
                return Some(n);
            }
            s = s.clamp(-MAX_STEP, MAX_STEP);
            let next = n + t * s;
            n = (next - axis * next.dot(axis)).normalize();
            if s.abs() < STOP_STEP {
                return Some(n);
            }
        }
        Some(n)
    }

    fn certified(bounds: &Bounds) -> bool {
        bounds.lower > 0.0 && bounds.upper - bounds.lower <= REL_TOL * bounds.upper
    }
}

/// The distance between two cylinders (`c2` along `axis2` at `center2` in `c1`'s frame) with
/// witness points and the normal from 1 to 2, in `c1`'s frame; `dir` is the starting direction
/// (from 1 toward 2). `None` when they overlap, touch, or the certificate fails.
pub(crate) fn cylinder_cylinder(
    c1: &Cylinder,
    c2: &Cylinder,
    axis2: DVec3,
    center2: DVec3,
    dir: DVec3,
) -> Option<Local> {
    let pair = Pair {
        h1: c1.half_height,
        r1: c1.radius,
        h2: c2.half_height,
        r2: c2.radius,
        axis: axis2,
        center: center2,
    };
    let mut bounds = Bounds {
        lower: f64::NEG_INFINITY,
        upper: f64::INFINITY,
        witness: (DVec3::ZERO, DVec3::ZERO),
    };
    // Rim against rim, the commonest case; the search stops at a side's ridge.
    let ridge = match pair.newton_sphere(dir) {
        Search::Converged(n) => {
            pair.try_direction(n, &mut bounds);
            None
        }
        Search::Ridge(axis, n) => Some((axis, n)),
        Search::Failed => None,
    };
    if !Pair::certified(&bounds) {
        // A rim against a side: on the ridge found first.
        let (first, start) = ridge.unwrap_or((DVec3::Y, dir));
        let second = if first == DVec3::Y { axis2 } else { DVec3::Y };
        for (axis, n) in [(first, start), (second, dir)] {
            if let Some(n) = pair.newton_circle(axis, n) {
                pair.try_direction(n, &mut bounds);
            }
            if Pair::certified(&bounds) {
                break;
            }
        }
    }
    if !Pair::certified(&bounds) {
        // A flat end against anything, and side against side.
        let common = DVec3::Y.cross(axis2).try_normalize();
        for n in [Some(DVec3::Y), Some(axis2), common].into_iter().flatten() {
            pair.try_direction(n, &mut bounds);
            pair.try_direction(-n, &mut bounds);
        }
    }
    if !Pair::certified(&bounds) {
        return None;
    }
    let (p, q) = bounds.witness;
    let d = q - p;
    Some((p, q, d / bounds.upper, bounds.upper))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gjk::{Polytope, signed_distance};
    use glam::DQuat;
    use parry3d_f64::math::Pose;

    /// Whether `x` (in the cylinder's frame) is on the surface of the cylinder.
    fn on_surface(c: &Cylinder, x: DVec3) -> bool {
        let rho = (x.x * x.x + x.z * x.z).sqrt();
        let (cap, side) = (x.y.abs() - c.half_height, rho - c.radius);
        (cap.abs() < 1e-9 && side <= 1e-9) || (side.abs() < 1e-9 && cap <= 1e-9)
    }

    /// Wherever the certificate holds, the distance is GJK's (to both tolerances) and the
    /// witnesses are on the surfaces, `distance` apart; most separated pairs are certified.
    #[test]
    fn matches_gjk_with_witnesses_on_the_surfaces() {
        let shapes = [
            Cylinder::new(0.06, 0.09),
            Cylinder::new(0.015, 0.09),
            Cylinder::new(0.14, 0.05),
            Cylinder::new(0.005, 0.045),
        ];
        let mut epa = Polytope::default();
        let (mut certified, mut separated) = (0, 0);
        for k in 0..3000 {
            let f = f64::from(k);
            let pos12 = Pose::from_parts(
                DVec3::new((f * 0.37).sin(), (f * 0.11).cos(), (f * 0.23).sin())
                    * (0.1 + 0.5 * (f * 0.05).sin().abs()),
                DQuat::from_euler(glam::EulerRot::XYZ, f * 0.7, f * 1.3, f * 0.3),
            );
            let (c1, c2) = (&shapes[k as usize % 4], &shapes[(k as usize / 4) % 4]);
            let dir = pos12.translation.normalize();
            let Some(gjk) = signed_distance(&pos12, c1, c2, dir, &mut epa) else {
                continue;
            };
            if gjk.3 <= 0.0 {
                continue;
            }
            separated += 1;
            let axis2 = pos12.rotation * DVec3::Y;
            let Some((p, q, n, d)) = cylinder_cylinder(c1, c2, axis2, pos12.translation, dir)
            else {
                continue;
            };
            certified += 1;
            assert!(
                (d - gjk.3).abs() <= 2.0 * REL_TOL * d,
                "{k}: {d} vs GJK {}",
                gjk.3
            );
            assert!(((q - p).length() - d).abs() < 1e-12 && (n.length() - 1.0).abs() < 1e-12);
            assert!(on_surface(c1, p), "{k}: {p}");
            assert!(on_surface(c2, pos12.inverse_transform_point(q)), "{k}: {q}");
        }
        assert!(
            certified * 10 > separated * 9,
            "{certified} of {separated} separated pairs certified"
        );
    }
}
