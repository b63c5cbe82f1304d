//! The lane kernel of batched RNEA: the one-state sweep of `rnea.rs` over a block of `L`
//! states at a time.

use crate::data::{DynamicsData, sign};
use kinetree_kinematics::JointModel;
use kinetree_kinematics::batch::{block_states, body_transform, gather};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::Motion;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::lanes::{LForce, LMotion, LSe3, LVec3, Lanes, rigid_rnea_force};

/// The per-body lane buffers of RNEA for one lane width.
#[derive(Clone, Debug, Default)]
pub(crate) struct RneaLanes<const L: usize> {
    parent_from_body: Vec<LSe3<L>>,
    velocity: Vec<LMotion<L>>,
    acceleration: Vec<LMotion<L>>,
    force: Vec<LForce<L>>,
    tau: Vec<Lanes<L>>,
}

impl<const L: usize> RneaLanes<L> {
    pub(crate) fn new(model: &Model) -> Self {
        let nb = model.nbodies();
        Self {
            parent_from_body: vec![LSe3::default(); nb],
            velocity: vec![LMotion::ZERO; nb],
            acceleration: vec![LMotion::ZERO; nb],
            force: vec![LForce::ZERO; nb],
            tau: vec![Lanes::ZERO; model.nv()],
        }
    }
}

/// `a × (s·e_K)` (as `cross_unit::<K>`), leaving out the zero component.
#[inline(always)]
fn add_cross_unit<const L: usize>(out: &mut LVec3<L>, k: usize, a: &LVec3<L>, s: Lanes<L>) {
    match k {
        0 => {
            out.y += a.z * s;
            out.z += -a.y * s;
        }
        1 => {
            out.x += -a.z * s;
            out.z += a.x * s;
        }
        _ => {
            out.x += a.y * s;
            out.y += -a.x * s;
        }
    }
}

/// The joint velocity `S·v` of a block of states, lane by lane with the one-state kernel.
#[inline(always)]
fn joint_motion<const L: usize>(
    jm: &JointModel,
    range: core::ops::Range<usize>,
    x: &[f64],
    nv: usize,
    idx: &[usize; L],
) -> LMotion<L> {
    let mut out = LMotion::ZERO;
    for l in 0..L {
        let base = idx[l] * nv;
        out.set_lane(l, &jm.motion(&x[base + range.start..base + range.end]));
    }
    out
}

/// RNEA of the `n` states of `(q, v, a)` into `tau` (inputs checked by the caller), as
/// `rnea::sweep::<true, true>` without external forces.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs, passed through"
)]
pub(crate) fn rnea<const L: usize>(
    bufs: &mut RneaLanes<L>,
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    n: usize,
    tau: &mut [f64],
) {
    let (nq, nv) = (model.nq(), model.nv());
    let bodies = model.bodies();
    let joint_models = data.kinematics.joint_models();
    let a0 = LMotion::splat(&Motion::new(-model.gravity(), DVec3::ZERO));
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        for i in 1..bodies.len() {
            let b = &bodies[i];
            let jm = &joint_models[i];
            let x = body_transform(jm, b, q, nq, &idx);
            bufs.parent_from_body[i] = x;
            let p = b.parent;
            let parent_a = if p == 0 { a0 } else { bufs.acceleration[p] };
            let (vi, ai) = match jm.axis_index() {
                Some((k, revolute)) => {
                    let qd = gather(v, nv, b.idx_v, &idx);
                    let qdd = gather(a, nv, b.idx_v, &idx);
                    let mut ai = x.act_inv_motion(&parent_a);
                    if revolute {
                        *ai.angular.get_mut(k) += qdd;
                    } else {
                        *ai.linear.get_mut(k) += qdd;
                    }
                    let mut vi = LMotion::ZERO;
                    if p != 0 {
                        vi = x.act_inv_motion(&bufs.velocity[p]);
                    }
                    if revolute {
                        *vi.angular.get_mut(k) += qd;
                        add_cross_unit(&mut ai.linear, k, &vi.linear, qd);
                        add_cross_unit(&mut ai.angular, k, &vi.angular, qd);
                    } else {
                        *vi.linear.get_mut(k) += qd;
                        add_cross_unit(&mut ai.linear, k, &vi.angular, qd);
                    }
                    (vi, ai)
                }
                None => {
                    let r = b.idx_v..b.idx_v + b.nv;
                    let mut ai = x.act_inv_motion(&parent_a);
                    ai += joint_motion(jm, r.clone(), a, nv, &idx);
                    let vj = joint_motion(jm, r, v, nv, &idx);
                    let vi = if p == 0 {
                        vj
                    } else {
                        x.act_inv_motion(&bufs.velocity[p]) + vj
                    };
                    ai += vi.cross_motion(&vj);
                    (vi, ai)
                }
            };
            let f = rigid_rnea_force(&b.inertia, &vi, &ai);
            bufs.velocity[i] = vi;
            bufs.acceleration[i] = ai;
            bufs.force[i] = f;
        }
        for i in (1..bodies.len()).rev() {
            let b = &bodies[i];
            let fi = bufs.force[i];
            let jm = &joint_models[i];
            match jm.axis_index() {
                Some((k, true)) => bufs.tau[b.idx_v] = fi.angular.get(k),
                Some((k, false)) => bufs.tau[b.idx_v] = fi.linear.get(k),
                None => {
                    for l in 0..count {
                        let base = (start + l) * nv + b.idx_v;
                        jm.project_force(&fi.lane(l), &mut tau[base..base + b.nv]);
                    }
                }
            }
            if b.parent != 0 {
                let fp = bufs.parent_from_body[i].act_force(&fi);
                bufs.force[b.parent] += fp;
            }
        }
        for i in 1..bodies.len() {
            let b = &bodies[i];
            if joint_models[i].axis_index().is_some() {
                let t = bufs.tau[b.idx_v];
                for l in 0..count {
                    tau[(start + l) * nv + b.idx_v] = t.0[l];
                }
            }
        }
    }
    if data.has_joint_terms {
        for s in 0..n {
            let out = &mut tau[s * nv..(s + 1) * nv];
            let (vs, as_) = (&v[s * nv..(s + 1) * nv], &a[s * nv..(s + 1) * nv]);
            for k in 0..nv {
                let mut t = 0.0;
                t += data.armature[k] * as_[k];
                t += data.damping[k] * vs[k] + data.friction[k] * sign(vs[k]);
                out[k] += t;
            }
        }
    }
}
