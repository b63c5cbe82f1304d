//! The lane kernel of batched RNEA: the one-state sweep of `rnea.rs` over a block of `L`
//! states at a time.

use super::crba::project_force;
use crate::data::{DynamicsData, sign};
use crate::rnea::turns_about;
use kinetree_kinematics::JointModel;
use kinetree_kinematics::batch::{Io, block_states, body_transform_in_lanes, suspect_lanes};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::Motion;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::lanes::{
    LForce, LMotion, LSe3, LVec3, LaneVec, Lanes, rigid_rnea_force,
};

/// The per-body lane buffers of RNEA for one lane width.
#[derive(Clone, Debug, Default)]
pub(crate) struct RneaLanes<const L: usize> {
    /// The block's `q`, `v` and `a` in lanes (`Io::load_coordinates`; lengths rounded up to 8).
    q: Vec<Lanes<L>>,
    v: Vec<Lanes<L>>,
    a: Vec<Lanes<L>>,
    parent_from_body: LaneVec<LSe3<L>>,
    velocity: LaneVec<LMotion<L>>,
    acceleration: LaneVec<LMotion<L>>,
    force: LaneVec<LForce<L>>,
    /// The block's torques, `nv` rounded up to 8 (`Io::store_coordinates`).
    tau: Vec<Lanes<L>>,
    /// Per body, the coordinate axis a revolute joint turns about when its placement does not
    /// rotate or rotates about the same axis (`rnea::turns_about`), else 3.
    turn: Vec<u8>,
}

impl<const L: usize> RneaLanes<L> {
    pub(crate) fn new(model: &Model, data: &DynamicsData) -> Self {
        let nb = model.nbodies();
        let joint_models = data.kinematics.joint_models();
        let turn = (0..nb)
            .map(|i| match joint_models[i].axis_index() {
                Some((k, true)) if i > 0 && turns_about(&data.placement_rot[i], k) => k as u8,
                _ => 3,
            })
            .collect();
        let nq8 = model.nq().next_multiple_of(8);
        let nv8 = model.nv().next_multiple_of(8);
        Self {
            q: vec![Lanes::ZERO; nq8],
            v: vec![Lanes::ZERO; nv8],
            a: vec![Lanes::ZERO; nv8],
            parent_from_body: LaneVec::new(LSe3::default(), nb),
            velocity: LaneVec::new(LMotion::ZERO, nb),
            acceleration: LaneVec::new(LMotion::ZERO, nb),
            force: LaneVec::new(LForce::ZERO, nb),
            tau: vec![Lanes::ZERO; nv8],
            turn,
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

/// `Rᵀ·u` for a rotation `r` about coordinate axis `K` only (as `AxisTurn::inverse_rotate` of
/// `rnea.rs`: the products by its 0 and 1 entries left out).
#[inline(always)]
fn turn_inverse_rotate<const L: usize, const K: usize>(
    r: &kinetree_kinematics::spatial::lanes::LMat3<L>,
    u: &LVec3<L>,
) -> LVec3<L> {
    match K {
        0 => LVec3 {
            x: u.x,
            y: r.y_axis.y * u.y + r.y_axis.z * u.z,
            z: r.z_axis.y * u.y + r.z_axis.z * u.z,
        },
        1 => LVec3 {
            x: r.x_axis.x * u.x + r.x_axis.z * u.z,
            y: u.y,
            z: r.z_axis.x * u.x + r.z_axis.z * u.z,
        },
        _ => LVec3 {
            x: r.x_axis.x * u.x + r.x_axis.y * u.y,
            y: r.y_axis.x * u.x + r.y_axis.y * u.y,
            z: u.z,
        },
    }
}

/// `R·u` for a rotation `r` about coordinate axis `K` only (as `AxisTurn::rotate`).
#[inline(always)]
fn turn_rotate<const L: usize, const K: usize>(
    r: &kinetree_kinematics::spatial::lanes::LMat3<L>,
    u: &LVec3<L>,
) -> LVec3<L> {
    match K {
        0 => LVec3 {
            x: u.x,
            y: r.y_axis.y * u.y + r.z_axis.y * u.z,
            z: r.y_axis.z * u.y + r.z_axis.z * u.z,
        },
        1 => LVec3 {
            x: r.x_axis.x * u.x + r.z_axis.x * u.z,
            y: u.y,
            z: r.x_axis.z * u.x + r.z_axis.z * u.z,
        },
        _ => LVec3 {
            x: r.x_axis.x * u.x + r.y_axis.x * u.y,
            y: r.x_axis.y * u.x + r.y_axis.y * u.y,
            z: u.z,
        },
    }
}

/// `x.act_inv_motion(m)` for a transform whose rotation turns about axis `K` only (as
/// `AxisTurn::act_inv_motion`).
#[inline(always)]
fn turn_act_inv_motion<const L: usize, const K: usize>(x: &LSe3<L>, m: &LMotion<L>) -> LMotion<L> {
    LMotion {
        linear: turn_inverse_rotate::<L, K>(
            &x.rotation,
            &(m.linear - x.translation.cross(&m.angular)),
        ),
        angular: turn_inverse_rotate::<L, K>(&x.rotation, &m.angular),
    }
}

/// `x.act_force(f)` for a transform whose rotation turns about axis `K` only (as
/// `AxisTurn::act_force`).
#[inline(always)]
fn turn_act_force<const L: usize, const K: usize>(x: &LSe3<L>, f: &LForce<L>) -> LForce<L> {
    let lin = turn_rotate::<L, K>(&x.rotation, &f.linear);
    LForce {
        linear: lin,
        angular: turn_rotate::<L, K>(&x.rotation, &f.angular) + x.translation.cross(&lin),
    }
}

/// `x.act_inv_motion(m)`, through [`turn_act_inv_motion`] for `T` < 3.
#[inline(always)]
fn inv_motion<const L: usize, const T: u8>(x: &LSe3<L>, m: &LMotion<L>) -> LMotion<L> {
    match T {
        0 => turn_act_inv_motion::<L, 0>(x, m),
        1 => turn_act_inv_motion::<L, 1>(x, m),
        2 => turn_act_inv_motion::<L, 2>(x, m),
        _ => x.act_inv_motion(m),
    }
}

/// The velocity and acceleration of a body whose joint is revolute about (`revolute`) or
/// prismatic along coordinate axis `k`, as `rnea::body::<true, true, K, REV, _>`, from its
/// placement `x` (whose rotation turns about axis `T` only, for `T` < 3).
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "one body's inputs, as rnea::body takes them"
)]
fn axis_body<const L: usize, const T: u8, const K: usize, const REV: bool>(
    x: &LSe3<L>,
    has_parent: bool,
    parent_v: &LMotion<L>,
    parent_a: &LMotion<L>,
    qd: Lanes<L>,
    qdd: Lanes<L>,
) -> (LMotion<L>, LMotion<L>) {
    let mut ai = inv_motion::<L, T>(x, parent_a);
    if REV {
        *ai.angular.get_mut(K) += qdd;
    } else {
        *ai.linear.get_mut(K) += qdd;
    }
    let mut vi = LMotion::ZERO;
    if has_parent {
        vi = inv_motion::<L, T>(x, parent_v);
    }
    if REV {
        *vi.angular.get_mut(K) += qd;
        add_cross_unit(&mut ai.linear, K, &vi.linear, qd);
        add_cross_unit(&mut ai.angular, K, &vi.angular, qd);
    } else {
        *vi.linear.get_mut(K) += qd;
        add_cross_unit(&mut ai.linear, K, &vi.angular, qd);
    }
    (vi, ai)
}

/// [`axis_body`] for the joint's axis `k` and kind (`revolute`) known only at run time: one
/// branch per axis and kind, so that each body's arithmetic has its axis as a constant.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "one body's inputs, as rnea::body takes them"
)]
fn axis_body_of<const L: usize, const T: u8>(
    x: &LSe3<L>,
    k: usize,
    revolute: bool,
    has_parent: bool,
    parent_v: &LMotion<L>,
    parent_a: &LMotion<L>,
    qd: Lanes<L>,
    qdd: Lanes<L>,
) -> (LMotion<L>, LMotion<L>) {
    let (hp, pv, pa) = (has_parent, parent_v, parent_a);
    match (k, revolute) {
        (0, true) => axis_body::<L, T, 0, true>(x, hp, pv, pa, qd, qdd),
        (1, true) => axis_body::<L, T, 1, true>(x, hp, pv, pa, qd, qdd),
        (_, true) => axis_body::<L, T, 2, true>(x, hp, pv, pa, qd, qdd),
        (0, false) => axis_body::<L, T, 0, false>(x, hp, pv, pa, qd, qdd),
        (1, false) => axis_body::<L, T, 1, false>(x, hp, pv, pa, qd, qdd),
        (_, false) => axis_body::<L, T, 2, false>(x, hp, pv, pa, qd, qdd),
    }
}

/// The joint velocity `S·v` of a block of states (`v` in lanes), as [`JointModel::motion`] does
/// it lane by lane (the same products and sums in the same order): single-axis joints along a
/// general axis (panda's fingers), cylindrical, spherical, planar and free joints in lane
/// vectors; the axis-aligned kinds are handled by the callers.
#[inline(always)]
fn joint_motion<const L: usize>(
    jm: &JointModel,
    range: core::ops::Range<usize>,
    lanes: &[Lanes<L>],
) -> LMotion<L> {
    let x = &lanes[range];
    let axis = |a: DVec3, s: Lanes<L>| LVec3::splat(a).scale(s);
    let vec = |x: Lanes<L>, y: Lanes<L>, z: Lanes<L>| LVec3 { x, y, z };
    let motion = |linear, angular| LMotion { linear, angular };
    match *jm {
        JointModel::Revolute(a) => motion(LVec3::ZERO, axis(a, x[0])),
        JointModel::Prismatic(a) => motion(axis(a, x[0]), LVec3::ZERO),
        JointModel::Cylindrical(a) => motion(axis(a, x[0]), axis(a, x[1])),
        JointModel::Spherical => motion(LVec3::ZERO, vec(x[0], x[1], x[2])),
        JointModel::Planar { u, w, n } => motion(axis(u, x[0]) + axis(w, x[1]), axis(n, x[2])),
        JointModel::Floating => motion(vec(x[0], x[1], x[2]), vec(x[3], x[4], x[5])),
        _ => {
            let mut out = LMotion::ZERO;
            let mut state = [0.0; 6];
            for l in 0..L {
                for (s, x) in state.iter_mut().zip(x) {
                    *s = x.0[l];
                }
                out.set_lane(l, &jm.motion(&state[..x.len()]));
            }
            out
        }
    }
}

/// `*dst = *src`, one lane vector at a time. A whole-struct assignment of a transform held in a
/// local compiles to a call of `memcpy` (768 bytes with 8 lanes, after a `vzeroupper`), which
/// took about 8 % of a batched panda RNEA; twelve vector copies do not.
#[inline(always)]
pub(crate) fn copy_se3<const L: usize>(dst: &mut LSe3<L>, src: &LSe3<L>) {
    let copy = |d: &mut LVec3<L>, s: &LVec3<L>| {
        d.x = s.x;
        d.y = s.y;
        d.z = s.z;
    };
    copy(&mut dst.rotation.x_axis, &src.rotation.x_axis);
    copy(&mut dst.rotation.y_axis, &src.rotation.y_axis);
    copy(&mut dst.rotation.z_axis, &src.rotation.z_axis);
    copy(&mut dst.translation, &src.translation);
}

/// The first of the `count` lanes (states from `start`) whose probe is not 0.
#[inline(always)]
fn first_flagged<const L: usize>(probe: Lanes<L>, start: usize, count: usize) -> Option<usize> {
    (0..count).find(|&k| probe.0[k] != 0.0).map(|k| start + k)
}

/// What a batched RNEA sweep found: the first state whose inputs the one-state function may
/// refuse (to be checked by it), and the first state with a torque that is not finite.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Flagged {
    pub(crate) suspect: Option<usize>,
    pub(crate) not_finite: Option<usize>,
}

/// RNEA of the `n` states of `(q, v, a)` into `tau` (buffer lengths checked by the caller), as
/// `rnea::sweep::<true, true>` without external forces. The states' inputs are checked in the
/// lanes: finiteness by a probe, quaternions by their sums of squares ([`suspect_lanes`]); a
/// state flagged there is reported for the one-state check to decide.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs, passed through"
)]
#[allow(
    clippy::too_many_lines,
    reason = "the two sweeps of one algorithm, as in rnea.rs"
)]
pub(crate) fn rnea<const L: usize>(
    bufs: &mut RneaLanes<L>,
    io: Io,
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    n: usize,
    tau: &mut [f64],
) -> Flagged {
    let (nq, nv) = (model.nq(), model.nv());
    let bodies = model.bodies();
    let joint_models = data.kinematics.joint_models();
    let a0 = LMotion::splat(&Motion::new(-model.gravity(), DVec3::ZERO));
    let mut flagged = Flagged::default();
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        let finite = io.load_coordinates(q, nq, &idx, &mut bufs.q)
            + io.load_coordinates(v, nv, &idx, &mut bufs.v)
            + io.load_coordinates(a, nv, &idx, &mut bufs.a);
        if flagged.suspect.is_none() {
            flagged.suspect = first_flagged(suspect_lanes(model, &bufs.q, finite), start, count);
        }
        for i in 1..bodies.len() {
            let b = &bodies[i];
            let jm = &joint_models[i];
            let x = body_transform_in_lanes(jm, b, &bufs.q, q, nq, &idx);
            copy_se3(&mut bufs.parent_from_body[i], &x);
            let p = b.parent;
            let parent_a = if p == 0 { a0 } else { bufs.acceleration[p] };
            let (vi, ai) = match jm.axis_index() {
                Some((k, revolute)) => {
                    let (qd, qdd) = (bufs.v[b.idx_v], bufs.a[b.idx_v]);
                    let parent_v = if p == 0 {
                        LMotion::ZERO
                    } else {
                        bufs.velocity[p]
                    };
                    let (pv, pa) = (&parent_v, &parent_a);
                    let (t, hp) = (bufs.turn[i], p != 0);
                    match t {
                        0 => axis_body_of::<L, 0>(&x, k, revolute, hp, pv, pa, qd, qdd),
                        1 => axis_body_of::<L, 1>(&x, k, revolute, hp, pv, pa, qd, qdd),
                        2 => axis_body_of::<L, 2>(&x, k, revolute, hp, pv, pa, qd, qdd),
                        _ => axis_body_of::<L, 3>(&x, k, revolute, hp, pv, pa, qd, qdd),
                    }
                }
                None => {
                    let r = b.idx_v..b.idx_v + b.nv;
                    let mut ai = x.act_inv_motion(&parent_a);
                    ai += joint_motion(jm, r.clone(), &bufs.a);
                    let vj = joint_motion(jm, r, &bufs.v);
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
                    let mut out = [Lanes::ZERO; 6];
                    project_force(jm, &fi, &mut out);
                    bufs.tau[b.idx_v..b.idx_v + b.nv].copy_from_slice(&out[..b.nv]);
                }
            }
            if b.parent != 0 {
                let x = &bufs.parent_from_body[i];
                let fp = match bufs.turn[i] {
                    0 => turn_act_force::<L, 0>(x, &fi),
                    1 => turn_act_force::<L, 1>(x, &fi),
                    2 => turn_act_force::<L, 2>(x, &fi),
                    _ => x.act_force(&fi),
                };
                bufs.force[b.parent] += fp;
            }
        }
        if data.has_joint_terms {
            // As the one-state sweep: `t = 0 + r·a`, `t += d·v + μ·sign(v)`, `τ += t`.
            for k in 0..nv {
                let (vk, ak) = (bufs.v[k], bufs.a[k]);
                let mut t = Lanes::ZERO;
                t += ak * data.armature[k];
                t += vk * data.damping[k] + vk.map(sign) * data.friction[k];
                bufs.tau[k] += t;
            }
        }
        if flagged.not_finite.is_none() {
            let mut probe = Lanes::ZERO;
            for t in &bufs.tau[..nv] {
                probe += *t * 0.0;
            }
            flagged.not_finite = first_flagged(probe, start, count);
        }
        io.store_coordinates(&bufs.tau, nv, tau, start, nv, count);
    }
    flagged
}
