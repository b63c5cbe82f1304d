//! One Levenberg–Marquardt iteration of [`IkSolver`](super::IkSolver): evaluating the residual,
//! linearising it, and the damped, box-constrained step (see the solver's module docs).

use super::cholesky::{self, dot};
use super::params::IkParams;
use crate::configuration::{difference_joint, integrate_joint};
use crate::data::KinematicsData;
use crate::joint::sin_cos;
use crate::joint::transform::rotate_about_axis;
use kinetree_model::Model;
use kinetree_model::spatial::explog::so3_left_jacobian_inverse;
use kinetree_model::spatial::rotation::log3;
use kinetree_model::spatial::{Motion, RotationForm, Se3};

use super::scratch::{DofBound, Eval, Workspace};
use glam::DVec3;

/// Bounds of `μ`: below, steps are pure Gauss–Newton; above, the try is stuck.
pub(super) const MU_MIN: f64 = 1e-12;
pub(super) const MU_MAX: f64 = 1e12;

impl Workspace {
    /// Forward kinematics of `q_trial` over the marked bodies, then the residual `r_trial`.
    pub(super) fn evaluate(&mut self, model: &Model, data: &mut KinematicsData) -> Eval {
        let bodies = model.bodies();
        let q = &self.q_trial;
        // Only the world placements are read (the solve ends with a full forward kinematics).
        for p in &self.path {
            let b = &bodies[p.body];
            if p.axis < 3 {
                // A revolute joint about a coordinate axis: the parent's rotation turned by the
                // placement's (in its cheap form), then by the joint's, two columns of three each.
                let (s, c) = sin_cos(q[p.qi]);
                let w = &data.world_from_body[p.parent];
                let placed = match p.place {
                    RotationForm::Identity => w.rotation,
                    RotationForm::Axis { k, s, c } => rotate_about_axis(&w.rotation, k, s, c),
                    RotationForm::General(r) => w.rotation * r,
                };
                let translation = w.rotation * b.placement.translation + w.translation;
                data.world_from_body[p.body] = Se3::new(
                    rotate_about_axis(&placed, usize::from(p.axis), s, c),
                    translation,
                );
            } else {
                let local = data.joint_models[p.body].body_transform(b, q);
                data.world_from_body[p.body] = if p.parent == 0 {
                    local
                } else {
                    data.world_from_body[p.parent] * local
                };
            }
        }
        let (mut e, mut pos2, mut ori2) = (0.0f64, 0.0f64, 0.0f64);
        for t in &mut self.targets[..self.ntargets] {
            let x = data.world_from_body[t.body] * t.body_from_frame;
            let dp = t.rot_t * (x.translation - t.position);
            let phi = log3(&(t.rot_t * x.rotation));
            t.frame_position = x.translation;
            t.phi = phi;
            let c = [dp.x, dp.y, dp.z, phi.x, phi.y, phi.z];
            let (mut p2, mut o2) = (0.0, 0.0);
            let rows = &mut self.r_trial[t.offset..t.offset + t.nrows];
            for (out, &a) in rows.iter_mut().zip(&t.rows[..t.nrows]) {
                let ca = c[a];
                if a < 3 {
                    p2 += ca * ca;
                } else {
                    o2 += ca * ca;
                }
                *out = t.weights[a] * ca;
                e += *out * *out;
            }
            pos2 = pos2.max(p2);
            ori2 = ori2.max(o2);
        }
        Eval {
            e: 0.5 * e,
            pos: pos2.sqrt(),
            ori: ori2.sqrt(),
        }
    }

    /// The weighted residual Jacobian at the current configuration (whose evaluation was the last
    /// one).
    pub(super) fn linearize(&mut self, model: &Model, data: &KinematicsData) {
        let bodies = model.bodies();
        let n = self.dofs.len();
        // Per target, the map from a world angular velocity to d(phi)/dt.
        for t in &mut self.targets[..self.ntargets] {
            t.ang_map = so3_left_jacobian_inverse(t.phi) * t.rot_t;
        }
        for c in 0..n {
            let body = self.dof_body[c];
            let b = &bodies[body];
            let x = &data.world_from_body[body];
            // The column of a joint about or along a coordinate axis is a column of the body's
            // rotation (the general product multiplies by 0 and 1 only).
            let col = match self.dof_kind[c] {
                k @ 0..3 => {
                    let w = x.rotation.col(usize::from(k));
                    Motion::new(x.translation.cross(w), w)
                }
                k @ 3..6 => Motion::new(x.rotation.col(usize::from(k - 3)), DVec3::ZERO),
                _ => x.act_motion(&self.dof_axis[c]),
            };
            for t in &self.targets[..self.ntargets] {
                let rows = t.offset..t.offset + t.nrows;
                if body <= t.body && t.body < b.subtree_end {
                    let v = col.linear + col.angular.cross(t.frame_position);
                    let lin = t.rot_t * v;
                    let ang = t.ang_map * col.angular;
                    let comp = [lin.x, lin.y, lin.z, ang.x, ang.y, ang.z];
                    if t.nrows == 6 {
                        // Every component weighted (the usual full-pose target): rows in order.
                        let col = &mut self.jac[t.offset * n + c..];
                        for (a, (&w, &x)) in t.weights.iter().zip(&comp).enumerate() {
                            col[a * n] = w * x;
                        }
                    } else {
                        for (k, &a) in rows.zip(&t.rows[..t.nrows]) {
                            self.jac[k * n + c] = t.weights[a] * comp[a];
                        }
                    }
                } else {
                    for k in rows {
                        self.jac[k * n + c] = 0.0;
                    }
                }
            }
        }
        // A coupled mimic follower adds its own motion, scaled, to its leader's column.
        for &(body, c, multiplier) in &self.followers {
            let b = &bodies[body];
            let col = data.world_from_body[body]
                .act_motion(&data.joint_models[body].subspace_column(0))
                * multiplier;
            for t in &self.targets[..self.ntargets] {
                if body <= t.body && t.body < b.subtree_end {
                    let v = col.linear + col.angular.cross(t.frame_position);
                    let lin = t.rot_t * v;
                    let ang = t.ang_map * col.angular;
                    let comp = [lin.x, lin.y, lin.z, ang.x, ang.y, ang.z];
                    for (k, &a) in (t.offset..t.offset + t.nrows).zip(&t.rows[..t.nrows]) {
                        self.jac[k * n + c] += t.weights[a] * comp[a];
                    }
                }
            }
        }
    }
}

/// Clamps the bounded moving coordinates of `q` into their limits.
pub(super) fn clamp_moving(bounds: &[DofBound], dofs: &[usize], q: &mut [f64]) {
    for &d in dofs {
        let b = &bounds[d];
        if b.is_bounded() {
            q[b.q] = q[b.q].clamp(b.lower, b.upper);
        }
    }
}

/// Whether the bounded moving coordinates of `q` are within their limits.
pub(super) fn within_limits(bounds: &[DofBound], dofs: &[usize], q: &[f64]) -> bool {
    dofs.iter().all(|&d| {
        let b = &bounds[d];
        q[b.q] >= b.lower && q[b.q] <= b.upper || !b.is_bounded()
    })
}

/// Computes the step at the current configuration for damping `lambda` and writes
/// `q_trial = clamp(q ⊕ dq)`. Returns the decrease of `½|r|²` the linear model predicts, or
/// `None` when the system is not numerically positive definite.
pub(super) fn step(
    ws: &mut Workspace,
    model: &Model,
    bounds: &[DofBound],
    params: &IkParams,
    lambda: f64,
    posture: Option<(&[f64], f64)>,
) -> Option<f64> {
    let n = ws.dofs.len();
    let bodies = model.bodies();
    // The posture step z, on the moving coordinates.
    ws.z[..n].fill(0.0);
    if let Some((qp, gain)) = posture {
        for &b in &ws.moving {
            let body = &bodies[b];
            let (qs, vs) = (
                body.idx_q..body.idx_q + body.nq,
                body.idx_v..body.idx_v + body.nv,
            );
            difference_joint(body.kind, &ws.q[qs.clone()], &qp[qs], &mut ws.dv[vs]);
        }
        for c in 0..n {
            ws.z[c] = gain * ws.dv[ws.dofs[c]];
        }
    }
    // Active set: freeze coordinates at a limit whose step points outwards.
    let m = ws.m;
    let jac = &ws.jac[..m * n];
    // Start from the coordinates at a limit that steepest descent (-Jᵀr) pushes outwards; the
    // loop below frees none of them and rarely has to freeze more.
    for c in 0..n {
        let b = &bounds[ws.dofs[c]];
        let x = ws.q[b.q];
        ws.fixed[c] = b.is_bounded() && (x <= b.lower || x >= b.upper) && {
            let descent: f64 = -(0..m).map(|k| jac[k * n + c] * ws.r[k]).sum::<f64>();
            (x <= b.lower && descent < 0.0) || (x >= b.upper && descent > 0.0)
        };
        if ws.fixed[c] {
            ws.z[c] = 0.0;
        }
    }
    for _round in 0..=n {
        ws.free.clear();
        for c in 0..n {
            if !ws.fixed[c] {
                ws.free.push(c);
            }
        }
        let f = ws.free.len();
        // w = -r - J z, and J_F: the free columns of J, packed (J itself when all are free).
        for k in 0..m {
            let row = &jac[k * n..(k + 1) * n];
            ws.w[k] = -ws.r[k]
                - if posture.is_some() {
                    dot(row, &ws.z[..n])
                } else {
                    0.0
                };
            if f < n {
                let packed = &mut ws.jf[k * f..(k + 1) * f];
                for (o, &c) in packed.iter_mut().zip(&ws.free) {
                    *o = row[c];
                }
            }
        }
        let jf = if f == n { jac } else { &ws.jf[..m * f] };
        // δ_F = (J_FᵀJ_F + λI)⁻¹ J_Fᵀ w = J_Fᵀ (J_F J_Fᵀ + λI)⁻¹ w: factor whichever is smaller.
        ws.step[..n].copy_from_slice(&ws.z[..n]);
        if m < f {
            let a = &mut ws.chol[..m * m];
            if !cholesky::normal_rows(jf, m, a) {
                for k in 0..m {
                    let rk = &jf[k * f..(k + 1) * f];
                    for l in 0..=k {
                        a[k * m + l] = dot(rk, &jf[l * f..(l + 1) * f]);
                    }
                }
            }
            for k in 0..m {
                a[k * m + k] += lambda;
            }
            if !cholesky::factor(a, m, &mut ws.inv_diag[..m]) {
                return None;
            }
            ws.y[..m].copy_from_slice(&ws.w[..m]);
            cholesky::solve(a, m, &ws.inv_diag[..m], &mut ws.y[..m]);
            for k in 0..m {
                let yk = ws.y[k];
                for (&c, jkc) in ws.free.iter().zip(&jf[k * f..(k + 1) * f]) {
                    ws.step[c] += jkc * yk;
                }
            }
        } else {
            let a = &mut ws.chol[..f * f];
            if !cholesky::normal_cols(jf, m, &ws.w[..m], a, &mut ws.rhs[..f]) {
                a.fill(0.0);
                ws.rhs[..f].fill(0.0);
                // Sums of one outer product per row: independent accumulators that vectorise.
                for k in 0..m {
                    let row = &jf[k * f..(k + 1) * f];
                    let wk = ws.w[k];
                    for (ra, x) in ws.rhs[..f].iter_mut().zip(row) {
                        *ra += x * wk;
                    }
                    for (i, &x) in row.iter().enumerate() {
                        if x != 0.0 {
                            for (aij, y) in a[i * f..i * f + i + 1].iter_mut().zip(row) {
                                *aij += x * y;
                            }
                        }
                    }
                }
            }
            for i in 0..f {
                a[i * f + i] += lambda;
            }
            if !cholesky::factor(a, f, &mut ws.inv_diag[..f]) {
                return None;
            }
            cholesky::solve(a, f, &ws.inv_diag[..f], &mut ws.rhs[..f]);
            for (&c, x) in ws.free.iter().zip(&ws.rhs[..f]) {
                ws.step[c] += x;
            }
        }
        let mut again = false;
        for &i in &ws.free {
            let b = &bounds[ws.dofs[i]];
            if b.is_bounded() {
                let x = ws.q[b.q];
                if (x <= b.lower && ws.step[i] < 0.0) || (x >= b.upper && ws.step[i] > 0.0) {
                    ws.fixed[i] = true;
                    ws.z[i] = 0.0;
                    again = true;
                }
            }
        }
        if !again {
            break;
        }
    }
    for c in 0..n {
        if ws.fixed[c] {
            ws.step[c] = 0.0;
        }
    }
    let largest = ws.step[..n].iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if largest > params.max_step {
        let s = params.max_step / largest;
        for x in &mut ws.step[..n] {
            *x *= s;
        }
    }
    // q_trial = clamp(q ⊕ dq), and the step actually taken (projection included).
    ws.q_trial.copy_from_slice(&ws.q);
    if ws.additive {
        for ((&qi, &d), x) in ws.dof_q.iter().zip(&ws.dofs).zip(&mut ws.step[..n]) {
            let b = &bounds[d];
            let moved = ws.q[qi] + *x;
            if b.is_bounded() {
                let clamped = moved.clamp(b.lower, b.upper);
                ws.q_trial[qi] = clamped;
                *x = clamped - ws.q[qi];
            } else {
                ws.q_trial[qi] = moved;
            }
        }
        return Some(predicted_decrease(jac, &ws.r[..m], &ws.step[..n]));
    }
    for c in 0..n {
        ws.dv[ws.dofs[c]] = ws.step[c];
    }
    for &b in &ws.moving {
        let body = &bodies[b];
        let (qs, vs) = (
            body.idx_q..body.idx_q + body.nq,
            body.idx_v..body.idx_v + body.nv,
        );
        integrate_joint(
            body.kind,
            &ws.q[qs.clone()],
            &ws.dv[vs],
            &mut ws.q_trial[qs],
        );
    }
    // The step actually taken (projection included), and the decrease the model predicts.
    for c in 0..n {
        let b = &bounds[ws.dofs[c]];
        if b.is_bounded() {
            let x = ws.q_trial[b.q].clamp(b.lower, b.upper);
            ws.q_trial[b.q] = x;
            ws.step[c] = x - ws.q[b.q];
        }
    }
    Some(predicted_decrease(jac, &ws.r[..m], &ws.step[..n]))
}

/// The decrease of `½|r|²` the linear model predicts for step `d`: `-(rᵀJd + ½|Jd|²)`.
#[inline]
fn predicted_decrease(jac: &[f64], r: &[f64], d: &[f64]) -> f64 {
    let n = d.len();
    let mut predicted = 0.0;
    for (k, rk) in r.iter().enumerate() {
        let jd = dot(&jac[k * n..(k + 1) * n], d);
        predicted -= rk * jd + 0.5 * jd * jd;
    }
    predicted
}
