//! The batched analytic derivatives: [`DerivativesBatch`] and [`rnea_derivatives_batch`].

use super::rnea_derivatives::{RneaDerivativesLanes, rnea_derivatives};
use super::{check_buffer, check_rnea_states, in_state, states};
use crate::data::{JointTerms, sign};
use crate::derivatives::DerivativesData;
use crate::error::DynamicsError;
use kinetree_kinematics::batch::{Simd, block_states};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::lanes::Lanes;

/// The buffers of the batched analytic derivatives for one [`Model`] (see the
/// [module](super) docs for the layout of a batch).
///
/// Create it once per model (and per thread); [`rnea_derivatives_batch`] allocates nothing
/// afterwards.
#[derive(Clone, Debug)]
pub struct DerivativesBatch {
    simd: Simd,
    /// One-state data: the joint models and terms, the tree's structure, the model check, and
    /// the error of a bad state.
    data: DerivativesData,
    lanes4: RneaDerivativesLanes<4>,
    lanes8: RneaDerivativesLanes<8>,
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
                RneaDerivativesLanes::default(),
                RneaDerivativesLanes::new(model),
            )
        } else {
            (
                RneaDerivativesLanes::new(model),
                RneaDerivativesLanes::default(),
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
    check_rnea_states(model, &batch.data.dynamics, n, q, v, a)?;
    let data = &batch.data;
    let first_bad = kinetree_kinematics::simd_dispatch!(
        batch.simd, RneaDerivativesLanes, &mut batch.lanes4, &mut batch.lanes8, kernel,
        (model: &Model = model, data: &DerivativesData = data, q: &[f64] = q, v: &[f64] = v,
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

/// Runs the lane kernel and copies each block out; the first state with a non-finite `τ` or
/// matrix entry (the one-state function's error), if any.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the kernel's inputs, passed through"
)]
fn kernel<const L: usize>(
    bufs: &mut RneaDerivativesLanes<L>,
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
    let mut first_bad = None;
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        rnea_derivatives(bufs, model, data, q, v, a, &idx);
        // `x · 0` is zero for a finite `x` and NaN otherwise: one probe per lane for the whole
        // block.
        let mut probe = Lanes::<L>::ZERO;
        for x in bufs
            .tau
            .iter()
            .chain(&bufs.dq)
            .chain(&bufs.dv)
            .chain(&bufs.da)
        {
            probe += *x * 0.0;
        }
        let rows = start * nn..(start + count) * nn;
        let (dq, dv, da) = (
            &mut dtau_dq[rows.clone()],
            &mut dtau_dv[rows.clone()],
            &mut dtau_da[rows],
        );
        let (bq, bv, ba) = (&bufs.dq[..nn], &bufs.dv[..nn], &bufs.da[..nn]);
        for l in 0..count {
            let at = l * nn..(l + 1) * nn;
            for (o, x) in dq[at.clone()].iter_mut().zip(bq) {
                *o = x.0[l];
            }
            for (o, x) in dv[at.clone()].iter_mut().zip(bv) {
                *o = x.0[l];
            }
            for (o, x) in da[at].iter_mut().zip(ba) {
                *o = x.0[l];
            }
        }
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
