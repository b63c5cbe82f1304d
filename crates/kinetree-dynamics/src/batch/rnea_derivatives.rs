//! The lane kernel of the batched inverse-dynamics derivatives: the one-state sweeps of
//! `derivatives/rnea.rs` (`sweep::<true>` without external forces) over a block of `L` states at
//! a time, every operation in the one-state order.

use crate::derivatives::DerivativesData;
use kinetree_kinematics::JointModel;
use kinetree_kinematics::batch::{body_transform, gather};
use kinetree_kinematics::model::{Body, Model};
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::lanes::{LForce, LMat3, LMotion, LSe3, LVec3, LaneVec, Lanes};
use kinetree_kinematics::spatial::real::{Matrix3 as _, Vector3 as _};
use kinetree_kinematics::spatial::{Inertia, Motion};

/// `a + b`, entry by entry.
#[inline(always)]
pub(crate) fn mat_add<const L: usize>(a: &LMat3<L>, b: &LMat3<L>) -> LMat3<L> {
    LMat3 {
        x_axis: a.x_axis + b.x_axis,
        y_axis: a.y_axis + b.y_axis,
        z_axis: a.z_axis + b.z_axis,
    }
}

/// `a - b`, entry by entry.
#[inline(always)]
pub(crate) fn mat_sub<const L: usize>(a: &LMat3<L>, b: &LMat3<L>) -> LMat3<L> {
    LMat3 {
        x_axis: a.x_axis - b.x_axis,
        y_axis: a.y_axis - b.y_axis,
        z_axis: a.z_axis - b.z_axis,
    }
}

/// The skew matrix `[x]×` (as `derivatives::data::skew`).
#[inline(always)]
pub(crate) fn skew<const L: usize>(x: &LVec3<L>) -> LMat3<L> {
    let z = Lanes::ZERO;
    LMat3 {
        x_axis: LVec3 {
            x: z,
            y: x.z,
            z: -x.y,
        },
        y_axis: LVec3 {
            x: -x.z,
            y: z,
            z: x.x,
        },
        z_axis: LVec3 { x: x.y, y: -x.x, z },
    }
}

/// A spatial inertia about the world origin in lanes (the lane form of
/// `derivatives::data::WorldInertia`); the mass is the same in every lane.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LWorldInertia<const L: usize> {
    pub(crate) m: f64,
    pub(crate) h: LVec3<L>,
    pub(crate) i: LMat3<L>,
}

impl<const L: usize> LWorldInertia<L> {
    /// The momentum `Y·s` (as `WorldInertia::mul`).
    #[inline(always)]
    pub(crate) fn mul(&self, s: &LMotion<L>) -> LForce<L> {
        LForce {
            linear: s.linear.scale_by(self.m) - self.h.cross(&s.angular),
            angular: self.h.cross(&s.linear) + self.i.mul_vec(&s.angular),
        }
    }

    #[inline(always)]
    fn add_assign(&mut self, o: &Self) {
        self.m += o.m;
        self.h += o.h;
        self.i = mat_add(&self.i, &o.i);
    }

    /// The body's inertia `inertia` (in its own frame) about the world origin, for the body
    /// placement `omi` (as `forward_velocity` builds it).
    #[inline(always)]
    fn of_body(inertia: &Inertia, omi: &LSe3<L>) -> Self {
        let r = &omi.rotation;
        // `Inertia::transformed`: the centre of mass placed, the rotational inertia rotated
        // (`Symmetric3::rotate`).
        let c = r.mul_const_vec(inertia.com) + omi.translation;
        let s = &inertia.rotational;
        let m0 = r.mul_const_vec(s.column(0));
        let m1 = r.mul_const_vec(s.column(1));
        let m2 = r.mul_const_vec(s.column(2));
        let entry = |i: usize, j: usize| {
            m0.get(i) * r.x_axis.get(j) + m1.get(i) * r.y_axis.get(j) + m2.get(i) * r.z_axis.get(j)
        };
        let (xx, xy, xz, yy, yz, zz) = (
            entry(0, 0),
            entry(0, 1),
            entry(0, 2),
            entry(1, 1),
            entry(1, 2),
            entry(2, 2),
        );
        let rot = LMat3 {
            x_axis: LVec3 {
                x: xx,
                y: xy,
                z: xz,
            },
            y_axis: LVec3 {
                x: xy,
                y: yy,
                z: yz,
            },
            z_axis: LVec3 {
                x: xz,
                y: yz,
                z: zz,
            },
        };
        let mass = inertia.mass;
        let l2 = c.dot(&c);
        let z = Lanes::ZERO;
        let diagonal = LMat3 {
            x_axis: LVec3 { x: l2, y: z, z },
            y_axis: LVec3 { x: z, y: l2, z },
            z_axis: LVec3 { x: z, y: z, z: l2 },
        };
        let outer = LMat3 {
            x_axis: c.scale(c.x),
            y_axis: c.scale(c.y),
            z_axis: c.scale(c.z),
        };
        let parallel = mat_sub(&diagonal, &outer);
        let parallel = LMat3 {
            x_axis: parallel.x_axis.scale_by(mass),
            y_axis: parallel.y_axis.scale_by(mass),
            z_axis: parallel.z_axis.scale_by(mass),
        };
        Self {
            m: mass,
            h: c.scale_by(mass),
            i: mat_add(&rot, &parallel),
        }
    }
}

/// `B·w` for the inertia-variation operator `B = [[0, -2[p]×], [0, d]]` (as
/// `derivatives::rnea::variation_mul`).
#[inline(always)]
fn variation_mul<const L: usize>(p: &LVec3<L>, d: &LMat3<L>, w: &LMotion<L>) -> LForce<L> {
    LForce {
        linear: p.cross(&w.angular).scale_by(-2.0),
        angular: d.mul_vec(&w.angular),
    }
}

/// `Bᵀ·s` for the same operator (as `derivatives::rnea::variation_transpose`; its linear part
/// is zero).
#[inline(always)]
fn variation_transpose<const L: usize>(p: &LVec3<L>, d: &LMat3<L>, s: &LMotion<L>) -> LForce<L> {
    LForce {
        linear: LVec3::ZERO,
        angular: p.cross(&s.linear).scale_by(2.0) + d.transpose_mul_vec(&s.angular),
    }
}

/// `[w]× · m` as `DMat3` computes it, without the products by the skew matrix's zeros (each
/// dropped term is a zero added to a sum: the values are the full product's, zeros' signs aside).
#[inline(always)]
fn skew_mul<const L: usize>(w: &LVec3<L>, m: &LMat3<L>) -> LMat3<L> {
    // Column j: [w]×'s columns (0, z, -y), (-z, 0, x), (y, -x, 0) times m's column j.
    let col = |c: &LVec3<L>| LVec3 {
        x: -w.z * c.y + w.y * c.z,
        y: w.z * c.x + -w.x * c.z,
        z: -w.y * c.x + w.x * c.y,
    };
    LMat3 {
        x_axis: col(&m.x_axis),
        y_axis: col(&m.y_axis),
        z_axis: col(&m.z_axis),
    }
}

/// `m · [w]×` as `DMat3` computes it, without the products by the skew matrix's zeros (as
/// [`skew_mul`]).
#[inline(always)]
fn mul_skew<const L: usize>(m: &LMat3<L>, w: &LVec3<L>) -> LMat3<L> {
    let (a, b, c) = (&m.x_axis, &m.y_axis, &m.z_axis);
    LMat3 {
        x_axis: b.scale(w.z) + c.scale(-w.y),
        y_axis: a.scale(-w.z) + c.scale(w.x),
        z_axis: a.scale(w.y) + b.scale(-w.x),
    }
}

/// The angular-angular block of a body's inertia variation (as
/// `derivatives::rnea::variation_block`, its products by the skew matrices' zeros left out).
#[inline(always)]
fn variation_block<const L: usize>(
    y: &LWorldInertia<L>,
    v: &LMotion<L>,
    h: &LForce<L>,
) -> LMat3<L> {
    let (vl, vw) = (&v.linear, &v.angular);
    let hx = skew(&y.h);
    let a = mat_sub(&skew_mul(vw, &y.i), &mul_skew(&y.i, vw));
    let b = mat_add(&skew_mul(vl, &hx), &mul_skew(&hx, vl));
    mat_sub(&mat_sub(&a, &b), &skew(&h.angular))
}

/// The per-body and per-degree-of-freedom lane buffers of the inverse-dynamics derivatives for
/// one lane width (the matrices go to a [`Sink`]).
#[derive(Clone, Debug, Default)]
pub(crate) struct RneaDerivativesLanes<const L: usize> {
    pub(crate) world_from_body: LaneVec<LSe3<L>>,
    pub(crate) velocity: LaneVec<LMotion<L>>,
    pub(crate) acceleration: LaneVec<LMotion<L>>,
    pub(crate) force: LaneVec<LForce<L>>,
    pub(crate) composite: LaneVec<LWorldInertia<L>>,
    pub(crate) momentum: LaneVec<LVec3<L>>,
    pub(crate) variation: LaneVec<LMat3<L>>,
    pub(crate) s: LaneVec<LMotion<L>>,
    pub(crate) dv_dq: LaneVec<LMotion<L>>,
    pub(crate) da_dq: LaneVec<LMotion<L>>,
    pub(crate) da_dv: LaneVec<LMotion<L>>,
    pub(crate) df_dq: LaneVec<LForce<L>>,
    pub(crate) df_dv: LaneVec<LForce<L>>,
    pub(crate) df_da: LaneVec<LForce<L>>,
    pub(crate) tau: Vec<Lanes<L>>,
}

/// Where the backward sweep puts the matrices' entries that can be nonzero: entry `(r, c)` of
/// `∂τ/∂q`, `∂τ/∂v` and `∂τ/∂a` for every lane of the block. Every other entry is zero.
pub(crate) trait Sink<const L: usize> {
    /// Stores entry `(r, c)` of the three matrices.
    fn put(&mut self, r: usize, c: usize, dq: Lanes<L>, dv: Lanes<L>, da: Lanes<L>);
}

/// A [`Sink`] writing straight into the callers' stacked `nv x nv` matrices (no lane matrices:
/// on large trees those outgrew the L2 cache), and a finiteness probe of everything written.
pub(crate) struct OutputSink<'a, const L: usize> {
    /// Each lane's state's first entry in the outputs.
    pub(crate) base: [usize; L],
    pub(crate) nv: usize,
    pub(crate) dq: &'a mut [f64],
    pub(crate) dv: &'a mut [f64],
    pub(crate) da: &'a mut [f64],
    /// `Σ x · 0` over the entries: zero in a lane exactly when its entries are finite.
    pub(crate) probe: Lanes<L>,
}

impl<const L: usize> Sink<L> for OutputSink<'_, L> {
    #[inline(always)]
    fn put(&mut self, r: usize, c: usize, dq: Lanes<L>, dv: Lanes<L>, da: Lanes<L>) {
        self.probe += dq * 0.0 + dv * 0.0 + da * 0.0;
        let at = r * self.nv + c;
        for l in 0..L {
            // Lanes past the batch repeat its last state: they write the same values again.
            let o = self.base[l] + at;
            self.dq[o] = dq.0[l];
            self.dv[o] = dv.0[l];
            self.da[o] = da.0[l];
        }
    }
}

/// A [`Sink`] writing into the block's three matrices in lanes (`∂τ/∂q`, `∂τ/∂v`, `∂τ/∂a`,
/// each `nv x nv` from a multiple of `half`); the caller probes them for finiteness once the
/// sweep is done (a probe per entry, carried from one entry to the next, cost more than the
/// loop over the whole buffer).
pub(crate) struct LaneSink<'a, const L: usize> {
    pub(crate) matrices: &'a mut [Lanes<L>],
    pub(crate) half: usize,
    pub(crate) nv: usize,
}

impl<const L: usize> Sink<L> for LaneSink<'_, L> {
    #[inline(always)]
    fn put(&mut self, r: usize, c: usize, dq: Lanes<L>, dv: Lanes<L>, da: Lanes<L>) {
        let at = r * self.nv + c;
        self.matrices[at] = dq;
        self.matrices[at + self.half] = dv;
        self.matrices[at + 2 * self.half] = da;
    }
}

impl<const L: usize> RneaDerivativesLanes<L> {
    pub(crate) fn new(model: &Model) -> Self {
        let (nb, nv) = (model.nbodies(), model.nv());
        let m = |n| LaneVec::new(LMotion::zero(), n);
        let f = |n| LaneVec::new(LForce::zero(), n);
        let x = |n| vec![Lanes::ZERO; n];
        Self {
            world_from_body: LaneVec::new(LSe3::default(), nb),
            velocity: m(nb),
            acceleration: m(nb),
            force: f(nb),
            composite: LaneVec::new(LWorldInertia::default(), nb),
            momentum: LaneVec::new(LVec3::ZERO, nb),
            variation: LaneVec::new(LMat3::default(), nb),
            s: m(nv),
            dv_dq: m(nv),
            da_dq: m(nv),
            da_dv: m(nv),
            df_dq: f(nv),
            df_dv: f(nv),
            df_da: f(nv),
            tau: x(nv),
        }
    }
}

/// The forward sweep of one block (`idx`): placements, velocities, accelerations, the bodies'
/// forces and inertias, and the per-column derivatives of velocity and acceleration (as
/// `forward_velocity` then `forward_acceleration`, body by body: each body's quantities depend
/// only on its ancestors', so the one-state results are reproduced).
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs, passed through"
)]
fn forward<const L: usize>(
    bufs: &mut RneaDerivativesLanes<L>,
    model: &Model,
    data: &DerivativesData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    idx: &[usize; L],
) {
    let nv = model.nv();
    let a0 = LMotion::splat(&Motion::new(-model.gravity(), DVec3::ZERO));
    for i in 1..model.bodies().len() {
        let b = &model.bodies()[i];
        let (bias, force) = velocity_body(bufs, model, data, q, v, idx, i);
        // `sweep` and `forward_acceleration`.
        let ap = if b.parent == 0 {
            a0
        } else {
            bufs.acceleration[b.parent]
        };
        let mut ai = ap + bias;
        for d in b.idx_v..b.idx_v + b.nv {
            ai += bufs.s[d].scale(gather(a, nv, d, idx));
        }
        acceleration_body(bufs, b, i, ap, ai, force);
    }
}

/// The forward sweep's part that does not depend on the acceleration, for body `i` (its
/// ancestors done): as `forward_velocity`, the placement, velocity, inertia, momentum,
/// variation and the columns `s`, `∂v/∂q`, `∂a/∂v` stored; the velocity-product bias and the
/// bias force `v × (Y·v)` returned.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs, passed through"
)]
pub(crate) fn velocity_body<const L: usize>(
    bufs: &mut RneaDerivativesLanes<L>,
    model: &Model,
    data: &DerivativesData,
    q: &[f64],
    v: &[f64],
    idx: &[usize; L],
    i: usize,
) -> (LMotion<L>, LForce<L>) {
    let (nq, nv) = (model.nq(), model.nv());
    let b = &model.bodies()[i];
    let jm: &JointModel = &data.dynamics.kinematics.joint_models()[i];
    let x = body_transform(jm, b, q, nq, idx);
    let p = b.parent;
    let (omi, vp) = if p == 0 {
        (x, LMotion::zero())
    } else {
        (bufs.world_from_body[p].compose(&x), bufs.velocity[p])
    };
    bufs.world_from_body[i] = omi;
    let mut vj = LMotion::zero();
    for k in 0..b.nv {
        let d = b.idx_v + k;
        let s = jm.act_column(&omi, k);
        bufs.s[d] = s;
        vj += s.scale(gather(v, nv, d, idx));
        bufs.dv_dq[d] = vp.cross_motion(&s);
    }
    let vi = vp + vj;
    for d in b.idx_v..b.idx_v + b.nv {
        bufs.da_dv[d] = vi.cross_motion(&bufs.s[d]) + bufs.dv_dq[d];
    }
    let y = LWorldInertia::of_body(&b.inertia, &omi);
    let h = y.mul(&vi);
    bufs.velocity[i] = vi;
    let bias = vp.cross_motion(&vj);
    let force = vi.cross_force(&h);
    bufs.momentum[i] = h.linear;
    bufs.variation[i] = variation_block(&y, &vi, &h);
    bufs.composite[i] = y;
    (bias, force)
}

/// The forward sweep's rest for body `i` (`b`) with parent acceleration `ap` and acceleration
/// `ai` (gravity included), as `forward_acceleration`: the columns `∂a/∂q`, the acceleration,
/// and the body's force (`force`, its bias force, plus `Y·ai`).
#[inline(always)]
pub(crate) fn acceleration_body<const L: usize>(
    bufs: &mut RneaDerivativesLanes<L>,
    b: &Body,
    i: usize,
    ap: LMotion<L>,
    ai: LMotion<L>,
    force: LForce<L>,
) {
    let vp = if b.parent == 0 {
        LMotion::zero()
    } else {
        bufs.velocity[b.parent]
    };
    for d in b.idx_v..b.idx_v + b.nv {
        bufs.da_dq[d] = ap.cross_motion(&bufs.s[d]) + vp.cross_motion(&bufs.dv_dq[d]);
    }
    bufs.acceleration[i] = ai;
    bufs.force[i] = force + bufs.composite[i].mul(&ai);
}

/// The backward sweep of one block (as `backward::<true>` without external forces and without
/// the finiteness bound): `τ` into `bufs`, and the three matrices' entries that can be nonzero
/// into `sink`.
#[inline(always)]
pub(crate) fn backward<const L: usize>(
    bufs: &mut RneaDerivativesLanes<L>,
    model: &Model,
    data: &DerivativesData,
    sink: &mut impl Sink<L>,
) {
    let bodies = model.bodies();
    for i in (1..bodies.len()).rev() {
        let b = &bodies[i];
        let (f, y, pm, dm) = (
            bufs.force[i],
            bufs.composite[i],
            bufs.momentum[i],
            bufs.variation[i],
        );
        let r0 = b.idx_v;
        let r1 = r0 + b.nv;
        let c1 = r0 + data.nv_subtree[i];
        for d in r0..r1 {
            let s = bufs.s[d];
            bufs.tau[d] = s.dot(&f);
            bufs.df_dq[d] = y.mul(&bufs.da_dq[d]) + variation_mul(&pm, &dm, &bufs.dv_dq[d]);
            bufs.df_da[d] = y.mul(&s);
            bufs.df_dv[d] = y.mul(&bufs.da_dv[d]) + variation_mul(&pm, &dm, &s);
        }
        // Rows of this joint, columns of its subtree (itself included).
        for r in r0..r1 {
            let s = bufs.s[r];
            for c in r0..c1 {
                let dq = s.dot(&bufs.df_dq[c]);
                let dv = s.dot(&bufs.df_dv[c]);
                let da = s.dot(&bufs.df_da[c]);
                sink.put(r, c, dq, dv, da);
            }
        }
        for d in r0..r1 {
            bufs.df_dq[d] = bufs.df_dq[d] + bufs.s[d].cross_force(&f);
        }
        // Rows of this joint, columns of its strict ancestors.
        let ancestors = if b.nv > 0 {
            data.tree.ancestors(r0)
        } else {
            &[]
        };
        if !ancestors.is_empty() {
            for r in r0..r1 {
                let s = bufs.s[r];
                // `Y·s`, as `df_da[r]` holds it.
                let ys = bufs.df_da[r];
                // `Bᵀ·s` has no linear part: its products are left out of the dots below.
                let bs = variation_transpose(&pm, &dm, &s);
                for &j in ancestors {
                    let sj = &bufs.s[j];
                    let dq = bufs.da_dq[j].dot(&ys) + bufs.dv_dq[j].angular.dot(&bs.angular);
                    let dv = bufs.da_dv[j].dot(&ys) + sj.angular.dot(&bs.angular);
                    let da = sj.dot(&ys);
                    sink.put(r, j, dq, dv, da);
                }
            }
        }
        let p = b.parent;
        if p != 0 {
            bufs.force[p] += f;
            let mut yp = bufs.composite[p];
            yp.add_assign(&y);
            bufs.composite[p] = yp;
            bufs.momentum[p] += pm;
            bufs.variation[p] = mat_add(&bufs.variation[p], &dm);
        }
    }
}

/// The inverse-dynamics derivatives of the block of states `idx` of `(q, v, a)` (inputs
/// checked by the caller): `τ` into the lane buffer `tau`, the matrices into `sink`.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs, passed through"
)]
pub(crate) fn rnea_derivatives<const L: usize>(
    bufs: &mut RneaDerivativesLanes<L>,
    model: &Model,
    data: &DerivativesData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    idx: &[usize; L],
    sink: &mut impl Sink<L>,
) {
    forward(bufs, model, data, q, v, a, idx);
    backward(bufs, model, data, sink);
}
