//! The lane kernel of the batched forward-dynamics derivatives: the one-state sweeps of
//! `derivatives/aba.rs` (without external forces) over a block of `L` states at a time, every
//! operation in the one-state order, then each state's tree-sparse solves (the one-state code:
//! they already run on whole rows in SIMD).

use super::lane_solve::LaneSolve;
use super::rnea_derivatives::{
    LWorldInertia, RneaDerivativesLanes, Sink, acceleration_body, backward, mat_add, mat_sub, skew,
    velocity_body,
};
use crate::data::sign;
use crate::derivatives::DerivativesData;
use crate::factor::PIVOT_TOLERANCE;
use kinetree_kinematics::batch::{Io, gather};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::Motion;
use kinetree_kinematics::spatial::glam::DVec3;
use kinetree_kinematics::spatial::lanes::{LForce, LMat3, LMotion, LVec3, LaneVec, Lanes};
use kinetree_kinematics::spatial::real::{Matrix3 as _, Vector3 as _};

/// A symmetric 6x6 inertia in world coordinates in lanes, in 3x3 blocks `[[a, b], [bᵀ, c]]`
/// (the lane form of `derivatives::data::Articulated`, its arithmetic in the same order).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LArticulated<const L: usize> {
    a: LMat3<L>,
    b: LMat3<L>,
    c: LMat3<L>,
}

/// The outer product `p·qᵀ` (as `DMat3::from_cols(p * q.x, p * q.y, p * q.z)`).
#[inline(always)]
fn outer<const L: usize>(p: &LVec3<L>, q: &LVec3<L>) -> LMat3<L> {
    LMat3 {
        x_axis: p.scale(q.x),
        y_axis: p.scale(q.y),
        z_axis: p.scale(q.z),
    }
}

impl<const L: usize> LArticulated<L> {
    /// `self += y` for a rigid inertia `y` (as `Articulated::add_rigid`, the diagonal matrix's
    /// zeros added too).
    #[inline(always)]
    fn add_rigid(&mut self, y: &LWorldInertia<L>) {
        let z = 0.0;
        let m = y.m;
        let diagonal = |x: f64, y: f64, zz: f64| LVec3 {
            x: Lanes::splat(x),
            y: Lanes::splat(y),
            z: Lanes::splat(zz),
        };
        self.a = mat_add(
            &self.a,
            &LMat3 {
                x_axis: diagonal(m, z, z),
                y_axis: diagonal(z, m, z),
                z_axis: diagonal(z, z, m),
            },
        );
        self.b = mat_sub(&self.b, &skew(&y.h));
        self.c = mat_add(&self.c, &y.i);
    }

    /// The momentum `self·s` (as `Articulated::mul`).
    #[inline(always)]
    fn mul(&self, s: &LMotion<L>) -> LForce<L> {
        let (v, w) = (&s.linear, &s.angular);
        LForce {
            linear: self.a.mul_vec(v) + self.b.mul_vec(w),
            angular: self.b.transpose_mul_vec(v) + self.c.mul_vec(w),
        }
    }

    /// `self -= x·yᵀ` (as `Articulated::sub_outer`).
    #[inline(always)]
    fn sub_outer(&mut self, x: &LForce<L>, y: &LForce<L>) {
        self.a = mat_sub(&self.a, &outer(&x.linear, &y.linear));
        self.b = mat_sub(&self.b, &outer(&x.linear, &y.angular));
        self.c = mat_sub(&self.c, &outer(&x.angular, &y.angular));
    }

    #[inline(always)]
    fn add_assign(&mut self, o: &Self) {
        self.a = mat_add(&self.a, &o.a);
        self.b = mat_add(&self.b, &o.b);
        self.c = mat_add(&self.c, &o.c);
    }

    /// The traces of the diagonal blocks (as `Articulated::scale`).
    #[inline(always)]
    fn scale(&self) -> Lanes<L> {
        let (a, c) = (&self.a, &self.c);
        (a.x_axis.x + a.y_axis.y + a.z_axis.z).map(f64::abs)
            + (c.x_axis.x + c.y_axis.y + c.z_axis.z).map(f64::abs)
    }
}

/// The lane buffers of the forward-dynamics derivatives for one lane width (beside the
/// inverse-dynamics ones), and each lane's factor and pair for the solves.
#[derive(Clone, Debug, Default)]
pub(crate) struct AbaDerivativesLanes<const L: usize> {
    bias: LaneVec<LMotion<L>>,
    articulated: LaneVec<LArticulated<L>>,
    articulated_force: LaneVec<LForce<L>>,
    u_column: LaneVec<LForce<L>>,
    pivot_inverse: Vec<Lanes<L>>,
    u: Vec<Lanes<L>>,
    pub(crate) ddq: Vec<Lanes<L>>,
    /// Each lane's factor, pair and `M⁻¹` for the solves.
    solve: LaneSolve<L>,
    /// The entries of the pair that the sweep does not write (row and column of two degrees of
    /// freedom neither of which supports the other, in both halves): the solve of the previous
    /// block left them nonzero.
    unrelated: Vec<usize>,
}

impl<const L: usize> AbaDerivativesLanes<L> {
    pub(crate) fn new(model: &Model, data: &DerivativesData) -> Self {
        let (nb, nv) = (model.nbodies(), model.nv());
        let x = |n| vec![Lanes::ZERO; n];
        let tree = &data.tree;
        let solve = LaneSolve::new(tree.clone(), nv);
        let half = solve.half;
        let supports = |a: usize, b: usize| a == b || tree.ancestors(b).contains(&a);
        let unrelated = (0..nv * nv)
            .filter(|&k| !supports(k / nv, k % nv) && !supports(k % nv, k / nv))
            .flat_map(|k| [k, k + half])
            .collect();
        Self {
            bias: LaneVec::new(LMotion::zero(), nb),
            articulated: LaneVec::new(LArticulated::default(), nb),
            articulated_force: LaneVec::new(LForce::zero(), nb),
            u_column: LaneVec::new(LForce::zero(), nv),
            pivot_inverse: x(nv),
            u: x(nv),
            ddq: x(nv),
            solve,
            unrelated,
        }
    }
}

/// A [`Sink`] putting `∂τ/∂q` and `∂τ/∂v` into the pair of the solves (`∂τ/∂a` is not needed).
struct PairSink<'a, const L: usize> {
    /// `∂τ/∂q` (`nv x nv`), and from `half` on `∂τ/∂v`.
    pair: &'a mut [Lanes<L>],
    half: usize,
    nv: usize,
}

impl<const L: usize> Sink<L> for PairSink<'_, L> {
    #[inline(always)]
    fn put(&mut self, r: usize, c: usize, dq: Lanes<L>, dv: Lanes<L>, _: Lanes<L>) {
        let at = r * self.nv + c;
        self.pair[at] = dq;
        self.pair[at + self.half] = dv;
    }
}

/// The articulated-body pass of one block (as `derivatives::aba::articulated`): the pivots and
/// `L`'s entries into each lane's factor, `U`, `1/D` and `u` into the buffers. A lane whose
/// pivot vanishes is marked in the returned mask (its inverse pivot is zero, as one state).
#[inline(always)]
fn articulated<const L: usize>(
    bufs: &mut AbaDerivativesLanes<L>,
    rnea: &RneaDerivativesLanes<L>,
    model: &Model,
    data: &DerivativesData,
    v: &[f64],
    tau: &[f64],
    idx: &[usize; L],
) -> [bool; L] {
    let nv = model.nv();
    let bodies = model.bodies();
    let dynamics = &data.dynamics;
    let tree = &data.tree;
    let factor = &mut bufs.solve.factor;
    let mut singular = [false; L];
    bufs.articulated.fill(LArticulated::default());
    bufs.articulated_force.fill(LForce::zero());
    for i in (1..bodies.len()).rev() {
        let b = &bodies[i];
        let mut ia = bufs.articulated[i];
        ia.add_rigid(&rnea.composite[i]);
        let mut pa = bufs.articulated_force[i] + rnea.force[i];
        for d in (b.idx_v..b.idx_v + b.nv).rev() {
            let s = rnea.s[d];
            let u_col = ia.mul(&s);
            let mut pivot = s.dot(&u_col);
            let mut u = gather(tau, nv, d, idx) - s.dot(&pa);
            if dynamics.has_joint_terms {
                let vd = gather(v, nv, d, idx);
                pivot = pivot + dynamics.armature[d];
                u -= vd * dynamics.damping[d] + vd.map(sign) * dynamics.friction[d];
            }
            let bound = ia.scale() * PIVOT_TOLERANCE;
            let mut inverse = Lanes::ZERO;
            for l in 0..L {
                if pivot.0[l] > bound.0[l] {
                    inverse.0[l] = 1.0 / pivot.0[l];
                } else {
                    singular[l] = true;
                }
            }
            factor[d * nv + d] = pivot;
            for &j in tree.ancestors(d) {
                factor[d * nv + j] = rnea.s[j].dot(&u_col) * inverse;
            }
            bufs.u_column[d] = u_col;
            bufs.pivot_inverse[d] = inverse;
            bufs.u[d] = u;
            ia.sub_outer(&u_col, &u_col.scale(inverse));
            pa += u_col.scale(inverse * u);
        }
        let p = b.parent;
        if p != 0 {
            pa += ia.mul(&bufs.bias[i]);
            bufs.articulated[p].add_assign(&ia);
            bufs.articulated_force[p] += pa;
        }
    }
    singular
}

/// The forward-dynamics derivatives of the block of states `idx` of `(q, v, tau)` (inputs
/// checked by the caller; the first `count` are consecutive, the rest repeat the last): `q̈` into
/// `bufs.ddq`, and for lane `l < count` the matrices of state `idx[l]` into `dq`, `dv` and
/// `dtau` (stacked `nv x nv`, moved out of the lanes by `io`). The lanes whose pivot vanished
/// are marked in the returned mask (their matrices are not to be trusted).
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs and outputs, passed through"
)]
pub(crate) fn aba_derivatives<const L: usize>(
    rnea: &mut RneaDerivativesLanes<L>,
    bufs: &mut AbaDerivativesLanes<L>,
    model: &Model,
    data: &DerivativesData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    idx: &[usize; L],
    count: usize,
    io: Io,
    out: [&mut [f64]; 3],
) -> [bool; L] {
    let nv = model.nv();
    let bodies = model.bodies();
    for i in 1..bodies.len() {
        let (bias, force) = velocity_body(rnea, model, data, q, v, idx, i);
        bufs.bias[i] = bias;
        rnea.force[i] = force;
    }
    let singular = articulated(bufs, rnea, model, data, v, tau, idx);
    // Forward: q̈, and with it the accelerations and forces of the derivatives.
    let a0 = LMotion::splat(&Motion::new(-model.gravity(), DVec3::ZERO));
    for i in 1..bodies.len() {
        let b = &bodies[i];
        let ap = if b.parent == 0 {
            a0
        } else {
            rnea.acceleration[b.parent]
        };
        let mut ai = ap + bufs.bias[i];
        for d in b.idx_v..b.idx_v + b.nv {
            let qdd = bufs.pivot_inverse[d] * (bufs.u[d] - ai.dot(&bufs.u_column[d]));
            bufs.ddq[d] = qdd;
            ai += rnea.s[d].scale(qdd);
        }
        let force = rnea.force[i];
        acceleration_body(rnea, b, i, ap, ai, force);
    }
    let solve = &mut bufs.solve;
    // The entries the sweep does not write are zero (the last block's solve overwrote them).
    for &k in &bufs.unrelated {
        solve.pair[k] = Lanes::ZERO;
    }
    let mut sink = PairSink {
        pair: &mut solve.pair[..],
        half: solve.half,
        nv,
    };
    backward(rnea, model, data, &mut sink);
    let dynamics = &data.dynamics;
    if dynamics.has_joint_terms {
        // As `backward::<true>`: the damping on the diagonal of `∂τ/∂v`.
        for (k, damping) in dynamics.damping.iter().enumerate() {
            let x = &mut solve.pair[solve.half + k * nv + k];
            *x = *x + *damping;
        }
    }
    solve.invert();
    solve.neg_solve();
    solve.store(io, idx[0], count, out);
    singular
}
