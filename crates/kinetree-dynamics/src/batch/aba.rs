//! The lane kernel of batched ABA: the three sweeps of `aba.rs` (world-frame articulated-body
//! inertias) over a block of `L` states at a time, with the one-state arithmetic in the same
//! order, so every lane is the one-state result bit for bit.

use super::articulated::{LArticulated, LRigid};
use crate::aba::PIVOT_TOLERANCE;
use crate::data::{DynamicsData, sign};
use kinetree_kinematics::JointModel;
use kinetree_kinematics::batch::{Io, block_states, body_transform_in_lanes};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::Motion;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::lanes::{LForce, LMotion, LSe3, LVec3, LaneVec, Lanes};
use kinetree_kinematics::spatial::real::{Matrix3 as _, Vector3 as _};

/// The per-body and per-coordinate lane buffers of ABA for one lane width.
#[derive(Clone, Debug, Default)]
pub(crate) struct AbaLanes<const L: usize> {
    /// The block's `q`, `v` and `tau` in lanes, and its accelerations before they are written
    /// out (`Io::load_coordinates`, `Io::store_coordinates`; lengths rounded up to 8).
    q: Vec<Lanes<L>>,
    v: Vec<Lanes<L>>,
    tau: Vec<Lanes<L>>,
    ddq: Vec<Lanes<L>>,
    world_from_body: LaneVec<LSe3<L>>,
    velocity: LaneVec<LMotion<L>>,
    bias: LaneVec<LMotion<L>>,
    articulated: LaneVec<LArticulated<L>>,
    force: LaneVec<LForce<L>>,
    acceleration: LaneVec<LMotion<L>>,
    subspace: LaneVec<LMotion<L>>,
    u_columns: LaneVec<LForce<L>>,
    u: Vec<Lanes<L>>,
    dinv: Vec<Lanes<L>>,
}

impl<const L: usize> AbaLanes<L> {
    pub(crate) fn new(model: &Model, data: &DynamicsData) -> Self {
        let (nb, nv) = (model.nbodies(), model.nv());
        let (nq8, nv8) = (model.nq().next_multiple_of(8), nv.next_multiple_of(8));
        Self {
            q: vec![Lanes::ZERO; nq8],
            v: vec![Lanes::ZERO; nv8],
            tau: vec![Lanes::ZERO; nv8],
            ddq: vec![Lanes::ZERO; nv8],
            world_from_body: LaneVec::new(LSe3::default(), nb),
            velocity: LaneVec::new(LMotion::zero(), nb),
            bias: LaneVec::new(LMotion::zero(), nb),
            articulated: LaneVec::new(LArticulated::default(), nb),
            force: LaneVec::new(LForce::zero(), nb),
            acceleration: LaneVec::new(LMotion::zero(), nb),
            subspace: LaneVec::new(LMotion::zero(), nv),
            u_columns: LaneVec::new(LForce::zero(), nv),
            u: vec![Lanes::ZERO; nv],
            dinv: vec![Lanes::ZERO; data.dinv.len()],
        }
    }
}

/// The world-frame subspace column `k` of body `i`'s joint moved by `x` (as `x.act_motion` of
/// the constant column; for the axis-aligned joints the column of `x`'s rotation, which skips
/// only products by 0 and 1).
#[inline(always)]
fn world_column<const L: usize>(jm: &JointModel, x: &LSe3<L>, k: usize) -> LMotion<L> {
    match jm.axis_index() {
        Some((a, true)) => {
            let axis = x.rotation.col(a);
            LMotion {
                linear: x.translation.cross(&axis),
                angular: axis,
            }
        }
        Some((a, false)) => LMotion {
            linear: x.rotation.col(a),
            angular: LVec3::ZERO,
        },
        None => x.act_motion(&LMotion::splat(&jm.subspace_column(k))),
    }
}

/// As `invert_spd` of `aba.rs` in every lane: the inverse of the symmetric `n x n` block `d`
/// into `out` (row-major); a lane whose pivot is `≤ tolerance` (or NaN) is marked in `bad`.
#[inline(always)]
fn invert_spd<const L: usize>(
    d: &[[Lanes<L>; 6]; 6],
    n: usize,
    tolerance: Lanes<L>,
    out: &mut [Lanes<L>],
    bad: &mut [bool; L],
) {
    let mut lo = [[Lanes::ZERO; 6]; 6];
    for j in 0..n {
        let mut s = d[j][j];
        for k in 0..j {
            s -= lo[j][k] * lo[j][k];
        }
        for l in 0..L {
            if s.0[l].is_nan() || s.0[l] <= tolerance.0[l] {
                bad[l] = true;
            }
        }
        let ljj = s.map(f64::sqrt);
        lo[j][j] = ljj;
        for i in j + 1..n {
            let mut s = d[i][j];
            for k in 0..j {
                s -= lo[i][k] * lo[j][k];
            }
            lo[i][j] = div(s, ljj);
        }
    }
    for c in 0..n {
        let mut y = [Lanes::ZERO; 6];
        for i in 0..n {
            let mut s = Lanes::splat(if i == c { 1.0 } else { 0.0 });
            for k in 0..i {
                s -= lo[i][k] * y[k];
            }
            y[i] = div(s, lo[i][i]);
        }
        for i in (0..n).rev() {
            let mut s = y[i];
            for k in i + 1..n {
                s -= lo[k][i] * y[k];
            }
            y[i] = div(s, lo[i][i]);
        }
        for i in 0..n {
            out[i * n + c] = y[i];
        }
    }
}

/// `a / b` lane by lane.
#[inline(always)]
fn div<const L: usize>(a: Lanes<L>, b: Lanes<L>) -> Lanes<L> {
    let mut out = a.0;
    for l in 0..L {
        out[l] /= b.0[l];
    }
    Lanes(out)
}

/// ABA of the `n` states of `(q, v, tau)` into `ddq` (inputs checked by the caller), as
/// `aba::compute` without external forces. A state whose pivot vanishes gets NaN accelerations,
/// for the caller to ask the one-state function for its error.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs, passed through"
)]
#[allow(
    clippy::too_many_lines,
    reason = "the three sweeps of one algorithm, as in aba.rs"
)]
pub(crate) fn aba<const L: usize>(
    bufs: &mut AbaLanes<L>,
    io: Io,
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    n: usize,
    ddq: &mut [f64],
) {
    let (nq, nv) = (model.nq(), model.nv());
    let bodies = model.bodies();
    let nb = bodies.len();
    let joint_models = data.kinematics.joint_models();
    let a0 = LMotion::splat(&Motion::new(-model.gravity(), DVec3::ZERO));
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        // The inputs were checked by the caller: the finiteness probes are not needed.
        let _ = io.load_coordinates(q, nq, &idx, &mut bufs.q);
        let _ = io.load_coordinates(v, nv, &idx, &mut bufs.v);
        let _ = io.load_coordinates(tau, nv, &idx, &mut bufs.tau);
        // Pass 1, root to leaves: placements, velocities, bias accelerations, inertias and bias
        // forces in the world frame.
        for i in 1..nb {
            let b = &bodies[i];
            let jm = &joint_models[i];
            let x = body_transform_in_lanes(jm, b, &bufs.q, q, nq, &idx);
            let p = b.parent;
            let world = if p == 0 {
                x
            } else {
                bufs.world_from_body[p].compose(&x)
            };
            bufs.world_from_body[i] = world;
            let mut vj = LMotion::zero();
            for k in 0..b.nv {
                let s = world_column(jm, &world, k);
                bufs.subspace[b.idx_v + k] = s;
                vj += s.scale(bufs.v[b.idx_v + k]);
            }
            let (vi, ci) = if p == 0 {
                (vj, LMotion::zero())
            } else {
                let vp = bufs.velocity[p];
                (vp + vj, vp.cross_motion(&vj))
            };
            bufs.velocity[i] = vi;
            bufs.bias[i] = ci;
            let inertia = LRigid::transformed(&b.inertia, &world.rotation, &world.translation);
            bufs.articulated[i] = LArticulated::from_rigid(&inertia);
            bufs.force[i] = vi.cross_force(&inertia.mul_motion(&vi));
        }
        // Pass 2, leaves to root: articulated inertias and bias forces.
        let mut bad = [false; L];
        for i in (1..nb).rev() {
            let b = &bodies[i];
            let (iv, ni) = (b.idx_v, b.nv);
            let ia = bufs.articulated[i];
            let pa = bufs.force[i];
            let off = data.dinv_offset[i];
            let tolerance = ia.scale() * PIVOT_TOLERANCE;
            if ni == 1 {
                let s = bufs.subspace[iv];
                let u_col = ia.mul_motion(&s);
                bufs.u_columns[iv] = u_col;
                let mut d = s.dot(&u_col);
                let mut u = bufs.tau[iv] - s.dot(&pa);
                if data.has_joint_terms {
                    let vk = bufs.v[iv];
                    d += Lanes::splat(data.armature[iv]);
                    u -= vk * data.damping[iv] + vk.map(sign) * data.friction[iv];
                }
                let mut dinv = [0.0; L];
                for l in 0..L {
                    if d.0[l] > tolerance.0[l] {
                        dinv[l] = 1.0 / d.0[l];
                    } else {
                        bad[l] = true;
                    }
                }
                let dinv = Lanes(dinv);
                bufs.dinv[off] = dinv;
                bufs.u[iv] = u;
                if b.parent != 0 {
                    let mut ia = ia;
                    ia.sub_outer(&u_col, &u_col.scale(dinv));
                    let pa = pa + ia.mul_motion(&bufs.bias[i]) + u_col.scale(dinv * u);
                    bufs.articulated[b.parent].add_assign(&ia);
                    bufs.force[b.parent] += pa;
                }
            } else {
                let mut d = [[Lanes::ZERO; 6]; 6];
                for k in 0..ni {
                    let s = bufs.subspace[iv + k];
                    let u_col = ia.mul_motion(&s);
                    bufs.u_columns[iv + k] = u_col;
                    let mut u = bufs.tau[iv + k] - s.dot(&pa);
                    if data.has_joint_terms {
                        let vk = bufs.v[iv + k];
                        d[k][k] += Lanes::splat(data.armature[iv + k]);
                        u -= vk * data.damping[iv + k] + vk.map(sign) * data.friction[iv + k];
                    }
                    bufs.u[iv + k] = u;
                }
                for k in 0..ni {
                    for l in 0..=k {
                        let x = bufs.subspace[iv + l].dot(&bufs.u_columns[iv + k]);
                        d[k][l] += x;
                        if l != k {
                            d[l][k] = d[k][l];
                        }
                    }
                }
                let dinv = &mut bufs.dinv[off..off + ni * ni];
                invert_spd(&d, ni, tolerance, dinv, &mut bad);
                if b.parent != 0 {
                    let mut ia = ia;
                    let mut pa = pa;
                    for k in 0..ni {
                        let mut w = LForce::zero();
                        let mut du = Lanes::ZERO;
                        for l in 0..ni {
                            w += bufs.u_columns[iv + l].scale(dinv[k * ni + l]);
                            du += dinv[k * ni + l] * bufs.u[iv + l];
                        }
                        ia.sub_outer(&bufs.u_columns[iv + k], &w);
                        pa += bufs.u_columns[iv + k].scale(du);
                    }
                    let pa = pa + ia.mul_motion(&bufs.bias[i]);
                    bufs.articulated[b.parent].add_assign(&ia);
                    bufs.force[b.parent] += pa;
                }
            }
        }
        // Pass 3, root to leaves: accelerations, written straight to `ddq`.
        for i in 1..nb {
            let b = &bodies[i];
            let (iv, ni) = (b.idx_v, b.nv);
            let p = b.parent;
            let mut ai = if p == 0 { a0 } else { bufs.acceleration[p] } + bufs.bias[i];
            let off = data.dinv_offset[i];
            if ni == 1 {
                let u_col = bufs.u_columns[iv];
                let qdd = bufs.dinv[off] * (bufs.u[iv] - ai.dot(&u_col));
                bufs.ddq[iv] = qdd;
                ai += bufs.subspace[iv].scale(qdd);
            } else {
                let mut r = [Lanes::ZERO; 6];
                for k in 0..ni {
                    r[k] = bufs.u[iv + k] - ai.dot(&bufs.u_columns[iv + k]);
                }
                let mut da = LMotion::zero();
                for k in 0..ni {
                    let mut qdd = Lanes::ZERO;
                    for l in 0..ni {
                        qdd += bufs.dinv[off + k * ni + l] * r[l];
                    }
                    bufs.ddq[iv + k] = qdd;
                    da += bufs.subspace[iv + k].scale(qdd);
                }
                ai += da;
            }
            bufs.acceleration[i] = ai;
        }
        io.store_coordinates(&bufs.ddq, nv, ddq, start, nv, count);
        for (l, &bad) in bad.iter().enumerate().take(count) {
            if bad {
                let s = start + l;
                ddq[s * nv..(s + 1) * nv].fill(f64::NAN);
            }
        }
    }
}
