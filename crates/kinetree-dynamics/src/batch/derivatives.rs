//! The batched analytic derivatives: [`DerivativesBatch`], [`rnea_derivatives_batch`] and
//! [`aba_derivatives_batch`].

use super::aba_derivatives::{AbaDerivativesLanes, aba_derivatives};
use super::rnea_derivatives::{LaneSink, OutputSink, RneaDerivativesLanes, rnea_derivatives};
use super::{check_aba_states, check_buffer, check_rnea_states, in_state, states, states_pass};
use crate::data::{JointTerms, sign};
use crate::derivatives::DerivativesData;
use crate::error::DynamicsError;
use kinetree_kinematics::batch::{Io, Simd, block_states};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::lanes::Lanes;

/// The buffers of the batched analytic derivatives for one [`Model`] (see the
/// [module](super) docs for the layout of a batch).
///
/// Create it once per model (and per thread); [`rnea_derivatives_batch`] and
/// [`aba_derivatives_batch`] allocate nothing afterwards.
#[derive(Clone, Debug)]
pub struct DerivativesBatch {
    simd: Simd,
    /// One-state data: the joint models and terms, the tree's structure, the model check, and
    /// the error of a bad state.
    data: DerivativesData,
    lanes4: DerivativesLanes<4>,
    lanes8: DerivativesLanes<8>,
}

/// The lane buffers of the batched derivatives for one lane width.
#[derive(Clone, Debug, Default)]
struct DerivativesLanes<const L: usize> {
    rnea: RneaDerivativesLanes<L>,
    aba: AbaDerivativesLanes<L>,
    /// Up to [`RNEA_LANES_OUT_MAX_NV`], the block's three inverse-dynamics matrices in lanes
    /// (`∂τ/∂q`, `∂τ/∂v`, `∂τ/∂a`, each `nv x nv` from a multiple of 8), moved to the outputs
    /// by the transposes; empty above it. Only the kernel's `LaneSink` writes into it, always the
    /// same entries, so the others keep their zeros from allocation.
    matrices: Vec<Lanes<L>>,
}

/// The largest `nv` whose inverse-dynamics derivatives are assembled in lane matrices and
/// leave them through the transposes; above it each entry goes straight to its state's place.
/// The lane matrices must be zeroed and moved out whole, so they pay only where most entries
/// are nonzero (N = 1024, AVX-512, one thread, min of 4 alternating rounds, ns/state: panda
/// 596 → 561, ur5 330 → 322, solo12 (nv = 18) 1357 → 1269; but talos_reduced (nv = 38) 4402 →
/// 5265 and talos_full_v2 (nv = 50) 7605 → 8144, whose matrices are mostly zeros).
const RNEA_LANES_OUT_MAX_NV: usize = 24;

/// The largest `nv` whose forward-dynamics derivatives run in lanes. With the solves in lanes
/// too, the lane kernel was faster than one state at a time at every size measured (N = 1024,
/// AVX-512, one thread: 3.4× at nv = 6, 2.7× at nv = 9, 2.0× at nv = 18, 1.3× at nv = 38,
/// 1.1× at nv = 50);
/// above 64 each block's pair of `nv x nv` lane matrices (`128·nv²` bytes) outgrows the L2
/// cache, so the one-state path stays there. The inverse-dynamics derivatives write straight to
/// the outputs and run in lanes at every size.
const ABA_LANES_MAX_NV: usize = 64;

impl<const L: usize> DerivativesLanes<L> {
    fn new(model: &Model, data: &DerivativesData) -> Self {
        Self {
            rnea: RneaDerivativesLanes::new(model),
            aba: if model.nv() <= ABA_LANES_MAX_NV {
                AbaDerivativesLanes::new(model, data)
            } else {
                AbaDerivativesLanes::default()
            },
            matrices: if model.nv() <= RNEA_LANES_OUT_MAX_NV {
                vec![Lanes::ZERO; 3 * (model.nv() * model.nv()).next_multiple_of(8)]
            } else {
                Vec::new()
            },
        }
    }
}

impl DerivativesBatch {
    /// Allocates every buffer for `model`, for the rigid-body dynamics (as
    /// [`DerivativesData::new`]).
    #[must_use]
    pub fn new(model: &Model) -> Self {
        Self::with_joint_terms(model, JointTerms::Ignored)
    }

    /// Allocates every buffer for `model`, choosing whether the joints' damping, friction and
    /// armature enter (as [`DerivativesData::with_joint_terms`]).
    #[must_use]
    pub fn with_joint_terms(model: &Model, joint_terms: JointTerms) -> Self {
        Self::with_options(model, joint_terms, Simd::detect())
    }

    /// Allocates every buffer for `model`, with the joint terms `joint_terms`, for the
    /// instruction set `simd` (or the widest one below it that this CPU has). The results do
    /// not depend on `simd`.
    #[must_use]
    pub fn with_options(model: &Model, joint_terms: JointTerms, simd: Simd) -> Self {
        let simd = simd.or_available();
        let data = DerivativesData::with_joint_terms(model, joint_terms);
        let (lanes4, lanes8) = if simd.lanes() == 8 {
            (
                DerivativesLanes::default(),
                DerivativesLanes::new(model, &data),
            )
        } else {
            (
                DerivativesLanes::new(model, &data),
                DerivativesLanes::default(),
            )
        };
        Self {
            simd,
            data,
            lanes4,
            lanes8,
        }
    }

    /// The instruction set the sweeps run with.
    #[must_use]
    pub fn simd(&self) -> Simd {
        self.simd
    }
}

/// The inverse-dynamics derivatives of `N` states: for each state `(q, v, a)` (`N · nq`,
/// `N · nv`, `N · nv`), `dtau_dq`, `dtau_dv` and `dtau_da` (each `N · nv · nv`, every state's
/// `nv x nv` matrix row-major) receive the matrices [`rnea_derivatives`](crate::rnea_derivatives)
/// computes, equal to them entry for entry. Allocates nothing.
///
/// # Errors
/// [`DynamicsError::DimensionMismatch`] for buffers of the wrong length,
/// [`DynamicsError::DataMismatch`] when `batch` belongs to another model,
/// [`DynamicsError::InBatchState`] wrapping the one-state error of the first bad state (an input
/// refused, or a result that overflowed).
///
/// # Examples
/// ```
/// use kinetree_dynamics::batch::{DerivativesBatch, rnea_derivatives_batch};
/// use kinetree_dynamics::{DerivativesData, rnea_derivatives};
/// # fn main() -> Result<(), kinetree_dynamics::DynamicsError> {
/// let model = kinetree_dynamics::model::samples::planar_2r(0.3, 0.2);
/// let q = [0.1, 0.2, -0.3, 0.4]; // two states of nq = 2
/// let v = [0.5, -0.5, 1.0, 0.0];
/// let a = [0.0, 1.0, 2.0, -1.0];
/// let mut batch = DerivativesBatch::new(&model);
/// let (mut dq, mut dv, mut da) = ([0.0; 8], [0.0; 8], [0.0; 8]);
/// rnea_derivatives_batch(&model, &mut batch, &q, &v, &a, &mut dq, &mut dv, &mut da)?;
/// let mut data = DerivativesData::new(&model);
/// let one = rnea_derivatives(&model, &mut data, &q[2..], &v[2..], &a[2..])?;
/// assert_eq!(&dq[4..], one.dtau_dq);
/// assert_eq!(&da[4..], one.dtau_da);
/// # Ok(())
/// # }
/// ```
#[allow(
    clippy::too_many_arguments,
    reason = "three inputs and three outputs of one batch"
)]
pub fn rnea_derivatives_batch(
    model: &Model,
    batch: &mut DerivativesBatch,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    dtau_dq: &mut [f64],
    dtau_dv: &mut [f64],
    dtau_da: &mut [f64],
) -> Result<(), DynamicsError> {
    batch.data.dynamics.check_model(model)?;
    let (nq, nv) = (model.nq(), model.nv());
    let nn = nv * nv;
    let n = states(model, q.len(), "dtau_dq", dtau_dq.len(), nn)?;
    check_buffer("v", v.len(), n, nv)?;
    check_buffer("a", a.len(), n, nv)?;
    check_buffer("dtau_dq", dtau_dq.len(), n, nn)?;
    check_buffer("dtau_dv", dtau_dv.len(), n, nn)?;
    check_buffer("dtau_da", dtau_da.len(), n, nn)?;
    if !states_pass(model, &[q, v, a]) {
        check_rnea_states(model, &batch.data.dynamics, (0, n), q, v, a)?;
    }
    let data = &batch.data;
    let io = Io::new(batch.simd);
    let first_bad = kinetree_kinematics::simd_dispatch!(
        batch.simd, DerivativesLanes, &mut batch.lanes4, &mut batch.lanes8, kernel,
        (io: Io = io, model: &Model = model, data: &DerivativesData = data, q: &[f64] = q, v: &[f64] = v,
         a: &[f64] = a, n: usize = n, dtau_dq: &mut [f64] = dtau_dq,
         dtau_dv: &mut [f64] = dtau_dv, dtau_da: &mut [f64] = dtau_da) -> Option<usize>
    );
    if let Some(k) = first_bad {
        // A result overflowed: the one-state function names it.
        let r = k * nv..(k + 1) * nv;
        crate::rnea_derivatives(
            model,
            &mut batch.data,
            &q[k * nq..(k + 1) * nq],
            &v[r.clone()],
            &a[r],
        )
        .map_err(in_state(k))?;
    }
    Ok(())
}

/// `Σ x · 0` over `xs`: zero in a lane exactly when all its numbers are finite (four sums, so
/// that the additions do not wait on one another).
#[inline(always)]
fn finiteness_probe<const L: usize>(xs: &[Lanes<L>]) -> Lanes<L> {
    let mut sums = [Lanes::ZERO; 4];
    let mut chunks = xs.chunks_exact(4);
    for c in &mut chunks {
        for (s, x) in sums.iter_mut().zip(c) {
            *s += *x * 0.0;
        }
    }
    for x in chunks.remainder() {
        sums[0] += *x * 0.0;
    }
    (sums[0] + sums[1]) + (sums[2] + sums[3])
}

/// Runs the lane kernel, which writes each block's entries into the outputs; the first state with a non-finite `τ` or
/// matrix entry (the one-state function's error), if any.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the kernel's inputs, passed through"
)]
fn kernel<const L: usize>(
    bufs: &mut DerivativesLanes<L>,
    io: Io,
    model: &Model,
    data: &DerivativesData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    n: usize,
    dtau_dq: &mut [f64],
    dtau_dv: &mut [f64],
    dtau_da: &mut [f64],
) -> Option<usize> {
    let nv = model.nv();
    let nn = nv * nv;
    let dynamics = &data.dynamics;
    let matrices_len = bufs.matrices.len();
    let mut first_bad = None;
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        let rows = start * nn..(start + count) * nn;
        let (rnea, matrices) = (&mut bufs.rnea, &mut bufs.matrices);
        let probe = if matrices.is_empty() {
            // The entries the sweep does not write are zero.
            dtau_dq[rows.clone()].fill(0.0);
            dtau_dv[rows.clone()].fill(0.0);
            dtau_da[rows.clone()].fill(0.0);
            let mut sink = OutputSink {
                base: idx.map(|k| k * nn),
                nv,
                dq: &mut *dtau_dq,
                dv: &mut *dtau_dv,
                da: &mut *dtau_da,
                probe: Lanes::ZERO,
            };
            rnea_derivatives(rnea, model, data, q, v, a, &idx, &mut sink);
            sink.probe
        } else {
            // The sweep writes the same entries in every block (the pairs of joints of which
            // one supports the other); the others stay the zeros of `DerivativesLanes::new`.
            let mut sink = LaneSink {
                matrices: &mut matrices[..],
                half: matrices_len / 3,
                nv,
            };
            rnea_derivatives(rnea, model, data, q, v, a, &idx, &mut sink);
            let probe = finiteness_probe(matrices);
            let (xq, rest) = matrices.split_at(matrices_len / 3);
            let (xv, xa) = rest.split_at(matrices_len / 3);
            io.store_coordinates(xq, nn, dtau_dq, start, nn, count);
            io.store_coordinates(xv, nn, dtau_dv, start, nn, count);
            io.store_coordinates(xa, nn, dtau_da, start, nn, count);
            probe
        };
        let bufs = &*rnea;
        // `x · 0` is zero for a finite `x` and NaN otherwise: one probe per lane for the whole
        // block.
        let mut probe = probe;
        for x in &bufs.tau {
            probe += *x * 0.0;
        }
        let (dv, da) = (&mut dtau_dv[rows.clone()], &mut dtau_da[rows]);
        for l in 0..count {
            let k = start + l;
            let mut finite = probe.0[l] == 0.0;
            if dynamics.has_joint_terms {
                let (dv, da) = (&mut dv[l * nn..(l + 1) * nn], &mut da[l * nn..(l + 1) * nn]);
                let (vk, ak) = (&v[k * nv..(k + 1) * nv], &a[k * nv..(k + 1) * nv]);
                for j in 0..nv {
                    let tau = bufs.tau[j].0[l]
                        + (dynamics.armature[j] * ak[j]
                            + dynamics.damping[j] * vk[j]
                            + dynamics.friction[j] * sign(vk[j]));
                    da[j * nv + j] += dynamics.armature[j];
                    dv[j * nv + j] += dynamics.damping[j];
                    finite &=
                        tau.is_finite() && da[j * nv + j].is_finite() && dv[j * nv + j].is_finite();
                }
            }
            if !finite && first_bad.is_none() {
                first_bad = Some(k);
            }
        }
    }
    first_bad
}

/// The forward-dynamics derivatives of `N` states: for each state `(q, v, tau)` (`N · nq`,
/// `N · nv`, `N · nv`), `dddq_dq`, `dddq_dv` and `dddq_dtau` (each `N · nv · nv`, every state's
/// `nv x nv` matrix row-major) receive `∂q̈/∂q`, `∂q̈/∂v` and `M⁻¹` as
/// [`aba_derivatives`](crate::aba_derivatives) computes them, equal to them entry for entry.
/// Up to 64 degrees of freedom the sweeps and the solves run in lanes (4 or 8 states at a
/// time), above it one state at a time, whichever was faster. Allocates nothing.
///
/// # Errors
/// As [`rnea_derivatives_batch`]; the one-state error of a state whose mass matrix is singular
/// is [`DynamicsError::SingularMassMatrix`].
///
/// # Examples
/// ```
/// use kinetree_dynamics::batch::{DerivativesBatch, aba_derivatives_batch};
/// use kinetree_dynamics::{DerivativesData, aba_derivatives};
/// # fn main() -> Result<(), kinetree_dynamics::DynamicsError> {
/// let model = kinetree_dynamics::model::samples::planar_2r(0.3, 0.2);
/// let q = [0.1, 0.2, -0.3, 0.4]; // two states of nq = 2
/// let v = [0.5, -0.5, 1.0, 0.0];
/// let tau = [0.0, 1.0, 2.0, -1.0];
/// let mut batch = DerivativesBatch::new(&model);
/// let (mut dq, mut dv, mut minv) = ([0.0; 8], [0.0; 8], [0.0; 8]);
/// aba_derivatives_batch(&model, &mut batch, &q, &v, &tau, &mut dq, &mut dv, &mut minv)?;
/// let mut data = DerivativesData::new(&model);
/// let one = aba_derivatives(&model, &mut data, &q[2..], &v[2..], &tau[2..])?;
/// assert_eq!(&dq[4..], one.dddq_dq);
/// assert_eq!(&minv[4..], one.dddq_dtau);
/// # Ok(())
/// # }
/// ```
#[allow(
    clippy::too_many_arguments,
    reason = "three inputs and three outputs of one batch"
)]
pub fn aba_derivatives_batch(
    model: &Model,
    batch: &mut DerivativesBatch,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    dddq_dq: &mut [f64],
    dddq_dv: &mut [f64],
    dddq_dtau: &mut [f64],
) -> Result<(), DynamicsError> {
    batch.data.dynamics.check_model(model)?;
    let (nq, nv) = (model.nq(), model.nv());
    let nn = nv * nv;
    let n = states(model, q.len(), "dddq_dq", dddq_dq.len(), nn)?;
    check_buffer("v", v.len(), n, nv)?;
    check_buffer("tau", tau.len(), n, nv)?;
    check_buffer("dddq_dq", dddq_dq.len(), n, nn)?;
    check_buffer("dddq_dv", dddq_dv.len(), n, nn)?;
    check_buffer("dddq_dtau", dddq_dtau.len(), n, nn)?;
    check_aba_states(model, &batch.data.dynamics, n, q, v, tau)?;
    if nv > ABA_LANES_MAX_NV {
        for k in 0..n {
            let (r, m) = (k * nv..(k + 1) * nv, k * nn..(k + 1) * nn);
            let d = crate::aba_derivatives(
                model,
                &mut batch.data,
                &q[k * nq..(k + 1) * nq],
                &v[r.clone()],
                &tau[r],
            )
            .map_err(in_state(k))?;
            dddq_dq[m.clone()].copy_from_slice(d.dddq_dq);
            dddq_dv[m.clone()].copy_from_slice(d.dddq_dv);
            dddq_dtau[m].copy_from_slice(d.dddq_dtau);
        }
        return Ok(());
    }
    let data = &batch.data;
    let io = Io::new(batch.simd);
    let first_bad = kinetree_kinematics::simd_dispatch!(
        batch.simd, DerivativesLanes, &mut batch.lanes4, &mut batch.lanes8, aba_kernel,
        (io: Io = io, model: &Model = model, data: &DerivativesData = data, q: &[f64] = q, v: &[f64] = v,
         tau: &[f64] = tau, n: usize = n, dddq_dq: &mut [f64] = dddq_dq,
         dddq_dv: &mut [f64] = dddq_dv, dddq_dtau: &mut [f64] = dddq_dtau) -> Option<usize>
    );
    if let Some(k) = first_bad {
        // A vanished pivot or a result that overflowed: the one-state function names it.
        let r = k * nv..(k + 1) * nv;
        crate::aba_derivatives(
            model,
            &mut batch.data,
            &q[k * nq..(k + 1) * nq],
            &v[r.clone()],
            &tau[r],
        )
        .map_err(in_state(k))?;
    }
    Ok(())
}

/// Whether every entry of `xs` is finite (`x · 0` is zero for a finite `x`, NaN otherwise;
/// eight independent sums, so the scan runs in SIMD).
#[inline(always)]
fn all_finite(xs: &[f64]) -> bool {
    let mut acc = [0.0; 8];
    let mut chunks = xs.chunks_exact(8);
    for c in &mut chunks {
        for (a, x) in acc.iter_mut().zip(c) {
            *a += *x * 0.0;
        }
    }
    let rest: f64 = chunks.remainder().iter().map(|x| *x * 0.0).sum();
    acc.iter().sum::<f64>() + rest == 0.0
}

/// Runs the lane kernel block by block; the first state whose pivot vanished or whose `q̈` or
/// matrices are not finite (the one-state function's error), if any.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the kernel's inputs, passed through"
)]
fn aba_kernel<const L: usize>(
    bufs: &mut DerivativesLanes<L>,
    io: Io,
    model: &Model,
    data: &DerivativesData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    n: usize,
    dddq_dq: &mut [f64],
    dddq_dv: &mut [f64],
    dddq_dtau: &mut [f64],
) -> Option<usize> {
    let nn = model.nv() * model.nv();
    let mut first_bad = None;
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        let out = [&mut *dddq_dq, &mut *dddq_dv, &mut *dddq_dtau];
        let (rnea, aba) = (&mut bufs.rnea, &mut bufs.aba);
        let singular = aba_derivatives(rnea, aba, model, data, q, v, tau, &idx, count, io, out);
        for l in 0..count {
            let m = (start + l) * nn..(start + l + 1) * nn;
            let finite = !singular[l]
                && aba.ddq.iter().all(|x| x.0[l].is_finite())
                && all_finite(&dddq_dq[m.clone()])
                && all_finite(&dddq_dv[m.clone()])
                && all_finite(&dddq_dtau[m]);
            if !finite && first_bad.is_none() {
                first_bad = Some(start + l);
            }
        }
    }
    first_bad
}
