//! The lane kernels of batched forward kinematics and frame Jacobians: the one-state sweeps of
//! `forward.rs` and `jacobian.rs`, over a block of `L` states at a time.

use super::simd::{
    Coordinates, Gathered, InLanes, block_states, body_transform_of, joint_sin_cos, suspect_lanes,
};
use super::transpose::Io;
use crate::error::check_q;
use crate::jacobian::ReferenceFrame;
use crate::joint::JointModel;
use crate::joint::axis_column;
use crate::joint::transform::rotate_about_axis;
use kinetree_model::Model;
use kinetree_model::spatial::lanes::{LMotion, LSe3, LVec3, LaneVec, Lanes};
use kinetree_model::spatial::real::{Matrix3 as _, Vector3 as _};
use kinetree_model::spatial::{Motion, Se3};

/// The per-body and per-link lane buffers of one lane width.
#[derive(Clone, Debug, Default)]
pub(crate) struct LaneBuffers<const L: usize> {
    /// The block's coordinates, `nq` rounded up to 8 (`Io::load_coordinates`).
    coordinates: Vec<Lanes<L>>,
    world_from_body: LaneVec<LSe3<L>>,
    world_from_link: LaneVec<LSe3<L>>,
    columns: LaneVec<LMotion<L>>,
    /// The Jacobian columns the frame's path writes (the others are zero in every state), and
    /// the same as a mask over the `nv` columns.
    path_columns: Vec<usize>,
    on_path: Vec<bool>,
    /// The runs of columns off the path, `[start, end)`.
    zero_runs: Vec<(usize, usize)>,
    /// The frame's body and its ancestors, root first (the bodies the Jacobian places), each
    /// with the range of its terms in `path_terms`.
    path_bodies: Vec<(usize, core::ops::Range<usize>)>,
    /// What each body on the path adds to which column, in the one-state function's order.
    path_terms: Vec<PathTerm>,
    /// Each term's world-frame column for the block, computed as its body is placed.
    term_columns: LaneVec<LMotion<L>>,
    /// For [`JacobianOut::Rows`]: the block's Jacobians as 6 rows of `nv` columns, one after
    /// another (`6·nv` rounded up to 8 for `Io::store_coordinates`); the columns off the path
    /// stay zero.
    rows: Vec<Lanes<L>>,
}

/// Where a batched Jacobian goes.
#[derive(Debug)]
pub(crate) enum JacobianOut<'a> {
    /// `nv` columns per state (`n · nv` motions).
    Columns(&'a mut [Motion]),
    /// A row-major `6 x nv` matrix per state (`n · 6 · nv` numbers), rows in `Motion`'s order
    /// (linear, then angular).
    Rows(&'a mut [f64]),
}

impl JacobianOut<'_> {
    /// The buffer's length and how much of it each state takes, for a model of `nv` velocities.
    pub(crate) fn shape(&self, nv: usize) -> (usize, usize) {
        match self {
            Self::Columns(out) => (out.len(), nv),
            Self::Rows(out) => (out.len(), 6 * nv),
        }
    }
}

/// Where batched forward kinematics puts the links' placements.
#[derive(Debug)]
pub(crate) enum PosesOut<'a> {
    /// Every link's placement, state `k`'s links at `k · nlinks ..`.
    Placements(&'a mut [Se3]),
    /// Row-major 4×4 homogeneous matrices of the links `links` (every link, in order, when
    /// `None`), state `k`'s `16 · links.len()` numbers at `k · 16 · links.len() ..`.
    Matrices {
        /// The matrices.
        out: &'a mut [f64],
        /// The links written, in the order written (indices checked by the caller).
        links: Option<&'a [usize]>,
    },
}

/// One term of a Jacobian column, worked out once per call so the block loop neither matches
/// on joint kinds nor reads the model.
#[derive(Clone, Copy, Debug)]
struct PathTerm {
    /// The column it adds to.
    column: usize,
    /// 0–2: a turn about that coordinate axis; 3–5: a slide along axis `axis − 3`; otherwise
    /// `motion`, the joint's subspace column.
    axis: u8,
    /// The subspace column of a joint on no coordinate axis.
    motion: Motion,
    /// A mimic follower's multiplier; 1 otherwise (a product by 1 changes no bit).
    multiplier: f64,
}

impl PathTerm {
    /// Term `k` of joint `jm` (as `compute_frame_jacobian`).
    fn new(column: usize, jm: &JointModel, k: usize, multiplier: f64) -> Self {
        let (axis, motion) = match jm.axis_index() {
            Some((a, revolute)) => (if revolute { a } else { a + 3 }, Motion::ZERO),
            None => (6, jm.subspace_column(k)),
        };
        Self {
            column,
            // An axis index is 0..3, so `axis` is at most 6.
            axis: u8::try_from(axis).unwrap_or(6),
            motion,
            multiplier,
        }
    }
}

impl<const L: usize> LaneBuffers<L> {
    pub(crate) fn new(model: &Model) -> Self {
        Self {
            coordinates: vec![Lanes::ZERO; model.nq().next_multiple_of(8)],
            world_from_body: LaneVec::new(LSe3::splat(&Se3::IDENTITY), model.nbodies()),
            world_from_link: LaneVec::new(LSe3::splat(&Se3::IDENTITY), model.links().len()),
            columns: LaneVec::new(LMotion::zero(), model.nv()),
            path_columns: Vec::with_capacity(model.nv()),
            on_path: vec![false; model.nv()],
            zero_runs: Vec::with_capacity(model.nv() + 1),
            path_bodies: Vec::with_capacity(model.nbodies()),
            path_terms: Vec::with_capacity(model.nv() + model.nbodies()),
            term_columns: LaneVec::new(LMotion::zero(), model.nv() + model.nbodies()),
            rows: vec![Lanes::ZERO; (6 * model.nv()).next_multiple_of(8)],
        }
    }
}

/// The model data the kernels read besides the [`Model`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shape<'a> {
    pub(crate) model: &'a Model,
    pub(crate) joint_models: &'a [JointModel],
    pub(crate) link_on_body_frame: &'a [bool],
    /// Per body, the coordinate axis a revolute joint whose placement does not rotate turns
    /// about (3 for other bodies), as `KinematicsData::turn_axis`.
    pub(crate) turn_axis: &'a [u8],
    /// How results leave the lanes.
    pub(crate) io: Io,
}

/// Every body's world placement for the block of states `idx` (the sweep of `placements`).
#[inline(always)]
fn body_sweep<const L: usize>(shape: &Shape<'_>, world: &mut LaneVec<LSe3<L>>, c: &InLanes<'_, L>) {
    for i in 1..shape.model.bodies().len() {
        place(shape, world, c, i);
    }
}

/// Body `i`'s world placement from its parent's, for the block of states `idx` (as
/// `forward::place`).
#[inline(always)]
fn place<const L: usize>(
    shape: &Shape<'_>,
    world: &mut LaneVec<LSe3<L>>,
    c: &InLanes<'_, L>,
    i: usize,
) {
    let b = &shape.model.bodies()[i];
    // As `forward::placements`: the parent's world rotation turned about the joint's axis,
    // two columns of three, where the placement does not rotate.
    let k = usize::from(shape.turn_axis[i]);
    if k < 3 {
        let (s, co) = joint_sin_cos(b, c);
        let w = &world[b.parent];
        world[i] = LSe3 {
            rotation: rotate_about_axis(&w.rotation, k, s, co),
            translation: w.rotation.mul_const_vec(b.placement.translation) + w.translation,
        };
        return;
    }
    let local = body_transform_of(&shape.joint_models[i], b, c);
    world[i] = if b.parent == 0 {
        local
    } else {
        world[b.parent].compose(&local)
    };
}

/// NaN in each lane where a coordinate of `t` is not finite, ±0 elsewhere: `0 · x` is ±0 for a
/// finite `x` and NaN for an infinity or NaN. Sums of probes stay 0 only when every probed
/// number is finite.
#[inline(always)]
#[allow(clippy::eq_op, reason = "`x - x` is the probe itself")]
fn non_finite<const L: usize>(t: &LVec3<L>) -> Lanes<L> {
    t.x * 0.0 + t.y * 0.0 + t.z * 0.0
}

/// The state of the first of the `count` lanes whose probe (a sum of [`non_finite`]) is not 0,
/// counting from state `start`.
#[inline(always)]
fn first_flagged<const L: usize>(probe: Lanes<L>, start: usize, count: usize) -> Option<usize> {
    (0..count).find(|&k| probe.0[k] != 0.0).map(|k| start + k)
}

/// The first of the block's `count` states (from state `start`) whose configuration the
/// one-state functions refuse: a lane whose finiteness probe (of
/// [`Io::load_coordinates`](super::transpose::Io::load_coordinates)) is not 0, or whose
/// quaternions' sums of squares are not well inside the tolerance (|norm² − 1| ≤ 1.9e-6, a norm
/// within 0.95e-6 of 1), goes through [`check_q`], which decides; so a batch accepts and refuses
/// exactly the states the one-state functions do.
#[inline(always)]
fn first_refused<const L: usize>(
    shape: &Shape<'_>,
    c: &InLanes<'_, L>,
    finite: Lanes<L>,
    start: usize,
    count: usize,
) -> Option<usize> {
    let suspect = suspect_lanes(shape.model, c.lanes, finite);
    (0..count)
        .find(|&k| suspect.0[k] != 0.0 && check_q(shape.model, "q", c.state(k)).is_err())
        .map(|k| start + k)
}

/// The earlier of two bad states.
#[inline(always)]
fn earliest(a: Option<usize>, b: Option<usize>) -> Option<usize> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Forward kinematics of the `n` states of `q`: the links' placements into `links`, and every
/// frame's into `frames` when given (buffer lengths and link indices checked by the caller).
/// Returns the first state whose configuration the one-state function refuses or with a link
/// whose translation is not finite (the one-state function's overflow check, over every link
/// whichever are written).
#[inline(always)]
pub(crate) fn forward_kinematics<const L: usize>(
    bufs: &mut LaneBuffers<L>,
    shape: &Shape<'_>,
    q: &[f64],
    n: usize,
    mut links: PosesOut<'_>,
    mut frames: Option<&mut [Se3]>,
) -> Option<usize> {
    let model = shape.model;
    let (nq, nl, nf) = (model.nq(), model.links().len(), model.frames().len());
    // A selection of links is written once all are placed (so every link is checked).
    let selection = match &links {
        PosesOut::Matrices {
            links: Some(sel), ..
        } => Some(*sel),
        _ => None,
    };
    // The links' lane placements are kept for the frames, which are placed from them, and for a
    // selection.
    let keep_links = (frames.is_some() && nf > 0) || selection.is_some();
    let mut bad = None;
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        let finite = shape
            .io
            .load_coordinates(q, nq, &idx, &mut bufs.coordinates);
        let c = InLanes {
            lanes: &bufs.coordinates,
            states: Gathered { q, nq, idx },
        };
        let refused = first_refused(shape, &c, finite, start, count);
        body_sweep(shape, &mut bufs.world_from_body, &c);
        let mut probe = Lanes::ZERO;
        for l in 0..nl {
            let (b, body_from_link) = model.link_body(l);
            let x = if shape.link_on_body_frame[l] {
                bufs.world_from_body[b]
            } else {
                bufs.world_from_body[b].mul_const(body_from_link)
            };
            probe += non_finite(&x.translation);
            if keep_links {
                bufs.world_from_link[l] = x;
            }
            match &mut links {
                PosesOut::Placements(out) => {
                    shape
                        .io
                        .store_placements(&x, out, start * nl + l, nl, count);
                }
                PosesOut::Matrices { out, links: None } => {
                    shape.io.store_matrix(&x, out, l, nl, start, count);
                }
                PosesOut::Matrices { .. } => {}
            }
        }
        if let (Some(sel), PosesOut::Matrices { out, .. }) = (selection, &mut links) {
            for (slot, &l) in sel.iter().enumerate() {
                let x = &bufs.world_from_link[l];
                shape.io.store_matrix(x, out, slot, sel.len(), start, count);
            }
        }
        if bad.is_none() {
            bad = earliest(refused, first_flagged(probe, start, count));
        }
        if let Some(frames) = frames.as_deref_mut() {
            for (f, frame) in model.frames().iter().enumerate() {
                let x = bufs.world_from_link[frame.link].mul_const(&frame.placement);
                shape
                    .io
                    .store_placements(&x, frames, start * nf + f, nf, count);
            }
        }
    }
    bad
}

/// A world-frame twist re-expressed for a frame at `world_from_frame` (as `world_to_reference`
/// of `jacobian.rs`).
#[inline(always)]
fn to_reference<const L: usize>(
    world_from_frame: &LSe3<L>,
    world: &LMotion<L>,
    reference: ReferenceFrame,
) -> LMotion<L> {
    match reference {
        ReferenceFrame::World => *world,
        ReferenceFrame::Local => world_from_frame.act_inv_motion(world),
        ReferenceFrame::LocalWorldAligned => LMotion {
            linear: world.linear + world.angular.cross(&world_from_frame.translation),
            angular: world.angular,
        },
    }
}

/// The subspace column of `term` moved by `x` (a world-frame Jacobian column when `x` is the
/// body's world placement).
#[inline(always)]
fn column<const L: usize>(x: &LSe3<L>, term: &PathTerm) -> LMotion<L> {
    match term.axis {
        a @ 0..3 => axis_column(x, usize::from(a), true),
        a @ 3..6 => axis_column(x, usize::from(a - 3), false),
        _ => x.act_motion(&LMotion::splat(&term.motion)),
    }
}

/// The Jacobian of `frame` in `reference` for the `n` states of `q`, into `out` (inputs checked
/// by the caller), as `compute_frame_jacobian`, which places only the frame's body and its
/// ancestors. Returns the first state whose configuration the one-state function refuses or
/// with a placement on that path or a column that is not finite.
#[inline(always)]
pub(crate) fn frame_jacobian<const L: usize>(
    bufs: &mut LaneBuffers<L>,
    shape: &Shape<'_>,
    q: &[f64],
    n: usize,
    body_and_placement: (usize, Se3),
    reference: ReferenceFrame,
    mut out: JacobianOut<'_>,
) -> Option<usize> {
    let model = shape.model;
    let (nq, nv) = (model.nq(), model.nv());
    let bodies = model.bodies();
    let (body, body_from_frame) = body_and_placement;
    // The columns the path writes (a coupled mimic follower writes its leader's); every other
    // column is zero in every state, so only these are cleared and read from the lanes.
    bufs.on_path.fill(false);
    bufs.path_columns.clear();
    bufs.path_bodies.clear();
    bufs.path_terms.clear();
    let mut i = body;
    while i != 0 {
        let b = &bodies[i];
        let jm = &shape.joint_models[i];
        let written = if b.mimic.is_some() { 1 } else { b.nv };
        let first = bufs.path_terms.len();
        bufs.path_bodies.push((i, first..first + written));
        for k in 0..written {
            let c = b.idx_v + k;
            let multiplier = b.mimic.as_ref().map_or(1.0, |m| m.multiplier);
            bufs.path_terms.push(PathTerm::new(c, jm, k, multiplier));
            if !bufs.on_path[c] {
                bufs.on_path[c] = true;
                bufs.path_columns.push(c);
            }
        }
        i = b.parent;
    }
    // Parents before children, as the one-state sweep (ancestors have smaller indices).
    bufs.path_bodies.reverse();
    bufs.path_columns.sort_unstable();
    bufs.zero_runs.clear();
    let mut next = 0;
    for &c in &bufs.path_columns {
        if next < c {
            bufs.zero_runs.push((next, c));
        }
        next = c + 1;
    }
    if next < nv {
        bufs.zero_runs.push((next, nv));
    }
    if matches!(out, JacobianOut::Rows(_)) {
        // Left zero for the columns off this call's path (a previous call's may have differed).
        bufs.rows.fill(Lanes::ZERO);
    }
    let mut bad = None;
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        let finite = shape
            .io
            .load_coordinates(q, nq, &idx, &mut bufs.coordinates);
        let c = InLanes {
            lanes: &bufs.coordinates,
            states: Gathered { q, nq, idx },
        };
        let refused = first_refused(shape, &c, finite, start, count);
        let mut probe = Lanes::ZERO;
        // A body's terms are taken while its placement is at hand: read back later by a
        // column index that varies, the placement's columns were gathered lane by lane.
        for (i, terms) in &bufs.path_bodies {
            place(shape, &mut bufs.world_from_body, &c, *i);
            let x = bufs.world_from_body[*i];
            probe += non_finite(&x.translation);
            for t in terms.clone() {
                bufs.term_columns[t] = column(&x, &bufs.path_terms[t]);
            }
        }
        let world_from_frame = bufs.world_from_body[body].mul_const(&body_from_frame);
        for &c in &bufs.path_columns {
            bufs.columns[c] = LMotion::zero();
        }
        for (t, term) in bufs.path_terms.iter().enumerate() {
            bufs.columns[term.column] +=
                to_reference(&world_from_frame, &bufs.term_columns[t], reference)
                    .scale(Lanes::splat(term.multiplier));
        }
        for &c in &bufs.path_columns {
            let col = &bufs.columns[c];
            probe += non_finite(&col.linear) + non_finite(&col.angular);
        }
        match &mut out {
            JacobianOut::Columns(out) => {
                // The runs of columns off the path are zero-filled whole, state by state; the
                // path's columns are moved out of the lanes column by column (a test of every
                // column and six single stores each made this copy half of the batch's time on
                // talos_full_v2).
                for k in 0..count {
                    let row = &mut out[(start + k) * nv..(start + k + 1) * nv];
                    for &(a, b) in &bufs.zero_runs {
                        shape.io.zero_motions(&mut row[a..b]);
                    }
                }
                for &c in &bufs.path_columns {
                    shape
                        .io
                        .store_motions(&bufs.columns[c], out, start * nv + c, nv, count);
                }
            }
            JacobianOut::Rows(out) if nv > 0 => {
                // The path's columns into the rows, then each state's matrix out through the
                // transposes as one record of `6·nv` numbers: written once, in order, zeros
                // and all, with whole-vector stores (row by row, a row of `nv` numbers took a
                // full and a masked store each, and the stores were a quarter of the kernel).
                for &c in &bufs.path_columns {
                    let col = &bufs.columns[c];
                    let (a, b) = (&col.linear, &col.angular);
                    for (r, x) in [a.x, a.y, a.z, b.x, b.y, b.z].into_iter().enumerate() {
                        bufs.rows[r * nv + c] = x;
                    }
                }
                shape
                    .io
                    .store_coordinates(&bufs.rows, 6 * nv, out, start, 6 * nv, count);
            }
            JacobianOut::Rows(_) => {}
        }
        if bad.is_none() {
            bad = earliest(refused, first_flagged(probe, start, count));
        }
    }
    bad
}
