//! Batched ABA: the block loop over `L` states at a time around the one-state sweeps of
//! `aba.rs` (`AbaSweep`'s three passes) instantiated on lanes. What is here is the edge: the
//! block's inputs into lanes and its accelerations out, and the states whose pivots were refused
//! (their accelerations are NaN, for the one-state function to name the joints).

use crate::aba::{AbaSweep, AbaTree, Pivots};
use crate::articulated::ArticulatedInertia;
use crate::data::DynamicsData;
use core::ops::Range;
use kinetree_kinematics::batch::{Io, block_states};
use kinetree_kinematics::model::Model;
use kinetree_kinematics::spatial::lanes::{LForce, LMotion, LSe3, LaneVec, Lanes};

/// The per-body lane buffers of ABA for one lane width.
#[derive(Clone, Debug, Default)]
pub(crate) struct AbaLanes<const L: usize> {
    /// The block's `q`, `v` and `tau` in lanes (`Io::load_coordinates`; lengths rounded up to
    /// 8).
    q: Vec<Lanes<L>>,
    v: Vec<Lanes<L>>,
    tau: Vec<Lanes<L>>,
    /// The block's accelerations, `nv` rounded up to 8 (`Io::store_coordinates`).
    ddq: Vec<Lanes<L>>,
    parent_from_body: LaneVec<LSe3<L>>,
    world_from_body: LaneVec<LSe3<L>>,
    velocity: LaneVec<LMotion<L>>,
    bias: LaneVec<LMotion<L>>,
    articulated: LaneVec<ArticulatedInertia<Lanes<L>>>,
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
            parent_from_body: LaneVec::new(LSe3::default(), nb),
            world_from_body: LaneVec::new(LSe3::default(), nb),
            velocity: LaneVec::new(LMotion::zero(), nb),
            bias: LaneVec::new(LMotion::zero(), nb),
            articulated: LaneVec::new(ArticulatedInertia::default(), nb),
            force: LaneVec::new(LForce::zero(), nb),
            acceleration: LaneVec::new(LMotion::zero(), nb),
            subspace: LaneVec::new(LMotion::zero(), nv),
            u_columns: LaneVec::new(LForce::zero(), nv),
            u: vec![Lanes::ZERO; nv],
            dinv: vec![Lanes::ZERO; data.dinv.len()],
        }
    }
}

/// The lanes of a block whose pivots were refused (not 0).
struct Refused<const L: usize>(Lanes<L>);

impl<const L: usize> Pivots<Lanes<L>> for Refused<L> {
    #[inline(always)]
    fn check(&mut self, _dofs: Range<usize>, refused: Lanes<L>, _dinv: &mut [Lanes<L>]) {
        self.0 += refused;
    }
}

/// ABA of the `n` states of `(q, v, tau)` into `ddq` (inputs checked by the caller), as
/// `aba::compute` without external forces: the same generic sweeps on lanes. A state with a
/// refused pivot gets NaN accelerations, for the caller to hand to the one-state function.
#[inline(always)]
#[allow(
    clippy::too_many_arguments,
    reason = "the batch's inputs, passed through"
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
    let tree = AbaTree::of(model, data);
    for start in (0..n).step_by(L) {
        let idx = block_states::<L>(start, n);
        let count = L.min(n - start);
        // The inputs were checked by the caller: the finiteness probes are not needed.
        let _ = io.load_coordinates(q, nq, &idx, &mut bufs.q);
        let _ = io.load_coordinates(v, nv, &idx, &mut bufs.v);
        let _ = io.load_coordinates(tau, nv, &idx, &mut bufs.tau);
        let mut sweep = AbaSweep {
            parent_from_body: &mut bufs.parent_from_body,
            world_from_body: &mut bufs.world_from_body,
            velocity: &mut bufs.velocity,
            bias: &mut bufs.bias,
            acceleration: &mut bufs.acceleration,
            subspace: &mut bufs.subspace,
            force: &mut bufs.force,
            u_columns: &mut bufs.u_columns,
            articulated: &mut bufs.articulated,
            u: &mut bufs.u,
            dinv: &mut bufs.dinv,
            ddq: &mut bufs.ddq,
        };
        sweep.forward(&tree, &bufs.q, &bufs.v);
        let mut refused = Refused(Lanes::ZERO);
        sweep.backward(&tree, &bufs.v, &bufs.tau, &mut refused);
        sweep.accelerations(&tree);
        io.store_coordinates(&bufs.ddq, nv, ddq, start, nv, count);
        for l in 0..count {
            if refused.0.0[l] != 0.0 {
                let s = start + l;
                ddq[s * nv..(s + 1) * nv].fill(f64::NAN);
            }
        }
    }
}
