//! Batched dynamics: RNEA, ABA, CRBA and the RNEA and ABA derivatives of `N` states in one
//! call, into buffers the caller owns.
//!
//! The states are stored one after another, as in
//! [`kinetree_kinematics::batch`]: `q` holds `N · model.nq()` numbers, `v`, `a` and `tau`
//! `N · model.nv()`, and a mass-matrix output `N · nv · nv` (each `nv x nv`, row-major). A
//! [`DynamicsBatch`] holds every buffer; after [`DynamicsBatch::new`] nothing allocates. State
//! `k`'s results equal the one-state [`rnea`](crate::rnea), [`aba`](crate::aba) and
//! [`crba`](crate::crba) to rounding (the tests hold them to 1e-14 relative on every reference
//! robot).
//!
//! The algorithms run on blocks of states in SIMD lanes (see
//! [`kinetree_kinematics::batch::Simd`]) that repeat the one-state arithmetic in the same order.
//! For all cores, `kinetree::parallel` splits a batch over a rayon pool with the same signatures.
//!
//! # Examples
//! ```
//! use kinetree_dynamics::batch::{DynamicsBatch, rnea_batch};
//! use kinetree_dynamics::{DynamicsData, rnea};
//! # fn main() -> Result<(), kinetree_dynamics::DynamicsError> {
//! let model = kinetree_dynamics::model::samples::planar_2r(0.3, 0.2);
//! let q = [0.1, 0.2, -0.3, 0.4]; // two states of nq = 2
//! let v = [0.5, -0.5, 1.0, 0.0];
//! let a = [0.0, 1.0, 2.0, -1.0];
//! let mut batch = DynamicsBatch::new(&model);
//! let mut tau = [0.0; 4];
//! rnea_batch(&model, &mut batch, &q, &v, &a, &mut tau)?;
//! let mut data = DynamicsData::new(&model);
//! let one = rnea(&model, &mut data, &q[2..], &v[2..], &a[2..])?;
//! assert!((tau[2] - one[0]).abs() < 1e-12 && (tau[3] - one[1]).abs() < 1e-12);
//! # Ok(())
//! # }
//! ```

mod aba;
mod aba_derivatives;
mod crba;
mod derivatives;
mod lane_solve;
mod rnea;
mod rnea_derivatives;

use crate::data::{DynamicsData, JointTerms};
use crate::error::{DynamicsError, check_vector, first_non_finite};
use crate::rnea::check_inputs;
use aba::AbaLanes;
use crba::CrbaLanes;
use kinetree_kinematics::batch::{Io, Simd, batch_size};
use kinetree_kinematics::model::Model;
use rnea::RneaLanes;

pub use derivatives::{DerivativesBatch, aba_derivatives_batch, rnea_derivatives_batch};

/// The lane buffers of every batched algorithm for one lane width.
#[derive(Clone, Debug, Default)]
struct BatchLanes<const L: usize> {
    rnea: RneaLanes<L>,
    aba: AbaLanes<L>,
    crba: CrbaLanes<L>,
}

impl<const L: usize> BatchLanes<L> {
    fn new(model: &Model, data: &DynamicsData) -> Self {
        Self {
            rnea: RneaLanes::new(model),
            aba: AbaLanes::new(model, data),
            crba: CrbaLanes::new(model),
        }
    }
}

/// The buffers of the batched dynamics for one [`Model`] (see the [module](self) docs).
///
/// Create it once per model (and per thread); the batched functions allocate nothing afterwards.
#[derive(Clone, Debug)]
pub struct DynamicsBatch {
    simd: Simd,
    /// One-state data: the joint models and terms, the model check, and the error of a bad
    /// state.
    data: DynamicsData,
    lanes4: BatchLanes<4>,
    lanes8: BatchLanes<8>,
}

impl DynamicsBatch {
    /// Allocates every buffer for `model`, for the rigid-body dynamics (as
    /// [`DynamicsData::new`]).
    #[must_use]
    pub fn new(model: &Model) -> Self {
        Self::with_joint_terms(model, JointTerms::Ignored)
    }

    /// Allocates every buffer for `model`, choosing whether the joints' damping, friction and
    /// armature enter the dynamics (as [`DynamicsData::with_joint_terms`]).
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
        let data = DynamicsData::with_joint_terms(model, joint_terms);
        let (lanes4, lanes8) = if simd.lanes() == 8 {
            (BatchLanes::default(), BatchLanes::new(model, &data))
        } else {
            (BatchLanes::new(model, &data), BatchLanes::default())
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

/// Wraps the error of state `index` of a batch.
fn in_state(index: usize) -> impl Fn(DynamicsError) -> DynamicsError {
    move |e| DynamicsError::InBatchState {
        index,
        source: Box::new(e),
    }
}

/// [`DynamicsError::DimensionMismatch`] unless a buffer of `len` numbers holds `n` states of
/// `per_state` each.
fn check_buffer(
    what: &'static str,
    len: usize,
    n: usize,
    per_state: usize,
) -> Result<(), DynamicsError> {
    if len != n * per_state {
        return Err(DynamicsError::DimensionMismatch {
            what,
            expected: n * per_state,
            actual: len,
        });
    }
    Ok(())
}

/// The number of states of a batch: `q.len() / nq`, or for a model without configuration
/// coordinates `out_len / per_state`.
fn states(
    model: &Model,
    q_len: usize,
    out_what: &'static str,
    out_len: usize,
    per_state: usize,
) -> Result<usize, DynamicsError> {
    let n = if model.nq() > 0 {
        batch_size("q", q_len, model.nq())?
    } else {
        batch_size(out_what, out_len, per_state)?
    };
    Ok(n)
}

/// Whether every state of the buffers `inputs` (their lengths already checked against the
/// model and each other) passes the one-state input checks, decided in one branch-free pass
/// over each buffer that the compiler vectorises: true when every number is finite and the model
/// has no quaternions (whose norms only the per-state checks test). False says nothing: the
/// per-state checks then find the first bad state, or none.
fn states_pass(model: &Model, inputs: &[&[f64]]) -> bool {
    model.quaternion_blocks().is_empty() && inputs.iter().all(|x| first_non_finite(x).is_none())
}

/// Checks the states `(q, v, a)` from state `from` on as [`rnea`](crate::rnea) does (the
/// buffers' lengths already checked); an error names the first bad state by its index.
fn check_rnea_states(
    model: &Model,
    data: &DynamicsData,
    (from, n): (usize, usize),
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Result<(), DynamicsError> {
    let (nq, nv) = (model.nq(), model.nv());
    for k in from..n {
        let r = k * nv..(k + 1) * nv;
        check_inputs(
            model,
            data,
            &q[k * nq..(k + 1) * nq],
            Some(&v[r.clone()]),
            Some(&a[r]),
        )
        .map_err(in_state(k))?;
    }
    Ok(())
}

/// Checks every one of the `n` states `(q, v, tau)` as [`aba`](crate::aba) does (the buffers'
/// lengths already checked); an error names the first bad state by its index.
fn check_aba_states(
    model: &Model,
    data: &DynamicsData,
    n: usize,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
) -> Result<(), DynamicsError> {
    if states_pass(model, &[q, v, tau]) {
        return Ok(());
    }
    let (nq, nv) = (model.nq(), model.nv());
    for k in 0..n {
        let r = k * nv..(k + 1) * nv;
        check_inputs(
            model,
            data,
            &q[k * nq..(k + 1) * nq],
            Some(&v[r.clone()]),
            None,
        )
        .and_then(|()| check_vector("tau", &tau[r], nv))
        .map_err(in_state(k))?;
    }
    Ok(())
}

/// Inverse dynamics of `N` states: `tau` (`N · nv`) receives the torques
/// [`rnea`](crate::rnea) computes for each state `(q, v, a)` (`N · nq`, `N · nv`, `N · nv`).
/// Allocates nothing.
///
/// # Errors
/// [`DynamicsError::DimensionMismatch`] for buffers of the wrong length,
/// [`DynamicsError::DataMismatch`] when `batch` belongs to another model,
/// [`DynamicsError::InBatchState`] wrapping the one-state error of the first bad state.
pub fn rnea_batch(
    model: &Model,
    batch: &mut DynamicsBatch,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    tau: &mut [f64],
) -> Result<(), DynamicsError> {
    batch.data.check_model(model)?;
    let (nq, nv) = (model.nq(), model.nv());
    let n = states(model, q.len(), "tau", tau.len(), nv)?;
    check_buffer("v", v.len(), n, nv)?;
    check_buffer("a", a.len(), n, nv)?;
    check_buffer("tau", tau.len(), n, nv)?;
    let data = &batch.data;
    let io = Io::new(batch.simd);
    let flagged = kinetree_kinematics::simd_dispatch!(
        batch.simd, BatchLanes, &mut batch.lanes4, &mut batch.lanes8, rnea_kernel,
        (io: Io = io, model: &Model = model, data: &DynamicsData = data, q: &[f64] = q,
         v: &[f64] = v, a: &[f64] = a, n: usize = n, tau: &mut [f64] = tau) -> rnea::Flagged
    );
    // The lanes proved every other state's inputs valid; the one-state checks decide from the
    // first state they could not.
    if let Some(k) = flagged.suspect {
        check_rnea_states(model, &batch.data, (k, n), q, v, a)?;
    }
    if let Some(k) = flagged.not_finite {
        // The one-state function names the joint that overflowed.
        let r = k * nv..(k + 1) * nv;
        crate::rnea(
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

#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the kernel's inputs, passed through"
)]
fn rnea_kernel<const L: usize>(
    bufs: &mut BatchLanes<L>,
    io: Io,
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    n: usize,
    tau: &mut [f64],
) -> rnea::Flagged {
    rnea::rnea(&mut bufs.rnea, io, model, data, q, v, a, n, tau)
}

/// Forward dynamics of `N` states: `ddq` (`N · nv`) receives the accelerations
/// [`aba`](crate::aba) computes for each state `(q, v, tau)` (`N · nq`, `N · nv`, `N · nv`).
/// Allocates nothing.
///
/// # Errors
/// As [`rnea_batch`].
pub fn aba_batch(
    model: &Model,
    batch: &mut DynamicsBatch,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    ddq: &mut [f64],
) -> Result<(), DynamicsError> {
    batch.data.check_model(model)?;
    let (nq, nv) = (model.nq(), model.nv());
    let n = states(model, q.len(), "ddq", ddq.len(), nv)?;
    check_buffer("v", v.len(), n, nv)?;
    check_buffer("tau", tau.len(), n, nv)?;
    check_buffer("ddq", ddq.len(), n, nv)?;
    check_aba_states(model, &batch.data, n, q, v, tau)?;
    let data = &batch.data;
    let io = Io::new(batch.simd);
    kinetree_kinematics::simd_dispatch!(
        batch.simd, BatchLanes, &mut batch.lanes4, &mut batch.lanes8, aba_kernel,
        (io: Io = io, model: &Model = model, data: &DynamicsData = data, q: &[f64] = q, v: &[f64] = v,
         tau: &[f64] = tau, n: usize = n, ddq: &mut [f64] = ddq) -> ()
    );
    // A vanished pivot or an overflow leaves a state's accelerations NaN: the one-state
    // function names the joints.
    let mut from = 0;
    while let Some(i) = first_non_finite(&ddq[from..]) {
        let k = (from + i) / nv;
        let r = k * nv..(k + 1) * nv;
        let out = crate::aba(
            model,
            &mut batch.data,
            &q[k * nq..(k + 1) * nq],
            &v[r.clone()],
            &tau[r.clone()],
        )
        .map_err(in_state(k))?;
        ddq[r.clone()].copy_from_slice(out);
        from = r.end;
    }
    Ok(())
}

#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the kernel's inputs, passed through"
)]
fn aba_kernel<const L: usize>(
    bufs: &mut BatchLanes<L>,
    io: Io,
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    n: usize,
    ddq: &mut [f64],
) {
    aba::aba(&mut bufs.aba, io, model, data, q, v, tau, n, ddq);
}

/// The joint-space mass matrices of `N` states: `mass_matrix` (`N · nv · nv`) receives, for
/// each configuration of `q` (`N · nq`), the full symmetric `nv x nv` matrix (row-major) that
/// [`crba`](crate::crba) computes. Allocates nothing.
///
/// # Errors
/// As [`rnea_batch`].
pub fn crba_batch(
    model: &Model,
    batch: &mut DynamicsBatch,
    q: &[f64],
    mass_matrix: &mut [f64],
) -> Result<(), DynamicsError> {
    batch.data.check_model(model)?;
    let (nq, nv) = (model.nq(), model.nv());
    let nn = nv * nv;
    let n = states(model, q.len(), "mass matrix", mass_matrix.len(), nn)?;
    check_buffer("mass matrix", mass_matrix.len(), n, nn)?;
    if !states_pass(model, &[q]) {
        for k in 0..n {
            check_inputs(model, &batch.data, &q[k * nq..(k + 1) * nq], None, None)
                .map_err(in_state(k))?;
        }
    }
    let data = &batch.data;
    let io = Io::new(batch.simd);
    let finite = kinetree_kinematics::simd_dispatch!(
        batch.simd, BatchLanes, &mut batch.lanes4, &mut batch.lanes8, crba_kernel,
        (io: Io = io, model: &Model = model, data: &DynamicsData = data, q: &[f64] = q,
         n: usize = n, mass_matrix: &mut [f64] = mass_matrix) -> bool
    );
    // Finite probes prove every entry finite; otherwise an entry is not, or finite entries
    // overflowed a probe's sum.
    if finite {
        return Ok(());
    }
    if let Some(i) = mass_matrix.iter().position(|x| !x.is_finite()) {
        // The one-state function names the joint that overflowed.
        let k = i / nn;
        crate::crba(model, &mut batch.data, &q[k * nq..(k + 1) * nq]).map_err(in_state(k))?;
    }
    Ok(())
}

#[inline(always)]
fn crba_kernel<const L: usize>(
    bufs: &mut BatchLanes<L>,
    io: Io,
    model: &Model,
    data: &DynamicsData,
    q: &[f64],
    n: usize,
    mass_matrix: &mut [f64],
) -> bool {
    crba::crba(&mut bufs.crba, io, model, data, q, n, mass_matrix)
}
