//! Batched kinematics: forward kinematics and frame Jacobians of `N` states in one call, into
//! buffers the caller owns.
//!
//! The states are stored one after another: `q` holds `N · model.nq()` numbers, state `k` at
//! `q[k·nq..(k+1)·nq]`; the results follow the same layout (`N · links` placements, or `N · links`
//! row-major 4×4 matrices from [`forward_kinematics_matrices_batch`]; `N · nv` Jacobian columns,
//! or `N` row-major `6 x nv` matrices from [`frame_jacobian_rows_batch`]). A [`KinematicsBatch`] holds every buffer; after [`KinematicsBatch::new`]
//! nothing allocates. The results equal the one-state functions' to rounding (the tests hold them
//! to 1e-14 relative on every reference robot).
//!
//! All states share the model, so every joint is of the same kind in every state: the sweeps run
//! over several states at once in SIMD lanes (4 with AVX2, 8 with AVX-512F, chosen at run time;
//! a portable path elsewhere). For all cores, `kinetree::parallel` splits a batch over a rayon
//! pool with the same signatures.
//!
//! # Examples
//! ```
//! use kinetree_kinematics::batch::{KinematicsBatch, forward_kinematics_batch};
//! use kinetree_kinematics::{KinematicsData, forward_kinematics};
//! use kinetree_kinematics::spatial::Se3;
//! # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
//! let model = kinetree_kinematics::model::samples::planar_2r(0.3, 0.2);
//! let qs = [0.1, 0.2, -0.3, 0.4, 1.0, -1.0]; // three states of nq = 2
//! let mut batch = KinematicsBatch::new(&model);
//! let mut links = vec![Se3::IDENTITY; 3 * model.links().len()];
//! forward_kinematics_batch(&model, &mut batch, &qs, &mut links, None)?;
//! // State 2 agrees with the one-state forward kinematics.
//! let mut data = KinematicsData::new(&model);
//! forward_kinematics(&model, &mut data, &qs[4..6])?;
//! let n = model.links().len();
//! assert!(links[2 * n + n - 1].abs_diff_eq(&data.world_from_link()[n - 1], 1e-15, 1e-15));
//! # Ok(())
//! # }
//! ```

mod simd;
mod sweep;
mod transpose;

pub use simd::Simd;
#[doc(hidden)]
pub use simd::{Half, Page, align_frame};
#[doc(hidden)]
pub use simd::{block_states, body_transform, gather, suspect_lanes};
#[doc(hidden)]
pub use transpose::Io;

use crate::data::{FrameId, KinematicsData};
use crate::error::KinematicsError;
use crate::jacobian::ReferenceFrame;
use kinetree_model::Model;
use kinetree_model::spatial::{Motion, Se3};
use sweep::{JacobianOut, LaneBuffers, PosesOut, Shape};

/// The buffers of the batched kinematics for one [`Model`] (see the [module](self) docs).
///
/// Create it once per model (and per thread); the batched functions allocate nothing afterwards.
#[derive(Clone, Debug)]
pub struct KinematicsBatch {
    simd: Simd,
    /// One-state data: the joint models, the model check, and the error of a bad state.
    data: KinematicsData,
    jacobian: Vec<Motion>,
    lanes4: LaneBuffers<4>,
    lanes8: LaneBuffers<8>,
}

impl KinematicsBatch {
    /// Allocates every buffer for `model`, for the widest instruction set of this CPU
    /// ([`Simd::detect`]).
    #[must_use]
    pub fn new(model: &Model) -> Self {
        Self::with_simd(model, Simd::detect())
    }

    /// Allocates every buffer for `model`, for the instruction set `simd` (or the widest one
    /// below it that this CPU has). The results do not depend on it.
    #[must_use]
    pub fn with_simd(model: &Model, simd: Simd) -> Self {
        let simd = simd.or_available();
        let (lanes4, lanes8) = if simd.lanes() == 8 {
            (LaneBuffers::default(), LaneBuffers::new(model))
        } else {
            (LaneBuffers::new(model), LaneBuffers::default())
        };
        Self {
            simd,
            data: KinematicsData::new(model),
            jacobian: vec![Motion::ZERO; model.nv()],
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

/// The number of states in a batch of `len` numbers of `per_state` each.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] when `len` is not a multiple of `per_state`.
pub fn batch_size(
    what: &'static str,
    len: usize,
    per_state: usize,
) -> Result<usize, KinematicsError> {
    if per_state == 0 {
        return if len == 0 {
            Ok(0)
        } else {
            Err(KinematicsError::DimensionMismatch {
                what,
                expected: 0,
                actual: len,
            })
        };
    }
    if !len.is_multiple_of(per_state) {
        return Err(KinematicsError::DimensionMismatch {
            what,
            expected: (len / per_state + 1) * per_state,
            actual: len,
        });
    }
    Ok(len / per_state)
}

/// [`KinematicsError::DimensionMismatch`] unless `buffer` holds `n` states of `per_state` each.
pub(crate) fn check_buffer(
    what: &'static str,
    len: usize,
    n: usize,
    per_state: usize,
) -> Result<(), KinematicsError> {
    if len != n * per_state {
        return Err(KinematicsError::DimensionMismatch {
            what,
            expected: n * per_state,
            actual: len,
        });
    }
    Ok(())
}

/// Wraps the error of state `index` of a batch.
pub(crate) fn in_state(index: usize) -> impl Fn(KinematicsError) -> KinematicsError {
    move |e| KinematicsError::InBatchState {
        index,
        source: Box::new(e),
    }
}

/// The number of states of a batch whose configurations are `q` (`N · model.nq()` numbers); a
/// model without configuration coordinates counts them in `out` (`per_state` each).
fn states(
    model: &Model,
    q: &[f64],
    out_what: &'static str,
    out_len: usize,
    per_state: usize,
) -> Result<usize, KinematicsError> {
    if model.nq() > 0 {
        let n = batch_size("q", q.len(), model.nq())?;
        check_buffer(out_what, out_len, n, per_state)?;
        Ok(n)
    } else {
        batch_size(out_what, out_len, per_state)
    }
}

/// Forward kinematics of `N` states: the world placement of every link, and optionally of every
/// named frame.
///
/// `q` holds the `N` configurations one after another (`N · model.nq()` numbers);
/// `world_from_link` receives `N · model.links().len()` placements (state `k`'s links at
/// `k · links ..`), and `world_from_frame`, when given, `N · model.frames().len()`. State `k`'s
/// results equal [`forward_kinematics`](crate::forward_kinematics) (and
/// [`update_frame_placements`](crate::update_frame_placements)) of `q[k·nq..(k+1)·nq]` to
/// rounding. Allocates nothing.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] for buffers of the wrong length;
/// [`KinematicsError::InBatchState`] wrapping the one-state error of the first bad state (a
/// non-finite value, a quaternion that is not unit, an overflow).
pub fn forward_kinematics_batch(
    model: &Model,
    batch: &mut KinematicsBatch,
    q: &[f64],
    world_from_link: &mut [Se3],
    world_from_frame: Option<&mut [Se3]>,
) -> Result<(), KinematicsError> {
    batch.data.check_model(model)?;
    let nl = model.links().len();
    let n = states(model, q, "world_from_link", world_from_link.len(), nl)?;
    if let Some(frames) = &world_from_frame {
        check_buffer("world_from_frame", frames.len(), n, model.frames().len())?;
    }
    poses(
        model,
        batch,
        q,
        n,
        PosesOut::Placements(world_from_link),
        world_from_frame,
    )
}

/// Forward kinematics of `N` states as row-major 4×4 homogeneous matrices (the layout of
/// numpy's `(N, links, 4, 4)` arrays and of Pinocchio's `SE3.homogeneous`): the world placement
/// of each link of `links` (link indices, in the order wanted; every link of the model, in
/// order, when `None`).
///
/// `q` holds the `N` configurations one after another; `out` receives `N · k · 16` numbers for
/// `k` links, state `s`'s matrices at `s · k · 16 ..`, each the rotation's rows with the
/// translation as fourth column, then `0 0 0 1`. The numbers are those of
/// [`forward_kinematics_batch`] bit for bit, written once each, with no placement buffer
/// between. Allocates nothing.
///
/// # Examples
/// ```
/// use kinetree_kinematics::batch::{KinematicsBatch, forward_kinematics_matrices_batch};
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let model = kinetree_kinematics::model::samples::planar_2r(0.3, 0.2);
/// let link2 = model.link_index("link2").expect("the sample has link2");
/// let q = [0.0, 0.0, std::f64::consts::FRAC_PI_2, 0.0]; // two states of nq = 2
/// let mut batch = KinematicsBatch::new(&model);
/// let mut poses = [0.0; 2 * 16]; // link2's 4 x 4 pose in each state
/// forward_kinematics_matrices_batch(&model, &mut batch, &q, Some(&[link2]), &mut poses)?;
/// // link2 hangs at the end of the first link (l1 = 0.3): along x stretched out, along y
/// // with the first joint turned a quarter.
/// assert!((poses[3] - 0.3).abs() < 1e-15 && poses[7].abs() < 1e-15);
/// assert!(poses[16 + 3].abs() < 1e-15 && (poses[16 + 7] - 0.3).abs() < 1e-15);
/// assert_eq!(&poses[12..16], &[0.0, 0.0, 0.0, 1.0]);
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// [`KinematicsError::FrameOutOfRange`] for a link index the model does not have,
/// [`KinematicsError::DimensionMismatch`] for buffers of the wrong length,
/// [`KinematicsError::InBatchState`] wrapping the one-state error of the first bad state (a
/// non-finite value, a quaternion that is not unit, an overflow).
pub fn forward_kinematics_matrices_batch(
    model: &Model,
    batch: &mut KinematicsBatch,
    q: &[f64],
    links: Option<&[usize]>,
    out: &mut [f64],
) -> Result<(), KinematicsError> {
    batch.data.check_model(model)?;
    let nl = model.links().len();
    if let Some(&index) = links.into_iter().flatten().find(|&&l| l >= nl) {
        return Err(KinematicsError::FrameOutOfRange {
            what: "link",
            index,
            count: nl,
        });
    }
    let k = links.map_or(nl, <[usize]>::len);
    let n = states(model, q, "matrices", out.len(), 16 * k)?;
    poses(model, batch, q, n, PosesOut::Matrices { out, links }, None)
}

/// Batched forward kinematics of the `n` states of `q` into `links` and `frames` (the model,
/// lengths and link indices checked by the caller).
fn poses(
    model: &Model,
    batch: &mut KinematicsBatch,
    q: &[f64],
    n: usize,
    links: PosesOut<'_>,
    frames: Option<&mut [Se3]>,
) -> Result<(), KinematicsError> {
    let shape = Shape {
        model,
        joint_models: &batch.data.joint_models,
        link_on_body_frame: &batch.data.link_on_body_frame,
        turn_axis: &batch.data.turn_axis,
        io: Io::new(batch.simd),
    };
    let bad = crate::simd_dispatch!(
        batch.simd, LaneBuffers, &mut batch.lanes4, &mut batch.lanes8, fk_kernel,
        (shape: &Shape<'_> = &shape, q: &[f64] = q, n: usize = n,
         links: PosesOut<'_> = links, frames: Option<&mut [Se3]> = frames) -> Option<usize>
    );
    if let Some(k) = bad {
        // The one-state function names the body that overflowed.
        let nq = model.nq();
        crate::forward_kinematics(model, &mut batch.data, &q[k * nq..(k + 1) * nq])
            .map_err(in_state(k))?;
    }
    Ok(())
}

#[inline(always)]
fn fk_kernel<const L: usize>(
    bufs: &mut LaneBuffers<L>,
    shape: &Shape<'_>,
    q: &[f64],
    n: usize,
    links: PosesOut<'_>,
    frames: Option<&mut [Se3]>,
) -> Option<usize> {
    sweep::forward_kinematics(bufs, shape, q, n, links, frames)
}

#[inline(always)]
fn jacobian_kernel<const L: usize>(
    bufs: &mut LaneBuffers<L>,
    shape: &Shape<'_>,
    q: &[f64],
    n: usize,
    target: (usize, Se3),
    reference: ReferenceFrame,
    out: JacobianOut<'_>,
) -> Option<usize> {
    sweep::frame_jacobian(bufs, shape, q, n, target, reference, out)
}

/// The Jacobian of one link or frame in `N` states.
///
/// `q` holds the `N` configurations one after another (`N · model.nq()` numbers); `out` receives
/// `N · model.nv()` columns (state `k`'s at `k · nv ..`), each the twist in `reference` produced
/// by a unit velocity of its coordinate, as
/// [`compute_frame_jacobian`](crate::compute_frame_jacobian) computes them. Allocates nothing.
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] for buffers of the wrong length,
/// [`KinematicsError::FrameOutOfRange`] for a frame the model does not have,
/// [`KinematicsError::InBatchState`] wrapping the one-state error of the first bad state.
pub fn frame_jacobian_batch(
    model: &Model,
    batch: &mut KinematicsBatch,
    q: &[f64],
    frame: FrameId,
    reference: ReferenceFrame,
    out: &mut [Motion],
) -> Result<(), KinematicsError> {
    jacobian(model, batch, q, frame, reference, JacobianOut::Columns(out))
}

/// The Jacobian of one link or frame in `N` states, as row-major `6 x nv` matrices (the layout of
/// Pinocchio's and numpy's Jacobians): `out` receives `N · 6 · model.nv()` numbers, state `k`'s
/// matrix at `k · 6 · nv ..`, its rows the linear then the angular components of
/// [`frame_jacobian_batch`]'s columns (bit for bit). Writing each matrix whole and in order,
/// this is faster than the columns followed by a transpose. Allocates nothing.
///
/// # Examples
/// ```
/// use kinetree_kinematics::batch::{KinematicsBatch, frame_jacobian_rows_batch};
/// use kinetree_kinematics::{FrameId, ReferenceFrame};
/// # fn main() -> Result<(), kinetree_kinematics::KinematicsError> {
/// let model = kinetree_kinematics::model::samples::planar_2r(0.3, 0.2);
/// let tool = FrameId::find(&model, "tool")?;
/// let q = [0.0, 0.0, 0.5, -0.5]; // two states of nq = 2
/// let mut batch = KinematicsBatch::new(&model);
/// let mut jac = [0.0; 2 * 6 * 2]; // two 6 x 2 matrices
/// let aligned = ReferenceFrame::LocalWorldAligned;
/// frame_jacobian_rows_batch(&model, &mut batch, &q, tool, aligned, &mut jac)?;
/// // Stretched out along x, the tool moves along y at l1 + l2 and l2 per unit joint rate
/// // (row 1), and both joints turn it about z (row 5).
/// assert!((jac[2] - 0.5).abs() < 1e-15 && (jac[3] - 0.2).abs() < 1e-15);
/// assert_eq!(&jac[10..12], &[1.0, 1.0]);
/// # Ok(())
/// # }
/// ```
///
/// # Errors
/// As [`frame_jacobian_batch`].
pub fn frame_jacobian_rows_batch(
    model: &Model,
    batch: &mut KinematicsBatch,
    q: &[f64],
    frame: FrameId,
    reference: ReferenceFrame,
    out: &mut [f64],
) -> Result<(), KinematicsError> {
    jacobian(model, batch, q, frame, reference, JacobianOut::Rows(out))
}

/// The batched Jacobian of the states of `q` into `out`, in either layout.
fn jacobian(
    model: &Model,
    batch: &mut KinematicsBatch,
    q: &[f64],
    frame: FrameId,
    reference: ReferenceFrame,
    out: JacobianOut<'_>,
) -> Result<(), KinematicsError> {
    batch.data.check_model(model)?;
    frame.check(model)?;
    let (len, per_state) = out.shape(model.nv());
    let n = states(model, q, "jacobian", len, per_state)?;
    let target = frame.body(model)?;
    let shape = Shape {
        model,
        joint_models: &batch.data.joint_models,
        link_on_body_frame: &batch.data.link_on_body_frame,
        turn_axis: &batch.data.turn_axis,
        io: Io::new(batch.simd),
    };
    let bad = crate::simd_dispatch!(
        batch.simd, LaneBuffers, &mut batch.lanes4, &mut batch.lanes8, jacobian_kernel,
        (shape: &Shape<'_> = &shape, q: &[f64] = q, n: usize = n,
         target: (usize, Se3) = target,
         reference: ReferenceFrame = reference, out: JacobianOut<'_> = out) -> Option<usize>
    );
    if let Some(k) = bad {
        // The one-state function names the body that overflowed.
        let nq = model.nq();
        crate::compute_frame_jacobian(
            model,
            &mut batch.data,
            &q[k * nq..(k + 1) * nq],
            frame,
            reference,
            &mut batch.jacobian,
        )
        .map_err(in_state(k))?;
        return Err(in_state(k)(KinematicsError::Overflow {
            what: "jacobian",
            body: frame.name(model)?.to_string(),
        }));
    }
    Ok(())
}
