//! Batched RNEA: the block loop over `L` states at a time, around the one-state sweeps of
//! `rnea.rs` (`forward`, `backward`, the joint terms) instantiated on lanes. What is here is the
//! edge: moving a block's coordinates into lanes and its torques out, and the checks that decide
//! which states the one-state function must look at.

use crate::data::DynamicsData;
use crate::rnea::{Bodies, JointTermsRef, Sweep, backward, forward};
use kinetree_kinematics::batch::{Io, block_states, suspect_lanes};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::lanes::{LForce, LMotion, LSe3, LaneVec, Lanes};

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
}

impl<const L: usize> RneaLanes<L> {
    pub(crate) fn new(model: &Model) -> Self {
        let nb = model.nbodies();
        let nq8 = model.nq().next_multiple_of(8);
        let nv8 = model.nv().next_multiple_of(8);
        Self {
            q: vec![Lanes::ZERO; nq8],
            v: vec![Lanes::ZERO; nv8],
            a: vec![Lanes::ZERO; nv8],
            parent_from_body: LaneVec::new(LSe3::default(), nb),
            velocity: LaneVec::new(LMotion::zero(), nb),
            acceleration: LaneVec::new(LMotion::zero(), nb),
            force: LaneVec::new(LForce::zero(), nb),
            tau: vec![Lanes::ZERO; nv8],
        }
    }
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
/// `rnea::sweep::<true, true>` without external forces: the same generic sweeps on lanes. The
/// states' inputs are checked in the lanes: finiteness by a probe, quaternions by their sums of
/// squares ([`suspect_lanes`]); a state flagged there is reported for the one-state check to
/// decide.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs, passed through"
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
    let bodies = Bodies {
        model,
        joint_models: data.kinematics.joint_models(),
        turn: &data.turn,
    };
    let terms = JointTermsRef {
        armature: &data.armature,
        damping: &data.damping,
        friction: &data.friction,
    };
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
        let mut state = Sweep {
            parent_from_body: &mut bufs.parent_from_body,
            velocity: &mut bufs.velocity,
            acceleration: &mut bufs.acceleration,
            force: &mut bufs.force,
        };
        forward::<Lanes<L>, true, true>(&bodies, &mut state, &bufs.q, &bufs.v, &bufs.a);
        backward(&bodies, &mut state, &mut bufs.tau);
        if data.has_joint_terms {
            terms.add::<Lanes<L>, true, true>(&bufs.v, &bufs.a, &mut bufs.tau);
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
